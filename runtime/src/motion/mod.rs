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
//! The pipeline of [`plan_motion`]:
//! 1. check the problem (arms, lengths, limits, options) and that start and goal are free;
//! 2. try the straight line from start to goal (most motions in an uncluttered cell);
//! 3. otherwise RRT-Connect: two trees (from the start and from the goal), each extended
//!    towards uniform samples within the joint limits (goal-biased), the other tree
//!    greedily connected to every new node;
//! 4. random shortcuts between waypoints, then dropping waypoints whose neighbours see
//!    each other;
//! 5. a trapezoidal velocity profile per segment (rest to rest, every joint synchronised),
//!    sampled so that no joint moves more than [`MotionOptions::step`] between points.
//!
//! Every edge is checked at [`MotionOptions::collision_resolution`]: no joint moves more
//! than that between two checked configurations. The checked configurations are exactly
//! those [`check_trajectory`] visits at that resolution once the edge is part of the timed
//! trajectory, so a planned trajectory always passes that re-check (a finer re-check can
//! still find contacts shallower than what a resolution step sweeps, as with any sampled
//! collision checking). The held object is part of every check and follows the hand (its
//! pose is recomputed from the arm's tip each time).
//!
//! Everything is deterministic for a seed: the only randomness is the caller's generator,
//! and no hash-map order or thread schedule is involved.

use std::fmt;

use rand::Rng;
use rand_chacha::ChaCha8Rng;

use crate::plan::Trajectory;
use crate::scene::{Holder, ObjectPlacement, QueryError, Scene, SceneScratch};

/// One motion to plan.
#[derive(Clone)]
pub struct MotionProblem<'a> {
    /// The cell.
    pub scene: &'a Scene,
    /// End-effectors (arms) that move together; their joints are concatenated in this
    /// order in `start`, `goal` and the trajectory's points.
    pub arms: Vec<u32>,
    /// Start joints, concatenated.
    pub start: Vec<f64>,
    /// Goal joints, concatenated.
    pub goal: Vec<f64>,
    /// Arms that do not move but are not at home either (where the plan left them), with
    /// their joints. Every arm in neither list stands at its home configuration.
    pub stationary: Vec<(u32, Vec<f64>)>,
    /// The object the placement refers to (index into the artifact's objects).
    pub object: u32,
    /// How the object travels.
    pub placement: ObjectPlacement,
}

impl fmt::Debug for MotionProblem<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        // The scene is large and has no `Debug`; the rest identifies the problem.
        f.debug_struct("MotionProblem")
            .field("arms", &self.arms)
            .field("start", &self.start)
            .field("goal", &self.goal)
            .field("stationary", &self.stationary)
            .field("object", &self.object)
            .field("placement", &self.placement)
            .finish_non_exhaustive()
    }
}

/// Planner settings.
#[derive(Clone, Debug, PartialEq)]
pub struct MotionOptions {
    /// RRT-Connect iterations (one sample each) before giving up.
    pub max_iterations: usize,
    /// Largest joint change of one tree extension, and between two output points (rad, or
    /// m for prismatic joints).
    pub step: f64,
    /// Largest joint change between two configurations checked along an edge (rad, or m).
    pub collision_resolution: f64,
    /// Random shortcut attempts after a path is found.
    pub shortcut_iterations: usize,
    /// Probability that a sample is the other tree's root.
    pub goal_bias: f64,
    /// Per-joint speed limit for timing (rad/s, or m/s for prismatic joints).
    pub velocity_limit: f64,
    /// Per-joint acceleration limit for timing (rad/s², or m/s²).
    pub acceleration_limit: f64,
}

impl Default for MotionOptions {
    fn default() -> MotionOptions {
        MotionOptions {
            max_iterations: 5000,
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
            // About half the LWR's rated joint speed (1.92 rad/s): a safe default for
            // execution and simulation.
            velocity_limit: 1.0,
            acceleration_limit: 2.0,
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
    /// The scene could not answer a collision query (a placement naming no arm or
    /// surface, a non-finite state).
    Query(QueryError),
    /// An end-effector in `arms` or `stationary` is not an arm of the scene.
    NotAnArm {
        /// End-effector.
        end_effector: u32,
    },
    /// An end-effector appears twice among `arms` and `stationary`.
    RepeatedArm {
        /// End-effector.
        end_effector: u32,
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
        end_effector: u32,
        /// Joint index in the arm's chain.
        joint: usize,
        /// The value.
        value: f64,
    },
    /// An option is not a positive finite number (or the goal bias not in [0, 1]).
    InvalidOption {
        /// Field of [`MotionOptions`].
        name: &'static str,
        /// Its value.
        value: f64,
    },
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
        }
    }
}

impl std::error::Error for MotionError {}

impl From<QueryError> for MotionError {
    fn from(e: QueryError) -> MotionError {
        MotionError::Query(e)
    }
}

/// A query error in words ([`QueryError`] has no `Display`).
fn query_text(e: &QueryError) -> String {
    match e {
        QueryError::NotAnArm(e) => format!("end-effector {e} is not an arm"),
        QueryError::NotASurface(e) => format!("end-effector {e} is not a surface"),
        QueryError::Collision(c) => c.to_string(),
    }
}

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
        end_effector: u32,
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
        end_effector: u32,
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

/// A moving arm's slice of the combined configuration.
#[derive(Clone, Copy, Debug)]
struct ArmSlice {
    end_effector: u32,
    robot: usize,
    offset: usize,
    len: usize,
}

/// The moving arms' slices, or the first end-effector that is not an arm (or repeats,
/// also against the stationary ones).
fn arm_slices(
    scene: &Scene,
    arms: &[u32],
    stationary: &[(u32, Vec<f64>)],
) -> Result<Vec<ArmSlice>, (u32, bool)> {
    let mut slices = Vec::with_capacity(arms.len());
    let mut offset = 0;
    for (i, &e) in arms.iter().enumerate() {
        let Some(Holder::Arm { robot, .. }) = scene.holders.get(e as usize) else {
            return Err((e, false));
        };
        if arms[..i].contains(&e) {
            return Err((e, true));
        }
        let len = scene.robots[*robot].n_joints();
        slices.push(ArmSlice {
            end_effector: e,
            robot: *robot,
            offset,
            len,
        });
        offset += len;
    }
    for (i, (e, _)) in stationary.iter().enumerate() {
        if !matches!(scene.holders.get(*e as usize), Some(Holder::Arm { .. })) {
            return Err((*e, false));
        }
        if arms.contains(e) || stationary[..i].iter().any(|(s, _)| s == e) {
            return Err((*e, true));
        }
    }
    Ok(slices)
}

/// The first joint of `q` outside its arm's limits (or not finite): (arm, joint, value).
fn out_of_limits(scene: &Scene, slices: &[ArmSlice], q: &[f64]) -> Option<(u32, usize, f64)> {
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

/// Arms listed in one query without allocating, up to this many (more fall back to a
/// vector).
const INLINE_ARMS: usize = 16;

/// Collision queries for configurations of the combined space, and edges checked exactly
/// as [`check_trajectory`] will check the timed result.
struct Checker<'a> {
    scene: &'a Scene,
    slices: &'a [ArmSlice],
    stationary: &'a [(u32, Vec<f64>)],
    object: u32,
    placement: ObjectPlacement,
    /// Output sampling step (see [`sample`]).
    step: f64,
    /// Largest joint change between checked configurations.
    resolution: f64,
    /// Reused by [`Checker::edge_free`].
    buffers: EdgeBuffers,
}

impl Checker<'_> {
    /// The first colliding pair at `q`.
    fn collision(
        &self,
        q: &[f64],
        scratch: &mut SceneScratch,
    ) -> Result<Option<(String, String)>, QueryError> {
        let n = self.slices.len() + self.stationary.len();
        let mut inline: [(u32, &[f64]); INLINE_ARMS] = [(0, &[]); INLINE_ARMS];
        let mut heap: Vec<(u32, &[f64])>;
        let list: &mut [(u32, &[f64])] = if n <= INLINE_ARMS {
            &mut inline[..n]
        } else {
            heap = vec![(0, &[][..]); n];
            &mut heap
        };
        for (slot, s) in list.iter_mut().zip(self.slices) {
            *slot = (s.end_effector, &q[s.offset..s.offset + s.len]);
        }
        for (slot, (e, joints)) in list[self.slices.len()..].iter_mut().zip(self.stationary) {
            *slot = (*e, joints.as_slice());
        }
        self.scene
            .collision(list, self.object, self.placement, scratch)
    }

    /// Whether `q` is collision-free.
    fn free(&self, q: &[f64], scratch: &mut SceneScratch) -> Result<bool, QueryError> {
        Ok(self.collision(q, scratch)?.is_none())
    }

    /// Whether the edge from `a` (assumed free) to `b` is free, checked at exactly the
    /// configurations [`check_trajectory`] at `resolution` will check once the edge is a
    /// segment of the timed trajectory: the edge is cut into the output samples ([`sample`]
    /// with `step`), each piece into the fewest equal steps that move no joint more than
    /// `resolution` ([`sample`] again), and every step's end is checked. So a planned
    /// trajectory always passes `check_trajectory` at the planner's resolution, bit for
    /// bit, whatever the rounding.
    ///
    /// The order is coarse to fine (the pieces' ends in bisection order, then the points
    /// inside each piece in bisection order), so a blocked edge is usually rejected after
    /// a few checks.
    fn edge_free(
        &mut self,
        a: &[f64],
        b: &[f64],
        scratch: &mut SceneScratch,
    ) -> Result<bool, QueryError> {
        let pieces = steps(a, b, self.step);
        if pieces == 0 {
            return Ok(true);
        }
        let mut buffers = std::mem::take(&mut self.buffers);
        let result = self.pieces_free(a, b, pieces, &mut buffers, scratch);
        self.buffers = buffers;
        result
    }

    /// [`Checker::edge_free`] for an edge of `pieces` output samples.
    fn pieces_free(
        &self,
        a: &[f64],
        b: &[f64],
        pieces: usize,
        buffers: &mut EdgeBuffers,
        scratch: &mut SceneScratch,
    ) -> Result<bool, QueryError> {
        let EdgeBuffers { from, to, point } = buffers;
        // The samples themselves (the pieces' ends) first, then inside each piece.
        let ends = bisection(pieces, |i| {
            sample(a, b, i, pieces, to);
            self.free(to, scratch)
        })?;
        if !ends {
            return Ok(false);
        }
        for i in 1..=pieces {
            sample(a, b, i - 1, pieces, from);
            sample(a, b, i, pieces, to);
            let n = steps(from, to, self.resolution);
            let inside = bisection(n.saturating_sub(1), |k| {
                sample(from, to, k, n, point);
                self.free(point, scratch)
            })?;
            if !inside {
                return Ok(false);
            }
        }
        Ok(true)
    }
}

/// Buffers of [`Checker::edge_free`]: both ends of a piece and a point between.
#[derive(Default)]
struct EdgeBuffers {
    from: Vec<f64>,
    to: Vec<f64>,
    point: Vec<f64>,
}

/// Calls `visit` on `n`, then on every `k` in `1..n` coarse to fine (the midpoint, the
/// quarters, ...), until it returns `false` or an error; `Ok(true)` when every call did.
fn bisection<E>(n: usize, mut visit: impl FnMut(usize) -> Result<bool, E>) -> Result<bool, E> {
    if n == 0 {
        return Ok(true);
    }
    if !visit(n)? {
        return Ok(false);
    }
    // Every k in 1..n is an odd multiple of exactly one power of two, so visiting odd
    // multiples of s for s = 2^m, ..., 2, 1 visits each once.
    let mut s = 1usize << (usize::BITS - 1 - n.leading_zeros());
    while s >= 1 {
        let mut k = s;
        while k < n {
            if !visit(k)? {
                return Ok(false);
            }
            k += 2 * s;
        }
        s /= 2;
    }
    Ok(true)
}

/// Sample `i` of `n` of the segment from `a` to `b`: `b` itself for `i == n` (so waypoints
/// are reproduced exactly), otherwise `a + (b - a) i / n`. The timed trajectory's points
/// and the planner's edge checks both come from here.
fn sample(a: &[f64], b: &[f64], i: usize, n: usize, out: &mut Vec<f64>) {
    if i >= n {
        out.clear();
        out.extend_from_slice(b);
    } else {
        interpolate(a, b, i as f64 / n as f64, out);
    }
}

/// Largest absolute joint difference.
fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// Steps so that no joint moves more than `resolution` per step (0 for equal points).
fn steps(a: &[f64], b: &[f64], resolution: f64) -> usize {
    let d = max_diff(a, b);
    if d == 0.0 {
        0
    } else {
        // Finite and positive by validation; the cast saturates anyway.
        (d / resolution).ceil().max(1.0) as usize
    }
}

/// `out = a + (b - a) s`.
fn interpolate(a: &[f64], b: &[f64], s: f64, out: &mut Vec<f64>) {
    out.clear();
    out.extend(a.iter().zip(b).map(|(x, y)| x + (y - x) * s));
}

/// A tree of configurations, stored flat (`dim` values per node) so growing it allocates
/// rarely and the nearest-neighbour scan runs over contiguous memory.
struct Tree {
    dim: usize,
    /// Rooted at the start: the path runs from parents to children. Otherwise (rooted at
    /// the goal) from children to parents, and edges are checked in that direction, as
    /// the trajectory will run along them.
    forward: bool,
    nodes: Vec<f64>,
    parents: Vec<u32>,
}

impl Tree {
    fn new(root: &[f64], forward: bool) -> Tree {
        let mut nodes = Vec::with_capacity(root.len() * 256);
        nodes.extend_from_slice(root);
        Tree {
            dim: root.len(),
            forward,
            nodes,
            parents: vec![0],
        }
    }

    fn len(&self) -> usize {
        self.parents.len()
    }

    fn node(&self, i: usize) -> &[f64] {
        &self.nodes[i * self.dim..(i + 1) * self.dim]
    }

    fn push(&mut self, q: &[f64], parent: usize) -> usize {
        self.nodes.extend_from_slice(q);
        // Trees never approach 2^32 nodes (iterations are bounded far below).
        self.parents.push(parent as u32);
        self.len() - 1
    }

    /// The node closest to `q` (Euclidean in joint space). A linear scan: trees have tens
    /// to a few thousand nodes, where it beats building a spatial index.
    fn nearest(&self, q: &[f64]) -> usize {
        let mut best = (0, f64::INFINITY);
        for (i, node) in self.nodes.chunks_exact(self.dim.max(1)).enumerate() {
            let d: f64 = node.iter().zip(q).map(|(x, y)| (x - y) * (x - y)).sum();
            if d < best.1 {
                best = (i, d);
            }
        }
        best.0
    }

    /// Node `i` and its ancestors up to the root, in that order, appended to `out`.
    fn chain(&self, mut i: usize, out: &mut Vec<f64>) {
        loop {
            out.extend_from_slice(self.node(i));
            if i == 0 {
                break;
            }
            i = self.parents[i] as usize;
        }
    }
}

/// The result of extending a tree towards a configuration.
enum Extension {
    /// Reached it (node index).
    Reached(usize),
    /// Moved one step towards it (node index).
    Advanced(usize),
    /// Blocked.
    Trapped,
}

/// The RRT-Connect extension and connection steps.
struct Rrt<'c, 'a> {
    checker: &'c mut Checker<'a>,
    step: f64,
    new: Vec<f64>,
}

impl Rrt<'_, '_> {
    /// One step of at most `step` (per joint) from the node nearest `target` towards it.
    fn extend(
        &mut self,
        tree: &mut Tree,
        target: &[f64],
        scratch: &mut SceneScratch,
    ) -> Result<Extension, QueryError> {
        let near = tree.nearest(target);
        let from = tree.node(near);
        let d = max_diff(from, target);
        if d == 0.0 {
            return Ok(Extension::Reached(near));
        }
        let reached = d <= self.step;
        if reached {
            // Exactly the target, so trees that meet share the configuration bit for bit.
            self.new.clear();
            self.new.extend_from_slice(target);
        } else {
            interpolate(from, target, self.step / d, &mut self.new);
        }
        let free = if tree.forward {
            self.checker.edge_free(from, &self.new, scratch)?
        } else {
            // The edge runs from the new node to its parent: check the new node itself
            // first, then the edge as the trajectory will run along it.
            self.checker.free(&self.new, scratch)?
                && self.checker.edge_free(&self.new, from, scratch)?
        };
        if !free {
            return Ok(Extension::Trapped);
        }
        let i = tree.push(&self.new, near);
        Ok(if reached {
            Extension::Reached(i)
        } else {
            Extension::Advanced(i)
        })
    }

    /// Extends `tree` towards `target` until it gets there or is blocked.
    fn connect(
        &mut self,
        tree: &mut Tree,
        target: &[f64],
        scratch: &mut SceneScratch,
    ) -> Result<Option<usize>, QueryError> {
        loop {
            match self.extend(tree, target, scratch)? {
                Extension::Reached(i) => return Ok(Some(i)),
                Extension::Advanced(_) => {}
                Extension::Trapped => return Ok(None),
            }
        }
    }
}

/// Uniform sampling ranges per dimension: the joints' sampling ranges (limits, or [-pi,
/// pi] for continuous joints), widened to include start and goal.
fn sampling_ranges(
    scene: &Scene,
    slices: &[ArmSlice],
    start: &[f64],
    goal: &[f64],
) -> Vec<(f64, f64)> {
    let mut ranges = Vec::with_capacity(start.len());
    for s in slices {
        let robot = &scene.robots[s.robot];
        for j in 0..s.len {
            let (lo, hi) = robot.sampling_range(j);
            let (a, b) = (start[s.offset + j], goal[s.offset + j]);
            ranges.push((lo.min(a).min(b), hi.max(a).max(b)));
        }
    }
    ranges
}

/// RRT-Connect from `start` to `goal`; the path's waypoints flat, start first.
fn rrt_connect(
    rrt: &mut Rrt<'_, '_>,
    start: &[f64],
    goal: &[f64],
    ranges: &[(f64, f64)],
    options: &MotionOptions,
    rng: &mut ChaCha8Rng,
    scratch: &mut SceneScratch,
) -> Result<Option<Vec<f64>>, MotionError> {
    let dim = start.len();
    let mut trees = [Tree::new(start, true), Tree::new(goal, false)];
    // Which tree grows towards the sample this iteration; the other connects to it.
    let mut active = 0;
    let mut sample = vec![0.0; dim];
    let mut reached = vec![0.0; dim];
    for _ in 0..options.max_iterations {
        let [a, b] = &mut trees;
        let (grow, other) = if active == 0 { (a, b) } else { (b, a) };
        if rng.random::<f64>() < options.goal_bias {
            sample.copy_from_slice(other.node(0));
        } else {
            for (v, &(lo, hi)) in sample.iter_mut().zip(ranges) {
                *v = lo + (hi - lo) * rng.random::<f64>();
            }
        }
        let new = match rrt.extend(grow, &sample, scratch)? {
            Extension::Trapped => None,
            Extension::Reached(i) | Extension::Advanced(i) => Some(i),
        };
        if let Some(i) = new {
            reached.copy_from_slice(grow.node(i));
            if let Some(j) = rrt.connect(other, &reached, scratch)? {
                // Both chains end at the same configuration: the start tree's chain
                // reversed, then the goal tree's chain (the shared node is deduplicated
                // later).
                let (from_start, i_s, from_goal, i_g) = if active == 0 {
                    (&*grow, i, &*other, j)
                } else {
                    (&*other, j, &*grow, i)
                };
                let mut path = Vec::new();
                from_start.chain(i_s, &mut path);
                reverse_waypoints(&mut path, dim);
                from_goal.chain(i_g, &mut path);
                return Ok(Some(path));
            }
        }
        active = 1 - active;
    }
    Ok(None)
}

/// Reverses the order of the `dim`-sized waypoints of `path`.
fn reverse_waypoints(path: &mut [f64], dim: usize) {
    if dim == 0 {
        return;
    }
    let m = path.len() / dim;
    for i in 0..m / 2 {
        let j = m - 1 - i;
        for k in 0..dim {
            path.swap(i * dim + k, j * dim + k);
        }
    }
}

/// Drops waypoints equal to their predecessor.
fn dedup_waypoints(path: &mut Vec<f64>, dim: usize) {
    if dim == 0 {
        return;
    }
    let m = path.len() / dim;
    let mut kept = 1;
    for i in 1..m {
        let same = path[(kept - 1) * dim..kept * dim] == path[i * dim..(i + 1) * dim];
        if !same {
            path.copy_within(i * dim..(i + 1) * dim, kept * dim);
            kept += 1;
        }
    }
    path.truncate(kept * dim);
}

/// Random shortcuts: two random waypoints are joined directly when the edge between them
/// is free, dropping those in between. Then every waypoint whose neighbours see each
/// other is dropped too, since each waypoint costs a stop in the timing. Shortcuts join
/// waypoints only (never points inside segments), so every segment of the result is an
/// edge checked as a whole, which keeps the planner's checks and [`check_trajectory`]'s
/// identical; RRT waypoints are at most `step` apart, so little is lost.
fn shortcut(
    checker: &mut Checker<'_>,
    path: &mut Vec<f64>,
    dim: usize,
    iterations: usize,
    rng: &mut ChaCha8Rng,
    scratch: &mut SceneScratch,
) -> Result<(), QueryError> {
    if dim == 0 {
        return Ok(());
    }
    for _ in 0..iterations {
        let m = path.len() / dim;
        if m <= 2 {
            break;
        }
        let (i, j) = (rng.random_range(0..m), rng.random_range(0..m));
        let (i, j) = (i.min(j), i.max(j));
        if j < i + 2 {
            continue;
        }
        let (head, tail) = path.split_at(j * dim);
        if checker.edge_free(&head[i * dim..(i + 1) * dim], &tail[..dim], scratch)? {
            path.drain((i + 1) * dim..j * dim);
        }
    }
    let mut i = 1;
    while (i + 1) * dim < path.len() {
        let (head, tail) = path.split_at(i * dim);
        let (before, after) = (&head[(i - 1) * dim..], &tail[dim..2 * dim]);
        if checker.edge_free(before, after, scratch)? {
            path.drain(i * dim..(i + 1) * dim);
        } else {
            i += 1;
        }
    }
    Ok(())
}

/// A rest-to-rest trapezoidal profile of the path parameter `s` from 0 to 1: the fastest
/// one that keeps every joint of a straight segment within the speed and acceleration
/// limits, with all joints synchronised (they start, cruise and stop together).
#[derive(Clone, Copy, Debug)]
struct Profile {
    /// Cruise rate of `s` (1/s).
    speed: f64,
    /// Acceleration of `s` (1/s²).
    accel: f64,
    /// `s` at the end of the acceleration phase.
    s_accel: f64,
    /// Duration of the acceleration phase.
    t_accel: f64,
    /// Total duration.
    duration: f64,
}

impl Profile {
    /// For a segment with largest joint displacement `d` (> 0).
    fn new(d: f64, velocity: f64, acceleration: f64) -> Profile {
        // Joint j moves d_j s(t): |d_j| s' <= v and |d_j| s'' <= a for every joint, which
        // the joint with the largest displacement binds.
        let (speed, accel) = (velocity / d, acceleration / d);
        if speed * speed / accel >= 1.0 {
            // Never reaches the cruise speed: accelerate to half-way, then brake.
            let t_accel = (1.0 / accel).sqrt();
            Profile {
                speed: accel * t_accel,
                accel,
                s_accel: 0.5,
                t_accel,
                duration: 2.0 * t_accel,
            }
        } else {
            let t_accel = speed / accel;
            let s_accel = 0.5 * speed * t_accel;
            Profile {
                speed,
                accel,
                s_accel,
                t_accel,
                duration: 2.0 * t_accel + (1.0 - 2.0 * s_accel) / speed,
            }
        }
    }

    /// The time at which the parameter reaches `s` (strictly increasing in `s`).
    fn time_at(&self, s: f64) -> f64 {
        if s <= self.s_accel {
            (2.0 * s / self.accel).sqrt()
        } else if s <= 1.0 - self.s_accel {
            self.t_accel + (s - self.s_accel) / self.speed
        } else {
            self.duration - (2.0 * (1.0 - s).max(0.0) / self.accel).sqrt()
        }
    }
}

/// Times the waypoints with a rest-to-rest trapezoid per segment and samples each segment
/// at [`sample`]`(.., step)`, so consecutive points differ by at most `step` per joint.
fn time_path(path: &[f64], dim: usize, arms: &[u32], options: &MotionOptions) -> Trajectory {
    let m = path.len().checked_div(dim).unwrap_or(1);
    let mut points = Vec::new();
    points.push((0.0, path[..dim].to_vec()));
    let mut t0 = 0.0;
    let mut q = Vec::with_capacity(dim);
    for i in 1..m {
        let (a, b) = (&path[(i - 1) * dim..i * dim], &path[i * dim..(i + 1) * dim]);
        let d = max_diff(a, b);
        if d == 0.0 {
            continue;
        }
        let profile = Profile::new(d, options.velocity_limit, options.acceleration_limit);
        let n = steps(a, b, options.step);
        for k in 1..=n {
            sample(a, b, k, n, &mut q);
            points.push((t0 + profile.time_at(k as f64 / n as f64), q.clone()));
        }
        t0 += profile.duration;
    }
    Trajectory {
        arms: arms.to_vec(),
        points,
    }
}

/// Checks that options are usable numbers.
fn check_options(options: &MotionOptions) -> Result<(), MotionError> {
    for (name, value) in [
        ("step", options.step),
        ("collision_resolution", options.collision_resolution),
        ("velocity_limit", options.velocity_limit),
        ("acceleration_limit", options.acceleration_limit),
    ] {
        if !(value.is_finite() && value > 0.0) {
            return Err(MotionError::InvalidOption { name, value });
        }
    }
    if !(0.0..=1.0).contains(&options.goal_bias) {
        return Err(MotionError::InvalidOption {
            name: "goal_bias",
            value: options.goal_bias,
        });
    }
    Ok(())
}

/// Plans a collision-free, timed joint motion of `problem.arms` from `problem.start` to
/// `problem.goal`: the straight line when it is free, otherwise RRT-Connect in the arms'
/// combined joint space, shortcut and timed (see the module documentation).
///
/// The result starts at time 0 with `start` and ends with exactly `goal`; consecutive
/// points differ by at most `options.step` per joint and every joint respects the speed
/// and acceleration limits. When start and goal are equal it has that one point.
pub fn plan_motion(
    problem: &MotionProblem<'_>,
    rng: &mut ChaCha8Rng,
    options: &MotionOptions,
    scratch: &mut SceneScratch,
) -> Result<Trajectory, MotionError> {
    check_options(options)?;
    let scene = problem.scene;
    let slices = arm_slices(scene, &problem.arms, &problem.stationary).map_err(
        |(end_effector, repeated)| {
            if repeated {
                MotionError::RepeatedArm { end_effector }
            } else {
                MotionError::NotAnArm { end_effector }
            }
        },
    )?;
    let dim: usize = slices.iter().map(|s| s.len).sum();
    for (joints, q) in [
        (Joints::Start, &problem.start),
        (Joints::Goal, &problem.goal),
    ] {
        if q.len() != dim {
            return Err(MotionError::WrongLength {
                joints,
                expected: dim,
                found: q.len(),
            });
        }
        if let Some((end_effector, joint, value)) = out_of_limits(scene, &slices, q) {
            return Err(MotionError::OutOfLimits {
                joints,
                end_effector,
                joint,
                value,
            });
        }
    }
    for (e, q) in &problem.stationary {
        let Some(Holder::Arm { robot, .. }) = scene.holders.get(*e as usize) else {
            return Err(MotionError::NotAnArm { end_effector: *e });
        };
        let robot = &scene.robots[*robot];
        if q.len() != robot.n_joints() {
            return Err(MotionError::WrongLength {
                joints: Joints::Stationary,
                expected: robot.n_joints(),
                found: q.len(),
            });
        }
        let (lower, upper) = robot.limits();
        for (joint, ((&value, &lo), &hi)) in q.iter().zip(lower).zip(upper).enumerate() {
            if !(value.is_finite() && lo <= value && value <= hi) {
                return Err(MotionError::OutOfLimits {
                    joints: Joints::Stationary,
                    end_effector: *e,
                    joint,
                    value,
                });
            }
        }
    }
    let mut checker = Checker {
        scene,
        slices: &slices,
        stationary: &problem.stationary,
        object: problem.object,
        placement: problem.placement,
        step: options.step,
        resolution: options.collision_resolution,
        buffers: EdgeBuffers::default(),
    };
    if let Some((a, b)) = checker.collision(&problem.start, scratch)? {
        return Err(MotionError::StartInCollision { a, b });
    }
    if let Some((a, b)) = checker.collision(&problem.goal, scratch)? {
        return Err(MotionError::GoalInCollision { a, b });
    }
    let mut path = Vec::with_capacity(2 * dim);
    path.extend_from_slice(&problem.start);
    path.extend_from_slice(&problem.goal);
    if !checker.edge_free(&problem.start, &problem.goal, scratch)? {
        let ranges = sampling_ranges(scene, &slices, &problem.start, &problem.goal);
        let mut rrt = Rrt {
            checker: &mut checker,
            step: options.step,
            new: Vec::with_capacity(dim),
        };
        path = rrt_connect(
            &mut rrt,
            &problem.start,
            &problem.goal,
            &ranges,
            options,
            rng,
            scratch,
        )?
        .ok_or(MotionError::NoPath {
            iterations: options.max_iterations,
        })?;
        dedup_waypoints(&mut path, dim);
        shortcut(
            &mut checker,
            &mut path,
            dim,
            options.shortcut_iterations,
            rng,
            scratch,
        )?;
    }
    dedup_waypoints(&mut path, dim);
    Ok(time_path(&path, dim, &problem.arms, options))
}

/// Re-checks `trajectory` independently of how it was planned: every point has the right
/// length and is within limits, times are finite and non-decreasing, and every segment
/// between consecutive points is collision-free at `resolution` (per joint), with
/// `stationary` arms at their joints, every other arm at home and the object placed as
/// `placement` (a held object following its hand). Used by tests and the simulator.
///
/// Segments are cut exactly as [`plan_motion`] cuts its edges, so a planned trajectory
/// always passes at the planner's `collision_resolution`; a finer `resolution` is a
/// stricter, independent test. A `resolution` that is not positive and finite means the
/// default one.
///
/// # Errors
/// The first fault along the trajectory, with its time.
pub fn check_trajectory(
    scene: &Scene,
    trajectory: &Trajectory,
    stationary: &[(u32, Vec<f64>)],
    object: u32,
    placement: &ObjectPlacement,
    resolution: f64,
    scratch: &mut SceneScratch,
) -> Result<(), TrajectoryFault> {
    let slices = arm_slices(scene, &trajectory.arms, stationary)
        .map_err(|(end_effector, _)| TrajectoryFault::BadArm { end_effector })?;
    let dim: usize = slices.iter().map(|s| s.len).sum();
    for (e, q) in stationary {
        let n = scene
            .holders
            .get(*e as usize)
            .and_then(|h| match h {
                Holder::Arm { robot, .. } => Some(scene.robots[*robot].n_joints()),
                _ => None,
            })
            .ok_or(TrajectoryFault::BadArm { end_effector: *e })?;
        if q.len() != n {
            return Err(TrajectoryFault::BadArm { end_effector: *e });
        }
    }
    let resolution = if resolution.is_finite() && resolution > 0.0 {
        resolution
    } else {
        MotionOptions::default().collision_resolution
    };
    let checker = Checker {
        scene,
        slices: &slices,
        stationary,
        object,
        placement: *placement,
        step: f64::INFINITY,
        resolution,
        buffers: EdgeBuffers::default(),
    };
    let mut q = Vec::with_capacity(dim);
    let mut previous: Option<(f64, &[f64])> = None;
    for (i, (t, point)) in trajectory.points.iter().enumerate() {
        if point.len() != dim {
            return Err(TrajectoryFault::WrongLength {
                point: i,
                expected: dim,
                found: point.len(),
            });
        }
        if !t.is_finite() || previous.is_some_and(|(t0, _)| *t < t0) {
            return Err(TrajectoryFault::Time { point: i });
        }
        if let Some((end_effector, joint, value)) = out_of_limits(scene, &slices, point) {
            return Err(TrajectoryFault::OutOfLimits {
                time: *t,
                end_effector,
                joint,
                value,
            });
        }
        let check = |q: &[f64], time: f64, scratch: &mut SceneScratch| match checker
            .collision(q, scratch)
        {
            Ok(None) => Ok(()),
            Ok(Some((a, b))) => Err(TrajectoryFault::Collision { time, a, b }),
            Err(error) => Err(TrajectoryFault::Query { time, error }),
        };
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
