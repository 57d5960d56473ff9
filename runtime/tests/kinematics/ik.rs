//! Inverse kinematics: reachable poses found again, points, unreachable targets, a
//! deadline that stops the restarts, seed lengths, determinism.

use std::f64::consts::FRAC_PI_2;

use cellc_runtime::kinematics::closed_chain::{solve_handoff, HandoffOptions, HandoffProblem};
use cellc_runtime::kinematics::{
    pose_error, random_configuration, solve_ik, IkError, IkOptions, IkTarget,
};
use cellc_runtime::math::{Iso, Point, Vec3};
use cellc_runtime::Termination;
use proptest::prelude::*;
use proptest::test_runner::FileFailurePersistence;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use super::facing_arms;
use super::models::*;

fn limits_strategy() -> impl Strategy<Value = Vec<f64>> {
    let robot = lwr();
    let (lower, upper) = robot.limits();
    lower
        .iter()
        .zip(upper)
        .map(|(&lo, &hi)| lo..=hi)
        .collect::<Vec<_>>()
}

proptest! {
    // A regression is kept next to this file (`ik.proptest-regressions`), not under
    // `tests/proptest-regressions/` where proptest would put it, having found `main.rs`.
    #![proptest_config(ProptestConfig {
        cases: 200,
        failure_persistence: Some(Box::new(FileFailurePersistence::WithSource(
            "proptest-regressions",
        ))),
        ..ProptestConfig::default()
    })]

    /// Any pose the arm can take is found again from a random seed, within the
    /// tolerances and the limits.
    #[test]
    fn ik_recovers_reachable_poses(q in limits_strategy(), seed in any::<u64>()) {
        let robot = lwr();
        let base = Iso::translation(0.0, 0.25, 1.0) * Iso::rotation(Vec3::x() * -FRAC_PI_2);
        let target = robot.tip_pose(&base, &q);
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let start = random_configuration(&robot, &mut rng);
        let opts = IkOptions::default();
        let solution = solve_ik(&robot, &base, &IkTarget::Pose(target), &start, &mut rng, &opts, &Termination::never());
        prop_assert!(solution.is_ok(), "no solution: {:?}", solution);
        let solution = solution.unwrap_or_default();
        prop_assert!(robot.within_limits(&solution));
        let (position_error, rotation_error) =
            pose_error(&robot.tip_pose(&base, &solution), &target);
        prop_assert!(position_error <= opts.position_tolerance, "{position_error}");
        prop_assert!(rotation_error <= opts.rotation_tolerance, "{rotation_error}");
    }
}

#[test]
fn position_only_ik_reaches_points() {
    let robot = lwr();
    let base = Iso::identity();
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let opts = IkOptions::default();
    for point in [
        Point::new(0.5, 0.2, 0.4),
        Point::new(-0.3, -0.4, 0.9),
        Point::new(0.0, 0.6, 0.1),
    ] {
        let q = solve_ik(
            &robot,
            &base,
            &IkTarget::Position(point),
            &[0.0; 7],
            &mut rng,
            &opts,
            &Termination::never(),
        )
        .expect("a point well inside the reach");
        assert!(robot.within_limits(&q));
        let tip = robot.tip_pose(&base, &q);
        assert!((tip.translation.vector - point.coords).norm() <= opts.position_tolerance);
    }
}

#[test]
fn unreachable_target_reports_the_error() {
    let robot = lwr();
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let opts = IkOptions {
        restarts: 5,
        ..IkOptions::default()
    };
    let target = IkTarget::Pose(Iso::translation(5.0, 0.0, 0.5));
    match solve_ik(
        &robot,
        &Iso::identity(),
        &target,
        &[0.0; 7],
        &mut rng,
        &opts,
        &Termination::never(),
    ) {
        Err(IkError::NotConverged {
            tries,
            position_error,
            rotation_error,
        }) => {
            assert_eq!(tries, 6);
            // The flange reaches at most 0.868 m from the shoulder at (0, 0, 0.31); the
            // best try trades some of that for orientation (the residual weighs metres
            // and radians alike), so it stops a little short of the closest point.
            let closest = (Vec3::new(5.0, 0.0, 0.5 - 0.31)).norm() - 0.868;
            assert!(
                position_error >= closest - 1e-3 && position_error < closest + 0.25,
                "position error {position_error}, closest possible {closest}"
            );
            assert!(rotation_error.is_finite());
        }
        other => panic!("expected NotConverged, got {other:?}"),
    }
    let point = IkTarget::Position(Point::new(0.0, 5.0, 0.0));
    assert!(matches!(
        solve_ik(&robot, &Iso::identity(), &point, &[0.0; 7], &mut rng, &opts, &Termination::never()),
        Err(IkError::NotConverged { rotation_error, .. }) if rotation_error == 0.0
    ));
}

/// A deadline that has passed lets each solver make its first try only, and says it was
/// stopped rather than that the target is out of reach.
#[test]
fn a_passed_deadline_stops_the_restarts() {
    let robot = lwr();
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let stop = Termination::at(std::time::Instant::now());
    let target = IkTarget::Pose(Iso::translation(5.0, 0.0, 0.5));
    let opts = IkOptions::default();
    assert_eq!(
        solve_ik(
            &robot,
            &Iso::identity(),
            &target,
            &[0.0; 7],
            &mut rng,
            &opts,
            &stop
        ),
        Err(IkError::Terminated { tries: 1 })
    );
    assert!(stop.fired());
    // Two arms 5 m apart never close the loop; stopped, they report it after one try.
    let (base_a, _, grasp_a, grasp_b) = facing_arms();
    let far = HandoffProblem {
        a: (&robot, base_a),
        b: (&robot, Iso::translation(0.0, 5.0, 0.0)),
        grasp_a,
        grasp_b,
        target: Point::new(0.0, 2.5, 0.5),
        bounds: None,
    };
    let opts = HandoffOptions::default();
    assert_eq!(
        solve_handoff(&far, &[0.0; 7], &[0.0; 7], &mut rng, &opts, &stop),
        Err(IkError::Terminated { tries: 1 })
    );
}

#[test]
fn wrong_seed_length_is_an_error() {
    let robot = lwr();
    let mut rng = ChaCha8Rng::seed_from_u64(0);
    let target = IkTarget::Position(Point::new(0.3, 0.0, 0.8));
    assert_eq!(
        solve_ik(
            &robot,
            &Iso::identity(),
            &target,
            &[0.0; 6],
            &mut rng,
            &IkOptions::default(),
            &Termination::never()
        ),
        Err(IkError::SeedLength {
            expected: 7,
            got: 6
        })
    );
}

#[test]
fn ik_is_deterministic_for_a_seed() {
    let robot = lwr();
    let base = Iso::identity();
    let target = IkTarget::Pose(robot.tip_pose(&base, &[0.4, 0.7, -0.3, -1.2, 0.5, 0.9, 0.1]));
    let solve = |seed| {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        solve_ik(
            &robot,
            &base,
            &target,
            &[2.0, -1.0, 2.0, 1.5, -2.0, -1.5, 2.5],
            &mut rng,
            &IkOptions::default(),
            &Termination::never(),
        )
        .expect("reachable")
    };
    assert_eq!(solve(42), solve(42));
}
