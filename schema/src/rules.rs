//! The graph rules: which states and arcs an object-state graph has (the paper's Sec. IV-A).
//!
//! They live here, once, because two phases need them: the compiler builds every graph
//! with [`CellRules::states`] and [`CellRules::for_each_arc`], and the runtime's
//! explanation of an unreachable goal asks the same rules which arcs a change to the cell
//! would add ([`CellRules::added_by`], on a copy edited with [`CellRules::extend_reach`]
//! and [`CellRules::declare_adjacency`]). A suggestion is therefore checked against the
//! graph the compiler would really build after the change.
//!
//! The rules read plain data: end-effectors (movable or fixed, the workspaces each
//! reaches), how workspaces are adjacent, and per object its grasps (who may hold each)
//! and declared transitions. From those:
//! - a state S(e, g, w) for every grasp g, every end-effector e that may hold it and every
//!   workspace w that e reaches;
//! - a *move* S(e, g, a) -> S(e, g, b) when e is movable, reaches both a and b, and a and b
//!   are adjacent (never a = b);
//! - a *transition* S(ei, gf, w) -> S(ej, gt, w) for every declared transition gf -> gt and
//!   every workspace w that both ei and ej reach, unless both are fixed (surfaces never
//!   exchange an object), or ei = ej while one of the grasps was declared for a hand kind (a
//!   hand never hands an object to itself; explicit same-holder transitions, as imported
//!   databases have, are kept);
//! - adjacency is declared (pairs of workspaces) or derived (two workspaces one movable
//!   end-effector reaches).
//!
//! No arc changes grasp and workspace at once. Every arc says what made it
//! ([`Provenance`]), so findings about arcs can point at source lines.

use std::collections::BTreeMap;

use crate::ids::{EndEffectorId, GraspId, WorkspaceId};
use crate::{Artifact, Holder, Node, Object};

/// A state S(end-effector, grasp, workspace): the object held by `end_effector` with
/// `grasp` in `workspace`. The artifact's [`Node`] is the same value (typed ids that
/// serialise as bare numbers), so the rules and the artifact share one definition.
pub type State = Node;

/// What the rules need to know of an end-effector.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct EndEffectorFacts {
    /// Movable (a hand, a conveyor) rather than fixed (a surface).
    pub movable: bool,
    /// The workspaces it reaches.
    pub reaches: Vec<WorkspaceId>,
}

/// Which workspaces are adjacent.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Adjacency {
    /// Two workspaces one movable end-effector reaches (cells that declare none).
    Derived,
    /// These pairs, in declaration order (either way round; repeats allowed).
    Declared(Vec<(WorkspaceId, WorkspaceId)>),
}

impl Adjacency {
    /// The adjacency an artifact records, if it records one (artifacts written by other
    /// tools may not).
    pub fn of_artifact(artifact: &Artifact) -> Option<Adjacency> {
        let record = artifact.adjacency.as_ref()?;
        Some(if record.declared {
            Adjacency::Declared(
                record
                    .pairs
                    .iter()
                    .map(|&(a, b)| (WorkspaceId(a), WorkspaceId(b)))
                    .collect(),
            )
        } else {
            Adjacency::Derived
        })
    }
}

/// Who may hold one grasp.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct GraspFacts {
    /// Every end-effector that may hold it (one, or every member of a hand kind).
    pub holders: Vec<EndEffectorId>,
    /// Declared for one end-effector rather than for a kind.
    pub explicit: bool,
}

/// A move within one end-effector's reach: (position of a, position of b, the
/// declaration that makes a and b adjacent, if declared).
type MovePair = (u32, u32, Option<usize>);

/// What made an arc.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Provenance {
    /// A move; the declared adjacency it uses (index into the [`Adjacency::Declared`]
    /// pairs, the first that names the pair), `None` when adjacency is derived.
    Move {
        /// Index of the declaring pair.
        adjacency: Option<usize>,
    },
    /// A grasp exchange.
    Transition {
        /// Index into [`ObjectRules::transitions`].
        transition: usize,
    },
}

/// A change to a cell's declarations whose arcs [`CellRules::added_by`] gives.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Edit {
    /// `transition from -> to` declared in the object (one way).
    Transition(GraspId, GraspId),
    /// `adjacent a b` declared.
    Adjacency(WorkspaceId, WorkspaceId),
    /// The end-effector's reach extended to the workspace.
    Reach(EndEffectorId, WorkspaceId),
}

/// The per-object half of the rules: grasps and declared transitions.
#[derive(Clone, Debug)]
pub struct ObjectRules {
    grasps: Vec<GraspFacts>,
    transitions: Vec<(GraspId, GraspId)>,
    /// The grasps each end-effector may hold, in grasp order.
    held: Vec<Vec<GraspId>>,
    /// The distinct declared transitions, sorted.
    declared: Vec<(GraspId, GraspId)>,
    /// Per grasp, the indices into `declared` of the transitions it takes part in.
    declared_by_grasp: Vec<Vec<usize>>,
}

impl ObjectRules {
    /// The rules of one object among `n_end_effectors`. Holders are sorted and those out
    /// of range dropped; transitions keep their order and repeats (each declaration makes
    /// its own arcs).
    pub fn new(
        n_end_effectors: usize,
        mut grasps: Vec<GraspFacts>,
        transitions: Vec<(GraspId, GraspId)>,
    ) -> ObjectRules {
        let mut held = vec![Vec::new(); n_end_effectors];
        for (g, grasp) in grasps.iter_mut().enumerate() {
            grasp.holders.retain(|e| e.index() < n_end_effectors);
            grasp.holders.sort_unstable();
            grasp.holders.dedup();
            for e in &grasp.holders {
                held[e.index()].push(GraspId(g as u32));
            }
        }
        let mut declared = transitions.clone();
        declared.sort_unstable();
        declared.dedup();
        let mut declared_by_grasp = vec![Vec::new(); grasps.len()];
        for (i, &(a, b)) in declared.iter().enumerate() {
            for g in [a, b] {
                if let Some(list) = declared_by_grasp.get_mut(g.index()) {
                    if list.last() != Some(&i) {
                        list.push(i);
                    }
                }
            }
        }
        ObjectRules {
            grasps,
            transitions,
            held,
            declared,
            declared_by_grasp,
        }
    }

    /// The rules of an artifact's object: a grasp declared for a hand kind may be held by
    /// every end-effector of that kind.
    pub fn from_artifact(artifact: &Artifact, object: &Object) -> ObjectRules {
        let n_ee = artifact.end_effectors.len();
        let grasps = object
            .grasps
            .iter()
            .map(|g| GraspFacts {
                holders: match g.holder {
                    Holder::EndEffector(e) => vec![EndEffectorId(e)],
                    Holder::Kind(k) => (0..n_ee as u32)
                        .filter(|&e| artifact.end_effectors[e as usize].kind == Some(k))
                        .map(EndEffectorId)
                        .collect(),
                },
                explicit: matches!(g.holder, Holder::EndEffector(_)),
            })
            .collect();
        let transitions = object
            .transitions
            .iter()
            .map(|t| (GraspId(t.from), GraspId(t.to)))
            .collect();
        ObjectRules::new(n_ee, grasps, transitions)
    }

    /// Number of grasps.
    pub fn n_grasps(&self) -> usize {
        self.grasps.len()
    }

    /// Who may hold grasp `g`, sorted (empty for an unknown grasp).
    pub fn holders(&self, g: GraspId) -> &[EndEffectorId] {
        self.grasps
            .get(g.index())
            .map_or(&[], |x| x.holders.as_slice())
    }

    /// True when `g` was declared for one end-effector rather than for a kind.
    pub fn is_explicit(&self, g: GraspId) -> bool {
        self.grasps.get(g.index()).is_some_and(|x| x.explicit)
    }

    /// The grasps `e` may hold, in grasp order.
    pub fn grasps_of(&self, e: EndEffectorId) -> &[GraspId] {
        self.held.get(e.index()).map_or(&[], |x| x.as_slice())
    }

    /// The declared transitions, in declaration order.
    pub fn transitions(&self) -> &[(GraspId, GraspId)] {
        &self.transitions
    }

    /// True when `from -> to` is declared.
    pub fn declares(&self, from: GraspId, to: GraspId) -> bool {
        self.declared.binary_search(&(from, to)).is_ok()
    }

    /// Whether a transition between these two grasps keeps a same-holder exchange (both
    /// grasps declared for end-effectors, not kinds).
    fn explicit_pair(&self, from: GraspId, to: GraspId) -> bool {
        self.is_explicit(from) && self.is_explicit(to)
    }
}

/// The cell-level half of the rules: end-effectors and adjacency.
#[derive(Clone, Debug)]
pub struct CellRules {
    end_effectors: Vec<EndEffectorFacts>,
    /// Per workspace, the end-effectors reaching it, sorted.
    reachers: Vec<Vec<EndEffectorId>>,
    /// Adjacency derived from reach (possibly with declared pairs on top, after
    /// [`CellRules::declare_adjacency`]).
    derived: bool,
    /// Declared pairs (smaller first) -> index of the first declaration.
    declared: BTreeMap<(WorkspaceId, WorkspaceId), usize>,
    /// Declarations made so far (the index the next one gets).
    n_declared: usize,
}

impl CellRules {
    /// The rules of a cell with `n_workspaces` workspaces. Reaches are sorted, and
    /// workspaces out of range dropped.
    pub fn new(
        n_workspaces: usize,
        mut end_effectors: Vec<EndEffectorFacts>,
        adjacency: Adjacency,
    ) -> CellRules {
        let mut reachers = vec![Vec::new(); n_workspaces];
        for (e, ee) in end_effectors.iter_mut().enumerate() {
            ee.reaches.retain(|w| w.index() < n_workspaces);
            ee.reaches.sort_unstable();
            ee.reaches.dedup();
            for w in &ee.reaches {
                reachers[w.index()].push(EndEffectorId(e as u32));
            }
        }
        let mut rules = CellRules {
            end_effectors,
            reachers,
            derived: matches!(adjacency, Adjacency::Derived),
            declared: BTreeMap::new(),
            n_declared: 0,
        };
        if let Adjacency::Declared(pairs) = adjacency {
            for (a, b) in pairs {
                rules.declare_adjacency(a, b);
            }
        }
        rules
    }

    /// The end-effector facts of an artifact.
    pub fn end_effectors_of(artifact: &Artifact) -> Vec<EndEffectorFacts> {
        artifact
            .end_effectors
            .iter()
            .map(|e| EndEffectorFacts {
                movable: e.movable,
                reaches: e.reaches.iter().map(|&w| WorkspaceId(w)).collect(),
            })
            .collect()
    }

    /// Number of workspaces.
    pub fn n_workspaces(&self) -> usize {
        self.reachers.len()
    }

    /// Number of end-effectors.
    pub fn n_end_effectors(&self) -> usize {
        self.end_effectors.len()
    }

    /// The workspaces `e` reaches, sorted (empty for an unknown end-effector).
    pub fn reach(&self, e: EndEffectorId) -> &[WorkspaceId] {
        self.end_effectors
            .get(e.index())
            .map_or(&[], |x| x.reaches.as_slice())
    }

    /// True when `e` reaches `w`.
    pub fn reaches(&self, e: EndEffectorId, w: WorkspaceId) -> bool {
        self.reach(e).binary_search(&w).is_ok()
    }

    /// The end-effectors reaching `w`, sorted.
    pub fn reachers(&self, w: WorkspaceId) -> &[EndEffectorId] {
        self.reachers.get(w.index()).map_or(&[], |x| x.as_slice())
    }

    /// True for movable end-effectors.
    pub fn is_movable(&self, e: EndEffectorId) -> bool {
        self.end_effectors.get(e.index()).is_some_and(|x| x.movable)
    }

    /// True when the cell declares its adjacency rather than deriving it.
    pub fn declares_adjacency(&self) -> bool {
        !self.derived
    }

    /// Whether `a` and `b` are adjacent: `Some(Some(i))` by the declared pair `i`,
    /// `Some(None)` by derivation, `None` not at all (a workspace is never adjacent to
    /// itself).
    pub fn adjacency(&self, a: WorkspaceId, b: WorkspaceId) -> Option<Option<usize>> {
        if a == b {
            return None;
        }
        if let Some(&i) = self.declared.get(&(a.min(b), a.max(b))) {
            return Some(Some(i));
        }
        let derived = self.derived
            && self
                .reachers(a)
                .iter()
                .any(|&e| self.is_movable(e) && self.reaches(e, b));
        derived.then_some(None)
    }

    /// True when `a` and `b` are adjacent.
    pub fn is_adjacent(&self, a: WorkspaceId, b: WorkspaceId) -> bool {
        self.adjacency(a, b).is_some()
    }

    /// True when `e` carries objects between `a` and `b`: movable, reaching both, and the
    /// two adjacent.
    pub fn carries(&self, e: EndEffectorId, a: WorkspaceId, b: WorkspaceId) -> bool {
        self.is_movable(e) && self.reaches(e, a) && self.reaches(e, b) && self.is_adjacent(a, b)
    }

    /// True when `giver` may pass an object to `taker` by a declared transition (in a
    /// workspace both reach): not two fixed end-effectors, and not one to itself unless
    /// the transition's grasps are both `explicit` (declared for end-effectors).
    pub fn may_exchange(&self, giver: EndEffectorId, taker: EndEffectorId, explicit: bool) -> bool {
        (giver != taker || explicit) && (self.is_movable(giver) || self.is_movable(taker))
    }

    /// The rules after `e` is made to reach `w` as well (for hypothetical changes).
    pub fn extend_reach(&mut self, e: EndEffectorId, w: WorkspaceId) {
        let (Some(ee), Some(reachers)) = (
            self.end_effectors.get_mut(e.index()),
            self.reachers.get_mut(w.index()),
        ) else {
            return;
        };
        if let Err(at) = ee.reaches.binary_search(&w) {
            ee.reaches.insert(at, w);
        }
        if let Err(at) = reachers.binary_search(&e) {
            reachers.insert(at, e);
        }
    }

    /// The rules after `adjacent a b` is declared as well; the declaration gets the next
    /// index. A repeated pair keeps its first index.
    pub fn declare_adjacency(&mut self, a: WorkspaceId, b: WorkspaceId) {
        let index = self.n_declared;
        self.n_declared += 1;
        if a != b {
            self.declared.entry((a.min(b), a.max(b))).or_insert(index);
        }
    }

    /// Every state of an object, in graph order: by grasp, then holder, then reached
    /// workspace.
    pub fn states(&self, object: &ObjectRules) -> Vec<State> {
        let mut states = Vec::new();
        for g in 0..object.n_grasps() {
            let grasp = GraspId(g as u32);
            for &e in object.holders(grasp) {
                states.extend(self.reach(e).iter().map(|&w| State {
                    end_effector: e,
                    grasp,
                    workspace: w,
                }));
            }
        }
        states
    }

    /// Calls `arc(from, to, provenance)` for every arc of an object's graph, with `from`
    /// and `to` indices into [`CellRules::states`]: the moves first (by grasp, holder,
    /// workspace pair), then the transitions (by declaration, workspace, giver, taker).
    /// This is the order the compiler writes.
    pub fn for_each_arc(&self, object: &ObjectRules, mut arc: impl FnMut(u32, u32, Provenance)) {
        // first[g][k]: the node of S(holders(g)[k], g, reach[0]); the states of one holder
        // and grasp are consecutive in reach order, so a state's node is found by two
        // binary searches instead of hashing every arc's endpoints.
        let mut first: Vec<Vec<u32>> = Vec::with_capacity(object.n_grasps());
        let mut next = 0u32;
        for g in 0..object.n_grasps() {
            let holders = object.holders(GraspId(g as u32));
            first.push(
                holders
                    .iter()
                    .map(|&e| {
                        let at = next;
                        next += self.reach(e).len() as u32;
                        at
                    })
                    .collect(),
            );
        }
        let node = |e: EndEffectorId, g: GraspId, w: WorkspaceId| -> Option<u32> {
            let k = object.holders(g).binary_search(&e).ok()?;
            let position = self.reach(e).binary_search(&w).ok()?;
            Some(first[g.index()][k] + position as u32)
        };
        // The adjacent pairs of each movable end-effector's reach (as positions), found
        // once rather than once per grasp.
        let mut pairs: Vec<Option<Vec<MovePair>>> = vec![None; self.end_effectors.len()];
        for (g, firsts) in first.iter().enumerate() {
            let grasp = GraspId(g as u32);
            for (&e, &at) in object.holders(grasp).iter().zip(firsts) {
                if !self.is_movable(e) {
                    continue;
                }
                let pairs = pairs[e.index()].get_or_insert_with(|| self.adjacent_pairs(e));
                for &(i, j, adjacency) in pairs.iter() {
                    arc(at + i, at + j, Provenance::Move { adjacency });
                }
            }
        }
        for (t, &(from, to)) in object.transitions().iter().enumerate() {
            let explicit = object.explicit_pair(from, to);
            let (givers, takers) = (object.holders(from), object.holders(to));
            for (w, here) in self.reachers.iter().enumerate() {
                let w = WorkspaceId(w as u32);
                for &ei in here.iter().filter(|e| givers.binary_search(e).is_ok()) {
                    for &ej in here.iter().filter(|e| takers.binary_search(e).is_ok()) {
                        if !self.may_exchange(ei, ej, explicit) {
                            continue;
                        }
                        if let (Some(a), Some(b)) = (node(ei, from, w), node(ej, to, w)) {
                            arc(a, b, Provenance::Transition { transition: t });
                        }
                    }
                }
            }
        }
    }

    /// (position of a, position of b, adjacency) for every ordered pair of adjacent
    /// workspaces `e` reaches, in reach order.
    fn adjacent_pairs(&self, e: EndEffectorId) -> Vec<MovePair> {
        let reach = self.reach(e);
        let mut out = Vec::new();
        if self.derived {
            // `e` itself makes every two of its workspaces adjacent (declared pairs only
            // add their provenance): all ordered pairs, as many as the moves it makes.
            for (i, &a) in reach.iter().enumerate() {
                for (j, &b) in reach.iter().enumerate() {
                    if a != b {
                        let declared = self.declared.get(&(a.min(b), a.max(b))).copied();
                        out.push((i as u32, j as u32, declared));
                    }
                }
            }
            return out;
        }
        // Declared adjacency: only the declared pairs, both ends in reach (a reach of 10^5
        // workspaces with a chain of `adjacent` lines costs the chain, not 10^10 lookups).
        for (&(a, b), &d) in &self.declared {
            if a == b {
                continue;
            }
            if let (Ok(i), Ok(j)) = (reach.binary_search(&a), reach.binary_search(&b)) {
                out.push((i as u32, j as u32, Some(d)));
                out.push((j as u32, i as u32, Some(d)));
            }
        }
        // In reach order, as the arcs have always been listed.
        out.sort_unstable_by_key(|&(i, j, _)| (i, j));
        out
    }
}

mod edits;

#[cfg(test)]
mod tests;
