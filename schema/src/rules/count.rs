//! How large a cell's graphs would be, counted before they are built.
//!
//! Memory grows with the graphs, and a cell of a few megabytes can ask for billions of
//! states and arcs: an arm that reaches `n` workspaces with derived adjacency moves
//! between `n (n - 1)` pairs, with every grasp it holds. [`CellRules::count`] counts the
//! pieces [`CellRules::for_each_arc`] builds from (see `arcs.rs`), cheapest first, and
//! stops at the first limit crossed, so a cell over a limit is refused in time
//! proportional to the limit, not to its graphs.

use std::collections::BTreeMap;

use super::arcs::Exchanges;
use super::{CellRules, ObjectRules};
use crate::ids::{EndEffectorId, GraspId, ObjectId};

/// The limits of a count.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Limits {
    /// The most states, arcs and adjacent workspace pairs the graphs may have in all
    /// (pairs counted per movable end-effector's reach before repeats are removed, when
    /// adjacency is derived).
    pub size: u64,
    /// The most states and pairs of holders the transitions may visit in all: a
    /// transition visits the states of its two grasps to find the workspaces they share,
    /// and every pair of holders in a shared workspace, so many transitions between
    /// grasps with many states cost time even when few arcs result.
    pub visits: u64,
}

/// Which limit a count crossed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Limit {
    /// [`Limits::size`].
    Size,
    /// [`Limits::visits`].
    Visits,
}

/// Where and how a count crossed a limit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Exceeded {
    /// The limit crossed.
    pub limit: Limit,
    /// What was counted of that measure when it was crossed (more than the limit).
    pub counted: u64,
    /// The object whose graph crossed it (index into the objects counted); `None` when
    /// the adjacent pairs alone do.
    pub object: Option<ObjectId>,
}

/// The running count of both measures.
struct Tally {
    limits: Limits,
    size: u64,
    visits: u64,
}

impl Tally {
    fn size(&mut self, n: u64) -> Result<(), Limit> {
        self.size = self.size.saturating_add(n);
        if self.size > self.limits.size {
            return Err(Limit::Size);
        }
        Ok(())
    }

    fn visits(&mut self, n: u64) -> Result<(), Limit> {
        self.visits = self.visits.saturating_add(n);
        if self.visits > self.limits.visits {
            return Err(Limit::Visits);
        }
        Ok(())
    }

    fn exceeded(&self, limit: Limit, object: Option<ObjectId>) -> Exceeded {
        Exceeded {
            limit,
            counted: match limit {
                Limit::Size => self.size,
                Limit::Visits => self.visits,
            },
            object,
        }
    }
}

impl CellRules {
    /// The size of the graphs of `objects` (their states and arcs) plus the adjacent
    /// pairs an artifact records, when within `limits`. Counted cheapest first: the
    /// adjacent pairs (by formula when derived), then every object's states and moves
    /// (per holder and grasp: the states by reach, the moves by formula or from the
    /// declared pairs, found once per end-effector), then every object's transitions,
    /// met workspace by workspace as the graph meets them, with the visits that takes.
    pub fn count(&self, objects: &[ObjectRules], limits: Limits) -> Result<u64, Exceeded> {
        let mut tally = Tally {
            limits,
            size: 0,
            visits: 0,
        };
        tally.size = match self.adjacent_pairs(limits.size) {
            Ok(pairs) => pairs.len() as u64,
            Err(listed) => listed,
        };
        if tally.size > limits.size {
            return Err(tally.exceeded(Limit::Size, None));
        }
        let mut moves: BTreeMap<EndEffectorId, u64> = BTreeMap::new();
        for (o, object) in objects.iter().enumerate() {
            for g in (0..object.n_grasps() as u32).map(GraspId) {
                for &e in object.holders(g) {
                    let n_moves = *moves.entry(e).or_insert_with(|| self.moves(e).len());
                    let n_states = self.holder_states(e, g).len() as u64;
                    tally
                        .size(n_states.saturating_add(n_moves))
                        .map_err(|limit| tally.exceeded(limit, Some(ObjectId(o as u32))))?;
                }
            }
        }
        for (o, object) in objects.iter().enumerate() {
            let exchanges = Exchanges::new(self, object);
            let mut transitions = || -> Result<(), Limit> {
                for t in 0..object.transitions().len() {
                    let Some(exchange) = exchanges.of(t) else {
                        continue;
                    };
                    tally.visits(exchange.visits())?;
                    for meeting in exchange.meetings() {
                        tally.visits(meeting.visits())?;
                        tally.size(meeting.arcs().count() as u64)?;
                    }
                }
                Ok(())
            };
            transitions().map_err(|limit| tally.exceeded(limit, Some(ObjectId(o as u32))))?;
        }
        Ok(tally.size)
    }
}
