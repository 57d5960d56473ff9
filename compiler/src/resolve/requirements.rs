//! The cell's own requirements (`expect`) and named example requests (`request`),
//! resolved last since their placements may name derived workspaces (the `world` and
//! `task`s, whose placements are a request's, are in `world.rs`).

use cellc_lang::ast::{self, Mobility};
use cellc_lang::FileId;

use super::{origin, Resolver};
use crate::diagnostics::{self, Sort};
use crate::ids::*;
use crate::model::*;
use crate::names::Kind;
use crate::units::FileUnits;

impl Resolver<'_, '_> {
    pub(super) fn resolve_expect(&mut self, file: FileId, e: &ast::ExpectItem) {
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

    /// A `request`: every name resolved (all reported), poses in SI.
    pub(super) fn resolve_request(&mut self, file: FileId, units: FileUnits, q: &ast::RequestItem) {
        self.declared(file, &q.name, Kind::Request, q.span);
        let object = self.object(file, &q.object);
        let from = self.request_placement(file, units, object, &q.from);
        let to = self.request_placement(file, units, object, &q.to);
        let (Some(object), Some(from), Some(to)) = (object, from, to) else {
            return;
        };
        if let Some(&first) = self.request_names.get(&q.name.text) {
            let origin = origin(file, q.span, &q.name);
            self.diagnostics.push(diagnostics::duplicate_name(
                Sort::Request,
                &q.name.text,
                first,
                origin,
            ));
            return;
        }
        self.request_names
            .insert(q.name.text.clone(), origin(file, q.span, &q.name));
        self.cell.requests.push(NamedRequest {
            name: q.name.text.clone(),
            object,
            from,
            to,
            origin: origin(file, q.span, &q.name),
        });
    }

    pub(super) fn request_placement(
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
