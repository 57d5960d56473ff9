//! Diagnostics of a robot's URDF as the compiler reads it (E04xx): a file that cannot be
//! read or parsed, a link or joint it does not have, no chain or nothing movable between
//! the base and the tip, a home beyond a joint's limits.

use cellc_lang::{Diagnostic, FileId, Span};
use cellc_schema::FileError;
use cellc_urdf::ParseError;

use super::codes::*;
use super::trust;

/// A URDF that can't be read (one too large or not a regular file has its own code).
pub fn urdf_unreadable(path: &str, error: &FileError, file: FileId, span: Span) -> Diagnostic {
    robot_file_unreadable("URDF", path, error, None, file, span)
}

/// A robot description file (`URDF` or `SRDF`) that can't be read. `package` is the
/// `package` item's (name, folder) when the file was named `package://NAME/…` through one:
/// a wrong folder there is the likelier cause than the path inside the package.
pub fn robot_file_unreadable(
    what: &str,
    path: &str,
    error: &FileError,
    package: Option<(&str, &str)>,
    file: FileId,
    span: Span,
) -> Diagnostic {
    if let Some(refused) = trust::refused_file(what, path, error, Some((file, span))) {
        return refused;
    }
    let d = Diagnostic::error(
        URDF_UNREADABLE,
        format!("cannot read {what} `{path}`: {error}"),
    )
    .primary(file, span, "referenced here");
    match package {
        Some((name, dir)) => d
            .note(format!("a `package` item declares `{name}` at `{dir}`"))
            .help(format!(
                "check that `package {name} at \"…\"` names the package's own folder (the one that holds its `package.xml`)"
            )),
        None => d.help("check the path: it is relative to the file that declares the robot"),
    }
}

/// A URDF urdf-rs rejects.
pub fn urdf_invalid(path: &str, error: &ParseError, file: FileId, span: Span) -> Diagnostic {
    Diagnostic::error(URDF_INVALID, format!("`{path}` is not a valid URDF"))
        .primary(file, span, "this URDF")
        .note(format!("the URDF reader says: {error}"))
        .help("fix the URDF file (check it with `check_urdf` from ROS, or compare with a known-good model)")
}

/// A link or joint not in the URDF.
pub fn urdf_unknown_link(
    what: &str,
    name: &str,
    path: &str,
    file: FileId,
    span: Span,
    suggestion: Option<&str>,
) -> Diagnostic {
    let help = match suggestion {
        Some(s) => format!("did you mean `{s}`?"),
        None => format!("name a {what} of `{path}`"),
    };
    Diagnostic::error(
        URDF_UNKNOWN_LINK,
        format!("`{path}` has no {what} `{name}`"),
    )
    .primary(file, span, format!("not a {what} of this URDF"))
    .help(help)
}

/// A `home` joint that is not a movable joint of the chain.
pub fn unknown_home_joint(
    joint: &str,
    robot: &str,
    file: FileId,
    span: Span,
    suggestion: Option<&str>,
) -> Diagnostic {
    let help = match suggestion {
        Some(s) => format!("did you mean `{s}`?"),
        None => format!("name a revolute or prismatic joint between the base and tip of `{robot}`"),
    };
    Diagnostic::error(
        URDF_UNKNOWN_LINK,
        format!("`{joint}` is not a movable joint of robot `{robot}`"),
    )
    .primary(file, span, "no such joint between base and tip")
    .help(help)
}

/// No chain from base to tip.
pub fn urdf_no_chain(base: &str, tip: &str, path: &str, file: FileId, span: Span) -> Diagnostic {
    Diagnostic::error(
        URDF_NO_CHAIN,
        format!("in `{path}`, `{tip}` is not below `{base}`"),
    )
    .primary(file, span, "no chain of joints from the base to the tip")
    .help("the tip must be a descendant of the base: swap them or pick other links")
}

/// A chain with nothing to move between the base and the tip.
pub fn urdf_no_movable_joint(
    base: &str,
    tip: &str,
    path: &str,
    file: FileId,
    span: Span,
) -> Diagnostic {
    Diagnostic::error(
        URDF_NO_CHAIN,
        format!("in `{path}`, no movable joint lies between `{base}` and `{tip}`"),
    )
    .primary(file, span, "this robot cannot move its tip")
    .help("pick a base and tip with at least one revolute, continuous or prismatic joint between them")
}

/// A home value beyond a joint limit.
pub fn home_out_of_limits(
    joint: &str,
    value: f64,
    lower: f64,
    upper: f64,
    unit: &str,
    file: FileId,
    span: Span,
) -> Diagnostic {
    let show = |v: f64| {
        if unit == "deg" {
            format!("{:.1} deg", v.to_degrees())
        } else {
            format!("{v:.3} m")
        }
    };
    Diagnostic::error(
        HOME_OUT_OF_LIMITS,
        format!("home value of `{joint}` is outside its limits"),
    )
    .primary(
        file,
        span,
        format!(
            "{} is not in {} .. {}",
            show(value),
            show(lower),
            show(upper)
        ),
    )
    .help(format!(
        "give `{joint}` a value between {} and {}",
        show(lower),
        show(upper)
    ))
}
