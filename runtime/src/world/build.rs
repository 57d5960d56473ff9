//! A world from what people write: the cell's `world` item (already resolved to ids by the
//! compiler) and world documents (names, untrusted). Every check happens here, once:
//! arm and joint names, joint values against the chain's limits, each placement against
//! the object's graph, a held object's pose against its arm's forward kinematics, and one
//! object per hand.

use cellc_schema::world::{ObjectEntry, PlacedEntry};
use cellc_schema::{Artifact, ObjectId, WorldDocument};

use super::{Whereabouts, World};
use crate::math::{Iso, Quat, Vec3};
use crate::plan::locate::{grasps_of, locate, locate_abstract};
use crate::plan::{names, LocateError, Placement, PlacementByName, PlanOptions};
use crate::scene::{Holder, Scene};
use crate::symmetry;

/// Why a world could not be made.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum WorldError {
    /// A name the cell does not have (arm, object, holder, grasp, workspace), with the
    /// names it could have been.
    Name(LocateError),
    /// Joints given for an end-effector that is not an arm.
    NotAnArm {
        /// Its name.
        name: String,
    },
    /// A joint name the arm's chain does not have.
    UnknownJoint {
        /// The arm.
        arm: String,
        /// The name given.
        joint: String,
        /// The chain's joints, base to tip.
        known: Vec<String>,
    },
    /// A joint value outside the joint's limits (or not finite).
    JointOutOfLimits {
        /// The arm.
        arm: String,
        /// The joint.
        joint: String,
        /// The value given.
        value: f64,
        /// Lower limit.
        lower: f64,
        /// Upper limit.
        upper: f64,
    },
    /// An object's placement matches no state of its graph.
    Placement {
        /// The object.
        object: String,
        /// Why.
        error: LocateError,
    },
    /// An object rests on a surface of a geometric cell without a pose: the world would
    /// not know where the obstacle is.
    PoseNeeded {
        /// The object.
        object: String,
        /// The surface.
        holder: String,
    },
    /// Both `rpy` and `quat`, or a quaternion that is not of unit length.
    Orientation {
        /// The object.
        object: String,
        /// What is wrong.
        detail: String,
    },
    /// A held object's pose given as well disagrees with where its arm's joints put it.
    PoseDisagrees {
        /// The object.
        object: String,
        /// The arm.
        holder: String,
        /// Distance between the two positions, metres.
        position_error: f64,
        /// Angle between the two orientations up to the object's symmetries, radians.
        rotation_error: f64,
    },
    /// A request starts with the object in a hand, and no configuration of the hand's arm
    /// found holds it there clear of the rest of the world.
    NoHold {
        /// The object.
        object: String,
        /// The hand.
        holder: String,
    },
    /// Two objects in one hand.
    HandFull {
        /// The hand.
        hand: String,
        /// The object it holds.
        first: String,
        /// The other object placed in it.
        second: String,
    },
}

impl World {
    /// The world the cell declares (`world { ... }`): arms at home, the objects it lists
    /// where it says, the others absent.
    ///
    /// # Errors
    /// A placement that matches no state (the compiler resolved its names, not its poses).
    pub fn initial(
        artifact: &Artifact,
        scene: Option<&Scene>,
        options: &PlanOptions,
    ) -> Result<World, WorldError> {
        let mut world = World::at_home(artifact, scene);
        for p in &artifact.world {
            let placement = crate::plan::placement_of(&p.placement);
            world.place(artifact, scene, p.object, &placement, options)?;
        }
        Ok(world)
    }

    /// The world a document describes: arms first (a held object's pose depends on
    /// them), then objects.
    ///
    /// # Errors
    /// The first problem found, in document order (arms by name, then objects by name).
    pub fn from_document(
        artifact: &Artifact,
        scene: Option<&Scene>,
        document: &WorldDocument,
        options: &PlanOptions,
    ) -> Result<World, WorldError> {
        let mut world = World::at_home(artifact, scene);
        for (arm, joints) in &document.arms {
            let e = names::end_effector(artifact, arm).map_err(WorldError::Name)?;
            let robot = match scene.and_then(|s| s.holders.get(e.index())) {
                Some(Holder::Arm { robot, .. }) => scene.and_then(|s| s.robots.get(*robot)),
                _ => None,
            };
            let Some(robot) = robot else {
                return Err(WorldError::NotAnArm { name: arm.clone() });
            };
            let mut q = world.arm(e).map(<[f64]>::to_vec).unwrap_or_default();
            let (lower, upper) = robot.limits();
            for (joint, &value) in joints {
                let Some(j) = robot.joint_names().iter().position(|n| n == joint) else {
                    return Err(WorldError::UnknownJoint {
                        arm: arm.clone(),
                        joint: joint.clone(),
                        known: robot.joint_names().to_vec(),
                    });
                };
                if !(value.is_finite() && lower[j] <= value && value <= upper[j]) {
                    return Err(WorldError::JointOutOfLimits {
                        arm: arm.clone(),
                        joint: joint.clone(),
                        value,
                        lower: lower[j],
                        upper: upper[j],
                    });
                }
                if let Some(slot) = q.get_mut(j) {
                    *slot = value;
                }
            }
            world.set_arm(e, q);
        }
        for (name, entry) in &document.objects {
            let object = names::object(artifact, name).map_err(WorldError::Name)?;
            let ObjectEntry::Placed(entry) = entry else {
                continue;
            };
            let by_name = placement_by_name(name, entry)?;
            let placement =
                names::placement(artifact, object, &by_name).map_err(WorldError::Name)?;
            world.place(artifact, scene, object, &placement, options)?;
        }
        Ok(world)
    }

    /// Puts `object` where `placement` says, checked against its graph (and, for a held
    /// object, against its arm's forward kinematics).
    ///
    /// # Errors
    /// See [`WorldError`].
    pub fn place(
        &mut self,
        artifact: &Artifact,
        scene: Option<&Scene>,
        object: ObjectId,
        placement: &Placement,
        options: &PlanOptions,
    ) -> Result<(), WorldError> {
        let name = artifact.object_name(object).to_string();
        let holder = placement.holder;
        let holder_name = artifact.end_effector_name(holder).to_string();
        let in_graph = |error| WorldError::Placement {
            object: name.clone(),
            error,
        };
        let geometric = scene.filter(|s| s.has_kinematics());
        let whereabouts = match geometric.map(|s| (s, s.holders.get(holder.index()))) {
            Some((scene, Some(Holder::Arm { .. }))) => {
                let grasp = hold_grasp(artifact, object, placement)?;
                let fk = self.arm(holder).and_then(|q| {
                    super::held_pose(scene, holder, q, &artifact.grasp_pose(object, grasp))
                });
                if let (Some(given), Some(fk)) = (placement.pose, fk) {
                    let symmetries = &artifact.objects[object.index()].symmetries;
                    let position_error = (given.translation.vector - fk.translation.vector).norm();
                    let rotation_error =
                        symmetry::residual(&(fk.rotation.inverse() * given.rotation), symmetries);
                    if position_error > options.position_tolerance
                        || rotation_error > options.rotation_tolerance
                    {
                        return Err(WorldError::PoseDisagrees {
                            object: name,
                            holder: holder_name,
                            position_error,
                            rotation_error,
                        });
                    }
                }
                let at = Placement {
                    holder,
                    grasp: Some(grasp),
                    workspace: placement.workspace,
                    pose: fk,
                };
                let state = locate(artifact, scene, object, &at, options).map_err(in_graph)?;
                Whereabouts::Placed { state, pose: None }
            }
            Some((scene, _)) => {
                if placement.pose.is_none() {
                    return Err(WorldError::PoseNeeded {
                        object: name,
                        holder: holder_name,
                    });
                }
                let state =
                    locate(artifact, scene, object, placement, options).map_err(in_graph)?;
                Whereabouts::Placed {
                    state,
                    pose: placement.pose,
                }
            }
            None => {
                let state = locate_abstract(artifact, object, placement).map_err(in_graph)?;
                Whereabouts::Placed { state, pose: None }
            }
        };
        // A hand (an arm, a conveyor, an abstract movable end-effector) holds one object;
        // surfaces hold many.
        if artifact.end_effectors[holder.index()].movable {
            if let Some(other) = self.held_by(holder).filter(|&o| o != object) {
                return Err(WorldError::HandFull {
                    hand: holder_name,
                    first: artifact.object_name(other).to_string(),
                    second: name,
                });
            }
        }
        self.set_object(object, whereabouts);
        Ok(())
    }
}

/// The grasp a hand holds `object` with at `placement`: the one given, or the hand's only
/// grasp of the object (otherwise the grasp must be named).
pub(super) fn hold_grasp(
    artifact: &Artifact,
    object: ObjectId,
    placement: &Placement,
) -> Result<cellc_schema::GraspId, WorldError> {
    let grasps = grasps_of(artifact, object, placement.holder);
    match (placement.grasp, grasps.as_slice()) {
        (Some(g), _) => Ok(g),
        (None, [only]) => Ok(*only),
        (None, _) => Err(WorldError::Placement {
            object: artifact.object_name(object).to_string(),
            error: LocateError::GraspNeeded {
                holder: artifact.end_effector_name(placement.holder).to_string(),
                grasps: grasps
                    .iter()
                    .map(|&g| artifact.grasp_name(object, g).to_string())
                    .collect(),
            },
        }),
    }
}

/// A document's object entry as a placement by name (metres and degrees).
fn placement_by_name(object: &str, e: &PlacedEntry) -> Result<PlacementByName, WorldError> {
    let orientation = |detail: &str| WorldError::Orientation {
        object: object.to_string(),
        detail: detail.to_string(),
    };
    let rotation = match (e.rpy, e.quat) {
        (Some(_), Some(_)) => return Err(orientation("give `rpy` or `quat`, not both")),
        (Some([r, p, y]), None) => {
            Quat::from_euler_angles(r.to_radians(), p.to_radians(), y.to_radians())
        }
        (None, Some([w, x, y, z])) => {
            let q = nalgebra::Quaternion::new(w, x, y, z);
            if (q.norm() - 1.0).abs() > 1e-3 || !q.norm().is_finite() {
                return Err(orientation("the quaternion is not of unit length"));
            }
            // A quaternion unit to within rounding (one the runtime wrote, as a stored
            // world) is kept as given, so reading a world back gives the same bits;
            // others are normalised.
            if (q.norm_squared() - 1.0).abs() <= 4.0 * f64::EPSILON {
                Quat::new_unchecked(q)
            } else {
                Quat::from_quaternion(q)
            }
        }
        (None, None) => Quat::identity(),
    };
    let pose = match e.at {
        Some([x, y, z]) => Some(Iso::from_parts(Vec3::new(x, y, z).into(), rotation)),
        None if e.rpy.is_some() || e.quat.is_some() => {
            return Err(orientation("an orientation needs a position (`at`)"))
        }
        None => None,
    };
    Ok(PlacementByName {
        holder: e.holder.clone(),
        grasp: e.grasp.clone(),
        workspace: e.workspace.clone(),
        pose,
    })
}
