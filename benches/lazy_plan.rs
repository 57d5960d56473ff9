//! A plan on the 10^6-arc artifact read in part (issue 17, deliverable 4), in process:
//! the sectioned binary of `benches/gen_abstract_line.py`'s cell (50 arms, 100 grasps
//! each; generated here by the same rules) is written to a temporary file once, then each
//! iteration does what `cellc plan a1m.bin` does after start-up: open the file, check its
//! table, read and validate the core, read and validate the requested object's nodes
//! and arcs, build its search graph, and plan the cell's request.
//!
//! The steps are also timed one by one, and the two checksums over the file's sections
//! (XXH3-64, which the layout uses, and SHA-256, which it replaced), for
//! docs/performance.md.

use std::path::PathBuf;

use cellc_compiler::MemoryFiles;
use cellc_driver::fs_files::{FsFiles, PieceFile};
use cellc_runtime::plan::search::SearchGraph;
use cellc_runtime::plan::PlanOptions;
use cellc_runtime::{Cell, ObjectId};
use cellc_schema::files::MAX_ARTIFACT_BYTES;
use cellc_schema::partial::{Partial, Parts};
use cellc_schema::sections::Sections;
use cellc_schema::Encoding;
use criterion::{criterion_group, criterion_main, BatchSize, Criterion};

/// `benches/gen_abstract_line.py N G`, line for line.
fn abstract_line(n: usize, g: usize) -> String {
    let mut out = vec!["cell abstract_line {".to_string()];
    out.extend((0..=n).map(|i| format!("  workspace w{i}")));
    out.extend((0..n).map(|i| format!("  adjacent w{i} w{}", i + 1)));
    out.extend((0..=n).map(|i| format!("  fixed bench{i} reaches w{i}")));
    out.extend((0..n).map(|i| format!("  movable a{i} reaches w{i}, w{}", i + 1)));
    out.push("  object part {".to_string());
    out.extend((0..=n).map(|i| format!("    grasp r{i} by bench{i}")));
    for i in 0..n {
        out.extend((0..g).map(|k| format!("    grasp a{i}g{k} by a{i}")));
    }
    for i in 0..n {
        let grasps = |arm: usize| {
            (0..g)
                .map(|k| format!("a{arm}g{k}"))
                .collect::<Vec<_>>()
                .join(", ")
        };
        let arm = grasps(i);
        if i + 1 < n {
            let right = grasps(i + 1);
            out.extend((0..g).map(|k| format!("    transition a{i}g{k} <-> {right}")));
        }
        out.push(format!("    transition r{i} <-> {arm}"));
        out.push(format!("    transition r{} <-> {arm}", i + 1));
    }
    out.push("  }".to_string());
    out.push(format!(
        "  request across: part from bench0.r0 in w0 to bench{n}.r{n} in w{n}"
    ));
    out.push("}".to_string());
    out.join("\n") + "\n"
}

/// The a1m artifact's sectioned bytes, written to a temporary file.
fn a1m() -> (PathBuf, Vec<u8>) {
    let path = "abstract1m.cell";
    let text = abstract_line(50, 100);
    let files = MemoryFiles::new([(path, text.as_str())]);
    let artifact = cellc_driver::build(&files, path, &cellc_driver::BuildOptions::unverified())
        .artifact
        .expect("the cell builds");
    let n_arcs: usize = artifact.objects.iter().map(|o| o.graph.arcs.len()).sum();
    assert!(n_arcs >= 1_000_000, "{n_arcs} arcs");
    let bytes = artifact.to_bytes(Encoding::Binary);
    let file = std::env::temp_dir().join(format!("cellc-bench-a1m-{}.bin", std::process::id()));
    std::fs::write(&file, &bytes).expect("write the artifact");
    (file, bytes)
}

fn open(file: &str) -> Sections<PieceFile> {
    let piece = PieceFile::open(file, MAX_ARTIFACT_BYTES).expect("opens");
    Sections::from_source(piece).expect("the table")
}

/// What `cellc plan` does after start-up, without printing.
fn load_and_plan(file: &str) -> usize {
    let sections = open(file);
    let cell =
        Cell::load_objects(&sections, &[ObjectId(0)], Parts::GRAPH, &FsFiles).expect("loads");
    let request = cell
        .named_request("across", PlanOptions::default())
        .expect("the request");
    cell.plan(&cell.home_world(), &request)
        .expect("a plan")
        .states
        .len()
}

fn bench(c: &mut Criterion) {
    let (path, bytes) = a1m();
    let file = path.to_string_lossy().into_owned();
    println!(
        "a1m: {} bytes, {} steps planned",
        bytes.len(),
        load_and_plan(&file)
    );
    let mut group = c.benchmark_group("a1m");
    group.sample_size(20);
    group.bench_function("load_and_plan", |b| b.iter(|| load_and_plan(&file)));
    group.bench_function("table_and_core", |b| {
        b.iter(|| Partial::open(&open(&file)).expect("the core"))
    });
    let sections = open(&file);
    let core = Partial::open(&sections).expect("the core");
    // The core is cloned outside the timed part (a clone of an artifact costs as much as
    // reading a small one).
    group.bench_function("nodes_and_arcs", |b| {
        b.iter_batched(
            || core.clone(),
            |mut partial| {
                partial
                    .read(&sections, ObjectId(0), Parts::GRAPH)
                    .expect("reads");
                partial
            },
            BatchSize::LargeInput,
        )
    });
    let mut partial = core.clone();
    partial
        .read(&sections, ObjectId(0), Parts::GRAPH)
        .expect("reads");
    let graph = &partial.artifact().objects[0].graph;
    group.bench_function("search_graph", |b| b.iter(|| SearchGraph::new(graph)));
    let cell = Cell::from_partial(partial.clone(), &FsFiles).expect("loads");
    let request = cell
        .named_request("across", PlanOptions::default())
        .expect("the request");
    group.bench_function("plan", |b| {
        b.iter(|| cell.plan(&cell.home_world(), &request).expect("a plan"))
    });
    // The checksums over every section's bytes, as a reader checks them all.
    let in_memory = Sections::open(&bytes).expect("opens");
    let bodies: Vec<&[u8]> = in_memory
        .table()
        .iter()
        .map(|s| &bytes[s.offset..s.offset + s.length])
        .collect();
    group.bench_function("xxh3_all_sections", |b| {
        b.iter(|| {
            bodies
                .iter()
                .map(|s| xxhash_rust::xxh3::xxh3_64(s))
                .fold(0, u64::wrapping_add)
        })
    });
    group.bench_function("sha256_all_sections", |b| {
        b.iter(|| {
            bodies
                .iter()
                .map(|s| cellc_schema::sha256_hex(s).len())
                .sum::<usize>()
        })
    });
    group.finish();
    let _ = std::fs::remove_file(&path);
}

criterion_group!(benches, bench);
criterion_main!(benches);
