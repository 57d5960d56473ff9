//! One full collision-world check of the Vito cell (`cells/vito.cell`): two KUKA LWR 4+
//! arms with SoftHands, the table, the bin floor, and a cylinder held by the left hand
//! above the table. Variants: collision-free, and the held cylinder lowered into the table
//! (the kind of state verification rejects), each for `first_collision`, plus
//! `all_collisions`, a 5 cm `clearance` query, and forward kinematics plus the check (what
//! a planner pays per sampled configuration).
//!
//! Heap allocations per check are counted and printed once: after the scratch has grown,
//! a check must allocate nothing.

use std::alloc::{GlobalAlloc, Layout, System};
use std::f64::consts::{FRAC_PI_2, FRAC_PI_6, PI};
use std::hint::black_box;
use std::sync::atomic::{AtomicUsize, Ordering};

use cellc_runtime::collision::{
    CollisionScratch, CollisionWorld, CollisionWorldBuilder, Configuration, Hand, ObjectState,
    Solid,
};
use cellc_runtime::kinematics::{solve_ik, IkOptions, IkTarget};
use cellc_runtime::math::{Iso, Quat, Vec3};
use cellc_runtime::robot::Robot;
use cellc_runtime::Termination;
use cellc_runtime::{FileError, Files};
use criterion::{criterion_group, criterion_main, Criterion};
use parry3d_f64::shape::SharedShape;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

/// Counts allocations.
struct Counting;

static ALLOCS: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCS.fetch_add(1, Ordering::Relaxed);
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, p: *mut u8, layout: Layout) {
        unsafe { System.dealloc(p, layout) };
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

struct Repo;

impl Files for Repo {
    fn read(&self, path: &str) -> Result<Vec<u8>, FileError> {
        let full = format!("{}/../{path}", env!("CARGO_MANIFEST_DIR"));
        Ok(std::fs::read(full)?)
    }
}

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

fn rpy(t: [f64; 3], r: [f64; 3]) -> Iso {
    Iso::from_parts(
        t.into(),
        Quat::from_euler_angles(r[0].to_radians(), r[1].to_radians(), r[2].to_radians()),
    )
}

struct Vito {
    robot: Robot,
    world: CollisionWorld,
    bases: [Iso; 2],
    /// Joint values of the free and the colliding state, per arm.
    free: [Vec<f64>; 2],
    colliding: [Vec<f64>; 2],
    grasp: Iso,
}

/// Joint values putting `robot`'s hand at `position`, pointing down.
fn reach(robot: &Robot, base: &Iso, position: [f64; 3], seed: &[f64]) -> Vec<f64> {
    let down = Iso::from_parts(position.into(), Quat::from_axis_angle(&Vec3::x_axis(), PI));
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    solve_ik(
        robot,
        base,
        &IkTarget::Pose(down),
        seed,
        &mut rng,
        &IkOptions::default(),
        &Termination::never(),
    )
    .expect("the Vito arms reach over the table")
}

fn vito() -> Vito {
    let path = "cells/robots/kuka_lwr4.urdf";
    let text = String::from_utf8(Repo.read(path).expect("URDF")).expect("UTF-8");
    let robot =
        Robot::from_urdf(&text, path, "lwr_base_link", "lwr_flange", &Repo).expect("the LWR loads");
    let mut b = CollisionWorldBuilder::new();
    b.add_robot("left", &robot, Some(softhand()));
    b.add_robot("right", &robot, Some(softhand()));
    b.add_fixed_box("table", [0.2, -0.7, 0.74], [1.0, 0.7, 0.76]);
    b.add_fixed_box("bin", [0.15, -0.85, 0.39], [0.45, -0.55, 0.41]);
    let cylinder = z_cylinder(Iso::identity(), 0.04, 0.2);
    b.add_object("cylinder", vec![cylinder]);
    let world = b.build().expect("the Vito world");
    let bases = [
        rpy([0.0, 0.3, 1.0], [-90.0, 0.0, 0.0]),
        rpy([0.0, -0.3, 1.0], [90.0, 0.0, 0.0]),
    ];
    // `grasp top by softhand at (0, 0.04, 0.2) rpy (180, 0, 0)`.
    let grasp = rpy([0.0, 0.04, 0.2], [180.0, 0.0, 0.0]);
    let seed = [0.0, 0.5, 0.0, -1.2, 0.0, 0.8, 0.0];
    // Left: the cylinder (0.2 below the flange) 4 cm above the table; lowered 8 cm it
    // goes 4 cm into the table while the fingertips stay above it. Right: waiting.
    let left_up = reach(&robot, &bases[0], [0.55, 0.25, 1.10], &seed);
    let left_down = reach(&robot, &bases[0], [0.55, 0.25, 1.02], &left_up);
    let right = reach(&robot, &bases[1], [0.55, -0.3, 1.15], &seed);
    Vito {
        robot,
        world,
        bases,
        free: [left_up, right.clone()],
        colliding: [left_down, right],
        grasp,
    }
}

impl Vito {
    fn frames(&self, q: &[Vec<f64>; 2], frames: &mut [Vec<Iso>; 2]) {
        for k in 0..2 {
            self.robot.fk_frames(&self.bases[k], &q[k], &mut frames[k]);
        }
    }

    fn objects(&self, frames: &[Vec<Iso>; 2]) -> [ObjectState; 1] {
        let tip = self.world.tip(0, &frames[0]).expect("left arm frames");
        [ObjectState::held(0, &tip, &self.grasp)]
    }
}

fn bench(c: &mut Criterion) {
    let v = vito();
    let mut scratch = CollisionScratch::default();
    let mut free_frames = [Vec::new(), Vec::new()];
    let mut hit_frames = [Vec::new(), Vec::new()];
    v.frames(&v.free, &mut free_frames);
    v.frames(&v.colliding, &mut hit_frames);
    let free_objects = v.objects(&free_frames);
    let hit_objects = v.objects(&hit_frames);
    let free_robots: [&[Iso]; 2] = [&free_frames[0], &free_frames[1]];
    let hit_robots: [&[Iso]; 2] = [&hit_frames[0], &hit_frames[1]];
    let free = Configuration {
        robots: &free_robots,
        objects: &free_objects,
    };
    let hit = Configuration {
        robots: &hit_robots,
        objects: &hit_objects,
    };

    let mut found = Vec::new();
    v.world
        .all_collisions(&free, &mut scratch, &mut found)
        .expect("well-formed");
    assert!(found.is_empty(), "free state collides: {found:?}");
    v.world
        .all_collisions(&hit, &mut scratch, &mut found)
        .expect("well-formed");
    let pairs: Vec<_> = found.iter().map(|c| v.world.describe(c)).collect();
    assert_eq!(pairs, ["`table` and `cylinder`"], "colliding state");
    let near = v
        .world
        .clearance(&free, &mut scratch, 0.05)
        .expect("well-formed");
    eprintln!(
        "bodies: {}; free state: closest pair within 5 cm: {}",
        v.world.bodies().count(),
        near.map_or("none".to_string(), |p| format!(
            "{} and {} at {:.3} m",
            v.world.name(p.a),
            v.world.name(p.b),
            p.distance
        ))
    );

    let before = ALLOCS.load(Ordering::Relaxed);
    for _ in 0..100 {
        black_box(v.world.first_collision(&free, &mut scratch).ok());
        black_box(v.world.first_collision(&hit, &mut scratch).ok());
        black_box(v.world.clearance(&free, &mut scratch, 0.05).ok());
        black_box(v.world.all_collisions(&hit, &mut scratch, &mut found).ok());
    }
    eprintln!(
        "heap allocations in 400 warm queries: {}",
        ALLOCS.load(Ordering::Relaxed) - before
    );

    let mut g = c.benchmark_group("collision");
    g.bench_function("first_collision/free", |b| {
        b.iter(|| v.world.first_collision(black_box(&free), &mut scratch))
    });
    g.bench_function("first_collision/colliding", |b| {
        b.iter(|| v.world.first_collision(black_box(&hit), &mut scratch))
    });
    g.bench_function("all_collisions/free", |b| {
        b.iter(|| {
            v.world
                .all_collisions(black_box(&free), &mut scratch, &mut found)
        })
    });
    g.bench_function("clearance_5cm/free", |b| {
        b.iter(|| v.world.clearance(black_box(&free), &mut scratch, 0.05))
    });
    let mut frames = [Vec::new(), Vec::new()];
    g.bench_function("fk_and_first_collision/free", |b| {
        b.iter(|| {
            v.frames(black_box(&v.free), &mut frames);
            let objects = v.objects(&frames);
            let robots: [&[Iso]; 2] = [&frames[0], &frames[1]];
            let state = Configuration {
                robots: &robots,
                objects: &objects,
            };
            v.world.first_collision(&state, &mut scratch).ok()
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
