//! The Vito cell's clear-the-table task (issue 10): three objects on the table at once,
//! each move planned with joint motions in the world (the other objects in the way, the
//! arms where the previous move left them) and executed in the kinematic simulator, the
//! world updated from it before the next move. One benchmark per seed of the randomized
//! solvers; docs/performance.md reports the median over seeds and the slowest seed.

use cellc_driver::fs_files::FsFiles;
use cellc_runtime::plan::PlanOptions;
use cellc_runtime::{Cell, ExecuteOptions};
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};

fn vito() -> Cell {
    let built = cellc_driver::build(&FsFiles, "cells/vito.cell", &Default::default());
    Cell::from_artifact(built.artifact.expect("vito builds"), &FsFiles).expect("loads")
}

/// Plans and executes every move of `clear_table` from the cell's world; the number of
/// trajectories executed.
fn clear_table(cell: &Cell, seed: u64) -> usize {
    let options = PlanOptions {
        seed,
        ..PlanOptions::default()
    };
    let mut world = cell.initial_world(&options).expect("the declared world");
    let mut trajectories = 0;
    for (object, goal) in cell.task("clear_table").expect("declared") {
        let plan = cell
            .plan_move(&world, object, &goal, &options)
            .expect("a plan");
        trajectories += plan.steps.iter().filter(|s| s.motion.is_some()).count();
        let mut simulator = cell.simulator(&world, &plan);
        let execute = ExecuteOptions {
            max_replans: 5,
            plan: options.clone(),
        };
        cell.execute(&mut world, plan, &mut simulator, &execute)
            .expect("executes");
    }
    trajectories
}

fn bench(c: &mut Criterion) {
    let cell = vito();
    let mut group = c.benchmark_group("world");
    group.sample_size(20);
    for seed in 0..5u64 {
        assert!(
            clear_table(&cell, seed) >= 6,
            "seed {seed}: too few motions"
        );
        group.bench_with_input(
            BenchmarkId::new("vito_clear_table_planned_and_executed", seed),
            &seed,
            |b, &seed| b.iter(|| clear_table(&cell, seed)),
        );
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
