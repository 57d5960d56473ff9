//! The cell's `world` (where the objects start) and its `task`s (moves in order),
//! resolved with the requests: their placements are a request's, and may name derived
//! workspaces.

use std::collections::HashMap;

use cellc_lang::{ast, FileId, Span};

use super::{origin, Resolver};
use crate::diagnostics::{self, Incomplete, Sort};
use crate::ids::*;
use crate::model::*;
use crate::names::Kind;
use crate::units::FileUnits;

impl Resolver<'_, '_> {
    /// A `world`: each line's object and placement (every name reported); a second
    /// `world`, anywhere in the loaded files, is refused whole.
    pub(super) fn resolve_world(&mut self, file: FileId, units: FileUnits, w: &ast::WorldItem) {
        let here = Origin {
            file,
            span: w.span,
            name_span: Span::new(w.span.start as usize, w.span.start as usize + "world".len()),
        };
        if let Some(first) = self.cell.world_origin {
            self.diagnostics
                .push(diagnostics::second_world(first, here));
            // Refused whole, but its names are written.
            for entry in &w.entries {
                self.used(file, &entry.object);
                self.used_entry(file, entry);
            }
            return;
        }
        self.cell.world_origin = Some(here);
        let mut placed: HashMap<ObjectId, Origin> = HashMap::new();
        for entry in &w.entries {
            let line = origin(file, entry.span, &entry.object);
            let object = self.object(file, &entry.object);
            if let Some(object) = object {
                if let Some(&first) = placed.get(&object) {
                    self.diagnostics.push(diagnostics::placed_twice(
                        &entry.object.text,
                        first,
                        line,
                    ));
                    self.used_entry(file, entry);
                    continue;
                }
                placed.insert(object, line);
            }
            let placement = self.world_placement(file, units, object, entry);
            if let (Some(object), Some(placement)) = (object, placement) {
                self.cell.world.push(InitialPlacement {
                    object,
                    placement,
                    origin: line,
                });
            }
        }
    }

    /// Records the names of a world line's placement where they are not looked up.
    fn used_entry(&mut self, file: FileId, entry: &ast::WorldEntry) {
        match &entry.placement {
            ast::WorldPlacement::Placed(p) => self.used_placement(file, &entry.object.text, p),
            ast::WorldPlacement::Bare(q) => self.used_holder(file, &entry.object.text, q),
        }
    }

    /// A line's placement: a request placement, or a bare `ARM.GRASP` (no workspace, no
    /// pose: the arm's joints give it). A bare holder that is not an arm, or an arm
    /// without its grasp, says too little.
    fn world_placement(
        &mut self,
        file: FileId,
        units: FileUnits,
        object: Option<ObjectId>,
        entry: &ast::WorldEntry,
    ) -> Option<RequestPlacement> {
        let holder = match &entry.placement {
            ast::WorldPlacement::Placed(p) => {
                return self.request_placement(file, units, object, p)
            }
            ast::WorldPlacement::Bare(holder) => holder,
        };
        let (end_effector, grasp) = self.holder_and_grasp(file, object, holder);
        let end_effector = end_effector?;
        let grasp = match grasp {
            Some(g) => Some(g?),
            None => None,
        };
        let written = match &holder.object {
            Some(h) => format!("{}.{}", h.text, holder.name.text),
            None => holder.name.text.clone(),
        };
        let ee = &self.cell.end_effectors[end_effector];
        let is_arm = matches!(ee.body, Body::Arm { .. });
        let what = match (is_arm, grasp, object) {
            (true, Some(grasp), _) => {
                return Some(RequestPlacement {
                    end_effector,
                    grasp: Some(grasp),
                    workspace: None,
                    pose: None,
                })
            }
            (false, _, _) => Incomplete::NotAnArm { written: &written },
            (true, None, Some(object)) => Incomplete::NoGrasp {
                arm: &ee.name,
                suggestion: self.cell.objects[object]
                    .grasps
                    .iter()
                    .find(|&&g| self.cell.holds(end_effector, g))
                    .map(|&g| self.cell.grasps[g].name.as_str()),
            },
            // The object is unknown, and said so: which grasp it needs cannot be told.
            (true, None, None) => return None,
        };
        let diagnostic =
            diagnostics::world_placement_incomplete(&entry.object.text, what, file, holder.span);
        self.diagnostics.push(diagnostic);
        None
    }

    /// A `task`: every step resolved like a request's goal (all names reported). Task
    /// names share the requests' namespace, so `cellc plan` and `cellc run` can take either
    /// name without ambiguity.
    pub(super) fn resolve_task(&mut self, file: FileId, units: FileUnits, t: &ast::TaskItem) {
        self.declared(file, &t.name, Kind::Task, t.span);
        let here = origin(file, t.span, &t.name);
        if t.steps.is_empty() {
            self.diagnostics
                .push(diagnostics::empty_task(&t.name.text, here));
            return;
        }
        let mut steps = Vec::with_capacity(t.steps.len());
        for step in &t.steps {
            let object = self.object(file, &step.object);
            let to = self.request_placement(file, units, object, &step.to);
            if let (Some(object), Some(to)) = (object, to) {
                steps.push(TaskStep {
                    object,
                    to,
                    origin: origin(file, step.span, &step.object),
                });
            }
        }
        if steps.len() < t.steps.len() {
            return;
        }
        if let Some(&first) = self.request_names.get(&t.name.text) {
            self.diagnostics.push(diagnostics::duplicate_name(
                Sort::Task,
                &t.name.text,
                first,
                here,
            ));
            return;
        }
        self.request_names.insert(t.name.text.clone(), here);
        self.cell.tasks.push(NamedTask {
            name: t.name.text.clone(),
            steps,
            origin: here,
        });
    }
}
