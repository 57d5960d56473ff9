//! Suggestions as source edits: each change of an unreachable goal's explanation
//! ([`cellc_runtime::explain::Change`]) as the text edit that makes it in the cell's
//! sources. The runtime says what to change in terms of the cell's named items (an
//! object's transitions, an end-effector's `reaches` list, an arm's `reach` box, an
//! `allow contact` line); this module finds those items in the text and writes the edit.
//! `cellc plan` shows the edits as fix notes under R0004, `tests/fixes.rs` applies every
//! one, compiles and plans again, and an editor can offer them as code actions.
//!
//! A change that cannot be made as an edit of these sources (a span that is not where the
//! artifact says, a reach box that no `reach` line gives) has no edit: [`edit`] returns
//! `None` rather than a guess.

use cellc_compiler::units::{Eval, FileUnits};
use cellc_lang::ast;
use cellc_lang::{written_name, FileId, SourceMap, Span};
use cellc_runtime::explain::{BodyName, Change};
use cellc_schema::{Aabb, Artifact, ObjectId};

/// Box corners written by an edit and read back may differ by this much, metres (the
/// compiler's box comparisons allow 1 µm).
const SAME_BOX: f64 = 1e-7;

/// One text edit: the bytes `span` of `file` replaced by `text` (an empty span inserts).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SourceEdit {
    /// The file.
    pub file: FileId,
    /// The bytes replaced.
    pub span: Span,
    /// What they become.
    pub text: String,
}

/// The edit that makes `change` in the sources the artifact was built from, or `None`
/// when it cannot be made as an edit of these sources.
pub fn edit(
    artifact: &Artifact,
    object: ObjectId,
    change: &Change,
    sources: &SourceMap,
) -> Option<SourceEdit> {
    let at = Places { artifact, sources };
    match change {
        Change::AddTransition {
            from_grasp,
            to_grasp,
            reverse_of,
            ..
        } => {
            let obj = artifact.objects.get(object.index())?;
            let grasp = |g: cellc_schema::GraspId| obj.grasps.get(g.index()).map(|x| &x.name);
            let (from, to) = (
                written_name(grasp(*from_grasp)?),
                written_name(grasp(*to_grasp)?),
            );
            match reverse_of {
                Some(span) => {
                    let (file, place, text) = at.span(span.0)?;
                    // `transition to -> from` alone on its line becomes two-way; a line
                    // that lists more grasps keeps them one-way and gets the way back.
                    match text.find("->") {
                        Some(arrow) if !text.contains(',') && !text.contains("<->") => {
                            let arrow = place.start as usize + arrow;
                            Some(SourceEdit {
                                file,
                                span: Span::new(arrow, arrow + 2),
                                text: "<->".to_string(),
                            })
                        }
                        _ => at.line_after(file, place, &format!("transition {from} -> {to}")),
                    }
                }
                None => {
                    // After the last grasp or transition of the object's block.
                    let members = obj
                        .grasps
                        .iter()
                        .map(|g| g.span)
                        .chain(obj.transitions.iter().map(|t| t.span));
                    let (file, _, _) = at.span(obj.span)?;
                    let last = members
                        .filter_map(|s| at.span(s))
                        .filter(|(f, _, _)| *f == file)
                        .map(|(_, place, _)| place)
                        .max_by_key(|place| place.end)?;
                    at.line_after(file, last, &format!("transition {from} <-> {to}"))
                }
            }
        }
        Change::AddAdjacency { a, b, .. } => {
            let ws = |w: cellc_schema::WorkspaceId| artifact.workspaces.get(w.index());
            let (wa, wb) = (ws(*a)?, ws(*b)?);
            if wa.derived || wb.derived {
                return None;
            }
            // Beside the cell's other `adjacent` lines, or after the second workspace.
            let declared = artifact
                .objects
                .iter()
                .flat_map(|o| {
                    o.graph
                        .arcs
                        .iter()
                        .chain(o.graph.pruned.iter().map(|p| &p.arc))
                })
                .filter_map(|arc| arc.via)
                .filter_map(|s| at.span(s))
                .max_by_key(|(f, place, _)| (*f, place.end));
            let (file, anchor, _) = declared.or_else(|| at.span(wb.span))?;
            let line = format!(
                "adjacent {} {}",
                written_name(&wa.name),
                written_name(&wb.name)
            );
            at.line_after(file, anchor, &line)
        }
        Change::ExtendReaches {
            end_effector,
            workspace,
            ..
        } => {
            let e = artifact.end_effectors.get(end_effector.index())?;
            let w = artifact.workspaces.get(workspace.index())?;
            if w.derived {
                return None;
            }
            let (file, place, text) = at.span(e.span)?;
            if !text.contains(" reaches ") {
                return None;
            }
            let separator = if text.trim_end().ends_with(',') {
                " "
            } else {
                ", "
            };
            let end = place.end as usize;
            Some(SourceEdit {
                file,
                span: Span::new(end, end),
                text: format!("{separator}{}", written_name(&w.name)),
            })
        }
        Change::GrowReach {
            end_effector,
            reach_box,
            grown,
            ..
        } => {
            let e = artifact.end_effectors.get(end_effector.index())?;
            match reach_box {
                Some(i) => {
                    let old = e.reach_boxes.get(*i as usize)?;
                    let (file, place, units) = at.reach_line(&e.name, old)?;
                    Some(SourceEdit {
                        file,
                        span: place,
                        text: box_text(grown, units),
                    })
                }
                None => {
                    let (file, place, _) = at.span(e.span)?;
                    let units = at.units(file)?;
                    let line =
                        format!("reach {} {}", written_name(&e.name), box_text(grown, units));
                    at.line_after(file, place, &line)
                }
            }
        }
        Change::AllowContact { a, b, .. } => {
            let line = format!("allow contact {} {}", written_body(a), written_body(b));
            allow_contact(artifact, &line, sources)
        }
    }
}

/// The edit that adds `line` (an `allow contact A B` line) to the cell: the last line of
/// its main file's block, where the cell's own contacts go.
pub fn allow_contact(artifact: &Artifact, line: &str, sources: &SourceMap) -> Option<SourceEdit> {
    Places { artifact, sources }.line_before_end(FileId(0), line)
}

/// Applies edits of one file to its text, from the last to the first (so each span still
/// means what it meant in the original); `None` when two overlap or one is out of range.
pub fn apply(text: &str, edits: &[&SourceEdit]) -> Option<String> {
    let mut sorted: Vec<&&SourceEdit> = edits.iter().collect();
    sorted.sort_by_key(|e| (e.span.start, e.span.end));
    for pair in sorted.windows(2) {
        if pair[0].span.end > pair[1].span.start {
            return None;
        }
    }
    let mut out = text.to_string();
    for e in sorted.into_iter().rev() {
        let range = e.span.start as usize..e.span.end as usize;
        if range.end > out.len()
            || !out.is_char_boundary(range.start)
            || !out.is_char_boundary(range.end)
        {
            return None;
        }
        out.replace_range(range, &e.text);
    }
    Some(out)
}

/// Where things are in the sources.
struct Places<'a> {
    artifact: &'a Artifact,
    sources: &'a SourceMap,
}

impl<'a> Places<'a> {
    fn text(&self, file: FileId) -> Option<&'a str> {
        self.sources
            .iter()
            .find(|(id, _)| *id == file)
            .map(|(_, f)| f.text.as_str())
    }

    /// A span of the artifact: its file, its bytes and its text.
    fn span(&self, span: u32) -> Option<(FileId, Span, &'a str)> {
        let s = self.artifact.spans.get(span as usize)?;
        let file = FileId(s.file);
        let text = self.text(file)?;
        let slice = text.get(s.start as usize..s.end as usize)?;
        Some((file, Span::new(s.start as usize, s.end as usize), slice))
    }

    /// Inserts `line` on a new line after the one `anchor` ends on, indented as the line
    /// `anchor` starts on.
    fn line_after(&self, file: FileId, anchor: Span, line: &str) -> Option<SourceEdit> {
        let text = self.text(file)?;
        let start = anchor.start as usize;
        let end = anchor.end as usize;
        let line_start = text.get(..start)?.rfind('\n').map_or(0, |i| i + 1);
        let indent: String = text[line_start..]
            .chars()
            .take_while(|c| *c == ' ' || *c == '\t')
            .collect();
        let line_end = text.get(end..)?.find('\n').map_or(text.len(), |i| end + i);
        Some(SourceEdit {
            file,
            span: Span::new(line_end, line_end),
            text: format!("\n{indent}{line}"),
        })
    }

    /// Inserts `line` as the last line of the file's `cell { ... }` block.
    fn line_before_end(&self, file: FileId, line: &str) -> Option<SourceEdit> {
        let text = self.text(file)?;
        let close = text.rfind('}')?;
        let line_start = text[..close].rfind('\n').map_or(0, |i| i + 1);
        // Alone on its line: the new line goes before it; after other text: before the
        // brace, on a line of its own.
        let (at, newline) = if text[line_start..close].trim().is_empty() {
            (line_start, "")
        } else {
            (close, "\n")
        };
        Some(SourceEdit {
            file,
            span: Span::new(at, at),
            text: format!("{newline}  {line}\n"),
        })
    }

    /// The length unit bare numbers of a file are read in.
    fn units(&self, file: FileId) -> Option<FileUnits> {
        let parsed = cellc_lang::parse(file, self.text(file)?);
        let items = parsed.file.map(|f| f.items).unwrap_or_default();
        Some(FileUnits::of(file, &items, &mut Vec::new()))
    }

    /// The `box ...` clause of the `reach NAME` line that gives `old` (compared in metres,
    /// with each file's units), with the file's units.
    fn reach_line(&self, owner: &str, old: &Aabb) -> Option<(FileId, Span, FileUnits)> {
        self.sources.iter().find_map(|(file, source)| {
            let parsed = cellc_lang::parse(file, &source.text).file?;
            let units = FileUnits::of(file, &parsed.items, &mut Vec::new());
            parsed.items.iter().find_map(|item| {
                let ast::Item::Reach(reach) = item else {
                    return None;
                };
                if reach.end_effector.text != owner {
                    return None;
                }
                let mut eval = Eval {
                    file,
                    units,
                    diagnostics: &mut Vec::new(),
                };
                let ast::ReachExtent::Box(written) = &reach.extent else {
                    return None;
                };
                let b = eval.aabb(written)?;
                let same = (0..3).all(|k| {
                    (b.mins[k] - old.min[k]).abs() < SAME_BOX
                        && (b.maxs[k] - old.max[k]).abs() < SAME_BOX
                });
                same.then_some((file, written.span, units))
            })
        })
    }
}

/// `left`, `left.lwr_link_7`.
pub fn written_body(b: &BodyName) -> String {
    match &b.part {
        Some(part) => format!("{}.{}", written_name(&b.owner), written_name(part)),
        None => written_name(&b.owner),
    }
}

/// `box center (x, y, z) size (x, y, z)` in the file's length unit (explicit metres when
/// it has none).
fn box_text(b: &Aabb, units: FileUnits) -> String {
    let (scale, suffix) = match units.length {
        Some(unit) => (1.0 / unit.to_si(), ""),
        None => (1.0, " m"),
    };
    let vector = |v: [f64; 3]| {
        let parts: Vec<String> = v
            .iter()
            .map(|x| format!("{}{suffix}", number(x * scale)))
            .collect();
        format!("({})", parts.join(", "))
    };
    let center = [0, 1, 2].map(|k| (b.min[k] + b.max[k]) / 2.0);
    let size = [0, 1, 2].map(|k| b.max[k] - b.min[k]);
    format!("box center {} size {}", vector(center), vector(size))
}

/// A number with at most nine decimals and no trailing zeros.
fn number(x: f64) -> String {
    let text = format!("{x:.9}");
    let text = text.trim_end_matches('0').trim_end_matches('.');
    match text {
        "-0" | "" => "0".to_string(),
        t => t.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use cellc_lang::ast::Unit;

    #[test]
    fn numbers_are_short_and_exact_enough() {
        assert_eq!(number(0.425_000_000_000_000_04), "0.425");
        assert_eq!(number(-0.0), "0");
        assert_eq!(number(1.2), "1.2");
        assert_eq!(number(1000.0), "1000");
    }

    #[test]
    fn boxes_are_written_in_the_files_unit() {
        let b = Aabb {
            min: [0.25, -0.42, 0.9],
            max: [0.6, 0.7, 1.5],
        };
        let metres = FileUnits {
            length: Some(Unit::M),
            angle: None,
        };
        assert_eq!(
            box_text(&b, metres),
            "box center (0.425, 0.14, 1.2) size (0.35, 1.12, 0.6)"
        );
        let mm = FileUnits {
            length: Some(Unit::Mm),
            angle: None,
        };
        assert_eq!(
            box_text(&b, mm),
            "box center (425, 140, 1200) size (350, 1120, 600)"
        );
        assert!(box_text(&b, FileUnits::default()).starts_with("box center (0.425 m, "));
    }

    #[test]
    fn edits_apply_from_the_end_and_refuse_overlaps() {
        let e = |start: usize, end: usize, text: &str| SourceEdit {
            file: FileId(0),
            span: Span::new(start, end),
            text: text.to_string(),
        };
        let (a, b) = (e(0, 1, "X"), e(3, 3, "!"));
        assert_eq!(apply("abc", &[&b, &a]).as_deref(), Some("Xbc!"));
        assert_eq!(apply("abc", &[&e(0, 2, ""), &e(1, 3, "")]), None);
        assert_eq!(apply("abc", &[&e(2, 9, "")]), None);
    }
}
