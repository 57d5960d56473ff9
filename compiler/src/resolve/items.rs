//! References between items: arms to robots and kinds (and their home configurations),
//! surfaces to kinds, reach boxes, grasps to holders, transitions to grasps (pass 3);
//! abstract reach lists and adjacencies (pass 5, as they may name derived workspaces).

use cellc_lang::ast::{self, GraspKeyword};
use cellc_lang::diagnostic::did_you_mean;
use cellc_lang::{Diagnostic, FileId};

use super::{Entry, Resolver};
use crate::diagnostics::{self, Sort};
use crate::ids::*;
use crate::model::*;
use crate::units::FileUnits;

impl Resolver<'_, '_> {
    pub(super) fn resolve_item(&mut self, file: FileId, units: FileUnits, item: &ast::Item) {
        match item {
            ast::Item::Arm(a) => {
                let id = match self.names.get(&a.name.text).copied() {
                    Some(Entry::EndEffector(id))
                        if self.cell.end_effectors[id].origin.span == a.span =>
                    {
                        id
                    }
                    // A duplicate, reported where it is declared; its names are written.
                    _ => {
                        self.used(file, &a.robot);
                        self.used(file, &a.kind);
                        return;
                    }
                };
                let robot = match self.lookup(
                    file,
                    &a.robot,
                    Sort::Robot,
                    " with `robot NAME urdf \"...\" tip LINK`",
                ) {
                    // A robot whose URDF failed to load is known by name but has no model.
                    Some(Entry::Robot(r)) if self.cell.robots.get(r).is_some() => Some(r),
                    _ => None,
                };
                let kind = self.kind(file, &a.kind);
                let home = robot
                    .map(|r| self.home(file, units, r, a))
                    .unwrap_or_default();
                let ee = &mut self.cell.end_effectors[id];
                ee.kind = kind;
                if let Body::Arm {
                    robot: slot,
                    home: home_slot,
                    ..
                } = &mut ee.body
                {
                    *slot = robot;
                    *home_slot = home;
                }
            }
            ast::Item::Surface(s) => {
                let id = match self.names.get(&s.name.text).copied() {
                    Some(Entry::EndEffector(id))
                        if self.cell.end_effectors[id].origin.span == s.span =>
                    {
                        id
                    }
                    _ => {
                        self.used(file, &s.kind);
                        return;
                    }
                };
                let kind = self.kind(file, &s.kind);
                if let Some(k) = kind {
                    let k = &self.cell.holder_kinds[k];
                    if k.class == HolderClass::Hand {
                        self.diagnostics.push(
                            Diagnostic::error(
                                diagnostics::codes::WRONG_SORT,
                                format!("`{}` is a hand kind, not a support kind", k.name),
                            )
                            .primary(file, s.kind.span, "a surface needs a support kind")
                            .secondary(
                                k.origin.file,
                                k.origin.name_span,
                                "declared with `hand` here",
                            )
                            .help("declare a support kind (`support NAME`) for the surface"),
                        );
                    }
                }
                self.cell.end_effectors[id].kind = kind;
            }
            ast::Item::Reach(r) => {
                let Some(id) = self.end_effector(file, &r.end_effector) else {
                    return;
                };
                let o = Origin {
                    file,
                    span: r.span,
                    name_span: r.end_effector.span,
                };
                let declared = self.cell.end_effectors[id].origin;
                let why = match self.cell.end_effectors[id].body {
                    Body::Arm { .. } => None,
                    Body::Abstract => Some("it is declared with `reaches`; list workspaces there"),
                    Body::Surface { .. } => Some(
                        "a surface reaches the space above it; set `reach height` on the surface",
                    ),
                };
                if let Some(why) = why {
                    self.diagnostics.push(diagnostics::misplaced_reach(
                        &r.end_effector.text,
                        why,
                        o,
                        declared,
                    ));
                    return;
                }
                match &r.extent {
                    ast::ReachExtent::Box(written) => {
                        if let Some(b) = self.eval(file, units).aabb(written) {
                            self.cell.end_effectors[id].reach_boxes.push(b);
                        }
                    }
                    // Computed once every reference is resolved (`crate::reach`); written
                    // twice, it is computed once.
                    ast::ReachExtent::Auto(_) => {
                        let arm = &mut self.cell.end_effectors[id];
                        arm.reach_auto = arm.reach_auto.or(Some(o));
                    }
                }
            }
            ast::Item::Object(obj) => self.resolve_object(file, obj),
            _ => {}
        }
    }

    fn resolve_object(&mut self, file: FileId, obj: &ast::ObjectItem) {
        let id = match self.names.get(&obj.name.text).copied() {
            Some(Entry::Object(id)) if self.cell.objects[id].origin.span == obj.span => id,
            // A duplicate, reported where it is declared; its names are written.
            _ => {
                for member in &obj.members {
                    match member {
                        ast::ObjectMember::Grasp(g) => self.used(file, &g.holder),
                        ast::ObjectMember::Transition(t) => {
                            for q in std::iter::once(&t.from).chain(&t.to) {
                                self.used_side(file, &obj.name.text, q);
                            }
                        }
                        _ => {}
                    }
                }
                return;
            }
        };
        for member in &obj.members {
            match member {
                ast::ObjectMember::Grasp(g) => {
                    // Looked up below unless the grasp is a duplicate or its family failed.
                    self.used(file, &g.holder);
                    let targets: Vec<GraspId> = if g.is_family() {
                        match self.families.get(id, &g.name.text) {
                            Some(f) if f.span == g.span => f.distinct(),
                            _ => continue,
                        }
                    } else {
                        match self.grasp_names.get(id, &g.name.text) {
                            Some(&gid) if self.cell.grasps[gid].origin.span == g.span => vec![gid],
                            _ => continue,
                        }
                    };
                    let Some(&gid) = targets.first() else {
                        continue;
                    };
                    let holder = match self.names.get(&g.holder.text).copied() {
                        Some(Entry::EndEffector(e)) => Some(Holder::EndEffector(e)),
                        Some(Entry::HolderKind(k)) => Some(Holder::Kind(k)),
                        Some(other) => {
                            let declared = self.origins[&g.holder.text];
                            self.diagnostics.push(diagnostics::wrong_sort(
                                &g.holder.text,
                                Sort::EndEffector,
                                other.sort(),
                                file,
                                g.holder.span,
                                declared,
                            ));
                            None
                        }
                        None => {
                            let names = &self.names;
                            let suggestion = self.suggestions.search(|| {
                                did_you_mean(
                                    &g.holder.text,
                                    names
                                        .iter()
                                        .filter(|(_, e)| {
                                            matches!(
                                                e,
                                                Entry::EndEffector(_) | Entry::HolderKind(_)
                                            )
                                        })
                                        .map(|(n, _)| n.as_str()),
                                )
                            });
                            self.diagnostics.push(diagnostics::unknown_name(
                                Sort::EndEffector,
                                &g.holder.text,
                                file,
                                g.holder.span,
                                suggestion,
                                " (or a hand or support kind)",
                            ));
                            None
                        }
                    };
                    for &member in &targets {
                        self.cell.grasps[member].holder = holder;
                    }
                    if let Some(holder) = holder {
                        if g.keyword == GraspKeyword::Rest && self.is_hand(holder) {
                            let o = self.cell.grasps[gid].origin;
                            self.diagnostics.push(diagnostics::rest_on_hand(
                                &g.holder.text,
                                o,
                                g.holder.span,
                            ));
                        }
                    }
                }
                ast::ObjectMember::Transition(t) => {
                    let o = Origin {
                        file,
                        span: t.span,
                        name_span: t.from.span,
                    };
                    let Some(from) = self.transition_side(file, id, &t.from) else {
                        // The other sides are not looked up; their names are written.
                        for q in &t.to {
                            self.used_side(file, &obj.name.text, q);
                        }
                        continue;
                    };
                    // Pairs once per line: families whose members alias one another, and
                    // `<->` between families, give some pairs more than once.
                    let mut added = rustc_hash::FxHashSet::default();
                    for to in &t.to {
                        let Some(to) = self.transition_side(file, id, to) else {
                            continue;
                        };
                        let Some(pairs) = self.side_pairs(file, t, &from, &to) else {
                            continue;
                        };
                        for (a, b) in pairs {
                            if added.insert((a, b)) {
                                self.add_transition(a, b, o);
                            }
                            // `g <-> g` (one hand kind's grasp passed between two hands of
                            // that kind) is one directed transition, not two.
                            if t.direction == ast::Direction::Both && a != b && added.insert((b, a))
                            {
                                self.add_transition(b, a, o);
                            }
                        }
                    }
                }
                _ => {}
            }
        }
    }

    /// The home configuration of an arm: zero for every chain joint (clamped into its
    /// limits), then the values written in `home (...)`, each checked against the URDF, or
    /// those of the SRDF group state `home NAME`.
    fn home(
        &mut self,
        file: FileId,
        units: FileUnits,
        robot: RobotId,
        arm: &ast::ArmItem,
    ) -> Vec<f64> {
        let joints = self.cell.robots[robot].chain_joints.clone();
        let mut home: Vec<f64> = joints
            .iter()
            .map(|j| 0.0f64.clamp(j.lower, j.upper))
            .collect();
        if let Some(state) = &arm.home_state {
            let values = crate::srdf::home_from_state(
                &self.cell.robots[robot],
                state,
                file,
                &mut self.suggestions,
                self.diagnostics,
            );
            for (i, v) in values.unwrap_or_default() {
                let joint = &joints[i];
                if v < joint.lower - 1e-6 || v > joint.upper + 1e-6 {
                    let unit = if joint.prismatic { "m" } else { "deg" };
                    self.diagnostics.push(diagnostics::home_out_of_limits(
                        &joint.name,
                        v,
                        joint.lower,
                        joint.upper,
                        unit,
                        file,
                        state.span,
                    ));
                    continue;
                }
                home[i] = v;
            }
        }
        for value in &arm.home {
            let Some(i) = joints.iter().position(|j| j.name == value.joint.text) else {
                let suggestion = self.suggestions.search(|| {
                    did_you_mean(&value.joint.text, joints.iter().map(|j| j.name.as_str()))
                });
                let robot_name = self.cell.robots[robot].name.clone();
                self.diagnostics.push(diagnostics::unknown_home_joint(
                    &value.joint.text,
                    &robot_name,
                    file,
                    value.joint.span,
                    suggestion,
                ));
                continue;
            };
            let joint = &joints[i];
            let mut eval = self.eval(file, units);
            let v = if joint.prismatic {
                eval.length(&value.value)
            } else {
                eval.angle(&value.value)
            };
            let Some(v) = v else { continue };
            // A micro-radian of slack: `-120 deg` and a URDF's `-2.0943951` are the same
            // limit written with different precision.
            if v < joint.lower - 1e-6 || v > joint.upper + 1e-6 {
                let unit = if joint.prismatic { "m" } else { "deg" };
                self.diagnostics.push(diagnostics::home_out_of_limits(
                    &joint.name,
                    v,
                    joint.lower,
                    joint.upper,
                    unit,
                    file,
                    value.span,
                ));
                continue;
            }
            home[i] = v;
        }
        home
    }

    /// Adds a directed transition once; a repeat is reported and adds no arcs.
    fn add_transition(&mut self, from: GraspId, to: GraspId, origin: Origin) {
        match self.transition_origins.entry((from, to)) {
            std::collections::hash_map::Entry::Occupied(first) => {
                let (a, b) = (&self.cell.grasps[from].name, &self.cell.grasps[to].name);
                self.diagnostics.push(diagnostics::duplicate_transition(
                    a,
                    b,
                    origin,
                    *first.get(),
                ));
            }
            std::collections::hash_map::Entry::Vacant(slot) => {
                slot.insert(origin);
                self.cell.transitions.push(Transition { from, to, origin });
            }
        }
    }

    fn is_hand(&self, holder: Holder) -> bool {
        let kind = match holder {
            Holder::Kind(k) => Some(k),
            Holder::EndEffector(e) => self.cell.end_effectors.get(e).and_then(|e| e.kind),
        };
        kind.is_some_and(|k| self.cell.holder_kinds[k].class == HolderClass::Hand)
    }

    pub(super) fn resolve_reaches(&mut self, file: FileId, e: &ast::EndEffectorItem) {
        let id = match self.names.get(&e.name.text).copied() {
            Some(Entry::EndEffector(id)) if self.cell.end_effectors[id].origin.span == e.span => id,
            // A duplicate, already reported; its names are written.
            _ => {
                e.reaches.iter().for_each(|w| self.used(file, w));
                return;
            }
        };
        let mut reaches: Vec<WorkspaceId> = e
            .reaches
            .iter()
            .filter_map(|w| self.workspace(file, w))
            .collect();
        reaches.sort();
        reaches.dedup();
        self.cell.end_effectors[id].reaches = reaches;
    }

    pub(super) fn resolve_adjacent(&mut self, file: FileId, adj: &ast::AdjacentItem) {
        let a = self.workspace(file, &adj.a);
        let b = self.workspace(file, &adj.b);
        let o = Origin {
            file,
            span: adj.span,
            name_span: adj.a.span,
        };
        if let (Some(a), Some(b)) = (a, b) {
            if a == b {
                self.diagnostics
                    .push(diagnostics::self_adjacency(&adj.a.text, o));
                return;
            }
            self.cell.adjacencies.push(Adjacency { a, b, origin: o });
        }
    }
}
