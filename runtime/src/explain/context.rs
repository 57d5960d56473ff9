//! What the analysis needs, computed once: the object's graph indexed (active arcs, the
//! arcs lost at build time or during the request), the graph rules of the cell, and the
//! two sides R and G with their distances.

use std::collections::{BTreeMap, BTreeSet, HashMap, HashSet};

use cellc_schema::rules::{Adjacency, CellRules, ObjectRules};
use cellc_schema::{
    Aabb, ArcKind, Artifact, Body, EndEffectorId, GraspId, Infeasibility, Node, Object, ObjectId,
    WorkspaceId,
};
use petgraph::graph::{DiGraph, NodeIndex};
use petgraph::visit::{EdgeFiltered, EdgeRef, Reversed};

use super::lost::{contact_pairs, ContactPairs};
use super::{BodyName, Cause, NoStates};
use crate::plan::Unreachable;

/// An arc removed at build time or during the request.
pub(super) struct Lost {
    pub from: u32,
    pub to: u32,
    pub kind: ArcKind,
    pub weight: f64,
    pub source: Option<u32>,
    pub reason: Infeasibility,
    pub failed: bool,
}

/// An arc of [`Ctx::graph`].
#[derive(Clone, Copy)]
pub(super) enum Link {
    /// An arc of the graph that did not fail, with its weight.
    Active(f64),
    /// An arc removed at build time or during the request (index into [`Ctx::lost`]).
    Lost(usize),
    /// From a goal state to the hub node that stands for "some goal".
    Goal,
}

/// Everything the analysis needs, computed once.
pub(super) struct Ctx<'a> {
    pub art: &'a Artifact,
    pub obj: &'a Object,
    pub object: ObjectId,
    pub nodes: &'a [Node],
    pub index: HashMap<Node, u32>,
    /// Active arcs (graph minus failed): (to, weight) per node, in the artifact's arc
    /// order, for the searches through hypothetical arcs.
    pub fwd: Vec<Vec<(u32, f64)>>,
    /// Every arc, active or lost, plus a hub node (index `nodes.len()`) that every goal
    /// state leads to, so that "distance to some goal" is one search (petgraph).
    pub graph: DiGraph<(), Link>,
    pub active: HashSet<(u32, u32)>,
    /// (giving end-effector, taking end-effector, workspace) of active transition arcs.
    pub active_exchanges: HashSet<(EndEffectorId, EndEffectorId, WorkspaceId)>,
    /// The same for pruned or failed transition arcs.
    pub lost_exchanges: HashSet<(EndEffectorId, EndEffectorId, WorkspaceId)>,
    pub lost: Vec<Lost>,
    pub lost_pairs: HashSet<(u32, u32)>,
    pub lost_from: Vec<Vec<usize>>,
    /// Pairs of bodies whose collision removed arcs and that `allow contact` could name,
    /// each once.
    pub contacts: Vec<(BodyName, BodyName)>,
    /// Per pair, the group of pairs that must be allowed together (see
    /// [`contact_pairs`]).
    pub contact_group: Vec<u32>,
    /// Per lost arc, its pair in [`Ctx::contacts`] (None: lost for another reason).
    pub contact_of: Vec<Option<u32>>,
    /// The cell's graph rules (the compiler's), for what changes would add.
    pub rules: CellRules,
    /// The object's grasps and transitions, as the rules read them.
    pub object_rules: ObjectRules,
    pub at_ws: Vec<Vec<u32>>,
    /// Declared transitions (from grasp, to grasp) -> their spans.
    pub declared: BTreeMap<(GraspId, GraspId), Vec<u32>>,
    pub start: u32,
    pub goals: Vec<u32>,
    pub is_goal: Vec<bool>,
    /// The start is a goal state (the goal is another pose in it): a plan must leave it
    /// and come back, so the start lies on both sides and paths take at least one arc.
    pub must_leave: bool,
    pub d_s: Vec<f64>,
    pub d_g: Vec<f64>,
    pub in_r: Vec<bool>,
    pub in_g: Vec<bool>,
}

impl<'a> Ctx<'a> {
    pub fn new(
        art: &'a Artifact,
        object: ObjectId,
        obj: &'a Object,
        un: &Unreachable,
    ) -> Result<Ctx<'a>, NoStates> {
        let nodes = obj.graph.nodes.as_slice();
        let n = nodes.len();
        let index: HashMap<Node, u32> = nodes
            .iter()
            .enumerate()
            .map(|(i, &node)| (node, i as u32))
            .collect();
        let failed: HashMap<(u32, u32), &Infeasibility> = un
            .failed
            .iter()
            .map(|(a, reason)| ((a.from.0, a.to.0), reason))
            .collect();
        let mut fwd = vec![Vec::new(); n];
        let mut graph: DiGraph<(), Link> = DiGraph::new();
        for _ in 0..=n {
            graph.add_node(());
        }
        let mut active = HashSet::new();
        for arc in &obj.graph.arcs {
            let (f, t) = (arc.from as usize, arc.to as usize);
            if f >= n || t >= n || failed.contains_key(&(arc.from, arc.to)) {
                continue;
            }
            fwd[f].push((arc.to, arc.weight));
            graph.add_edge(
                NodeIndex::new(f),
                NodeIndex::new(t),
                Link::Active(arc.weight),
            );
            active.insert((arc.from, arc.to));
        }
        let lost = lost_arcs(art, obj, un);
        for (i, l) in lost.iter().enumerate() {
            graph.add_edge(
                NodeIndex::new(l.from as usize),
                NodeIndex::new(l.to as usize),
                Link::Lost(i),
            );
        }
        let exchange = |f: u32, t: u32| {
            let (x, y) = (nodes[f as usize], nodes[t as usize]);
            (x.end_effector, y.end_effector, x.workspace)
        };
        let active_exchanges = obj
            .graph
            .arcs
            .iter()
            .filter(|a| a.kind == ArcKind::Transition && active.contains(&(a.from, a.to)))
            .map(|a| exchange(a.from, a.to))
            .collect();
        let lost_exchanges = lost
            .iter()
            .filter(|l| l.kind == ArcKind::Transition)
            .map(|l| exchange(l.from, l.to))
            .collect();
        let mut lost_from = vec![Vec::new(); n];
        for (i, l) in lost.iter().enumerate() {
            lost_from[l.from as usize].push(i);
        }
        let rules = CellRules::new(
            art.workspaces.len(),
            CellRules::end_effectors_of(art),
            Adjacency::of_artifact(art).unwrap_or_else(|| infer_adjacency(art)),
        );
        let mut at_ws = vec![Vec::new(); art.workspaces.len()];
        for (i, node) in nodes.iter().enumerate() {
            if let Some(list) = at_ws.get_mut(node.workspace.index()) {
                list.push(i as u32);
            }
        }
        let mut declared: BTreeMap<(GraspId, GraspId), Vec<u32>> = BTreeMap::new();
        for t in &obj.transitions {
            declared
                .entry((GraspId(t.from), GraspId(t.to)))
                .or_default()
                .push(t.span);
        }
        let start = *index.get(&un.start).ok_or(NoStates::Start)?;
        let mut goals: Vec<u32> = un
            .goals
            .iter()
            .filter_map(|g| index.get(g).copied())
            .collect();
        goals.sort_unstable();
        goals.dedup();
        if goals.is_empty() {
            return Err(NoStates::Goals);
        }
        let ContactPairs {
            pairs: contacts,
            groups: contact_group,
            of: contact_of,
        } = contact_pairs(art, nodes, &lost);
        let mut is_goal = vec![false; n];
        for &g in &goals {
            is_goal[g as usize] = true;
            graph.add_edge(NodeIndex::new(g as usize), NodeIndex::new(n), Link::Goal);
        }
        let mut ctx = Ctx {
            art,
            obj,
            object,
            nodes,
            index,
            fwd,
            graph,
            active,
            active_exchanges,
            lost_exchanges,
            lost_pairs: lost.iter().map(|l| (l.from, l.to)).collect(),
            lost,
            lost_from,
            contacts,
            contact_group,
            contact_of,
            rules,
            object_rules: ObjectRules::from_artifact(art, obj),
            at_ws,
            declared,
            must_leave: goals.contains(&start),
            start,
            goals,
            is_goal,
            d_s: Vec::new(),
            d_g: Vec::new(),
            in_r: Vec::new(),
            in_g: Vec::new(),
        };
        (ctx.d_s, ctx.d_g) = ctx.distances(false);
        ctx.in_r = ctx.d_s.iter().map(|d| d.is_finite()).collect();
        ctx.in_g = ctx.d_g.iter().map(|d| d.is_finite()).collect();
        Ok(ctx)
    }

    /// Distances from the start and to the nearest goal (infinity where there is no
    /// path), over the active arcs, or with `restored` over the lost ones too.
    pub fn distances(&self, restored: bool) -> (Vec<f64>, Vec<f64>) {
        let graph = EdgeFiltered::from_fn(
            &self.graph,
            |e: petgraph::graph::EdgeReference<'_, Link>| {
                restored || !matches!(e.weight(), Link::Lost(_))
            },
        );
        let weight = |link: &Link| match *link {
            Link::Active(w) => w,
            Link::Lost(i) => self.lost[i].weight,
            Link::Goal => 0.0,
        };
        let n = self.nodes.len();
        let start = NodeIndex::new(self.start as usize);
        let from_start = petgraph::algo::dijkstra(&graph, start, None, |e| weight(e.weight()));
        let hub = NodeIndex::new(n);
        let to_goal = petgraph::algo::dijkstra(Reversed(&graph), hub, None, |e| weight(e.weight()));
        let from_start = (0..n)
            .map(|i| from_start.get(&NodeIndex::new(i)).copied())
            .map(|d| d.unwrap_or(f64::INFINITY))
            .collect();
        let to_goal = (0..n)
            .map(|i| to_goal.get(&NodeIndex::new(i)).copied())
            .map(|d| d.unwrap_or(f64::INFINITY))
            .collect();
        (from_start, to_goal)
    }

    /// True when the graph (minus the failed arcs) connects the start to a goal, with at
    /// least one arc when the start must be left.
    pub fn connected(&self) -> bool {
        if self.must_leave {
            self.fwd[self.start as usize]
                .iter()
                .any(|&(v, _)| self.in_g[v as usize])
        } else {
            self.goals.iter().any(|&g| self.in_r[g as usize])
        }
    }

    /// Restoring which lost arcs connects the start to a goal.
    pub fn cause(&self) -> Cause {
        if self.reaches_goal_with(|l| !l.failed) {
            Cause::Pruned
        } else if self.reaches_goal_with(|_| true) {
            Cause::Failed
        } else {
            Cause::Missing
        }
    }

    fn reaches_goal_with(&self, restore: impl Fn(&Lost) -> bool) -> bool {
        let kept = |link: &Link| match *link {
            Link::Lost(i) => restore(&self.lost[i]),
            Link::Active(_) | Link::Goal => true,
        };
        let graph = EdgeFiltered::from_fn(
            &self.graph,
            |e: petgraph::graph::EdgeReference<'_, Link>| kept(e.weight()),
        );
        let hub = NodeIndex::new(self.nodes.len());
        let start = NodeIndex::new(self.start as usize);
        if !self.must_leave {
            return petgraph::algo::has_path_connecting(&graph, start, hub, None);
        }
        // Leaving first: some arc out of the start (not the start's own link to the hub)
        // to a state that leads to a goal.
        self.graph.edges(start).any(|e| {
            !matches!(e.weight(), Link::Goal)
                && kept(e.weight())
                && petgraph::algo::has_path_connecting(&graph, e.target(), hub, None)
        })
    }

    /// True when a change may make `e` reach `w` as an edit of the source: a declared
    /// workspace added to the `reaches` list of an end-effector without geometry, or an
    /// arm's reach box grown over a workspace that has boxes (declared or derived).
    pub fn reach_editable(&self, e: EndEffectorId, w: WorkspaceId) -> bool {
        let (Some(ee), Some(ws)) = (
            self.art.end_effectors.get(e.index()),
            self.art.workspaces.get(w.index()),
        ) else {
            return false;
        };
        match ee.body {
            Body::Abstract => !ws.derived,
            Body::Arm { .. } => !ws.boxes.is_empty(),
            Body::Surface { .. } => false,
        }
    }

    /// True when `adjacent a b` can be written: both workspaces are declared (a derived
    /// name disappears when the reach it comes from changes).
    pub fn adjacency_editable(&self, a: WorkspaceId, b: WorkspaceId) -> bool {
        let declared = |w: WorkspaceId| {
            self.art
                .workspaces
                .get(w.index())
                .is_some_and(|x| !x.derived)
        };
        declared(a) && declared(b)
    }

    /// The group of pairs that must be allowed together for the lost arc `i`, if any.
    pub fn contact_key(&self, i: usize) -> Option<u32> {
        let pair = self.contact_of.get(i).copied().flatten()?;
        self.contact_group.get(pair as usize).copied()
    }

    pub fn node(&self, i: u32) -> Node {
        self.nodes[i as usize]
    }

    /// The workspaces `e` reaches, in order.
    pub fn reach(&self, e: EndEffectorId) -> impl Iterator<Item = WorkspaceId> + '_ {
        self.rules.reach(e).iter().copied()
    }

    pub fn reaches(&self, e: EndEffectorId, w: WorkspaceId) -> bool {
        self.rules.reaches(e, w)
    }

    pub fn is_movable(&self, e: EndEffectorId) -> bool {
        self.rules.is_movable(e)
    }

    /// True when `e` is movable and may hold this object.
    pub fn is_hand(&self, e: EndEffectorId) -> bool {
        self.is_movable(e) && !self.object_rules.grasps_of(e).is_empty()
    }

    pub fn is_adjacent(&self, a: WorkspaceId, b: WorkspaceId) -> bool {
        self.rules.is_adjacent(a, b)
    }

    pub fn declares(&self, from: GraspId, to: GraspId) -> bool {
        self.object_rules.declares(from, to)
    }

    pub fn ee_span(&self, e: EndEffectorId) -> Option<u32> {
        self.art.end_effectors.get(e.index()).map(|x| x.span)
    }

    pub fn ws_span(&self, w: WorkspaceId) -> Option<u32> {
        self.art.workspaces.get(w.index()).map(|x| x.span)
    }

    /// Distance from an end-effector's reach boxes to a workspace's boxes, when both have
    /// geometry.
    pub fn reach_distance(&self, e: EndEffectorId, w: WorkspaceId) -> Option<f64> {
        let reach = &self.art.end_effectors.get(e.index())?.reach_boxes;
        let boxes = &self.art.workspaces.get(w.index())?.boxes;
        reach
            .iter()
            .flat_map(|a| boxes.iter().map(move |b| box_distance(a, b)))
            .min_by(|a, b| a.total_cmp(b))
    }
}

impl Ctx<'_> {
    /// The reach box of arm `e` nearest to workspace `w` (None: the arm has none), and the
    /// box it grows into to cover every box of `w`: the smallest one holding both.
    pub fn grown_reach(&self, e: EndEffectorId, w: WorkspaceId) -> (Option<u32>, Aabb) {
        let reach: &[Aabb] = self
            .art
            .end_effectors
            .get(e.index())
            .map_or(&[], |x| x.reach_boxes.as_slice());
        let boxes: &[Aabb] = self
            .art
            .workspaces
            .get(w.index())
            .map_or(&[], |x| x.boxes.as_slice());
        let gap = |a: &Aabb| {
            boxes
                .iter()
                .map(|b| box_distance(a, b))
                .fold(f64::INFINITY, f64::min)
        };
        let nearest = (0..reach.len()).min_by(|&i, &j| gap(&reach[i]).total_cmp(&gap(&reach[j])));
        let mut grown = Aabb {
            min: [f64::INFINITY; 3],
            max: [f64::NEG_INFINITY; 3],
        };
        for b in nearest.map(|i| &reach[i]).into_iter().chain(boxes) {
            for k in 0..3 {
                grown.min[k] = grown.min[k].min(b.min[k]);
                grown.max[k] = grown.max[k].max(b.max[k]);
            }
        }
        (nearest.map(|i| i as u32), grown)
    }
}

/// The arcs pruned at build time and those that failed during the request (each failed
/// pair once).
fn lost_arcs(art: &Artifact, obj: &Object, un: &Unreachable) -> Vec<Lost> {
    let nodes = &obj.graph.nodes;
    let n = nodes.len();
    let mut lost = Vec::new();
    for p in &obj.graph.pruned {
        if (p.arc.from as usize) < n && (p.arc.to as usize) < n {
            lost.push(Lost {
                from: p.arc.from,
                to: p.arc.to,
                kind: p.arc.kind,
                weight: p.arc.weight,
                source: Some(p.arc.source),
                reason: p.reason.clone(),
                failed: false,
            });
        }
    }
    let mut seen_failed = HashSet::new();
    for (a, reason) in &un.failed {
        let (f, t) = (a.from.index(), a.to.index());
        if f >= n || t >= n || !seen_failed.insert((a.from, a.to)) {
            continue;
        }
        let arc = obj
            .graph
            .arcs
            .iter()
            .find(|x| x.from == a.from.0 && x.to == a.to.0);
        let same_grasp =
            nodes[f].end_effector == nodes[t].end_effector && nodes[f].grasp == nodes[t].grasp;
        let kind = arc.map_or(
            if same_grasp {
                ArcKind::Move
            } else {
                ArcKind::Transition
            },
            |x| x.kind,
        );
        let weight = arc.map_or(
            if kind == ArcKind::Move {
                art.weights.move_weight
            } else {
                art.weights.transition_weight
            },
            |x| x.weight,
        );
        lost.push(Lost {
            from: a.from.0,
            to: a.to.0,
            kind,
            weight,
            source: arc.map(|x| x.source),
            reason: reason.clone(),
            failed: true,
        });
    }
    lost
}

/// The adjacency of an artifact that does not record it, read off the move arcs. A move
/// arc over a declared adjacency carries its span (`via`); and with derived adjacency,
/// every movable end-effector has move arcs (kept or pruned) between every two workspaces
/// it reaches, for each grasp it holds. Either sign of declared adjacency, or no move arc
/// at all, gives the pairs the move arcs show. That can miss declared pairs no hand spans,
/// which is safe: a suggestion checked with fewer arcs than the real graph has still
/// connects, at worst with an extra `adjacent` line. With no move arc anywhere, a derived
/// cell has no adjacency worth keeping either, so declaring one is harmless there too.
fn infer_adjacency(art: &Artifact) -> Adjacency {
    let movable = |e: EndEffectorId| art.end_effectors.get(e.index()).is_some_and(|x| x.movable);
    let mut declared = false;
    let mut any = false;
    let mut pairs = BTreeSet::new();
    for obj in &art.objects {
        let g = &obj.graph;
        let mut moves: HashSet<(u32, u32)> = HashSet::new();
        let arcs = g.arcs.iter().chain(g.pruned.iter().map(|p| &p.arc));
        for arc in arcs.filter(|a| a.kind == ArcKind::Move) {
            declared |= arc.via.is_some();
            any = true;
            moves.insert((arc.from, arc.to));
            if let (Some(a), Some(b)) =
                (g.nodes.get(arc.from as usize), g.nodes.get(arc.to as usize))
            {
                pairs.insert(ordered(a.workspace, b.workspace));
            }
        }
        // Derived adjacency would have made a move between any two states of one movable
        // hand and grasp.
        let mut by_hand: BTreeMap<(EndEffectorId, GraspId), Vec<u32>> = BTreeMap::new();
        for (i, n) in g.nodes.iter().enumerate() {
            if movable(n.end_effector) {
                by_hand
                    .entry((n.end_effector, n.grasp))
                    .or_default()
                    .push(i as u32);
            }
        }
        declared |= by_hand.values().any(|states| {
            states
                .iter()
                .any(|&a| states.iter().any(|&b| a != b && !moves.contains(&(a, b))))
        });
    }
    if declared || !any {
        Adjacency::Declared(pairs.into_iter().collect())
    } else {
        Adjacency::Derived
    }
}

/// Smallest distance between two boxes (0 when they touch or overlap).
fn box_distance(a: &Aabb, b: &Aabb) -> f64 {
    (0..3)
        .map(|i| {
            let gap = (b.min[i] - a.max[i]).max(a.min[i] - b.max[i]).max(0.0);
            gap * gap
        })
        .sum::<f64>()
        .sqrt()
}

/// An unordered pair, smaller first.
pub(super) fn ordered<T: Ord + Copy>(a: T, b: T) -> (T, T) {
    (a.min(b), a.max(b))
}
