//! The joint motion that leads to each command of a realised path.

use cellc_schema::{BlockedStep, Blocker, EndEffectorId, GraspId, Infeasibility, Node, ObjectId};
use rand_chacha::ChaCha8Rng;

use super::blocking::blocker_on_path;
use super::{step_arc, Failure, Planner, Setback, WorldState};
use crate::motion::{MotionError, MotionOptions, MotionProblem, TimingOptions};
use crate::plan::{ArmConfigurations, Command, Step};
use crate::scene::{Holder, ObjectPlacement, SceneScratch};
use crate::termination::Termination;
use crate::validity::SceneValidity;

impl Planner<'_> {
    /// Plans the joint motion that leads to each command: the arms whose configuration
    /// changes move together in their combined space, every other arm stands where it is,
    /// a held object travels with its hand, and an arm that lets go returns home. A motion
    /// that cannot be found fails the arc of its command, so the search tries another way;
    /// when the world's other objects stand on its straight path, which is free without
    /// them, the failure names the one met first. A motion that refuses the request's
    /// timing (more points at its rate than a motion may have) refuses the request.
    // The request's parts a motion needs, each its own concern: grouping them in a struct
    // would only rename the call.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn add_motions(
        &self,
        object: ObjectId,
        start_state: Node,
        steps: &mut [Step],
        start: &WorldState,
        timing: &TimingOptions,
        rng: &mut ChaCha8Rng,
        stop: &Termination,
    ) -> Result<(), Setback> {
        let Some(scene) = self.scene.filter(|s| s.has_kinematics()) else {
            return Ok(());
        };
        let grasp_pose = |g: GraspId| self.artifact.grasp_pose(object, g);
        let is_arm =
            |e: EndEffectorId| matches!(scene.holders.get(e.index()), Some(Holder::Arm { .. }));
        let mut arms = start.arms.clone();
        let mut object_pose = start.object;
        // Who holds the object now, and with which grasp.
        let mut holder: Option<(EndEffectorId, GraspId)> =
            Some((start_state.end_effector, start_state.grasp));
        let mut scratch = SceneScratch::default();
        // A carry begins where a pick left the object (still touching that surface) and
        // may end where a put-down needs it (touching the next one): at those ends the
        // object touches a surface, which the carry's checks must allow.
        let put_down_after: Vec<Option<EndEffectorId>> = (0..steps.len())
            .map(|i| match steps.get(i + 1).map(|s| &s.command) {
                Some(Command::Grasp { holder, .. }) if !is_arm(*holder) => Some(*holder),
                _ => None,
            })
            .collect();
        // An arm that let go but could not retreat still has its hand on the object: the
        // next carry may touch it while it moves the object away.
        let mut lingering: Option<EndEffectorId> = None;
        let mut lifted_from: Option<EndEffectorId> =
            (!is_arm(start_state.end_effector)).then_some(start_state.end_effector);
        for (index, step) in steps.iter_mut().enumerate() {
            let (targets, placement, fail_arc) = match &step.command {
                Command::Move {
                    holder: e,
                    configurations,
                    object: pose,
                    ..
                } => {
                    // Lifted from one surface and put straight down on another (a bench
                    // to the next one): the carry touches both, the first at its start.
                    let (touching, from) = match (lifted_from.take(), put_down_after[index]) {
                        (Some(lifted), Some(next)) if lifted != next => (Some(next), Some(lifted)),
                        (lifted, next) => (lifted.or(next), None),
                    };
                    let placement = match (holder, touching) {
                        (Some((_, g)), Some(surface)) if is_arm(*e) => ObjectPlacement::Placing {
                            by: *e,
                            grasp: grasp_pose(g),
                            on: surface,
                            also: lingering.filter(|l| l != e),
                            from,
                        },
                        (Some((_, g)), None) if is_arm(*e) => match lingering.filter(|l| l != e) {
                            Some(l) => ObjectPlacement::Handoff {
                                a: *e,
                                grasp_a: grasp_pose(g),
                                b: l,
                            },
                            None => ObjectPlacement::Held {
                                by: *e,
                                grasp: grasp_pose(g),
                            },
                        },
                        _ => ObjectPlacement::Absent,
                    };
                    if pose.is_some() {
                        object_pose = *pose;
                    }
                    (configurations.clone(), placement, step_arc(step))
                }
                Command::Grasp {
                    holder: receiver,
                    grasp,
                    configurations,
                    object: pose,
                    ..
                } => {
                    // Before the exchange the object is where the giver has it; the
                    // receiver's hand reaches it at the end.
                    let placement = match (holder, pose.or(object_pose)) {
                        (Some((giver, g)), _) if is_arm(giver) && is_arm(*receiver) => {
                            ObjectPlacement::Handoff {
                                a: giver,
                                grasp_a: grasp_pose(g),
                                b: *receiver,
                            }
                        }
                        (Some((giver, g)), _) if is_arm(giver) => ObjectPlacement::Placing {
                            by: giver,
                            grasp: grasp_pose(g),
                            on: *receiver,
                            also: lingering.filter(|l| *l != giver),
                            from: None,
                        },
                        (Some((giver, _)), Some(p)) => ObjectPlacement::Resting {
                            on: giver,
                            pose: p,
                            by: is_arm(*receiver).then_some(*receiver),
                        },
                        _ => ObjectPlacement::Absent,
                    };
                    if pose.is_some() {
                        object_pose = *pose;
                    }
                    let targets = configurations.clone();
                    // Taken from a surface: the next carry starts touching it.
                    lifted_from = match holder {
                        Some((giver, _)) if !is_arm(giver) && is_arm(*receiver) => Some(giver),
                        _ => None,
                    };
                    holder = Some((*receiver, *grasp));
                    (targets, placement, step_arc(step))
                }
                Command::Ungrasp { holder: giver, .. } => {
                    // The arm that let go returns home, around the object's new holder.
                    if !is_arm(*giver) {
                        continue;
                    }
                    let Holder::Arm { home, .. } = &scene.holders[giver.index()] else {
                        continue;
                    };
                    // It starts with its hand on the object it just let go of: that contact
                    // is allowed while it leaves.
                    let placement = match (holder, object_pose) {
                        (Some((now, g)), _) if is_arm(now) => ObjectPlacement::Handoff {
                            a: now,
                            grasp_a: grasp_pose(g),
                            b: *giver,
                        },
                        (Some((now, _)), Some(p)) => ObjectPlacement::Resting {
                            on: now,
                            pose: p,
                            by: Some(*giver),
                        },
                        _ => ObjectPlacement::Absent,
                    };
                    (vec![(*giver, home.clone())], placement, None)
                }
            };
            let moving: Vec<(EndEffectorId, Vec<f64>, Vec<f64>)> = targets
                .iter()
                .filter(|(e, _)| is_arm(*e))
                .filter_map(|(e, goal)| {
                    let now = arms.get(e.index())?.clone()?;
                    let changes = now.iter().zip(goal).any(|(a, b)| (a - b).abs() > 1e-9);
                    changes.then(|| (*e, now, goal.clone()))
                })
                .collect();
            if moving.is_empty() {
                continue;
            }
            let stationary: ArmConfigurations = arms
                .iter()
                .enumerate()
                .filter_map(|(e, q)| Some((EndEffectorId(e as u32), q.clone()?)))
                .filter(|(e, _)| !moving.iter().any(|m| m.0 == *e))
                .collect();
            let moving_arms: Vec<EndEffectorId> = moving.iter().map(|m| m.0).collect();
            let from: Vec<f64> = moving.iter().flat_map(|m| m.1.iter().copied()).collect();
            let to: Vec<f64> = moving.iter().flat_map(|m| m.2.iter().copied()).collect();
            let obstacles = &start.around.obstacles;
            let without = SceneValidity::new(scene, &moving_arms, &stationary, object, placement);
            let motion = without
                .clone()
                .map(|v| v.with_obstacles(obstacles))
                .map_err(MotionError::from)
                .and_then(|validity| {
                    let problem = MotionProblem {
                        scene,
                        arms: &moving_arms,
                        start: &from,
                        goal: &to,
                        validity: &validity,
                        timing: *timing,
                    };
                    self.motion_planner.solve(&problem, rng, stop, &mut scratch)
                });
            match motion {
                Ok(trajectory) => {
                    for (e, _, goal) in &moving {
                        arms[e.index()] = Some(goal.clone());
                    }
                    if !matches!(step.command, Command::Ungrasp { .. }) {
                        lingering = None;
                    }
                    step.motion = Some(trajectory);
                    step.motion_context = Some(crate::plan::MotionContext {
                        stationary,
                        placement,
                        obstacles: obstacles.clone(),
                    });
                }
                Err(MotionError::InvalidOption { name, value }) => {
                    return Err(Setback::Refused(crate::plan::PlanError::InvalidOption {
                        name,
                        value,
                    }));
                }
                Err(error) => {
                    // A retreat that cannot be planned leaves the arm where it is.
                    let Some(arc) = fail_arc else {
                        if let Command::Ungrasp { holder: giver, .. } = &step.command {
                            lingering = Some(*giver);
                        }
                        continue;
                    };
                    let blocker = match &without {
                        Ok(without) if !obstacles.is_empty() => blocker_on_path(
                            scene,
                            object,
                            (without, &without.clone().with_obstacles(obstacles)),
                            (&from, &to),
                            MotionOptions::default().collision_resolution,
                            &mut scratch,
                        ),
                        _ => None,
                    };
                    let reason = match blocker {
                        Some((by, part)) => Infeasibility::Blocked(Blocker {
                            by,
                            part,
                            during: BlockedStep::Motion,
                        }),
                        None => Infeasibility::NoPlacement {
                            detail: format!("{}: {error}", crate::plan::NO_MOTION),
                        },
                    };
                    return Err(Setback::Failed(Failure { arc, reason }));
                }
            }
        }
        Ok(())
    }
}
