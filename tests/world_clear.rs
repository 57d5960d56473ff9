//! Objects in the way on `cells/vito.cell`: a goal taken by another object and a pick
//! blocked by one are refused with the blocking object named, and planning with clearing
//! ([`Cell::plan_clearing`]) moves it to a free resting pose first. The plans are executed
//! one after the other in the simulator, every trajectory re-checked four times finer with
//! the world as it stands before it, and the world the simulator leaves is the one
//! [`Cell::world_after`] predicts: the blocking object moved off every other object, the
//! moved object where the request said.

#[path = "support/world.rs"]
mod support;

use cellc::plan_report::plan_error;
use cellc_driver::runtime_codes;
use cellc_runtime::plan::{Goal, Placement};
use cellc_runtime::scene::{ObjectPlacement, SceneScratch};
use cellc_runtime::validity::SceneValidity;
use cellc_runtime::{
    BlockedPart, BlockedStep, Cell, ExecuteOptions, Iso, ObjectId, Plan, PlanError, PlanOptions,
    StateValidity, Whereabouts, World,
};
use support::{document, options, recheck, vito};

/// The ball 12.5 cm from the pitcher's axis, on the right part of the table: the right
/// hand, the only one that reaches the ball there, closes round it into the pitcher.
const PITCHER_BY_THE_BALL: &str = r#"{ "objects": {
    "ball": { "holder": "table", "at": [0.45, -0.25, 0.95] },
    "pitcher": { "holder": "table", "at": [0.45, -0.375, 1.01] } } }"#;

/// Into the bin (resting there, not held over it).
fn to_the_bin(cell: &Cell) -> Goal {
    Goal::Workspace {
        workspace: cell.workspace("ws_right_bin").unwrap(),
        holder: Some(cell.end_effector("bin").unwrap()),
    }
}

/// Executes `plans` one after the other from `world`, each re-checked in the world it
/// starts from and the world after it compared with the prediction; the world at the end.
fn execute_all(cell: &Cell, mut world: World, plans: Vec<Plan>) -> World {
    for plan in plans {
        assert!(recheck(cell, &world, &plan) > 0, "no trajectory re-checked");
        let predicted = cell.world_after(&world, &plan);
        let object = plan.object;
        let mut simulator = cell.simulator(&world, &plan);
        cell.execute(&mut world, plan, &mut simulator, &ExecuteOptions::default())
            .expect("executes");
        assert_eq!(world.state(object), predicted.state(object));
        assert_eq!(world.arms(), predicted.arms(), "the arms end where planned");
        let at = |w: &World| w.pose(cell.artifact(), cell.scene(), object).unwrap();
        let off = (at(&world).translation.vector - at(&predicted).translation.vector).norm();
        assert!(off < 1e-3, "{off} m from the predicted pose");
    }
    world
}

/// Every object of `world` that rests on a surface touches no other object.
fn assert_no_contact(cell: &Cell, world: &World) {
    let (art, scene) = (cell.artifact(), cell.scene().unwrap());
    for o in 0..art.objects.len() {
        let o = ObjectId(o as u32);
        let (Whereabouts::Placed { state, .. }, Some(pose)) =
            (world.whereabouts(o), world.pose(art, Some(scene), o))
        else {
            continue;
        };
        let placement = ObjectPlacement::Resting {
            on: state.end_effector,
            pose,
            by: None,
        };
        let obstacles = world.obstacles(art, scene, o);
        let validity = SceneValidity::new(scene, &[], &[], o, placement)
            .unwrap()
            .with_obstacles(&obstacles);
        let fault = validity.check(&[], &mut SceneScratch::default()).unwrap();
        assert!(fault.is_none(), "{}: {fault:?}", art.object_name(o));
    }
}

#[test]
fn a_goal_taken_by_another_object_is_cleared_first() {
    let cell = vito();
    let world = cell.initial_world(&options(0)).expect("the declared world");
    let (cylinder, ball) = (
        cell.object("cylinder").unwrap(),
        cell.object("ball").unwrap(),
    );
    let ball_at = world.pose(cell.artifact(), cell.scene(), ball).unwrap();
    // The cylinder standing where the ball lies.
    let goal_pose = Iso::translation(ball_at.translation.x, ball_at.translation.y, 1.0);
    let goal = Goal::Placement(Placement {
        holder: cell.end_effector("table").unwrap(),
        grasp: None,
        workspace: None,
        pose: Some(goal_pose),
    });
    let direct = cell.plan_move(&world, cylinder, &goal, &options(0));
    assert!(matches!(&direct, Err(PlanError::GoalOccupied { by }) if *by == ball));
    assert_eq!(direct.unwrap_err().blockers(), vec![ball]);
    for seed in 0..2 {
        let plans = cell
            .plan_clearing(&world, cylinder, &goal, &options(seed))
            .unwrap_or_else(|e| panic!("seed {seed}: {e:?}"));
        let objects: Vec<ObjectId> = plans.iter().map(|p| p.object).collect();
        assert_eq!(objects, vec![ball, cylinder], "seed {seed}");
        let end = execute_all(&cell, world.clone(), plans);
        let at = |o| end.pose(cell.artifact(), cell.scene(), o).unwrap();
        let cylinder_off = (at(cylinder).translation.vector - goal_pose.translation.vector).norm();
        assert!(
            cylinder_off < 0.01,
            "the cylinder is {cylinder_off} m off its goal"
        );
        let moved = (at(ball).translation.vector - ball_at.translation.vector).norm();
        assert!(moved > 0.1, "the ball moved only {moved} m");
        assert_no_contact(&cell, &end);
    }
    // The same seed, the same plans.
    let again = |seed| {
        cell.plan_clearing(&world, cylinder, &goal, &options(seed))
            .unwrap()
            .iter()
            .map(|p| p.steps.len())
            .collect::<Vec<_>>()
    };
    assert_eq!(again(3), again(3));
    // Nothing in the way: the direct plan alone.
    let plans = cell
        .plan_clearing(&world, ball, &to_the_bin(&cell), &options(0))
        .expect("a plan");
    assert_eq!(plans.len(), 1);
    assert_eq!(plans[0].object, ball);
    // No time at all: out of time, not cleared.
    let rushed = PlanOptions {
        time_budget: Some(std::time::Duration::ZERO),
        ..options(0)
    };
    assert!(matches!(
        cell.plan_clearing(&world, cylinder, &goal, &rushed),
        Err(PlanError::TimeBudget { .. })
    ));
}

#[test]
fn a_pick_blocked_by_another_object_names_it_and_clearing_moves_it() {
    let cell = vito();
    let (ball, pitcher) = (
        cell.object("ball").unwrap(),
        cell.object("pitcher").unwrap(),
    );
    let right = cell.end_effector("right").unwrap();
    let world = cell
        .world(&document(PITCHER_BY_THE_BALL), &options(0))
        .expect("a valid world");
    // Without the pitcher the ball goes into the bin.
    let alone = cell
        .world(
            &document(
                r#"{ "objects": { "ball": { "holder": "table", "at": [0.45, -0.25, 0.95] } } }"#,
            ),
            &options(0),
        )
        .unwrap();
    assert!(cell
        .plan_move(&alone, ball, &to_the_bin(&cell), &options(0))
        .is_ok());
    for seed in 0..2 {
        let error = match cell.plan_move(&world, ball, &to_the_bin(&cell), &options(seed)) {
            Err(error @ PlanError::Unreachable(_)) => error,
            other => panic!("seed {seed}: the pitcher is in the way: {other:?}"),
        };
        assert_eq!(error.blockers(), vec![pitcher], "seed {seed}");
        let PlanError::Unreachable(u) = &error else {
            unreachable!()
        };
        let (_, blocker) = u.blockers().next().expect("a blocked step");
        assert_eq!(blocker.part, BlockedPart::Hand(right));
        let BlockedStep::Pick { at } = blocker.during else {
            panic!("the pick is blocked: {blocker:?}");
        };
        assert!(
            (at[0] - 0.45).abs() < 1e-9 && (at[1] + 0.25).abs() < 1e-9,
            "{at:?}"
        );
        // The diagnostic names it.
        let d = plan_error(cell.artifact(), &error, None, None);
        assert_eq!(d.code, runtime_codes::UNREACHABLE);
        assert!(
            d.message.contains(
                "`pitcher` blocks the pick at (0.450, -0.250, 0.950), in the way of `right`'s hand"
            ),
            "{}",
            d.message
        );
        assert!(d
            .help
            .as_deref()
            .unwrap_or("")
            .contains("move `pitcher` out of the way"));

        let plans = cell
            .plan_clearing(&world, ball, &to_the_bin(&cell), &options(seed))
            .unwrap_or_else(|e| panic!("seed {seed}: {e:?}"));
        let objects: Vec<ObjectId> = plans.iter().map(|p| p.object).collect();
        assert_eq!(objects, vec![pitcher, ball], "seed {seed}");
        let end = execute_all(&cell, world.clone(), plans);
        let bin = cell.end_effector("bin").unwrap();
        assert_eq!(end.state(ball).map(|s| s.end_effector), Some(bin));
        assert_no_contact(&cell, &end);
    }
}
