//! Unreachable goals as diagnostics: what the start can reach, what the goal needs, the
//! cut between them and what to change, labelled at the cell's source lines. The analysis
//! is the runtime's (`cellc_runtime::explain`, a structured value with no sentences); this
//! module is where it becomes words: `words.rs` names and phrases (among them the one
//! wording of why an arc is infeasible, which the W0006 warnings of
//! [`crate::verify_report`] use too), `cut.rs` the gaps,
//! `suggestions.rs` the changes (and, given the sources, the edits that make them, from
//! [`crate::fixes`]), and here the message, the labels and the notes.

mod cut;
pub(crate) mod suggestions;
pub mod words;

use crate::advice::FrontEnd;
use std::collections::BTreeSet;

use cellc_lang::{Diagnostic, FileId, SourceMap, Span};
use cellc_runtime::explain::{Cause, CutItem, CutKind, Explanation, GaveUp, NoStates};
use cellc_runtime::plan::Unreachable;
use cellc_schema::{Artifact, Body, EndEffectorId, GraspId, Object, ObjectId, SpanId};

use crate::runtime_codes as codes;
use words::{count, q, short, Words};

/// Source labels at most: a diagnostic with more labels than lines is unreadable.
const MAX_SPANS: usize = 12;

fn place(artifact: &Artifact, span: u32) -> Option<(FileId, Span)> {
    let s = artifact.spans.get(span as usize)?;
    Some((
        FileId(s.file),
        Span {
            start: s.start,
            end: s.end,
        },
    ))
}

/// The diagnostic of an unreachable goal; with the cell's sources, each suggestion's edits
/// as fix notes.
pub fn unreachable(
    artifact: &Artifact,
    u: &Unreachable,
    sources: Option<&SourceMap>,
) -> Diagnostic {
    unreachable_for(FrontEnd::CommandLine, artifact, u, sources)
}

/// [`unreachable`], its advice naming `front_end`'s options.
pub fn unreachable_for(
    front_end: FrontEnd,
    artifact: &Artifact,
    u: &Unreachable,
    sources: Option<&SourceMap>,
) -> Diagnostic {
    let object = artifact.objects.get(u.object.index());
    let explained = cellc_runtime::explain::explain(artifact, u);
    let (mut d, labels) = match (&explained, object) {
        (Ok(explanation), Some(obj)) => {
            let words = Words::new(artifact, obj).for_front_end(front_end);
            let mut message = words.summary(explanation);
            // Another object in the way is named in the message: the notes list every
            // step it blocked.
            if let Some((_, blocker)) = u.blockers().next() {
                message = format!("{message}; {}", words::blocked(artifact, blocker));
            }
            let d = Diagnostic::error(codes::UNREACHABLE, message);
            (d, words.labels(explanation))
        }
        (Ok(_), None) | (Err(_), _) => {
            let d = Diagnostic::error(codes::UNREACHABLE, no_states(object, u.object, &explained));
            (d, Vec::new())
        }
    };
    // The object's declaration is the primary place; the lines that matter follow.
    if let Some((file, span)) = object.and_then(|o| place(artifact, o.span)) {
        d = d.primary(file, span, "no path in this object's graph");
    }
    for (span, label) in labels {
        if let Some((file, at)) = place(artifact, span) {
            if d.labels.iter().any(|l| l.file == file && l.span == at) {
                continue;
            }
            d = d.secondary(file, at, label);
        }
    }
    let (Ok(explanation), Some(obj)) = (&explained, object) else {
        return d;
    };
    let words = Words::new(artifact, obj).for_front_end(front_end);
    let cut: Vec<String> = explanation
        .cut
        .iter()
        .map(|item| words.gap_text(&item.gap))
        .collect();
    let named: BTreeSet<EndEffectorId> = explanation
        .cut
        .iter()
        .flat_map(|c| c.gap.near().into_iter().chain(c.gap.far()))
        .collect();
    d = d.note(format!(
        "the start side: {}",
        words.side_text(&explanation.start_side, &named)
    ));
    d = d.note(format!(
        "the goal side: {}",
        words.side_text(&explanation.goal_side, &named)
    ));
    for text in cut {
        d = d.note(text);
    }
    if explanation.cut_omitted > 0 {
        d = d.note(format!("and {} more cuts", explanation.cut_omitted));
    }
    for arc in &explanation.pruned {
        d = d.note(words.lost_text(arc));
    }
    if explanation.pruned_omitted > 0 {
        d = d.note(format!(
            "and {} more pruned or failed arcs",
            explanation.pruned_omitted
        ));
    }
    if let Some(GaveUp::Backtracks { failed, omitted }) = &explanation.gave_up {
        for arc in failed {
            d = d.note(words.lost_text(arc));
        }
        if *omitted > 0 {
            d = d.note(format!("and {omitted} more failed steps"));
        }
    }
    let geometric = artifact
        .end_effectors
        .iter()
        .any(|e| matches!(e.body, Body::Arm { .. }));
    if explanation.cause != Cause::Connected {
        if explanation.suggestions.is_empty() {
            d = d.note(
                "no single edit, nor a short set of transitions, adjacencies, allowed contacts \
                 or reach extensions, connects them",
            );
        } else if geometric {
            d = d.note(
                "suggestions are checked on the graph, not kinematically: verification checks \
                 the arcs they add when the cell is built again",
            );
        }
    }
    if let Some(sources) = sources {
        for (i, suggestion) in explanation.suggestions.iter().enumerate() {
            for change in &suggestion.changes {
                let fix = crate::fixes::edit(artifact, explanation.object, change, sources);
                if let Some(text) = fix.and_then(|f| suggestions::fix_text(&f, sources)) {
                    d = d.note(format!("to make suggestion {}, {text}", i + 1));
                }
            }
        }
    }
    let texts: Vec<String> = explanation
        .suggestions
        .iter()
        .map(|s| words.suggestion_text(s))
        .collect();
    let help = match texts.as_slice() {
        [] => words.no_suggestion_help(explanation),
        [one] => one.clone(),
        many => many
            .iter()
            .enumerate()
            .map(|(i, s)| format!("{}) {s}", i + 1))
            .collect::<Vec<_>>()
            .join("\n"),
    };
    // An object in the way is moved before the cell is edited.
    let help = match u.blockers().next() {
        Some((_, blocker)) => {
            let hint = words::blocked_hint(artifact, blocker, front_end);
            if help.contains(&hint) {
                help
            } else {
                format!("{hint}\nwithout moving it: {help}")
            }
        }
        None => help,
    };
    d.help(help)
}

/// The message when the request does not fit the artifact (the planner never gives such
/// a request; a caller with inconsistent data might).
fn no_states(
    object: Option<&Object>,
    index: ObjectId,
    explained: &Result<Explanation, NoStates>,
) -> String {
    let name = object.map_or_else(String::new, |o| o.name.clone());
    match (explained, object) {
        (Err(NoStates::Start), Some(_)) => {
            format!("the start state is not a state of `{name}`'s graph")
        }
        (Err(NoStates::Goals), Some(_)) => {
            format!("no goal state of the request is a state of `{name}`'s graph")
        }
        _ => format!(
            "the request names object #{}, which the artifact does not have",
            index.0
        ),
    }
}

impl Words<'_> {
    /// The diagnostic's message.
    fn summary(&self, ex: &Explanation) -> String {
        let object = self.object_name();
        let from = self.state_text(self.node(ex.start));
        let to = if ex.must_leave {
            "another pose there".to_string()
        } else {
            self.goals_text(&ex.goals)
        };
        let place = if ex.must_leave { "back" } else { "there" };
        let why = match (ex.cause, &ex.gave_up) {
            (Cause::Connected, Some(GaveUp::Backtracks { failed, omitted })) => {
                return format!(
                    "the graph of {object} connects {from} to {to}, but the planner gave up \
                     after {} failed during this request",
                    count(failed.len() + omitted, "step")
                );
            }
            (Cause::Connected, _) => {
                return format!(
                    "the graph of {object} connects {from} to {to} and no step failed: the \
                     planner's answer does not fit this artifact"
                );
            }
            (Cause::Pruned, _) => {
                "the arcs that would join them were pruned as kinematically infeasible".to_string()
            }
            (Cause::Failed, _) => {
                "arcs that would join them failed during this request".to_string()
            }
            (Cause::Missing, _) => format!(
                "the cell declares no way from the {} it reaches to the {} that {} {place}",
                count(ex.start_side.states.len(), "state"),
                count(ex.goal_side.states.len(), "state"),
                if ex.goal_side.states.len() == 1 {
                    "leads"
                } else {
                    "lead"
                },
            ),
        };
        if ex.must_leave {
            format!(
                "no path takes {object} from {from} to {to}: it must leave that state and come \
                 back, and {why}"
            )
        } else {
            format!("no path takes {object} from {from} to {to}: {why}")
        }
    }

    /// The help when nothing is suggested: what would make the lost arcs feasible, or where
    /// to look.
    fn no_suggestion_help(&self, ex: &Explanation) -> String {
        let lost = match &ex.gave_up {
            Some(GaveUp::Backtracks { failed, .. }) => failed.first(),
            _ => ex.pruned.first(),
        };
        match (ex.cause, lost) {
            (Cause::Connected, Some(arc)) => format!(
                "the planner removes the arc of each step that fails and searches again, up to \
                 its limit of backtracks; to make the first one feasible: {}",
                self.reason_hint(&arc.reason, self.node(arc.to).workspace)
            ),
            (Cause::Connected, None) => {
                "plan the request on the artifact it was made for".to_string()
            }
            (_, Some(arc)) => format!(
                "no edit of the cell's declarations joins the two sides, and the arcs that would \
                 are infeasible; to make the first one feasible: {}",
                self.reason_hint(&arc.reason, self.node(arc.to).workspace)
            ),
            (_, None) => {
                "no single change joins the two sides: see the notes for where they are cut apart"
                    .to_string()
            }
        }
    }

    /// Source places to label, one label per span, most important first: the start and
    /// the goal, the end-effectors the cut names, what each suggestion edits, the other
    /// places of the cut, the pruned arcs' declarations, the object.
    fn labels(&self, ex: &Explanation) -> Vec<(u32, String)> {
        let mut labels: Vec<(u32, String)> = Vec::new();
        let n_spans = self.art.spans.len();
        let mut add = |span: Option<u32>, text: String| {
            if let Some(s) = span {
                if (s as usize) < n_spans && !labels.iter().any(|l| l.0 == s) {
                    labels.push((s, text));
                }
            }
        };
        let grasp_span = |g: GraspId| self.obj.grasps.get(g.index()).map(|x| x.span);
        let start = self.node(ex.start);
        let start_span = grasp_span(start.grasp);
        let goal_span = ex
            .goals
            .first()
            .and_then(|&g| grasp_span(self.node(g).grasp));
        let (start_text, goal_text) = (self.state_text(start), self.goals_text(&ex.goals));
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
        for item in &ex.cut {
            for s in item
                .spans
                .iter()
                .map(|s| s.0)
                .filter(|s| ee_spans.contains(s))
            {
                add(Some(s), self.span_label(s, item, ex));
            }
        }
        for (i, suggestion) in ex.suggestions.iter().enumerate() {
            for change in &suggestion.changes {
                let text = short(&self.change_text(change));
                for span in change.places(self.art, ex.object) {
                    add(Some(span.0), format!("suggestion {}: {text}", i + 1));
                }
            }
        }
        for item in &ex.cut {
            let others = item
                .spans
                .iter()
                .map(|s| s.0)
                .filter(|s| !ee_spans.contains(s));
            for s in others.take(3) {
                add(Some(s), self.span_label(s, item, ex));
            }
        }
        for arc in &ex.pruned {
            add(
                arc.source.map(|s: SpanId| s.0),
                format!("infeasible: {}", self.reason_text(&arc.reason)),
            );
        }
        if let Some(GaveUp::Backtracks { failed, .. }) = &ex.gave_up {
            for arc in failed {
                add(
                    arc.source.map(|s: SpanId| s.0),
                    format!("failed: {}", self.reason_text(&arc.reason)),
                );
            }
        }
        add(Some(self.obj.span), format!("object {}", q(&self.obj.name)));
        labels.truncate(MAX_SPANS);
        labels
    }

    /// A label for a span a cut item points at.
    fn span_label(&self, span: u32, item: &CutItem, ex: &Explanation) -> String {
        let side_of = |e: EndEffectorId| {
            let start = ex.start_side.holdings.iter().any(|h| h.end_effector == e);
            let goal = ex.goal_side.holdings.iter().any(|h| h.end_effector == e);
            match (start, goal) {
                (true, true) => "on both sides",
                (true, false) => "on the start's side",
                (false, true) => "on the goal's side",
                (false, false) => "on neither side",
            }
        };
        for e in item.gap.near().into_iter().chain(item.gap.far()) {
            if self.art.end_effectors.get(e.index()).map(|x| x.span) == Some(span) {
                let reach = self.ws_list(self.reach(e), "and");
                return format!("{} ({}) reaches {reach}", self.ee(e), side_of(e));
            }
        }
        if self.obj.transitions.iter().any(|t| t.span == span) {
            return match item.gap.kind() {
                CutKind::NoTransition => "declared only one way".to_string(),
                _ => format!(
                    "declared, but infeasible in {}",
                    self.ws_list(&item.gap.workspaces(), "and")
                ),
            };
        }
        if self.art.workspaces.iter().any(|w| w.span == span) {
            return match item.gap.kind() {
                CutKind::NoHand => "no hand that can hold it reaches this workspace".to_string(),
                _ => "not adjacent".to_string(),
            };
        }
        short(&self.gap_text(&item.gap))
    }
}
