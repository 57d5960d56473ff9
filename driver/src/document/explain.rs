//! The explanation document: why a move has no plan, by names and in the words of
//! `cellc plan`'s R0004 (`POST /v1/explain`).

use cellc_runtime::explain::{Cause as RuntimeCause, CutKind, Explanation as RuntimeExplanation};
use cellc_runtime::NodeId;
use cellc_schema::Artifact;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::plan::{Plan, State};
use super::report::Report;
use crate::advice::FrontEnd;
use crate::explain_report::words::Words;

/// The answer of `POST /v1/explain`: the plan when the move has one, otherwise why not.
#[derive(Serialize, Deserialize, JsonSchema, Clone, Debug, PartialEq)]
#[serde(untagged)]
pub enum Explained {
    /// The move has a plan.
    Reachable {
        /// Always `true`.
        #[schemars(schema_with = "always_true")]
        reachable: bool,
        /// The plan.
        plan: Plan,
    },
    /// It has none.
    Unreachable {
        /// Always `false`.
        #[schemars(schema_with = "always_false")]
        reachable: bool,
        /// Why, in structure (`null` when the runtime could not explain it).
        explanation: Option<Explanation>,
        /// The R0004 diagnostic, as a report.
        diagnostic: Report,
    },
}

fn always_true(_: &mut schemars::SchemaGenerator) -> schemars::Schema {
    schemars::json_schema!({"const": true})
}

fn always_false(_: &mut schemars::SchemaGenerator) -> schemars::Schema {
    schemars::json_schema!({"const": false})
}

/// Why a move has no plan.
#[derive(Serialize, Deserialize, JsonSchema, Clone, Debug, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Explanation {
    /// The object.
    pub object: String,
    /// What kind of problem separates the start from the goal.
    pub cause: Cause,
    /// Where the object starts.
    pub start: Option<State>,
    /// The goal's states.
    pub goals: Vec<Option<State>>,
    /// The states the start reaches.
    pub start_side: Vec<Option<State>>,
    /// The states that reach a goal.
    pub goal_side: Vec<Option<State>>,
    /// Whether the start is also a goal the object must leave and come back to.
    pub must_leave: bool,
    /// What separates the two sides.
    pub cut: Vec<CutEntry>,
    /// Entries of the cut left out.
    pub cut_omitted: usize,
    /// Changes of the cell that would connect them, cheapest first.
    pub suggestions: Vec<Suggestion>,
    /// Arcs verification or planning removed between the sides.
    pub pruned: Vec<Pruned>,
    /// Pruned arcs left out.
    pub pruned_omitted: usize,
}

/// What kind of problem separates the start from the goal.
#[derive(Serialize, Deserialize, JsonSchema, Clone, Copy, Debug, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum Cause {
    /// The cell lacks an arc (a transition, an adjacency, a hand).
    Missing,
    /// Verification pruned the arcs that would connect them.
    Pruned,
    /// Steps failed while planning.
    Failed,
    /// The graph connects them; the planner gave up.
    Connected,
}

/// The kind of one gap of the cut (the runtime's `CutKind`, by its Rust name).
#[derive(Serialize, Deserialize, JsonSchema, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Gap {
    /// Transitions are declared between the sides' grasps, but every one was pruned or
    /// failed.
    InfeasibleTransition,
    /// A hand would carry the object on, but that move was pruned or failed.
    InfeasibleMove,
    /// No transition is declared between the sides' grasps there.
    NoTransition,
    /// A hand holds the object on both sides in workspaces that are not adjacent.
    NotAdjacent,
    /// The end-effectors of the two sides reach no common workspace.
    NoCommonWorkspace,
    /// Only fixed end-effectors hold the object on one side, and no movable one reaches.
    NoHand,
    /// Only fixed end-effectors hold the object on both sides.
    OnlyFixed,
    /// None of the above: the sides are apart.
    Apart,
}

/// One gap of the cut.
#[derive(Serialize, Deserialize, JsonSchema, Clone, Debug, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct CutEntry {
    /// Its kind.
    pub kind: Gap,
    /// In words.
    pub text: String,
}

/// A change of the cell that would connect the sides.
#[derive(Serialize, Deserialize, JsonSchema, Clone, Debug, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Suggestion {
    /// In words.
    pub text: String,
    /// Its cost (smaller is a smaller change).
    pub cost: f64,
}

/// An arc removed between the sides.
#[derive(Serialize, Deserialize, JsonSchema, Clone, Debug, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Pruned {
    /// Its first state.
    pub from: Option<State>,
    /// Its last state.
    pub to: Option<State>,
    /// Whether it failed while planning (rather than in verification).
    pub failed: bool,
    /// Why, in words.
    pub text: String,
}

impl Explanation {
    /// The explanation `e`, by names, its advice naming `front_end`'s options; `None`
    /// when its object is not the artifact's.
    pub fn of(a: &Artifact, e: &RuntimeExplanation, front_end: FrontEnd) -> Option<Explanation> {
        let object = a.objects.get(e.object.index())?;
        let words = Words::new(a, object).for_front_end(front_end);
        let state = |n: NodeId| {
            object
                .graph
                .nodes
                .get(n.index())
                .map(|&s| State::of(a, e.object, s))
        };
        let states = |list: &[NodeId]| list.iter().map(|&n| state(n)).collect::<Vec<_>>();
        Some(Explanation {
            object: a.object_name(e.object).to_string(),
            cause: match e.cause {
                RuntimeCause::Missing => Cause::Missing,
                RuntimeCause::Pruned => Cause::Pruned,
                RuntimeCause::Failed => Cause::Failed,
                RuntimeCause::Connected => Cause::Connected,
            },
            start: state(e.start),
            goals: states(&e.goals),
            start_side: states(&e.start_side.states),
            goal_side: states(&e.goal_side.states),
            must_leave: e.must_leave,
            cut: e
                .cut
                .iter()
                .map(|c| CutEntry {
                    kind: gap(c.gap.kind()),
                    text: words.gap_text(&c.gap),
                })
                .collect(),
            cut_omitted: e.cut_omitted,
            suggestions: e
                .suggestions
                .iter()
                .map(|s| Suggestion {
                    text: words.suggestion_text(s),
                    cost: s.cost,
                })
                .collect(),
            pruned: e
                .pruned
                .iter()
                .map(|l| Pruned {
                    from: state(l.from),
                    to: state(l.to),
                    failed: l.failed,
                    text: words.lost_text(l),
                })
                .collect(),
            pruned_omitted: e.pruned_omitted,
        })
    }
}

fn gap(k: CutKind) -> Gap {
    match k {
        CutKind::InfeasibleTransition => Gap::InfeasibleTransition,
        CutKind::InfeasibleMove => Gap::InfeasibleMove,
        CutKind::NoTransition => Gap::NoTransition,
        CutKind::NotAdjacent => Gap::NotAdjacent,
        CutKind::NoCommonWorkspace => Gap::NoCommonWorkspace,
        CutKind::NoHand => Gap::NoHand,
        CutKind::OnlyFixed => Gap::OnlyFixed,
        CutKind::Apart => Gap::Apart,
    }
}
