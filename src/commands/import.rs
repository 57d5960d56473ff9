//! `cellc import dualmanip INPUT -o OUT.cell [--format human|short|json]`

use std::io::Write;
use std::path::Path;
use std::process::ExitCode;

use crate::render::{self, Format, Style};

/// Imports a dual_manipulation database. Exit 0 when the cell was written (its warnings
/// are left to `cellc check`), 1 on errors; on errors nothing is written.
///
/// What the import says of itself ("wrote ...", "nothing written ...") goes to standard
/// output in human form, and to standard error with `--format short` or `json`, whose
/// standard output is the diagnostics' alone (the JSON report written on every path).
pub fn dualmanip(db: &Path, output: &Path, style: Style) -> ExitCode {
    let say = |text: String| {
        let _ = if style.is_human() {
            writeln!(std::io::stdout().lock(), "{text}")
        } else {
            writeln!(std::io::stderr().lock(), "{text}")
        };
    };
    let imported = match crate::import::dualmanip(db) {
        Ok(imported) => imported,
        Err(failure) => {
            render::emit(style, &failure.diagnostics, &failure.sources);
            let mut text = String::new();
            if style.is_human() {
                text.push_str(&render::summary(&failure.diagnostics));
                text.push('\n');
            }
            text.push_str(&format!("nothing written to `{}`\n", output.display()));
            let _ = std::io::stderr().lock().write_all(text.as_bytes());
            return ExitCode::from(1);
        }
    };
    if let Err(d) = crate::output::write(output, imported.text.as_bytes(), [db]) {
        render::emit(style, &[d], &cellc_lang::SourceMap::new());
        return ExitCode::from(1);
    }
    if style.format == Format::Json {
        render::emit(style, &[], &cellc_lang::SourceMap::new());
    }
    say(format!(
        "wrote `{}`; run `cellc check {}` to see its warnings",
        output.display(),
        output.display()
    ));
    ExitCode::SUCCESS
}
