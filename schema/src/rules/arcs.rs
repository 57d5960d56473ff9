//! The graph rule by rule: the states of one holder and grasp, the moves of one
//! end-effector, the exchanges of one declared transition, and the adjacent pairs an
//! artifact records. [`CellRules::states`] and [`CellRules::for_each_arc`] build a graph
//! from these pieces and [`CellRules::count`](super::count) counts the same pieces before
//! anything is built, so what is counted is what is built. Every piece can say how large
//! it is without being listed when listing would cost more than it makes (the moves of a
//! hand reaching 10^5 workspaces with derived adjacency are 10^10 pairs).

use std::collections::BTreeMap;

use super::{CellRules, ObjectRules, Provenance, State};
use crate::ids::{EndEffectorId, GraspId, WorkspaceId};

/// A move within one end-effector's reach: (position of a, position of b, the
/// declaration that makes a and b adjacent, if declared).
pub(super) type MovePair = (u32, u32, Option<usize>);

/// The moves one end-effector makes with every grasp it holds: each ordered pair of
/// adjacent workspaces in its reach, in reach order (by the first, then the second).
pub(super) enum Moves<'a> {
    /// A fixed end-effector never moves.
    Fixed,
    /// Derived adjacency: the end-effector itself makes every two workspaces it reaches
    /// adjacent (declared pairs only add their provenance), so its moves are all ordered
    /// pairs of its reach, never listed.
    All {
        rules: &'a CellRules,
        reach: &'a [WorkspaceId],
    },
    /// Declared adjacency: the declared pairs with both ends in reach, listed (a reach of
    /// 10^5 workspaces with a chain of `adjacent` lines costs the chain, not 10^10
    /// lookups).
    Listed(Vec<MovePair>),
}

impl Moves<'_> {
    /// How many moves there are, without listing them.
    pub(super) fn len(&self) -> u64 {
        match self {
            Moves::Fixed => 0,
            Moves::All { reach, .. } => {
                let r = reach.len() as u64;
                r * r.saturating_sub(1)
            }
            Moves::Listed(pairs) => pairs.len() as u64,
        }
    }

    /// The moves, in reach order.
    pub(super) fn iter(&self) -> impl Iterator<Item = MovePair> + '_ {
        let (all, listed) = match self {
            Moves::Fixed => (None, &[][..]),
            Moves::All { rules, reach } => (Some((*rules, *reach)), &[][..]),
            Moves::Listed(pairs) => (None, pairs.as_slice()),
        };
        let all = all.into_iter().flat_map(|(rules, reach)| {
            reach.iter().enumerate().flat_map(move |(i, &a)| {
                reach
                    .iter()
                    .enumerate()
                    .filter(move |&(j, _)| j != i)
                    .map(move |(j, &b)| (i as u32, j as u32, rules.declaration(a, b)))
            })
        });
        all.chain(listed.iter().copied())
    }
}

/// A state as a transition finds it: (workspace, holder, node), so that sorting puts
/// the states of one workspace together, by holder.
type Placed = (WorkspaceId, EndEffectorId, u32);

/// One object's states arranged for its transitions: per grasp that takes part in one,
/// its states sorted by workspace and holder, with their nodes. The arcs of a transition
/// are found by merging the lists of its two grasps, so a transition costs the states of
/// its grasps, not every workspace of the cell.
pub(super) struct Exchanges<'a> {
    rules: &'a CellRules,
    object: &'a ObjectRules,
    by_grasp: Vec<Vec<Placed>>,
}

impl<'a> Exchanges<'a> {
    /// The lists of `object`'s grasps (nodes numbered as [`CellRules::states`] lists them).
    pub(super) fn new(rules: &'a CellRules, object: &'a ObjectRules) -> Exchanges<'a> {
        let mut by_grasp = vec![Vec::new(); object.n_grasps()];
        let mut node = 0u32;
        for (g, placed) in by_grasp.iter_mut().enumerate() {
            let grasp = GraspId(g as u32);
            let wanted = !object.declared_by_grasp[g].is_empty();
            for &e in object.holders(grasp) {
                let states = rules.holder_states(e, grasp);
                let n = states.len() as u32;
                if wanted {
                    let first = node;
                    placed.extend(
                        states
                            .zip(first..)
                            .map(|(s, node)| (s.workspace, s.end_effector, node)),
                    );
                }
                node += n;
            }
            placed.sort_unstable();
        }
        Exchanges {
            rules,
            object,
            by_grasp,
        }
    }

    /// The exchanges of the object's transition `t` (index into
    /// [`ObjectRules::transitions`]); `None` when it names an unknown grasp.
    pub(super) fn of(&self, t: usize) -> Option<Exchange<'_>> {
        let &(from, to) = self.object.transitions().get(t)?;
        Some(Exchange {
            rules: self.rules,
            givers: self.by_grasp.get(from.index())?,
            takers: self.by_grasp.get(to.index())?,
            explicit: self.object.explicit_pair(from, to),
        })
    }
}

/// The states of one transition's two grasps, to be met workspace by workspace.
pub(super) struct Exchange<'a> {
    rules: &'a CellRules,
    givers: &'a [Placed],
    takers: &'a [Placed],
    explicit: bool,
}

impl<'a> Exchange<'a> {
    /// The states the transition visits to find where its grasps meet.
    pub(super) fn visits(&self) -> u64 {
        (self.givers.len() + self.takers.len()) as u64
    }

    /// The workspaces where both grasps have states, in workspace order, each with the
    /// states of both there.
    pub(super) fn meetings(&self) -> impl Iterator<Item = Meeting<'a>> + 'a {
        let (rules, explicit) = (self.rules, self.explicit);
        let (from, to) = (self.givers, self.takers);
        let (mut i, mut j) = (0, 0);
        std::iter::from_fn(move || {
            while i < from.len() && j < to.len() {
                let (wa, wb) = (from[i].0, to[j].0);
                if wa != wb {
                    if wa < wb {
                        i += 1;
                    } else {
                        j += 1;
                    }
                    continue;
                }
                let i_end = i + from[i..].partition_point(|s| s.0 == wa);
                let j_end = j + to[j..].partition_point(|s| s.0 == wa);
                let here = Meeting {
                    rules,
                    givers: &from[i..i_end],
                    takers: &to[j..j_end],
                    explicit,
                };
                (i, j) = (i_end, j_end);
                return Some(here);
            }
            None
        })
    }
}

/// One workspace where a transition's two grasps both have states.
pub(super) struct Meeting<'a> {
    rules: &'a CellRules,
    givers: &'a [Placed],
    takers: &'a [Placed],
    explicit: bool,
}

impl<'a> Meeting<'a> {
    /// The pairs of holders tried here.
    pub(super) fn visits(&self) -> u64 {
        (self.givers.len() as u64).saturating_mul(self.takers.len() as u64)
    }

    /// The arcs made here, as (giver's node, taker's node), by giver then taker: every
    /// pair that [may exchange](CellRules::may_exchange).
    pub(super) fn arcs(&self) -> impl Iterator<Item = (u32, u32)> + 'a {
        let (rules, explicit, takers) = (self.rules, self.explicit, self.takers);
        self.givers.iter().flat_map(move |&(_, ei, a)| {
            takers
                .iter()
                .filter(move |&&(_, ej, _)| rules.may_exchange(ei, ej, explicit))
                .map(move |&(_, _, b)| (a, b))
        })
    }
}

impl CellRules {
    /// The states of `e` holding `grasp`: one per workspace it reaches, in reach order.
    pub(super) fn holder_states(
        &self,
        e: EndEffectorId,
        grasp: GraspId,
    ) -> impl ExactSizeIterator<Item = State> + '_ {
        self.reach(e).iter().map(move |&workspace| State {
            end_effector: e,
            grasp,
            workspace,
        })
    }

    /// The moves `e` makes with each grasp it holds.
    pub(super) fn moves(&self, e: EndEffectorId) -> Moves<'_> {
        let reach = self.reach(e);
        if !self.is_movable(e) {
            Moves::Fixed
        } else if self.derived {
            Moves::All { rules: self, reach }
        } else {
            Moves::Listed(self.declared_moves(reach))
        }
    }

    /// The declared pairs with both ends in `reach` (sorted), both ways, in reach order.
    /// Each workspace's neighbours are met with the reach from the shorter side, so the
    /// work is bounded by the declarations as well as by the reach.
    fn declared_moves(&self, reach: &[WorkspaceId]) -> Vec<MovePair> {
        let mut out = Vec::new();
        for (i, &a) in reach.iter().enumerate() {
            let near = self.neighbours(a);
            if near.len() <= reach.len() {
                out.extend(near.iter().filter_map(|&(b, d)| {
                    let j = reach.binary_search(&b).ok()?;
                    Some((i as u32, j as u32, Some(d)))
                }));
            } else {
                out.extend(reach.iter().enumerate().filter_map(|(j, &b)| {
                    let k = near.binary_search_by_key(&b, |&(w, _)| w).ok()?;
                    Some((i as u32, j as u32, Some(near[k].1)))
                }));
            }
        }
        out
    }

    /// Every adjacent pair `(a, b)` with `a < b`, each once, in order: what an artifact
    /// records. When listing them would take more than `limit` pairs (counted before
    /// repeats are removed), `Err` with that count instead, found without listing: two
    /// hands that each reach 10^5 workspaces with derived adjacency are refused, not
    /// listed.
    pub fn adjacent_pairs(&self, limit: u64) -> Result<Vec<(WorkspaceId, WorkspaceId)>, u64> {
        let mut pairs = Vec::new();
        for (a, near) in self.neighbours.iter().enumerate() {
            let a = WorkspaceId(a as u32);
            pairs.extend(near.iter().filter(|&&(b, _)| a < b).map(|&(b, _)| (a, b)));
        }
        let mut listed = pairs.len() as u64;
        if listed > limit {
            return Err(listed);
        }
        if self.derived {
            for ee in self.end_effectors.iter().filter(|e| e.movable) {
                let r = ee.reaches.len() as u64;
                listed = listed.saturating_add(r * r.saturating_sub(1) / 2);
                if listed > limit {
                    return Err(listed);
                }
                for (i, &a) in ee.reaches.iter().enumerate() {
                    pairs.extend(ee.reaches[i + 1..].iter().map(|&b| (a, b)));
                }
            }
            pairs.sort_unstable();
            pairs.dedup();
        }
        Ok(pairs)
    }

    /// Every state of an object, in graph order: by grasp, then holder, then reached
    /// workspace.
    pub fn states(&self, object: &ObjectRules) -> Vec<State> {
        (0..object.n_grasps() as u32)
            .map(GraspId)
            .flat_map(|g| {
                object
                    .holders(g)
                    .iter()
                    .flat_map(move |&e| self.holder_states(e, g))
            })
            .collect()
    }

    /// Calls `arc(from, to, provenance)` for every arc of an object's graph, with `from`
    /// and `to` indices into [`CellRules::states`]: the moves first (by grasp, holder,
    /// workspace pair), then the transitions (by declaration, workspace, giver, taker).
    /// This is the order the compiler writes.
    pub fn for_each_arc(&self, object: &ObjectRules, mut arc: impl FnMut(u32, u32, Provenance)) {
        // The states of one holder and grasp are consecutive, in reach order, so a move's
        // nodes are the first of them plus the positions of its workspaces. Each hand's
        // moves are found once, not once per grasp it holds.
        let mut moves: BTreeMap<EndEffectorId, Moves<'_>> = BTreeMap::new();
        let mut first = 0u32;
        for g in (0..object.n_grasps() as u32).map(GraspId) {
            for &e in object.holders(g) {
                let moves = moves.entry(e).or_insert_with(|| self.moves(e));
                for (i, j, adjacency) in moves.iter() {
                    arc(first + i, first + j, Provenance::Move { adjacency });
                }
                first += self.holder_states(e, g).len() as u32;
            }
        }
        let exchanges = Exchanges::new(self, object);
        for t in 0..object.transitions().len() {
            let Some(exchange) = exchanges.of(t) else {
                continue;
            };
            for meeting in exchange.meetings() {
                for (a, b) in meeting.arcs() {
                    arc(a, b, Provenance::Transition { transition: t });
                }
            }
        }
    }
}
