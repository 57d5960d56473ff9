//! The side panel's data: each object's graph as SVG with its states, the witness
//! configuration shown when a state is clicked (the arms and the object as verification
//! found them on an arc at that state), and, for an unreachable request, the two sides
//! and the cut of the runtime's explanation in the CLI's words.

use cellc_runtime::explain::Gap;
use cellc_runtime::math::iso_from_schema;
use cellc_runtime::plan::Unreachable;
use cellc_runtime::scene::{Holder, Scene};
use cellc_schema::{Artifact, ObjectId, WorkspaceId};
use serde::Serialize;

use super::geometry::Built;
use super::timeline::{poses, Poses, Start, Whereabouts};
use cellc_driver::explain_report::words::Words;

/// Snapshots (witness configurations) at most in one page; states past it show none.
pub const MAX_SNAPSHOTS: usize = 4096;

/// A state as the panel lists it.
#[derive(Serialize)]
pub struct StateOut {
    end_effector: String,
    grasp: String,
    workspace: String,
    /// Index into the document's snapshots: a witness of an arc at this state.
    snapshot: Option<usize>,
}

/// One object's graph.
#[derive(Serialize)]
pub struct GraphOut {
    object: String,
    svg: String,
    states: Vec<StateOut>,
    pruned: usize,
}

/// Every object's graph, and the snapshots its states point at.
pub fn graphs(
    artifact: &Artifact,
    scene: Option<&Scene>,
    built: &Built,
    start: &Start,
) -> (Vec<GraphOut>, Vec<Poses>) {
    let home: Vec<Option<Vec<f64>>> = (0..artifact.end_effectors.len())
        .map(|e| match scene.and_then(|s| s.holders.get(e)) {
            Some(Holder::Arm { home, .. }) => Some(home.clone()),
            _ => start.arms.get(e).cloned().flatten(),
        })
        .collect();
    let mut snapshots = Vec::new();
    let mut out = Vec::new();
    for (o, object) in artifact.objects.iter().enumerate() {
        let graph = &object.graph;
        // The first witnessed arc at each state.
        let mut witness = vec![None; graph.nodes.len()];
        for arc in &graph.arcs {
            for n in [arc.from, arc.to] {
                if let (Some(slot @ None), Some(w)) = (witness.get_mut(n as usize), arc.witness) {
                    *slot = Some(w as usize);
                }
            }
        }
        let mut taken: Vec<(usize, usize)> = Vec::new();
        let states = graph
            .nodes
            .iter()
            .enumerate()
            .map(|(n, node)| {
                let snapshot = witness[n].and_then(|w| {
                    if let Some(&(_, s)) = taken.iter().find(|(x, _)| *x == w) {
                        return Some(s);
                    }
                    if snapshots.len() >= MAX_SNAPSHOTS || scene.is_none() {
                        return None;
                    }
                    let wit = graph.witnesses.get(w)?;
                    let mut arms = home.clone();
                    for c in &wit.configurations {
                        if let Some(slot) = arms.get_mut(c.end_effector.index()) {
                            *slot = Some(c.joints.clone());
                        }
                    }
                    let mut objects = vec![None; artifact.objects.len()];
                    objects[o] = Some(Whereabouts::Lying(iso_from_schema(&wit.object)));
                    snapshots.push(poses(built, scene, &arms, &objects));
                    taken.push((w, snapshots.len() - 1));
                    Some(snapshots.len() - 1)
                });
                StateOut {
                    end_effector: artifact.end_effector_name(node.end_effector).to_string(),
                    grasp: artifact
                        .grasp_name(ObjectId(o as u32), node.grasp)
                        .to_string(),
                    workspace: artifact.workspace_name(node.workspace).to_string(),
                    snapshot,
                }
            })
            .collect();
        out.push(GraphOut {
            object: object.name.clone(),
            svg: crate::commands::graph::svg(artifact, object),
            states,
            pruned: graph.pruned.len(),
        });
    }
    (out, snapshots)
}

/// An arc the explanation says was lost (pruned, or failed during the request).
#[derive(Serialize)]
pub struct LostOut {
    from: u32,
    to: u32,
    text: String,
}

/// Why a request has no plan, for the panel and the scene.
#[derive(Serialize)]
pub struct ExplanationOut {
    object: String,
    start: u32,
    goals: Vec<u32>,
    start_side: Vec<u32>,
    goal_side: Vec<u32>,
    cut: Vec<String>,
    lost: Vec<LostOut>,
    /// Workspaces the cut is about (highlighted in the scene).
    workspaces: Vec<String>,
}

fn gap_workspaces(gap: &Gap) -> Vec<WorkspaceId> {
    match gap {
        Gap::NoTransition { workspaces, .. }
        | Gap::InfeasibleTransition { workspaces, .. }
        | Gap::NoHand { workspaces, .. } => workspaces.clone(),
        Gap::InfeasibleMove { from, to, .. } | Gap::NotAdjacent { from, to, .. } => {
            vec![*from, *to]
        }
        Gap::OnlyFixed {
            near_workspaces,
            far_workspaces,
            ..
        } => near_workspaces
            .iter()
            .chain(far_workspaces)
            .copied()
            .collect(),
        Gap::Apart { shared, .. } => shared.clone(),
        Gap::NoCommonWorkspace { .. } => Vec::new(),
    }
}

/// The explanation of `u` (`None` when its start or goals are no states of the graph).
pub fn explanation(artifact: &Artifact, u: &Unreachable) -> Option<ExplanationOut> {
    let object = artifact.objects.get(u.object.index())?;
    let ex = cellc_runtime::explain::explain(artifact, u).ok()?;
    let words = Words::new(artifact, object);
    let ids = |v: &[cellc_schema::NodeId]| v.iter().map(|n| n.0).collect::<Vec<u32>>();
    let mut workspaces: Vec<WorkspaceId> =
        ex.cut.iter().flat_map(|c| gap_workspaces(&c.gap)).collect();
    workspaces.sort_unstable();
    workspaces.dedup();
    Some(ExplanationOut {
        object: object.name.clone(),
        start: ex.start.0,
        goals: ids(&ex.goals),
        start_side: ids(&ex.start_side.states),
        goal_side: ids(&ex.goal_side.states),
        cut: ex.cut.iter().map(|c| words.gap_text(&c.gap)).collect(),
        lost: ex
            .pruned
            .iter()
            .map(|l| LostOut {
                from: l.from.0,
                to: l.to.0,
                text: words.lost_text(l),
            })
            .collect(),
        workspaces: workspaces
            .iter()
            .map(|&w| artifact.workspace_name(w).to_string())
            .collect(),
    })
}
