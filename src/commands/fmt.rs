//! `cellc fmt [--check] FILE...`

use std::path::PathBuf;
use std::process::ExitCode;

use cellc_lang::{FileId, SourceMap};

use crate::render::{self, Color};

/// Formats files in place, or with `--check` reports those that are not formatted.
/// A file with syntax errors is never rewritten.
pub fn run(files: &[PathBuf], check: bool) -> ExitCode {
    let mut failed = false;
    for path in files {
        let display = path.to_string_lossy().to_string();
        let text = match std::fs::read_to_string(path) {
            Ok(text) => text,
            Err(e) => {
                let d = cellc_lang::Diagnostic::error(
                    cellc_compiler::diagnostics::codes::FILE_UNREADABLE,
                    format!("cannot read `{display}`: {e}"),
                )
                .help("check the path and that the file is readable");
                eprint!("{}", render::human(&[d], &SourceMap::new(), Color::Never));
                failed = true;
                continue;
            }
        };
        let parsed = cellc_lang::parse(FileId(0), &text);
        let file = match (parsed.file, parsed.diagnostics.is_empty()) {
            (Some(file), true) => file,
            (_, _) => {
                let mut sources = SourceMap::new();
                sources.add(display.clone(), text.clone());
                eprint!(
                    "{}",
                    render::human(&parsed.diagnostics, &sources, Color::Never)
                );
                eprintln!("not formatted: `{display}` has syntax errors");
                failed = true;
                continue;
            }
        };
        let formatted = cellc_lang::format(&file, &text);
        if formatted == text {
            continue;
        }
        if check {
            println!("would reformat {display}");
            failed = true;
        } else if let Err(d) = crate::output::write(path, formatted.as_bytes(), []) {
            eprint!("{}", render::human(&[d], &SourceMap::new(), Color::Never));
            failed = true;
        }
    }
    if failed {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    }
}
