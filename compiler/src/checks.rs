//! Semantic checks on the resolved cell, before and after graph generation.

use std::collections::BTreeMap;

use cellc_lang::Diagnostic;
use petgraph::Direction as Dir;
use rustc_hash::FxHashSet as HashSet;

use crate::diagnostics;
use crate::graph::ObjectGraph;
use crate::ids::*;
use crate::math::{overlap, Aabb, EPS};
use crate::model::*;

/// Checks that need only the resolved cell.
pub fn check_cell(cell: &Cell, diagnostics: &mut Vec<Diagnostic>) {
    check_reach(cell, diagnostics);
    check_workspaces(cell, diagnostics);
    check_grasps(cell, diagnostics);
    check_transitions(cell, diagnostics);
    check_requests(cell, diagnostics);
}

/// A placement (of a request, a line of the world or a task's step) naming a grasp its
/// holder cannot hold is wrong before any plan.
fn check_requests(cell: &Cell, diagnostics: &mut Vec<Diagnostic>) {
    let requests = cell
        .requests
        .iter()
        .flat_map(|r| [(&r.from, r.origin), (&r.to, r.origin)]);
    let world = cell.world.iter().map(|p| (&p.placement, p.origin));
    let steps = cell
        .tasks
        .iter()
        .flat_map(|t| t.steps.iter().map(|s| (&s.to, s.origin)));
    for (p, origin) in requests.chain(world).chain(steps) {
        if let Some(g) = p.grasp.filter(|&g| !cell.holds(p.end_effector, g)) {
            diagnostics.push(diagnostics::placement_grasp_mismatch(
                &cell.end_effectors[p.end_effector].name,
                &cell.grasps[g].name,
                origin.file,
                origin.span,
            ));
        }
    }
}

fn check_reach(cell: &Cell, diagnostics: &mut Vec<Diagnostic>) {
    for (_, e) in cell.end_effectors.iter() {
        // `reach auto` that found nothing is reported where it was written (E0423).
        if matches!(e.body, Body::Arm { .. }) && e.reach_boxes.is_empty() && e.reach_auto.is_none()
        {
            diagnostics.push(diagnostics::no_reach(&e.name, e.origin));
        }
    }
}

fn check_workspaces(cell: &Cell, diagnostics: &mut Vec<Diagnostic>) {
    let mut reached = vec![false; cell.workspaces.len()];
    // Who reaches each workspace, movable ones only, for the adjacency check.
    let mut movers: Vec<Vec<EndEffectorId>> = vec![Vec::new(); cell.workspaces.len()];
    for (e, ee) in cell.end_effectors.iter() {
        for &w in &ee.reaches {
            reached[w.index()] = true;
            if ee.is_movable() {
                movers[w.index()].push(e);
            }
        }
    }
    for (w, ws) in cell.workspaces.iter() {
        if !ws.derived && !reached[w.index()] {
            diagnostics.push(diagnostics::unreached_workspace(&ws.name, ws.origin));
        }
    }
    for adj in &cell.adjacencies {
        // Look through the shorter list of movers, in the other side's sorted reach.
        let (a, b) = if movers[adj.a.index()].len() <= movers[adj.b.index()].len() {
            (adj.a, adj.b)
        } else {
            (adj.b, adj.a)
        };
        let shared = movers[a.index()]
            .iter()
            .any(|&e| cell.end_effectors[e].reaches.binary_search(&b).is_ok());
        if !shared {
            diagnostics.push(diagnostics::useless_adjacency(
                &cell.workspaces[adj.a].name,
                &cell.workspaces[adj.b].name,
                adj.origin,
            ));
        }
    }
    check_overlaps(cell, diagnostics);
}

/// At most this many pairs of overlapping declared workspaces are reported.
pub const MAX_REPORTED_OVERLAPS: usize = 20;

/// Declared workspaces that overlap, found by sweeping their bounding boxes along the
/// axis on which they overlap least, so the pairs compared are those that are close, not
/// all pairs. Reports stop after [`MAX_REPORTED_OVERLAPS`].
fn check_overlaps(cell: &Cell, diagnostics: &mut Vec<Diagnostic>) {
    let declared: Vec<(&Workspace, Aabb)> = cell
        .workspaces
        .iter()
        .filter(|(_, w)| !w.derived && !w.boxes.is_empty())
        .map(|(_, w)| {
            let mut bound = w.boxes[0];
            for b in &w.boxes[1..] {
                bound.mins = bound.mins.inf(&b.mins);
                bound.maxs = bound.maxs.sup(&b.maxs);
            }
            (w, bound)
        })
        .collect();
    if declared.len() < 2 {
        return;
    }
    // The axis where the boxes' extents cover the least of their total span: boxes side
    // by side along it are compared only with their neighbours.
    let depth = |axis: usize| {
        let lengths: f64 = declared
            .iter()
            .map(|(_, b)| b.maxs[axis] - b.mins[axis])
            .sum();
        let lo = declared
            .iter()
            .map(|(_, b)| b.mins[axis])
            .fold(f64::INFINITY, f64::min);
        let hi = declared
            .iter()
            .map(|(_, b)| b.maxs[axis])
            .fold(f64::NEG_INFINITY, f64::max);
        lengths / (hi - lo).max(f64::MIN_POSITIVE)
    };
    let axis = (0..3)
        .min_by(|&a, &b| depth(a).total_cmp(&depth(b)))
        .unwrap_or(0);
    // Declaration order, then sorted by the sweep axis (stable: ties keep declaration order).
    let mut order: Vec<usize> = (0..declared.len()).collect();
    order.sort_by(|&i, &j| declared[i].1.mins[axis].total_cmp(&declared[j].1.mins[axis]));
    let mut pairs: Vec<(usize, usize, f64)> = Vec::new();
    let mut active: Vec<usize> = Vec::new();
    for &j in &order {
        let start = declared[j].1.mins[axis];
        active.retain(|&i| declared[i].1.maxs[axis] > start + EPS);
        for &i in &active {
            let (first, second) = (i.min(j), i.max(j));
            let (a, b) = (declared[first].0, declared[second].0);
            let volume: f64 = a
                .boxes
                .iter()
                .flat_map(|x| b.boxes.iter().filter_map(move |y| overlap(x, y)))
                .map(|i| i.volume())
                .sum();
            if volume > 0.0 {
                pairs.push((first, second, volume));
            }
        }
        if pairs.len() > MAX_REPORTED_OVERLAPS {
            break;
        }
        active.push(j);
    }
    // Report in declaration order of the pairs, as a scan of all pairs would.
    pairs.sort_by_key(|&(a, b, _)| (a, b));
    for &(a, b, volume) in pairs.iter().take(MAX_REPORTED_OVERLAPS) {
        let (a, b) = (declared[a].0, declared[b].0);
        diagnostics.push(diagnostics::overlapping_workspaces(
            &a.name, a.origin, &b.name, b.origin, volume,
        ));
    }
}

/// Whether each grasp (by index) is in some transition: a flag per grasp, as a cell of
/// 10^6 transitions would spend more hashing them than checking.
fn used_grasps(cell: &Cell) -> Vec<bool> {
    let mut used = vec![false; cell.grasps.len()];
    for t in &cell.transitions {
        used[t.from.index()] = true;
        used[t.to.index()] = true;
    }
    used
}

fn check_grasps(cell: &Cell, diagnostics: &mut Vec<Diagnostic>) {
    let used = used_grasps(cell);
    let mut kind_has_holder = vec![false; cell.holder_kinds.len()];
    for (_, e) in cell.end_effectors.iter() {
        if let Some(kind) = e.kind {
            kind_has_holder[kind.index()] = true;
        }
    }
    for (g, grasp) in cell.grasps.iter() {
        if let Some(Holder::Kind(kind)) = grasp.holder {
            if !kind_has_holder[kind.index()] {
                let k = &cell.holder_kinds[kind];
                diagnostics.push(diagnostics::kind_without_holder(
                    &k.name,
                    grasp.origin,
                    k.origin,
                ));
                continue;
            }
        }
        if grasp.holder.is_some()
            && !used[g.index()]
            && !cell.incomplete_objects.contains(&grasp.object)
        {
            diagnostics.push(diagnostics::unused_grasp(&grasp.name, grasp.origin));
        }
    }
}

fn check_transitions(cell: &Cell, diagnostics: &mut Vec<Diagnostic>) {
    let declared: HashSet<(GraspId, GraspId)> =
        cell.transitions.iter().map(|t| (t.from, t.to)).collect();
    let mut reported: HashSet<(GraspId, GraspId)> = HashSet::default();
    let holders = cell.holders();
    for t in &cell.transitions {
        let (from, to) = (&cell.grasps[t.from], &cell.grasps[t.to]);
        let (Some(_), Some(_)) = (from.holder, to.holder) else {
            continue;
        };
        let key = (t.from.min(t.to), t.from.max(t.to));
        let holders_from = holders.of(t.from);
        let holders_to = holders.of(t.to);
        let all_fixed = |hs: &[EndEffectorId]| {
            !hs.is_empty() && hs.iter().all(|&e| !cell.end_effectors[e].is_movable())
        };
        if all_fixed(holders_from) && all_fixed(holders_to) {
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
    let used = used_grasps(cell);
    for graph in graphs {
        // (grasp, "entered"/"left") -> (first such state, how many), so one warning
        // covers all workspaces; a name is made only for the state shown.
        let mut dead: BTreeMap<(GraspId, &str), (crate::graph::State, usize)> = BTreeMap::new();
        for node in graph.graph.node_indices() {
            let state = graph.graph[node];
            if !used[state.grasp.index()] {
                continue;
            }
            for (direction, never) in [(Dir::Incoming, "entered"), (Dir::Outgoing, "left")] {
                if graph
                    .graph
                    .neighbors_directed(node, direction)
                    .next()
                    .is_none()
                {
                    dead.entry((state.grasp, never))
                        .and_modify(|(_, n)| *n += 1)
                        .or_insert((state, 1));
                }
            }
        }
        for ((grasp, never), (state, n)) in dead {
            let first = describe_state(cell, state);
            let shown = match n {
                1 => first,
                n => format!("{first} (and {} more)", n - 1),
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
