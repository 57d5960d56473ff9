//! The cell and explanations as JSON for the service: names, metres and radians, so a
//! client needs no artifact to form its requests.

use cellc_runtime::explain::{Cause, Explanation};
use cellc_runtime::NodeId;
use cellc_schema::{Aabb, Artifact, Body, Holder, ObjectId};
use serde_json::{json, Value};

use cellc_driver::explain_report::words::Words;

/// `GET /v1/cell`: objects (grasps and resting poses), end-effectors, workspaces (boxes),
/// arms (joints with limits, home), and the cell's named requests and tasks.
pub fn cell(a: &Artifact) -> Value {
    let holder = |h: Holder| match h {
        Holder::EndEffector(e) => a.end_effectors.get(e as usize).map(|e| e.name.as_str()),
        Holder::Kind(k) => a.holder_kinds.get(k as usize).map(|k| k.name.as_str()),
    };
    let objects: Vec<Value> = a
        .objects
        .iter()
        .map(|o| {
            let poses = |rest: bool| -> Vec<Value> {
                o.grasps
                    .iter()
                    .filter(|g| g.rest == rest)
                    .map(|g| json!({"name": g.name, "label": g.label, "holder": holder(g.holder)}))
                    .collect()
            };
            json!({
                "name": o.name,
                "grasps": poses(false),
                "resting_poses": poses(true),
                "states": o.graph.nodes.len(),
                "arcs": o.graph.arcs.len(),
            })
        })
        .collect();
    let end_effectors: Vec<Value> = a
        .end_effectors
        .iter()
        .map(|e| {
            let body = match e.body {
                Body::Arm { .. } => "arm",
                Body::Surface { .. } => "surface",
                _ => "abstract",
            };
            json!({
                "name": e.name,
                "movable": e.movable,
                "body": body,
                "kind": e.kind.and_then(|k| a.holder_kinds.get(k as usize)).map(|k| &k.name),
                "reaches": e.reaches.iter().filter_map(|&w| a.workspaces.get(w as usize)).map(|w| &w.name).collect::<Vec<_>>(),
            })
        })
        .collect();
    let workspaces: Vec<Value> = a
        .workspaces
        .iter()
        .map(|w| {
            json!({
                "name": w.name,
                "label": w.label,
                "boxes": w.boxes.iter().map(aabb).collect::<Vec<_>>(),
                "derived": w.derived,
            })
        })
        .collect();
    let arms: Vec<Value> = a
        .end_effectors
        .iter()
        .filter_map(|e| match &e.body {
            Body::Arm { robot, home, .. } => {
                let robot = a.robots.get(*robot as usize)?;
                Some(json!({
                    "name": e.name,
                    "robot": robot.name,
                    "joints": robot.joints.iter().map(|j| json!({
                        "name": j.name,
                        "prismatic": j.prismatic,
                        "lower": j.lower,
                        "upper": j.upper,
                    })).collect::<Vec<_>>(),
                    "home": home,
                }))
            }
            _ => None,
        })
        .collect();
    json!({
        "cell": a.cell,
        "objects": objects,
        "end_effectors": end_effectors,
        "workspaces": workspaces,
        "arms": arms,
        "requests": a.requests.iter().map(|r| &r.name).collect::<Vec<_>>(),
        "tasks": a.tasks.iter().map(|t| &t.name).collect::<Vec<_>>(),
    })
}

fn aabb(b: &Aabb) -> Value {
    json!({"min": b.min, "max": b.max})
}

/// The structured explanation of an unreachable request, built from its fields with
/// the words of `cellc plan`'s R0004 (the runtime's type is not serialisable).
pub fn explanation(a: &Artifact, e: &Explanation) -> Value {
    let Some(object) = a.objects.get(e.object.index()) else {
        return Value::Null;
    };
    let words = Words::new(a, object);
    let state = |n: NodeId| {
        object.graph.nodes.get(n.index()).map(|s| {
            json!({
                "end_effector": a.end_effector_name(s.end_effector),
                "grasp": a.grasp_name(e.object, s.grasp),
                "workspace": a.workspace_name(s.workspace),
            })
        })
    };
    let states = |list: &[NodeId]| list.iter().map(|&n| state(n)).collect::<Vec<_>>();
    let cause = match e.cause {
        Cause::Missing => "missing",
        Cause::Pruned => "pruned",
        Cause::Failed => "failed",
        Cause::Connected => "connected",
    };
    json!({
        "object": a.object_name(ObjectId(e.object.0)),
        "cause": cause,
        "start": state(e.start),
        "goals": states(&e.goals),
        "start_side": states(&e.start_side.states),
        "goal_side": states(&e.goal_side.states),
        "must_leave": e.must_leave,
        "cut": e.cut.iter().map(|c| json!({
            "kind": format!("{:?}", c.gap.kind()),
            "text": words.gap_text(&c.gap),
        })).collect::<Vec<_>>(),
        "cut_omitted": e.cut_omitted,
        "suggestions": e.suggestions.iter().map(|s| json!({
            "text": words.suggestion_text(s),
            "cost": s.cost,
        })).collect::<Vec<_>>(),
        "pruned": e.pruned.iter().map(|l| json!({
            "from": state(l.from),
            "to": state(l.to),
            "failed": l.failed,
            "text": words.lost_text(l),
        })).collect::<Vec<_>>(),
        "pruned_omitted": e.pruned_omitted,
    })
}
