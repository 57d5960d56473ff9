//! Plans and simulates the Vito cell's handoff through the runtime's front door.
//!
//! `cargo run -p cellc-runtime --example plan_vito [REQUEST]`. A task planner would read
//! the artifact `cellc build` wrote; here the cell is compiled in memory first.

use cellc_runtime::{Cell, ExecuteOptions, FileError, Files, PlanOptions, VerifyOptions};

/// Files read from disk: the cell and its includes, robot models, meshes.
struct Disk;

impl Files for Disk {
    fn read(&self, path: &str) -> Result<Vec<u8>, FileError> {
        Ok(std::fs::read(path)?)
    }
}

/// The artifact of `cells/vito.cell`, as `cellc build` writes it (without verification).
fn vito_artifact() -> Vec<u8> {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../cells/vito.cell");
    let compiled = cellc_compiler::compile(&Disk, path);
    let cell = compiled.cell.as_ref().expect("vito.cell compiles");
    let artifact = cellc_compiler::artifact::lower(cell, &compiled.graphs, &compiled.sources);
    artifact.to_bytes(cellc_schema::Encoding::Json)
}

pub fn main() -> Result<(), Box<dyn std::error::Error>> {
    run(&std::env::args().nth(1).unwrap_or("handoff_cylinder".into()))
}

/// Plans and executes the cell's request `name`.
pub fn run(name: &str) -> Result<(), Box<dyn std::error::Error>> {
    let mut cell = Cell::load(&vito_artifact(), &Disk)?;
    cell.verify(&VerifyOptions::default());
    let request = cell
        .named_request(name, PlanOptions::default())
        .ok_or("no such request")?;
    let plan = cell.plan(&request)?;
    println!("{name}: {} in {} steps", plan.strategy, plan.steps.len());
    let mut simulator = cell.simulator(&plan);
    let run = cell.execute(plan, &mut simulator, &ExecuteOptions::default())?;
    let holder = cell
        .artifact()
        .end_effector_name(run.final_state.end_effector);
    println!("done: held by `{holder}` after {} steps", run.steps_done);
    Ok(())
}
