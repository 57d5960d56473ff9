//! Kinematics of the shipped robot models: forward kinematics against poses worked out by
//! hand, the Jacobian against finite differences, inverse kinematics (pose, position,
//! unreachable, determinism) and closed-chain handoffs (arm to arm, arm to conveyor). The
//! collision solids the URDFs give are tested in `robot_models.rs`.
//!
//! This file holds the layouts more than one module uses; the modules hold the cases:
//! `forward.rs` chains, forward kinematics and the Jacobian, `ik.rs` inverse kinematics,
//! `closed_chain.rs` handoffs.

use std::f64::consts::{FRAC_PI_2, PI};

use cellc_runtime::kinematics::closed_chain::HandoffProblem;
use cellc_runtime::kinematics::IkOptions;
use cellc_runtime::math::{Iso, Vec3};
use cellc_runtime::robot::Robot;

#[path = "../support/models.rs"]
mod models;

mod closed_chain;
mod forward;
mod ik;

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

#[test]
fn robots_can_be_shared_between_threads() {
    fn send_sync<T: Send + Sync>() {}
    send_sync::<Robot>();
    send_sync::<HandoffProblem<'static>>();
    send_sync::<IkOptions>();
}
