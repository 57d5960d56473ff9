//! Chains as read from the URDFs, forward kinematics against poses worked out by hand,
//! and the geometric Jacobian against finite differences.

use std::f64::consts::FRAC_PI_2;

use cellc_runtime::kinematics::{random_configuration, rotation_log};
use cellc_runtime::math::{Iso, Vec3};
use cellc_runtime::robot::{JointKind, Robot};
use nalgebra as na;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use super::models::*;

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
