//! One arm reaching one object pose (the IK solve, the state check, the witness), and
//! what the failed attempts of a check report.

use cellc_schema::{self as schema, EndEffectorId, Infeasibility, ObjectId, Witness};
use nalgebra as na;
use rand::Rng;
use rand_chacha::ChaCha8Rng;

use super::VerifyOptions;
use crate::collision::{BodyId, Collision};
use crate::kinematics::{solve_ik, IkError, IkTarget};
use crate::math::Aabb;
use crate::math::{iso_to_schema, Iso, Point};
use crate::robot::Robot;
use crate::scene::{Holder, ObjectPlacement, Scene, SceneScratch};
use crate::termination::Termination;
use crate::validity::{SceneValidity, StateValidity};

/// A point drawn uniformly from a union of boxes (volume-weighted).
pub(super) fn sample_point(boxes: &[Aabb], rng: &mut ChaCha8Rng) -> Option<Point> {
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
        chosen.mins[i] + rng.random::<f64>() * (chosen.maxs[i] - chosen.mins[i])
    })))
}

/// Keeps the smallest IK errors seen, for the reason of a failed check.
#[derive(Default)]
pub(super) struct BestIk {
    end_effector: EndEffectorId,
    tries: u32,
    position_error: f64,
    rotation_error: f64,
    seen: bool,
}

impl BestIk {
    pub(super) fn record(&mut self, end_effector: EndEffectorId, error: &IkError) {
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

/// What the failed attempts of a check saw, for its reason.
pub(super) struct Outcome {
    pub(super) best_ik: BestIk,
    /// For a handoff, the other arm: the failure is the closed chain's, not one arm's.
    pub(super) partner: Option<EndEffectorId>,
    pub(super) last_collision: Option<Fault>,
}

/// A failed state check as it was found. The pair a pruned arc names is worked out only
/// for the last one, when the check's reason is asked for: naming it means asking the
/// plain broad phase, which places every body of the cell (a free state is proved so
/// by a query that places only what is away from home, `collision::home`), and can mean
/// listing every collision of the state ([`blamed`]); a check that fails all its
/// placements (a nest handoff of the assembly line closes its chain 16 times) used to
/// pay that for each of them, though only the last is reported.
pub(super) enum Fault {
    /// Named already: a hand in a fixed body, a query that failed, a joint limit.
    Named(String, String),
    /// A collision in the state of `arms` at `q`, not named yet.
    Collision {
        arms: Vec<EndEffectorId>,
        q: Vec<f64>,
        placement: ObjectPlacement,
    },
}

impl Outcome {
    pub(super) fn new() -> Outcome {
        Outcome {
            best_ik: BestIk::default(),
            partner: None,
            last_collision: None,
        }
    }

    /// The reason of the failed check: the last collision seen, else the best IK (or
    /// closed-chain) error, else `no_placement`.
    pub(super) fn reason(
        &self,
        (scene, object, scratch): (&Scene, ObjectId, &mut SceneScratch),
        no_placement: &str,
    ) -> Infeasibility {
        if let Some(fault) = &self.last_collision {
            let (a, b) = match fault {
                Fault::Named(a, b) => (a.clone(), b.clone()),
                Fault::Collision { arms, q, placement } => {
                    blamed(scene, (arms, q), object, *placement, scratch)
                }
            };
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

/// The robot, base and home of an arm.
pub(super) fn arm(scene: &Scene, e: EndEffectorId) -> Option<(&Robot, Iso, &[f64])> {
    match &scene.holders[e.index()] {
        Holder::Arm { robot, base, home } => Some((&scene.robots[*robot], *base, home.as_slice())),
        _ => None,
    }
}

/// One arm holding the object with `grasp` at a given object pose: the IK solve, the
/// collision check and the witness, shared by holds and rests.
pub(super) struct Attempt<'s> {
    pub(super) scene: &'s Scene,
    pub(super) object: ObjectId,
    pub(super) e: EndEffectorId,
    pub(super) robot: &'s Robot,
    pub(super) base: Iso,
    pub(super) home: &'s [f64],
    pub(super) grasp: Iso,
}

impl Attempt<'_> {
    /// A witness when the arm reaches the pose free of collisions; otherwise records why
    /// not in `outcome`.
    pub(super) fn run(
        &self,
        object_pose: Iso,
        placement: ObjectPlacement,
        rng: &mut ChaCha8Rng,
        options: &VerifyOptions,
        scratch: &mut SceneScratch,
        outcome: &mut Outcome,
    ) -> Option<Witness> {
        let tip = object_pose * self.grasp.inverse();
        // Where the hand must be is known before any IK: a hand in the table is refused
        // at once, whatever the joints would be.
        if let Some(c) = self.scene.tip_hits_fixed(self.e, &tip) {
            let (a, b) = self.scene.world.names(&c);
            outcome.last_collision = Some(Fault::Named(a.to_string(), b.to_string()));
            return None;
        }
        match solve_ik(
            self.robot,
            &self.base,
            &IkTarget::Pose(tip),
            self.home,
            rng,
            &options.ik,
            &Termination::never(),
        ) {
            Ok(q) => match invalidity(self.scene, &[self.e], &q, self.object, placement, scratch) {
                None => Some(Witness {
                    object: iso_to_schema(&object_pose),
                    configurations: vec![schema::ArmConfiguration {
                        end_effector: self.e,
                        joints: q,
                    }],
                }),
                Some(fault) => {
                    outcome.last_collision = Some(fault);
                    None
                }
            },
            Err(error) => {
                outcome.best_ik.record(self.e, &error);
                None
            }
        }
    }
}

/// Why a state is not valid, or `None` when it is. A state the scene cannot evaluate
/// counts as colliding (with the reason as the pair), never as free; so would a joint
/// outside its limits, which the solvers never return.
pub(super) fn invalidity(
    scene: &Scene,
    arms: &[EndEffectorId],
    q: &[f64],
    object: ObjectId,
    placement: ObjectPlacement,
    scratch: &mut SceneScratch,
) -> Option<Fault> {
    let validity = match SceneValidity::new(scene, arms, &[], object, placement) {
        Ok(validity) => validity,
        Err(error) => return Some(Fault::Named("state".to_string(), format!("{error:?}"))),
    };
    if let Some(fault) = validity.limits_fault(q) {
        return Some(Fault::Named("joint limits".to_string(), fault.to_string()));
    }
    match validity.is_valid(q, scratch) {
        Ok(true) => None,
        Ok(false) => Some(Fault::Collision {
            arms: arms.to_vec(),
            q: q.to_vec(),
            placement,
        }),
        Err(error) => Some(Fault::Named(
            "collision query".to_string(),
            format!("{error:?}"),
        )),
    }
}

/// The colliding pair a failed check reports: the first, in body order, of the state's
/// collisions that involve an arm of the check or its object (so a reason names the
/// bodies of the arc in question, never an arm standing by touching a fixed body), found
/// without placing the bodies that stand at home (`Scene::live_collisions`), so naming
/// costs the same in a cell of fifty arms as of two. When nothing of the check collides,
/// the first pair the plain broad phase finds stays: a standing arm's own collision,
/// which `cellc build` refuses before verifying (E0420), so a built artifact never
/// blames it.
fn blamed(
    scene: &Scene,
    (arms, q): (&[EndEffectorId], &[f64]),
    object: ObjectId,
    placement: ObjectPlacement,
    scratch: &mut SceneScratch,
) -> (String, String) {
    let involves = |body: BodyId| {
        body == BodyId::Object(object.index())
            || scene.arm_of(body).is_some_and(|e| arms.contains(&e))
    };
    let moving: Option<Vec<(EndEffectorId, &[f64])>> =
        crate::validity::arm_slices(scene, arms).ok().map(|slices| {
            slices
                .iter()
                .map(|s| {
                    (
                        s.end_effector,
                        q.get(s.offset..s.offset + s.len).unwrap_or(&[]),
                    )
                })
                .collect()
        });
    let Some(moving) = moving else {
        return ("state".to_string(), "not a layout of arms".to_string());
    };
    let names = |c: &Collision| {
        let (a, b) = scene.world.names(c);
        (a.to_string(), b.to_string())
    };
    let mut live = Vec::new();
    match scene.live_collisions(&moving, object, placement, scratch, &mut live) {
        Ok(()) => {
            if let Some(c) = live.iter().find(|c| involves(c.a) || involves(c.b)) {
                return names(c);
            }
        }
        Err(error) => return ("collision query".to_string(), format!("{error:?}")),
    }
    match scene.collision(&moving, object, placement, &[], scratch) {
        Ok(Some(found)) => found,
        Ok(None) => (
            "collision query".to_string(),
            "the state is free when asked again".to_string(),
        ),
        Err(error) => ("collision query".to_string(), format!("{error:?}")),
    }
}
