//! Diagnostics of units and values (E02xx): a bare number where a unit is needed, a unit
//! of the wrong dimension or set twice, numbers out of their domain, weights set twice.

use cellc_lang::{Diagnostic, FileId, Span};

use super::codes::*;
use crate::model::Origin;

/// What a quantity should measure.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dimension {
    /// Metres.
    Length,
    /// Radians.
    Angle,
    /// A pure number (quaternion components).
    Number,
    /// A joint limit: a length (`linear`) or angle per second to the `order` (1 to 3).
    Rate {
        /// Metres (a prismatic joint) rather than radians.
        linear: bool,
        /// The power of the second.
        order: u8,
    },
}

impl Dimension {
    fn describe(self) -> &'static str {
        match self {
            Dimension::Length => "a length",
            Dimension::Angle => "an angle",
            Dimension::Number => "a plain number",
            Dimension::Rate { linear, order } => match (linear, order) {
                (true, 1) => "a linear velocity",
                (true, 2) => "a linear acceleration",
                (true, _) => "a linear jerk",
                (false, 1) => "an angular velocity",
                (false, 2) => "an angular acceleration",
                (false, _) => "an angular jerk",
            },
        }
    }

    /// The units that measure it, for help lines.
    fn units(self) -> String {
        match self {
            Dimension::Length => "`m`, `cm` or `mm`".to_string(),
            Dimension::Angle => "`deg` or `rad`".to_string(),
            Dimension::Number => "no unit".to_string(),
            Dimension::Rate { linear, order } => {
                let per = if order == 1 {
                    "/s".to_string()
                } else {
                    format!("/s{order}")
                };
                if linear {
                    format!("`m{per}`, `cm{per}` or `mm{per}`")
                } else {
                    format!("`rad{per}` or `deg{per}`")
                }
            }
        }
    }
}

/// A bare number where a unit is needed and the file declares no default.
pub fn missing_unit(dimension: Dimension, file: FileId, span: Span) -> Diagnostic {
    let (example, units) = match dimension {
        Dimension::Angle => ("90 deg", "units m, deg"),
        Dimension::Rate { linear: false, .. } => ("2 rad/s2", "units m, rad"),
        Dimension::Rate { linear: true, .. } => ("0.5 m/s", "units m, deg"),
        _ => ("0.5 m", "units m, deg"),
    };
    Diagnostic::error(
        MISSING_UNIT,
        format!("{} without a unit", dimension.describe()),
    )
    .primary(file, span, "which unit is this in?")
    .help(format!(
        "write the unit (`{example}`) or declare `{units}` at the top of the file"
    ))
}

/// A unit of the wrong dimension.
pub fn wrong_unit(dimension: Dimension, unit: &str, file: FileId, span: Span) -> Diagnostic {
    let fix = match dimension {
        Dimension::Number => "remove the unit".to_string(),
        _ => format!("use {}", dimension.units()),
    };
    Diagnostic::error(
        WRONG_UNIT,
        format!("expected {}, found `{unit}`", dimension.describe()),
    )
    .primary(
        file,
        span,
        format!("`{unit}` is not {}", dimension.describe()),
    )
    .help(fix)
}

/// A quaternion of non-unit length.
pub fn not_a_rotation(norm: f64, file: FileId, span: Span) -> Diagnostic {
    Diagnostic::error(NOT_A_ROTATION, "this quaternion is not a rotation")
        .primary(
            file,
            span,
            format!("its length is {norm:.4}, a rotation's is 1"),
        )
        .help("normalise the quaternion (divide each part by its length), or use `rpy (r, p, y)`")
}

/// A non-positive size.
pub fn not_positive(what: &str, value: f64, file: FileId, span: Span) -> Diagnostic {
    Diagnostic::error(NOT_POSITIVE, format!("{what} must be positive"))
        .primary(file, span, format!("this is {value}"))
        .help(format!("use {what} greater than zero"))
}

/// A negative or non-finite weight.
pub fn bad_weight(value: f64, file: FileId, span: Span) -> Diagnostic {
    Diagnostic::error(BAD_WEIGHT, "arc weights must be finite and not negative")
        .primary(file, span, format!("this weight is {value}"))
        .help("use a weight of zero or more; the shortest-path search needs it")
}

/// `symmetry about z order 0`.
pub fn bad_symmetry_order(file: FileId, span: Span) -> Diagnostic {
    Diagnostic::error(BAD_SYMMETRY_ORDER, "a symmetry order must be at least 1")
        .primary(file, span, "order 0")
        .help("write `order N` for a symmetry under rotations by 360°/N, or drop `order` for any angle")
}

/// `1e999`.
pub fn not_finite(file: FileId, span: Span) -> Diagnostic {
    Diagnostic::error(NOT_FINITE, "this number is too large")
        .primary(file, span, "beyond the range of a 64-bit float")
        .help("write a number below 1e308 (cell dimensions are metres and radians)")
}

/// `weights move 0.1` twice (also across included files).
pub fn weight_set_twice(what: &str, file: FileId, span: Span, first: Origin) -> Diagnostic {
    Diagnostic::error(WEIGHT_SET_TWICE, format!("the {what} weight is set twice"))
        .primary(file, span, "set again here")
        .secondary(first.file, first.span, "first set here")
        .help(format!(
            "set the {what} weight once, in the cell (not in a library it includes)"
        ))
}

/// Two length units or two angle units.
pub fn conflicting_units(file: FileId, span: Span, first: Span, what: &str) -> Diagnostic {
    Diagnostic::error(CONFLICTING_UNITS, format!("the {what} unit is set twice"))
        .primary(file, span, "set again here")
        .secondary(file, first, "first set here")
        .help(format!("keep one {what} unit per file"))
}
