//! The shipped robot models, loaded as the kinematics and model tests use them (each test
//! binary uses some of them).
#![allow(dead_code)]

use cellc_runtime::math::Vec3;
use cellc_runtime::robot::Robot;
use cellc_runtime::MemoryFiles;

/// A file of `cells/robots/`.
pub fn shipped(name: &str) -> String {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../cells/robots")
        .join(name);
    std::fs::read_to_string(&path).expect("the shipped robot models are readable")
}

/// The KUKA LWR 4 as the Vito cell uses it, base to flange.
pub fn lwr() -> Robot {
    Robot::from_urdf(
        &shipped("kuka_lwr4.urdf"),
        "robots/kuka_lwr4.urdf",
        "lwr_base_link",
        "lwr_flange",
        &MemoryFiles::default(),
    )
    .expect("the LWR model loads")
}

/// The conveyor of the assembly line, base to its top.
pub fn conveyor() -> Robot {
    Robot::from_urdf(
        &shipped("conveyor.urdf"),
        "robots/conveyor.urdf",
        "conveyor_base",
        "conveyor_top",
        &MemoryFiles::default(),
    )
    .expect("the conveyor model loads")
}

/// `a` and `b` within `tolerance`, or a message that says by how much not.
pub fn assert_close(a: &Vec3, b: &Vec3, tolerance: f64, what: &str) {
    assert!(
        (a - b).norm() <= tolerance,
        "{what}: {a:?} is not {b:?} (off by {})",
        (a - b).norm()
    );
}
