//! One module per subcommand, each with a `run` returning the exit code.

pub mod build;
pub mod check;
pub mod explain;
pub mod export;
pub mod fmt;
pub mod graph;
pub mod import;
pub mod info;
pub mod job;
pub mod lsp;
pub mod plan;
pub mod run;
pub mod serve;
pub mod view;
