//! Diagnostics of joint limits: a `limits` line (a joint the chain lacks, a limit given
//! twice), a `joint_limits.yaml` that cannot be read or is not of MoveIt's shape (E0328),
//! and joints timed with a default limit (W0007).

use cellc_lang::{Diagnostic, FileId, Span};

use super::codes::*;
use crate::model::Origin;

/// A limit (or a robot's joint limits file) given twice at one level.
pub fn limit_set_twice(what: &str, file: FileId, span: Span, first: Origin) -> Diagnostic {
    Diagnostic::error(LIMIT_SET_TWICE, format!("{what} is given twice"))
        .primary(file, span, "given again here")
        .secondary(first.file, first.span, "first given here")
        .help(format!(
            "give {what} once (a joint's own line already wins over its robot's)"
        ))
}

/// A `limits ROBOT.JOINT` line naming no movable joint of the robot's chain.
pub fn unknown_limits_joint(
    joint: &str,
    robot: &str,
    file: FileId,
    span: Span,
    suggestion: Option<&str>,
) -> Diagnostic {
    super::unknown_home_joint(joint, robot, file, span, suggestion)
}

/// A joint limits file that cannot be read (one too large or not a regular file has its
/// own code).
pub fn limits_file_unreadable(
    path: &str,
    error: &cellc_schema::FileError,
    file: FileId,
    span: Span,
) -> Diagnostic {
    super::refused_file("joint limits file", path, error, Some((file, span))).unwrap_or_else(|| {
        Diagnostic::error(
            FILE_UNREADABLE,
            format!("cannot read joint limits file `{path}`: {error}"),
        )
        .primary(file, span, "named here")
        .help("check the path: it is relative to the file that names it, or a `package://` URI")
    })
}

/// A joint limits file that is not text (binary, not UTF-8): described, never quoted.
pub fn limits_file_not_text(path: &str, why: &str, file: FileId, span: Span) -> Diagnostic {
    Diagnostic::error(
        BAD_LIMITS_FILE,
        format!("joint limits file `{path}` is not text: {why}"),
    )
    .primary(file, span, "named here")
    .help("name MoveIt's `joint_limits.yaml` (a text file) of this robot")
}

/// A joint limits file that is not of MoveIt's shape, at the place in it.
pub fn bad_limits_file(path: &str, message: &str, at: (FileId, Span), named: Origin) -> Diagnostic {
    Diagnostic::error(
        BAD_LIMITS_FILE,
        format!("joint limits file `{path}`: {message}"),
    )
    .primary(at.0, at.1, "here")
    .secondary(named.file, named.span, "read for this line")
    .help(
        "write it as MoveIt does: `joint_limits:`, then per joint `has_velocity_limits: true` and `max_velocity: 1.5` (rad/s or m/s), likewise for acceleration and jerk",
    )
}

/// A robot-wide limit whose unit does not fit one of the robot's joints.
pub fn robot_limit_does_not_fit(
    d: Diagnostic,
    robot: &str,
    joint: &str,
    prismatic: bool,
) -> Diagnostic {
    let kind = if prismatic { "prismatic" } else { "revolute" };
    d.note(format!(
        "this line holds for every joint of `{robot}`, and `{joint}` is {kind}: give it its own `limits {robot}.{joint} ...` line"
    ))
}

/// The joints of a robot timed with a default limit, because none is declared (an
/// acceleration limit) or given anywhere (a velocity limit). `defaults` is the default
/// with its unit, `joints` the joints' names.
pub fn missing_limits(
    limit: &str,
    robot: &str,
    joints: &[&str],
    defaults: &str,
    origin: Origin,
    help: String,
) -> Diagnostic {
    const SHOWN: usize = 8;
    let mut names: Vec<String> = joints
        .iter()
        .take(SHOWN)
        .map(|j| format!("`{j}`"))
        .collect();
    if joints.len() > SHOWN {
        names.push(format!("{} more", joints.len() - SHOWN));
    }
    let which = if joints.len() == 1 {
        format!("joint {}", names[0])
    } else {
        format!("{} joints ({})", joints.len(), names.join(", "))
    };
    Diagnostic::warning(
        MISSING_LIMITS,
        format!("robot `{robot}` has no {limit} limit for {which}"),
    )
    .primary(
        origin.file,
        origin.name_span,
        format!("timed with the default, {defaults}"),
    )
    .help(help)
}
