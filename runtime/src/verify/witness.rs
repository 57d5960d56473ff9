//! How each question is answered: a hold by sampling object poses in the workspace, a
//! handoff with the closed-chain solver, a rest by sampling resting poses on the surface,
//! and a regrasp within one hand by refusing it.

use cellc_schema::{
    self as schema, Artifact, EndEffectorId, GraspId, Infeasibility, ObjectId, Witness, WorkspaceId,
};
use rand::Rng;
use rand_chacha::ChaCha8Rng;

use super::attempt::{arm, invalidity, sample_point, Attempt, Fault, Outcome};
use super::chains::{Chain, ChainTable, Start};
use super::hands::{TurnTable, Turns};
use super::{rng_for, Check, VerifyOptions};
use crate::kinematics::closed_chain::HandoffProblem;
use crate::math::{iso_to_schema, Iso, Point, Quat, Vec3};
use crate::rest::RestRegions;
use crate::scene::{Holder, ObjectPlacement, Scene, SceneScratch};

/// The answer to one question: a witness, or why there is none.
pub(super) fn run_check(
    artifact: &Artifact,
    scene: &Scene,
    scratch: &mut SceneScratch,
    options: &VerifyOptions,
    (turns, chains): (&TurnTable, &ChainTable),
    check: Check,
) -> Result<Witness, Infeasibility> {
    let mut answer = Answer {
        artifact,
        turns,
        chains,
        scene,
        options,
        scratch,
        rng: rng_for(options.seed, &check),
        outcome: Outcome::new(),
    };
    match check {
        Check::Hold { object, e, g, w } => answer.hold(object, e, g, w),
        Check::Handoff {
            object,
            a,
            ga,
            b,
            gb,
            w,
        } => answer.handoff(object, (a, ga), (b, gb), w),
        Check::Rest {
            object,
            arm,
            g,
            surface,
            r,
            w,
        } => answer.rest(object, (arm, g), (surface, r), w),
        Check::Regrasp {
            object,
            e,
            from,
            to,
            w: _,
        } => Err(regrasp(artifact, object, e, from, to)),
    }
}

/// What answering a check needs: its inputs, its own generator, and what its failed
/// attempts saw.
struct Answer<'a> {
    artifact: &'a Artifact,
    turns: &'a TurnTable,
    chains: &'a ChainTable,
    scene: &'a Scene,
    options: &'a VerifyOptions,
    scratch: &'a mut SceneScratch,
    rng: ChaCha8Rng,
    outcome: Outcome,
}

impl Answer<'_> {
    /// Arm `e` holding the object with grasp `g` somewhere in workspace `w`.
    fn hold(
        &mut self,
        object: ObjectId,
        e: EndEffectorId,
        g: GraspId,
        w: WorkspaceId,
    ) -> Result<Witness, Infeasibility> {
        let (artifact, scene, options) = (self.artifact, self.scene, self.options);
        let (rng, outcome, scratch) = (&mut self.rng, &mut self.outcome, &mut *self.scratch);
        let Some((robot, base, home)) = arm(scene, e) else {
            return Err(Infeasibility::NoPlacement {
                detail: "the holder is not an arm".into(),
            });
        };
        let grasp = artifact.grasp_pose(object, g);
        // A robot with fewer than six joints (a conveyor) cannot take an arbitrary
        // pose: sample its joints instead and keep a placement inside the workspace.
        if robot.n_joints() < 6 {
            let mut q = home.to_vec();
            for _ in 0..options.placements * 4 {
                robot.sample_configuration(rng, &mut q);
                let object_pose = robot.tip_pose(&base, &q) * grasp;
                let center = Point::from(object_pose.translation.vector);
                if !scene.workspaces[w.index()]
                    .iter()
                    .any(|b| crate::math::contains_point(b, &center))
                {
                    continue;
                }
                let placement = ObjectPlacement::Held { by: e, grasp };
                match invalidity(scene, &[e], &q, object, placement, scratch) {
                    None => {
                        return Ok(Witness {
                            object: iso_to_schema(&object_pose),
                            configurations: vec![schema::ArmConfiguration {
                                end_effector: e,
                                joints: q,
                            }],
                        })
                    }
                    Some(fault) => outcome.last_collision = Some(fault),
                }
            }
            return Err(outcome.reason(
                (scene, object, scratch),
                "the robot's joints never bring the object into the workspace",
            ));
        }
        let attempt = Attempt {
            scene,
            object,
            e,
            robot,
            base,
            home,
            grasp,
        };
        for _ in 0..options.placements {
            let Some(center) = sample_point(&scene.workspaces[w.index()], rng) else {
                break;
            };
            // Objects are carried upright, turned about the vertical at random.
            let yaw = rng.random::<f64>() * std::f64::consts::TAU;
            let object_pose = Iso::from_parts(
                center.coords.into(),
                Quat::from_axis_angle(&Vec3::z_axis(), yaw),
            );
            let placement = ObjectPlacement::Held { by: e, grasp };
            if let Some(witness) =
                attempt.run(object_pose, placement, rng, options, scratch, outcome)
            {
                return Ok(witness);
            }
        }
        Err(outcome.reason((scene, object, scratch), "the workspace has no volume"))
    }

    /// Arms `a` and `b`, each with its grasp, holding the object at once in `w`.
    fn handoff(
        &mut self,
        object: ObjectId,
        (a, ga): (EndEffectorId, GraspId),
        (b, gb): (EndEffectorId, GraspId),
        w: WorkspaceId,
    ) -> Result<Witness, Infeasibility> {
        let (artifact, scene, options) = (self.artifact, self.scene, self.options);
        let (rng, outcome, scratch) = (&mut self.rng, &mut self.outcome, &mut *self.scratch);
        let (Some((robot_a, base_a, home_a)), Some((robot_b, base_b, home_b))) =
            (arm(scene, a), arm(scene, b))
        else {
            return Err(Infeasibility::NoPlacement {
                detail: "a holder is not an arm".into(),
            });
        };
        let boxes = &scene.workspaces[w.index()];
        outcome.partner = Some(b);
        // A symmetric object may be held by B in a grasp turned by a symmetry (a ball
        // passed between two hands with the same grasp is held from opposite sides); the
        // turns that put the two hands into each other are left out before any IK.
        let turns = match self.turns.get(artifact, scene, object, (a, ga), (b, gb)) {
            Turns::Apart(turns) if !turns.is_empty() => turns,
            Turns::Apart(_) => {
                return Err(Infeasibility::NoPlacement {
                    detail: "the object has no symmetry turn to try".into(),
                })
            }
            Turns::Overlap { a, b } => {
                return Err(Infeasibility::Collision {
                    a: scene.world.name(a).to_string(),
                    b: scene.world.name(b).to_string(),
                })
            }
        };
        let (grasp_a, grasp_b) = (
            artifact.grasp_pose(object, ga),
            artifact.grasp_pose(object, gb),
        );
        // The positions tried are the chain's, not the check's: see `chains.rs`.
        // From the homes, and in the second half of the placements from drawn
        // configurations once a chain has closed into a collision (see `Start::Drawn`).
        let mut collided = false;
        let mut targets = Chain::of(a, b, &grasp_a, &(grasp_b * turns[0])).targets(options.seed, w);
        for attempt in 0..options.placements {
            let Some(target) = sample_point(boxes, &mut targets) else {
                break;
            };
            let start = if collided && attempt >= options.placements / 2 {
                Start::Drawn
            } else {
                Start::Homes
            };
            let turn = if attempt == 0 {
                turns[0]
            } else {
                turns[rng.random_range(0..turns.len())]
            };
            let bounds = boxes
                .iter()
                .find(|bx| crate::math::contains_point(bx, &target))
                .map(|bx| (bx.mins, bx.maxs));
            let problem = HandoffProblem {
                a: (robot_a, base_a),
                b: (robot_b, base_b),
                grasp_a,
                grasp_b: grasp_b * turn,
                target,
                bounds,
            };
            let seeds = ((home_a, home_b), start);
            match self
                .chains
                .solve(options.seed, (a, b), &problem, seeds, &options.handoff)
            {
                Ok((solution, shared)) => {
                    let center = Point::from(solution.object.translation.vector);
                    if !boxes
                        .iter()
                        .any(|bx| crate::math::contains_point(bx, &center))
                    {
                        continue;
                    }
                    let placement = ObjectPlacement::Handoff {
                        a,
                        grasp_a: problem.grasp_a,
                        b,
                    };
                    let q = [solution.qa.as_slice(), solution.qb.as_slice()].concat();
                    // Arms that collide on their own collide with the object too: a fact
                    // of the chain's joints, decided once for every check that takes them.
                    let arms_alone = || {
                        let absent = ObjectPlacement::Absent;
                        let fault = invalidity(scene, &[a, b], &q, object, absent, scratch);
                        matches!(fault, Some(Fault::Collision { .. }))
                    };
                    if shared.is_some_and(|joints| joints.arms_collide(arms_alone)) {
                        collided = true;
                        outcome.last_collision = Some(Fault::Collision {
                            arms: vec![a, b],
                            q,
                            placement,
                        });
                        continue;
                    }
                    match invalidity(scene, &[a, b], &q, object, placement, scratch) {
                        None => {
                            return Ok(Witness {
                                object: iso_to_schema(&solution.object),
                                configurations: vec![
                                    schema::ArmConfiguration {
                                        end_effector: a,
                                        joints: solution.qa,
                                    },
                                    schema::ArmConfiguration {
                                        end_effector: b,
                                        joints: solution.qb,
                                    },
                                ],
                            })
                        }
                        Some(fault) => {
                            collided = true;
                            outcome.last_collision = Some(fault);
                        }
                    }
                }
                Err(error) => outcome.best_ik.record(a, &error),
            }
        }
        Err(outcome.reason((scene, object, scratch), "the workspace has no volume"))
    }

    /// Arm `e` with grasp `g` taking the object from (or leaving it on) `surface`, where
    /// it rests as `r`, in `w`.
    fn rest(
        &mut self,
        object: ObjectId,
        (e, g): (EndEffectorId, GraspId),
        (surface, r): (EndEffectorId, GraspId),
        w: WorkspaceId,
    ) -> Result<Witness, Infeasibility> {
        let (artifact, scene, options) = (self.artifact, self.scene, self.options);
        let (rng, outcome, scratch) = (&mut self.rng, &mut self.outcome, &mut *self.scratch);
        let Some((robot, base, home)) = arm(scene, e) else {
            return Err(Infeasibility::NoPlacement {
                detail: "the holder is not an arm".into(),
            });
        };
        let Holder::Surface { slab, .. } = &scene.holders[surface.index()] else {
            return Err(Infeasibility::NoPlacement {
                detail: "the support is not a surface".into(),
            });
        };
        let rest = artifact.grasp_pose(object, r);
        let grasp = artifact.grasp_pose(object, g);
        // The object rests on the top face, anywhere and turned any way about the
        // vertical, as long as its centre lies in the workspace.
        let regions = RestRegions::new(slab, &scene.workspaces[w.index()], &rest);
        if regions.is_empty() {
            let center_z = regions.center_height();
            let surface_name = &artifact.end_effectors[surface.index()].name;
            let rest_name = &artifact.objects[object.index()].grasps[r.index()].name;
            let ws = &artifact.workspaces[w.index()].name;
            return Err(Infeasibility::NoPlacement {
                detail: format!(
                    "resting as `{rest_name}` on `{surface_name}`, the object's centre ({center_z:.3} m high) is never inside `{ws}`"
                ),
            });
        }
        let attempt = Attempt {
            scene,
            object,
            e,
            robot,
            base,
            home,
            grasp,
        };
        for _ in 0..options.placements {
            let Some(object_pose) = regions.sample(rng) else {
                break;
            };
            let placement = ObjectPlacement::Resting {
                on: surface,
                pose: object_pose,
                by: Some(e),
            };
            if let Some(witness) =
                attempt.run(object_pose, placement, rng, options, scratch, outcome)
            {
                return Ok(witness);
            }
        }
        Err(outcome.reason((scene, object, scratch), "no resting pose"))
    }
}

/// Why arm `e` cannot change its own grasp of `object` from `from` to `to`: nothing
/// would hold the object between letting go and taking it again. The compiler keeps
/// such transitions (imported databases list them) and warns; verification refuses
/// them, so no plan relies on an arc without a witness.
fn regrasp(
    artifact: &Artifact,
    object: ObjectId,
    e: EndEffectorId,
    from: GraspId,
    to: GraspId,
) -> Infeasibility {
    let arm = &artifact.end_effectors[e.index()].name;
    let grasps = &artifact.objects[object.index()].grasps;
    let (from, to) = (&grasps[from.index()].name, &grasps[to.index()].name);
    Infeasibility::NoPlacement {
        detail: format!(
            "`{arm}` cannot pass the object to itself: nothing holds it while the grasp changes from `{from}` to `{to}`"
        ),
    }
}
