//! Trajectory timing against the peers (issue 34, point 6): on the same geometric paths
//! and the same per-joint limits, the total duration of the motions and the compute time
//! per motion of
//! - cellc: the certified path smoothed with circular blends (each arc certified again
//!   against the scene) and parameterised by cellc's TOPP-RA
//!   ([`time_smoothed`] after [`smooth_waypoints`], what the planner does);
//! - cellc's rest-to-rest baseline, the timing before blends and TOPP-RA: a trapezoid of
//!   the slowest joint per straight segment, stopping at every waypoint
//!   ([`rest_to_rest`]), under the same per-joint limits;
//! - toppra (PyPI): its TOPP-RA on cellc's smoothed path itself, evaluated exactly, on a
//!   grid as dense as cellc's and on one four times denser (the reference optimum on
//!   that path), and as its examples use it, on a cubic spline through the waypoints (a
//!   different, uncertified path: shown for what toppra's usual use gives);
//! - ruckig (PyPI): the community version has no intermediate waypoints, so from rest to
//!   rest on each straight segment, phase-synchronised (the joints stay on the segment),
//!   with the cells' declared jerk limits (none where a cell declares none), and without
//!   jerk limits, which must agree with the rest-to-rest baseline.
//!
//! The paths: every motion of a plan of the Vito handoff (`cells/vito.cell`,
//! `handoff_cylinder`), the Panda cage (`cells/panda_cage.cell`, `through_cage`) and the
//! two Pandas' handoff (`cells/two_pandas.cell`, `handoff`), each planned with the plan's
//! seed 0; each motion's certified waypoints are then found again by
//! [`RrtConnect::path`] with seed 0 in the motion's own world (the arms that stand, the
//! object where the plan has it), the path [`RrtConnect::solve`] would time. Like for
//! like: every column gets those waypoints and the limits the artifact resolved (URDF
//! velocities, the cells' accelerations and jerks); the TOPP-RA columns are compared on
//! cellc's smoothed path, which toppra receives piece by piece. Jerk: cellc slows a
//! motion evenly where a declared jerk limit asks it; toppra knows no jerk, so the ratio
//! to toppra is taken on cellc's timing under the velocity and acceleration limits alone,
//! and the table says how much the jerk limits changed.
//!
//! Compute time: each motion timed REPS times, the median. cellc's "TOPP-RA" is
//! [`time_smoothed`] whole (grid, both passes, the jerk check, the points written out);
//! its smoothing, which queries the scene to certify the blends, is shown apart (at most
//! 11 runs). toppra's
//! is its whole parameterisation (constraints, grid, solve, output), ruckig's every
//! segment's `calculate` (`benches/timing_peers.py`).
//!
//! `cargo bench --bench timing` (repetitions: `CELLC_TIMING_REPS`, default 201 here and
//! 21 for the peers). The peers run in the same run through
//! `CELLC_PEER_PYTHON`, else `.venv/bin/python` in the repository, else `python3`
//! (`python3 -m venv .venv && .venv/bin/pip install toppra ruckig numpy`); without them
//! the peers' columns are left out, and the bench says why. Prints markdown tables.

use std::hint::black_box;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

use cellc_driver::fs_files::FsFiles;
use cellc_runtime::motion::{
    arm_limits, rest_to_rest, smooth_waypoints, time_smoothed, MotionOptions, MotionProblem, Piece,
    RrtConnect, SmoothedPath, TimingOptions,
};
use cellc_runtime::plan::PlanOptions;
use cellc_runtime::robot::RateLimits;
use cellc_runtime::scene::SceneScratch;
use cellc_runtime::validity::SceneValidity;
use cellc_runtime::{Cell, EndEffectorId, Termination};
use criterion::Criterion;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use serde_json::{json, Value};

/// (cell, request): the motions of one plan of each.
const CASES: [(&str, &str); 3] = [
    ("cells/vito.cell", "handoff_cylinder"),
    ("cells/panda_cage.cell", "through_cage"),
    ("cells/two_pandas.cell", "handoff"),
];

/// The goals of issue 34: durations within this share of toppra's on the same path ...
const SAME_PATH: f64 = 0.03;
/// ... a parameterisation at most this long per motion (µs, the median) ...
const PER_MOTION_US: f64 = 500.0;
/// ... and the Vito handoff's motions at least this share shorter than rest to rest.
const HANDOFF_GAIN: f64 = 0.30;

/// Wider blend deviations tried on the Vito handoff (rad; the default is 0.1), for what
/// the deviation is worth there.
const WIDER: [f64; 2] = [0.2, 0.4];

/// Largest turn of an arc between two of cellc's grid points (rad; `timing.rs`), for the
/// peer's grid of the same density.
const MAX_TURN: f64 = 0.02;

/// One motion of a plan, its certified path and its smoothing.
struct Motion {
    cell: &'static str,
    label: String,
    arms: Vec<EndEffectorId>,
    waypoints: Vec<f64>,
    limits: RateLimits,
    smoothed: SmoothedPath,
    /// Median time of the smoothing with its certification (µs).
    smoothing_us: f64,
    /// cellc's duration with blends of each of [`WIDER`] deviations, certified again.
    wider: Vec<f64>,
}

impl Motion {
    fn dim(&self) -> usize {
        self.smoothed.dim()
    }

    fn corners(&self) -> usize {
        (self.waypoints.len() / self.dim()).saturating_sub(2)
    }

    fn arcs(&self) -> usize {
        let arc = |p: &&Piece| matches!(p, Piece::Arc { .. });
        self.smoothed.sections().flatten().filter(arc).count()
    }

    fn stops(&self) -> usize {
        self.smoothed.sections().count().saturating_sub(1)
    }
}

fn median(mut xs: Vec<f64>) -> f64 {
    xs.sort_by(f64::total_cmp);
    xs[xs.len() / 2]
}

/// The median time of `reps` runs of `run` (µs), after one untimed run.
fn timed<T>(reps: usize, mut run: impl FnMut() -> T) -> f64 {
    black_box(run());
    let times = (0..reps)
        .map(|_| {
            let t = Instant::now();
            black_box(run());
            t.elapsed().as_secs_f64() * 1e6
        })
        .collect();
    median(times)
}

/// The motions of one plan of `request` in `path`.
fn plan_motions(path: &'static str, request: &str, smoothing_reps: usize) -> Vec<Motion> {
    let built = cellc_driver::build(&FsFiles, path, &Default::default());
    let artifact = built
        .artifact
        .unwrap_or_else(|| panic!("{path} has errors"));
    let cell = Cell::from_artifact(artifact, &FsFiles).expect("the cell loads");
    let scene = cell.scene().expect("geometric");
    let request = cell
        .named_request(request, PlanOptions::default())
        .expect("declared");
    let plan = cell
        .plan(&cell.home_world(), &request)
        .expect("the request plans");
    let options = MotionOptions::default();
    let planner = RrtConnect::new(options.clone());
    let name = Path::new(path)
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or(path);
    let mut out = Vec::new();
    let mut scratch = SceneScratch::default();
    for (k, step) in plan.steps.iter().enumerate() {
        let (Some(t), Some(context)) = (&step.motion, &step.motion_context) else {
            continue;
        };
        let (Some(first), Some(last)) = (t.points.first(), t.points.last()) else {
            continue;
        };
        if first.positions == last.positions {
            continue;
        }
        let validity = SceneValidity::new(
            scene,
            &t.arms,
            &context.stationary,
            request.object,
            context.placement,
        )
        .expect("the plan's layout")
        .with_obstacles(&context.obstacles);
        let problem = MotionProblem {
            scene,
            arms: &t.arms,
            start: &first.positions,
            goal: &last.positions,
            validity: &validity,
            timing: TimingOptions::default(),
        };
        let mut rng = ChaCha8Rng::seed_from_u64(0);
        let waypoints = planner
            .path(&problem, &mut rng, &Termination::never(), &mut scratch)
            .expect("the plan's motion plans again");
        let dim = first.positions.len();
        let mut smooth = || smooth_waypoints(&waypoints, dim, &options, &validity, &mut scratch);
        let smoothing_us = timed(smoothing_reps, &mut smooth);
        let smoothed = smooth().expect("smooths");
        let limits = arm_limits(scene, &t.arms).expect("arms");
        let wider = WIDER
            .iter()
            .map(|&deviation| {
                let options = MotionOptions {
                    blend_deviation: deviation,
                    ..options.clone()
                };
                let smoothed = smooth_waypoints(&waypoints, dim, &options, &validity, &mut scratch)
                    .expect("smooths");
                duration(&smoothed, &t.arms, &limits)
            })
            .collect();
        let arms: Vec<String> = t
            .arms
            .iter()
            .map(|&e| cell.artifact().end_effectors[e.index()].name.clone())
            .collect();
        out.push(Motion {
            cell: name,
            label: format!("{name} {k} {}", arms.join("+")),
            arms: t.arms.clone(),
            limits,
            waypoints,
            smoothed,
            smoothing_us,
            wider,
        });
    }
    out
}

/// cellc's duration of a smoothed path (s) under `limits`.
fn duration(path: &SmoothedPath, arms: &[EndEffectorId], limits: &RateLimits) -> f64 {
    let options = MotionOptions::default();
    let t = time_smoothed(path, arms, limits, &options, &TimingOptions::default());
    t.expect("times").points.last().map_or(0.0, |p| p.time)
}

/// cellc's duration of `m` (s) under `limits`.
fn ours(m: &Motion, limits: &RateLimits) -> f64 {
    duration(&m.smoothed, &m.arms, limits)
}

fn baseline(m: &Motion) -> f64 {
    rest_to_rest(&m.waypoints, m.dim(), &m.limits, &TimingOptions::default())
        .expect("times")
        .iter()
        .sum()
}

/// How many points cellc's trajectory of `m` has: its grid points, the knots.
fn knots(m: &Motion) -> usize {
    let options = MotionOptions::default();
    time_smoothed(
        &m.smoothed,
        &m.arms,
        &m.limits,
        &options,
        &TimingOptions::default(),
    )
    .map_or(0, |t| t.points.len())
}

/// The same limits without jerk.
fn without_jerk(limits: &RateLimits) -> RateLimits {
    RateLimits {
        jerk: vec![None; limits.jerk.len()],
        ..limits.clone()
    }
}

fn piece_json(p: &Piece) -> Value {
    match p {
        Piece::Line { a, b, .. } => json!({ "line": { "a": a, "b": b } }),
        Piece::Arc {
            centre,
            u,
            v,
            radius,
            angle,
        } => json!({ "arc": {
            "centre": centre, "u": u, "v": v, "radius": radius, "angle": angle
        } }),
    }
}

/// The paths and limits for the peers.
fn export(motions: &[Motion], reps: usize) -> Value {
    let motions: Vec<Value> = motions
        .iter()
        .map(|m| {
            let waypoints: Vec<&[f64]> = m.waypoints.chunks_exact(m.dim()).collect();
            let sections: Vec<Vec<Value>> = m
                .smoothed
                .sections()
                .map(|s| s.iter().map(piece_json).collect())
                .collect();
            json!({
                "label": m.label,
                "dim": m.dim(),
                "velocity": m.limits.velocity,
                "acceleration": m.limits.acceleration,
                "jerk": m.limits.jerk,
                "waypoints": waypoints,
                "sections": sections,
                "grid_step": MotionOptions::default().grid_step,
                "max_turn": MAX_TURN,
            })
        })
        .collect();
    json!({ "reps": reps, "motions": motions })
}

/// The Python the peers run with.
fn peer_python() -> PathBuf {
    if let Some(p) = std::env::var_os("CELLC_PEER_PYTHON") {
        return PathBuf::from(p);
    }
    let venv = Path::new(".venv/bin/python");
    if venv.exists() {
        return venv.to_path_buf();
    }
    PathBuf::from("python3")
}

/// What the peers measured, per motion; `None` (and why, printed) when they could not run.
fn peers(motions: &[Motion], reps: usize) -> Option<Value> {
    let dir = std::env::var("CARGO_TARGET_DIR").unwrap_or_else(|_| "target".into());
    let input = Path::new(&dir).join("timing_paths.json");
    let output = Path::new(&dir).join("timing_peers.json");
    std::fs::write(&input, export(motions, reps).to_string()).expect("the export is written");
    let _ = std::fs::remove_file(&output);
    let python = peer_python();
    let run = Command::new(&python)
        .arg("benches/timing_peers.py")
        .arg(&input)
        .arg(&output)
        .output();
    match run {
        Err(e) => {
            println!("peers skipped: {} does not run ({e})", python.display());
            return None;
        }
        Ok(out) if !out.status.success() => {
            println!(
                "peers skipped: benches/timing_peers.py failed: {}",
                String::from_utf8_lossy(&out.stderr)
            );
            return None;
        }
        Ok(_) => {}
    }
    let text = std::fs::read_to_string(&output).expect("the peers' results");
    let v: Value = serde_json::from_str(&text).expect("the peers' results are JSON");
    let missing: Vec<&str> = v["missing"]
        .as_array()
        .map(|a| a.iter().filter_map(Value::as_str).collect())
        .unwrap_or_default();
    if !missing.is_empty() {
        println!(
            "peers left out: {} cannot import {} (python3 -m venv .venv && \
             .venv/bin/pip install toppra ruckig numpy)",
            python.display(),
            missing.join(", ")
        );
    }
    Some(v)
}

fn load_average() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .map(|l| l.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
        .unwrap_or_else(|_| "unknown".into())
}

/// A peer's figure of motion `i`, when it ran.
fn peer(v: Option<&Value>, i: usize, column: &str, field: &str) -> Option<f64> {
    v?["motions"][i][column][field].as_f64()
}

fn cell_or_dash(x: Option<f64>, digits: usize) -> String {
    x.map_or_else(|| "–".to_string(), |x| format!("{x:.digits$}"))
}

fn main() {
    // `cargo bench` passes `--bench`; without it (`cargo test --benches`) everything runs
    // once, as criterion's own test mode does.
    let bench = std::env::args().any(|a| a == "--bench");
    let reps = |default: usize| {
        if !bench {
            return 1;
        }
        std::env::var("CELLC_TIMING_REPS")
            .ok()
            .and_then(|p| p.parse().ok())
            .filter(|&p| p > 0)
            .unwrap_or(default)
    };
    let mut motions = Vec::new();
    for (path, request) in CASES {
        let t = Instant::now();
        // The smoothing queries the scene (milliseconds): at most 11 runs.
        motions.extend(plan_motions(path, request, reps(11).min(11)));
        eprintln!(
            "{path} {request}: planned, paths found again and smoothed in {:.1} s (not timed)",
            t.elapsed().as_secs_f64()
        );
    }
    let mut c = Criterion::default().configure_from_args();
    for (path, _) in CASES {
        let of_cell: Vec<&Motion> = motions.iter().filter(|m| path.contains(m.cell)).collect();
        c.bench_function(&format!("timing/topp/{}", of_cell[0].cell), |b| {
            b.iter(|| of_cell.iter().map(|m| ours(m, &m.limits)).sum::<f64>())
        });
        c.bench_function(&format!("timing/rest_to_rest/{}", of_cell[0].cell), |b| {
            b.iter(|| of_cell.iter().map(|m| baseline(m)).sum::<f64>())
        });
    }
    c.final_summary();

    let load_before = load_average();
    let options = MotionOptions::default();
    let topp_us: Vec<f64> = motions
        .iter()
        .map(|m| timed(reps(201), || ours(m, &m.limits)))
        .collect();
    let baseline_us: Vec<f64> = motions
        .iter()
        .map(|m| timed(reps(201), || baseline(m)))
        .collect();
    let theirs = peers(&motions, reps(21));
    let load_after = load_average();
    let theirs = theirs.as_ref();
    let versions = theirs
        .map(|v| {
            ["toppra", "ruckig", "python"]
                .iter()
                .filter_map(|k| Some(format!("{k} {}", v["versions"][k].as_str()?)))
                .collect::<Vec<_>>()
                .join(", ")
        })
        .unwrap_or_default();

    println!("\n# Trajectory timing against toppra and ruckig ({versions})\n");
    println!("load average: {load_before} before, {load_after} after");
    println!(
        "cellc: blends of at most {} rad, grid step {} rad; REPS {} (peers {})\n",
        options.blend_deviation,
        options.grid_step,
        reps(201),
        reps(21)
    );
    println!("## Durations (s)\n");
    println!(
        "| motion | joints | corners (blended, stops) | cellc | cellc, no jerk | \
         rest to rest | toppra same path | toppra 4× grid | cellc no jerk / toppra 4× | \
         toppra spline | ruckig on segments | ruckig per joint |"
    );
    println!("|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
    let mut rows = Vec::new();
    for (i, m) in motions.iter().enumerate() {
        let d = ours(m, &m.limits);
        let free = ours(m, &without_jerk(&m.limits));
        let r2r = baseline(m);
        let dense = peer(theirs, i, "toppra_dense", "duration");
        println!(
            "| {} | {} | {} ({}, {}) | {d:.3} | {free:.3} | {r2r:.3} | {} | {} | {} | {} | {} | {} |",
            m.label,
            m.dim(),
            m.corners(),
            m.arcs(),
            m.stops(),
            cell_or_dash(peer(theirs, i, "toppra_same", "duration"), 3),
            cell_or_dash(dense, 3),
            cell_or_dash(dense.map(|t| free / t), 4),
            cell_or_dash(peer(theirs, i, "toppra_spline", "duration"), 3),
            cell_or_dash(peer(theirs, i, "ruckig", "duration"), 3),
            cell_or_dash(peer(theirs, i, "ruckig_joints", "duration"), 3),
        );
        rows.push((d, free, r2r, dense));
    }
    println!("\n## Compute time per motion (µs, median of REPS)\n");
    println!(
        "| motion | grid points (cellc, toppra) | cellc TOPP-RA | cellc smoothing (certified) | \
         rest to rest | toppra same path | toppra spline | ruckig on segments | ruckig per joint |"
    );
    println!("|---|---:|---:|---:|---:|---:|---:|---:|---:|");
    for (i, m) in motions.iter().enumerate() {
        println!(
            "| {} | {}, {} | {:.1} | {:.0} | {:.2} | {} | {} | {} | {} |",
            m.label,
            knots(m),
            cell_or_dash(peer(theirs, i, "toppra_same", "grid_points"), 0),
            topp_us[i],
            m.smoothing_us,
            baseline_us[i],
            cell_or_dash(peer(theirs, i, "toppra_same", "median_us"), 0),
            cell_or_dash(peer(theirs, i, "toppra_spline", "median_us"), 0),
            cell_or_dash(peer(theirs, i, "ruckig", "median_us"), 1),
            cell_or_dash(peer(theirs, i, "ruckig_joints", "median_us"), 1),
        );
    }

    println!("\n## Per cell (sums of the motions' durations, s; medians of compute, µs)\n");
    println!(
        "| cell | motions | cellc | cellc, no jerk | rest to rest | cellc / rest to rest | \
         toppra 4× grid | cellc TOPP-RA µs | toppra same path µs |"
    );
    println!("|---|---:|---:|---:|---:|---:|---:|---:|---:|");
    for (path, _) in CASES {
        let idx: Vec<usize> = (0..motions.len())
            .filter(|&i| path.contains(motions[i].cell))
            .collect();
        let sum = |f: &dyn Fn(usize) -> f64| idx.iter().map(|&i| f(i)).sum::<f64>();
        let (d, free, r2r) = (
            sum(&|i| rows[i].0),
            sum(&|i| rows[i].1),
            sum(&|i| rows[i].2),
        );
        let dense: Option<f64> = idx.iter().map(|&i| rows[i].3).sum();
        let theirs_us: Option<Vec<f64>> = idx
            .iter()
            .map(|&i| peer(theirs, i, "toppra_same", "median_us"))
            .collect();
        println!(
            "| {} | {} | {d:.3} | {free:.3} | {r2r:.3} | {:.3} | {} | {:.1} | {} |",
            motions[idx[0]].cell,
            idx.len(),
            d / r2r,
            cell_or_dash(dense, 3),
            median(idx.iter().map(|&i| topp_us[i]).collect()),
            cell_or_dash(theirs_us.map(median), 0),
        );
    }

    println!("\n## Goals of issue 34\n");
    let worst = rows
        .iter()
        .filter_map(|&(_, free, _, dense)| Some(free / dense? - 1.0))
        .fold(None, |w: Option<f64>, r| {
            Some(w.map_or(r, |w| if r.abs() > w.abs() { r } else { w }))
        });
    match worst {
        Some(w) => println!(
            "- same path as toppra (4× grid): worst {:+.2}% over {} motions (goal: within {:.0}%): {}",
            w * 100.0,
            rows.len(),
            SAME_PATH * 100.0,
            if w.abs() <= SAME_PATH { "met" } else { "missed" }
        ),
        None => println!("- same path as toppra: not measured (no toppra)"),
    }
    let per_motion = median(topp_us.clone());
    println!(
        "- parameterisation: median {per_motion:.1} µs per motion, worst {:.1} µs (goal: at most {PER_MOTION_US:.0} µs): {}",
        topp_us.iter().copied().fold(0.0, f64::max),
        if per_motion <= PER_MOTION_US { "met" } else { "missed" }
    );
    let vito: Vec<usize> = (0..motions.len())
        .filter(|&i| motions[i].cell == "vito")
        .collect();
    let (d, r2r): (f64, f64) = (
        vito.iter().map(|&i| rows[i].0).sum(),
        vito.iter().map(|&i| rows[i].2).sum(),
    );
    let gain = 1.0 - d / r2r;
    println!(
        "- Vito handoff: {d:.3} s against {r2r:.3} s rest to rest, {:.1}% shorter (goal: at least {:.0}%): {}",
        gain * 100.0,
        HANDOFF_GAIN * 100.0,
        if gain >= HANDOFF_GAIN { "met" } else { "missed" }
    );
    // The "today": every joint at 1 rad/s and 2 rad/s², rest to rest.
    let then: f64 = vito
        .iter()
        .map(|&i| {
            let m = &motions[i];
            let uniform = RateLimits {
                velocity: vec![1.0; m.dim()],
                acceleration: vec![2.0; m.dim()],
                jerk: vec![None; m.dim()],
            };
            rest_to_rest(&m.waypoints, m.dim(), &uniform, &TimingOptions::default())
                .expect("times")
                .iter()
                .sum::<f64>()
        })
        .sum();
    println!(
        "  against the timing the issue was written on (rest to rest, every joint at 1 rad/s \
         and 2 rad/s²): {then:.3} s, {:.1}% shorter",
        (1.0 - d / then) * 100.0
    );
    let cornered: Vec<usize> = vito
        .iter()
        .copied()
        .filter(|&i| motions[i].corners() > 0)
        .collect();
    let (dc, rc): (f64, f64) = (
        cornered.iter().map(|&i| rows[i].0).sum(),
        cornered.iter().map(|&i| rows[i].2).sum(),
    );
    println!(
        "  its {} motions with corners alone: {dc:.3} s against {rc:.3} s, {:.1}% shorter",
        cornered.len(),
        (1.0 - dc / rc) * 100.0
    );
    for (k, deviation) in WIDER.iter().enumerate() {
        let total: f64 = vito.iter().map(|&i| motions[i].wider[k]).sum();
        println!(
            "  with blends of at most {deviation} rad (certified again): {total:.3} s, {:.1}% shorter",
            (1.0 - total / r2r) * 100.0
        );
    }
    let check: Option<Vec<f64>> = (0..motions.len())
        .map(|i| Some(peer(theirs, i, "ruckig_trapezoid", "duration")? / rows[i].2 - 1.0))
        .collect();
    if let Some(check) = check {
        let worst = check.iter().copied().fold(0.0, |w: f64, r| w.max(r.abs()));
        println!(
            "- rest to rest against ruckig without jerk limits (the same trapezoids): largest difference {:.2e}",
            worst
        );
    }
}
