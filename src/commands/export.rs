//! `cellc export pddl INPUT [--object O | --request NAME] [--from P --to P]
//! -o DIR`

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use cellc_lang::Diagnostic;
use cellc_runtime::plan::{GoalByName, PlanError, PlanOptions, Request};
use cellc_runtime::ObjectId;

use super::plan::{LoadArgs, Loaded};
use crate::args::PddlArgs;
use crate::export::pddl::{self, Problem, ProblemError};
use crate::plan_report;

/// One object to export and the problems of its file set.
struct Selected {
    object: ObjectId,
    problems: Vec<Problem>,
}

/// Loads the cell as `cellc plan` does, locates the requests asked for, and writes a
/// domain per object and a problem per request.
pub fn run_pddl(args: &PddlArgs, color: crate::render::Color) -> ExitCode {
    let style = crate::render::Style {
        format: crate::render::Format::Human,
        color,
    };
    let load_args = LoadArgs::new(&args.input, &args.packages, args.seed, style);
    let loaded = match super::plan::load(&load_args) {
        Ok(loaded) => loaded,
        Err(code) => return code,
    };
    let options = PlanOptions {
        seed: args.seed,
        motions: false,
        ..PlanOptions::default()
    };
    let selected = match select(args, &loaded, &options) {
        Ok(selected) => selected,
        Err(code) => return code,
    };
    let artifact = loaded.cell.artifact();
    let mut exports = Vec::new();
    for s in &selected {
        match pddl::export(artifact, s.object, &s.problems) {
            Ok(export) => exports.push(export),
            Err(too_large) => {
                loaded.report(&[too_large.diagnostic()]);
                return ExitCode::from(1);
            }
        }
    }
    let mut inputs: Vec<PathBuf> = loaded
        .cell
        .artifact()
        .sources
        .iter()
        .map(|s| PathBuf::from(&s.path))
        .collect();
    inputs.push(args.input.clone());
    for (export, s) in exports.iter().zip(&selected) {
        if let Err(d) = write(&args.output, export, &inputs) {
            loaded.report(&[d]);
            return ExitCode::from(1);
        }
        summarise(&args.output, export, artifact, s);
    }
    ExitCode::SUCCESS
}

/// The objects and problems the flags ask for: a named request, a request given with
/// --object, --from and --to, an object's named requests, or every object's.
fn select(
    args: &PddlArgs,
    loaded: &Loaded,
    options: &PlanOptions,
) -> Result<Vec<Selected>, ExitCode> {
    let cell = &loaded.cell;
    let artifact = cell.artifact();
    let object_named = |name: &str| {
        cell.object(name).map_err(|e| {
            let d = plan_report::plan_error(artifact, &PlanError::Locate(e), None, None);
            loaded.report(&[d]);
            ExitCode::from(1)
        })
    };
    let objects: Vec<ObjectId> = match (&args.request, &args.object, &args.from, &args.to) {
        (Some(name), ..) => {
            let Some(index) = artifact.requests.iter().position(|r| &r.name == name) else {
                loaded.report(&[plan_report::no_request(artifact, Some(name))]);
                return Err(ExitCode::from(1));
            };
            let object = artifact.requests[index].object;
            let problem = named_problem(loaded, index, options).map_err(|d| {
                loaded.report(&[d]);
                ExitCode::from(1)
            })?;
            return Ok(vec![Selected {
                object,
                problems: vec![problem],
            }]);
        }
        (None, Some(name), Some(from), Some(to)) => {
            let object = object_named(name)?;
            let request = given_request(loaded, name, from, to, options)?;
            let title = "the request of the command line".to_string();
            let problem = Problem::of_request(cell, &request, "command_line".into(), title)
                .map_err(|e| {
                    loaded.report(&[problem_diagnostic(loaded, &e, None)]);
                    ExitCode::from(1)
                })?;
            return Ok(vec![Selected {
                object,
                problems: vec![problem],
            }]);
        }
        (None, Some(name), None, None) => vec![object_named(name)?],
        (None, None, None, None) => (0..artifact.objects.len() as u32).map(ObjectId).collect(),
        // The argument parser requires --from and --to together, and with --object.
        _ => return Err(ExitCode::from(2)),
    };
    // Every request's problem is located before anything is written, and every failure
    // is reported at once.
    let mut failures = Vec::new();
    let mut selected = Vec::new();
    for object in objects {
        let mut problems = Vec::new();
        for (index, _) in pddl::problem_ids(artifact, object) {
            match named_problem(loaded, index, options) {
                Ok(p) => problems.push(p),
                Err(d) => failures.push(d),
            }
        }
        selected.push(Selected { object, problems });
    }
    if !failures.is_empty() {
        loaded.report(&failures);
        return Err(ExitCode::from(1));
    }
    Ok(selected)
}

/// The problem of the cell's request number `index`.
fn named_problem(
    loaded: &Loaded,
    index: usize,
    options: &PlanOptions,
) -> Result<Problem, Diagnostic> {
    let artifact = loaded.cell.artifact();
    let named = &artifact.requests[index];
    let id = pddl::problem_ids(artifact, named.object)
        .into_iter()
        .find(|(i, _)| *i == index)
        .map(|(_, id)| id)
        .unwrap_or_else(|| "request".to_string());
    let request = cellc_runtime::plan::named_request(named, options.clone());
    let title = format!("request `{}`", named.name);
    Problem::of_request(&loaded.cell, &request, id, title)
        .map_err(|e| problem_diagnostic(loaded, &e, Some(named.span)))
}

/// The request of --object, --from and --to.
fn given_request(
    loaded: &Loaded,
    object: &str,
    from: &str,
    to: &str,
    options: &PlanOptions,
) -> Result<Request, ExitCode> {
    let parsed = super::plan::placement_from_text(from, "from")
        .and_then(|f| super::plan::placement_from_text(to, "to").map(|t| (f, t)));
    let (from, to) = match parsed {
        Ok(placements) => placements,
        Err(failure) => {
            let (d, sources) = *failure;
            crate::render::emit(loaded.style, &[d], &sources);
            return Err(ExitCode::from(2));
        }
    };
    loaded
        .cell
        .request(object, &from, &GoalByName::Placement(to), options.clone())
        .map_err(|e| {
            let artifact = loaded.cell.artifact();
            let d = plan_report::plan_error(artifact, &PlanError::Locate(e), None, None);
            loaded.report(&[d]);
            ExitCode::from(1)
        })
}

/// A request that gives no problem, in the words `cellc plan` uses.
fn problem_diagnostic(loaded: &Loaded, error: &ProblemError, span: Option<u32>) -> Diagnostic {
    let artifact = loaded.cell.artifact();
    match error {
        ProblemError::Plan(e) => plan_report::plan_error(artifact, e, span, Some(loaded.sources())),
        ProblemError::StartNotInGraph { object, state } => Diagnostic::error(
            cellc_driver::runtime_codes::LOCATE,
            format!(
                "the start of `{}` (`{}` holding it with `{}` in `{}`) is no state of its graph",
                artifact.object_name(*object),
                artifact.end_effector_name(state.end_effector),
                artifact.grasp_name(*object, state.grasp),
                artifact.workspace_name(state.workspace)
            ),
        )
        .help("rebuild the artifact with `cellc build`"),
    }
}

/// Writes one object's files into `DIR/FOLDER/`, making the folders when missing.
fn write(dir: &Path, export: &pddl::Export, inputs: &[PathBuf]) -> Result<(), Diagnostic> {
    let folder = dir.join(&export.folder);
    std::fs::create_dir_all(&folder).map_err(|e| crate::output::unwritable(&folder, &e))?;
    for file in &export.files {
        crate::output::write(
            &folder.join(&file.name),
            file.text.as_bytes(),
            inputs.iter().map(PathBuf::as_path),
        )?;
    }
    Ok(())
}

/// One line per file written, on standard output.
fn summarise(dir: &Path, export: &pddl::Export, artifact: &cellc_schema::Artifact, s: &Selected) {
    let folder = dir.join(&export.folder);
    let shown =
        |name: &str| crate::render::escape(&folder.join(name).to_string_lossy()).into_owned();
    let graph = artifact.objects.get(s.object.index()).map(|o| &o.graph);
    println!(
        "wrote {}: {} states, {} arc actions",
        shown("domain.pddl"),
        graph.map_or(0, |g| g.nodes.len()),
        graph.map_or(0, |g| g.arcs.len())
    );
    for (file, problem) in export.files.iter().skip(1).zip(&s.problems) {
        println!("wrote {}: {}", shown(&file.name), problem.title);
    }
    if s.problems.is_empty() {
        println!(
            "the cell declares no request of `{}`: no problem written (give --object, --from \
             and --to for one)",
            crate::render::escape(artifact.object_name(s.object))
        );
    }
}
