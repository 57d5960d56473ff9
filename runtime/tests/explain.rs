//! Explanations of unreachable goals, on small cells built directly as artifacts
//! (`explain_cells/`), checked on the structure (the words are the CLI's, tested in the
//! package's `tests/explain.rs`).
//!
//! Every explanation is checked the same way: at most three suggestions, none a
//! transition between two fixed end-effectors, every id and source place in range, and
//! each suggestion, applied to the cell's description and the graph rebuilt from scratch,
//! connects the start to the goal (checked with the search of `explain_cells`, not with
//! the runtime's).

mod explain_cells;

use cellc_runtime::explain::{
    explain, BodyName, Cause, Change, CutKind, Exchange, Explanation, Gap, GaveUp, NoStates,
};
use cellc_schema::{EndEffectorId, GraspId, NodeId, ObjectId, WorkspaceId};
use explain_cells::*;
use proptest::prelude::*;

fn ee(e: u32) -> EndEffectorId {
    EndEffectorId(e)
}

fn ws(w: u32) -> WorkspaceId {
    WorkspaceId(w)
}

/// Explains an unreachable request and checks what every explanation must satisfy.
fn check((d, req): &(Desc, Req)) -> Explanation {
    assert_eq!(
        connects(d, req),
        Some(false),
        "the request must be unreachable"
    );
    let art = d.build();
    let ex = explain(&art, &unreachable(d, &art, req)).expect("the states exist");
    println!("{ex:#?}");
    let n_nodes = art.objects[0].graph.nodes.len();
    let nodes_ok = |states: &[NodeId]| states.iter().all(|s| s.index() < n_nodes);
    assert!(nodes_ok(&ex.start_side.states) && nodes_ok(&ex.goal_side.states));
    assert!(ex.start_side.states.contains(&ex.start));
    assert!(ex.goals.iter().all(|g| ex.goal_side.states.contains(g)));
    assert!(ex.suggestions.len() <= 3);
    assert!(!ex.cut.is_empty(), "a cut explains every unreachable goal");
    for item in &ex.cut {
        assert!(item.spans.iter().all(|s| s.index() < art.spans.len()));
        let named = item.gap.near().into_iter().chain(item.gap.far());
        assert!(named.clone().all(|e| e.index() < art.end_effectors.len()));
    }
    for arc in &ex.pruned {
        assert!(arc.from.index() < n_nodes && arc.to.index() < n_nodes);
    }
    for sug in &ex.suggestions {
        assert!(!sug.changes.is_empty());
        for c in &sug.changes {
            let places = c.places(&art, ObjectId(0));
            assert!(places.iter().all(|s| s.index() < art.spans.len()));
            if let Change::AddTransition {
                from_grasp,
                to_grasp,
                ..
            } = c
            {
                // Some pair of distinct holders, not both fixed, must exchange it.
                let holders = |g: GraspId| d.holders(&d.grasps[g.index()].1);
                let fine = holders(*from_grasp).iter().any(|&a| {
                    holders(*to_grasp)
                        .iter()
                        .any(|&b| a != b && (d.end_effectors[a].1 || d.end_effectors[b].1))
                });
                assert!(fine, "a transition no two end-effectors can make: {c:?}");
            }
        }
        let (d2, req2) = apply(d, &art, req, &sug.changes);
        assert_eq!(
            connects(&d2, &req2),
            Some(true),
            "suggestion does not connect: {sug:?}"
        );
    }
    ex
}

fn only_change(ex: &Explanation, i: usize) -> &Change {
    match ex.suggestions[i].changes.as_slice() {
        [one] => one,
        many => panic!("{} changes", many.len()),
    }
}

#[test]
fn fig3_is_connected_as_published() {
    let (d, req) = fig3_connected();
    assert_eq!(connects(&d, &req), Some(true));
}

#[test]
fn fig3_with_the_right_arm_unable_to_take_names_the_cut_and_reconnects() {
    let ex = check(&fig3_right_arm_cannot_take());
    assert_eq!(ex.cause, Cause::Missing);
    let Gap::NoTransition {
        near,
        far,
        workspaces,
        one_way,
    } = &ex.cut[0].gap
    else {
        panic!("{:?}", ex.cut[0]);
    };
    let holders: Vec<EndEffectorId> = near.iter().map(|h| h.end_effector).collect();
    assert_eq!(
        holders,
        [ee(0), ee(1)],
        "`table` and `left_arm` on the start's side"
    );
    assert_eq!(far[0].end_effector, ee(2), "`right_arm` on the goal's side");
    // Every grasp of the table and of the left arm, in `w2`.
    assert!(near.iter().all(|h| h.grasps.len() == 3));
    assert_eq!(workspaces, &[ws(1)]);
    assert!(
        !one_way.is_empty(),
        "the right arm's transitions go one way"
    );
    assert!(!ex.suggestions.is_empty());
    for i in 0..ex.suggestions.len() {
        assert!(matches!(only_change(&ex, i), Change::AddTransition { .. }));
    }
    let Change::AddTransition { exchanges, .. } = only_change(&ex, 0) else {
        unreachable!()
    };
    assert_eq!(exchanges[0].taker, ee(2));
    assert_eq!(exchanges[0].workspace, ws(1));
}

#[test]
fn fig3_with_the_right_arm_isolated_explains_the_way_through_it() {
    let ex = check(&fig3_right_arm_isolated());
    assert_eq!(ex.cause, Cause::Missing);
    assert!(
        ex.cut.iter().any(
            |c| c.gap.near().contains(&ee(0)) && c.gap.far().contains(&ee(2))
                || c.gap.near().contains(&ee(2)) && c.gap.far().contains(&ee(0))
        ),
        "{:?}",
        ex.cut
    );
    // One two-way transition between a table grasp and a right-arm grasp suffices: the
    // right arm takes it in `w2` and puts it back on the table in `w3`.
    assert!(ex.suggestions.iter().all(|s| s.changes.len() == 1));
    let Change::AddTransition { exchanges, .. } = only_change(&ex, 0) else {
        panic!("{:?}", ex.suggestions[0]);
    };
    assert_eq!(
        exchanges,
        &[
            Exchange {
                giver: ee(0),
                taker: ee(2),
                workspace: ws(1)
            },
            Exchange {
                giver: ee(2),
                taker: ee(0),
                workspace: ws(2)
            }
        ]
    );
}

#[test]
fn arms_without_a_common_workspace_get_the_nearest_reach_extension() {
    let ex = check(&arms_apart_with_boxes());
    assert_eq!(ex.cause, Cause::Missing);
    assert_eq!(ex.cut.len(), 1);
    assert_eq!(
        ex.cut[0].gap,
        Gap::NoCommonWorkspace {
            near: ee(1),
            far: ee(2)
        }
    );
    // End-effectors without geometry get a declared workspace added to their `reaches`
    // list.
    let reach: Vec<(EndEffectorId, WorkspaceId)> = ex
        .suggestions
        .iter()
        .filter_map(|s| match s.changes.as_slice() {
            [Change::ExtendReaches {
                end_effector,
                workspace,
                ..
            }] => Some((*end_effector, *workspace)),
            _ => None,
        })
        .collect();
    // `left` to `w3` and `right` to `w2` (0.1 m away) before the far workspaces.
    assert_eq!(reach[..2], [(ee(1), ws(2)), (ee(2), ws(1))]);
    let Change::ExtendReaches { meets, .. } = only_change(&ex, 0) else {
        unreachable!()
    };
    assert_eq!(meets, &[ee(2)], "where it meets `right`");
}

#[test]
fn arms_without_a_common_workspace_in_a_cell_that_declares_adjacency() {
    // The suggestion then also declares the adjacency it needs (harmless if it is already
    // there), and still connects.
    let ex = check(&arms_apart_declaring_adjacency());
    assert!(!ex.suggestions.is_empty());
    assert!(ex.suggestions.iter().all(|s| s
        .changes
        .iter()
        .any(|c| matches!(c, Change::ExtendReaches { .. }))));
}

#[test]
fn hands_of_one_kind_get_a_handoff_of_their_kind_grasp() {
    let ex = check(&hands_of_one_kind());
    let Gap::NoTransition {
        near,
        far,
        workspaces,
        ..
    } = &ex.cut[0].gap
    else {
        panic!("{:?}", ex.cut[0]);
    };
    // Grasp `pinch` (2) of `left` (1) with grasp `pinch` of `right` (2) in `w2`.
    assert_eq!(
        (near[0].end_effector, near[0].grasps.as_slice()),
        (ee(1), &[GraspId(2)][..])
    );
    assert_eq!(
        (far[0].end_effector, far[0].grasps.as_slice()),
        (ee(2), &[GraspId(2)][..])
    );
    assert_eq!(workspaces, &[ws(1)]);
    assert_eq!(
        only_change(&ex, 0),
        &Change::AddTransition {
            from_grasp: GraspId(2),
            to_grasp: GraspId(2),
            reverse_of: None,
            exchanges: vec![Exchange {
                giver: ee(1),
                taker: ee(2),
                workspace: ws(1)
            }],
        }
    );
}

#[test]
fn a_line_of_arms_names_its_one_missing_handoff() {
    let ex = check(&line_with_a_gap());
    assert_eq!(ex.cut.len(), 1);
    // `arm4` is end-effector 6 (after `start` and `end`), `arm5` is 7.
    let Gap::NoTransition {
        near,
        far,
        workspaces,
        ..
    } = &ex.cut[0].gap
    else {
        panic!("{:?}", ex.cut[0]);
    };
    assert_eq!(
        (near.len(), near[0].end_effector, far[0].end_effector),
        (1, ee(6), ee(7))
    );
    assert!(
        near[0].grasps.len() == 4 && far[0].grasps.len() == 4,
        "any grasp"
    );
    assert_eq!(workspaces, &[ws(5)]);
    assert_eq!(
        ex.suggestions.len(),
        1,
        "one idea: a handoff from `arm4` to `arm5`"
    );
    let Change::AddTransition { exchanges, .. } = only_change(&ex, 0) else {
        unreachable!()
    };
    assert_eq!(
        exchanges.last(),
        Some(&Exchange {
            giver: ee(6),
            taker: ee(7),
            workspace: ws(5)
        })
    );
}

#[test]
fn pruned_handoffs_are_explained_with_their_reasons() {
    let ex = check(&fig3_handoffs_pruned());
    assert_eq!(ex.cause, Cause::Pruned);
    let infeasible: Vec<&Gap> = ex
        .cut
        .iter()
        .map(|c| &c.gap)
        .filter(|g| g.kind() == CutKind::InfeasibleTransition)
        .collect();
    // From the table (the right arm cannot reach) and from the left arm (no closed chain).
    let givers: Vec<Vec<EndEffectorId>> = infeasible.iter().map(|g| g.near()).collect();
    assert!(
        givers.contains(&vec![ee(0)]) && givers.contains(&vec![ee(1)]),
        "{givers:?}"
    );
    for g in infeasible {
        let Gap::InfeasibleTransition { arcs, .. } = g else {
            unreachable!()
        };
        assert!(!arcs.is_empty() && arcs.iter().all(|a| !a.failed));
    }
    assert!(!ex.pruned.is_empty());
    assert!(ex.pruned.iter().all(|p| !p.failed));
    // No IK solution and no closed chain are explained, not suggested away (which base
    // to move, and how far, is not known); no new transition where every declared one
    // between the same arms failed: what is left is more reach.
    assert!(!ex.suggestions.is_empty());
    assert!(ex.suggestions.iter().all(|s| s
        .changes
        .iter()
        .all(|c| matches!(c, Change::ExtendReaches { .. }))));
}

#[test]
fn a_failed_move_of_the_one_hand_is_explained() {
    let ex = check(&one_hand_move_failed());
    assert_eq!(ex.cause, Cause::Failed);
    let Gap::InfeasibleMove {
        hand,
        grasps,
        from,
        to,
        arcs,
    } = &ex.cut[0].gap
    else {
        panic!("{:?}", ex.cut[0]);
    };
    assert_eq!(
        (*hand, grasps.as_slice(), *from, *to),
        (ee(0), &[GraspId(0)][..], ws(0), ws(1))
    );
    assert!(arcs.iter().all(|a| a.failed));
    assert!(ex.pruned[0].failed);
    // An arm that cannot reach is not an edit: nothing to suggest in a cell of one hand.
    assert!(ex.suggestions.is_empty());
}

#[test]
fn a_pruned_move_of_the_one_hand_is_explained() {
    let ex = check(&one_hand_move_pruned());
    assert_eq!(ex.cause, Cause::Pruned);
    assert_eq!(ex.cut[0].gap.kind(), CutKind::InfeasibleMove);
    let Change::AllowContact { a, b, arcs } = only_change(&ex, 0) else {
        panic!("{:?}", ex.suggestions[0]);
    };
    let body = |owner: &str, part: Option<&str>| BodyName {
        owner: owner.to_string(),
        part: part.map(str::to_string),
    };
    assert_eq!(
        (a, b),
        (&body("right", Some("link_4")), &body("shelf", None))
    );
    assert!(arcs.len() == 1 && !arcs[0].failed);
}

#[test]
fn a_collision_with_something_the_cell_cannot_name_is_not_suggested_away() {
    // Without the shelf among the obstacles, `allow contact` could not name it.
    let (mut d, req) = one_hand_move_pruned();
    d.obstacles.clear();
    let ex = check(&(d, req));
    assert!(ex.suggestions.is_empty(), "{:?}", ex.suggestions);
}

#[test]
fn a_pick_and_place_on_one_table_must_leave_it_and_come_back() {
    for one_way in [false, true] {
        let ex = check(&back_to_the_table(one_way));
        assert!(ex.must_leave);
        assert_eq!(ex.cause, Cause::Missing);
        assert!(ex.start_side.states.contains(&ex.start));
        assert!(ex.goal_side.states.contains(&ex.start));
        // `standing` (0) of the table and `top` (1) of the arm, both ways, or the missing
        // way back.
        let Change::AddTransition {
            from_grasp,
            to_grasp,
            reverse_of,
            ..
        } = only_change(&ex, 0)
        else {
            panic!("{:?}", ex.suggestions);
        };
        if one_way {
            assert_eq!((*from_grasp, *to_grasp), (GraspId(1), GraspId(0)));
            assert!(reverse_of.is_some());
        } else {
            assert!(reverse_of.is_none());
        }
    }
}

#[test]
fn a_connected_graph_says_which_steps_failed() {
    let (d, req) = fig3_gave_up();
    assert_eq!(connects(&d, &req), Some(true));
    let art = d.build();
    let ex = explain(&art, &unreachable(&d, &art, &req)).expect("the states exist");
    assert_eq!(ex.cause, Cause::Connected);
    let Some(GaveUp::Backtracks { failed, omitted: 0 }) = &ex.gave_up else {
        panic!("{:?}", ex.gave_up);
    };
    assert_eq!(failed.len(), 1);
    assert!(failed[0].failed);
    assert!(ex.suggestions.is_empty() && ex.cut.is_empty());
}

#[test]
fn two_surfaces_and_an_arm_need_two_transitions_never_a_surface_to_surface_one() {
    let ex = check(&two_surfaces_and_an_arm());
    assert_eq!(ex.cause, Cause::Missing);
    assert_eq!(ex.suggestions.len(), 1);
    assert_eq!(ex.suggestions[0].changes.len(), 2);
    // `table_a` (0) to `arm` (2), and `arm` to `table_b` (1).
    let pairs: Vec<(Vec<EndEffectorId>, Vec<EndEffectorId>)> =
        ex.cut.iter().map(|c| (c.gap.near(), c.gap.far())).collect();
    assert!(pairs.contains(&(vec![ee(0)], vec![ee(2)])), "{pairs:?}");
    assert!(pairs.contains(&(vec![ee(2)], vec![ee(1)])), "{pairs:?}");
}

#[test]
fn surfaces_alone_cannot_be_helped_and_say_so() {
    let ex = check(&surfaces_alone());
    assert!(ex.suggestions.is_empty());
    assert_eq!(ex.cut.len(), 1);
    assert_eq!(
        ex.cut[0].gap,
        Gap::NoHand {
            near: vec![ee(0)],
            far: vec![ee(1)],
            workspaces: vec![ws(0)]
        }
    );
}

#[test]
fn workspaces_that_are_not_adjacent_get_an_adjacency() {
    let ex = check(&workspaces_not_adjacent());
    assert_eq!(
        ex.cut[0].gap,
        Gap::NotAdjacent {
            hand: ee(2),
            from: ws(0),
            to: ws(2)
        }
    );
    assert!(matches!(
        only_change(&ex, 0),
        Change::AddAdjacency { a, b, carrier: Some(c) } if (*a, *b, *c) == (ws(0), ws(2), ee(2))
    ));
}

#[test]
fn a_reachable_goal_is_reported_as_connected() {
    let (d, req) = fig3_connected();
    let art = d.build();
    let ex = explain(&art, &unreachable(&d, &art, &req)).expect("the states exist");
    assert_eq!(ex.cause, Cause::Connected);
    assert_eq!(ex.gave_up, Some(GaveUp::NothingFailed));
    assert!(ex.suggestions.is_empty() && ex.cut.is_empty() && ex.pruned.is_empty());
    assert!(!ex.start_side.states.is_empty());
}

#[test]
fn a_request_outside_the_graph_is_reported_without_panicking() {
    let (d, _) = fig3_connected();
    let art = d.build();
    let mut un = unreachable(&d, &art, &Req::new(st("table", "g1", "w1"), vec![]));
    assert_eq!(explain(&art, &un), Err(NoStates::Goals));
    un.goals = vec![art.objects[0].graph.nodes[3]];
    un.start.grasp = GraspId(99);
    assert_eq!(explain(&art, &un), Err(NoStates::Start));
    un.object = ObjectId(7);
    assert_eq!(explain(&art, &un), Err(NoStates::Object(ObjectId(7))));
}

proptest! {
    // About half the random requests are reachable and skipped.
    #![proptest_config(ProptestConfig {
        cases: 500,
        max_global_rejects: 1 << 20,
        ..ProptestConfig::default()
    })]

    /// On random cells, every explanation keeps its promises: few suggestions, never a
    /// surface-to-surface transition, and each one really connects.
    #[test]
    fn suggestions_on_random_cells_connect(seed in any::<u64>()) {
        let cell = random_cell(seed);
        prop_assume!(connects(&cell.0, &cell.1) == Some(false));
        let ex = check(&cell);
        prop_assert!(ex.cause != Cause::Connected);
        if ex.cause != Cause::Missing {
            prop_assert!(!ex.pruned.is_empty());
        }
    }
}
