//! The checks: every problem that keeps the rows from being a cell without errors, each
//! reported with the table and row to change.

use std::collections::{BTreeMap, BTreeSet, HashMap};

use cellc_lang::Diagnostic;

use crate::import::diagnostics::{self as diag, shown};
use crate::import::{Database, EndEffectorRow, GraspRow, ObjectRow, WorkspaceRow};

/// Every problem that keeps the rows from being a cell without errors.
pub fn check(db: &Database) -> Vec<Diagnostic> {
    let mut out = Vec::new();
    duplicates(
        &mut out,
        "Workspaces",
        "Id",
        db.workspaces.iter().map(|r| r.id),
    );
    duplicates(
        &mut out,
        "EndEffectors",
        "Id",
        db.end_effectors.iter().map(|r| r.id),
    );
    duplicates(&mut out, "Objects", "Id", db.objects.iter().map(|r| r.id));
    duplicates(
        &mut out,
        "Grasps",
        "Grasp_id",
        db.grasps.iter().map(|r| r.id),
    );
    if !out.is_empty() {
        // References are ambiguous until ids are unique.
        return out;
    }
    let workspaces: HashMap<i64, &WorkspaceRow> = db.workspaces.iter().map(|r| (r.id, r)).collect();
    let end_effectors: HashMap<i64, &EndEffectorRow> =
        db.end_effectors.iter().map(|r| (r.id, r)).collect();
    let objects: HashMap<i64, &ObjectRow> = db.objects.iter().map(|r| (r.id, r)).collect();
    let grasps: HashMap<i64, &GraspRow> = db.grasps.iter().map(|r| (r.id, r)).collect();

    for e in &db.end_effectors {
        if e.movable != 0 && e.movable != 1 {
            out.push(diag::bad_movable(
                e.id,
                &shown(e.name.as_deref()),
                e.movable,
            ));
        }
    }

    // Reachability and adjacency.
    let mut reach: BTreeSet<(i64, i64)> = BTreeSet::new();
    for r in &db.reachability {
        let row = format!(
            "(EndEffector_id = {}, Workspace_id = {})",
            r.end_effector, r.workspace
        );
        let known_e = end_effectors.contains_key(&r.end_effector);
        let known_w = workspaces.contains_key(&r.workspace);
        if !known_e {
            out.push(diag::unknown_id(
                "Reachability",
                &row,
                "end-effector",
                r.end_effector,
                "EndEffectors",
            ));
        }
        if !known_w {
            out.push(diag::unknown_id(
                "Reachability",
                &row,
                "workspace",
                r.workspace,
                "Workspaces",
            ));
        }
        if known_e && known_w {
            reach.insert((r.end_effector, r.workspace));
        }
    }
    for w in &db.workspaces {
        if !reach.iter().any(|&(_, rw)| rw == w.id) {
            out.push(diag::unreached_workspace(w.id, &shown(w.name.as_deref())));
        }
    }
    for e in &db.end_effectors {
        if !reach.iter().any(|&(re, _)| re == e.id) {
            out.push(diag::reaches_nothing(e.id, &shown(e.name.as_deref())));
        }
    }
    // An end-effector whose `Movable` is neither 0 nor 1 is reported above; here it gets the
    // benefit of the doubt, so that one mistake is not reported again as another.
    let movable = |e: i64| end_effectors.get(&e).is_some_and(|r| r.movable != 0);
    let ws_name = |w: i64| shown(workspaces.get(&w).and_then(|r| r.name.as_deref()));
    for a in &db.adjacency {
        let row = format!("(id_source = {}, id_target = {})", a.source, a.target);
        let mut known = true;
        for w in [a.source, a.target] {
            if !workspaces.contains_key(&w) {
                known = false;
                out.push(diag::unknown_id(
                    "WorkspacesAdjacency",
                    &row,
                    "workspace",
                    w,
                    "Workspaces",
                ));
                if a.source == a.target {
                    break;
                }
            }
        }
        if !known {
            continue;
        }
        if a.source == a.target {
            out.push(diag::self_adjacency(&row, &ws_name(a.source)));
        } else if !reach
            .iter()
            .any(|&(e, w)| w == a.source && movable(e) && reach.contains(&(e, a.target)))
        {
            out.push(diag::useless_adjacency(
                &row,
                &ws_name(a.source),
                &ws_name(a.target),
            ));
        }
    }
    if db.adjacency.is_empty() {
        // The cell would derive adjacency from reach: say so when that adds moves.
        for e in db.end_effectors.iter().filter(|e| e.movable == 1) {
            let reached: Vec<i64> = reach
                .iter()
                .filter(|&&(re, _)| re == e.id)
                .map(|&(_, w)| w)
                .collect();
            if reached.len() >= 2 {
                let names: Vec<String> = reached
                    .iter()
                    .map(|&w| format!("`{}`", ws_name(w)))
                    .collect();
                let shared = format!(
                    "movable end-effector `{}` reaches {}",
                    shown(e.name.as_deref()),
                    join_and(&names)
                );
                out.push(diag::no_adjacency((reached[0], reached[1]), &shared));
                break;
            }
        }
    }

    // Grasps.
    for g in &db.grasps {
        let row = format!(
            "(Object_id = {}, EndEffector_id = {}, Grasp_id = {})",
            g.object, g.end_effector, g.id
        );
        if !objects.contains_key(&g.object) {
            out.push(diag::unknown_id(
                "Grasps", &row, "object", g.object, "Objects",
            ));
        }
        if !end_effectors.contains_key(&g.end_effector) {
            out.push(diag::unknown_id(
                "Grasps",
                &row,
                "end-effector",
                g.end_effector,
                "EndEffectors",
            ));
        }
    }

    // Transitions.
    for t in &db.transitions {
        let row = format!("(Source_id = {}, Target_id = {})", t.source, t.target);
        let (Some(from), Some(to)) = (grasps.get(&t.source), grasps.get(&t.target)) else {
            for g in [t.source, t.target] {
                if !grasps.contains_key(&g) {
                    out.push(diag::unknown_id(
                        "Grasp_transitions",
                        &row,
                        "grasp",
                        g,
                        "Grasps",
                    ));
                    if t.source == t.target {
                        break;
                    }
                }
            }
            continue;
        };
        if from.object != to.object {
            let name = |o: i64| shown(objects.get(&o).and_then(|r| r.name.as_deref()));
            out.push(diag::cross_object_transition(
                &row,
                (from.object, &name(from.object)),
                (to.object, &name(to.object)),
            ));
            continue;
        }
        let fixed = |e: i64| end_effectors.get(&e).is_some_and(|r| r.movable == 0);
        if fixed(from.end_effector) && fixed(to.end_effector) {
            let name = |e: i64| shown(end_effectors.get(&e).and_then(|r| r.name.as_deref()));
            let (a, b) = (name(from.end_effector), name(to.end_effector));
            let b = if from.end_effector == to.end_effector {
                a.clone()
            } else {
                b
            };
            out.push(diag::fixed_to_fixed(&row, &a, &b));
        }
    }
    out
}

fn duplicates(
    out: &mut Vec<Diagnostic>,
    table: &str,
    column: &str,
    ids: impl Iterator<Item = i64>,
) {
    let mut counts: BTreeMap<i64, usize> = BTreeMap::new();
    for id in ids {
        *counts.entry(id).or_default() += 1;
    }
    for (id, count) in counts {
        if count > 1 {
            out.push(diag::duplicate_id(table, column, id, count));
        }
    }
}

/// `a`, `a and b`, `a, b and c`.
fn join_and(items: &[String]) -> String {
    match items {
        [] => String::new(),
        [one] => one.clone(),
        [init @ .., last] => format!("{} and {last}", init.join(", ")),
    }
}
