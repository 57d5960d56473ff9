//! `cellc explain CODE`

use std::process::ExitCode;

/// Prints the documentation page of a diagnostic code, found in the registry
/// (`cellc_lang::codes`, which embeds every page when it is built).
pub fn run(code: &str, color: crate::render::Color) -> ExitCode {
    let wanted = code.trim().to_ascii_uppercase();
    match cellc_lang::Code::find(&wanted) {
        Some(found) => {
            print!("{}", found.page());
            ExitCode::SUCCESS
        }
        None => {
            let d = cellc_lang::Diagnostic::error(
                crate::output::codes::UNKNOWN_CODE,
                format!("`{code}` is not a cellc diagnostic code"),
            )
            .help("codes look like `E0101` or `W0001`; docs/diagnostics/ has a page for each");
            let style = crate::render::Style {
                format: crate::render::Format::Human,
                color,
            };
            crate::render::emit(style, &[d], &cellc_lang::SourceMap::new());
            ExitCode::from(2)
        }
    }
}
