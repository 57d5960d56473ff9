//! Compile-time benchmarks (issue 3): building the imported Vito database of the original
//! planner, the shipped cells, and a generated 50-arm line with shared hand kinds
//! (over 10⁶ arcs). "Build" is everything `cellc build` does in memory: parse, resolve,
//! derive workspaces, check, build the graphs, lower to the artifact and encode it.
//!
//! Peak heap is measured with a counting allocator and printed once per case.

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

use cellc_compiler::MemoryFiles;
use cellc_schema::Encoding;
use criterion::{criterion_group, criterion_main, Criterion};

#[path = "line.rs"]
mod line;

/// Counts live heap bytes and their high-water mark.
struct Counting;

static LIVE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let p = unsafe { System.alloc(layout) };
        if !p.is_null() {
            let live = LIVE.fetch_add(layout.size(), Ordering::Relaxed) + layout.size();
            PEAK.fetch_max(live, Ordering::Relaxed);
        }
        p
    }
    unsafe fn dealloc(&self, p: *mut u8, layout: Layout) {
        unsafe { System.dealloc(p, layout) };
        LIVE.fetch_sub(layout.size(), Ordering::Relaxed);
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

fn files(main: (&str, String)) -> Vec<(String, String)> {
    let mut files = vec![(main.0.to_string(), main.1)];
    for entry in std::fs::read_dir("cells/robots").expect("cells/robots exists") {
        let path = entry.expect("entry").path();
        if let Ok(text) = std::fs::read_to_string(&path) {
            let name = format!(
                "cells/robots/{}",
                path.file_name().unwrap().to_string_lossy()
            );
            files.push((name, text));
        }
    }
    files
}

/// One whole in-memory build; returns the number of arcs (so nothing is optimised away).
fn build(world: &MemoryFiles, path: &str) -> usize {
    let artifact = cellc_driver::build(world, path, &cellc_driver::BuildOptions::unverified())
        .artifact
        .expect("the cell builds");
    let bytes = artifact.to_bytes(Encoding::Binary);
    std::hint::black_box(bytes.len());
    artifact.objects.iter().map(|o| o.graph.arcs.len()).sum()
}

fn case(c: &mut Criterion, name: &str, main: (&str, String)) {
    let files = files(main.clone());
    let world = MemoryFiles::new(files.iter().map(|(p, t)| (p.as_str(), t.as_str())));
    let before = LIVE.load(Ordering::Relaxed);
    PEAK.store(before, Ordering::Relaxed);
    let arcs = build(&world, main.0);
    let peak = PEAK.load(Ordering::Relaxed) - before;
    println!(
        "{name}: {arcs} arcs, peak heap {:.1} MiB",
        peak as f64 / (1024.0 * 1024.0)
    );
    c.bench_function(name, |b| b.iter(|| build(&world, main.0)));
}

fn benches(c: &mut Criterion) {
    let imported =
        cellc::import::dualmanip(std::path::Path::new("tests/data/dualmanip/vito_full.db"))
            .expect("the Vito database imports");
    case(
        c,
        "build/imported_vito_full_db",
        ("cells/vito_full.cell", imported.text),
    );
    case(
        c,
        "build/fig3",
        (
            "cells/fig3.cell",
            std::fs::read_to_string("cells/fig3.cell").unwrap(),
        ),
    );
    case(
        c,
        "build/vito",
        (
            "cells/vito.cell",
            std::fs::read_to_string("cells/vito.cell").unwrap(),
        ),
    );
    // A build of the line takes about half a second: ten samples keep the run short.
    let line50 = line::line_cell(50, 100, 4);
    let mut slow = Criterion::default().sample_size(10);
    case(
        &mut slow,
        "build/line_50_arms_2m_arcs",
        ("cells/line50.cell", line50),
    );
}

criterion_group!(build_benches, benches);
criterion_main!(build_benches);
