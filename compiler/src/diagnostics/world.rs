//! Diagnostics of the `world` (where the objects start) and of `task`s.

use cellc_lang::{Diagnostic, FileId, Span};

use super::codes::*;
use crate::model::Origin;

/// A second `world` item, in the cell or in a library it includes: a cell starts in one
/// world. Both origins' name spans are the `world` keyword.
pub fn second_world(first: Origin, again: Origin) -> Diagnostic {
    Diagnostic::error(SECOND_WORLD, "the cell has two `world` items")
        .primary(again.file, again.name_span, "a second `world`")
        .secondary(first.file, first.name_span, "the first `world` is here")
        .help("put every object's line into one `world` (a library's `world` counts too)")
}

/// One object on two lines of the world.
pub fn placed_twice(object: &str, first: Origin, again: Origin) -> Diagnostic {
    Diagnostic::error(
        PLACED_TWICE,
        format!("`{object}` is placed twice in the world"),
    )
    .primary(again.file, again.span, "placed again here")
    .secondary(first.file, first.span, "first placed here")
    .help(format!(
        "keep one line for `{object}`: an object starts in one place"
    ))
}

/// What a bare world placement `HOLDER[.GRASP]` lacks.
#[derive(Clone, Copy, Debug)]
pub enum Incomplete<'a> {
    /// The holder is not an arm (a surface, or an abstract end-effector), so nothing gives
    /// the object's pose: it needs `in WORKSPACE` or `at POSE`. The example placement is
    /// the holder as written.
    NotAnArm {
        /// `HOLDER[.GRASP]` as written.
        written: &'a str,
    },
    /// The holder is an arm but no grasp is named, so the pose cannot follow from its
    /// joints. The suggestion is a grasp of the object the arm can hold, if any.
    NoGrasp {
        /// The arm.
        arm: &'a str,
        /// A grasp to name.
        suggestion: Option<&'a str>,
    },
}

/// `ball: table.lying` (a surface without `in` or `at`) or `pitcher: left` (an arm without
/// its grasp).
pub fn world_placement_incomplete(
    object: &str,
    what: Incomplete<'_>,
    file: FileId,
    span: Span,
) -> Diagnostic {
    match what {
        Incomplete::NotAnArm { written } => Diagnostic::error(
            WORLD_PLACEMENT_INCOMPLETE,
            format!("the world does not say where `{object}` is"),
        )
        .primary(file, span, "no workspace or pose")
        .help(format!(
            "write `{written} in WORKSPACE` or `{written} at (x, y, z)`: only an arm's grasp gives the pose by itself"
        )),
        Incomplete::NoGrasp { arm, suggestion } => {
            let help = match suggestion {
                Some(grasp) => format!(
                    "name the grasp `{arm}` holds it with, e.g. `{arm}.{grasp}`: the pose follows from the arm's joints and the grasp"
                ),
                None => format!(
                    "`{arm}` has no grasp of `{object}`: declare one, or place `{object}` `in` a workspace or `at` a pose"
                ),
            };
            Diagnostic::error(
                WORLD_PLACEMENT_INCOMPLETE,
                format!("the world does not say how `{arm}` holds `{object}`"),
            )
            .primary(file, span, "no grasp")
            .help(help)
        }
    }
}

/// `task t {}`.
pub fn empty_task(name: &str, origin: Origin) -> Diagnostic {
    Diagnostic::error(EMPTY_TASK, format!("task `{name}` has no steps"))
        .primary(origin.file, origin.name_span, "nothing to do")
        .help("add a step like `OBJECT to HOLDER in WORKSPACE`, or remove the task")
}
