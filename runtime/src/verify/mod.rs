//! Build-time verification: every arc of every object graph is checked kinematically
//! once, and either gets a witness (an object pose and joint configurations that realise
//! it, collision-free and within limits) or is pruned with a reason.
//!
//! Handoff and resting-pose feasibility depend only on (end-effectors, grasps, workspace),
//! never on a request, so checking them here, in parallel, means the runtime planner
//! rarely backtracks. Results are deterministic for a seed: each check draws from its own
//! generator, seeded from the seed and the check's identity, so thread scheduling cannot
//! change them.
//!
//! What each arc needs:
//! - move S(e, g, wi) -> S(e, g, wj): e holds the object with g somewhere in wj;
//! - transition between two arms in w (a handoff): one object pose in w where both hold
//!   it at once, found with the closed-chain solver;
//! - transition between an arm and a fixed surface in w: a resting pose on the surface
//!   inside w that the arm reaches with its grasp.
//!
//! A move into a state is realised by the same holding pose whatever workspace it comes
//! from, and a handoff A -> B by the same configurations as B -> A, so checks are keyed
//! by what they depend on and shared between arcs.

use std::collections::BTreeMap;

use cellc_schema::{self as schema, ArcKind, Artifact, Infeasibility, Witness};
use nalgebra as na;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

use crate::closed_chain::{solve_handoff, HandoffOptions, HandoffProblem};
use crate::kinematics::{solve_ik, IkError, IkOptions, IkTarget};
use crate::math::{iso_from_schema, iso_to_schema, Iso, Point, Quat, Vec3};
use crate::scene::{Aabb, Holder, ObjectPlacement, Scene, SceneScratch};

/// Verification settings.
#[derive(Clone, Debug)]
pub struct VerifyOptions {
    /// Seed of every randomized solver.
    pub seed: u64,
    /// Object poses tried per check before giving up.
    pub placements: u32,
    /// Inverse-kinematics settings.
    pub ik: IkOptions,
    /// Closed-chain (handoff) settings.
    pub handoff: HandoffOptions,
}

impl Default for VerifyOptions {
    fn default() -> VerifyOptions {
        VerifyOptions {
            seed: 0,
            // Failing checks dominate the time: a few placements, each with a modest number
            // of restarts, find the feasible arcs of real cells (measured on the shipped
            // cells) while keeping infeasible ones cheap.
            placements: 16,
            ik: IkOptions {
                restarts: 12,
                ..IkOptions::default()
            },
            handoff: HandoffOptions {
                ik: IkOptions {
                    restarts: 20,
                    ..HandoffOptions::default().ik
                },
                ..HandoffOptions::default()
            },
        }
    }
}

/// What verification found, for reporting.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct VerifyReport {
    /// Arcs checked.
    pub n_checked: u64,
    /// Arcs pruned.
    pub n_pruned: u64,
    /// Distinct feasibility checks run (arcs share checks).
    pub n_checks: u64,
}

/// One feasibility question, keyed by everything its answer depends on.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
enum Check {
    /// Arm `e` holds the object with grasp `g` somewhere in workspace `w`.
    Hold { object: u32, e: u32, g: u32, w: u32 },
    /// Arms (or an arm and a conveyor) `a` with `ga` and `b` with `gb` hold it at once in
    /// `w`; stored with (a, ga) <= (b, gb) so both directions share it.
    Handoff {
        object: u32,
        a: u32,
        ga: u32,
        b: u32,
        gb: u32,
        w: u32,
    },
    /// Arm `arm` with `g` and surface `surface` with resting pose `r` in `w`.
    Rest {
        object: u32,
        arm: u32,
        g: u32,
        surface: u32,
        r: u32,
        w: u32,
    },
}

/// Verifies every arc of `artifact` in place: feasible arcs get witnesses, infeasible ones
/// move to `pruned`. `progress` is called with (done, total) as checks finish.
pub fn verify(
    artifact: &mut Artifact,
    scene: &Scene,
    options: &VerifyOptions,
    progress: &(dyn Fn(u64, u64) + Sync),
) -> VerifyReport {
    // Which check each arc needs (None: nothing geometric to check, e.g. abstract holders).
    let mut arc_checks: Vec<Vec<Option<Check>>> = Vec::new();
    let mut checks: BTreeMap<Check, ()> = BTreeMap::new();
    for (o, object) in artifact.objects.iter().enumerate() {
        let mut per_arc = Vec::with_capacity(object.graph.arcs.len());
        for arc in &object.graph.arcs {
            let check = check_of(artifact, scene, o as u32, object, arc);
            if let Some(c) = check {
                checks.insert(c, ());
            }
            per_arc.push(check);
        }
        arc_checks.push(per_arc);
    }
    let checks: Vec<Check> = checks.into_keys().collect();
    let total = checks.len() as u64;
    let done = std::sync::atomic::AtomicU64::new(0);
    let results: Vec<(Check, Result<Witness, Infeasibility>)> = checks
        .par_iter()
        .map_init(SceneScratch::default, |scratch, &check| {
            let result = run_check(artifact, scene, scratch, options, check);
            let n = done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
            progress(n, total);
            (check, result)
        })
        .collect();
    let results: BTreeMap<Check, Result<Witness, Infeasibility>> = results.into_iter().collect();

    let mut report = VerifyReport {
        n_checks: total,
        ..VerifyReport::default()
    };
    for (object, per_arc) in artifact.objects.iter_mut().zip(arc_checks) {
        let graph = &mut object.graph;
        let mut witness_of: BTreeMap<Check, u32> = BTreeMap::new();
        let mut kept = Vec::with_capacity(graph.arcs.len());
        for (mut arc, check) in graph.arcs.drain(..).zip(per_arc) {
            let Some(check) = check else {
                kept.push(arc);
                continue;
            };
            report.n_checked += 1;
            match &results[&check] {
                Ok(witness) => {
                    let index = *witness_of.entry(check).or_insert_with(|| {
                        graph.witnesses.push(witness.clone());
                        graph.witnesses.len() as u32 - 1
                    });
                    arc.witness = Some(index);
                    kept.push(arc);
                }
                Err(reason) => {
                    report.n_pruned += 1;
                    graph.pruned.push(schema::PrunedArc {
                        arc,
                        reason: reason.clone(),
                    });
                }
            }
        }
        graph.arcs = kept;
    }
    artifact.verification = Some(schema::Verification {
        seed: options.seed,
        n_checked: report.n_checked,
        n_pruned: report.n_pruned,
    });
    report
}

fn check_of(
    artifact: &Artifact,
    scene: &Scene,
    object: u32,
    obj: &schema::Object,
    arc: &schema::Arc,
) -> Option<Check> {
    let from = obj.graph.nodes[arc.from as usize];
    let to = obj.graph.nodes[arc.to as usize];
    let holder = |e: u32| &scene.holders[e as usize];
    match arc.kind {
        ArcKind::Move => match holder(to.end_effector) {
            Holder::Arm { .. } => Some(Check::Hold {
                object,
                e: to.end_effector,
                g: to.grasp,
                w: to.workspace,
            }),
            _ => None,
        },
        ArcKind::Transition => {
            let w = to.workspace;
            let (a, ga, b, gb) = (from.end_effector, from.grasp, to.end_effector, to.grasp);
            match (holder(a), holder(b)) {
                (Holder::Arm { .. }, Holder::Arm { .. }) if a != b => {
                    let ((a, ga), (b, gb)) = if (a, ga) <= (b, gb) {
                        ((a, ga), (b, gb))
                    } else {
                        ((b, gb), (a, ga))
                    };
                    Some(Check::Handoff {
                        object,
                        a,
                        ga,
                        b,
                        gb,
                        w,
                    })
                }
                (Holder::Arm { .. }, Holder::Surface { .. }) => Some(Check::Rest {
                    object,
                    arm: a,
                    g: ga,
                    surface: b,
                    r: gb,
                    w,
                }),
                (Holder::Surface { .. }, Holder::Arm { .. }) => Some(Check::Rest {
                    object,
                    arm: b,
                    g: gb,
                    surface: a,
                    r: ga,
                    w,
                }),
                _ => {
                    let _ = artifact;
                    None
                }
            }
        }
    }
}

/// The generator of one check: the same for a given seed and check, whatever thread runs
/// it and in whatever order.
fn rng_for(seed: u64, check: &Check) -> ChaCha8Rng {
    let mut h: u64 = seed ^ 0x9E37_79B9_7F4A_7C15;
    let words: Vec<u32> = match *check {
        Check::Hold { object, e, g, w } => vec![1, object, e, g, w],
        Check::Handoff {
            object,
            a,
            ga,
            b,
            gb,
            w,
        } => vec![2, object, a, ga, b, gb, w],
        Check::Rest {
            object,
            arm,
            g,
            surface,
            r,
            w,
        } => vec![3, object, arm, g, surface, r, w],
    };
    for word in words {
        // SplitMix64 steps: a cheap, well-mixed hash of the check's identity.
        h = h
            .wrapping_add(u64::from(word))
            .wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = h;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        h = z ^ (z >> 31);
    }
    ChaCha8Rng::seed_from_u64(h)
}

/// A point drawn uniformly from a union of boxes (volume-weighted).
fn sample_point(boxes: &[Aabb], rng: &mut ChaCha8Rng) -> Option<Point> {
    let total: f64 = boxes.iter().map(Aabb::volume).sum();
    if boxes.is_empty() || total <= 0.0 {
        return None;
    }
    let mut pick = rng.random::<f64>() * total;
    let chosen = boxes
        .iter()
        .find(|b| {
            pick -= b.volume();
            pick <= 0.0
        })
        .unwrap_or(&boxes[boxes.len() - 1]);
    Some(Point::from(na::Vector3::from_fn(|i, _| {
        chosen.min[i] + rng.random::<f64>() * (chosen.max[i] - chosen.min[i])
    })))
}

fn grasp_pose(artifact: &Artifact, object: u32, g: u32) -> Iso {
    artifact.objects[object as usize].grasps[g as usize]
        .pose
        .as_ref()
        .map(iso_from_schema)
        .unwrap_or_else(Iso::identity)
}

/// Keeps the smallest IK errors seen, for the reason of a failed check.
#[derive(Default)]
struct BestIk {
    end_effector: u32,
    tries: u32,
    position_error: f64,
    rotation_error: f64,
    seen: bool,
}

impl BestIk {
    fn record(&mut self, end_effector: u32, error: &IkError) {
        let IkError::NotConverged {
            tries,
            position_error,
            rotation_error,
        } = error
        else {
            return;
        };
        self.tries += *tries as u32;
        if !self.seen || *position_error < self.position_error {
            self.end_effector = end_effector;
            self.position_error = *position_error;
            self.rotation_error = *rotation_error;
            self.seen = true;
        }
    }
}

struct Outcome {
    best_ik: BestIk,
    /// For a handoff, the other arm: the failure is the closed chain's, not one arm's.
    partner: Option<u32>,
    last_collision: Option<(String, String)>,
}

impl Outcome {
    fn new() -> Outcome {
        Outcome {
            best_ik: BestIk::default(),
            partner: None,
            last_collision: None,
        }
    }

    fn into_reason(self, no_placement: &str) -> Infeasibility {
        if let Some((a, b)) = self.last_collision {
            return Infeasibility::Collision { a, b };
        }
        if let (true, Some(b)) = (self.best_ik.seen, self.partner) {
            return Infeasibility::NoClosedChain {
                a: self.best_ik.end_effector,
                b,
                tries: self.best_ik.tries,
                position_error: self.best_ik.position_error,
                rotation_error: self.best_ik.rotation_error,
            };
        }
        if self.best_ik.seen {
            return Infeasibility::NoIkSolution {
                end_effector: self.best_ik.end_effector,
                tries: self.best_ik.tries,
                position_error: self.best_ik.position_error,
                rotation_error: self.best_ik.rotation_error,
            };
        }
        Infeasibility::NoPlacement {
            detail: no_placement.to_string(),
        }
    }
}

fn arm(scene: &Scene, e: u32) -> Option<(&crate::robot::Robot, Iso, &[f64])> {
    match &scene.holders[e as usize] {
        Holder::Arm { robot, base, home } => Some((&scene.robots[*robot], *base, home.as_slice())),
        _ => None,
    }
}

/// One arm holding the object with `grasp` at a given object pose: the IK solve, the
/// collision check and the witness, shared by holds and rests.
struct Attempt<'s> {
    scene: &'s Scene,
    object: u32,
    e: u32,
    robot: &'s crate::robot::Robot,
    base: Iso,
    home: &'s [f64],
    grasp: Iso,
}

impl Attempt<'_> {
    /// A witness when the arm reaches the pose free of collisions; otherwise records why
    /// not in `outcome`.
    fn run(
        &self,
        object_pose: Iso,
        placement: ObjectPlacement,
        rng: &mut ChaCha8Rng,
        options: &VerifyOptions,
        scratch: &mut SceneScratch,
        outcome: &mut Outcome,
    ) -> Option<Witness> {
        let tip = object_pose * self.grasp.inverse();
        match solve_ik(
            self.robot,
            &self.base,
            &IkTarget::Pose(tip),
            self.home,
            rng,
            &options.ik,
        ) {
            Ok(q) => {
                match collision(self.scene, &[(self.e, &q)], self.object, placement, scratch) {
                    None => Some(Witness {
                        object: iso_to_schema(&object_pose),
                        configurations: vec![schema::ArmConfiguration {
                            end_effector: self.e,
                            joints: q,
                        }],
                    }),
                    Some(pair) => {
                        outcome.last_collision = Some(pair);
                        None
                    }
                }
            }
            Err(error) => {
                outcome.best_ik.record(self.e, &error);
                None
            }
        }
    }
}

/// The colliding pair of a state, or `None` when it is free. A state the collision world
/// cannot evaluate counts as colliding (with the reason as the pair), never as free.
fn collision(
    scene: &Scene,
    arms: &[(u32, &[f64])],
    object: u32,
    placement: ObjectPlacement,
    scratch: &mut SceneScratch,
) -> Option<(String, String)> {
    match scene.collision(arms, object, placement, scratch) {
        Ok(found) => found,
        Err(error) => Some(("collision query".to_string(), format!("{error:?}"))),
    }
}

fn run_check(
    artifact: &Artifact,
    scene: &Scene,
    scratch: &mut SceneScratch,
    options: &VerifyOptions,
    check: Check,
) -> Result<Witness, Infeasibility> {
    let mut rng = rng_for(options.seed, &check);
    let mut outcome = Outcome::new();
    match check {
        Check::Hold { object, e, g, w } => {
            let Some((robot, base, home)) = arm(scene, e) else {
                return Err(Infeasibility::NoPlacement {
                    detail: "the holder is not an arm".into(),
                });
            };
            let grasp = grasp_pose(artifact, object, g);
            // A robot with fewer than six joints (a conveyor) cannot take an arbitrary
            // pose: sample its joints instead and keep a placement inside the workspace.
            if robot.n_joints() < 6 {
                let mut q = home.to_vec();
                for _ in 0..options.placements * 4 {
                    robot.sample_configuration(&mut rng, &mut q);
                    let object_pose = robot.tip_pose(&base, &q) * grasp;
                    let center = Point::from(object_pose.translation.vector);
                    if !scene.workspaces[w as usize]
                        .iter()
                        .any(|b| b.contains(&center))
                    {
                        continue;
                    }
                    let placement = ObjectPlacement::Held { by: e, grasp };
                    match collision(scene, &[(e, &q)], object, placement, scratch) {
                        None => {
                            return Ok(Witness {
                                object: iso_to_schema(&object_pose),
                                configurations: vec![schema::ArmConfiguration {
                                    end_effector: e,
                                    joints: q,
                                }],
                            })
                        }
                        Some(pair) => outcome.last_collision = Some(pair),
                    }
                }
                return Err(outcome
                    .into_reason("the robot's joints never bring the object into the workspace"));
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
                let Some(center) = sample_point(&scene.workspaces[w as usize], &mut rng) else {
                    break;
                };
                // Objects are carried upright, turned about the vertical at random.
                let yaw = rng.random::<f64>() * std::f64::consts::TAU;
                let object_pose = Iso::from_parts(
                    center.coords.into(),
                    Quat::from_axis_angle(&Vec3::z_axis(), yaw),
                );
                let placement = ObjectPlacement::Held { by: e, grasp };
                if let Some(witness) = attempt.run(
                    object_pose,
                    placement,
                    &mut rng,
                    options,
                    scratch,
                    &mut outcome,
                ) {
                    return Ok(witness);
                }
            }
            Err(outcome.into_reason("the workspace has no volume"))
        }
        Check::Handoff {
            object,
            a,
            ga,
            b,
            gb,
            w,
        } => {
            let (Some((robot_a, base_a, home_a)), Some((robot_b, base_b, home_b))) =
                (arm(scene, a), arm(scene, b))
            else {
                return Err(Infeasibility::NoPlacement {
                    detail: "a holder is not an arm".into(),
                });
            };
            let boxes = &scene.workspaces[w as usize];
            outcome.partner = Some(b);
            // A symmetric object may be held by B in a grasp turned by a symmetry: a ball
            // passed between two hands with the same grasp is held from opposite sides.
            let all_turns =
                crate::symmetry::candidates(&artifact.objects[object as usize].symmetries);
            // With the same grasp on both sides, the unturned grasp puts both hands in one
            // place: only turns that send the second hand round to the other side (over
            // 120°) can work, so only those are tried.
            let turns: Vec<_> = if ga == gb {
                let far: Vec<_> = all_turns
                    .iter()
                    .copied()
                    .filter(|t| t.angle() > 2.0)
                    .collect();
                if far.is_empty() {
                    all_turns
                } else {
                    far
                }
            } else {
                all_turns
            };
            for attempt in 0..options.placements {
                let Some(target) = sample_point(boxes, &mut rng) else {
                    break;
                };
                let turn = if attempt == 0 {
                    turns[0]
                } else {
                    turns[rng.random_range(0..turns.len())]
                };
                let bounds = boxes
                    .iter()
                    .find(|bx| bx.contains(&target))
                    .map(|bx| (bx.min, bx.max));
                let problem = HandoffProblem {
                    a: (robot_a, base_a),
                    b: (robot_b, base_b),
                    grasp_a: grasp_pose(artifact, object, ga),
                    grasp_b: grasp_pose(artifact, object, gb) * turn,
                    target,
                    bounds,
                };
                match solve_handoff(&problem, home_a, home_b, &mut rng, &options.handoff) {
                    Ok(solution) => {
                        let center = Point::from(solution.object.translation.vector);
                        if !boxes.iter().any(|bx| bx.contains(&center)) {
                            continue;
                        }
                        let placement = ObjectPlacement::Handoff {
                            a,
                            grasp_a: problem.grasp_a,
                            b,
                        };
                        let arms = [(a, solution.qa.as_slice()), (b, solution.qb.as_slice())];
                        match collision(scene, &arms, object, placement, scratch) {
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
                            Some(pair) => outcome.last_collision = Some(pair),
                        }
                    }
                    Err(error) => outcome.best_ik.record(a, &error),
                }
            }
            Err(outcome.into_reason("the workspace has no volume"))
        }
        Check::Rest {
            object,
            arm: e,
            g,
            surface,
            r,
            w,
        } => {
            let Some((robot, base, home)) = arm(scene, e) else {
                return Err(Infeasibility::NoPlacement {
                    detail: "the holder is not an arm".into(),
                });
            };
            let Holder::Surface { slab, .. } = &scene.holders[surface as usize] else {
                return Err(Infeasibility::NoPlacement {
                    detail: "the support is not a surface".into(),
                });
            };
            let rest = grasp_pose(artifact, object, r);
            let grasp = grasp_pose(artifact, object, g);
            // The object rests on the top face, anywhere and turned any way about the
            // vertical, as long as its centre lies in the workspace.
            let top = slab.max.z;
            let center_z = top + rest.translation.vector.z;
            let regions: Vec<Aabb> = scene.workspaces[w as usize]
                .iter()
                .filter_map(|bx| {
                    let min = Point::new(bx.min.x.max(slab.min.x), bx.min.y.max(slab.min.y), top);
                    let max = Point::new(bx.max.x.min(slab.max.x), bx.max.y.min(slab.max.y), top);
                    let z_inside = bx.min.z <= center_z + 1e-6 && bx.max.z >= center_z - 1e-6;
                    (max.x > min.x && max.y > min.y && z_inside).then_some(Aabb { min, max })
                })
                .collect();
            if regions.is_empty() {
                let surface_name = &artifact.end_effectors[surface as usize].name;
                let rest_name = &artifact.objects[object as usize].grasps[r as usize].name;
                let ws = &artifact.workspaces[w as usize].name;
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
                let area: f64 = regions
                    .iter()
                    .map(|a| (a.max.x - a.min.x) * (a.max.y - a.min.y))
                    .sum();
                let mut pick = rng.random::<f64>() * area;
                let region = regions
                    .iter()
                    .find(|a| {
                        pick -= (a.max.x - a.min.x) * (a.max.y - a.min.y);
                        pick <= 0.0
                    })
                    .unwrap_or(&regions[regions.len() - 1]);
                let x = region.min.x + rng.random::<f64>() * (region.max.x - region.min.x);
                let y = region.min.y + rng.random::<f64>() * (region.max.y - region.min.y);
                let yaw = rng.random::<f64>() * std::f64::consts::TAU;
                let surface_frame = Iso::from_parts(
                    na::Translation3::new(x, y, top),
                    Quat::from_axis_angle(&Vec3::z_axis(), yaw),
                );
                let object_pose = surface_frame * rest;
                let placement = ObjectPlacement::Resting {
                    on: surface,
                    pose: object_pose,
                    by: Some(e),
                };
                if let Some(witness) = attempt.run(
                    object_pose,
                    placement,
                    &mut rng,
                    options,
                    scratch,
                    &mut outcome,
                ) {
                    return Ok(witness);
                }
            }
            Err(outcome.into_reason("no resting pose"))
        }
    }
}
