//! Collision-free joint motions: step 7 of the paper's Algorithm 1, "execute each command
//! with a collision-free joint motion".
//!
//! The paper ran RRT* for 5 s with RRT-Connect as a backup and reports that RRT* failed in
//! about 40% of transitions. Here RRT-Connect is the planner: it answers in milliseconds
//! for the arms and furniture of a cell, and shortcut smoothing afterwards removes most of
//! the detours that RRT* would have spent seconds optimising away. Several arms that move
//! at once are planned together in their combined joint space, so they avoid each other as
//! well as the rest of the cell.
//!
//! # Seams
//!
//! Three traits, where OMPL and MoveIt put them, so a part can be replaced without
//! editing the others:
//! - [`StateValidity`]: is one configuration valid (the
//!   default, [`SceneValidity`](crate::validity::SceneValidity), checks limits and
//!   collisions in the cell with the object placed as the motion carries it);
//! - [`MotionValidity`]: is the straight segment between two configurations valid (the
//!   default, [`CertifiedMotion`], proves it free with clearance certificates; the
//!   sampled [`DiscreteMotion`] is its fallback for checkers that measure no clearance);
//! - [`MotionPlanner`]: a [`MotionProblem`] to a timed trajectory or a [`MotionError`]
//!   (the default, [`RrtConnect`]).
//!
//! Every search loop checks a [`Termination`] (the request's deadline, a cancel flag)
//! once per iteration and returns [`MotionError::Terminated`] when told to stop.
//!
//! # The pipeline of [`RrtConnect`]
//! 1. check the problem (arms, lengths, limits, options) and that start and goal are
//!    valid;
//! 2. try the straight line from start to goal (most motions in an uncluttered cell);
//! 3. otherwise RRT-Connect (`tree.rs`): two trees (from the start and from the goal), each
//!    extended towards uniform samples within the joint limits (goal-biased), the other
//!    tree greedily connected to every new node; lazily, as in Lazy PRM: a node joins
//!    when it is valid, its edge is checked only if it is still on the path after 4;
//! 4. random shortcuts between waypoints, then dropping waypoints whose neighbours see
//!    each other (`shortcut.rs`), each taken on a cheap sampled check; then every edge
//!    left is checked soundly: a refused shortcut gets its waypoints back, and a refused
//!    tree edge is cut off its tree, which grows on to the next path (`rrt.rs` runs
//!    these rounds);
//! 5. circular blends through the corners, each arc certified again (`blend.rs`), then a
//!    time-optimal parameterisation under every joint's speed and acceleration limits
//!    (`topp.rs`, TOPP-RA), rest to rest at the ends and at corners no blend clears, as
//!    points with positions, velocities and accelerations at most
//!    [`MotionOptions::grid_step`] apart, or at a control rate (`timing.rs`).
//!
//! [`RrtConnect::path`] gives the certified path of step 4, and `retime.rs` runs step 5
//! on a given path in its parts ([`smooth_waypoints`], [`time_smoothed`]) beside the
//! rest-to-rest trapezoids that came before it ([`rest_to_rest`]), so that other
//! parameterisations can be compared on the same paths (`benches/timing.rs`).
//!
//! # Sound edge checks
//!
//! A sampled check (every configuration a resolution apart) misses contacts shallower
//! than what one step sweeps: at 0.03 rad a hand a metre from the shoulder moves 3 cm
//! between samples, and a re-check at a finer resolution finds the graze the planner
//! passed through. So edges are not sampled but *certified* ([`CertifiedMotion`],
//! `certified.rs`), as in exact path checkers (Schwarzer, Saha and Latombe, 2005):
//! - a conservative bound on how far any point of the moving bodies (links, hand solids,
//!   a held object) can travel along a segment: `sum_j |b_j - a_j| R_j` per unit of the
//!   segment's parameter, with `R_j` the largest distance from joint `j`'s axis to any
//!   point of the bodies it moves, computed once per arm and grasp from the collision
//!   shapes' bounding spheres (`crate::swept`); for two bodies of one arm only the joints
//!   between them count;
//! - at a configuration, the distance of every pair of bodies that may not touch (allowed
//!   contacts and an object's holders excluded, as in collision checks; the other moving
//!   arm's bodies included), from the collision world;
//! - no configuration within `d / p` (in the segment's parameter) of one where a pair is
//!   `d` apart and can approach at `p` brings it into contact, so the midpoint of an
//!   uncovered part of the segment proves a whole interval free, and the rest is
//!   bisected, coarse to fine, until the segment is covered or a certificate fails.
//!
//! An accepted edge is therefore free at every configuration (at least a micrometre from
//! contact), and a re-check at any resolution, however fine, finds nothing. Every edge of
//! the result has been accepted so (the lazy trees and the screened shortcuts only decide
//! which edges are worth certifying). Smoothing keeps parts of those edges and adds arcs
//! that are certified themselves, chords between the knots on them included
//! (`blend.rs`), so every segment between two knots lies in certified space. Points
//! resampled at a control rate lie on the certified path itself; the straight chords
//! between them are not certified (a controller interpolates them with the velocities
//! and accelerations, not linearly). [`MotionOptions::collision_resolution`] is left to the
//! sampled fallback and to [`check_trajectory`], the independent re-check, which stays a
//! plain sampled check at the resolution it is given. The held object is part of every
//! check and follows the hand (its pose is recomputed from the arm's tip each time).
//!
//! Everything is deterministic for a seed: the only randomness is the caller's generator,
//! and no hash-map order or thread schedule is involved.

mod blend;
mod certified;
mod check;
mod problem;
mod retime;
mod rrt;
mod segment;
mod shortcut;
mod timing;
pub mod topp;
mod tree;

use std::fmt;

use cellc_schema::EndEffectorId;

use crate::plan::Trajectory;
use crate::scene::{QueryError, Scene, SceneScratch};
use crate::termination::Termination;
use crate::validity::StateValidity;

pub use blend::Piece;
pub use certified::CertifiedMotion;
pub use check::{check_trajectory, TrajectoryFault};
pub use problem::{check_timing, Joints, MotionError, MotionOptions, TimingOptions};
/// The generator [`MotionPlanner::solve`] draws from, re-exported so that an
/// implementation needs no dependency of its own.
pub use rand_chacha::ChaCha8Rng;
pub use retime::{arm_limits, rest_to_rest, smooth_waypoints, time_smoothed, SmoothedPath};
pub use rrt::RrtConnect;
pub use segment::DiscreteMotion;

/// One motion to plan: arms that move together from one configuration to another, and
/// which configurations they may pass through. `S` is the checker's
/// [`StateValidity::Scratch`] (the scene's, unless another checker is plugged in).
pub struct MotionProblem<'a, S = SceneScratch> {
    /// The cell (the arms' joint limits and sampling ranges).
    pub scene: &'a Scene,
    /// End-effectors (arms) that move together; their joints are concatenated in this
    /// order in `start`, `goal` and the trajectory's points.
    pub arms: &'a [EndEffectorId],
    /// Start joints, concatenated.
    pub start: &'a [f64],
    /// Goal joints, concatenated.
    pub goal: &'a [f64],
    /// Which configurations of `arms` are valid: usually a
    /// [`SceneValidity`](crate::validity::SceneValidity) for these arms, with the others
    /// where they stand and the object placed as the motion carries it.
    pub validity: &'a dyn StateValidity<Scratch = S>,
    /// How the request wants the motion timed (scalings of the joints' limits, a rate).
    pub timing: TimingOptions,
}

// By hand: a derive would ask `S: Clone`, which a problem that only borrows its checker
// does not need.
impl<S> Clone for MotionProblem<'_, S> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<S> Copy for MotionProblem<'_, S> {}

impl<S> fmt::Debug for MotionProblem<'_, S> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        // The scene and the checker have no `Debug`; the rest identifies the problem.
        f.debug_struct("MotionProblem")
            .field("arms", &self.arms)
            .field("start", &self.start)
            .field("goal", &self.goal)
            .finish_non_exhaustive()
    }
}

/// Plans motions (OMPL's `Planner`, MoveIt's planning plugin): a problem to a timed
/// trajectory from exactly `start` to exactly `goal` through valid configurations, or
/// why not. `S` is the scratch of the problems' checkers; the cell's planner
/// ([`crate::plan::planner::Planner`]) asks with the scene's.
pub trait MotionPlanner<S = SceneScratch> {
    /// Plans `problem`, drawing randomness from `rng` only (the same generator state
    /// gives the same answer) and stopping with [`MotionError::Terminated`] when `stop`
    /// says so; `scratch` is handed to the problem's checker.
    fn solve(
        &self,
        problem: &MotionProblem<'_, S>,
        rng: &mut ChaCha8Rng,
        stop: &Termination,
        scratch: &mut S,
    ) -> Result<Trajectory, MotionError>;
}

/// A borrowed planner plans as the planner does (so a caller can lend one to
/// [`crate::plan::planner::Planner`] and keep it).
impl<S, P: MotionPlanner<S> + ?Sized> MotionPlanner<S> for &P {
    fn solve(
        &self,
        problem: &MotionProblem<'_, S>,
        rng: &mut ChaCha8Rng,
        stop: &Termination,
        scratch: &mut S,
    ) -> Result<Trajectory, MotionError> {
        (**self).solve(problem, rng, stop, scratch)
    }
}

/// Decides whether the straight joint-space segment between two configurations is valid
/// (OMPL's `MotionValidator`).
pub trait MotionValidity {
    /// The per-thread buffers of the state checks behind it (its
    /// [`StateValidity::Scratch`]).
    type Scratch;

    /// Whether every configuration on the straight segment from `a` to `b` is valid, `b`
    /// included; `a` is known to be valid and need not be checked.
    fn check_motion(
        &mut self,
        a: &[f64],
        b: &[f64],
        scratch: &mut Self::Scratch,
    ) -> Result<bool, QueryError>;
}
