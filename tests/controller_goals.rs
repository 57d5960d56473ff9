//! The request's timing options and the controller goals on a shipped cell, end to end:
//! `cellc plan --emit follow-joint-trajectory` is the plan document's motions, arm by arm,
//! with the robot's joint names; the scalings slow the motions down; the runtime refuses
//! an option out of range, and a rate with too many points, as the request's error.

use std::process::Command;

use cellc_driver::document::controller::ControllerGoals;
use cellc_driver::document::run::Run;
use cellc_driver::fs_files::FsFiles;
use cellc_runtime::motion::TimingOptions;
use cellc_runtime::plan::{PlanError, PlanOptions};
use cellc_runtime::{Cell, TaskOptions};

fn cellc(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_cellc"))
        .args(args)
        .output()
        .expect("cellc runs")
}

fn plans(args: &[&str]) -> Run {
    let out = cellc(&[args, &["--format", "json"]].concat());
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stdout)
    );
    serde_json::from_slice(&out.stdout).expect("a plan document")
}

#[test]
fn the_goals_are_the_plans_motions_arm_by_arm() {
    let task = [
        "plan",
        "cells/vito.cell",
        "--task",
        "clear_table",
        "--rate",
        "250",
    ];
    let run = plans(&task);
    let out = cellc(&[&task[..], &["--emit", "follow-joint-trajectory"]].concat());
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let emitted: ControllerGoals = serde_json::from_slice(&out.stdout).expect("goals");
    assert_eq!(emitted, ControllerGoals::of(&run.plans).expect("goals"));
    // The same bytes every time.
    let again = cellc(&[&task[..], &["--emit", "follow-joint-trajectory"]].concat());
    assert_eq!(again.stdout, out.stdout);

    let built = cellc_driver::build(&FsFiles, "cells/vito.cell", &Default::default());
    let artifact = built.artifact.expect("vito builds");
    assert_eq!(emitted.plans.len(), run.plans.len());
    let mut goals = 0;
    for (plan, with_goals) in run.plans.iter().zip(&emitted.plans) {
        assert_eq!(with_goals.request, plan.request);
        let mut next = with_goals.goals.iter();
        for (i, step) in plan.steps.iter().enumerate() {
            let Some(motion) = &step.motion else {
                continue;
            };
            let mut start = 0;
            for arm in &motion.arms {
                let goal = next.next().expect("a goal per arm per step");
                assert_eq!((goal.step, &goal.arm), (i, &arm.arm));
                let e = (0..artifact.end_effectors.len() as u32)
                    .map(cellc_schema::EndEffectorId)
                    .find(|&e| artifact.end_effector_name(e) == arm.arm)
                    .expect("an arm of the cell");
                let trajectory = &goal.goal.trajectory;
                assert_eq!(trajectory.joint_names, artifact.joint_names(e));
                let columns = start..start + arm.joints.len();
                start = columns.end;
                assert_eq!(trajectory.points.len(), motion.points.len());
                for (p, q) in trajectory.points.iter().zip(&motion.points) {
                    assert_eq!(p.positions, q.positions[columns.clone()]);
                    assert_eq!(p.velocities, q.velocities[columns.clone()]);
                    assert_eq!(p.accelerations, q.accelerations[columns.clone()]);
                    assert!(p.time_from_start.nanosec < 1_000_000_000);
                    let nanos = p.time_from_start.nanoseconds() as f64;
                    assert!((nanos - q.time_from_start * 1e9).abs() <= 1.0);
                }
                // 250 Hz: every point 4 ms after the one before, the goal at the end.
                let times: Vec<i64> = trajectory
                    .points
                    .iter()
                    .map(|p| p.time_from_start.nanoseconds())
                    .collect();
                let gaps: Vec<i64> = times.windows(2).map(|w| w[1] - w[0]).collect();
                let (last, before) = gaps.split_last().expect("points");
                assert!(before.iter().all(|&g| g == 4_000_000), "{gaps:?}");
                assert!((1..=4_000_000).contains(last), "{gaps:?}");
                goals += 1;
            }
        }
        assert!(next.next().is_none(), "a goal of no step");
    }
    assert!(goals >= 6, "{goals} goals");
}

#[test]
fn scalings_given_on_the_command_line_slow_every_motion() {
    let request = ["plan", "cells/vito.cell", "--request", "handoff_cylinder"];
    let fast = plans(&request);
    let slow = plans(
        &[
            &request[..],
            &[
                "--velocity-scaling",
                "0.5",
                "--acceleration-scaling",
                "0.25",
            ],
        ]
        .concat(),
    );
    let duration = |m: &cellc_driver::document::plan::Trajectory| {
        m.points.last().map_or(0.0, |p| p.time_from_start)
    };
    let mut motions = 0;
    for (a, b) in fast.plans[0].steps.iter().zip(&slow.plans[0].steps) {
        if let (Some(a), Some(b)) = (&a.motion, &b.motion) {
            // At least half the speed and a quarter of the acceleration: at least 1.5x
            // as long whichever limit binds.
            assert!(
                duration(b) > 1.5 * duration(a),
                "{} {}",
                duration(a),
                duration(b)
            );
            motions += 1;
        }
    }
    assert!(motions >= 4, "{motions}");
}

fn vito() -> Cell {
    let built = cellc_driver::build(&FsFiles, "cells/vito.cell", &Default::default());
    Cell::from_artifact(built.artifact.expect("builds"), &FsFiles).expect("loads")
}

fn timed(velocity_scaling: f64, acceleration_scaling: f64, rate: Option<f64>) -> PlanOptions {
    PlanOptions {
        timing: TimingOptions {
            velocity_scaling,
            acceleration_scaling,
            rate,
        },
        ..PlanOptions::default()
    }
}

#[test]
fn the_runtime_refuses_options_out_of_range_as_the_requests_error() {
    let cell = vito();
    let plan = |options: PlanOptions| {
        let request = cell
            .named_request("handoff_cylinder", options)
            .expect("declared");
        cell.plan(&cell.home_world(), &request)
    };
    for (options, name, value) in [
        (timed(0.0, 1.0, None), "velocity_scaling", 0.0),
        (timed(1.0, 1.5, None), "acceleration_scaling", 1.5),
        (timed(1.0, 1.0, Some(0.0)), "rate", 0.0),
        (timed(1.0, 1.0, Some(1000.5)), "rate", 1000.5),
        // In range, but a minute at a kilohertz is exceeded by a thousandfold slower motion.
        (timed(0.001, 0.001, Some(1000.0)), "rate", 1000.0),
    ] {
        match plan(options) {
            Err(PlanError::InvalidOption { name: n, value: v }) => {
                assert_eq!((n, v), (name, value));
            }
            other => panic!("{name} {value}: {other:?}"),
        }
    }
    match plan(timed(f64::NAN, 1.0, None)) {
        Err(PlanError::InvalidOption { name, value }) => {
            assert!(name == "velocity_scaling" && value.is_nan());
        }
        other => panic!("NaN: {other:?}"),
    }
    // A task stops at its first move, with that error, having planned nothing.
    let moves = cell.task("clear_table").expect("declared");
    let world = cell
        .initial_world(&PlanOptions::default())
        .expect("the world");
    let options = TaskOptions {
        plan: timed(0.001, 0.001, Some(1000.0)),
        ..TaskOptions::default()
    };
    let planned = cell.plan_task(&world, &moves, &options);
    let failure = planned.failure.expect("refused");
    assert_eq!(failure.index, 0);
    assert!(planned.plans.is_empty());
    assert!(matches!(
        failure.error,
        cellc_runtime::TaskError::Plan(PlanError::InvalidOption { name: "rate", .. })
    ));
}
