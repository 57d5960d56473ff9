//! State validity: whether one configuration of the arms that move, with the rest of the
//! cell as it stands, is a state a plan may pass through (OMPL's
//! `StateValidityChecker`).
//!
//! [`StateValidity`] is the seam: RRT-Connect, its shortcutting, the re-check of a
//! trajectory and the verification of arcs ask it about configurations and never look
//! at the collision world themselves, so another checker (a safety margin, a cache, a
//! world with perceived obstacles, a test double) plugs in without editing them.
//! [`SceneValidity`] is the default: joint limits, then [`Scene::collision`] with the
//! stationary arms where they stand, every other arm at home and the object placed as
//! given (a held object following its hand).

use std::fmt;

use cellc_schema::EndEffectorId;

use crate::scene::{Holder, QueryError, Scene};

mod scene;

pub use scene::SceneValidity;

/// Decides whether configurations of a fixed set of moving arms (their joints
/// concatenated, as in a [`crate::motion::MotionProblem`]) are valid.
///
/// Implementations must be deterministic (the same answer for the same configuration),
/// since plans are reproducible from a seed, and must not call a state they cannot
/// evaluate valid: that is an error, not a free state.
pub trait StateValidity {
    /// The per-thread buffers a query reuses, owned by the caller (a motion planner keeps
    /// one for all its queries, so no query allocates):
    /// [`SceneScratch`](crate::scene::SceneScratch) for [`SceneValidity`] and checkers that
    /// wrap it, `()` for one that needs none.
    type Scratch;

    /// What is wrong with `q`, or `None` when it is valid.
    fn check(
        &self,
        q: &[f64],
        scratch: &mut Self::Scratch,
    ) -> Result<Option<StateFault>, QueryError>;

    /// Whether `q` is valid. The default asks [`StateValidity::check`]; implementations
    /// may answer without building the fault (no names, no allocation).
    fn is_valid(&self, q: &[f64], scratch: &mut Self::Scratch) -> Result<bool, QueryError> {
        Ok(self.check(q, scratch)?.is_none())
    }

    /// A screen of several configurations at once (`qs`, concatenated, one verdict
    /// per configuration in `out`): [`Screened::Valid`] or [`Screened::Invalid`] only
    /// where [`StateValidity::is_valid`] is certain to give that answer, so that a
    /// sampled motion check ([`DiscreteMotion`](crate::motion::DiscreteMotion)) asks
    /// the full check only about the others and its answers do not change. The default
    /// knows nothing.
    fn screen(&self, qs: &[f64], out: &mut [Screened], scratch: &mut Self::Scratch) {
        let _ = (qs, scratch);
        out.fill(Screened::Unknown);
    }

    /// A clearance certificate for sound motion checks
    /// ([`CertifiedMotion`](crate::motion::CertifiedMotion)): a radius `t` in
    /// `[0, horizon]` such that every configuration `q + s delta` with `|s| <= t` that is
    /// within the joint limits is valid, where `delta` is the joint change of the
    /// segment being checked (`b - a`). `Some(0.0)` when `q` is not valid or too close
    /// to an invalid state to prove anything; `None`, the default, when this checker
    /// measures no clearance (motion checks then sample at a resolution).
    ///
    /// Only what the changing joints move needs measuring: the rest is as it was at the
    /// segment's start, which a motion check knows to be valid.
    fn free_radius(
        &self,
        q: &[f64],
        delta: &[f64],
        horizon: f64,
        scratch: &mut Self::Scratch,
    ) -> Result<Option<f64>, QueryError> {
        let _ = (q, delta, horizon, scratch);
        Ok(None)
    }

    /// Whether a certificate of [`StateValidity::free_radius`] proves the whole box
    /// `|q'_j - q_j| <= t |delta_j|` free, not only the segment through `q`: true for a
    /// bound that depends on the joints' changes only through `|delta_j|`, as the scene's
    /// swept-distance bound does. Smoothing (`motion/blend.rs`) certifies its arcs with
    /// boxes, so a checker that says false gets no blends (its corners are passed at
    /// rest). The default says false.
    fn certifies_boxes(&self) -> bool {
        false
    }
}

/// Whether every configuration of `qs` (concatenated, `out.len()` of them) is valid,
/// asked in order: [`StateValidity::screen`] first, then [`StateValidity::is_valid`] for
/// each it left unknown, until one is invalid. The answer is the one-by-one answer; `out`
/// is the screen's buffer.
pub(crate) fn all_valid<S>(
    validity: &dyn StateValidity<Scratch = S>,
    qs: &[f64],
    out: &mut [Screened],
    scratch: &mut S,
) -> Result<bool, QueryError> {
    validity.screen(qs, out, scratch);
    let dim = qs.len() / out.len().max(1);
    for (q, &verdict) in qs.chunks_exact(dim.max(1)).zip(out.iter()) {
        let valid = match verdict {
            Screened::Valid => true,
            Screened::Invalid => false,
            Screened::Unknown => validity.is_valid(q, scratch)?,
        };
        if !valid {
            return Ok(false);
        }
    }
    Ok(true)
}

/// What [`StateValidity::screen`] proves of one configuration.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Screened {
    /// [`StateValidity::is_valid`] would say valid.
    Valid,
    /// [`StateValidity::is_valid`] would say invalid.
    Invalid,
    /// Not judged: ask [`StateValidity::is_valid`].
    Unknown,
}

/// Why a configuration is not valid.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum StateFault {
    /// Two bodies intersect.
    Collision {
        /// One body.
        a: String,
        /// The other.
        b: String,
    },
    /// A joint is outside its limits or not finite.
    OutOfLimits {
        /// The arm.
        end_effector: EndEffectorId,
        /// Joint index in the arm's chain.
        joint: usize,
        /// The value.
        value: f64,
    },
}

impl fmt::Display for StateFault {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            StateFault::Collision { a, b } => write!(f, "`{a}` and `{b}` collide"),
            StateFault::OutOfLimits {
                end_effector,
                joint,
                value,
            } => write!(
                f,
                "joint {joint} of arm {end_effector} is {value}, outside its limits"
            ),
        }
    }
}

/// Why a set of arms and stationary arms cannot be checked.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum LayoutError {
    /// The end-effector is not an arm of the scene.
    NotAnArm {
        /// End-effector.
        end_effector: EndEffectorId,
    },
    /// The end-effector is listed twice (among the moving arms, the stationary ones, or
    /// in both).
    RepeatedArm {
        /// End-effector.
        end_effector: EndEffectorId,
    },
    /// A stationary arm's joints have the wrong length.
    WrongLength {
        /// The arm.
        end_effector: EndEffectorId,
        /// Values expected.
        expected: usize,
        /// Values given.
        found: usize,
    },
    /// A stationary arm's joint is outside its limits or not finite.
    OutOfLimits {
        /// The arm.
        end_effector: EndEffectorId,
        /// Joint index in the arm's chain.
        joint: usize,
        /// The value.
        value: f64,
    },
}

/// A moving arm's slice of the combined configuration.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ArmSlice {
    pub(crate) end_effector: EndEffectorId,
    pub(crate) robot: usize,
    pub(crate) offset: usize,
    pub(crate) len: usize,
}

/// The slices of `arms` in the combined configuration, in order.
pub(crate) fn arm_slices(
    scene: &Scene,
    arms: &[EndEffectorId],
) -> Result<Vec<ArmSlice>, LayoutError> {
    let mut slices = Vec::with_capacity(arms.len());
    let mut offset = 0;
    for (i, &end_effector) in arms.iter().enumerate() {
        let Some(Holder::Arm { robot, .. }) = scene.holders.get(end_effector.index()) else {
            return Err(LayoutError::NotAnArm { end_effector });
        };
        if arms[..i].contains(&end_effector) {
            return Err(LayoutError::RepeatedArm { end_effector });
        }
        let len = scene.robots[*robot].n_joints();
        slices.push(ArmSlice {
            end_effector,
            robot: *robot,
            offset,
            len,
        });
        offset += len;
    }
    Ok(slices)
}

/// The first joint of `q` outside its arm's limits (or not finite): (arm, joint, value).
pub(crate) fn out_of_limits(
    scene: &Scene,
    slices: &[ArmSlice],
    q: &[f64],
) -> Option<(EndEffectorId, usize, f64)> {
    for s in slices {
        let (lower, upper) = scene.robots[s.robot].limits();
        let values = &q[s.offset..s.offset + s.len];
        for (j, ((&v, &lo), &hi)) in values.iter().zip(lower).zip(upper).enumerate() {
            if !(v.is_finite() && lo <= v && v <= hi) {
                return Some((s.end_effector, j, v));
            }
        }
    }
    None
}
