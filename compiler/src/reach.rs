//! `reach ARM auto`: an arm's reach boxes computed from its kinematics and its grasps
//! rather than written by hand.
//!
//! The compiler does not compute kinematics (it depends on neither the runtime nor a
//! solver; crates depend `compiler -> urdf, schema` only): it asks a [`ReachSolver`], a
//! seam like [`Files`](cellc_schema::Files), which the `cellc` binary implements with the
//! runtime. What crosses the seam is plain data: the cell so far as an artifact without
//! workspaces or graphs (robots, arms, hands, objects with their grasps, surfaces,
//! obstacles, allowed contacts: everything a scene is built from), and per arm the
//! regions to look in. The answers are boxes, which become the arm's reach boxes before
//! workspaces are derived, so everything after (derivation, graphs, the artifact) is as if
//! the boxes had been written; the same cell gives the same boxes and the same artifact.
//!
//! The regions are the reach spaces of the cell's surfaces (each surface's top face
//! extruded by its reach height): workspaces are where an arm's reach meets a surface's
//! or another arm's, and reach over a surface is what an engineer writes by hand. One box
//! per surface, at most, keeps the result readable. How the solver samples, and how far
//! its boxes may be from the true reachable set, is documented in `docs/language.md`
//! (section "Reach from kinematics").

use std::time::Duration;

use cellc_lang::{Diagnostic, SourceMap};
use cellc_schema as schema;
use cellc_schema::math::{aabb_from_schema, aabb_to_schema, Aabb};

use crate::diagnostics::{self, ReachAutoProblem};
use crate::ids::EndEffectorId;
use crate::model::{Body, Cell, Holder, HolderClass};

/// Where to look for one arm's reach.
#[derive(Clone, Debug, PartialEq)]
pub struct ReachQuery {
    /// The arm: index into the scene's end-effectors.
    pub arm: u32,
    /// The regions, one box at most each.
    pub regions: Vec<ReachRegion>,
}

/// A region an arm's reach is looked for in: a surface's reach space.
#[derive(Clone, Debug, PartialEq)]
pub struct ReachRegion {
    /// The surface: index into the scene's end-effectors.
    pub surface: u32,
    /// Its reach space: the top face of its slab, extruded by its reach height.
    pub space: schema::Aabb,
}

/// The reach found for one arm.
#[derive(Clone, Debug, PartialEq)]
pub struct ReachFound {
    /// One box per region where the arm reaches anything: (surface, box).
    pub boxes: Vec<(u32, schema::Aabb)>,
    /// Places (grid points) tried.
    pub tried: u64,
    /// Inverse-kinematics solves run.
    pub solves: u64,
    /// How long the arm took.
    pub elapsed: Duration,
}

/// Computes the reach of arms declared with `reach ARM auto`.
pub trait ReachSolver {
    /// The reach of each query's arm in `scene` (an artifact with no workspaces and empty
    /// graphs; its spans point into `sources`), one answer per query in order; `Err` with
    /// diagnostics when the scene cannot be built or is wrong whatever the reach (a home
    /// that collides).
    fn solve(
        &self,
        scene: &schema::Artifact,
        sources: &SourceMap,
        queries: &[ReachQuery],
    ) -> Result<Vec<Result<ReachFound, ReachAutoProblem>>, Vec<Diagnostic>>;
}

/// No kinematics: every `reach auto` is an error that says to compile with `cellc`. What
/// [`crate::compile`] uses; the binary passes the runtime's solver to
/// [`crate::compile_with`].
#[derive(Clone, Copy, Debug, Default)]
pub struct NoReachSolver;

impl ReachSolver for NoReachSolver {
    fn solve(
        &self,
        _: &schema::Artifact,
        _: &SourceMap,
        queries: &[ReachQuery],
    ) -> Result<Vec<Result<ReachFound, ReachAutoProblem>>, Vec<Diagnostic>> {
        Ok(queries
            .iter()
            .map(|_| Err(ReachAutoProblem::NoKinematics))
            .collect())
    }
}

/// What `reach auto` found for one arm, for `cellc info`.
#[derive(Clone, Debug, PartialEq)]
pub struct AutoReach {
    /// The arm.
    pub end_effector: EndEffectorId,
    /// The boxes, each with the surface it is over.
    pub boxes: Vec<(String, Aabb)>,
    /// Places tried.
    pub tried: u64,
    /// Inverse-kinematics solves run.
    pub solves: u64,
    /// How long it took.
    pub elapsed: Duration,
}

/// Fills the reach boxes of every arm declared with `reach ARM auto` (called between
/// resolving references and deriving workspaces). Problems are reported at the `reach`
/// line.
pub fn compute(
    cell: &mut Cell,
    sources: &SourceMap,
    solver: &dyn ReachSolver,
    diagnostics: &mut Vec<Diagnostic>,
) -> Vec<AutoReach> {
    // An arm whose robot did not load has its error already; a cell with errors so far
    // is not worth sampling (its scene may be partial).
    let auto: Vec<EndEffectorId> = cell
        .end_effectors
        .iter()
        .filter(|(_, e)| e.reach_auto.is_some())
        .filter(|(_, e)| matches!(e.body, Body::Arm { robot: Some(_), .. }))
        .map(|(id, _)| id)
        .collect();
    if auto.is_empty() || diagnostics.iter().any(Diagnostic::is_error) {
        return Vec::new();
    }
    let regions: Vec<ReachRegion> = cell
        .end_effectors
        .iter()
        .filter(|(_, e)| matches!(e.body, Body::Surface { .. }))
        .filter_map(|(id, e)| {
            let space = crate::workspaces::reach_boxes(e).into_iter().next()?;
            Some(ReachRegion {
                surface: id.0,
                space: aabb_to_schema(&space),
            })
        })
        .collect();
    let mut queries = Vec::new();
    let mut asked = Vec::new();
    for &e in &auto {
        let arm = &cell.end_effectors[e];
        let origin = arm.reach_auto.unwrap_or(arm.origin);
        let problem = if regions.is_empty() {
            Some(ReachAutoProblem::NoSurface)
        } else if !has_grasps(cell, e) {
            let kind = arm.kind.map(|k| cell.holder_kinds[k].name.clone());
            Some(ReachAutoProblem::NoGrasps { kind })
        } else {
            None
        };
        match problem {
            Some(problem) => {
                diagnostics.push(diagnostics::reach_auto_failed(&arm.name, &problem, origin))
            }
            None => {
                queries.push(ReachQuery {
                    arm: e.0,
                    regions: regions.clone(),
                });
                asked.push(e);
            }
        }
    }
    if queries.is_empty() {
        return Vec::new();
    }
    let scene = crate::artifact::lower_scene(cell, sources);
    let answers = match solver.solve(&scene, sources, &queries) {
        Ok(answers) => answers,
        Err(found) => {
            diagnostics.extend(found);
            return Vec::new();
        }
    };
    let mut report = Vec::new();
    for (e, answer) in asked.into_iter().zip(answers) {
        let arm = &cell.end_effectors[e];
        let origin = arm.reach_auto.unwrap_or(arm.origin);
        match answer {
            Ok(found) if !found.boxes.is_empty() => {
                let boxes: Vec<(String, Aabb)> = found
                    .boxes
                    .iter()
                    .map(|(surface, b)| {
                        let name = cell
                            .end_effectors
                            .get(EndEffectorId(*surface))
                            .map_or_else(String::new, |s| s.name.clone());
                        (name, aabb_from_schema(b))
                    })
                    .collect();
                cell.end_effectors[e]
                    .reach_boxes
                    .extend(boxes.iter().map(|(_, b)| *b));
                report.push(AutoReach {
                    end_effector: e,
                    boxes,
                    tried: found.tried,
                    solves: found.solves,
                    elapsed: found.elapsed,
                });
            }
            Ok(found) => diagnostics.push(diagnostics::reach_auto_failed(
                &arm.name,
                &ReachAutoProblem::NothingReached { tried: found.tried },
                origin,
            )),
            Err(problem) => {
                diagnostics.push(diagnostics::reach_auto_failed(&arm.name, &problem, origin))
            }
        }
    }
    report
}

/// Whether arm `e` can hold some grasp (not a resting pose) of some object.
fn has_grasps(cell: &Cell, e: EndEffectorId) -> bool {
    let kind = cell.end_effectors[e].kind;
    let is_hand = kind.is_some_and(|k| cell.holder_kinds[k].class == HolderClass::Hand);
    cell.grasps.iter().any(|(_, g)| match g.holder {
        Some(Holder::EndEffector(holder)) => holder == e,
        Some(Holder::Kind(k)) => is_hand && kind == Some(k),
        None => false,
    })
}
