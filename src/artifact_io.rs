//! The artifact of a command's input, a `.cell` file compiled now or an artifact file
//! read ([`cellc_driver::load::artifact`], which has the reading and its codes), with
//! failures reported as the command's output asks ([`Report`]).

use cellc_lang::{Diagnostic, SourceMap};
use cellc_schema::Artifact;

use crate::render::{self, Color};
use cellc_driver::fs_files::FsFiles;

/// The artifact of a `.cell` file (compiled now) or of an artifact file. On failure the
/// diagnostics are already printed to standard error.
pub fn cell_or_artifact(path: &str, options: &cellc_compiler::CompileOptions) -> Option<Artifact> {
    cell_or_artifact_reporting(path, Report::Human, options)
}

/// How [`cell_or_artifact_reporting`] reports failures.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Report {
    /// Human text on standard error.
    Human,
    /// The JSON diagnostics report on standard output (for commands whose output is JSON,
    /// so that it stays JSON on every path).
    Json,
}

impl Report {
    /// Writes `diagnostics` where this report goes (plain text, no colour).
    pub fn emit(self, diagnostics: &[Diagnostic], sources: &SourceMap) {
        match self {
            Report::Human => eprint!("{}", render::human(diagnostics, sources, Color::Never)),
            Report::Json => print!("{}", render::json(diagnostics, sources)),
        }
    }
}

/// [`cell_or_artifact`], reporting failures as `report` says.
pub fn cell_or_artifact_reporting(
    path: &str,
    report: Report,
    options: &cellc_compiler::CompileOptions,
) -> Option<Artifact> {
    if path.ends_with(".cell") {
        return compiled_cell(path, report, options).map(|(artifact, _)| artifact);
    }
    match cellc_driver::load::artifact::read(path) {
        Ok(artifact) => Some(artifact),
        Err(d) => {
            report.emit(&[d], &SourceMap::new());
            None
        }
    }
}

/// A `.cell` file compiled now, with its compilation (for what only a compilation knows,
/// such as how long `reach auto` took), or `None` after reporting its errors as `report`
/// says (human text ends with a summary line).
pub fn compiled_cell(
    path: &str,
    report: Report,
    options: &cellc_compiler::CompileOptions,
) -> Option<(Artifact, cellc_compiler::Compilation)> {
    let options = cellc_driver::BuildOptions {
        compile: options.clone(),
        ..cellc_driver::BuildOptions::unverified()
    };
    let built = cellc_driver::build(&FsFiles, path, &options);
    let Some(artifact) = built.artifact else {
        let errors: Vec<Diagnostic> = built
            .diagnostics
            .into_iter()
            .filter(Diagnostic::is_error)
            .collect();
        report.emit(&errors, &built.compilation.sources);
        if report == Report::Human {
            eprintln!("{}", render::summary(&errors));
        }
        return None;
    };
    Some((artifact, built.compilation))
}
