//! Why a move request has no plan, as facts a cell engineer acts on.
//!
//! When no path joins the start state to a goal state the planner returns an
//! [`Unreachable`]. A list of node indices helps nobody: the engineer wants to know what the
//! object can reach, what the goal needs, which missing or infeasible declaration separates
//! the two, and what to change. [`explain`] computes that as a structured value
//! ([`Explanation`]): the two sides, the cut between them, the pruned and failed arcs with
//! their reasons, and the suggestions as edits of named cell items. It holds no sentences:
//! the CLI words it (and labels the cell's source through the span ids it carries), and a
//! service can send it as it is.
//!
//! The analysis, on the object's graph with the arcs that failed during the request
//! removed (`context.rs`):
//! - R, the states reachable from the start, and G, the states from which some goal state
//!   is reachable. The goal is unreachable exactly when they are disjoint; then no arc
//!   leaves R and no arc enters G, so every statement about "no transition joins ..." below
//!   is true by construction rather than by heuristics.
//! - The cut (`cut.rs`), grouped the way the cell is written: for each end-effector holding
//!   the object in R and each holding it in G, in each workspace where both hold it, either
//!   no transition is declared between their grasps, or the declared ones were pruned at
//!   build time or failed during the request (with the reasons). One hand on both sides
//!   with the same grasp is a move between workspaces that are not adjacent, or whose move
//!   was pruned. When the start side and the goal side are separated by a hand that
//!   belongs to neither, the cut also describes the gaps on the way through it, taken from
//!   the best suggestion. When nothing of that kind exists: no hand that can hold the
//!   object reaches a side held by fixed surfaces only; else the end-effectors of the two
//!   sides reach no common workspace; else only fixed surfaces hold it (they never
//!   exchange it); else where each side lies.
//! - Suggestions (`suggest.rs`): the fewest changes to the cell that connect the start to
//!   the goal, each an edit of something the cell's author wrote, so that it can be made
//!   as a text edit of the source (and never names a derived workspace, whose name
//!   changes with the reach it comes from). A single change is tried first: declaring a
//!   transition (both ways, as the cell normally writes it) between two grasps held by
//!   different end-effectors that share a workspace, never two fixed ones; declaring an
//!   adjacency between two declared workspaces (cells that declare theirs); declaring
//!   `allow contact` for two bodies whose collision is all that removed some arcs;
//!   extending a movable end-effector's reach to one more workspace (a declared workspace
//!   added to the `reaches` list of an end-effector without geometry, or an arm's reach
//!   box grown over the workspace's boxes, given as boxes in metres). Arcs infeasible for
//!   other reasons (no IK solution, no closed chain, no placement) are explained, not
//!   suggested away: which base to move and by how much is not known here. Only when no
//!   single change connects, sets of changes along a path that needs the fewest of them (a
//!   0-1 breadth-first search where existing arcs cost nothing and each hypothetical arc
//!   costs one), also after each of the nearest reach extensions. Every suggestion is
//!   checked (`overlay.rs`) by adding every arc it would create, as the shared graph rules
//!   ([`cellc_schema::rules`], the compiler's) say, and searching again; only those that
//!   really connect are kept. They are ranked by number of changes, then by whether they
//!   repeat something that already failed kinematically (a new transition between two
//!   hands in a workspace where every declared one between them was infeasible), then by
//!   kind (a transition is the cheapest edit, a reach extension the dearest), then by how
//!   far a reach must grow, then by the cost of the plan they give. Doubtful ones are
//!   dropped when others exist, and so are reach extensions (a robot moved or replaced)
//!   when a declaration connects; one suggestion per idea (per pair of hands and workspace
//!   of a new transition); at most three.
//! - A goal that is the start's own state at another pose (a pick-and-place within one
//!   state): the object must leave the start and come back, so R is what the start
//!   reaches and G what leads back, and a path must take at least one arc
//!   ([`Explanation::must_leave`]).
//! - When the graph does connect the start to a goal, the planner gave up for a reason
//!   the graph does not show: the arcs that failed during the request, with why
//!   ([`GaveUp`]).
//! - Pruned arcs (`lost.rs`): the pruned or failed arcs that lie on some start-to-goal
//!   path of the graph with every pruned and failed arc restored, those on the border of R
//!   or G first.

mod change;
mod context;
mod cut;
mod lost;
mod overlay;
mod suggest;

use cellc_schema::{
    ArcKind, Artifact, EndEffectorId, GraspId, Infeasibility, NodeId, ObjectId, SpanId, WorkspaceId,
};

use crate::plan::Unreachable;

pub use change::{BodyName, Change, Exchange, Suggestion};
use context::Ctx;

/// Suggestions at most: more would bury the good ones.
const MAX_SUGGESTIONS: usize = 3;
/// Cut items at most; the rest are counted in [`Explanation::cut_omitted`].
const MAX_CUT: usize = 6;
/// Pruned arcs listed at most; the rest are counted in [`Explanation::pruned_omitted`].
const MAX_PRUNED: usize = 8;

/// Why a request has no plan.
#[derive(Clone, Debug, PartialEq)]
pub struct Explanation {
    /// The object.
    pub object: ObjectId,
    /// What kind of problem it is.
    pub cause: Cause,
    /// The start state.
    pub start: NodeId,
    /// The goal states of the object's graph, sorted.
    pub goals: Vec<NodeId>,
    /// What the start can reach.
    pub start_side: Side,
    /// What leads to the goal.
    pub goal_side: Side,
    /// Why the two sides do not meet, most telling first.
    pub cut: Vec<CutItem>,
    /// Cut items left out of [`Explanation::cut`].
    pub cut_omitted: usize,
    /// What to change, best first; each one verified to connect the start to the goal.
    pub suggestions: Vec<Suggestion>,
    /// Arcs removed at build time or during the request that would have joined the sides.
    pub pruned: Vec<LostArc>,
    /// Arcs left out of [`Explanation::pruned`].
    pub pruned_omitted: usize,
    /// The goal is the start's own state at another pose: a plan must leave the start and
    /// come back, so the start is on both sides and every path takes at least one arc.
    pub must_leave: bool,
    /// When the graph connects the start to a goal ([`Cause::Connected`]): why the
    /// planner found no plan anyway.
    pub gave_up: Option<GaveUp>,
}

/// Why the planner found no plan although the graph connects the start to a goal.
#[derive(Clone, Debug, PartialEq)]
pub enum GaveUp {
    /// Steps failed during the request (each removed its arc and the search ran again),
    /// and the planner stopped at its limit of backtracks while other paths remained.
    Backtracks {
        /// The arcs that failed, in the order they failed, with why.
        failed: Vec<LostArc>,
        /// Failed arcs left out of `failed`.
        omitted: usize,
    },
    /// No step failed: the answer does not fit the artifact (a caller's inconsistent
    /// data; the planner never gives such an answer).
    NothingFailed,
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
    /// The graph does connect the start to a goal: the planner gave up for the reason in
    /// [`Explanation::gave_up`] (steps that failed, with why). Such an explanation has its
    /// sides, and no cut, suggestions or pruned arcs.
    Connected,
}

/// Why there is nothing to explain: the request does not fit the artifact.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NoStates {
    /// The artifact has no such object.
    Object(ObjectId),
    /// The start is not a state of the object's graph.
    Start,
    /// No goal is a state of the object's graph.
    Goals,
}

/// One side of the cut.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Side {
    /// States of the object's graph, sorted.
    pub states: Vec<NodeId>,
    /// The same states per end-effector, in end-effector order.
    pub holdings: Vec<Holding>,
}

/// What one end-effector holds on one side.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Holding {
    /// The end-effector.
    pub end_effector: EndEffectorId,
    /// Grasps, sorted.
    pub grasps: Vec<GraspId>,
    /// Workspaces, sorted.
    pub workspaces: Vec<WorkspaceId>,
}

/// What kind of gap a cut item describes (the order is the order of importance).
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
    /// The gap.
    pub gap: Gap,
    /// Source places that matter (declarations of the end-effectors, transitions,
    /// workspaces or arcs involved).
    pub spans: Vec<SpanId>,
}

/// An end-effector with the grasps it holds there.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct HeldWith {
    /// The end-effector.
    pub end_effector: EndEffectorId,
    /// Grasps, sorted.
    pub grasps: Vec<GraspId>,
}

/// A gap between the sides, with what it involves ("near": on the start's side; "far":
/// on the goal's side).
#[derive(Clone, Debug, PartialEq)]
pub enum Gap {
    /// No transition is declared between the grasps the two sides hold in these
    /// workspaces.
    NoTransition {
        /// End-effectors of the start's side with their grasps there.
        near: Vec<HeldWith>,
        /// End-effectors of the goal's side with their grasps there.
        far: Vec<HeldWith>,
        /// Where.
        workspaces: Vec<WorkspaceId>,
        /// Transitions declared only the other way, (goal-side grasp, start-side grasp).
        one_way: Vec<(GraspId, GraspId)>,
    },
    /// Every transition declared between the two sides there was pruned or failed.
    InfeasibleTransition {
        /// Givers.
        near: Vec<EndEffectorId>,
        /// Takers.
        far: Vec<EndEffectorId>,
        /// Where.
        workspaces: Vec<WorkspaceId>,
        /// The arcs, with their reasons.
        arcs: Vec<LostArc>,
    },
    /// The move that would carry the object on was pruned or failed.
    InfeasibleMove {
        /// The hand.
        hand: EndEffectorId,
        /// The grasps it holds the object with.
        grasps: Vec<GraspId>,
        /// From the start's side.
        from: WorkspaceId,
        /// To the goal's side.
        to: WorkspaceId,
        /// The arcs, with their reasons.
        arcs: Vec<LostArc>,
    },
    /// The hand holds the object on both sides, in two workspaces that are not adjacent.
    NotAdjacent {
        /// The hand.
        hand: EndEffectorId,
        /// On the start's side.
        from: WorkspaceId,
        /// On the goal's side.
        to: WorkspaceId,
    },
    /// Two end-effectors of the sides reach no common workspace.
    NoCommonWorkspace {
        /// On the start's side.
        near: EndEffectorId,
        /// On the goal's side.
        far: EndEffectorId,
    },
    /// Only fixed end-effectors hold a side, and no movable one that can hold the object
    /// reaches its workspaces (one of `near` and `far` may be empty: that side has hands).
    NoHand {
        /// Fixed holders on the start's side.
        near: Vec<EndEffectorId>,
        /// Fixed holders on the goal's side.
        far: Vec<EndEffectorId>,
        /// The workspaces no hand reaches.
        workspaces: Vec<WorkspaceId>,
    },
    /// Only fixed end-effectors hold the object on either side.
    OnlyFixed {
        /// Holders on the start's side.
        near: Vec<EndEffectorId>,
        /// Holders on the goal's side.
        far: Vec<EndEffectorId>,
        /// Where the start's side lies.
        near_workspaces: Vec<WorkspaceId>,
        /// Where the goal's side lies.
        far_workspaces: Vec<WorkspaceId>,
    },
    /// None of the above: where each side lies, and who holds it where both do.
    Apart {
        /// Holders on the start's side.
        near: Vec<EndEffectorId>,
        /// Holders on the goal's side.
        far: Vec<EndEffectorId>,
        /// Where the start's side lies.
        near_workspaces: Vec<WorkspaceId>,
        /// Where the goal's side lies.
        far_workspaces: Vec<WorkspaceId>,
        /// Where both lie (empty: nowhere).
        shared: Vec<WorkspaceId>,
        /// The end-effectors holding it there on either side.
        holders_there: Vec<EndEffectorId>,
    },
}

impl Gap {
    /// The kind of gap.
    pub fn kind(&self) -> CutKind {
        match self {
            Gap::NoTransition { .. } => CutKind::NoTransition,
            Gap::InfeasibleTransition { .. } => CutKind::InfeasibleTransition,
            Gap::InfeasibleMove { .. } => CutKind::InfeasibleMove,
            Gap::NotAdjacent { .. } => CutKind::NotAdjacent,
            Gap::NoCommonWorkspace { .. } => CutKind::NoCommonWorkspace,
            Gap::NoHand { .. } => CutKind::NoHand,
            Gap::OnlyFixed { .. } => CutKind::OnlyFixed,
            Gap::Apart { .. } => CutKind::Apart,
        }
    }

    /// The end-effectors on the start's side of the gap.
    pub fn near(&self) -> Vec<EndEffectorId> {
        match self {
            Gap::NoTransition { near, .. } => near.iter().map(|h| h.end_effector).collect(),
            Gap::InfeasibleMove { hand, .. } | Gap::NotAdjacent { hand, .. } => vec![*hand],
            Gap::NoCommonWorkspace { near, .. } => vec![*near],
            Gap::InfeasibleTransition { near, .. }
            | Gap::NoHand { near, .. }
            | Gap::OnlyFixed { near, .. }
            | Gap::Apart { near, .. } => near.clone(),
        }
    }

    /// The end-effectors on the goal's side of the gap.
    pub fn far(&self) -> Vec<EndEffectorId> {
        match self {
            Gap::NoTransition { far, .. } => far.iter().map(|h| h.end_effector).collect(),
            Gap::InfeasibleMove { hand, .. } | Gap::NotAdjacent { hand, .. } => vec![*hand],
            Gap::NoCommonWorkspace { far, .. } => vec![*far],
            Gap::InfeasibleTransition { far, .. }
            | Gap::NoHand { far, .. }
            | Gap::OnlyFixed { far, .. }
            | Gap::Apart { far, .. } => far.clone(),
        }
    }

    /// Every workspace the gap concerns, sorted.
    pub fn workspaces(&self) -> Vec<WorkspaceId> {
        let mut out = match self {
            Gap::NoTransition { workspaces, .. }
            | Gap::InfeasibleTransition { workspaces, .. }
            | Gap::NoHand { workspaces, .. } => workspaces.clone(),
            Gap::InfeasibleMove { from, to, .. } | Gap::NotAdjacent { from, to, .. } => {
                vec![*from, *to]
            }
            Gap::NoCommonWorkspace { .. } => Vec::new(),
            Gap::OnlyFixed {
                near_workspaces,
                far_workspaces,
                ..
            }
            | Gap::Apart {
                near_workspaces,
                far_workspaces,
                ..
            } => near_workspaces
                .iter()
                .chain(far_workspaces)
                .copied()
                .collect(),
        };
        out.sort_unstable();
        out.dedup();
        out
    }
}

/// An arc removed at build time (pruned) or during the request (failed).
#[derive(Clone, Debug, PartialEq)]
pub struct LostArc {
    /// Tail state.
    pub from: NodeId,
    /// Head state.
    pub to: NodeId,
    /// Move or transition.
    pub kind: ArcKind,
    /// Failed during this request rather than pruned at build time.
    pub failed: bool,
    /// Why.
    pub reason: Infeasibility,
    /// The declaration that made the arc.
    pub source: Option<SpanId>,
}

/// Explains why `unreachable.goals` cannot be reached from `unreachable.start`.
///
/// R is recomputed from the graph minus `unreachable.failed` rather than taken from
/// `unreachable.reachable`, so that the cut and the verification of suggestions reason
/// about one and the same graph.
pub fn explain(artifact: &Artifact, unreachable: &Unreachable) -> Result<Explanation, NoStates> {
    let object = unreachable.object;
    let obj = artifact
        .objects
        .get(object.index())
        .ok_or(NoStates::Object(object))?;
    let ctx = Ctx::new(artifact, unreachable.object, obj, unreachable)?;
    Ok(ctx.explain())
}

impl Ctx<'_> {
    fn explain(&self) -> Explanation {
        let n = self.nodes.len() as u32;
        let mut out = Explanation {
            object: self.object,
            cause: Cause::Connected,
            start: NodeId(self.start),
            goals: self.goals.iter().map(|&g| NodeId(g)).collect(),
            start_side: self.side((0..n).filter(|&i| self.in_r[i as usize])),
            goal_side: self.side((0..n).filter(|&i| self.in_g[i as usize])),
            cut: Vec::new(),
            cut_omitted: 0,
            suggestions: Vec::new(),
            pruned: Vec::new(),
            pruned_omitted: 0,
            must_leave: self.must_leave,
            gave_up: None,
        };
        if self.connected() {
            out.gave_up = Some(self.gave_up());
            return out;
        }
        out.cause = self.cause();
        let candidates = self.suggest();
        (out.cut, out.cut_omitted) = self.cut(candidates.first());
        out.suggestions = candidates.iter().map(|c| self.suggestion(c)).collect();
        (out.pruned, out.pruned_omitted) = self.pruned_arcs();
        out
    }

    fn side(&self, states: impl Iterator<Item = u32>) -> Side {
        use std::collections::{BTreeMap, BTreeSet};
        let states: Vec<u32> = states.collect();
        let mut per: BTreeMap<EndEffectorId, (BTreeSet<GraspId>, BTreeSet<WorkspaceId>)> =
            BTreeMap::new();
        for &i in &states {
            let n = self.node(i);
            let entry = per.entry(n.end_effector).or_default();
            entry.0.insert(n.grasp);
            entry.1.insert(n.workspace);
        }
        Side {
            states: states.into_iter().map(NodeId).collect(),
            holdings: per
                .into_iter()
                .map(|(e, (g, w))| Holding {
                    end_effector: e,
                    grasps: g.into_iter().collect(),
                    workspaces: w.into_iter().collect(),
                })
                .collect(),
        }
    }

    /// A lost arc as the public value.
    fn lost_arc(&self, i: usize) -> LostArc {
        let l = &self.lost[i];
        LostArc {
            from: NodeId(l.from),
            to: NodeId(l.to),
            kind: l.kind,
            failed: l.failed,
            reason: l.reason.clone(),
            source: l.source.map(SpanId),
        }
    }
}
