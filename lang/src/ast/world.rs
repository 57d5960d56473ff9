//! The syntax of the world and of tasks: where the objects start (`world`), and moves
//! planned one after the other (`task`).

use super::{Name, Qualified, RequestPlacement};
use crate::span::Span;

/// `world { OBJECT: PLACEMENT ... }`: where the objects are when the cell starts (objects
/// not listed are absent).
#[derive(Clone, Debug, PartialEq)]
pub struct WorldItem {
    /// The lines, in source order.
    pub entries: Vec<WorldEntry>,
    /// Whole item.
    pub span: Span,
}

/// `OBJECT: PLACEMENT`, one line of a `world`.
#[derive(Clone, Debug, PartialEq)]
pub struct WorldEntry {
    /// The object.
    pub object: Name,
    /// Where it is.
    pub placement: WorldPlacement,
    /// The whole line.
    pub span: Span,
}

/// Where an object of the world is.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Debug, PartialEq)]
pub enum WorldPlacement {
    /// `HOLDER[.GRASP] in WORKSPACE` or `HOLDER[.GRASP] at POSE`, as in a request.
    Placed(RequestPlacement),
    /// `HOLDER[.GRASP]` alone: held by an arm, at the pose its joints give. The grammar
    /// also takes a surface or a missing grasp here, so that the compiler can say what is
    /// missing rather than a syntax error.
    Bare(Qualified),
}

impl WorldPlacement {
    /// The holder, optionally with its grasp, as written.
    pub fn holder(&self) -> &Qualified {
        match self {
            WorldPlacement::Placed(p) => &p.holder,
            WorldPlacement::Bare(q) => q,
        }
    }

    /// Span of the whole placement.
    pub fn span(&self) -> Span {
        match self {
            WorldPlacement::Placed(p) => p.span,
            WorldPlacement::Bare(q) => q.span,
        }
    }
}

/// `task NAME { OBJECT to PLACEMENT ... }`: moves planned and executed in order, each from
/// where the previous ones left the objects.
#[derive(Clone, Debug, PartialEq)]
pub struct TaskItem {
    /// Task name.
    pub name: Name,
    /// The moves, in order.
    pub steps: Vec<TaskStep>,
    /// Whole item.
    pub span: Span,
}

/// `OBJECT to PLACEMENT`, one move of a task.
#[derive(Clone, Debug, PartialEq)]
pub struct TaskStep {
    /// The object moved.
    pub object: Name,
    /// Where it must go.
    pub to: RequestPlacement,
    /// The whole line.
    pub span: Span,
}
