//! Grasp-set files: the poses a grasp planner found for one object and one hand kind, one
//! per row, read by `grasp NAME by HAND from "FILE"`.
//!
//! The format is CSV, so that any planner's output converts with a one-line script:
//!
//! ```text
//! # comments and blank lines are skipped
//! x,y,z,qx,qy,qz,qw
//! 0.0,0.12,0.09,0.5,-0.5,0.5,0.5
//! ```
//!
//! Each row is the object's pose in the hand frame (as `at (x, y, z) quat (...)` would
//! write it): a position in metres and a unit quaternion (x, y, z, w; normalised when its
//! norm is within 1e-3 of 1). The file is untrusted: it is read within
//! [`MAX_GRASP_FILE_BYTES`], at most [`crate::resolve::MAX_FAMILY_MEMBERS`] rows are
//! taken, and every row that is not a pose is a diagnostic with its span in the file
//! (at most [`MAX_ROW_DIAGNOSTICS`] of them, then one note of how many more).

use cellc_lang::{Diagnostic, FileId, Span};

use crate::diagnostics;
use crate::math::{Iso, Quat};
use crate::resolve::MAX_FAMILY_MEMBERS;

/// The largest grasp-set file read (1 MiB: 1,024 rows of 7 numbers with 20 digits each
/// fit several times over).
pub const MAX_GRASP_FILE_BYTES: u64 = 1 << 20;

/// Bad rows reported per file; the rest are counted in one note.
pub const MAX_ROW_DIAGNOSTICS: usize = 10;

/// The header every file starts with.
pub const HEADER: [&str; 7] = ["x", "y", "z", "qx", "qy", "qz", "qw"];

/// How far a quaternion's norm may be from 1 and still be read as a rotation.
const QUATERNION_NORM_TOLERANCE: f64 = 1e-3;

/// The poses of a grasp-set file, each with the span of its row.
#[derive(Debug, Default)]
pub struct GraspRows {
    /// Rows read, in file order.
    pub poses: Vec<(Iso, Span)>,
    /// True when some row was not a pose (the family is then not expanded, so that a
    /// bad row never shifts the names of the members after it).
    pub failed: bool,
}

/// Reads the rows of `text` (file `file` of the source map).
pub fn parse(file: FileId, text: &str, diagnostics: &mut Vec<Diagnostic>) -> GraspRows {
    let mut rows = GraspRows::default();
    let mut header_seen = false;
    let mut bad = 0usize;
    let mut offset = 0usize;
    for raw in text.split_inclusive('\n') {
        let start = offset;
        offset += raw.len();
        let line = raw.trim_end_matches(['\n', '\r']);
        let trimmed = line.trim();
        if trimmed.is_empty() || trimmed.starts_with('#') {
            continue;
        }
        let line_span = Span::new(
            start + (line.len() - line.trim_start().len()),
            start + line.trim_end().len(),
        );
        let fields = fields(line, start);
        if !header_seen {
            header_seen = true;
            let names: Vec<&str> = fields.iter().map(|(f, _)| *f).collect();
            if names != HEADER {
                diagnostics.push(diagnostics::bad_grasp_row(
                    file,
                    line_span,
                    "the first line is not the header `x,y,z,qx,qy,qz,qw`",
                    "expected the header here",
                ));
                rows.failed = true;
                return rows;
            }
            continue;
        }
        if rows.poses.len() == MAX_FAMILY_MEMBERS {
            diagnostics.push(diagnostics::grasp_file_too_long(file, line_span));
            rows.failed = true;
            return rows;
        }
        match row(&fields, line_span) {
            Ok(pose) => rows.poses.push((pose, line_span)),
            Err((span, what, label)) => {
                rows.failed = true;
                bad += 1;
                if bad <= MAX_ROW_DIAGNOSTICS {
                    diagnostics.push(diagnostics::bad_grasp_row(file, span, &what, label));
                }
            }
        }
    }
    if !header_seen {
        diagnostics.push(diagnostics::bad_grasp_row(
            file,
            Span::new(0, 0),
            "the file has no header `x,y,z,qx,qy,qz,qw`",
            "expected the header here",
        ));
        rows.failed = true;
    }
    if bad > MAX_ROW_DIAGNOSTICS {
        if let Some(last) = diagnostics.last_mut() {
            let more = bad - MAX_ROW_DIAGNOSTICS;
            *last = last
                .clone()
                .note(format!("{more} more bad rows are not shown"));
        }
    }
    rows
}

/// The comma-separated fields of `line` (starting at byte `start` of the file), trimmed,
/// each with its span.
fn fields(line: &str, start: usize) -> Vec<(&str, Span)> {
    let mut out = Vec::new();
    let mut at = 0usize;
    for field in line.split(',') {
        let lead = field.len() - field.trim_start().len();
        let trimmed = field.trim();
        let s = start + at + lead;
        out.push((trimmed, Span::new(s, s + trimmed.len())));
        at += field.len() + 1;
    }
    out
}

type RowError = (Span, String, &'static str);

/// One row: seven finite numbers, the last four a unit quaternion.
fn row(fields: &[(&str, Span)], line: Span) -> Result<Iso, RowError> {
    if fields.len() != HEADER.len() {
        return Err((
            line,
            format!("a row has {} fields, not 7", fields.len()),
            "expected `x,y,z,qx,qy,qz,qw`",
        ));
    }
    let mut values = [0.0f64; 7];
    for (i, (text, span)) in fields.iter().enumerate() {
        let value: f64 = text.parse().map_err(|_| {
            (
                *span,
                format!("`{}` is not a number", shorten(text)),
                "expected a number",
            )
        })?;
        if !value.is_finite() {
            return Err((
                *span,
                format!("`{}` is not finite", shorten(text)),
                "expected a finite number",
            ));
        }
        values[i] = value;
    }
    let q = nalgebra::Quaternion::new(values[6], values[3], values[4], values[5]);
    let norm = q.norm();
    if (norm - 1.0).abs() > QUATERNION_NORM_TOLERANCE {
        let span = fields[3].1.join(fields[6].1);
        return Err((
            span,
            format!("the quaternion's norm is {norm:.4}, not 1"),
            "not a unit quaternion",
        ));
    }
    Ok(Iso::from_parts(
        nalgebra::Translation3::new(values[0], values[1], values[2]),
        Quat::from_quaternion(q),
    ))
}

/// A field as quoted in a message: at most 24 characters of it.
fn shorten(text: &str) -> String {
    let mut out: String = text.chars().take(24).collect();
    if out.len() < text.len() {
        out.push_str("...");
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(text: &str) -> (GraspRows, Vec<Diagnostic>) {
        let mut d = Vec::new();
        let rows = parse(FileId(0), text, &mut d);
        (rows, d)
    }

    #[test]
    fn rows_become_poses_with_their_spans() {
        let text = "# two grasps\nx,y,z,qx,qy,qz,qw\n0,0.1,0.2,0,0,0,1\n\n 1, 2, 3, 0, 0, 1, 0\n";
        let (rows, d) = read(text);
        assert!(d.is_empty(), "{d:?}");
        assert!(!rows.failed);
        assert_eq!(rows.poses.len(), 2);
        assert!((rows.poses[0].0.translation.vector.z - 0.2).abs() < 1e-12);
        assert!((rows.poses[1].0.rotation.angle() - std::f64::consts::PI).abs() < 1e-9);
        assert_eq!(&text[rows.poses[1].1.range()], "1, 2, 3, 0, 0, 1, 0");
    }

    #[test]
    fn a_bad_field_is_reported_at_its_span() {
        let text = "x,y,z,qx,qy,qz,qw\n0,zero,0,0,0,0,1\n";
        let (rows, d) = read(text);
        assert!(rows.failed);
        assert_eq!(d.len(), 1);
        assert_eq!(d[0].code, crate::diagnostics::codes::BAD_GRASP_FILE);
        assert_eq!(&text[d[0].labels[0].span.range()], "zero");
    }

    #[test]
    fn a_quaternion_far_from_unit_is_refused() {
        let (rows, d) = read("x,y,z,qx,qy,qz,qw\n0,0,0,0,0,0,2\n0,0,0,0,0,0,1.0005\n");
        assert!(rows.failed);
        assert_eq!(d.len(), 1);
        assert_eq!(rows.poses.len(), 1);
    }

    #[test]
    fn a_missing_header_and_too_many_rows_are_errors() {
        let (_, d) = read("0,0,0,0,0,0,1\n");
        assert_eq!(d.len(), 1);
        let mut text = String::from("x,y,z,qx,qy,qz,qw\n");
        for _ in 0..=MAX_FAMILY_MEMBERS {
            text.push_str("0,0,0,0,0,0,1\n");
        }
        let (rows, d) = read(&text);
        assert!(rows.failed);
        assert_eq!(d[0].code, crate::diagnostics::codes::FAMILY_TOO_LARGE);
        assert_eq!(rows.poses.len(), MAX_FAMILY_MEMBERS);
    }

    #[test]
    fn bad_rows_are_reported_up_to_the_cap() {
        let mut text = String::from("x,y,z,qx,qy,qz,qw\n");
        for _ in 0..50 {
            text.push_str("1,2\n");
        }
        let (_, d) = read(&text);
        assert_eq!(d.len(), MAX_ROW_DIAGNOSTICS);
    }
}
