//! Kinematics benchmarks on the shipped KUKA LWR 4+ model: forward kinematics, one
//! full-pose IK solve from a cold (random) start, and one closed-chain handoff between two
//! facing arms.
//!
//! Besides criterion's estimates, each solver case first runs a fixed set of problems once
//! and prints the success rate, the median and 90th-percentile time per solve (criterion's
//! own figure is a mean over its samples, which the slow tail of restarts pulls up), and
//! the heap allocations per solve (counted by a wrapping allocator: a fixed handful per
//! call, none per iteration).

use std::alloc::{GlobalAlloc, Layout, System};
use std::f64::consts::{FRAC_PI_2, PI};
use std::hint::black_box;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

use cellc_runtime::kinematics::closed_chain::{solve_handoff, HandoffOptions, HandoffProblem};
use cellc_runtime::kinematics::{random_configuration, solve_ik, IkOptions, IkTarget};
use cellc_runtime::math::{Iso, Point, Vec3};
use cellc_runtime::robot::Robot;
use cellc_runtime::MemoryFiles;
use cellc_runtime::Termination;
use criterion::{criterion_group, criterion_main, Criterion};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Counts heap allocations.
struct Counting;

static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, p: *mut u8, layout: Layout) {
        unsafe { System.dealloc(p, layout) };
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

fn lwr() -> Robot {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../cells/robots/kuka_lwr4.urdf");
    let text = std::fs::read_to_string(path).expect("the shipped LWR model is readable");
    Robot::from_urdf(
        &text,
        "kuka_lwr4.urdf",
        "lwr_base_link",
        "lwr_flange",
        // The LWR has no meshes, so no file is ever read.
        &MemoryFiles::default(),
    )
    .expect("the LWR model loads")
}

/// Success rate, median and 90th percentile of `solve` over `cases` (each run once).
fn summarise<T>(name: &str, cases: &[T], mut solve: impl FnMut(&T) -> bool) {
    let mut times: Vec<Duration> = Vec::with_capacity(cases.len());
    let mut successes = 0;
    let allocations_before = ALLOCATIONS.load(Ordering::Relaxed);
    for case in cases {
        let start = Instant::now();
        if solve(case) {
            successes += 1;
        }
        times.push(start.elapsed());
    }
    let allocations = ALLOCATIONS.load(Ordering::Relaxed) - allocations_before;
    times.sort();
    let at = |fraction: f64| times[((times.len() - 1) as f64 * fraction).round() as usize];
    println!(
        "{name}: {successes}/{} solved ({:.1}%), median {:.1?}, p90 {:.1?}, max {:.1?}, \
         {:.1} allocations per solve",
        cases.len(),
        100.0 * successes as f64 / cases.len() as f64,
        at(0.5),
        at(0.9),
        at(1.0),
        allocations as f64 / cases.len() as f64,
    );
}

fn forward_kinematics(c: &mut Criterion) {
    let robot = lwr();
    let base = Iso::translation(0.0, 0.25, 1.0);
    let q = [0.3, -0.7, 0.2, 1.1, -0.4, 0.8, 0.1];
    let mut frames = Vec::with_capacity(8);
    c.bench_function("lwr fk_frames", |b| {
        b.iter(|| {
            robot.fk_frames(black_box(&base), black_box(&q), &mut frames);
            black_box(&frames);
        })
    });
    c.bench_function("lwr tip_pose", |b| {
        b.iter(|| black_box(robot.tip_pose(black_box(&base), black_box(&q))))
    });
}

/// Random reachable full-pose targets (FK of random configurations inside the limits),
/// each solved from a random start with its own seeded RNG.
fn inverse_kinematics(c: &mut Criterion) {
    let robot = lwr();
    let base = Iso::identity();
    let opts = IkOptions::default();
    let mut rng = ChaCha8Rng::seed_from_u64(2024);
    let cases: Vec<(Iso, Vec<f64>, u64)> = (0..1000)
        .map(|_| {
            let q = random_configuration(&robot, &mut rng);
            let start = random_configuration(&robot, &mut rng);
            (robot.tip_pose(&base, &q), start, rng.random())
        })
        .collect();
    let solve = |(target, start, seed): &(Iso, Vec<f64>, u64)| {
        let mut rng = ChaCha8Rng::seed_from_u64(*seed);
        solve_ik(
            &robot,
            &base,
            &IkTarget::Pose(*target),
            start,
            &mut rng,
            &opts,
            &Termination::never(),
        )
    };
    summarise("lwr ik (pose, cold start)", &cases, |case| {
        solve(case).is_ok()
    });
    let mut next = 0;
    c.bench_function("lwr ik (pose, cold start)", |b| {
        b.iter(|| {
            next = (next + 1) % cases.len();
            black_box(solve(&cases[next]).is_ok())
        })
    });
}

/// Two LWRs facing each other 1 m apart, each holding the object 0.1 m in front of the
/// flange, targets drawn in a 0.3 m box between them.
fn handoff(c: &mut Criterion) {
    let robot = lwr();
    let base_a = Iso::translation(0.0, -0.5, 0.0) * Iso::rotation(Vec3::z() * FRAC_PI_2);
    let base_b = Iso::translation(0.0, 0.5, 0.0) * Iso::rotation(Vec3::z() * -FRAC_PI_2);
    let grasp_a = Iso::translation(0.0, 0.0, 0.1);
    let grasp_b = Iso::translation(0.0, 0.0, 0.1) * Iso::rotation(Vec3::x() * PI);
    let (min, max) = (Point::new(0.15, -0.15, 0.45), Point::new(0.45, 0.15, 0.75));
    let opts = HandoffOptions::default();
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let cases: Vec<(Point, u64)> = (0..200)
        .map(|_| {
            let target = Point::new(
                rng.random_range(min.x..max.x),
                rng.random_range(min.y..max.y),
                rng.random_range(min.z..max.z),
            );
            (target, rng.random())
        })
        .collect();
    let problem = |target: &Point| HandoffProblem {
        a: (&robot, base_a),
        b: (&robot, base_b),
        grasp_a,
        grasp_b,
        target: *target,
        bounds: Some((min, max)),
    };
    // Both arms start straight up (the zero pose), as a planner without a better guess
    // would seed them.
    let solve = |(target, seed): &(Point, u64)| {
        let mut rng = ChaCha8Rng::seed_from_u64(*seed);
        solve_handoff(
            &problem(target),
            &[0.0; 7],
            &[0.0; 7],
            &mut rng,
            &opts,
            &Termination::never(),
        )
    };
    let near_target = |(target, seed): &(Point, u64)| {
        solve(&(*target, *seed)).is_ok_and(|solution| {
            (solution.object.translation.vector - target.coords).norm() <= opts.target_tolerance
        })
    };
    summarise(
        "lwr-lwr handoff (within target tolerance)",
        &cases,
        near_target,
    );
    // Cold starts: both seeds drawn at random, a harder and less typical case.
    summarise("lwr-lwr handoff, random seeds", &cases, |(target, seed)| {
        let mut rng = ChaCha8Rng::seed_from_u64(*seed);
        let seed_a = random_configuration(&robot, &mut rng);
        let seed_b = random_configuration(&robot, &mut rng);
        solve_handoff(
            &problem(target),
            &seed_a,
            &seed_b,
            &mut rng,
            &opts,
            &Termination::never(),
        )
        .is_ok()
    });
    let mut next = 0;
    c.bench_function("lwr-lwr handoff", |b| {
        b.iter(|| {
            next = (next + 1) % cases.len();
            black_box(solve(&cases[next]).is_ok())
        })
    });
}

criterion_group!(benches, forward_kinematics, inverse_kinematics, handoff);
criterion_main!(benches);
