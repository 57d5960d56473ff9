//! `cellc lsp`: the language server (`crate::lsp`), until the client says `exit`.

use std::process::ExitCode;

use crate::args::PackageArgs;

/// Serves the protocol on standard input and output; 0 after `shutdown` then `exit`.
pub fn run(packages: &PackageArgs) -> ExitCode {
    crate::lsp::run(crate::packages::compile_options(packages))
}
