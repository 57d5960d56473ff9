//! Build-time verification benchmarks (issue 4): checking every arc of the shipped
//! geometric cells, and of a generated five-arm line (LWR arms with a shared hand kind,
//! benches between them), on all cores (rayon).

use cellc_compiler::MemoryFiles;
use cellc_driver::fs_files::FsFiles;
use cellc_runtime::scene::Scene;
use cellc_runtime::verify::{verify, VerifyOptions};
use cellc_schema::Artifact;
use criterion::{criterion_group, criterion_main, Criterion};

#[path = "line.rs"]
mod line;

fn artifact(path: &str, text: String) -> Artifact {
    let mut files = vec![(path.to_string(), text)];
    for entry in std::fs::read_dir("cells/robots").expect("cells/robots exists") {
        let p = entry.expect("entry").path();
        if let Ok(t) = std::fs::read_to_string(&p) {
            files.push((
                format!("cells/robots/{}", p.file_name().unwrap().to_string_lossy()),
                t,
            ));
        }
    }
    let world = MemoryFiles::new(files.iter().map(|(p, t)| (p.as_str(), t.as_str())));
    cellc_driver::build(&world, path, &cellc_driver::BuildOptions::unverified())
        .artifact
        .expect("the cell builds")
}

fn case(c: &mut Criterion, name: &str, artifact: Artifact) {
    let scene = Scene::load(&artifact, &FsFiles).expect("scene loads");
    let options = VerifyOptions::default();
    let mut once = artifact.clone();
    let report = verify(&mut once, &scene, &options, &|_, _| {});
    println!(
        "{name}: {} arcs checked in {} distinct checks ({} closed chains solved), {} pruned",
        report.n_checked, report.n_checks, report.n_chains, report.n_pruned
    );
    c.bench_function(name, |b| {
        b.iter(|| {
            let mut a = artifact.clone();
            verify(&mut a, &scene, &options, &|_, _| {})
        })
    });
}

fn benches(c: &mut Criterion) {
    let mut c = std::mem::take(c).sample_size(10);
    case(
        &mut c,
        "verify/vito",
        artifact(
            "cells/vito.cell",
            std::fs::read_to_string("cells/vito.cell").unwrap(),
        ),
    );
    case(
        &mut c,
        "verify/assembly_line",
        artifact(
            "cells/assembly_line.cell",
            std::fs::read_to_string("cells/assembly_line.cell").unwrap(),
        ),
    );
    // The same line at 5 to 50 arms, 8 hand grasps and 2 resting poses: arcs per arm
    // stay about equal, so time per arc (criterion's time over the printed arcs checked)
    // should not grow with the arms (issue 17).
    for arms in [5, 10, 20, 50] {
        case(
            &mut c,
            &format!("verify/line_{arms}_arms"),
            artifact(
                &format!("cells/line{arms}.cell"),
                line::line_cell(arms, 8, 2),
            ),
        );
    }
    // The 5-arm slice of the 10^6-arc line (`line_cell -- 50 70 4`): 70 grasps one yaw
    // family, so its 4,900 grasp pairs per arm pair are about 120 closed chains, which
    // verification solves once each per target (`runtime/src/verify/chains.rs`).
    case(
        &mut c,
        "verify/line_5_arms_70_grasps",
        artifact("cells/line5_70.cell", line::line_cell(5, 70, 4)),
    );
}

criterion_group!(verify_benches, benches);
criterion_main!(verify_benches);
