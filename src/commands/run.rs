//! `cellc run ...`: plans a request like `cellc plan`, then executes it in the kinematic
//! simulator, replanning from where the object is when a step fails. The final error is
//! measured on the simulated object, whose pose comes from the kinematics of its holders.

use std::process::ExitCode;

use cellc_lang::Diagnostic;
use cellc_runtime::execute::SimulatorTolerance;
use cellc_runtime::{ExecuteOptions, ExecutionError};

use super::plan::{load, prepare, PlanArgs, Prepared};
use crate::plan_report::{codes, describe, plan_error};

/// Plans and simulates; `fail_at` makes the motion of that step (1-based) fail.
pub fn run(args: &PlanArgs, fail_at: Option<usize>) -> ExitCode {
    let loaded = match load(args) {
        Ok(l) => l,
        Err(code) => return code,
    };
    let Prepared {
        request,
        name,
        span,
    } = match prepare(args, &loaded) {
        Ok(p) => p,
        Err(code) => return code,
    };
    let cell = &loaded.cell;
    let artifact = cell.artifact();
    let plan = match cell.plan(&request) {
        Ok(plan) => plan,
        Err(e) => {
            loaded.report(&[plan_error(artifact, &e, span, Some(&loaded.sources))]);
            return ExitCode::from(1);
        }
    };
    print!("{}", describe(artifact, &name, &plan));
    let goal_pose = plan.goal.pose;
    // An object let go above its surface by no more than the request calls resting
    // falls onto it (the planner put it down there).
    let mut simulator = cell.simulator(&plan).with_tolerance(SimulatorTolerance {
        drop: request.options.position_tolerance,
        ..SimulatorTolerance::default()
    });
    if let Some(step) = fail_at {
        simulator = simulator.fail_motion_at(step.saturating_sub(1));
    }
    let options = ExecuteOptions {
        max_replans: 5,
        plan: request.options.clone(),
    };
    let result = cell.execute(plan, &mut simulator, &options);
    println!("simulation:");
    for line in &simulator.log {
        println!("  {line}");
    }
    match result {
        Ok(run) => {
            for (i, replan) in run.plans.iter().enumerate().skip(1) {
                println!("replan {i}, from where the object was:");
                print!("{}", describe(artifact, &name, replan));
            }
            let object = &artifact.objects[run.plans[0].object.index()];
            let holder = &artifact.end_effectors[run.final_state.end_effector.index()].name;
            let grasp = &object.grasps[run.final_state.grasp.index()].name;
            let ws = &artifact.workspaces[run.final_state.workspace.index()].name;
            println!(
                "done: `{}` held by `{holder}` with `{grasp}` in `{ws}`",
                object.name
            );
            if let Some(pose) = run.final_pose {
                let t = pose.translation.vector;
                print!("final object pose: ({:.4}, {:.4}, {:.4})", t.x, t.y, t.z);
                match goal_pose {
                    Some(g) => {
                        // A turn by one of the object's symmetries leaves it unchanged.
                        let d = g.inverse() * pose;
                        let rotation =
                            cellc_runtime::symmetry::residual(&d.rotation, &object.symmetries);
                        println!(
                            "; error {:.2} mm, {:.3} deg from the goal",
                            (pose.translation.vector - g.translation.vector).norm() * 1000.0,
                            rotation.to_degrees()
                        );
                    }
                    None => println!(),
                }
            }
            ExitCode::SUCCESS
        }
        Err(ExecutionError::Replan(e)) => {
            loaded.report(&[plan_error(artifact, &e, span, Some(&loaded.sources))]);
            ExitCode::from(1)
        }
        Err(ExecutionError::FailedAtStart { error }) => {
            let d = Diagnostic::error(
                codes::EXECUTION_FAILED,
                format!("{error}, before the object left its start"),
            )
            .help(
                "nothing moved, so there is nothing to recover from: fix the cause and run again",
            );
            loaded.report(&[d]);
            ExitCode::from(1)
        }
        Err(ExecutionError::TooManyFailures { replans, last }) => {
            let d = Diagnostic::error(
                codes::EXECUTION_FAILED,
                format!("steps kept failing ({last}); gave up after {replans} replans"),
            )
            .help("the object is where the last step left it; see the simulation log above");
            loaded.report(&[d]);
            ExitCode::from(1)
        }
        Err(e) => {
            let d = Diagnostic::error(codes::EXECUTION_FAILED, format!("execution failed: {e}"))
                .help("see the simulation log above");
            loaded.report(&[d]);
            ExitCode::from(1)
        }
    }
}
