//! [`SceneValidity`], the default [`StateValidity`]: joint limits, then the scene's
//! collision query, through the frozen standing part of the scene once a checker has
//! answered enough queries to pay for the freeze.

use std::sync::atomic::{AtomicBool, AtomicU32, Ordering};
use std::sync::OnceLock;

use cellc_schema::{EndEffectorId, ObjectId};

use super::{
    arm_slices, out_of_limits, ArmSlice, LayoutError, Screened, StateFault, StateValidity,
};
use crate::collision::Collision;
use crate::scene::{
    FrozenScene, Holder, ObjectPlacement, Obstacle, Placed, QueryError, Scene, SceneScratch,
};
use crate::swept::{SweptBodies, LOOKAHEAD};

/// Arms listed in one query without allocating, up to this many (more fall back to a
/// vector).
const INLINE_ARMS: usize = 16;

/// The default [`StateValidity`]: the moving arms within their limits and the cell free
/// of collisions, with `stationary` arms at their joints, every other arm at home and the
/// object placed as given. Its [`free_radius`](StateValidity::free_radius) is the
/// collision world's distance to every pair that may not touch, against how far the
/// moving bodies can travel (`crate::swept`).
#[derive(Clone)]
pub struct SceneValidity<'a> {
    scene: &'a Scene,
    slices: Vec<ArmSlice>,
    dim: usize,
    stationary: &'a [(EndEffectorId, Vec<f64>)],
    object: ObjectId,
    placement: ObjectPlacement,
    /// The world's other objects, standing still (resting, or held by a stationary arm).
    obstacles: &'a [Obstacle],
    /// The moving bodies' reach radii, computed on the first clearance query (most
    /// checkers, in verification, only ever judge single states).
    swept: OnceLock<SweptBodies>,
    /// The standing part of the scene, frozen once this checker has answered
    /// [`FREEZE_AFTER`] queries (a motion asks thousands; an IK screen a handful, for
    /// which freezing would cost more than it saves). `None` inside when it could not
    /// be built: the plain queries then answer, and report why.
    frozen: OnceLock<Option<FrozenScene>>,
    queries: Counter,
    /// Whether a plain query found a state free of collisions: the standing bodies are
    /// the same in every state, so none of them intersect, which the freeze need not
    /// check again.
    seen_free: Flag,
}

/// A flag that clones as its current value.
#[derive(Default)]
struct Flag(AtomicBool);

impl Clone for Flag {
    fn clone(&self) -> Flag {
        Flag(AtomicBool::new(self.0.load(Ordering::Relaxed)))
    }
}

/// Queries a [`SceneValidity`] answers the plain way before it freezes the standing
/// part of the scene (the freeze costs about as much as two plain checks).
const FREEZE_AFTER: u32 = 4;

/// A query counter that clones as a fresh count.
#[derive(Default)]
struct Counter(AtomicU32);

impl Clone for Counter {
    fn clone(&self) -> Counter {
        Counter(AtomicU32::new(self.0.load(Ordering::Relaxed)))
    }
}

impl<'a> SceneValidity<'a> {
    /// States of `arms` (joints concatenated in that order) in `scene`, with `stationary`
    /// arms standing at their joints and `object` placed as `placement`.
    ///
    /// # Errors
    /// An end-effector that is not an arm or is listed twice, or a stationary arm whose
    /// joints have the wrong length or leave its limits.
    pub fn new(
        scene: &'a Scene,
        arms: &[EndEffectorId],
        stationary: &'a [(EndEffectorId, Vec<f64>)],
        object: ObjectId,
        placement: ObjectPlacement,
    ) -> Result<SceneValidity<'a>, LayoutError> {
        let slices = arm_slices(scene, arms)?;
        for (i, (e, q)) in stationary.iter().enumerate() {
            let end_effector = *e;
            let Some(Holder::Arm { robot, .. }) = scene.holders.get(end_effector.index()) else {
                return Err(LayoutError::NotAnArm { end_effector });
            };
            if arms.contains(e) || stationary[..i].iter().any(|(s, _)| s == e) {
                return Err(LayoutError::RepeatedArm { end_effector });
            }
            let robot = &scene.robots[*robot];
            if q.len() != robot.n_joints() {
                return Err(LayoutError::WrongLength {
                    end_effector,
                    expected: robot.n_joints(),
                    found: q.len(),
                });
            }
            let (lower, upper) = robot.limits();
            for (joint, ((&value, &lo), &hi)) in q.iter().zip(lower).zip(upper).enumerate() {
                if !(value.is_finite() && lo <= value && value <= hi) {
                    return Err(LayoutError::OutOfLimits {
                        end_effector,
                        joint,
                        value,
                    });
                }
            }
        }
        let dim = slices.iter().map(|s| s.len).sum();
        Ok(SceneValidity {
            scene,
            slices,
            dim,
            stationary,
            object,
            placement,
            obstacles: &[],
            swept: OnceLock::new(),
            frozen: OnceLock::new(),
            queries: Counter::default(),
            seen_free: Flag::default(),
        })
    }

    /// The same checks with the world's other objects in the scene. They stand still
    /// during a motion, so none may be held by one of the moving arms (the planner never
    /// moves a hand that holds another object); such an obstacle is left out of the
    /// swept bounds and would make clearance queries unsound.
    pub fn with_obstacles(mut self, obstacles: &'a [Obstacle]) -> SceneValidity<'a> {
        debug_assert!(obstacles.iter().all(|o| match o.placement {
            ObjectPlacement::Held { by, .. } => !self.slices.iter().any(|s| s.end_effector == by),
            _ => true,
        }));
        self.obstacles = obstacles;
        self.frozen = OnceLock::new();
        self.seen_free = Flag::default();
        self
    }

    /// The frozen standing part, once enough queries have been asked (built on the
    /// first query past [`FREEZE_AFTER`], with the moving arms at `q`, which does not
    /// matter: their entries are recomputed per query).
    fn frozen(&self, q: &[f64], scratch: &mut SceneScratch) -> Option<&FrozenScene> {
        if let Some(f) = self.frozen.get() {
            return f.as_ref();
        }
        if self.queries.0.fetch_add(1, Ordering::Relaxed) < FREEZE_AFTER {
            return None;
        }
        self.frozen
            .get_or_init(|| {
                let moving: Vec<EndEffectorId> =
                    self.slices.iter().map(|s| s.end_effector).collect();
                let at = Placed {
                    object: self.object,
                    placement: self.placement,
                    obstacles: self.obstacles,
                };
                let known_free = self.seen_free.0.load(Ordering::Relaxed);
                self.with_arms(q, |arms| {
                    Ok(self
                        .scene
                        .freeze(arms, &moving, at, known_free, scratch)
                        .ok())
                })
                .ok()
                .flatten()
            })
            .as_ref()
    }

    /// Calls `query` with only the moving arms' joints at `q` (what the frozen queries
    /// take: the stationary arms are frozen with the rest).
    fn with_moving<T>(
        &self,
        q: &[f64],
        query: impl FnOnce(&[(EndEffectorId, &[f64])]) -> Result<T, QueryError>,
    ) -> Result<T, QueryError> {
        self.list_arms(q, &[], query)
    }

    /// Joint values in one configuration.
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// The first joint of `q` (of the right length) outside its limits, as a fault.
    pub(crate) fn limits_fault(&self, q: &[f64]) -> Option<StateFault> {
        out_of_limits(self.scene, &self.slices, q).map(|(end_effector, joint, value)| {
            StateFault::OutOfLimits {
                end_effector,
                joint,
                value,
            }
        })
    }

    /// The first colliding pair at `q` as body ids (joint limits are not looked at), for
    /// reports that name what collides by id: which of the world's objects blocks a step.
    pub(crate) fn first_contact(
        &self,
        q: &[f64],
        scratch: &mut SceneScratch,
    ) -> Result<Option<Collision>, QueryError> {
        self.with_arms(q, |arms| {
            self.scene
                .first_collision(arms, self.object, self.placement, self.obstacles, scratch)
        })
    }

    /// Calls `query` with every arm's joints at `q` (moving arms from `q`, then the
    /// stationary ones).
    fn with_arms<T>(
        &self,
        q: &[f64],
        query: impl FnOnce(&[(EndEffectorId, &[f64])]) -> Result<T, QueryError>,
    ) -> Result<T, QueryError> {
        self.list_arms(q, self.stationary, query)
    }

    /// The moving arms at `q`, then `stationary`, listed without allocating for up to
    /// [`INLINE_ARMS`] arms.
    fn list_arms<T>(
        &self,
        q: &[f64],
        stationary: &[(EndEffectorId, Vec<f64>)],
        query: impl FnOnce(&[(EndEffectorId, &[f64])]) -> Result<T, QueryError>,
    ) -> Result<T, QueryError> {
        if q.len() != self.dim {
            return Err(QueryError::WrongLength {
                expected: self.dim,
                found: q.len(),
            });
        }
        let n = self.slices.len() + stationary.len();
        let mut inline: [(EndEffectorId, &[f64]); INLINE_ARMS] =
            [(EndEffectorId(0), &[]); INLINE_ARMS];
        let mut heap: Vec<(EndEffectorId, &[f64])>;
        let list: &mut [(EndEffectorId, &[f64])] = if n <= INLINE_ARMS {
            &mut inline[..n]
        } else {
            heap = vec![(EndEffectorId(0), &[][..]); n];
            &mut heap
        };
        for (slot, s) in list.iter_mut().zip(&self.slices) {
            *slot = (s.end_effector, &q[s.offset..s.offset + s.len]);
        }
        for (slot, (e, joints)) in list[self.slices.len()..].iter_mut().zip(stationary) {
            *slot = (*e, joints.as_slice());
        }
        query(list)
    }
}

impl StateValidity for SceneValidity<'_> {
    type Scratch = SceneScratch;

    fn check(
        &self,
        q: &[f64],
        scratch: &mut SceneScratch,
    ) -> Result<Option<StateFault>, QueryError> {
        self.with_arms(q, |arms| {
            if let Some(fault) = self.limits_fault(q) {
                return Ok(Some(fault));
            }
            let pair =
                self.scene
                    .collision(arms, self.object, self.placement, self.obstacles, scratch)?;
            if pair.is_none() {
                self.seen_free.0.store(true, Ordering::Relaxed);
            }
            Ok(pair.map(|(a, b)| StateFault::Collision { a, b }))
        })
    }

    fn is_valid(&self, q: &[f64], scratch: &mut SceneScratch) -> Result<bool, QueryError> {
        if q.len() == self.dim {
            if let Some(frozen) = self.frozen(q, scratch) {
                if out_of_limits(self.scene, &self.slices, q).is_some() {
                    return Ok(false);
                }
                return self
                    .with_moving(q, |arms| self.scene.is_free_frozen(frozen, arms, scratch));
            }
        }
        self.with_arms(q, |arms| {
            if out_of_limits(self.scene, &self.slices, q).is_some() {
                return Ok(false);
            }
            let free =
                self.scene
                    .is_free(arms, self.object, self.placement, self.obstacles, scratch)?;
            if free {
                self.seen_free.0.store(true, Ordering::Relaxed);
            }
            Ok(free)
        })
    }

    /// The batched screen of the motion's frozen scene (`collision/batch.rs`):
    /// forward kinematics of every configuration first, then each live body's capsule
    /// against the standing bodies near it and the live bodies' own pairs, the exact
    /// test only for the pairs the capsules do not settle. Nothing is judged before the
    /// checker has frozen (its first few queries); a configuration outside the joint
    /// limits is invalid.
    fn screen(&self, qs: &[f64], out: &mut [Screened], scratch: &mut SceneScratch) {
        out.fill(Screened::Unknown);
        let dim = self.dim;
        if dim == 0 || out.is_empty() || qs.len() != out.len() * dim {
            return;
        }
        let Some(frozen) = self.frozen(&qs[..dim], scratch) else {
            return;
        };
        if self.scene.screen_begin(frozen, scratch).is_err() {
            return;
        }
        for q in qs.chunks_exact(dim) {
            let placed = self.with_moving(q, |arms| self.scene.screen_place(frozen, arms, scratch));
            if placed.is_err() {
                return;
            }
        }
        let mut verdicts = std::mem::take(&mut scratch.verdicts);
        verdicts.clear();
        verdicts.resize(out.len(), None);
        self.scene.screen_clear(frozen, scratch, &mut verdicts);
        for ((q, verdict), slot) in qs.chunks_exact(dim).zip(&verdicts).zip(out.iter_mut()) {
            *slot = if out_of_limits(self.scene, &self.slices, q).is_some() {
                Screened::Invalid
            } else {
                match verdict {
                    Some(true) => Screened::Valid,
                    Some(false) => Screened::Invalid,
                    None => Screened::Unknown,
                }
            };
        }
        scratch.verdicts = verdicts;
    }

    fn free_radius(
        &self,
        q: &[f64],
        delta: &[f64],
        horizon: f64,
        scratch: &mut SceneScratch,
    ) -> Result<Option<f64>, QueryError> {
        if delta.len() != self.dim {
            return Err(QueryError::WrongLength {
                expected: self.dim,
                found: delta.len(),
            });
        }
        let swept = self.swept.get_or_init(|| {
            SweptBodies::new(self.scene, &self.slices, self.object, &self.placement)
        });
        // The bounds live in the scratch so that no query allocates; taken out while the
        // scratch's other buffers serve the query.
        let mut bounds = std::mem::take(&mut scratch.sweep);
        let result = match swept.fill(delta, &mut bounds, self.scene.world.body_count()) {
            None => Ok(None),
            Some(fastest) => {
                let horizon = if fastest > 0.0 {
                    horizon.min(LOOKAHEAD / fastest)
                } else {
                    horizon
                };
                let frozen = if q.len() == self.dim {
                    self.frozen(q, scratch)
                } else {
                    None
                };
                match frozen {
                    Some(frozen) => self.with_moving(q, |arms| {
                        self.scene
                            .free_radius_frozen(frozen, arms, &bounds, horizon, scratch)
                    }),
                    None => self.with_arms(q, |arms| {
                        let at = Placed {
                            object: self.object,
                            placement: self.placement,
                            obstacles: self.obstacles,
                        };
                        self.scene.free_radius(arms, at, &bounds, horizon, scratch)
                    }),
                }
                .map(Some)
            }
        };
        scratch.sweep = bounds;
        result
    }

    /// The swept-distance bound sees each joint only through `|delta_j| R_j`, and any
    /// configuration within `|q'_j - q_j| <= t |delta_j|` of `q` moves every point by at
    /// most `t sum_j |delta_j| R_j` (moving the joints one at a time), so a certificate
    /// proves the whole box.
    fn certifies_boxes(&self) -> bool {
        true
    }
}
