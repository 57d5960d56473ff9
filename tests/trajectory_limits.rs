//! Every shipped cell's trajectories, held to each joint's limits by finite differences:
//! speeds between consecutive points within 1% of the joint's velocity limit, the change
//! of the points' velocities within 5% of its acceleration limit (the profile imposes the
//! limits at the knots; on an arc the acceleration turns in between), the change of the
//! points' accelerations within 1% of a declared jerk limit, and the velocities the
//! points carry within 2% of the limit of what their positions' differences say. The
//! limits are the artifact's, as the compiler resolved them, scaled as the request asks.

use cellc_driver::fs_files::FsFiles;
use cellc_runtime::motion::TimingOptions;
use cellc_runtime::plan::{PlanOptions, Trajectory};
use cellc_runtime::Cell;
use cellc_schema::{Artifact, Body};

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

/// Per joint of `t`, in its order: velocity, acceleration and jerk limits.
fn limits(artifact: &Artifact, t: &Trajectory) -> Vec<(f64, f64, Option<f64>)> {
    let mut out = Vec::new();
    for e in &t.arms {
        let Body::Arm { robot, .. } = &artifact.end_effectors[e.index()].body else {
            panic!("a trajectory of a surface");
        };
        for j in &artifact.robots[*robot as usize].joints {
            out.push((j.velocity, j.acceleration, j.jerk));
        }
    }
    out
}

/// The worst share of each limit the trajectory uses: (speed, acceleration, jerk, how far
/// the carried velocities are from the differences), as fractions of the limits.
fn worst(t: &Trajectory, limits: &[(f64, f64, Option<f64>)], scale: (f64, f64)) -> [f64; 4] {
    let mut w = [0.0_f64; 4];
    for pair in t.points.windows(2) {
        let (a, b) = (&pair[0], &pair[1]);
        let dt = b.time - a.time;
        assert!(dt > 0.0, "times increase");
        for (j, &(v, acc, jerk)) in limits.iter().enumerate() {
            let (v, acc) = (v * scale.0, acc * scale.1);
            let speed = (b.positions[j] - a.positions[j]) / dt;
            w[0] = w[0].max(speed.abs() / v);
            w[1] = w[1].max((b.velocities[j] - a.velocities[j]).abs() / dt / acc);
            if let Some(jerk) = jerk {
                let jerk = jerk * scale.1;
                w[2] = w[2].max((b.accelerations[j] - a.accelerations[j]).abs() / dt / jerk);
            }
            let carried = 0.5 * (a.velocities[j] + b.velocities[j]);
            w[3] = w[3].max((carried - speed).abs() / v);
        }
    }
    w
}

fn check(scale: (f64, f64)) {
    let mut motions = 0;
    let mut jerk_limited = 0;
    let mut peak: f64 = 0.0;
    for path in CELLS {
        let cell = cell(path);
        for named in &cell.artifact().requests {
            let options = PlanOptions {
                seed: 1,
                timing: TimingOptions {
                    velocity_scaling: scale.0,
                    acceleration_scaling: scale.1,
                    rate: None,
                },
                ..PlanOptions::default()
            };
            let request = cell.named_request(&named.name, options).expect("declared");
            let plan = cell
                .plan(&cell.home_world(), &request)
                .unwrap_or_else(|e| panic!("{path} {}: {e:?}", named.name));
            for t in plan.steps.iter().filter_map(|s| s.motion.as_ref()) {
                if t.points.len() < 2 {
                    continue;
                }
                let limits = limits(cell.artifact(), t);
                let w = worst(t, &limits, scale);
                let at = format!("{path} {}", named.name);
                assert!(
                    w[0] <= 1.01,
                    "{at}: a joint at {:.4} of its speed limit",
                    w[0]
                );
                assert!(w[1] <= 1.05, "{at}: {:.4} of an acceleration limit", w[1]);
                assert!(w[2] <= 1.01, "{at}: {:.4} of a jerk limit", w[2]);
                assert!(
                    w[3] <= 0.02,
                    "{at}: velocities {:.4} off the positions",
                    w[3]
                );
                motions += 1;
                jerk_limited += usize::from(limits.iter().any(|l| l.2.is_some()));
                peak = peak.max(w[0].max(w[1]));
            }
        }
    }
    assert!(motions >= 40, "only {motions} motions checked");
    assert!(
        jerk_limited >= 5,
        "only {jerk_limited} motions with jerk limits"
    );
    // Time-optimal: some joint of some motion runs at its limit.
    assert!(peak >= 0.95, "no motion comes near its limits ({peak:.3})");
}

#[test]
fn every_shipped_trajectory_is_within_its_joints_limits() {
    check((1.0, 1.0));
}

#[test]
fn scaled_requests_are_within_the_scaled_limits() {
    check((0.5, 0.25));
}

#[test]
fn a_rate_gives_points_at_that_rate() {
    let cell = cell("cells/two_pandas.cell");
    let named = &cell.artifact().requests[0];
    let timed = |rate| PlanOptions {
        seed: 1,
        timing: TimingOptions {
            rate,
            ..TimingOptions::default()
        },
        ..PlanOptions::default()
    };
    let plan = |rate| {
        let request = cell
            .named_request(&named.name, timed(rate))
            .expect("declared");
        cell.plan(&cell.home_world(), &request).expect("plans")
    };
    let (knots, sampled) = (plan(None), plan(Some(250.0)));
    let mut motions = 0;
    for (a, b) in knots.steps.iter().zip(&sampled.steps) {
        let (Some(a), Some(b)) = (&a.motion, &b.motion) else {
            continue;
        };
        let (ta, tb) = (a.points.last().unwrap(), b.points.last().unwrap());
        // The same motion, the same duration and goal, sampled every 4 ms.
        assert!((ta.time - tb.time).abs() < 1e-9);
        assert_eq!(ta.positions, tb.positions);
        for (k, p) in b.points[..b.points.len() - 1].iter().enumerate() {
            assert!(
                (p.time - k as f64 / 250.0).abs() < 1e-9,
                "point {k} at {}",
                p.time
            );
        }
        assert!(b.points.len() as f64 >= tb.time * 250.0);
        motions += 1;
    }
    assert!(motions >= 2, "{motions} motions compared");
}
