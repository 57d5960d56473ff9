//! The world a move request starts in: a base world with the request's object put where
//! the request says it is.
//!
//! A request names where its object is, not where the arms are. When the object rests on
//! a surface nothing else follows. When a hand holds it, the hand's arm must stand where
//! it holds the object there, or the first motion would start from a configuration that
//! does not hold the object at all (the arm at home, the object in mid-air). So the arm's
//! joints are found here: by inverse kinematics when the request gives a pose, or from a
//! build-time witness of the object's graph that holds it with that grasp in that
//! workspace when it gives only a workspace. Either way the configuration is checked
//! collision-free with the rest of the world before it is used.

use cellc_schema::{Artifact, EndEffectorId, Node, ObjectId};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use super::build::hold_grasp;
use super::{Whereabouts, World, WorldError};
use crate::kinematics::{solve_ik, IkOptions, IkTarget};
use crate::math::Iso;
use crate::plan::{Placement, PlanOptions};
use crate::scene::{Holder, ObjectPlacement, Scene, SceneScratch};
use crate::termination::Termination;
use crate::validity::{SceneValidity, StateValidity};

/// Inverse kinematics for an arm holding the request's object at a given pose: as precise
/// as the world's own check of a held pose against forward kinematics, with enough
/// restarts to find a configuration clear of the rest of the cell.
const HOLD_IK: IkOptions = IkOptions {
    max_iterations: 200,
    restarts: 24,
    position_tolerance: 1e-5,
    rotation_tolerance: 1e-4,
    damping: 0.1,
    max_step: 1.0,
};

impl World {
    /// `base` with `object` at `start` instead of wherever `base` has it. When a hand of a
    /// geometric cell holds it, that hand's arm is moved to a collision-free
    /// configuration that holds it there (see the module documentation); every other arm
    /// and object stays where `base` has it.
    ///
    /// # Errors
    /// The start matches no state of the object's graph, names a grasp the hand lacks,
    /// or no configuration of the arm holds the object there clear of the rest of the
    /// world ([`WorldError::NoHold`]).
    pub fn for_request(
        &self,
        artifact: &Artifact,
        scene: Option<&Scene>,
        object: ObjectId,
        start: &Placement,
        options: &PlanOptions,
    ) -> Result<World, WorldError> {
        let mut world = self.clone();
        world.set_object(object, Whereabouts::Absent);
        let arm = scene.filter(|s| s.has_kinematics()).filter(|s| {
            matches!(
                s.holders.get(start.holder.index()),
                Some(Holder::Arm { .. })
            )
        });
        let Some(scene) = arm else {
            match scene.filter(|s| s.has_kinematics()) {
                // A request may start "somewhere in this workspace" of a surface: the moved
                // object is no obstacle to itself, so it needs no pose (the planner takes
                // the first pick from a build-time witness).
                Some(geometric) if start.pose.is_none() => {
                    let state =
                        crate::plan::locate::locate(artifact, geometric, object, start, options)
                            .map_err(|error| WorldError::Placement {
                                object: artifact.object_name(object).to_string(),
                                error,
                            })?;
                    world.set_object(object, Whereabouts::Placed { state, pose: None });
                }
                _ => world.place(artifact, scene, object, start, options)?,
            }
            return Ok(world);
        };
        // Already held there in `base` (a world document that puts it in the hand).
        if let Some(state) = self.state(object) {
            let same = matches_start(state, start);
            let pose_agrees = match (start.pose, self.pose(artifact, Some(scene), object)) {
                (Some(given), Some(now)) => {
                    let (p, r) = crate::kinematics::pose_error(&given, &now);
                    p <= options.position_tolerance && r <= options.rotation_tolerance
                }
                (None, _) => true,
                (Some(_), None) => false,
            };
            if same && pose_agrees {
                return Ok(self.clone());
            }
        }
        let grasp = hold_grasp(artifact, object, start)?;
        let candidates = match start.pose {
            Some(pose) => {
                world.solve_hold(artifact, scene, object, start.holder, grasp, pose, options)
            }
            None => witness_holds(artifact, object, start, grasp),
        };
        let mut last = None;
        for q in candidates {
            let mut trial = world.clone();
            trial.set_arm(start.holder, q);
            match trial.place(artifact, Some(scene), object, start, options) {
                // A witness of a move arc may hold the object in the arc's other workspace.
                Ok(()) if trial.state(object).is_some_and(|s| matches_start(s, start)) => {
                    if trial.hold_is_clear(artifact, scene, object, start.holder) {
                        return Ok(trial);
                    }
                }
                Ok(()) => {}
                Err(e) => last = Some(e),
            }
        }
        Err(match last {
            Some(e @ WorldError::PoseDisagrees { .. }) | Some(e @ WorldError::HandFull { .. }) => e,
            _ => WorldError::NoHold {
                object: artifact.object_name(object).to_string(),
                holder: artifact.end_effector_name(start.holder).to_string(),
            },
        })
    }

    /// Configurations of `arm` whose hand holds `object` with `grasp` at `pose` (turned by
    /// the object's symmetries), from inverse kinematics seeded at the arm's current
    /// joints; deterministic under the options' seed.
    #[allow(clippy::too_many_arguments)]
    fn solve_hold(
        &self,
        artifact: &Artifact,
        scene: &Scene,
        object: ObjectId,
        arm: EndEffectorId,
        grasp: cellc_schema::GraspId,
        pose: Iso,
        options: &PlanOptions,
    ) -> Vec<Vec<f64>> {
        let Some(Holder::Arm { robot, base, home }) = scene.holders.get(arm.index()) else {
            return Vec::new();
        };
        let Some(robot) = scene.robots.get(*robot) else {
            return Vec::new();
        };
        let seed = self.arm(arm).unwrap_or(home);
        let grasp_pose = artifact.grasp_pose(object, grasp);
        let turns = crate::symmetry::candidates(&artifact.objects[object.index()].symmetries);
        let mut rng = ChaCha8Rng::seed_from_u64(options.seed ^ 0x686f_6c64);
        let stop = Termination::after(options.time_budget);
        turns
            .iter()
            .filter_map(|turn| {
                let tip = pose * (grasp_pose * turn).inverse();
                solve_ik(
                    robot,
                    base,
                    &IkTarget::Pose(tip),
                    seed,
                    &mut rng,
                    &HOLD_IK,
                    &stop,
                )
                .ok()
            })
            .collect()
    }

    /// Whether `arm`, holding `object` at its current joints, touches nothing it may not:
    /// the cell, the other arms where they stand, and the world's other objects.
    fn hold_is_clear(
        &self,
        artifact: &Artifact,
        scene: &Scene,
        object: ObjectId,
        arm: EndEffectorId,
    ) -> bool {
        let Some((state, q)) = self.state(object).zip(self.arm(arm)) else {
            return false;
        };
        let stationary: Vec<(EndEffectorId, Vec<f64>)> = self
            .arms
            .iter()
            .enumerate()
            .filter(|&(e, _)| e != arm.index())
            .filter_map(|(e, q)| Some((EndEffectorId(e as u32), q.clone()?)))
            .collect();
        let obstacles = self.obstacles(artifact, scene, object);
        let placement = ObjectPlacement::Held {
            by: arm,
            grasp: artifact.grasp_pose(object, state.grasp),
        };
        let Ok(validity) = SceneValidity::new(scene, &[arm], &stationary, object, placement) else {
            return false;
        };
        matches!(
            validity
                .with_obstacles(&obstacles)
                .check(q, &mut SceneScratch::default()),
            Ok(None)
        )
    }
}

/// Whether a located state is the one the start names (what it leaves out may be anything).
fn matches_start(state: Node, start: &Placement) -> bool {
    state.end_effector == start.holder
        && start.grasp.is_none_or(|g| g == state.grasp)
        && start.workspace.is_none_or(|w| w == state.workspace)
}

/// The holding arm's configurations in the build-time witnesses of the arcs that leave or
/// enter the start state (holder, grasp, workspace): each held the object there, checked
/// by verification in the empty cell. Transitions first (the object is in the state's
/// workspace at both ends), then moves.
fn witness_holds(
    artifact: &Artifact,
    object: ObjectId,
    start: &Placement,
    grasp: cellc_schema::GraspId,
) -> Vec<Vec<f64>> {
    let Some(workspace) = start.workspace else {
        return Vec::new();
    };
    let node = Node {
        end_effector: start.holder,
        grasp,
        workspace,
    };
    let graph = &artifact.objects[object.index()].graph;
    let mut transitions = Vec::new();
    let mut moves = Vec::new();
    for arc in &graph.arcs {
        let (from, to) = (graph.nodes[arc.from as usize], graph.nodes[arc.to as usize]);
        if from != node && to != node {
            continue;
        }
        let Some(w) = arc.witness.and_then(|w| graph.witnesses.get(w as usize)) else {
            continue;
        };
        let Some(c) = w
            .configurations
            .iter()
            .find(|c| c.end_effector == start.holder)
        else {
            continue;
        };
        if from.end_effector == to.end_effector {
            moves.push(c.joints.clone());
        } else {
            transitions.push(c.joints.clone());
        }
    }
    transitions.extend(moves);
    transitions.dedup();
    transitions
}
