//! The cell text: header, workspaces, adjacencies, end-effectors, objects with grasps and
//! transitions, each declaration with its row id in a trailing comment.

use std::collections::{BTreeMap, BTreeSet, HashMap};

use super::names::{comment_text, names, string};
use super::Converted;
use crate::import::{Database, GraspRow};
use cellc_lang::written_name as name;

/// Transition lines are filled up to this width (the formatter never wraps lines, so the
/// import keeps them readable itself).
const WIDTH: usize = 100;

pub(super) fn write(db: &Database, file_name: &str) -> Converted {
    let names = names(db, file_name);
    let mut out = String::new();
    let mut line = |text: &str| {
        out.push_str(text);
        out.push('\n');
    };

    // Header.
    let transitions: BTreeSet<(i64, i64)> = db
        .transitions
        .iter()
        .map(|t| (t.source, t.target))
        .collect();
    line(&format!(
        "// Imported from {} by `cellc import dualmanip`: the grasp database of the",
        comment_text(file_name)
    ));
    line("// dual_manipulation planner (Marino et al., RA-L 2016). Regenerate it rather than edit it.");
    line(&format!(
        "// Rows: {} workspaces, {} end-effectors, {} objects, {} grasps, {} transitions.",
        db.workspaces.len(),
        db.end_effectors.len(),
        db.objects.len(),
        db.grasps.len(),
        db.transitions.len()
    ));
    line("//");
    line("// Each declaration ends with the id of its row; the label of a workspace or a grasp is");
    line("// its name in the database. Names several workspaces, end-effectors or objects share");
    line(
        "// (one namespace in a cell) get `_ws<Id>`, `_ee<Id>` or `_obj<Id>`; a grasp name several",
    );
    line("// grasps of one object share gets `_<end-effector>` when that tells them apart, else");
    line("// `_<Grasp_id>`. Each Grasp_transitions row is one directed transition; `a <-> b` is");
    line(
        "// the two rows a -> b and b -> a. Geometry (WorkspaceGeometry, ObjectCenter, Grasp_info)",
    );
    line("// is not imported.");
    let merged = [
        (
            "Grasp_transitions",
            db.transitions.len() - transitions.len(),
        ),
        (
            "Reachability",
            db.reachability.len() - db.reachability.iter().collect::<BTreeSet<_>>().len(),
        ),
        (
            "WorkspacesAdjacency",
            db.adjacency.len() - db.adjacency.iter().collect::<BTreeSet<_>>().len(),
        ),
    ];
    for (table, n) in merged {
        if n > 0 {
            line(&format!(
                "// {n} duplicate {} of {table} {} written once.",
                if n == 1 { "row" } else { "rows" },
                if n == 1 { "is" } else { "are" }
            ));
        }
    }
    line("");
    line(&format!("cell {} {{", name(&names.cell)));

    // Workspaces and adjacency.
    for w in &db.workspaces {
        let label = w
            .name
            .as_deref()
            .map(|n| format!(" {}", string(n)))
            .unwrap_or_default();
        line(&format!(
            "  workspace {}{label} // Workspaces.Id {}",
            name(&names.workspaces[&w.id]),
            w.id
        ));
    }
    let mut pairs: BTreeMap<(i64, i64), Vec<(i64, i64)>> = BTreeMap::new();
    for a in &db.adjacency {
        let rows = pairs
            .entry((a.source.min(a.target), a.source.max(a.target)))
            .or_default();
        if !rows.contains(&(a.source, a.target)) {
            rows.push((a.source, a.target));
        }
    }
    for ((a, b), rows) in &pairs {
        let rows: Vec<String> = rows.iter().map(|(s, t)| format!("({s}, {t})")).collect();
        line(&format!(
            "  adjacent {} {} // WorkspacesAdjacency {}",
            name(&names.workspaces[a]),
            name(&names.workspaces[b]),
            rows.join(", ")
        ));
    }

    // End-effectors.
    if !db.end_effectors.is_empty() {
        line("");
    }
    let position: HashMap<i64, usize> = db
        .workspaces
        .iter()
        .enumerate()
        .map(|(i, w)| (w.id, i))
        .collect();
    for e in &db.end_effectors {
        let mut reached: Vec<i64> = db
            .reachability
            .iter()
            .filter(|r| r.end_effector == e.id)
            .map(|r| r.workspace)
            .collect();
        reached.sort_by_key(|w| position[w]);
        reached.dedup();
        let reached: Vec<String> = reached.iter().map(|w| name(&names.workspaces[w])).collect();
        let keyword = if e.movable == 1 { "movable" } else { "fixed" };
        line(&format!(
            "  {keyword} {} reaches {} // EndEffectors.Id {}{}",
            name(&names.end_effectors[&e.id]),
            reached.join(", "),
            e.id,
            renamed(e.name.as_deref(), &names.end_effectors[&e.id])
        ));
    }

    // Objects.
    let mut grasp_names = BTreeMap::new();
    for o in &db.objects {
        line("");
        let object_name = &names.objects[&o.id];
        let mesh = o
            .mesh_path
            .as_deref()
            .map(|m| format!(", MeshPath {}", comment_text(m)))
            .unwrap_or_default();
        line(&format!(
            "  object {} {{ // Objects.Id {}{}{mesh}",
            name(object_name),
            o.id,
            renamed(o.name.as_deref(), object_name)
        ));
        let grasps: Vec<&GraspRow> = db.grasps.iter().filter(|g| g.object == o.id).collect();
        for g in &grasps {
            let label = g
                .name
                .as_deref()
                .map(|n| format!(" {}", string(n)))
                .unwrap_or_default();
            line(&format!(
                "    grasp {}{label} by {} // Grasp_id {}",
                name(&names.grasps[&g.id]),
                name(&names.end_effectors[&g.end_effector]),
                g.id
            ));
            grasp_names.insert(g.id, (object_name.clone(), names.grasps[&g.id].clone()));
        }
        let ids: BTreeSet<i64> = grasps.iter().map(|g| g.id).collect();
        let mine: Vec<(i64, i64)> = transitions
            .iter()
            .copied()
            .filter(|(s, _)| ids.contains(s))
            .collect();
        if !mine.is_empty() {
            line("");
        }
        for text in transition_lines(&mine, &transitions, &names.grasps) {
            line(&text);
        }
        line("  }");
    }
    line("}");
    Converted {
        cell_name: names.cell,
        text: out,
        grasps: grasp_names,
    }
}

/// `, Name "..."` when the cell name is not the database name.
fn renamed(original: Option<&str>, cell_name: &str) -> String {
    match original {
        Some(n) if n == cell_name => String::new(),
        Some(n) => format!(", Name {}", comment_text(n)),
        None => ", Name NULL".to_string(),
    }
}

/// The transitions of one object: for each source grasp (by id), `<->` to the grasps it
/// has rows with both ways (written at the smaller id), then `->` to the others, lines
/// filled up to [`WIDTH`].
fn transition_lines(
    mine: &[(i64, i64)],
    all: &BTreeSet<(i64, i64)>,
    grasp_names: &HashMap<i64, String>,
) -> Vec<String> {
    let mut both: BTreeMap<i64, Vec<i64>> = BTreeMap::new();
    let mut one: BTreeMap<i64, Vec<i64>> = BTreeMap::new();
    for &(s, t) in mine {
        if s != t && all.contains(&(t, s)) {
            if s < t {
                both.entry(s).or_default().push(t);
            }
        } else {
            one.entry(s).or_default().push(t);
        }
    }
    let sources: BTreeSet<i64> = both.keys().chain(one.keys()).copied().collect();
    let mut lines = Vec::new();
    for s in sources {
        for (arrow, targets) in [("<->", both.get(&s)), ("->", one.get(&s))] {
            let Some(targets) = targets else { continue };
            let head = format!("    transition {} {arrow} ", name(&grasp_names[&s]));
            let mut current = head.clone();
            let mut count = 0;
            for t in targets {
                let target = name(&grasp_names[t]);
                let width = target.chars().count();
                let extra = if count == 0 { width } else { width + 2 };
                if count > 0 && current.chars().count() + extra > WIDTH {
                    lines.push(current);
                    current = head.clone();
                    count = 0;
                }
                if count > 0 {
                    current.push_str(", ");
                }
                current.push_str(&target);
                count += 1;
            }
            lines.push(current);
        }
    }
    lines
}
