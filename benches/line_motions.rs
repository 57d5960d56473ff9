//! Plans with joint motions along generated lines of 5, 10, 20 and 50 LWR arms (issue
//! 17): the part from the first bench to the last, every arm carrying it one bench on,
//! so a line of n arms plans n - 2 carries with their grasps, put-downs and returns
//! home. The cost should grow with the number of steps, not with the number of arms
//! times the steps: each motion moves one arm, and the collision checks of a motion
//! place the standing arms once (`collision::frozen`).
//!
//! Verification (once per line, outside the timing) prunes what no motion can do; each
//! iteration plans with the next of 16 seeds.

use cellc_compiler::MemoryFiles;
use cellc_driver::fs_files::FsFiles;
use cellc_runtime::math::Iso;
use cellc_runtime::plan::planner::Planner;
use cellc_runtime::plan::{Goal, Placement, PlanOptions, Request};
use cellc_runtime::scene::Scene;
use cellc_runtime::verify::{verify, VerifyOptions};
use cellc_schema::{Artifact, EndEffectorId, ObjectId};
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

/// The part resting on bench `k` (its centre 5 cm above the bench top).
fn on_bench(a: &Artifact, k: usize) -> Placement {
    let name = format!("bench{k}");
    let holder = a
        .end_effectors
        .iter()
        .position(|e| e.name == name)
        .expect("the bench exists");
    Placement {
        holder: EndEffectorId(holder as u32),
        grasp: None,
        workspace: None,
        pose: Some(Iso::translation(k as f64 + 0.5, 0.5, 0.81)),
    }
}

fn case(c: &mut Criterion, arms: usize) {
    let mut a = artifact(
        &format!("cells/line{arms}.cell"),
        line::line_cell(arms, 2, 1),
    );
    let scene = Scene::load(&a, &FsFiles).expect("scene loads");
    verify(&mut a, &scene, &VerifyOptions::default(), &|_, _| {});
    let planner = Planner::new(&a, Some(&scene));
    let request = Request {
        object: ObjectId(0),
        start: on_bench(&a, 0),
        goal: Goal::Placement(on_bench(&a, arms - 2)),
        options: PlanOptions::default(),
    };
    let plan = planner.plan(&request).expect("the line plans");
    println!(
        "plan_motions/line_{arms}_arms: {} steps, {} motions",
        plan.steps.len(),
        plan.steps.iter().filter(|s| s.motion.is_some()).count()
    );
    let mut seed = 0u64;
    c.bench_function(&format!("plan_motions/line_{arms}_arms"), |b| {
        b.iter(|| {
            seed += 1;
            let mut r = request.clone();
            r.options.seed = seed % 16;
            std::hint::black_box(planner.plan(&r).expect("plans"))
        })
    });
}

fn benches(c: &mut Criterion) {
    let mut c = std::mem::take(c).sample_size(10);
    for arms in [5, 10, 20, 50] {
        case(&mut c, arms);
    }
}

criterion_group!(line_benches, benches);
criterion_main!(line_benches);
