//! What a planned trajectory is beyond its path: timed within the limits, the same for the
//! same seed, one point when there is nothing to do, and an error for a malformed problem.

use cellc_runtime::math::Iso;
use cellc_runtime::motion::{Joints, MotionError, MotionOptions, TimingOptions};
use cellc_runtime::scene::ObjectPlacement;
use cellc_runtime::EndEffectorId;
use cellc_runtime::Termination;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use super::{down, max_diff, plan, problem, scene, swap, ARM, FACING, PILLAR};
use cellc_runtime::plan::TrajectoryPoint;

/// The fixture's joints have the defaults' 1 rad/s and 2 rad/s² (`motion_fixture.rs`).
const SLOW: TimingOptions = TimingOptions {
    velocity_scaling: 0.3,
    acceleration_scaling: 0.25,
    rate: None,
};

#[test]
fn timing_is_monotonic_and_within_scaled_limits() {
    let scene = scene(&[ARM], &[PILLAR]);
    let p = problem(
        &scene,
        vec![0],
        down(ARM.1, [0.5, -0.35, 0.35]),
        down(ARM.1, [0.5, 0.35, 0.35]),
    );
    let options = MotionOptions::default();
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let t = p.solve_timed(&options, SLOW, &mut rng).expect("a path");
    // Finite differences of the points: speeds within 0.3 rad/s, and the velocities the
    // points carry agree with them.
    let (mut peak, mut peak_accel): (f64, f64) = (0.0, 0.0);
    for pair in t.points.windows(2) {
        let (a, b) = (&pair[0], &pair[1]);
        assert!(b.time > a.time);
        let dt = b.time - a.time;
        peak = peak.max(max_diff(&a.positions, &b.positions) / dt);
        peak_accel = peak_accel.max(max_diff(&a.velocities, &b.velocities) / dt);
    }
    assert!(peak <= 0.3 * 1.01, "peak speed {peak}");
    assert!(peak_accel <= 0.5 * 1.05, "peak acceleration {peak_accel}");
    assert!(
        peak >= 0.3 * 0.5,
        "peak speed {peak}: nowhere near the limit"
    );
    // No joint can go faster than its limit, so the motion takes at least its largest
    // joint travel over that.
    let total = t.points[t.points.len() - 1].time;
    let travelled: f64 = t
        .points
        .windows(2)
        .map(|w| max_diff(&w[0].positions, &w[1].positions))
        .sum();
    assert!(total >= travelled / 0.3, "{total} s for {travelled} rad");
    // The same motion at the full limits is faster.
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let fast = p
        .solve_timed(&options, TimingOptions::default(), &mut rng)
        .expect("a path");
    assert!(fast.points[fast.points.len() - 1].time < total);
}

#[test]
fn same_seed_same_trajectory() {
    let scene = scene(&FACING, &[]);
    let p = swap(&scene);
    let a = plan(&p, 11).expect("a path");
    let b = plan(&p, 11).expect("a path");
    assert_eq!(a, b);
}

#[test]
fn equal_start_and_goal_is_one_point() {
    let scene = scene(&[ARM], &[]);
    let q = down(ARM.1, [0.5, 0.0, 0.4]);
    let t = plan(&problem(&scene, vec![0], q.clone(), q.clone()), 0).expect("no motion");
    assert_eq!(t.points, vec![TrajectoryPoint::at_rest(0.0, &q)]);
}

#[test]
fn malformed_problems_are_errors() {
    let scene = scene(&[ARM], &[PILLAR]);
    let q = down(ARM.1, [0.5, -0.35, 0.35]);
    let short = q[..6].to_vec();
    assert!(matches!(
        plan(&problem(&scene, vec![0], short, q.clone()), 0),
        Err(MotionError::WrongLength {
            joints: Joints::Start,
            expected: 7,
            found: 6
        })
    ));
    let mut far = q.clone();
    far[1] = 3.0;
    assert!(matches!(
        plan(&problem(&scene, vec![0], q.clone(), far), 0),
        Err(MotionError::OutOfLimits {
            joints: Joints::Goal,
            end_effector: EndEffectorId(0),
            joint: 1,
            ..
        })
    ));
    // End-effector 1 is the pillar.
    assert_eq!(
        plan(&problem(&scene, vec![1], Vec::new(), Vec::new()), 0),
        Err(MotionError::NotAnArm {
            end_effector: EndEffectorId(1)
        })
    );
    assert_eq!(
        plan(
            &problem(
                &scene,
                vec![0, 0],
                [q.clone(), q.clone()].concat(),
                [q.clone(), q.clone()].concat()
            ),
            0
        ),
        Err(MotionError::RepeatedArm {
            end_effector: EndEffectorId(0)
        })
    );
    let mut rng = ChaCha8Rng::seed_from_u64(0);
    let bad = MotionOptions {
        collision_resolution: 0.0,
        ..MotionOptions::default()
    };
    assert!(matches!(
        problem(&scene, vec![0], q.clone(), q.clone()).solve(&bad, &mut rng, &Termination::never()),
        Err(MotionError::InvalidOption {
            name: "collision_resolution",
            ..
        })
    ));
    // A held object's holder must be an arm.
    let mut p = problem(&scene, vec![0], q.clone(), q);
    p.placement = ObjectPlacement::Held {
        by: EndEffectorId(1),
        grasp: Iso::identity(),
    };
    assert!(matches!(plan(&p, 0), Err(MotionError::Query(_))));
}
