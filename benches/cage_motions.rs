//! Joint motions of a Franka Panda in a cage of 14 cubes (issue 17; `cells/panda_cage.cell`,
//! VAMP's cage problem with cubes): RRT-Connect, in-process, from start to goal
//! configuration. Two kinds of motion:
//!
//! - `vamp`: VAMP's own start and goal (the SRDF's `default` state, and
//!   `(2.35, 1, 0, -0.8, 0, 2.5, 0.785)` rad), the hand swung from the front of the cage
//!   out through the gap in the lower ring behind it, with no object;
//! - `plan_k`: the motions of the cell's request `through_cage` as planned with seed 0
//!   (the arm to the part on the front cube, the carry round to the pad behind the cage,
//!   the retreat), each planned again from its start to its goal, with the part where
//!   that motion has it.
//!
//! Each criterion iteration plans with the next of [`SEEDS`] seeds; a summary over all
//! of them (median time, success rate) is printed first. The goal of issue 17 is a median
//! at or under 5 ms on `vamp`; VAMP reports 7.5 ms on this problem (Thomason, Kingston and
//! Kavraki, ICRA 2024; figure quoted, VAMP has no wheel to run here).
//!
//! The peer, in the same run: the same motions, joint limits and boxes written to
//! `cage_problem.json` in the target folder and planned by OMPL's RRT-Connect through its
//! Python bindings (`benches/cage_ompl.py`), when `CELLC_PEER_PYTHON` or
//! `/work/venv-peers/bin/python` names a Python with `ompl`, `python-fcl`, `numpy-stl`
//! and `scipy` (`pip install ompl python-fcl numpy-stl scipy`). Both medians and their
//! ratio are printed. How comparable the two are is in docs/performance.md.

use std::hint::black_box;
use std::path::{Path, PathBuf};
use std::time::Instant;

use cellc_driver::fs_files::FsFiles;
use cellc_runtime::motion::{MotionPlanner, MotionProblem, RrtConnect};
use cellc_runtime::plan::{MotionContext, PlanOptions};
use cellc_runtime::scene::{Holder, ObjectPlacement, Scene, SceneScratch};
use cellc_runtime::validity::SceneValidity;
use cellc_runtime::Termination;
use cellc_runtime::{Cell, EndEffectorId, ObjectId};
use cellc_schema::{Artifact, Shape};
use criterion::{criterion_group, criterion_main, Criterion};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

const CELL: &str = "cells/panda_cage.cell";

/// Seeds per motion, cycled by the criterion iterations and all run for the summary.
const SEEDS: u64 = 32;

/// VAMP's goal configuration for the cage problem (their `sphere_cage_example`), rad.
const VAMP_GOAL: [f64; 7] = [2.35, 1.0, 0.0, -0.8, 0.0, 2.5, 0.785];

/// One motion to plan again and again.
struct Case {
    name: String,
    arms: Vec<EndEffectorId>,
    start: Vec<f64>,
    goal: Vec<f64>,
    context: MotionContext,
}

/// The cell compiled as `cellc` compiles it (its reach is `auto`), verified.
fn cell() -> Cell {
    let built = cellc_driver::build(&FsFiles, CELL, &Default::default());
    let artifact = built
        .artifact
        .unwrap_or_else(|| panic!("{CELL} has errors"));
    Cell::from_artifact(artifact, &FsFiles).expect("the cell loads")
}

/// VAMP's motion, then the motions of the request's plan with seed 0.
fn cases(cell: &Cell) -> Vec<Case> {
    let scene = cell.scene().expect("geometric");
    let arm = cell.end_effector("franka").expect("the arm");
    let Holder::Arm { home, .. } = &scene.holders[arm.index()] else {
        panic!("`franka` is an arm");
    };
    let mut cases = vec![Case {
        name: "vamp".into(),
        arms: vec![arm],
        start: home.clone(),
        goal: VAMP_GOAL.to_vec(),
        context: MotionContext {
            stationary: Vec::new(),
            placement: ObjectPlacement::Absent,
            obstacles: Vec::new(),
        },
    }];
    let request = cell
        .named_request("through_cage", PlanOptions::default())
        .expect("declared");
    let plan = cell
        .plan(&cell.home_world(), &request)
        .expect("the request plans");
    for (k, step) in plan.steps.iter().enumerate() {
        let (Some(t), Some(context)) = (&step.motion, &step.motion_context) else {
            continue;
        };
        let (first, last) = (t.points.first(), t.points.last());
        let (Some(start), Some(goal)) = (first.map(|p| &p.positions), last.map(|p| &p.positions))
        else {
            continue;
        };
        if start == goal {
            continue;
        }
        cases.push(Case {
            name: format!("plan_{k}"),
            arms: t.arms.clone(),
            start: start.clone(),
            goal: goal.clone(),
            context: context.clone(),
        });
    }
    cases
}

/// Plans `case` with `seed`: the joint-space length of the motion found (radians, the
/// Euclidean length of the polyline through its points), `None` when it failed.
fn solve(
    scene: &Scene,
    object: ObjectId,
    case: &Case,
    seed: u64,
    scratch: &mut SceneScratch,
) -> Option<f64> {
    let validity = SceneValidity::new(
        scene,
        &case.arms,
        &case.context.stationary,
        object,
        case.context.placement,
    )
    .expect("the plan's layout")
    .with_obstacles(&case.context.obstacles);
    let problem = MotionProblem {
        scene,
        arms: &case.arms,
        start: &case.start,
        goal: &case.goal,
        validity: &validity,
        timing: Default::default(),
    };
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let t = RrtConnect::default()
        .solve(&problem, &mut rng, &Termination::never(), scratch)
        .ok()?;
    let length = t
        .points
        .windows(2)
        .map(|w| {
            let d2: f64 = w[0]
                .positions
                .iter()
                .zip(&w[1].positions)
                .map(|(a, b)| (b - a) * (b - a))
                .sum();
            d2.sqrt()
        })
        .sum();
    Some(length)
}

/// Median and success count over every seed; prints one line.
fn summarise(scene: &Scene, object: ObjectId, case: &Case) -> (Vec<f64>, u64) {
    let mut scratch = SceneScratch::default();
    let mut times = Vec::new();
    let mut successes = 0;
    let mut lengths = Vec::new();
    for seed in 0..SEEDS {
        let start = Instant::now();
        let length = solve(scene, object, case, seed, &mut scratch);
        times.push(start.elapsed().as_secs_f64() * 1e3);
        successes += u64::from(length.is_some());
        lengths.extend(length);
    }
    let mut sorted = times.clone();
    sorted.sort_by(f64::total_cmp);
    lengths.sort_by(f64::total_cmp);
    let path = if lengths.is_empty() {
        "no path".to_string()
    } else {
        format!("median path {:.3} rad", median(&lengths))
    };
    println!(
        "cage/{}: {SEEDS} seeds, median {:.2} ms, worst {:.2} ms, success {successes}/{SEEDS}, {path}",
        case.name,
        median(&sorted),
        sorted[sorted.len() - 1],
    );
    (times, successes)
}

fn median(sorted: &[f64]) -> f64 {
    let n = sorted.len();
    if n % 2 == 1 {
        sorted[n / 2]
    } else {
        0.5 * (sorted[n / 2 - 1] + sorted[n / 2])
    }
}

/// The problem as JSON for the peer: the robot's files, base and limits, the motions,
/// the fixed boxes (obstacles and surface slabs) and the hand's solids.
fn problem_json(artifact: &Artifact, scene: &Scene, cases: &[Case]) -> String {
    let arm = cases[0].arms[0];
    let Holder::Arm { robot, base, .. } = &scene.holders[arm.index()] else {
        panic!("an arm");
    };
    let model = &artifact.robots[*robot];
    let (lower, upper) = scene.robots[*robot].limits();
    let limits: Vec<[f64; 2]> = lower.iter().zip(upper).map(|(&l, &u)| [l, u]).collect();
    let matrix = |iso: &cellc_runtime::math::Iso| {
        let m = iso.to_homogeneous();
        (0..4)
            .map(|r| (0..4).map(|c| m[(r, c)]).collect::<Vec<f64>>())
            .collect::<Vec<_>>()
    };
    let mut boxes = Vec::new();
    for (_, b) in &artifact.obstacles {
        boxes.push(aabb_json(b.min, b.max));
    }
    for h in &scene.holders {
        if let Holder::Surface { slab, .. } = h {
            boxes.push(aabb_json(slab.mins.into(), slab.maxs.into()));
        }
    }
    let end_effector = &artifact.end_effectors[arm.index()];
    let solids = end_effector
        .kind
        .and_then(|k| artifact.holder_kinds.get(k as usize))
        .map_or(&[][..], |k| &k.solids);
    let hand_boxes: Vec<serde_json::Value> = solids
        .iter()
        .filter_map(|s| match s.shape {
            Shape::Box { size } => Some(serde_json::json!({
                "pose": matrix(&cellc_schema::math::iso_from_schema(&s.pose)),
                "half_extents": [size[0] / 2.0, size[1] / 2.0, size[2] / 2.0],
            })),
            _ => None,
        })
        .collect();
    let motions: Vec<serde_json::Value> = cases
        .iter()
        .filter(|c| matches!(c.context.placement, ObjectPlacement::Absent))
        .map(|c| serde_json::json!({"name": c.name, "start": c.start, "goal": c.goal}))
        .collect();
    serde_json::json!({
        "urdf": model.urdf_path,
        "disabled_collisions": model.disabled_collisions,
        "meshes": model.meshes.iter().map(|m| (m.written.clone(), m.path.clone())).collect::<std::collections::BTreeMap<_, _>>(),
        "base_link": model.base_link,
        "tip_link": model.tip_link,
        "base_pose": matrix(base),
        "limits": limits,
        "boxes": boxes,
        "hand_boxes": hand_boxes,
        "seeds": SEEDS,
        "motions": motions,
    })
    .to_string()
}

fn aabb_json(min: [f64; 3], max: [f64; 3]) -> serde_json::Value {
    serde_json::json!({
        "centre": [0.5 * (min[0] + max[0]), 0.5 * (min[1] + max[1]), 0.5 * (min[2] + max[2])],
        "half_extents": [0.5 * (max[0] - min[0]), 0.5 * (max[1] - min[1]), 0.5 * (max[2] - min[2])],
    })
}

/// The Python the peer runs with, when there is one.
fn peer_python() -> Option<PathBuf> {
    if let Some(p) = std::env::var_os("CELLC_PEER_PYTHON") {
        return Some(PathBuf::from(p));
    }
    let default = Path::new("/work/venv-peers/bin/python");
    default.exists().then(|| default.to_path_buf())
}

/// Runs the OMPL peer on `json`; its median (ms) and success line, printed as it says.
fn run_peer(json: &str) -> Option<f64> {
    let python = peer_python()?;
    let dir = std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("target"));
    let path = dir.join("cage_problem.json");
    std::fs::write(&path, json).ok()?;
    let out = std::process::Command::new(python)
        .arg("benches/cage_ompl.py")
        .arg(&path)
        .output()
        .ok()?;
    let said = String::from_utf8_lossy(&out.stdout);
    print!("{said}");
    if !out.status.success() {
        println!(
            "the OMPL peer failed: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        return None;
    }
    said.lines()
        .find_map(|l| l.strip_prefix("ompl median_ms "))
        .and_then(|rest| rest.split_whitespace().next())
        .and_then(|ms| ms.parse().ok())
}

fn benches(c: &mut Criterion) {
    let cell = cell();
    let scene = cell.scene().expect("geometric");
    let object = ObjectId(0);
    let cases = cases(&cell);
    let mut vamp_times = Vec::new();
    for case in &cases {
        let (times, _) = summarise(scene, object, case);
        if case.name == "vamp" {
            vamp_times = times;
        }
    }
    vamp_times.sort_by(f64::total_cmp);
    let ours = median(&vamp_times);
    match run_peer(&problem_json(cell.artifact(), scene, &cases)) {
        Some(theirs) => println!(
            "cage/vamp: cellc median {ours:.2} ms, OMPL (Python) median {theirs:.2} ms, \
             OMPL / cellc {:.1}; VAMP reports 7.5 ms",
            theirs / ours
        ),
        None => println!(
            "cage/vamp: cellc median {ours:.2} ms; no OMPL peer (set CELLC_PEER_PYTHON); \
             VAMP reports 7.5 ms"
        ),
    }
    let mut c = std::mem::take(c).sample_size(32);
    for case in &cases {
        let mut scratch = SceneScratch::default();
        let mut seed = 0u64;
        c.bench_function(&format!("cage/{}", case.name), |b| {
            b.iter(|| {
                seed += 1;
                black_box(solve(scene, object, case, seed % SEEDS, &mut scratch))
            })
        });
    }
}

criterion_group!(cage_benches, benches);
criterion_main!(cage_benches);
