//! Requests in a world, and the machine-readable results of `cellc plan` and `cellc run`.
//!
//! A request whose object starts in a hand used to plan its first motion from the arm's
//! home, with the object somewhere else: the plan must start where the hand really holds
//! the object. And `--format json` must give a document on every path, success and
//! failure, whose trajectories name every joint next to its value.

use std::process::Command;

use cellc_runtime::plan::{Command as PlanCommand, PlanOptions};

#[path = "support/world.rs"]
mod support;
use support::vito;

fn cellc(args: &[&str]) -> (bool, serde_json::Value) {
    let out = Command::new(env!("CARGO_BIN_EXE_cellc"))
        .args(args)
        .output()
        .expect("cellc runs");
    let text = String::from_utf8_lossy(&out.stdout);
    let value = serde_json::from_str(&text).unwrap_or_else(|e| panic!("{args:?}: {e}\n{text}"));
    (out.status.success(), value)
}

/// `single_arm_regrasp` starts with the cylinder in the left hand (`left.top in
/// ws_left_table`): the left arm's first motion starts at joints whose forward kinematics
/// put the hand where it holds the cylinder at the plan's start pose, not at home.
#[test]
fn a_request_that_starts_in_hand_starts_where_the_hand_holds_it() {
    let cell = vito();
    for name in ["single_arm_regrasp", "dual_arm_regrasp"] {
        let request = cell
            .named_request(name, PlanOptions::default())
            .expect("declared");
        let mut world = cell
            .request_world(&cell.home_world(), &request)
            .expect("a start");
        let plan = cell
            .plan_move(&world, request.object, &request.goal, &request.options)
            .expect("a plan");
        let left = cell.end_effector("left").unwrap();
        let start = plan.start_arms[left.index()].clone().expect("an arm");
        let scene = cell.scene().unwrap();
        let cellc_runtime::scene::Holder::Arm { robot, base, home } = &scene.holders[left.index()]
        else {
            panic!("left is an arm");
        };
        assert!(
            start.iter().zip(home).any(|(a, b)| (a - b).abs() > 1e-3),
            "{name}: the left arm starts at home"
        );
        // The hand's pose at the start joints, times the grasp, is the object's start pose.
        let grasp = cell
            .artifact()
            .grasp_pose(plan.object, plan.states[0].grasp);
        let held = scene.robots[*robot].tip_pose(base, &start) * grasp;
        let given = plan.start_pose.expect("a start pose");
        let error = (held.translation.vector - given.translation.vector).norm();
        assert!(error < 1e-6, "{name}: the hand holds it {error} m away");
        // The first motion of the left arm begins exactly there.
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
            .map(|&e| plan.start_arms[e.index()].as_ref().map_or(0, Vec::len))
            .sum();
        assert_eq!(
            &first.points[0].positions[offset..offset + start.len()],
            start.as_slice(),
            "{name}"
        );
        // And the simulator agrees: executing it ends where the goal says.
        let mut simulator = cell.simulator(&world, &plan);
        cell.execute(&mut world, plan, &mut simulator, &Default::default())
            .unwrap_or_else(|e| panic!("{name}: {e}"));
    }
}

/// A hand start the hand cannot hold (out of reach, or the cylinder sunk into the table)
/// is a coded error naming the hand, not a plan that starts from home; one it can hold
/// plans.
#[test]
fn a_hand_start_the_hand_cannot_hold_is_refused() {
    for (at, holds) in [
        ("(1.5, 1.5, 1.0)", false),
        ("(0.45, 0.45, 0.9)", false),
        ("(0.4, 0.3, 1.1)", true),
    ] {
        let from = format!("left.top at {at}");
        let (ok, doc) = cellc(&[
            "plan",
            "cells/vito.cell",
            "--object",
            "cylinder",
            "--from",
            &from,
            "--to",
            "table.standing in ws_right_table",
            "--no-motions",
            "--format",
            "json",
        ]);
        assert_eq!(ok, holds, "{at}: {doc}");
        if !holds {
            assert_eq!(doc["diagnostics"][0]["code"], "R0009", "{at}: {doc}");
            let message = doc["diagnostics"][0]["message"].as_str().unwrap();
            assert!(message.contains("`left`"), "{message}");
        }
    }
}

/// Every trajectory point has one position per named joint, and the names are the arm's
/// URDF joints; configurations too.
fn check_joint_names(plan: &serde_json::Value) -> usize {
    let mut points = 0;
    for step in plan["steps"].as_array().expect("steps") {
        for c in step["configurations"].as_array().expect("configurations") {
            let names = c["joints"].as_array().expect("names");
            assert_eq!(names.len(), c["positions"].as_array().unwrap().len());
            assert!(names
                .iter()
                .all(|n| n.as_str().unwrap().starts_with("lwr_a")));
        }
        let Some(motion) = step["motion"].as_object() else {
            continue;
        };
        let width: usize = motion["arms"]
            .as_array()
            .unwrap()
            .iter()
            .map(|a| a["joints"].as_array().unwrap().len())
            .sum();
        assert!(width > 0);
        for p in motion["points"].as_array().unwrap() {
            assert_eq!(p["positions"].as_array().unwrap().len(), width);
            points += 1;
        }
    }
    points
}

#[test]
fn plan_and_run_give_json_on_success_with_joint_names() {
    let (ok, doc) = cellc(&[
        "plan",
        "cells/vito.cell",
        "--request",
        "trash",
        "--format",
        "json",
    ]);
    assert!(ok, "{doc}");
    assert_eq!(doc["kind"], "plan");
    assert_eq!(doc["errors"], 0);
    assert!(check_joint_names(&doc["plans"][0]) > 10);

    let (ok, doc) = cellc(&[
        "run",
        "cells/vito.cell",
        "--task",
        "clear_table",
        "--format",
        "json",
        "--no-motions",
    ]);
    assert!(ok, "{doc}");
    assert_eq!(doc["kind"], "run");
    let moves = doc["moves"].as_array().expect("moves");
    assert_eq!(moves.len(), 3);
    assert!(moves.iter().all(|m| m["done"] == true));
    // The world at the end has the ball and the cylinder in the bin.
    let objects = doc["world"]["objects"].as_array().expect("objects");
    for name in ["ball", "cylinder"] {
        let o = objects.iter().find(|o| o["object"] == name).expect(name);
        assert_eq!(o["state"]["end_effector"], "bin", "{name}: {o}");
    }
    // Every arm of the world is listed with its joint names.
    for arm in doc["world"]["arms"].as_array().expect("arms") {
        assert_eq!(
            arm["joints"].as_array().unwrap().len(),
            arm["positions"].as_array().unwrap().len()
        );
    }
}

/// A run that fails part way is still one JSON document: the moves carried out, the world
/// as it is, and the diagnostic with its code.
#[test]
fn a_failing_run_is_json_with_the_world_as_it_is() {
    let (ok, doc) = cellc(&[
        "run",
        "cells/vito.cell",
        "--move",
        "ball to bin in ws_right_bin",
        "--move",
        // Where the cylinder stands: refused, naming it.
        "ball to table at (0.45, 0.45, 0.95)",
        "--format",
        "json",
        "--no-motions",
    ]);
    assert!(!ok, "{doc}");
    assert_eq!(doc["ok"], false);
    let moves = doc["moves"].as_array().expect("moves");
    assert_eq!(moves.len(), 1, "the second move has no plan");
    assert_eq!(moves[0]["done"], true);
    let ball = doc["world"]["objects"]
        .as_array()
        .unwrap()
        .iter()
        .find(|o| o["object"] == "ball")
        .expect("ball")
        .clone();
    assert_eq!(
        ball["state"]["end_effector"], "bin",
        "moved so far stays moved"
    );
    assert_eq!(doc["diagnostics"][0]["code"], "R0010", "{doc}");
    let message = doc["diagnostics"][0]["message"].as_str().unwrap();
    assert!(message.contains("`cylinder`"), "{message}");
}

/// Commands in a plan's JSON follow the plan: a grasp names its grasp, an ungrasp has no
/// configuration.
#[test]
fn plan_json_commands_follow_the_plan() {
    let cell = vito();
    let request = cell
        .named_request("handoff_cylinder", PlanOptions::default())
        .unwrap();
    let plan = cell.plan(&cell.home_world(), &request).unwrap();
    let (_, doc) = cellc(&[
        "plan",
        "cells/vito.cell",
        "--request",
        "handoff_cylinder",
        "--format",
        "json",
    ]);
    let steps = doc["plans"][0]["steps"].as_array().unwrap();
    assert_eq!(steps.len(), plan.steps.len());
    for (json, step) in steps.iter().zip(&plan.steps) {
        let expected = match step.command {
            PlanCommand::Move { .. } => "move",
            PlanCommand::Grasp { .. } => "grasp",
            PlanCommand::Ungrasp { .. } => "ungrasp",
        };
        assert_eq!(json["command"], expected);
    }
}

/// `cellc info` lists the cell's world and tasks (the moves in order).
#[test]
fn info_lists_the_world_and_the_tasks() {
    let out = Command::new(env!("CARGO_BIN_EXE_cellc"))
        .args(["info", "cells/vito.cell"])
        .output()
        .expect("cellc runs");
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    let cell = vito();
    let a = cell.artifact();
    assert!(
        text.contains(&format!("world ({} objects)", a.world.len())),
        "{text}"
    );
    for p in &a.world {
        let line = format!("  {}: {}", a.object_name(p.object), "table at (");
        assert!(text.contains(&line), "{line} in\n{text}");
    }
    let task = &a.tasks[0];
    let header = format!("  {} ({} moves):", task.name, task.steps.len());
    let at = text
        .find(&header)
        .unwrap_or_else(|| panic!("{header} in\n{text}"));
    let listed: Vec<&str> = text[at..].lines().skip(1).take(task.steps.len()).collect();
    for (line, step) in listed.iter().zip(&task.steps) {
        assert!(
            line.trim_start()
                .starts_with(&format!("{} to ", a.object_name(step.object))),
            "{line}"
        );
    }
}

/// The ball stands where `handoff_cylinder` puts the cylinder: refused with R0010 naming
/// it; with `--clear`, `cellc run` first moves the ball to a free place, then the cylinder
/// to its goal, and the JSON shows both moves.
#[test]
fn clear_moves_the_object_in_the_way_first() {
    let world = "tests/ui/cli/support/goal_taken_world.json";
    let base = [
        "run",
        "cells/vito.cell",
        "--request",
        "handoff_cylinder",
        "--world",
        world,
        "--no-motions",
        "--format",
        "json",
    ];
    let (ok, doc) = cellc(&base);
    assert!(!ok);
    assert_eq!(doc["diagnostics"][0]["code"], "R0010", "{doc}");
    assert!(doc["diagnostics"][0]["message"]
        .as_str()
        .unwrap()
        .contains("`ball`"));

    let mut args = base.to_vec();
    args.push("--clear");
    let (ok, doc) = cellc(&args);
    assert!(ok, "{doc}");
    let moves = doc["moves"].as_array().expect("moves");
    assert_eq!(moves.len(), 2, "{doc}");
    assert_eq!(moves[0]["object"], "ball");
    assert_eq!(moves[0]["clears"], "cylinder");
    assert_eq!(moves[1]["object"], "cylinder");
    assert!(moves.iter().all(|m| m["done"] == true));
    assert!(moves[1]["position_error"].as_f64().unwrap() < 1e-3);
    // The ball left the goal: its footprint (5 cm) and the cylinder's (4 cm) are apart.
    let pose = |name: &str| {
        let o = doc["world"]["objects"]
            .as_array()
            .unwrap()
            .iter()
            .find(|o| o["object"] == name)
            .unwrap()
            .clone();
        let p = o["pose"]["position"].as_array().unwrap().clone();
        (p[0].as_f64().unwrap(), p[1].as_f64().unwrap())
    };
    let (b, c) = (pose("ball"), pose("cylinder"));
    let d = ((b.0 - c.0).powi(2) + (b.1 - c.1).powi(2)).sqrt();
    assert!(d > 0.09, "ball {b:?}, cylinder {c:?}");
    assert!(
        (c.0 - 0.4).abs() < 1e-3 && (c.1 + 0.3).abs() < 1e-3,
        "{c:?}"
    );
}

/// The task API: `plan_task` plans `clear_table` ahead (each move in the world the plans
/// before it leave) and `run_task` carries it out in the simulator; both end with every
/// object in the same state. A task whose second move has no plan stops there with its
/// index, the first move done and kept in the world.
#[test]
fn tasks_are_planned_ahead_and_run_and_stop_at_the_failing_move() {
    use cellc_runtime::{TaskError, TaskOptions, Whereabouts};
    let cell = vito();
    let options = TaskOptions::default();
    let start = cell
        .initial_world(&options.plan)
        .expect("the declared world");
    let task = cell.task("clear_table").expect("declared");
    let planned = cell.plan_task(&start, &task, &options);
    assert!(planned.failure.is_none());
    assert_eq!(planned.plans.len(), 3);
    let ahead = planned.world;
    let mut world = start.clone();
    let run = cell.run_task(&mut world, &task, &options);
    assert!(run.failure.is_none());
    let record = run.record;
    assert_eq!(record.len(), 3);
    assert!(record
        .iter()
        .all(|e| e.result.is_ok() && e.clears.is_none()));
    for (i, _) in cell.artifact().objects.iter().enumerate() {
        let o = cellc_runtime::ObjectId(i as u32);
        assert_eq!(ahead.state(o), world.state(o), "object {i}");
    }

    let ball = cell.object("ball").unwrap();
    let taken = cellc_runtime::plan::Goal::Placement(cellc_runtime::plan::Placement {
        holder: cell.end_effector("table").unwrap(),
        grasp: None,
        workspace: None,
        // Where the cylinder stands.
        pose: Some(cellc_runtime::Iso::translation(0.45, 0.45, 0.95)),
    });
    let moves = vec![task[0].clone(), (ball, taken)];
    let mut world = start.clone();
    let run = cell.run_task(&mut world, &moves, &options);
    let (record, failure) = (
        run.record,
        run.failure.expect("the second move's goal is taken"),
    );
    assert_eq!(failure.index, 1);
    assert!(matches!(
        failure.error,
        TaskError::Plan(cellc_runtime::PlanError::GoalOccupied { .. })
    ));
    assert_eq!(record.len(), 1);
    let bin = cell.end_effector("bin").unwrap();
    assert!(
        matches!(world.whereabouts(ball), Whereabouts::Placed { state, .. } if state.end_effector == bin),
        "the ball stays in the bin"
    );
}
