//! High-level search at the paper's scale against networkx (issue 17): Dijkstra from one
//! state to another on the object graphs of `cells/vito_full.cell` and
//! `cells/assembly_line_full.cell` (compiled and verified once, as `cellc build` does,
//! outside the timing) and of the original Vito database (`tests/data/dualmanip/
//! vito_full.db`, imported; abstract, so its graphs are the compiler's).
//!
//! Per object graph, 100 start/goal pairs drawn with a seeded generator (ChaCha8, seed
//! 17), a pair kept when its goal can be reached. Each search is
//! [`SearchGraph::search`] with one reused scratch and no arc left out, path and cost
//! included. criterion times a pass over all pairs; then, for the side by side, both
//! sides run the same protocol: passes over all pairs, each pass timed, the median pass
//! divided by the number of pairs. networkx runs in `benches/search_networkx.py` on the
//! same graphs and pairs, exported as JSON into the target directory
//! (`single_source_dijkstra` with the target: cost and path, as here; a `DiGraph` holds
//! one arc per ordered pair, so parallel arcs become the cheapest of them, which can only
//! make networkx's graph smaller). The costs of both sides are compared pair by pair.
//!
//! `cargo bench --bench search` (passes: `CELLC_SEARCH_PASSES`, default 101 here and
//! 11 for networkx). Prints a markdown table: medians per query and the ratio
//! networkx / ours.

use std::collections::HashSet;
use std::hint::black_box;
use std::path::Path;
use std::process::Command;
use std::time::Instant;

use cellc_driver::fs_files::FsFiles;
use cellc_runtime::plan::search::{Scratch, SearchGraph};
use cellc_runtime::plan::ArcRef;
use cellc_schema::{Artifact, Graph, NodeId};
use criterion::Criterion;
use rand::{Rng, SeedableRng};

/// Pairs per graph.
const PAIRS: usize = 100;

/// One object graph with its pairs.
struct Row {
    label: String,
    graph: Graph,
    search: SearchGraph,
    pairs: Vec<(NodeId, NodeId)>,
}

fn verified(path: &str) -> Artifact {
    cellc_driver::build(&FsFiles, path, &Default::default())
        .artifact
        .expect("the cell builds")
}

fn imported(path: &str) -> Artifact {
    let imported = cellc::import::dualmanip(Path::new(path)).expect("the database imports");
    let world = cellc_compiler::MemoryFiles::new([("vito_full.cell", imported.text.as_str())]);
    cellc_driver::build(
        &world,
        "vito_full.cell",
        &cellc_driver::BuildOptions::unverified(),
    )
    .artifact
    .expect("the cell builds")
}

/// Up to [`PAIRS`] pairs of distinct states, the goal reachable from the start, drawn
/// deterministically.
fn pairs(search: &SearchGraph) -> Vec<(NodeId, NodeId)> {
    let n = search.n_nodes() as u32;
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(17);
    let mut scratch = Scratch::default();
    let none = HashSet::new();
    let mut out = Vec::new();
    for _ in 0..100 * PAIRS {
        if out.len() == PAIRS || n < 2 {
            break;
        }
        let (s, t) = (
            NodeId(rng.random_range(0..n)),
            NodeId(rng.random_range(0..n)),
        );
        if s != t && search.search(&mut scratch, s, &[t], &none).is_some() {
            out.push((s, t));
        }
    }
    out
}

fn rows() -> Vec<Row> {
    let mut rows = Vec::new();
    let mut add = |file: &str, artifact: Artifact| {
        for object in artifact.objects {
            let search = SearchGraph::new(&object.graph);
            let pairs = pairs(&search);
            if pairs.is_empty() {
                continue;
            }
            rows.push(Row {
                label: format!("{file} {}", object.name),
                graph: object.graph,
                search,
                pairs,
            });
        }
    };
    for path in ["cells/vito_full.cell", "cells/assembly_line_full.cell"] {
        let t = Instant::now();
        let artifact = verified(path);
        eprintln!(
            "{path}: compiled and verified in {:.1} s (not timed)",
            t.elapsed().as_secs_f64()
        );
        add(path.trim_start_matches("cells/"), artifact);
    }
    add(
        "vito_full.db",
        imported("tests/data/dualmanip/vito_full.db"),
    );
    rows
}

/// One pass: every pair searched once; the sum of the costs, so nothing is optimised out.
fn pass(row: &Row, scratch: &mut Scratch, none: &HashSet<ArcRef>) -> f64 {
    let mut total = 0.0;
    for &(s, t) in &row.pairs {
        let route = row.search.search(scratch, s, &[t], none);
        total += black_box(route).map_or(0.0, |r| r.cost + r.nodes.len() as f64);
    }
    total
}

fn median(mut xs: Vec<f64>) -> f64 {
    xs.sort_by(f64::total_cmp);
    xs[xs.len() / 2]
}

/// The median time per query, in microseconds, over `passes` timed passes.
fn ours(row: &Row, passes: usize) -> f64 {
    let mut scratch = Scratch::default();
    let none = HashSet::new();
    pass(row, &mut scratch, &none);
    let per_pass = (0..passes)
        .map(|_| {
            let t = Instant::now();
            black_box(pass(row, &mut scratch, &none));
            t.elapsed().as_secs_f64()
        })
        .collect();
    median(per_pass) / row.pairs.len() as f64 * 1e6
}

/// The graphs and pairs for the Python side: per arc (from, to, weight) with the weight
/// searched here.
fn export(rows: &[Row], passes: usize) -> serde_json::Value {
    let graphs: Vec<serde_json::Value> = rows
        .iter()
        .map(|row| {
            let arcs: Vec<(u32, u32, f64)> = row
                .graph
                .arcs
                .iter()
                .map(|a| (a.from, a.to, a.weight))
                .collect();
            let pairs: Vec<(u32, u32)> = row.pairs.iter().map(|&(s, t)| (s.0, t.0)).collect();
            serde_json::json!({
                "label": row.label,
                "nodes": row.graph.nodes.len(),
                "arcs": arcs,
                "pairs": pairs,
            })
        })
        .collect();
    serde_json::json!({ "passes": passes, "graphs": graphs })
}

/// What networkx measured on one graph.
struct Theirs {
    /// Median time per query, in microseconds.
    median_us: f64,
    /// Per pair, the cost (`None`: not reachable).
    costs: Vec<Option<f64>>,
}

/// networkx's version, and what it measured per graph.
fn networkx(rows: &[Row], passes: usize) -> (String, Vec<Theirs>) {
    let dir = std::env::var("CARGO_TARGET_DIR").unwrap_or_else(|_| "target".into());
    let input = Path::new(&dir).join("search_networkx.json");
    std::fs::write(&input, export(rows, passes).to_string()).expect("the export is written");
    let output = Command::new("python3")
        .arg("benches/search_networkx.py")
        .arg(&input)
        .output()
        .expect("python3 runs");
    assert!(
        output.status.success(),
        "benches/search_networkx.py failed (is networkx installed?): {}",
        String::from_utf8_lossy(&output.stderr)
    );
    let v: serde_json::Value =
        serde_json::from_slice(&output.stdout).expect("the script prints JSON");
    let version = v["networkx"].as_str().unwrap_or("?").to_string();
    let graphs = v["graphs"]
        .as_array()
        .expect("graphs")
        .iter()
        .map(|g| {
            let median_us = g["median_us"].as_f64().expect("median_us");
            let costs = g["costs"]
                .as_array()
                .expect("costs")
                .iter()
                .map(serde_json::Value::as_f64)
                .collect();
            Theirs { median_us, costs }
        })
        .collect();
    (version, graphs)
}

fn load_average() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .map(|l| l.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
        .unwrap_or_else(|_| "unknown".into())
}

fn main() {
    // `cargo bench` passes `--bench`; without it (`cargo test --benches`) every part runs
    // once, as criterion's own test mode does.
    let bench = std::env::args().any(|a| a == "--bench");
    let passes = |default: usize| {
        if !bench {
            return 1;
        }
        std::env::var("CELLC_SEARCH_PASSES")
            .ok()
            .and_then(|p| p.parse().ok())
            .filter(|&p| p > 0)
            .unwrap_or(default)
    };
    let rows = rows();
    let mut c = Criterion::default().configure_from_args();
    for row in &rows {
        let mut scratch = Scratch::default();
        let none = HashSet::new();
        let id = format!("search/{} ({} pairs)", row.label, row.pairs.len());
        c.bench_function(&id, |b| b.iter(|| pass(row, &mut scratch, &none)));
    }
    c.final_summary();

    let load_before = load_average();
    let medians: Vec<f64> = rows.iter().map(|row| ours(row, passes(101))).collect();
    let (version, theirs) = networkx(&rows, passes(11));
    let mut scratch = Scratch::default();
    let none = HashSet::new();
    for (row, Theirs { costs, .. }) in rows.iter().zip(&theirs) {
        for (&(s, t), cost) in row.pairs.iter().zip(costs) {
            let here = row
                .search
                .search(&mut scratch, s, &[t], &none)
                .map(|r| r.cost);
            let same = match (here, *cost) {
                (Some(a), Some(b)) => (a - b).abs() <= 1e-9 * b.abs().max(1.0),
                (None, None) => true,
                _ => false,
            };
            assert!(
                same,
                "{}: {s:?} -> {t:?} costs {here:?} here, {cost:?} in networkx",
                row.label
            );
        }
    }
    println!("\n# High-level search against networkx {version}\n");
    println!(
        "load average: {load_before} before, {} after",
        load_average()
    );
    println!("| graph | nodes | arcs | pairs | ours (µs/query) | networkx (µs/query) | networkx / ours |");
    println!("|---|---:|---:|---:|---:|---:|---:|");
    for ((row, us), them) in rows.iter().zip(&medians).zip(&theirs) {
        println!(
            "| {} | {} | {} | {} | {us:.2} | {:.1} | {:.0} |",
            row.label,
            row.graph.nodes.len(),
            row.graph.arcs.len(),
            row.pairs.len(),
            them.median_us,
            them.median_us / us
        );
    }
}
