//! An object-state graph as SVG, laid out here without Graphviz (`cellc graph --emit
//! svg`, and the side panel of `cellc view`).
//!
//! The layout is a grid that follows the graph's own structure rather than a general
//! graph drawing: one column (a cluster, as in the DOT output) per workspace, ordered
//! along the moves so that neighbouring workspaces stand side by side, one row
//! band per end-effector, so a state S(e, g, w) sits at (row of e, column of w), its
//! grasps side by side (wrapping after [`WRAP`]). Moves keep the end-effector and grasp
//! and change the workspace, so they run along a row between clusters; transitions keep
//! the workspace and change the end-effector, so they run up and down inside one
//! cluster. Arcs both ways are drawn once with two arrow heads; arcs verification pruned
//! are drawn grey, dotted, with their reason as a tooltip. The drawing is linear in the
//! graph's size and the same graph always gives the same bytes.

use std::collections::BTreeMap;
use std::fmt::Write;

use cellc_schema::{ArcKind, Artifact, Object};

/// Grasps side by side in one cell of the grid before wrapping.
pub const WRAP: usize = 3;
const W: f64 = 104.0;
const H: f64 = 34.0;
const GAP: f64 = 10.0;
const PAD: f64 = 12.0;
const LABEL: f64 = 22.0;
const COLUMN_GAP: f64 = 48.0;
/// How far an arc bends away from the straight line at most; the drawing keeps this
/// margin below the clusters for the bends of the last row.
const MAX_BEND: f64 = 24.0;

/// Escapes text for XML.
pub fn xml(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            c if c.is_control() => out.push(' '),
            c => out.push(c),
        }
    }
    out
}

/// Where each state of the graph is drawn (centres), and the drawing's size.
pub struct Layout {
    /// Centre of each node.
    pub centres: Vec<(f64, f64)>,
    /// Clusters: workspace index and rectangle (x, y, width, height).
    pub clusters: Vec<(usize, [f64; 4])>,
    /// Width.
    pub width: f64,
    /// Height.
    pub height: f64,
}

/// The grid layout of `o`'s graph.
pub fn layout(o: &Object) -> Layout {
    let nodes = &o.graph.nodes;
    // Columns and rows that have states, in declaration order.
    let mut columns: Vec<usize> = nodes.iter().map(|n| n.workspace.index()).collect();
    columns.sort_unstable();
    columns.dedup();
    let mut rows: Vec<usize> = nodes.iter().map(|n| n.end_effector.index()).collect();
    rows.sort_unstable();
    rows.dedup();
    let columns = along_moves(o, &columns);
    let col_of: BTreeMap<usize, usize> = columns.iter().enumerate().map(|(i, &c)| (c, i)).collect();
    let row_of: BTreeMap<usize, usize> = rows.iter().enumerate().map(|(i, &r)| (r, i)).collect();
    // Nodes of each grid cell, by grasp.
    let mut cells: BTreeMap<(usize, usize), Vec<usize>> = BTreeMap::new();
    for (i, n) in nodes.iter().enumerate() {
        cells
            .entry((
                row_of[&n.end_effector.index()],
                col_of[&n.workspace.index()],
            ))
            .or_default()
            .push(i);
    }
    for v in cells.values_mut() {
        v.sort_by_key(|&i| (nodes[i].grasp.index(), i));
    }
    let mut slots = vec![1usize; columns.len()];
    for (&(_, c), v) in &cells {
        slots[c] = slots[c].max(v.len().min(WRAP));
    }
    let mut lines = vec![1usize; rows.len()];
    for (&(r, c), v) in &cells {
        lines[r] = lines[r].max(v.len().div_ceil(slots[c]));
    }
    let mut xs = Vec::with_capacity(columns.len());
    let mut x = 0.0;
    for &s in &slots {
        xs.push(x);
        x += s as f64 * W + (s as f64 - 1.0) * GAP + 2.0 * PAD + COLUMN_GAP;
    }
    let width = (x - COLUMN_GAP).max(W);
    let mut ys = Vec::with_capacity(rows.len());
    let mut y = LABEL + PAD;
    for &l in &lines {
        ys.push(y);
        y += l as f64 * (H + GAP);
    }
    let height = y + PAD - GAP + MAX_BEND;
    let mut centres = vec![(0.0, 0.0); nodes.len()];
    for (&(r, c), v) in &cells {
        for (k, &i) in v.iter().enumerate() {
            let (line, slot) = (k / slots[c], k % slots[c]);
            centres[i] = (
                xs[c] + PAD + slot as f64 * (W + GAP) + W / 2.0,
                ys[r] + line as f64 * (H + GAP) + H / 2.0,
            );
        }
    }
    let clusters = columns
        .iter()
        .enumerate()
        .map(|(c, &w)| {
            let cw = slots[c] as f64 * W + (slots[c] as f64 - 1.0) * GAP + 2.0 * PAD;
            (w, [xs[c], 0.0, cw, height - MAX_BEND])
        })
        .collect();
    Layout {
        centres,
        clusters,
        width,
        height,
    }
}

/// The workspaces in an order that keeps moves short: from an end of the chain the moves
/// make (a workspace with the fewest neighbours, the first declared among equals), each
/// next one the unplaced workspace with the most moves to the last placed (the first
/// declared when none has any). Greedy and linear in the moves times the workspaces.
fn along_moves(o: &Object, columns: &[usize]) -> Vec<usize> {
    let mut links: BTreeMap<(usize, usize), usize> = BTreeMap::new();
    for arc in o.graph.arcs.iter().filter(|a| a.kind == ArcKind::Move) {
        let (Some(a), Some(b)) = (
            o.graph.nodes.get(arc.from as usize),
            o.graph.nodes.get(arc.to as usize),
        ) else {
            continue;
        };
        let (a, b) = (a.workspace.index(), b.workspace.index());
        if a != b {
            *links.entry((a.min(b), a.max(b))).or_default() += 1;
        }
    }
    // Neighbours of each column with the number of moves between them.
    let mut near: BTreeMap<usize, Vec<(usize, usize)>> = BTreeMap::new();
    for (&(a, b), &n) in &links {
        near.entry(a).or_default().push((b, n));
        near.entry(b).or_default().push((a, n));
    }
    let degree = |c: usize| near.get(&c).map_or(0, Vec::len);
    // Ends of chains first; workspaces without moves last.
    let Some(first) = columns
        .iter()
        .copied()
        .min_by_key(|&c| (degree(c) == 0, degree(c), c))
    else {
        return Vec::new();
    };
    let mut placed: std::collections::BTreeSet<usize> = std::collections::BTreeSet::new();
    let mut order = Vec::with_capacity(columns.len());
    let mut next_unplaced = 0;
    let mut current = first;
    loop {
        placed.insert(current);
        order.push(current);
        if order.len() == columns.len() {
            return order;
        }
        let best = near.get(&current).and_then(|v| {
            v.iter()
                .filter(|(c, _)| !placed.contains(c))
                .max_by_key(|&&(c, n)| (n, std::cmp::Reverse(c)))
                .map(|&(c, _)| c)
        });
        current = match best {
            Some(c) => c,
            None => {
                while placed.contains(&columns[next_unplaced]) {
                    next_unplaced += 1;
                }
                columns[next_unplaced]
            }
        };
    }
}

/// Where a line from `from` towards `to` leaves the node box around `to`.
fn trim(from: (f64, f64), to: (f64, f64)) -> (f64, f64) {
    let (dx, dy) = (to.0 - from.0, to.1 - from.1);
    let tx = if dx.abs() > 1e-9 {
        (W / 2.0 + 2.0) / dx.abs()
    } else {
        f64::INFINITY
    };
    let ty = if dy.abs() > 1e-9 {
        (H / 2.0 + 2.0) / dy.abs()
    } else {
        f64::INFINITY
    };
    let t = tx.min(ty).min(1.0);
    (to.0 - dx * t, to.1 - dy * t)
}

/// The style the SVG carries, so the file stands alone; `cellc view` adds its own rules
/// for selection and highlights over these classes.
const STYLE: &str = "\
.cluster rect{fill:#f4f6fa;stroke:#9aa5b8;stroke-width:1}\
.cluster text{font:bold 12px sans-serif;fill:#334}\
.state rect{fill:#fff;stroke:#334;stroke-width:1.2}\
.state text{font:10px sans-serif;fill:#111;text-anchor:middle}\
.arc{fill:none;stroke:#445;stroke-width:1.2}\
.arc.move{stroke-dasharray:5 3}\
.arc.pruned{stroke:#bbb;stroke-dasharray:2 3}\
";

/// Two arcs between the same states, one each way, are one line.
fn key(a: u32, b: u32) -> (u32, u32) {
    (a.min(b), a.max(b))
}

/// `o`'s graph as an SVG document; `reason(i)` words pruned arc `i`'s reason.
pub fn svg(a: &Artifact, o: &Object, reason: &dyn Fn(usize) -> String) -> String {
    let l = layout(o);
    let mut out = String::new();
    let _ = write!(
        out,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" class=\"cellc-graph\" data-object=\"{}\" viewBox=\"-4 -4 {:.0} {:.0}\" width=\"{:.0}\" height=\"{:.0}\">",
        xml(&o.name),
        l.width + 8.0,
        l.height + 8.0,
        l.width + 8.0,
        l.height + 8.0
    );
    let _ = write!(
        out,
        "<style>{STYLE}</style><defs>\
<marker id=\"head\" viewBox=\"0 0 10 10\" refX=\"9\" refY=\"5\" markerWidth=\"7\" markerHeight=\"7\" orient=\"auto-start-reverse\"><path d=\"M0,0L10,5L0,10z\" fill=\"#445\"/></marker>\
<marker id=\"head-pruned\" viewBox=\"0 0 10 10\" refX=\"9\" refY=\"5\" markerWidth=\"7\" markerHeight=\"7\" orient=\"auto-start-reverse\"><path d=\"M0,0L10,5L0,10z\" fill=\"#bbb\"/></marker></defs>"
    );
    for (w, [x, y, cw, ch]) in &l.clusters {
        let ws = &a.workspaces[*w];
        let label = match &ws.label {
            Some(text) if !ws.derived => format!("{} ({text})", ws.name),
            _ => ws.name.clone(),
        };
        let _ = write!(
            out,
            "<g class=\"cluster\" data-workspace=\"{}\"><rect x=\"{x:.1}\" y=\"{y:.1}\" width=\"{cw:.1}\" height=\"{ch:.1}\" rx=\"6\"/><text x=\"{:.1}\" y=\"{:.1}\">{}</text></g>",
            xml(&ws.name),
            x + 8.0,
            y + 15.0,
            xml(&label)
        );
    }
    // Live arcs, then pruned ones, each pair once (`both`: the reverse arc is there too).
    struct Line {
        from: u32,
        to: u32,
        kind: ArcKind,
        pruned: bool,
        both: bool,
        index: usize,
    }
    let mut seen: BTreeMap<((u32, u32), bool), usize> = BTreeMap::new();
    let mut lines: Vec<Line> = Vec::new();
    let arcs = o.graph.arcs.iter().map(|arc| (arc, false, 0));
    let pruned = o
        .graph
        .pruned
        .iter()
        .enumerate()
        .map(|(i, p)| (&p.arc, true, i));
    for (arc, is_pruned, index) in arcs.chain(pruned) {
        if arc.from as usize >= l.centres.len() || arc.to as usize >= l.centres.len() {
            continue;
        }
        match seen.get(&(key(arc.from, arc.to), is_pruned)) {
            Some(&at) => {
                if lines[at].from != arc.from {
                    lines[at].both = true;
                }
            }
            None => {
                seen.insert((key(arc.from, arc.to), is_pruned), lines.len());
                lines.push(Line {
                    from: arc.from,
                    to: arc.to,
                    kind: arc.kind,
                    pruned: is_pruned,
                    both: false,
                    index,
                });
            }
        }
    }
    for line in &lines {
        let Line {
            from,
            to,
            kind,
            pruned: is_pruned,
            both,
            index,
        } = *line;
        let (p, q) = (l.centres[from as usize], l.centres[to as usize]);
        // Bend arcs that would run through other states: long moves along a row, and
        // transitions between rows.
        let (dx, dy) = (q.0 - p.0, q.1 - p.1);
        let length = (dx * dx + dy * dy).sqrt().max(1.0);
        let bend = match kind {
            ArcKind::Move if dy.abs() < 1.0 => (0.08 * length).min(MAX_BEND),
            _ => (0.12 * length).min(MAX_BEND),
        };
        let control = (
            (p.0 + q.0) / 2.0 - dy / length * bend,
            (p.1 + q.1) / 2.0 + dx / length * bend,
        );
        let start = trim(control, p);
        let end = trim(control, q);
        let class = match (kind, is_pruned) {
            (_, true) => "arc pruned",
            (ArcKind::Move, false) => "arc move",
            (ArcKind::Transition, false) => "arc transition",
        };
        let marker = if is_pruned { "head-pruned" } else { "head" };
        let title = if is_pruned {
            format!("<title>{}</title>", xml(&reason(index)))
        } else {
            String::new()
        };
        let _ = write!(
            out,
            "<path class=\"{class}\" data-from=\"{from}\" data-to=\"{to}\" data-both=\"{both}\" d=\"M{:.1},{:.1}Q{:.1},{:.1} {:.1},{:.1}\" marker-end=\"url(#{marker})\"{}>{title}</path>",
            start.0,
            start.1,
            control.0,
            control.1,
            end.0,
            end.1,
            if both { format!(" marker-start=\"url(#{marker})\"") } else { String::new() },
        );
    }
    for (i, n) in o.graph.nodes.iter().enumerate() {
        let (cx, cy) = l.centres[i];
        let ee = a.end_effector_name(n.end_effector);
        let grasp = o
            .grasps
            .get(n.grasp.index())
            .map_or("?", |g| g.name.as_str());
        let ws = a.workspace_name(n.workspace);
        let _ = write!(
            out,
            "<g class=\"state\" data-state=\"{i}\"><title>S({}, {}, {})</title><rect x=\"{:.1}\" y=\"{:.1}\" width=\"{W}\" height=\"{H}\" rx=\"7\"/><text x=\"{cx:.1}\" y=\"{:.1}\">{}</text><text x=\"{cx:.1}\" y=\"{:.1}\">{}</text></g>",
            xml(ee),
            xml(grasp),
            xml(ws),
            cx - W / 2.0,
            cy - H / 2.0,
            cy - 3.0,
            xml(&short(ee)),
            cy + 10.0,
            xml(&short(grasp)),
        );
    }
    out.push_str("</svg>\n");
    out
}

/// A name cut to fit a node box.
fn short(name: &str) -> String {
    const MAX: usize = 17;
    if name.chars().count() <= MAX {
        name.to_string()
    } else {
        let cut: String = name.chars().take(MAX - 1).collect();
        format!("{cut}…")
    }
}
