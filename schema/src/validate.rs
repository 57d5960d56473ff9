//! Validation of an artifact read from outside: every index in range, every number
//! finite and in its domain, every reference resolvable.
//!
//! An artifact is untrusted input (it may be stale, damaged past its checksum, or written
//! by hand to attack a planner). [`Artifact::from_bytes`](crate::Artifact::from_bytes)
//! runs [`validate`] after decoding, so that nothing downstream ever indexes with a number
//! it did not check. The rules are those the compiler's lowering guarantees; a finding
//! names the offending field by its path (`objects[0].graph.arcs[17].to`) and says what is
//! wrong with it, never echoing the field's content beyond numbers.

use crate::{Aabb, Artifact, Body, Holder, ObjectId, Pose, RequestPlacement, Shape};

pub mod graph;

/// Why an artifact is inconsistent.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Invalid {
    /// Where: a path of field names and indices.
    pub path: String,
    /// What is wrong, e.g. "index 12 out of range (9 nodes)".
    pub problem: String,
}

impl std::fmt::Display for Invalid {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "`{}`: {}", self.path, self.problem)
    }
}

/// Largest magnitude accepted for a coordinate or size, metres: a cell is a room, not a
/// planet, and larger numbers only serve to overflow later arithmetic.
pub const MAX_COORDINATE: f64 = 1.0e6;

/// Checks everything the runtime relies on; the first finding is returned.
pub fn validate(a: &Artifact) -> Result<(), Invalid> {
    core(a)?;
    for (i, o) in a.objects.iter().enumerate() {
        let (g, id) = (&o.graph, ObjectId(i as u32));
        graph::nodes(a, id, &g.nodes)?;
        graph::arcs(a, id, &g.arcs, g.nodes.len(), Some(g.witnesses.len()))?;
        graph::pruned(a, id, &g.pruned, g.nodes.len(), Some(g.witnesses.len()))?;
        graph::witnesses(a, id, &g.witnesses)?;
        graph::transitions(a, id, &o.transitions)?;
    }
    Ok(())
}

/// Checks everything but the objects' graphs and declared transitions (which [`graph`]
/// checks part by part, as a reader of the sectioned binary decodes them), as
/// [`validate`] would.
pub fn core(a: &Artifact) -> Result<(), Invalid> {
    Validator::new(a).core()
}

struct Validator<'a> {
    a: &'a Artifact,
    path: Vec<Step>,
}

/// One step of a finding's path: a field, or an element of a list field. Steps stay
/// parts and are joined into text only when a finding is reported: formatting the path
/// of every element took over half the time of a plan on a 10^6-arc artifact.
#[derive(Clone, Copy, Debug)]
enum Step {
    /// A field by name.
    Field(&'static str),
    /// Element `1` of list field `0` (`arcs[17]`; `[3]` when the name is empty).
    Item(&'static str, usize),
}

impl From<&'static str> for Step {
    fn from(name: &'static str) -> Step {
        Step::Field(name)
    }
}

impl std::fmt::Display for Step {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Step::Field(name) => f.write_str(name),
            Step::Item(name, i) => write!(f, "{name}[{i}]"),
        }
    }
}

type Check = Result<(), Invalid>;

impl<'a> Validator<'a> {
    fn new(a: &'a Artifact) -> Validator<'a> {
        Validator {
            a,
            path: Vec::new(),
        }
    }

    fn fail(&self, problem: impl Into<String>) -> Invalid {
        Invalid {
            path: self
                .path
                .iter()
                .map(Step::to_string)
                .collect::<Vec<_>>()
                .join("."),
            problem: problem.into(),
        }
    }

    /// Runs `f` with `name` appended to the path.
    fn at<T>(&mut self, name: impl Into<Step>, f: impl FnOnce(&mut Self) -> T) -> T {
        self.path.push(name.into());
        let out = f(self);
        self.path.pop();
        out
    }

    /// `value` (a raw index or a typed id) must index a list of `len`.
    fn index(
        &mut self,
        field: impl Into<Step>,
        value: impl Into<u32>,
        len: usize,
        what: &str,
    ) -> Check {
        let value: u32 = value.into();
        if (value as usize) < len {
            Ok(())
        } else {
            self.at(field, |v| {
                Err(v.fail(format!("index {value} out of range ({len} {what})")))
            })
        }
    }

    fn span(&mut self, field: impl Into<Step>, value: u32) -> Check {
        let n = self.a.spans.len();
        self.index(field, value, n, "spans")
    }

    fn number(&mut self, field: impl Into<Step>, x: f64) -> Check {
        if x.is_finite() && x.abs() <= MAX_COORDINATE {
            Ok(())
        } else {
            self.at(field, |v| {
                Err(v.fail(format!("{x} is not a finite number of sensible size")))
            })
        }
    }

    fn positive(&mut self, field: impl Into<Step>, x: f64) -> Check {
        let field = field.into();
        self.number(field, x)?;
        if x > 0.0 {
            Ok(())
        } else {
            self.at(field, |v| Err(v.fail(format!("{x} must be positive"))))
        }
    }

    /// An arc weight: finite and not negative, as the compiler requires (E0205), so the
    /// shortest-path search is sound.
    fn weight(&mut self, field: impl Into<Step>, x: f64) -> Check {
        let field = field.into();
        self.number(field, x)?;
        if x >= 0.0 {
            Ok(())
        } else {
            self.at(field, |v| Err(v.fail(format!("{x} is negative"))))
        }
    }

    fn pose(&mut self, field: impl Into<Step>, p: &Pose) -> Check {
        self.at(field, |v| {
            for (i, x) in p.translation.iter().enumerate() {
                v.number(Step::Item("translation", i), *x)?;
            }
            if !p.rotation.iter().all(|x| x.is_finite()) {
                return Err(v.fail("the rotation is not finite"));
            }
            let norm = p.rotation.iter().map(|x| x * x).sum::<f64>().sqrt();
            if (norm - 1.0).abs() > 1e-6 {
                return Err(v.fail(format!("the rotation quaternion has norm {norm}, not 1")));
            }
            Ok(())
        })
    }

    fn aabb(&mut self, field: impl Into<Step>, b: &Aabb) -> Check {
        self.at(field, |v| {
            for i in 0..3 {
                v.number(Step::Item("min", i), b.min[i])?;
                v.number(Step::Item("max", i), b.max[i])?;
                if b.min[i] > b.max[i] {
                    return Err(v.fail(format!("min[{i}] is above max[{i}]")));
                }
            }
            Ok(())
        })
    }

    fn shape(&mut self, field: impl Into<Step>, s: &Shape) -> Check {
        self.at(field, |v| match s {
            Shape::Box { size } => {
                for (i, x) in size.iter().enumerate() {
                    v.positive(Step::Item("size", i), *x)?;
                }
                Ok(())
            }
            Shape::Cylinder { radius, height } => {
                v.positive("radius", *radius)?;
                v.positive("height", *height)
            }
            Shape::Sphere { radius } => v.positive("radius", *radius),
            Shape::Mesh { path } if path.is_empty() => Err(v.fail("the mesh path is empty")),
            Shape::Mesh { .. } => Ok(()),
        })
    }

    fn core(&mut self) -> Check {
        let a = self.a;
        for (i, s) in a.spans.iter().enumerate() {
            self.at(Step::Item("spans", i), |v| {
                v.index("file", s.file, a.sources.len(), "sources")?;
                if s.start > s.end {
                    return Err(v.fail("start is after end"));
                }
                Ok(())
            })?;
        }
        self.at("weights", |v| {
            v.weight("move_weight", a.weights.move_weight)?;
            v.weight("transition_weight", a.weights.transition_weight)
        })?;
        for (i, r) in a.robots.iter().enumerate() {
            self.at(Step::Item("robots", i), |v| {
                v.span("span", r.span)?;
                for (j, joint) in r.joints.iter().enumerate() {
                    v.at(Step::Item("joints", j), |v| {
                        if let Some(lower) = joint.lower {
                            v.number("lower", lower)?;
                        }
                        if let Some(upper) = joint.upper {
                            v.number("upper", upper)?;
                        }
                        v.positive("velocity", joint.velocity)?;
                        v.positive("acceleration", joint.acceleration)?;
                        if let Some(jerk) = joint.jerk {
                            v.positive("jerk", jerk)?;
                        }
                        match (joint.lower, joint.upper) {
                            (Some(l), Some(u)) if l > u => Err(v.fail("lower limit above upper")),
                            (Some(_), None) | (None, Some(_)) => {
                                Err(v.fail("only one limit is given"))
                            }
                            _ => Ok(()),
                        }
                    })?;
                }
                Ok(())
            })?;
        }
        for (i, k) in a.holder_kinds.iter().enumerate() {
            self.at(Step::Item("holder_kinds", i), |v| {
                for (j, solid) in k.solids.iter().enumerate() {
                    v.at(Step::Item("solids", j), |v| {
                        v.shape("shape", &solid.shape)?;
                        v.pose("pose", &solid.pose)
                    })?;
                }
                Ok(())
            })?;
        }
        for (i, w) in a.workspaces.iter().enumerate() {
            self.at(Step::Item("workspaces", i), |v| {
                v.span("span", w.span)?;
                for (j, b) in w.boxes.iter().enumerate() {
                    v.aabb(Step::Item("boxes", j), b)?;
                }
                Ok(())
            })?;
        }
        for i in 0..a.end_effectors.len() {
            self.at(Step::Item("end_effectors", i), |v| v.end_effector(i))?;
        }
        for i in 0..a.objects.len() {
            self.at(Step::Item("objects", i), |v| v.object(i))?;
        }
        if let Some(adjacency) = &a.adjacency {
            for (i, (x, y)) in adjacency.pairs.iter().enumerate() {
                self.at(Step::Item("adjacency.pairs", i), |v| {
                    v.index("0", *x, a.workspaces.len(), "workspaces")?;
                    v.index("1", *y, a.workspaces.len(), "workspaces")
                })?;
            }
        }
        for (i, (_, b)) in a.obstacles.iter().enumerate() {
            self.aabb(Step::Item("obstacles", i), b)?;
        }
        for (i, r) in a.requests.iter().enumerate() {
            self.at(Step::Item("requests", i), |v| {
                v.span("span", r.span)?;
                v.index("object", r.object, a.objects.len(), "objects")?;
                let n_grasps = a.objects[r.object.index()].grasps.len();
                v.at("from", |v| v.placement(&r.from, n_grasps))?;
                v.at("to", |v| v.placement(&r.to, n_grasps))
            })?;
        }
        for (i, p) in a.world.iter().enumerate() {
            self.at(Step::Item("world", i), |v| {
                v.span("span", p.span)?;
                v.index("object", p.object, a.objects.len(), "objects")?;
                let n_grasps = a.objects[p.object.index()].grasps.len();
                v.at("placement", |v| v.placement(&p.placement, n_grasps))
            })?;
        }
        for (i, t) in a.tasks.iter().enumerate() {
            self.at(Step::Item("tasks", i), |v| {
                v.span("span", t.span)?;
                for (j, step) in t.steps.iter().enumerate() {
                    v.at(Step::Item("steps", j), |v| {
                        v.span("span", step.span)?;
                        v.index("object", step.object, a.objects.len(), "objects")?;
                        let n_grasps = a.objects[step.object.index()].grasps.len();
                        v.at("to", |v| v.placement(&step.to, n_grasps))
                    })?;
                }
                Ok(())
            })?;
        }
        Ok(())
    }

    fn placement(&mut self, p: &RequestPlacement, n_grasps: usize) -> Check {
        let a = self.a;
        self.index(
            "end_effector",
            p.end_effector,
            a.end_effectors.len(),
            "end-effectors",
        )?;
        if let Some(g) = p.grasp {
            self.index("grasp", g, n_grasps, "grasps")?;
        }
        if let Some(w) = p.workspace {
            self.index("workspace", w, a.workspaces.len(), "workspaces")?;
        }
        if let Some(pose) = &p.pose {
            self.pose("pose", pose)?;
        }
        Ok(())
    }

    fn end_effector(&mut self, i: usize) -> Check {
        let a = self.a;
        let e = &a.end_effectors[i];
        self.span("span", e.span)?;
        if let Some(k) = e.kind {
            self.index("kind", k, a.holder_kinds.len(), "holder kinds")?;
        }
        for (j, w) in e.reaches.iter().enumerate() {
            self.index(
                Step::Item("reaches", j),
                *w,
                a.workspaces.len(),
                "workspaces",
            )?;
        }
        for (j, b) in e.reach_boxes.iter().enumerate() {
            self.aabb(Step::Item("reach_boxes", j), b)?;
        }
        self.at("body", |v| match &e.body {
            Body::Abstract => Ok(()),
            Body::Arm { robot, base, home } => {
                v.index("robot", *robot, a.robots.len(), "robots")?;
                v.pose("base", base)?;
                v.joints("home", *robot, home)
            }
            Body::Surface { slab, reach_height } => {
                v.aabb("slab", slab)?;
                v.number("reach_height", *reach_height)?;
                if *reach_height < 0.0 {
                    return Err(v.fail("reach_height is negative"));
                }
                Ok(())
            }
        })
    }

    /// Joint values of robot `robot`: one per joint, finite, within its limits.
    fn joints(&mut self, field: impl Into<Step>, robot: u32, q: &[f64]) -> Check {
        let joints = &self.a.robots[robot as usize].joints;
        self.at(field, |v| {
            if q.len() != joints.len() {
                return Err(v.fail(format!(
                    "{} values for a chain of {} joints",
                    q.len(),
                    joints.len()
                )));
            }
            for (j, (x, joint)) in q.iter().zip(joints).enumerate() {
                v.number(Step::Item("", j), *x)?;
                let slack = 1e-9;
                if joint.lower.is_some_and(|l| *x < l - slack)
                    || joint.upper.is_some_and(|u| *x > u + slack)
                {
                    return v.at(Step::Item("", j), |v| {
                        Err(v.fail("outside the joint's limits"))
                    });
                }
            }
            Ok(())
        })
    }

    fn object(&mut self, i: usize) -> Check {
        let a = self.a;
        let o = &a.objects[i];
        self.span("span", o.span)?;
        if let Some(shape) = &o.shape {
            self.shape("shape", shape)?;
        }
        for (j, s) in o.symmetries.iter().enumerate() {
            self.at(Step::Item("symmetries", j), |v| {
                for (k, x) in s.axis.iter().enumerate() {
                    v.number(Step::Item("axis", k), *x)?;
                }
                if s.axis.iter().map(|x| x * x).sum::<f64>() < 1e-12 {
                    return Err(v.fail("the axis is zero"));
                }
                if s.order == Some(0) {
                    return Err(v.fail("order 0"));
                }
                Ok(())
            })?;
        }
        for (j, g) in o.grasps.iter().enumerate() {
            self.at(Step::Item("grasps", j), |v| {
                v.span("span", g.span)?;
                match g.holder {
                    Holder::EndEffector(e) => {
                        v.index("holder", e, a.end_effectors.len(), "end-effectors")
                    }
                    Holder::Kind(k) => v.index("holder", k, a.holder_kinds.len(), "holder kinds"),
                }?;
                match &g.pose {
                    Some(p) => v.pose("pose", p),
                    None => Ok(()),
                }
            })?;
        }
        Ok(())
    }
}
