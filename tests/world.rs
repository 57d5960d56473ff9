//! Planning in a world on `cells/vito.cell`: several objects on the table at once, arms
//! that are not at home, objects in hand located by forward kinematics, goals occupied by
//! another object, and the clear-the-table task, whose every trajectory is re-checked
//! four times finer than planned with every object of the world in the scene (one of its
//! moves goes round an object that takes its witnessed place).

#[path = "support/world.rs"]
mod support;

use cellc_runtime::plan::{Goal, Placement};
use cellc_runtime::Executor;
use cellc_runtime::{
    Around, Cell, EndEffectorId, ExecuteOptions, ObjectId, PlanError, Whereabouts, WorldError,
};
use support::{document, options, recheck, vito};

/// The joints (as a JSON object by joint name) at which a verified arc's witness has `hand`
/// holding `object` with `grasp`: a configuration known to hold it inside a workspace.
fn arm_holding(cell: &Cell, object: &str, hand: &str, grasp: &str) -> String {
    let a = cell.artifact();
    let o = cell.object(object).unwrap();
    let e = cell.end_effector(hand).unwrap();
    let g = cell.grasp(o, e, grasp).unwrap();
    let graph = &a.objects[o.index()].graph;
    let q = graph
        .arcs
        .iter()
        .filter(|arc| {
            let n = graph.nodes[arc.to as usize];
            n.end_effector == e && n.grasp == g
        })
        .filter_map(|arc| graph.witnesses.get(arc.witness? as usize))
        .find_map(|w| w.configurations.iter().find(|c| c.end_effector == e))
        .expect("a witness of the hold")
        .joints
        .clone();
    let scene = cell.scene().unwrap();
    let cellc_runtime::scene::Holder::Arm { robot, .. } = &scene.holders[e.index()] else {
        panic!("{hand} is an arm");
    };
    let names = scene.robots[*robot].joint_names();
    let fields: Vec<String> = names
        .iter()
        .zip(&q)
        .map(|(n, v)| format!("\"{n}\": {v}"))
        .collect();
    format!("{{ {} }}", fields.join(", "))
}

#[test]
fn the_declared_world_has_three_objects_on_the_table() {
    let cell = vito();
    let world = cell.initial_world(&options(0)).expect("the declared world");
    let table = cell.end_effector("table").unwrap();
    for name in ["cylinder", "pitcher", "ball"] {
        let o = cell.object(name).unwrap();
        assert_eq!(
            world.state(o).map(|s| s.end_effector),
            Some(table),
            "{name}"
        );
        assert!(
            world.pose(cell.artifact(), cell.scene(), o).is_some(),
            "{name}"
        );
    }
    let scene = cell.scene().unwrap();
    let cylinder = cell.object("cylinder").unwrap();
    assert_eq!(world.obstacles(cell.artifact(), scene, cylinder).len(), 2);
}

#[test]
fn a_plan_from_a_non_home_joint_state_starts_exactly_there() {
    let cell = vito();
    let world = cell
        .world(
            &document(
                r#"{
                    "arms": { "left": { "lwr_a1_joint": 0.3, "lwr_a3_joint": -0.2 } },
                    "objects": { "cylinder": { "holder": "table", "at": [0.45, 0.45, 1.0] } }
                }"#,
            ),
            &options(0),
        )
        .expect("a valid world");
    let left = cell.end_effector("left").unwrap();
    let q = world.arm(left).expect("an arm").to_vec();
    assert!(
        (q[0] - 0.3).abs() < 1e-12 && (q[2] + 0.2).abs() < 1e-12,
        "{q:?}"
    );
    let cylinder = cell.object("cylinder").unwrap();
    let goal = Goal::Workspace {
        workspace: cell.workspace("ws_right_bin").unwrap(),
        holder: None,
    };
    let plan = cell
        .plan_move(&world, cylinder, &goal, &options(0))
        .expect("a plan");
    let first = plan
        .steps
        .iter()
        .filter_map(|s| s.motion.as_ref())
        .find(|t| t.arms.contains(&left))
        .expect("the left arm moves");
    let offset: usize = first
        .arms
        .iter()
        .take_while(|&&e| e != left)
        .map(|&e| world.arm(e).map_or(0, <[f64]>::len))
        .sum();
    assert_eq!(
        &first.points[0].positions[offset..offset + q.len()],
        q.as_slice()
    );
}

#[test]
fn an_object_in_hand_is_located_by_forward_kinematics() {
    let cell = vito();
    let arm = arm_holding(&cell, "cylinder", "left", "top");
    let world = cell
        .world(
            &document(&format!(
                r#"{{ "arms": {{ "left": {arm} }}, "objects": {{ "cylinder": {{ "holder": "left", "grasp": "top" }} }} }}"#
            )),
            &options(0),
        )
        .expect("held where a witness holds it");
    let cylinder = cell.object("cylinder").unwrap();
    let pose = world
        .pose(cell.artifact(), cell.scene(), cylinder)
        .expect("a held object has a pose");
    let p = pose.translation.vector;
    // Where the hand is at home, not at the origin or on the table.
    let json = format!(
        r#"{{ "arms": {{ "left": {arm} }}, "objects": {{ "cylinder": {{ "holder": "left", "grasp": "top", "at": [{}, {}, {}] }} }} }}"#,
        p.x, p.y, p.z
    );
    let again = cell
        .world(&document(&json), &options(0))
        .expect("the same pose agrees");
    assert_eq!(again.state(cylinder), world.state(cylinder));
    let off = format!(
        r#"{{ "arms": {{ "left": {arm} }}, "objects": {{ "cylinder": {{ "holder": "left", "grasp": "top", "at": [{}, {}, {}] }} }} }}"#,
        p.x + 0.05,
        p.y,
        p.z
    );
    match cell.world(&document(&off), &options(0)) {
        Err(WorldError::PoseDisagrees { position_error, .. }) => {
            assert!((position_error - 0.05).abs() < 1e-6, "{position_error}")
        }
        other => panic!("a pose 5 cm off is refused: {other:?}"),
    }
    // At home the hand is in no workspace: no state holds the object there.
    assert!(matches!(
        cell.world(
            &document(r#"{ "objects": { "cylinder": { "holder": "left", "grasp": "top" } } }"#),
            &options(0)
        ),
        Err(WorldError::Placement { .. })
    ));
}

#[test]
fn bad_documents_are_coded_errors() {
    let cell = vito();
    for (json, what) in [
        (r#"{ "arms": { "lefty": {} } }"#, "unknown arm"),
        (r#"{ "arms": { "table": {} } }"#, "not an arm"),
        (
            r#"{ "arms": { "left": { "elbow": 0.0 } } }"#,
            "unknown joint",
        ),
        (
            r#"{ "arms": { "left": { "lwr_a1_joint": 9.0 } } }"#,
            "out of limits",
        ),
        (
            r#"{ "objects": { "cup": { "holder": "table" } } }"#,
            "unknown object",
        ),
        (
            r#"{ "objects": { "ball": { "holder": "table", "grasp": "lying" } } }"#,
            "no pose",
        ),
        (
            r#"{ "objects": { "ball": { "holder": "table", "at": [0, 0, 0], "rpy": [0, 0, 0], "quat": [1, 0, 0, 0] } } }"#,
            "two orientations",
        ),
    ] {
        let got = cell.world(&document(json), &options(0));
        assert!(got.is_err(), "{what}: {got:?}");
    }
}

#[test]
fn a_goal_occupied_by_another_object_is_refused_and_names_it() {
    let cell = vito();
    let world = cell.initial_world(&options(0)).expect("the declared world");
    let cylinder = cell.object("cylinder").unwrap();
    let ball = cell.object("ball").unwrap();
    let at = world.pose(cell.artifact(), cell.scene(), ball).unwrap();
    // The cylinder standing (10 cm above the table top) where the ball lies.
    let goal = |x: f64| {
        Goal::Placement(Placement {
            holder: cell.end_effector("table").unwrap(),
            grasp: None,
            workspace: None,
            pose: Some(cellc_runtime::Iso::translation(x, at.translation.y, 1.0)),
        })
    };
    match cell.plan_move(&world, cylinder, &goal(at.translation.x), &options(0)) {
        Err(PlanError::GoalOccupied { by }) => assert_eq!(by, ball),
        other => panic!("the ball's place is taken: {other:?}"),
    }
    // 15 cm further along x it is free.
    assert!(!matches!(
        cell.plan_move(
            &world,
            cylinder,
            &goal(at.translation.x + 0.15),
            &options(0)
        ),
        Err(PlanError::GoalOccupied { .. })
    ));
}

#[test]
fn a_hand_that_holds_another_object_takes_no_part() {
    let cell = vito();
    let arm = arm_holding(&cell, "ball", "right", "power");
    let world = cell
        .world(
            &document(&format!(
                r#"{{ "arms": {{ "right": {arm} }}, "objects": {{
                    "ball": {{ "holder": "right", "grasp": "power" }},
                    "cylinder": {{ "holder": "table", "at": [0.45, 0.45, 1.0] }} }} }}"#
            )),
            &options(0),
        )
        .expect("a valid world");
    let right = cell.end_effector("right").unwrap();
    let cylinder = cell.object("cylinder").unwrap();
    let goal = Goal::Placement(Placement {
        holder: cell.end_effector("table").unwrap(),
        grasp: None,
        workspace: None,
        pose: Some(cellc_runtime::Iso::translation(0.4, -0.3, 1.0)),
    });
    match cell.plan_move(&world, cylinder, &goal, &options(0)) {
        Ok(plan) => assert!(
            plan.states.iter().all(|s| s.end_effector != right),
            "the right hand holds the ball: {:?}",
            plan.states
        ),
        Err(PlanError::Unreachable(u)) => assert!(u
            .failed
            .iter()
            .any(|(_, r)| matches!(r, cellc_schema::Infeasibility::HandBusy { .. }))),
        Err(other) => panic!("{other:?}"),
    }
}

#[test]
fn the_table_is_cleared_and_the_world_follows_the_simulator() {
    let cell = vito();
    let mut world = cell.initial_world(&options(0)).expect("the declared world");
    let task = cell.task("clear_table").expect("declared");
    assert_eq!(task.len(), 3);
    let mut checked = 0;
    let mut blocked = Vec::new();
    for (object, goal) in &task {
        let plan = cell
            .plan_move(&world, *object, goal, &options(0))
            .unwrap_or_else(|e| panic!("{}: {e:?}", cell.artifact().object_name(*object)));
        checked += recheck(&cell, &world, &plan);
        // Where the direct plan (the witnessed steps) ran into another object.
        for detour in &plan.detours {
            blocked.push((*object, detour.blocker.by, detour.around));
        }
        let mut simulator = cell.simulator(&world, &plan);
        let run = cell
            .execute(&mut world, plan, &mut simulator, &ExecuteOptions::default())
            .expect("executes");
        // The world is what the simulator reports.
        assert_eq!(world.state(*object), Some(run.final_state));
        for (e, q) in simulator.arms().into_iter().enumerate() {
            let e = EndEffectorId(e as u32);
            assert_eq!(q.as_deref(), world.arm(e), "the simulator's arm {e:?}");
        }
        assert_eq!(
            world
                .pose(cell.artifact(), cell.scene(), *object)
                .map(|p| p.translation),
            simulator.object_pose().map(|p| p.translation)
        );
    }
    assert!(checked >= 6, "only {checked} trajectories re-checked");
    // The cylinder's witnessed drop into the bin is where the ball lies by then: it is
    // put down elsewhere in the bin.
    let (cylinder, ball) = (
        cell.object("cylinder").unwrap(),
        cell.object("ball").unwrap(),
    );
    assert!(
        blocked.contains(&(cylinder, ball, Around::OtherPose)),
        "no move of the task went round another object: {blocked:?}"
    );
    // And the pitcher stands in the way of the cylinder's cheapest handoff: another path.
    let pitcher = cell.object("pitcher").unwrap();
    assert!(
        blocked.contains(&(cylinder, pitcher, Around::OtherPath)),
        "the pitcher blocked nothing: {blocked:?}"
    );
    let bin = cell.end_effector("bin").unwrap();
    for name in ["ball", "cylinder"] {
        let o: ObjectId = cell.object(name).unwrap();
        assert!(
            matches!(world.whereabouts(o), Whereabouts::Placed { state, .. } if state.end_effector == bin),
            "{name} is in the bin"
        );
    }
}
