//! Kinematics of the shipped robot models: forward kinematics against poses worked out by
//! hand, the Jacobian against finite differences, inverse kinematics (pose, position,
//! unreachable, determinism) and closed-chain handoffs (arm to arm, arm to conveyor). The
//! collision solids the URDFs give are tested in `robot_models.rs`.

use std::f64::consts::{FRAC_PI_2, PI};

use cellc_runtime::closed_chain::{solve_handoff, HandoffOptions, HandoffProblem};
use cellc_runtime::kinematics::{
    pose_error, random_configuration, rotation_log, solve_ik, IkError, IkOptions, IkTarget,
};
use cellc_runtime::math::{Iso, Point, Vec3};
use cellc_runtime::robot::{JointKind, Robot};
use cellc_runtime::termination::Termination;
use nalgebra as na;
use proptest::prelude::*;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

#[path = "support/models.rs"]
mod models;
use models::*;

fn deg(d: f64) -> f64 {
    d.to_radians()
}

/// Checks the flange position and z axis for a configuration given in degrees.
fn check_flange(robot: &Robot, q_deg: [f64; 7], position: [f64; 3], z_axis: [f64; 3]) {
    let q: Vec<f64> = q_deg.iter().map(|d| deg(*d)).collect();
    let flange = robot.tip_pose(&Iso::identity(), &q);
    assert_close(
        &flange.translation.vector,
        &Vec3::from(position),
        1e-4,
        &format!("flange position at {q_deg:?}"),
    );
    assert_close(
        &(flange.rotation * Vec3::z()),
        &Vec3::from(z_axis),
        1e-6,
        &format!("flange z axis at {q_deg:?}"),
    );
}

#[test]
fn lwr_chain_is_read() {
    let robot = lwr();
    assert_eq!(robot.n_joints(), 7);
    assert_eq!(robot.n_frames(), 8);
    assert_eq!(robot.base_link(), "lwr_base_link");
    assert_eq!(robot.tip_link(), "lwr_flange");
    assert_eq!(robot.frame_link(7), Some("lwr_link_7"));
    let names: Vec<&str> = robot.joint_names().iter().map(String::as_str).collect();
    assert_eq!(
        names,
        [
            "lwr_a1_joint",
            "lwr_a2_joint",
            "lwr_a3_joint",
            "lwr_a4_joint",
            "lwr_a5_joint",
            "lwr_a6_joint",
            "lwr_a7_joint"
        ]
    );
    assert!(robot
        .joint_kinds()
        .iter()
        .all(|k| *k == JointKind::Revolute));
    let (lower, upper) = robot.limits();
    for j in [0, 2, 4, 6] {
        assert!((upper[j] - deg(170.0)).abs() < 1e-6 && (lower[j] + deg(170.0)).abs() < 1e-6);
    }
    for j in [1, 3, 5] {
        assert!((upper[j] - deg(120.0)).abs() < 1e-6 && (lower[j] + deg(120.0)).abs() < 1e-6);
    }
    // The flange joint is fixed: folded into the tip offset, 0.078 m along z.
    assert_close(
        &robot.tip_offset().translation.vector,
        &Vec3::new(0.0, 0.0, 0.078),
        1e-12,
        "tip offset",
    );
}

/// Forward kinematics against poses worked out by hand.
///
/// In the zero pose every joint sits on the z axis of the base: A1 at 0.11, A2 at 0.31
/// (0.11 + 0.20), A3 at 0.51, A4 at 0.71, A5 at 0.91, A6 at 1.10 (0.91 + 0.19), A7 at
/// 1.10, and the flange 0.078 further up, at 1.178. Axes: A1 +z, A2 -y, A3 +z, A4 +y,
/// A5 +z, A6 -y, A7 +z.
///
/// A turn by θ about +y maps z to (sin θ, 0, cos θ); about -y, to (-sin θ, 0, cos θ).
/// Turns about the z joints (A3, A5, A7) at zero leave everything else on one line, so
/// only the y joints bend the arm:
///
/// 1. A2 = 90: everything above the shoulder (0, 0, 0.31) points along
///    (-sin 90, 0, cos 90) = (-1, 0, 0); the flange is 0.40 + 0.39 + 0.078 = 0.868 m out:
///    (-0.868, 0, 0.31), flange z = (-1, 0, 0).
/// 2. A4 = 90: the forearm, from the elbow (0, 0, 0.71), turns about +y: direction
///    (1, 0, 0), 0.39 + 0.078 = 0.468 m: (0.468, 0, 0.71), z = (1, 0, 0).
/// 3. A2 = 90, A4 = -90: the upper arm along -x puts the elbow at (-0.40, 0, 0.31); A4
///    turns a further 90 deg the same way round (-90 about +y = +90 about -y), so the
///    forearm points along (-sin 180, 0, cos 180) = (0, 0, -1): the flange is 0.468 m
///    below the elbow, (-0.40, 0, -0.158), z = (0, 0, -1).
/// 4. A1 = 90, A2 = 45, A4 = -90, A6 = 45: in the arm's plane (before A1), the upper arm
///    points along (-sin 45, 0, cos 45), the elbow at (-0.2828, 0, 0.5928); the forearm
///    has turned 45 + 90 = 135 deg: (-sin 135, 0, cos 135) = (-0.7071, 0, -0.7071), the
///    wrist at (-0.5586, 0, 0.3170); A6 turns 45 more, 180 in all: the flange points
///    straight down, at (-0.5586, 0, 0.2390). A1 = 90 about z takes x to y: the flange
///    is at (0, -0.5586, 0.2390), z = (0, 0, -1).
/// 5. A1 = 90 alone turns the straight arm about its own line: the position stays
///    (0, 0, 1.178), z stays up, and the flange's x axis turns from x to y.
#[test]
fn lwr_forward_kinematics_matches_hand_computed_poses() {
    let robot = lwr();
    check_flange(&robot, [0.0; 7], [0.0, 0.0, 1.178], [0.0, 0.0, 1.0]);
    check_flange(
        &robot,
        [0.0, 90.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        [-0.868, 0.0, 0.31],
        [-1.0, 0.0, 0.0],
    );
    check_flange(
        &robot,
        [0.0, 0.0, 0.0, 90.0, 0.0, 0.0, 0.0],
        [0.468, 0.0, 0.71],
        [1.0, 0.0, 0.0],
    );
    check_flange(
        &robot,
        [0.0, 90.0, 0.0, -90.0, 0.0, 0.0, 0.0],
        [-0.4, 0.0, -0.158],
        [0.0, 0.0, -1.0],
    );
    check_flange(
        &robot,
        [90.0, 45.0, 0.0, -90.0, 0.0, 45.0, 0.0],
        [0.0, -0.5586, 0.2390],
        [0.0, 0.0, -1.0],
    );
    let turned = robot.tip_pose(&Iso::identity(), &[FRAC_PI_2, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]);
    assert_close(
        &(turned.rotation * Vec3::x()),
        &Vec3::y(),
        1e-9,
        "A1 = 90 x axis",
    );

    // The frames: frame 2 (lwr_link_2) sits on the A2 axis, 0.31 above the base, and a
    // base pose moves every frame with it.
    let base = Iso::translation(1.0, 2.0, 3.0);
    let mut frames = Vec::new();
    robot.fk_frames(&base, &[0.0; 7], &mut frames);
    assert_eq!(frames.len(), 8);
    assert_close(
        &frames[2].translation.vector,
        &Vec3::new(1.0, 2.0, 3.31),
        1e-12,
        "frame 2",
    );
    assert_close(
        &frames[6].translation.vector,
        &Vec3::new(1.0, 2.0, 4.10),
        1e-12,
        "frame 6 (wrist centre)",
    );
}

#[test]
fn conveyor_top_slides_along_x() {
    let robot = conveyor();
    assert_eq!(robot.n_joints(), 1);
    assert_eq!(robot.joint_kinds(), &[JointKind::Prismatic]);
    assert_eq!(robot.limits(), (&[-0.7][..], &[0.7][..]));
    // conveyor_top is at (q, 0, 0.12): the carriage's origin 0.10 up, plus 0.02.
    for q in [-0.7, 0.0, 0.35] {
        let top = robot.tip_pose(&Iso::identity(), &[q]);
        assert_close(
            &top.translation.vector,
            &Vec3::new(q, 0.0, 0.12),
            1e-12,
            "conveyor top",
        );
        assert!(top.rotation.angle() < 1e-12);
    }
}

/// Central differences of the tip pose, one joint at a time.
#[test]
fn jacobian_matches_finite_differences() {
    let robot = lwr();
    let base = Iso::from_parts(
        na::Translation3::new(0.2, -0.3, 0.9),
        na::UnitQuaternion::from_euler_angles(0.3, -0.2, 1.1),
    );
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let h = 1e-6;
    for _ in 0..20 {
        let q = random_configuration(&robot, &mut rng);
        let jacobian = robot.jacobian(&base, &q);
        assert_eq!(jacobian.ncols(), 7);
        for j in 0..7 {
            let mut plus = q.clone();
            let mut minus = q.clone();
            plus[j] += h;
            minus[j] -= h;
            let (a, b) = (robot.tip_pose(&base, &plus), robot.tip_pose(&base, &minus));
            let linear = (a.translation.vector - b.translation.vector) / (2.0 * h);
            let angular = rotation_log(&(a.rotation * b.rotation.inverse())) / (2.0 * h);
            assert_close(
                &jacobian.fixed_view::<3, 1>(0, j).into_owned(),
                &linear,
                1e-6,
                "linear column",
            );
            assert_close(
                &jacobian.fixed_view::<3, 1>(3, j).into_owned(),
                &angular,
                1e-6,
                "angular column",
            );
        }
    }
    // A prismatic joint: the column is its axis, no rotation.
    let belt = conveyor();
    let jacobian = belt.jacobian(&base, &[0.1]);
    assert_close(
        &jacobian.fixed_view::<3, 1>(0, 0).into_owned(),
        &(base.rotation * Vec3::x()),
        1e-12,
        "prismatic linear column",
    );
    assert!(jacobian.fixed_view::<3, 1>(3, 0).norm() == 0.0);
}

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
    #![proptest_config(ProptestConfig { cases: 200, ..ProptestConfig::default() })]

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

/// Two LWRs facing each other 1 m apart, each holding the object 0.1 m in front of its
/// flange; B's grasp is turned 180 deg about x, so the two flanges face each other.
fn facing_arms() -> (Iso, Iso, Iso, Iso) {
    // A at y = -0.5 with its x axis along +y; B at y = +0.5 with its x axis along -y.
    let base_a = Iso::translation(0.0, -0.5, 0.0) * Iso::rotation(Vec3::z() * FRAC_PI_2);
    let base_b = Iso::translation(0.0, 0.5, 0.0) * Iso::rotation(Vec3::z() * -FRAC_PI_2);
    let grasp_a = Iso::translation(0.0, 0.0, 0.1);
    let grasp_b = Iso::translation(0.0, 0.0, 0.1) * Iso::rotation(Vec3::x() * PI);
    (base_a, base_b, grasp_a, grasp_b)
}

fn check_handoff(
    problem: &HandoffProblem<'_>,
    solution: &cellc_runtime::closed_chain::HandoffSolution,
    opts: &HandoffOptions,
) {
    let (robot_a, base_a) = problem.a;
    let (robot_b, base_b) = problem.b;
    assert!(robot_a.within_limits(&solution.qa));
    assert!(robot_b.within_limits(&solution.qb));
    let through_a = robot_a.tip_pose(&base_a, &solution.qa) * problem.grasp_a;
    let through_b = robot_b.tip_pose(&base_b, &solution.qb) * problem.grasp_b;
    let (position_error, rotation_error) = pose_error(&through_a, &through_b);
    assert!(
        position_error <= opts.ik.position_tolerance,
        "{position_error}"
    );
    assert!(
        rotation_error <= opts.ik.rotation_tolerance,
        "{rotation_error}"
    );
    assert!(pose_error(&solution.object, &through_a).0 < 1e-12);
    if let Some((min, max)) = problem.bounds {
        let p = solution.object.translation.vector;
        for k in 0..3 {
            assert!(
                p[k] >= min[k] - opts.ik.position_tolerance
                    && p[k] <= max[k] + opts.ik.position_tolerance,
                "object at {p:?} outside the bounds"
            );
        }
    }
}

#[test]
fn handoff_between_facing_arms_closes_the_loop_near_the_target() {
    let robot = lwr();
    let (base_a, base_b, grasp_a, grasp_b) = facing_arms();
    let target = Point::new(0.3, 0.0, 0.6);
    let problem = HandoffProblem {
        a: (&robot, base_a),
        b: (&robot, base_b),
        grasp_a,
        grasp_b,
        target,
        bounds: Some((Point::new(0.15, -0.15, 0.45), Point::new(0.45, 0.15, 0.75))),
    };
    let opts = HandoffOptions::default();
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let solution = solve_handoff(
        &problem,
        &[0.0; 7],
        &[0.0; 7],
        &mut rng,
        &opts,
        &Termination::never(),
    )
    .expect("a handoff");
    check_handoff(&problem, &solution, &opts);
    let distance = (solution.object.translation.vector - target.coords).norm();
    assert!(
        distance <= opts.target_tolerance + 1e-9,
        "object {distance} m from the target"
    );
    // The flanges face each other: their z axes are opposite.
    let za = robot.tip_pose(&base_a, &solution.qa).rotation * Vec3::z();
    let zb = robot.tip_pose(&base_b, &solution.qb).rotation * Vec3::z();
    assert!((za + zb).norm() < 1e-2);

    // Same seed, same answer.
    let mut again = ChaCha8Rng::seed_from_u64(5);
    assert_eq!(
        solve_handoff(
            &problem,
            &[0.0; 7],
            &[0.0; 7],
            &mut again,
            &opts,
            &Termination::never()
        ),
        Ok(solution)
    );
}

#[test]
fn handoff_with_an_out_of_reach_target_still_closes_the_loop() {
    // The target is beyond both arms' reach (3 m up): the pull is soft, so the loop
    // still closes, with the object as close as the arms get.
    let robot = lwr();
    let (base_a, base_b, grasp_a, grasp_b) = facing_arms();
    let problem = HandoffProblem {
        a: (&robot, base_a),
        b: (&robot, base_b),
        grasp_a,
        grasp_b,
        target: Point::new(0.0, 0.0, 3.0),
        bounds: None,
    };
    let opts = HandoffOptions::default();
    let mut rng = ChaCha8Rng::seed_from_u64(9);
    let solution = solve_handoff(
        &problem,
        &[0.0; 7],
        &[0.0; 7],
        &mut rng,
        &opts,
        &Termination::never(),
    )
    .expect("a handoff");
    check_handoff(&problem, &solution, &opts);
    assert!(
        solution.object.translation.z > 0.9,
        "{}",
        solution.object.translation.z
    );
}

#[test]
fn handoff_from_an_arm_onto_a_conveyor() {
    let arm = lwr();
    let belt = conveyor();
    // The belt runs along x in front of the arm, its carriage top at z = 0.42.
    let belt_base = Iso::translation(0.55, 0.0, 0.3);
    // The object (its frame at its centre) rests 0.05 m above the carriage, upright; the
    // arm holds it from above, 0.1 m in front of a flange that points down.
    let grasp_b = Iso::translation(0.0, 0.0, 0.05);
    let grasp_a = Iso::translation(0.0, 0.0, 0.1) * Iso::rotation(Vec3::x() * PI);
    let problem = HandoffProblem {
        a: (&arm, Iso::identity()),
        b: (&belt, belt_base),
        grasp_a,
        grasp_b,
        target: Point::new(0.5, 0.0, 0.47),
        bounds: Some((Point::new(0.3, -0.2, 0.3), Point::new(0.8, 0.2, 0.7))),
    };
    let opts = HandoffOptions::default();
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    let solution = solve_handoff(
        &problem,
        &[0.0; 7],
        &[0.0],
        &mut rng,
        &opts,
        &Termination::never(),
    )
    .expect("a handoff");
    check_handoff(&problem, &solution, &opts);
    // Resting on the belt: upright, at the carriage height, where the carriage is.
    let object = solution.object;
    assert!((object.translation.z - 0.47).abs() < 1e-3);
    assert!(object.rotation.angle() < 1e-3);
    assert!((object.translation.x - (0.55 + solution.qb[0])).abs() < 1e-3);
    assert!((object.translation.x - 0.5).abs() <= opts.target_tolerance + 1e-9);
}

#[test]
fn handoff_seed_lengths_are_checked() {
    let arm = lwr();
    let belt = conveyor();
    let problem = HandoffProblem {
        a: (&arm, Iso::identity()),
        b: (&belt, Iso::identity()),
        grasp_a: Iso::identity(),
        grasp_b: Iso::identity(),
        target: Point::origin(),
        bounds: None,
    };
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    assert_eq!(
        solve_handoff(
            &problem,
            &[0.0; 7],
            &[0.0; 7],
            &mut rng,
            &HandoffOptions::default(),
            &Termination::never()
        ),
        Err(IkError::SeedLength {
            expected: 1,
            got: 7
        })
    );
}

#[test]
fn robots_can_be_shared_between_threads() {
    fn send_sync<T: Send + Sync>() {}
    send_sync::<Robot>();
    send_sync::<HandoffProblem<'static>>();
    send_sync::<IkOptions>();
}
