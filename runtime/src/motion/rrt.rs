//! [`RrtConnect`], the default [`MotionPlanner`]: RRT-Connect (Kuffner and LaValle, 2000)
//! in the combined joint space of the arms that move together, its trees grown lazily
//! (`tree.rs`), the path shortened and then checked (`shortcut.rs`), in rounds until a
//! path survives.

use rand_chacha::ChaCha8Rng;

use super::problem::{check_options, check_timing};
use super::segment::DiscreteMotion;
use super::shortcut::{dedup_waypoints, shortcut};
use super::timing::{time_path, MotionLimits};
use super::tree::Search;
use super::{
    CertifiedMotion, Joints, MotionError, MotionOptions, MotionPlanner, MotionProblem,
    MotionValidity,
};
use crate::plan::Trajectory;
use crate::scene::Scene;
use crate::termination::Termination;
use crate::validity::{arm_slices, out_of_limits, ArmSlice, StateFault};

/// Resolution (rad, per joint) of the sampled check a shortcut must pass before it is
/// taken (and certified only if it survives; see `shortcut.rs`). Coarse: the screen only
/// keeps shortcuts that would be refused from costing a certification, and the
/// certification decides. 0.03 and 0.25 rad measured no better on the cage.
const SCREEN: f64 = 0.1;

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
    pub fn solve_with<S>(
        &self,
        problem: &MotionProblem<'_, S>,
        motion: &mut dyn MotionValidity<Scratch = S>,
        rng: &mut ChaCha8Rng,
        stop: &Termination,
        scratch: &mut S,
    ) -> Result<Trajectory, MotionError> {
        let path = self.path_with(problem, motion, rng, stop, scratch)?;
        let scene = problem.scene;
        let dim = problem.start.len();
        let mut limits = MotionLimits::default();
        for s in &arm_slices(scene, problem.arms)? {
            limits.push(scene.robots[s.robot].rate_limits());
        }
        time_path(
            &path,
            dim,
            problem.arms,
            &limits,
            &self.options,
            &problem.timing,
            problem.validity,
            scratch,
        )
    }

    /// The certified path that [`MotionPlanner::solve`] times, before it is smoothed and
    /// timed: its waypoints, the arms' joints concatenated (`problem.start.len()` values
    /// each), from exactly `start` to exactly `goal`, consecutive ones distinct, every
    /// segment between two of them certified by [`CertifiedMotion`]. The same generator
    /// state gives the path that `solve` would time
    /// ([`smooth_waypoints`](super::smooth_waypoints) and
    /// [`time_smoothed`](super::time_smoothed) time it the same way), so another timing
    /// can be compared on it.
    ///
    /// # Errors
    /// As [`MotionPlanner::solve`], but for the timing's.
    pub fn path<S>(
        &self,
        problem: &MotionProblem<'_, S>,
        rng: &mut ChaCha8Rng,
        stop: &Termination,
        scratch: &mut S,
    ) -> Result<Vec<f64>, MotionError> {
        let mut motion = CertifiedMotion::new(
            problem.validity,
            self.options.step,
            self.options.collision_resolution,
        );
        self.path_with(problem, &mut motion, rng, stop, scratch)
    }

    /// [`RrtConnect::path`] with segments checked by `motion`.
    fn path_with<S>(
        &self,
        problem: &MotionProblem<'_, S>,
        motion: &mut dyn MotionValidity<Scratch = S>,
        rng: &mut ChaCha8Rng,
        stop: &Termination,
        scratch: &mut S,
    ) -> Result<Vec<f64>, MotionError> {
        let options = &self.options;
        check_options(options)?;
        check_timing(&problem.timing)?;
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
            let mut search = Search::new(problem.validity, options.step, start, goal);
            let mut screen = DiscreteMotion::new(problem.validity, f64::INFINITY, SCREEN);
            path = loop {
                let found = search.next_path(&ranges, options, rng, stop, scratch)?;
                let Some((mut found, edges)) = found else {
                    return Err(MotionError::NoPath {
                        iterations: options.max_iterations,
                    });
                };
                let mut accepted: Vec<bool> = edges.iter().map(|&e| search.checked(e)).collect();
                let refused = shortcut(
                    motion,
                    &mut screen,
                    &mut found,
                    dim,
                    &mut accepted,
                    options.shortcut_iterations,
                    rng,
                    stop,
                    scratch,
                )
                .map_err(|e| match e {
                    // Stopped while shortening or checking: say how far the search got.
                    MotionError::Terminated { .. } => MotionError::Terminated {
                        iterations: search.iterations(),
                    },
                    e => e,
                })?;
                for (&edge, &ok) in edges.iter().zip(&accepted) {
                    if ok {
                        search.accept(edge);
                    }
                }
                match refused {
                    None => break found,
                    Some(e) => search.refuse(edges[e]),
                }
            };
        }
        dedup_waypoints(&mut path, dim);
        Ok(path)
    }
}

impl<S> MotionPlanner<S> for RrtConnect {
    /// A collision-free, timed joint motion of `problem.arms` from `problem.start` to
    /// `problem.goal`. The result starts at time 0 with `start` and ends with exactly
    /// `goal`; consecutive points differ by at most `options.step` per joint and every
    /// joint respects the speed and acceleration limits. When start and goal are equal it
    /// has that one point.
    fn solve(
        &self,
        problem: &MotionProblem<'_, S>,
        rng: &mut ChaCha8Rng,
        stop: &Termination,
        scratch: &mut S,
    ) -> Result<Trajectory, MotionError> {
        let mut motion = CertifiedMotion::new(
            problem.validity,
            self.options.step,
            self.options.collision_resolution,
        );
        self.solve_with(problem, &mut motion, rng, stop, scratch)
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
