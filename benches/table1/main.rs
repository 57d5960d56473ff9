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
//! - `cells/vito.cell` (geometric: the two LWRs, table, bin), one row per object, and
//!   `cells/vito_full.cell`, the same cell with grasp families at the paper's scale. The
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
//! - `cells/assembly_line.cell` and `cells/assembly_line_full.cell` (the same line with
//!   grasp families, at the paper's scale); a row is skipped when its cell does not plan.
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
//!
//! Modules: `paper.rs` the paper's figures; `pairs.rs` the start/goal pairs; `measure.rs`
//! the timing of a row; `report.rs` the tables.

mod measure;
mod pairs;
mod paper;
mod report;

use std::path::Path;
use std::time::Instant;

use cellc_driver::fs_files::FsFiles;
use cellc_runtime::plan::planner::Planner;
use cellc_runtime::scene::Scene;
use cellc_schema::Artifact;

use measure::{measure, skipped};
use paper::paper;
use report::ms;

/// A compiled, verified geometric cell, and how long that took (build time, parallel).
struct Geometric {
    artifact: Artifact,
    scene: Scene,
    build_seconds: f64,
}

fn geometric(path: &str) -> Result<Geometric, String> {
    let t = Instant::now();
    let built = cellc_driver::build(&FsFiles, path, &Default::default());
    let Some(artifact) = built.artifact else {
        let first = built
            .diagnostics
            .iter()
            .find(|d| d.is_error())
            .map(|d| d.message.clone())
            .unwrap_or_default();
        return Err(format!("{path} has errors: {first}"));
    };
    let scene = Scene::load(&artifact, &FsFiles).map_err(|e| format!("{path}: {e:?}"))?;
    Ok(Geometric {
        artifact,
        scene,
        build_seconds: t.elapsed().as_secs_f64(),
    })
}

fn trials() -> usize {
    std::env::var("CELLC_TABLE1_TRIALS")
        .ok()
        .and_then(|t| t.parse().ok())
        .filter(|&t| t > 0)
        .unwrap_or(100)
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

    // The shipped geometric Vito cell, and the same cell at the paper's scale (grasp and
    // rest families: graphs at least as large as the paper's).
    for path in ["cells/vito.cell", "cells/vito_full.cell"] {
        let file = path.trim_start_matches("cells/");
        match geometric(path) {
            Ok(g) => {
                println!(
                    "{file}: compiled and verified once in {} ms (build time, parallel, not part of any request)",
                    ms(g.build_seconds)
                );
                let planner = Planner::new(&g.artifact, Some(&g.scene));
                for object in ["pitcher", "colander", "ball", "cylinder"] {
                    let label = format!("{file} {object}");
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
            Err(e) => rows.push(skipped(file, None, e)),
        }
    }

    // The original database: the paper's pitcher and colander graphs, abstract.
    match cellc::import::dualmanip(Path::new("tests/data/dualmanip/vito_full.db")) {
        Ok(imported) => {
            let world =
                cellc_compiler::MemoryFiles::new([("vito_full.cell", imported.text.as_str())]);
            let artifact = cellc_driver::build(
                &world,
                "vito_full.cell",
                &cellc_driver::BuildOptions::unverified(),
            )
            .artifact
            .expect("the cell builds");
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

    // The assembly line, and the same line at the paper's scale (grasp families).
    for line in ["cells/assembly_line.cell", "cells/assembly_line_full.cell"] {
        let label = line.trim_start_matches("cells/");
        match geometric(line) {
            Ok(g) => {
                println!(
                    "{label}: compiled and verified once in {} ms (build time, parallel, not part of any request)",
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
    }

    report::print(&rows);
}
