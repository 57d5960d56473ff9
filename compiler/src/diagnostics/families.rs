//! Grasp and rest families (`every`, `along`, `from "FILE"`) and the grasp-set files they
//! read: the E0323 to E0327 problems.

use cellc_lang::{Diagnostic, FileId, Span};

use super::codes::*;
use crate::resolve::MAX_FAMILY_MEMBERS;

/// A family whose clauses give no member (a step that is not positive, a file of no
/// rows).
pub fn family_empty(name: &str, file: FileId, span: Span, why: &str) -> Diagnostic {
    Diagnostic::error(
        FAMILY_EMPTY,
        format!("family `{name}` has no members: {why}"),
    )
    .primary(file, span, "this gives no member")
    .help(
        "give a positive step (`every 30 deg about z`), or a grasp-set file with at least one row",
    )
}

/// A family of more members than [`MAX_FAMILY_MEMBERS`].
pub fn family_too_large(name: &str, members: f64, file: FileId, span: Span) -> Diagnostic {
    let count = if members.is_finite() && members < 1e15 {
        format!("{members:.0}")
    } else {
        "too many".to_string()
    };
    Diagnostic::error(
        FAMILY_TOO_LARGE,
        format!(
            "family `{name}` would have {count} members, more than the limit of {MAX_FAMILY_MEMBERS}"
        ),
    )
    .primary(file, span, "these clauses multiply to too many members")
    .help(format!(
        "use a larger step or fewer offsets, or split the family: one family has at most {MAX_FAMILY_MEMBERS} members"
    ))
}

/// `matching` between sides that do not pair up member by member.
pub fn family_mismatch(file: FileId, span: Span, left: &str, right: &str) -> Diagnostic {
    Diagnostic::error(
        FAMILY_MISMATCH,
        format!("`matching` pairs members with the same indices, but {left} and {right} do not pair up"),
    )
    .primary(file, span, "these sides have different members")
    .help("use `matching` between families with the same clauses' counts, or drop it to join every member with every member")
}

/// A family where one grasp or resting pose is needed (a placement, `ARM.GRASP`).
pub fn family_not_a_grasp(
    name: &str,
    first: &str,
    members: usize,
    file: FileId,
    span: Span,
) -> Diagnostic {
    Diagnostic::error(
        FAMILY_NOT_A_GRASP,
        format!("`{name}` is a family of {members} members, not one grasp or resting pose"),
    )
    .primary(file, span, "a family")
    .help(format!(
        "name one member, like `{first}` (see the naming rule in docs/language.md)"
    ))
}

/// A grasp-set file that is not text.
pub fn grasp_file_not_text(path: &str, at: (FileId, Span), why: &str) -> Diagnostic {
    Diagnostic::error(
        BAD_GRASP_FILE,
        format!("grasp-set file `{path}` is not a text file: {why}"),
    )
    .primary(at.0, at.1, "named here")
    .help("name a CSV file with the header `x,y,z,qx,qy,qz,qw` and one pose per row")
}

/// A row (or the header) of a grasp-set file that is not what the format says.
pub fn bad_grasp_row(file: FileId, span: Span, what: &str, label: &str) -> Diagnostic {
    Diagnostic::error(BAD_GRASP_FILE, format!("bad grasp-set file: {what}"))
        .primary(file, span, label.to_string())
        .help("write the header `x,y,z,qx,qy,qz,qw`, then one pose per row: a position in metres and a unit quaternion")
}

/// A grasp-set file of more rows than [`MAX_FAMILY_MEMBERS`].
pub fn grasp_file_too_long(file: FileId, span: Span) -> Diagnostic {
    Diagnostic::error(
        FAMILY_TOO_LARGE,
        format!("grasp-set file has more than {MAX_FAMILY_MEMBERS} rows"),
    )
    .primary(file, span, "the first row over the limit")
    .help(format!(
        "split the file: one family has at most {MAX_FAMILY_MEMBERS} members"
    ))
}
