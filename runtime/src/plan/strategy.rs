//! The name of what a plan does, read off its path: nothing in the planner chooses a
//! strategy; pick-and-place, handoffs and regrasps emerge from the graph, and this only
//! says which one came out.

use std::fmt;

use cellc_schema::{Artifact, EndEffectorId, Node};

/// What a plan amounts to.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Strategy {
    /// Start and goal are the same state.
    AlreadyThere,
    /// One end-effector carries the object (moves only).
    Carry,
    /// One arm picks the object up from a surface (and keeps it).
    Pick,
    /// One arm puts the object it holds down on a surface.
    Place,
    /// One arm picks the object from a surface and places it on a surface.
    PickAndPlace,
    /// The object passes directly between hands, without a surface in between.
    Handoff {
        /// Hand-to-hand exchanges.
        handoffs: u32,
    },
    /// The object is put down on a surface and picked up again, by the same arm (1) or
    /// another (2), to change grasp.
    RegraspViaSurface {
        /// Distinct arms involved.
        arms: u32,
    },
    /// A longer chain mixing handoffs and surface regrasps (e.g. an assembly line).
    Chain {
        /// Hand-to-hand exchanges.
        handoffs: u32,
        /// Put-downs on intermediate surfaces.
        regrasps: u32,
        /// Distinct movable end-effectors that hold the object.
        movers: u32,
    },
}

impl fmt::Display for Strategy {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Strategy::AlreadyThere => f.write_str("already there"),
            Strategy::Carry => f.write_str("carry"),
            Strategy::Pick => f.write_str("pick"),
            Strategy::Place => f.write_str("place"),
            Strategy::PickAndPlace => f.write_str("pick-and-place"),
            Strategy::Handoff { handoffs: 1 } => f.write_str("handoff"),
            Strategy::Handoff { handoffs } => write!(f, "{handoffs} handoffs"),
            Strategy::RegraspViaSurface { arms: 1 } => {
                f.write_str("single-arm regrasp via surface")
            }
            Strategy::RegraspViaSurface { .. } => f.write_str("dual-arm regrasp via surface"),
            Strategy::Chain {
                handoffs,
                regrasps,
                movers,
            } => write!(
                f,
                "chain of {movers} movers ({handoffs} handoffs, {regrasps} put-downs)"
            ),
        }
    }
}

/// Classifies a simplified state path.
pub fn classify(artifact: &Artifact, states: &[Node]) -> Strategy {
    // The sequence of holders, repeats merged (a move keeps its holder).
    let mut holders: Vec<EndEffectorId> = Vec::new();
    for s in states {
        if holders.last() != Some(&s.end_effector) {
            holders.push(s.end_effector);
        }
    }
    let movable = |e: EndEffectorId| {
        artifact
            .end_effectors
            .get(e.index())
            .is_some_and(|e| e.movable)
    };
    if states.len() <= 1 || (holders.len() == 1 && states.windows(2).all(|w| w[0] == w[1])) {
        return Strategy::AlreadyThere;
    }
    if holders.len() == 1 {
        return Strategy::Carry;
    }
    let mut handoffs = 0;
    let mut regrasps = 0;
    for w in holders.windows(2) {
        if movable(w[0]) && movable(w[1]) {
            handoffs += 1;
        }
    }
    // Intermediate fixed holders: put down and picked up again.
    for (i, &h) in holders.iter().enumerate() {
        if i > 0 && i + 1 < holders.len() && !movable(h) {
            regrasps += 1;
        }
    }
    let mut movers: Vec<EndEffectorId> = holders.iter().copied().filter(|&h| movable(h)).collect();
    movers.sort_unstable();
    movers.dedup();
    let movers = movers.len() as u32;
    match (handoffs, regrasps, movers) {
        (0, 0, 1) if holders.len() == 2 && movable(holders[1]) => Strategy::Pick,
        (0, 0, 1) if holders.len() == 2 => Strategy::Place,
        (0, 0, 1) => Strategy::PickAndPlace,
        (h, 0, _) if h > 0 => Strategy::Handoff { handoffs: h },
        (0, 1, arms @ (1 | 2)) => Strategy::RegraspViaSurface { arms },
        (handoffs, regrasps, movers) => Strategy::Chain {
            handoffs,
            regrasps,
            movers,
        },
    }
}
