//! Another object in the way: the fact a planner records when a step of a plan in a world
//! is infeasible only because one of the world's other objects stands where the step
//! needs room (the step is free once that object is taken out of the check).
//!
//! It is a fact with ids, never a sentence: which object blocks, which part of the plan
//! runs into it, and which step it blocks. Explanations word it ("`ball` blocks the
//! put-down at (0.500, -0.644, 0.960), in the way of the object"), and a caller that
//! moves blocking objects out of the way first (`cellc_runtime::Cell::plan_clearing`)
//! reads which object to move. Build-time verification never records one: the cell is
//! verified empty.

use serde::{Deserialize, Serialize};

use crate::ids::{EndEffectorId, ObjectId};

/// One object of the world in the way of one step of a plan.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Blocker {
    /// The object in the way.
    pub by: ObjectId,
    /// What of the plan runs into it.
    pub part: BlockedPart,
    /// The step it blocks.
    pub during: BlockedStep,
}

/// The part of a plan that runs into a blocking object.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum BlockedPart {
    /// The object being moved.
    Object,
    /// A link of an arm.
    Arm(EndEffectorId),
    /// The hand on an arm's tip.
    Hand(EndEffectorId),
}

/// The step of a plan a blocking object is in the way of. Exchanges carry the position of
/// the moved object's frame in the cell (metres), where the exchange would happen.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum BlockedStep {
    /// An arm taking the object from a surface.
    Pick {
        /// The object's position.
        at: [f64; 3],
    },
    /// An arm putting the object down on a surface.
    PutDown {
        /// The object's position.
        at: [f64; 3],
    },
    /// One arm handing the object to another.
    Handoff {
        /// The object's position.
        at: [f64; 3],
    },
    /// The joint motion that leads to a command: the blocking object stands on the
    /// straight joint-space path, which is free without it, and the motion planner found
    /// no way round.
    Motion,
}

impl BlockedStep {
    /// Where the exchange would happen, for the exchanges.
    pub fn position(&self) -> Option<[f64; 3]> {
        match self {
            BlockedStep::Pick { at }
            | BlockedStep::PutDown { at }
            | BlockedStep::Handoff { at } => Some(*at),
            BlockedStep::Motion => None,
        }
    }
}
