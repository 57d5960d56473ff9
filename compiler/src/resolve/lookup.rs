//! Name lookups: a name of the wanted sort, or a report (unknown, with a suggestion among
//! names of that sort; or declared as something else). Each lookup records the name it
//! looked up in the table of names ([`crate::names`]), and the declaring passes record
//! their declarations through [`Resolver::declared`] and [`Resolver::declared_grasp`].

use cellc_lang::ast;
use cellc_lang::diagnostic::did_you_mean;
use cellc_lang::{FileId, Span};

use super::{Entry, Resolver};
use crate::diagnostics::{self, Sort};
use crate::ids::*;
use crate::names::{Key, Kind};

impl Resolver<'_, '_> {
    /// Records that `name` declares a name of the one namespace (or, for requests and
    /// tasks, of theirs) in the item at `item`.
    pub(super) fn declared(&mut self, file: FileId, name: &ast::Name, kind: Kind, item: Span) {
        let key = match kind {
            Kind::Request | Kind::Task => Key::Request(name.text.clone()),
            _ => Key::Global(name.text.clone()),
        };
        self.written.declare(file, name.span, key, kind, item);
    }

    /// Records that `name` declares a grasp or resting pose of the object `object`.
    pub(super) fn declared_grasp(
        &mut self,
        file: FileId,
        object: &str,
        name: &ast::Name,
        kind: Kind,
        item: Span,
    ) {
        let key = Key::Grasp {
            object: object.to_string(),
            grasp: name.text.clone(),
        };
        self.written.declare(file, name.span, key, kind, item);
    }

    /// Records a use of `name` in the one namespace.
    pub(super) fn used(&mut self, file: FileId, name: &ast::Name) {
        self.written
            .uses(file, name.span, Key::Global(name.text.clone()));
    }

    /// Records a use of `name` as a grasp of the object named `object`.
    pub(super) fn used_grasp(&mut self, file: FileId, object: &str, name: &ast::Name) {
        let key = Key::Grasp {
            object: object.to_string(),
            grasp: name.text.clone(),
        };
        self.written.uses(file, name.span, key);
    }

    /// Records the names of `HOLDER` or `HOLDER.GRASP`, a placement of the object named
    /// `object`, where the resolver does not look them up (the item is refused before).
    pub(super) fn used_holder(&mut self, file: FileId, object: &str, holder: &ast::Qualified) {
        match &holder.object {
            Some(h) => {
                self.used(file, h);
                self.used_grasp(file, object, &holder.name);
            }
            None => self.used(file, &holder.name),
        }
    }

    /// Records the names of a request placement of the object named `object` where the
    /// resolver does not look them up.
    pub(super) fn used_placement(&mut self, file: FileId, object: &str, p: &ast::RequestPlacement) {
        self.used_holder(file, object, &p.holder);
        if let ast::PlaceSpec::In(w) = &p.place {
            self.used(file, w);
        }
    }

    /// Records the names of one side of a transition of the object named `object`
    /// (`g`, or `OTHER.g`) where the resolver does not look them up.
    pub(super) fn used_side(&mut self, file: FileId, object: &str, q: &ast::Qualified) {
        match &q.object {
            Some(other) => {
                self.used(file, other);
                self.used_grasp(file, &other.text, &q.name);
            }
            None => self.used_grasp(file, object, &q.name),
        }
    }

    /// Looks a name up, wanting one sort. Reports unknown names (with a suggestion among
    /// names of the wanted sort) and names of the wrong sort.
    pub(super) fn lookup(
        &mut self,
        file: FileId,
        name: &ast::Name,
        want: Sort,
        context: &str,
    ) -> Option<Entry> {
        self.used(file, name);
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
            None if want == Sort::Workspace && self.workspaces_incomplete => None,
            None => {
                let names = &self.names;
                let suggestion = self.suggestions.search(|| {
                    did_you_mean(
                        &name.text,
                        names
                            .iter()
                            .filter(|(_, e)| e.sort() == want)
                            .map(|(n, _)| n.as_str()),
                    )
                });
                self.diagnostics.push(diagnostics::unknown_name(
                    want, &name.text, file, name.span, suggestion, context,
                ));
                None
            }
        }
    }

    pub(super) fn workspace(&mut self, file: FileId, name: &ast::Name) -> Option<WorkspaceId> {
        match self.lookup(file, name, Sort::Workspace, "")? {
            Entry::Workspace(id) => Some(id),
            _ => None,
        }
    }

    pub(super) fn end_effector(&mut self, file: FileId, name: &ast::Name) -> Option<EndEffectorId> {
        match self.lookup(file, name, Sort::EndEffector, "")? {
            Entry::EndEffector(id) => Some(id),
            _ => None,
        }
    }

    pub(super) fn object(&mut self, file: FileId, name: &ast::Name) -> Option<ObjectId> {
        match self.lookup(file, name, Sort::Object, "")? {
            Entry::Object(id) => Some(id),
            _ => None,
        }
    }

    pub(super) fn kind(&mut self, file: FileId, name: &ast::Name) -> Option<HolderKindId> {
        match self.lookup(file, name, Sort::HolderKind, " with `hand` or `support`")? {
            Entry::HolderKind(id) => Some(id),
            _ => None,
        }
    }

    pub(super) fn grasp_of(
        &mut self,
        file: FileId,
        object: ObjectId,
        name: &ast::Name,
    ) -> Option<GraspId> {
        let object_name = self.cell.objects[object].name.clone();
        self.used_grasp(file, &object_name, name);
        if let Some(&g) = self.grasp_names.get(object, &name.text) {
            return Some(g);
        }
        if let Some(f) = self.families.get(object, &name.text) {
            if let Some((indices, _)) = f.members.first() {
                let first = crate::resolve::member_name(&name.text, indices);
                let n = f.members.len();
                self.diagnostics.push(diagnostics::family_not_a_grasp(
                    &name.text, &first, n, file, name.span,
                ));
            }
            return None;
        }
        let cell = &self.cell;
        let suggestion = self.suggestions.search(|| {
            did_you_mean(
                &name.text,
                cell.objects[object]
                    .grasps
                    .iter()
                    .map(|&g| cell.grasps[g].name.as_str()),
            )
        });
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

    /// `g` (a grasp of `object`) or `other.g` (a grasp of another object: an error, but
    /// resolved first so the message can say whose grasp it is).
    pub(super) fn qualified_grasp(
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

    /// `HOLDER` or `HOLDER.GRASP` of a placement: the end-effector, and the grasp when one
    /// is written (`Some(None)` when it was written but did not resolve). Every name is
    /// looked up and reported even when an earlier one failed.
    pub(super) fn holder_and_grasp(
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
}
