//! The object-state graph, one per object (the paper's Sec. IV-A).
//!
//! Nodes are states S(end-effector, grasp, workspace), one for every grasp an
//! end-effector can hold and every workspace it reaches. Arcs:
//! - *move*: S(e, g, wi) -> S(e, g, wj), for a movable e, adjacent wi and wj both reached
//!   by e;
//! - *transition*: S(ei, gk, w) -> S(ej, gl, w), for a declared transition gk -> gl and
//!   every workspace w both ei and ej reach.
//!
//! No arc changes grasp and workspace at once. Each arc records which declaration made
//! it, so any finding about an arc can point at source lines.

use std::collections::HashMap;

use petgraph::graph::{DiGraph, NodeIndex};

use crate::ids::*;
use crate::model::*;

/// A node: the object held by `end_effector` with `grasp` in `workspace`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct State {
    /// Holder.
    pub end_effector: EndEffectorId,
    /// Grasp or resting pose.
    pub grasp: GraspId,
    /// Workspace.
    pub workspace: WorkspaceId,
}

/// What made an arc.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ArcSource {
    /// A move; the declared adjacency it uses, if adjacency was declared.
    Move {
        /// Index into [`Cell::adjacencies`].
        adjacency: Option<usize>,
    },
    /// A grasp transition.
    Transition {
        /// Index into [`Cell::transitions`].
        transition: usize,
    },
}

/// An arc with its weight.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StateArc {
    /// Cost for the shortest-path search.
    pub weight: f64,
    /// Provenance.
    pub source: ArcSource,
}

impl StateArc {
    /// True for move arcs.
    pub fn is_move(&self) -> bool {
        matches!(self.source, ArcSource::Move { .. })
    }
}

/// The graph of one object.
#[derive(Clone, Debug)]
pub struct ObjectGraph {
    /// The object.
    pub object: ObjectId,
    /// Nodes and arcs.
    pub graph: DiGraph<State, StateArc>,
    index: HashMap<State, NodeIndex>,
}

impl ObjectGraph {
    /// The node of a state, if the state exists.
    pub fn node(&self, state: State) -> Option<NodeIndex> {
        self.index.get(&state).copied()
    }

    /// Number of move arcs.
    pub fn n_moves(&self) -> usize {
        self.graph.edge_weights().filter(|a| a.is_move()).count()
    }

    /// Number of transition arcs.
    pub fn n_transitions(&self) -> usize {
        self.graph.edge_count() - self.n_moves()
    }
}

/// Which workspaces are adjacent: the declared pairs, or (when the cell declares none)
/// every two workspaces one movable end-effector reaches. Kept as lists of neighbours,
/// never as a matrix: a cell of 10⁵ workspaces has 10¹⁰ pairs, and only the few that are
/// adjacent are stored.
#[derive(Clone, Debug)]
pub enum Adjacency {
    /// Derived from reach: two workspaces are adjacent when a movable end-effector reaches
    /// both. Nothing is stored: an end-effector's moves are all pairs of what it reaches.
    Derived,
    /// Declared: per workspace, its neighbours in id order, each with the first `adjacent`
    /// item (index into [`Cell::adjacencies`]) that declares the pair.
    Declared(Vec<Vec<(WorkspaceId, usize)>>),
}

impl Adjacency {
    /// The adjacency of a cell.
    pub fn of(cell: &Cell) -> Adjacency {
        if cell.adjacencies.is_empty() {
            return Adjacency::Derived;
        }
        let mut neighbours: Vec<Vec<(WorkspaceId, usize)>> =
            vec![Vec::new(); cell.workspaces.len()];
        for (i, adj) in cell.adjacencies.iter().enumerate() {
            neighbours[adj.a.index()].push((adj.b, i));
            neighbours[adj.b.index()].push((adj.a, i));
        }
        for list in &mut neighbours {
            // Sorted by neighbour, then declaration: the first of a repeated pair stays.
            list.sort_unstable();
            list.dedup_by_key(|(w, _)| *w);
        }
        Adjacency::Declared(neighbours)
    }

    /// The move arcs of a movable end-effector that reaches `reaches` (sorted): every
    /// ordered pair of adjacent workspaces in it, in order of the first then the second,
    /// with the declaring `adjacent` (if declared).
    fn moves<'a>(
        &'a self,
        reaches: &'a [WorkspaceId],
    ) -> impl Iterator<Item = (WorkspaceId, WorkspaceId, Option<usize>)> + 'a {
        reaches.iter().flat_map(move |&wi| {
            let pairs: Box<dyn Iterator<Item = (WorkspaceId, WorkspaceId, Option<usize>)>> =
                match self {
                    Adjacency::Derived => Box::new(
                        reaches
                            .iter()
                            .filter(move |&&wj| wj != wi)
                            .map(move |&wj| (wi, wj, None)),
                    ),
                    Adjacency::Declared(neighbours) => Box::new(
                        neighbours[wi.index()]
                            .iter()
                            .filter(|(wj, _)| reaches.binary_search(wj).is_ok())
                            .map(move |&(wj, i)| (wi, wj, Some(i))),
                    ),
                };
            pairs
        })
    }

    /// How many move arcs [`Adjacency::moves`] gives for `reaches`, without listing them.
    pub(crate) fn n_moves(&self, reaches: &[WorkspaceId]) -> u64 {
        match self {
            Adjacency::Derived => {
                let r = reaches.len() as u64;
                r * r.saturating_sub(1)
            }
            Adjacency::Declared(_) => self.moves(reaches).count() as u64,
        }
    }

    /// Every adjacent pair `(a, b)` with `a < b`, each once, in order; when deriving them
    /// would list more than `limit` (before removing repeats), that count instead.
    pub fn pairs(&self, cell: &Cell, limit: u64) -> Result<Vec<(WorkspaceId, WorkspaceId)>, u64> {
        let mut pairs = Vec::new();
        match self {
            Adjacency::Derived => {
                let mut listed = 0u64;
                for (_, e) in cell.end_effectors.iter().filter(|(_, e)| e.is_movable()) {
                    let r = e.reaches.len() as u64;
                    listed = listed.saturating_add(r * r.saturating_sub(1) / 2);
                    if listed > limit {
                        return Err(listed);
                    }
                    for (i, &a) in e.reaches.iter().enumerate() {
                        pairs.extend(e.reaches[i + 1..].iter().map(|&b| (a, b)));
                    }
                }
                pairs.sort_unstable();
                pairs.dedup();
            }
            Adjacency::Declared(neighbours) => {
                for (a, list) in neighbours.iter().enumerate() {
                    let a = WorkspaceId(a as u32);
                    pairs.extend(list.iter().filter(|(b, _)| a < *b).map(|&(b, _)| (a, b)));
                }
            }
        }
        Ok(pairs)
    }
}

/// A grasp's states as `(workspace, holder)`, sorted: the order in which a transition's
/// arcs are found, by merging the lists of its two grasps.
pub(crate) fn states_by_workspace(
    cell: &Cell,
    holders: &Holders,
    g: GraspId,
) -> Vec<(WorkspaceId, EndEffectorId)> {
    let mut states: Vec<(WorkspaceId, EndEffectorId)> = holders
        .of(g)
        .iter()
        .flat_map(|&e| cell.end_effectors[e].reaches.iter().map(move |&w| (w, e)))
        .collect();
    states.sort_unstable();
    states
}

/// A grasp's states in one workspace, as `(workspace, holder)`.
pub(crate) type StatesHere<'a> = &'a [(WorkspaceId, EndEffectorId)];

/// The workspaces two sorted state lists share, each with both lists' states there, in
/// workspace order.
pub(crate) fn shared_workspaces<'a>(
    from: StatesHere<'a>,
    to: StatesHere<'a>,
) -> impl Iterator<Item = (WorkspaceId, StatesHere<'a>, StatesHere<'a>)> + 'a {
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
            let here = (wa, &from[i..i_end], &to[j..j_end]);
            (i, j) = (i_end, j_end);
            return Some(here);
        }
        None
    })
}

/// Whether `giver` passes an object to `taker` by a transition: never two fixed
/// end-effectors, and a hand kind's grasps expand to every hand of that kind but no hand
/// passes an object to itself (explicit same-holder rows, as imported databases have, are
/// kept and warned about).
pub(crate) fn exchanges(
    cell: &Cell,
    giver: EndEffectorId,
    taker: EndEffectorId,
    explicit: bool,
) -> bool {
    (giver != taker || explicit)
        && (cell.end_effectors[giver].is_movable() || cell.end_effectors[taker].is_movable())
}

/// Whether a transition's two grasps are both declared for end-effectors (not kinds).
pub(crate) fn is_explicit(cell: &Cell, transition: &Transition) -> bool {
    let explicit = |g: GraspId| matches!(cell.grasps[g].holder, Some(Holder::EndEffector(_)));
    explicit(transition.from) && explicit(transition.to)
}

/// Each object's transitions (indices into [`Cell::transitions`]), in declaration order.
pub(crate) fn transitions_by_object(cell: &Cell) -> Vec<Vec<usize>> {
    let mut transitions: Vec<Vec<usize>> = vec![Vec::new(); cell.objects.len()];
    for (t, transition) in cell.transitions.iter().enumerate() {
        let object = cell.grasps[transition.from].object;
        if cell.grasps[transition.to].object == object {
            transitions[object.index()].push(t);
        }
    }
    transitions
}

/// Builds the graph of every object, in object order. Callers check the size first
/// ([`crate::budget::check`]): building costs what the graphs hold.
pub fn build(cell: &Cell) -> Vec<ObjectGraph> {
    let adjacency = Adjacency::of(cell);
    let holders = cell.holders();
    let transitions = transitions_by_object(cell);
    cell.objects
        .iter()
        .map(|(object, obj)| {
            let parts = Parts {
                cell,
                holders: &holders,
                adjacency: &adjacency,
                transitions: &transitions[object.index()],
            };
            build_object(&parts, object, obj)
        })
        .collect()
}

/// What every object's graph is built from.
struct Parts<'a> {
    cell: &'a Cell,
    holders: &'a Holders,
    adjacency: &'a Adjacency,
    /// The object's transitions (indices into [`Cell::transitions`]).
    transitions: &'a [usize],
}

fn build_object(parts: &Parts<'_>, object: ObjectId, obj: &Object) -> ObjectGraph {
    let Parts {
        cell,
        holders,
        adjacency,
        ..
    } = *parts;
    let mut graph = DiGraph::new();
    let mut index = HashMap::new();
    // first[(e, g)] = node of S(e, g, reaches(e)[0]); the states of one (e, g) are
    // consecutive, in the order of e's sorted reach, so a state's node is found by a
    // binary search instead of hashing every arc's endpoints.
    let mut first: HashMap<(EndEffectorId, GraspId), u32> = HashMap::new();
    for &g in &obj.grasps {
        for &e in holders.of(g) {
            first.insert((e, g), graph.node_count() as u32);
            for &w in &cell.end_effectors[e].reaches {
                let state = State {
                    end_effector: e,
                    grasp: g,
                    workspace: w,
                };
                index.insert(state, graph.add_node(state));
            }
        }
    }
    let node = |e: EndEffectorId, g: GraspId, w: WorkspaceId| -> Option<NodeIndex> {
        let start = *first.get(&(e, g))?;
        let position = cell.end_effectors[e].reaches.binary_search(&w).ok()?;
        Some(NodeIndex::new(start as usize + position))
    };
    let weights = cell.weights;
    for &g in &obj.grasps {
        for &e in holders.of(g) {
            let ee = &cell.end_effectors[e];
            if !ee.is_movable() {
                continue;
            }
            for (wi, wj, adj) in adjacency.moves(&ee.reaches) {
                if let (Some(from), Some(to)) = (node(e, g, wi), node(e, g, wj)) {
                    graph.add_edge(
                        from,
                        to,
                        StateArc {
                            weight: weights.move_weight,
                            source: ArcSource::Move { adjacency: adj },
                        },
                    );
                }
            }
        }
    }
    let states_of: HashMap<GraspId, Vec<(WorkspaceId, EndEffectorId)>> = obj
        .grasps
        .iter()
        .map(|&g| (g, states_by_workspace(cell, holders, g)))
        .collect();
    for &t in parts.transitions {
        let transition = &cell.transitions[t];
        let explicit = is_explicit(cell, transition);
        let (Some(givers), Some(takers)) = (
            states_of.get(&transition.from),
            states_of.get(&transition.to),
        ) else {
            continue;
        };
        for (w, here_from, here_to) in shared_workspaces(givers, takers) {
            for &(_, ei) in here_from {
                for &(_, ej) in here_to {
                    if !exchanges(cell, ei, ej, explicit) {
                        continue;
                    }
                    if let (Some(from), Some(to)) =
                        (node(ei, transition.from, w), node(ej, transition.to, w))
                    {
                        graph.add_edge(
                            from,
                            to,
                            StateArc {
                                weight: weights.transition_weight,
                                source: ArcSource::Transition { transition: t },
                            },
                        );
                    }
                }
            }
        }
    }
    ObjectGraph {
        object,
        graph,
        index,
    }
}
