//! Hover: what the name under the cursor is, from the compiled cell, in SI units
//! (metres, and degrees for angles, as cells are usually written); on a number, the value
//! it resolves to.

use std::collections::BTreeMap;
use std::fmt::Write;

use cellc_compiler::math::{Aabb, Iso};
use cellc_compiler::model::{Body, Cell, Holder, Joint};
use cellc_lang::FileId;
use lsp_types::{Hover, HoverContents, HoverParams, MarkupContent, MarkupKind};

use super::analysis::Analysis;
use super::navigate::locate;
use super::position::Lines;
use super::quantities::{self, Measure};
use cellc_compiler::names::{Key, Kind};

/// The description of the name under the cursor.
pub fn hover(analyses: &BTreeMap<String, Analysis>, params: HoverParams) -> Option<Hover> {
    let (analysis, file, offset) = locate(analyses, &params.text_document_position_params)?;
    let (_, text) = analysis.source(file)?;
    let cell = analysis.compilation.cell.as_ref();
    let (value, span) = match analysis.names().at(file, offset) {
        Some(occurrence) => {
            let kind = analysis.names().kind_of(&occurrence.key);
            (describe(cell, &occurrence.key, kind)?, occurrence.span)
        }
        None => quantity(analysis, cell, file, offset)?,
    };
    Some(Hover {
        contents: HoverContents::Markup(MarkupContent {
            kind: MarkupKind::Markdown,
            value,
        }),
        range: Some(Lines::new(text).range(span)),
    })
}

/// The value of the quantity at `offset`, in SI, as the resolver reads it.
fn quantity(
    analysis: &Analysis,
    cell: Option<&Cell>,
    file: FileId,
    offset: usize,
) -> Option<(String, cellc_lang::Span)> {
    let tree = analysis
        .trees
        .iter()
        .find(|(id, _)| *id == file)?
        .1
        .as_ref()?;
    let (written, units) = quantities::of_file(file, tree);
    let prismatic = |arm: &str, joint: &str| {
        let Some(cell) = cell else { return false };
        let robot = cell
            .end_effectors
            .iter()
            .find(|(_, e)| e.name == arm)
            .and_then(|(_, e)| match e.body {
                Body::Arm { robot, .. } => robot.and_then(|r| cell.robots.get(r)),
                _ => None,
            });
        robot.is_some_and(|r| {
            r.chain_joints
                .iter()
                .any(|j| j.name == joint && j.prismatic)
        })
    };
    let (w, value, is_length) = quantities::at(&written, units, file, offset, prismatic)?;
    let what = match &w.measure {
        Measure::Home { joint, .. } => format!("home of `{joint}`"),
        Measure::Length | Measure::Angle if is_length => "length".to_string(),
        _ => "angle".to_string(),
    };
    let text = if is_length {
        format!("**{what}** {} m", num(value))
    } else {
        format!(
            "**{what}** {}° ({} rad)",
            num(value.to_degrees()),
            num(value)
        )
    };
    Some((text, w.quantity.span))
}

/// What `key` is: the compiled cell's facts when it has them, else what the text
/// declares it as; `None` for a name declared nowhere.
pub fn describe(cell: Option<&Cell>, key: &Key, kind: Option<Kind>) -> Option<String> {
    let facts = cell.and_then(|cell| match key {
        Key::Global(name) => global(cell, name, kind),
        Key::Grasp { object, grasp } => grasp_facts(cell, object, grasp),
        Key::Request(_) => None,
    });
    facts.or_else(|| Some(format!("**{}** `{}`", kind?.noun(), key.name())))
}

fn global(cell: &Cell, name: &str, kind: Option<Kind>) -> Option<String> {
    let mut out = String::new();
    if let Some((id, w)) = cell.workspaces.iter().find(|(_, w)| w.name == name) {
        let derived = if w.derived { " (derived)" } else { "" };
        let _ = write!(out, "**workspace** `{name}`{derived}");
        if let Some(label) = &w.label {
            let _ = write!(out, " \"{label}\"");
        }
        out.push_str("\n\n");
        for b in &w.boxes {
            let _ = writeln!(out, "- box {}", aabb(b));
        }
        let reachers: Vec<String> = cell
            .end_effectors
            .iter()
            .filter(|(_, e)| e.reaches.contains(&id))
            .map(|(_, e)| format!("`{}`", e.name))
            .collect();
        let _ = write!(out, "\nreached by {}", list(&reachers));
        return Some(out);
    }
    if let Some((_, e)) = cell.end_effectors.iter().find(|(_, e)| e.name == name) {
        let noun = kind
            .filter(|k| k.is_end_effector())
            .map_or("end-effector", Kind::noun);
        let mobility = if e.is_movable() { "movable" } else { "fixed" };
        let _ = write!(out, "**{noun}** `{name}` ({mobility}");
        if let Some(k) = e.kind.and_then(|k| cell.holder_kinds.get(k)) {
            let _ = write!(out, ", kind `{}`", k.name);
        }
        out.push_str(")\n\n");
        match &e.body {
            Body::Arm { robot, home, .. } => {
                if let Some(robot) = robot.and_then(|r| cell.robots.get(r)) {
                    let _ = writeln!(out, "robot `{}`, URDF `{}`\n", robot.name, robot.urdf_path);
                    joints(&mut out, &robot.chain_joints, Some(home));
                }
            }
            Body::Surface { slab, reach_height } => {
                let _ = writeln!(
                    out,
                    "slab {}, reach height {} m",
                    aabb(slab),
                    num(*reach_height)
                );
            }
            Body::Abstract => {}
        }
        if !e.reach_boxes.is_empty() {
            out.push_str("\nreach:\n");
        }
        for b in &e.reach_boxes {
            let _ = writeln!(out, "- box {}", aabb(b));
        }
        let reaches: Vec<String> = e
            .reaches
            .iter()
            .filter_map(|&w| cell.workspaces.get(w))
            .map(|w| format!("`{}`", w.name))
            .collect();
        let _ = write!(out, "\nreaches {}", list(&reaches));
        return Some(out);
    }
    if let Some((_, k)) = cell.holder_kinds.iter().find(|(_, k)| k.name == name) {
        let noun = kind
            .filter(|k| k.is_holder_kind())
            .map_or("holder kind", Kind::noun);
        let _ = write!(out, "**{noun}** `{name}`, {} solids", k.solids.len());
        return Some(out);
    }
    if let Some((_, r)) = cell.robots.iter().find(|(_, r)| r.name == name) {
        let _ = writeln!(
            out,
            "**robot** `{name}`, URDF `{}`, chain `{}` to `{}`\n",
            r.urdf_path, r.base_link, r.tip_link
        );
        joints(&mut out, &r.chain_joints, None);
        return Some(out);
    }
    if let Some((_, o)) = cell.objects.iter().find(|(_, o)| o.name == name) {
        let grasps: Vec<String> = o
            .grasps
            .iter()
            .filter_map(|&g| cell.grasps.get(g))
            .map(|g| format!("`{}`", g.name))
            .collect();
        let _ = write!(
            out,
            "**object** `{name}`: grasps and resting poses {}",
            list(&grasps)
        );
        return Some(out);
    }
    if let Some((_, b, _)) = cell.obstacles.iter().find(|(n, _, _)| n == name) {
        let _ = write!(out, "**obstacle** `{name}`: {}", aabb(b));
        return Some(out);
    }
    None
}

fn grasp_facts(cell: &Cell, object: &str, grasp: &str) -> Option<String> {
    let (_, o) = cell.objects.iter().find(|(_, o)| o.name == object)?;
    let g = o
        .grasps
        .iter()
        .filter_map(|&g| cell.grasps.get(g))
        .find(|g| g.name == grasp)?;
    let noun = match g.keyword {
        cellc_lang::ast::GraspKeyword::Grasp => "grasp",
        cellc_lang::ast::GraspKeyword::Rest => "resting pose",
    };
    let mut out = format!("**{noun}** `{grasp}` of `{object}`");
    if let Some(label) = &g.label {
        let _ = write!(out, " \"{label}\"");
    }
    let holder = match g.holder {
        Some(Holder::Kind(k)) => cell.holder_kinds.get(k).map(|k| k.name.as_str()),
        Some(Holder::EndEffector(e)) => cell.end_effectors.get(e).map(|e| e.name.as_str()),
        None => None,
    };
    if let Some(holder) = holder {
        let _ = write!(out, ", by `{holder}`");
    }
    if let Some(pose) = &g.pose {
        let _ = write!(out, "\n\nobject in the holder's frame: {}", iso(pose));
    }
    Some(out)
}

/// The chain's joints with their limits (and the home value, for an arm).
fn joints(out: &mut String, joints: &[Joint], home: Option<&Vec<f64>>) {
    for (i, j) in joints.iter().enumerate() {
        let (scale, unit) = if j.prismatic {
            (1.0, "m")
        } else {
            (180.0 / std::f64::consts::PI, "°")
        };
        let _ = write!(
            out,
            "- `{}` {}{unit} .. {}{unit}",
            j.name,
            num(j.lower * scale),
            num(j.upper * scale)
        );
        if let Some(value) = home.and_then(|h| h.get(i)) {
            let _ = write!(out, ", home {}{unit}", num(value * scale));
        }
        out.push('\n');
    }
}

/// `x a .. b, y .., z .. m`.
fn aabb(b: &Aabb) -> String {
    format!(
        "x {} .. {}, y {} .. {}, z {} .. {} m",
        num(b.mins.x),
        num(b.maxs.x),
        num(b.mins.y),
        num(b.maxs.y),
        num(b.mins.z),
        num(b.maxs.z)
    )
}

/// `at (x, y, z) m rpy (r, p, y) deg`.
fn iso(pose: &Iso) -> String {
    let t = pose.translation.vector;
    let (r, p, y) = pose.rotation.euler_angles();
    let deg = |a: f64| num(a.to_degrees());
    format!(
        "at ({}, {}, {}) m rpy ({}, {}, {}) deg",
        num(t.x),
        num(t.y),
        num(t.z),
        deg(r),
        deg(p),
        deg(y)
    )
}

/// A number rounded to 0.1 mm or 0.0001 degree, without a negative zero.
fn num(v: f64) -> String {
    let rounded = (v * 1e4).round() / 1e4;
    format!("{}", if rounded == 0.0 { 0.0 } else { rounded })
}

fn list(names: &[String]) -> String {
    if names.is_empty() {
        "nothing".to_string()
    } else {
        names.join(", ")
    }
}
