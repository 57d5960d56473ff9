//! Verification findings as diagnostics: pruned arcs as warnings that point at the
//! declarations that made them (each reason worded as the explanations of unreachable
//! goals word it, by `explain_report::words::infeasibility`), and scene problems (stale or
//! broken robot models) as runtime errors.

use std::collections::BTreeMap;

use cellc_lang::{Code, Diagnostic, FileId, Span};
use cellc_runtime::scene::SceneError;
use cellc_schema::{ArcKind, Artifact, EndEffectorId, GraspId, Infeasibility, Object};

use crate::explain_report::words::infeasibility;

/// Codes of verification and of loading a scene (the registry's `cellc_lang::codes::verify`).
pub use cellc_lang::codes::verify as codes;

/// A scene that cannot be built, labelled at the robot's declaration when the artifact
/// knows it.
pub fn scene_error_at(
    error: &SceneError,
    robots: &[cellc_schema::Robot],
    spans: &[cellc_schema::SourceSpan],
) -> Diagnostic {
    let robot = match error {
        SceneError::StaleUrdf { robot, .. }
        | SceneError::Robot { robot, .. }
        | SceneError::JointCount { robot, .. } => Some(robot),
        _ => None,
    };
    let place = robot
        .and_then(|name| robots.iter().find(|r| &r.name == name))
        .and_then(|r| span(spans, r.span));
    let d = scene_error(error);
    match place {
        Some((file, at)) => d.primary(file, at, "robot declared here"),
        None => d,
    }
}

/// A scene that cannot be built.
pub fn scene_error(error: &SceneError) -> Diagnostic {
    let (code, help): (Code, &str) = match error {
        SceneError::StaleUrdf { .. } => (
            codes::STALE_URDF,
            "rebuild the artifact from its cell (`cellc build CELL`) so that it matches the robot model",
        ),
        SceneError::Mesh { .. } | SceneError::HandMesh { .. } => (
            codes::MODEL_UNUSABLE,
            "fix the mesh file: an STL or OBJ whose vertices enclose a volume, within the limits `cellc explain R0002` lists",
        ),
        SceneError::JointCount { .. } => (
            codes::MODEL_UNUSABLE,
            "rebuild the artifact from its cell (`cellc build CELL`): it does not match the robot model",
        ),
        _ => (
            codes::MODEL_UNUSABLE,
            "fix the robot model file (collision geometry as URDF primitives, or STL/OBJ meshes next to the URDF)",
        ),
    };
    Diagnostic::error(code, error.to_string()).help(help)
}

fn span(spans: &[cellc_schema::SourceSpan], index: u32) -> Option<(FileId, Span)> {
    let s = spans.get(index as usize)?;
    Some((
        FileId(s.file),
        Span {
            start: s.start,
            end: s.end,
        },
    ))
}

fn ee(artifact: &Artifact, e: EndEffectorId) -> &str {
    artifact.end_effector_name(e)
}

fn describe_arc(artifact: &Artifact, object: &Object, arc: &cellc_schema::Arc) -> String {
    let from = object.graph.nodes[arc.from as usize];
    let to = object.graph.nodes[arc.to as usize];
    let grasp = |g: GraspId| {
        object
            .grasps
            .get(g.index())
            .map_or("?", |g| g.name.as_str())
    };
    let ws = artifact
        .workspaces
        .get(to.workspace.index())
        .map_or("?", |w| w.name.as_str());
    match arc.kind {
        ArcKind::Move => format!(
            "`{}` holding `{}` in `{ws}`",
            ee(artifact, to.end_effector),
            grasp(to.grasp)
        ),
        ArcKind::Transition => format!(
            "`{}` (`{}`) to `{}` (`{}`) in `{ws}`",
            ee(artifact, from.end_effector),
            grasp(from.grasp),
            ee(artifact, to.end_effector),
            grasp(to.grasp)
        ),
    }
}

/// One warning per (object, declaration, reason kind), listing the arcs it removed.
pub fn pruned_warnings(artifact: &Artifact) -> Vec<Diagnostic> {
    let mut groups: BTreeMap<(usize, u32, String), Vec<(String, String)>> = BTreeMap::new();
    for (o, object) in artifact.objects.iter().enumerate() {
        for pruned in &object.graph.pruned {
            let reason = infeasibility(artifact, &pruned.reason);
            let kind = match &pruned.reason {
                Infeasibility::NoIkSolution { .. } | Infeasibility::NoClosedChain { .. } => "ik",
                Infeasibility::Collision { .. } => "collision",
                _ => "placement",
            };
            groups
                .entry((o, pruned.arc.source, kind.to_string()))
                .or_default()
                .push((describe_arc(artifact, object, &pruned.arc), reason));
        }
    }
    let mut diagnostics = Vec::new();
    for ((o, source, _), arcs) in groups {
        let object = &artifact.objects[o];
        let n = arcs.len();
        let (first_arc, first_reason) = &arcs[0];
        let message = if n == 1 {
            format!(
                "an arc of `{}` is infeasible and was pruned: {first_arc}",
                object.name
            )
        } else {
            format!(
                "{n} arcs of `{}` are infeasible and were pruned, e.g. {first_arc}",
                object.name
            )
        };
        let mut d = Diagnostic::warning(codes::PRUNED_ARC, message);
        if let Some((file, span)) = span(&artifact.spans, source) {
            d = d.primary(file, span, first_reason.clone());
        }
        // The grasps involved, so the engineer sees which poses to change.
        let mut grasp_spans: Vec<u32> = Vec::new();
        for pruned in object
            .graph
            .pruned
            .iter()
            .filter(|p| p.arc.source == source)
        {
            for node in [pruned.arc.from, pruned.arc.to] {
                let g = object.graph.nodes[node as usize].grasp;
                if let Some(grasp) = object.grasps.get(g.index()) {
                    if grasp.span != source && !grasp_spans.contains(&grasp.span) {
                        grasp_spans.push(grasp.span);
                    }
                }
            }
        }
        for s in grasp_spans.into_iter().take(4) {
            if let Some((file, span)) = span(&artifact.spans, s) {
                d = d.secondary(file, span, "grasp involved");
            }
        }
        let mut seen = vec![format!("{first_arc}: {first_reason}")];
        for (arc, reason) in arcs.iter().skip(1) {
            let note = format!("{arc}: {reason}");
            if seen.contains(&note) || seen.len() > 4 {
                continue;
            }
            d = d.note(format!("also {note}"));
            seen.push(note);
        }
        if n > 5 {
            d = d.note(format!("and {} more", n - 5));
        }
        diagnostics.push(d.help(
            "move the grasp or resting pose, or the arms or surfaces, so the pose is reachable and free; `cellc build --no-verify` keeps every arc",
        ));
    }
    diagnostics
}
