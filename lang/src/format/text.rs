//! The text of each item, member and value in the canonical layout, one line each (the
//! printer in the parent module places them and their comments).

use crate::ast::*;
use crate::keywords::written_name;

/// A name where the grammar refuses reserved words as plain names, so a name spelled like
/// one was quoted in the source and must be quoted again.
pub(super) fn name(name: &Name) -> String {
    written_name(&name.text)
}

/// A name an SRDF gives: reserved words need no quotes after `group` and `home`.
fn srdf_name(name: &Name) -> String {
    if name.needs_quotes() {
        format!("`{}`", name.text)
    } else {
        name.text.clone()
    }
}

fn request_placement(p: &RequestPlacement) -> String {
    match &p.place {
        PlaceSpec::In(w) => format!("{} in {}", qualified(&p.holder), name(w)),
        PlaceSpec::At(at) => format!("{} {}", qualified(&p.holder), pose(at)),
    }
}

fn qualified(q: &Qualified) -> String {
    match &q.object {
        Some(object) => format!("{}.{}", name(object), name(&q.name)),
        None => name(&q.name),
    }
}

fn string(s: &StringLit) -> String {
    string_literal(&s.value)
}

/// `text` as a string literal of the language, escaped the one way the formatter writes
/// it (also used by the importer, so imported cells are already canonical).
pub fn string_literal(text: &str) -> String {
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

fn quantity(q: &Quantity) -> String {
    match q.unit {
        Some(unit) => format!("{} {}", q.number, unit.as_str()),
        None => q.number.clone(),
    }
}

fn rate(r: &Rate) -> String {
    match r.unit {
        Some(unit) => format!("{} {}", r.number, unit.as_string()),
        None => r.number.clone(),
    }
}

fn tuple(parts: &[Quantity]) -> String {
    let parts: Vec<String> = parts.iter().map(quantity).collect();
    format!("({})", parts.join(", "))
}

fn pose(p: &Pose) -> String {
    let mut out = format!("at {}", tuple(&p.at.parts));
    match &p.rotation {
        Some(Rotation::Rpy(v, _)) => out.push_str(&format!(" rpy {}", tuple(&v.parts))),
        Some(Rotation::Quat(q, _)) => out.push_str(&format!(" quat {}", tuple(q))),
        None => {}
    }
    out
}

fn aabb(b: &Aabb) -> String {
    format!(
        "box center {} size {}",
        tuple(&b.center.parts),
        tuple(&b.size.parts)
    )
}

fn shape(s: &Shape) -> String {
    match s {
        Shape::Box { size } => format!("box size {}", tuple(&size.parts)),
        Shape::Cylinder { radius, height } => format!(
            "cylinder radius {} height {}",
            quantity(radius),
            quantity(height)
        ),
        Shape::Sphere { radius } => format!("sphere radius {}", quantity(radius)),
        Shape::Mesh { path } => format!("mesh {}", string(path)),
    }
}

pub(super) fn solid(s: &Solid) -> String {
    match &s.pose {
        Some(p) => format!("{} {}", shape(&s.shape), pose(p)),
        None => shape(&s.shape),
    }
}

fn names(list: &[Name]) -> String {
    list.iter().map(name).collect::<Vec<_>>().join(", ")
}

fn mobility(m: Mobility) -> &'static str {
    match m {
        Mobility::Fixed => "fixed",
        Mobility::Movable => "movable",
    }
}

/// An item that is laid out on one line (everything but objects and hands with more than
/// one solid).
pub(super) fn item_text(item: &Item) -> String {
    match item {
        Item::Units(u) => {
            let units: Vec<&str> = u.units.iter().map(|(unit, _)| unit.as_str()).collect();
            format!("units {}", units.join(", "))
        }
        Item::Weights(w) => {
            let weights: Vec<String> = w
                .weights
                .iter()
                .map(|w| {
                    let kind = match w.kind {
                        ArcKind::Move => "move",
                        ArcKind::Transition => "transition",
                    };
                    format!("{kind} {}", w.number)
                })
                .collect();
            format!("weights {}", weights.join(", "))
        }
        Item::Include(i) => format!("include {}", string(&i.path)),
        Item::Package(p) => format!("package {} at {}", p.name.text, string(&p.dir)),
        Item::WorkspacesFromReach(_) => "workspaces from reach".to_string(),
        Item::Workspace(w) => {
            let mut out = format!("workspace {}", name(&w.name));
            if let Some(label) = &w.label {
                out.push(' ');
                out.push_str(&string(label));
            }
            for b in &w.boxes {
                out.push(' ');
                out.push_str(&aabb(b));
            }
            out
        }
        Item::Adjacent(a) => format!("adjacent {} {}", name(&a.a), name(&a.b)),
        Item::EndEffector(e) => format!(
            "{} {} reaches {}",
            mobility(e.mobility),
            name(&e.name),
            names(&e.reaches)
        ),
        Item::Hand(h) => {
            let solids: Vec<String> = h.solids.iter().map(solid).collect();
            if solids.is_empty() {
                format!("hand {}", name(&h.name))
            } else {
                // One solid (the block form for more is printed by the block printer; if
                // it ever lands here, the solids still all appear).
                format!("hand {} {{ {} }}", name(&h.name), solids.join(" "))
            }
        }
        Item::Support(s) => format!("support {}", name(&s.name)),
        Item::Robot(r) => {
            let mut out = format!("robot {} urdf {}", name(&r.name), string(&r.urdf));
            if let Some(srdf) = &r.srdf {
                out.push_str(&format!(" srdf {}", string(srdf)));
            }
            if let Some(group) = &r.group {
                out.push_str(&format!(" group {}", srdf_name(group)));
            }
            if let Some(base) = &r.base {
                out.push_str(&format!(" base {}", name(base)));
            }
            if let Some(tip) = &r.tip {
                out.push_str(&format!(" tip {}", name(tip)));
            }
            out
        }
        Item::Arm(a) => {
            let mut out = format!(
                "arm {} = {} {} with {}",
                name(&a.name),
                name(&a.robot),
                pose(&a.pose),
                name(&a.kind)
            );
            if !a.home.is_empty() {
                let values: Vec<String> = a
                    .home
                    .iter()
                    .map(|j| format!("{} {}", name(&j.joint), quantity(&j.value)))
                    .collect();
                out.push_str(&format!(" home ({})", values.join(", ")));
            }
            if let Some(state) = &a.home_state {
                out.push_str(&format!(" home {}", srdf_name(state)));
            }
            out
        }
        Item::Surface(s) => {
            let mut out = format!(
                "surface {} : {} {}",
                name(&s.name),
                name(&s.kind),
                aabb(&s.slab)
            );
            if let Some(h) = &s.reach_height {
                out.push_str(&format!(" reach height {}", quantity(h)));
            }
            out
        }
        Item::Reach(r) => match &r.extent {
            ReachExtent::Box(b) => format!("reach {} {}", name(&r.end_effector), aabb(b)),
            ReachExtent::Auto(_) => format!("reach {} auto", name(&r.end_effector)),
        },
        Item::Allow(a) => format!("allow contact {} {}", qualified(&a.a), qualified(&a.b)),
        Item::Obstacle(o) => format!("obstacle {} {}", name(&o.name), aabb(&o.aabb)),
        Item::Limits(l) => {
            let mut out = format!("limits {}", qualified(&l.target));
            if let Some(file) = &l.file {
                out.push_str(&format!(" from {}", string(file)));
            }
            for v in &l.values {
                out.push_str(&format!(" {} {}", v.kind.as_str(), rate(&v.rate)));
            }
            out
        }
        Item::Request(r) => format!(
            "request {}: {} from {} to {}",
            name(&r.name),
            name(&r.object),
            request_placement(&r.from),
            request_placement(&r.to)
        ),
        Item::Object(o) => {
            // Objects are printed by the block printer; this one-line form only keeps the
            // function total.
            let members: Vec<String> = o.members.iter().map(member_text).collect();
            format!("object {} {{ {} }}", name(&o.name), members.join(" "))
        }
        Item::Expect(e) => format!("expect {}", requirement(&e.requirement)),
        // The world and tasks are printed by the block printer; these one-line forms only
        // keep the function total.
        Item::World(w) => {
            let entries: Vec<String> = w.entries.iter().map(world_entry_text).collect();
            format!("world {{ {} }}", entries.join(" "))
        }
        Item::Task(t) => {
            let steps: Vec<String> = t.steps.iter().map(task_step_text).collect();
            format!("task {} {{ {} }}", name(&t.name), steps.join(" "))
        }
    }
}

fn requirement(r: &Requirement) -> String {
    match r {
        Requirement::Reach { object, from, to } => {
            format!("{}: {} -> {}", name(object), placement(from), placement(to))
        }
        Requirement::Coverage {
            workspace,
            at_least,
            mobility: kind,
        } => {
            let mut out = format!("{} reached by at least {}", name(workspace), at_least.0);
            if let Some(kind) = kind {
                out.push(' ');
                out.push_str(mobility(*kind));
            }
            out
        }
        Requirement::NoIsolatedStates { object } => match object {
            Some(object) => format!("no isolated states for {}", name(object)),
            None => "no isolated states".to_string(),
        },
    }
}

fn placement(p: &Placement) -> String {
    format!("{} in {}", qualified(&p.holder), name(&p.workspace))
}

pub(super) fn member_text(member: &ObjectMember) -> String {
    match member {
        ObjectMember::Shape(s) => format!("shape {}", shape(&s.shape)),
        ObjectMember::Symmetry(s) => match s.order {
            Some((order, _)) => format!("symmetry about {} order {order}", s.axis.as_str()),
            None => format!("symmetry about {}", s.axis.as_str()),
        },
        ObjectMember::Grasp(g) => {
            let (keyword, preposition) = match g.keyword {
                GraspKeyword::Grasp => ("grasp", "by"),
                GraspKeyword::Rest => ("rest", "on"),
            };
            let mut out = format!("{keyword} {}", name(&g.name));
            if let Some(label) = &g.label {
                out.push(' ');
                out.push_str(&string(label));
            }
            out.push_str(&format!(" {preposition} {}", name(&g.holder)));
            if let Some(p) = &g.pose {
                out.push(' ');
                out.push_str(&pose(p));
            }
            if let Some(file) = &g.file {
                out.push_str(&format!(" from {}", string(file)));
            }
            for clause in &g.family {
                out.push(' ');
                out.push_str(&family_clause(clause));
            }
            out
        }
        ObjectMember::Transition(t) => {
            let arrow = match t.direction {
                Direction::Both => "<->",
                Direction::OneWay => "->",
            };
            let to: Vec<String> = t.to.iter().map(qualified).collect();
            let matching = if t.matching.is_some() {
                " matching"
            } else {
                ""
            };
            format!(
                "transition {} {arrow} {}{matching}",
                qualified(&t.from),
                to.join(", ")
            )
        }
    }
}

/// `every 30 deg about z` or `along z at (-5 cm, 0 cm)`, as written.
fn family_clause(clause: &FamilyClause) -> String {
    match clause {
        FamilyClause::Every { step, axis, .. } => {
            format!("every {} about {}", quantity(step), axis.as_str())
        }
        FamilyClause::Along { axis, offsets, .. } => {
            let offsets: Vec<String> = offsets.iter().map(quantity).collect();
            format!("along {} at ({})", axis.as_str(), offsets.join(", "))
        }
    }
}

// ---- the world and tasks ---------------------------------------------------------------

/// `OBJECT: PLACEMENT`, a line of the world.
pub(super) fn world_entry_text(entry: &WorldEntry) -> String {
    let placement = match &entry.placement {
        WorldPlacement::Placed(p) => request_placement(p),
        WorldPlacement::Bare(holder) => qualified(holder),
    };
    format!("{}: {placement}", name(&entry.object))
}

/// `OBJECT to PLACEMENT`, a step of a task.
pub(super) fn task_step_text(step: &TaskStep) -> String {
    format!("{} to {}", name(&step.object), request_placement(&step.to))
}
