//! The rows of a dual_manipulation database, checked against each other and written as
//! an abstract-form cell.
//!
//! The translation keeps every row: a workspace per `Workspaces` row, an `adjacent` line
//! per adjacent pair, an end-effector per `EndEffectors` row with its `Reachability`, an
//! object per `Objects` row, a grasp per `Grasps` row and exactly one directed transition
//! per `Grasp_transitions` row (a pair of rows A -> B and B -> A is written `A <-> B`).
//! Asymmetric transitions and transitions between two grasps of one end-effector are kept:
//! `cellc check` warns about them. Rows that no cell can hold without errors (a
//! transition between two objects or two fixed end-effectors, a workspace nobody
//! reaches, ...) are reported instead, with what to change in the database.
//!
//! Names: the database's names are kept where they can be (quoted with backticks when
//! they are not plain identifiers or are reserved words). Workspaces, end-effectors and
//! objects share one namespace in a cell: a name several of them have gets `_ws<Id>`,
//! `_ee<Id>` or `_obj<Id>` on each. A grasp name several grasps of one object have gets
//! `_<end-effector>` when that tells them apart, otherwise `_<Grasp_id>`. A generated
//! name never takes a name the database has; if it is taken anyway, `_2`, `_3`, ... follow.
//! Every declaration carries its row id in a trailing comment, and a workspace's and a
//! grasp's label is the database name, so the cell leads back to the rows.

use std::collections::{BTreeMap, BTreeSet, HashMap, HashSet};

use cellc_lang::Diagnostic;

use super::diagnostics::{self as diag, shown};
use super::{Database, EndEffectorRow, GraspRow, ObjectRow, WorkspaceRow};

/// A cell made from a database, before formatting.
#[derive(Clone, Debug)]
pub struct Converted {
    /// The cell's name (without quotes).
    pub cell_name: String,
    /// The cell text (parses; not yet in the canonical layout).
    pub text: String,
    /// `Grasp_id` -> (object name, grasp name), as written in the cell.
    pub grasps: BTreeMap<i64, (String, String)>,
}

/// Checks the rows and writes the cell; `file_name` is the database's file name (the cell
/// is named after it and the header says where the cell came from).
pub fn convert(db: &Database, file_name: &str) -> Result<Converted, Vec<Diagnostic>> {
    let problems = check(db);
    if !problems.is_empty() {
        return Err(diag::limit(problems));
    }
    Ok(write(db, file_name))
}

// ---- checks ----------------------------------------------------------------------------

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

// ---- names -----------------------------------------------------------------------------

/// A database name as a cell name: backticks and control characters (which a quoted name
/// cannot hold) are replaced; NULL or empty gives the fallback.
fn base_name(name: Option<&str>, fallback: String) -> String {
    let cleaned: String = name
        .unwrap_or_default()
        .chars()
        .map(|c| match c {
            '`' => '\'',
            c if c.is_control() => '_',
            c => c,
        })
        .collect();
    if cleaned.is_empty() {
        fallback
    } else {
        cleaned
    }
}

/// Makes names unique: a base name that only one entry has is kept; entries sharing a base
/// get `base_suffix`. Generated names avoid every base name and each other.
fn unique(entries: &[(String, String)]) -> Vec<String> {
    let mut count: HashMap<&str, usize> = HashMap::new();
    for (base, _) in entries {
        *count.entry(base.as_str()).or_default() += 1;
    }
    let mut taken: HashSet<String> = entries.iter().map(|(b, _)| b.clone()).collect();
    entries
        .iter()
        .map(|(base, suffix)| {
            if count[base.as_str()] == 1 {
                return base.clone();
            }
            let first = format!("{base}_{suffix}");
            let mut candidate = first.clone();
            let mut n = 2;
            while taken.contains(&candidate) {
                candidate = format!("{first}_{n}");
                n += 1;
            }
            taken.insert(candidate.clone());
            candidate
        })
        .collect()
}

/// A name as cell text: plain when it can be, else in backticks.
fn name(text: &str) -> String {
    if cellc_lang::ast::needs_quotes(text) || cellc_lang::phrases::RESERVED.contains(&text) {
        format!("`{text}`")
    } else {
        text.to_string()
    }
}

/// A string literal (as the formatter escapes it).
fn string(text: &str) -> String {
    let mut out = String::with_capacity(text.len() + 2);
    out.push('"');
    for c in text.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\t' => out.push_str("\\t"),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

/// Text for a comment: one line, whatever the database holds.
fn comment_text(text: &str) -> String {
    string(text)
        .chars()
        .map(|c| if c.is_control() { ' ' } else { c })
        .collect()
}

/// The names every row gets in the cell.
struct Names {
    cell: String,
    workspaces: HashMap<i64, String>,
    end_effectors: HashMap<i64, String>,
    objects: HashMap<i64, String>,
    grasps: HashMap<i64, String>,
}

fn names(db: &Database, file_name: &str) -> Names {
    let stem = file_name
        .rsplit_once('.')
        .map_or(file_name, |(stem, _)| stem);
    let cell = base_name(Some(stem), "imported".to_string());

    let mut entries: Vec<(String, String)> = Vec::new();
    for w in &db.workspaces {
        entries.push((
            base_name(w.name.as_deref(), format!("workspace_{}", w.id)),
            format!("ws{}", w.id),
        ));
    }
    for e in &db.end_effectors {
        entries.push((
            base_name(e.name.as_deref(), format!("end_effector_{}", e.id)),
            format!("ee{}", e.id),
        ));
    }
    for o in &db.objects {
        entries.push((
            base_name(o.name.as_deref(), format!("object_{}", o.id)),
            format!("obj{}", o.id),
        ));
    }
    let mut unique_names = unique(&entries).into_iter();
    let mut take = |ids: Vec<i64>| -> HashMap<i64, String> {
        ids.into_iter().zip(unique_names.by_ref()).collect()
    };
    let workspaces = take(db.workspaces.iter().map(|r| r.id).collect());
    let end_effectors = take(db.end_effectors.iter().map(|r| r.id).collect());
    let objects = take(db.objects.iter().map(|r| r.id).collect());

    let mut grasps = HashMap::new();
    for o in &db.objects {
        let of_object: Vec<&GraspRow> = db.grasps.iter().filter(|g| g.object == o.id).collect();
        let bases: Vec<String> = of_object
            .iter()
            .map(|g| base_name(g.name.as_deref(), format!("grasp_{}", g.id)))
            .collect();
        let mut per_holder: HashMap<(&str, i64), usize> = HashMap::new();
        for (g, base) in of_object.iter().zip(&bases) {
            *per_holder
                .entry((base.as_str(), g.end_effector))
                .or_default() += 1;
        }
        let entries: Vec<(String, String)> = of_object
            .iter()
            .zip(&bases)
            .map(|(g, base)| {
                let suffix = if per_holder[&(base.as_str(), g.end_effector)] == 1 {
                    end_effectors[&g.end_effector].clone()
                } else {
                    g.id.to_string()
                };
                (base.clone(), suffix)
            })
            .collect();
        for (g, unique_name) in of_object.iter().zip(unique(&entries)) {
            grasps.insert(g.id, unique_name);
        }
    }
    Names {
        cell,
        workspaces,
        end_effectors,
        objects,
        grasps,
    }
}

// ---- text ------------------------------------------------------------------------------

/// Transition lines are filled up to this width (the formatter never wraps lines, so the
/// import keeps them readable itself).
const WIDTH: usize = 100;

fn write(db: &Database, file_name: &str) -> Converted {
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
