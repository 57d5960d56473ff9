//! The collision world: static scenes, the LWR's self-collision, arms against furniture,
//! held objects, allowed pairs, two arms, and the state checks.

use std::f64::consts::{FRAC_PI_2, FRAC_PI_6};

use cellc_runtime::collision::{
    BodyId, BuildError, Collision, CollisionError, CollisionScratch, CollisionWorld,
    CollisionWorldBuilder, Configuration, Hand, Holder, ObjectState, Solid,
};
use cellc_runtime::math::{Iso, Vec3};
use cellc_runtime::robot::Robot;
use cellc_runtime::{FileError, Files};
use parry3d_f64::shape::SharedShape;

/// Reads files from the repository (paths relative to the workspace root).
struct Repo;

impl Files for Repo {
    fn read(&self, path: &str) -> Result<Vec<u8>, FileError> {
        let full = format!("{}/../{path}", env!("CARGO_MANIFEST_DIR"));
        Ok(std::fs::read(full)?)
    }
}

fn lwr() -> Robot {
    let path = "cells/robots/kuka_lwr4.urdf";
    let bytes = Repo.read(path).expect("the LWR URDF is in the repository");
    let text = String::from_utf8(bytes).expect("the URDF is UTF-8");
    Robot::from_urdf(&text, path, "lwr_base_link", "lwr_flange", &Repo).expect("the LWR loads")
}

/// A cylinder along z (parry's are along y).
fn z_cylinder(at: Iso, radius: f64, height: f64) -> Solid {
    Solid {
        local: at * Iso::rotation(Vec3::x() * FRAC_PI_2),
        shape: SharedShape::cylinder(height / 2.0, radius),
    }
}

fn cuboid(at: Iso, size: [f64; 3]) -> Solid {
    Solid {
        local: at,
        shape: SharedShape::cuboid(size[0] / 2.0, size[1] / 2.0, size[2] / 2.0),
    }
}

/// The SoftHand's solids, as in `cells/robots/softhand.cell`.
fn softhand() -> Hand {
    Hand {
        name: "softhand".into(),
        solids: vec![
            z_cylinder(Iso::translation(0.0, 0.0, 0.01), 0.035, 0.02),
            cuboid(Iso::translation(0.0, 0.0, 0.07), [0.09, 0.03, 0.10]),
            cuboid(Iso::translation(0.0, 0.0, 0.1625), [0.085, 0.025, 0.085]),
            z_cylinder(
                Iso::translation(0.05, 0.0325, 0.0803) * Iso::rotation(Vec3::x() * -FRAC_PI_6),
                0.012,
                0.07,
            ),
        ],
    }
}

fn deg(d: f64) -> f64 {
    d.to_radians()
}

fn frames(robot: &Robot, base: &Iso, q: &[f64]) -> Vec<Iso> {
    let mut f = Vec::new();
    robot.fk_frames(base, q, &mut f);
    f
}

fn names(world: &CollisionWorld, c: &Collision) -> (String, String) {
    let (a, b) = world.names(c);
    (a.to_string(), b.to_string())
}

fn all(world: &CollisionWorld, state: &Configuration<'_>) -> Vec<(String, String)> {
    let mut out = Vec::new();
    world
        .all_collisions(state, &mut CollisionScratch::default(), &mut out)
        .expect("a well-formed state");
    out.iter().map(|c| names(world, c)).collect()
}

fn first(world: &CollisionWorld, state: &Configuration<'_>) -> Option<(String, String)> {
    world
        .first_collision(state, &mut CollisionScratch::default())
        .expect("a well-formed state")
        .map(|c| names(world, &c))
}

fn is_link(name: &str, robot: &str) -> bool {
    name.starts_with(&format!("{robot}/lwr_"))
}

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

#[test]
fn lwr_zero_pose_has_no_self_collision() {
    let robot = lwr();
    let mut b = CollisionWorldBuilder::new();
    b.add_robot("left", &robot, Some(softhand()));
    let world = b.build().expect("valid world");
    let f = frames(&robot, &Iso::identity(), &[0.0; 7]);
    let state = Configuration {
        robots: &[&f],
        objects: &[],
    };
    assert_eq!(all(&world, &state), Vec::<(String, String)>::new());

    // Each joint alone through its whole range: the bare arm's non-adjacent links never
    // touch then (`cells/robots/README.md`). With the hand they do: A6 folds the hand back
    // onto the forearm near its limits, as on the real arm.
    let mut b = CollisionWorldBuilder::new();
    b.add_robot("left", &robot, None);
    let world = b.build().expect("valid world");
    let (lower, upper) = robot.limits();
    for j in 0..7 {
        for k in 0..=12 {
            let mut q = [0.0; 7];
            q[j] = lower[j] + (upper[j] - lower[j]) * k as f64 / 12.0;
            let f = frames(&robot, &Iso::identity(), &q);
            let state = Configuration {
                robots: &[&f],
                objects: &[],
            };
            assert_eq!(first(&world, &state), None, "joint {j} at {:.3}", q[j]);
        }
    }
    let mut b = CollisionWorldBuilder::new();
    b.add_robot("left", &robot, Some(softhand()));
    let world = b.build().expect("valid world");
    let f = frames(
        &robot,
        &Iso::identity(),
        &[0.0, 0.0, 0.0, 0.0, 0.0, deg(-120.0), 0.0],
    );
    let state = Configuration {
        robots: &[&f],
        objects: &[],
    };
    assert_eq!(
        first(&world, &state),
        Some(("left/lwr_link_5".to_string(), "left/softhand".to_string()))
    );
}

#[test]
fn lwr_folded_hits_its_own_base() {
    let robot = lwr();
    let mut b = CollisionWorldBuilder::new();
    b.add_robot("left", &robot, Some(softhand()));
    let world = b.build().expect("valid world");
    for (a2, a4) in [(120.0, -120.0), (-120.0, 120.0)] {
        let q = [0.0, deg(a2), 0.0, deg(a4), 0.0, 0.0, 0.0];
        let f = frames(&robot, &Iso::identity(), &q);
        let state = Configuration {
            robots: &[&f],
            objects: &[],
        };
        let found = all(&world, &state);
        assert!(
            found
                .iter()
                .any(|(a, b)| a == "left/lwr_base_link" || b == "left/lwr_base_link"),
            "A2 {a2}, A4 {a4}: {found:?}"
        );
        let (a, b) = first(&world, &state).expect("a collision");
        assert!(is_link(&a, "left") || a == "left/softhand", "{a}");
        assert!(is_link(&b, "left") || b == "left/softhand", "{b}");
    }
}

#[test]
fn arm_through_table() {
    let robot = lwr();
    let mut b = CollisionWorldBuilder::new();
    b.add_robot("left", &robot, Some(softhand()));
    // A slab at 0.60 .. 0.62 m across the straight-up arm.
    b.add_fixed_box("table", [-0.5, -0.5, 0.60], [0.5, 0.5, 0.62]);
    let world = b.build().expect("valid world");
    let f = frames(&robot, &Iso::identity(), &[0.0; 7]);
    let state = Configuration {
        robots: &[&f],
        objects: &[],
    };
    let found = all(&world, &state);
    assert!(!found.is_empty());
    for (a, b) in &found {
        assert!(is_link(a, "left"), "{a}");
        assert_eq!(b, "table");
    }
    assert_eq!(
        first(&world, &state).map(|p| p.1),
        Some("table".to_string())
    );

    // The same arm mounted on a table surface: the cell allows the base on it, and
    // the arm above is free.
    let mut b = CollisionWorldBuilder::new();
    b.add_robot("left", &robot, Some(softhand()));
    b.add_fixed_box("bench", [-0.5, -0.5, -0.05], [0.5, 0.5, 0.005]);
    let world = b.build().expect("valid world");
    let f = frames(&robot, &Iso::identity(), &[0.0; 7]);
    let state = Configuration {
        robots: &[&f],
        objects: &[],
    };
    assert_eq!(
        first(&world, &state),
        Some(("left/lwr_base_link".to_string(), "bench".to_string()))
    );
}

#[test]
fn allowed_pairs_from_the_cell() {
    let robot = lwr();
    let f = frames(&robot, &Iso::identity(), &[0.0; 7]);
    let state = Configuration {
        robots: &[&f],
        objects: &[],
    };
    let build = |allow: &[(&str, &str)]| {
        let mut b = CollisionWorldBuilder::new();
        b.add_robot("left", &robot, Some(softhand()));
        b.add_fixed_box("bench", [-0.5, -0.5, -0.05], [0.5, 0.5, 0.005]);
        b.add_fixed_box("table", [-0.5, -0.5, 0.60], [0.5, 0.5, 0.62]);
        for (x, y) in allow {
            b.allow(x, y);
        }
        b.build()
    };
    let world = build(&[]).expect("valid world");
    assert_eq!(
        all(&world, &state),
        vec![
            ("left/lwr_base_link".to_string(), "bench".to_string()),
            ("left/lwr_link_3".to_string(), "table".to_string()),
        ]
    );
    // One body by name: only that pair goes.
    let world = build(&[("bench", "left/lwr_base_link")]).expect("valid world");
    assert_eq!(
        all(&world, &state),
        vec![("left/lwr_link_3".to_string(), "table".to_string())]
    );
    // A robot's name stands for all its bodies.
    let world = build(&[("bench", "left/lwr_base_link"), ("left", "table")]).expect("valid");
    assert_eq!(first(&world, &state), None);
    assert!(world.is_allowed(BodyId::Fixed(1), BodyId::Link { robot: 0, shape: 4 }));
    // Unknown names are refused.
    assert_eq!(
        build(&[("left/lwr_link_9", "table")]).err(),
        Some(BuildError::UnknownName {
            name: "left/lwr_link_9".into()
        })
    );
}

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

/// Two hands on base-only "robots" (one frame, no links), facing each other along x
/// around an object at the origin.
fn handoff_world() -> (CollisionWorld, Vec<Iso>, Vec<Iso>) {
    let hand = || Hand {
        name: "gripper".into(),
        solids: vec![cuboid(Iso::translation(0.0, 0.0, 0.05), [0.06, 0.06, 0.1])],
    };
    let mut b = CollisionWorldBuilder::new();
    for name in ["a", "b"] {
        b.add_chain(
            name,
            1,
            Iso::identity(),
            Vec::new(),
            |x, y| x.abs_diff(y) <= 1,
            Some(hand()),
        );
    }
    b.add_object(
        "ball",
        vec![Solid {
            local: Iso::identity(),
            shape: SharedShape::ball(0.05),
        }],
    );
    let world = b.build().expect("valid world");
    // Hand frames' z point at the origin; the fingers reach 1 cm into the ball.
    let fa = vec![Iso::translation(-0.14, 0.0, 0.0) * Iso::rotation(Vec3::y() * FRAC_PI_2)];
    let fb = vec![Iso::translation(0.14, 0.0, 0.0) * Iso::rotation(Vec3::y() * -FRAC_PI_2)];
    (world, fa, fb)
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

#[test]
fn two_arms_close_together() {
    let robot = lwr();
    let mut b = CollisionWorldBuilder::new();
    b.add_robot("left", &robot, Some(softhand()));
    b.add_robot("right", &robot, Some(softhand()));
    let world = b.build().expect("valid world");
    let base_left = Iso::translation(0.0, 0.0, 0.0);
    let base_right = Iso::translation(0.0, 0.5, 0.0);
    let fr = frames(&robot, &base_right, &[0.0; 7]);

    // Side by side, upright: free.
    let fl = frames(&robot, &base_left, &[0.0; 7]);
    let state = Configuration {
        robots: &[&fl, &fr],
        objects: &[],
    };
    assert_eq!(first(&world, &state), None);

    // A1 -90 turns the tilt towards +y; A2 90 lays the left arm across the right one.
    let fl = frames(
        &robot,
        &base_left,
        &[deg(-90.0), deg(90.0), 0.0, 0.0, 0.0, 0.0, 0.0],
    );
    let state = Configuration {
        robots: &[&fl, &fr],
        objects: &[],
    };
    let found = all(&world, &state);
    assert!(!found.is_empty());
    for (a, b) in &found {
        assert!(a.starts_with("left/"), "{a}");
        assert!(b.starts_with("right/"), "{b}");
    }
}

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
