//! The LWR against itself (at zero, folded onto its base), through a table, with the
//! cell's allowed pairs, and against a second arm close by.

use cellc_runtime::collision::{BodyId, BuildError, CollisionWorldBuilder, Configuration};
use cellc_runtime::math::Iso;

use super::{all, deg, first, frames, is_link, lwr, softhand};

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
