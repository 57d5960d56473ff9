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
pub mod state;
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
    // Colour is decided here, once, and passed to whatever renders diagnostics.
    let color = args.color.decide();
    let style = |report: &args::ReportFlags| render::Style {
        format: report.format,
        color,
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
            style(report),
            &packages::compile_options(packages),
        ),
        args::Command::Fmt { files, check } => commands::fmt::run(files, *check, color),
        args::Command::Explain { code } => commands::explain::run(code, color),
        args::Command::Build {
            cell,
            output,
            encoding,
            report,
            explain,
            deny_warnings,
            no_verify,
            seed,
            packages,
        } => {
            let encoding = match encoding {
                args::ArtifactEncoding::Json => cellc_schema::Encoding::Json,
                args::ArtifactEncoding::Bin => cellc_schema::Encoding::Binary,
            };
            if *explain && report.format != render::Format::Human {
                return usage_error(
                    "build",
                    clap::error::ErrorKind::ArgumentConflict,
                    "`--explain` prints text on standard output, which `--format short` and \
                     `--format json` keep for diagnostics: use `cellc info` for the explanation",
                );
            }
            let options = commands::build::BuildOptions {
                encoding,
                style: style(report),
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
            color,
            &packages::compile_options(packages),
        ),
        args::Command::Run { request, fail_at } => {
            commands::run::run(&commands::plan::PlanArgs::new(request, color), *fail_at)
        }
        args::Command::Plan { request, emit } => {
            if emit.is_some() && request.format != render::Format::Human {
                return usage_error(
                    "plan",
                    clap::error::ErrorKind::ArgumentConflict,
                    "`--emit` writes its document on standard output, which `--format short` \
                     and `--format json` keep for diagnostics: leave `--format` at `human`",
                );
            }
            let mut args = commands::plan::PlanArgs::new(request, color);
            args.emit = *emit;
            commands::plan::run(&args)
        }
        args::Command::Graph {
            file,
            object,
            emit,
            packages,
        } => commands::graph::run(
            &file.to_string_lossy(),
            object,
            *emit,
            color,
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
            state,
            seed,
            output,
        } => commands::view::run(&commands::view::ViewArgs {
            load: commands::plan::LoadArgs::new(
                input,
                packages,
                *seed,
                render::Style {
                    format: render::Format::Human,
                    color,
                },
            ),
            job: commands::job::JobArgs {
                request: request.clone(),
                object: object.clone(),
                from: from.clone(),
                to: to.clone(),
                task: task.clone(),
                moves: Vec::new(),
                world: world.as_ref().map(|p| p.to_string_lossy().into_owned()),
                state: state.as_ref().map(|p| p.to_string_lossy().into_owned()),
            },
            plan_file: plan.clone(),
            output: output.clone(),
        }),
        args::Command::Serve {
            input,
            addr,
            seed,
            state,
            ephemeral,
            durability,
            journal_keep,
            journal_days,
            sim_pace,
            packages,
        } => {
            let durability = match durability {
                args::DurabilityArg::Full => cellc_store::Durability::Full,
                args::DurabilityArg::Normal => cellc_store::Durability::Normal,
            };
            let state = if *ephemeral {
                Some(commands::serve::StateAt::Memory)
            } else {
                Some(commands::serve::StateAt::File(
                    state
                        .clone()
                        .unwrap_or_else(|| crate::state::default_path(input)),
                    durability,
                ))
            };
            commands::serve::run(&commands::serve::ServeArgs {
                input: input.to_string_lossy().into_owned(),
                addr: *addr,
                seed: *seed,
                compile: packages::compile_options(packages),
                color,
                state,
                retention: cellc_store::Retention {
                    max_executions: *journal_keep,
                    max_age_ms: Some(i64::from(*journal_days) * 24 * 3600 * 1000),
                },
                pace: *sim_pace,
            })
        }
        args::Command::Import { source } => match source {
            args::ImportSource::Dualmanip { db, output, report } => {
                commands::import::dualmanip(db, output, style(report))
            }
        },
        args::Command::Export { format } => match format {
            args::ExportFormat::Pddl(pddl) => commands::export::run_pddl(pddl, color),
        },
        args::Command::Lsp { packages } => commands::lsp::run(packages),
    }
}

/// A usage error found after parsing (two flags that cannot go together whatever their
/// values), printed as clap prints its own, with the subcommand's usage line and exit
/// status 2.
fn usage_error(subcommand: &str, kind: clap::error::ErrorKind, message: &str) -> ExitCode {
    use clap::CommandFactory;
    let mut command = args::Args::command();
    command.build();
    let error = match command.find_subcommand_mut(subcommand) {
        Some(sub) => sub.error(kind, message),
        None => command.error(kind, message),
    };
    let _ = error.print();
    ExitCode::from(2)
}
