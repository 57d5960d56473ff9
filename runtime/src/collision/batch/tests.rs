//! The batched screen against brute force on random worlds: every verdict it gives is
//! the exact answer, and with its capsules shrunk (an unsound screen) the comparison
//! finds states it calls free that collide.

use parry3d_f64::query;
use parry3d_f64::shape::SharedShape;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::super::{CollisionWorldBuilder, Hand, Solid};
use super::*;
use crate::math::Vec3;
use crate::robot::LinkShape;

fn random_pose(rng: &mut ChaCha8Rng, spread: f64) -> Iso {
    let t = Vec3::from_fn(|_, _| rng.random_range(-spread..spread));
    let axis = Vec3::from_fn(|_, _| rng.random_range(-1.0..1.0));
    Iso::new(t, axis * rng.random_range(0.0..3.0))
}

fn random_shape(rng: &mut ChaCha8Rng) -> SharedShape {
    let s: [f64; 3] = std::array::from_fn(|_| rng.random_range(0.02..0.25));
    match rng.random_range(0..3) {
        0 => SharedShape::ball(s[0]),
        1 => SharedShape::cuboid(s[0], s[1], s[2]),
        _ => SharedShape::cylinder(s[0], s[1]),
    }
}

/// Whether the state with the moving chain's frames `frames` collides, every pair that
/// may not touch tested exactly (no broad phase, no capsules).
fn collides(world: &CollisionWorld, frames: &[Iso]) -> bool {
    let pose = |i: usize| {
        let b = &world.bodies[i];
        match b.mount {
            Mount::Frame { frame, .. } => frames[frame] * b.local,
            _ => b.local,
        }
    };
    let n = world.bodies.len();
    (0..n).any(|i| {
        (i + 1..n).any(|j| {
            let moving = |k: usize| matches!(world.bodies[k].mount, Mount::Frame { .. });
            if !(moving(i) || moving(j)) || world.allowed.get(i, j) {
                return false;
            }
            let (si, sj) = (
                world.bodies[i].shape.as_ref(),
                world.bodies[j].shape.as_ref(),
            );
            query::intersection_test(&pose(i), si, &pose(j), sj).expect("supported")
        })
    })
}

/// Screens random states of a random chain among random fixed bodies, in batches,
/// with capsules shrunk by `shrink`: (states proved free, proved colliding, states
/// whose verdict brute force contradicts).
fn screen_against_brute_force(shrink: f64) -> (usize, usize, usize) {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let (mut free, mut colliding, mut wrong) = (0, 0, 0);
    for _ in 0..60 {
        let mut b = CollisionWorldBuilder::new();
        let shapes = (0..8)
            .map(|k| LinkShape {
                link: format!("link_{}", k / 2),
                frame: k / 2,
                local: random_pose(&mut rng, 0.15),
                shape: random_shape(&mut rng),
            })
            .collect();
        let hand = Hand {
            name: "hand".into(),
            solids: vec![Solid {
                local: random_pose(&mut rng, 0.05),
                shape: random_shape(&mut rng),
            }],
        };
        b.add_chain(
            "arm",
            4,
            Iso::identity(),
            shapes,
            |a, c| a.abs_diff(c) <= 1,
            Some(hand),
        );
        for k in 0..6 {
            let (pose, shape) = (random_pose(&mut rng, 1.0), random_shape(&mut rng));
            b.add_fixed(&format!("f{k}"), pose, shape);
        }
        let world = b.build().expect("valid world");
        let home_frames: Vec<Iso> = (0..4).map(|_| random_pose(&mut rng, 1.0)).collect();
        let robots: [&[Iso]; 1] = [&home_frames];
        let state = Configuration {
            robots: &robots,
            objects: &[],
        };
        let home = world.at_home(&state).expect("a home");
        let mut scratch = super::super::CollisionScratch::default();
        let frozen = world
            .freeze(&home, &state, &[true], &[false], &[], true, &mut scratch)
            .expect("frozen");
        let standing = Standing {
            home: &home,
            live: frozen.moving(),
            frozen: Some(&frozen),
        };
        let mut batch = BatchScratch {
            shrink,
            ..BatchScratch::default()
        };
        for _ in 0..10 {
            // A batch of states along a random walk of the chain's frames.
            let mut states: Vec<Vec<Iso>> = Vec::new();
            world.batch_begin(&standing, &mut batch);
            let mut frames: Vec<Iso> = (0..4).map(|_| random_pose(&mut rng, 0.8)).collect();
            for _ in 0..8 {
                for f in &mut frames {
                    *f = random_pose(&mut rng, 0.05) * *f;
                }
                let robots: [&[Iso]; 1] = [&frames];
                let state = Configuration {
                    robots: &robots,
                    objects: &[],
                };
                world.batch_place(&standing, &state, &mut batch);
                states.push(frames.clone());
            }
            let mut out = vec![None; states.len()];
            world.batch_clear(&standing, &mut batch, &mut out);
            for (frames, verdict) in states.iter().zip(&out) {
                let Some(free_here) = *verdict else {
                    continue;
                };
                if free_here {
                    free += 1;
                } else {
                    colliding += 1;
                }
                if free_here == collides(&world, frames) {
                    wrong += 1;
                }
            }
        }
    }
    (free, colliding, wrong)
}

/// The screen's verdicts are brute force's, and both occur often.
#[test]
fn the_screens_verdicts_are_exact() {
    let (free, colliding, wrong) = screen_against_brute_force(0.0);
    assert_eq!(wrong, 0);
    assert!(
        free >= 300 && colliding >= 100,
        "{free} free, {colliding} colliding"
    );
}

/// Capsules 3 cm smaller than their bodies make the screen unsound, and the comparison
/// with brute force shows it: the test above would fail.
#[test]
fn a_screen_with_shrunk_capsules_is_caught() {
    let (_, _, wrong) = screen_against_brute_force(0.03);
    assert!(wrong >= 10, "only {wrong} wrong verdicts");
}
