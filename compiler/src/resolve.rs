//! Syntax trees to the resolved [`Cell`]: names to typed ids, quantities to SI.
//!
//! Two passes over the items of every loaded file: the first declares every name (so
//! items may refer to names declared later or in an included library), the second
//! resolves references. A reference that fails to resolve is reported and the item is
//! dropped or left partial; resolution always goes on, so one run reports every problem.

use std::collections::HashMap;

use cellc_lang::ast::{self, GraspKeyword, Mobility};
use cellc_lang::diagnostic::did_you_mean;
use cellc_lang::{Diagnostic, FileId, Span};
use cellc_schema::files::{join, Files};

use crate::diagnostics::{self, Sort};
use crate::ids::*;
use crate::load::Loaded;
use crate::model::*;
use crate::units::{Eval, FileUnits};
use crate::urdf;

/// Default height of a surface's reach above its top face: tall enough for the objects
/// a cell handles to stand on it.
pub const DEFAULT_SURFACE_REACH_HEIGHT: f64 = 0.3;

#[derive(Clone, Copy, Debug)]
enum Entry {
    Workspace(WorkspaceId),
    EndEffector(EndEffectorId),
    HolderKind(HolderKindId),
    Robot(RobotId),
    Object(ObjectId),
    Obstacle,
}

impl Entry {
    fn sort(self) -> Sort {
        match self {
            Entry::Workspace(_) => Sort::Workspace,
            Entry::EndEffector(_) => Sort::EndEffector,
            Entry::HolderKind(_) => Sort::HolderKind,
            Entry::Robot(_) => Sort::Robot,
            Entry::Object(_) => Sort::Object,
            Entry::Obstacle => Sort::Obstacle,
        }
    }
}

/// Resolves every loaded file into one cell, deriving workspaces on the way (see
/// [`crate::workspaces`]). Diagnostics are appended to `diagnostics`.
pub fn resolve(files: &dyn Files, loaded: &Loaded, diagnostics: &mut Vec<Diagnostic>) -> Cell {
    let mut r = Resolver {
        files,
        cell: Cell::default(),
        names: HashMap::new(),
        origins: HashMap::new(),
        grasp_names: HashMap::new(),
        weight_origins: [None, None],
        transition_origins: HashMap::new(),
        diagnostics,
    };
    if let Some(main) = loaded.files.first().and_then(|f| f.ast.as_ref()) {
        r.cell.name = main.name.text.clone();
    }
    let files: Vec<(FileId, &str, &ast::File)> = loaded
        .files
        .iter()
        .filter_map(|f| f.ast.as_ref().map(|a| (f.id, f.path.as_str(), a)))
        .collect();
    let units: Vec<FileUnits> = files
        .iter()
        .map(|(id, _, file)| FileUnits::of(*id, &file.items, r.diagnostics))
        .collect();
    for (i, (id, path, file)) in files.iter().enumerate() {
        for item in &file.items {
            r.declare(*id, path, units[i], item);
        }
    }
    for (i, (id, _, file)) in files.iter().enumerate() {
        for item in &file.items {
            r.resolve_item(*id, units[i], item);
        }
    }
    // Workspaces are derived before anything that may name them is resolved.
    crate::workspaces::assign(&mut r.cell, r.diagnostics);
    let derived: Vec<(String, WorkspaceId, Origin)> = r
        .cell
        .workspaces
        .iter()
        .filter(|(_, w)| w.derived)
        .map(|(id, w)| (w.name.clone(), id, w.origin))
        .collect();
    for (name, id, origin) in derived {
        r.names.insert(name.clone(), Entry::Workspace(id));
        r.origins.insert(name, origin);
    }
    for (id, _, file) in &files {
        for item in &file.items {
            if let ast::Item::Allow(a) = item {
                r.resolve_allow(*id, a);
            }
        }
    }
    // Abstract reach lists, adjacencies and requirements may name derived workspaces.
    for (id, _, file) in &files {
        for item in &file.items {
            match item {
                ast::Item::EndEffector(e) => r.resolve_reaches(*id, e),
                ast::Item::Adjacent(adj) => r.resolve_adjacent(*id, adj),
                _ => {}
            }
        }
    }
    for (i, (id, _, file)) in files.iter().enumerate() {
        for item in &file.items {
            match item {
                ast::Item::Expect(e) => r.resolve_expect(*id, e),
                ast::Item::Request(q) => r.resolve_request(*id, units[i], q),
                _ => {}
            }
        }
    }
    r.cell
}

struct Resolver<'w, 'd> {
    files: &'w dyn Files,
    cell: Cell,
    names: HashMap<String, Entry>,
    origins: HashMap<String, Origin>,
    grasp_names: HashMap<(ObjectId, String), GraspId>,
    /// Where the move and transition weights were set, to refuse setting them twice.
    weight_origins: [Option<Origin>; 2],
    /// First declaration of each directed transition.
    transition_origins: HashMap<(GraspId, GraspId), Origin>,
    diagnostics: &'d mut Vec<Diagnostic>,
}

fn origin(file: FileId, span: Span, name: &ast::Name) -> Origin {
    Origin {
        file,
        span,
        name_span: name.span,
    }
}

impl Resolver<'_, '_> {
    fn eval(&mut self, file: FileId, units: FileUnits) -> Eval<'_> {
        Eval {
            file,
            units,
            diagnostics: self.diagnostics,
        }
    }

    /// Adds a name to the one namespace of workspaces, end-effectors, kinds, robots and
    /// objects. One namespace (rather than one per sort) means a name always means one
    /// thing, so `left` in a message is never ambiguous.
    fn add_name(&mut self, name: &ast::Name, entry: Entry, origin: Origin) -> bool {
        if let Some(first) = self.origins.get(&name.text) {
            let sort = self.names[&name.text].sort();
            self.diagnostics.push(diagnostics::duplicate_name(
                sort, &name.text, *first, origin,
            ));
            return false;
        }
        self.names.insert(name.text.clone(), entry);
        self.origins.insert(name.text.clone(), origin);
        true
    }

    fn declare(&mut self, file: FileId, path: &str, units: FileUnits, item: &ast::Item) {
        match item {
            ast::Item::Workspace(w) => {
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
                let o = origin(file, e.span, &e.name);
                self.declare_end_effector(&e.name, e.mobility, Body::Abstract, o);
            }
            ast::Item::Arm(a) => {
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
                let o = origin(file, h.span, &h.name);
                let solids = h
                    .solids
                    .iter()
                    .filter_map(|s| self.solid(file, path, units, s))
                    .collect();
                self.declare_kind(&h.name, HolderClass::Hand, solids, o);
            }
            ast::Item::Support(s) => {
                let o = origin(file, s.span, &s.name);
                self.declare_kind(&s.name, HolderClass::Support, Vec::new(), o);
            }
            ast::Item::Robot(r) => {
                let o = origin(file, r.span, &r.name);
                if self.names.contains_key(&r.name.text) {
                    self.add_name(&r.name, Entry::Robot(RobotId(0)), o);
                    return;
                }
                if let Some(robot) =
                    urdf::load_robot(self.files, path, file, r, o, self.diagnostics)
                {
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
                let origin = origin(file, o.span, &o.name);
                if self.add_name(&o.name, Entry::Obstacle, origin) {
                    if let Some(b) = self.eval(file, units).aabb(&o.aabb) {
                        self.cell.obstacles.push((o.name.text.clone(), b, origin));
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
            | ast::Item::Adjacent(_)
            | ast::Item::Reach(_)
            | ast::Item::Expect(_)
            | ast::Item::Request(_)
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
                ast::ObjectMember::Grasp(g) => {
                    let go = origin(file, g.span, &g.name);
                    if let Some(&first) = self.grasp_names.get(&(id, g.name.text.clone())) {
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
                    self.grasp_names.insert((id, g.name.text.clone()), gid);
                    self.cell.objects[id].grasps.push(gid);
                }
                ast::ObjectMember::Transition(_) => {}
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

    /// Looks a name up, wanting one sort. Reports unknown names (with a suggestion among
    /// names of the wanted sort) and names of the wrong sort.
    fn lookup(
        &mut self,
        file: FileId,
        name: &ast::Name,
        want: Sort,
        context: &str,
    ) -> Option<Entry> {
        match self.names.get(&name.text) {
            Some(entry) if entry.sort() == want => Some(*entry),
            Some(entry) => {
                let declared = self.origins[&name.text];
                self.diagnostics.push(diagnostics::wrong_sort(
                    &name.text,
                    want,
                    entry.sort(),
                    file,
                    name.span,
                    declared,
                ));
                None
            }
            None => {
                let candidates: Vec<&str> = self
                    .names
                    .iter()
                    .filter(|(_, e)| e.sort() == want)
                    .map(|(n, _)| n.as_str())
                    .collect();
                let suggestion = did_you_mean(&name.text, candidates.iter().copied());
                self.diagnostics.push(diagnostics::unknown_name(
                    want, &name.text, file, name.span, suggestion, context,
                ));
                None
            }
        }
    }

    fn workspace(&mut self, file: FileId, name: &ast::Name) -> Option<WorkspaceId> {
        match self.lookup(file, name, Sort::Workspace, "")? {
            Entry::Workspace(id) => Some(id),
            _ => None,
        }
    }

    fn end_effector(&mut self, file: FileId, name: &ast::Name) -> Option<EndEffectorId> {
        match self.lookup(file, name, Sort::EndEffector, "")? {
            Entry::EndEffector(id) => Some(id),
            _ => None,
        }
    }

    fn object(&mut self, file: FileId, name: &ast::Name) -> Option<ObjectId> {
        match self.lookup(file, name, Sort::Object, "")? {
            Entry::Object(id) => Some(id),
            _ => None,
        }
    }

    fn kind(&mut self, file: FileId, name: &ast::Name) -> Option<HolderKindId> {
        match self.lookup(file, name, Sort::HolderKind, " with `hand` or `support`")? {
            Entry::HolderKind(id) => Some(id),
            _ => None,
        }
    }

    fn grasp_of(&mut self, file: FileId, object: ObjectId, name: &ast::Name) -> Option<GraspId> {
        if let Some(&g) = self.grasp_names.get(&(object, name.text.clone())) {
            return Some(g);
        }
        let object_name = self.cell.objects[object].name.clone();
        let candidates: Vec<String> = self.cell.objects[object]
            .grasps
            .iter()
            .map(|&g| self.cell.grasps[g].name.clone())
            .collect();
        let suggestion = did_you_mean(&name.text, candidates.iter().map(String::as_str));
        self.diagnostics.push(diagnostics::unknown_name(
            Sort::Grasp,
            &name.text,
            file,
            name.span,
            suggestion,
            &format!(" in object `{object_name}`"),
        ));
        None
    }

    fn resolve_item(&mut self, file: FileId, units: FileUnits, item: &ast::Item) {
        match item {
            ast::Item::Arm(a) => {
                let Some(Entry::EndEffector(id)) = self.names.get(&a.name.text).copied() else {
                    return;
                };
                if self.cell.end_effectors[id].origin.span != a.span {
                    return;
                }
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
                    .map(|r| self.home(file, units, r, &a.home))
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
                let Some(Entry::EndEffector(id)) = self.names.get(&s.name.text).copied() else {
                    return;
                };
                if self.cell.end_effectors[id].origin.span != s.span {
                    return;
                }
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
                if let Some(b) = self.eval(file, units).aabb(&r.aabb) {
                    self.cell.end_effectors[id].reach_boxes.push(b);
                }
            }
            ast::Item::Object(obj) => self.resolve_object(file, obj),
            _ => {}
        }
    }

    fn resolve_reaches(&mut self, file: FileId, e: &ast::EndEffectorItem) {
        let Some(Entry::EndEffector(id)) = self.names.get(&e.name.text).copied() else {
            return;
        };
        if self.cell.end_effectors[id].origin.span != e.span {
            return; // a duplicate, already reported
        }
        let mut reaches: Vec<WorkspaceId> = e
            .reaches
            .iter()
            .filter_map(|w| self.workspace(file, w))
            .collect();
        reaches.sort();
        reaches.dedup();
        self.cell.end_effectors[id].reaches = reaches;
    }

    fn resolve_adjacent(&mut self, file: FileId, adj: &ast::AdjacentItem) {
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

    fn resolve_object(&mut self, file: FileId, obj: &ast::ObjectItem) {
        let Some(Entry::Object(id)) = self.names.get(&obj.name.text).copied() else {
            return;
        };
        if self.cell.objects[id].origin.span != obj.span {
            return;
        }
        for member in &obj.members {
            match member {
                ast::ObjectMember::Grasp(g) => {
                    let Some(&gid) = self.grasp_names.get(&(id, g.name.text.clone())) else {
                        continue;
                    };
                    if self.cell.grasps[gid].origin.span != g.span {
                        continue;
                    }
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
                            let candidates: Vec<&str> = self
                                .names
                                .iter()
                                .filter(|(_, e)| {
                                    matches!(e, Entry::EndEffector(_) | Entry::HolderKind(_))
                                })
                                .map(|(n, _)| n.as_str())
                                .collect();
                            let suggestion =
                                did_you_mean(&g.holder.text, candidates.iter().copied());
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
                    match holder {
                        Some(holder) => {
                            self.cell.grasps[gid].holder = Some(holder);
                            if g.keyword == GraspKeyword::Rest && self.is_hand(holder) {
                                let o = self.cell.grasps[gid].origin;
                                self.diagnostics.push(diagnostics::rest_on_hand(
                                    &g.holder.text,
                                    o,
                                    g.holder.span,
                                ));
                            }
                        }
                        None => self.cell.grasps[gid].holder = None,
                    }
                }
                ast::ObjectMember::Transition(t) => {
                    let o = Origin {
                        file,
                        span: t.span,
                        name_span: t.from.span,
                    };
                    let Some(from) = self.qualified_grasp(file, id, &t.from) else {
                        continue;
                    };
                    for to in &t.to {
                        let Some(to) = self.qualified_grasp(file, id, to) else {
                            continue;
                        };
                        self.add_transition(from, to, o);
                        // `g <-> g` (one hand kind's grasp passed between two hands of
                        // that kind) is one directed transition, not two.
                        if t.direction == ast::Direction::Both && from != to {
                            self.add_transition(to, from, o);
                        }
                    }
                }
                _ => {}
            }
        }
    }

    /// The home configuration of an arm: zero for every chain joint (clamped into its
    /// limits), then the values written in `home (...)`, each checked against the URDF.
    fn home(
        &mut self,
        file: FileId,
        units: FileUnits,
        robot: RobotId,
        values: &[ast::JointValue],
    ) -> Vec<f64> {
        let joints = self.cell.robots[robot].chain_joints.clone();
        let mut home: Vec<f64> = joints
            .iter()
            .map(|j| 0.0f64.clamp(j.lower, j.upper))
            .collect();
        for value in values {
            let Some(i) = joints.iter().position(|j| j.name == value.joint.text) else {
                let suggestion =
                    did_you_mean(&value.joint.text, joints.iter().map(|j| j.name.as_str()));
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

    /// A `request`: every name resolved (all reported), poses in SI.
    fn resolve_request(&mut self, file: FileId, units: FileUnits, q: &ast::RequestItem) {
        let object = self.object(file, &q.object);
        let from = self.request_placement(file, units, object, &q.from);
        let to = self.request_placement(file, units, object, &q.to);
        let (Some(object), Some(from), Some(to)) = (object, from, to) else {
            return;
        };
        if let Some(first) = self.cell.requests.iter().find(|r| r.name == q.name.text) {
            let origin = origin(file, q.span, &q.name);
            self.diagnostics.push(diagnostics::duplicate_name(
                Sort::Object,
                &q.name.text,
                first.origin,
                origin,
            ));
            return;
        }
        self.cell.requests.push(NamedRequest {
            name: q.name.text.clone(),
            object,
            from,
            to,
            origin: origin(file, q.span, &q.name),
        });
    }

    fn request_placement(
        &mut self,
        file: FileId,
        units: FileUnits,
        object: Option<ObjectId>,
        p: &ast::RequestPlacement,
    ) -> Option<RequestPlacement> {
        let (end_effector, grasp) = self.holder_and_grasp(file, object, &p.holder);
        let (workspace, pose) = match &p.place {
            ast::PlaceSpec::In(w) => (Some(self.workspace(file, w)), None),
            ast::PlaceSpec::At(pose) => (None, Some(self.eval(file, units).pose(pose))),
        };
        let grasp = match grasp {
            Some(g) => Some(g?),
            None => None,
        };
        let workspace = match workspace {
            Some(w) => Some(w?),
            None => None,
        };
        let pose = match pose {
            Some(p) => Some(p?),
            None => None,
        };
        Some(RequestPlacement {
            end_effector: end_effector?,
            grasp,
            workspace,
            pose,
        })
    }

    /// `allow contact A B`: both bodies must exist; a dotted name is a link or the hand of
    /// an arm.
    fn resolve_allow(&mut self, file: FileId, item: &ast::AllowItem) {
        let a = self.body(file, &item.a);
        let b = self.body(file, &item.b);
        if let (Some(a), Some(b)) = (a, b) {
            let origin = Origin {
                file,
                span: item.span,
                name_span: item.a.span,
            };
            self.cell.allowed_contacts.push((a, b, origin));
        }
    }

    /// The collision-body name of `left`, `left.lwr_link_7`, `left.softhand`, `table` or
    /// an object.
    fn body(&mut self, file: FileId, q: &ast::Qualified) -> Option<String> {
        let Some(owner) = &q.object else {
            if self.cell.obstacles.iter().any(|o| o.0 == q.name.text) {
                return Some(q.name.text.clone());
            }
            return match self.names.get(&q.name.text).copied() {
                Some(Entry::EndEffector(_)) | Some(Entry::Object(_)) => Some(q.name.text.clone()),
                Some(other) => {
                    let declared = self.origins[&q.name.text];
                    self.diagnostics.push(diagnostics::wrong_sort(
                        &q.name.text,
                        Sort::EndEffector,
                        other.sort(),
                        file,
                        q.name.span,
                        declared,
                    ));
                    None
                }
                None => {
                    self.lookup(file, &q.name, Sort::EndEffector, " (or an object)");
                    None
                }
            };
        };
        let e = self.end_effector(file, owner)?;
        let (robot, kind) = match &self.cell.end_effectors[e].body {
            Body::Arm {
                robot: Some(robot), ..
            } => (*robot, self.cell.end_effectors[e].kind),
            _ => {
                self.diagnostics.push(
                    Diagnostic::error(
                        diagnostics::codes::WRONG_SORT,
                        format!("`{}` is not an arm, so it has no links", owner.text),
                    )
                    .primary(file, owner.span, "links belong to arms")
                    .help(format!(
                        "write `{}` alone to name the whole body",
                        owner.text
                    )),
                );
                return None;
            }
        };
        let robot = &self.cell.robots[robot];
        let hand = kind.map(|k| self.cell.holder_kinds[k].name.clone());
        let known =
            robot.links.contains(&q.name.text) || hand.as_deref() == Some(q.name.text.as_str());
        if known {
            return Some(format!("{}/{}", owner.text, q.name.text));
        }
        let candidates: Vec<&str> = robot
            .links
            .iter()
            .map(String::as_str)
            .chain(hand.as_deref())
            .collect();
        let suggestion = did_you_mean(&q.name.text, candidates.iter().copied());
        self.diagnostics.push(diagnostics::urdf_unknown_link(
            "link",
            &q.name.text,
            &robot.urdf_path,
            file,
            q.name.span,
            suggestion,
        ));
        None
    }

    /// Adds a directed transition once; a repeat is reported and adds no arcs.
    fn add_transition(&mut self, from: GraspId, to: GraspId, origin: Origin) {
        if let Some(&first) = self.transition_origins.get(&(from, to)) {
            let (a, b) = (&self.cell.grasps[from].name, &self.cell.grasps[to].name);
            self.diagnostics
                .push(diagnostics::duplicate_transition(a, b, origin, first));
            return;
        }
        self.transition_origins.insert((from, to), origin);
        self.cell.transitions.push(Transition { from, to, origin });
    }

    fn is_hand(&self, holder: Holder) -> bool {
        let kind = match holder {
            Holder::Kind(k) => Some(k),
            Holder::EndEffector(e) => self.cell.end_effectors.get(e).and_then(|e| e.kind),
        };
        kind.is_some_and(|k| self.cell.holder_kinds[k].class == HolderClass::Hand)
    }

    /// `g` (a grasp of `object`) or `other.g` (a grasp of another object: an error, but
    /// resolved first so the message can say whose grasp it is).
    fn qualified_grasp(
        &mut self,
        file: FileId,
        object: ObjectId,
        q: &ast::Qualified,
    ) -> Option<GraspId> {
        match &q.object {
            None => self.grasp_of(file, object, &q.name),
            Some(other) => {
                let other_id = self.object(file, other)?;
                let grasp = self.grasp_of(file, other_id, &q.name)?;
                if other_id != object {
                    let (a, b) = (
                        self.cell.objects[object].name.clone(),
                        self.cell.objects[other_id].name.clone(),
                    );
                    self.diagnostics
                        .push(diagnostics::cross_object_transition(&a, &b, file, q.span));
                    return None;
                }
                Some(grasp)
            }
        }
    }

    fn resolve_expect(&mut self, file: FileId, e: &ast::ExpectItem) {
        let o = Origin {
            file,
            span: e.span,
            name_span: e.span,
        };
        let text = describe_requirement(&e.requirement);
        let requirement = match &e.requirement {
            ast::Requirement::Reach { object, from, to } => {
                let object = self.object(file, object);
                let from = self.placement(file, object, from);
                let to = self.placement(file, object, to);
                let (Some(object), Some(from), Some(to)) = (object, from, to) else {
                    return;
                };
                Requirement::Reach { object, from, to }
            }
            ast::Requirement::Coverage {
                workspace,
                at_least,
                mobility,
            } => Requirement::Coverage {
                workspace: match self.workspace(file, workspace) {
                    Some(w) => w,
                    None => return,
                },
                at_least: at_least.0,
                mobility: *mobility,
            },
            ast::Requirement::NoIsolatedStates { object } => Requirement::NoIsolatedStates {
                object: match object {
                    Some(name) => match self.object(file, name) {
                        Some(o) => Some(o),
                        None => return,
                    },
                    None => None,
                },
            },
        };
        self.cell.expectations.push(Expectation {
            requirement,
            origin: o,
            text,
        });
    }

    /// `HOLDER` or `HOLDER.GRASP` of a placement: the end-effector, and the grasp when one
    /// is written (`Some(None)` when it was written but did not resolve). Every name is
    /// looked up and reported even when an earlier one failed.
    fn holder_and_grasp(
        &mut self,
        file: FileId,
        object: Option<ObjectId>,
        holder: &ast::Qualified,
    ) -> (Option<EndEffectorId>, Option<Option<GraspId>>) {
        let (holder_name, grasp_name) = match &holder.object {
            Some(h) => (h, Some(&holder.name)),
            None => (&holder.name, None),
        };
        let end_effector = self.end_effector(file, holder_name);
        let grasp = match (grasp_name, object) {
            (Some(g), Some(object)) => Some(self.grasp_of(file, object, g)),
            (Some(_), None) => Some(None),
            (None, _) => None,
        };
        (end_effector, grasp)
    }

    fn placement(
        &mut self,
        file: FileId,
        object: Option<ObjectId>,
        p: &ast::Placement,
    ) -> Option<Placement> {
        let (end_effector, grasp) = self.holder_and_grasp(file, object, &p.holder);
        let workspace = self.workspace(file, &p.workspace);
        let grasp = match grasp {
            Some(g) => Some(g?),
            None => None,
        };
        Some(Placement {
            end_effector: end_effector?,
            grasp,
            workspace: workspace?,
            span: p.span,
        })
    }
}

/// The requirement as the user would write it, for messages.
fn describe_requirement(r: &ast::Requirement) -> String {
    fn placement(p: &ast::Placement) -> String {
        let holder = match &p.holder.object {
            Some(e) => format!("{}.{}", e.text, p.holder.name.text),
            None => p.holder.name.text.clone(),
        };
        format!("{holder} in {}", p.workspace.text)
    }
    match r {
        ast::Requirement::Reach { object, from, to } => {
            format!("{}: {} -> {}", object.text, placement(from), placement(to))
        }
        ast::Requirement::Coverage {
            workspace,
            at_least,
            mobility,
        } => {
            let which = match mobility {
                Some(Mobility::Movable) => " movable",
                Some(Mobility::Fixed) => " fixed",
                None => "",
            };
            format!(
                "{} reached by at least {}{which}",
                workspace.text, at_least.0
            )
        }
        ast::Requirement::NoIsolatedStates { object } => match object {
            Some(o) => format!("no isolated states for {}", o.text),
            None => "no isolated states".to_string(),
        },
    }
}
