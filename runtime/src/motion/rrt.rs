//! RRT-Connect (Kuffner and LaValle, 2000) in the combined joint space of the arms that
//! move together, and [`RrtConnect`], the default [`MotionPlanner`] built on it.

use rand::Rng;
use rand_chacha::ChaCha8Rng;

use super::problem::check_options;
use super::segment::{interpolate, max_diff};
use super::shortcut::{dedup_waypoints, shortcut};
use super::timing::time_path;
use super::{
    CertifiedMotion, Joints, MotionError, MotionOptions, MotionPlanner, MotionProblem,
    MotionValidity,
};
use crate::plan::Trajectory;
use crate::scene::{QueryError, Scene, SceneScratch};
use crate::termination::Termination;
use crate::validity::{arm_slices, out_of_limits, ArmSlice, StateFault, StateValidity};

/// The default motion planner: the straight line when it is valid, otherwise
/// RRT-Connect, shortcut and timed (see [the module](super) documentation).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RrtConnect {
    /// Settings.
    pub options: MotionOptions,
}

impl RrtConnect {
    /// A planner with these settings.
    pub fn new(options: MotionOptions) -> RrtConnect {
        RrtConnect { options }
    }

    /// [`MotionPlanner::solve`] with segments checked by `motion` instead of the
    /// [`CertifiedMotion`] the planner would build (a sampled check such as
    /// [`DiscreteMotion`](super::DiscreteMotion), a validator that counts or caches). The
    /// timed trajectory's points are still cut by [`MotionOptions::step`].
    pub fn solve_with(
        &self,
        problem: &MotionProblem<'_>,
        motion: &mut dyn MotionValidity,
        rng: &mut ChaCha8Rng,
        stop: &Termination,
        scratch: &mut SceneScratch,
    ) -> Result<Trajectory, MotionError> {
        let options = &self.options;
        check_options(options)?;
        let scene = problem.scene;
        let slices = arm_slices(scene, problem.arms)?;
        let dim: usize = slices.iter().map(|s| s.len).sum();
        let ends = [(Joints::Start, problem.start), (Joints::Goal, problem.goal)];
        for (joints, q) in ends {
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
        for (joints, q) in ends {
            match problem.validity.check(q, scratch)? {
                None => {}
                Some(StateFault::Collision { a, b }) if joints == Joints::Start => {
                    return Err(MotionError::StartInCollision { a, b })
                }
                Some(StateFault::Collision { a, b }) => {
                    return Err(MotionError::GoalInCollision { a, b })
                }
                Some(StateFault::OutOfLimits {
                    end_effector,
                    joint,
                    value,
                }) => {
                    return Err(MotionError::OutOfLimits {
                        joints,
                        end_effector,
                        joint,
                        value,
                    })
                }
            }
        }
        // A request already out of time gets no motion, not even a free straight line.
        if stop.should_stop() {
            return Err(MotionError::Terminated { iterations: 0 });
        }
        let (start, goal) = (problem.start, problem.goal);
        let mut path = Vec::with_capacity(2 * dim);
        path.extend_from_slice(start);
        path.extend_from_slice(goal);
        if !motion.check_motion(start, goal, scratch)? {
            let ranges = sampling_ranges(scene, &slices, start, goal);
            let mut rrt = Rrt {
                validity: problem.validity,
                motion: &mut *motion,
                step: options.step,
                new: Vec::with_capacity(dim),
            };
            path = rrt_connect(&mut rrt, start, goal, &ranges, options, rng, stop, scratch)?
                .ok_or(MotionError::NoPath {
                    iterations: options.max_iterations,
                })?;
            dedup_waypoints(&mut path, dim);
            shortcut(
                motion,
                &mut path,
                dim,
                options.shortcut_iterations,
                rng,
                stop,
                scratch,
            )?;
        }
        dedup_waypoints(&mut path, dim);
        Ok(time_path(&path, dim, problem.arms, options))
    }
}

impl MotionPlanner for RrtConnect {
    /// A collision-free, timed joint motion of `problem.arms` from `problem.start` to
    /// `problem.goal`. The result starts at time 0 with `start` and ends with exactly
    /// `goal`; consecutive points differ by at most `options.step` per joint and every
    /// joint respects the speed and acceleration limits. When start and goal are equal it
    /// has that one point.
    fn solve(
        &self,
        problem: &MotionProblem<'_>,
        rng: &mut ChaCha8Rng,
        stop: &Termination,
        scratch: &mut SceneScratch,
    ) -> Result<Trajectory, MotionError> {
        let mut motion = CertifiedMotion::new(
            problem.validity,
            self.options.step,
            self.options.collision_resolution,
        );
        self.solve_with(problem, &mut motion, rng, stop, scratch)
    }
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
struct Rrt<'c, 'v> {
    validity: &'v dyn StateValidity,
    motion: &'c mut dyn MotionValidity,
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
            self.motion.check_motion(from, &self.new, scratch)?
        } else {
            // The edge runs from the new node to its parent: check the new node itself
            // first, then the edge as the trajectory will run along it.
            self.validity.is_valid(&self.new, scratch)?
                && self.motion.check_motion(&self.new, from, scratch)?
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
pub(super) fn sampling_ranges(
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

/// RRT-Connect from `start` to `goal`; the path's waypoints flat, start first. `stop` is
/// checked at the start of every iteration.
#[allow(clippy::too_many_arguments)]
fn rrt_connect(
    rrt: &mut Rrt<'_, '_>,
    start: &[f64],
    goal: &[f64],
    ranges: &[(f64, f64)],
    options: &MotionOptions,
    rng: &mut ChaCha8Rng,
    stop: &Termination,
    scratch: &mut SceneScratch,
) -> Result<Option<Vec<f64>>, MotionError> {
    let dim = start.len();
    let mut trees = [Tree::new(start, true), Tree::new(goal, false)];
    // Which tree grows towards the sample this iteration; the other connects to it.
    let mut active = 0;
    let mut sample = vec![0.0; dim];
    let mut reached = vec![0.0; dim];
    for iteration in 0..options.max_iterations {
        if stop.should_stop() {
            return Err(MotionError::Terminated {
                iterations: iteration,
            });
        }
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
