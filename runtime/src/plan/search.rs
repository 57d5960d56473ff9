//! Cheapest state paths on an object's graph, with arcs that failed during this request
//! left out, and the paper's simplification of runs of moves.
//!
//! The graph is stored once per object in compressed sparse rows (an offset per node,
//! then its leaving arcs as target, weight and arc index, contiguous), and Dijkstra runs
//! in a [`Scratch`] that the caller keeps: distances, predecessors, the goal and
//! left-out marks are stamped with the search's epoch, so starting a search is O(1)
//! however large the graph, and a search allocates nothing once its scratch has grown to
//! the graph. A request searches again after every failed step, and a service answers
//! many requests on one graph, so the per-search cost is the heap work alone.
//!
//! Ties are broken as the petgraph search this replaced broke them (a cell's plans did not
//! change with it; the property test below holds the two to the same paths): a node's
//! leaving arcs are relaxed last-declared first, a distance is replaced only by a strictly
//! lower one, the queue is the standard binary heap ordered by distance alone, and the
//! first goal taken from it ends the search. Between two consecutive states of the path,
//! the cheapest arc is taken, the first declared among equals.

use std::collections::{BinaryHeap, HashSet};

use cellc_schema::{ArcKind, Graph, NodeId};

use super::ArcRef;

/// An arc as stored in the rows of its tail: where it leads, what it costs, which arc of
/// the artifact's graph it is.
#[derive(Clone, Copy, Debug, PartialEq)]
struct OutArc {
    to: u32,
    weight: f64,
    arc: u32,
}

/// An object's graph ready for repeated searches.
#[derive(Clone, Debug)]
pub struct SearchGraph {
    /// Node `n`'s leaving arcs are `out[offsets[n]..offsets[n + 1]]`, last declared first.
    offsets: Vec<u32>,
    /// Every arc's weight is kept here only, in its tail's row (the artifact's, or by kind
    /// when re-weighted): a copy per arc of the artifact's graph cost a pass over 10^6
    /// arcs and megabytes to fault in at every load.
    out: Vec<OutArc>,
}

/// Billionths per unit of cost, for [`SearchGraph::path_cost`].
const BILLION: f64 = 1e9;

/// No predecessor: the search's start.
const NONE: u32 = u32::MAX;

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

/// A path found by [`SearchGraph::search`], borrowed from its scratch (no allocation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Route<'s> {
    /// Nodes, start first.
    pub nodes: &'s [NodeId],
    /// Arc indices, one fewer than nodes.
    pub arcs: &'s [usize],
    /// Sum of arc weights.
    pub cost: f64,
}

impl Route<'_> {
    /// The path, owned.
    pub fn to_path(&self) -> Path {
        Path {
            nodes: self.nodes.to_vec(),
            arcs: self.arcs.to_vec(),
            cost: self.cost,
        }
    }
}

/// What a search writes as it goes, kept between searches so that none allocates: sized
/// to the largest graph searched with it, and reset by moving to the next epoch (an entry
/// stamped with an older epoch reads as unwritten).
#[derive(Clone, Debug, Default)]
pub struct Scratch {
    epoch: u32,
    /// Per node: the epoch in which `distance` and `predecessor` were written.
    reached: Vec<u32>,
    distance: Vec<f64>,
    predecessor: Vec<u32>,
    /// Per node: the epoch in which it was made a goal.
    goal: Vec<u32>,
    /// Per stored arc (index into the rows): the epoch in which it was left out. Grown
    /// and read only by searches that leave arcs out: a first search on 10^6 arcs leaves
    /// none out, and 4 MB of marks cost it more to fault in than to search.
    left_out: Vec<u32>,
    /// Whether this epoch's search leaves arcs out.
    leaving_out: bool,
    heap: BinaryHeap<Queued>,
    nodes: Vec<NodeId>,
    arcs: Vec<usize>,
}

impl Scratch {
    /// Starts a search on a graph of `n_nodes` nodes and `n_out` stored arcs: grows the
    /// marks if needed, and moves to a fresh epoch (clearing every mark only when the
    /// epoch counter wraps, once in four billion searches).
    fn begin(&mut self, n_nodes: usize, n_out: usize, leaving_out: bool) {
        if self.reached.len() < n_nodes {
            self.reached.resize(n_nodes, 0);
            self.distance.resize(n_nodes, 0.0);
            self.predecessor.resize(n_nodes, NONE);
            self.goal.resize(n_nodes, 0);
        }
        if leaving_out && self.left_out.len() < n_out {
            self.left_out.resize(n_out, 0);
        }
        self.leaving_out = leaving_out;
        self.epoch = match self.epoch.checked_add(1) {
            Some(next) => next,
            None => {
                self.reached.fill(0);
                self.goal.fill(0);
                self.left_out.fill(0);
                1
            }
        };
        self.heap.clear();
    }

    fn distance(&self, n: u32) -> Option<f64> {
        (self.reached[n as usize] == self.epoch).then(|| self.distance[n as usize])
    }

    /// Whether the stored arc in `slot` is left out of this search.
    fn is_left_out(&self, slot: usize) -> bool {
        self.leaving_out && self.left_out[slot] == self.epoch
    }

    fn reach(&mut self, n: u32, distance: f64, predecessor: u32) {
        self.reached[n as usize] = self.epoch;
        self.distance[n as usize] = distance;
        self.predecessor[n as usize] = predecessor;
    }
}

/// A node in the queue, ordered by distance alone, least first: petgraph's `MinScored`
/// order (NaN last), which the tie-breaking depends on (see the module's documentation).
#[derive(Clone, Copy, Debug)]
struct Queued {
    distance: f64,
    node: u32,
}

impl PartialEq for Queued {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == std::cmp::Ordering::Equal
    }
}

impl Eq for Queued {}

impl PartialOrd for Queued {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Queued {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        use std::cmp::Ordering::{Equal, Greater, Less};
        let (a, b) = (self.distance, other.distance);
        if a == b {
            Equal
        } else if a < b {
            Greater
        } else if a > b {
            Less
        } else if a.is_nan() && b.is_nan() {
            Equal
        } else if a.is_nan() {
            Less
        } else {
            Greater
        }
    }
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

    /// Indexes the artifact's graph of one object. An arc whose ends are not nodes of the
    /// graph (which a validated artifact never has) is never searched.
    pub fn new(graph: &Graph) -> SearchGraph {
        let n = graph.nodes.len();
        let valid = |a: &cellc_schema::Arc| (a.from as usize) < n && (a.to as usize) < n;
        let mut offsets = vec![0u32; n + 1];
        for arc in graph.arcs.iter().filter(|a| valid(a)) {
            offsets[arc.from as usize + 1] += 1;
        }
        for i in 0..n {
            offsets[i + 1] += offsets[i];
        }
        let mut next: Vec<u32> = offsets[..n].to_vec();
        let placeholder = OutArc {
            to: 0,
            weight: 0.0,
            arc: 0,
        };
        // Rows of a 10^6-arc graph are 16 MB of fresh memory: asked for in huge pages.
        let mut out = cellc_schema::huge::with_capacity(offsets[n] as usize);
        out.resize(offsets[n] as usize, placeholder);
        for (i, arc) in graph.arcs.iter().enumerate().rev() {
            if !valid(arc) {
                continue;
            }
            let slot = &mut next[arc.from as usize];
            out[*slot as usize] = OutArc {
                to: arc.to,
                weight: arc.weight,
                arc: i as u32,
            };
            *slot += 1;
        }
        SearchGraph { offsets, out }
    }

    /// The same graph (indexed from `graph`) with every move costing `weights.0` and
    /// every transition `weights.1`.
    pub fn reweighted(&self, graph: &Graph, weights: (f64, f64)) -> SearchGraph {
        let mut search = self.clone();
        for out in &mut search.out {
            let is_move = graph
                .arcs
                .get(out.arc as usize)
                .is_some_and(|a| a.kind == ArcKind::Move);
            out.weight = if is_move { weights.0 } else { weights.1 };
        }
        search
    }

    /// Number of nodes.
    pub fn n_nodes(&self) -> usize {
        self.offsets.len() - 1
    }

    /// The stored arcs leaving `n`, with their indices into the rows.
    fn leaving(&self, n: u32) -> impl Iterator<Item = (usize, &OutArc)> {
        let (lo, hi) = (self.offsets[n as usize], self.offsets[n as usize + 1]);
        (lo as usize..hi as usize).zip(&self.out[lo as usize..hi as usize])
    }

    /// The cheapest path from `start` to any of `goals`, not using `removed` arcs, in
    /// `scratch` (which any earlier search may have used). `None` when no goal can be
    /// reached, or `start` is not a node; goals that are not nodes are never reached.
    pub fn search<'s>(
        &self,
        scratch: &'s mut Scratch,
        start: NodeId,
        goals: &[NodeId],
        removed: &HashSet<ArcRef>,
    ) -> Option<Route<'s>> {
        let n = self.n_nodes();
        if start.index() >= n {
            return None;
        }
        let leaving_out = removed.iter().any(|r| r.from.index() < n);
        scratch.begin(n, self.out.len(), leaving_out);
        let epoch = scratch.epoch;
        for goal in goals.iter().filter(|g| g.index() < n) {
            scratch.goal[goal.index()] = epoch;
        }
        for r in removed.iter().filter(|r| r.from.index() < n) {
            for (slot, out) in self.leaving(r.from.0) {
                if out.to == r.to.0 {
                    scratch.left_out[slot] = epoch;
                }
            }
        }
        scratch.reach(start.0, 0.0, NONE);
        scratch.heap.push(Queued {
            distance: 0.0,
            node: start.0,
        });
        let mut found = None;
        while let Some(Queued { distance, node }) = scratch.heap.pop() {
            if scratch.goal[node as usize] == epoch {
                found = Some(node);
                break;
            }
            if scratch.distance(node).is_some_and(|best| best < distance) {
                continue;
            }
            for (slot, out) in self.leaving(node) {
                if scratch.is_left_out(slot) {
                    continue;
                }
                let through = distance + out.weight;
                if scratch.distance(out.to).is_some_and(|d| through >= d) {
                    continue;
                }
                scratch.reach(out.to, through, node);
                scratch.heap.push(Queued {
                    distance: through,
                    node: out.to,
                });
            }
        }
        let goal = found?;
        scratch.nodes.clear();
        let mut at = goal;
        while at != NONE {
            scratch.nodes.push(NodeId(at));
            at = scratch.predecessor[at as usize];
        }
        scratch.nodes.reverse();
        scratch.arcs.clear();
        for i in 1..scratch.nodes.len() {
            let (from, to) = (scratch.nodes[i - 1], scratch.nodes[i]);
            let arc = self.cheapest_arc(scratch, from.0, to.0)?;
            scratch.arcs.push(arc);
        }
        let cost = self
            .path_cost(&scratch.nodes, &scratch.arcs)
            .unwrap_or(scratch.distance[goal as usize]);
        Some(Route {
            nodes: &scratch.nodes,
            arcs: &scratch.arcs,
            cost,
        })
    }

    /// [`SearchGraph::search`], the path owned.
    pub fn shortest(
        &self,
        scratch: &mut Scratch,
        start: NodeId,
        goals: &[NodeId],
        removed: &HashSet<ArcRef>,
    ) -> Option<Path> {
        self.search(scratch, start, goals, removed)
            .map(|r| r.to_path())
    }

    /// The cheapest path of at least one arc from `start` to a goal (the start may be a
    /// goal: the object must leave it and come back). One search per arc leaving the
    /// start, taken in the order searches relax them; a later one wins only if cheaper.
    pub fn shortest_leaving(
        &self,
        scratch: &mut Scratch,
        start: NodeId,
        goals: &[NodeId],
        removed: &HashSet<ArcRef>,
    ) -> Option<Path> {
        if start.index() >= self.n_nodes() {
            return None;
        }
        let mut best: Option<Path> = None;
        for (_, out) in self.leaving(start.0) {
            let next = NodeId(out.to);
            if removed.contains(&ArcRef {
                from: start,
                to: next,
            }) {
                continue;
            }
            let Some(rest) = self.search(scratch, next, goals, removed) else {
                continue;
            };
            let cost = out.weight + rest.cost;
            if best.as_ref().is_none_or(|b| cost < b.cost) {
                let mut nodes = vec![start];
                nodes.extend_from_slice(rest.nodes);
                let mut arcs = vec![out.arc as usize];
                arcs.extend_from_slice(rest.arcs);
                let cost = self.path_cost(&nodes, &arcs).unwrap_or(cost);
                best = Some(Path { nodes, arcs, cost });
            }
        }
        best
    }

    /// The cost of a path of `arcs` as the sum of its weights in decimal: the weights
    /// are written in decimal (0.1 per move), and their binary sum drifts
    /// (`8.599999999999998` for 8.6), so they are added as whole billionths and the
    /// total converted once. `None` when a weight is not a whole number of billionths
    /// within 10^-12 (or is too large for that), which no cell's weights are, or when an
    /// arc does not leave the node before it in `nodes`.
    fn path_cost(&self, nodes: &[NodeId], arcs: &[usize]) -> Option<f64> {
        let mut total: i128 = 0;
        for (&from, &arc) in nodes.iter().zip(arcs) {
            let weight = self.weight(from, arc)?;
            let scaled = weight * BILLION;
            let whole = scaled.round();
            if !whole.is_finite() || whole.abs() >= 1e18 || (scaled - whole).abs() > 1e-3 {
                return None;
            }
            total += whole as i128;
        }
        Some(total as f64 / BILLION)
    }

    /// The weight here of arc `arc` (an index into the artifact's graph) leaving `from`.
    pub fn weight(&self, from: NodeId, arc: usize) -> Option<f64> {
        if from.index() >= self.n_nodes() {
            return None;
        }
        self.leaving(from.0)
            .find(|(_, out)| out.arc as usize == arc)
            .map(|(_, out)| out.weight)
    }

    /// The cheapest arc from `from` to `to` not left out in this search, the first
    /// declared among equals.
    fn cheapest_arc(&self, scratch: &Scratch, from: u32, to: u32) -> Option<usize> {
        self.leaving(from)
            .filter(|(slot, out)| out.to == to && !scratch.is_left_out(*slot))
            .map(|(_, out)| (out.weight, out.arc))
            .min_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)))
            .map(|(_, arc)| arc as usize)
    }

    /// Every node reachable from `start` without `removed` arcs (for explanations).
    pub fn reachable(&self, start: NodeId, removed: &HashSet<ArcRef>) -> Vec<NodeId> {
        let mut seen = vec![false; self.n_nodes()];
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
            for (_, arc) in self.leaving(n.0) {
                let to = NodeId(arc.to);
                if !removed.contains(&ArcRef { from: n, to }) && !seen[to.index()] {
                    stack.push(to);
                }
            }
        }
        out.sort_unstable();
        out
    }
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

#[cfg(test)]
mod tests;
