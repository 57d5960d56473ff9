//! `reach ARM auto` computed with the runtime: the [`ReachSolver`] the compiler asks
//! (it depends on no kinematics), and the compile every command uses.
//!
//! The scene is built from the cell so far and checked as `cellc build` checks it (a home
//! that collides or a link that touches a fixed body in every configuration makes every
//! sample fail for that reason alone, so those are reported instead of a reach that is
//! not found, E0420 and E0421); each arm's reach is then sampled by
//! [`cellc_runtime::reach::arm_reach`].

use cellc_compiler::diagnostics::ReachAutoProblem;
use cellc_compiler::reach::{ReachFound, ReachQuery, ReachSolver};
use cellc_compiler::Compilation;
use cellc_lang::{Diagnostic, SourceMap};
use cellc_runtime::reach::{arm_reach, ReachError, ReachOptions, Region};
use cellc_runtime::scene::Scene;
use cellc_schema::math::{aabb_from_schema, aabb_to_schema};
use cellc_schema::{Artifact, EndEffectorId, Files};

/// The runtime's kinematics, reading robot models and meshes through `files`.
pub struct RuntimeReach<'f> {
    /// Where robot models and meshes are read.
    pub files: &'f dyn Files,
}

impl ReachSolver for RuntimeReach<'_> {
    fn solve(
        &self,
        scene: &Artifact,
        sources: &SourceMap,
        queries: &[ReachQuery],
    ) -> Result<Vec<Result<ReachFound, ReachAutoProblem>>, Vec<Diagnostic>> {
        let built = Scene::load(scene, self.files).map_err(|e| {
            vec![crate::verify_report::scene_error_at(
                &e,
                &scene.robots,
                &scene.spans,
            )]
        })?;
        let preflight = cellc_runtime::verify::preflight::preflight(scene, &built);
        if preflight.blocks_verification() {
            let found = crate::scene_report::diagnostics(scene, &preflight, sources);
            return Err(found.into_iter().filter(Diagnostic::is_error).collect());
        }
        let options = ReachOptions::default();
        Ok(queries
            .iter()
            .map(|query| {
                let regions: Vec<Region> = query
                    .regions
                    .iter()
                    .map(|r| Region {
                        surface: EndEffectorId(r.surface),
                        space: aabb_from_schema(&r.space),
                    })
                    .collect();
                let found = arm_reach(scene, &built, EndEffectorId(query.arm), &regions, &options)
                    .map_err(|e| match e {
                        ReachError::TooFewJoints { joints } => {
                            ReachAutoProblem::TooFewJoints { joints }
                        }
                        _ => ReachAutoProblem::NothingReached { tried: 0 },
                    })?;
                Ok(ReachFound {
                    boxes: regions
                        .iter()
                        .zip(&found.boxes)
                        .flat_map(|(r, boxes)| {
                            boxes.iter().map(|b| (r.surface.0, aabb_to_schema(b)))
                        })
                        .collect(),
                    tried: found.tried,
                    solves: found.solves,
                    elapsed: found.elapsed,
                })
            })
            .collect())
    }
}

/// Compiles the cell at `path` with the runtime's kinematics for `reach auto` and the
/// package path of `options`.
pub fn compile(
    files: &dyn Files,
    path: &str,
    options: &cellc_compiler::CompileOptions,
) -> Compilation {
    cellc_compiler::compile_with(files, &RuntimeReach { files }, path, options)
}
