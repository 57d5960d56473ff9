//! The independent re-check of a timed trajectory: lengths, limits, times, and every
//! segment at a resolution, through the default state validity.

use std::fmt;

use super::problem::query_text;
use super::segment::{sample, steps};
use super::MotionOptions;
use cellc_schema::{EndEffectorId, ObjectId};

use crate::plan::{MotionContext, Trajectory};
use crate::scene::{QueryError, Scene, SceneScratch};
use crate::validity::{LayoutError, SceneValidity, StateFault, StateValidity};

/// What is wrong with a trajectory, found by [`check_trajectory`].
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum TrajectoryFault {
    /// Two bodies intersect at `time` (interpolated between samples).
    Collision {
        /// Seconds from the start.
        time: f64,
        /// One body.
        a: String,
        /// The other.
        b: String,
    },
    /// A joint leaves its limits.
    OutOfLimits {
        /// Seconds from the start.
        time: f64,
        /// The arm.
        end_effector: EndEffectorId,
        /// Joint index in the arm's chain.
        joint: usize,
        /// The value.
        value: f64,
    },
    /// A point has the wrong number of joint values.
    WrongLength {
        /// Point index.
        point: usize,
        /// Values expected.
        expected: usize,
        /// Values given.
        found: usize,
    },
    /// Times are not finite and non-decreasing.
    Time {
        /// Point index.
        point: usize,
    },
    /// An arm of the trajectory (or a stationary one) is not an arm of the scene, or is
    /// listed twice.
    BadArm {
        /// End-effector.
        end_effector: EndEffectorId,
    },
    /// The scene could not answer a collision query.
    Query {
        /// Seconds from the start.
        time: f64,
        /// Why.
        error: QueryError,
    },
}

impl fmt::Display for TrajectoryFault {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            TrajectoryFault::Collision { time, a, b } => {
                write!(f, "at {time:.3} s, `{a}` and `{b}` collide")
            }
            TrajectoryFault::OutOfLimits {
                time,
                end_effector,
                joint,
                value,
            } => write!(
                f,
                "at {time:.3} s, joint {joint} of arm {end_effector} is {value}, outside its limits"
            ),
            TrajectoryFault::WrongLength {
                point,
                expected,
                found,
            } => write!(
                f,
                "point {point} has {found} joint values, {expected} expected"
            ),
            TrajectoryFault::Time { point } => {
                write!(
                    f,
                    "the time of point {point} is not finite or goes backwards"
                )
            }
            TrajectoryFault::BadArm { end_effector } => {
                write!(
                    f,
                    "end-effector {end_effector} is not an arm or is listed twice"
                )
            }
            TrajectoryFault::Query { time, error } => {
                write!(f, "at {time:.3} s, {}", query_text(error))
            }
        }
    }
}

impl std::error::Error for TrajectoryFault {}

/// Re-checks `trajectory` independently of how it was planned: every point has the right
/// length and is within limits, times are finite and non-decreasing, and every segment
/// between consecutive points is collision-free at `resolution` (per joint), with
/// `stationary` arms at their joints, every other arm at home and the object placed as
/// `placement` (a held object following its hand). Used by tests and the simulator.
///
/// The states are judged by [`SceneValidity`], the default state validity, and only
/// sampled: this is the oracle the planner's sound edge checks
/// ([`super::CertifiedMotion`]) answer to, so it shares nothing with them but the state
/// validity. A trajectory they accepted passes at every `resolution`; one planned with
/// the sampled [`super::DiscreteMotion`] passes at the resolution it was planned with,
/// whose cuts these are. A `resolution` that is not positive and finite means the default
/// one.
///
/// # Errors
/// The first fault along the trajectory, with its time.
pub fn check_trajectory(
    scene: &Scene,
    trajectory: &Trajectory,
    object: ObjectId,
    context: &MotionContext,
    resolution: f64,
    scratch: &mut SceneScratch,
) -> Result<(), TrajectoryFault> {
    let validity = SceneValidity::new(
        scene,
        &trajectory.arms,
        &context.stationary,
        object,
        context.placement,
    )
    .map(|v| v.with_obstacles(&context.obstacles))
    .map_err(|e| match e {
        LayoutError::OutOfLimits {
            end_effector,
            joint,
            value,
        } => TrajectoryFault::OutOfLimits {
            time: trajectory.points.first().map_or(0.0, |p| p.time),
            end_effector,
            joint,
            value,
        },
        LayoutError::NotAnArm { end_effector }
        | LayoutError::RepeatedArm { end_effector }
        | LayoutError::WrongLength { end_effector, .. } => TrajectoryFault::BadArm { end_effector },
    })?;
    let dim = validity.dim();
    let resolution = if resolution.is_finite() && resolution > 0.0 {
        resolution
    } else {
        MotionOptions::default().collision_resolution
    };
    let mut q = Vec::with_capacity(dim);
    let mut previous: Option<(f64, &[f64])> = None;
    for (i, p) in trajectory.points.iter().enumerate() {
        let (t, point) = (&p.time, &p.positions[..]);
        for found in [point.len(), p.velocities.len(), p.accelerations.len()] {
            if found != dim {
                return Err(TrajectoryFault::WrongLength {
                    point: i,
                    expected: dim,
                    found,
                });
            }
        }
        if !t.is_finite() || previous.is_some_and(|(t0, _)| *t < t0) {
            return Err(TrajectoryFault::Time { point: i });
        }
        let check =
            |q: &[f64], time: f64, scratch: &mut SceneScratch| match validity.check(q, scratch) {
                Ok(None) => Ok(()),
                Ok(Some(StateFault::Collision { a, b })) => {
                    Err(TrajectoryFault::Collision { time, a, b })
                }
                Ok(Some(StateFault::OutOfLimits {
                    end_effector,
                    joint,
                    value,
                })) => Err(TrajectoryFault::OutOfLimits {
                    time,
                    end_effector,
                    joint,
                    value,
                }),
                Err(error) => Err(TrajectoryFault::Query { time, error }),
            };
        if let Some(StateFault::OutOfLimits {
            end_effector,
            joint,
            value,
        }) = validity.limits_fault(point)
        {
            return Err(TrajectoryFault::OutOfLimits {
                time: *t,
                end_effector,
                joint,
                value,
            });
        }
        match previous {
            None => check(point, *t, scratch)?,
            Some((t0, p0)) => {
                let n = steps(p0, point, resolution);
                for k in 1..=n {
                    sample(p0, point, k, n, &mut q);
                    check(&q, t0 + (t - t0) * k as f64 / n as f64, scratch)?;
                }
            }
        }
        previous = Some((*t, point));
    }
    Ok(())
}
