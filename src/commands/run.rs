//! `cellc run ...`: plans each move of a job (a request, a task, `--move`s) in the world,
//! executes it in the kinematic simulator (replanning from where things are when a step
//! fails), and brings the world up to date from what the simulator reports before the
//! next move. The final error is measured on the simulated object, whose pose comes from
//! the kinematics of its holders. A failing move is reported with its place in the job;
//! the world printed at the end is as it really is: the objects moved so far stay moved.

use std::process::ExitCode;

use cellc_lang::Diagnostic;
use cellc_runtime::execute::SimulatorTolerance;
use cellc_runtime::{ExecuteOptions, Execution, ExecutionError, Executor};

use super::job::{job, world_text, Job};
use super::plan::{load, Loaded, PlanArgs};
use crate::args::PlanFormat;
use crate::plan_json::{self, JsonMove, JsonRun};
use crate::plan_report::{codes, describe, plan_error};

/// Runs the job `args` ask for; `fail_at` makes the motion of that step (1-based) of the
/// first move fail.
pub fn run(args: &PlanArgs, fail_at: Option<usize>) -> ExitCode {
    let loaded = match load(args) {
        Ok(l) => l,
        Err(code) => return code,
    };
    let Job {
        mut world,
        moves,
        title,
    } = match job(args, &loaded) {
        Ok(j) => j,
        Err(code) => return code,
    };
    let cell = &loaded.cell;
    let artifact = cell.artifact();
    let options = args.options();
    let human = args.format == PlanFormat::Human;
    let mut done: Vec<JsonMove> = Vec::new();
    let mut failure: Option<Diagnostic> = None;
    let several = moves.len() > 1 || !title.starts_with("request");
    for (i, m) in moves.iter().enumerate() {
        let name = artifact.object_name(m.object);
        let label = if title.starts_with("request") {
            title
                .trim_start_matches("request `")
                .trim_end_matches('`')
                .to_string()
        } else {
            format!("move {} of {}", i + 1, moves.len())
        };
        if human && several {
            println!("{title}, move {} of {}: `{name}`", i + 1, moves.len());
        }
        let in_job = |d: Diagnostic| {
            if several {
                d.note(format!(
                    "move {} of {} of the {title} failed; the moves before it were carried out",
                    i + 1,
                    moves.len()
                ))
            } else {
                d
            }
        };
        let plans = match super::job::plans_for(cell, &world, m, &options, args.clear) {
            Ok(plans) => plans,
            Err(e) => {
                failure = Some(in_job(plan_error(
                    artifact,
                    &e,
                    m.span,
                    Some(&loaded.sources),
                )));
                break;
            }
        };
        let count = plans.len();
        let mut replanned = false;
        let mut stopped = false;
        for (k, mut plan) in plans.into_iter().enumerate() {
            let clearing = k + 1 < count;
            if !clearing && replanned {
                // A clearing move needed a replan, so its object may stand elsewhere than
                // the request's plan assumed: plan the request again in the world as it is.
                plan = match cell.plan_in(&world, m.object, &m.goal, &options) {
                    Ok(p) => p,
                    Err(e) => {
                        failure = Some(in_job(plan_error(
                            artifact,
                            &e,
                            m.span,
                            Some(&loaded.sources),
                        )));
                        stopped = true;
                        break;
                    }
                };
            }
            let label = if clearing {
                format!("clearing for {name}")
            } else {
                label.clone()
            };
            if human {
                if clearing {
                    println!(
                        "`{}` is in the way: moving it to a free place first",
                        artifact.object_name(plan.object)
                    );
                }
                print!("{}", describe(artifact, &label, &plan));
            }
            let (record, result) = execute_plan(
                &loaded,
                &mut world,
                plan,
                &options,
                &label,
                fail_at.filter(|_| i == 0 && k == 0),
            );
            replanned |= result.as_ref().is_ok_and(|r| r.plans.len() > 1);
            let record = JsonMove {
                clears: clearing.then_some(name),
                ..record
            };
            done.push(record);
            if let Err(e) = result {
                failure = Some(in_job(execution_error(artifact, &e, m.span, &loaded)));
                stopped = true;
                break;
            }
        }
        if stopped {
            break;
        }
    }
    let ok = failure.is_none();
    let diagnostics: Vec<Diagnostic> = failure.into_iter().collect();
    if human {
        // A lone request's world is the request itself; a world given or several moves
        // are worth showing as they end.
        if several || args.world.is_some() {
            print!("{}", world_text(cell, &world));
        }
        loaded.report(&diagnostics);
    } else {
        let document = JsonRun {
            version: plan_json::VERSION,
            kind: "run",
            ok,
            plans: Vec::new(),
            moves: done,
            world: Some(plan_json::world(cell, &world)),
            report: loaded.json_report(&diagnostics),
        };
        println!("{}", plan_json::to_text(&document));
    }
    if ok {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    }
}

/// Executes one plan in the simulator from `world` and brings the world up to date; the
/// human output (the simulation log, replans, the final pose) is printed here, the JSON
/// record returned with the result.
fn execute_plan<'a>(
    loaded: &'a Loaded,
    world: &mut cellc_runtime::World,
    plan: cellc_runtime::Plan,
    options: &cellc_runtime::plan::PlanOptions,
    label: &str,
    fail_at: Option<usize>,
) -> (JsonMove<'a>, Result<Execution, ExecutionError>) {
    let cell = &loaded.cell;
    let artifact = cell.artifact();
    let human = loaded.format == PlanFormat::Human;
    let object = plan.object;
    let goal_pose = plan.goal.pose;
    let first = plan.clone();
    // An object let go above its surface by no more than the request calls resting
    // falls onto it (the planner put it down there).
    let mut simulator = cell
        .simulator_in(world, &plan)
        .with_tolerance(SimulatorTolerance {
            drop: options.position_tolerance,
            ..SimulatorTolerance::default()
        });
    if let Some(step) = fail_at {
        simulator = simulator.fail_motion_at(step.saturating_sub(1));
    }
    let execute = ExecuteOptions {
        max_replans: 5,
        plan: options.clone(),
    };
    let result = cell.execute_in(world, plan, &mut simulator, &execute);
    if human {
        println!("simulation:");
        for line in &simulator.log {
            println!("  {line}");
        }
    }
    let observed = simulator.object_state();
    let (final_state, final_pose, position_error, rotation_error) = plan_json::final_place(
        artifact,
        object,
        Some((observed.state, observed.pose)),
        goal_pose,
    );
    if human {
        if let Ok(run) = &result {
            print!(
                "{}",
                done_text(loaded, label, run, position_error, rotation_error)
            );
        }
    }
    let plans = match &result {
        Ok(run) => run.plans.clone(),
        Err(_) => vec![first],
    };
    let record = JsonMove {
        object: artifact.object_name(object),
        clears: None,
        plans: plans
            .iter()
            .filter_map(|p| serde_json::to_value(plan_json::plan(artifact, label, p)).ok())
            .collect(),
        log: simulator.log.clone(),
        done: result.is_ok(),
        final_state,
        final_pose,
        position_error,
        rotation_error,
    };
    (record, result)
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
    let object = run.plans[0].object;
    let s = run.final_state;
    let _ = writeln!(
        out,
        "done: `{}` held by `{}` with `{}` in `{}`",
        artifact.object_name(object),
        artifact.end_effector_name(s.end_effector),
        artifact.grasp_name(object, s.grasp),
        artifact.workspace_name(s.workspace)
    );
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

/// An execution failure as a diagnostic.
fn execution_error(
    artifact: &cellc_schema::Artifact,
    e: &ExecutionError,
    span: Option<u32>,
    loaded: &Loaded,
) -> Diagnostic {
    match e {
        ExecutionError::Replan(e) => plan_error(artifact, e, span, Some(&loaded.sources)),
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
