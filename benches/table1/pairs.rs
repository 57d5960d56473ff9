//! The start/goal pairs of a row: the object's named requests, then resting states of
//! fixed surfaces in different workspaces (at the object pose of a verified witness),
//! kept only when they plan; and each placement as `cellc plan` reads it.

use std::collections::BTreeMap;

use cellc_runtime::math::{iso_from_schema, Iso};
use cellc_runtime::plan::planner::Planner;
use cellc_runtime::plan::{Goal, Placement, PlanOptions, Request};
use cellc_schema::{ArcKind, Artifact, Body, Node, ObjectId, RequestPlacement, WorkspaceId};

/// A request of the benchmark: a start and a goal placement.
#[derive(Clone)]
pub(crate) struct Pair {
    pub(crate) what: String,
    pub(crate) start: Placement,
    pub(crate) goal: Placement,
}

impl Pair {
    pub(crate) fn request(&self, object: u32, seed: u64, motions: bool) -> Request {
        Request {
            object: ObjectId(object),
            start: self.start.clone(),
            goal: Goal::Placement(self.goal.clone()),
            options: PlanOptions {
                seed,
                motions,
                ..PlanOptions::default()
            },
        }
    }
}

fn placement_of(p: &RequestPlacement) -> Placement {
    Placement {
        holder: p.end_effector,
        grasp: p.grasp,
        workspace: p.workspace,
        pose: p.pose.as_ref().map(iso_from_schema),
    }
}

/// Where an object can be: a state of a fixed holder and, in geometric cells, a pose.
fn candidates(a: &Artifact, object: u32, geometric: bool) -> Vec<(Node, Option<Iso>)> {
    let graph = &a.objects[object as usize].graph;
    let mut out = Vec::new();
    for (i, node) in graph.nodes.iter().enumerate() {
        let e = &a.end_effectors[node.end_effector.index()];
        if e.movable {
            continue;
        }
        if !geometric {
            out.push((*node, None));
            continue;
        }
        if !matches!(e.body, Body::Surface { .. }) {
            continue;
        }
        // The object pose of the first verified exchange with this resting state.
        let pose = graph.arcs.iter().find_map(|arc| {
            let touches = arc.from as usize == i || arc.to as usize == i;
            (arc.kind == ArcKind::Transition && touches)
                .then_some(arc.witness)
                .flatten()
                .map(|w| iso_from_schema(&graph.witnesses[w as usize].object))
        });
        if let Some(pose) = pose {
            out.push((*node, Some(pose)));
        }
    }
    out
}

fn placement_at(node: Node, pose: Option<Iso>) -> Placement {
    match pose {
        // A pose on a surface: located by pose, as a Cartesian request is.
        Some(pose) => Placement {
            holder: node.end_effector,
            grasp: None,
            workspace: None,
            pose: Some(pose),
        },
        None => Placement::at_state(node),
    }
}

/// Up to five pairs that plan: the named requests of the object, then resting states in
/// different workspaces, round-robin over workspace combinations.
pub(crate) fn pairs(planner: &Planner<'_>, object: u32, geometric: bool) -> Vec<Pair> {
    let a = planner.artifact();
    let name = &a.objects[object as usize].name;
    let mut proposed: Vec<Pair> = a
        .requests
        .iter()
        .filter(|r| r.object.0 == object)
        .map(|r| Pair {
            what: format!("request {}", r.name),
            start: placement_of(&r.from),
            goal: placement_of(&r.to),
        })
        .collect();
    let cands = candidates(a, object, geometric);
    let mut groups: BTreeMap<(WorkspaceId, WorkspaceId), Vec<(usize, usize)>> = BTreeMap::new();
    for (i, s) in cands.iter().enumerate() {
        for (j, g) in cands.iter().enumerate() {
            if s.0.workspace != g.0.workspace {
                groups
                    .entry((s.0.workspace, g.0.workspace))
                    .or_default()
                    .push((i, j));
            }
        }
    }
    let depth = groups.values().map(Vec::len).max().unwrap_or(0);
    for k in 0..depth {
        for list in groups.values() {
            if let Some(&(i, j)) = list.get(k) {
                let (s, g) = (cands[i], cands[j]);
                proposed.push(Pair {
                    what: format!(
                        "{} in {} -> {} in {}",
                        a.end_effectors[s.0.end_effector.index()].name,
                        a.workspaces[s.0.workspace.index()].name,
                        a.end_effectors[g.0.end_effector.index()].name,
                        a.workspaces[g.0.workspace.index()].name
                    ),
                    start: placement_at(s.0, s.1),
                    goal: placement_at(g.0, g.1),
                });
            }
        }
    }
    let mut out = Vec::new();
    for pair in proposed {
        if out.len() == 5 {
            break;
        }
        let checked = planner.plan(&pair.request(object, 0, false)).and_then(|_| {
            if geometric {
                planner.plan(&pair.request(object, 0, true)).map(|_| ())
            } else {
                Ok(())
            }
        });
        match checked {
            Ok(()) => out.push(pair),
            Err(e) => {
                let mut e = format!("{e:?}");
                e.truncate(400);
                eprintln!("  {name}: pair left out ({}): {e}", pair.what);
            }
        }
    }
    out
}

/// A placement as `cellc plan --from/--to` reads it (metres and degrees).
pub(crate) fn cli(a: &Artifact, object: u32, p: &Placement) -> String {
    let holder = &a.end_effectors[p.holder.index()].name;
    let holder = match p.grasp {
        Some(g) => format!(
            "{holder}.{}",
            a.objects[object as usize].grasps[g.index()].name
        ),
        None => holder.clone(),
    };
    let workspace = p.workspace.map(|w| &a.workspaces[w.index()].name);
    match (&p.pose, workspace) {
        (Some(pose), _) => {
            let t = pose.translation.vector;
            let (r, pi, y) = pose.rotation.euler_angles();
            format!(
                "{holder} at ({:.6}, {:.6}, {:.6}) rpy ({:.6}, {:.6}, {:.6})",
                t.x,
                t.y,
                t.z,
                r.to_degrees(),
                pi.to_degrees(),
                y.to_degrees()
            )
        }
        (None, Some(w)) => format!("{holder} in {w}"),
        (None, None) => holder,
    }
}
