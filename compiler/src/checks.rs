//! Semantic checks on the resolved cell, before and after graph generation.

use std::collections::{BTreeMap, HashSet};

use cellc_lang::Diagnostic;
use petgraph::Direction as Dir;

use crate::diagnostics;
use crate::graph::ObjectGraph;
use crate::ids::*;
use crate::math::overlap;
use crate::model::*;

/// Checks that need only the resolved cell.
pub fn check_cell(cell: &Cell, diagnostics: &mut Vec<Diagnostic>) {
    check_reach(cell, diagnostics);
    check_workspaces(cell, diagnostics);
    check_grasps(cell, diagnostics);
    check_transitions(cell, diagnostics);
    check_requests(cell, diagnostics);
}

/// A request placement naming a grasp its holder cannot hold is wrong before any plan.
fn check_requests(cell: &Cell, diagnostics: &mut Vec<Diagnostic>) {
    for r in &cell.requests {
        for p in [&r.from, &r.to] {
            if let Some(g) = p.grasp.filter(|&g| !cell.holds(p.end_effector, g)) {
                diagnostics.push(diagnostics::placement_grasp_mismatch(
                    &cell.end_effectors[p.end_effector].name,
                    &cell.grasps[g].name,
                    r.origin.file,
                    r.origin.span,
                ));
            }
        }
    }
}

fn check_reach(cell: &Cell, diagnostics: &mut Vec<Diagnostic>) {
    for (_, e) in cell.end_effectors.iter() {
        if matches!(e.body, Body::Arm { .. }) && e.reach_boxes.is_empty() {
            diagnostics.push(diagnostics::no_reach(&e.name, e.origin));
        }
    }
}

fn check_workspaces(cell: &Cell, diagnostics: &mut Vec<Diagnostic>) {
    for (w, ws) in cell.workspaces.iter() {
        if ws.derived {
            continue;
        }
        if !cell
            .end_effectors
            .iter()
            .any(|(_, e)| e.reaches.contains(&w))
        {
            diagnostics.push(diagnostics::unreached_workspace(&ws.name, ws.origin));
        }
    }
    for adj in &cell.adjacencies {
        let shared = cell.end_effectors.iter().any(|(_, e)| {
            e.is_movable() && e.reaches.contains(&adj.a) && e.reaches.contains(&adj.b)
        });
        if !shared {
            diagnostics.push(diagnostics::useless_adjacency(
                &cell.workspaces[adj.a].name,
                &cell.workspaces[adj.b].name,
                adj.origin,
            ));
        }
    }
    let declared: Vec<(WorkspaceId, &Workspace)> =
        cell.workspaces.iter().filter(|(_, w)| !w.derived).collect();
    for (i, (_, a)) in declared.iter().enumerate() {
        for (_, b) in &declared[i + 1..] {
            let volume: f64 = a
                .boxes
                .iter()
                .flat_map(|x| b.boxes.iter().filter_map(move |y| overlap(x, y)))
                .map(|i| i.volume())
                .sum();
            if volume > 0.0 {
                diagnostics.push(diagnostics::overlapping_workspaces(
                    &a.name, a.origin, &b.name, b.origin, volume,
                ));
            }
        }
    }
}

fn check_grasps(cell: &Cell, diagnostics: &mut Vec<Diagnostic>) {
    let used: HashSet<GraspId> = cell
        .transitions
        .iter()
        .flat_map(|t| [t.from, t.to])
        .collect();
    for (g, grasp) in cell.grasps.iter() {
        if let Some(Holder::Kind(kind)) = grasp.holder {
            if !cell.end_effectors.iter().any(|(_, e)| e.kind == Some(kind)) {
                let k = &cell.holder_kinds[kind];
                diagnostics.push(diagnostics::kind_without_holder(
                    &k.name,
                    grasp.origin,
                    k.origin,
                ));
                continue;
            }
        }
        if grasp.holder.is_some() && !used.contains(&g) {
            diagnostics.push(diagnostics::unused_grasp(&grasp.name, grasp.origin));
        }
    }
}

fn check_transitions(cell: &Cell, diagnostics: &mut Vec<Diagnostic>) {
    let declared: HashSet<(GraspId, GraspId)> =
        cell.transitions.iter().map(|t| (t.from, t.to)).collect();
    let mut reported: HashSet<(GraspId, GraspId)> = HashSet::new();
    for t in &cell.transitions {
        let (from, to) = (&cell.grasps[t.from], &cell.grasps[t.to]);
        let (Some(_), Some(_)) = (from.holder, to.holder) else {
            continue;
        };
        let key = (t.from.min(t.to), t.from.max(t.to));
        let holders_from = cell.holders_of(t.from);
        let holders_to = cell.holders_of(t.to);
        let all_fixed = |hs: &[EndEffectorId]| {
            !hs.is_empty() && hs.iter().all(|&e| !cell.end_effectors[e].is_movable())
        };
        if all_fixed(&holders_from) && all_fixed(&holders_to) {
            if reported.insert(key) {
                let a = &cell.end_effectors[holders_from[0]];
                let b = &cell.end_effectors[holders_to[0]];
                diagnostics.push(diagnostics::fixed_to_fixed(
                    t.origin,
                    (&a.name, a.origin),
                    (&b.name, b.origin),
                ));
            }
            continue;
        }
        if let (Some(Holder::EndEffector(a)), Some(Holder::EndEffector(b))) =
            (from.holder, to.holder)
        {
            if a == b && reported.insert(key) {
                diagnostics.push(diagnostics::same_holder_transition(
                    &cell.end_effectors[a].name,
                    &from.name,
                    &to.name,
                    t.origin,
                ));
            }
        }
        if !declared.contains(&(t.to, t.from)) && reported.insert(key) {
            diagnostics.push(diagnostics::asymmetric_transition(
                &from.name, &to.name, t.origin,
            ));
        }
    }
}

/// Checks that need the graphs: states that can never be entered or left. Grasps in no
/// transition are already reported as unused, so their states are not reported again.
pub fn check_graphs(cell: &Cell, graphs: &[ObjectGraph], diagnostics: &mut Vec<Diagnostic>) {
    let used: HashSet<GraspId> = cell
        .transitions
        .iter()
        .flat_map(|t| [t.from, t.to])
        .collect();
    for graph in graphs {
        // (grasp, "entered"/"left") -> states, so one warning covers all workspaces.
        let mut dead: BTreeMap<(GraspId, &str), Vec<String>> = BTreeMap::new();
        for node in graph.graph.node_indices() {
            let state = graph.graph[node];
            if !used.contains(&state.grasp) {
                continue;
            }
            let name = describe_state(cell, state);
            if graph
                .graph
                .neighbors_directed(node, Dir::Incoming)
                .next()
                .is_none()
            {
                dead.entry((state.grasp, "entered"))
                    .or_default()
                    .push(name.clone());
            }
            if graph
                .graph
                .neighbors_directed(node, Dir::Outgoing)
                .next()
                .is_none()
            {
                dead.entry((state.grasp, "left")).or_default().push(name);
            }
        }
        for ((grasp, never), states) in dead {
            let shown = match states.len() {
                1 => states[0].clone(),
                n => format!("{} (and {} more)", states[0], n - 1),
            };
            diagnostics.push(diagnostics::dead_end_state(
                &shown,
                never,
                cell.grasps[grasp].origin,
            ));
        }
    }
}

/// `(holder, grasp, workspace)` with names, for messages.
pub fn describe_state(cell: &Cell, state: crate::graph::State) -> String {
    format!(
        "(`{}`, `{}`, `{}`)",
        cell.end_effectors[state.end_effector].name,
        cell.grasps[state.grasp].name,
        cell.workspaces[state.workspace].name
    )
}
