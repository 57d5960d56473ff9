//! The object-state graph, one per object (the paper's Sec. IV-A).
//!
//! Which states and arcs a graph has is decided by the shared rules in
//! [`cellc_schema::rules`] (the runtime's explanations of unreachable goals use the same
//! rules to know what a change to the cell would add); this module feeds them the
//! resolved cell and keeps the result as a petgraph graph of the compiler's typed ids.
//! Each arc records which declaration made it, so any finding about an arc can point at
//! source lines.

use rustc_hash::FxHashMap as HashMap;

use cellc_schema::rules::{
    Adjacency, CellRules, EndEffectorFacts, GraspFacts, ObjectRules, Provenance,
};
use cellc_schema::{EndEffectorId as EeIndex, GraspId as GraspIndex, WorkspaceId as WsIndex};
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
    /// The graph of `object` with no states (the scene of `reach auto` is lowered before
    /// any graph is built).
    pub fn empty(object: ObjectId) -> ObjectGraph {
        ObjectGraph {
            object,
            graph: DiGraph::new(),
            index: HashMap::default(),
        }
    }

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

/// The shared graph rules fed with a resolved cell, once: what [`crate::budget::check`]
/// counts and [`build`] builds, so the two cannot disagree.
#[derive(Clone, Debug)]
pub struct GraphRules {
    /// The cell-level rules: end-effectors with their reach, and adjacency.
    pub cell: CellRules,
    /// Each object's rules (its grasps, their holders, its transitions), in object order.
    pub objects: Vec<ObjectRules>,
    /// Per object, the cell's transition (index into [`Cell::transitions`]) behind each
    /// transition of its rules.
    transitions: Vec<Vec<usize>>,
}

/// The graph rules of a resolved cell: [`cell_rules`], and per object its grasps (a
/// kind's grasp held by every end-effector of the kind) and transitions.
pub fn rules_of(cell: &Cell) -> GraphRules {
    let holders = cell.holders();
    let by_object = transitions_by_object(cell);
    let (objects, transitions) = cell
        .objects
        .iter()
        .map(|(object, obj)| object_rules(cell, &holders, &by_object[object.index()], obj))
        .unzip();
    GraphRules {
        cell: cell_rules(cell),
        objects,
        transitions,
    }
}

/// The cell-level graph rules of a resolved cell: end-effectors with their reach, and the
/// declared adjacency (or, when the cell declares none, adjacency derived from reach).
pub fn cell_rules(cell: &Cell) -> CellRules {
    let end_effectors = cell
        .end_effectors
        .iter()
        .map(|(_, e)| EndEffectorFacts {
            movable: e.is_movable(),
            reaches: e.reaches.iter().map(|w| WsIndex(w.0)).collect(),
        })
        .collect();
    let adjacency = if cell.adjacencies.is_empty() {
        Adjacency::Derived
    } else {
        Adjacency::Declared(
            cell.adjacencies
                .iter()
                .map(|adj| (WsIndex(adj.a.0), WsIndex(adj.b.0)))
                .collect(),
        )
    };
    CellRules::new(cell.workspaces.len(), end_effectors, adjacency)
}

/// One object's rules, with the cell's transition behind each of its own.
fn object_rules(
    cell: &Cell,
    holders: &Holders,
    own: &[usize],
    obj: &Object,
) -> (ObjectRules, Vec<usize>) {
    // The rules index an object's own grasps; the cell's transitions are global.
    let local: HashMap<GraspId, u32> = obj
        .grasps
        .iter()
        .enumerate()
        .map(|(i, &g)| (g, i as u32))
        .collect();
    let grasps = obj
        .grasps
        .iter()
        .map(|&g| GraspFacts {
            holders: holders.of(g).iter().map(|e| EeIndex(e.0)).collect(),
            explicit: matches!(cell.grasps[g].holder, Some(Holder::EndEffector(_))),
        })
        .collect();
    let mut declared = Vec::new();
    let mut transitions = Vec::new();
    for &t in own {
        let transition = &cell.transitions[t];
        if let (Some(&from), Some(&to)) = (local.get(&transition.from), local.get(&transition.to)) {
            declared.push(t);
            transitions.push((GraspIndex(from), GraspIndex(to)));
        }
    }
    let rules = ObjectRules::new(cell.end_effectors.len(), grasps, transitions);
    (rules, declared)
}

/// Each object's transitions (indices into [`Cell::transitions`]), in declaration order:
/// cells list transitions globally, and looking at every transition for every object
/// would be quadratic.
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

/// Builds the graph of every object, in object order. Callers count the graphs first
/// ([`crate::budget::check`] on the same `rules`): building costs what the graphs hold.
pub fn build(cell: &Cell, rules: &GraphRules) -> Vec<ObjectGraph> {
    cell.objects
        .iter()
        .map(|(object, obj)| build_object(cell, rules, object, obj))
        .collect()
}

fn build_object(cell: &Cell, rules: &GraphRules, object: ObjectId, obj: &Object) -> ObjectGraph {
    let object_rules = &rules.objects[object.index()];
    let declared = &rules.transitions[object.index()];
    let mut graph = DiGraph::new();
    let mut index = HashMap::default();
    for s in rules.cell.states(object_rules) {
        let state = State {
            end_effector: EndEffectorId(s.end_effector.0),
            grasp: obj.grasps[s.grasp.index()],
            workspace: WorkspaceId(s.workspace.0),
        };
        index.insert(state, graph.add_node(state));
    }
    let weights = cell.weights;
    rules
        .cell
        .for_each_arc(object_rules, |from, to, provenance| {
            let arc = match provenance {
                Provenance::Move { adjacency } => StateArc {
                    weight: weights.move_weight,
                    source: ArcSource::Move { adjacency },
                },
                Provenance::Transition { transition } => StateArc {
                    weight: weights.transition_weight,
                    source: ArcSource::Transition {
                        transition: declared[transition],
                    },
                },
            };
            graph.add_edge(
                NodeIndex::new(from as usize),
                NodeIndex::new(to as usize),
                arc,
            );
        });
    ObjectGraph {
        object,
        graph,
        index,
    }
}
