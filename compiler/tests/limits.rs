//! Joint limits on a real robot (the shipped LWR 4+ URDF): which line wins (joint over
//! robot over `joint_limits.yaml` over the URDF over the default), where each came from,
//! what the artifact carries, and the warning of a robot left to the defaults.

use cellc_compiler::model::{Joint, LimitSource};
use cellc_compiler::{compile, Compilation, MemoryFiles};

const URDF: &str = include_str!("../../cells/robots/kuka_lwr4.urdf");

fn cell(lines: &str) -> String {
    format!(
        "cell pick {{\n  units m, deg\n  robot lwr4 urdf \"lwr4.urdf\" base lwr_base_link tip lwr_flange\n{lines}\n  hand gripper\n  support tabletop\n  arm left = lwr4 at (0, 0, 1) with gripper\n  reach left box center (0.5, 0, 0.8) size (0.6, 0.8, 0.4)\n  surface table : tabletop box center (0.5, 0, 0.75) size (0.6, 0.8, 0.02)\n  workspaces from reach\n  object cube {{\n    rest standing on tabletop at (0, 0, 0.05)\n    grasp top by gripper at (0, 0, 0.1) rpy (180, 0, 0)\n    transition standing <-> top\n  }}\n}}\n"
    )
}

fn build(lines: &str, yaml: &str) -> Compilation {
    let text = cell(lines);
    let files = MemoryFiles::new([
        ("pick.cell", text.as_bytes()),
        ("lwr4.urdf", URDF.as_bytes()),
        ("config/joint_limits.yaml", yaml.as_bytes()),
    ]);
    compile(&files, "pick.cell")
}

fn codes(c: &Compilation) -> Vec<&str> {
    c.diagnostics.iter().map(|d| d.code.as_str()).collect()
}

fn joints(c: &Compilation) -> &[Joint] {
    let cell = c.cell.as_ref().expect("a cell");
    &cell.robots.iter().next().expect("a robot").1.chain_joints
}

const YAML: &str = "joint_limits:\n  lwr_a1_joint:\n    has_velocity_limits: true\n    max_velocity: 1.0\n    has_acceleration_limits: true\n    max_acceleration: 3.0\n  lwr_a2_joint:\n    has_velocity_limits: true\n    max_velocity: 1.2\n    has_acceleration_limits: true\n    max_acceleration: 3.5\n    has_jerk_limits: true\n    max_jerk: 30\n  lwr_a3_joint:\n    has_acceleration_limits: false\n    max_acceleration: 9\n  panda_finger_joint1:\n    has_velocity_limits: true\n    max_velocity: 0.1\n";

#[test]
fn the_joints_line_wins_over_the_robots_over_the_file_over_the_urdf() {
    let c = build(
        "  limits lwr4 from \"config/joint_limits.yaml\"\n  limits lwr4 acceleration 180 deg/s2\n  limits lwr4.lwr_a1_joint acceleration 4 rad/s2 jerk 40 rad/s3",
        YAML,
    );
    assert_eq!(codes(&c), Vec::<&str>::new(), "{:#?}", c.diagnostics);
    let j = joints(&c);
    // a1: velocity from the file, acceleration and jerk from its own line.
    let a1 = &j[0];
    assert_eq!(a1.velocity.as_ref().map(|l| l.value), Some(1.0));
    assert!(
        matches!(a1.velocity.as_ref().unwrap().source, LimitSource::File(ref p, _) if p == "config/joint_limits.yaml")
    );
    assert_eq!(a1.acceleration.as_ref().map(|l| l.value), Some(4.0));
    assert!(matches!(
        a1.acceleration.as_ref().unwrap().source,
        LimitSource::Joint(_)
    ));
    assert_eq!(a1.jerk.as_ref().map(|l| l.value), Some(40.0));
    // a2: the robot's line (180 deg/s2 = pi rad/s2) over the file's 3.5; jerk the file's.
    let a2 = &j[1];
    let pi = std::f64::consts::PI;
    assert!((a2.acceleration.as_ref().unwrap().value - pi).abs() < 1e-12);
    assert!(matches!(
        a2.acceleration.as_ref().unwrap().source,
        LimitSource::Robot(_)
    ));
    assert_eq!(a2.jerk.as_ref().map(|l| l.value), Some(30.0));
    assert_eq!(a2.velocity.as_ref().map(|l| l.value), Some(1.2));
    // a3: the file disables its acceleration; the URDF's velocity stays.
    let a3 = &j[2];
    assert!((a3.acceleration.as_ref().unwrap().value - pi).abs() < 1e-12);
    assert!((a3.velocity.as_ref().unwrap().value - 1.9198622).abs() < 1e-9);
    assert_eq!(a3.velocity.as_ref().unwrap().source, LimitSource::Urdf);
    assert!(a3.jerk.is_none());
    // The artifact carries the values.
    let artifact = cellc_compiler::artifact::lower(c.cell.as_ref().unwrap(), &c.graphs, &c.sources);
    let robot = &artifact.robots[0];
    assert_eq!(robot.joints[0].acceleration, 4.0);
    assert_eq!(robot.joints[0].jerk, Some(40.0));
    assert_eq!(robot.joints[6].jerk, None);
}

#[test]
fn a_robot_without_acceleration_limits_is_warned_of_once() {
    let c = build("", YAML);
    assert_eq!(codes(&c), ["W0007"]);
    let message = &c.diagnostics[0].message;
    assert!(message.contains("7 joints"), "{message}");
    // Timed with the default, which the artifact carries.
    let j = joints(&c);
    assert!(j.iter().all(|j| j.acceleration.is_none()));
    let artifact = cellc_compiler::artifact::lower(c.cell.as_ref().unwrap(), &c.graphs, &c.sources);
    assert!(artifact.robots[0]
        .joints
        .iter()
        .all(|j| j.acceleration == Joint::DEFAULT_ACCELERATION));
    // A file covering some joints leaves the others named.
    let c = build("  limits lwr4 from \"config/joint_limits.yaml\"", YAML);
    assert_eq!(codes(&c), ["W0007"]);
    assert!(
        c.diagnostics[0].message.contains("5 joints"),
        "{}",
        c.diagnostics[0].message
    );
}

#[test]
fn bad_values_and_files_are_refused_with_their_codes() {
    for (lines, yaml, expect) in [
        ("  limits lwr4 acceleration 0 rad/s2", YAML, "E0204"),
        ("  limits lwr4 acceleration 1e999 rad/s2", YAML, "E0208"),
        ("  limits lwr4 acceleration 2 m/s2", YAML, "E0202"),
        ("  limits lwr4 jerk 2 rad/s2", YAML, "E0202"),
        ("  limits lwr4x acceleration 2 rad/s2", YAML, "E0101"),
        ("  limits lwr4.lwr_a8_joint acceleration 2 rad/s2", YAML, "E0403"),
        (
            "  limits lwr4 from \"config/joint_limits.yaml\"\n  limits lwr4 from \"config/joint_limits.yaml\" acceleration 2",
            YAML,
            "E0210",
        ),
        ("  limits lwr4 from \"config/joint_limits.yaml\" acceleration 2", "joint_limits: [", "E0328"),
        ("  limits lwr4 from \"config/other.yaml\" acceleration 2", YAML, "E0308"),
    ] {
        let c = build(lines, yaml);
        assert!(codes(&c).contains(&expect), "{lines}: {:?}", codes(&c));
    }
    // A bare number takes the file's units: 90 (deg/s2) is pi/2 rad/s2.
    let c = build("  limits lwr4 acceleration 90", YAML);
    assert!(codes(&c).is_empty(), "{:?}", codes(&c));
    let a = joints(&c)[0].acceleration.as_ref().unwrap().value;
    assert!((a - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
}
