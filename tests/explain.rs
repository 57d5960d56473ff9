//! Explanations of unreachable goals in words: the runtime's structured explanation of
//! the small cells of `runtime/tests/explain_cells/` (its tests check the structure),
//! rendered as the `R0004` diagnostic `cellc plan` prints.
//!
//! Every rendering is checked the same way: a lowercase message naming the object, notes
//! that say something, at most one label per source place and no more than the cap. A
//! request on Vito whose motions all fail shows what a connected graph's explanation says:
//! the steps that failed, with why.

#[path = "../runtime/tests/explain_cells/mod.rs"]
mod explain_cells;

use std::collections::BTreeSet;

use cellc_driver::fs_files::FsFiles;
use cellc_lang::Diagnostic;
use cellc_runtime::explain::Cause;
use cellc_runtime::motion::{ChaCha8Rng, MotionError, MotionPlanner, MotionProblem};
use cellc_runtime::plan::{PlanError, PlanOptions, Trajectory};
use cellc_runtime::scene::SceneScratch;
use cellc_runtime::Cell;
use cellc_runtime::Termination;
use explain_cells::*;

/// The diagnostic of an unreachable request, checked as every one must be.
fn render((d, req): &(Desc, Req)) -> Diagnostic {
    let art = d.build();
    let diagnostic =
        cellc_driver::explain_report::unreachable(&art, &unreachable(d, &art, req), None);
    println!("{diagnostic:#?}");
    let message = &diagnostic.message;
    assert!(message.starts_with(|c: char| c.is_lowercase()), "{message}");
    assert!(message.contains("`cylinder`"), "{message}");
    assert!(diagnostic
        .notes
        .iter()
        .all(|n| !n.is_empty() && !n.ends_with(": ")));
    let places: BTreeSet<(u32, u32)> = diagnostic
        .labels
        .iter()
        .map(|l| (l.span.start, l.span.end))
        .collect();
    assert_eq!(places.len(), diagnostic.labels.len(), "one label per place");
    assert!(
        diagnostic.labels.len() <= 13,
        "the object and at most 12 more"
    );
    assert!(diagnostic.labels.iter().all(|l| !l.message.is_empty()));
    diagnostic
}

/// The suggestions of the help, one per line ("1) ..."), or the help when it has one.
fn suggestions(d: &Diagnostic) -> Vec<String> {
    let help = d.help.clone().unwrap_or_default();
    if !help.starts_with("1) ") {
        return vec![help];
    }
    help.lines()
        .map(|l| l.split_once(") ").map_or(l, |(_, rest)| rest).to_string())
        .collect()
}

/// The cut: the notes after the two sides, up to the pruned arcs and remarks.
fn cut(d: &Diagnostic) -> &[String] {
    let end = d
        .notes
        .iter()
        .position(|n| {
            n.contains(" was pruned at build time")
                || n.contains(" failed during this request:")
                || n.starts_with("suggestions are checked")
                || n.starts_with("no single edit")
                || n.starts_with("to make suggestion")
        })
        .unwrap_or(d.notes.len());
    &d.notes[2..end]
}

#[test]
fn the_sides_come_first_in_the_notes() {
    let d = render(&fig3_right_arm_cannot_take());
    assert!(d.notes[0].starts_with("the start side: "), "{:?}", d.notes);
    assert!(d.notes[1].starts_with("the goal side: "), "{:?}", d.notes);
    assert!(
        d.message.starts_with(
            "no path takes `cylinder` from `table` with `g1` in `w1` to `table` with `g1` in \
             `w3`: the cell declares no way from the "
        ),
        "{}",
        d.message
    );
}

#[test]
fn fig3_with_the_right_arm_unable_to_take_names_the_cut_and_reconnects() {
    let d = render(&fig3_right_arm_cannot_take());
    let first = &cut(&d)[0];
    assert!(
        first.contains("any grasp of `table` or `left_arm`"),
        "{first}"
    );
    assert!(first.contains("`right_arm`"), "{first}");
    assert!(first.contains("in `w2`"), "{first}");
    assert!(first.contains("declared only the other way"), "{first}");
    let best = &suggestions(&d)[0];
    assert!(best.contains("to `right_arm` in `w2`"), "{best}");
}

#[test]
fn fig3_with_the_right_arm_isolated_explains_the_way_through_it() {
    let d = render(&fig3_right_arm_isolated());
    assert!(
        cut(&d)
            .iter()
            .any(|t| t.contains("`right_arm`") && t.contains("`table`")),
        "{:?}",
        d.notes
    );
    let best = &suggestions(&d)[0];
    assert!(
        best.ends_with(
            "so `right_arm` can take it from `table` in `w2`, and `right_arm` can put it on \
             `table` in `w3`"
        ),
        "{best}"
    );
}

#[test]
fn arms_without_a_common_workspace_get_the_nearest_reach_extension() {
    let d = render(&arms_apart_with_boxes());
    assert_eq!(cut(&d).len(), 1);
    assert!(cut(&d)[0].contains("`left` and `right` reach no common workspace"));
    // Without geometry, the workspace goes into the `reaches` list.
    assert_eq!(
        suggestions(&d)[0],
        "add `w3` to the `reaches` list of `left`, where it meets `right`"
    );
}

#[test]
fn hands_of_one_kind_get_a_handoff_of_their_kind_grasp() {
    let d = render(&hands_of_one_kind());
    assert_eq!(
        cut(&d)[0],
        "no transition joins grasp `pinch` of `left` with grasp `pinch` of `right` in `w2`"
    );
    assert_eq!(
        suggestions(&d)[0],
        "add `transition pinch <-> pinch` to `cylinder`, so `left` can hand it to `right` in `w2`"
    );
}

#[test]
fn a_line_of_arms_names_its_one_missing_handoff() {
    let d = render(&line_with_a_gap());
    assert_eq!(
        cut(&d),
        ["no transition joins any grasp of `arm4` with any grasp of `arm5` in `w5`"]
    );
    let only = suggestions(&d);
    assert_eq!(only.len(), 1);
    assert!(
        only[0].ends_with("so `arm4` can hand it to `arm5` in `w5`"),
        "{}",
        only[0]
    );
}

#[test]
fn pruned_handoffs_are_explained_with_their_reasons() {
    let d = render(&fig3_handoffs_pruned());
    assert!(
        d.message
            .ends_with("were pruned as kinematically infeasible"),
        "{}",
        d.message
    );
    let cut = cut(&d);
    assert!(
        cut.iter()
            .any(|t| t.contains("`right_arm` cannot reach the pose, closest 0.21 m")),
        "{cut:?}"
    );
    assert!(
        cut.iter()
            .any(|t| t.contains("`left_arm` and `right_arm` cannot hold the object at once")),
        "{cut:?}"
    );
    assert!(d
        .notes
        .iter()
        .any(|n| n.contains("was pruned at build time")));
    // The reasons are explained, not suggested away: what is suggested is more reach.
    assert!(
        suggestions(&d)
            .iter()
            .all(|s| s.starts_with("add `w") && s.contains("to the `reaches` list of")),
        "{:?}",
        suggestions(&d)
    );
}

#[test]
fn a_failed_move_of_the_one_hand_is_explained() {
    let d = render(&one_hand_move_failed());
    assert!(
        d.message.ends_with("failed during this request"),
        "{}",
        d.message
    );
    assert!(cut(&d)[0]
        .starts_with("`right` cannot carry it with `g7` from `w2` to `w3`: `right` cannot reach"));
    assert!(d
        .notes
        .iter()
        .any(|n| n.contains("failed during this request")));
    // Nothing to declare: the help says what would make the move feasible.
    assert!(
        d.help
            .as_deref()
            .is_some_and(|h| h.contains("move `right`'s base or `w3` closer together")),
        "{:?}",
        d.help
    );
}

#[test]
fn a_pruned_move_of_the_one_hand_is_explained() {
    let d = render(&one_hand_move_pruned());
    assert!(cut(&d)[0].contains("`right/link_4` collides with `shelf`"));
    assert!(suggestions(&d)[0].contains("allow contact right.link_4 shelf"));
}

#[test]
fn two_surfaces_and_an_arm_need_two_transitions_never_a_surface_to_surface_one() {
    let d = render(&two_surfaces_and_an_arm());
    let cut = cut(&d);
    assert!(cut
        .iter()
        .any(|c| c.contains("`table_a`") && c.contains("`arm`")));
    assert!(cut
        .iter()
        .any(|c| c.contains("`arm`") && c.contains("`table_b`")));
    let only = suggestions(&d);
    assert_eq!(only.len(), 1);
    assert_eq!(only[0].matches("transition").count(), 2, "{}", only[0]);
}

#[test]
fn surfaces_alone_cannot_be_helped_and_say_so() {
    let d = render(&surfaces_alone());
    assert_eq!(
        cut(&d),
        [
            "no movable end-effector that can hold `cylinder` reaches `w1`, so nothing can take \
          it from `table_a` nor bring it to `table_b` there"
        ]
    );
    assert!(d
        .notes
        .iter()
        .any(|n| n.starts_with("no single edit, nor a short set")));
    assert_eq!(
        suggestions(&d),
        ["no single change joins the two sides: see the notes for where they are cut apart"]
    );
}

#[test]
fn workspaces_that_are_not_adjacent_get_an_adjacency() {
    let d = render(&workspaces_not_adjacent());
    assert_eq!(
        cut(&d)[0],
        "`w1` and `w3` are not adjacent, so `arm` cannot carry it from one to the other"
    );
    assert!(suggestions(&d)[0].starts_with("declare `adjacent w1 w3`, so `arm` can carry it"));
}

#[test]
fn a_reachable_goal_is_reported_as_connected() {
    let d = render(&fig3_connected());
    assert!(
        d.message.starts_with("the graph of `cylinder` connects")
            && d.message.contains("no step failed"),
        "{}",
        d.message
    );
}

#[test]
fn a_connected_graph_says_which_steps_failed_and_why() {
    let d = render(&fig3_gave_up());
    assert_eq!(
        d.message,
        "the graph of `cylinder` connects `table` with `g1` in `w1` to `table` with `g1` in \
         `w3`, but the planner gave up after 1 step failed during this request"
    );
    assert!(
        d.notes.iter().any(|n| n
            == "the transition `g5 -> g7` from `left_arm` to `right_arm` in `w2` failed during \
                this request: no collision-free motion found in 10000 iterations"),
        "{:?}",
        d.notes
    );
    assert!(d
        .help
        .as_deref()
        .is_some_and(|h| h.contains("move what blocks the motion")));
}

#[test]
fn a_pick_and_place_on_one_table_must_leave_it_and_come_back() {
    let d = render(&back_to_the_table(true));
    assert!(
        d.message.starts_with(
            "no path takes `cylinder` from `table` with `standing` in `w1` to another pose \
             there: it must leave that state and come back"
        ),
        "{}",
        d.message
    );
    assert_eq!(
        suggestions(&d),
        [
            "make `transition standing -> top` two-way (`transition top <-> standing`), so `arm` \
          can put it on `table` in `w1`"
        ]
    );
}

/// A motion planner that finds no motion, ever.
struct Blocked;

impl MotionPlanner for Blocked {
    fn solve(
        &self,
        _: &MotionProblem<'_>,
        _: &mut ChaCha8Rng,
        _: &Termination,
        _: &mut SceneScratch,
    ) -> Result<Trajectory, MotionError> {
        Err(MotionError::NoPath { iterations: 0 })
    }
}

#[test]
fn vito_with_every_motion_blocked_says_what_failed_never_another_reason() {
    let built = cellc_driver::build(&FsFiles, "cells/vito.cell", &Default::default());
    let artifact = built.artifact.expect("vito builds");
    let cell = Cell::from_artifact(artifact, &FsFiles).expect("vito loads");
    // No backtrack: the first failed step stops the planner while the graph still has
    // other paths (the start's other grasp).
    let options = PlanOptions {
        max_backtracks: 0,
        ..PlanOptions::default()
    };
    let request = cell
        .named_request("handoff_cylinder", options)
        .expect("declared");
    let planner = cell.planner().with_motion_planner(Blocked);
    let Err(PlanError::Unreachable(u)) = planner.plan(&request) else {
        panic!("every motion is blocked");
    };
    assert_eq!(u.failed.len(), 1);
    let explanation = cell.explain(&u).expect("the states exist");
    assert_eq!(explanation.cause, Cause::Connected);
    let d = cellc_driver::explain_report::unreachable(
        cell.artifact(),
        &u,
        Some(&built.compilation.sources),
    );
    println!("{d:#?}");
    assert!(!d.message.contains("another reason"), "{}", d.message);
    assert!(
        d.message
            .ends_with("but the planner gave up after 1 step failed during this request"),
        "{}",
        d.message
    );
    let failed: Vec<&String> = d
        .notes
        .iter()
        .filter(|n| {
            n.ends_with(
                " failed during this request: no collision-free motion found in 0 iterations",
            )
        })
        .collect();
    assert_eq!(failed.len(), 1, "{:?}", d.notes);
    assert!(d.labels.iter().any(|l| l.message.starts_with("failed: ")));
}

#[test]
fn a_request_outside_the_graph_says_what_does_not_fit() {
    let (d, _) = fig3_connected();
    let art = d.build();
    let mut un = unreachable(&d, &art, &Req::new(st("table", "g1", "w1"), vec![]));
    let message = |un: &_| cellc_driver::explain_report::unreachable(&art, un, None).message;
    assert_eq!(
        message(&un),
        "no goal state of the request is a state of `cylinder`'s graph"
    );
    un.object = cellc_schema::ObjectId(7);
    assert_eq!(
        message(&un),
        "the request names object #7, which the artifact does not have"
    );
}

#[test]
fn random_cells_render_cleanly() {
    let mut rendered = 0;
    for seed in 0..300 {
        let cell = random_cell(seed);
        if connects(&cell.0, &cell.1) == Some(false) {
            render(&cell);
            rendered += 1;
        }
    }
    assert!(rendered > 100, "only {rendered} unreachable requests");
}
