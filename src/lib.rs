//! The `cellc` command line: a thin layer over the compiler that reads files, renders
//! diagnostics and sets exit codes. Its library target exists so that the end-to-end and
//! UI tests in `tests/` render diagnostics exactly as the binary does.

pub mod args;
pub mod artifact_io;
pub mod commands;
pub mod export;
pub mod fuzzing;
pub mod graph_svg;
pub mod grouping;
pub mod import;
pub mod lsp;
pub mod output;
pub mod packages;
pub mod plan_report;
pub mod render;
pub mod snippet;
pub mod world_report;

use std::process::ExitCode;

use clap::Parser;

/// Parses the command line and runs the subcommand.
pub fn dispatch() -> ExitCode {
    let args = match args::Args::try_parse() {
        Ok(args) => args,
        Err(e) => {
            let _ = e.print();
            return match e.kind() {
                clap::error::ErrorKind::DisplayHelp | clap::error::ErrorKind::DisplayVersion => {
                    ExitCode::SUCCESS
                }
                _ => ExitCode::from(2),
            };
        }
    };
    match &args.command {
        args::Command::Check {
            files,
            deny_warnings,
            report,
            packages,
        } => commands::check::run(
            files,
            *deny_warnings,
            report,
            &packages::compile_options(packages),
        ),
        args::Command::Fmt { files, check } => commands::fmt::run(files, *check),
        args::Command::Explain { code } => commands::explain::run(code),
        args::Command::Build {
            cell,
            output,
            format,
            explain,
            deny_warnings,
            no_verify,
            seed,
            packages,
        } => {
            let encoding = match format {
                args::ArtifactFormat::Json => cellc_schema::Encoding::Json,
                args::ArtifactFormat::Bin => cellc_schema::Encoding::Binary,
            };
            let options = commands::build::BuildOptions {
                encoding,
                explain: *explain,
                deny_warnings: *deny_warnings,
                verify: !*no_verify,
                seed: *seed,
                compile: packages::compile_options(packages),
            };
            commands::build::run(cell, output.as_deref(), &options)
        }
        args::Command::Info { file, packages } => commands::info::run(
            &file.to_string_lossy(),
            &packages::compile_options(packages),
        ),
        args::Command::Run { request, fail_at } => {
            commands::run::run(&commands::plan::PlanArgs::new(request), *fail_at)
        }
        args::Command::Plan { request } => {
            commands::plan::run(&commands::plan::PlanArgs::new(request))
        }
        args::Command::Graph {
            file,
            object,
            format,
            packages,
        } => commands::graph::run(
            &file.to_string_lossy(),
            object,
            *format,
            &packages::compile_options(packages),
        ),
        args::Command::View {
            input,
            packages,
            request,
            object,
            from,
            to,
            task,
            plan,
            world,
            seed,
            output,
        } => commands::view::run(&commands::view::ViewArgs {
            plan: commands::plan::PlanArgs {
                input: input.to_string_lossy().into_owned(),
                request: request.clone(),
                object: object.clone(),
                from: from.clone(),
                to: to.clone(),
                format: args::PlanFormat::Human,
                seed: *seed,
                motions: true,
                weights: None,
                time_budget: None,
                compile: packages::compile_options(packages),
                task: task.clone(),
                moves: Vec::new(),
                world: world.as_ref().map(|p| p.to_string_lossy().into_owned()),
                clear: false,
            },
            plan_file: plan.clone(),
            output: output.clone(),
        }),
        args::Command::Serve {
            input,
            addr,
            seed,
            packages,
        } => commands::serve::run(&commands::serve::ServeArgs {
            input: input.to_string_lossy().into_owned(),
            addr: *addr,
            seed: *seed,
            compile: packages::compile_options(packages),
        }),
        args::Command::Import { source } => commands::import::run(source),
        args::Command::Export { format } => match format {
            args::ExportFormat::Pddl(pddl) => commands::export::run_pddl(pddl),
        },
        args::Command::Lsp { packages } => commands::lsp::run(packages),
    }
}
