//! The paper's Table I (Marino et al., RA-L 2016, Sec. V) with its protocol: per object,
//! five start/goal pairs, many trials each; graph nodes and arcs, high-level time
//! avg / max / min per request, total time avg per request. Prints markdown tables: what
//! was measured here, then beside the paper's figures with the ratios paper / ours.
//!
//! `cargo bench --bench table1` (trials per pair: `CELLC_TABLE1_TRIALS`, default 100 as in
//! the paper). Plain `fn main` (harness = false): every request is timed on its own with
//! `Instant`, on one thread (the planner is single-threaded).
//!
//! Rows:
//! - `cells/vito.cell` (geometric: the two LWRs, table, bin), one row per object. The
//!   artifact is compiled and verified once (in parallel, build time, not counted), then
//!   "high level" is `Planner::plan` with `motions: false`: locate (Cartesian pose ->
//!   state), Dijkstra with backtracking, simplification, and the state path -> Cartesian
//!   conversion (IK for picks and placements at the request's poses, handoffs from the
//!   build-time witnesses, collision checks). "Total" is `Planner::plan` with
//!   `motions: true` (the same, plus joint-space motion planning of every command:
//!   RRT-Connect, shortcutting, time parametrisation) followed by execution in the
//!   kinematic simulator (`execute` with `Simulator`); not the robot's motion time.
//! - The original Vito database (`tests/data/dualmanip/vito_full.db`, imported): the
//!   paper's pitcher (`containerA`) and colander (`containerB`) graphs at the paper's
//!   sizes. They are abstract (no geometry): high level is search + simplification only,
//!   and there is no total.
//! - `cells/assembly_line.cell`, when it exists and plans; otherwise a skipped row.
//!
//! Start/goal pairs, deterministic: the cell's named requests for the object first (for
//! the assembly line, its one request), then resting states of fixed surfaces in
//! different workspaces, each at the object pose of a verified witness of that state
//! (a real pose on the table, located by pose), spread round-robin over (start
//! workspace, goal workspace) combinations. A pair is kept only if it plans, with and
//! without motions, at seed 0; that untimed check is also the warm-up. Then each pair is
//! planned `trials` times per measure with seeds 0..trials. Failed requests are timed and
//! counted in the averages (which are also given over successful requests only); standard
//! error names each failure and each pair, with a `cellc plan` line for the pair.

use std::collections::BTreeMap;
use std::path::Path;
use std::time::Instant;

use cellc::fs_files::FsFiles;
use cellc_runtime::execute::{execute, ExecuteOptions, Simulator};
use cellc_runtime::math::{iso_from_schema, Iso};
use cellc_runtime::plan::planner::Planner;
use cellc_runtime::plan::{Goal, Placement, PlanOptions, Request};
use cellc_runtime::scene::Scene;
use cellc_runtime::verify::{verify, VerifyOptions};
use cellc_schema::{ArcKind, Artifact, Body, Node, ObjectId, RequestPlacement, WorkspaceId};

/// One column of the paper's Table I (times in seconds).
struct Paper {
    graph: &'static str,
    nodes: usize,
    arcs: usize,
    hl_avg: f64,
    hl_max: f64,
    hl_min: f64,
    total_avg: f64,
}

const PAPER: [Paper; 5] = [
    Paper {
        graph: "pitcher",
        nodes: 108,
        arcs: 1609,
        hl_avg: 3.2,
        hl_max: 4.6,
        hl_min: 1.8,
        total_avg: 24.2,
    },
    Paper {
        graph: "colander",
        nodes: 144,
        arcs: 3426,
        hl_avg: 5.4,
        hl_max: 9.4,
        hl_min: 2.5,
        total_avg: 28.5,
    },
    Paper {
        graph: "ball",
        nodes: 80,
        arcs: 1056,
        hl_avg: 1.9,
        hl_max: 2.4,
        hl_min: 1.1,
        total_avg: 17.6,
    },
    Paper {
        graph: "cylinder",
        nodes: 224,
        arcs: 5248,
        hl_avg: 2.6,
        hl_max: 3.2,
        hl_min: 2.1,
        total_avg: 21.5,
    },
    Paper {
        graph: "assembly line",
        nodes: 736,
        arcs: 14016,
        hl_avg: 8.5,
        hl_max: 21.3,
        hl_min: 3.1,
        total_avg: 53.0,
    },
];

fn paper(graph: &str) -> Option<&'static Paper> {
    PAPER.iter().find(|p| p.graph == graph)
}

/// Times of many requests, seconds: every request, and the successful ones.
#[derive(Default)]
struct Stats {
    samples: Vec<f64>,
    successful: Vec<f64>,
}

impl Stats {
    fn push(&mut self, s: f64, ok: bool) {
        self.samples.push(s);
        if ok {
            self.successful.push(s);
        }
    }
    fn failures(&self) -> usize {
        self.samples.len() - self.successful.len()
    }
    fn avg(&self) -> f64 {
        self.samples.iter().sum::<f64>() / self.samples.len().max(1) as f64
    }
    fn ok_avg(&self) -> f64 {
        self.successful.iter().sum::<f64>() / self.successful.len().max(1) as f64
    }
    fn max(&self) -> f64 {
        self.samples.iter().copied().fold(0.0, f64::max)
    }
    fn min(&self) -> f64 {
        self.samples.iter().copied().fold(f64::INFINITY, f64::min)
    }
    fn median(&self) -> f64 {
        let mut v = self.samples.clone();
        v.sort_by(f64::total_cmp);
        v.get(v.len() / 2).copied().unwrap_or(0.0)
    }
}

/// One measured row.
struct Row {
    /// What the row is ("vito.cell cylinder").
    label: String,
    /// The paper's column it compares with, if any.
    paper: Option<&'static Paper>,
    nodes: usize,
    arcs: usize,
    pairs: usize,
    trials: usize,
    hl: Stats,
    /// `None` for abstract graphs (no geometry, no motions).
    total: Option<Stats>,
    /// Per pair: what, high-level and total times.
    per_pair: Vec<(String, Stats, Option<Stats>)>,
    /// Why the row was not measured.
    skipped: Option<String>,
}

/// A request of the benchmark: a start and a goal placement.
#[derive(Clone)]
struct Pair {
    what: String,
    start: Placement,
    goal: Placement,
}

impl Pair {
    fn request(&self, object: u32, seed: u64, motions: bool) -> Request {
        Request {
            object: ObjectId(object),
            start: self.start.clone(),
            goal: Goal::Placement(self.goal.clone()),
            options: PlanOptions {
                seed,
                motions,
                ..PlanOptions::default()
            },
        }
    }
}

/// A compiled, verified geometric cell, and how long that took (build time, parallel).
struct Geometric {
    artifact: Artifact,
    scene: Scene,
    build_seconds: f64,
}

fn geometric(path: &str) -> Result<Geometric, String> {
    let t = Instant::now();
    let compilation = cellc_compiler::compile(&FsFiles, path);
    if compilation.has_errors() {
        let first = compilation
            .diagnostics
            .iter()
            .find(|d| d.severity == cellc_lang::Severity::Error)
            .map(|d| d.message.clone())
            .unwrap_or_default();
        return Err(format!("{path} has errors: {first}"));
    }
    let cell = compilation.cell.as_ref().ok_or("not resolved")?;
    let mut artifact =
        cellc_compiler::artifact::lower(cell, &compilation.graphs, &compilation.sources);
    let scene = Scene::load(&artifact, &FsFiles).map_err(|e| format!("{path}: {e:?}"))?;
    verify(&mut artifact, &scene, &VerifyOptions::default(), &|_, _| {});
    Ok(Geometric {
        artifact,
        scene,
        build_seconds: t.elapsed().as_secs_f64(),
    })
}

fn placement_of(p: &RequestPlacement) -> Placement {
    Placement {
        holder: p.end_effector,
        grasp: p.grasp,
        workspace: p.workspace,
        pose: p.pose.as_ref().map(iso_from_schema),
    }
}

/// Where an object can be: a state of a fixed holder and, in geometric cells, a pose.
fn candidates(a: &Artifact, object: u32, geometric: bool) -> Vec<(Node, Option<Iso>)> {
    let graph = &a.objects[object as usize].graph;
    let mut out = Vec::new();
    for (i, node) in graph.nodes.iter().enumerate() {
        let e = &a.end_effectors[node.end_effector.index()];
        if e.movable {
            continue;
        }
        if !geometric {
            out.push((*node, None));
            continue;
        }
        if !matches!(e.body, Body::Surface { .. }) {
            continue;
        }
        // The object pose of the first verified exchange with this resting state.
        let pose = graph.arcs.iter().find_map(|arc| {
            let touches = arc.from as usize == i || arc.to as usize == i;
            (arc.kind == ArcKind::Transition && touches)
                .then_some(arc.witness)
                .flatten()
                .map(|w| iso_from_schema(&graph.witnesses[w as usize].object))
        });
        if let Some(pose) = pose {
            out.push((*node, Some(pose)));
        }
    }
    out
}

fn placement_at(node: Node, pose: Option<Iso>) -> Placement {
    match pose {
        // A pose on a surface: located by pose, as a Cartesian request is.
        Some(pose) => Placement {
            holder: node.end_effector,
            grasp: None,
            workspace: None,
            pose: Some(pose),
        },
        None => Placement::at_state(node),
    }
}

/// Up to five pairs that plan: the named requests of the object, then resting states in
/// different workspaces, round-robin over workspace combinations.
fn pairs(planner: &Planner<'_>, object: u32, geometric: bool) -> Vec<Pair> {
    let a = planner.artifact();
    let name = &a.objects[object as usize].name;
    let mut proposed: Vec<Pair> = a
        .requests
        .iter()
        .filter(|r| r.object.0 == object)
        .map(|r| Pair {
            what: format!("request {}", r.name),
            start: placement_of(&r.from),
            goal: placement_of(&r.to),
        })
        .collect();
    let cands = candidates(a, object, geometric);
    let mut groups: BTreeMap<(WorkspaceId, WorkspaceId), Vec<(usize, usize)>> = BTreeMap::new();
    for (i, s) in cands.iter().enumerate() {
        for (j, g) in cands.iter().enumerate() {
            if s.0.workspace != g.0.workspace {
                groups
                    .entry((s.0.workspace, g.0.workspace))
                    .or_default()
                    .push((i, j));
            }
        }
    }
    let depth = groups.values().map(Vec::len).max().unwrap_or(0);
    for k in 0..depth {
        for list in groups.values() {
            if let Some(&(i, j)) = list.get(k) {
                let (s, g) = (cands[i], cands[j]);
                proposed.push(Pair {
                    what: format!(
                        "{} in {} -> {} in {}",
                        a.end_effectors[s.0.end_effector.index()].name,
                        a.workspaces[s.0.workspace.index()].name,
                        a.end_effectors[g.0.end_effector.index()].name,
                        a.workspaces[g.0.workspace.index()].name
                    ),
                    start: placement_at(s.0, s.1),
                    goal: placement_at(g.0, g.1),
                });
            }
        }
    }
    let mut out = Vec::new();
    for pair in proposed {
        if out.len() == 5 {
            break;
        }
        let checked = planner.plan(&pair.request(object, 0, false)).and_then(|_| {
            if geometric {
                planner.plan(&pair.request(object, 0, true)).map(|_| ())
            } else {
                Ok(())
            }
        });
        match checked {
            Ok(()) => out.push(pair),
            Err(e) => {
                let mut e = format!("{e:?}");
                e.truncate(400);
                eprintln!("  {name}: pair left out ({}): {e}", pair.what);
            }
        }
    }
    out
}

/// A placement as `cellc plan --from/--to` reads it (metres and degrees).
fn cli(a: &Artifact, object: u32, p: &Placement) -> String {
    let holder = &a.end_effectors[p.holder.index()].name;
    let holder = match p.grasp {
        Some(g) => format!(
            "{holder}.{}",
            a.objects[object as usize].grasps[g.index()].name
        ),
        None => holder.clone(),
    };
    let workspace = p.workspace.map(|w| &a.workspaces[w.index()].name);
    match (&p.pose, workspace) {
        (Some(pose), _) => {
            let t = pose.translation.vector;
            let (r, pi, y) = pose.rotation.euler_angles();
            format!(
                "{holder} at ({:.6}, {:.6}, {:.6}) rpy ({:.6}, {:.6}, {:.6})",
                t.x,
                t.y,
                t.z,
                r.to_degrees(),
                pi.to_degrees(),
                y.to_degrees()
            )
        }
        (None, Some(w)) => format!("{holder} in {w}"),
        (None, None) => holder,
    }
}

fn trials() -> usize {
    std::env::var("CELLC_TABLE1_TRIALS")
        .ok()
        .and_then(|t| t.parse().ok())
        .filter(|&t| t > 0)
        .unwrap_or(100)
}

/// Plans and (in geometric cells) executes every pair `trials` times.
fn measure(
    label: &str,
    paper: Option<&'static Paper>,
    planner: &Planner<'_>,
    scene: Option<&Scene>,
    object: &str,
    trials: usize,
) -> Row {
    let a = planner.artifact();
    let index = a
        .objects
        .iter()
        .position(|o| o.name == object)
        .expect("object exists") as u32;
    let graph = &a.objects[index as usize].graph;
    let pairs = pairs(planner, index, scene.is_some());
    for p in &pairs {
        eprintln!(
            "  {label}: {} (cellc plan --object {object} --from '{}' --to '{}')",
            p.what,
            cli(a, index, &p.start),
            cli(a, index, &p.goal)
        );
    }
    let mut row = Row {
        label: label.to_string(),
        paper,
        nodes: graph.nodes.len(),
        arcs: graph.arcs.len(),
        pairs: pairs.len(),
        trials,
        hl: Stats::default(),
        total: scene.map(|_| Stats::default()),
        per_pair: Vec::new(),
        skipped: None,
    };
    if pairs.is_empty() {
        row.skipped = Some("no start/goal pair plans".into());
        return row;
    }
    let mut per_pair: Vec<(Stats, Stats)> = pairs.iter().map(|_| Default::default()).collect();
    for trial in 0..trials {
        let seed = trial as u64;
        for (pair, stats) in pairs.iter().zip(per_pair.iter_mut()) {
            let request = pair.request(index, seed, false);
            let t = Instant::now();
            let plan = planner.plan(&request);
            let seconds = t.elapsed().as_secs_f64();
            let ok = std::hint::black_box(&plan).is_ok();
            row.hl.push(seconds, ok);
            stats.0.push(seconds, ok);
            if let Err(e) = plan {
                eprintln!(
                    "  high level failed: {label}, {}, seed {seed}: {e:?}",
                    pair.what
                );
            }
            let Some(total) = row.total.as_mut() else {
                continue;
            };
            let request = pair.request(index, seed, true);
            let t = Instant::now();
            let outcome = match planner.plan(&request) {
                Ok(plan) => {
                    let mut simulator =
                        Simulator::new(a, scene, plan.object, plan.states[0], plan.start_pose);
                    let options = ExecuteOptions {
                        max_replans: 5,
                        plan: request.options.clone(),
                    };
                    execute(planner, plan, &mut simulator, &options)
                        .map(|_| ())
                        .map_err(|e| format!("execution: {e:?}"))
                }
                Err(e) => Err(format!("plan: {e:?}")),
            };
            let seconds = t.elapsed().as_secs_f64();
            total.push(seconds, outcome.is_ok());
            stats.1.push(seconds, outcome.is_ok());
            if let Err(e) = outcome {
                let mut e = e;
                e.truncate(1500);
                eprintln!("  total failed: {label}, {}, seed {seed}: {e}", pair.what);
            }
        }
    }
    let geometric = row.total.is_some();
    row.per_pair = pairs
        .iter()
        .zip(per_pair)
        .map(|(p, (hl, total))| (p.what.clone(), hl, geometric.then_some(total)))
        .collect();
    row
}

fn skipped(label: &str, paper: Option<&'static Paper>, why: String) -> Row {
    Row {
        label: label.to_string(),
        paper,
        nodes: 0,
        arcs: 0,
        pairs: 0,
        trials: 0,
        hl: Stats::default(),
        total: None,
        per_pair: Vec::new(),
        skipped: Some(why),
    }
}

/// Milliseconds with four significant digits.
fn ms(seconds: f64) -> String {
    let m = seconds * 1e3;
    if m >= 100.0 {
        format!("{m:.1}")
    } else if m >= 10.0 {
        format!("{m:.2}")
    } else if m >= 1.0 {
        format!("{m:.3}")
    } else if m >= 0.1 {
        format!("{m:.4}")
    } else {
        format!("{m:.5}")
    }
}

fn ratio(x: f64) -> String {
    if x >= 100.0 {
        format!("{:.0}x", x)
    } else {
        format!("{:.1}x", x)
    }
}

fn machine() -> String {
    let cpu = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|t| {
            t.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split(':').nth(1))
                .map(|s| s.trim().to_string())
        })
        .unwrap_or_else(|| "unknown CPU".into());
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    format!("{cpu}, {threads} hardware threads available (requests run on one)")
}

fn main() {
    // `cargo bench` passes `--bench`; nothing else is taken.
    let trials = trials();
    println!("# Table I, measured\n");
    println!("machine: {}", machine());
    println!("protocol: 5 start/goal pairs x {trials} trials per row (seeds 0..{trials}), every request timed alone; times per request in ms\n");
    let mut rows = Vec::new();

    // The shipped geometric Vito cell.
    match geometric("cells/vito.cell") {
        Ok(g) => {
            println!(
                "vito.cell: compiled and verified once in {} ms (build time, parallel, not part of any request)",
                ms(g.build_seconds)
            );
            let planner = Planner::new(&g.artifact, Some(&g.scene));
            for object in ["pitcher", "colander", "ball", "cylinder"] {
                let label = format!("vito.cell {object}");
                eprintln!("measuring {label}");
                rows.push(measure(
                    &label,
                    paper(object),
                    &planner,
                    Some(&g.scene),
                    object,
                    trials,
                ));
            }
        }
        Err(e) => rows.push(skipped("vito.cell", None, e)),
    }

    // The original database: the paper's pitcher and colander graphs, abstract.
    match cellc::import::dualmanip(Path::new("tests/data/dualmanip/vito_full.db")) {
        Ok(imported) => {
            let world =
                cellc_compiler::MemoryFiles::new([("vito_full.cell", imported.text.as_str())]);
            let compilation = cellc_compiler::compile(&world, "vito_full.cell");
            assert!(!compilation.has_errors(), "the imported database compiles");
            let artifact = cellc_compiler::artifact::lower(
                compilation.cell.as_ref().expect("resolved"),
                &compilation.graphs,
                &compilation.sources,
            );
            let planner = Planner::new(&artifact, None);
            for (object, graph) in [("containerA", "pitcher"), ("containerB", "colander")] {
                let label = format!("vito_full.db {object} ({graph}, abstract)");
                eprintln!("measuring {label}");
                rows.push(measure(
                    &label,
                    paper(graph),
                    &planner,
                    None,
                    object,
                    trials,
                ));
            }
        }
        Err(e) => rows.push(skipped(
            "vito_full.db",
            None,
            format!("import failed: {e:?}"),
        )),
    }

    // The assembly line, when it exists and plans.
    let line = "cells/assembly_line.cell";
    let label = "assembly_line.cell";
    if Path::new(line).exists() {
        match geometric(line) {
            Ok(g) => {
                println!(
                    "assembly_line.cell: compiled and verified once in {} ms (build time, parallel, not part of any request)",
                    ms(g.build_seconds)
                );
                let planner = Planner::new(&g.artifact, Some(&g.scene));
                let object = g
                    .artifact
                    .requests
                    .first()
                    .map(|r| r.object.index())
                    .unwrap_or(0);
                match g.artifact.objects.get(object) {
                    Some(o) => {
                        let name = o.name.clone();
                        let label = format!("{label} {name}");
                        eprintln!("measuring {label}");
                        rows.push(measure(
                            &label,
                            paper("assembly line"),
                            &planner,
                            Some(&g.scene),
                            &name,
                            trials,
                        ));
                    }
                    None => rows.push(skipped(label, paper("assembly line"), "no object".into())),
                }
            }
            Err(e) => rows.push(skipped(label, paper("assembly line"), e)),
        }
    } else {
        rows.push(skipped(
            label,
            paper("assembly line"),
            format!("{line} does not exist yet"),
        ));
    }

    println!();
    println!("| graph | nodes | arcs | pairs x trials | high-level avg / max / min (ms) | high-level median (ms) | total avg (ms) | total median (ms) | failed requests (high level / total) | successful only: high-level avg / total avg (ms) |");
    println!("|---|---|---|---|---|---|---|---|---|---|");
    for r in &rows {
        if let Some(why) = &r.skipped {
            println!("| {} | — | — | — | skipped: {why} | | | | | |", r.label);
            continue;
        }
        let (total, total_median, total_failed, total_ok) = match &r.total {
            Some(t) => (
                ms(t.avg()),
                ms(t.median()),
                t.failures().to_string(),
                ms(t.ok_avg()),
            ),
            None => (
                "n/a (no geometry)".into(),
                "n/a".into(),
                "n/a".into(),
                "n/a".into(),
            ),
        };
        println!(
            "| {} | {} | {} | {} x {} | {} / {} / {} | {} | {} | {} | {} / {} | {} / {} |",
            r.label,
            r.nodes,
            r.arcs,
            r.pairs,
            r.trials,
            ms(r.hl.avg()),
            ms(r.hl.max()),
            ms(r.hl.min()),
            ms(r.hl.median()),
            total,
            total_median,
            r.hl.failures(),
            total_failed,
            ms(r.hl.ok_avg()),
            total_ok
        );
    }

    println!();
    println!("Per pair (over the trials):\n");
    println!("| graph | pair | high-level avg (ms) | failed | total avg (ms) | failed |");
    println!("|---|---|---|---|---|---|");
    for r in &rows {
        for (what, hl, total) in &r.per_pair {
            let (t, f) = match total {
                Some(t) => (ms(t.avg()), t.failures().to_string()),
                None => ("n/a".into(), "n/a".into()),
            };
            println!(
                "| {} | {what} | {} | {} | {t} | {f} |",
                r.label,
                ms(hl.avg()),
                hl.failures()
            );
        }
    }

    println!();
    println!("# Beside the paper's Table I (i7-4770K, single thread)\n");
    println!("Ratios are paper / ours on the average over every request (failed ones included); in brackets, on the successful requests only. \"Per arc\" divides both times by their graph's arcs (pessimistic for our smaller graphs: it assumes the time grows with the graph).\n");
    println!("| graph | paper nodes / arcs | ours nodes / arcs | paper high-level avg / max / min (s) | ours (ms) | high-level ratio | per arc | paper total avg (s) | ours (ms) | total ratio | per arc |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|");
    for r in &rows {
        let Some(p) = r.paper else { continue };
        if r.skipped.is_some() {
            println!(
                "| {} | {} / {} | — | {} / {} / {} | — | — | — | {} | — | — | — |",
                r.label, p.nodes, p.arcs, p.hl_avg, p.hl_max, p.hl_min, p.total_avg
            );
            continue;
        }
        let per_arc = r.arcs as f64 / p.arcs as f64;
        let both = |x: f64, y: f64| {
            if (x - y).abs() <= 1e-9 * x.abs() {
                ratio(x)
            } else {
                format!("{} ({})", ratio(x), ratio(y))
            }
        };
        let hl = (p.hl_avg / r.hl.avg(), p.hl_avg / r.hl.ok_avg());
        let (total_ours, total_ratio, total_per_arc) = match &r.total {
            Some(t) => {
                let x = (p.total_avg / t.avg(), p.total_avg / t.ok_avg());
                (
                    ms(t.avg()),
                    both(x.0, x.1),
                    both(x.0 * per_arc, x.1 * per_arc),
                )
            }
            None => ("n/a".into(), "n/a".into(), "n/a".into()),
        };
        println!(
            "| {} | {} / {} | {} / {} | {} / {} / {} | {} / {} / {} | {} | {} | {} | {} | {} | {} |",
            r.label,
            p.nodes,
            p.arcs,
            r.nodes,
            r.arcs,
            p.hl_avg,
            p.hl_max,
            p.hl_min,
            ms(r.hl.avg()),
            ms(r.hl.max()),
            ms(r.hl.min()),
            both(hl.0, hl.1),
            both(hl.0 * per_arc, hl.1 * per_arc),
            p.total_avg,
            total_ours,
            total_ratio,
            total_per_arc
        );
    }
    println!();
    println!("high level = Planner::plan with motions off (geometric rows: locate, search, path -> Cartesian conversion with IK and collision checks; abstract rows: search and simplification only). total = Planner::plan with motions on (adds RRT-Connect motions, shortcuts, timing) + execution in the kinematic simulator. Goals: high-level ratio >= 1000x, total ratio >= 200x.");
}
