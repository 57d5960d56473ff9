//! `reach ARM auto` computed with the runtime: the [`ReachSolver`] the compiler asks
//! (it depends on no kinematics), and the compile every command uses.
//!
//! The scene is built from the cell so far and checked as `cellc build` checks it (a home
//! that collides or a link that touches a fixed body in every configuration makes every
//! sample fail for that reason alone, so those are reported instead of a reach that is
//! not found, E0420 and E0421); each arm's reach is then sampled by
//! [`cellc_runtime::reach::arm_reach`].
//!
//! A front end that compiles the same cell after every keystroke (the language server)
//! compiles through [`compile_reusing`]: the trees of unchanged files come from its
//! parser, and `reach ARM auto`, which samples kinematics for seconds, is answered from a
//! [`ReachCache`] when the scene is the one already answered.

use std::cell::RefCell;
use std::collections::HashMap;

use cellc_compiler::diagnostics::ReachAutoProblem;
use cellc_compiler::load::Parser;
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

/// Compiles the cell at `path` as [`compile`] does, with the trees of `trees` (a cache of
/// unchanged files' trees) and the reach answers `reach` remembers.
pub fn compile_reusing(
    files: &dyn Files,
    path: &str,
    options: &cellc_compiler::CompileOptions,
    trees: &dyn Parser,
    reach: &ReachCache,
) -> Compilation {
    let solver = CachedReach {
        solver: RuntimeReach { files },
        cache: reach,
    };
    cellc_compiler::compile_parsed_with(files, &solver, trees, path, options)
}

/// Scenes remembered at most; past this the cache starts again.
const MAX_CACHED_SCENES: usize = 16;

/// The answers of one scene's reach.
type Answers = Vec<Result<ReachFound, ReachAutoProblem>>;

/// The runtime's reach answers, by the scene and queries they answer. An edit that does
/// not touch the scene (a comment, a request, a grasp's label) is answered from here.
#[derive(Default)]
pub struct ReachCache {
    answers: RefCell<HashMap<String, Answers>>,
}

/// The runtime's solver in front of the cache.
struct CachedReach<'a> {
    solver: RuntimeReach<'a>,
    cache: &'a ReachCache,
}

impl ReachSolver for CachedReach<'_> {
    fn solve(
        &self,
        scene: &Artifact,
        sources: &SourceMap,
        queries: &[ReachQuery],
    ) -> Result<Answers, Vec<Diagnostic>> {
        // Where the items are written (spans, source hashes) changes with every edit
        // and changes no reach: the key is the scene without them.
        let mut geometry = scene.clone();
        geometry.sources.clear();
        geometry.spans.clear();
        let key = match serde_json::to_string(&geometry) {
            Ok(json) => format!("{json}{queries:?}"),
            Err(_) => return self.solver.solve(scene, sources, queries),
        };
        if let Some(answers) = self.cache.answers.borrow().get(&key) {
            return Ok(answers.clone());
        }
        // Diagnostics point into this compilation's sources, so only answers are kept.
        let answers = self.solver.solve(scene, sources, queries)?;
        let mut cache = self.cache.answers.borrow_mut();
        if cache.len() >= MAX_CACHED_SCENES {
            cache.clear();
        }
        cache.insert(key, answers.clone());
        Ok(answers)
    }
}
