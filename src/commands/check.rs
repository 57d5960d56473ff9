//! `cellc check FILE...`

use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

use cellc_lang::Diagnostic;

use crate::render::{self, Format, Style};
use cellc_driver::fs_files::FsFiles;

/// Checks every file; exit 0 when clean, 1 on errors (or warnings with `--deny-warnings`).
pub fn run(
    files: &[PathBuf],
    deny_warnings: bool,
    style: Style,
    options: &cellc_compiler::CompileOptions,
) -> ExitCode {
    let mut failed = false;
    let mut all: Vec<(Vec<Diagnostic>, cellc_lang::SourceMap)> = Vec::new();
    for file in files {
        let compilation = cellc_driver::compile(&FsFiles, &file.to_string_lossy(), options);
        failed |= compilation
            .diagnostics
            .iter()
            .any(|d| d.is_error() || deny_warnings);
        all.push((compilation.diagnostics, compilation.sources));
    }
    let mut stdout = std::io::stdout().lock();
    let mut stderr = std::io::stderr().lock();
    // Output errors (a closed pipe) must not panic; the exit code still tells the result.
    let _ = match style.format {
        Format::Json => {
            // One document for all files, so programs parse one value.
            let mut merged = Vec::new();
            let mut sources = cellc_lang::SourceMap::new();
            for (diagnostics, file_sources) in &all {
                let base = sources.iter().count() as u32;
                for (_, f) in file_sources.iter() {
                    sources.add(f.path.clone(), f.text.clone());
                }
                for d in diagnostics {
                    let mut d = d.clone();
                    for label in &mut d.labels {
                        label.file = cellc_lang::FileId(label.file.0 + base);
                    }
                    merged.push(d);
                }
            }
            stdout.write_all(render::json(&merged, &sources).as_bytes())
        }
        Format::Short => {
            let mut text = String::new();
            for (diagnostics, sources) in &all {
                text.push_str(&render::short(diagnostics, sources));
            }
            stdout.write_all(text.as_bytes())
        }
        Format::Human => {
            let mut text = String::new();
            let mut total = Vec::new();
            for (diagnostics, sources) in &all {
                text.push_str(&render::human(diagnostics, sources, style.color));
                total.extend(diagnostics.iter().cloned());
            }
            if !total.is_empty() {
                text.push_str(&render::summary(&total));
                text.push('\n');
            }
            stderr.write_all(text.as_bytes())
        }
    };
    if failed {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    }
}
