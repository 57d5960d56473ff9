//! Planning move requests: the paper's Fig. 8 and Fig. 9 come out of the Fig. 3 cell,
//! every plan is a walk of the object's graph whose holders change only through
//! transitions, a motion failure part way leads to a replan from where the object is, and
//! unreachable requests are refused with the start's reachable set.

#[path = "support/verified.rs"]
mod verified;

use std::collections::HashSet;

use cellc_driver::fs_files::FsFiles;
use cellc_driver::BuildOptions;
use cellc_runtime::plan::planner::Planner;
use cellc_runtime::plan::{
    names, Command, Goal, LocateError, PlacementByName, Plan, PlanError, PlanOptions, Request,
};
use cellc_runtime::Cell;
use cellc_runtime::{ExecuteOptions, ExecutionError, Executor, Simulator};
use cellc_schema::{ArcKind, Artifact, Node};
use proptest::prelude::*;
use verified::verified_cell;

fn artifact(path: &str) -> Artifact {
    cellc_driver::build(&FsFiles, path, &BuildOptions::unverified())
        .artifact
        .unwrap_or_else(|| panic!("{path} has errors"))
}

fn placement(holder: &str, grasp: Option<&str>, workspace: &str) -> PlacementByName {
    PlacementByName {
        holder: holder.into(),
        grasp: grasp.map(Into::into),
        workspace: Some(workspace.into()),
        pose: None,
    }
}

/// A request for the cylinder, its names resolved as the front door does.
fn request(a: &Artifact, from: PlacementByName, to: PlacementByName) -> Request {
    let object = names::object(a, "cylinder").expect("the cell has a cylinder");
    Request {
        object,
        start: names::placement(a, object, &from).expect("known names"),
        goal: Goal::Placement(names::placement(a, object, &to).expect("known names")),
        options: PlanOptions {
            motions: false,
            ..PlanOptions::default()
        },
    }
}

fn holders(artifact: &Artifact, plan: &Plan) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for s in &plan.states {
        let name = artifact.end_effectors[s.end_effector.index()].name.clone();
        if out.last() != Some(&name) {
            out.push(name);
        }
    }
    out
}

#[test]
fn fig8_is_a_direct_handoff() {
    let a = artifact("cells/fig3.cell");
    let planner = Planner::new(&a, None);
    let plan = planner
        .plan(&request(
            &a,
            placement("left_arm", Some("g5"), "w1"),
            placement("right_arm", Some("g7"), "w3"),
        ))
        .expect("plans");
    assert_eq!(holders(&a, &plan), ["left_arm", "right_arm"]);
    assert_eq!(plan.strategy.to_string(), "handoff");
    assert!((plan.cost - 1.2).abs() < 1e-9, "{}", plan.cost);
    // One move per run of moves: w1 -> w2, handoff, w2 -> w3.
    let kinds: Vec<&str> = plan
        .steps
        .iter()
        .map(|s| match s.command {
            Command::Move { .. } => "move",
            Command::Grasp { .. } => "grasp",
            Command::Ungrasp { .. } => "ungrasp",
        })
        .collect();
    assert_eq!(kinds, ["move", "grasp", "ungrasp", "move"]);
}

#[test]
fn fig9_goes_through_the_table() {
    let a = artifact("cells/fig3.cell");
    let planner = Planner::new(&a, None);
    let plan = planner
        .plan(&request(
            &a,
            placement("left_arm", Some("g6"), "w1"),
            placement("right_arm", Some("g9"), "w3"),
        ))
        .expect("plans");
    assert_eq!(holders(&a, &plan), ["left_arm", "table", "right_arm"]);
    assert_eq!(plan.strategy.to_string(), "dual-arm regrasp via surface");
    assert!((plan.cost - 2.2).abs() < 1e-9, "{}", plan.cost);
}

#[test]
fn the_named_requests_of_fig3_are_the_papers_figures() {
    let a = artifact("cells/fig3.cell");
    let names: Vec<&str> = a.requests.iter().map(|r| r.name.as_str()).collect();
    assert_eq!(names, ["fig8", "fig9"]);
}

/// A walk of the graph: each simplified step is an arc, or a run of moves of one holder
/// with one grasp; holders and grasps change only through transition arcs.
fn assert_walk(a: &Artifact, plan: &Plan) {
    let graph = &a.objects[plan.object.index()].graph;
    let arc = |x: &Node, y: &Node, kind: ArcKind| {
        graph.arcs.iter().any(|arc| {
            arc.kind == kind
                && graph.nodes[arc.from as usize] == *x
                && graph.nodes[arc.to as usize] == *y
        })
    };
    for w in plan.states.windows(2) {
        let (x, y) = (&w[0], &w[1]);
        if x.end_effector == y.end_effector && x.grasp == y.grasp {
            // A (merged) run of moves: reachable by move arcs of that holder and grasp.
            let mut seen = HashSet::from([x.workspace]);
            let mut stack = vec![x.workspace];
            while let Some(ws) = stack.pop() {
                for next in graph.arcs.iter().filter(|arc| arc.kind == ArcKind::Move) {
                    let (f, t) = (
                        graph.nodes[next.from as usize],
                        graph.nodes[next.to as usize],
                    );
                    if f.end_effector == x.end_effector
                        && f.grasp == x.grasp
                        && f.workspace == ws
                        && seen.insert(t.workspace)
                    {
                        stack.push(t.workspace);
                    }
                }
            }
            assert!(
                seen.contains(&y.workspace),
                "{x:?} -> {y:?} is no run of moves"
            );
        } else {
            assert_eq!(x.workspace, y.workspace, "a grasp change moved the object");
            assert!(
                arc(x, y, ArcKind::Transition),
                "{x:?} -> {y:?} is no transition"
            );
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    /// Any start and goal state of the Fig. 3 graph: a plan, when there is one, is a walk
    /// whose cost is the sum of its arcs, and the commands agree with the states.
    #[test]
    fn every_plan_is_a_walk_of_the_graph(start in 0usize..21, goal in 0usize..21) {
        let a = artifact("cells/fig3.cell");
        let graph = &a.objects[0].graph;
        let name = |n: &Node| a.end_effectors[n.end_effector.index()].name.clone();
        let (s, g) = (graph.nodes[start], graph.nodes[goal]);
        let grasp = |n: &Node| a.objects[0].grasps[n.grasp.index()].name.clone();
        let ws = |n: &Node| a.workspaces[n.workspace.index()].name.clone();
        let planner = Planner::new(&a, None);
        let result = planner.plan(&request(
            &a,
            placement(&name(&s), Some(&grasp(&s)), &ws(&s)),
            placement(&name(&g), Some(&grasp(&g)), &ws(&g)),
        ));
        match result {
            Ok(plan) => {
                prop_assert_eq!(plan.states.first(), Some(&s));
                prop_assert_eq!(plan.states.last(), Some(&g));
                assert_walk(&a, &plan);
                let grasps = plan.steps.iter().filter(|st| matches!(st.command, Command::Grasp { .. })).count();
                let ungrasps = plan.steps.iter().filter(|st| matches!(st.command, Command::Ungrasp { .. })).count();
                prop_assert_eq!(grasps, ungrasps);
            }
            Err(PlanError::Unreachable(u)) => {
                prop_assert!(!u.reachable.contains(&cellc_schema::NodeId(goal as u32)));
            }
            Err(other) => prop_assert!(false, "{other:?}"),
        }
    }
}

#[test]
fn a_failed_motion_after_the_first_step_replans_from_the_new_state() {
    let a = artifact("cells/fig3.cell");
    let planner = Planner::new(&a, None);
    let req = request(
        &a,
        placement("table", Some("g1"), "w1"),
        placement("table", Some("g2"), "w3"),
    );
    let plan = planner.plan(&req).expect("plans");
    let start = plan.states[0];
    let goal = *plan.states.last().unwrap();
    // The first step (left arm grasps in w1) succeeds; the motion of the third fails.
    let mut sim = Simulator::new(&a, None, plan.object, start, None).fail_motion_at(2);
    let options = ExecuteOptions {
        max_replans: 3,
        plan: req.options.clone(),
    };
    let run = planner.execute(plan, &mut sim, &options).expect("recovers");
    assert_eq!(run.plans.len(), 2, "one replan");
    assert_eq!(run.final_state, goal);
    // The replan starts where the object was when the motion failed: held by the arm.
    let replan_start = run.plans[1].states[0];
    assert_eq!(
        a.end_effectors[replan_start.end_effector.index()].name,
        "left_arm"
    );
    assert!(sim.log.iter().any(|l| l.contains("injected")));
}

#[test]
fn a_failure_before_the_object_moved_is_final() {
    let a = artifact("cells/fig3.cell");
    let planner = Planner::new(&a, None);
    let req = request(
        &a,
        placement("table", Some("g1"), "w1"),
        placement("table", Some("g2"), "w3"),
    );
    let plan = planner.plan(&req).expect("plans");
    let (start, goal) = (plan.states[0], *plan.states.last().unwrap());
    let _ = goal;
    let mut sim = Simulator::new(&a, None, plan.object, start, None).fail_motion_at(0);
    let result = planner.execute(plan, &mut sim, &ExecuteOptions::default());
    assert!(
        matches!(result, Err(ExecutionError::FailedAtStart { .. })),
        "{result:?}"
    );
    assert_eq!(sim.object_state().state, start);
}

#[test]
fn unknown_names_are_located_errors() {
    let a = artifact("cells/fig3.cell");
    let object = names::object(&a, "cylinder").expect("known");
    let result = names::placement(&a, object, &placement("tabel", Some("g1"), "w1"));
    let error = match result {
        Err(e @ LocateError::UnknownHolder { .. }) => e,
        other => panic!("{other:?}"),
    };
    assert!(
        error.to_string().contains("no end-effector `tabel`"),
        "{error}"
    );
    // The CLI says what was meant.
    let d = cellc::plan_report::plan_error(&a, &PlanError::Locate(error), None, None);
    assert_eq!(d.help.as_deref(), Some("did you mean `table`?"));
    // Grasps are scoped per object and per holder: `g7` is the right arm's.
    let result = names::placement(&a, object, &placement("left_arm", Some("g7"), "w1"));
    assert!(
        matches!(result, Err(LocateError::UnknownGrasp { ref known, .. }) if known.len() == 3),
        "{result:?}"
    );
}

/// UI tests of planning: `tests/ui/plan/CODE_what.cell` is compiled and its first request
/// planned (or the missing request reported); exactly that code must come out, and the
/// rendered diagnostic is snapshotted.
#[test]
fn plan_ui() {
    let mut checked = 0;
    insta::glob!("ui/plan/*.cell", |path| {
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        let code = name.split('_').next().unwrap_or_default().to_string();
        let relative = format!("tests/ui/plan/{name}");
        // Built as `cellc plan` builds it (verified when it has arms). Warnings may be
        // what the case is about (a transition declared one way only, arcs pruned); only
        // the planner's diagnostic is snapshotted.
        let built = cellc_driver::build(&FsFiles, &relative, &Default::default());
        let compilation = built.compilation;
        let a = built
            .artifact
            .unwrap_or_else(|| panic!("{name} must build"));
        let diagnostic = match a.requests.first() {
            None => cellc::plan_report::no_request(&a, None),
            Some(named) => {
                let req = cellc_runtime::plan::named_request(
                    named,
                    PlanOptions {
                        time_budget: name
                            .contains("time_budget")
                            .then_some(std::time::Duration::ZERO),
                        ..PlanOptions::default()
                    },
                );
                // A cell with arms is planned with its geometry, as `cellc plan` does.
                let cell = Cell::from_artifact(a.clone(), &FsFiles).expect("loads");
                let error = cell
                    .plan(&cell.home_world(), &req)
                    .expect_err("the request must fail");
                cellc::plan_report::plan_error(
                    cell.artifact(),
                    &error,
                    Some(named.span),
                    Some(&compilation.sources),
                )
            }
        };
        assert_eq!(diagnostic.code.as_str(), code, "{name}");
        let source = std::fs::read_to_string(path).unwrap_or_default();
        let rendered = cellc::render::human(
            std::slice::from_ref(&diagnostic),
            &compilation.sources,
            cellc::render::Color::Never,
        );
        insta::assert_snapshot!(format!("{source}\n----- diagnostics -----\n{rendered}"));
        checked += 1;
    });
    assert_eq!(checked, 10);
}

#[test]
fn request_weights_replace_the_cells() {
    let a = artifact("cells/fig3.cell");
    let planner = Planner::new(&a, None);
    let mut req = request(
        &a,
        placement("table", Some("g1"), "w1"),
        placement("table", Some("g2"), "w3"),
    );
    let default = planner.plan(&req).expect("plans");
    assert!((default.cost - 3.2).abs() < 1e-9, "{}", default.cost);
    // The original planner's integer costs: a move 1, a transition 2.
    req.options.weights = Some((1.0, 2.0));
    let original = planner.plan(&req).expect("plans");
    assert!((original.cost - 8.0).abs() < 1e-9, "{}", original.cost);
}

/// Costs are the decimal sums of the arc weights, not their drifting binary sums: the
/// assembly line's plan (many moves of 0.1 and transitions of 1, whose floating-point
/// sum is 8.599999999999998) costs exactly what its arcs add up to in tenths, and the
/// JSON says so in the shortest decimal.
#[test]
fn plan_costs_are_decimal_sums_of_the_weights() {
    let cell = verified_cell("cells/assembly_line.cell");
    let named = &cell.artifact().requests[0].clone();
    let request = cellc_runtime::plan::named_request(
        named,
        PlanOptions {
            motions: false,
            ..PlanOptions::default()
        },
    );
    let plan = cell
        .plan(&cell.home_world(), &request)
        .expect("the line plans");
    let graph = &cell.artifact().objects[request.object.index()].graph;
    let mut tenths = 0u64;
    let mut float_sum = 0.0;
    for w in plan.states.windows(2) {
        let arc = graph
            .arcs
            .iter()
            .filter(|arc| {
                graph.nodes[arc.from as usize] == w[0] && graph.nodes[arc.to as usize] == w[1]
            })
            .min_by(|x, y| x.weight.total_cmp(&y.weight))
            .expect("consecutive states are joined by an arc");
        tenths += (arc.weight * 10.0).round() as u64;
        float_sum += arc.weight;
    }
    assert!(
        plan.states.len() > 10,
        "a long plan: {} states",
        plan.states.len()
    );
    assert_ne!(
        float_sum,
        tenths as f64 / 10.0,
        "the binary sum drifts on this plan"
    );
    assert_eq!(plan.cost, tenths as f64 / 10.0);
    let json = serde_json::to_string(&plan.cost).expect("serialises");
    assert_eq!(json, format!("{}", tenths as f64 / 10.0));
    assert!(!json.contains("0000"), "{json}");
}
