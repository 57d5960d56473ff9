//! Scale guard for grasp sets (issue 16): how build memory and verification grow as a
//! hand's grasp set grows from 10 to 50 to 200 grasps.
//!
//! The cell is `cells/vito_full.cell`'s arms, table and bin with one cylinder, no symmetry
//! declared (so no member is merged), whose side grasps come from a grasp-set file of N
//! rows (in memory): the side grasp of `vito.cell` at N heights and turns about the hand's
//! approach. Every grasp joins the standing rest and is handed between the two hands
//! (`grasps <-> grasps matching`), so the arcs grow linearly with N. Printed once per
//! case: arcs, distinct checks, pruned arcs, arcs verified per second and distinct checks
//! per second (one timed verification on all cores), and the build's peak heap (a
//! counting allocator); criterion then times the verification.

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

use cellc_compiler::MemoryFiles;
use cellc_driver::fs_files::FsFiles;
use cellc_runtime::scene::Scene;
use cellc_runtime::verify::{verify, VerifyOptions};
use cellc_schema::Artifact;
use criterion::{criterion_group, criterion_main, Criterion};

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

/// The grasp-set file: `n` side grasps, heights from -6 to 6 cm crossed with turns about
/// the approach of up to 30° either way.
fn grasp_file(n: usize) -> String {
    let mut text = String::from("# generated: side grasps of the cylinder\nx,y,z,qx,qy,qz,qw\n");
    let side =
        nalgebra::UnitQuaternion::from_euler_angles(180f64.to_radians(), -90f64.to_radians(), 0.0);
    for i in 0..n {
        let t = i as f64 / n.max(2) as f64;
        let height = -0.06 + 0.12 * ((i * 7) % n) as f64 / n as f64;
        let turn = (t - 0.5) * 60f64.to_radians();
        // The hand turned about the object's y (the approach) and moved along its z.
        let motion = nalgebra::Isometry3::from_parts(
            nalgebra::Translation3::new(0.0, 0.0, height),
            nalgebra::UnitQuaternion::from_axis_angle(&nalgebra::Vector3::y_axis(), turn),
        );
        let written =
            nalgebra::Isometry3::from_parts(nalgebra::Translation3::new(0.0, 0.06, 0.1), side);
        let pose = written * motion.inverse();
        let p = pose.translation.vector;
        let q = pose.rotation.coords;
        text.push_str(&format!(
            "{},{},{},{},{},{},{}\n",
            p.x, p.y, p.z, q.x, q.y, q.z, q.w
        ));
    }
    text
}

/// The cell: vito_full's setting (everything before its first object) and one cylinder.
fn cell() -> String {
    let full = std::fs::read_to_string("cells/vito_full.cell").expect("cells/vito_full.cell");
    let head = &full[..full.find("  object cylinder {").expect("a cylinder")];
    format!(
        "{head}  object cylinder {{
    shape cylinder radius 0.04 height 0.2
    rest standing on tabletop at (0, 0, 0.1)
    grasp side by softhand from \"grasps.csv\"
    transition standing <-> side
    transition side <-> side matching
  }}
}}
"
    )
}

fn files(n: usize) -> Vec<(String, String)> {
    let mut files = vec![
        ("cells/scale.cell".to_string(), cell()),
        ("cells/grasps.csv".to_string(), grasp_file(n)),
    ];
    for entry in std::fs::read_dir("cells/robots").expect("cells/robots exists") {
        let p = entry.expect("entry").path();
        if let Ok(t) = std::fs::read_to_string(&p) {
            files.push((
                format!("cells/robots/{}", p.file_name().unwrap().to_string_lossy()),
                t,
            ));
        }
    }
    files
}

fn build(files: &[(String, String)]) -> Artifact {
    let world = MemoryFiles::new(files.iter().map(|(p, t)| (p.as_str(), t.as_str())));
    cellc_driver::build(
        &world,
        "cells/scale.cell",
        &cellc_driver::BuildOptions::unverified(),
    )
    .artifact
    .expect("the cell builds")
}

fn benches(c: &mut Criterion) {
    let mut c = std::mem::take(c).sample_size(10);
    for n in [10, 50, 200] {
        let files = files(n);
        let before = LIVE.load(Ordering::Relaxed);
        PEAK.store(before, Ordering::Relaxed);
        let artifact = build(&files);
        let build_peak = PEAK.load(Ordering::Relaxed) - before;
        let scene = Scene::load(&artifact, &FsFiles).expect("scene loads");
        let options = VerifyOptions::default();
        let mut once = artifact.clone();
        let started = Instant::now();
        let report = verify(&mut once, &scene, &options, &|_, _| {});
        let seconds = started.elapsed().as_secs_f64();
        println!(
            "grasps/{n}: {} arcs in {} distinct checks, {} pruned; {:.0} arcs/s, {:.0} checks/s; build peak heap {:.2} MiB",
            report.n_checked,
            report.n_checks,
            report.n_pruned,
            report.n_checked as f64 / seconds,
            report.n_checks as f64 / seconds,
            build_peak as f64 / (1024.0 * 1024.0)
        );
        c.bench_function(&format!("grasp_scale/verify_{n}_grasps"), |b| {
            b.iter(|| {
                let mut a = artifact.clone();
                verify(&mut a, &scene, &options, &|_, _| {})
            })
        });
    }
}

criterion_group!(grasp_scale_benches, benches);
criterion_main!(grasp_scale_benches);
