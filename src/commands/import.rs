//! `cellc import dualmanip DB -o OUT.cell`

use std::io::{IsTerminal, Write};
use std::path::Path;
use std::process::ExitCode;

use crate::args::ImportSource;
use crate::render::{self, Color};

/// Runs `cellc import SOURCE ...`.
pub fn run(source: &ImportSource) -> ExitCode {
    match source {
        ImportSource::Dualmanip { db, output } => dualmanip(db, output),
    }
}

/// Imports a dual_manipulation database. Exit 0 when the cell was written (its warnings
/// are left to `cellc check`), 1 on errors; on errors nothing is written.
pub fn dualmanip(db: &Path, output: &Path) -> ExitCode {
    let color = if std::io::stderr().is_terminal() {
        Color::Always
    } else {
        Color::Never
    };
    let imported = match crate::import::dualmanip(db) {
        Ok(imported) => imported,
        Err(failure) => {
            let mut text = render::human(&failure.diagnostics, &failure.sources, color);
            text.push_str(&render::summary(&failure.diagnostics));
            text.push('\n');
            text.push_str(&format!("nothing written to `{}`\n", output.display()));
            let _ = std::io::stderr().lock().write_all(text.as_bytes());
            return ExitCode::from(1);
        }
    };
    if let Err(e) = write_whole(output, &imported.text) {
        eprintln!("error: cannot write `{}`: {e}", output.display());
        return ExitCode::from(1);
    }
    let _ = writeln!(
        std::io::stdout().lock(),
        "wrote `{}`; run `cellc check {}` to see its warnings",
        output.display(),
        output.display()
    );
    ExitCode::SUCCESS
}

/// Writes `text` to a temporary file beside `path` and renames it over `path`, so that
/// `path` is never left half written.
fn write_whole(path: &Path, text: &str) -> std::io::Result<()> {
    let file_name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let temp = path.with_file_name(format!(".{file_name}.cellc-import-{}", std::process::id()));
    let result = std::fs::write(&temp, text).and_then(|()| std::fs::rename(&temp, path));
    if result.is_err() {
        let _ = std::fs::remove_file(&temp);
    }
    result
}
