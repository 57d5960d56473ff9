//! Inverse kinematics: damped least squares with Levenberg-Marquardt damping, joint
//! limits, seeded restarts and the caller's termination condition (see the parent
//! module's documentation), and the generic solver core the closed-chain solver shares.

use std::fmt;

use nalgebra as na;
use rand_chacha::ChaCha8Rng;

use super::rotation_log;
use crate::math::{Iso, Point};
use crate::robot::Robot;
use crate::termination::Termination;

/// What an inverse-kinematics solve should reach.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum IkTarget {
    /// The tip link's full pose (world frame).
    Pose(Iso),
    /// Only the position of the tip link's origin (world frame); its orientation is free.
    Position(Point),
}

/// Parameters of the inverse-kinematics solvers.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IkOptions {
    /// Iterations of one try (one start configuration) before giving up on it; a rejected
    /// Levenberg-Marquardt step counts as an iteration.
    pub max_iterations: usize,
    /// Random restarts after the try from the seed: at most `1 + restarts` tries.
    pub restarts: usize,
    /// The largest accepted tip position error, metres.
    pub position_tolerance: f64,
    /// The largest accepted tip rotation error, radians.
    pub rotation_tolerance: f64,
    /// The initial Levenberg-Marquardt damping λ (adapted as the solve goes).
    pub damping: f64,
    /// The largest change of any one joint in one step (radians or metres): keeps early
    /// steps, taken where the linearisation is poor, from flinging the arm around.
    pub max_step: f64,
}

impl Default for IkOptions {
    fn default() -> Self {
        IkOptions {
            max_iterations: 100,
            restarts: 50,
            position_tolerance: 1e-4,
            rotation_tolerance: 1e-3,
            damping: 0.1,
            max_step: 1.0,
        }
    }
}

/// Why inverse kinematics gave no configuration.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum IkError {
    /// No try reached the tolerances; the errors are those of the best try.
    NotConverged {
        /// How many start configurations were tried.
        tries: usize,
        /// The best try's position error, metres.
        position_error: f64,
        /// The best try's rotation error, radians (0 for a position-only target).
        rotation_error: f64,
    },
    /// The termination condition stopped the restarts before any try converged.
    Terminated {
        /// How many start configurations were tried.
        tries: usize,
    },
    /// A seed configuration does not have one value per joint.
    SeedLength {
        /// The number of joints.
        expected: usize,
        /// The seed's length.
        got: usize,
    },
}

impl fmt::Display for IkError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            IkError::NotConverged {
                tries,
                position_error,
                rotation_error,
            } => write!(
                f,
                "inverse kinematics did not converge in {tries} tries (best: {position_error:.2e} m, \
                 {rotation_error:.2e} rad off)"
            ),
            IkError::Terminated { tries } => {
                write!(f, "inverse kinematics was stopped after {tries} tries")
            }
            IkError::SeedLength { expected, got } => write!(
                f,
                "the seed has {got} joint values, the robot has {expected} joints"
            ),
        }
    }
}

impl std::error::Error for IkError {}

/// Finds a configuration within the joint limits that puts the tip of `robot` (placed
/// at `base`) on `target`, trying first from `seed` and then from random configurations
/// drawn with `rng`.
///
/// The result reaches the target within `opts`' tolerances and lies within the limits;
/// the same `rng` state and inputs always give the same result. `stop` is checked before
/// every restart.
pub fn solve_ik(
    robot: &Robot,
    base: &Iso,
    target: &IkTarget,
    seed: &[f64],
    rng: &mut ChaCha8Rng,
    opts: &IkOptions,
    stop: &Termination,
) -> Result<Vec<f64>, IkError> {
    let n = robot.n_joints();
    if seed.len() != n {
        return Err(IkError::SeedLength {
            expected: n,
            got: seed.len(),
        });
    }
    let (lower, upper) = robot.limits();
    let mut start = seed.to_vec();
    robot.clamp_to_limits(&mut start);
    match target {
        IkTarget::Pose(pose) => {
            let mut problem = PoseResidual {
                robot,
                base,
                target: *pose,
                position_tolerance: opts.position_tolerance,
                rotation_tolerance: opts.rotation_tolerance,
                frames: Vec::with_capacity(n + 1),
            };
            let mut buffers = LmBuffers::new(n);
            solve_with_restarts(
                &mut problem,
                &mut buffers,
                &start,
                (lower, upper),
                opts,
                stop,
                |q| robot.sample_configuration(rng, q),
            )
            .map_err(|failure| match failure {
                Unsolved::Terminated { tries } => IkError::Terminated { tries },
                Unsolved::NotConverged { tries, best: r } => IkError::NotConverged {
                    tries,
                    position_error: r.fixed_rows::<3>(0).norm(),
                    rotation_error: r.fixed_rows::<3>(3).norm(),
                },
            })
        }
        IkTarget::Position(point) => {
            let mut problem = PositionResidual {
                robot,
                base,
                target: *point,
                position_tolerance: opts.position_tolerance,
                frames: Vec::with_capacity(n + 1),
            };
            let mut buffers = LmBuffers::new(n);
            solve_with_restarts(
                &mut problem,
                &mut buffers,
                &start,
                (lower, upper),
                opts,
                stop,
                |q| robot.sample_configuration(rng, q),
            )
            .map_err(|failure| match failure {
                Unsolved::Terminated { tries } => IkError::Terminated { tries },
                Unsolved::NotConverged { tries, best: r } => IkError::NotConverged {
                    tries,
                    position_error: r.norm(),
                    rotation_error: 0.0,
                },
            })
        }
    }
}

/// Why [`solve_with_restarts`] found nothing.
enum Unsolved<const R: usize> {
    /// Every try ended away from the target; the residual of the best one.
    NotConverged {
        tries: usize,
        best: na::SVector<f64, R>,
    },
    /// The termination condition stopped the restarts.
    Terminated { tries: usize },
}

/// Runs [`lm_solve`] from `start`, then from up to `opts.restarts` configurations drawn
/// by `sample`, checking `stop` before each restart.
fn solve_with_restarts<const R: usize, P: Residual<R>>(
    problem: &mut P,
    buffers: &mut LmBuffers<R>,
    start: &[f64],
    (lower, upper): (&[f64], &[f64]),
    opts: &IkOptions,
    stop: &Termination,
    mut sample: impl FnMut(&mut [f64]),
) -> Result<Vec<f64>, Unsolved<R>> {
    let mut q = start.to_vec();
    let mut best: Option<na::SVector<f64, R>> = None;
    for attempt in 0..=opts.restarts {
        if attempt > 0 {
            if stop.should_stop() {
                return Err(Unsolved::Terminated { tries: attempt });
            }
            sample(&mut q);
        }
        let outcome = lm_solve(problem, buffers, &mut q, lower, upper, opts);
        if outcome.converged {
            return Ok(q);
        }
        if best.is_none_or(|b| outcome.residual.norm_squared() < b.norm_squared()) {
            best = Some(outcome.residual);
        }
    }
    Err(Unsolved::NotConverged {
        tries: opts.restarts + 1,
        best: best.unwrap_or_else(na::SVector::zeros),
    })
}

/// A least-squares problem over joint values: a residual with `R` rows to drive to zero.
pub(crate) trait Residual<const R: usize> {
    /// Writes the residual at `q` into `r` and its derivative by `q[j]` into `columns[j]`.
    fn eval(&mut self, q: &[f64], r: &mut na::SVector<f64, R>, columns: &mut [na::SVector<f64, R>]);
    /// Whether the residual is good enough to stop.
    fn done(&self, r: &na::SVector<f64, R>) -> bool;
}

/// Scratch space of [`lm_solve`], allocated once per solve so the iterations don't
/// allocate.
pub(crate) struct LmBuffers<const R: usize> {
    q_try: Vec<f64>,
    step: Vec<f64>,
    columns: Vec<na::SVector<f64, R>>,
    columns_try: Vec<na::SVector<f64, R>>,
    active: Vec<bool>,
}

impl<const R: usize> LmBuffers<R> {
    /// Buffers for `n` unknowns.
    pub(crate) fn new(n: usize) -> Self {
        LmBuffers {
            q_try: vec![0.0; n],
            step: vec![0.0; n],
            columns: vec![na::SVector::zeros(); n],
            columns_try: vec![na::SVector::zeros(); n],
            active: vec![true; n],
        }
    }
}

/// How one try ended.
pub(crate) struct LmOutcome<const R: usize> {
    /// Whether the residual satisfied [`Residual::done`].
    pub(crate) converged: bool,
    /// The residual at the final configuration.
    pub(crate) residual: na::SVector<f64, R>,
}

/// The damping never drops below this (keeps `J Jᵀ + λ I` safely positive definite).
const MIN_DAMPING: f64 = 1e-9;
/// A try whose damping must grow beyond this to make progress is stuck in a local
/// minimum (or against a limit) and is abandoned.
const MAX_DAMPING: f64 = 1e4;
/// Accepted steps that lower the squared error by less than this fraction count as no
/// progress; this many in a row end the try.
const MIN_PROGRESS: f64 = 1e-5;
const MAX_IDLE_STEPS: usize = 8;

/// One Levenberg-Marquardt try from `q` (updated in place to the final configuration,
/// always within `lower..=upper`).
pub(crate) fn lm_solve<const R: usize, P: Residual<R>>(
    problem: &mut P,
    buffers: &mut LmBuffers<R>,
    q: &mut [f64],
    lower: &[f64],
    upper: &[f64],
    opts: &IkOptions,
) -> LmOutcome<R> {
    let n = q.len();
    for j in 0..n {
        q[j] = q[j].clamp(lower[j], upper[j]);
    }
    let mut r = na::SVector::<f64, R>::zeros();
    let mut r_try = na::SVector::<f64, R>::zeros();
    problem.eval(q, &mut r, &mut buffers.columns);
    let mut cost = r.norm_squared();
    let mut damping = opts.damping.max(MIN_DAMPING);
    let mut idle = 0;
    for _ in 0..opts.max_iterations {
        if problem.done(&r) {
            return LmOutcome {
                converged: true,
                residual: r,
            };
        }
        // The step, with joints resting on a limit that it would push further out left
        // out of the system: solve once with every joint, and once more without those.
        // A joint that only the second solve would push out is simply clamped.
        buffers.active.fill(true);
        let mut solved = false;
        for _round in 0..2 {
            // Only the lower triangle: the Cholesky factorisation reads nothing else, and
            // these rank-one updates are most of an iteration's arithmetic (17% less CPU
            // for the assembly line's verification, with the same bits as full products).
            let mut system = na::SMatrix::<f64, R, R>::identity() * damping;
            for (column, _) in buffers
                .columns
                .iter()
                .zip(&buffers.active)
                .filter(|(_, &active)| active)
            {
                system.syger(1.0, column, column, 1.0);
            }
            let Some(cholesky) = system.cholesky() else {
                break;
            };
            let y = cholesky.solve(&r);
            let mut pinned = false;
            for j in 0..n {
                let step = if buffers.active[j] {
                    -buffers.columns[j].dot(&y)
                } else {
                    0.0
                };
                buffers.step[j] = step;
                let at_lower = q[j] <= lower[j] && step < 0.0;
                let at_upper = q[j] >= upper[j] && step > 0.0;
                if buffers.active[j] && (at_lower || at_upper) {
                    buffers.active[j] = false;
                    pinned = true;
                }
            }
            solved = true;
            if !pinned {
                break;
            }
        }
        if !solved {
            break;
        }
        let largest = buffers.step.iter().fold(0.0f64, |m, s| m.max(s.abs()));
        let scale = if largest > opts.max_step {
            opts.max_step / largest
        } else {
            1.0
        };
        for j in 0..n {
            buffers.q_try[j] = (q[j] + scale * buffers.step[j]).clamp(lower[j], upper[j]);
        }
        problem.eval(&buffers.q_try, &mut r_try, &mut buffers.columns_try);
        let cost_try = r_try.norm_squared();
        if cost_try < cost {
            if cost - cost_try < MIN_PROGRESS * cost {
                idle += 1;
                if idle >= MAX_IDLE_STEPS {
                    q.copy_from_slice(&buffers.q_try);
                    r = r_try;
                    break;
                }
            } else {
                idle = 0;
            }
            q.copy_from_slice(&buffers.q_try);
            std::mem::swap(&mut buffers.columns, &mut buffers.columns_try);
            r = r_try;
            cost = cost_try;
            damping = (damping * 0.3).max(MIN_DAMPING);
        } else {
            damping *= 4.0;
            if damping > MAX_DAMPING || !cost_try.is_finite() {
                break;
            }
        }
    }
    LmOutcome {
        converged: problem.done(&r),
        residual: r,
    }
}

/// Tip pose minus target: position (rows 0..3) and rotation vector (rows 3..6).
struct PoseResidual<'a> {
    robot: &'a Robot,
    base: &'a Iso,
    target: Iso,
    position_tolerance: f64,
    rotation_tolerance: f64,
    frames: Vec<Iso>,
}

impl Residual<6> for PoseResidual<'_> {
    fn eval(&mut self, q: &[f64], r: &mut na::Vector6<f64>, columns: &mut [na::Vector6<f64>]) {
        self.robot.fk_frames(self.base, q, &mut self.frames);
        let tip = self.frames[self.robot.n_joints()] * self.robot.tip_offset();
        let position = tip.translation.vector - self.target.translation.vector;
        let rotation = rotation_log(&(tip.rotation * self.target.rotation.inverse()));
        r.fixed_rows_mut::<3>(0).copy_from(&position);
        r.fixed_rows_mut::<3>(3).copy_from(&rotation);
        self.robot.point_jacobian(
            &self.frames,
            &Point::from(tip.translation.vector),
            |j, linear, angular| {
                columns[j].fixed_rows_mut::<3>(0).copy_from(&linear);
                columns[j].fixed_rows_mut::<3>(3).copy_from(&angular);
            },
        );
    }

    fn done(&self, r: &na::Vector6<f64>) -> bool {
        r.fixed_rows::<3>(0).norm() <= self.position_tolerance
            && r.fixed_rows::<3>(3).norm() <= self.rotation_tolerance
    }
}

/// Tip origin minus target point.
struct PositionResidual<'a> {
    robot: &'a Robot,
    base: &'a Iso,
    target: Point,
    position_tolerance: f64,
    frames: Vec<Iso>,
}

impl Residual<3> for PositionResidual<'_> {
    fn eval(&mut self, q: &[f64], r: &mut na::Vector3<f64>, columns: &mut [na::Vector3<f64>]) {
        self.robot.fk_frames(self.base, q, &mut self.frames);
        let tip = self.frames[self.robot.n_joints()] * self.robot.tip_offset();
        *r = tip.translation.vector - self.target.coords;
        self.robot.point_jacobian(
            &self.frames,
            &Point::from(tip.translation.vector),
            |j, linear, _| columns[j] = linear,
        );
    }

    fn done(&self, r: &na::Vector3<f64>) -> bool {
        r.norm() <= self.position_tolerance
    }
}
