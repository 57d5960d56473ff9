//! `allow contact A B`: the names of collision bodies (arms, their links and hands,
//! surfaces, obstacles, objects).

use cellc_lang::ast;
use cellc_lang::diagnostic::did_you_mean;
use cellc_lang::{Diagnostic, FileId};

use super::{Entry, Resolver};
use crate::diagnostics::{self, Sort};
use crate::model::*;

impl Resolver<'_, '_> {
    /// `allow contact A B`: both bodies must exist; a dotted name is a link or the hand of
    /// an arm.
    pub(super) fn resolve_allow(&mut self, file: FileId, item: &ast::AllowItem) {
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
            self.used(file, &q.name);
            if self.obstacle_names.contains(&q.name.text) {
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
            // An arm whose robot did not load: that error is reported where the robot
            // is; its links are unknown, not missing.
            Body::Arm { robot: None, .. } => return None,
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
        let suggestion = self.suggestions.search(|| {
            did_you_mean(
                &q.name.text,
                robot
                    .links
                    .iter()
                    .map(String::as_str)
                    .chain(hand.as_deref()),
            )
        });
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
}
