//! The artifact of a command's input, a `.cell` file compiled now or an artifact file
//! read ([`cellc_driver::load::artifact`], which has the reading and its codes), with
//! failures reported as the command's output asks ([`Style`]).

use cellc_lang::{Diagnostic, SourceMap};
use cellc_schema::Artifact;

use crate::render::{self, Style};
use cellc_driver::fs_files::FsFiles;

/// The artifact of a `.cell` file (compiled now) or of an artifact file, or `None` after
/// reporting why not as `report` says ([`render::emit`]: human text on standard error,
/// short lines or the JSON report on standard output, so JSON output stays JSON).
pub fn cell_or_artifact(
    path: &str,
    report: Style,
    options: &cellc_compiler::CompileOptions,
) -> Option<Artifact> {
    if path.ends_with(".cell") {
        return compiled_cell(path, report, options).map(|(artifact, _)| artifact);
    }
    match cellc_driver::load::artifact::read(path) {
        Ok(artifact) => Some(artifact),
        Err(d) => {
            render::emit(report, &[d], &SourceMap::new());
            None
        }
    }
}

/// A `.cell` file compiled now, with its compilation (for what only a compilation knows,
/// such as how long `reach auto` took), or `None` after reporting its errors as `report`
/// says (human text ends with a summary line).
pub fn compiled_cell(
    path: &str,
    report: Style,
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
        render::emit(report, &errors, &built.compilation.sources);
        if report.is_human() {
            eprintln!("{}", render::summary(&errors));
        }
        return None;
    };
    Some((artifact, built.compilation))
}
