//! The graph rules: which states and arcs an object-state graph has (the paper's Sec. IV-A).
//!
//! They live here, once, because two phases need them: the compiler counts every graph
//! with [`CellRules::count`] (refusing a cell over its limits before anything is built),
//! then builds it with [`CellRules::states`] and [`CellRules::for_each_arc`]; both read
//! the same rule-by-rule pieces (`arcs.rs`), so the count is what the build makes. The
//! runtime's explanation of an unreachable goal asks the same rules which arcs a change
//! to the cell would add ([`CellRules::added_by`], on a copy edited with
//! [`CellRules::extend_reach`] and [`CellRules::declare_adjacency`]). A suggestion is
//! therefore checked against the graph the compiler would really build after the change.
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
    /// The holder of every (holder, grasp) pair, sorted by holder then grasp: the grasps
    /// one end-effector may hold are a run of `held`. Sparse, so that an object costs its
    /// grasps and not the cell's end-effectors (counting many objects stays linear).
    holding: Vec<EndEffectorId>,
    /// The grasp of each pair in `holding`.
    held: Vec<GraspId>,
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
        let mut pairs = Vec::new();
        for (g, grasp) in grasps.iter_mut().enumerate() {
            grasp.holders.retain(|e| e.index() < n_end_effectors);
            grasp.holders.sort_unstable();
            grasp.holders.dedup();
            pairs.extend(grasp.holders.iter().map(|&e| (e, GraspId(g as u32))));
        }
        pairs.sort_unstable();
        let (holding, held) = pairs.into_iter().unzip();
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
            holding,
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
        let start = self.holding.partition_point(|&x| x < e);
        let end = start + self.holding[start..].partition_point(|&x| x == e);
        &self.held[start..end]
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
    /// Per workspace, the workspaces declared adjacent to it, sorted, each with the index
    /// of the first declaration of the pair: neighbour lists, never a matrix (a cell of
    /// 10^5 workspaces has 10^10 pairs, and only the declared few are stored).
    neighbours: Vec<Vec<(WorkspaceId, usize)>>,
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
        let mut neighbours = vec![Vec::new(); n_workspaces];
        let mut n_declared = 0;
        if let Adjacency::Declared(pairs) = &adjacency {
            n_declared = pairs.len();
            for (i, &(a, b)) in pairs.iter().enumerate() {
                if a != b && a.index() < n_workspaces && b.index() < n_workspaces {
                    neighbours[a.index()].push((b, i));
                    neighbours[b.index()].push((a, i));
                }
            }
            for list in &mut neighbours {
                // By neighbour, then declaration: the first of a repeated pair stays.
                list.sort_unstable();
                list.dedup_by_key(|(w, _)| *w);
            }
        }
        CellRules {
            end_effectors,
            reachers,
            derived: matches!(adjacency, Adjacency::Derived),
            neighbours,
            n_declared,
        }
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
        if let Some(i) = self.declaration(a, b) {
            return Some(Some(i));
        }
        let derived = self.derived
            && self
                .reachers(a)
                .iter()
                .any(|&e| self.is_movable(e) && self.reaches(e, b));
        derived.then_some(None)
    }

    /// The first declaration of `adjacent a b` (either way round), if any.
    fn declaration(&self, a: WorkspaceId, b: WorkspaceId) -> Option<usize> {
        let near = self.neighbours.get(a.index())?;
        let at = near.binary_search_by_key(&b, |&(w, _)| w).ok()?;
        Some(near[at].1)
    }

    /// The workspaces declared adjacent to `w`, sorted, with their first declarations.
    fn neighbours(&self, w: WorkspaceId) -> &[(WorkspaceId, usize)] {
        self.neighbours.get(w.index()).map_or(&[], |x| x.as_slice())
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
        if a == b || a.index() >= self.n_workspaces() || b.index() >= self.n_workspaces() {
            return;
        }
        for (x, y) in [(a, b), (b, a)] {
            let near = &mut self.neighbours[x.index()];
            if let Err(at) = near.binary_search_by_key(&y, |&(w, _)| w) {
                near.insert(at, (y, index));
            }
        }
    }
}

mod arcs;
mod count;
mod edits;

pub use count::{Exceeded, Limit, Limits};

#[cfg(test)]
mod tests;
