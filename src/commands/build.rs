//! `cellc build INPUT [-o OUT] [--encoding json|bin] [--format human|short|json] [--explain]
//! [--no-verify] [--seed N]``

use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use cellc_schema::Encoding;

use crate::render::{self, Format, Style};
use cellc_driver::fs_files::FsFiles;
use cellc_lang::Diagnostic;

/// What `cellc build` was asked to do.
#[derive(Clone, Debug)]
pub struct BuildOptions {
    /// Artifact encoding.
    pub encoding: Encoding,
    /// How diagnostics are reported.
    pub style: Style,
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
    let style = options.style;
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
    let built = cellc_driver::build(
        &FsFiles,
        &path,
        &cellc_driver::BuildOptions {
            compile: options.compile.clone(),
            no_verify: !options.verify,
            seed: options.seed,
            progress: Some(&progress),
        },
    );
    if let Some(bar) = bar {
        bar.finish_and_clear();
    }
    let diagnostics = &built.diagnostics;
    let sources = &built.compilation.sources;
    // Human and short diagnostics are written as soon as they are known; the JSON report
    // once, as the build ends, with all of them (a failure to write the artifact too), so
    // a program reads exactly one document on every path.
    let json = style.format == Format::Json;
    if !json {
        render::emit(style, diagnostics, sources);
    }
    if style.is_human() && !diagnostics.is_empty() {
        eprintln!("{}", render::summary(diagnostics));
    }
    let report_json = |more: Option<Diagnostic>| {
        if json {
            let all: Vec<Diagnostic> = diagnostics.iter().cloned().chain(more).collect();
            render::emit(style, &all, sources);
        }
    };
    let failed = diagnostics
        .iter()
        .any(|d| d.is_error() || options.deny_warnings);
    let Some(artifact) = built.artifact.filter(|_| !failed) else {
        report_json(None);
        eprintln!("no artifact written");
        return ExitCode::from(1);
    };
    let output: PathBuf = match output {
        Some(o) => o.to_path_buf(),
        None => default_output(Path::new(&path), options.encoding),
    };
    // Every file the build read is an input: the cell, its includes, robot models, meshes.
    let mut inputs: Vec<PathBuf> = built
        .compilation
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
    cellc_driver::load::paths::relative_to_output(&mut artifact, &output);
    let bytes = artifact.to_bytes(options.encoding);
    if let Err(d) = crate::output::write(&output, &bytes, inputs.iter().map(PathBuf::as_path)) {
        if json {
            report_json(Some(d));
        } else {
            render::emit(style, &[d], sources);
        }
        return ExitCode::from(1);
    }
    report_json(None);
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

/// `cells/fig3.cell` -> `cells/fig3.artifact.json` (or `.artifact.bin`).
fn default_output(cell: &Path, encoding: Encoding) -> PathBuf {
    let extension = match encoding {
        Encoding::Json => "artifact.json",
        Encoding::Binary => "artifact.bin",
    };
    cell.with_extension(extension)
}
