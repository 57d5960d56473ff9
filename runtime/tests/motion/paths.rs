//! The paths the planner finds: the straight line when it is free, a way round a pillar,
//! two arms passing each other or one parked in the way, a held object that follows its
//! hand; and the fixture's closed-form inverse kinematics they are all built on.

use cellc_runtime::math::Iso;
use cellc_runtime::motion::{MotionError, TrajectoryFault};
use cellc_runtime::scene::{Holder, ObjectPlacement};
use cellc_runtime::EndEffectorId;

use super::{
    assert_valid, down, is_straight, plan, problem, recheck, scene, straight, swap, ARM, FACING,
    PILLAR,
};

/// The fixture's closed-form inverse kinematics is right (everything below relies on it).
#[test]
fn down_puts_the_hand_where_asked() {
    let scene = scene(&FACING, &[]);
    for (e, target) in [
        (0, [0.5, -0.35, 0.35]),
        (0, [0.5, 0.4, 0.6]),
        (1, [0.5, 0.25, 0.3]),
    ] {
        let Holder::Arm { robot, base, .. } = &scene.holders[e] else {
            panic!("end-effector {e} is an arm");
        };
        let q = down(FACING[e].1, target);
        let tip = scene.robots[*robot].tip_pose(base, &q);
        let error = (tip.translation.vector - nalgebra::Vector3::from(target)).norm();
        assert!(error < 1e-9, "{target:?}: {error} m off");
        let z = tip.rotation * nalgebra::Vector3::z();
        assert!((z.z + 1.0).abs() < 1e-9, "{target:?}: hand axis {z:?}");
    }
}

#[test]
fn straight_line_when_free() {
    let scene = scene(&[ARM], &[]);
    let p = problem(
        &scene,
        vec![0],
        down(ARM.1, [0.5, -0.35, 0.35]),
        down(ARM.1, [0.5, 0.35, 0.35]),
    );
    let t = plan(&p, 1).expect("a free straight line");
    assert_valid(&p, &t);
    assert!(is_straight(&t), "the planner keeps the straight line");
    // About 1 rad of A1 at 0.25 rad per point.
    assert!(t.points.len() >= 5, "{} points", t.points.len());
}

#[test]
fn path_around_an_obstacle() {
    let scene = scene(&[ARM], &[PILLAR]);
    let p = problem(
        &scene,
        vec![0],
        down(ARM.1, [0.5, -0.35, 0.35]),
        down(ARM.1, [0.5, 0.35, 0.35]),
    );
    match recheck(&p, &straight(&p)) {
        Err(TrajectoryFault::Collision { a, b, .. }) => {
            assert!(a == "pillar" || b == "pillar", "{a} / {b}")
        }
        other => panic!("the straight line hits the pillar: {other:?}"),
    }
    let t = plan(&p, 1).expect("a way around the pillar");
    assert_valid(&p, &t);
    assert!(!is_straight(&t));
}

#[test]
fn start_or_goal_in_collision() {
    let scene = scene(&[ARM], &[PILLAR]);
    let free = down(ARM.1, [0.5, -0.35, 0.35]);
    let inside = down(ARM.1, [0.55, 0.0, 0.35]);
    match plan(&problem(&scene, vec![0], inside.clone(), free.clone()), 1) {
        Err(MotionError::StartInCollision { a, b }) => {
            assert!(a == "pillar" || b == "pillar", "{a} / {b}");
            assert!(
                a.starts_with("left/") || b.starts_with("left/"),
                "{a} / {b}"
            );
        }
        other => panic!("expected StartInCollision, got {other:?}"),
    }
    match plan(&problem(&scene, vec![0], free, inside), 1) {
        Err(MotionError::GoalInCollision { a, b }) => {
            assert!(a == "pillar" || b == "pillar", "{a} / {b}")
        }
        other => panic!("expected GoalInCollision, got {other:?}"),
    }
}

#[test]
fn two_arms_avoid_each_other() {
    let scene = scene(&FACING, &[]);
    let p = swap(&scene);
    match recheck(&p, &straight(&p)) {
        Err(TrajectoryFault::Collision { a, b, .. }) => assert!(
            a.starts_with("left/") && b.starts_with("right/")
                || a.starts_with("right/") && b.starts_with("left/"),
            "{a} / {b}"
        ),
        other => panic!("the straight line makes the arms meet: {other:?}"),
    }
    let t = plan(&p, 2).expect("the arms can pass each other");
    assert_eq!(t.points[0].positions.len(), 14);
    assert_valid(&p, &t);
}

#[test]
fn stationary_arms_are_obstacles() {
    let scene = scene(&FACING, &[]);
    let l = FACING[0].1;
    let mut p = problem(
        &scene,
        vec![0],
        down(l, [0.5, 0.25, 0.3]),
        down(l, [0.5, -0.25, 0.3]),
    );
    // The right arm at home (upright) is out of the way.
    let t = plan(&p, 3).expect("a free straight line");
    assert!(is_straight(&t));
    // Parked in the middle, it is in the way.
    p.stationary = vec![(EndEffectorId(1), down(FACING[1].1, [0.55, 0.0, 0.3]))];
    assert!(matches!(
        recheck(&p, &straight(&p)),
        Err(TrajectoryFault::Collision { .. })
    ));
    let t = plan(&p, 3).expect("a way around the parked arm");
    assert_valid(&p, &t);
    assert!(!is_straight(&t));
}

#[test]
fn held_object_follows_the_hand() {
    // A block under the hand's path: the hand passes over it, the can hanging from the
    // hand (grasped 25 cm out along the hand axis, 30 cm long) does not.
    let table = ("table", [0.35, -0.2, 0.0], [0.8, 0.2, 0.3]);
    let scene = scene(&[ARM], &[table]);
    let mut p = problem(
        &scene,
        vec![0],
        down(ARM.1, [0.5, -0.4, 0.6]),
        down(ARM.1, [0.5, 0.4, 0.6]),
    );
    let empty = plan(&p, 4).expect("empty-handed, the straight line is free");
    assert!(is_straight(&empty));
    p.placement = ObjectPlacement::Held {
        by: EndEffectorId(0),
        grasp: Iso::translation(0.0, 0.0, 0.25),
    };
    match recheck(&p, &straight(&p)) {
        Err(TrajectoryFault::Collision { a, b, .. }) => {
            let mut pair = [a, b];
            pair.sort();
            assert_eq!(pair, ["can".to_string(), "table".to_string()]);
        }
        other => panic!("the held can hits the table: {other:?}"),
    }
    let t = plan(&p, 4).expect("a way over the table with the can");
    assert_valid(&p, &t);
    assert!(!is_straight(&t));
}
