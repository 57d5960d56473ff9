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

/// The most states, arcs and adjacent workspace pairs the graphs of one cell may have in
/// all. Memory grows with them (about 60 bytes each, with the artifact), so a cell that
/// would need more is refused before anything is built.
pub const MAX_GRAPH_SIZE: u64 = 5_000_000;

/// The most states expanding transitions may visit in all: a transition visits the states
/// of its two grasps to find those that share a workspace, so a cell with many
/// transitions between grasps with many states is refused even when few arcs result.
pub const MAX_TRANSITION_VISITS: u64 = 100_000_000;

/// Why the graphs were not built: they would exceed [`MAX_GRAPH_SIZE`] or
/// [`MAX_TRANSITION_VISITS`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TooLarge {
    /// The object whose graph crossed the limit (`None` when the adjacency of the cell
    /// alone does).
    pub object: Option<ObjectId>,
    /// What was counted when the limit was crossed (at least the limit).
    pub counted: u64,
    /// The limit crossed.
    pub limit: u64,
    /// The movable end-effector that reaches the most workspaces, with how many (it
    /// makes the most move arcs).
    pub biggest_reach: Option<(EndEffectorId, usize)>,
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
    fn n_moves(&self, reaches: &[WorkspaceId]) -> u64 {
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

/// Counts toward [`MAX_GRAPH_SIZE`] and [`MAX_TRANSITION_VISITS`].
struct Budget {
    size: u64,
    visits: u64,
}

impl Budget {
    fn add_size(&mut self, n: u64) -> Result<(), u64> {
        self.size = self.size.saturating_add(n);
        if self.size > MAX_GRAPH_SIZE {
            return Err(MAX_GRAPH_SIZE);
        }
        Ok(())
    }

    fn add_visits(&mut self, n: u64) -> Result<(), u64> {
        self.visits = self.visits.saturating_add(n);
        if self.visits > MAX_TRANSITION_VISITS {
            return Err(MAX_TRANSITION_VISITS);
        }
        Ok(())
    }
}

/// Builds the graph of every object, in object order; refuses (before building, as far as
/// counting allows) graphs beyond [`MAX_GRAPH_SIZE`] or [`MAX_TRANSITION_VISITS`].
pub fn build(cell: &Cell) -> Result<Vec<ObjectGraph>, TooLarge> {
    let adjacency = Adjacency::of(cell);
    let holders = cell.holders();
    let biggest_reach = cell
        .end_effectors
        .iter()
        .filter(|(_, e)| e.is_movable())
        .map(|(id, e)| (id, e.reaches.len()))
        .max_by_key(|&(id, n)| (n, std::cmp::Reverse(id)));
    let too_large = |object: Option<ObjectId>, budget: &Budget, limit: u64| TooLarge {
        object,
        counted: if limit == MAX_GRAPH_SIZE {
            budget.size
        } else {
            budget.visits
        },
        limit,
        biggest_reach,
    };
    let mut budget = Budget { size: 0, visits: 0 };
    // The artifact records the adjacent pairs: they count, and must be few enough to list.
    match adjacency.pairs(cell, MAX_GRAPH_SIZE) {
        Ok(pairs) => budget.size = pairs.len() as u64,
        Err(listed) => budget.size = listed,
    }
    if budget.size > MAX_GRAPH_SIZE {
        return Err(too_large(None, &budget, MAX_GRAPH_SIZE));
    }
    // Count states and move arcs of every object first (cheap, exact), so a cell far
    // beyond the limit is refused before any graph exists.
    let moves_of: Vec<u64> = cell
        .end_effectors
        .iter()
        .map(|(_, e)| {
            if e.is_movable() {
                adjacency.n_moves(&e.reaches)
            } else {
                0
            }
        })
        .collect();
    for (object, obj) in cell.objects.iter() {
        for &g in &obj.grasps {
            for &e in holders.of(g) {
                budget
                    .add_size(cell.end_effectors[e].reaches.len() as u64 + moves_of[e.index()])
                    .map_err(|limit| too_large(Some(object), &budget, limit))?;
            }
        }
    }
    // Each object's transitions, in declaration order.
    let mut transitions: Vec<Vec<usize>> = vec![Vec::new(); cell.objects.len()];
    for (t, transition) in cell.transitions.iter().enumerate() {
        let object = cell.grasps[transition.from].object;
        if cell.grasps[transition.to].object == object {
            transitions[object.index()].push(t);
        }
    }
    let mut graphs = Vec::with_capacity(cell.objects.len());
    for (object, obj) in cell.objects.iter() {
        let parts = Parts {
            cell,
            holders: &holders,
            adjacency: &adjacency,
            transitions: &transitions[object.index()],
        };
        let graph = build_object(&parts, object, obj, &mut budget)
            .map_err(|limit| too_large(Some(object), &budget, limit))?;
        graphs.push(graph);
    }
    Ok(graphs)
}

/// What every object's graph is built from.
struct Parts<'a> {
    cell: &'a Cell,
    holders: &'a Holders,
    adjacency: &'a Adjacency,
    /// The object's transitions (indices into [`Cell::transitions`]).
    transitions: &'a [usize],
}

fn build_object(
    parts: &Parts<'_>,
    object: ObjectId,
    obj: &Object,
    budget: &mut Budget,
) -> Result<ObjectGraph, u64> {
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
    // The states of each grasp sorted by workspace, then holder: a transition's arcs join
    // the states of its two grasps that share a workspace, found by merging the two lists.
    let by_workspace = |g: GraspId| -> Vec<(WorkspaceId, EndEffectorId)> {
        let mut states: Vec<(WorkspaceId, EndEffectorId)> = holders
            .of(g)
            .iter()
            .flat_map(|&e| cell.end_effectors[e].reaches.iter().map(move |&w| (w, e)))
            .collect();
        states.sort_unstable();
        states
    };
    let states_of: HashMap<GraspId, Vec<(WorkspaceId, EndEffectorId)>> =
        obj.grasps.iter().map(|&g| (g, by_workspace(g))).collect();
    for &t in parts.transitions {
        let transition = &cell.transitions[t];
        let explicit = matches!(
            cell.grasps[transition.from].holder,
            Some(Holder::EndEffector(_))
        ) && matches!(
            cell.grasps[transition.to].holder,
            Some(Holder::EndEffector(_))
        );
        let (Some(from_states), Some(to_states)) = (
            states_of.get(&transition.from),
            states_of.get(&transition.to),
        ) else {
            continue;
        };
        budget.add_visits((from_states.len() + to_states.len()) as u64)?;
        let (mut i, mut j) = (0, 0);
        while i < from_states.len() && j < to_states.len() {
            let (wa, wb) = (from_states[i].0, to_states[j].0);
            if wa < wb {
                i += 1;
                continue;
            }
            if wb < wa {
                j += 1;
                continue;
            }
            let w = wa;
            let i_end = i + from_states[i..].partition_point(|s| s.0 == w);
            let j_end = j + to_states[j..].partition_point(|s| s.0 == w);
            budget.add_visits(((i_end - i) * (j_end - j)) as u64)?;
            for &(_, ei) in &from_states[i..i_end] {
                for &(_, ej) in &to_states[j..j_end] {
                    // A hand kind's grasps expand to every hand of that kind, but no hand
                    // passes an object to itself; explicit same-holder rows (imported
                    // databases) are kept and warned about.
                    if ei == ej && !explicit {
                        continue;
                    }
                    if !cell.end_effectors[ei].is_movable() && !cell.end_effectors[ej].is_movable()
                    {
                        continue;
                    }
                    if let (Some(from), Some(to)) =
                        (node(ei, transition.from, w), node(ej, transition.to, w))
                    {
                        budget.add_size(1)?;
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
            i = i_end;
            j = j_end;
        }
    }
    Ok(ObjectGraph {
        object,
        graph,
        index,
    })
}
