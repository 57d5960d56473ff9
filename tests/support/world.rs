//! What the world tests share: the Vito cell compiled and verified, options by seed,
//! world documents, and the independent dense re-check of a plan's trajectories with
//! every object of the world in the scene.

// Each test binary that includes this module uses some of it.
#![allow(dead_code)]

use cellc_driver::fs_files::FsFiles;
use cellc_runtime::motion::{check_trajectory, MotionOptions};
use cellc_runtime::plan::{MotionContext, PlanOptions};
use cellc_runtime::scene::SceneScratch;
use cellc_runtime::{Cell, Plan, World};
use cellc_schema::WorldDocument;

/// `cells/vito.cell`, compiled (clean) and verified.
pub fn vito() -> Cell {
    let built = cellc_driver::build(&FsFiles, "cells/vito.cell", &Default::default());
    assert!(
        built.compilation.diagnostics.is_empty(),
        "vito is not clean"
    );
    Cell::from_artifact(built.artifact.expect("vito builds"), &FsFiles).expect("loads")
}

/// Default options with `seed`.
pub fn options(seed: u64) -> PlanOptions {
    PlanOptions {
        seed,
        ..PlanOptions::default()
    }
}

/// A valid world document.
pub fn document(json: &str) -> WorldDocument {
    WorldDocument::from_json(json.as_bytes()).expect("a valid document")
}

/// Every trajectory of `plan` re-checked at a quarter of the planner's resolution, the
/// world's other objects placed by the test itself (from `world`, not from the plan);
/// panics on the first that hits something.
pub fn recheck(cell: &Cell, world: &World, plan: &Plan) -> usize {
    checked(cell, world, plan).unwrap_or_else(|e| panic!("{e}"))
}

/// [`recheck`] as a result: how many trajectories were checked, or the first that hits
/// something.
pub fn checked(cell: &Cell, world: &World, plan: &Plan) -> Result<usize, String> {
    let scene = cell.scene().expect("geometric");
    let obstacles = world.obstacles(cell.artifact(), scene, plan.object);
    let fine = MotionOptions::default().collision_resolution / 4.0;
    let mut checked = 0;
    for step in &plan.steps {
        let (Some(t), Some(context)) = (&step.motion, &step.motion_context) else {
            continue;
        };
        // The plan's own record of the obstacles is replaced by the test's.
        let context = MotionContext {
            obstacles: obstacles.clone(),
            ..context.clone()
        };
        check_trajectory(
            scene,
            t,
            plan.object,
            &context,
            fine,
            &mut SceneScratch::default(),
        )
        .map_err(|e| format!("a trajectory hits something: {e:?}"))?;
        checked += 1;
    }
    Ok(checked)
}
