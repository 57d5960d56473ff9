//! The paper's Vito behaviours emerge from `cells/vito.cell` without any strategy being
//! chosen: each named request plans to the expected sequence of holders, with joint
//! motions, and executes in the kinematic simulator to its goal.

use cellc::fs_files::FsFiles;
use cellc_runtime::execute::{execute, Simulator};
use cellc_runtime::math::iso_from_schema;
use cellc_runtime::plan::planner::Planner;
use cellc_runtime::plan::{Goal, Placement, PlanOptions, Request};
use cellc_runtime::scene::Scene;
use cellc_runtime::verify::{verify, VerifyOptions};
use cellc_schema::Artifact;

fn vito() -> (Artifact, Scene) {
    let compilation = cellc_compiler::compile(&FsFiles, "cells/vito.cell");
    assert!(compilation.diagnostics.is_empty(), "vito.cell is not clean");
    let mut artifact = cellc_compiler::artifact::lower(
        compilation.cell.as_ref().unwrap(),
        &compilation.graphs,
        &compilation.sources,
    );
    let scene = Scene::load(&artifact, &FsFiles).expect("scene loads");
    verify(&mut artifact, &scene, &VerifyOptions::default(), &|_, _| {});
    (artifact, scene)
}

fn request(a: &Artifact, name: &str, seed: u64) -> Request {
    let r = a
        .requests
        .iter()
        .find(|r| r.name == name)
        .unwrap_or_else(|| panic!("request `{name}`"));
    let obj = &a.objects[r.object as usize];
    let place = |p: &cellc_schema::RequestPlacement| Placement {
        holder: a.end_effectors[p.end_effector as usize].name.clone(),
        grasp: p.grasp.map(|g| obj.grasps[g as usize].name.clone()),
        workspace: p.workspace.map(|w| a.workspaces[w as usize].name.clone()),
        pose: p.pose.as_ref().map(iso_from_schema),
    };
    Request {
        object: obj.name.clone(),
        start: place(&r.from),
        goal: Goal::Placement(place(&r.to)),
        options: PlanOptions {
            seed,
            ..PlanOptions::default()
        },
    }
}

/// Plans and simulates a named request; returns the holder sequence and the strategy.
fn behaviour(a: &Artifact, scene: &Scene, name: &str, seed: u64) -> (Vec<String>, String) {
    let planner = Planner::new(a, Some(scene));
    let req = request(a, name, seed);
    let plan = planner
        .plan(&req)
        .unwrap_or_else(|e| panic!("{name}: {e:?}"));
    let mut holders: Vec<String> = Vec::new();
    for s in &plan.states {
        let h = a.end_effectors[s.end_effector as usize].name.clone();
        if holders.last() != Some(&h) {
            holders.push(h);
        }
    }
    let strategy = plan.strategy.to_string();
    // Every command that moves an arm comes with a collision-checked trajectory.
    assert!(
        plan.steps.iter().any(|s| s.motion.is_some()),
        "{name}: no motions"
    );
    let goal = *plan.states.last().unwrap();
    let goal_pose = match &req.goal {
        Goal::Placement(p) => p.pose,
        Goal::Workspace { .. } => None,
    };
    let mut sim = Simulator::new(a, Some(scene), plan.object, plan.states[0], req.start.pose);
    let run = execute(
        &planner,
        plan,
        &[goal],
        goal_pose,
        &mut sim,
        &req.options,
        0,
    )
    .unwrap_or_else(|e| panic!("{name}: {e:?}"));
    assert_eq!(
        run.final_state, goal,
        "{name}: the simulation ends elsewhere"
    );
    if let (Some(want), Some(got)) = (goal_pose, run.final_pose) {
        assert!(
            (want.inverse() * got).translation.vector.norm() < 1e-3,
            "{name}: final pose off"
        );
    }
    (holders, strategy)
}

#[test]
fn the_five_vito_behaviours_emerge() {
    let (a, scene) = vito();
    for seed in [0, 1] {
        let (h, s) = behaviour(&a, &scene, "handoff_cylinder", seed);
        assert_eq!(h, ["table", "left", "right", "table"]);
        assert_eq!(s, "handoff");
        let (h, s) = behaviour(&a, &scene, "single_arm_regrasp", seed);
        assert_eq!(h, ["left", "table", "left", "table"]);
        assert_eq!(s, "single-arm regrasp via surface");
        let (h, s) = behaviour(&a, &scene, "dual_arm_regrasp", seed);
        assert_eq!(h, ["left", "table", "right", "table"]);
        assert_eq!(s, "dual-arm regrasp via surface");
        let (h, s) = behaviour(&a, &scene, "pick_and_place", seed);
        assert_eq!(h, ["table", "left", "table"]);
        assert_eq!(s, "pick-and-place");
        // Trashing: the bin is a non-movable end-effector like the table.
        let (h, _) = behaviour(&a, &scene, "trash", seed);
        assert_eq!(h, ["table", "right", "bin"]);
    }
}

#[test]
fn the_colander_is_handed_over_too() {
    let (a, scene) = vito();
    let (h, s) = behaviour(&a, &scene, "handoff_colander", 0);
    assert_eq!(h, ["table", "left", "right", "table"]);
    assert_eq!(s, "handoff");
}

/// Every motion of every plan, on both geometric cells and for any seed, passes an
/// independent dense re-check: every point within joint limits and collision-free, with
/// the object travelling as the plan says; and the simulated run ends at the goal.
mod trajectories {
    use super::*;
    use cellc_runtime::motion::check_trajectory;
    use cellc_runtime::scene::SceneScratch;
    use proptest::prelude::*;

    fn cell(path: &str) -> (Artifact, Scene) {
        let compilation = cellc_compiler::compile(&FsFiles, path);
        let mut artifact = cellc_compiler::artifact::lower(
            compilation.cell.as_ref().unwrap(),
            &compilation.graphs,
            &compilation.sources,
        );
        let scene = Scene::load(&artifact, &FsFiles).expect("scene loads");
        verify(&mut artifact, &scene, &VerifyOptions::default(), &|_, _| {});
        (artifact, scene)
    }

    /// Found by the property below: verified with seed 0, planned with seed 1002, arm 1
    /// could not retreat after handing over and kept its hand on the cylinder, which made
    /// the next carry "start in collision". That contact is now allowed until the object
    /// has been carried away.
    #[test]
    fn a_giver_that_cannot_retreat_does_not_block_the_next_carry() {
        let (a, scene) = cell("cells/assembly_line.cell");
        let planner = Planner::new(&a, Some(&scene));
        let plan = planner.plan(&request(&a, "line", 1002)).expect("plans");
        let mut scratch = SceneScratch::default();
        for step in &plan.steps {
            if let (Some(t), Some(context)) = (&step.motion, &step.motion_context) {
                check_trajectory(
                    &scene,
                    t,
                    &context.stationary,
                    plan.object,
                    &context.placement,
                    0.03,
                    &mut scratch,
                )
                .expect("trajectory re-checks");
            }
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 6, ..ProptestConfig::default() })]

        #[test]
        fn every_trajectory_point_is_within_limits_and_free(seed in 0u64..10_000) {
            for path in ["cells/vito.cell", "cells/assembly_line.cell"] {
                let (a, scene) = cell(path);
                let planner = Planner::new(&a, Some(&scene));
                for named in &a.requests {
                    let req = request(&a, &named.name, seed);
                    // The property is about the plans that exist; a rare motion give-up that
                    // leaves a request unplanned is not a violation of it.
                    let Ok(plan) = planner.plan(&req) else { continue };
                    let mut scratch = SceneScratch::default();
                    for step in &plan.steps {
                        let (Some(t), Some(context)) = (&step.motion, &step.motion_context) else { continue };
                        let checked = check_trajectory(&scene, t, &context.stationary, plan.object, &context.placement, 0.03, &mut scratch);
                        prop_assert!(checked.is_ok(), "{path} {} seed {seed}: {checked:?}", named.name);
                        let times: Vec<f64> = t.points.iter().map(|p| p.0).collect();
                        prop_assert!(times.windows(2).all(|w| w[1] > w[0]), "time goes back");
                    }
                }
            }
        }
    }
}
