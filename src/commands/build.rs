//! `cellc build CELL [-o OUT] [--format json|bin] [--explain] [--no-verify] [--seed N]`

use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use cellc_lang::Diagnostic;
use cellc_schema::{Artifact, Body, Encoding};

use crate::fs_files::FsFiles;
use crate::render::{self, Color};

/// What `cellc build` was asked to do.
#[derive(Clone, Debug)]
pub struct BuildOptions {
    /// Artifact encoding.
    pub encoding: Encoding,
    /// Print the workspaces and who reaches them.
    pub explain: bool,
    /// Warnings fail the build.
    pub deny_warnings: bool,
    /// Check every arc kinematically (when the cell has arms).
    pub verify: bool,
    /// Seed of the randomized solvers.
    pub seed: u64,
    /// What the compilation is told (the package path).
    pub compile: cellc_compiler::CompileOptions,
}

/// Compiles a cell, verifies its arcs when it has arms, and writes its artifact.
pub fn run(cell: &Path, output: Option<&Path>, options: &BuildOptions) -> ExitCode {
    let path = cell.to_string_lossy().to_string();
    let compilation = crate::reach::compile(&FsFiles, &path, &options.compile);
    let color = if std::io::stderr().is_terminal() {
        Color::Always
    } else {
        Color::Never
    };
    let mut diagnostics = compilation.diagnostics.clone();
    let mut artifact = match compilation
        .cell
        .as_ref()
        .filter(|_| !compilation.has_errors())
    {
        Some(resolved) => Some(cellc_compiler::artifact::lower(
            resolved,
            &compilation.graphs,
            &compilation.sources,
        )),
        None => None,
    };
    if let Some(artifact) = artifact.as_mut().filter(|a| options.verify && has_arms(a)) {
        diagnostics.extend(verify(artifact, options.seed, &compilation.sources));
    }
    if !diagnostics.is_empty() {
        eprint!(
            "{}",
            render::human(&diagnostics, &compilation.sources, color)
        );
        eprintln!("{}", render::summary(&diagnostics));
    }
    let failed = diagnostics
        .iter()
        .any(|d| d.is_error() || options.deny_warnings);
    let Some(artifact) = artifact.filter(|_| !failed) else {
        eprintln!("no artifact written");
        return ExitCode::from(1);
    };
    let output: PathBuf = match output {
        Some(o) => o.to_path_buf(),
        None => default_output(Path::new(&path), options.encoding),
    };
    // Every file the build read is an input: the cell, its includes, robot models, meshes.
    let mut inputs: Vec<PathBuf> = compilation
        .sources
        .iter()
        .map(|(_, f)| PathBuf::from(&f.path))
        .collect();
    for r in &artifact.robots {
        inputs.push(PathBuf::from(&r.urdf_path));
        inputs.extend(r.srdf.iter().map(|s| PathBuf::from(&s.path)));
        inputs.extend(r.meshes.iter().map(|m| PathBuf::from(&m.path)));
    }
    let solids = artifact
        .holder_kinds
        .iter()
        .flat_map(|k| k.solids.iter().map(|s| &s.shape));
    let shapes = artifact.objects.iter().filter_map(|o| o.shape.as_ref());
    inputs.extend(solids.chain(shapes).filter_map(|shape| match shape {
        cellc_schema::Shape::Mesh { path } => Some(PathBuf::from(path)),
        _ => None,
    }));
    inputs.push(cell.to_path_buf());
    let mut artifact = artifact;
    crate::artifact_io::paths_relative_to_output(&mut artifact, &output);
    let bytes = artifact.to_bytes(options.encoding);
    if let Err(d) = crate::output::write(&output, &bytes, inputs.iter().map(PathBuf::as_path)) {
        eprint!("{}", render::human(&[d], &compilation.sources, color));
        return ExitCode::from(1);
    }
    if options.explain {
        print!("{}", crate::commands::info::describe(&artifact));
    }
    if let Some(v) = &artifact.verification {
        eprintln!(
            "verified {} arcs (seed {}): {} pruned",
            v.n_checked, v.seed, v.n_pruned
        );
    }
    eprintln!("wrote {}", output.display());
    ExitCode::SUCCESS
}

/// Whether any end-effector is an arm (the artifact has geometry to verify).
pub fn has_arms(artifact: &Artifact) -> bool {
    artifact
        .end_effectors
        .iter()
        .any(|e| matches!(e.body, Body::Arm { .. }))
}

/// Loads the scene, checks it as a whole (homes, permanent contacts, grasps), then every
/// arc; pruned arcs come back as warnings. A scene wrong whatever the arc (a home that
/// collides, a link touching a fixed body in every configuration) is reported and no arc
/// is checked: each would be pruned for it.
fn verify(artifact: &mut Artifact, seed: u64, sources: &cellc_lang::SourceMap) -> Vec<Diagnostic> {
    let scene = match cellc_runtime::scene::Scene::load(artifact, &FsFiles) {
        Ok(scene) => scene,
        Err(e) => {
            return vec![crate::verify_report::scene_error_at(
                &e,
                &artifact.robots,
                &artifact.spans,
            )]
        }
    };
    let preflight = cellc_runtime::verify::preflight::preflight(artifact, &scene);
    let mut found = crate::scene_report::diagnostics(artifact, &preflight, sources);
    if preflight.blocks_verification() {
        return found;
    }
    let options = cellc_runtime::verify::VerifyOptions {
        seed,
        ..Default::default()
    };
    let bar = std::io::stderr().is_terminal().then(|| {
        let bar = indicatif::ProgressBar::new(0);
        bar.set_style(
            indicatif::ProgressStyle::with_template(
                "verifying arcs {bar:30} {pos}/{len} checks ({eta} left)",
            )
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        bar
    });
    let progress = |done: u64, total: u64| {
        if let Some(bar) = &bar {
            bar.set_length(total);
            bar.set_position(done);
        }
    };
    cellc_runtime::verify::verify(artifact, &scene, &options, &progress);
    if let Some(bar) = bar {
        bar.finish_and_clear();
    }
    found.extend(crate::verify_report::pruned_warnings(artifact));
    found
}

/// `cells/fig3.cell` -> `cells/fig3.artifact.json` (or `.artifact.bin`).
fn default_output(cell: &Path, encoding: Encoding) -> PathBuf {
    let extension = match encoding {
        Encoding::Json => "artifact.json",
        Encoding::Binary => "artifact.bin",
    };
    cell.with_extension(extension)
}
