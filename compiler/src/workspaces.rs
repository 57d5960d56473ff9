//! Workspace derivation and reach: which end-effector reaches which workspace.
//!
//! Abstract end-effectors list the workspaces they reach. Geometric ones have reach
//! cuboids (arms: declared `reach` boxes; surfaces: a thin extrusion above the top face).
//! With `workspaces from reach`, space is cut along every cuboid face into cells, each
//! cell is labelled with the set of end-effectors whose reach covers it, and the cells
//! of one label form one workspace. Workspaces therefore never overlap, and two of them
//! are adjacent exactly when a movable end-effector reaches both.

use std::collections::BTreeMap;

use cellc_lang::Diagnostic;

use crate::diagnostics;
use crate::ids::*;
use crate::math::{contains_point, covered_by_union, Aabb, Point, EPS};
use crate::model::*;

/// The reach cuboids of a geometric end-effector (empty for abstract ones).
pub fn reach_boxes(e: &EndEffector) -> Vec<Aabb> {
    match &e.body {
        Body::Abstract => Vec::new(),
        Body::Arm { .. } => e.reach_boxes.clone(),
        Body::Surface { slab, reach_height } => vec![Aabb::new(
            Point::new(slab.mins[0], slab.mins[1], slab.maxs[2]),
            Point::new(slab.maxs[0], slab.maxs[1], slab.maxs[2] + reach_height),
        )],
    }
}

/// The most box tests deriving workspaces may take (space cells times the boxes each is
/// tested against), and again the most that finding who reaches which workspace may take
/// (reach boxes times workspace boxes). Every box face cuts space along its plane, so
/// `n` scattered boxes make up to `8 n³` cells: forty arms are fine, a thousand are not.
pub const MAX_DERIVATION_WORK: u64 = 100_000_000;

/// Derives workspaces when asked, then fills `reaches` of every geometric end-effector.
/// Refuses (E0321) geometry that would exceed [`MAX_DERIVATION_WORK`].
pub fn assign(cell: &mut Cell, diagnostics: &mut Vec<Diagnostic>) {
    let reach: Vec<(EndEffectorId, Vec<Aabb>)> = cell
        .end_effectors
        .iter()
        .map(|(id, e)| (id, reach_boxes(e)))
        .filter(|(_, boxes)| !boxes.is_empty())
        .collect();
    if let Some(origin) = cell.derive_workspaces {
        if reach.is_empty() {
            diagnostics.push(diagnostics::derivation_conflict(
                "`workspaces from reach` but nothing in the cell has a reach box",
                origin,
                "add `reach ARM box ...` lines or surfaces, or declare the workspaces",
            ));
        } else if let Err(work) = derive(cell, &reach, origin) {
            // Declared workspaces still get their reach, so nothing else is misreported.
            diagnostics.push(diagnostics::derivation_too_large(
                origin,
                work,
                MAX_DERIVATION_WORK,
            ));
        }
    }
    let workspace_boxes: u64 = cell
        .workspaces
        .iter()
        .map(|(_, w)| w.boxes.len() as u64)
        .sum();
    let reach_boxes: u64 = reach.iter().map(|(_, b)| b.len() as u64).sum();
    let work = workspace_boxes.saturating_mul(reach_boxes);
    if work > MAX_DERIVATION_WORK {
        let at = cell
            .derive_workspaces
            .or_else(|| reach.first().map(|(e, _)| cell.end_effectors[*e].origin));
        if let Some(origin) = at {
            diagnostics.push(diagnostics::derivation_too_large(
                origin,
                work,
                MAX_DERIVATION_WORK,
            ));
        }
        return;
    }
    for (e, boxes) in &reach {
        let mut reaches: Vec<WorkspaceId> = cell
            .workspaces
            .iter()
            .filter(|(_, w)| {
                !w.boxes.is_empty() && w.boxes.iter().all(|b| covered_by_union(b, boxes))
            })
            .map(|(id, _)| id)
            .collect();
        reaches.extend(cell.end_effectors[*e].reaches.iter().copied());
        reaches.sort();
        reaches.dedup();
        cell.end_effectors[*e].reaches = reaches;
    }
}

/// Cuts space along every box face and names the regions; `Err` with the work it would
/// take when that is over [`MAX_DERIVATION_WORK`].
fn derive(
    cell: &mut Cell,
    reach: &[(EndEffectorId, Vec<Aabb>)],
    origin: Origin,
) -> Result<(), u64> {
    let declared: Vec<Aabb> = cell
        .workspaces
        .iter()
        .flat_map(|(_, w)| w.boxes.iter().copied())
        .collect();
    // Surfaces are solid: space inside a slab is no place for an object.
    let solids: Vec<Aabb> = cell
        .end_effectors
        .iter()
        .filter_map(|(_, e)| match &e.body {
            Body::Surface { slab, .. } => Some(*slab),
            _ => None,
        })
        .chain(cell.obstacles.iter().map(|o| o.1))
        .collect();
    let cuts: [Vec<f64>; 3] = [0, 1, 2].map(|axis| {
        // Declared workspaces cut space too, so that no derived cell straddles one.
        let mut cuts: Vec<f64> = reach
            .iter()
            .flat_map(|(_, boxes)| boxes.iter())
            .chain(declared.iter())
            .chain(solids.iter())
            .flat_map(|b| [b.mins[axis], b.maxs[axis]])
            .collect();
        cuts.sort_by(f64::total_cmp);
        cuts.dedup_by(|a, b| (*a - *b).abs() <= EPS);
        cuts
    });
    let cells = cuts
        .iter()
        .map(|c| c.len().saturating_sub(1) as u64)
        .fold(1u64, u64::saturating_mul);
    let tested = (declared.len() + solids.len()) as u64
        + reach.iter().map(|(_, b)| b.len() as u64).sum::<u64>();
    let work = cells.saturating_mul(tested.max(1));
    if work > MAX_DERIVATION_WORK {
        return Err(work);
    }
    // label (sorted end-effectors) -> cells; BTreeMap so that naming and order are
    // deterministic.
    let mut regions: BTreeMap<Vec<EndEffectorId>, Vec<Aabb>> = BTreeMap::new();
    for x in cuts[0].windows(2) {
        for y in cuts[1].windows(2) {
            for z in cuts[2].windows(2) {
                let cell_box =
                    Aabb::new(Point::new(x[0], y[0], z[0]), Point::new(x[1], y[1], z[1]));
                let center = cell_box.center();
                if declared
                    .iter()
                    .chain(&solids)
                    .any(|b| contains_point(b, &center))
                {
                    continue;
                }
                let label: Vec<EndEffectorId> = reach
                    .iter()
                    .filter(|(_, boxes)| boxes.iter().any(|b| contains_point(b, &center)))
                    .map(|(e, _)| *e)
                    .collect();
                // Nothing can bring an object into space no movable end-effector
                // reaches, so such space is not a workspace.
                if label.iter().any(|&e| cell.end_effectors[e].is_movable()) {
                    regions.entry(label).or_default().push(cell_box);
                }
            }
        }
    }
    let mut taken: std::collections::HashSet<String> = cell
        .end_effectors
        .iter()
        .map(|(_, e)| e.name.clone())
        .chain(cell.workspaces.iter().map(|(_, w)| w.name.clone()))
        .chain(cell.objects.iter().map(|(_, o)| o.name.clone()))
        .chain(cell.holder_kinds.iter().map(|(_, k)| k.name.clone()))
        .chain(cell.robots.iter().map(|(_, r)| r.name.clone()))
        .chain(cell.obstacles.iter().map(|o| o.0.clone()))
        .collect();
    // Name order follows the order of the end-effectors' declarations.
    let mut ordered: Vec<(Vec<EndEffectorId>, Vec<Aabb>)> = regions.into_iter().collect();
    ordered.sort_by(|a, b| a.0.cmp(&b.0));
    for (label, boxes) in ordered {
        let names: Vec<&str> = label
            .iter()
            .map(|&e| cell.end_effectors[e].name.as_str())
            .collect();
        let base = format!("ws_{}", names.join("_"));
        let mut name = base.clone();
        let mut n = 2;
        while taken.contains(&name) {
            name = format!("{base}_{n}");
            n += 1;
        }
        taken.insert(name.clone());
        cell.workspaces.insert(Workspace {
            name,
            label: Some(format!("reached by {}", names.join(", "))),
            boxes: crate::merge::merge_boxes(boxes),
            origin,
            derived: true,
        });
    }
    Ok(())
}
