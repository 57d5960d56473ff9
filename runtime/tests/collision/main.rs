//! The collision world: static scenes, the LWR's self-collision, arms against furniture,
//! held objects, allowed pairs, two arms, and the state checks.
//!
//! This file holds the shared models, worlds and queries; the modules hold the cases:
//! `bodies.rs` scenes without robots, `arms.rs` the LWR against itself, furniture, allowed
//! pairs and another arm, `held.rs` held and handed-off objects, `states.rs` malformed
//! states and scratch buffers reused across worlds.

use std::f64::consts::{FRAC_PI_2, FRAC_PI_6};

use cellc_runtime::collision::{
    Collision, CollisionScratch, CollisionWorld, CollisionWorldBuilder, Configuration, Hand, Solid,
};
use cellc_runtime::math::{Iso, Vec3};
use cellc_runtime::robot::Robot;
use cellc_runtime::{FileError, Files};
use parry3d_f64::shape::SharedShape;

mod arms;
mod bodies;
mod held;
mod states;

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
