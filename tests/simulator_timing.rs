//! The kinematic simulator plays every motion by time, as a joint-trajectory controller
//! does, and holds each instant to the joints' limits: every shipped cell's plans play
//! within them (at the knots and at a control rate) with the simulator's clock equal to
//! the plans' motion time, and the same plans made faster, pushed past a joint's range or
//! given a wrong acceleration are refused, each with what broke and when.

use cellc_driver::fs_files::FsFiles;
use cellc_runtime::motion::TimingOptions;
use cellc_runtime::plan::{Plan, PlanOptions};
use cellc_runtime::{Cell, ExecuteOptions, ExecutionError, Quantity, StepError};
use cellc_schema::Body;

/// The shipped cells with robots and requests.
const CELLS: [&str; 6] = [
    "cells/vito.cell",
    "cells/two_pandas.cell",
    "cells/panda_cage.cell",
    "cells/ur_shelf.cell",
    "cells/assembly_line.cell",
    "cells/vito_full.cell",
];

fn cell(path: &str) -> Cell {
    let built = cellc_driver::build(&FsFiles, path, &Default::default());
    Cell::from_artifact(built.artifact.expect("builds"), &FsFiles).expect("loads")
}

fn options(rate: Option<f64>) -> PlanOptions {
    PlanOptions {
        seed: 1,
        timing: TimingOptions {
            rate,
            ..TimingOptions::default()
        },
        ..PlanOptions::default()
    }
}

fn once() -> ExecuteOptions {
    ExecuteOptions {
        max_replans: 0,
        ..ExecuteOptions::default()
    }
}

/// Plans request `name` of `cell` and executes it once in the simulator: the simulator's
/// clock, or the failure.
fn run(
    cell: &Cell,
    name: &str,
    rate: Option<f64>,
    edit: impl Fn(&mut Plan),
) -> Result<f64, StepError> {
    let request = cell.named_request(name, options(rate)).expect("declared");
    let start = cell
        .request_world(&cell.home_world(), &request)
        .expect("a start");
    let mut plan = cell
        .plan_move(&start, request.object, &request.goal, &request.options)
        .unwrap_or_else(|e| panic!("{name}: {e:?}"));
    edit(&mut plan);
    let mut simulator = cell.simulator(&start, &plan);
    let expected: f64 = plan
        .steps
        .iter()
        .filter_map(|s| s.motion.as_ref())
        .filter_map(|t| Some(t.points.last()?.time - t.points.first()?.time))
        .sum();
    match cell.execute(&mut start.clone(), plan, &mut simulator, &once()) {
        Ok(_) => {
            let clock = simulator.motion_time();
            assert!(
                (clock - expected).abs() < 1e-9,
                "{name}: the clock says {clock} s, the motions last {expected} s"
            );
            Ok(clock)
        }
        Err(ExecutionError::FailedAtStart { error })
        | Err(ExecutionError::TooManyFailures { last: error, .. }) => Err(error),
        Err(e) => panic!("{name}: {e:?}"),
    }
}

#[test]
fn every_shipped_plan_plays_within_its_joints_limits_at_the_knots_and_at_a_rate() {
    let mut played = 0;
    for path in CELLS {
        let cell = cell(path);
        for named in &cell.artifact().requests {
            for rate in [None, Some(250.0)] {
                let clock = run(&cell, &named.name, rate, |_| {})
                    .unwrap_or_else(|e| panic!("{path} {} at {rate:?}: {e}", named.name));
                assert!(clock > 0.0, "{path} {}: no motion played", named.name);
                played += 1;
            }
        }
    }
    assert!(played >= 30, "only {played} runs");
}

/// The Vito handoff with every motion played in `k` of its time, the velocities and
/// accelerations its points state scaled to match (so the points stay a consistent
/// trajectory, only faster).
fn faster(k: f64) -> impl Fn(&mut Plan) {
    move |plan: &mut Plan| {
        for t in plan.steps.iter_mut().filter_map(|s| s.motion.as_mut()) {
            for p in &mut t.points {
                p.time *= k;
                p.velocities.iter_mut().for_each(|v| *v /= k);
                p.accelerations.iter_mut().for_each(|a| *a /= k * k);
            }
        }
    }
}

#[test]
fn a_plan_played_faster_than_its_joints_allow_is_refused_with_the_joint_and_the_time() {
    let cell = cell("cells/vito.cell");
    // Within its limits at the planned speed...
    run(&cell, "handoff_cylinder", None, faster(1.0)).expect("plays as planned");
    // ...and over them at 1.25 times that speed: 1.56 times the accelerations.
    let error = run(&cell, "handoff_cylinder", None, faster(0.8)).expect_err("too fast");
    // What docs/world.md quotes.
    eprintln!("{error}");
    let StepError::LimitExceeded {
        arm,
        joint,
        quantity,
        value,
        limit,
        time,
    } = &error
    else {
        panic!("{error:?}");
    };
    assert!(matches!(
        quantity,
        Quantity::Velocity | Quantity::Acceleration
    ));
    assert!(value.abs() > 1.05 * limit, "{value} against {limit}");
    assert!(*time >= 0.0);
    let artifact = cell.artifact();
    let Body::Arm { robot, .. } = &artifact.end_effectors[arm.index()].body else {
        panic!("not an arm");
    };
    let joints = &artifact.robots[*robot as usize].joints;
    let declared = joints
        .iter()
        .find(|j| &j.name == joint)
        .expect("a joint of the arm");
    let bound = match quantity {
        Quantity::Velocity => declared.velocity,
        _ => declared.acceleration,
    };
    assert_eq!(*limit, bound, "the limit is the joint's own");
}

#[test]
fn a_motion_past_a_joints_range_or_with_a_wrong_acceleration_is_refused() {
    let cell = cell("cells/two_pandas.cell");
    // The first motion's first joint pushed past its upper limit for the whole motion.
    let past = |plan: &mut Plan| {
        let t = plan
            .steps
            .iter_mut()
            .find_map(|s| s.motion.as_mut())
            .expect("a motion");
        for p in &mut t.points {
            p.positions[0] += 10.0;
        }
    };
    match run(&cell, "handoff", None, past) {
        Err(StepError::LimitExceeded {
            quantity: Quantity::Position,
            time,
            ..
        }) => assert_eq!(time, 0.0),
        other => panic!("{other:?}"),
    }
    // A point in the middle of the first motion states the opposite of the acceleration
    // it has.
    let flipped = |plan: &mut Plan| {
        let t = plan
            .steps
            .iter_mut()
            .find_map(|s| s.motion.as_mut())
            .expect("a motion");
        // Where the steps on both sides accelerate that joint the same way, strongly.
        let a = |i: usize, j: usize| t.points[i].accelerations[j];
        let (i, j) = (1..t.points.len() - 1)
            .flat_map(|i| (0..t.points[i].accelerations.len()).map(move |j| (i, j)))
            .max_by(|&(i, j), &(k, l)| {
                let steady = |i: usize, j: usize| {
                    let (x, y, z) = (a(i - 1, j), a(i, j), a(i + 1, j));
                    if x * y > 0.0 && y * z > 0.0 {
                        x.abs().min(y.abs()).min(z.abs())
                    } else {
                        0.0
                    }
                };
                steady(i, j).total_cmp(&steady(k, l))
            })
            .expect("points");
        assert!(a(i, j).abs() > 0.5, "no steady acceleration to flip");
        t.points[i].accelerations[j] *= -1.0;
    };
    match run(&cell, "handoff", None, flipped) {
        Err(StepError::LimitExceeded {
            quantity: Quantity::StatedAcceleration,
            ..
        }) => {}
        other => panic!("{other:?}"),
    }
    // Times that go back.
    let back = |plan: &mut Plan| {
        let t = plan
            .steps
            .iter_mut()
            .find_map(|s| s.motion.as_mut())
            .expect("a motion");
        t.points[2].time = t.points[1].time;
    };
    assert_eq!(
        run(&cell, "handoff", None, back),
        Err(StepError::MalformedTrajectory { point: 2 })
    );
}
