//! The compressed search against two oracles on random graphs: the petgraph search it
//! replaced (the same paths, ties included) and petgraph's Dijkstra (the same costs, and
//! no path exactly when no goal can be reached). Arcs are left out at random, goals are
//! often unreachable or absent, and one scratch serves every search of a case, so stale
//! marks from an earlier search would show.

use std::collections::HashSet;

use cellc_schema::{Arc, ArcKind, EndEffectorId, Graph, GraspId, Node, NodeId, WorkspaceId};
use petgraph::graph::{DiGraph, NodeIndex};
use petgraph::visit::{EdgeFiltered, EdgeRef};
use proptest::prelude::*;

use super::{Path, Scratch, SearchGraph};
use crate::plan::ArcRef;

/// Weights as cells write them: decimals, repeated often so that ties are common.
const WEIGHTS: [f64; 6] = [0.0, 0.1, 0.1, 0.3, 1.0, 2.5];

fn graph(n: usize, arcs: &[(usize, usize, usize, bool)]) -> Graph {
    Graph {
        nodes: (0..n as u32)
            .map(|i| Node {
                end_effector: EndEffectorId(i % 3),
                grasp: GraspId(i),
                workspace: WorkspaceId(i / 3),
            })
            .collect(),
        arcs: arcs
            .iter()
            .map(|&(from, to, w, is_move)| Arc {
                from: (from % n) as u32,
                to: (to % n) as u32,
                kind: if is_move {
                    ArcKind::Move
                } else {
                    ArcKind::Transition
                },
                weight: WEIGHTS[w % WEIGHTS.len()],
                source: 0,
                via: None,
                witness: None,
            })
            .collect(),
        pruned: Vec::new(),
        witnesses: Vec::new(),
    }
}

/// petgraph's graph of the search it was: per arc its weight and index.
type Petgraph = DiGraph<(), (f64, usize)>;
type EdgeReference<'a> = petgraph::graph::EdgeReference<'a, (f64, usize)>;

/// The petgraph search as it was before the compressed rows replaced it.
struct Oracle {
    graph: Petgraph,
    sums: SearchGraph,
}

impl Oracle {
    fn new(g: &Graph, reweight: Option<(f64, f64)>) -> Oracle {
        let mut graph = DiGraph::new();
        for _ in &g.nodes {
            graph.add_node(());
        }
        for (i, arc) in g.arcs.iter().enumerate() {
            let weight = match reweight {
                Some((moves, _)) if arc.kind == ArcKind::Move => moves,
                Some((_, transitions)) => transitions,
                None => arc.weight,
            };
            graph.add_edge(
                NodeIndex::new(arc.from as usize),
                NodeIndex::new(arc.to as usize),
                (weight, i),
            );
        }
        let sums = SearchGraph::new(g);
        let sums = reweight.map_or(sums.clone(), |w| sums.reweighted(g, w));
        Oracle { graph, sums }
    }

    fn filtered<'a>(
        &'a self,
        removed: &'a HashSet<ArcRef>,
    ) -> EdgeFiltered<&'a Petgraph, impl Fn(EdgeReference<'a>) -> bool + 'a> {
        EdgeFiltered::from_fn(&self.graph, move |e: EdgeReference<'a>| {
            !removed.contains(&ArcRef {
                from: NodeId(e.source().index() as u32),
                to: NodeId(e.target().index() as u32),
            })
        })
    }

    fn shortest(&self, start: NodeId, goals: &[NodeId], removed: &HashSet<ArcRef>) -> Option<Path> {
        let goal_set: HashSet<NodeId> = goals.iter().copied().collect();
        let (cost, nodes) = petgraph::algo::astar(
            &self.filtered(removed),
            NodeIndex::new(start.index()),
            |n| goal_set.contains(&NodeId(n.index() as u32)),
            |e| e.weight().0,
            |_| 0.0,
        )?;
        let nodes: Vec<NodeId> = nodes
            .into_iter()
            .map(|n| NodeId(n.index() as u32))
            .collect();
        let arcs = nodes
            .windows(2)
            .map(|w| {
                self.graph
                    .edges_connecting(NodeIndex::new(w[0].index()), NodeIndex::new(w[1].index()))
                    .map(|e| *e.weight())
                    .min_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)))
                    .map(|(_, i)| i)
            })
            .collect::<Option<Vec<usize>>>()?;
        let cost = self.sums.path_cost(&nodes, &arcs).unwrap_or(cost);
        Some(Path { nodes, arcs, cost })
    }

    fn shortest_leaving(
        &self,
        start: NodeId,
        goals: &[NodeId],
        removed: &HashSet<ArcRef>,
    ) -> Option<Path> {
        let mut best: Option<Path> = None;
        for e in self.graph.edges(NodeIndex::new(start.index())) {
            let next = NodeId(e.target().index() as u32);
            let (weight, arc) = *e.weight();
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
                let cost = self.sums.path_cost(&nodes, &arcs).unwrap_or(cost);
                best = Some(Path { nodes, arcs, cost });
            }
        }
        best
    }

    /// petgraph's Dijkstra: the cost to the cheapest reachable goal.
    fn cost(&self, start: NodeId, goals: &[NodeId], removed: &HashSet<ArcRef>) -> Option<f64> {
        let d = petgraph::algo::dijkstra(
            &self.filtered(removed),
            NodeIndex::new(start.index()),
            None,
            |e| e.weight().0,
        );
        goals
            .iter()
            .filter_map(|g| d.get(&NodeIndex::new(g.index())).copied())
            .min_by(f64::total_cmp)
    }
}

/// A path is a walk of the graph from the start to a goal over arcs not left out, and
/// costs the sum of its arcs' weights.
fn check_walk(
    g: &Graph,
    search: &SearchGraph,
    path: &Path,
    start: NodeId,
    goals: &[NodeId],
    removed: &HashSet<ArcRef>,
) {
    assert_eq!(path.nodes[0], start);
    assert!(goals.contains(path.nodes.last().unwrap()));
    assert_eq!(path.arcs.len() + 1, path.nodes.len());
    let mut sum = 0.0;
    for (i, &a) in path.arcs.iter().enumerate() {
        let arc = &g.arcs[a];
        assert_eq!((arc.from, arc.to), (path.nodes[i].0, path.nodes[i + 1].0));
        assert!(!removed.contains(&ArcRef::of(arc)));
        sum += search.weight(path.nodes[i], a).expect("an arc of the path");
    }
    assert!((sum - path.cost).abs() <= 1e-9, "{sum} vs {}", path.cost);
}

type Case = (
    usize,
    Vec<(usize, usize, usize, bool)>,
    Vec<usize>,
    Vec<(usize, usize)>,
    Vec<(usize, Vec<usize>)>,
    Option<(usize, usize)>,
);

fn cases() -> impl Strategy<Value = Case> {
    (1usize..30).prop_flat_map(|n| {
        (
            Just(n),
            prop::collection::vec((0..n, 0..n, 0..WEIGHTS.len(), any::<bool>()), 0..4 * n),
            // Arcs of the graph to leave out, by index (modulo the number of arcs).
            prop::collection::vec(0usize..1000, 0..6),
            // Pairs to leave out, whether or not they are arcs (some are not nodes).
            prop::collection::vec((0..n + 2, 0..n + 2), 0..3),
            // Searches: a start and goals (some not nodes, sometimes none).
            prop::collection::vec((0..n, prop::collection::vec(0..n + 1, 0..4)), 1..6),
            prop::option::of((0..WEIGHTS.len(), 0..WEIGHTS.len())),
        )
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    #[test]
    fn same_paths_as_petgraph_and_same_costs_as_its_dijkstra(
        (n, arcs, out_arcs, out_pairs, searches, reweight) in cases()
    ) {
        let g = graph(n, &arcs);
        let reweight = reweight.map(|(m, t)| (WEIGHTS[m], WEIGHTS[t]));
        let base = SearchGraph::new(&g);
        let search = reweight.map_or(base.clone(), |w| base.reweighted(&g, w));
        let oracle = Oracle::new(&g, reweight);
        let mut removed: HashSet<ArcRef> = out_pairs
            .iter()
            .map(|&(a, b)| ArcRef { from: NodeId(a as u32), to: NodeId(b as u32) })
            .collect();
        if !g.arcs.is_empty() {
            removed.extend(out_arcs.iter().map(|&i| ArcRef::of(&g.arcs[i % g.arcs.len()])));
        }
        let mut scratch = Scratch::default();
        for (start, goals) in &searches {
            let start = NodeId(*start as u32);
            let goals: Vec<NodeId> = goals.iter().map(|&x| NodeId(x as u32)).collect();
            let ours = search.shortest(&mut scratch, start, &goals, &removed);
            prop_assert_eq!(&ours, &oracle.shortest(start, &goals, &removed));
            let best = oracle.cost(start, &goals, &removed);
            prop_assert_eq!(ours.is_some(), best.is_some());
            if let (Some(path), Some(best)) = (&ours, best) {
                prop_assert!((path.cost - best).abs() <= 1e-9, "{} vs {best}", path.cost);
                check_walk(&g, &search, path, start, &goals, &removed);
            }
            let leaving = search.shortest_leaving(&mut scratch, start, &goals, &removed);
            prop_assert_eq!(&leaving, &oracle.shortest_leaving(start, &goals, &removed));
            if let Some(path) = &leaving {
                prop_assert!(!path.arcs.is_empty());
                check_walk(&g, &search, path, start, &goals, &removed);
            }
        }
    }
}

/// A scratch grown on a large graph and then used on a smaller one, and one whose epoch
/// counter wraps, answer as a fresh one does.
#[test]
fn a_scratch_is_reset_between_graphs_and_across_its_epochs_wrapping() {
    let chain = |n: usize| {
        let arcs: Vec<_> = (0..n - 1).map(|i| (i, i + 1, 1, true)).collect();
        graph(n, &arcs)
    };
    let (big, small) = (SearchGraph::new(&chain(50)), SearchGraph::new(&chain(5)));
    let none = HashSet::new();
    let mut scratch = Scratch::default();
    let far = big
        .shortest(&mut scratch, NodeId(0), &[NodeId(49)], &none)
        .unwrap();
    assert_eq!(far.nodes.len(), 50);
    // Node 3 was reached in the big search; going back from it must find nothing.
    assert_eq!(
        small.shortest(&mut scratch, NodeId(3), &[NodeId(0)], &none),
        None
    );
    scratch.epoch = u32::MAX;
    let path = small
        .shortest(&mut scratch, NodeId(1), &[NodeId(4)], &none)
        .unwrap();
    assert_eq!(scratch.epoch, 1);
    assert_eq!(path.nodes, [1, 2, 3, 4].map(NodeId));
    assert!((path.cost - 0.3).abs() < 1e-12);
    let blocked: HashSet<ArcRef> = [ArcRef {
        from: NodeId(2),
        to: NodeId(3),
    }]
    .into();
    assert_eq!(
        small.shortest(&mut scratch, NodeId(1), &[NodeId(4)], &blocked),
        None
    );
    assert_eq!(
        small.shortest(&mut scratch, NodeId(1), &[NodeId(4)], &none),
        Some(path)
    );
}
