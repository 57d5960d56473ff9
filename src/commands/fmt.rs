//! `cellc fmt [--check] INPUT...`

use std::path::PathBuf;
use std::process::ExitCode;

use cellc_lang::{FileId, SourceMap};

use cellc_compiler::load::read_source;
use cellc_schema::files::MAX_SOURCE_BYTES;

use crate::render::{self, Color};
use cellc_driver::fs_files::FsFiles;

/// Formats files in place, or with `--check` reports those that are not formatted.
/// A file with syntax errors is never rewritten.
pub fn run(files: &[PathBuf], check: bool, color: Color) -> ExitCode {
    let mut failed = false;
    for path in files {
        let display = path.to_string_lossy().to_string();
        // Read as `cellc check` reads: within the size limit, and a file that is not a cell
        // is described, never shown.
        let text = match read_source(&FsFiles, &display, MAX_SOURCE_BYTES, None) {
            Ok(text) => text,
            Err(d) => {
                eprint!("{}", render::human(&[d], &SourceMap::new(), color));
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
                eprint!("{}", render::human(&parsed.diagnostics, &sources, color));
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
        } else if let Err(d) = crate::output::rewrite(path, formatted.as_bytes()) {
            eprint!("{}", render::human(&[d], &SourceMap::new(), color));
            failed = true;
        }
    }
    if failed {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    }
}
