//! Pass 1: every item's names enter the namespace, with what can be evaluated without
//! knowing other items (boxes, poses, shapes, URDF chains, grasps).

use cellc_lang::ast::{self, Mobility};
use cellc_lang::{Diagnostic, FileId, Span};
use cellc_schema::files::join;

use super::{origin, Entry, Resolver, DEFAULT_SURFACE_REACH_HEIGHT};
use crate::diagnostics::{self, Sort};
use crate::ids::*;
use crate::model::*;
use crate::names::Kind;
use crate::units::FileUnits;

impl Resolver<'_, '_> {
    pub(super) fn declare(&mut self, file: FileId, path: &str, units: FileUnits, item: &ast::Item) {
        match item {
            ast::Item::Workspace(w) => {
                self.declared(file, &w.name, Kind::Workspace, w.span);
                let boxes = w
                    .boxes
                    .iter()
                    .filter_map(|b| self.eval(file, units).aabb(b))
                    .collect();
                let o = origin(file, w.span, &w.name);
                if self.names.contains_key(&w.name.text) {
                    self.add_name(&w.name, Entry::Workspace(WorkspaceId(0)), o);
                    return;
                }
                let id = self.cell.workspaces.insert(Workspace {
                    name: w.name.text.clone(),
                    label: w.label.as_ref().map(|l| l.value.clone()),
                    boxes,
                    origin: o,
                    derived: false,
                });
                self.add_name(&w.name, Entry::Workspace(id), o);
            }
            ast::Item::EndEffector(e) => {
                let kind = match e.mobility {
                    Mobility::Fixed => Kind::Fixed,
                    Mobility::Movable => Kind::Movable,
                };
                self.declared(file, &e.name, kind, e.span);
                let o = origin(file, e.span, &e.name);
                self.declare_end_effector(&e.name, e.mobility, Body::Abstract, o);
            }
            ast::Item::Arm(a) => {
                self.declared(file, &a.name, Kind::Arm, a.span);
                let o = origin(file, a.span, &a.name);
                // The body is completed in the second pass, once robots are known.
                let base = self.eval(file, units).pose(&a.pose);
                let body = Body::Arm {
                    robot: None,
                    base: base.unwrap_or_default(),
                    home: Vec::new(),
                };
                self.declare_end_effector(&a.name, Mobility::Movable, body, o);
            }
            ast::Item::Surface(s) => {
                self.declared(file, &s.name, Kind::Surface, s.span);
                let o = origin(file, s.span, &s.name);
                let slab = self.eval(file, units).aabb(&s.slab);
                let reach_height = match &s.reach_height {
                    Some(q) => self.eval(file, units).positive_length(q, "a reach height"),
                    None => Some(DEFAULT_SURFACE_REACH_HEIGHT),
                };
                let body = Body::Surface {
                    slab: slab.unwrap_or(crate::math::Aabb::new(
                        crate::math::Point::origin(),
                        crate::math::Point::origin(),
                    )),
                    reach_height: reach_height.unwrap_or(DEFAULT_SURFACE_REACH_HEIGHT),
                };
                self.declare_end_effector(&s.name, Mobility::Fixed, body, o);
            }
            ast::Item::Hand(h) => {
                self.declared(file, &h.name, Kind::Hand, h.span);
                let o = origin(file, h.span, &h.name);
                let solids = h
                    .solids
                    .iter()
                    .filter_map(|s| self.solid(file, path, units, s))
                    .collect();
                self.declare_kind(&h.name, HolderClass::Hand, solids, o);
            }
            ast::Item::Support(s) => {
                self.declared(file, &s.name, Kind::Support, s.span);
                let o = origin(file, s.span, &s.name);
                self.declare_kind(&s.name, HolderClass::Support, Vec::new(), o);
            }
            ast::Item::Robot(r) => {
                self.declared(file, &r.name, Kind::Robot, r.span);
                let o = origin(file, r.span, &r.name);
                if self.names.contains_key(&r.name.text) {
                    self.add_name(&r.name, Entry::Robot(RobotId(0)), o);
                    return;
                }
                let named = crate::urdf::Named {
                    files: self.files,
                    packages: &self.packages,
                    declaring_path: path,
                    file,
                };
                if let Some(robot) = self.urdfs.load_robot(&named, r, o, self.diagnostics) {
                    let id = self.cell.robots.insert(robot);
                    self.add_name(&r.name, Entry::Robot(id), o);
                } else {
                    // Keep the name so that arms using it do not also report it unknown.
                    self.names
                        .insert(r.name.text.clone(), Entry::Robot(RobotId(u32::MAX)));
                    self.origins.insert(r.name.text.clone(), o);
                }
            }
            ast::Item::Object(obj) => self.declare_object(file, path, units, obj),
            ast::Item::Obstacle(o) => {
                self.declared(file, &o.name, Kind::Obstacle, o.span);
                let origin = origin(file, o.span, &o.name);
                if self.add_name(&o.name, Entry::Obstacle, origin) {
                    if let Some(b) = self.eval(file, units).aabb(&o.aabb) {
                        self.cell.obstacles.push((o.name.text.clone(), b, origin));
                        self.obstacle_names.insert(o.name.text.clone());
                    }
                }
            }
            ast::Item::WorkspacesFromReach(span) => {
                let o = Origin {
                    file,
                    span: *span,
                    name_span: *span,
                };
                if let Some(first) = self.cell.derive_workspaces {
                    self.diagnostics.push(
                        diagnostics::derivation_conflict(
                            "`workspaces from reach` is written twice",
                            o,
                            "keep one `workspaces from reach` line",
                        )
                        .secondary(
                            first.file,
                            first.span,
                            "first written here",
                        ),
                    );
                } else {
                    self.cell.derive_workspaces = Some(o);
                }
            }
            ast::Item::Weights(w) => {
                for weight in &w.weights {
                    if !(weight.value.is_finite() && weight.value >= 0.0) {
                        self.diagnostics.push(diagnostics::bad_weight(
                            weight.value,
                            file,
                            weight.span,
                        ));
                        continue;
                    }
                    let (slot, what) = match weight.kind {
                        ast::ArcKind::Move => (0, "move"),
                        ast::ArcKind::Transition => (1, "transition"),
                    };
                    if let Some(first) = self.weight_origins[slot] {
                        self.diagnostics.push(diagnostics::weight_set_twice(
                            what,
                            file,
                            weight.span,
                            first,
                        ));
                        continue;
                    }
                    self.weight_origins[slot] = Some(Origin {
                        file,
                        span: weight.span,
                        name_span: weight.span,
                    });
                    match weight.kind {
                        ast::ArcKind::Move => self.cell.weights.move_weight = weight.value,
                        ast::ArcKind::Transition => {
                            self.cell.weights.transition_weight = weight.value
                        }
                    }
                }
            }
            ast::Item::Units(_)
            | ast::Item::Include(_)
            | ast::Item::Package(_)
            | ast::Item::Adjacent(_)
            | ast::Item::Reach(_)
            | ast::Item::Expect(_)
            | ast::Item::Request(_)
            | ast::Item::World(_)
            | ast::Item::Task(_)
            | ast::Item::Limits(_)
            | ast::Item::Allow(_) => {}
        }
    }

    fn declare_end_effector(
        &mut self,
        name: &ast::Name,
        mobility: Mobility,
        body: Body,
        o: Origin,
    ) {
        if self.names.contains_key(&name.text) {
            self.add_name(name, Entry::EndEffector(EndEffectorId(0)), o);
            return;
        }
        let id = self.cell.end_effectors.insert(EndEffector {
            name: name.text.clone(),
            mobility,
            kind: None,
            body,
            reach_boxes: Vec::new(),
            reach_auto: None,
            reaches: Vec::new(),
            origin: o,
        });
        self.add_name(name, Entry::EndEffector(id), o);
    }

    fn declare_kind(
        &mut self,
        name: &ast::Name,
        class: HolderClass,
        solids: Vec<Solid>,
        o: Origin,
    ) {
        if self.names.contains_key(&name.text) {
            self.add_name(name, Entry::HolderKind(HolderKindId(0)), o);
            return;
        }
        let id = self.cell.holder_kinds.insert(HolderKind {
            name: name.text.clone(),
            class,
            solids,
            origin: o,
        });
        self.add_name(name, Entry::HolderKind(id), o);
    }

    fn declare_object(
        &mut self,
        file: FileId,
        path: &str,
        units: FileUnits,
        obj: &ast::ObjectItem,
    ) {
        // Every grasp is recorded as declared in the object's scope, a duplicate's too
        // (its name is written, and an editor shows both places).
        self.declared(file, &obj.name, Kind::Object, obj.span);
        for member in &obj.members {
            if let ast::ObjectMember::Grasp(g) = member {
                let kind = match g.keyword {
                    ast::GraspKeyword::Grasp => Kind::Grasp,
                    ast::GraspKeyword::Rest => Kind::Rest,
                };
                self.declared_grasp(file, &obj.name.text, &g.name, kind, g.span);
            }
        }
        let o = origin(file, obj.span, &obj.name);
        if self.names.contains_key(&obj.name.text) {
            self.add_name(&obj.name, Entry::Object(ObjectId(0)), o);
            return;
        }
        let id = self.cell.objects.insert(Object {
            name: obj.name.text.clone(),
            shape: None,
            symmetries: Vec::new(),
            grasps: Vec::new(),
            origin: o,
        });
        self.add_name(&obj.name, Entry::Object(id), o);
        let mut shape_seen: Option<Span> = None;
        for member in &obj.members {
            match member {
                ast::ObjectMember::Shape(s) => {
                    if let Some(first) = shape_seen {
                        self.diagnostics.push(
                            Diagnostic::error(
                                diagnostics::codes::DUPLICATE_NAME,
                                format!("object `{}` has two shapes", obj.name.text),
                            )
                            .primary(file, s.span, "second shape")
                            .secondary(file, first, "first shape")
                            .help("keep one `shape` line per object"),
                        );
                        continue;
                    }
                    shape_seen = Some(s.span);
                    self.cell.objects[id].shape = self.shape(file, path, units, &s.shape);
                }
                ast::ObjectMember::Symmetry(s) => {
                    let order = match s.order {
                        Some((0, span)) => {
                            self.diagnostics
                                .push(diagnostics::bad_symmetry_order(file, span));
                            continue;
                        }
                        Some((n, _)) => Some(n),
                        None => None,
                    };
                    let axis = match s.axis {
                        ast::Axis::X => [1.0, 0.0, 0.0],
                        ast::Axis::Y => [0.0, 1.0, 0.0],
                        ast::Axis::Z => [0.0, 0.0, 1.0],
                    };
                    self.cell.objects[id]
                        .symmetries
                        .push(Symmetry { axis, order });
                }
                ast::ObjectMember::Grasp(_) | ast::ObjectMember::Transition(_) => {}
            }
        }
        // Grasps after the symmetries, which families need wherever they are written.
        for member in &obj.members {
            match member {
                ast::ObjectMember::Grasp(g) if g.is_family() => {
                    self.declare_family(file, path, units, id, g);
                }
                ast::ObjectMember::Grasp(g) => {
                    let go = origin(file, g.span, &g.name);
                    if let Some(family) = self.families.get(id, &g.name.text) {
                        let first = Origin {
                            file,
                            span: family.span,
                            name_span: family.span,
                        };
                        self.diagnostics.push(diagnostics::duplicate_name(
                            Sort::Grasp,
                            &g.name.text,
                            first,
                            go,
                        ));
                        continue;
                    }
                    if let Some(&first) = self.grasp_names.get(id, &g.name.text) {
                        let first = self.cell.grasps[first].origin;
                        self.diagnostics.push(diagnostics::duplicate_name(
                            Sort::Grasp,
                            &g.name.text,
                            first,
                            go,
                        ));
                        continue;
                    }
                    let pose = g.pose.as_ref().and_then(|p| self.eval(file, units).pose(p));
                    let gid = self.cell.grasps.insert(Grasp {
                        name: g.name.text.clone(),
                        label: g.label.as_ref().map(|l| l.value.clone()),
                        object: id,
                        // Resolved in the second pass.
                        holder: None,
                        keyword: g.keyword,
                        pose,
                        origin: go,
                    });
                    self.grasp_names.insert(id, g.name.text.clone(), gid);
                    self.cell.objects[id].grasps.push(gid);
                }
                _ => {}
            }
        }
    }

    fn shape(
        &mut self,
        file: FileId,
        path: &str,
        units: FileUnits,
        shape: &ast::Shape,
    ) -> Option<Shape> {
        let mut eval = self.eval(file, units);
        Some(match shape {
            ast::Shape::Box { size } => Shape::Box {
                size: eval.sizes(size, "a box size")?,
            },
            ast::Shape::Cylinder { radius, height } => {
                let radius = eval.positive_length(radius, "a radius");
                let height = eval.positive_length(height, "a height");
                Shape::Cylinder {
                    radius: radius?,
                    height: height?,
                }
            }
            ast::Shape::Sphere { radius } => Shape::Sphere {
                radius: eval.positive_length(radius, "a radius")?,
            },
            ast::Shape::Mesh { path: mesh } => Shape::Mesh {
                path: join(path, &mesh.value),
            },
        })
    }

    fn solid(
        &mut self,
        file: FileId,
        path: &str,
        units: FileUnits,
        solid: &ast::Solid,
    ) -> Option<Solid> {
        let shape = self.shape(file, path, units, &solid.shape);
        let pose = match &solid.pose {
            Some(p) => self.eval(file, units).pose(p)?,
            None => crate::math::Iso::identity(),
        };
        Some(Solid {
            shape: shape?,
            pose,
        })
    }
}
