//! How an exchange of the object is carried out: from the build-time witness, or solved
//! for this request where the object lies or must be placed, and the resting pose a
//! put-down shares with the next pick.

use cellc_schema::{BlockedStep, Blocker, GraspId, Infeasibility, Node, ObjectId};
use rand_chacha::ChaCha8Rng;

use super::blocking::{blocker_at, fault_of, Fault};
use super::{Exchange, Failure, Planner, SCREENING};
use crate::kinematics::{solve_ik, IkError, IkTarget};
use crate::math::{iso_from_schema, Iso};
use crate::plan::{ArcRef, ArmConfigurations};
use crate::rest::RestRegions;
use crate::scene::{Holder, ObjectPlacement, Obstacle, SceneScratch};
use crate::termination::Termination;
use crate::validity::{SceneValidity, StateFault, StateValidity};

/// Resting poses tried for a put-down whose witness pose is taken by another object.
const PUT_DOWN_SAMPLES: usize = 40;

impl Planner<'_> {
    /// A resting pose on the surface between a put-down (`giver`, arc `put`) and a pick
    /// (`picker`, arc `pick`) that both arms reach collision-free with their grasps.
    pub(super) fn shared_rest_pose(
        &self,
        object: ObjectId,
        giver: (Node, usize),
        picker: (Node, usize),
        obstacles: &[Obstacle],
        rng: &mut ChaCha8Rng,
        stop: &Termination,
    ) -> Option<Iso> {
        let scene = self.scene.filter(|s| s.has_kinematics())?;
        let graph = &self.artifact.objects[object.index()].graph;
        let (giver, put) = giver;
        let (picker, pick) = picker;
        let rest_node = graph.nodes[graph.arcs[put].to as usize];
        let Holder::Surface { slab, .. } = &scene.holders[rest_node.end_effector.index()] else {
            return None;
        };
        let obj = &self.artifact.objects[object.index()];
        let pose_of = |g: GraspId| self.artifact.grasp_pose(object, g);
        let rest = pose_of(rest_node.grasp);
        let turns = crate::symmetry::candidates(&obj.symmetries);
        let works = |pose: &Iso, rng: &mut ChaCha8Rng| -> bool {
            [giver, picker].iter().all(|arm| {
                let Holder::Arm { robot, base, home } = &scene.holders[arm.end_effector.index()]
                else {
                    return false;
                };
                // Either arm may hold a symmetric object with its grasp turned.
                // Many candidates are screened, so each gets a few restarts only.
                let found = turns.iter().find_map(|turn| {
                    let tip = pose * (pose_of(arm.grasp) * turn).inverse();
                    if scene.tip_hits_fixed(arm.end_effector, &tip).is_some() {
                        return None;
                    }
                    solve_ik(
                        &scene.robots[*robot],
                        base,
                        &IkTarget::Pose(tip),
                        home,
                        rng,
                        &SCREENING,
                        stop,
                    )
                    .ok()
                });
                let Some(q) = found else {
                    return false;
                };
                let placement = ObjectPlacement::Resting {
                    on: rest_node.end_effector,
                    pose: *pose,
                    by: Some(arm.end_effector),
                };
                SceneValidity::new(scene, &[arm.end_effector], &[], object, placement)
                    .map(|v| v.with_obstacles(obstacles))
                    .is_ok_and(|v| matches!(v.is_valid(&q, &mut SceneScratch::default()), Ok(true)))
            })
        };
        let witnessed = [
            self.witness_of(object, pick).0,
            self.witness_of(object, put).0,
        ];
        for pose in witnessed.into_iter().flatten() {
            if works(&pose, rng) {
                return Some(pose);
            }
        }
        // Sampled resting poses: anywhere on the top face with the centre in the workspace.
        let workspace = &scene.workspaces[rest_node.workspace.index()];
        let regions = RestRegions::new(slab, workspace, &rest);
        for _ in 0..100 {
            if stop.should_stop() {
                return None;
            }
            let pose = regions.sample(rng)?;
            if works(&pose, rng) {
                return Some(pose);
            }
        }
        None
    }

    /// The object pose and arm configurations of a witnessed arc.
    pub(super) fn witness_of(
        &self,
        object: ObjectId,
        arc: usize,
    ) -> (Option<Iso>, ArmConfigurations) {
        let graph = &self.artifact.objects[object.index()].graph;
        match graph.arcs[arc]
            .witness
            .and_then(|w| graph.witnesses.get(w as usize))
        {
            Some(w) => (
                Some(iso_from_schema(&w.object)),
                w.configurations
                    .iter()
                    .map(|c| (c.end_effector, c.joints.clone()))
                    .collect(),
            ),
            None => (None, Vec::new()),
        }
    }

    /// How a transition arc is carried out: from its witness, except a first pick (the
    /// object is where the request says) and a last place (where the goal says), which are
    /// solved for this request.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn exchange(
        &self,
        object: ObjectId,
        arc: usize,
        from: Node,
        to: Node,
        lying_at: Option<Iso>,
        place_at: Option<Iso>,
        obstacles: &[Obstacle],
        rng: &mut ChaCha8Rng,
        stop: &Termination,
    ) -> Result<Exchange, Failure> {
        let graph = &self.artifact.objects[object.index()].graph;
        let arc_ref = ArcRef::of(&graph.arcs[arc]);
        let Some(scene) = self.scene.filter(|s| s.has_kinematics()) else {
            return Ok(Exchange::default());
        };
        let surface_and_arm = match (
            &scene.holders[from.end_effector.index()],
            &scene.holders[to.end_effector.index()],
        ) {
            (Holder::Surface { .. }, Holder::Arm { .. }) => Some((from, to)),
            (Holder::Arm { .. }, Holder::Surface { .. }) => Some((to, from)),
            _ => None,
        };
        let specific_pose = match (surface_and_arm, lying_at, place_at) {
            (Some((surface, _)), Some(pose), _) if surface == from => Some(pose),
            (Some((surface, _)), _, Some(goal)) if surface == to => Some(goal),
            _ => None,
        };
        if let (Some(ends), Some(pose)) = (surface_and_arm, specific_pose) {
            let during = if ends.0 == from {
                BlockedStep::Pick {
                    at: position(&pose),
                }
            } else {
                BlockedStep::PutDown {
                    at: position(&pose),
                }
            };
            return self
                .solve_at(object, scene, ends, (pose, during), 8, obstacles, rng, stop)
                .map_err(|reason| Failure {
                    arc: arc_ref,
                    reason,
                });
        }
        let (object_pose, configurations) = self.witness_of(object, arc);
        let Some(pose) = object_pose else {
            return Err(Failure {
                arc: arc_ref,
                reason: Infeasibility::NoPlacement {
                    detail: "the arc has no witness (build with verification)".into(),
                },
            });
        };
        // The witness was found in the empty cell: the world's other objects may stand
        // where it puts the object or the arms.
        if let Some(reason) =
            self.blocked_by(object, scene, (from, to), pose, &configurations, obstacles)
        {
            // A put-down anywhere in the workspace: another resting pose there, clear of
            // the objects already in it.
            if let Some((surface, arm)) = surface_and_arm.filter(|(s, _)| *s == to) {
                if let Holder::Surface { slab, .. } = &scene.holders[surface.end_effector.index()] {
                    let rest = self.artifact.grasp_pose(object, surface.grasp);
                    let regions =
                        RestRegions::new(slab, &scene.workspaces[surface.workspace.index()], &rest);
                    for _ in 0..PUT_DOWN_SAMPLES {
                        if stop.should_stop() {
                            break;
                        }
                        let Some(candidate) = regions.sample(rng) else {
                            break;
                        };
                        let during = BlockedStep::PutDown {
                            at: position(&candidate),
                        };
                        if let Ok(found) = self.solve_at(
                            object,
                            scene,
                            (surface, arm),
                            (candidate, during),
                            2,
                            obstacles,
                            rng,
                            stop,
                        ) {
                            // Put down elsewhere: the plan went round what took the place.
                            let detour = match reason {
                                Infeasibility::Blocked(blocker) => Some(blocker),
                                _ => None,
                            };
                            return Ok(Exchange { detour, ..found });
                        }
                    }
                }
            }
            return Err(Failure {
                arc: arc_ref,
                reason,
            });
        }
        Ok(Exchange {
            object: object_pose,
            configurations,
            detour: None,
        })
    }

    /// Why an exchange's configurations (and the object at `pose` between `from` and
    /// `to`) fail once `obstacles` stand in the cell: the object that blocks them, or the
    /// first collision when the check without the obstacles does not clear them; `None`
    /// when clear or when there are none. The witness was free in the empty cell (other
    /// arms at home, as now), so a collision normally involves an obstacle.
    fn blocked_by(
        &self,
        object: ObjectId,
        scene: &crate::scene::Scene,
        (from, to): (Node, Node),
        pose: Iso,
        configurations: &ArmConfigurations,
        obstacles: &[Obstacle],
    ) -> Option<Infeasibility> {
        if obstacles.is_empty() {
            return None;
        }
        let grasp = |n: Node| self.artifact.grasp_pose(object, n.grasp);
        let is_arm = |n: Node| {
            matches!(
                scene.holders.get(n.end_effector.index()),
                Some(Holder::Arm { .. })
            )
        };
        let at = position(&pose);
        let (placement, during) = match (is_arm(from), is_arm(to)) {
            (true, true) => (
                ObjectPlacement::Handoff {
                    a: from.end_effector,
                    grasp_a: grasp(from),
                    b: to.end_effector,
                },
                BlockedStep::Handoff { at },
            ),
            (true, false) => (
                ObjectPlacement::Resting {
                    on: to.end_effector,
                    pose,
                    by: Some(from.end_effector),
                },
                BlockedStep::PutDown { at },
            ),
            (false, true) => (
                ObjectPlacement::Resting {
                    on: from.end_effector,
                    pose,
                    by: Some(to.end_effector),
                },
                BlockedStep::Pick { at },
            ),
            (false, false) => (ObjectPlacement::Absent, BlockedStep::PutDown { at }),
        };
        let arms: Vec<_> = configurations.iter().map(|(e, _)| *e).collect();
        let q: Vec<f64> = configurations
            .iter()
            .flat_map(|(_, q)| q.iter().copied())
            .collect();
        let without = SceneValidity::new(scene, &arms, &[], object, placement).ok()?;
        let with = without.clone().with_obstacles(obstacles);
        let mut scratch = SceneScratch::default();
        let Ok(Some(StateFault::Collision { a, b })) = with.check(&q, &mut scratch) else {
            return None;
        };
        Some(
            match blocker_at(scene, object, (&without, &with), &q, &mut scratch) {
                Some((by, part)) => Infeasibility::Blocked(Blocker { by, part, during }),
                None => Infeasibility::Collision { a, b },
            },
        )
    }

    /// An arm exchanging the object with a surface where it rests at `pose` (the step
    /// `during`, should one of the world's other objects block it): IK for the arm's grasp
    /// (turned by the object's symmetries), checked with the world's other objects in the
    /// cell. When a configuration found is free but for one of them, the failure is the
    /// object that blocks the first such configuration.
    #[allow(clippy::too_many_arguments)]
    fn solve_at(
        &self,
        object: ObjectId,
        scene: &crate::scene::Scene,
        (surface, arm): (Node, Node),
        (pose, during): (Iso, BlockedStep),
        attempts: usize,
        obstacles: &[Obstacle],
        rng: &mut ChaCha8Rng,
        stop: &Termination,
    ) -> Result<Exchange, Infeasibility> {
        let obj = &self.artifact.objects[object.index()];
        let grasp = self.artifact.grasp_pose(object, arm.grasp);
        let Holder::Arm { robot, base, home } = &scene.holders[arm.end_effector.index()] else {
            return Err(Infeasibility::NoPlacement {
                detail: "not an arm".into(),
            });
        };
        let robot = &scene.robots[*robot];
        // A symmetric object may be taken with the grasp turned by a symmetry.
        let turns = crate::symmetry::candidates(&obj.symmetries);
        let mut last_collision = None;
        let mut blocked = None;
        let mut best: Option<IkError> = None;
        let mut scratch = SceneScratch::default();
        for attempt in 0..attempts {
            if stop.should_stop() {
                break;
            }
            let tip = pose * (grasp * turns[attempt % turns.len()]).inverse();
            if let Some(c) = scene.tip_hits_fixed(arm.end_effector, &tip) {
                let (a, b) = scene.world.names(&c);
                last_collision = Some((a.to_string(), b.to_string()));
                continue;
            }
            match solve_ik(
                robot,
                base,
                &IkTarget::Pose(tip),
                home,
                rng,
                &SCREENING,
                stop,
            ) {
                Ok(q) => {
                    let placement = ObjectPlacement::Resting {
                        on: surface.end_effector,
                        pose,
                        by: Some(arm.end_effector),
                    };
                    let without = match SceneValidity::new(
                        scene,
                        &[arm.end_effector],
                        &[],
                        object,
                        placement,
                    ) {
                        Ok(v) => v,
                        Err(e) => {
                            last_collision = Some(("collision query".into(), format!("{e:?}")));
                            continue;
                        }
                    };
                    let with = without.clone().with_obstacles(obstacles);
                    let fault = match with.check(&q, &mut scratch) {
                        Ok(None) => {
                            return Ok(Exchange {
                                object: Some(pose),
                                configurations: vec![(arm.end_effector, q)],
                                detour: None,
                            })
                        }
                        Ok(Some(found)) if obstacles.is_empty() => Fault::Own(found),
                        Ok(Some(found)) => {
                            fault_of(scene, object, (&without, &with), &q, found, &mut scratch)
                        }
                        Err(e) => {
                            last_collision = Some(("collision query".into(), format!("{e:?}")));
                            continue;
                        }
                    };
                    match fault {
                        Fault::Blocked(by, part) => {
                            blocked = blocked.or(Some(Blocker { by, part, during }))
                        }
                        Fault::Own(StateFault::Collision { a, b }) => last_collision = Some((a, b)),
                        Fault::Own(fault) => {
                            last_collision = Some(("joint limits".into(), fault.to_string()))
                        }
                    }
                }
                Err(e) => best = Some(e),
            }
        }
        // A configuration that is free but for another object proves the exchange
        // feasible without it: that object is the reason, before any collision of the
        // arm's own (other configurations) and before an unreached pose.
        let reason = match (blocked, last_collision, best) {
            (Some(blocker), _, _) => Infeasibility::Blocked(blocker),
            (None, Some((a, b)), _) => Infeasibility::Collision { a, b },
            (
                None,
                None,
                Some(IkError::NotConverged {
                    tries,
                    position_error,
                    rotation_error,
                }),
            ) => Infeasibility::NoIkSolution {
                end_effector: arm.end_effector,
                tries: tries as u32,
                position_error,
                rotation_error,
            },
            _ => Infeasibility::NoPlacement {
                detail: "no configuration".into(),
            },
        };
        Err(reason)
    }
}

/// The position of a pose, as a blocked step records where it happens.
fn position(pose: &Iso) -> [f64; 3] {
    let t = pose.translation.vector;
    [t.x, t.y, t.z]
}
