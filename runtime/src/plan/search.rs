//! Cheapest state paths on an object's graph (Dijkstra through petgraph), with arcs that
//! failed during this request left out, and the paper's simplification of runs of moves.

use std::collections::HashSet;

use cellc_schema::{ArcKind, Graph, NodeId};
use petgraph::graph::{DiGraph, EdgeIndex, NodeIndex};
use petgraph::visit::EdgeFiltered;

use super::ArcRef;

/// An object's graph ready for repeated searches.
#[derive(Clone, Debug)]
pub struct SearchGraph {
    graph: DiGraph<(), (f64, usize)>,
    /// Per arc: true for moves (to re-weight by kind).
    is_move: Vec<bool>,
    /// Weights replacing the artifact's, by kind (move, transition).
    reweight: Option<(f64, f64)>,
}

/// Billionths per unit of cost, for [`SearchGraph::path_cost`].
const BILLION: f64 = 1e9;

/// A path: node indices, the arcs between them (indices into `Graph::arcs`), its cost.
#[derive(Clone, Debug, PartialEq)]
pub struct Path {
    /// Nodes, start first.
    pub nodes: Vec<NodeId>,
    /// Arc indices, one fewer than nodes.
    pub arcs: Vec<usize>,
    /// Sum of arc weights.
    pub cost: f64,
}

impl SearchGraph {
    /// The search graphs of every object of an artifact, in object order.
    pub fn for_artifact(artifact: &cellc_schema::Artifact) -> Vec<SearchGraph> {
        artifact
            .objects
            .iter()
            .map(|o| SearchGraph::new(&o.graph))
            .collect()
    }

    /// Indexes the artifact's graph of one object.
    pub fn new(graph: &Graph) -> SearchGraph {
        let mut g = DiGraph::with_capacity(graph.nodes.len(), graph.arcs.len());
        for _ in &graph.nodes {
            g.add_node(());
        }
        for (i, arc) in graph.arcs.iter().enumerate() {
            g.add_edge(
                NodeIndex::new(arc.from as usize),
                NodeIndex::new(arc.to as usize),
                (arc.weight, i),
            );
        }
        SearchGraph {
            graph: g,
            is_move: graph.arcs.iter().map(|a| a.kind == ArcKind::Move).collect(),
            reweight: None,
        }
    }

    /// The same graph with every move costing `weights.0` and every transition
    /// `weights.1`.
    pub fn reweighted(&self, weights: (f64, f64)) -> SearchGraph {
        SearchGraph {
            graph: self.graph.clone(),
            is_move: self.is_move.clone(),
            reweight: Some(weights),
        }
    }

    fn weight(&self, w: &(f64, usize)) -> f64 {
        match self.reweight {
            Some((moves, _)) if self.is_move[w.1] => moves,
            Some((_, transitions)) => transitions,
            None => w.0,
        }
    }

    /// The cheapest path from `start` to any of `goals`, not using `removed` arcs. Ties are
    /// broken by petgraph's deterministic order (arc order of the artifact).
    pub fn shortest(
        &self,
        start: NodeId,
        goals: &[NodeId],
        removed: &HashSet<ArcRef>,
    ) -> Option<Path> {
        let goal_set: HashSet<NodeId> = goals.iter().copied().collect();
        let filtered = EdgeFiltered::from_fn(
            &self.graph,
            |e: petgraph::graph::EdgeReference<'_, (f64, usize)>| {
                use petgraph::visit::EdgeRef;
                !removed.contains(&ArcRef {
                    from: node_id(e.source()),
                    to: node_id(e.target()),
                })
            },
        );
        let (cost, nodes) = petgraph::algo::astar(
            &filtered,
            NodeIndex::new(start.index()),
            |n| goal_set.contains(&node_id(n)),
            |e| self.weight(e.weight()),
            |_| 0.0,
        )?;
        let nodes: Vec<NodeId> = nodes.into_iter().map(node_id).collect();
        let arcs = nodes
            .windows(2)
            .map(|w| self.cheapest_arc(w[0], w[1], removed))
            .collect::<Option<Vec<usize>>>()?;
        let cost = self.path_cost(&arcs).unwrap_or(cost);
        Some(Path { nodes, arcs, cost })
    }

    /// The cheapest path of at least one arc from `start` to a goal (the start may be a
    /// goal: the object must leave it and come back).
    pub fn shortest_leaving(
        &self,
        start: NodeId,
        goals: &[NodeId],
        removed: &HashSet<ArcRef>,
    ) -> Option<Path> {
        use petgraph::visit::EdgeRef;
        let mut best: Option<Path> = None;
        for e in self.graph.edges(NodeIndex::new(start.index())) {
            let next = node_id(e.target());
            let (weight, arc) = (self.weight(e.weight()), e.weight().1);
            if removed.contains(&ArcRef {
                from: start,
                to: next,
            }) {
                continue;
            }
            let Some(rest) = self.shortest(next, goals, removed) else {
                continue;
            };
            let cost = weight + rest.cost;
            if best.as_ref().is_none_or(|b| cost < b.cost) {
                let mut nodes = vec![start];
                nodes.extend(rest.nodes);
                let mut arcs = vec![arc];
                arcs.extend(rest.arcs);
                let cost = self.path_cost(&arcs).unwrap_or(cost);
                best = Some(Path { nodes, arcs, cost });
            }
        }
        best
    }

    /// The cost of a path of `arcs` as the sum of its weights in decimal: the weights
    /// are written in decimal (0.1 per move), and their binary sum drifts
    /// (`8.599999999999998` for 8.6), so they are added as whole billionths and the
    /// total converted once. `None` when a weight is not a whole number of billionths
    /// within 10^-12 (or is too large for that), which no cell's weights are.
    fn path_cost(&self, arcs: &[usize]) -> Option<f64> {
        let mut total: i128 = 0;
        for &arc in arcs {
            let w = self.weight(self.graph.edge_weight(EdgeIndex::new(arc))?);
            let scaled = w * BILLION;
            let whole = scaled.round();
            if !whole.is_finite() || whole.abs() >= 1e18 || (scaled - whole).abs() > 1e-3 {
                return None;
            }
            total += whole as i128;
        }
        Some(total as f64 / BILLION)
    }

    fn cheapest_arc(&self, from: NodeId, to: NodeId, removed: &HashSet<ArcRef>) -> Option<usize> {
        if removed.contains(&ArcRef { from, to }) {
            return None;
        }
        self.graph
            .edges_connecting(NodeIndex::new(from.index()), NodeIndex::new(to.index()))
            .map(|e| (self.weight(e.weight()), e.weight().1))
            .min_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)))
            .map(|(_, i)| i)
    }

    /// Every node reachable from `start` without `removed` arcs (for explanations).
    pub fn reachable(&self, start: NodeId, removed: &HashSet<ArcRef>) -> Vec<NodeId> {
        let mut seen = vec![false; self.graph.node_count()];
        let mut stack = vec![start];
        let mut out = Vec::new();
        while let Some(n) = stack.pop() {
            if seen
                .get_mut(n.index())
                .is_none_or(|s| std::mem::replace(s, true))
            {
                continue;
            }
            out.push(n);
            for e in self.graph.edges(NodeIndex::new(n.index())) {
                use petgraph::visit::EdgeRef;
                let to = node_id(e.target());
                if !removed.contains(&ArcRef { from: n, to }) && !seen[to.index()] {
                    stack.push(to);
                }
            }
        }
        out.sort_unstable();
        out
    }

    /// The arc index of an edge (test helper).
    pub fn arc_of(&self, e: EdgeIndex) -> Option<usize> {
        self.graph.edge_weight(e).map(|w| w.1)
    }
}

/// A petgraph node as the artifact's node id (the graph is built with one petgraph node
/// per artifact node, in order).
fn node_id(n: NodeIndex) -> NodeId {
    NodeId(n.index() as u32)
}

/// The paper's simplification: a run of consecutive moves of one end-effector becomes one
/// move to the run's last workspace. Returns the kept node indices (start, the end of
/// each move run, and both ends of every transition).
pub fn simplify(graph: &Graph, path: &Path) -> Vec<NodeId> {
    let mut kept = vec![path.nodes[0]];
    for (i, &arc) in path.arcs.iter().enumerate() {
        let is_move = graph.arcs[arc].kind == ArcKind::Move;
        let next_is_move = path
            .arcs
            .get(i + 1)
            .is_some_and(|&a| graph.arcs[a].kind == ArcKind::Move);
        if is_move && next_is_move {
            continue;
        }
        kept.push(path.nodes[i + 1]);
    }
    kept
}

/// What a search does with a node an arc leads to (see [`cheapest_exit`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Visit {
    /// Do not enter it.
    Skip,
    /// Search on from it.
    Enter,
    /// The rest of the way from it is known and costs this much: a path may end here.
    Exit(f64),
}

/// Dijkstra for graphs that exist only as a function: the cheapest path from any of
/// `sources` (each with the cost already paid to get there) through nodes that `visit`
/// lets the search [enter](Visit::Enter) to an arc leading to an [exit](Visit::Exit).
/// `arcs(u, out)` appends the arcs leaving `u` as (head, weight, label). Returns the total
/// cost and the labels of the arcs taken, in path order.
///
/// The explanation of an unreachable goal uses it to search hypothetical arcs on top of an
/// object's graph without building a graph per hypothesis: it starts on the start's side,
/// explores only the states between the two sides, and exits on entering the goal's side
/// (whose distances to the goal are known). Ties go to the node with the smaller id, then
/// to the arc found first.
pub fn cheapest_exit<N, L>(
    sources: impl IntoIterator<Item = (N, f64)>,
    mut arcs: impl FnMut(N, &mut Vec<(N, f64, L)>),
    mut visit: impl FnMut(N) -> Visit,
) -> Option<(f64, Vec<L>)>
where
    N: Copy + Ord + std::hash::Hash,
    L: Copy,
{
    use std::cmp::Reverse;
    use std::collections::{BinaryHeap, HashMap};

    /// A cost ordered totally, for the heap.
    #[derive(Clone, Copy, PartialEq)]
    struct Cost(f64);
    impl Eq for Cost {}
    impl PartialOrd for Cost {
        fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
            Some(self.cmp(other))
        }
    }
    impl Ord for Cost {
        fn cmp(&self, other: &Self) -> std::cmp::Ordering {
            self.0.total_cmp(&other.0)
        }
    }

    let mut dist: HashMap<N, f64> = HashMap::new();
    let mut pred: HashMap<N, (N, L)> = HashMap::new();
    let mut heap = BinaryHeap::new();
    for (node, cost) in sources {
        if let std::collections::hash_map::Entry::Vacant(slot) = dist.entry(node) {
            slot.insert(cost);
            heap.push(Reverse((Cost(cost), node)));
        }
    }
    let mut best: Option<(f64, N, L)> = None;
    let mut out = Vec::new();
    while let Some(Reverse((Cost(d), u))) = heap.pop() {
        if dist.get(&u).is_some_and(|&x| d > x) {
            continue;
        }
        if best.as_ref().is_some_and(|b| d >= b.0) {
            break;
        }
        out.clear();
        arcs(u, &mut out);
        for &(v, weight, label) in &out {
            let nd = d + weight;
            match visit(v) {
                Visit::Skip => {}
                Visit::Exit(rest) => {
                    let through = nd + rest;
                    if best.as_ref().is_none_or(|b| through < b.0) {
                        best = Some((through, u, label));
                    }
                }
                Visit::Enter => {
                    if dist.get(&v).is_none_or(|&x| nd < x) {
                        dist.insert(v, nd);
                        pred.insert(v, (u, label));
                        heap.push(Reverse((Cost(nd), v)));
                    }
                }
            }
        }
    }
    let (cost, mut u, last) = best?;
    let mut labels = vec![last];
    while let Some(&(p, label)) = pred.get(&u) {
        labels.push(label);
        u = p;
    }
    labels.reverse();
    Some((cost, labels))
}
