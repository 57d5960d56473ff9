//! Unreachable goals as diagnostics: what the start can reach, what the goal needs, the
//! cut between them and what to change, labelled at the cell's source lines.

use cellc_lang::{Diagnostic, FileId, Span};
use cellc_runtime::plan::Unreachable;
use cellc_schema::{Artifact, Node};

use crate::commands::plan::codes;

fn state(artifact: &Artifact, object: u32, n: &Node) -> String {
    let obj = &artifact.objects[object as usize];
    format!(
        "(`{}`, `{}`, `{}`)",
        artifact
            .end_effectors
            .get(n.end_effector as usize)
            .map_or("?", |e| e.name.as_str()),
        obj.grasps
            .get(n.grasp as usize)
            .map_or("?", |g| g.name.as_str()),
        artifact
            .workspaces
            .get(n.workspace as usize)
            .map_or("?", |w| w.name.as_str())
    )
}

/// The diagnostic of an unreachable goal.
pub fn unreachable(artifact: &Artifact, u: &Unreachable) -> Diagnostic {
    let object = &artifact.objects[u.object as usize];
    let goal = match u.goals.as_slice() {
        [one] => state(artifact, u.object, one),
        many => format!("any of {} goal states", many.len()),
    };
    let mut d = Diagnostic::error(
        codes::UNREACHABLE,
        format!(
            "no plan moves `{}` from {} to {goal}",
            object.name,
            state(artifact, u.object, &u.start)
        ),
    );
    if let Some(s) = artifact.spans.get(object.span as usize) {
        d = d.primary(
            FileId(s.file),
            Span {
                start: s.start,
                end: s.end,
            },
            "the object's graph has no path",
        );
    }
    d = d.note(format!(
        "from the start the object can reach {} of {} states",
        u.reachable.len(),
        object.graph.nodes.len()
    ));
    for (arc, reason) in u.failed.iter().take(5) {
        let from = object.graph.nodes[arc.from as usize];
        let to = object.graph.nodes[arc.to as usize];
        d = d.note(format!(
            "{} -> {} failed: {reason:?}",
            state(artifact, u.object, &from),
            state(artifact, u.object, &to)
        ));
    }
    d.help("add a transition or reach that joins what the start reaches to what the goal needs")
}
