//! Validation of one object's graph, part by part: its nodes, its arcs, its pruned arcs,
//! its witnesses, and its declared transitions. A reader of the sectioned binary decodes those one section at a time
//! (and a plan needs only the requested object's nodes and arcs), so each part is
//! checked on its own against the artifact's core, which [`super::core`] has checked.
//!
//! An arc's witness index is checked against the object's witnesses when both are
//! present: `n_witnesses` is `None` while the witnesses are not read, and the arcs are
//! checked again (`Some`) once they are. Until then the object has no witnesses, and every
//! reader takes a witness with `get`, so an unchecked index is never followed.
//!
//! The common case, an element that is fine, is tested without building a path: with a
//! path pushed per arc, validation took the largest share of a plan on a 10^6-arc
//! artifact. Only an element that fails is checked again the slow way, which finds and
//! words the same first problem as before.

use super::{Check, Invalid, Step, Validator, MAX_COORDINATE};
use crate::{
    Arc, Artifact, Body, DeclaredTransition, Infeasibility, Node, ObjectId, PrunedArc, Witness,
};

/// The object's grasp count, or a finding when the core has no such object.
fn n_grasps(a: &Artifact, o: ObjectId) -> Result<usize, Invalid> {
    a.objects
        .get(o.index())
        .map(|x| x.grasps.len())
        .ok_or_else(|| Invalid {
            path: "objects".into(),
            problem: format!("no object {} ({} objects)", o.0, a.objects.len()),
        })
}

/// Runs `f` at `objects[o].graph`.
fn at_graph(a: &Artifact, o: ObjectId, f: impl FnOnce(&mut Validator) -> Check) -> Check {
    let mut v = Validator::new(a);
    v.at(Step::Item("objects", o.index()), |v| v.at("graph", f))
}

/// The nodes of object `o`: every end-effector, grasp and workspace in range.
pub fn nodes(a: &Artifact, o: ObjectId, nodes: &[Node]) -> Check {
    let n_grasps = n_grasps(a, o)?;
    let (n_ends, n_workspaces) = (a.end_effectors.len(), a.workspaces.len());
    let fine = |n: &Node| {
        n.end_effector.index() < n_ends
            && n.grasp.index() < n_grasps
            && n.workspace.index() < n_workspaces
    };
    let Some(i) = nodes.iter().position(|n| !fine(n)) else {
        return Ok(());
    };
    let n = nodes[i];
    at_graph(a, o, |v| {
        v.at(Step::Item("nodes", i), |v| {
            v.index("end_effector", n.end_effector, n_ends, "end-effectors")?;
            v.index("grasp", n.grasp, n_grasps, "grasps")?;
            v.index("workspace", n.workspace, n_workspaces, "workspaces")
        })
    })
}

/// What an arc is checked against.
#[derive(Clone, Copy)]
struct Bounds {
    n_nodes: usize,
    n_spans: usize,
    n_witnesses: Option<usize>,
}

impl Bounds {
    /// The bounds of an object's arcs in `a`, its graph having `n_nodes` nodes and (when
    /// read) `n_witnesses` witnesses.
    fn of(a: &Artifact, n_nodes: usize, n_witnesses: Option<usize>) -> Bounds {
        Bounds {
            n_nodes,
            n_spans: a.spans.len(),
            n_witnesses,
        }
    }

    fn fine(&self, arc: &Arc) -> bool {
        (arc.from as usize) < self.n_nodes
            && (arc.to as usize) < self.n_nodes
            && arc.weight.is_finite()
            && arc.weight >= 0.0
            && arc.weight <= MAX_COORDINATE
            && (arc.source as usize) < self.n_spans
            && arc.via.is_none_or(|s| (s as usize) < self.n_spans)
            && match (arc.witness, self.n_witnesses) {
                (Some(w), Some(n)) => (w as usize) < n,
                _ => true,
            }
    }
}

/// The test [`arcs`] makes of each arc before it looks closer: true for an arc that is
/// fine. A reader that applies it while decoding ([`crate::sections::Sections::arcs_testing`])
/// needs [`arcs`] only when an arc fails it, to find and word the problem.
pub fn arc_test(a: &Artifact, n_nodes: usize, n_witnesses: Option<usize>) -> impl Fn(&Arc) -> bool {
    let bounds = Bounds::of(a, n_nodes, n_witnesses);
    move |arc| bounds.fine(arc)
}

/// The arcs of object `o`, whose graph has `n_nodes` nodes and (when read) `n_witnesses`
/// witnesses: ends in range, weights finite and not negative, spans in range.
pub fn arcs(
    a: &Artifact,
    o: ObjectId,
    arcs: &[Arc],
    n_nodes: usize,
    n_witnesses: Option<usize>,
) -> Check {
    n_grasps(a, o)?;
    let bounds = Bounds::of(a, n_nodes, n_witnesses);
    let Some(i) = arcs.iter().position(|arc| !bounds.fine(arc)) else {
        return Ok(());
    };
    at_graph(a, o, |v| {
        v.at(Step::Item("arcs", i), |v| v.arc(&arcs[i], bounds))
    })
}

/// The pruned arcs of object `o`: each arc as [`arcs`] checks it, each reason's indices
/// and numbers.
pub fn pruned(
    a: &Artifact,
    o: ObjectId,
    pruned: &[PrunedArc],
    n_nodes: usize,
    n_witnesses: Option<usize>,
) -> Check {
    n_grasps(a, o)?;
    let bounds = Bounds::of(a, n_nodes, n_witnesses);
    at_graph(a, o, |v| {
        for (i, p) in pruned.iter().enumerate() {
            v.at(Step::Item("pruned", i), |v| {
                v.at("arc", |v| v.arc(&p.arc, bounds))?;
                v.at("reason", |v| v.reason(&p.reason))
            })?;
        }
        Ok(())
    })
}

/// The witnesses of object `o`: poses, and one configuration per arm within its limits.
pub fn witnesses(a: &Artifact, o: ObjectId, witnesses: &[Witness]) -> Check {
    n_grasps(a, o)?;
    at_graph(a, o, |v| {
        for (i, w) in witnesses.iter().enumerate() {
            v.at(Step::Item("witnesses", i), |v| {
                v.pose("object", &w.object)?;
                for (j, c) in w.configurations.iter().enumerate() {
                    v.at(Step::Item("configurations", j), |v| {
                        v.index(
                            "end_effector",
                            c.end_effector,
                            a.end_effectors.len(),
                            "end-effectors",
                        )?;
                        match &a.end_effectors[c.end_effector.index()].body {
                            Body::Arm { robot, .. } => v.joints("joints", *robot, &c.joints),
                            _ => Err(v.fail("a configuration of an end-effector that is no arm")),
                        }
                    })?;
                }
                Ok(())
            })?;
        }
        Ok(())
    })
}

/// The declared transitions of object `o`: spans and grasps in range.
pub fn transitions(a: &Artifact, o: ObjectId, transitions: &[DeclaredTransition]) -> Check {
    let (n_grasps, n_spans) = (n_grasps(a, o)?, a.spans.len());
    let fine = |t: &DeclaredTransition| {
        (t.span as usize) < n_spans && (t.from as usize) < n_grasps && (t.to as usize) < n_grasps
    };
    let Some(j) = transitions.iter().position(|t| !fine(t)) else {
        return Ok(());
    };
    let t = transitions[j];
    let mut v = Validator::new(a);
    v.at(Step::Item("objects", o.index()), |v| {
        v.at(Step::Item("transitions", j), |v| {
            v.span("span", t.span)?;
            v.index("from", t.from, n_grasps, "grasps")?;
            v.index("to", t.to, n_grasps, "grasps")
        })
    })
}

impl Validator<'_> {
    fn arc(&mut self, arc: &Arc, bounds: Bounds) -> Check {
        self.index("from", arc.from, bounds.n_nodes, "nodes")?;
        self.index("to", arc.to, bounds.n_nodes, "nodes")?;
        self.weight("weight", arc.weight)?;
        self.span("source", arc.source)?;
        if let Some(via) = arc.via {
            self.span("via", via)?;
        }
        if let (Some(w), Some(n)) = (arc.witness, bounds.n_witnesses) {
            self.index("witness", w, n, "witnesses")?;
        }
        Ok(())
    }

    fn reason(&mut self, r: &Infeasibility) -> Check {
        let n = self.a.end_effectors.len();
        match r {
            Infeasibility::NoIkSolution {
                end_effector,
                position_error,
                rotation_error,
                ..
            } => {
                self.index("end_effector", *end_effector, n, "end-effectors")?;
                self.error_value("position_error", *position_error)?;
                self.error_value("rotation_error", *rotation_error)
            }
            Infeasibility::NoClosedChain {
                a,
                b,
                position_error,
                rotation_error,
                ..
            } => {
                self.index("a", *a, n, "end-effectors")?;
                self.index("b", *b, n, "end-effectors")?;
                self.error_value("position_error", *position_error)?;
                self.error_value("rotation_error", *rotation_error)
            }
            Infeasibility::HandBusy { hand, holds } => {
                self.index("hand", *hand, n, "end-effectors")?;
                self.index("holds", *holds, self.a.objects.len(), "objects")
            }
            Infeasibility::Blocked(blocker) => {
                self.index("by", blocker.by, self.a.objects.len(), "objects")?;
                match blocker.part {
                    crate::BlockedPart::Arm(e) | crate::BlockedPart::Hand(e) => {
                        self.index("part", e, n, "end-effectors")?
                    }
                    crate::BlockedPart::Object => {}
                }
                match blocker.during.position() {
                    Some(at) => at.iter().try_for_each(|&x| self.number("at", x)),
                    None => Ok(()),
                }
            }
            Infeasibility::Collision { .. } | Infeasibility::NoPlacement { .. } => Ok(()),
        }
    }

    /// A residual: finite and not negative (an unreached target may be infinitely far in
    /// JSON terms only as `null`, which does not decode into a number).
    fn error_value(&mut self, field: impl Into<Step>, x: f64) -> Check {
        if x.is_finite() && x >= 0.0 {
            Ok(())
        } else {
            self.at(field, |v| Err(v.fail(format!("{x} is not a residual"))))
        }
    }
}
