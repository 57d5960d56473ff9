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
    if let Err(d) = crate::output::write(output, imported.text.as_bytes(), [db]) {
        eprint!(
            "{}",
            render::human(&[d], &cellc_lang::SourceMap::new(), color)
        );
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

