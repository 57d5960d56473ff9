//! `cellc build CELL [-o OUT] [--format json|bin] [--explain]`

use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use cellc_schema::Encoding;

use crate::fs_world::FsWorld;
use crate::render::{self, Color};

/// Compiles a cell and writes its artifact; with `--explain` also prints the workspaces
/// and who reaches them.
pub fn run(
    cell: &Path,
    output: Option<&Path>,
    encoding: Encoding,
    explain: bool,
    deny_warnings: bool,
) -> ExitCode {
    let path = cell.to_string_lossy().to_string();
    let compilation = cellc_compiler::compile(&FsWorld, &path);
    let color = if std::io::stderr().is_terminal() {
        Color::Always
    } else {
        Color::Never
    };
    if !compilation.diagnostics.is_empty() {
        eprint!(
            "{}",
            render::human(&compilation.diagnostics, &compilation.sources, color)
        );
        eprintln!("{}", render::summary(&compilation.diagnostics));
    }
    let failed = compilation
        .diagnostics
        .iter()
        .any(|d| d.is_error() || deny_warnings);
    let Some(cell) = compilation.cell.as_ref().filter(|_| !failed) else {
        eprintln!("no artifact written");
        return ExitCode::from(1);
    };
    let artifact = cellc_compiler::artifact::lower(cell, &compilation.graphs, &compilation.sources);
    let output: PathBuf = match output {
        Some(o) => o.to_path_buf(),
        None => default_output(cell_path(&path), encoding),
    };
    if let Err(e) = std::fs::write(&output, artifact.to_bytes(encoding)) {
        eprintln!("error: cannot write `{}`: {e}", output.display());
        return ExitCode::from(1);
    }
    if explain {
        print!("{}", crate::commands::info::describe(&artifact));
    }
    eprintln!("wrote {}", output.display());
    ExitCode::SUCCESS
}

fn cell_path(path: &str) -> &Path {
    Path::new(path)
}

/// `cells/fig3.cell` -> `cells/fig3.artifact.json` (or `.artifact.bin`).
fn default_output(cell: &Path, encoding: Encoding) -> PathBuf {
    let extension = match encoding {
        Encoding::Json => "artifact.json",
        Encoding::Binary => "artifact.bin",
    };
    cell.with_extension(extension)
}
