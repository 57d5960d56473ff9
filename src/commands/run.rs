//! `cellc run ...`: plans a request like `cellc plan`, then executes it in the kinematic
//! simulator, replanning from where the object is when a motion fails.

use std::process::ExitCode;

use cellc_runtime::execute::{execute, ExecutionError, Executor, Simulator};
use cellc_runtime::plan::planner::Planner;
use cellc_runtime::plan::Goal;

use super::plan::{describe, load, plan_error, prepare, print, PlanArgs, Prepared};

/// Plans and simulates; `fail_at` makes the motion of that step (1-based) fail.
pub fn run(args: &PlanArgs, fail_at: Option<usize>) -> ExitCode {
    let loaded = match load(&args.input, args.seed) {
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
    let artifact = &loaded.artifact;
    let planner = Planner::new(artifact, loaded.scene.as_ref());
    let plan = match planner.plan(&request) {
        Ok(plan) => plan,
        Err(e) => {
            print(&[plan_error(artifact, &e, span)], &loaded.sources);
            return ExitCode::from(1);
        }
    };
    print!("{}", describe(artifact, &name, &plan));
    let goal = *plan.states.last().unwrap_or(&plan.states[0]);
    let goal_pose = match &request.goal {
        Goal::Placement(p) => p.pose,
        Goal::Workspace { .. } => None,
    };
    let mut simulator = Simulator::new(
        artifact,
        loaded.scene.as_ref(),
        plan.object,
        plan.states[0],
        request.start.pose,
    );
    if let Some(step) = fail_at {
        simulator = simulator.fail_motion_at(step.saturating_sub(1));
    }
    let result = execute(
        &planner,
        plan,
        &[goal],
        goal_pose,
        &mut simulator,
        &request.options,
        5,
    );
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
            let object = &artifact.objects[run.plans[0].object as usize];
            let holder = &artifact.end_effectors[run.final_state.end_effector as usize].name;
            let grasp = &object.grasps[run.final_state.grasp as usize].name;
            let ws = &artifact.workspaces[run.final_state.workspace as usize].name;
            println!(
                "done: `{}` held by `{holder}` with `{grasp}` in `{ws}`",
                object.name
            );
            if let Some(pose) = run.final_pose {
                let t = pose.translation.vector;
                print!("final object pose: ({:.4}, {:.4}, {:.4})", t.x, t.y, t.z);
                match goal_pose {
                    Some(g) => {
                        let d = g.inverse() * pose;
                        println!(
                            "; error {:.2} mm, {:.3} deg from the goal",
                            d.translation.vector.norm() * 1000.0,
                            d.rotation.angle().to_degrees()
                        );
                    }
                    None => println!(),
                }
            }
            let _ = simulator.object_state();
            ExitCode::SUCCESS
        }
        Err(ExecutionError::Replan(e)) => {
            print(&[plan_error(artifact, &e, span)], &loaded.sources);
            ExitCode::from(1)
        }
        Err(ExecutionError::FailedAtStart { reason }) => {
            eprintln!("error: a motion failed ({reason}) before the object left its start; nothing to recover from");
            ExitCode::from(1)
        }
        Err(ExecutionError::TooManyFailures { replans }) => {
            eprintln!("error: motions kept failing; gave up after {replans} replans");
            ExitCode::from(1)
        }
        Err(e) => {
            eprintln!("error: execution failed: {e:?}");
            ExitCode::from(1)
        }
    }
}
