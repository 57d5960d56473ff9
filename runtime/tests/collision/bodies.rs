//! Scenes without robots: boxes and spheres, overlapping or not, and the world shared
//! between threads.

use cellc_runtime::collision::{
    BodyId, CollisionScratch, CollisionWorld, CollisionWorldBuilder, Configuration, ObjectState,
    Solid,
};
use cellc_runtime::math::Iso;
use parry3d_f64::shape::SharedShape;

use super::{all, first};

#[test]
fn world_is_shareable_between_threads() {
    fn send_sync<T: Send + Sync>() {}
    send_sync::<CollisionWorld>();
    send_sync::<CollisionScratch>();
}

#[test]
fn boxes_overlap_or_not() {
    let mut b = CollisionWorldBuilder::new();
    let table = b.add_fixed_box("table", [0.0, -0.5, 0.70], [1.0, 0.5, 0.75]);
    b.add_fixed_box("shelf", [0.0, -0.5, 0.72], [0.3, 0.5, 1.2]);
    let crate_ = b.add_object(
        "crate",
        vec![Solid {
            local: Iso::identity(),
            shape: SharedShape::cuboid(0.1, 0.1, 0.1),
        }],
    );
    let world = b.build().expect("valid world");
    assert_eq!(crate_, 0);

    // Above the table, clear of everything.
    let objects = [ObjectState::free(Iso::translation(0.6, 0.0, 0.9))];
    let state = Configuration {
        robots: &[],
        objects: &objects,
    };
    assert_eq!(first(&world, &state), None);
    // The table and the shelf overlap, but fixed bodies never move: not reported.
    assert!(all(&world, &state).is_empty());

    // Sunk 5 cm into the table.
    let objects = [ObjectState::free(Iso::translation(0.6, 0.0, 0.80))];
    let state = Configuration {
        robots: &[],
        objects: &objects,
    };
    assert_eq!(
        first(&world, &state),
        Some(("table".to_string(), "crate".to_string()))
    );

    // Resting on the table: touching is allowed, even sunk a little.
    let objects = [ObjectState::resting(
        Iso::translation(0.6, 0.0, 0.849),
        table,
    )];
    let state = Configuration {
        robots: &[],
        objects: &objects,
    };
    assert_eq!(first(&world, &state), None);

    // Resting on the table but pushed into the shelf: the shelf is still reported.
    let objects = [ObjectState::resting(
        Iso::translation(0.35, 0.0, 0.85),
        table,
    )];
    let state = Configuration {
        robots: &[],
        objects: &objects,
    };
    assert_eq!(
        all(&world, &state),
        vec![("shelf".to_string(), "crate".to_string())]
    );

    // An absent object is not checked.
    let objects = [ObjectState::absent()];
    let state = Configuration {
        robots: &[],
        objects: &objects,
    };
    assert_eq!(first(&world, &state), None);
}

#[test]
fn spheres_without_robots() {
    let mut b = CollisionWorldBuilder::new();
    for name in ["a", "b", "c"] {
        b.add_object(
            name,
            vec![Solid {
                local: Iso::identity(),
                shape: SharedShape::ball(0.1),
            }],
        );
    }
    let world = b.build().expect("valid world");
    let mut scratch = CollisionScratch::default();

    // a and b 0.15 apart (overlapping by 5 cm), c far away.
    let objects = [
        ObjectState::free(Iso::translation(0.0, 0.0, 0.0)),
        ObjectState::free(Iso::translation(0.15, 0.0, 0.0)),
        ObjectState::free(Iso::translation(0.0, 0.0, 5.0)),
    ];
    let state = Configuration {
        robots: &[],
        objects: &objects,
    };
    assert_eq!(all(&world, &state), vec![("a".into(), "b".into())]);
    let c = world
        .first_collision(&state, &mut scratch)
        .expect("well-formed")
        .expect("a and b collide");
    assert_eq!((c.a, c.b), (BodyId::Object(0), BodyId::Object(1)));

    // Spread out: free, and the clearance query finds the closest pair.
    let objects = [
        ObjectState::free(Iso::translation(0.0, 0.0, 0.0)),
        ObjectState::free(Iso::translation(0.3, 0.0, 0.0)),
        ObjectState::free(Iso::translation(0.0, 0.25, 0.0)),
    ];
    let state = Configuration {
        robots: &[],
        objects: &objects,
    };
    assert!(world.is_free(&state, &mut scratch).expect("well-formed"));
    let near = world
        .clearance(&state, &mut scratch, 0.5)
        .expect("well-formed")
        .expect("pairs within 0.5 m");
    assert_eq!((near.a, near.b), (BodyId::Object(0), BodyId::Object(2)));
    assert!((near.distance - 0.05).abs() < 1e-9, "{}", near.distance);
    // Nothing within 1 cm.
    assert_eq!(
        world
            .clearance(&state, &mut scratch, 0.01)
            .expect("well-formed"),
        None
    );
}
