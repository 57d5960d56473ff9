//! Grasp and rest families: one line that declares many grasps or resting poses related
//! by a motion of the holder round the object (`every 30 deg about z`, `along z at (...)`)
//! or read from a grasp-set file (`from "FILE"`), expanded here into members.
//!
//! **Members and names.** A family's members are every combination of its index ranges:
//! first the row of its file (when it has one), then each clause in written order
//! (`every STEP about AXIS`: 0 up to the last step before a full turn; `along AXIS at
//! (D0, D1, ...)`: one per offset). A member is named `NAME_I` (one range) or
//! `NAME_I_J...` (one index per range, in that order), counted from 0, so the names
//! depend only on the line, never on the object's symmetry or on other lines.
//!
//! **Poses.** The clauses move the *holder* in the object's frame, the first clause
//! first: member (i, j) of `every 30 deg about z along z at (...)` is the holder moved by
//! offset j along z, then turned by i x 30° about z. With `T` the written pose (the
//! object in the holder's frame) and `M` that motion, the member's pose is `T * M⁻¹`.
//!
//! **Symmetry.** Two members that differ by a symmetry of the object (the holder turned
//! about a `symmetry` axis through the object's origin) are one state: the first in
//! index order is kept, and a later one's name is an alias of it (usable anywhere the
//! member's own name is, meaning the kept member). So `every 30 deg about z` on an
//! object with `symmetry about z` is one grasp, and on one with `symmetry about z order
//! 2` six.

use cellc_lang::{ast, FileId, Span};
use cellc_schema::files::join;

use super::{origin, Resolver, MAX_FAMILY_MEMBERS};
use crate::diagnostics::{self, Sort};
use crate::ids::*;
use crate::math::{Iso, Quat, Vec3};
use crate::model::*;
use crate::units::FileUnits;

/// Poses closer than this (metres, radians) are the same member.
const SAME_POSE: f64 = 1e-7;

/// A family as the resolver keeps it: every member by index, with the grasp it means
/// (aliases mean the member they duplicate).
#[derive(Clone, Debug)]
pub(super) struct Family {
    /// Members in index order: (indices, grasp).
    pub members: Vec<(Vec<usize>, GraspId)>,
    /// The size of each index range.
    pub dims: Vec<usize>,
    /// The line.
    pub span: Span,
}

impl Family {
    /// The distinct grasps, in index order of their first member.
    pub fn distinct(&self) -> Vec<GraspId> {
        let mut seen = std::collections::HashSet::new();
        self.members
            .iter()
            .filter(|(_, g)| seen.insert(*g))
            .map(|(_, g)| *g)
            .collect()
    }
}

/// One side of a transition line.
pub(super) enum Side {
    /// One grasp.
    Grasp(GraspId),
    /// A family.
    Family(Family),
}

impl Side {
    /// The distinct grasps the side means.
    fn grasps(&self) -> Vec<GraspId> {
        match self {
            Side::Grasp(g) => vec![*g],
            Side::Family(f) => f.distinct(),
        }
    }

    /// For messages: "one grasp" or "a family of 3 x 4 members".
    fn describe(&self) -> String {
        match self {
            Side::Grasp(_) => "one grasp".to_string(),
            Side::Family(f) => {
                let dims: Vec<String> = f.dims.iter().map(usize::to_string).collect();
                format!("a family of {} members", dims.join(" x "))
            }
        }
    }
}

/// One index range of a family, its motions in index order.
enum Range {
    /// The rows of a file: each a base pose.
    Rows,
    /// The holder's motions in the object frame.
    Motions(Vec<Iso>),
}

fn unit_axis(axis: ast::Axis) -> nalgebra::Unit<Vec3> {
    match axis {
        ast::Axis::X => Vec3::x_axis(),
        ast::Axis::Y => Vec3::y_axis(),
        ast::Axis::Z => Vec3::z_axis(),
    }
}

/// The member name for `indices`.
pub fn member_name(family: &str, indices: &[usize]) -> String {
    let mut name = family.to_string();
    for i in indices {
        name.push('_');
        name.push_str(&i.to_string());
    }
    name
}

impl Resolver<'_, '_> {
    /// Declares the members of the family `g` of object `id`.
    pub(super) fn declare_family(
        &mut self,
        file: FileId,
        path: &str,
        units: FileUnits,
        id: ObjectId,
        g: &ast::GraspMember,
    ) {
        let go = origin(file, g.span, &g.name);
        if let Some(first) = self.family_or_grasp_origin(id, &g.name.text) {
            self.diagnostics.push(diagnostics::duplicate_name(
                Sort::Grasp,
                &g.name.text,
                first,
                go,
            ));
            return;
        }
        // Registered before expansion, so that a family whose expansion failed is still
        // known by name (its transitions then report nothing more).
        self.families.insert(
            id,
            g.name.text.clone(),
            Family {
                members: Vec::new(),
                dims: Vec::new(),
                span: g.span,
            },
        );
        let written = g.pose.as_ref().and_then(|p| self.eval(file, units).pose(p));
        if g.pose.is_some() && written.is_none() {
            return;
        }
        // The base poses: the file's rows, or the one written pose.
        let mut bases: Vec<Option<Iso>> = vec![written];
        let mut ranges: Vec<Range> = Vec::new();
        if let Some(name) = &g.file {
            let grasps = join(path, &name.value);
            let Some(&fid) = self.loaded.grasp_files.get(&grasps) else {
                return; // Not read: reported when it was loaded.
            };
            let rows =
                crate::grasp_file::parse(fid, &self.loaded.sources.get(fid).text, self.diagnostics);
            if rows.failed {
                return;
            }
            if rows.poses.is_empty() {
                self.diagnostics.push(diagnostics::family_empty(
                    &g.name.text,
                    file,
                    name.span,
                    "the grasp-set file has no rows",
                ));
                return;
            }
            bases = rows.poses.iter().map(|(p, _)| Some(*p)).collect();
            ranges.push(Range::Rows);
        }
        let mut count = bases.len() as f64;
        for clause in &g.family {
            let motions = match clause {
                ast::FamilyClause::Every { step, axis, span } => {
                    let Some(step_rad) = self.eval(file, units).angle(step) else {
                        return;
                    };
                    if step_rad.is_nan() || step_rad <= 0.0 {
                        self.diagnostics.push(diagnostics::family_empty(
                            &g.name.text,
                            file,
                            *span,
                            "the step is not positive",
                        ));
                        return;
                    }
                    let steps = (std::f64::consts::TAU / step_rad - 1e-9).ceil().max(1.0);
                    count *= steps;
                    if count > MAX_FAMILY_MEMBERS as f64 {
                        break;
                    }
                    let a = unit_axis(*axis);
                    (0..steps as usize)
                        .map(|k| {
                            Iso::from_parts(
                                Default::default(),
                                Quat::from_axis_angle(&a, step_rad * k as f64),
                            )
                        })
                        .collect()
                }
                ast::FamilyClause::Along { axis, offsets, .. } => {
                    count *= offsets.len() as f64;
                    if count > MAX_FAMILY_MEMBERS as f64 {
                        break;
                    }
                    let a = unit_axis(*axis);
                    let mut out = Vec::new();
                    for q in offsets {
                        let Some(d) = self.eval(file, units).length(q) else {
                            return;
                        };
                        out.push(Iso::translation(a.x * d, a.y * d, a.z * d));
                    }
                    out
                }
            };
            ranges.push(Range::Motions(motions));
        }
        if count > MAX_FAMILY_MEMBERS as f64 {
            let span = g
                .family
                .first()
                .map_or(g.span, |c| c.span())
                .join(g.family.last().map_or(g.span, |c| c.span()));
            let span = match &g.file {
                Some(f) => f.span.join(span),
                None => span,
            };
            self.diagnostics.push(diagnostics::family_too_large(
                &g.name.text,
                count,
                file,
                span,
            ));
            return;
        }
        let dims: Vec<usize> = ranges
            .iter()
            .map(|r| match r {
                Range::Rows => bases.len(),
                Range::Motions(m) => m.len(),
            })
            .collect();
        let symmetries: Vec<cellc_schema::Symmetry> = self.cell.objects[id]
            .symmetries
            .iter()
            .map(|s| cellc_schema::Symmetry {
                axis: s.axis,
                order: s.order,
            })
            .collect();
        let mut members = Vec::new();
        let mut kept: Vec<(Iso, GraspId)> = Vec::new();
        for indices in index_tuples(&dims) {
            let mut base = bases[0];
            let mut motion = Iso::identity();
            for (range, &i) in ranges.iter().zip(&indices) {
                match range {
                    Range::Rows => base = bases[i],
                    // Later clauses move the holder after earlier ones.
                    Range::Motions(m) => motion = m[i] * motion,
                }
            }
            let pose = base.unwrap_or_else(Iso::identity) * motion.inverse();
            let name = member_name(&g.name.text, &indices);
            if let Some(first) = self.family_or_grasp_origin(id, &name) {
                self.diagnostics
                    .push(diagnostics::duplicate_name(Sort::Grasp, &name, first, go));
                continue;
            }
            let same = kept.iter().find(|(k, _)| {
                let rel = k.inverse() * pose;
                rel.translation.vector.norm() < SAME_POSE
                    && cellc_schema::symmetry::residual(&rel.rotation, &symmetries) < SAME_POSE
            });
            let gid = match same {
                Some(&(_, gid)) => gid,
                None => {
                    let gid = self.cell.grasps.insert(Grasp {
                        name: name.clone(),
                        label: g
                            .label
                            .as_ref()
                            .map(|l| format!("{} ({})", l.value, &name[g.name.text.len() + 1..])),
                        object: id,
                        holder: None,
                        keyword: g.keyword,
                        pose: base.map(|b| b * motion.inverse()),
                        origin: go,
                    });
                    self.cell.objects[id].grasps.push(gid);
                    kept.push((pose, gid));
                    gid
                }
            };
            self.grasp_names.insert(id, name, gid);
            members.push((indices, gid));
        }
        self.families.insert(
            id,
            g.name.text.clone(),
            Family {
                members,
                dims,
                span: g.span,
            },
        );
    }

    /// One side of a transition: a grasp, or every member of a family (by index).
    pub(super) fn transition_side(
        &mut self,
        file: FileId,
        id: ObjectId,
        q: &ast::Qualified,
    ) -> Option<Side> {
        if q.object.is_none() && self.families.get(id, &q.name.text).is_some() {
            // Not looked up by `grasp_of`: recorded here.
            let object = self.cell.objects[id].name.clone();
            self.used_grasp(file, &object, &q.name);
            if let Some(f) = self.families.get(id, &q.name.text) {
                // A family whose expansion failed was reported where it is declared.
                if f.members.is_empty() {
                    if !self.cell.incomplete_objects.contains(&id) {
                        self.cell.incomplete_objects.push(id);
                    }
                    return None;
                }
                return Some(Side::Family(f.clone()));
            }
        }
        self.qualified_grasp(file, id, q).map(Side::Grasp)
    }

    /// The directed pairs `from -> to` of transition line `t`: every member with every
    /// member, or with `matching` the members of equal indices.
    pub(super) fn side_pairs(
        &mut self,
        file: FileId,
        t: &ast::TransitionMember,
        from: &Side,
        to: &Side,
    ) -> Option<Vec<(GraspId, GraspId)>> {
        if let Some(span) = t.matching {
            return match (from, to) {
                (Side::Family(a), Side::Family(b)) if a.dims == b.dims => Some(
                    a.members
                        .iter()
                        .zip(&b.members)
                        .map(|((_, x), (_, y))| (*x, *y))
                        .collect(),
                ),
                _ => {
                    self.diagnostics.push(diagnostics::family_mismatch(
                        file,
                        t.span.join(span),
                        &from.describe(),
                        &to.describe(),
                    ));
                    None
                }
            };
        }
        let left = from.grasps();
        let right = to.grasps();
        Some(
            left.iter()
                .flat_map(|&a| right.iter().map(move |&b| (a, b)))
                .collect(),
        )
    }

    /// Where `name` is already declared in object `id`, as a grasp, a member or a family.
    fn family_or_grasp_origin(&self, id: ObjectId, name: &str) -> Option<Origin> {
        if let Some(&g) = self.grasp_names.get(id, name) {
            return Some(self.cell.grasps[g].origin);
        }
        self.families.get(id, name).map(|f| Origin {
            file: self.cell.objects[id].origin.file,
            span: f.span,
            name_span: f.span,
        })
    }
}

/// Every index tuple of ranges of sizes `dims`, in lexicographic order.
fn index_tuples(dims: &[usize]) -> Vec<Vec<usize>> {
    let mut out = vec![Vec::new()];
    for &n in dims {
        out = out
            .into_iter()
            .flat_map(|prefix| {
                (0..n).map(move |i| {
                    let mut t = prefix.clone();
                    t.push(i);
                    t
                })
            })
            .collect();
    }
    out
}
