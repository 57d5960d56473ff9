//! Evaluates the cell's own `expect` requirements on the resolved cell and its graphs.

use cellc_lang::ast::Mobility;
use cellc_lang::Diagnostic;
use petgraph::Direction;

use crate::checks::describe_state;
use crate::diagnostics;
use crate::graph::ObjectGraph;
use crate::model::*;

/// The most states, arcs and end-effectors the requirements of one cell may look at in
/// all: each `expect` costs a pass over its object's graph, so 10⁵ of them on a graph of
/// 10⁶ states would take hours. Requirements past the budget are reported as not checked.
pub const MAX_EXPECT_VISITS: u64 = 100_000_000;

/// Reports every requirement that does not hold.
pub fn check(cell: &Cell, graphs: &[ObjectGraph], diagnostics: &mut Vec<Diagnostic>) {
    let mut visits: u64 = 0;
    for (i, expectation) in cell.expectations.iter().enumerate() {
        visits = visits.saturating_add(cost(cell, graphs, &expectation.requirement));
        if visits > MAX_EXPECT_VISITS {
            diagnostics.push(diagnostics::expectations_not_checked(
                cell.expectations.len() - i,
                MAX_EXPECT_VISITS,
                expectation.origin,
            ));
            return;
        }
        if let Requirement::Reach { from, to, .. } = &expectation.requirement {
            let mut mismatch = false;
            for p in [from, to] {
                if let Some(g) = p.grasp.filter(|&g| !cell.holds(p.end_effector, g)) {
                    mismatch = true;
                    diagnostics.push(diagnostics::placement_grasp_mismatch(
                        &cell.end_effectors[p.end_effector].name,
                        &cell.grasps[g].name,
                        expectation.origin.file,
                        p.span,
                    ));
                }
            }
            if mismatch {
                continue;
            }
        }
        if let Err(why) = holds(cell, graphs, &expectation.requirement) {
            diagnostics.push(diagnostics::expectation_failed(
                &expectation.text,
                expectation.origin,
                &why,
            ));
        }
    }
}

/// What checking a requirement looks at: its object's graph (or all graphs), or the
/// end-effectors.
fn cost(cell: &Cell, graphs: &[ObjectGraph], requirement: &Requirement) -> u64 {
    let size = |g: &ObjectGraph| (g.graph.node_count() + g.graph.edge_count()) as u64;
    match requirement {
        Requirement::Reach { object, .. } => graphs
            .iter()
            .filter(|g| g.object == *object)
            .map(size)
            .sum::<u64>()
            .max(1),
        Requirement::Coverage { .. } => cell.end_effectors.len().max(1) as u64,
        Requirement::NoIsolatedStates { object } => graphs
            .iter()
            .filter(|g| object.is_none_or(|o| o == g.object))
            .map(size)
            .sum::<u64>()
            .max(1),
    }
}

fn matching(graph: &ObjectGraph, cell: &Cell, p: &Placement) -> Vec<petgraph::graph::NodeIndex> {
    graph
        .graph
        .node_indices()
        .filter(|&n| {
            let s = graph.graph[n];
            s.end_effector == p.end_effector
                && s.workspace == p.workspace
                && p.grasp.is_none_or(|g| g == s.grasp)
                && cell.holds(s.end_effector, s.grasp)
        })
        .collect()
}

fn describe_placement(cell: &Cell, p: &Placement) -> String {
    let grasp = match p.grasp {
        Some(g) => format!(" with `{}`", cell.grasps[g].name),
        None => String::new(),
    };
    format!(
        "`{}`{grasp} in `{}`",
        cell.end_effectors[p.end_effector].name, cell.workspaces[p.workspace].name
    )
}

/// `Ok` when the requirement holds, else why not.
pub fn holds(cell: &Cell, graphs: &[ObjectGraph], requirement: &Requirement) -> Result<(), String> {
    match requirement {
        Requirement::Reach { object, from, to } => {
            let graph = graphs
                .iter()
                .find(|g| g.object == *object)
                .ok_or_else(|| "the object has no graph".to_string())?;
            let starts = matching(graph, cell, from);
            if starts.is_empty() {
                return Err(format!(
                    "there is no state with the object held by {}",
                    describe_placement(cell, from)
                ));
            }
            let goals = matching(graph, cell, to);
            if goals.is_empty() {
                return Err(format!(
                    "there is no state with the object held by {}",
                    describe_placement(cell, to)
                ));
            }
            // One search from all the starts at once: a search per start would cost the
            // graph once per start.
            let mut reached = vec![false; graph.graph.node_count()];
            let mut queue: std::collections::VecDeque<petgraph::graph::NodeIndex> =
                std::collections::VecDeque::new();
            for &start in &starts {
                if !reached[start.index()] {
                    reached[start.index()] = true;
                    queue.push_back(start);
                }
            }
            while let Some(n) = queue.pop_front() {
                for next in graph.graph.neighbors(n) {
                    if !reached[next.index()] {
                        reached[next.index()] = true;
                        queue.push_back(next);
                    }
                }
            }
            if goals.iter().any(|g| reached[g.index()]) {
                return Ok(());
            }
            let n_reached = reached.iter().filter(|r| **r).count();
            Err(format!(
                "from {} the object can reach {n_reached} of {} states, none held by {}",
                describe_placement(cell, from),
                graph.graph.node_count(),
                describe_placement(cell, to)
            ))
        }
        Requirement::Coverage {
            workspace,
            at_least,
            mobility,
        } => {
            let reachers: Vec<&str> = cell
                .end_effectors
                .iter()
                .filter(|(_, e)| {
                    e.reaches.binary_search(workspace).is_ok()
                        && mobility.is_none_or(|m| m == e.mobility)
                })
                .map(|(_, e)| e.name.as_str())
                .collect();
            if reachers.len() as u64 >= u64::from(*at_least) {
                return Ok(());
            }
            let which = match mobility {
                Some(Mobility::Movable) => "movable end-effectors",
                Some(Mobility::Fixed) => "fixed end-effectors",
                None => "end-effectors",
            };
            let list = if reachers.is_empty() {
                "none".to_string()
            } else {
                reachers
                    .iter()
                    .map(|r| format!("`{r}`"))
                    .collect::<Vec<_>>()
                    .join(", ")
            };
            let which = if reachers.len() == 1 {
                which.trim_end_matches('s')
            } else {
                which
            };
            Err(format!(
                "`{}` is reached by {} {which} ({list}), fewer than {at_least}",
                cell.workspaces[*workspace].name,
                reachers.len()
            ))
        }
        Requirement::NoIsolatedStates { object } => {
            let mut isolated = Vec::new();
            for graph in graphs
                .iter()
                .filter(|g| object.is_none_or(|o| o == g.object))
            {
                for n in graph.graph.node_indices() {
                    let no_in = graph
                        .graph
                        .neighbors_directed(n, Direction::Incoming)
                        .next()
                        .is_none();
                    let no_out = graph
                        .graph
                        .neighbors_directed(n, Direction::Outgoing)
                        .next()
                        .is_none();
                    if no_in && no_out {
                        isolated.push(format!(
                            "{} of `{}`",
                            describe_state(cell, graph.graph[n]),
                            cell.objects[graph.object].name
                        ));
                    }
                }
            }
            match isolated.len() {
                0 => Ok(()),
                1 => Err(format!("state {} has no arcs", isolated[0])),
                n => Err(format!(
                    "{n} states have no arcs, e.g. {}",
                    isolated[..n.min(3)].join(", ")
                )),
            }
        }
    }
}
