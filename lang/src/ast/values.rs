//! The values the items are written with: names (plain or quoted), quantities with their
//! units as written, vectors, rotations and poses, boxes, string literals and shapes.

use crate::span::Span;

/// A name as written: plain (`left_arm`) or quoted (`` `top_x- (copy)` ``).
#[derive(Clone, Debug, PartialEq)]
pub struct Name {
    /// The name without quotes.
    pub text: String,
    /// Span of the name including quotes.
    pub span: Span,
}

impl Name {
    /// True when the name must be quoted to be written back (it is not a plain
    /// identifier).
    pub fn needs_quotes(&self) -> bool {
        needs_quotes(&self.text)
    }
}

/// True when `text` is not a plain identifier (`[A-Za-z_][A-Za-z0-9_]*`).
pub fn needs_quotes(text: &str) -> bool {
    let mut chars = text.chars();
    match chars.next() {
        Some(c) if c.is_ascii_alphabetic() || c == '_' => {}
        _ => return true,
    }
    !chars.all(|c| c.is_ascii_alphanumeric() || c == '_')
}

/// `name` or `object.name` (a grasp of another object, in transitions).
#[derive(Clone, Debug, PartialEq)]
pub struct Qualified {
    /// The object part, when written.
    pub object: Option<Name>,
    /// The last part.
    pub name: Name,
    /// The whole reference.
    pub span: Span,
}

/// A unit of measure written after a number.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Unit {
    /// Metres.
    M,
    /// Centimetres.
    Cm,
    /// Millimetres.
    Mm,
    /// Degrees.
    Deg,
    /// Radians.
    Rad,
}

impl Unit {
    /// As written in the language.
    pub fn as_str(self) -> &'static str {
        match self {
            Unit::M => "m",
            Unit::Cm => "cm",
            Unit::Mm => "mm",
            Unit::Deg => "deg",
            Unit::Rad => "rad",
        }
    }

    /// True for length units.
    pub fn is_length(self) -> bool {
        matches!(self, Unit::M | Unit::Cm | Unit::Mm)
    }

    /// Factor to SI (metres or radians).
    pub fn to_si(self) -> f64 {
        match self {
            Unit::M | Unit::Rad => 1.0,
            Unit::Cm => 0.01,
            Unit::Mm => 0.001,
            Unit::Deg => std::f64::consts::PI / 180.0,
        }
    }

    /// Parses a unit as written.
    pub fn parse(text: &str) -> Option<Unit> {
        Some(match text {
            "m" => Unit::M,
            "cm" => Unit::Cm,
            "mm" => Unit::Mm,
            "deg" => Unit::Deg,
            "rad" => Unit::Rad,
            _ => return None,
        })
    }
}

/// A number with an optional unit, e.g. `0.6`, `600 mm`, `-90 deg`.
#[derive(Clone, Debug, PartialEq)]
pub struct Quantity {
    /// The number as written (kept so formatting never changes a value's spelling).
    pub number: String,
    /// The parsed value.
    pub value: f64,
    /// The unit, if one was written.
    pub unit: Option<Unit>,
    /// Span of number and unit.
    pub span: Span,
}

/// A length or angle per second, squared or cubed: `rad/s2`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct RateUnit {
    /// The length or angle unit.
    pub base: Unit,
    /// The power of the second (1 to 3).
    pub order: u8,
}

impl RateUnit {
    /// Parses a rate unit as written (`deg/s`, `m/s2`).
    pub fn parse(text: &str) -> Option<RateUnit> {
        let (base, per) = text.split_once("/s")?;
        let order = match per {
            "" => 1,
            "2" => 2,
            "3" => 3,
            _ => return None,
        };
        Some(RateUnit {
            base: Unit::parse(base)?,
            order,
        })
    }

    /// As written in the language.
    pub fn as_string(self) -> String {
        match self.order {
            1 => format!("{}/s", self.base.as_str()),
            n => format!("{}/s{n}", self.base.as_str()),
        }
    }
}

/// A number with an optional rate unit, e.g. `1.5 rad/s`, `4 rad/s2`, `120 deg/s`.
#[derive(Clone, Debug, PartialEq)]
pub struct Rate {
    /// The number as written.
    pub number: String,
    /// The parsed value.
    pub value: f64,
    /// The unit, if one was written.
    pub unit: Option<RateUnit>,
    /// Span of number and unit.
    pub span: Span,
}

/// `(x, y, z)`.
#[derive(Clone, Debug, PartialEq)]
pub struct Vec3 {
    /// The three components.
    pub parts: [Quantity; 3],
    /// Span including parentheses.
    pub span: Span,
}

/// A rotation as written.
#[derive(Clone, Debug, PartialEq)]
pub enum Rotation {
    /// `rpy (roll, pitch, yaw)`: fixed-axis X, then Y, then Z.
    Rpy(Vec3, Span),
    /// `quat (w, x, y, z)`.
    Quat([Quantity; 4], Span),
}

impl Rotation {
    /// Span of the whole rotation clause.
    pub fn span(&self) -> Span {
        match self {
            Rotation::Rpy(_, s) | Rotation::Quat(_, s) => *s,
        }
    }
}

/// `at (x, y, z) [rpy (...) | quat (...)]`.
#[derive(Clone, Debug, PartialEq)]
pub struct Pose {
    /// Translation.
    pub at: Vec3,
    /// Rotation, identity when absent.
    pub rotation: Option<Rotation>,
    /// Whole pose.
    pub span: Span,
}

/// `box center (x, y, z) size (dx, dy, dz)`: an axis-aligned cuboid.
#[derive(Clone, Debug, PartialEq)]
pub struct Aabb {
    /// Centre.
    pub center: Vec3,
    /// Edge lengths.
    pub size: Vec3,
    /// Whole clause.
    pub span: Span,
}

/// A string literal: its value (escapes applied) and span (with quotes).
#[derive(Clone, Debug, PartialEq)]
pub struct StringLit {
    /// Value.
    pub value: String,
    /// Span including quotes.
    pub span: Span,
}

/// A primitive or mesh shape.
#[derive(Clone, Debug, PartialEq)]
pub enum Shape {
    /// `box size (dx, dy, dz)`, centred on the frame.
    Box {
        /// Edge lengths.
        size: Vec3,
    },
    /// `cylinder radius R height H`, axis along z, centred on the frame.
    Cylinder {
        /// Radius.
        radius: Quantity,
        /// Height.
        height: Quantity,
    },
    /// `sphere radius R`.
    Sphere {
        /// Radius.
        radius: Quantity,
    },
    /// `mesh "file.stl"`.
    Mesh {
        /// Path relative to the declaring file.
        path: StringLit,
    },
}

/// A shape placed in a frame (hand collision bodies).
#[derive(Clone, Debug, PartialEq)]
pub struct Solid {
    /// The shape.
    pub shape: Shape,
    /// Where, in the parent frame (identity when absent).
    pub pose: Option<Pose>,
    /// Whole solid.
    pub span: Span,
}
