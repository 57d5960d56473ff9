//! Handoff poses: two end-effectors holding one object at once (method.md, "Planning a
//! move request", step 5).
//!
//! The two chains plus the object form one closed chain: base of A -> A's tip -> object
//! -> B's tip -> base of B. Its unknowns are both arms' joints stacked (`n_a + n_b`), and
//! it is solved like single-arm IK (the same Levenberg-Marquardt core, joint limits,
//! seeded random restarts, see [`crate::kinematics`]) on a 12-row residual:
//!
//! - rows 0..6, the loop closure: the object pose through A, `X_a = tip_a(qa) * grasp_a`,
//!   minus the one through B, `X_b = tip_b(qb) * grasp_b` (position, rotation vector);
//! - rows 6..9, a soft pull of the object (the midpoint of the two estimates) towards the
//!   caller's target point, weighted by [`HandoffOptions::target_weight`]; with 6 closure
//!   constraints and 7 + 7 joints this is usually satisfiable exactly, and it keeps the
//!   object inside the handoff workspace as the original system kept it near the centre;
//! - rows 9..12, a penalty on the object leaving the caller's box (zero inside it).
//!
//! A try first solves with the target pull and succeeds at once if the loop closes with
//! the object within [`HandoffOptions::target_tolerance`] of the target. Otherwise (the
//! target is out of reach, or the try settled in a compromise between closure and pull)
//! it polishes from where it stopped without the pull, so the loop closes to the
//! tolerances; such a solution far from the target is kept as a fallback while a few
//! more tries ([`HandoffOptions::target_attempts`]) look for one near it. Loop closure
//! and the bounds are hard requirements; the target is a preference.
//!
//! The caller's [`Termination`] is checked before every try after the first, as in
//! single-arm IK.
//!
//! B may be any chain, including a 1-DoF prismatic conveyor: then `grasp_b` is the
//! object's resting pose on the conveyor's tip and the solve finds where the carriage and
//! arm A meet.

use nalgebra as na;
use rand_chacha::ChaCha8Rng;

use crate::kinematics::{lm_solve, rotation_log, IkError, IkOptions, LmBuffers, Residual};
use crate::math::{Iso, Point, Vec3};
use crate::robot::Robot;
use crate::termination::Termination;

/// A handoff to solve: two placed chains, how each holds the object, and where the
/// object should be.
#[derive(Debug, Clone, Copy)]
pub struct HandoffProblem<'a> {
    /// The giving (or first) chain and its base pose in the world.
    pub a: (&'a Robot, Iso),
    /// The receiving (or second) chain and its base pose in the world.
    pub b: (&'a Robot, Iso),
    /// The object's pose in A's tip frame.
    pub grasp_a: Iso,
    /// The object's pose in B's tip frame (for a conveyor: its resting pose on the tip).
    pub grasp_b: Iso,
    /// Where the object should be (world), e.g. a point sampled in the handoff workspace.
    pub target: Point,
    /// An axis-aligned box (`min`, `max`, world) the object's position must end inside.
    pub bounds: Option<(Point, Point)>,
}

/// Parameters of [`solve_handoff`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HandoffOptions {
    /// Iterations, restarts, loop-closure tolerances (position and rotation between the
    /// object poses through A and through B), damping and step limit.
    pub ik: IkOptions,
    /// The weight of the object-to-target distance relative to the loop-closure error
    /// (0 turns the pull off).
    pub target_weight: f64,
    /// A solution whose object is this close to the target (metres) is returned at once.
    pub target_tolerance: f64,
    /// Once a try has closed the loop (inside the bounds) but left the object farther
    /// than `target_tolerance` from the target, at most this many more tries look for a
    /// closer one before the closest found is returned: the target is a preference, and
    /// an unreachable one must not cost every restart.
    pub target_attempts: usize,
    /// The weight of the object's distance outside `bounds`.
    pub bounds_weight: f64,
}

impl Default for HandoffOptions {
    fn default() -> Self {
        HandoffOptions {
            ik: IkOptions {
                max_iterations: 200,
                restarts: 100,
                ..IkOptions::default()
            },
            target_weight: 1.0,
            target_tolerance: 0.01,
            target_attempts: 10,
            bounds_weight: 1.0,
        }
    }
}

/// A solved handoff.
#[derive(Debug, Clone, PartialEq)]
pub struct HandoffSolution {
    /// A's joint values.
    pub qa: Vec<f64>,
    /// B's joint values.
    pub qb: Vec<f64>,
    /// The object's world pose (through A; through B it agrees within the tolerances).
    pub object: Iso,
}

/// Finds joint values for both chains such that they hold the object at the same pose
/// (within `opts.ik`'s tolerances), inside `problem.bounds` if given, within both chains'
/// joint limits, and preferably within `opts.target_tolerance` of `problem.target`
/// (otherwise as close as the tries found). Tries first from (`seed_a`, `seed_b`), then
/// from random configurations drawn with `rng`; the same inputs and `rng` state always
/// give the same result.
///
/// On failure, [`IkError::NotConverged`] carries the loop-closure error of the best try
/// (the position and rotation difference between the object poses through A and B);
/// [`IkError::Terminated`] says `stop` ended the tries first.
pub fn solve_handoff(
    problem: &HandoffProblem<'_>,
    seed_a: &[f64],
    seed_b: &[f64],
    rng: &mut ChaCha8Rng,
    opts: &HandoffOptions,
    stop: &Termination,
) -> Result<HandoffSolution, IkError> {
    let (robot_a, base_a) = problem.a;
    let (robot_b, base_b) = problem.b;
    let (na_, nb) = (robot_a.n_joints(), robot_b.n_joints());
    for (robot, seed) in [(robot_a, seed_a), (robot_b, seed_b)] {
        if seed.len() != robot.n_joints() {
            return Err(IkError::SeedLength {
                expected: robot.n_joints(),
                got: seed.len(),
            });
        }
    }
    let (lower_a, upper_a) = robot_a.limits();
    let (lower_b, upper_b) = robot_b.limits();
    let lower: Vec<f64> = lower_a.iter().chain(lower_b).copied().collect();
    let upper: Vec<f64> = upper_a.iter().chain(upper_b).copied().collect();

    let mut residual = LoopResidual {
        problem,
        base_a,
        base_b,
        target_weight: opts.target_weight,
        target_tolerance: opts.target_tolerance,
        bounds_weight: opts.bounds_weight,
        position_tolerance: opts.ik.position_tolerance,
        rotation_tolerance: opts.ik.rotation_tolerance,
        frames_a: Vec::with_capacity(na_ + 1),
        frames_b: Vec::with_capacity(nb + 1),
    };
    let mut buffers = LmBuffers::<12>::new(na_ + nb);
    let mut q: Vec<f64> = seed_a.iter().chain(seed_b).copied().collect();
    let solution = |q: &[f64]| {
        let (qa, qb) = q.split_at(na_);
        HandoffSolution {
            qa: qa.to_vec(),
            qb: qb.to_vec(),
            object: robot_a.tip_pose(&base_a, qa) * problem.grasp_a,
        }
    };
    // The best try that closed the loop inside the bounds but left the object farther
    // than the target tolerance from the target: (distance, configuration).
    let mut fallback: Option<(f64, Vec<f64>)> = None;
    let mut tries_since_fallback = 0;
    // The loop-closure residual of the best try, for the error.
    let mut best: Option<na::SVector<f64, 12>> = None;
    let mut tries = 0;
    for attempt in 0..=opts.ik.restarts {
        if fallback.is_some() {
            if tries_since_fallback >= opts.target_attempts {
                break;
            }
            tries_since_fallback += 1;
        }
        if attempt > 0 {
            if stop.should_stop() {
                return Err(IkError::Terminated { tries });
            }
            let (qa, qb) = q.split_at_mut(na_);
            robot_a.sample_configuration(rng, qa);
            robot_b.sample_configuration(rng, qb);
        }
        tries += 1;
        residual.target_weight = opts.target_weight;
        let mut outcome = lm_solve(
            &mut residual,
            &mut buffers,
            &mut q,
            &lower,
            &upper,
            &opts.ik,
        );
        if outcome.converged {
            return Ok(solution(&q));
        }
        if !residual.acceptable(&outcome.residual) {
            // The pull may have held the loop open (a target out of reach competes with
            // closure, or the try settled in a compromise): close it without the pull,
            // from where the first phase ended.
            residual.target_weight = 0.0;
            outcome = lm_solve(
                &mut residual,
                &mut buffers,
                &mut q,
                &lower,
                &upper,
                &opts.ik,
            );
        }
        if residual.acceptable(&outcome.residual) {
            let (qa, _) = q.split_at(na_);
            let object = robot_a.tip_pose(&base_a, qa) * problem.grasp_a;
            let distance = (object.translation.vector - problem.target.coords).norm();
            if distance <= opts.target_tolerance {
                return Ok(solution(&q));
            }
            if fallback.as_ref().is_none_or(|(d, _)| distance < *d) {
                fallback = Some((distance, q.clone()));
            }
            continue;
        }
        let closure = |r: &na::SVector<f64, 12>| r.fixed_rows::<6>(0).norm_squared();
        if best.is_none_or(|b| closure(&outcome.residual) < closure(&b)) {
            best = Some(outcome.residual);
        }
    }
    if let Some((_, q)) = fallback {
        return Ok(solution(&q));
    }
    let best = best.unwrap_or_else(na::SVector::zeros);
    Err(IkError::NotConverged {
        tries,
        position_error: best.fixed_rows::<3>(0).norm(),
        rotation_error: best.fixed_rows::<3>(3).norm(),
    })
}

/// Whether `qa` and `qb` hold `problem`'s object at one pose: the loop closes within
/// `opts.ik`'s tolerances and the midpoint of the two estimates of the object's position
/// lies inside `problem.bounds` (within the position tolerance), the test
/// [`solve_handoff`] accepts a solution by. The target is a preference and is not tested.
/// For a solution found for a nearby problem (`verify` shares solves between grasp pairs
/// that are one problem up to rounding), this is what makes it one of this problem.
pub fn closes(problem: &HandoffProblem<'_>, qa: &[f64], qb: &[f64], opts: &HandoffOptions) -> bool {
    let (robot_a, base_a) = problem.a;
    let (robot_b, base_b) = problem.b;
    if qa.len() != robot_a.n_joints() || qb.len() != robot_b.n_joints() {
        return false;
    }
    closes_at(
        problem,
        &robot_a.tip_pose(&base_a, qa),
        &robot_b.tip_pose(&base_b, qb),
        opts,
    )
}

/// [`closes`] with the two tips' world poses already computed from the joints.
pub fn closes_at(
    problem: &HandoffProblem<'_>,
    tip_a: &Iso,
    tip_b: &Iso,
    opts: &HandoffOptions,
) -> bool {
    let object_a = tip_a * problem.grasp_a;
    let object_b = tip_b * problem.grasp_b;
    let pa = Point::from(object_a.translation.vector);
    let pb = Point::from(object_b.translation.vector);
    if (pa - pb).norm() > opts.ik.position_tolerance
        || rotation_log(&(object_a.rotation * object_b.rotation.inverse())).norm()
            > opts.ik.rotation_tolerance
    {
        return false;
    }
    let Some((min, max)) = problem.bounds else {
        return true;
    };
    let middle = na::center(&pa, &pb);
    let outside = Vec3::from_fn(|k, _| middle[k] - middle[k].clamp(min[k], max[k]));
    (outside * opts.bounds_weight).norm() <= opts.bounds_weight * opts.ik.position_tolerance
}

/// The closed chain's residual (see the module documentation for its rows).
struct LoopResidual<'p, 'a> {
    problem: &'p HandoffProblem<'a>,
    base_a: Iso,
    base_b: Iso,
    target_weight: f64,
    target_tolerance: f64,
    bounds_weight: f64,
    position_tolerance: f64,
    rotation_tolerance: f64,
    frames_a: Vec<Iso>,
    frames_b: Vec<Iso>,
}

impl LoopResidual<'_, '_> {
    /// Loop closed within the tolerances and the object inside the bounds.
    fn acceptable(&self, r: &na::SVector<f64, 12>) -> bool {
        r.fixed_rows::<3>(0).norm() <= self.position_tolerance
            && r.fixed_rows::<3>(3).norm() <= self.rotation_tolerance
            && self.inside_bounds(r)
    }

    fn inside_bounds(&self, r: &na::SVector<f64, 12>) -> bool {
        // Rows 9..12 are the weighted distance outside the box; allow the position
        // tolerance (the two estimates of the object's position differ by up to that).
        self.problem.bounds.is_none()
            || r.fixed_rows::<3>(9).norm() <= self.bounds_weight * self.position_tolerance
    }
}

impl Residual<12> for LoopResidual<'_, '_> {
    fn eval(
        &mut self,
        q: &[f64],
        r: &mut na::SVector<f64, 12>,
        columns: &mut [na::SVector<f64, 12>],
    ) {
        let (robot_a, _) = self.problem.a;
        let (robot_b, _) = self.problem.b;
        let (qa, qb) = q.split_at(robot_a.n_joints());
        robot_a.fk_frames(&self.base_a, qa, &mut self.frames_a);
        robot_b.fk_frames(&self.base_b, qb, &mut self.frames_b);
        let object_a =
            self.frames_a[robot_a.n_joints()] * robot_a.tip_offset() * self.problem.grasp_a;
        let object_b =
            self.frames_b[robot_b.n_joints()] * robot_b.tip_offset() * self.problem.grasp_b;
        let pa = Point::from(object_a.translation.vector);
        let pb = Point::from(object_b.translation.vector);
        let middle = na::center(&pa, &pb);

        r.fixed_rows_mut::<3>(0).copy_from(&(pa - pb));
        r.fixed_rows_mut::<3>(3).copy_from(&rotation_log(
            &(object_a.rotation * object_b.rotation.inverse()),
        ));
        r.fixed_rows_mut::<3>(6)
            .copy_from(&((middle - self.problem.target) * self.target_weight));
        // Outside the box: the distance per axis, and a 0/1 mask for the Jacobian.
        let mut outside = Vec3::zeros();
        let mut mask = Vec3::zeros();
        if let Some((min, max)) = self.problem.bounds {
            for k in 0..3 {
                let clamped = middle[k].clamp(min[k], max[k]);
                outside[k] = middle[k] - clamped;
                if outside[k] != 0.0 {
                    mask[k] = 1.0;
                }
            }
        }
        r.fixed_rows_mut::<3>(9)
            .copy_from(&(outside * self.bounds_weight));

        // The midpoint moves at half each object estimate's velocity.
        let pull = 0.5 * self.target_weight;
        let fence = 0.5 * self.bounds_weight;
        robot_a.point_jacobian(&self.frames_a, &pa, |j, linear, angular| {
            let column = &mut columns[j];
            column.fixed_rows_mut::<3>(0).copy_from(&linear);
            column.fixed_rows_mut::<3>(3).copy_from(&angular);
            column.fixed_rows_mut::<3>(6).copy_from(&(linear * pull));
            column
                .fixed_rows_mut::<3>(9)
                .copy_from(&(linear.component_mul(&mask) * fence));
        });
        let offset = robot_a.n_joints();
        robot_b.point_jacobian(&self.frames_b, &pb, |j, linear, angular| {
            let column = &mut columns[offset + j];
            column.fixed_rows_mut::<3>(0).copy_from(&(-linear));
            column.fixed_rows_mut::<3>(3).copy_from(&(-angular));
            column.fixed_rows_mut::<3>(6).copy_from(&(linear * pull));
            column
                .fixed_rows_mut::<3>(9)
                .copy_from(&(linear.component_mul(&mask) * fence));
        });
    }

    fn done(&self, r: &na::SVector<f64, 12>) -> bool {
        let near_target = self.target_weight == 0.0
            || r.fixed_rows::<3>(6).norm() <= self.target_weight * self.target_tolerance;
        self.acceptable(r) && near_target
    }
}
