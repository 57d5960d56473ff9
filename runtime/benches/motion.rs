//! Joint motion planning (`cellc_runtime::motion`): one LWR arm swinging around a pillar
//! (the straight line hits it), and two facing LWR arms swapping sides (the straight line
//! makes them meet), each over a cycle of seeds so the median covers the planner's
//! spread. A summary over 64 seeds (median and worst time, failures) is printed once.
//!
//! The goal these serve: a five-arm line planned with every motion in under 250 ms, so a
//! typical motion should take a few milliseconds.

use std::f64::consts::PI;
use std::hint::black_box;
use std::time::Instant;

use cellc_runtime::motion::{MotionPlanner, MotionProblem, RrtConnect};
use cellc_runtime::scene::ObjectPlacement;
use cellc_runtime::scene::{Scene, SceneScratch};
use cellc_runtime::validity::SceneValidity;
use cellc_runtime::Termination;
use cellc_runtime::{EndEffectorId, ObjectId};
use criterion::{criterion_group, criterion_main, Criterion};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

#[path = "../tests/support/motion_fixture.rs"]
mod fixture;
use fixture::*;

/// The fixture's arms, in the order it declares them.
const LEFT: EndEffectorId = EndEffectorId(0);
const RIGHT: EndEffectorId = EndEffectorId(1);

fn scene(arms: &[(&str, [f64; 4])], boxes: &[(&str, [f64; 3], [f64; 3])]) -> Scene {
    Scene::load(&artifact(arms, boxes), &Repo).expect("the test cell loads")
}

/// Joints of an LWR whose base is at `base` (upright) putting its flange at `at` with the
/// hand pointing straight down, elbow up: A1 turns towards the target, A2/A4 solve the
/// planar two-link problem (upper arm 0.4 m, forearm 0.39 m, shoulder 0.31 m up, flange
/// 0.078 m past the wrist), A6 points the hand down.
fn down(base: [f64; 4], at: [f64; 3]) -> Vec<f64> {
    let (dx, dy) = (at[0] - base[0], at[1] - base[1]);
    let r = dx.hypot(dy);
    let z = at[2] + 0.078 - base[2] - 0.31;
    let (l1, l2) = (0.4_f64, 0.39_f64);
    let d = r.hypot(z);
    let gamma = ((l1 * l1 + l2 * l2 - d * d) / (2.0 * l1 * l2)).acos();
    let alpha = ((l1 * l1 + d * d - l2 * l2) / (2.0 * l1 * d)).acos();
    let a = r.atan2(z) - alpha;
    let b = std::f64::consts::PI - gamma;
    let c = std::f64::consts::PI - a - b;
    let turn = (dy.atan2(dx) - base[3] + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU)
        - std::f64::consts::PI;
    let q = vec![turn, -a, 0.0, b, 0.0, -c, 0.0];
    assert!(q.iter().all(|v| v.is_finite()), "{at:?} is out of reach");
    q
}

/// Plans `problem` once per seed of `seeds`, printing the median and worst time and how
/// many failed.
fn summarise(name: &str, problem: &MotionProblem<'_>, seeds: u64) {
    let mut scratch = SceneScratch::default();
    let planner = RrtConnect::default();
    let mut times = Vec::new();
    let mut points = Vec::new();
    let mut failures = 0;
    for seed in 0..seeds {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let start = Instant::now();
        let result = planner.solve(problem, &mut rng, &Termination::never(), &mut scratch);
        times.push(start.elapsed().as_secs_f64() * 1e3);
        match result {
            Ok(t) => points.push(t.points.len()),
            Err(_) => failures += 1,
        }
    }
    times.sort_by(f64::total_cmp);
    points.sort_unstable();
    println!(
        "{name}: {seeds} seeds, median {:.2} ms, worst {:.2} ms, {failures} failed, median {} points",
        times[times.len() / 2],
        times[times.len() - 1],
        points.get(points.len() / 2).copied().unwrap_or(0),
    );
}

fn bench_problem(c: &mut Criterion, name: &str, problem: &MotionProblem<'_>) {
    summarise(name, problem, 64);
    let mut scratch = SceneScratch::default();
    let planner = RrtConnect::default();
    let never = Termination::never();
    let mut seed = 0;
    c.bench_function(name, |b| {
        b.iter(|| {
            seed = (seed + 1) % 32;
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            black_box(
                planner
                    .solve(problem, &mut rng, &never, &mut scratch)
                    .is_ok(),
            )
        })
    });
}

fn motions(c: &mut Criterion) {
    let arm = [0.0, 0.0, 0.0, 0.0];
    let pillar = scene(
        &[("left", arm)],
        &[("pillar", [0.4, -0.1, 0.0], [0.7, 0.1, 0.75])],
    );
    let validity = SceneValidity::new(&pillar, &[LEFT], &[], ObjectId(0), ObjectPlacement::Absent)
        .expect("one arm");
    let (start, goal) = (down(arm, [0.5, -0.35, 0.35]), down(arm, [0.5, 0.35, 0.35]));
    let one = MotionProblem {
        scene: &pillar,
        arms: &[LEFT],
        start: &start,
        goal: &goal,
        validity: &validity,
        timing: Default::default(),
    };
    bench_problem(c, "motion: one arm around a pillar", &one);

    let (l, r) = ([0.0, 0.0, 0.0, 0.0], [1.0, 0.0, 0.0, PI]);
    let facing = scene(&[("left", l), ("right", r)], &[]);
    let (a, b) = ([0.5, 0.25, 0.3], [0.5, -0.25, 0.3]);
    let validity = SceneValidity::new(
        &facing,
        &[LEFT, RIGHT],
        &[],
        ObjectId(0),
        ObjectPlacement::Absent,
    )
    .expect("two arms");
    let (start, goal) = (
        [down(l, a), down(r, b)].concat(),
        [down(l, b), down(r, a)].concat(),
    );
    let two = MotionProblem {
        scene: &facing,
        arms: &[LEFT, RIGHT],
        start: &start,
        goal: &goal,
        validity: &validity,
        timing: Default::default(),
    };
    bench_problem(c, "motion: two arms swapping sides", &two);
}

criterion_group!(benches, motions);
criterion_main!(benches);
