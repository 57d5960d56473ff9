//! `object NAME { members }`: an object's shape, symmetries, grasps and resting poses, and
//! the transitions between them.

use super::{Name, Pose, Qualified, Quantity, Shape, StringLit};
use crate::span::Span;

/// `object NAME { members }`.
#[derive(Clone, Debug, PartialEq)]
pub struct ObjectItem {
    /// Name.
    pub name: Name,
    /// Members in source order.
    pub members: Vec<ObjectMember>,
    /// Whole item.
    pub span: Span,
}

/// One line inside an object block.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Debug, PartialEq)]
pub enum ObjectMember {
    /// `shape ...`.
    Shape(ShapeMember),
    /// `symmetry about z [order N]`.
    Symmetry(SymmetryMember),
    /// `grasp NAME ["label"] by HOLDER [at POSE]` or `rest NAME ["label"] on HOLDER [at POSE]`.
    Grasp(GraspMember),
    /// `transition A <-> B, C`.
    Transition(TransitionMember),
}

impl ObjectMember {
    /// Span of the member.
    pub fn span(&self) -> Span {
        match self {
            ObjectMember::Shape(m) => m.span,
            ObjectMember::Symmetry(m) => m.span,
            ObjectMember::Grasp(m) => m.span,
            ObjectMember::Transition(m) => m.span,
        }
    }
}

/// `shape SHAPE`.
#[derive(Clone, Debug, PartialEq)]
pub struct ShapeMember {
    /// The shape.
    pub shape: Shape,
    /// Whole member.
    pub span: Span,
}

/// A coordinate axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Axis {
    /// x.
    X,
    /// y.
    Y,
    /// z.
    Z,
}

impl Axis {
    /// As written.
    pub fn as_str(self) -> &'static str {
        match self {
            Axis::X => "x",
            Axis::Y => "y",
            Axis::Z => "z",
        }
    }
}

/// `symmetry about AXIS [order N]`: the object looks the same after any rotation about
/// the axis (no order) or after rotations by 360°/N.
#[derive(Clone, Debug, PartialEq)]
pub struct SymmetryMember {
    /// Axis in the object frame.
    pub axis: Axis,
    /// Discrete order, `None` for continuous symmetry.
    pub order: Option<(u32, Span)>,
    /// Whole member.
    pub span: Span,
}

/// Which keyword introduced a grasp.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GraspKeyword {
    /// `grasp NAME by HOLDER`.
    Grasp,
    /// `rest NAME on HOLDER`: a resting pose on a surface.
    Rest,
}

/// A grasp or resting pose.
#[derive(Clone, Debug, PartialEq)]
pub struct GraspMember {
    /// `grasp` or `rest`.
    pub keyword: GraspKeyword,
    /// Name, unique in the object.
    pub name: Name,
    /// Human label.
    pub label: Option<StringLit>,
    /// End-effector (abstract cells) or holder kind (geometric cells).
    pub holder: Name,
    /// Pose of the object in the holder's frame.
    pub pose: Option<Pose>,
    /// `from "FILE"`: the poses of a grasp-set file instead of one pose (grasps only).
    pub file: Option<StringLit>,
    /// The family clauses in written order; empty for a single grasp. A member with a
    /// file or any clause is a family: the compiler expands it into members.
    pub family: Vec<FamilyClause>,
    /// Whole member.
    pub span: Span,
}

impl GraspMember {
    /// True when the line declares a family (a file, or family clauses) rather than one
    /// grasp or resting pose.
    pub fn is_family(&self) -> bool {
        self.file.is_some() || !self.family.is_empty()
    }
}

/// One clause of a family: how the holder moves relative to the object from one member
/// to the next. The syntax tree keeps the clause as written; the compiler expands it.
#[derive(Clone, Debug, PartialEq)]
pub enum FamilyClause {
    /// `every STEP about AXIS`: the holder turned about the object's axis by 0, STEP,
    /// 2 STEP, ... up to a full turn.
    Every {
        /// The angle between members.
        step: Quantity,
        /// The object's axis.
        axis: Axis,
        /// The clause.
        span: Span,
    },
    /// `along AXIS at (D1, D2, ...)`: the holder moved along the object's axis by each
    /// offset.
    Along {
        /// The object's axis.
        axis: Axis,
        /// The offsets, at least one.
        offsets: Vec<Quantity>,
        /// The clause.
        span: Span,
    },
}

impl FamilyClause {
    /// Span of the clause.
    pub fn span(&self) -> Span {
        match self {
            FamilyClause::Every { span, .. } | FamilyClause::Along { span, .. } => *span,
        }
    }
}

/// `<->` or `->`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Direction {
    /// Both ways.
    Both,
    /// From the left grasp to each right grasp only.
    OneWay,
}

/// `transition A <-> B, C`.
#[derive(Clone, Debug, PartialEq)]
pub struct TransitionMember {
    /// Left side.
    pub from: Qualified,
    /// Arrow.
    pub direction: Direction,
    /// Right side.
    pub to: Vec<Qualified>,
    /// `matching`: between families, members with the same indices only.
    pub matching: Option<Span>,
    /// Whole member.
    pub span: Span,
}
