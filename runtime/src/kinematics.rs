//! Forward kinematics, Jacobians and inverse kinematics of a [`Robot`].
//!
//! Inverse kinematics is damped least squares with Levenberg-Marquardt damping: each
//! step solves `(J Jᵀ + λ I) y = r`, `Δq = -Jᵀ y` in the task space (6 x 6 for a pose,
//! 3 x 3 for a position), so the linear algebra is fixed-size and allocation-free however
//! many joints the arm has. λ shrinks after a step that lowers the error and grows after
//! one that does not (the step is then rejected), which gives Gauss-Newton speed near a
//! solution and gradient-descent safety far from one or near a singularity. Joint limits
//! are enforced by clamping every step; a joint resting on a limit whose step would push
//! it further out is dropped from that step's system, so the other joints take up the
//! motion instead of the step stalling against the limit. A try that stalls or runs out
//! of iterations is followed by a restart from a configuration drawn uniformly inside the
//! limits with the caller's seeded RNG, so the result depends on the seed only. The
//! caller's [`Termination`] is checked before every restart, so a request out of time
//! stops within one try ([`IkError::Terminated`]).
//!
//! The solver core (`lm_solve`) is generic over the residual, so the closed-chain
//! handoff solver in [`crate::closed_chain`] uses the same machinery.

use std::fmt;

use nalgebra as na;
use rand::Rng;
use rand_chacha::ChaCha8Rng;

use crate::math::{Iso, Point, Quat, Vec3};
use crate::robot::{JointKind, Robot};
use crate::termination::Termination;

impl Robot {
    /// World poses of frames 0..=n (frame 0 = the base link placed at `base`) for the
    /// configuration `q`, written into `frames` (resized to `n + 1`; reuse the buffer in
    /// loops to avoid allocating).
    ///
    /// # Panics
    /// If `q.len() != self.n_joints()`: that is a caller bug, not bad data.
    pub fn fk_frames(&self, base: &Iso, q: &[f64], frames: &mut Vec<Iso>) {
        let n = self.n_joints();
        assert_eq!(
            q.len(),
            n,
            "configuration length must equal the number of joints"
        );
        frames.resize(n + 1, Iso::identity());
        frames[0] = *base;
        let origins = self.origins();
        let axes = self.axes();
        let kinds = self.joint_kinds();
        for j in 0..n {
            let joint_frame = frames[j] * origins[j];
            frames[j + 1] = joint_motion(&joint_frame, kinds[j], &axes[j], q[j]);
        }
    }

    /// The world pose of the tip link for configuration `q`.
    ///
    /// # Panics
    /// If `q.len() != self.n_joints()`.
    pub fn tip_pose(&self, base: &Iso, q: &[f64]) -> Iso {
        let n = self.n_joints();
        assert_eq!(
            q.len(),
            n,
            "configuration length must equal the number of joints"
        );
        let origins = self.origins();
        let axes = self.axes();
        let kinds = self.joint_kinds();
        let mut frame = *base;
        for j in 0..n {
            frame = joint_motion(&(frame * origins[j]), kinds[j], &axes[j], q[j]);
        }
        frame * self.tip_offset()
    }

    /// The geometric Jacobian of the tip (6 x n): rows 0..3 the tip origin's linear
    /// velocity, rows 3..6 the tip's angular velocity, both in the world frame, per unit
    /// joint velocity.
    ///
    /// # Panics
    /// If `q.len() != self.n_joints()`.
    pub fn jacobian(&self, base: &Iso, q: &[f64]) -> na::Matrix6xX<f64> {
        let mut frames = Vec::with_capacity(self.n_joints() + 1);
        self.fk_frames(base, q, &mut frames);
        let tip = frames[self.n_joints()] * self.tip_offset();
        let mut jacobian = na::Matrix6xX::zeros(self.n_joints());
        self.point_jacobian(
            &frames,
            &Point::from(tip.translation.vector),
            |j, linear, angular| {
                jacobian.fixed_view_mut::<3, 1>(0, j).copy_from(&linear);
                jacobian.fixed_view_mut::<3, 1>(3, j).copy_from(&angular);
            },
        );
        jacobian
    }

    /// The Jacobian columns of a world point moving rigidly with the last frame, from
    /// frames computed by [`Robot::fk_frames`]: calls `column(j, linear, angular)` for
    /// each joint `j`. Allocation-free, for inner loops.
    pub fn point_jacobian(
        &self,
        frames: &[Iso],
        point: &Point,
        mut column: impl FnMut(usize, Vec3, Vec3),
    ) {
        let axes = self.axes();
        for (j, kind) in self.joint_kinds().iter().enumerate() {
            // Frame j + 1 is joint j's frame after its motion; a joint's motion leaves its
            // own axis (and, for a turning joint, its origin) where they are.
            let frame = &frames[j + 1];
            let axis = frame.rotation * axes[j];
            match kind {
                JointKind::Prismatic => column(j, axis, Vec3::zeros()),
                JointKind::Revolute | JointKind::Continuous => {
                    let lever = point.coords - frame.translation.vector;
                    column(j, axis.cross(&lever), axis);
                }
            }
        }
    }
}

/// `joint_frame` moved by joint value `q` about / along `axis`.
#[inline]
fn joint_motion(joint_frame: &Iso, kind: JointKind, axis: &Vec3, q: f64) -> Iso {
    match kind {
        JointKind::Prismatic => Iso::from_parts(
            na::Translation3::from(
                joint_frame.translation.vector + joint_frame.rotation * (axis * q),
            ),
            joint_frame.rotation,
        ),
        JointKind::Revolute | JointKind::Continuous => {
            // The axis is unit by construction (normalised when the URDF was read).
            let (sin, cos) = (0.5 * q).sin_cos();
            let turn = Quat::new_unchecked(na::Quaternion::new(
                cos,
                axis.x * sin,
                axis.y * sin,
                axis.z * sin,
            ));
            Iso::from_parts(joint_frame.translation, joint_frame.rotation * turn)
        }
    }
}

/// The rotation vector (axis times angle, angle in [0, pi]) of `rotation`: the shortest
/// turn that gives it. Cheaper than going through `axis()` and `angle()` separately.
#[inline]
pub fn rotation_log(rotation: &Quat) -> Vec3 {
    let q = rotation.quaternion();
    let (w, v) = if q.w >= 0.0 {
        (q.w, q.imag())
    } else {
        (-q.w, -q.imag())
    };
    let s = v.norm();
    if s < 1e-12 {
        // sin(θ/2) ≈ θ/2 for tiny angles: θ·axis ≈ 2·v.
        v * 2.0
    } else {
        v * (2.0 * s.atan2(w) / s)
    }
}

/// The position error (metres) and rotation error (radians) between two poses.
pub fn pose_error(a: &Iso, b: &Iso) -> (f64, f64) {
    (
        (a.translation.vector - b.translation.vector).norm(),
        a.rotation.angle_to(&b.rotation),
    )
}

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
            let mut system = na::SMatrix::<f64, R, R>::identity() * damping;
            for (column, _) in buffers
                .columns
                .iter()
                .zip(&buffers.active)
                .filter(|(_, &active)| active)
            {
                system += column * column.transpose();
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

/// Draws a configuration uniformly inside `robot`'s sampling ranges (a convenience over
/// [`Robot::sample_configuration`]).
pub fn random_configuration<R: Rng + ?Sized>(robot: &Robot, rng: &mut R) -> Vec<f64> {
    let mut q = vec![0.0; robot.n_joints()];
    robot.sample_configuration(rng, &mut q);
    q
}
