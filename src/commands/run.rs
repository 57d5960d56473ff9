//! `cellc run ...`: plans each move of a job (a request, a task, `--move`s) in the world,
//! executes it in the kinematic simulator (replanning from where things are when a step
//! fails), and brings the world up to date from what the simulator reports before the
//! next move. The final error is measured on the simulated object, whose pose comes from
//! the kinematics of its holders. A failing move is reported with its place in the job;
//! the world printed at the end is as it really is: the objects moved so far stay moved.
//! With `--state PATH` the run starts from a service's stored world and leaves the file
//! as it was: the service owns it, and a simulated run is not the cell's history.

use std::process::ExitCode;

use cellc_lang::Diagnostic;
use cellc_runtime::{Executed, Execution, ExecutionError, TaskError, TaskFailure, TaskOptions};

use super::job::{job, world_text, Job};
use super::plan::{load, Loaded, PlanArgs};
use crate::plan_report::{self, codes, describe, plan_error};
use crate::render::Format;
use cellc_driver::document::run::{Kind, Move, Run};
use cellc_driver::document::world::World as WorldDocument;

/// Runs the job `args` ask for; `fail_at` makes the motion of that step (1-based) of the
/// first plan executed fail.
pub fn run(args: &PlanArgs, fail_at: Option<usize>) -> ExitCode {
    // Step 0 does not exist whatever the cell: refused before the cell is read.
    if fail_at == Some(0) {
        crate::render::emit(
            args.load.style,
            &[fail_at_out_of_range(0, None)],
            &Default::default(),
        );
        return ExitCode::from(2);
    }
    if let Some(d) = args.refused_timing() {
        crate::render::emit(args.load.style, &[d], &Default::default());
        return ExitCode::from(1);
    }
    let loaded = match load(&args.load) {
        Ok(l) => l,
        Err(code) => return code,
    };
    let Job {
        mut world,
        moves,
        title,
    } = match job(&args.job, &args.options(), &loaded) {
        Ok(j) => j,
        Err(code) => return code,
    };
    let cell = &loaded.cell;
    let artifact = cell.artifact();
    let human = args.load.style.is_human();
    let several = moves.len() > 1 || !title.starts_with("request");
    let options = TaskOptions {
        plan: args.options(),
        clear: args.clear,
        max_replans: 5,
        fail_motion_at: fail_at.map(|s| s.saturating_sub(1)),
    };
    let list: Vec<_> = moves.iter().map(|m| (m.object, m.goal.clone())).collect();
    let cellc_runtime::TaskRun { record, failure } = cell.run_task(&mut world, &list, &options);
    // The first plan executed is known only once it is planned; a step past its end was
    // never failed, so what ran is not what was asked: nothing of it is shown.
    if let (Some(n), Some(first)) = (fail_at, record.first()) {
        if n > first.plan.steps.len() {
            let d = fail_at_out_of_range(n, Some(first.plan.steps.len()));
            crate::render::emit(args.load.style, &[d], &Default::default());
            return ExitCode::from(2);
        }
    }
    let label = |index: usize| {
        if several {
            format!("move {} of {}", index + 1, moves.len())
        } else {
            title
                .trim_start_matches("request `")
                .trim_end_matches('`')
                .to_string()
        }
    };
    let mut done: Vec<Move> = Vec::new();
    let mut shown = None;
    for executed in &record {
        let name = artifact.object_name(moves[executed.index].object);
        if human && several && shown != Some(executed.index) {
            println!(
                "{title}, move {} of {}: `{name}`",
                executed.index + 1,
                moves.len()
            );
        }
        shown = Some(executed.index);
        let label = match executed.clears {
            Some(_) => format!("clearing for {name}"),
            None => label(executed.index),
        };
        done.push(report(&loaded, executed, &label));
    }
    // A move that had no plan was never executed: its header still says which it was.
    if let Some(TaskFailure {
        index,
        error: TaskError::Plan(_),
    }) = &failure
    {
        if human && several && shown != Some(*index) {
            let name = artifact.object_name(moves[*index].object);
            println!("{title}, move {} of {}: `{name}`", index + 1, moves.len());
        }
    }
    let diagnostics: Vec<Diagnostic> = failure
        .iter()
        .map(|f| {
            let span = moves[f.index].span;
            let d = match &f.error {
                TaskError::Plan(e) => plan_error(artifact, e, span, Some(loaded.sources())),
                TaskError::Execute(e) => execution_error(artifact, e, span, &loaded),
            };
            if several {
                d.note(format!(
                    "move {} of {} of the {title} failed; the moves before it were carried out",
                    f.index + 1,
                    moves.len()
                ))
            } else {
                d
            }
        })
        .collect();
    let ok = diagnostics.is_empty();
    if args.load.style.format != Format::Json {
        // A lone request's world is the request itself; a world given or several moves
        // are worth showing as they end.
        if human && (several || args.job.world.is_some()) {
            print!("{}", world_text(cell, &world));
        }
        loaded.report(&diagnostics);
    } else {
        let document = Run::new(
            Kind::Run,
            ok,
            Vec::new(),
            done,
            Some(WorldDocument::of(cell, &world)),
            loaded.json_report(&diagnostics),
        );
        println!("{}", document.to_text());
    }
    if ok {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    }
}

/// One executed plan: printed (human and short output) and returned as its JSON record.
fn report(loaded: &Loaded, executed: &Executed, label: &str) -> Move {
    let cell = &loaded.cell;
    let artifact = cell.artifact();
    let format = loaded.style.format;
    let human = format == Format::Human;
    let plan = &executed.plan;
    let object = plan.object;
    let record = Move::of(artifact, executed, label);
    if format == Format::Short {
        print!("{}", short(loaded, executed, label, &record));
        return record;
    }
    if human {
        if executed.clears.is_some() {
            println!(
                "`{}` is in the way: moving it to a free place first",
                artifact.object_name(object)
            );
        }
        print!("{}", describe(artifact, label, plan));
        println!("simulation:");
        for line in &executed.log {
            println!("  {line}");
        }
    }
    if let (true, Ok(run)) = (human, &executed.result) {
        print!(
            "{}",
            done_text(
                loaded,
                label,
                run,
                record.position_error,
                record.rotation_error
            )
        );
    }
    record
}

/// "done: ..." and the final pose's error, after a move's simulation (and its replans).
fn done_text(
    loaded: &Loaded,
    label: &str,
    run: &Execution,
    position_error: Option<f64>,
    rotation_error: Option<f64>,
) -> String {
    use std::fmt::Write as _;
    let artifact = loaded.cell.artifact();
    let mut out = String::new();
    for (i, replan) in run.plans.iter().enumerate().skip(1) {
        let _ = writeln!(out, "replan {i}, from where the object was:");
        out.push_str(&describe(artifact, label, replan));
    }
    let _ = writeln!(out, "done: {}", where_it_ended(artifact, run));
    if let Some(pose) = run.final_pose {
        let t = pose.translation.vector;
        let _ = write!(
            out,
            "final object pose: ({:.4}, {:.4}, {:.4})",
            t.x, t.y, t.z
        );
        match position_error.zip(rotation_error) {
            Some((p, r)) => {
                let _ = writeln!(
                    out,
                    "; error {:.2} mm, {:.3} deg from the goal",
                    p * 1000.0,
                    r.to_degrees()
                );
            }
            None => out.push('\n'),
        }
    }
    out
}

/// One executed plan in `--format short`: the plan's lines, the simulator's log, each
/// replan's lines and the outcome, every line naming the plan.
fn short(loaded: &Loaded, executed: &Executed, label: &str, record: &Move) -> String {
    use std::fmt::Write as _;
    let artifact = loaded.cell.artifact();
    let mut out = plan_report::short(artifact, label, &executed.plan);
    for line in &executed.log {
        let _ = writeln!(out, "plan `{label}` simulation: {line}");
    }
    let Ok(run) = &executed.result else {
        return out;
    };
    for (i, replan) in run.plans.iter().enumerate().skip(1) {
        out.push_str(&plan_report::short(
            artifact,
            &format!("{label}, replan {i}"),
            replan,
        ));
    }
    let _ = write!(
        out,
        "plan `{label}` done: {}",
        where_it_ended(artifact, run)
    );
    if let Some((p, r)) = record.position_error.zip(record.rotation_error) {
        let _ = write!(
            out,
            "; error {:.2} mm, {:.3} deg from the goal",
            p * 1000.0,
            r.to_degrees()
        );
    }
    out.push('\n');
    out
}

/// `--fail-at N` names no step of the first plan executed (`steps`, when it is known).
fn fail_at_out_of_range(n: usize, steps: Option<usize>) -> Diagnostic {
    let message = match steps {
        Some(steps) => format!(
            "`--fail-at {n}` is past the end of the first plan executed, which has {steps} steps"
        ),
        None => "`--fail-at 0` names no step: steps are counted from 1".to_string(),
    };
    let help = match steps {
        Some(0) => "this plan has no steps to fail: leave out `--fail-at`".to_string(),
        Some(steps) => format!("give a step from 1 to {steps}, or leave out `--fail-at`"),
        None => "give a step from 1 (the first) to the plan's number of steps".to_string(),
    };
    Diagnostic::error(crate::output::codes::FAIL_AT_OUT_OF_RANGE, message).help(help)
}

/// An execution failure as a diagnostic.
fn execution_error(
    artifact: &cellc_schema::Artifact,
    e: &ExecutionError,
    span: Option<u32>,
    loaded: &Loaded,
) -> Diagnostic {
    match e {
        ExecutionError::Replan(e) => plan_error(artifact, e, span, Some(loaded.sources())),
        ExecutionError::FailedAtStart { error } => Diagnostic::error(
            codes::EXECUTION_FAILED,
            format!("{error}, before the object left its start"),
        )
        .help("nothing moved, so there is nothing to recover from: fix the cause and run again"),
        ExecutionError::TooManyFailures { replans, last } => Diagnostic::error(
            codes::EXECUTION_FAILED,
            format!("steps kept failing ({last}); gave up after {replans} replans"),
        )
        .help("the object is where the last step left it; see the simulation log above"),
        e => Diagnostic::error(codes::EXECUTION_FAILED, format!("execution failed: {e}"))
            .help("see the simulation log above; the world is where it stopped"),
    }
}

/// Where an execution left its object, as both reports say it: "`OBJECT` held by `HOLDER`
/// with `GRASP` in `WORKSPACE`".
fn where_it_ended(artifact: &cellc_schema::Artifact, run: &Execution) -> String {
    let object = run.plans[0].object;
    let s = run.final_state;
    format!(
        "`{}` held by `{}` with `{}` in `{}`",
        artifact.object_name(object),
        artifact.end_effector_name(s.end_effector),
        artifact.grasp_name(object, s.grasp),
        artifact.workspace_name(s.workspace)
    )
}
