//! Diagnostics of an arm's kinematics as the compiler sees them: a chain that runs into
//! a gripper's finger.

use cellc_lang::{Diagnostic, FileId, Span};

use super::codes::*;

/// A finger's prismatic joint between the base and the tip of a robot: the tip was put
/// on a finger, so inverse kinematics would slide the finger as an axis of the arm.
pub fn finger_on_chain(
    joint: &str,
    stroke: f64,
    parent: &str,
    tip: &str,
    file: FileId,
    tip_span: Span,
) -> Diagnostic {
    Diagnostic::error(
        FINGER_ON_CHAIN,
        format!("joint `{joint}` between the base and the tip `{tip}` moves a finger"),
    )
    .primary(
        file,
        tip_span,
        format!(
            "this tip puts `{joint}` (prismatic, {:.0} mm of stroke, after the arm's turning joints) on the chain",
            stroke * 1000.0
        ),
    )
    .help(format!(
        "end the chain above the fingers, at `tip {}`, and describe the gripper as a `hand` kind with its solids",
        written(parent)
    ))
    .note("a finger is not an axis of the arm: planning would slide it to reach poses")
}

/// A name as the language writes it: quoted when it is not a plain identifier or is a
/// reserved word.
fn written(name: &str) -> String {
    if cellc_lang::ast::needs_quotes(name) || cellc_lang::phrases::RESERVED.contains(&name) {
        format!("`{name}`")
    } else {
        name.to_string()
    }
}
