//! The build pipeline: a cell's source to a verified artifact, with every diagnostic
//! found on the way.
//!
//! One function, [`build`], so that `cellc build`, `cellc plan CELL`, the service and
//! embedders all give the same answer: compile (with the runtime's kinematics for
//! `reach ARM auto`), lower to an artifact, and, for a cell with arms, load the scene,
//! check it as a whole (homes, permanent contacts, grasps: a scene wrong whatever the
//! arc is reported and no arc is checked, as each would be pruned for it) and verify
//! every arc, pruned arcs coming back as warnings.

use cellc_compiler::{Compilation, CompileOptions};
use cellc_lang::{Diagnostic, SourceMap};
use cellc_runtime::verify::{Checked, VerifyOptions};
use cellc_schema::{Artifact, Body, Files};

/// What a build is asked to do.
#[derive(Clone, Default)]
pub struct BuildOptions<'p> {
    /// What the compilation is told (the package path).
    pub compile: CompileOptions,
    /// Leave the scene and the arcs unchecked (`cellc build --no-verify`): the artifact
    /// is as compiled.
    pub no_verify: bool,
    /// Seed of the randomized solvers of verification.
    pub seed: u64,
    /// Called as verification goes, with (checks done, checks in all), from any thread.
    pub progress: Option<&'p (dyn Fn(u64, u64) + Sync)>,
}

impl BuildOptions<'_> {
    /// Compile and lower only, the scene and the arcs left unchecked: the artifact
    /// `cellc build --no-verify` writes, for uses that check or verify it themselves.
    pub fn unverified() -> Self {
        BuildOptions {
            no_verify: true,
            ..BuildOptions::default()
        }
    }
}

/// What a build gives.
pub struct Built {
    /// The artifact, verified when the cell has arms; `None` when any diagnostic is an
    /// error.
    pub artifact: Option<Artifact>,
    /// Every diagnostic: the compiler's, then the scene's and verification's.
    pub diagnostics: Vec<Diagnostic>,
    /// The compilation: its `sources` are what the diagnostics are rendered against, and
    /// it keeps what only it knows (the reach `reach ARM auto` found).
    pub compilation: Compilation,
}

/// Builds the cell at `path`, reading every file through `files`.
pub fn build(files: &dyn Files, path: &str, options: &BuildOptions<'_>) -> Built {
    let compilation = crate::reach::compile(files, path, &options.compile);
    let mut diagnostics = compilation.diagnostics.clone();
    let mut artifact = lowered(&compilation);
    if let Some(artifact) = artifact
        .as_mut()
        .filter(|a| has_arms(a) && !options.no_verify)
    {
        diagnostics.extend(check_and_verify(
            files,
            artifact,
            options,
            &compilation.sources,
        ));
    }
    let failed = diagnostics.iter().any(Diagnostic::is_error);
    Built {
        artifact: artifact.filter(|_| !failed),
        diagnostics,
        compilation,
    }
}

/// The artifact of a compilation without errors, as lowered (nothing checked yet).
pub(crate) fn lowered(compilation: &Compilation) -> Option<Artifact> {
    compilation
        .cell
        .as_ref()
        .filter(|_| !compilation.has_errors())
        .map(|cell| {
            cellc_compiler::artifact::lower(cell, &compilation.graphs, &compilation.sources)
        })
}

/// Whether any end-effector is an arm (the artifact has geometry to verify).
pub fn has_arms(artifact: &Artifact) -> bool {
    artifact
        .end_effectors
        .iter()
        .any(|e| matches!(e.body, Body::Arm { .. }))
}

/// Loads the scene, checks it as a whole, then every arc.
fn check_and_verify(
    files: &dyn Files,
    artifact: &mut Artifact,
    options: &BuildOptions<'_>,
    sources: &SourceMap,
) -> Vec<Diagnostic> {
    let scene = match cellc_runtime::scene::Scene::load(artifact, files) {
        Ok(scene) => scene,
        Err(e) => {
            return vec![crate::verify_report::scene_error_at(
                &e,
                &artifact.robots,
                &artifact.spans,
            )]
        }
    };
    let verify = VerifyOptions {
        seed: options.seed,
        ..VerifyOptions::default()
    };
    let silent = |_: u64, _: u64| {};
    let progress = options.progress.unwrap_or(&silent);
    let checked = cellc_runtime::verify::check_and_verify(artifact, &scene, &verify, progress);
    checked_diagnostics(artifact, &checked, sources)
}

/// What a check of the scene and the arcs found, in words: the preflight's findings,
/// then the arcs it pruned (when the arcs were checked).
pub(crate) fn checked_diagnostics(
    artifact: &Artifact,
    checked: &Checked,
    sources: &SourceMap,
) -> Vec<Diagnostic> {
    let mut found = crate::scene_report::diagnostics(artifact, &checked.preflight, sources);
    if checked.report.is_some() {
        found.extend(crate::verify_report::pruned_warnings(artifact));
    }
    found
}
