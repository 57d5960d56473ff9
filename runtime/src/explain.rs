//! Why a move request has no plan, said in terms a cell engineer acts on.
//!
//! When no path joins the start state to a goal state the planner returns an
//! [`Unreachable`]. A list of node indices helps nobody: the engineer wants to know what the
//! object can reach, what the goal needs, which missing or infeasible declaration separates
//! the two, and what to change. [`explain`] computes that as plain data
//! ([`Explanation`]); the CLI renders it as a coded diagnostic against the cell's source
//! through the span indices it carries (the runtime does not depend on the diagnostics
//! crate).
//!
//! The analysis, on the object's graph with the arcs that failed during the request
//! removed:
//! - R, the states reachable from the start, and G, the states from which some goal state
//!   is reachable. The goal is unreachable exactly when they are disjoint; then no arc
//!   leaves R and no arc enters G, so every statement about "no transition joins ..." below
//!   is true by construction rather than by heuristics.
//! - The cut, grouped the way the cell is written: for each end-effector holding the object
//!   in R and each holding it in G, in each workspace where both hold it, either no
//!   transition is declared between their grasps, or the declared ones were pruned at build
//!   time or failed during the request (with the reasons in words). One hand on both sides
//!   with the same grasp is a move between workspaces that are not adjacent, or whose move
//!   was pruned. When the start side and the goal side are separated by a hand that
//!   belongs to neither, the cut also describes the gaps on the way through it, taken from
//!   the best suggestion. When nothing of that kind exists: no hand that can hold the
//!   object reaches a side held by fixed surfaces only; else the end-effectors of the two
//!   sides reach no common workspace; else only fixed surfaces hold it (they never
//!   exchange it); else where each side lies.
//! - Suggestions: the fewest changes to the cell that connect the start to the goal. A
//!   single change is tried first: declaring a transition (both ways, as the cell normally
//!   writes it) between two grasps held by different end-effectors that share a
//!   workspace, never two fixed ones; declaring an adjacency (cells that declare theirs);
//!   making a pruned or failed arc feasible; extending a movable end-effector's reach to
//!   one more workspace. Only when none connects, sets of changes along a path that needs
//!   the fewest of them (a 0-1 breadth-first search where existing arcs cost nothing and
//!   each hypothetical arc costs one), also after each of the nearest reach extensions.
//!   Every suggestion is checked by adding every arc it
//!   would create, with the compiler's rules, and searching again; only those that really
//!   connect are kept. They are ranked by number of changes, then by whether they repeat
//!   something that already failed kinematically (a new transition between two hands in a
//!   workspace where every declared one between them was infeasible), then by kind (a
//!   transition is the cheapest edit, a reach extension the dearest), then by how far a
//!   reach must grow, then by the cost of the plan they give. Doubtful ones are dropped
//!   when others exist, and so are reach extensions (a robot moved or replaced) when a
//!   declaration or a geometric fix connects; one suggestion per idea (per root cause of
//!   pruned arcs, per pair of hands and workspace of a new transition); at most three.
//! - Pruned notes: the pruned or failed arcs that lie on some start-to-goal path of the
//!   graph with every pruned and failed arc restored, those on the border of R or G first.

use std::cmp::{Ordering, Reverse};
use std::collections::{BTreeMap, BTreeSet, BinaryHeap, HashMap, HashSet, VecDeque};

use cellc_schema::{Aabb, ArcKind, Artifact, Holder, Infeasibility, Node, Object};

use crate::plan::{ArcRef, Unreachable};

/// Suggestions shown at most: more would bury the good ones.
const MAX_SUGGESTIONS: usize = 3;
/// Cut items shown at most; the rest are counted in [`Explanation::cut_omitted`].
const MAX_CUT: usize = 6;
/// Pruned notes shown at most; the rest are counted in [`Explanation::pruned_omitted`].
const MAX_PRUNED: usize = 8;
/// Source labels at most: a diagnostic with more labels than lines is unreadable.
const MAX_SPANS: usize = 12;
/// Names listed in one sentence before "and N more".
const MAX_LISTED: usize = 4;
/// Hypothetical changes tried at most per kind, so a huge cell cannot make the
/// explanation slower than the search it explains.
const MAX_TRIES: usize = 4000;
/// Reach extensions tried with the further changes they need, nearest first.
const MAX_REACH_SETS: usize = 32;

/// Why a request has no plan, as data for a diagnostic.
#[derive(Clone, Debug, PartialEq)]
pub struct Explanation {
    /// Index of the object in [`Artifact::objects`].
    pub object: u32,
    /// What kind of problem it is (also picks the diagnostic's code in the CLI).
    pub cause: Cause,
    /// One lowercase sentence, names in backticks: the diagnostic's message.
    pub summary: String,
    /// What the start can reach.
    pub start_side: Side,
    /// What leads to the goal.
    pub goal_side: Side,
    /// Why the two sides do not meet, one item per pair of end-effectors (most telling
    /// first).
    pub cut: Vec<CutItem>,
    /// Cut items left out of [`Explanation::cut`].
    pub cut_omitted: usize,
    /// What to change, best first; each one verified to connect the start to the goal.
    pub suggestions: Vec<Suggestion>,
    /// Arcs removed at build time or during the request that would have joined the sides.
    pub pruned: Vec<PrunedNote>,
    /// Pruned notes left out of [`Explanation::pruned`].
    pub pruned_omitted: usize,
    /// Further remarks for the diagnostic's notes.
    pub notes: Vec<String>,
    /// Source places to label: (index into [`Artifact::spans`], label), at most one label
    /// per span, most important first.
    pub spans: Vec<(u32, String)>,
}

/// What kind of problem separates the start from the goal.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Cause {
    /// The cell declares no way: even with every pruned and failed arc restored there is
    /// no path.
    Missing,
    /// Arcs pruned at build time (kinematically infeasible) are what cuts the path.
    Pruned,
    /// Arcs that failed during this request are needed (possibly with pruned ones).
    Failed,
    /// The graph does connect the start to a goal: nothing to explain (the request failed
    /// for another reason, or the caller's data is inconsistent).
    Connected,
    /// The start or every goal is not a state of the object's graph.
    NoStates,
}

/// One side of the cut.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Side {
    /// Node indices of the object's graph, sorted.
    pub states: Vec<u32>,
    /// The same states per end-effector, in end-effector order.
    pub holdings: Vec<Holding>,
    /// The side in words: "10 states: `left_arm` with `g4`, `g5` in `w1`, `w2`; ...".
    pub text: String,
}

/// What one end-effector holds on one side.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Holding {
    /// Index into [`Artifact::end_effectors`].
    pub end_effector: u32,
    /// Grasps (indices into the object's grasps), sorted.
    pub grasps: Vec<u32>,
    /// Workspaces (indices into [`Artifact::workspaces`]), sorted.
    pub workspaces: Vec<u32>,
}

/// What kind of gap a cut item describes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum CutKind {
    /// Transitions are declared between the two sides' grasps there, but every one was
    /// pruned or failed.
    InfeasibleTransition,
    /// A hand would carry the object on, but that move was pruned or failed.
    InfeasibleMove,
    /// No transition is declared between the two sides' grasps there.
    NoTransition,
    /// A hand holds the object on both sides in two workspaces that are not adjacent.
    NotAdjacent,
    /// The end-effectors of the two sides reach no common workspace.
    NoCommonWorkspace,
    /// Only fixed end-effectors hold the object on one side, and no movable one that can
    /// hold it reaches their workspaces.
    NoHand,
    /// Only fixed end-effectors hold the object on the two sides, and fixed ones never
    /// exchange it.
    OnlyFixed,
    /// None of the above: the sides are held in different workspaces with no hand
    /// carrying between them, or only by end-effectors that cannot exchange it.
    Apart,
}

/// One reason the sides do not meet.
#[derive(Clone, Debug, PartialEq)]
pub struct CutItem {
    /// Kind of gap.
    pub kind: CutKind,
    /// End-effectors on the start's side of the gap.
    pub near: Vec<u32>,
    /// End-effectors on the goal's side of the gap.
    pub far: Vec<u32>,
    /// Workspaces where it matters.
    pub workspaces: Vec<u32>,
    /// The gap in words.
    pub text: String,
    /// Source places that matter (indices into [`Artifact::spans`]).
    pub spans: Vec<u32>,
}

/// One change to the cell.
#[derive(Clone, Debug, PartialEq)]
pub enum Change {
    /// Declare `transition from_grasp <-> to_grasp` in the object.
    AddTransition {
        /// Grasp given up on the way to the goal (index into the object's grasps).
        from_grasp: u32,
        /// Grasp taken.
        to_grasp: u32,
        /// Where the plan would use it.
        workspace: u32,
        /// The existing one-way declaration `to_grasp -> from_grasp` to make two-way, if
        /// any (index into [`Artifact::spans`]).
        reverse_of: Option<u32>,
    },
    /// Declare `adjacent a b`.
    AddAdjacency {
        /// A workspace.
        a: u32,
        /// The other.
        b: u32,
    },
    /// Extend a movable end-effector's reach to cover one more workspace.
    ExtendReach {
        /// Index into [`Artifact::end_effectors`].
        end_effector: u32,
        /// Index into [`Artifact::workspaces`].
        workspace: u32,
        /// How far the reach boxes are from the workspace's boxes, metres (when both have
        /// geometry).
        distance: Option<f64>,
    },
    /// Make an arc that was pruned (or failed) feasible, e.g. by moving an arm.
    RelaxPruned {
        /// The arc.
        arc: ArcRef,
        /// Move or transition.
        kind: ArcKind,
        /// Why it was removed.
        reason: Infeasibility,
        /// Failed during this request rather than pruned at build time.
        failed: bool,
    },
}

/// A set of changes that, together, connect the start to the goal.
#[derive(Clone, Debug, PartialEq)]
pub struct Suggestion {
    /// The changes, all needed.
    pub changes: Vec<Change>,
    /// What to do, in words.
    pub text: String,
    /// Cost of the cheapest plan once the changes are made (sum of arc weights).
    pub cost: f64,
    /// Source places to edit (indices into [`Artifact::spans`]).
    pub spans: Vec<u32>,
}

/// A pruned or failed arc that would have joined the sides.
#[derive(Clone, Debug, PartialEq)]
pub struct PrunedNote {
    /// The arc.
    pub arc: ArcRef,
    /// Move or transition.
    pub kind: ArcKind,
    /// Failed during this request rather than pruned at build time.
    pub failed: bool,
    /// Why.
    pub reason: Infeasibility,
    /// The arc and its reason in words.
    pub text: String,
    /// The declaration that made the arc (index into [`Artifact::spans`]).
    pub span: Option<u32>,
}

/// Explains why `unreachable.goals` cannot be reached from `unreachable.start`.
///
/// R is recomputed from the graph minus `unreachable.failed` rather than taken from
/// `unreachable.reachable`, so that the cut and the verification of suggestions reason
/// about one and the same graph.
pub fn explain(artifact: &Artifact, unreachable: &Unreachable) -> Explanation {
    let Some(object) = artifact.objects.get(unreachable.object as usize) else {
        return Explanation::bare(
            unreachable.object,
            Cause::NoStates,
            format!(
                "the request names object #{}, which the artifact does not have",
                unreachable.object
            ),
        );
    };
    let ctx = match Ctx::new(artifact, unreachable.object, object, unreachable) {
        Ok(ctx) => ctx,
        Err(summary) => return Explanation::bare(unreachable.object, Cause::NoStates, summary),
    };
    ctx.explain()
}

impl Explanation {
    fn bare(object: u32, cause: Cause, summary: String) -> Explanation {
        Explanation {
            object,
            cause,
            summary,
            start_side: Side::default(),
            goal_side: Side::default(),
            cut: Vec::new(),
            cut_omitted: 0,
            suggestions: Vec::new(),
            pruned: Vec::new(),
            pruned_omitted: 0,
            notes: Vec::new(),
            spans: Vec::new(),
        }
    }
}

/// A hypothetical change, as an orderable key (the public [`Change`] holds reasons with
/// floats, which cannot be ordered).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
enum Key {
    /// Unordered grasp pair (smaller first), declared both ways.
    Transition(u32, u32),
    /// Unordered workspace pair.
    Adjacency(u32, u32),
    /// (end-effector, workspace).
    Reach(u32, u32),
    /// Index into [`Ctx::lost`].
    Relax(usize),
}

impl Key {
    /// Rank of the kind of edit: a transition is one line in the object, an adjacency one
    /// line in the cell, a pruned arc needs geometry changed, a reach extension needs a
    /// robot moved or replaced.
    fn class(self) -> u8 {
        match self {
            Key::Transition(..) => 0,
            Key::Adjacency(..) => 1,
            Key::Relax(_) => 2,
            Key::Reach(..) => 3,
        }
    }
}

/// An arc removed at build time or during the request.
struct Lost {
    from: u32,
    to: u32,
    kind: ArcKind,
    weight: f64,
    source: Option<u32>,
    reason: Infeasibility,
    failed: bool,
}

/// Which workspaces are adjacent: declared ones (known from the move arcs that use them),
/// or derived (two workspaces reached by one movable end-effector).
enum Adjacency {
    Derived,
    Declared(BTreeSet<(u32, u32)>),
}

/// Hypothetical nodes and arcs on top of the graph.
#[derive(Default)]
struct Overlay {
    nodes: Vec<Node>,
    index: HashMap<Node, u32>,
    arcs: Vec<NewArc>,
}

/// A hypothetical arc and the change (index into the change list) that makes it.
#[derive(Clone, Copy)]
struct NewArc {
    from: u32,
    to: u32,
    weight: f64,
    change: usize,
}

/// A start-to-goal path through hypothetical arcs.
struct Route {
    cost: f64,
    /// The hypothetical arcs used, in path order.
    arcs: Vec<NewArc>,
}

/// A verified set of changes.
struct Candidate {
    keys: Vec<Key>,
    route: Route,
    overlay: Overlay,
    doubtful: bool,
    effort: f64,
}

impl Candidate {
    fn class(&self) -> u8 {
        self.keys.iter().map(|k| k.class()).max().unwrap_or(0)
    }

    fn rank(&self, other: &Candidate) -> Ordering {
        self.keys
            .len()
            .cmp(&other.keys.len())
            .then(self.doubtful.cmp(&other.doubtful))
            .then(self.class().cmp(&other.class()))
            .then(self.effort.total_cmp(&other.effort))
            .then(self.route.cost.total_cmp(&other.route.cost))
            .then(self.keys.cmp(&other.keys))
    }
}

/// A cost ordered totally, for the heaps.
#[derive(Clone, Copy, PartialEq)]
struct Cost(f64);

impl Eq for Cost {}

impl PartialOrd for Cost {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Cost {
    fn cmp(&self, other: &Self) -> Ordering {
        self.0.total_cmp(&other.0)
    }
}

/// A gap before merging into cut items.
#[derive(Clone)]
struct Gap {
    kind: CutKind,
    workspaces: BTreeSet<u32>,
    /// (end-effector, grasps) on the start's side.
    near: Vec<(u32, BTreeSet<u32>)>,
    /// (end-effector, grasps) on the goal's side.
    far: Vec<(u32, BTreeSet<u32>)>,
    /// Indices into [`Ctx::lost`].
    lost: BTreeSet<usize>,
    /// Declared transitions the other way: (from grasp, to grasp).
    reverse: BTreeSet<(u32, u32)>,
}

/// Gaps keyed by (kind, near end-effector, far end-effector or first workspace,
/// workspace).
type Gaps = BTreeMap<(CutKind, u32, u32, u32), Gap>;

/// Everything the analysis needs, computed once.
struct Ctx<'a> {
    art: &'a Artifact,
    obj: &'a Object,
    object: u32,
    nodes: &'a [Node],
    index: HashMap<Node, u32>,
    /// Active arcs (graph minus failed): (to, weight) per node, and reversed.
    fwd: Vec<Vec<(u32, f64)>>,
    bwd: Vec<Vec<(u32, f64)>>,
    active: HashSet<(u32, u32)>,
    /// (giving end-effector, taking end-effector, workspace) of active transition arcs.
    active_exchanges: HashSet<(u32, u32, u32)>,
    /// The same for pruned or failed transition arcs.
    lost_exchanges: HashSet<(u32, u32, u32)>,
    lost: Vec<Lost>,
    lost_pairs: HashSet<(u32, u32)>,
    lost_from: Vec<Vec<usize>>,
    /// End-effectors that can hold each grasp, sorted.
    holders: Vec<Vec<u32>>,
    /// Grasps declared for one end-effector (not a kind).
    explicit: Vec<bool>,
    /// Grasps of this object each end-effector can hold.
    ee_grasps: Vec<Vec<u32>>,
    reaches: Vec<Vec<u32>>,
    movable: Vec<bool>,
    adjacency: Adjacency,
    at_ws: Vec<Vec<u32>>,
    /// Declared transitions (from grasp, to grasp) -> their spans.
    declared: BTreeMap<(u32, u32), Vec<u32>>,
    /// The declared transitions each grasp takes part in.
    declared_by_grasp: Vec<Vec<(u32, u32)>>,
    move_weight: f64,
    transition_weight: f64,
    start: u32,
    goals: Vec<u32>,
    is_goal: Vec<bool>,
    d_s: Vec<f64>,
    d_g: Vec<f64>,
    in_r: Vec<bool>,
    in_g: Vec<bool>,
}

impl<'a> Ctx<'a> {
    fn new(
        art: &'a Artifact,
        object: u32,
        obj: &'a Object,
        un: &Unreachable,
    ) -> Result<Ctx<'a>, String> {
        let nodes = obj.graph.nodes.as_slice();
        let n = nodes.len();
        let n_ee = art.end_effectors.len();
        let n_ws = art.workspaces.len();
        let index: HashMap<Node, u32> = nodes
            .iter()
            .enumerate()
            .map(|(i, &node)| (node, i as u32))
            .collect();
        let failed: HashMap<(u32, u32), &Infeasibility> = un
            .failed
            .iter()
            .map(|(a, reason)| ((a.from, a.to), reason))
            .collect();
        let mut fwd = vec![Vec::new(); n];
        let mut bwd = vec![Vec::new(); n];
        let mut active = HashSet::new();
        for arc in &obj.graph.arcs {
            let (f, t) = (arc.from as usize, arc.to as usize);
            if f >= n || t >= n || failed.contains_key(&(arc.from, arc.to)) {
                continue;
            }
            fwd[f].push((arc.to, arc.weight));
            bwd[t].push((arc.from, arc.weight));
            active.insert((arc.from, arc.to));
        }
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
            let (f, t) = (a.from as usize, a.to as usize);
            if f >= n || t >= n || !seen_failed.insert((a.from, a.to)) {
                continue;
            }
            let arc = obj
                .graph
                .arcs
                .iter()
                .find(|x| x.from == a.from && x.to == a.to);
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
                from: a.from,
                to: a.to,
                kind,
                weight,
                source: arc.map(|x| x.source),
                reason: reason.clone(),
                failed: true,
            });
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
        let holders: Vec<Vec<u32>> = obj
            .grasps
            .iter()
            .map(|g| match g.holder {
                Holder::EndEffector(e) if (e as usize) < n_ee => vec![e],
                Holder::EndEffector(_) => Vec::new(),
                Holder::Kind(k) => (0..n_ee as u32)
                    .filter(|&e| art.end_effectors[e as usize].kind == Some(k))
                    .collect(),
            })
            .collect();
        let explicit = obj
            .grasps
            .iter()
            .map(|g| matches!(g.holder, Holder::EndEffector(_)))
            .collect();
        let mut ee_grasps = vec![Vec::new(); n_ee];
        for (g, hs) in holders.iter().enumerate() {
            for &e in hs {
                ee_grasps[e as usize].push(g as u32);
            }
        }
        let reaches: Vec<Vec<u32>> = art
            .end_effectors
            .iter()
            .map(|e| {
                let mut r: Vec<u32> = e
                    .reaches
                    .iter()
                    .copied()
                    .filter(|&w| (w as usize) < n_ws)
                    .collect();
                r.sort_unstable();
                r.dedup();
                r
            })
            .collect();
        let movable = art.end_effectors.iter().map(|e| e.movable).collect();
        let mut at_ws = vec![Vec::new(); n_ws];
        for (i, node) in nodes.iter().enumerate() {
            if let Some(list) = at_ws.get_mut(node.workspace as usize) {
                list.push(i as u32);
            }
        }
        let mut declared: BTreeMap<(u32, u32), Vec<u32>> = BTreeMap::new();
        for t in &obj.transitions {
            declared.entry((t.from, t.to)).or_default().push(t.span);
        }
        let start = *index.get(&un.start).ok_or_else(|| {
            format!(
                "the start state is not a state of `{}`'s graph",
                obj.name.as_str()
            )
        })?;
        let mut goals: Vec<u32> = un
            .goals
            .iter()
            .filter_map(|g| index.get(g).copied())
            .collect();
        goals.sort_unstable();
        goals.dedup();
        if goals.is_empty() {
            return Err(format!(
                "no goal state of the request is a state of `{}`'s graph",
                obj.name.as_str()
            ));
        }
        let mut is_goal = vec![false; n];
        for &g in &goals {
            is_goal[g as usize] = true;
        }
        let d_s = dijkstra(&fwd, &[start]);
        let d_g = dijkstra(&bwd, &goals);
        let in_r = d_s.iter().map(|d| d.is_finite()).collect();
        let in_g = d_g.iter().map(|d| d.is_finite()).collect();
        let mut ctx = Ctx {
            art,
            obj,
            object,
            nodes,
            index,
            fwd,
            bwd,
            active,
            active_exchanges,
            lost_exchanges,
            lost_pairs: lost.iter().map(|l| (l.from, l.to)).collect(),
            lost,
            lost_from,
            holders,
            explicit,
            ee_grasps,
            reaches,
            movable,
            adjacency: Adjacency::Derived,
            at_ws,
            declared_by_grasp: {
                let mut by = vec![Vec::new(); obj.grasps.len()];
                for &(a, b) in declared.keys() {
                    for g in [a, b] {
                        if let Some(list) = by.get_mut(g as usize) {
                            if !list.contains(&(a, b)) {
                                list.push((a, b));
                            }
                        }
                    }
                }
                by
            },
            declared,
            move_weight: art.weights.move_weight,
            transition_weight: art.weights.transition_weight,
            start,
            goals,
            is_goal,
            d_s,
            d_g,
            in_r,
            in_g,
        };
        ctx.adjacency = ctx.find_adjacency();
        Ok(ctx)
    }

    /// The artifact keeps no adjacency list, so it is read off the move arcs. A move arc
    /// over a declared adjacency carries its span (`via`); and with derived adjacency,
    /// every movable end-effector has move arcs (kept or pruned) between every two
    /// workspaces it reaches, for each grasp it holds. Either sign of declared adjacency,
    /// or no move arc at all, gives the pairs the move arcs show. That can miss declared
    /// pairs no hand spans, which is safe: a suggestion checked with fewer arcs than the
    /// real graph has still connects, at worst with an extra `adjacent` line. With no move
    /// arc anywhere, a derived cell has no adjacency worth keeping either, so declaring
    /// one is harmless there too.
    fn find_adjacency(&self) -> Adjacency {
        // Artifacts from the compiler say which pairs were declared; the inference below
        // is for artifacts that do not.
        if let Some(record) = &self.art.adjacency {
            return if record.declared {
                Adjacency::Declared(record.pairs.iter().map(|&(a, b)| ordered(a, b)).collect())
            } else {
                Adjacency::Derived
            };
        }
        let mut declared = false;
        let mut any = false;
        let mut pairs = BTreeSet::new();
        for obj in &self.art.objects {
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
            // Derived adjacency would have made a move between any two states of one
            // movable hand and grasp.
            let mut by_hand: BTreeMap<(u32, u32), Vec<u32>> = BTreeMap::new();
            for (i, n) in g.nodes.iter().enumerate() {
                if self.is_movable(n.end_effector) {
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
            Adjacency::Declared(pairs)
        } else {
            Adjacency::Derived
        }
    }

    // ---- names -------------------------------------------------------------------------

    fn ee(&self, e: u32) -> String {
        self.art
            .end_effectors
            .get(e as usize)
            .map_or_else(|| format!("`end-effector #{e}`"), |x| q(&x.name))
    }

    fn ws(&self, w: u32) -> String {
        self.art
            .workspaces
            .get(w as usize)
            .map_or_else(|| format!("`workspace #{w}`"), |x| q(&x.name))
    }

    fn grasp(&self, g: u32) -> String {
        self.obj
            .grasps
            .get(g as usize)
            .map_or_else(|| format!("`grasp #{g}`"), |x| q(&x.name))
    }

    fn ee_span(&self, e: u32) -> Option<u32> {
        self.art.end_effectors.get(e as usize).map(|x| x.span)
    }

    fn grasp_span(&self, g: u32) -> Option<u32> {
        self.obj.grasps.get(g as usize).map(|x| x.span)
    }

    fn node(&self, i: u32) -> Node {
        self.nodes[i as usize]
    }

    /// "`table` with `g1` in `w1`".
    fn state_text(&self, n: Node) -> String {
        format!(
            "{} with {} in {}",
            self.ee(n.end_effector),
            self.grasp(n.grasp),
            self.ws(n.workspace)
        )
    }

    /// "any grasp of `left_arm`", "grasp `g4` of `left_arm`", "grasps `g4`, `g5` of ...".
    fn grasps_phrase(&self, e: u32, grasps: &BTreeSet<u32>) -> String {
        let all: BTreeSet<u32> = self
            .ee_grasps
            .get(e as usize)
            .map(|g| g.iter().copied().collect())
            .unwrap_or_default();
        if grasps.len() > 1 && *grasps == all {
            format!("any grasp of {}", self.ee(e))
        } else if grasps.len() == 1 {
            let g = grasps.iter().next().copied().unwrap_or(0);
            format!("grasp {} of {}", self.grasp(g), self.ee(e))
        } else {
            format!(
                "grasps {} of {}",
                list(grasps.iter().map(|&g| self.grasp(g)).collect(), "and"),
                self.ee(e)
            )
        }
    }

    /// The grasps of several end-effectors: "any grasp of `left_arm` or `table`".
    fn holders_phrase(&self, side: &[(u32, BTreeSet<u32>)]) -> String {
        let all_any = side.len() > 1
            && side.iter().all(|(e, g)| {
                g.len() > 1 && self.ee_grasps.get(*e as usize).map(|x| x.len()) == Some(g.len())
            });
        if all_any {
            format!(
                "any grasp of {}",
                list(side.iter().map(|(e, _)| self.ee(*e)).collect(), "or")
            )
        } else {
            list(
                side.iter()
                    .map(|(e, g)| self.grasps_phrase(*e, g))
                    .collect(),
                "or",
            )
        }
    }

    /// "the transition `g1 -> g8` from `table` to `right_arm` in `w2`" or "the move of
    /// `right_arm` with `g7` from `w2` to `w3`".
    fn arc_text(&self, from: Node, to: Node, kind: ArcKind) -> String {
        match kind {
            ArcKind::Move => format!(
                "the move of {} with {} from {} to {}",
                self.ee(from.end_effector),
                self.grasp(from.grasp),
                self.ws(from.workspace),
                self.ws(to.workspace)
            ),
            ArcKind::Transition => format!(
                "the transition {} from {} to {} in {}",
                q(&format!(
                    "{} -> {}",
                    self.grasp_name(from.grasp),
                    self.grasp_name(to.grasp)
                )),
                self.ee(from.end_effector),
                self.ee(to.end_effector),
                self.ws(from.workspace)
            ),
        }
    }

    fn grasp_name(&self, g: u32) -> String {
        self.obj
            .grasps
            .get(g as usize)
            .map_or_else(|| format!("#{g}"), |x| x.name.clone())
    }

    fn ws_name(&self, w: u32) -> String {
        self.art
            .workspaces
            .get(w as usize)
            .map_or_else(|| format!("#{w}"), |x| x.name.clone())
    }

    /// Why an arc is infeasible, in words.
    fn reason_text(&self, reason: &Infeasibility) -> String {
        match reason {
            Infeasibility::NoIkSolution {
                end_effector,
                tries,
                position_error,
                rotation_error,
            } => format!(
                "{} cannot reach the pose, closest {} and {:.2} rad off over {} tries",
                self.ee(*end_effector),
                metres(*position_error),
                rotation_error,
                tries
            ),
            Infeasibility::NoClosedChain {
                a,
                b,
                tries,
                position_error,
                rotation_error,
            } => format!(
                "{} and {} cannot hold it at once, the closed chain staying {} and {:.2} rad \
                 open over {} tries",
                self.ee(*a),
                self.ee(*b),
                metres(*position_error),
                rotation_error,
                tries
            ),
            Infeasibility::Collision { a, b } => {
                format!("{} collides with {}", q(a), q(b))
            }
            Infeasibility::NoPlacement { detail } => format!("no placement: {detail}"),
            _ => "it was found infeasible".to_string(),
        }
    }

    /// What would make an infeasible arc feasible.
    fn reason_hint(&self, reason: &Infeasibility, workspace: u32) -> String {
        match reason {
            Infeasibility::NoIkSolution { end_effector, .. } => format!(
                "move {}'s base or {} closer together, or choose a grasp it can reach",
                self.ee(*end_effector),
                self.ws(workspace)
            ),
            Infeasibility::NoClosedChain { .. } => "move the arms closer together, or choose \
                 grasps that leave room for both hands"
                .to_string(),
            // Collision bodies are named `arm/link`; the cell language writes `arm.link`.
            Infeasibility::Collision { a, b } => format!(
                "move one of them, or declare `allow contact {} {}` if the contact is harmless",
                a.replace('/', "."),
                b.replace('/', ".")
            ),
            Infeasibility::NoPlacement { .. } => format!(
                "extend the surface into {}, or choose another resting pose",
                self.ws(workspace)
            ),
            _ => "change the geometry so it becomes feasible".to_string(),
        }
    }

    /// A discriminant of a loss's cause, so suggestions do not repeat one root cause.
    fn cause_key(&self, l: &Lost) -> (u32, u32, u32, String) {
        let from = self.node(l.from);
        let to = self.node(l.to);
        let reason = match &l.reason {
            Infeasibility::NoIkSolution { end_effector, .. } => format!("ik {end_effector}"),
            Infeasibility::NoClosedChain { a, b, .. } => format!("chain {a} {b}"),
            Infeasibility::Collision { a, b } => format!("collision {a} {b}"),
            Infeasibility::NoPlacement { detail } => format!("placement {detail}"),
            _ => "other".to_string(),
        };
        (from.end_effector, to.end_effector, from.workspace, reason)
    }

    // ---- the analysis ------------------------------------------------------------------

    fn explain(&self) -> Explanation {
        let start_side = self.side((0..self.nodes.len() as u32).filter(|&i| self.in_r[i as usize]));
        let goal_side = self.side((0..self.nodes.len() as u32).filter(|&i| self.in_g[i as usize]));
        let mut out = Explanation::bare(self.object, Cause::Missing, String::new());
        out.start_side = start_side;
        out.goal_side = goal_side;
        let from = self.state_text(self.node(self.start));
        let to = self.goals_text();
        let object = q(&self.obj.name);
        if self.goals.iter().any(|&g| self.in_r[g as usize]) {
            out.cause = Cause::Connected;
            out.summary = format!(
                "the graph of {object} does connect {from} to {to}: the request failed for \
                 another reason"
            );
            out.spans = self.labels(&out, &[]);
            return out;
        }
        out.cause = self.cause();
        let candidates = self.suggest();
        let best = candidates.first();
        let (cut, cut_omitted) = self.cut(best);
        let named: BTreeSet<u32> = cut
            .iter()
            .flat_map(|c| c.near.iter().chain(&c.far))
            .copied()
            .collect();
        out.start_side.text = self.side_text(&out.start_side, &named);
        out.goal_side.text = self.side_text(&out.goal_side, &named);
        out.cut = cut;
        out.cut_omitted = cut_omitted;
        let (suggestions, suggestion_labels): (Vec<Suggestion>, Vec<_>) =
            candidates.iter().map(|c| self.suggestion(c)).unzip();
        out.suggestions = suggestions;
        let (pruned, pruned_omitted) = self.pruned_notes();
        out.pruned = pruned;
        out.pruned_omitted = pruned_omitted;
        let why = match out.cause {
            Cause::Pruned => "the arcs that would join them were pruned as kinematically \
                              infeasible"
                .to_string(),
            Cause::Failed => "arcs that would join them failed during this request".to_string(),
            _ => format!(
                "the cell declares no way from the {} it reaches to the {} that {} there",
                count(out.start_side.states.len(), "state"),
                count(out.goal_side.states.len(), "state"),
                if out.goal_side.states.len() == 1 {
                    "leads"
                } else {
                    "lead"
                },
            ),
        };
        out.summary = format!("no path takes {object} from {from} to {to}: {why}");
        if out.suggestions.is_empty() {
            out.notes.push(
                "no single change, nor a short set of transitions, adjacencies or \
                 relaxed arcs, connects them"
                    .to_string(),
            );
        } else if out
            .suggestions
            .iter()
            .flat_map(|s| &s.changes)
            .any(|c| !matches!(c, Change::RelaxPruned { .. }))
        {
            out.notes.push(
                "suggestions are checked on the graph, not kinematically: build with \
                 verification again after the change"
                    .to_string(),
            );
        }
        out.spans = self.labels(&out, &suggestion_labels);
        out
    }

    fn goals_text(&self) -> String {
        let mut holders = BTreeSet::new();
        let mut grasps = BTreeSet::new();
        let mut wss = BTreeSet::new();
        for &g in &self.goals {
            let n = self.node(g);
            holders.insert(n.end_effector);
            grasps.insert(n.grasp);
            wss.insert(n.workspace);
        }
        let holders = list(holders.iter().map(|&e| self.ee(e)).collect(), "or");
        let wss = list(wss.iter().map(|&w| self.ws(w)).collect(), "or");
        if grasps.len() <= 3 {
            let grasps = list(grasps.iter().map(|&g| self.grasp(g)).collect(), "or");
            format!("{holders} with {grasps} in {wss}")
        } else {
            format!("{holders} in {wss}")
        }
    }

    fn side(&self, states: impl Iterator<Item = u32>) -> Side {
        let states: Vec<u32> = states.collect();
        let mut per: BTreeMap<u32, (BTreeSet<u32>, BTreeSet<u32>)> = BTreeMap::new();
        for &i in &states {
            let n = self.node(i);
            let entry = per.entry(n.end_effector).or_default();
            entry.0.insert(n.grasp);
            entry.1.insert(n.workspace);
        }
        let holdings: Vec<Holding> = per
            .into_iter()
            .map(|(e, (g, w))| Holding {
                end_effector: e,
                grasps: g.into_iter().collect(),
                workspaces: w.into_iter().collect(),
            })
            .collect();
        let mut side = Side {
            states,
            holdings,
            text: String::new(),
        };
        side.text = self.side_text(&side, &BTreeSet::new());
        side
    }

    /// "41 states: `arm4` with ... in `w4` and `w5`; ... and 6 more end-effectors", the
    /// end-effectors in `first` (those the cut names) before the others.
    fn side_text(&self, side: &Side, first: &BTreeSet<u32>) -> String {
        let mut holdings: Vec<&Holding> = side.holdings.iter().collect();
        holdings.sort_by_key(|h| (!first.contains(&h.end_effector), h.end_effector));
        let mut parts: Vec<String> = holdings
            .iter()
            .take(MAX_LISTED)
            .map(|h| {
                format!(
                    "{} with {} in {}",
                    self.ee(h.end_effector),
                    list(h.grasps.iter().map(|&g| self.grasp(g)).collect(), "and"),
                    list(h.workspaces.iter().map(|&w| self.ws(w)).collect(), "and")
                )
            })
            .collect();
        if holdings.len() > MAX_LISTED {
            let more = holdings.len() - MAX_LISTED;
            let noun = if more == 1 {
                "end-effector"
            } else {
                "end-effectors"
            };
            parts.push(format!("and {more} more {noun}"));
        }
        format!(
            "{}: {}",
            count(side.states.len(), "state"),
            parts.join("; ")
        )
    }

    /// Restoring which lost arcs connects the start to a goal.
    fn cause(&self) -> Cause {
        let pruned_only = |l: &Lost| !l.failed;
        if self.reaches_goal_with(pruned_only) {
            Cause::Pruned
        } else if self.reaches_goal_with(|_| true) {
            Cause::Failed
        } else {
            Cause::Missing
        }
    }

    fn reaches_goal_with(&self, restore: impl Fn(&Lost) -> bool) -> bool {
        let n = self.nodes.len();
        let mut seen = vec![false; n];
        let mut stack = vec![self.start];
        seen[self.start as usize] = true;
        while let Some(u) = stack.pop() {
            if self.is_goal[u as usize] {
                return true;
            }
            let lost = self.lost_from[u as usize]
                .iter()
                .map(|&i| &self.lost[i])
                .filter(|l| restore(l))
                .map(|l| l.to);
            for v in self.fwd[u as usize].iter().map(|a| a.0).chain(lost) {
                if !seen[v as usize] {
                    seen[v as usize] = true;
                    stack.push(v);
                }
            }
        }
        false
    }

    // ---- hypothetical changes ----------------------------------------------------------

    fn node_at(&self, ov: &Overlay, n: Node) -> Option<u32> {
        self.index.get(&n).or_else(|| ov.index.get(&n)).copied()
    }

    fn adjacent(&self, reaches: &[Vec<u32>], added: &BTreeSet<(u32, u32)>, a: u32, b: u32) -> bool {
        if a == b {
            return false;
        }
        if added.contains(&ordered(a, b)) {
            return true;
        }
        match &self.adjacency {
            Adjacency::Declared(pairs) => pairs.contains(&ordered(a, b)),
            Adjacency::Derived => reaches
                .iter()
                .enumerate()
                .any(|(e, r)| self.movable[e] && r.contains(&a) && r.contains(&b)),
        }
    }

    /// Every node and arc that `changes` would add, by the compiler's graph rules.
    fn apply(&self, changes: &[Key]) -> Overlay {
        let mut ov = Overlay::default();
        let mut reaches = self.reaches.clone();
        let mut added = BTreeSet::new();
        for &key in changes {
            match key {
                Key::Reach(e, w) => {
                    if let Some(r) = reaches.get_mut(e as usize) {
                        if !r.contains(&w) {
                            r.push(w);
                            r.sort_unstable();
                        }
                    }
                }
                Key::Adjacency(a, b) => {
                    added.insert(ordered(a, b));
                }
                _ => {}
            }
        }
        let base = self.nodes.len() as u32;
        for &key in changes {
            if let Key::Reach(e, w) = key {
                for &g in self.ee_grasps.get(e as usize).into_iter().flatten() {
                    let n = Node {
                        end_effector: e,
                        grasp: g,
                        workspace: w,
                    };
                    if !self.index.contains_key(&n) && !ov.index.contains_key(&n) {
                        ov.index.insert(n, base + ov.nodes.len() as u32);
                        ov.nodes.push(n);
                    }
                }
            }
        }
        for (ci, &key) in changes.iter().enumerate() {
            match key {
                Key::Transition(a, b) => {
                    self.transition_arcs(&mut ov, &reaches, (a, b), false, None, ci);
                    if a != b {
                        self.transition_arcs(&mut ov, &reaches, (b, a), false, None, ci);
                    }
                }
                Key::Adjacency(a, b) => {
                    for (e, r) in reaches.iter().enumerate() {
                        if self.movable[e] && r.contains(&a) && r.contains(&b) {
                            self.move_arcs(&mut ov, e as u32, a, b, ci);
                        }
                    }
                }
                Key::Reach(e, w) => {
                    let Some(r) = reaches.get(e as usize) else {
                        continue;
                    };
                    if self.movable[e as usize] {
                        for &x in r {
                            if self.adjacent(&reaches, &added, w, x) {
                                self.move_arcs(&mut ov, e, w, x, ci);
                            }
                        }
                    }
                    // Derived adjacency is global: the extended hand makes `w` adjacent to
                    // its other workspaces for every movable hand reaching both.
                    if matches!(self.adjacency, Adjacency::Derived) && self.movable[e as usize] {
                        for &x in r {
                            if x == w || self.adjacent(&self.reaches, &BTreeSet::new(), w, x) {
                                continue;
                            }
                            for (e2, r2) in reaches.iter().enumerate() {
                                if e2 as u32 != e
                                    && self.movable[e2]
                                    && r2.contains(&w)
                                    && r2.contains(&x)
                                {
                                    self.move_arcs(&mut ov, e2 as u32, w, x, ci);
                                }
                            }
                        }
                    }
                    let touching = self
                        .ee_grasps
                        .get(e as usize)
                        .into_iter()
                        .flatten()
                        .flat_map(|g| {
                            self.declared_by_grasp
                                .get(*g as usize)
                                .into_iter()
                                .flatten()
                        });
                    for &(from, to) in touching {
                        let explicit = self.is_explicit(from) && self.is_explicit(to);
                        self.transition_arcs(
                            &mut ov,
                            &reaches,
                            (from, to),
                            explicit,
                            Some((e, w)),
                            ci,
                        );
                    }
                }
                Key::Relax(i) => {
                    if let Some(l) = self.lost.get(i) {
                        ov.arcs.push(NewArc {
                            from: l.from,
                            to: l.to,
                            weight: l.weight,
                            change: ci,
                        });
                    }
                }
            }
        }
        ov
    }

    fn is_explicit(&self, g: u32) -> bool {
        self.explicit.get(g as usize).copied().unwrap_or(false)
    }

    /// Move arcs both ways between `a` and `b` for every grasp `e` holds.
    fn move_arcs(&self, ov: &mut Overlay, e: u32, a: u32, b: u32, change: usize) {
        if a == b {
            return;
        }
        for &g in self.ee_grasps.get(e as usize).into_iter().flatten() {
            let at = |w| Node {
                end_effector: e,
                grasp: g,
                workspace: w,
            };
            if let (Some(x), Some(y)) = (self.node_at(ov, at(a)), self.node_at(ov, at(b))) {
                for (from, to) in [(x, y), (y, x)] {
                    if self.lost_pairs.contains(&(from, to)) {
                        continue;
                    }
                    ov.arcs.push(NewArc {
                        from,
                        to,
                        weight: self.move_weight,
                        change,
                    });
                }
            }
        }
    }

    /// Transition arcs `grasps.0 -> grasps.1` in every workspace both holders reach; with
    /// `only`, just those touching that end-effector in that workspace.
    fn transition_arcs(
        &self,
        ov: &mut Overlay,
        reaches: &[Vec<u32>],
        (from, to): (u32, u32),
        allow_same: bool,
        only: Option<(u32, u32)>,
        change: usize,
    ) {
        let (Some(hf), Some(ht)) = (
            self.holders.get(from as usize),
            self.holders.get(to as usize),
        ) else {
            return;
        };
        for &ei in hf {
            for &ej in ht {
                if (ei == ej && !allow_same)
                    || (!self.movable[ei as usize] && !self.movable[ej as usize])
                {
                    continue;
                }
                if let Some((e, _)) = only {
                    if ei != e && ej != e {
                        continue;
                    }
                }
                let (ri, rj) = (&reaches[ei as usize], &reaches[ej as usize]);
                for &w in ri.iter().filter(|w| rj.contains(w)) {
                    if only.is_some_and(|(_, ow)| ow != w) {
                        continue;
                    }
                    let a = Node {
                        end_effector: ei,
                        grasp: from,
                        workspace: w,
                    };
                    let b = Node {
                        end_effector: ej,
                        grasp: to,
                        workspace: w,
                    };
                    // A declaration cannot bring back an arc that was pruned or failed:
                    // the same check would remove it again.
                    if let (Some(x), Some(y)) = (self.node_at(ov, a), self.node_at(ov, b)) {
                        if !self.lost_pairs.contains(&(x, y)) {
                            ov.arcs.push(NewArc {
                                from: x,
                                to: y,
                                weight: self.transition_weight,
                                change,
                            });
                        }
                    }
                }
            }
        }
    }

    /// The cheapest start-to-goal path through the overlay, if any. R and G are already
    /// known, so the search starts at the tails of hypothetical arcs inside R (at their
    /// distance from the start) and stops on entering G (adding the distance to the goal);
    /// only the states in between are explored.
    fn connect(&self, ov: &Overlay) -> Option<Route> {
        let n = self.nodes.len();
        let total = n + ov.nodes.len();
        // Sparse: the search rarely leaves the few states between R and G.
        let mut extra: HashMap<u32, Vec<usize>> = HashMap::new();
        let mut dist: HashMap<u32, f64> = HashMap::new();
        let mut pred: HashMap<u32, (u32, Option<usize>)> = HashMap::new();
        let mut heap = BinaryHeap::new();
        for (i, a) in ov.arcs.iter().enumerate() {
            extra.entry(a.from).or_default().push(i);
            let f = a.from as usize;
            if f < n && self.in_r[f] && !dist.contains_key(&a.from) {
                dist.insert(a.from, self.d_s[f]);
                heap.push(Reverse((Cost(self.d_s[f]), a.from)));
            }
        }
        let mut best: Option<(f64, u32, Option<usize>)> = None;
        while let Some(Reverse((Cost(d), u))) = heap.pop() {
            if dist.get(&u).is_some_and(|&x| d > x) {
                continue;
            }
            if best.is_some_and(|b| d >= b.0) {
                break;
            }
            let old: &[(u32, f64)] = if (u as usize) < n && !self.in_r[u as usize] {
                &self.fwd[u as usize]
            } else {
                &[]
            };
            let new = extra
                .get(&u)
                .into_iter()
                .flatten()
                .map(|&i| (ov.arcs[i].to, ov.arcs[i].weight, Some(i)));
            for (v, w, arc) in old.iter().map(|&(v, w)| (v, w, None)).chain(new) {
                let nd = d + w;
                let vi = v as usize;
                if vi >= total || (vi < n && self.in_r[vi]) {
                    continue;
                }
                if vi < n && self.in_g[vi] {
                    let through = nd + self.d_g[vi];
                    if best.is_none_or(|b| through < b.0) {
                        best = Some((through, u, arc));
                    }
                    continue;
                }
                if dist.get(&v).is_none_or(|&x| nd < x) {
                    dist.insert(v, nd);
                    pred.insert(v, (u, arc));
                    heap.push(Reverse((Cost(nd), v)));
                }
            }
        }
        let (cost, mut u, last) = best?;
        let mut arcs: Vec<NewArc> = last.map(|i| ov.arcs[i]).into_iter().collect();
        while let Some(&(p, arc)) = pred.get(&u) {
            arcs.extend(arc.map(|i| ov.arcs[i]));
            u = p;
        }
        arcs.reverse();
        Some(Route { cost, arcs })
    }

    fn try_keys(&self, keys: Vec<Key>) -> Option<Candidate> {
        let overlay = self.apply(&keys);
        let route = self.connect(&overlay)?;
        let mut c = Candidate {
            keys,
            route,
            overlay,
            doubtful: false,
            effort: 0.0,
        };
        c.doubtful = self.doubtful(&c);
        c.effort = c
            .keys
            .iter()
            .map(|&k| match k {
                Key::Reach(e, w) => self.reach_distance(e, w).unwrap_or(0.0),
                _ => 0.0,
            })
            .sum();
        Some(c)
    }

    /// A new transition whose every use lies between two hands in a workspace where each
    /// transition declared between them was infeasible is likely to fail the same way.
    fn doubtful(&self, c: &Candidate) -> bool {
        if !c.keys.iter().all(|k| matches!(k, Key::Transition(..))) {
            return false;
        }
        let n = self.nodes.len();
        let mut uses = c
            .route
            .arcs
            .iter()
            .filter(|a| (a.from as usize) < n && (a.to as usize) < n)
            .peekable();
        if uses.peek().is_none() {
            return false;
        }
        uses.all(|a| {
            let (x, y) = (self.node(a.from), self.node(a.to));
            let key = (x.end_effector, y.end_effector, x.workspace);
            self.lost_exchanges.contains(&key) && !self.active_exchanges.contains(&key)
        })
    }

    /// Distance from an end-effector's reach boxes to a workspace's boxes, when both have
    /// geometry.
    fn reach_distance(&self, e: u32, w: u32) -> Option<f64> {
        let reach = &self.art.end_effectors.get(e as usize)?.reach_boxes;
        let boxes = &self.art.workspaces.get(w as usize)?.boxes;
        reach
            .iter()
            .flat_map(|a| boxes.iter().map(move |b| box_distance(a, b)))
            .min_by(|a, b| a.total_cmp(b))
    }

    /// Verified candidates, best first, chosen for the explanation.
    fn suggest(&self) -> Vec<Candidate> {
        let mut found = self.single_changes();
        if found.is_empty() {
            found = self.several_changes();
        }
        found.sort_by(|a, b| a.rank(b));
        // A transition likely to fail like its neighbours is worth showing only when
        // nothing better exists.
        if found.iter().any(|c| !c.doubtful) {
            found.retain(|c| !c.doubtful);
        }
        // Extending a reach means moving or replacing a robot: a last resort, shown only
        // when no declaration or geometric fix connects.
        if found.iter().any(|c| c.class() < Key::Reach(0, 0).class()) {
            found.retain(|c| c.class() < Key::Reach(0, 0).class());
        }
        // One suggestion per root cause: eleven arcs pruned because one arm cannot reach
        // one workspace are one problem, and ten ways for the same two hands to exchange
        // the object in the same workspace are one idea.
        let mut seen = BTreeSet::new();
        found.retain(|c| seen.insert(self.idea(c)));
        found.truncate(MAX_SUGGESTIONS);
        found
    }

    /// What makes two suggestions the same idea (see [`Ctx::suggest`]).
    fn idea(&self, c: &Candidate) -> (Vec<Key>, String) {
        match c.keys.as_slice() {
            [Key::Relax(i)] => {
                let (a, b, w, why) = self.cause_key(&self.lost[*i]);
                (Vec::new(), format!("relax {a} {b} {w} {why}"))
            }
            [Key::Transition(..)] => match c.route.arcs.first() {
                Some(arc) => match (self.overlay_node(c, arc.from), self.overlay_node(c, arc.to)) {
                    (Some(x), Some(y)) => (
                        Vec::new(),
                        format!(
                            "exchange {} {} {}",
                            x.end_effector, y.end_effector, x.workspace
                        ),
                    ),
                    _ => (c.keys.clone(), String::new()),
                },
                None => (c.keys.clone(), String::new()),
            },
            _ => (c.keys.clone(), String::new()),
        }
    }

    fn single_changes(&self) -> Vec<Candidate> {
        let mut found = Vec::new();
        let n_grasps = self.obj.grasps.len() as u32;
        let mut in_g = vec![false; n_grasps as usize];
        for (i, node) in self.nodes.iter().enumerate() {
            if let Some(slot) = in_g.get_mut(node.grasp as usize) {
                *slot |= self.in_g[i];
            }
        }
        // A declaration helps only if one of its arcs leaves R (so it joins a state of R
        // to a state outside R in one workspace) and one enters G.
        let mut pairs = BTreeSet::new();
        for (u, nu) in self.nodes.iter().enumerate() {
            if !self.in_r[u] {
                continue;
            }
            for &v in self.at_ws.get(nu.workspace as usize).into_iter().flatten() {
                let nv = self.node(v);
                if self.in_r[v as usize]
                    || nv.end_effector == nu.end_effector
                    || !(self.is_movable(nu.end_effector) || self.is_movable(nv.end_effector))
                    || self.declared.contains_key(&(nu.grasp, nv.grasp))
                    || !(in_g.get(nu.grasp as usize).copied().unwrap_or(false)
                        || in_g.get(nv.grasp as usize).copied().unwrap_or(false))
                {
                    continue;
                }
                pairs.insert(ordered(nu.grasp, nv.grasp));
            }
        }
        for (a, b) in pairs.into_iter().take(MAX_TRIES) {
            found.extend(self.try_keys(vec![Key::Transition(a, b)]));
        }
        if let Adjacency::Declared(pairs) = &self.adjacency {
            let n_ws = self.art.workspaces.len() as u32;
            for a in 0..n_ws {
                for b in a + 1..n_ws {
                    let spanned = self.reaches.iter().enumerate().any(|(e, r)| {
                        self.movable[e]
                            && !self.ee_grasps[e].is_empty()
                            && r.contains(&a)
                            && r.contains(&b)
                    });
                    if spanned && !pairs.contains(&(a, b)) {
                        found.extend(self.try_keys(vec![Key::Adjacency(a, b)]));
                    }
                }
            }
        }
        for (i, l) in self.lost.iter().enumerate() {
            if self.in_r[l.from as usize] && self.in_g[l.to as usize] {
                found.extend(self.try_keys(vec![Key::Relax(i)]));
            }
        }
        // The new states of a reach extension join R by a move of the hand or a
        // transition in the new workspace, and G likewise.
        let mut sides: HashMap<(bool, u32), (bool, bool)> = HashMap::new();
        for (i, n) in self.nodes.iter().enumerate() {
            for key in [(true, n.end_effector), (false, n.workspace)] {
                let entry = sides.entry(key).or_default();
                entry.0 |= self.in_r[i];
                entry.1 |= self.in_g[i];
            }
        }
        let side = |key| sides.get(&key).copied().unwrap_or_default();
        let helps = |e: u32, w: u32| {
            let (hand, here) = (side((true, e)), side((false, w)));
            (hand.0 || here.0) && (hand.1 || here.1)
        };
        let reach = self
            .reach_candidates()
            .into_iter()
            .filter(|&(e, w)| helps(e, w));
        for (e, w) in reach.take(MAX_TRIES) {
            found.extend(self.try_keys(vec![Key::Reach(e, w)]));
        }
        found
    }

    /// (movable end-effector, workspace it does not reach), nearest first when the cell
    /// has geometry.
    fn reach_candidates(&self) -> Vec<(u32, u32)> {
        let n_ws = self.art.workspaces.len() as u32;
        let mut out: Vec<(f64, u32, u32)> = Vec::new();
        for (e, r) in self.reaches.iter().enumerate() {
            if !self.movable[e] || self.ee_grasps[e].is_empty() {
                continue;
            }
            for w in (0..n_ws).filter(|w| !r.contains(w)) {
                let d = self.reach_distance(e as u32, w).unwrap_or(0.0);
                out.push((d, e as u32, w));
            }
        }
        out.sort_by(|a, b| a.0.total_cmp(&b.0).then((a.1, a.2).cmp(&(b.1, b.2))));
        out.into_iter().map(|(_, e, w)| (e, w)).collect()
    }

    /// When no single change connects: the change sets of paths needing the fewest
    /// hypothetical arcs, the first and the alternatives found by forbidding each of its
    /// changes in turn; plus, in cells that declare adjacency, a reach extension with the
    /// adjacency it needs.
    fn several_changes(&self) -> Vec<Candidate> {
        let mut sets: BTreeSet<Vec<Key>> = BTreeSet::new();
        if let Some(first) = self.fewest_changes(&BTreeSet::new(), &[]) {
            for &k in &first {
                if let Some(alt) = self.fewest_changes(&BTreeSet::from([k]), &[]) {
                    sets.insert(self.minimal(alt));
                }
            }
            sets.insert(self.minimal(first));
        }
        // A reach extension with what else it needs (a transition with the hand it now
        // meets, an adjacency), nearest workspaces first.
        for (e, w) in self.reach_candidates().into_iter().take(MAX_REACH_SETS) {
            if let Some(keys) = self.fewest_changes(&BTreeSet::new(), &[Key::Reach(e, w)]) {
                sets.insert(self.minimal(keys));
            }
        }
        sets.into_iter()
            .filter(|s| !s.is_empty())
            .filter_map(|s| self.try_keys(s))
            .collect()
    }

    /// Drops changes that are not needed.
    fn minimal(&self, mut keys: Vec<Key>) -> Vec<Key> {
        keys.sort();
        keys.dedup();
        let mut i = 0;
        while i < keys.len() && keys.len() > 1 {
            let mut rest = keys.clone();
            rest.remove(i);
            if self.connect(&self.apply(&rest)).is_some() {
                keys = rest;
            } else {
                i += 1;
            }
        }
        keys
    }

    /// 0-1 breadth-first search from the start over the graph with the `base` changes
    /// made: existing arcs cost nothing, hypothetical ones (a transition between two
    /// grasps held in one workspace, an adjacency, a restored arc) cost one. Returns the
    /// distinct changes of the path found, `base` included.
    fn fewest_changes(&self, banned: &BTreeSet<Key>, base: &[Key]) -> Option<Vec<Key>> {
        let ov = self.apply(base);
        let n = self.nodes.len();
        let total = n + ov.nodes.len();
        let node_of = |i: u32| -> Node {
            match (i as usize).checked_sub(n) {
                Some(k) => ov.nodes[k],
                None => self.node(i),
            }
        };
        let mut extra_at_ws: BTreeMap<u32, Vec<u32>> = BTreeMap::new();
        for (k, node) in ov.nodes.iter().enumerate() {
            extra_at_ws
                .entry(node.workspace)
                .or_default()
                .push((n + k) as u32);
        }
        let mut extra_from: HashMap<u32, Vec<u32>> = HashMap::new();
        for a in &ov.arcs {
            extra_from.entry(a.from).or_default().push(a.to);
        }
        let mut dist = vec![u32::MAX; total];
        let mut pred: Vec<Option<(u32, Option<Key>)>> = vec![None; total];
        let mut deque = VecDeque::new();
        dist[self.start as usize] = 0;
        deque.push_back((self.start, 0u32));
        let mut reached = None;
        while let Some((u, d)) = deque.pop_front() {
            let ui = u as usize;
            if d > dist[ui] {
                continue;
            }
            if ui < n && self.is_goal[ui] {
                reached = Some(u);
                break;
            }
            let mut next: Vec<(u32, Option<Key>)> = Vec::new();
            if ui < n {
                next.extend(self.fwd[ui].iter().map(|&(v, _)| (v, None)));
                next.extend(
                    self.lost_from[ui]
                        .iter()
                        .map(|&i| (self.lost[i].to, Some(Key::Relax(i)))),
                );
            }
            next.extend(extra_from.get(&u).into_iter().flatten().map(|&v| (v, None)));
            let nu = node_of(u);
            let hu = nu.end_effector;
            let here = self
                .at_ws
                .get(nu.workspace as usize)
                .into_iter()
                .flatten()
                .chain(extra_at_ws.get(&nu.workspace).into_iter().flatten());
            for &v in here {
                let nv = node_of(v);
                let hv = nv.end_effector;
                if hu == hv
                    || !(self.is_movable(hu) || self.is_movable(hv))
                    || self.active.contains(&(u, v))
                    || self.declared.contains_key(&(nu.grasp, nv.grasp))
                {
                    continue;
                }
                let key = Key::Transition(nu.grasp.min(nv.grasp), nu.grasp.max(nv.grasp));
                next.push((v, Some(key)));
            }
            if let Adjacency::Declared(pairs) = &self.adjacency {
                if self.is_movable(hu) {
                    let all = self.reach(hu).iter().copied();
                    for x in all.chain(base.iter().filter_map(|&k| match k {
                        Key::Reach(e, x) if e == hu => Some(x),
                        _ => None,
                    })) {
                        let pair = ordered(nu.workspace, x);
                        if x == nu.workspace || pairs.contains(&pair) {
                            continue;
                        }
                        let to = Node { workspace: x, ..nu };
                        if let Some(v) = self.node_at(&ov, to) {
                            next.push((v, Some(Key::Adjacency(pair.0, pair.1))));
                        }
                    }
                }
            }
            for (v, key) in next {
                if key.is_some_and(|k| banned.contains(&k)) || v as usize >= total {
                    continue;
                }
                let step = u32::from(key.is_some());
                let nd = d + step;
                if nd < dist[v as usize] {
                    dist[v as usize] = nd;
                    pred[v as usize] = Some((u, key));
                    if step == 0 {
                        deque.push_front((v, nd));
                    } else {
                        deque.push_back((v, nd));
                    }
                }
            }
        }
        let mut u = reached?;
        let mut keys = base.to_vec();
        while let Some((p, key)) = pred[u as usize] {
            keys.extend(key);
            u = p;
        }
        keys.sort();
        keys.dedup();
        Some(keys)
    }

    // ---- suggestions in words ----------------------------------------------------------

    fn overlay_node(&self, c: &Candidate, i: u32) -> Option<Node> {
        let n = self.nodes.len();
        if (i as usize) < n {
            Some(self.node(i))
        } else {
            c.overlay.nodes.get(i as usize - n).copied()
        }
    }

    /// A candidate in words, with a label for each source place to edit.
    fn suggestion(&self, c: &Candidate) -> (Suggestion, Vec<(u32, String)>) {
        let mut changes = Vec::new();
        let mut texts = Vec::new();
        let mut spans = Vec::new();
        let mut labels = Vec::new();
        for (ci, &key) in c.keys.iter().enumerate() {
            let used: Vec<(Node, Node)> = c
                .route
                .arcs
                .iter()
                .filter(|a| a.change == ci)
                .filter_map(|a| Some((self.overlay_node(c, a.from)?, self.overlay_node(c, a.to)?)))
                .collect();
            let (change, text, span) = self.change(key, &used);
            labels.extend(span.iter().map(|&s| (s, short(&text))));
            changes.push(change);
            texts.push(text);
            spans.extend(span);
        }
        let text = match texts.len() {
            1 => texts.remove(0),
            _ => {
                let last = texts.pop().unwrap_or_default();
                format!("{}, and {}", texts.join(", "), last)
            }
        };
        spans.sort_unstable();
        spans.dedup();
        (
            Suggestion {
                changes,
                text,
                cost: c.route.cost,
                spans,
            },
            labels,
        )
    }

    /// A change, its words, and the source places to edit.
    fn change(&self, key: Key, used: &[(Node, Node)]) -> (Change, String, Vec<u32>) {
        let object = q(&self.obj.name);
        match key {
            Key::Transition(a, b) => {
                let first = used
                    .iter()
                    .find(|(x, y)| x.workspace == y.workspace && x.end_effector != y.end_effector);
                let (from, to, workspace) = match first {
                    Some((x, y)) => (x.grasp, y.grasp, x.workspace),
                    None => (a, b, 0),
                };
                // Every distinct exchange the plan would make with it, in order: one
                // two-way declaration may serve twice ("take it ... and put it ...").
                let mut uses: Vec<String> = Vec::new();
                for (x, y) in used {
                    let how = self.exchange(*x, *y);
                    if x.workspace == y.workspace
                        && x.end_effector != y.end_effector
                        && !uses.contains(&how)
                    {
                        uses.push(how);
                    }
                }
                let how = uses.join(", and ");
                let reverse_of = self
                    .declared
                    .get(&(to, from))
                    .and_then(|s| s.first().copied());
                let line = q(&format!(
                    "transition {} <-> {}",
                    self.grasp_name(from),
                    self.grasp_name(to)
                ));
                let mut text = match reverse_of {
                    Some(_) => format!(
                        "make {} two-way ({line})",
                        q(&format!(
                            "transition {} -> {}",
                            self.grasp_name(to),
                            self.grasp_name(from)
                        ))
                    ),
                    None => format!("add {line} to {object}"),
                };
                if !how.is_empty() {
                    text.push_str(&format!(", so {how}"));
                }
                let spans = match reverse_of {
                    Some(s) => vec![s],
                    None => [self.grasp_span(from), self.grasp_span(to)]
                        .into_iter()
                        .flatten()
                        .collect(),
                };
                (
                    Change::AddTransition {
                        from_grasp: from,
                        to_grasp: to,
                        workspace,
                        reverse_of,
                    },
                    text,
                    spans,
                )
            }
            Key::Adjacency(a, b) => {
                let who = used.first().map(|(x, _)| x.end_effector);
                let mut text = format!(
                    "declare {}",
                    q(&format!("adjacent {} {}", self.ws_name(a), self.ws_name(b)))
                );
                if let Some(e) = who {
                    text.push_str(&format!(
                        ", so {} can carry it between {} and {}",
                        self.ee(e),
                        self.ws(a),
                        self.ws(b)
                    ));
                }
                let spans = [a, b]
                    .iter()
                    .filter_map(|&w| self.art.workspaces.get(w as usize).map(|x| x.span))
                    .collect();
                (Change::AddAdjacency { a, b }, text, spans)
            }
            Key::Reach(e, w) => {
                let distance = self.reach_distance(e, w);
                let mut meets = BTreeSet::new();
                for (x, y) in used {
                    if x.workspace == w && y.workspace == w && x.end_effector != y.end_effector {
                        meets.insert(if x.end_effector == e {
                            y.end_effector
                        } else {
                            x.end_effector
                        });
                    }
                }
                let mut text =
                    format!("extend the reach of {} to cover {}", self.ee(e), self.ws(w));
                if let Some(d) = distance {
                    text.push_str(&format!(" ({} beyond it)", metres(d)));
                }
                if !meets.is_empty() {
                    text.push_str(&format!(
                        ", where it meets {}",
                        list(meets.iter().map(|&m| self.ee(m)).collect(), "and")
                    ));
                }
                (
                    Change::ExtendReach {
                        end_effector: e,
                        workspace: w,
                        distance,
                    },
                    text,
                    self.ee_span(e).into_iter().collect(),
                )
            }
            Key::Relax(i) => {
                let l = &self.lost[i];
                let (x, y) = (self.node(l.from), self.node(l.to));
                let text = format!(
                    "make {} feasible ({}): {}",
                    self.arc_text(x, y, l.kind),
                    self.reason_text(&l.reason),
                    self.reason_hint(&l.reason, y.workspace)
                );
                (
                    Change::RelaxPruned {
                        arc: ArcRef {
                            from: l.from,
                            to: l.to,
                        },
                        kind: l.kind,
                        reason: l.reason.clone(),
                        failed: l.failed,
                    },
                    text,
                    l.source.into_iter().collect(),
                )
            }
        }
    }

    /// "`left_arm` can hand it to `right_arm` in `w2`", "... put it on `table` ...".
    fn exchange(&self, x: Node, y: Node) -> String {
        let (mx, my) = (
            self.movable
                .get(x.end_effector as usize)
                .copied()
                .unwrap_or(false),
            self.movable
                .get(y.end_effector as usize)
                .copied()
                .unwrap_or(false),
        );
        let (a, b, w) = (
            self.ee(x.end_effector),
            self.ee(y.end_effector),
            self.ws(x.workspace),
        );
        match (mx, my) {
            (true, true) => format!("{a} can hand it to {b} in {w}"),
            (true, false) => format!("{a} can put it on {b} in {w}"),
            _ => format!("{b} can take it from {a} in {w}"),
        }
    }

    // ---- the cut -----------------------------------------------------------------------

    fn cut(&self, best: Option<&Candidate>) -> (Vec<CutItem>, usize) {
        let mut gaps: Gaps = BTreeMap::new();
        self.border_gaps(&mut gaps);
        if let Some(c) = best {
            if !c.keys.iter().any(|k| matches!(k, Key::Reach(..))) {
                self.route_gaps(c, &mut gaps);
            }
        }
        let mut items = self.merge(gaps.into_values().collect());
        if items.is_empty() {
            items = self.fallback_items();
        }
        let omitted = items.len().saturating_sub(MAX_CUT);
        items.truncate(MAX_CUT);
        (items, omitted)
    }

    /// Gaps between states of R and states of G that share a workspace.
    fn border_gaps(&self, gaps: &mut Gaps) {
        for (w, states) in self.at_ws.iter().enumerate() {
            let w = w as u32;
            let mut near: BTreeMap<u32, BTreeSet<u32>> = BTreeMap::new();
            let mut far: BTreeMap<u32, BTreeSet<u32>> = BTreeMap::new();
            for &i in states {
                let n = self.node(i);
                if self.in_r[i as usize] {
                    near.entry(n.end_effector).or_default().insert(n.grasp);
                }
                if self.in_g[i as usize] {
                    far.entry(n.end_effector).or_default().insert(n.grasp);
                }
            }
            for (&a, ng) in &near {
                for (&b, fg) in &far {
                    if a == b || !(self.is_movable(a) || self.is_movable(b)) {
                        continue;
                    }
                    self.transition_gap(gaps, w, (a, ng.clone()), (b, fg.clone()));
                }
            }
        }
        // One hand on both sides with one grasp: a move that is missing or infeasible.
        for (i, n) in self.nodes.iter().enumerate() {
            if !self.in_r[i] || !self.is_movable(n.end_effector) {
                continue;
            }
            for &x in self
                .reaches
                .get(n.end_effector as usize)
                .into_iter()
                .flatten()
            {
                let other = Node { workspace: x, ..*n };
                let Some(&j) = self.index.get(&other) else {
                    continue;
                };
                if x != n.workspace && self.in_g[j as usize] {
                    self.move_gap(gaps, i as u32, j);
                }
            }
        }
    }

    fn reach(&self, e: u32) -> &[u32] {
        self.reaches.get(e as usize).map_or(&[], |r| r.as_slice())
    }

    fn is_movable(&self, e: u32) -> bool {
        self.movable.get(e as usize).copied().unwrap_or(false)
    }

    /// A gap between `near` grasps of one end-effector and `far` grasps of another in `w`.
    fn transition_gap(
        &self,
        gaps: &mut Gaps,
        w: u32,
        near: (u32, BTreeSet<u32>),
        far: (u32, BTreeSet<u32>),
    ) {
        let (a, b) = (near.0, far.0);
        let mut lost = BTreeSet::new();
        for (li, l) in self.lost.iter().enumerate() {
            let (x, y) = (self.node(l.from), self.node(l.to));
            if l.kind == ArcKind::Transition
                && x.workspace == w
                && y.workspace == w
                && x.end_effector == a
                && y.end_effector == b
                && near.1.contains(&x.grasp)
                && far.1.contains(&y.grasp)
            {
                lost.insert(li);
            }
        }
        let mut reverse = BTreeSet::new();
        for &g in &far.1 {
            for &h in &near.1 {
                if self.declared.contains_key(&(g, h)) && !self.declared.contains_key(&(h, g)) {
                    reverse.insert((g, h));
                }
            }
        }
        let kind = if lost.is_empty() {
            CutKind::NoTransition
        } else {
            CutKind::InfeasibleTransition
        };
        let gap = gaps.entry((kind, a, b, w)).or_insert_with(|| Gap {
            kind,
            workspaces: BTreeSet::from([w]),
            near: vec![(a, BTreeSet::new())],
            far: vec![(b, BTreeSet::new())],
            lost: BTreeSet::new(),
            reverse: BTreeSet::new(),
        });
        gap.near[0].1.extend(near.1);
        gap.far[0].1.extend(far.1);
        gap.lost.extend(lost);
        gap.reverse.extend(reverse);
    }

    /// A gap between two states of one hand with one grasp in two workspaces.
    fn move_gap(&self, gaps: &mut Gaps, i: u32, j: u32) {
        let (x, y) = (self.node(i), self.node(j));
        let lost: BTreeSet<usize> = self.lost_from[i as usize]
            .iter()
            .copied()
            .filter(|&l| self.lost[l].to == j)
            .collect();
        let kind = if !lost.is_empty() {
            CutKind::InfeasibleMove
        } else if !self.adjacent(&self.reaches, &BTreeSet::new(), x.workspace, y.workspace) {
            CutKind::NotAdjacent
        } else {
            return;
        };
        let gap = gaps
            .entry((kind, x.end_effector, x.workspace, y.workspace))
            .or_insert_with(|| Gap {
                kind,
                workspaces: BTreeSet::from([x.workspace, y.workspace]),
                near: vec![(x.end_effector, BTreeSet::new())],
                far: vec![(y.end_effector, BTreeSet::new())],
                lost: BTreeSet::new(),
                reverse: BTreeSet::new(),
            });
        gap.near[0].1.insert(x.grasp);
        gap.far[0].1.insert(y.grasp);
        gap.lost.extend(lost);
    }

    /// Gaps on the best suggestion's path that do not join R to G directly: the object
    /// must pass through a hand that belongs to neither side.
    fn route_gaps(&self, c: &Candidate, gaps: &mut Gaps) {
        let n = self.nodes.len();
        for a in &c.route.arcs {
            let (u, v) = (a.from as usize, a.to as usize);
            if u >= n || v >= n || (self.in_r[u] && self.in_g[v]) {
                continue;
            }
            let (x, y) = (self.node(a.from), self.node(a.to));
            if x.end_effector == y.end_effector && x.grasp == y.grasp {
                if x.workspace != y.workspace {
                    self.move_gap(gaps, a.from, a.to);
                }
                continue;
            }
            let w = x.workspace;
            // The near side: R if the arc leaves it (R is closed, so no arc joins any of
            // its grasps there to the other hand), otherwise what is not in G (G is closed
            // the other way).
            let side = |e: u32, pick: &dyn Fn(usize) -> bool| -> BTreeSet<u32> {
                self.at_ws
                    .get(w as usize)
                    .into_iter()
                    .flatten()
                    .filter(|&&i| self.node(i).end_effector == e && pick(i as usize))
                    .map(|&i| self.node(i).grasp)
                    .collect()
            };
            let near = if self.in_r[u] {
                side(x.end_effector, &|i| self.in_r[i])
            } else if self.in_g[v] {
                side(x.end_effector, &|i| !self.in_g[i])
            } else {
                BTreeSet::from([x.grasp])
            };
            let far = if self.in_g[v] {
                side(y.end_effector, &|i| self.in_g[i])
            } else if self.in_r[u] {
                side(y.end_effector, &|i| !self.in_r[i])
            } else {
                BTreeSet::from([y.grasp])
            };
            self.transition_gap(gaps, w, (x.end_effector, near), (y.end_effector, far));
        }
    }

    /// Merges gaps that say the same thing in several workspaces, then transition gaps to
    /// one goal-side hand from several start-side hands; orders and words them.
    fn merge(&self, gaps: Vec<Gap>) -> Vec<CutItem> {
        let mut by_pair: Vec<Gap> = Vec::new();
        for g in gaps {
            let same = by_pair.iter_mut().find(|m| {
                m.kind == g.kind
                    && m.near == g.near
                    && m.far == g.far
                    && matches!(
                        g.kind,
                        CutKind::NoTransition | CutKind::InfeasibleTransition
                    )
            });
            match same {
                Some(m) => {
                    m.workspaces.extend(g.workspaces);
                    m.lost.extend(g.lost);
                    m.reverse.extend(g.reverse);
                }
                None => by_pair.push(g),
            }
        }
        let mut merged: Vec<Gap> = Vec::new();
        for g in by_pair {
            let same = merged.iter_mut().find(|m| {
                m.kind == CutKind::NoTransition
                    && g.kind == CutKind::NoTransition
                    && m.far == g.far
                    && m.workspaces == g.workspaces
            });
            match same {
                Some(m) => {
                    m.near.extend(g.near);
                    m.reverse.extend(g.reverse);
                }
                None => merged.push(g),
            }
        }
        for g in &mut merged {
            g.near.sort();
            g.near.dedup();
        }
        merged.sort_by(|a, b| {
            (a.kind, &a.near, &a.far, &a.workspaces).cmp(&(b.kind, &b.near, &b.far, &b.workspaces))
        });
        merged.iter().map(|g| self.item(g)).collect()
    }

    fn item(&self, g: &Gap) -> CutItem {
        let wss = list(g.workspaces.iter().map(|&w| self.ws(w)).collect(), "or");
        let near_ee: Vec<u32> = g.near.iter().map(|(e, _)| *e).collect();
        let far_ee: Vec<u32> = g.far.iter().map(|(e, _)| *e).collect();
        let mut spans: Vec<u32> = near_ee
            .iter()
            .chain(&far_ee)
            .filter_map(|&e| self.ee_span(e))
            .collect();
        let text = match g.kind {
            CutKind::NoTransition => {
                let mut text = format!(
                    "no transition joins {} with {} in {wss}",
                    self.holders_phrase(&g.near),
                    self.holders_phrase(&g.far)
                );
                if !g.reverse.is_empty() {
                    let lines: Vec<String> = g
                        .reverse
                        .iter()
                        .map(|&(a, b)| {
                            q(&format!("{} -> {}", self.grasp_name(a), self.grasp_name(b)))
                        })
                        .collect();
                    text.push_str(&format!(
                        " (declared only the other way: {})",
                        list(lines, "and")
                    ));
                    for r in &g.reverse {
                        spans.extend(self.declared.get(r).into_iter().flatten().copied());
                    }
                }
                text
            }
            CutKind::InfeasibleTransition => {
                let mut arcs = Vec::new();
                let mut reasons: Vec<String> = Vec::new();
                let mut failed = false;
                for &i in &g.lost {
                    let l = &self.lost[i];
                    let (x, y) = (self.node(l.from), self.node(l.to));
                    let line = q(&format!(
                        "{} -> {}",
                        self.grasp_name(x.grasp),
                        self.grasp_name(y.grasp)
                    ));
                    if !arcs.contains(&line) {
                        arcs.push(line);
                    }
                    let r = self.reason_text(&l.reason);
                    if !reasons.contains(&r) {
                        reasons.push(r);
                    }
                    failed |= l.failed;
                    spans.extend(l.source);
                }
                let found = if failed {
                    "were infeasible (pruned, or failed during this request)"
                } else {
                    "were all pruned as infeasible"
                };
                let shown: Vec<String> = reasons.iter().take(2).cloned().collect();
                let mut why = shown.join("; ");
                if reasons.len() > 2 {
                    why.push_str(&format!("; and {} other reasons", reasons.len() - 2));
                }
                format!(
                    "the transitions declared from {} to {} in {wss} {found}: {} ({why})",
                    list(near_ee.iter().map(|&e| self.ee(e)).collect(), "and"),
                    list(far_ee.iter().map(|&e| self.ee(e)).collect(), "and"),
                    list(arcs, "and"),
                )
            }
            CutKind::InfeasibleMove => {
                let mut reasons: Vec<String> = Vec::new();
                for &i in &g.lost {
                    let r = self.reason_text(&self.lost[i].reason);
                    if !reasons.contains(&r) {
                        reasons.push(r);
                    }
                    spans.extend(self.lost[i].source);
                }
                let ws: Vec<u32> = g.workspaces.iter().copied().collect();
                let (from, to) = self.move_ends(g, &ws);
                format!(
                    "{} cannot carry it with {} from {} to {}: {}",
                    self.ee(near_ee.first().copied().unwrap_or(0)),
                    list(
                        g.near
                            .iter()
                            .flat_map(|(_, s)| s)
                            .map(|&x| self.grasp(x))
                            .collect(),
                        "or"
                    ),
                    self.ws(from),
                    self.ws(to),
                    reasons.join("; ")
                )
            }
            CutKind::NotAdjacent => {
                let ws: Vec<u32> = g.workspaces.iter().copied().collect();
                let (from, to) = self.move_ends(g, &ws);
                for w in [from, to] {
                    spans.extend(self.art.workspaces.get(w as usize).map(|x| x.span));
                }
                format!(
                    "{} and {} are not adjacent, so {} cannot carry it from one to the other",
                    self.ws(from),
                    self.ws(to),
                    self.ee(near_ee.first().copied().unwrap_or(0))
                )
            }
            CutKind::NoCommonWorkspace | CutKind::NoHand | CutKind::OnlyFixed | CutKind::Apart => {
                String::new()
            }
        };
        spans.sort_unstable();
        spans.dedup();
        CutItem {
            kind: g.kind,
            near: near_ee,
            far: far_ee,
            workspaces: g.workspaces.iter().copied().collect(),
            text,
            spans,
        }
    }

    /// The two workspaces of a move gap, from the start's side to the goal's.
    fn move_ends(&self, g: &Gap, ws: &[u32]) -> (u32, u32) {
        let e = g.near.first().map_or(0, |(e, _)| *e);
        let grasp = g.near.first().and_then(|(_, s)| s.iter().next().copied());
        let in_r = |w: u32| {
            grasp.is_some_and(|grasp| {
                self.index
                    .get(&Node {
                        end_effector: e,
                        grasp,
                        workspace: w,
                    })
                    .is_some_and(|&i| self.in_r[i as usize])
            })
        };
        match ws {
            [a, b] if in_r(*b) && !in_r(*a) => (*b, *a),
            [a, b] => (*a, *b),
            [a] => (*a, *a),
            _ => (0, 0),
        }
    }

    /// When no two end-effectors of the sides share a workspace where they hold it: a
    /// side that no hand can reach, else pairs of end-effectors that reach no common
    /// workspace (pairs of hands first), else sides held by fixed end-effectors only.
    fn fallback_items(&self) -> Vec<CutItem> {
        let side = |pick: &dyn Fn(usize) -> bool| -> (BTreeSet<u32>, BTreeSet<u32>) {
            let picked = (0..self.nodes.len()).filter(|&i| pick(i));
            let holders = picked.clone().map(|i| self.nodes[i].end_effector).collect();
            let wss = picked.map(|i| self.nodes[i].workspace).collect();
            (holders, wss)
        };
        let (near, near_ws) = side(&|i| self.in_r[i]);
        let (far, far_ws) = side(&|i| self.in_g[i]);
        let mut items = Vec::new();
        if near_ws == far_ws {
            items.extend(self.no_hand(&near, &far, &near_ws));
        } else {
            items.extend(self.no_hand(&near, &BTreeSet::new(), &near_ws));
            items.extend(self.no_hand(&BTreeSet::new(), &far, &far_ws));
        }
        if !items.is_empty() {
            return items;
        }
        let mut pairs: Vec<(u32, u32, u8)> = Vec::new();
        for &a in &near {
            for &b in &far {
                let (ma, mb) = (self.is_movable(a), self.is_movable(b));
                if a == b || !(ma || mb) {
                    continue;
                }
                let (ra, rb) = (self.reach(a), self.reach(b));
                if ra.iter().any(|w| rb.contains(w)) {
                    continue;
                }
                pairs.push((a, b, u8::from(ma) + u8::from(mb)));
            }
        }
        let most = pairs.iter().map(|p| p.2).max().unwrap_or(0);
        let reach = |e: u32| list(self.reach(e).iter().map(|&w| self.ws(w)).collect(), "and");
        items.extend(pairs.iter().filter(|p| p.2 == most).map(|&(a, b, _)| {
            CutItem {
                kind: CutKind::NoCommonWorkspace,
                near: vec![a],
                far: vec![b],
                workspaces: Vec::new(),
                text: format!(
                    "{} and {} reach no common workspace ({} reaches {}; {} reaches {})",
                    self.ee(a),
                    self.ee(b),
                    self.ee(a),
                    reach(a),
                    self.ee(b),
                    reach(b)
                ),
                spans: [self.ee_span(a), self.ee_span(b)]
                    .into_iter()
                    .flatten()
                    .collect(),
            }
        }));
        if items.is_empty() && near.iter().chain(&far).all(|&e| !self.is_movable(e)) {
            let all: Vec<u32> = near.union(&far).copied().collect();
            items.push(CutItem {
                kind: CutKind::OnlyFixed,
                near: near.iter().copied().collect(),
                far: far.iter().copied().collect(),
                workspaces: near_ws.union(&far_ws).copied().collect(),
                text: format!(
                    "only fixed end-effectors hold it on either side ({}), and they neither \
                     move an object nor pass it to each other: a movable end-effector must \
                     take it in {} and bring it to {}",
                    list(all.iter().map(|&e| self.ee(e)).collect(), "and"),
                    list(near_ws.iter().map(|&w| self.ws(w)).collect(), "or"),
                    list(far_ws.iter().map(|&w| self.ws(w)).collect(), "or"),
                ),
                spans: all.iter().filter_map(|&e| self.ee_span(e)).collect(),
            });
        }
        if items.is_empty() {
            items.push(self.apart(&near, &near_ws, &far, &far_ws));
        }
        items
    }

    /// The last resort: where each side is, and why nothing joins them there.
    fn apart(
        &self,
        near: &BTreeSet<u32>,
        near_ws: &BTreeSet<u32>,
        far: &BTreeSet<u32>,
        far_ws: &BTreeSet<u32>,
    ) -> CutItem {
        let names = |set: &BTreeSet<u32>| list(set.iter().map(|&e| self.ee(e)).collect(), "and");
        let places = |set: &BTreeSet<u32>| list(set.iter().map(|&w| self.ws(w)).collect(), "and");
        let common: BTreeSet<u32> = near_ws.intersection(far_ws).copied().collect();
        let text = if common.is_empty() {
            format!(
                "what the start reaches ({} in {}) and what leads to the goal ({} in {}) lie \
                 in different workspaces, and no hand carries it from one to the other",
                names(near),
                places(near_ws),
                names(far),
                places(far_ws)
            )
        } else {
            let both: BTreeSet<u32> = (0..self.nodes.len())
                .filter(|&i| {
                    (self.in_r[i] || self.in_g[i]) && common.contains(&self.nodes[i].workspace)
                })
                .map(|i| self.nodes[i].end_effector)
                .collect();
            format!(
                "where both sides hold it ({}), only {} do, and an end-effector never passes \
                 an object to itself, nor a fixed one to another",
                places(&common),
                names(&both)
            )
        };
        let all: Vec<u32> = near.union(far).copied().collect();
        CutItem {
            kind: CutKind::Apart,
            near: near.iter().copied().collect(),
            far: far.iter().copied().collect(),
            workspaces: near_ws.union(far_ws).copied().collect(),
            text,
            spans: all.iter().filter_map(|&e| self.ee_span(e)).collect(),
        }
    }

    /// "no movable end-effector that can hold `cylinder` reaches `w0`, so nothing can take
    /// it from `table` there": sides held by fixed end-effectors only (`near` on the
    /// start's, `far` on the goal's; one may be empty), in workspaces out of every hand's
    /// reach.
    fn no_hand(
        &self,
        near: &BTreeSet<u32>,
        far: &BTreeSet<u32>,
        wss: &BTreeSet<u32>,
    ) -> Option<CutItem> {
        let holders: Vec<u32> = near.union(far).copied().collect();
        if holders.is_empty() || holders.iter().any(|&e| self.is_movable(e)) {
            return None;
        }
        let hand_reaches = |w: u32| {
            self.reaches
                .iter()
                .enumerate()
                .any(|(e, r)| self.movable[e] && !self.ee_grasps[e].is_empty() && r.contains(&w))
        };
        if wss.iter().any(|&w| hand_reaches(w)) {
            return None;
        }
        let names = |set: &BTreeSet<u32>| list(set.iter().map(|&e| self.ee(e)).collect(), "or");
        let what = match (near.is_empty(), far.is_empty()) {
            (false, true) => format!("take it from {}", names(near)),
            (true, false) => format!("bring it to {}", names(far)),
            _ => format!(
                "take it from {} nor bring it to {}",
                names(near),
                names(far)
            ),
        };
        Some(CutItem {
            kind: CutKind::NoHand,
            near: near.iter().copied().collect(),
            far: far.iter().copied().collect(),
            workspaces: wss.iter().copied().collect(),
            text: format!(
                "no movable end-effector that can hold {} reaches {}, so nothing can {what} \
                 there",
                q(&self.obj.name),
                list(wss.iter().map(|&w| self.ws(w)).collect(), "or"),
            ),
            spans: holders
                .iter()
                .filter_map(|&e| self.ee_span(e))
                .chain(
                    wss.iter()
                        .filter_map(|&w| self.art.workspaces.get(w as usize).map(|x| x.span)),
                )
                .collect(),
        })
    }

    // ---- pruned notes ------------------------------------------------------------------

    /// Pruned and failed arcs on some start-to-goal path once they are all restored, those
    /// leaving R into G first, then those leaving R, then those entering G.
    fn pruned_notes(&self) -> (Vec<PrunedNote>, usize) {
        let n = self.nodes.len();
        let mut fwd_all = self.fwd.clone();
        let mut bwd_all = self.bwd.clone();
        for l in &self.lost {
            fwd_all[l.from as usize].push((l.to, l.weight));
            bwd_all[l.to as usize].push((l.from, l.weight));
        }
        let r_all = dijkstra(&fwd_all, &[self.start]);
        let g_all = dijkstra(&bwd_all, &self.goals);
        let mut picked: Vec<(u8, usize)> = self
            .lost
            .iter()
            .enumerate()
            .filter(|(_, l)| {
                let (f, t) = (l.from as usize, l.to as usize);
                f < n && t < n && r_all[f].is_finite() && g_all[t].is_finite()
            })
            .map(|(i, l)| {
                let (f, t) = (l.from as usize, l.to as usize);
                let rank = match (self.in_r[f], self.in_g[t]) {
                    (true, true) => 0,
                    (true, false) => 1,
                    (false, true) => 2,
                    (false, false) => 3,
                };
                (rank, i)
            })
            .collect();
        picked.sort_unstable();
        let omitted = picked.len().saturating_sub(MAX_PRUNED);
        let notes = picked
            .into_iter()
            .take(MAX_PRUNED)
            .map(|(_, i)| {
                let l = &self.lost[i];
                let (x, y) = (self.node(l.from), self.node(l.to));
                let when = if l.failed {
                    "failed during this request"
                } else {
                    "was pruned at build time"
                };
                let mut text = self.arc_text(x, y, l.kind);
                text.push_str(&format!(" {when}: {}", self.reason_text(&l.reason)));
                PrunedNote {
                    arc: ArcRef {
                        from: l.from,
                        to: l.to,
                    },
                    kind: l.kind,
                    failed: l.failed,
                    reason: l.reason.clone(),
                    text,
                    span: l.source,
                }
            })
            .collect();
        (notes, omitted)
    }

    // ---- labels ------------------------------------------------------------------------

    /// Source places to label, one label per span, most important first.
    fn labels(
        &self,
        out: &Explanation,
        suggestion_labels: &[Vec<(u32, String)>],
    ) -> Vec<(u32, String)> {
        let mut labels: Vec<(u32, String)> = Vec::new();
        let n_spans = self.art.spans.len();
        let mut add = |span: Option<u32>, text: String| {
            if let Some(s) = span {
                if (s as usize) < n_spans && !labels.iter().any(|l| l.0 == s) {
                    labels.push((s, text));
                }
            }
        };
        let start = self.node(self.start);
        let start_span = self.grasp_span(start.grasp);
        let goal_span = self
            .goals
            .first()
            .and_then(|&g| self.grasp_span(self.node(g).grasp));
        let (start_text, goal_text) = (self.state_text(start), self.goals_text());
        if start_span == goal_span {
            add(
                start_span,
                format!("the start: {start_text}; the goal: {goal_text}"),
            );
        } else {
            add(start_span, format!("the start: {start_text}"));
            add(goal_span, format!("the goal: {goal_text}"));
        }
        let ee_spans: BTreeSet<u32> = self.art.end_effectors.iter().map(|e| e.span).collect();
        for item in &out.cut {
            for &s in item.spans.iter().filter(|s| ee_spans.contains(s)) {
                add(Some(s), self.span_label(s, item, out));
            }
        }
        for (i, spans) in suggestion_labels.iter().enumerate() {
            for (span, text) in spans {
                add(Some(*span), format!("suggestion {}: {text}", i + 1));
            }
        }
        for item in &out.cut {
            for &s in item.spans.iter().filter(|s| !ee_spans.contains(s)).take(3) {
                add(Some(s), self.span_label(s, item, out));
            }
        }
        for p in &out.pruned {
            add(
                p.span,
                format!("infeasible: {}", self.reason_text(&p.reason)),
            );
        }
        add(Some(self.obj.span), format!("object {}", q(&self.obj.name)));
        labels.truncate(MAX_SPANS);
        labels
    }

    /// A label for a span a cut item points at.
    fn span_label(&self, span: u32, item: &CutItem, out: &Explanation) -> String {
        let side_of = |e: u32| {
            let start = out.start_side.holdings.iter().any(|h| h.end_effector == e);
            let goal = out.goal_side.holdings.iter().any(|h| h.end_effector == e);
            match (start, goal) {
                (true, true) => "on both sides",
                (true, false) => "on the start's side",
                (false, true) => "on the goal's side",
                (false, false) => "on neither side",
            }
        };
        for &e in item.near.iter().chain(&item.far) {
            if self.ee_span(e) == Some(span) {
                let reach = list(self.reach(e).iter().map(|&w| self.ws(w)).collect(), "and");
                return format!("{} ({}) reaches {reach}", self.ee(e), side_of(e));
            }
        }
        if self.obj.transitions.iter().any(|t| t.span == span) {
            return match item.kind {
                CutKind::NoTransition => "declared only one way".to_string(),
                _ => format!("declared, but infeasible in {}", {
                    list(item.workspaces.iter().map(|&w| self.ws(w)).collect(), "and")
                }),
            };
        }
        if self.art.workspaces.iter().any(|w| w.span == span) {
            return match item.kind {
                CutKind::NoHand => "no hand that can hold it reaches this workspace".to_string(),
                _ => "not adjacent".to_string(),
            };
        }
        short(&item.text)
    }
}

/// Shortest distances from `sources` over `adj`; infinity where unreachable.
fn dijkstra(adj: &[Vec<(u32, f64)>], sources: &[u32]) -> Vec<f64> {
    let mut dist = vec![f64::INFINITY; adj.len()];
    let mut heap = BinaryHeap::new();
    for &s in sources {
        if let Some(d) = dist.get_mut(s as usize) {
            *d = 0.0;
            heap.push(Reverse((Cost(0.0), s)));
        }
    }
    while let Some(Reverse((Cost(d), u))) = heap.pop() {
        if d > dist[u as usize] {
            continue;
        }
        for &(v, w) in &adj[u as usize] {
            let nd = d + w;
            if let Some(slot) = dist.get_mut(v as usize) {
                if nd < *slot {
                    *slot = nd;
                    heap.push(Reverse((Cost(nd), v)));
                }
            }
        }
    }
    dist
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

fn ordered(a: u32, b: u32) -> (u32, u32) {
    (a.min(b), a.max(b))
}

fn q(name: &str) -> String {
    format!("`{name}`")
}

/// "0.21 m", or millimetres below a centimetre.
fn metres(x: f64) -> String {
    if x.abs() < 0.01 {
        format!("{:.1} mm", x * 1000.0)
    } else {
        format!("{x:.2} m")
    }
}

/// "1 state", "10 states".
fn count(n: usize, noun: &str) -> String {
    if n == 1 {
        format!("1 {noun}")
    } else {
        format!("{n} {noun}s")
    }
}

/// "`a`", "`a` or `b`", "`a`, `b` or `c`", "`a`, `b`, `c`, `d` or 3 more".
fn list(items: Vec<String>, conj: &str) -> String {
    let n = items.len();
    if n > MAX_LISTED + 1 {
        return format!(
            "{} {conj} {} more",
            items[..MAX_LISTED].join(", "),
            n - MAX_LISTED
        );
    }
    match n {
        0 => String::new(),
        1 => items[0].clone(),
        _ => format!("{} {conj} {}", items[..n - 1].join(", "), items[n - 1]),
    }
}

/// The first clause of a text, for a label.
fn short(text: &str) -> String {
    let cut = [", so ", ", where ", ":", " ("]
        .iter()
        .filter_map(|m| text.find(m))
        .min()
        .unwrap_or(text.len());
    text[..cut].to_string()
}
