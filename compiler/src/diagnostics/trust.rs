//! Diagnostics of the trust boundary: files refused before they are read or parsed,
//! robot descriptions that are unsound, and cells whose graphs would exceed the limits.
//!
//! None of them quotes a refused file: a path named by a cell under review may be any
//! file of the machine, so the message says what the file is and how large, never what
//! it holds.

use cellc_lang::{Diagnostic, FileId, NotACell, Span};
use cellc_schema::files::{human_bytes, FileError};
use cellc_urdf::Problem;

use super::codes::*;
use crate::model::Origin;

/// A file refused before reading: too large, or not a regular file. `None` for other
/// errors, which keep the code of the phase that read the file.
pub(crate) fn refused_file(
    what: &str,
    path: &str,
    error: &FileError,
    at: Option<(FileId, Span)>,
) -> Option<Diagnostic> {
    let d = match error {
        FileError::TooLarge { size, limit } => Diagnostic::error(
            FILE_TOO_LARGE,
            format!(
                "{what} `{path}` is too large: {size} bytes, over the limit of {limit} ({})",
                human_bytes(*limit)
            ),
        )
        .help(format!(
            "check the path; a {what} larger than {} is not read (see `cellc explain E0317`)",
            human_bytes(*limit)
        )),
        FileError::NotRegular { what: kind } => Diagnostic::error(
            NOT_A_REGULAR_FILE,
            format!("{what} `{path}` is not a regular file: it is {kind}"),
        )
        .help(format!(
            "name a regular {what}; pipes, devices and sockets are never read, as they may never end"
        )),
        _ => return None,
    };
    Some(match at {
        Some((file, span)) => d.primary(file, span, "named here"),
        None => d,
    })
}

/// A file given on the command line as `what` (an artifact, a database) that cannot be
/// read: too large or not a regular file with their own codes, anything else as E0308.
pub fn input_unreadable(what: &str, path: &str, error: &FileError) -> Diagnostic {
    refused_file(what, path, error, None).unwrap_or_else(|| {
        Diagnostic::error(FILE_UNREADABLE, format!("cannot read `{path}`: {error}"))
            .help("check the path and that the file is readable")
    })
}

/// The cell and its includes would exceed the budget of source text in all.
pub fn sources_too_large(path: &str, limit: u64, at: Option<(FileId, Span)>) -> Diagnostic {
    let d = Diagnostic::error(
        FILE_TOO_LARGE,
        format!(
            "`{path}` is not read: with it, the cell and its includes exceed {} of source in all",
            human_bytes(limit)
        ),
    )
    .help("include fewer or smaller files; a compilation reads at most this much source");
    match at {
        Some((file, span)) => d.primary(file, span, "included here"),
        None => d,
    }
}

/// The URDFs of the cell would exceed the budget of URDF text in all.
pub fn urdfs_too_large(path: &str, limit: u64, file: FileId, span: Span) -> Diagnostic {
    Diagnostic::error(
        FILE_TOO_LARGE,
        format!(
            "URDF `{path}` is not read: with it, the cell's robot descriptions exceed {} in all",
            human_bytes(limit)
        ),
    )
    .primary(file, span, "named here")
    .help("name fewer or smaller URDF files; a compilation reads at most this much of them")
}

/// Why a file read as a cell is not one, with the facts the loader knows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NotCellReason {
    /// The bytes are not UTF-8.
    NotUtf8 {
        /// Offset of the first invalid byte.
        offset: usize,
    },
    /// What the syntax screen found.
    Screen(NotACell),
}

/// A file read as a cell or library that is not one. Its content is never shown: the
/// label, when there is one, is at the `include` that named it.
pub fn not_a_cell_file(
    path: &str,
    size: usize,
    reason: NotCellReason,
    at: Option<(FileId, Span)>,
) -> Diagnostic {
    let size = human_bytes(size as u64);
    let what = match reason {
        NotCellReason::NotUtf8 { offset } => {
            format!("{size} of binary data (not UTF-8 text: an invalid byte at offset {offset})")
        }
        NotCellReason::Screen(NotACell::Binary { nul_at }) => {
            format!("{size} of binary data (a NUL byte at offset {nul_at})")
        }
        NotCellReason::Screen(NotACell::Empty) => {
            format!("{size} of blanks and comments, with no `cell` or `library` in it")
        }
        NotCellReason::Screen(_) => {
            format!("{size} of text that does not begin with `cell NAME {{` or `library NAME {{`")
        }
    };
    let d = Diagnostic::error(
        NOT_A_CELL_FILE,
        format!("`{path}` is not a cell file: it holds {what}"),
    );
    let help = "check the path; cellc never shows the content of a file that is not a cell";
    match at {
        Some((file, span)) => d.primary(file, span, "included here").help(help),
        None => d.help(help),
    }
}

/// One problem of a robot description, at the robot's `urdf` path; `more` problems of the
/// same file are counted on it and not reported.
pub fn urdf_problem(
    path: &str,
    problem: &Problem,
    file: FileId,
    span: Span,
    more: usize,
) -> Diagnostic {
    let (code, label, help) = if problem.is_structural() {
        (
            URDF_NOT_A_TREE,
            "this robot description is not one tree",
            "a URDF is one tree: every joint joins two links the file defines, and every link \
             but the root is the child of exactly one joint",
        )
    } else {
        (
            URDF_BAD_VALUE,
            "this robot description has a value out of range",
            "fix the value in the URDF: lengths in metres, angles in radians, masses in \
             kilograms, within the bounds `cellc explain E0407` lists",
        )
    };
    let d = Diagnostic::error(code, format!("in `{path}`, {problem}"))
        .primary(file, span, label)
        .help(help);
    if more > 0 {
        d.note(format!("{more} more problems of this file are not shown"))
    } else {
        d
    }
}

/// What a limit of the graphs counts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GraphMeasure {
    /// States, arcs and adjacent pairs of workspaces.
    Size,
    /// States visited to expand transitions.
    TransitionVisits,
}

/// Where the graphs crossed their limit.
#[derive(Clone, Copy, Debug)]
pub enum GraphAt<'a> {
    /// While counting or building the graph of this object.
    Object(&'a str, Origin),
    /// Counting the adjacent pairs that movable end-effectors' reach makes, before any
    /// graph; this one reaches the most.
    Reach(&'a str, Origin),
}

/// The graphs of the cell would exceed a limit. `biggest` is the movable end-effector that
/// reaches the most workspaces.
pub fn graph_too_large(
    at: Option<GraphAt<'_>>,
    measure: GraphMeasure,
    counted: u64,
    limit: u64,
    biggest: Option<(&str, usize)>,
) -> Diagnostic {
    let what = match measure {
        GraphMeasure::Size => format!(
            "the object-state graphs would have more than {limit} states, arcs and adjacent \
             workspace pairs"
        ),
        GraphMeasure::TransitionVisits => {
            format!("expanding the transitions would visit more than {limit} states")
        }
    };
    let d = Diagnostic::error(GRAPH_TOO_LARGE, what);
    let d = match at {
        Some(GraphAt::Object(name, origin)) => d.primary(
            origin.file,
            origin.name_span,
            format!("{counted} counted up to the graph of `{name}`"),
        ),
        Some(GraphAt::Reach(name, origin)) => d.primary(
            origin.file,
            origin.name_span,
            format!("`{name}` and the others make {counted} pairs of adjacent workspaces"),
        ),
        None => d,
    };
    let d = match biggest {
        Some((holder, reached)) => d.note(format!(
            "movable `{holder}` reaches {reached} workspaces; it moves between every two \
             adjacent ones, with every grasp it holds"
        )),
        None => d,
    };
    d.help(
        "split the cell, or declare `adjacent` pairs so that not every two workspaces an arm \
         reaches are adjacent (see `cellc explain E0320` for the limits)",
    )
}

/// Requirements left unchecked because checking them would exceed the budget.
pub fn expectations_not_checked(left: usize, limit: u64, first: Origin) -> Diagnostic {
    Diagnostic::error(
        EXPECT_TOO_COSTLY,
        format!("{left} requirements are not checked: checking them would visit more than {limit} states and arcs"),
    )
    .primary(first.file, first.span, "the first requirement not checked")
    .help("write fewer `expect` lines, or check a smaller cell; a cell whose requirements are not all checked does not pass")
}

/// Deriving workspaces, or finding who reaches which, would take more box tests than the
/// limit.
pub fn derivation_too_large(origin: Origin, work: u64, limit: u64) -> Diagnostic {
    Diagnostic::error(
        DERIVATION_TOO_LARGE,
        format!(
            "the workspace geometry would take {work} box tests to work out, more than {limit}"
        ),
    )
    .primary(
        origin.file,
        origin.span,
        "workspaces and reach are computed from here",
    )
    .help(
        "use fewer reach boxes, obstacles and workspace boxes (every box face cuts space \
         along its plane), or declare the workspaces and who reaches them",
    )
}
