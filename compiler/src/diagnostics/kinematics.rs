//! Diagnostics of an arm's kinematics as the compiler sees them: a chain that runs into
//! a gripper's finger, and `reach auto` that cannot be computed or finds nothing.

use cellc_lang::{Diagnostic, FileId, Span};

use super::codes::*;
use crate::model::Origin;

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
        cellc_lang::written_name(parent)
    ))
    .note("a finger is not an axis of the arm: planning would slide it to reach poses")
}

/// Why `reach auto` gives no box for an arm.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum ReachAutoProblem {
    /// The compiler was given no kinematics to sample with (a caller other than `cellc`).
    NoKinematics,
    /// The arm can hold no grasp to sample with.
    NoGrasps {
        /// Its hand kind (`None`: it has none).
        kind: Option<String>,
    },
    /// The cell has no surface to reach over.
    NoSurface,
    /// The robot has too few joints to take the poses sampled.
    TooFewJoints {
        /// Its movable joints.
        joints: usize,
    },
    /// No surface has a place where every grasp works.
    NothingReached {
        /// Places tried.
        tried: u64,
    },
}

/// `reach ARM auto` that gives no box.
pub fn reach_auto_failed(arm: &str, problem: &ReachAutoProblem, origin: Origin) -> Diagnostic {
    let (message, label, help) = match problem {
        ReachAutoProblem::NoKinematics => (
            format!("the reach of `{arm}` cannot be computed here"),
            "`reach auto` needs the runtime's kinematics".to_string(),
            "compile with `cellc` (`cellc check`, `cellc build`), which samples the arm's kinematics"
                .to_string(),
        ),
        ReachAutoProblem::NoGrasps { kind } => (
            format!("`{arm}` has no grasp to compute its reach from"),
            "`reach auto` samples where the arm's grasps work".to_string(),
            match kind {
                Some(kind) => format!("declare grasps `by {kind}` (or `by {arm}`) in an object"),
                None => format!("give `{arm}` a hand kind (`with KIND`) and grasps by it"),
            },
        ),
        ReachAutoProblem::NoSurface => (
            format!("the cell has no surface for `{arm}` to reach over"),
            "`reach auto` looks for the arm's reach over each surface".to_string(),
            "declare the surfaces (`surface NAME : KIND box ...`), or write the reach as `reach ARM box ...`"
                .to_string(),
        ),
        ReachAutoProblem::TooFewJoints { joints } => (
            format!("`{arm}` has {joints} joints, too few for `reach auto`"),
            "`reach auto` solves for whole poses of the hand, which take 6 joints".to_string(),
            "write the reach as `reach ARM box center (...) size (...)`".to_string(),
        ),
        ReachAutoProblem::NothingReached { tried } => (
            format!("`reach auto` found no place over any surface where `{arm}` can use every grasp"),
            format!("{tried} places tried"),
            "check the arm's placement and home, and the grasps (`cellc explain E0423`), or write the reach as `reach ARM box ...`"
                .to_string(),
        ),
    };
    Diagnostic::error(REACH_AUTO_FAILED, message)
        .primary(origin.file, origin.span, label)
        .help(help)
}
