//! Closed-chain handoffs: arm to arm (near the target, and with one out of reach) and
//! arm to conveyor, within the tolerances, the limits and the bounds.

use std::f64::consts::PI;

use cellc_runtime::kinematics::closed_chain::{solve_handoff, HandoffOptions, HandoffProblem};
use cellc_runtime::kinematics::{pose_error, IkError};
use cellc_runtime::math::{Iso, Point, Vec3};
use cellc_runtime::Termination;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use super::facing_arms;
use super::models::*;

fn check_handoff(
    problem: &HandoffProblem<'_>,
    solution: &cellc_runtime::kinematics::closed_chain::HandoffSolution,
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
