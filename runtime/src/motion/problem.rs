//! What a motion planner is told and what it answers: settings, and the errors of a
//! problem that cannot be planned.

use std::fmt;

use cellc_schema::EndEffectorId;

use crate::scene::QueryError;
use crate::validity::LayoutError;

/// Planner settings.
#[derive(Clone, Debug, PartialEq)]
pub struct MotionOptions {
    /// RRT-Connect iterations (one sample each) before giving up, over all the rounds of
    /// the lazy search (`tree.rs`). An iteration checks nodes only, about a third of what
    /// one that checked its edges cost, so the default is twice the 5,000 it was when
    /// edges were checked as the trees grew: in the cage of `cells/panda_cage.cell` the
    /// carry round the cage then plans for 31 of 32 seeds, where 5,000 eager iterations
    /// planned 14, in half the time (`docs/performance.md`).
    pub max_iterations: usize,
    /// Largest joint change of one tree extension, and between two output points (rad, or
    /// m for prismatic joints).
    pub step: f64,
    /// Largest joint change between two configurations checked along an edge by the
    /// sampled check (rad, or m): the fallback for state validities that measure no
    /// clearance, and the default resolution of the re-check
    /// ([`check_trajectory`](super::check_trajectory)). Edges of the default validity are
    /// certified, not sampled.
    pub collision_resolution: f64,
    /// Random shortcut attempts after a path is found.
    pub shortcut_iterations: usize,
    /// Probability that a sample is the other tree's root.
    pub goal_bias: f64,
    /// Largest distance (rad, or m, Euclidean in the arms' joint space) a blend through a
    /// corner of the path may pass from the corner (`blend.rs`); 0 passes every corner at
    /// rest.
    pub blend_deviation: f64,
    /// Largest arc length (in joint space) between two grid points of the time
    /// parameterisation, and so between two points of the trajectory.
    pub grid_step: f64,
}

/// How a request wants its motions timed: scaling factors on every joint's limits (as
/// MoveIt's `max_velocity_scaling_factor` and `max_acceleration_scaling_factor`) and,
/// optionally, points at a control rate instead of the parameterisation's knots.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TimingOptions {
    /// Share of each joint's speed limit used, in (0, 1].
    pub velocity_scaling: f64,
    /// Share of each joint's acceleration (and jerk) limit used, in (0, 1].
    pub acceleration_scaling: f64,
    /// Points every `1 / rate` seconds (Hz, at most [`TimingOptions::MAX_RATE`]), the last
    /// one at the end, instead of at the knots.
    pub rate: Option<f64>,
}

impl TimingOptions {
    /// The fastest control rate a trajectory is resampled at (Hz): a kilohertz, libfranka's.
    pub const MAX_RATE: f64 = 1000.0;
    /// The most points one resampled motion may have (a minute at the fastest rate), so
    /// that a tiny scaling factor cannot ask for unbounded memory.
    pub const MAX_POINTS: usize = 60_000;
}

impl Default for TimingOptions {
    fn default() -> TimingOptions {
        TimingOptions {
            velocity_scaling: 1.0,
            acceleration_scaling: 1.0,
            rate: None,
        }
    }
}

impl Default for MotionOptions {
    fn default() -> MotionOptions {
        MotionOptions {
            max_iterations: 10000,
            // A quarter radian per extension: a handful of checks per edge, trees of tens
            // of nodes around a table-sized obstacle.
            step: 0.25,
            // On the LWR (about 1.2 m long), 0.03 rad moves the hand by 1 to 4 cm when one
            // or two joints dominate a motion, less than the links' and slabs' thickness.
            // Measured on 2000 random motions around an obstacle: one showed a grazing
            // contact when re-checked at 0.005 rad; 0.05 gave 13.
            collision_resolution: 0.03,
            shortcut_iterations: 40,
            goal_bias: 0.05,
            // MoveIt's default path tolerance for its time-optimal parameterisation.
            blend_deviation: 0.1,
            // A few dozen knots per metre-sized motion: the time parameterisation is then
            // within a percent of the optimum on the same path (`topp/tests.rs`).
            grid_step: 0.02,
        }
    }
}

/// Which joint values of a problem or trajectory are meant.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Joints {
    /// The start configuration.
    Start,
    /// The goal configuration.
    Goal,
    /// A stationary arm's configuration.
    Stationary,
}

/// Why a motion could not be planned.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum MotionError {
    /// The start configuration collides.
    StartInCollision {
        /// One body.
        a: String,
        /// The other.
        b: String,
    },
    /// The goal configuration collides.
    GoalInCollision {
        /// One body.
        a: String,
        /// The other.
        b: String,
    },
    /// RRT-Connect found no path within its iterations.
    NoPath {
        /// Iterations run.
        iterations: usize,
    },
    /// The termination condition (a deadline, a cancel flag) stopped the search: nothing
    /// is known about whether a path exists.
    Terminated {
        /// RRT-Connect iterations run (0 when the search had not started, or was stopped
        /// while shortcutting a path it had found).
        iterations: usize,
    },
    /// The scene could not answer a collision query (a placement naming no arm or
    /// surface, a non-finite state).
    Query(QueryError),
    /// An end-effector in `arms` or `stationary` is not an arm of the scene.
    NotAnArm {
        /// End-effector.
        end_effector: EndEffectorId,
    },
    /// An end-effector appears twice among `arms` and `stationary`.
    RepeatedArm {
        /// End-effector.
        end_effector: EndEffectorId,
    },
    /// A configuration has the wrong number of values.
    WrongLength {
        /// Which configuration.
        joints: Joints,
        /// Values expected.
        expected: usize,
        /// Values given.
        found: usize,
    },
    /// A joint value is outside its limits or not finite.
    OutOfLimits {
        /// Which configuration.
        joints: Joints,
        /// The arm.
        end_effector: EndEffectorId,
        /// Joint index in the arm's chain.
        joint: usize,
        /// The value.
        value: f64,
    },
    /// An option is not a positive finite number (or the goal bias not in [0, 1], a
    /// scaling not in (0, 1], a rate above [`TimingOptions::MAX_RATE`], or a rate that
    /// would give a motion more than [`TimingOptions::MAX_POINTS`] points).
    InvalidOption {
        /// Field of [`MotionOptions`] or [`TimingOptions`].
        name: &'static str,
        /// Its value.
        value: f64,
    },
    /// The certified path could not be timed within the joints' limits (at grid point
    /// `index` of a section): only a degenerate path gets here.
    Untimed {
        /// The grid point.
        index: usize,
    },
    /// A path given to time (`motion::smooth_waypoints`, `motion::rest_to_rest`) or its
    /// limits do not fit together: waypoints of different lengths, a value that is not
    /// finite, limits not one positive number per joint.
    MalformedPath(&'static str),
}

impl fmt::Display for MotionError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            MotionError::StartInCollision { a, b } => {
                write!(f, "the start configuration collides: `{a}` and `{b}`")
            }
            MotionError::GoalInCollision { a, b } => {
                write!(f, "the goal configuration collides: `{a}` and `{b}`")
            }
            MotionError::NoPath { iterations } => {
                write!(
                    f,
                    "no collision-free motion found in {iterations} iterations"
                )
            }
            MotionError::Terminated { iterations } => {
                write!(
                    f,
                    "the motion search was stopped after {iterations} iterations"
                )
            }
            MotionError::Query(e) => write!(f, "collision query failed: {}", query_text(e)),
            MotionError::NotAnArm { end_effector } => {
                write!(f, "end-effector {end_effector} is not an arm")
            }
            MotionError::RepeatedArm { end_effector } => {
                write!(f, "arm {end_effector} is listed twice")
            }
            MotionError::WrongLength {
                joints,
                expected,
                found,
            } => write!(
                f,
                "{joints:?} configuration has {found} joint values, {expected} expected"
            ),
            MotionError::OutOfLimits {
                joints,
                end_effector,
                joint,
                value,
            } => write!(
                f,
                "{joints:?} configuration: joint {joint} of arm {end_effector} is {value}, \
                 outside its limits"
            ),
            MotionError::InvalidOption { name, value } => {
                write!(f, "motion option `{name}` cannot be {value}")
            }
            MotionError::Untimed { index } => write!(
                f,
                "the path cannot be timed within the joints' limits (at grid point {index})"
            ),
            MotionError::MalformedPath(why) => write!(f, "the path to time is malformed: {why}"),
        }
    }
}

impl std::error::Error for MotionError {}

impl From<QueryError> for MotionError {
    fn from(e: QueryError) -> MotionError {
        MotionError::Query(e)
    }
}

impl From<LayoutError> for MotionError {
    /// The layout's errors are about the arms and the stationary arms' joints.
    fn from(e: LayoutError) -> MotionError {
        match e {
            LayoutError::NotAnArm { end_effector } => MotionError::NotAnArm { end_effector },
            LayoutError::RepeatedArm { end_effector } => MotionError::RepeatedArm { end_effector },
            LayoutError::WrongLength {
                expected, found, ..
            } => MotionError::WrongLength {
                joints: Joints::Stationary,
                expected,
                found,
            },
            LayoutError::OutOfLimits {
                end_effector,
                joint,
                value,
            } => MotionError::OutOfLimits {
                joints: Joints::Stationary,
                end_effector,
                joint,
                value,
            },
        }
    }
}

/// A query error in words ([`QueryError`] has no `Display`).
pub(super) fn query_text(e: &QueryError) -> String {
    match e {
        QueryError::NotAnArm(e) => format!("end-effector {e} is not an arm"),
        QueryError::NotASurface(e) => format!("end-effector {e} is not a surface"),
        QueryError::Collision(c) => c.to_string(),
        QueryError::WrongLength { expected, found } => {
            format!("a configuration has {found} joint values, {expected} expected")
        }
    }
}

/// Checks that a request's timing options are usable: scalings in (0, 1], a rate in
/// (0, [`TimingOptions::MAX_RATE`]].
pub fn check_timing(timing: &TimingOptions) -> Result<(), MotionError> {
    for (name, value) in [
        ("velocity_scaling", timing.velocity_scaling),
        ("acceleration_scaling", timing.acceleration_scaling),
    ] {
        if !(value.is_finite() && value > 0.0 && value <= 1.0) {
            return Err(MotionError::InvalidOption { name, value });
        }
    }
    if let Some(rate) = timing.rate {
        if !(rate.is_finite() && rate > 0.0 && rate <= TimingOptions::MAX_RATE) {
            return Err(MotionError::InvalidOption {
                name: "rate",
                value: rate,
            });
        }
    }
    Ok(())
}

/// Checks that options are usable numbers.
pub(super) fn check_options(options: &MotionOptions) -> Result<(), MotionError> {
    for (name, value) in [
        ("step", options.step),
        ("collision_resolution", options.collision_resolution),
        ("grid_step", options.grid_step),
    ] {
        if !(value.is_finite() && value > 0.0) {
            return Err(MotionError::InvalidOption { name, value });
        }
    }
    if !(options.blend_deviation.is_finite() && options.blend_deviation >= 0.0) {
        return Err(MotionError::InvalidOption {
            name: "blend_deviation",
            value: options.blend_deviation,
        });
    }
    if !(0.0..=1.0).contains(&options.goal_bias) {
        return Err(MotionError::InvalidOption {
            name: "goal_bias",
            value: options.goal_bias,
        });
    }
    Ok(())
}
