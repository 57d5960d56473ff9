//! Cartesian to state (Algorithm 1, step 2): which workspace a pose lies in, and which
//! grasp or resting pose of its holder the object's pose matches.
//!
//! The original planner compared orientation only, ignored position and symmetry, and
//! handled table grasps only. Here a resting pose matches when the object is at the
//! resting height above the surface and its orientation equals the resting orientation
//! turned about the vertical, up to the object's declared symmetries; position and
//! orientation both count, within the request's tolerances. Hands need their grasp named
//! (the object pose alone does not say how a hand holds it) unless the hand has one grasp.
//! When nothing matches, the error lists the nearest candidates and how far off they are.

use cellc_schema::{
    Artifact, EndEffectorId, GraspId, Holder as GraspHolder, Node, ObjectId, WorkspaceId,
};

use crate::math::{iso_from_schema, Iso, Point, Quat, Vec3};
use crate::scene::{Holder, Scene};
use crate::symmetry;

use super::{Goal, Placement, PlanOptions};

/// A candidate that did not match, and by how much.
#[derive(Clone, Debug, PartialEq)]
pub struct NearMiss {
    /// Workspace or grasp name.
    pub name: String,
    /// Position error, metres.
    pub position_error: f64,
    /// Orientation error, radians (0 for workspaces).
    pub rotation_error: f64,
}

/// Why a request could not be located in the graph.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum LocateError {
    /// No object of that name.
    UnknownObject {
        /// Name asked for.
        name: String,
        /// Objects the artifact has.
        known: Vec<String>,
    },
    /// No end-effector of that name.
    UnknownHolder {
        /// Name asked for.
        name: String,
        /// End-effectors the artifact has.
        known: Vec<String>,
    },
    /// The holder has no grasp of that name for this object.
    UnknownGrasp {
        /// Holder.
        holder: String,
        /// Name asked for.
        name: String,
        /// Its grasps of this object.
        known: Vec<String>,
    },
    /// No workspace of that name.
    UnknownWorkspace {
        /// Name asked for.
        name: String,
        /// Workspaces the artifact has.
        known: Vec<String>,
    },
    /// The placement gives neither a pose nor a workspace.
    NoWhere {
        /// Holder.
        holder: String,
    },
    /// The pose is in no workspace.
    NoWorkspace {
        /// The position.
        position: [f64; 3],
        /// Nearest workspaces and their distance.
        nearest: Vec<NearMiss>,
    },
    /// The holder does not reach the workspace named, or the one the pose is in.
    NotReached {
        /// Holder.
        holder: String,
        /// Workspace.
        workspace: String,
        /// The workspace is the one a pose of the request lies in (not one it names).
        from_pose: bool,
    },
    /// The holder reaches the workspace and has grasps of the object, but the graph has
    /// none of its states there: verification pruned them, or no transition or move
    /// leads to or from them.
    NoStateThere {
        /// Holder.
        holder: String,
        /// Workspace.
        workspace: String,
        /// Its grasps of the object.
        grasps: Vec<String>,
    },
    /// The object has no grasp and no resting pose at all: nothing can hold it.
    Ungraspable {
        /// Object.
        object: String,
    },
    /// The pose matches no grasp or resting pose of the holder.
    NoGrasp {
        /// Holder.
        holder: String,
        /// Workspace.
        workspace: String,
        /// Nearest grasps and how far off they are.
        nearest: Vec<NearMiss>,
    },
    /// The request uses an id the artifact does not have (a caller's bug, not a name).
    NoSuchId {
        /// What the id was meant to name.
        kind: super::names::IdKind,
        /// The id.
        id: u32,
    },
    /// The holder has no grasp (a surface: no resting pose) for this object at all.
    NothingToHoldBy {
        /// Holder.
        holder: String,
        /// Object.
        object: String,
        /// The holder is a surface (resting poses) rather than a hand (grasps).
        surface: bool,
    },
    /// A pose of the request has a coordinate that is not a finite number.
    NonFinitePose,
    /// A hand holds the object but the request does not say how.
    GraspNeeded {
        /// Holder.
        holder: String,
        /// Its grasps of this object.
        grasps: Vec<String>,
    },
}

impl std::fmt::Display for LocateError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let list = |v: &[String]| {
            v.iter()
                .map(|s| format!("`{s}`"))
                .collect::<Vec<_>>()
                .join(", ")
        };
        let misses = |v: &[NearMiss]| {
            v.iter()
                .map(|m| {
                    if m.rotation_error > 0.0 {
                        format!(
                            "`{}` ({:.3} m, {:.1} deg off)",
                            m.name,
                            m.position_error,
                            m.rotation_error.to_degrees()
                        )
                    } else {
                        format!("`{}` ({:.3} m away)", m.name, m.position_error)
                    }
                })
                .collect::<Vec<_>>()
                .join(", ")
        };
        match self {
            LocateError::UnknownObject { name, known } => write!(f, "no object `{name}`; the objects are {}", list(known)),
            LocateError::UnknownHolder { name, known } => write!(f, "no end-effector `{name}`; the end-effectors are {}", list(known)),
            LocateError::UnknownGrasp { holder, name, known } => {
                write!(f, "`{holder}` has no grasp `{name}` of this object; its grasps are {}", list(known))
            }
            LocateError::UnknownWorkspace { name, known } => write!(f, "no workspace `{name}`; the workspaces are {}", list(known)),
            LocateError::NoWhere { holder } => write!(f, "say where `{holder}` holds the object: a pose or a workspace"),
            LocateError::NoWorkspace { position, nearest } => write!(
                f,
                "({:.3}, {:.3}, {:.3}) is in no workspace; nearest: {}",
                position[0],
                position[1],
                position[2],
                misses(nearest)
            ),
            LocateError::NotReached { holder, workspace, from_pose: true } => write!(f, "`{holder}` does not reach `{workspace}`, the workspace the pose lies in"),
            LocateError::NotReached { holder, workspace, from_pose: false } => write!(f, "`{holder}` does not reach `{workspace}`"),
            LocateError::NoStateThere { holder, workspace, grasps } => write!(
                f,
                "`{holder}` reaches `{workspace}` and holds the object by {}, but the graph has no such state in `{workspace}` (verification pruned it, or no move or transition reaches it)",
                list(grasps)
            ),
            LocateError::Ungraspable { object } => write!(f, "`{object}` has no grasp and no resting pose: nothing can hold it"),
            LocateError::NoGrasp { holder, workspace, nearest } => write!(
                f,
                "the pose matches no grasp or resting pose of `{holder}` in `{workspace}`; nearest: {}",
                misses(nearest)
            ),
            LocateError::NoSuchId { kind, id } => write!(f, "the request names {kind} #{id}, which the cell does not have"),
            LocateError::NothingToHoldBy { holder, object, surface: true } => write!(f, "the surface `{holder}` has no resting pose for `{object}`: it cannot hold it anywhere"),
            LocateError::NothingToHoldBy { holder, object, surface: false } => write!(f, "`{holder}` has no grasp of `{object}`"),
            LocateError::NonFinitePose => write!(f, "a pose of the request is not finite (NaN or infinite coordinates)"),
            LocateError::GraspNeeded { holder, grasps } => {
                write!(f, "say which grasp `{holder}` holds the object with: {}", list(grasps))
            }
        }
    }
}

/// Grasps of `object` that end-effector `e` can hold.
pub(crate) fn grasps_of(artifact: &Artifact, object: ObjectId, e: EndEffectorId) -> Vec<GraspId> {
    let kind = artifact.end_effectors[e.index()].kind;
    artifact.objects[object.index()]
        .grasps
        .iter()
        .enumerate()
        .filter(|(_, g)| match g.holder {
            GraspHolder::EndEffector(h) => h == e.0,
            GraspHolder::Kind(k) => Some(k) == kind,
        })
        .map(|(i, _)| GraspId(i as u32))
        .collect()
}

/// The workspace containing `position`, or the nearest ones.
fn workspace_at(
    artifact: &Artifact,
    scene: &Scene,
    position: &Point,
) -> Result<WorkspaceId, LocateError> {
    if let Some(w) = scene.workspaces.iter().position(|boxes| {
        boxes
            .iter()
            .any(|b| crate::math::contains_point(b, position))
    }) {
        return Ok(WorkspaceId(w as u32));
    }
    let mut nearest: Vec<NearMiss> = scene
        .workspaces
        .iter()
        .enumerate()
        .filter(|(_, boxes)| !boxes.is_empty())
        .map(|(w, boxes)| {
            let d = boxes
                .iter()
                .map(|b| {
                    let clamped = Point::new(
                        position.x.clamp(b.mins.x, b.maxs.x),
                        position.y.clamp(b.mins.y, b.maxs.y),
                        position.z.clamp(b.mins.z, b.maxs.z),
                    );
                    (clamped - position).norm()
                })
                .fold(f64::INFINITY, f64::min);
            NearMiss {
                name: artifact.workspaces[w].name.clone(),
                position_error: d,
                rotation_error: 0.0,
            }
        })
        .collect();
    nearest.sort_by(|a, b| a.position_error.total_cmp(&b.position_error));
    nearest.truncate(3);
    Err(LocateError::NoWorkspace {
        position: [position.x, position.y, position.z],
        nearest,
    })
}

/// How far `pose` is from resting as `rest` on a surface whose top face is at `top`:
/// (height error, orientation error up to a turn about the vertical and the object's
/// symmetries).
pub(crate) fn rest_error(
    pose: &Iso,
    rest: &Iso,
    top: f64,
    symmetries: &[cellc_schema::Symmetry],
) -> (f64, f64) {
    let height = (pose.translation.vector.z - top - rest.translation.vector.z).abs();
    // Best turn about the vertical: a coarse scan, then a fine one around the best.
    let error_at = |yaw: f64| {
        let expected = Quat::from_axis_angle(&Vec3::z_axis(), yaw) * rest.rotation;
        symmetry::residual(&(expected.inverse() * pose.rotation), symmetries)
    };
    // Coarse to fine: 10° steps over the circle, then 1°, 0.1° and 0.01° around the best
    // (the error is smooth in the turn, so each level only refines the previous one).
    let mut best = (0.0, f64::INFINITY);
    for k in 0..36 {
        let yaw = f64::from(k * 10).to_radians();
        let e = error_at(yaw);
        if e < best.1 {
            best = (yaw, e);
        }
    }
    for step in [1.0_f64, 0.1, 0.01] {
        let center = best.0;
        for k in -10..=10 {
            let yaw = center + f64::from(k) * step.to_radians();
            let e = error_at(yaw);
            if e < best.1 {
                best = (yaw, e);
            }
        }
    }
    (height, best.1)
}

/// The state of a placement of `object`.
pub fn locate(
    artifact: &Artifact,
    scene: &Scene,
    object: ObjectId,
    placement: &Placement,
    options: &PlanOptions,
) -> Result<Node, LocateError> {
    let e = placement.holder;
    let holder_name = || artifact.end_effectors[e.index()].name.clone();
    let grasps = grasps_of(artifact, object, e);
    if grasps.is_empty() {
        return Err(nothing_to_hold_by(artifact, object, e, || {
            matches!(scene.holders[e.index()], Holder::Surface { .. })
        }));
    }
    let names = |gs: &[GraspId]| -> Vec<String> {
        gs.iter()
            .map(|&g| {
                artifact.objects[object.index()].grasps[g.index()]
                    .name
                    .clone()
            })
            .collect()
    };
    let w = match (placement.workspace, &placement.pose) {
        (Some(w), _) => w,
        (None, Some(pose)) => workspace_at(artifact, scene, &Point::from(pose.translation.vector))?,
        (None, None) => {
            return Err(LocateError::NoWhere {
                holder: holder_name(),
            })
        }
    };
    if !artifact.end_effectors[e.index()].reaches.contains(&w.0) {
        return Err(LocateError::NotReached {
            holder: holder_name(),
            workspace: artifact.workspaces[w.index()].name.clone(),
            from_pose: placement.workspace.is_none(),
        });
    }
    let node = |g: GraspId| Node {
        end_effector: e,
        grasp: g,
        workspace: w,
    };
    if let Some(g) = placement.grasp {
        return grasps
            .iter()
            .copied()
            .find(|&h| h == g)
            .map(node)
            .ok_or_else(|| LocateError::UnknownGrasp {
                holder: holder_name(),
                name: grasp_name(artifact, object, g),
                known: names(&grasps),
            });
    }
    match (&scene.holders[e.index()], &placement.pose) {
        (Holder::Surface { slab, .. }, Some(pose)) => {
            let obj = &artifact.objects[object.index()];
            let mut misses: Vec<(GraspId, f64, f64)> = grasps
                .iter()
                .map(|&g| {
                    let rest = obj.grasps[g.index()]
                        .pose
                        .as_ref()
                        .map(iso_from_schema)
                        .unwrap_or_else(Iso::identity);
                    let (dp, dr) = rest_error(pose, &rest, slab.maxs.z, &obj.symmetries);
                    (g, dp, dr)
                })
                .collect();
            misses.sort_by(|a, b| {
                (a.1 / options.position_tolerance + a.2 / options.rotation_tolerance).total_cmp(
                    &(b.1 / options.position_tolerance + b.2 / options.rotation_tolerance),
                )
            });
            match misses.first() {
                Some(&(g, dp, dr))
                    if dp <= options.position_tolerance && dr <= options.rotation_tolerance =>
                {
                    Ok(node(g))
                }
                _ => Err(LocateError::NoGrasp {
                    holder: holder_name(),
                    workspace: artifact.workspaces[w.index()].name.clone(),
                    nearest: misses
                        .iter()
                        .take(3)
                        .map(|&(g, dp, dr)| NearMiss {
                            name: obj.grasps[g.index()].name.clone(),
                            position_error: dp,
                            rotation_error: dr,
                        })
                        .collect(),
                }),
            }
        }
        _ if grasps.len() == 1 => Ok(node(grasps[0])),
        _ => Err(LocateError::GraspNeeded {
            holder: holder_name(),
            grasps: names(&grasps),
        }),
    }
}

/// Every state that satisfies a goal.
/// With a `scene`, a placement goal is located by its pose; without one (abstract cells)
/// any grasp of the holder in the workspace will do, unless the goal names one.
pub fn goal_states(
    artifact: &Artifact,
    scene: Option<&Scene>,
    object: ObjectId,
    goal: &Goal,
    options: &PlanOptions,
) -> Result<Vec<Node>, LocateError> {
    match goal {
        // `HOLDER in WS` names no pose and no grasp: every state of the holder there is
        // a goal, and the search picks the cheapest.
        Goal::Placement(p) if p.pose.is_none() && p.grasp.is_none() => {
            abstract_states(artifact, object, p)
        }
        Goal::Placement(p) => match scene {
            Some(scene) => Ok(vec![locate(artifact, scene, object, p, options)?]),
            None => abstract_states(artifact, object, p),
        },
        Goal::Workspace { workspace, holder } => {
            let w = *workspace;
            let e = *holder;
            Ok(artifact.objects[object.index()]
                .graph
                .nodes
                .iter()
                .copied()
                .filter(|n| n.workspace == w && e.is_none_or(|e| n.end_effector == e))
                .collect())
        }
    }
}

/// The states of a placement in an abstract cell, where there are no poses: the holder's
/// states in the named workspace, narrowed to the grasp when one is named.
fn abstract_states(
    artifact: &Artifact,
    object: ObjectId,
    p: &Placement,
) -> Result<Vec<Node>, LocateError> {
    let e = p.holder;
    let holder_name = || artifact.end_effectors[e.index()].name.clone();
    let Some(w) = p.workspace else {
        return Err(LocateError::NoWhere {
            holder: holder_name(),
        });
    };
    let obj = &artifact.objects[object.index()];
    if grasps_of(artifact, object, e).is_empty() {
        let surface = || !artifact.end_effectors[e.index()].movable;
        return Err(nothing_to_hold_by(artifact, object, e, surface));
    }
    if !artifact.end_effectors[e.index()].reaches.contains(&w.0) {
        return Err(LocateError::NotReached {
            holder: holder_name(),
            workspace: artifact.workspaces[w.index()].name.clone(),
            from_pose: false,
        });
    }
    let candidates: Vec<Node> = obj
        .graph
        .nodes
        .iter()
        .copied()
        .filter(|n| n.end_effector == e && n.workspace == w)
        .collect();
    match p.grasp {
        Some(g) => candidates
            .iter()
            .copied()
            .find(|n| n.grasp == g)
            .map(|n| vec![n])
            .ok_or_else(|| LocateError::UnknownGrasp {
                holder: holder_name(),
                name: grasp_name(artifact, object, g),
                known: candidates
                    .iter()
                    .map(|n| obj.grasps[n.grasp.index()].name.clone())
                    .collect(),
            }),
        None if candidates.is_empty() => Err(no_state(artifact, object, e, w)),
        None => Ok(candidates),
    }
}

/// Why holder `e` can hold `object` in no way: the object has no grasps at all, or none
/// of them is the holder's.
fn nothing_to_hold_by(
    artifact: &Artifact,
    object: ObjectId,
    e: EndEffectorId,
    surface: impl Fn() -> bool,
) -> LocateError {
    let obj = &artifact.objects[object.index()];
    if obj.grasps.is_empty() {
        return LocateError::Ungraspable {
            object: obj.name.clone(),
        };
    }
    LocateError::NothingToHoldBy {
        holder: artifact.end_effectors[e.index()].name.clone(),
        object: obj.name.clone(),
        surface: surface(),
    }
}

/// Why the graph has no state of `e` holding `object` in `w`, when `e` reaches `w` and
/// has grasps of `object`.
fn no_state(
    artifact: &Artifact,
    object: ObjectId,
    e: EndEffectorId,
    w: WorkspaceId,
) -> LocateError {
    let obj = &artifact.objects[object.index()];
    LocateError::NoStateThere {
        holder: artifact.end_effectors[e.index()].name.clone(),
        workspace: artifact.workspaces[w.index()].name.clone(),
        grasps: grasps_of(artifact, object, e)
            .iter()
            .map(|g| obj.grasps[g.index()].name.clone())
            .collect(),
    }
}

/// The name of grasp `g` of `object`, for messages (`#g` if the id is out of range).
fn grasp_name(artifact: &Artifact, object: ObjectId, g: GraspId) -> String {
    artifact.objects[object.index()]
        .grasps
        .get(g.index())
        .map_or_else(|| format!("#{}", g.0), |x| x.name.clone())
}

/// The one state of a placement in an abstract cell: the holder, the workspace and (when
/// the holder has several grasps there) the grasp must be named.
pub fn locate_abstract(
    artifact: &Artifact,
    object: ObjectId,
    p: &Placement,
) -> Result<Node, LocateError> {
    match abstract_states(artifact, object, p)?.as_slice() {
        [one] => Ok(*one),
        many => Err(LocateError::GraspNeeded {
            holder: artifact.end_effectors[p.holder.index()].name.clone(),
            grasps: many
                .iter()
                .map(|n| {
                    artifact.objects[object.index()].grasps[n.grasp.index()]
                        .name
                        .clone()
                })
                .collect(),
        }),
    }
}

impl std::error::Error for LocateError {}
