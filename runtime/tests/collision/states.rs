//! States the world cannot evaluate are errors, and scratch buffers are reused across
//! worlds and states.

use cellc_runtime::collision::{
    BodyId, BuildError, Collision, CollisionError, CollisionScratch, CollisionWorldBuilder,
    Configuration, Holder, ObjectState, Solid,
};
use cellc_runtime::math::Iso;
use parry3d_f64::shape::SharedShape;

use super::{frames, handoff_world, lwr};

#[test]
fn malformed_states_are_errors() {
    let robot = lwr();
    let mut b = CollisionWorldBuilder::new();
    b.add_robot("left", &robot, None);
    b.add_object(
        "ball",
        vec![Solid {
            local: Iso::identity(),
            shape: SharedShape::ball(0.05),
        }],
    );
    let world = b.build().expect("valid world");
    let mut scratch = CollisionScratch::default();
    let f = frames(&robot, &Iso::identity(), &[0.0; 7]);
    let ok = [ObjectState::absent()];

    let state = Configuration {
        robots: &[],
        objects: &ok,
    };
    assert_eq!(
        world.first_collision(&state, &mut scratch),
        Err(CollisionError::RobotCount {
            expected: 1,
            found: 0
        })
    );
    let state = Configuration {
        robots: &[&f[..5]],
        objects: &ok,
    };
    assert!(matches!(
        world.first_collision(&state, &mut scratch),
        Err(CollisionError::FrameCount {
            expected: 8,
            found: 5,
            ..
        })
    ));
    let state = Configuration {
        robots: &[&f],
        objects: &[],
    };
    assert!(matches!(
        world.first_collision(&state, &mut scratch),
        Err(CollisionError::ObjectCount { .. })
    ));
    let bad_holder = [ObjectState::resting(Iso::identity(), 3)];
    let state = Configuration {
        robots: &[&f],
        objects: &bad_holder,
    };
    assert!(matches!(
        world.first_collision(&state, &mut scratch),
        Err(CollisionError::UnknownHolder { .. })
    ));
    let nan = frames(&robot, &Iso::identity(), &[f64::NAN; 7]);
    let state = Configuration {
        robots: &[&nan],
        objects: &ok,
    };
    assert!(matches!(
        world.first_collision(&state, &mut scratch),
        Err(CollisionError::NonFinite { .. })
    ));

    // Names.
    let mut b = CollisionWorldBuilder::new();
    b.add_robot("left", &robot, None);
    b.add_fixed_box("left", [0.0; 3], [1.0; 3]);
    assert_eq!(
        b.build().err(),
        Some(BuildError::DuplicateName {
            name: "left".into()
        })
    );
    let mut b = CollisionWorldBuilder::new();
    b.add_fixed_box("a/b", [0.0; 3], [1.0; 3]);
    assert!(matches!(b.build(), Err(BuildError::BadName { .. })));
}

#[test]
fn scratch_is_reused_across_worlds_and_states() {
    // One scratch, different worlds and states: results must not leak between calls.
    let (world, fa, fb) = handoff_world();
    let robots: [&[Iso]; 2] = [&fa, &fb];
    let mut scratch = CollisionScratch::default();
    let held = [ObjectState::free(Iso::identity())
        .also_held_by(Holder::Robot(0))
        .also_held_by(Holder::Robot(1))];
    let free = [ObjectState::free(Iso::translation(3.0, 0.0, 0.0))];
    for _ in 0..3 {
        for objects in [&held, &free] {
            let state = Configuration {
                robots: &robots,
                objects,
            };
            assert_eq!(world.first_collision(&state, &mut scratch), Ok(None));
        }
        let mut b = CollisionWorldBuilder::new();
        b.add_object(
            "x",
            vec![Solid {
                local: Iso::identity(),
                shape: SharedShape::ball(0.1),
            }],
        );
        b.add_object(
            "y",
            vec![Solid {
                local: Iso::identity(),
                shape: SharedShape::ball(0.1),
            }],
        );
        let small = b.build().expect("valid world");
        let objects = [
            ObjectState::free(Iso::identity()),
            ObjectState::free(Iso::translation(0.1, 0.0, 0.0)),
        ];
        let state = Configuration {
            robots: &[],
            objects: &objects,
        };
        assert_eq!(
            small.first_collision(&state, &mut scratch),
            Ok(Some(Collision {
                a: BodyId::Object(0),
                b: BodyId::Object(1)
            }))
        );
    }
}
