//! `cellc explain CODE`

use std::process::ExitCode;

/// Prints the documentation page of a diagnostic code.
pub fn run(code: &str) -> ExitCode {
    let wanted = code.trim().to_ascii_uppercase();
    match crate::docs::page(&wanted) {
        Some(page) => {
            print!("{page}");
            ExitCode::SUCCESS
        }
        None => {
            eprintln!("error: `{code}` is not a cellc diagnostic code");
            eprintln!("help: codes look like `E0101` or `W0001`; see docs/diagnostics/");
            ExitCode::from(2)
        }
    }
}
