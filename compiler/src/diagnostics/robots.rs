//! Diagnostics of robot files as ROS ships them: packages that cannot be found, xacro
//! files given as URDFs, SRDFs that do not parse or contradict their URDF, and the names
//! a cell takes from an SRDF (groups, group states).

use cellc_lang::{Diagnostic, FileId, Span};
use cellc_urdf::{GroupChainError, SrdfError, SrdfProblem};

use super::codes::*;
use crate::model::Origin;

/// What names a file of a package that could not be found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NamedBy<'a> {
    /// The cell's `robot` item, as its URDF or SRDF.
    Cell,
    /// A mesh of the URDF at this path.
    Mesh(&'a str),
}

/// `package://NAME/...` when no folder of the package path holds `NAME`.
pub fn unresolved_package(
    package: &str,
    uri: &str,
    named_by: NamedBy<'_>,
    searched: &[String],
    file: FileId,
    span: Span,
) -> Diagnostic {
    let (message, label) = match named_by {
        NamedBy::Cell => (
            format!("cannot find ROS package `{package}` of `{uri}`"),
            "names a file of this package".to_string(),
        ),
        NamedBy::Mesh(urdf) => (
            format!("cannot find ROS package `{package}` of mesh `{uri}` in `{urdf}`"),
            "this robot's URDF names a mesh of the package".to_string(),
        ),
    };
    let looked = if searched.is_empty() {
        "no package was declared and the package path is empty".to_string()
    } else {
        format!(
            "looked for `{package}/package.xml` in {}",
            searched
                .iter()
                .map(|d| format!("`{d}`"))
                .collect::<Vec<_>>()
                .join(", ")
        )
    };
    Diagnostic::error(UNRESOLVED_PACKAGE, message)
        .primary(file, span, label)
        .note(looked)
        .help(format!(
            "point cellc at the package's folder: write `package {package} at \"DIR\"` in the \
             cell (relative to the cell file), or pass `--package-path DIR` (or set \
             `ROS_PACKAGE_PATH`) with a folder that holds `{package}/`"
        ))
}

/// A malformed `package://` URI (no package name, or nothing after it).
pub fn bad_package_uri(uri: &str, file: FileId, span: Span) -> Diagnostic {
    Diagnostic::error(
        UNRESOLVED_PACKAGE,
        format!("`{uri}` is not a `package://` URI cellc can resolve"),
    )
    .primary(file, span, "here")
    .help("write `package://NAME/path/inside/the/package`")
}

/// A package declared twice with different folders.
pub fn package_declared_twice(name: &str, first: Origin, again: Origin) -> Diagnostic {
    Diagnostic::error(
        DUPLICATE_NAME,
        format!("package `{name}` is declared twice, with different folders"),
    )
    .primary(again.file, again.name_span, "declared again here")
    .secondary(first.file, first.name_span, "first declared here")
    .help(format!("keep one `package {name} at \"...\"` line"))
}

/// A xacro file given where a URDF is needed.
pub fn xacro_file(path: &str, file: FileId, span: Span) -> Diagnostic {
    Diagnostic::error(XACRO_FILE, format!("`{path}` is a xacro file, not a URDF"))
        .primary(file, span, "a URDF is needed here")
        .note("xacro files hold macros and properties that the `xacro` tool expands into a URDF")
        .help(format!(
            "expand it once with ROS's xacro, `xacro {path} > {}`, and name the output here",
            expanded_name(path)
        ))
}

/// `robot.urdf.xacro` -> `robot.urdf`; `arm.xacro` -> `arm.urdf`.
fn expanded_name(path: &str) -> String {
    let stem = path
        .strip_suffix(".xacro")
        .or_else(|| path.strip_suffix(".XACRO"))
        .unwrap_or(path);
    if stem.to_ascii_lowercase().ends_with(".urdf") {
        stem.to_string()
    } else {
        format!("{stem}.urdf")
    }
}

/// An SRDF that does not parse.
pub fn srdf_invalid(path: &str, error: &SrdfError, file: FileId, span: Span) -> Diagnostic {
    Diagnostic::error(
        SRDF_INVALID,
        format!("`{path}` is not a valid SRDF: {error}"),
    )
    .primary(file, span, "this SRDF")
    .help("fix the SRDF file (MoveIt's setup assistant writes valid ones)")
}

/// An SRDF that names what its URDF does not define.
pub fn srdf_problem(
    path: &str,
    urdf: &str,
    problem: &SrdfProblem,
    file: FileId,
    span: Span,
    more: usize,
) -> Diagnostic {
    let d = Diagnostic::error(SRDF_INVALID, format!("in `{path}`, {problem}"))
        .primary(file, span, "this SRDF")
        .help(format!(
            "an SRDF describes one URDF: check that `{urdf}` is the robot it was written for"
        ));
    if more > 0 {
        d.note(format!("{more} more problems of this file are not shown"))
    } else {
        d
    }
}

/// `home NAME` or `group NAME` that the robot's SRDF does not define (or a robot without
/// an SRDF).
pub fn unknown_srdf_name(
    what: &str,
    name: &str,
    robot: &str,
    srdf: Option<&str>,
    file: FileId,
    span: Span,
    suggestion: Option<&str>,
) -> Diagnostic {
    let (message, help) = match srdf {
        None => (
            format!("robot `{robot}` has no SRDF, so it has no {what} `{name}`"),
            format!("add `srdf \"FILE.srdf\"` to `robot {robot}`, or write the values out"),
        ),
        Some(srdf) => (
            format!("`{srdf}` defines no {what} `{name}`"),
            match suggestion {
                Some(s) => format!("did you mean `{s}`?"),
                None => format!("name a {what} of `{srdf}`"),
            },
        ),
    };
    Diagnostic::error(UNKNOWN_SRDF_NAME, message)
        .primary(file, span, format!("not a {what} of robot `{robot}`"))
        .help(help)
}

/// A group state of one name defined for several groups, none of them the robot's.
pub fn ambiguous_group_state(
    name: &str,
    groups: &[&str],
    robot: &str,
    file: FileId,
    span: Span,
) -> Diagnostic {
    Diagnostic::error(
        UNKNOWN_SRDF_NAME,
        format!(
            "group state `{name}` is defined for {} groups: {}",
            groups.len(),
            groups
                .iter()
                .map(|g| format!("`{g}`"))
                .collect::<Vec<_>>()
                .join(", ")
        ),
    )
    .primary(file, span, "which one is meant is not said")
    .help(format!(
        "write `group GROUP` on `robot {robot}` to say which group the arm is"
    ))
}

/// A robot item that gives no tip, or names a group that gives no chain.
pub fn no_chain_given(
    robot: &str,
    group: Option<(&str, &GroupChainError)>,
    file: FileId,
    span: Span,
) -> Diagnostic {
    match group {
        None => Diagnostic::error(
            CHAIN_NOT_GIVEN,
            format!("robot `{robot}` names no tip link"),
        )
        .primary(file, span, "the chain ends nowhere")
        .help("write `tip LINK` (the link the hand is mounted on), or `srdf \"...\" group GROUP` to take it from a planning group"),
        Some((group, error)) => Diagnostic::error(
            CHAIN_NOT_GIVEN,
            format!("group `{group}` gives robot `{robot}` no base and tip: {error}"),
        )
        .primary(file, span, "the chain is taken from this group")
        .help("name a group with a `<chain>` or with the joints of one serial chain, or write `base LINK tip LINK`"),
    }
}

/// `home NAME` whose group state sets no joint between the robot's base and tip.
pub fn state_sets_no_chain_joint(
    state: &str,
    group: &str,
    robot: &str,
    file: FileId,
    span: Span,
) -> Diagnostic {
    Diagnostic::error(
        UNKNOWN_SRDF_NAME,
        format!("group state `{state}` (of group `{group}`) sets no joint of robot `{robot}`"),
    )
    .primary(file, span, "this state moves other joints")
    .help("name a state of the group that holds the robot's chain (the arm, not the hand)")
}
