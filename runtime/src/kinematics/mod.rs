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
//! caller's [`Termination`](crate::termination::Termination) is checked before every restart, so a request out of time
//! stops within one try ([`IkError::Terminated`]).
//!
//! The solver core (`lm_solve`) is generic over the residual, so the closed-chain
//! handoff solver in [`crate::kinematics::closed_chain`] uses the same machinery.

pub mod closed_chain;
mod ik;

pub(crate) use ik::{lm_solve, LmBuffers, Residual};
pub use ik::{solve_ik, IkError, IkOptions, IkTarget};

use nalgebra as na;
use rand::Rng;

use crate::math::{Iso, Point, Quat, Vec3};
use crate::robot::{JointKind, Robot};

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
/// Draws a configuration uniformly inside `robot`'s sampling ranges (a convenience over
/// [`Robot::sample_configuration`]).
pub fn random_configuration<R: Rng + ?Sized>(robot: &Robot, rng: &mut R) -> Vec<f64> {
    let mut q = vec![0.0; robot.n_joints()];
    robot.sample_configuration(rng, &mut q);
    q
}
