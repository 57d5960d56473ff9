//! Builds the Vito cell from source, plans its handoff and simulates it: the way in a Rust
//! program takes (a task planner holding the artifact `cellc build` wrote would start at
//! `Cell::load` instead).
//!
//! `cargo run --release -p cellc-driver --example plan_vito [REQUEST]`

use cellc_driver::fs_files::FsFiles;
use cellc_runtime::{Cell, ExecuteOptions, PlanOptions};

pub fn main() -> Result<(), Box<dyn std::error::Error>> {
    run(&std::env::args().nth(1).unwrap_or("handoff_cylinder".into()))
}

/// Builds `cells/vito.cell` (compiled and verified, as `cellc build` does), then plans
/// and executes its request `name` on the simulator.
pub fn run(name: &str) -> Result<(), Box<dyn std::error::Error>> {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../cells/vito.cell");
    let built = cellc_driver::build(&FsFiles, path, &Default::default());
    let artifact = built.artifact.ok_or("vito.cell has errors")?;
    let cell = Cell::from_artifact(artifact, &FsFiles)?;
    let request = cell
        .named_request(name, PlanOptions::default())
        .ok_or("no such request")?;
    // The request's object at its start, its hand's arm holding it, nothing else placed.
    let mut world = cell.request_world(&cell.home_world(), &request)?;
    let plan = cell.plan_move(&world, request.object, &request.goal, &request.options)?;
    println!("{name}: {} in {} steps", plan.strategy, plan.steps.len());
    let mut simulator = cell.simulator(&world, &plan);
    let run = cell.execute(&mut world, plan, &mut simulator, &ExecuteOptions::default())?;
    let holder = cell
        .artifact()
        .end_effector_name(run.final_state.end_effector);
    println!("done: held by `{holder}` after {} steps", run.steps_done);
    Ok(())
}
