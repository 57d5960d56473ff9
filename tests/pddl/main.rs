//! `cellc export pddl` solved by Fast Downward: for the shipped cells' requests, an optimal
//! PDDL plan (A* with LM-cut) costs exactly cellc's own high-level plan times
//! `COST_SCALE`, and its actions read back as a walk of the object's graph from the
//! request's start to a goal state, every step an arc the planner searches at its cost.
//! The same cell gives the same bytes, and docs/pddl.md shows real output.
//!
//! Fast Downward is found through `CELLC_FAST_DOWNWARD` (the path of its driver,
//! `fast-downward.py`) or in the repository's `.venv/` (made by `.ci/run` with the PyPI
//! package `up-fast-downward`); without either the tests fail, saying how to install it.

mod fast_downward;
mod text;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

use cellc::export::pddl::{action_cost, Names};
use cellc_driver::fs_files::FsFiles;
use cellc_runtime::plan::{GoalByName, PlanOptions, Request};
use cellc_runtime::Cell;
use cellc_schema::ObjectId;

use text::{actions, asked, Sexp};

/// A scratch folder of this test, emptied.
fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("pddl")
        .join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch folder");
    dir
}

fn cellc(args: &[&str]) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_cellc"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("cellc runs");
    assert!(
        out.status.success(),
        "cellc {}: {}",
        args.join(" "),
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// The shipped cell built into `dir`, loaded.
fn built(cell: &str, dir: &Path) -> (PathBuf, Cell) {
    let artifact = dir.join("cell.json");
    cellc(&["build", cell, "-o", &artifact.to_string_lossy()]);
    let read =
        cellc_driver::load::artifact::read(&artifact.to_string_lossy()).expect("artifact reads");
    let loaded = Cell::from_artifact(read, &FsFiles).expect("artifact loads");
    (artifact, loaded)
}

/// Solves `DIR/FOLDER/PROBLEM.pddl`, walks the plan through the graph and compares its
/// cost with cellc's plan of `request`.
fn check_round_trip(cell: &Cell, dir: &Path, problem_name: &str, request: &Request) {
    let artifact = cell.artifact();
    let object: ObjectId = request.object;
    let names = Names::of(artifact, object);
    let folder = dir.join(&names.item);
    let domain_path = folder.join("domain.pddl");
    let problem_path = folder.join(format!("{problem_name}.pddl"));
    let read = |p: &Path| std::fs::read_to_string(p).expect("exported file");
    let actions = actions(&Sexp::parse(&read(&domain_path)));
    let asked = asked(&Sexp::parse(&read(&problem_path)));
    let work = dir.join(format!("solve-{problem_name}"));
    std::fs::create_dir_all(&work).expect("work folder");
    let (steps, fd_cost) = fast_downward::solve(&domain_path, &problem_path, &work);

    // The plan as a walk of states, read from the domain's own actions.
    let mut at = Some(asked.start.clone());
    let mut path = vec![asked.start.clone()];
    let (mut sum, mut arrived) = (0, false);
    for (i, step) in steps.iter().enumerate() {
        assert_eq!(step.get(1), Some(&names.item), "{problem_name}: {step:?}");
        if step[0] == "arrive" {
            let state = &step[2];
            assert_eq!(
                at.as_ref(),
                Some(state),
                "{problem_name}: arrives elsewhere"
            );
            assert!(
                asked.targets.contains(state),
                "{problem_name}: not a target"
            );
            assert_eq!(i + 1, steps.len(), "{problem_name}: `arrive` ends the plan");
            at = None;
            arrived = true;
            continue;
        }
        let action = &actions[&step[0]];
        assert_eq!(at.as_ref(), Some(&action.from), "{problem_name}: step {i}");
        at = Some(action.to.clone());
        path.push(action.to.clone());
        sum += action.cost;
    }
    match &asked.goal_state {
        Some(goal) => assert_eq!(at.as_ref(), Some(goal), "{problem_name}: ends elsewhere"),
        None => assert!(arrived, "{problem_name}: never arrives"),
    }
    assert!(
        !asked.must_leave || path.len() > 1,
        "{problem_name}: never left"
    );
    assert_eq!(
        sum, fd_cost,
        "{problem_name}: the plan's cost as the domain says"
    );

    // The walk in the artifact's graph: every step an arc at its cost.
    let graph = &artifact.objects[object.index()].graph;
    let node = |state: &str| {
        names
            .states
            .iter()
            .position(|s| s == state)
            .unwrap_or_else(|| panic!("`{state}` is no state of {}", names.item))
    };
    for pair in path.windows(2) {
        let (from, to) = (node(&pair[0]), node(&pair[1]));
        let cost = actions
            .values()
            .find(|a| a.from == pair[0] && a.to == pair[1])
            .map(|a| a.cost);
        assert!(
            graph.arcs.iter().any(|a| a.from as usize == from
                && a.to as usize == to
                && Some(action_cost(a.weight)) == cost),
            "{problem_name}: {} -> {} is no arc of the graph at that cost",
            pair[0],
            pair[1]
        );
    }

    // cellc's own plan, high level only, costs the same.
    let plan = cell
        .plan(&cell.home_world(), request)
        .expect("cellc plans the request");
    let expected = action_cost(plan.cost);
    assert_eq!(
        fd_cost, expected,
        "{problem_name}: Fast Downward's optimal cost {fd_cost} against cellc's {} x 1000 \
         ({} backtracks)",
        plan.cost, plan.backtracks
    );
    let first = graph.nodes[node(&path[0])];
    assert_eq!(
        Some(&first),
        plan.states.first(),
        "{problem_name}: the start"
    );
    if let Some(last) = path.last() {
        assert!(
            plan.goal.states.contains(&graph.nodes[node(last)]),
            "{problem_name}: the plan ends in a goal state"
        );
    }
}

fn high_level() -> PlanOptions {
    PlanOptions {
        motions: false,
        ..PlanOptions::default()
    }
}

fn named(cell: &Cell, name: &str) -> Request {
    cell.named_request(name, high_level())
        .unwrap_or_else(|| panic!("the cell declares `{name}`"))
}

/// A request as `cellc plan --object O --from F --to T` reads it.
fn given(cell: &Cell, object: &str, from: &str, to: &str) -> Request {
    let from = cellc::commands::plan::placement_from_text(from, "from").expect("a placement");
    let to = cellc::commands::plan::placement_from_text(to, "to").expect("a placement");
    cell.request(object, &from, &GoalByName::Placement(to), high_level())
        .expect("the request locates")
}

fn files_of(dir: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    let mut out = BTreeMap::new();
    let mut folders = vec![dir.to_path_buf()];
    while let Some(folder) = folders.pop() {
        for entry in std::fs::read_dir(&folder).expect("a folder").flatten() {
            let path = entry.path();
            if path.is_dir() {
                folders.push(path);
            } else if path.extension().is_some_and(|e| e == "pddl") {
                let bytes = std::fs::read(&path).expect("readable");
                out.insert(path.strip_prefix(dir).unwrap_or(&path).to_path_buf(), bytes);
            }
        }
    }
    out
}

#[test]
fn fig3_requests_solve_at_cellcs_cost() {
    let dir = scratch("fig3");
    let (artifact, cell) = built("cells/fig3.cell", &dir);
    let out = dir.join("out");
    let art = artifact.to_string_lossy();
    cellc(&[
        "export",
        "pddl",
        &art,
        "--object",
        "cylinder",
        "-o",
        &out.to_string_lossy(),
    ]);
    for name in ["fig8", "fig9"] {
        check_round_trip(&cell, &out, name, &named(&cell, name));
    }
    // A goal of several states (any grasp of the table in w3): targets and `arrive`.
    let given_out = dir.join("given");
    let (from, to) = ("left_arm.g5 in w1", "table in w3");
    cellc(&[
        "export",
        "pddl",
        &art,
        "--object",
        "cylinder",
        "--from",
        from,
        "--to",
        to,
        "-o",
        &given_out.to_string_lossy(),
    ]);
    let problem = std::fs::read_to_string(given_out.join("cylinder/command_line.pddl"))
        .expect("the problem is written");
    assert!(problem.contains("(target table__g3__w3)"), "{problem}");
    let request = given(&cell, "cylinder", from, to);
    check_round_trip(&cell, &given_out, "command_line", &request);
}

#[test]
fn vito_requests_solve_at_cellcs_cost() {
    let dir = scratch("vito");
    let (artifact, cell) = built("cells/vito.cell", &dir);
    let art = artifact.to_string_lossy();
    let out = dir.join("out");
    cellc(&["export", "pddl", &art, "-o", &out.to_string_lossy()]);
    let requests: Vec<String> = cell
        .artifact()
        .requests
        .iter()
        .map(|r| r.name.clone())
        .collect();
    assert!(requests.len() >= 6, "{requests:?}");
    for name in &requests {
        check_round_trip(&cell, &out, name, &named(&cell, name));
    }
    // The same artifact exported again gives the same bytes.
    let again = dir.join("again");
    cellc(&["export", "pddl", &art, "-o", &again.to_string_lossy()]);
    assert_eq!(files_of(&out), files_of(&again));
    // A pick-and-place within one resting pose and workspace: the object must leave it.
    let given_out = dir.join("given");
    let (from, to) = ("table at (0.45, 0.45, 1.0)", "table at (0.40, 0.40, 1.0)");
    cellc(&[
        "export",
        "pddl",
        &art,
        "--object",
        "cylinder",
        "--from",
        from,
        "--to",
        to,
        "-o",
        &given_out.to_string_lossy(),
    ]);
    let problem = std::fs::read_to_string(given_out.join("cylinder/command_line.pddl"))
        .expect("the problem is written");
    assert!(problem.contains("(moved cylinder)"), "{problem}");
    check_round_trip(
        &cell,
        &given_out,
        "command_line",
        &given(&cell, "cylinder", from, to),
    );
}

#[test]
fn assembly_line_solves_at_cellcs_cost() {
    let dir = scratch("assembly_line");
    let (artifact, cell) = built("cells/assembly_line.cell", &dir);
    let out = dir.join("out");
    cellc(&[
        "export",
        "pddl",
        &artifact.to_string_lossy(),
        "--request",
        "line",
        "-o",
        &out.to_string_lossy(),
    ]);
    check_round_trip(&cell, &out, "line", &named(&cell, "line"));
    // Verification pruned arcs here (the handoffs in the nest): none is an action.
    let object = named(&cell, "line").object;
    let graph = &cell.artifact().objects[object.index()].graph;
    let names = Names::of(cell.artifact(), object);
    let domain = std::fs::read_to_string(out.join(&names.item).join("domain.pddl"))
        .expect("the domain is written");
    let actions = actions(&Sexp::parse(&domain));
    assert!(!graph.pruned.is_empty(), "the line prunes arcs");
    assert_eq!(actions.len(), graph.arcs.len());
    for pruned in &graph.pruned {
        let (from, to) = (
            &names.states[pruned.arc.from as usize],
            &names.states[pruned.arc.to as usize],
        );
        let kept = graph
            .arcs
            .iter()
            .any(|a| a.from == pruned.arc.from && a.to == pruned.arc.to);
        assert!(
            kept || !actions.values().any(|a| &a.from == from && &a.to == to),
            "pruned {from} -> {to} is an action"
        );
    }
}

#[test]
fn a_cell_and_its_artifact_give_the_same_bytes() {
    let dir = scratch("same_bytes");
    let (artifact, _) = built("cells/fig3.cell", &dir);
    let from_cell = dir.join("from_cell");
    let from_artifact = dir.join("from_artifact");
    cellc(&[
        "export",
        "pddl",
        "cells/fig3.cell",
        "-o",
        &from_cell.to_string_lossy(),
    ]);
    cellc(&[
        "export",
        "pddl",
        &artifact.to_string_lossy(),
        "-o",
        &from_artifact.to_string_lossy(),
    ]);
    let files = files_of(&from_cell);
    assert_eq!(files.len(), 3, "{:?}", files.keys());
    assert_eq!(files, files_of(&from_artifact));
}

#[test]
fn the_docs_show_real_output() {
    let dir = scratch("docs");
    let out = dir.join("pddl");
    let summary = cellc(&[
        "export",
        "pddl",
        "cells/fig3.cell",
        "-o",
        &out.to_string_lossy(),
    ]);
    let page = std::fs::read_to_string("docs/pddl.md").expect("docs/pddl.md");
    let problem = std::fs::read_to_string(out.join("cylinder/fig8.pddl")).expect("written");
    assert!(
        page.contains(&problem),
        "docs/pddl.md must show fig8.pddl:\n{problem}"
    );
    let domain = std::fs::read_to_string(out.join("cylinder/domain.pddl")).expect("written");
    let start = page
        .find("; cellc PDDL domain:")
        .expect("docs/pddl.md shows the domain");
    let end = start + page[start..].find("```").expect("a closed block");
    for excerpt in page[start..end].split("  ...\n") {
        assert!(
            domain.contains(excerpt),
            "docs/pddl.md's domain excerpt is not in the real domain:\n{excerpt}"
        );
    }
    let shown = summary.replace(&*out.to_string_lossy(), "pddl");
    assert!(
        page.contains(&shown),
        "docs/pddl.md must show the summary:\n{shown}"
    );
}
