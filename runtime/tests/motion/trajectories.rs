//! What a planned trajectory is beyond its path: timed within the limits, the same for the
//! same seed, one point when there is nothing to do, and an error for a malformed problem.

use cellc_runtime::math::Iso;
use cellc_runtime::motion::{Joints, MotionError, MotionOptions};
use cellc_runtime::scene::ObjectPlacement;
use cellc_runtime::EndEffectorId;
use cellc_runtime::Termination;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use super::{down, max_diff, plan, problem, scene, swap, ARM, FACING, PILLAR};

#[test]
fn timing_is_monotonic_and_within_limits() {
    let scene = scene(&[ARM], &[PILLAR]);
    let p = problem(
        &scene,
        vec![0],
        down(ARM.1, [0.5, -0.35, 0.35]),
        down(ARM.1, [0.5, 0.35, 0.35]),
    );
    let slow = MotionOptions {
        velocity_limit: 0.3,
        acceleration_limit: 0.5,
        ..MotionOptions::default()
    };
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let t = p
        .solve(&slow, &mut rng, &Termination::never())
        .expect("a path");
    let mut peak: f64 = 0.0;
    for pair in t.points.windows(2) {
        let ((t0, a), (t1, b)) = (&pair[0], &pair[1]);
        assert!(t1 > t0);
        peak = peak.max(max_diff(a, b) / (t1 - t0));
    }
    assert!(peak <= 0.3 * (1.0 + 1e-9), "peak speed {peak}");
    // A rest-to-rest trapezoid takes at least d / v + v / a per segment when it cruises,
    // 2 sqrt(d / a) when it does not; the whole motion at least the sum.
    let total = t.points[t.points.len() - 1].0;
    let travelled: f64 = t
        .points
        .windows(2)
        .map(|w| max_diff(&w[0].1, &w[1].1))
        .sum();
    assert!(total >= travelled / 0.3, "{total} s for {travelled} rad");
    // The same motion with the defaults is faster.
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let fast = p
        .solve(&MotionOptions::default(), &mut rng, &Termination::never())
        .expect("a path");
    assert!(fast.points[fast.points.len() - 1].0 < total);
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
    assert_eq!(t.points, vec![(0.0, q)]);
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
