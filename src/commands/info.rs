//! `cellc info INPUT`: what a compiled cell holds.

use std::fmt::Write;
use std::process::ExitCode;

use cellc_schema::{
    Artifact, Body, EndEffectorId, Holder, ObjectId, RequestPlacement, WorkspaceId,
};

use crate::render::{Color, Format, Style};

/// Prints the summary of a cell (compiled now, with what `reach auto` computed and how
/// long it took) or of an artifact file.
pub fn run(path: &str, color: Color, options: &cellc_compiler::CompileOptions) -> ExitCode {
    let report = Style {
        format: Format::Human,
        color,
    };
    if path.ends_with(".cell") {
        let Some((artifact, compilation)) =
            crate::artifact_io::compiled_cell(path, report, options)
        else {
            return ExitCode::from(1);
        };
        print!("{}", describe(&artifact));
        if let Some(cell) = &compilation.cell {
            print!("{}", joint_limits(cell, &compilation.sources));
            print!("{}", computed_reach(cell));
        }
        return ExitCode::SUCCESS;
    }
    match crate::artifact_io::cell_or_artifact(path, report, options) {
        Some(artifact) => {
            print!("{}", describe(&artifact));
            ExitCode::SUCCESS
        }
        None => ExitCode::from(1),
    }
}

/// Each robot's joints with the velocity, acceleration and jerk they are timed with and
/// where each came from (the artifact keeps the values only, so this is shown for a cell
/// compiled now).
pub fn joint_limits(cell: &cellc_compiler::Cell, sources: &cellc_lang::SourceMap) -> String {
    use cellc_compiler::model::{Joint, Limit, LimitSource};
    let mut out = String::new();
    if cell.robots.is_empty() {
        return out;
    }
    let _ = writeln!(
        out,
        "\njoint limits ({})",
        count(cell.robots.len(), "robot")
    );
    let line = |o: &cellc_compiler::model::Origin| {
        let file = sources.get(o.file);
        let (l, _) = file.line_col(o.span.start);
        format!("{}:{}", file.path, l)
    };
    let shown = |limit: Option<&Limit>, default: Option<f64>, unit: &str| -> String {
        match (limit, default) {
            (Some(l), _) => {
                let from = match &l.source {
                    LimitSource::Urdf => "urdf".to_string(),
                    LimitSource::File(path, _) => format!("file {path}"),
                    LimitSource::Robot(o) | LimitSource::Joint(o) => format!("cell {}", line(o)),
                };
                format!("{} {unit} ({from})", round(l.value))
            }
            (None, Some(d)) => format!("{d} {unit} (default)"),
            (None, None) => "none".to_string(),
        }
    };
    for (_, robot) in cell.robots.iter() {
        let _ = writeln!(out, "  {}:", robot.name);
        for j in &robot.chain_joints {
            let (u1, u2, u3) = if j.prismatic {
                ("m/s", "m/s2", "m/s3")
            } else {
                ("rad/s", "rad/s2", "rad/s3")
            };
            let _ = writeln!(
                out,
                "    {}: velocity {}, acceleration {}, jerk {}",
                j.name,
                shown(j.velocity.as_ref(), Some(Joint::DEFAULT_VELOCITY), u1),
                shown(
                    j.acceleration.as_ref(),
                    Some(Joint::DEFAULT_ACCELERATION),
                    u2
                ),
                shown(j.jerk.as_ref(), None, u3),
            );
        }
    }
    out
}

/// A limit to six significant digits at most, as `cellc info` shows it.
fn round(v: f64) -> String {
    let r = format!("{v:.6}");
    let r = r.trim_end_matches('0').trim_end_matches('.');
    r.to_string()
}

/// The boxes `reach auto` found per arm, with the work and the time it took (nothing
/// when no arm asked). The time is the one thing here that changes from run to run; it
/// is never in the artifact.
pub fn computed_reach(cell: &cellc_compiler::Cell) -> String {
    let mut out = String::new();
    if cell.auto_reach.is_empty() {
        return out;
    }
    let _ = writeln!(
        out,
        "\nreach auto ({})",
        count(cell.auto_reach.len(), "arm")
    );
    for reach in &cell.auto_reach {
        let arm = &cell.end_effectors[reach.end_effector].name;
        let _ = writeln!(
            out,
            "  {arm}: {} over the surfaces, {} places tried, {} solves, {:.2} s",
            count(reach.boxes.len(), "box"),
            reach.tried,
            reach.solves,
            reach.elapsed.as_secs_f64()
        );
        for (surface, b) in &reach.boxes {
            let _ = writeln!(
                out,
                "    over {surface}: box x {}..{}, y {}..{}, z {}..{} m",
                m(b.mins.x),
                m(b.maxs.x),
                m(b.mins.y),
                m(b.maxs.y),
                m(b.mins.z),
                m(b.maxs.z)
            );
        }
    }
    out
}

fn names<Id>(
    artifact: &Artifact,
    indices: impl Iterator<Item = Id>,
    of: impl Fn(&Artifact, Id) -> String,
) -> String {
    let list: Vec<String> = indices.map(|i| of(artifact, i)).collect();
    if list.is_empty() {
        "nothing".to_string()
    } else {
        list.join(", ")
    }
}

fn ee_name(a: &Artifact, e: EndEffectorId) -> String {
    a.end_effector_name(e).to_string()
}

fn ws_name(a: &Artifact, w: WorkspaceId) -> String {
    a.workspace_name(w).to_string()
}

/// `1 node`, `2 nodes`, `2 boxes`.
fn count(n: usize, noun: &str) -> String {
    match (n, noun.ends_with('x')) {
        (1, _) => format!("1 {noun}"),
        (_, true) => format!("{n} {noun}es"),
        _ => format!("{n} {noun}s"),
    }
}

fn m(v: f64) -> String {
    let rounded = (v * 1000.0).round() / 1000.0;
    format!("{}", if rounded == 0.0 { 0.0 } else { rounded })
}

/// The human summary: workspaces with their boxes and reachers, end-effectors, and per
/// object its nodes and arcs by kind.
pub fn describe(a: &Artifact) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "cell {} (artifact format {}, cellc {})",
        a.cell, a.format_version, a.compiler_version
    );
    let _ = writeln!(
        out,
        "weights: move {}, transition {}",
        a.weights.move_weight, a.weights.transition_weight
    );
    let _ = writeln!(out, "\nworkspaces ({})", a.workspaces.len());
    for (i, w) in a.workspaces.iter().enumerate() {
        let reachers = names(
            a,
            a.end_effectors
                .iter()
                .enumerate()
                .filter(|(_, e)| e.reaches.contains(&(i as u32)))
                .map(|(j, _)| EndEffectorId(j as u32)),
            ee_name,
        );
        let label = w
            .label
            .as_ref()
            .map(|l| format!(" \"{l}\""))
            .unwrap_or_default();
        let derived = if w.derived { " (derived)" } else { "" };
        let _ = writeln!(out, "  {}{label}{derived}: reached by {reachers}", w.name);
        for b in &w.boxes {
            let _ = writeln!(
                out,
                "    box x {}..{}, y {}..{}, z {}..{} m",
                m(b.min[0]),
                m(b.max[0]),
                m(b.min[1]),
                m(b.max[1]),
                m(b.min[2]),
                m(b.max[2])
            );
        }
    }
    let _ = writeln!(out, "\nend-effectors ({})", a.end_effectors.len());
    for e in &a.end_effectors {
        let kind = e
            .kind
            .and_then(|k| a.holder_kinds.get(k as usize))
            .map(|k| format!(" {}", k.name))
            .unwrap_or_default();
        let body = match &e.body {
            Body::Abstract => String::new(),
            Body::Arm { robot, .. } => a
                .robots
                .get(*robot as usize)
                .map(|r| format!(", robot {}", r.name))
                .unwrap_or_default(),
            Body::Surface { .. } => ", surface".to_string(),
        };
        let mobility = if e.movable { "movable" } else { "fixed" };
        let reaches = names(a, e.reaches.iter().copied().map(WorkspaceId), ws_name);
        let _ = writeln!(
            out,
            "  {} ({mobility}{kind}{body}): reaches {reaches}",
            e.name
        );
    }
    let _ = writeln!(out, "\nobjects ({})", a.objects.len());
    for o in &a.objects {
        let g = &o.graph;
        let mut holders: Vec<EndEffectorId> = g.nodes.iter().map(|n| n.end_effector).collect();
        holders.sort();
        holders.dedup();
        let mut workspaces: Vec<WorkspaceId> = g.nodes.iter().map(|n| n.workspace).collect();
        workspaces.sort();
        workspaces.dedup();
        let _ = writeln!(
            out,
            "  {}: {}, {} ({}, {}); {}, {}, {}",
            o.name,
            count(g.nodes.len(), "node"),
            count(g.arcs.len(), "arc"),
            count(g.n_moves(), "move"),
            count(g.n_transitions(), "transition"),
            count(o.grasps.len(), "grasp"),
            count(holders.len(), "end-effector"),
            count(workspaces.len(), "workspace")
        );
        let by_kind = o
            .grasps
            .iter()
            .filter(|gr| matches!(gr.holder, Holder::Kind(_)))
            .count();
        if by_kind > 0 {
            let verb = if by_kind == 1 { "is" } else { "are" };
            let _ = writeln!(
                out,
                "    {by_kind} of the grasps {verb} declared per holder kind"
            );
        }
    }
    if !a.world.is_empty() {
        let _ = writeln!(out, "\nworld ({})", count(a.world.len(), "object"));
        for p in &a.world {
            let _ = writeln!(
                out,
                "  {}: {}",
                a.object_name(p.object),
                placement_text(a, p.object, &p.placement)
            );
        }
    }
    if !a.requests.is_empty() {
        let _ = writeln!(out, "\nrequests ({})", a.requests.len());
        for r in &a.requests {
            let _ = writeln!(
                out,
                "  {}: {} from {} to {}",
                r.name,
                a.object_name(r.object),
                placement_text(a, r.object, &r.from),
                placement_text(a, r.object, &r.to)
            );
        }
    }
    if !a.tasks.is_empty() {
        let _ = writeln!(out, "\ntasks ({})", a.tasks.len());
        for t in &a.tasks {
            let _ = writeln!(out, "  {} ({}):", t.name, count(t.steps.len(), "move"));
            for s in &t.steps {
                let _ = writeln!(
                    out,
                    "    {} to {}",
                    a.object_name(s.object),
                    placement_text(a, s.object, &s.to)
                );
            }
        }
    }
    out
}

/// A placement as the language writes it: `HOLDER[.GRASP] [in WS] [at (x, y, z) m]`.
fn placement_text(a: &Artifact, object: ObjectId, p: &RequestPlacement) -> String {
    let mut out = a.end_effector_name(p.end_effector).to_string();
    if let Some(g) = p.grasp {
        let _ = write!(out, ".{}", a.grasp_name(object, g));
    }
    if let Some(w) = p.workspace {
        let _ = write!(out, " in {}", a.workspace_name(w));
    }
    if let Some(pose) = &p.pose {
        let [x, y, z] = pose.translation;
        let _ = write!(out, " at ({}, {}, {}) m", m(x), m(y), m(z));
    }
    out
}
