//! Held objects: one touches only its own hand, and one handed off touches both.

use cellc_runtime::collision::{
    CollisionWorld, CollisionWorldBuilder, Configuration, Holder, ObjectState,
};
use cellc_runtime::math::{Iso, Vec3};

use super::{all, deg, first, frames, handoff_world, lwr, softhand, z_cylinder};

/// One LWR at `z` hanging nowhere: A2 90, A4 -90 puts the flange at (-0.4, 0, z - 0.158)
/// pointing down; the cylinder is held 0.16 m into the hand.
fn held_scene(base_z: f64) -> (CollisionWorld, Vec<Iso>, Iso) {
    let robot = lwr();
    let mut b = CollisionWorldBuilder::new();
    let left = b.add_robot("left", &robot, Some(softhand()));
    b.add_fixed_box("table", [-0.7, -0.3, 0.50], [-0.1, 0.3, 0.55]);
    let cylinder = z_cylinder(Iso::identity(), 0.04, 0.2);
    b.add_object("cylinder", vec![cylinder]);
    let world = b.build().expect("valid world");
    let base = Iso::translation(0.0, 0.0, base_z);
    let q = [0.0, deg(90.0), 0.0, deg(-90.0), 0.0, 0.0, 0.0];
    let f = frames(&robot, &base, &q);
    let tip = world.tip(left, &f).expect("frames of the arm");
    assert!((tip.translation.vector - Vec3::new(-0.4, 0.0, base_z - 0.158)).norm() < 1e-9);
    (world, f, tip)
}

#[test]
fn held_object_touches_its_hand_only() {
    let grasp = Iso::translation(0.0, 0.0, 0.16);
    let (world, f, tip) = held_scene(1.0);
    // Held: inside the hand, nothing reported.
    let objects = [ObjectState::held(0, &tip, &grasp)];
    let state = Configuration {
        robots: &[&f],
        objects: &objects,
    };
    assert_eq!(all(&world, &state), Vec::<(String, String)>::new());
    // The same pose without the holder: it collides with the hand.
    let objects = [ObjectState::free(tip * grasp)];
    let state = Configuration {
        robots: &[&f],
        objects: &objects,
    };
    let found = all(&world, &state);
    assert!(
        found.contains(&("left/softhand".to_string(), "cylinder".to_string())),
        "{found:?}"
    );

    // Lowered 4 cm: the cylinder's bottom (0.582 -> 0.542) goes into the table top
    // (0.55), the fingertips (0.597) stay above it.
    let (world, f, tip) = held_scene(0.96);
    let objects = [ObjectState::held(0, &tip, &grasp)];
    let state = Configuration {
        robots: &[&f],
        objects: &objects,
    };
    assert_eq!(
        all(&world, &state),
        vec![("table".to_string(), "cylinder".to_string())]
    );
    // Placing it on the table (hand and table both hold it) is allowed.
    let objects = [ObjectState::held(0, &tip, &grasp).also_held_by(Holder::Fixed(0))];
    let state = Configuration {
        robots: &[&f],
        objects: &objects,
    };
    assert_eq!(first(&world, &state), None);
}

#[test]
fn handoff_object_touches_both_hands() {
    let (world, fa, fb) = handoff_world();
    let robots: [&[Iso]; 2] = [&fa, &fb];
    let both = [ObjectState::free(Iso::identity())
        .also_held_by(Holder::Robot(0))
        .also_held_by(Holder::Robot(1))];
    let state = Configuration {
        robots: &robots,
        objects: &both,
    };
    assert_eq!(first(&world, &state), None);
    let one = [ObjectState::free(Iso::identity()).also_held_by(Holder::Robot(0))];
    let state = Configuration {
        robots: &robots,
        objects: &one,
    };
    assert_eq!(
        all(&world, &state),
        vec![("b/gripper".to_string(), "ball".to_string())]
    );
}
