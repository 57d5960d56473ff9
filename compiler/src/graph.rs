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

/// Builds the graph of every object, in object order.
pub fn build(cell: &Cell) -> Vec<ObjectGraph> {
    let n_ws = cell.workspaces.len();
    // adjacency[a * n + b] -> index of the declaring `adjacent` (or usize::MAX when
    // adjacency is derived from reach).
    let mut adjacency: Vec<Option<Option<usize>>> = vec![None; n_ws * n_ws];
    if cell.adjacencies.is_empty() {
        for (_, e) in cell.end_effectors.iter().filter(|(_, e)| e.is_movable()) {
            for &a in &e.reaches {
                for &b in &e.reaches {
                    if a != b {
                        adjacency[a.index() * n_ws + b.index()] = Some(None);
                    }
                }
            }
        }
    } else {
        for (i, adj) in cell.adjacencies.iter().enumerate() {
            for (a, b) in [(adj.a, adj.b), (adj.b, adj.a)] {
                let slot = &mut adjacency[a.index() * n_ws + b.index()];
                if slot.is_none() {
                    *slot = Some(Some(i));
                }
            }
        }
    }
    let holders: Vec<Vec<EndEffectorId>> = cell.grasps.ids().map(|g| cell.holders_of(g)).collect();
    cell.objects
        .iter()
        .map(|(object, obj)| build_object(cell, object, obj, &holders, &adjacency, n_ws))
        .collect()
}

fn build_object(
    cell: &Cell,
    object: ObjectId,
    obj: &Object,
    holders: &[Vec<EndEffectorId>],
    adjacency: &[Option<Option<usize>>],
    n_ws: usize,
) -> ObjectGraph {
    let mut graph = DiGraph::new();
    let mut index = HashMap::new();
    // first[(e, g)] = node of S(e, g, reaches(e)[0]); the states of one (e, g) are
    // consecutive, in the order of e's sorted reach, so a state's node is found by a
    // binary search instead of hashing every arc's endpoints.
    let mut first: HashMap<(EndEffectorId, GraspId), u32> = HashMap::new();
    for &g in &obj.grasps {
        for &e in &holders[g.index()] {
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
        for &e in &holders[g.index()] {
            let ee = &cell.end_effectors[e];
            if !ee.is_movable() {
                continue;
            }
            for &wi in &ee.reaches {
                for &wj in &ee.reaches {
                    let Some(adj) = adjacency[wi.index() * n_ws + wj.index()] else {
                        continue;
                    };
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
    }
    // Who reaches each workspace: usually two or three end-effectors, so transitions are
    // expanded per workspace rather than per pair of holders.
    let mut reachers: Vec<Vec<EndEffectorId>> = vec![Vec::new(); n_ws];
    for (e, ee) in cell.end_effectors.iter() {
        for &w in &ee.reaches {
            reachers[w.index()].push(e);
        }
    }
    for (t, transition) in cell.transitions.iter().enumerate() {
        if cell.grasps[transition.from].object != object
            || cell.grasps[transition.to].object != object
        {
            continue;
        }
        let explicit = matches!(
            cell.grasps[transition.from].holder,
            Some(Holder::EndEffector(_))
        ) && matches!(
            cell.grasps[transition.to].holder,
            Some(Holder::EndEffector(_))
        );
        let (from_holders, to_holders) = (
            &holders[transition.from.index()],
            &holders[transition.to.index()],
        );
        for (w, here) in reachers.iter().enumerate() {
            let w = WorkspaceId(w as u32);
            for &ei in here
                .iter()
                .filter(|e| from_holders.binary_search(e).is_ok())
            {
                for &ej in here.iter().filter(|e| to_holders.binary_search(e).is_ok()) {
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
