//! Executing plans: an [`Executor`] trait for real drivers, a kinematic [`Simulator`]
//! that plays each motion by time as a joint-trajectory controller would (`playback.rs`),
//! and the paper's recovery rule (step 7 of Algorithm 1): when a step fails, if the
//! object is still where it started the request fails; otherwise the planner is asked
//! again from where the object is now.
//!
//! The simulator is a check of the plan, not an echo of it: the object's pose always
//! comes from the forward kinematics of whoever holds it, or from where a hand left it on
//! a surface, never from the pose written in a command. A grasp whose hand is not where
//! the object is, or a put-down that leaves the object floating higher than the request
//! calls resting, fails the step.

use cellc_schema::{Artifact, EndEffectorId, GraspId, Node, ObjectId};

use crate::math::Iso;
use crate::plan::planner::{Planner, WorldState};
use crate::plan::{Command, Plan, PlanError, PlanOptions, Step};
use crate::scene::{Holder, Scene};

mod playback;

pub use playback::Quantity;
use playback::{Fault, JointBounds, Slack};

/// Why an executor could not carry out a step.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum StepError {
    /// The motion leading to the command failed (blocked, a driver fault, ...).
    MotionFailed {
        /// What happened, for the report.
        reason: String,
    },
    /// A hand closed where the object is not: its grasp does not match the object's pose.
    GraspMissed {
        /// The grasping end-effector.
        holder: EndEffectorId,
        /// Distance between where the grasp puts the object and where it is, metres.
        position_error: f64,
        /// Orientation difference up to the object's symmetries, radians.
        rotation_error: f64,
    },
    /// A hand let go of the object where it does not rest on the receiving surface as
    /// the surface's resting pose says (and it would not fall onto it, see
    /// [`SimulatorTolerance::drop`]).
    NotResting {
        /// The surface.
        surface: EndEffectorId,
        /// Height error above the surface, metres.
        height_error: f64,
        /// Orientation error up to a turn about the vertical, radians.
        rotation_error: f64,
    },
    /// A command names a holder that does not hold the object.
    NotHolding {
        /// The end-effector the command names.
        holder: EndEffectorId,
        /// The one that holds the object.
        actual: EndEffectorId,
    },
    /// A motion ends elsewhere than the configuration its command states.
    MotionMismatch {
        /// The arm.
        arm: EndEffectorId,
        /// Largest joint difference, radians or metres.
        joint_error: f64,
    },
    /// Played by time, a motion takes a joint past one of its limits (position, speed,
    /// acceleration, a declared jerk), or a point states an acceleration its motion does
    /// not have.
    LimitExceeded {
        /// The arm.
        arm: EndEffectorId,
        /// The joint's name.
        joint: String,
        /// What is over the limit.
        quantity: Quantity,
        /// The value reached (signed).
        value: f64,
        /// The limit (a speed, acceleration or jerk limit is a magnitude).
        limit: f64,
        /// Seconds from the start of the motion.
        time: f64,
    },
    /// A point of a motion has the wrong number of values, a value that is not finite, or
    /// a time that does not come after the one before; or the motion moves an
    /// end-effector that is not an arm.
    MalformedTrajectory {
        /// Point index (0 for an end-effector that is not an arm).
        point: usize,
    },
}

impl std::fmt::Display for StepError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            StepError::MotionFailed { reason } => write!(f, "motion failed: {reason}"),
            StepError::GraspMissed {
                holder,
                position_error,
                rotation_error,
            } => write!(
                f,
                "end-effector #{} grasped {:.1} mm, {:.2} deg away from the object",
                holder.0,
                position_error * 1000.0,
                rotation_error.to_degrees()
            ),
            StepError::NotResting {
                surface,
                height_error,
                rotation_error,
            } => write!(
                f,
                "the object was let go {:.1} mm, {:.2} deg away from resting on surface #{}",
                height_error * 1000.0,
                rotation_error.to_degrees(),
                surface.0
            ),
            StepError::NotHolding { holder, actual } => write!(
                f,
                "end-effector #{} was commanded but #{} holds the object",
                holder.0, actual.0
            ),
            StepError::MotionMismatch { arm, joint_error } => write!(
                f,
                "the motion of arm #{} ends {joint_error:.4} away from its command",
                arm.0
            ),
            StepError::LimitExceeded {
                arm,
                joint,
                quantity: Quantity::StatedAcceleration,
                value,
                time,
                ..
            } => write!(
                f,
                "at {time:.3} s into its motion, a point states an acceleration of joint \
                 `{joint}` of arm #{} {value:.4} away from what the motion does there",
                arm.0
            ),
            StepError::LimitExceeded {
                arm,
                joint,
                quantity,
                value,
                limit,
                time,
            } => write!(
                f,
                "at {time:.3} s into its motion, joint `{joint}` of arm #{} reaches {} \
                 {value:.4}, over its limit {limit:.4}",
                arm.0,
                quantity.word()
            ),
            StepError::MalformedTrajectory { point } => {
                write!(f, "point {point} of the motion is malformed")
            }
        }
    }
}

/// Carries out steps on a robot cell (a driver) or a simulation of it.
pub trait Executor {
    /// Performs one step: the motion (if any), then the command.
    fn execute(&mut self, step: &Step) -> Result<(), StepError>;
    /// Where the object is now and who holds it, as far as the executor knows: the state
    /// to replan from after a failure.
    fn object_state(&self) -> ObservedObject;
    /// Current joint values of every arm (index = end-effector).
    fn arms(&self) -> Vec<Option<Vec<f64>>>;
}

/// The object as observed: its holder state and pose.
#[derive(Clone, Debug, PartialEq)]
pub struct ObservedObject {
    /// The state (holder, grasp, workspace).
    pub state: Node,
    /// The pose, when known.
    pub pose: Option<Iso>,
}

/// How far the simulator lets reality differ from a command before failing the step.
/// IK and loop closure converge to 0.1 mm and 1 mrad; these bounds are ten times that.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SimulatorTolerance {
    /// Metres.
    pub position: f64,
    /// Radians.
    pub rotation: f64,
    /// Joint units (radians or metres) between a motion's end and its command.
    pub joint: f64,
    /// Metres an object let go above its surface, in its resting orientation, falls onto
    /// it. The planner puts a request's goal down where the request says, and a goal
    /// within the request's [`PlanOptions::position_tolerance`] above the resting height
    /// counts as resting (a goal a little above a shelf keeps the carry that brings it
    /// clear of the shelf), so `cellc run` sets this to that tolerance: a put-down the
    /// planner accepts is one the simulator accepts. The object then rests where it
    /// fell, and the final error from the goal says how far that is.
    pub drop: f64,
    /// Share by which a motion may go over a joint's speed, acceleration or jerk limit.
    /// The planner imposes the limits at its profile's knots; on an arc of a smoothed
    /// corner the acceleration turns in between, which its margins cover to within a few
    /// percent (`tests/trajectory_limits.rs` measures it on every shipped cell).
    pub rate: f64,
}

impl Default for SimulatorTolerance {
    fn default() -> SimulatorTolerance {
        SimulatorTolerance {
            position: 1e-3,
            rotation: 1e-2,
            joint: 1e-6,
            // The default request's position tolerance.
            drop: 1e-2,
            rate: 0.05,
        }
    }
}

/// A kinematic simulator: arms follow trajectories, the object is attached to the holder
/// that grasped it last and detached when let go, and its pose follows the holder.
pub struct Simulator<'a> {
    artifact: &'a Artifact,
    scene: Option<&'a Scene>,
    object: ObjectId,
    state: Node,
    pose: Option<Iso>,
    /// Object pose in the holding arm's tip frame, while an arm holds it.
    grasp_in_tip: Option<Iso>,
    arms: Vec<Option<Vec<f64>>>,
    tolerance: SimulatorTolerance,
    /// Step index (counted over the whole run) whose motion fails, for tests.
    fail_at: Option<usize>,
    executed: usize,
    /// Seconds of motion played so far.
    clock: f64,
    /// What happened, one line per step.
    pub log: Vec<String>,
}

impl<'a> Simulator<'a> {
    /// A simulation of `object` starting in `state` at `pose`, arms at home.
    pub fn new(
        artifact: &'a Artifact,
        scene: Option<&'a Scene>,
        object: ObjectId,
        state: Node,
        pose: Option<Iso>,
    ) -> Simulator<'a> {
        let arms = WorldState::at_home(scene, artifact.end_effectors.len(), None).arms;
        Simulator::with_arms(artifact, scene, object, state, pose, arms)
    }

    /// A simulation of `object` starting in `state` at `pose`, every arm at the joints
    /// given (index = end-effector; `None` for those that are not arms): how a world's
    /// request is simulated.
    pub fn with_arms(
        artifact: &'a Artifact,
        scene: Option<&'a Scene>,
        object: ObjectId,
        state: Node,
        pose: Option<Iso>,
        arms: Vec<Option<Vec<f64>>>,
    ) -> Simulator<'a> {
        let mut simulator = Simulator {
            artifact,
            scene,
            object,
            state,
            pose,
            grasp_in_tip: None,
            arms,
            tolerance: SimulatorTolerance::default(),
            fail_at: None,
            executed: 0,
            clock: 0.0,
            log: Vec::new(),
        };
        // An object that starts in a hand sits where that hand's grasp puts it.
        if simulator.is_arm(state.end_effector) {
            let grasp = simulator.grasp_pose(state.grasp);
            if let Some(pose) = simulator.held(state.end_effector, &grasp) {
                simulator.grasp_in_tip = Some(grasp);
                simulator.pose = Some(pose);
            }
        }
        simulator
    }

    /// Makes the motion of step number `index` (0-based, over the whole run) fail.
    pub fn fail_motion_at(mut self, index: usize) -> Self {
        self.fail_at = Some(index);
        self
    }

    /// Replaces the default tolerances.
    pub fn with_tolerance(mut self, tolerance: SimulatorTolerance) -> Self {
        self.tolerance = tolerance;
        self
    }

    /// Seconds of motion played so far: the simulated clock, over every step executed
    /// (grasps and releases take no time here).
    pub fn motion_time(&self) -> f64 {
        self.clock
    }

    /// The object's current pose.
    pub fn object_pose(&self) -> Option<Iso> {
        self.pose
    }

    fn is_arm(&self, e: EndEffectorId) -> bool {
        self.scene
            .is_some_and(|s| matches!(s.holders.get(e.index()), Some(Holder::Arm { .. })))
    }

    fn tip(&self, e: EndEffectorId) -> Option<Iso> {
        let q = self.arms.get(e.index())?.as_ref()?;
        crate::world::arm_tip(self.scene?, e, q)
    }

    /// Where an object held by arm `e` with `grasp` is, at the arm's current joints.
    fn held(&self, e: EndEffectorId, grasp: &Iso) -> Option<Iso> {
        let q = self.arms.get(e.index())?.as_ref()?;
        crate::world::held_pose(self.scene?, e, q, grasp)
    }

    fn grasp_pose(&self, g: GraspId) -> Iso {
        self.artifact.grasp_pose(self.object, g)
    }

    fn set_arms(&mut self, configurations: &[(EndEffectorId, Vec<f64>)]) {
        for (e, q) in configurations {
            if let Some(slot) = self.arms.get_mut(e.index()) {
                *slot = Some(q.clone());
            }
        }
        // A held object follows its arm.
        if let Some(pose) = self
            .grasp_in_tip
            .and_then(|g| self.held(self.state.end_effector, &g))
        {
            self.pose = Some(pose);
        }
    }

    /// Plays a step's motion by time against its arms' limits, then moves the arms
    /// through its points (a held object follows its hand at every one): the motion's
    /// duration, or none for a step without one.
    fn follow(&mut self, step: &Step) -> Result<Option<f64>, StepError> {
        let (Some(trajectory), Some(scene)) = (&step.motion, self.scene) else {
            return Ok(None);
        };
        // Each column's arm, joint name and limits.
        let mut columns = Vec::new();
        let mut bounds = Vec::new();
        let mut widths = Vec::new();
        for &e in &trajectory.arms {
            let robot = match scene.holders.get(e.index()) {
                Some(Holder::Arm { robot, .. }) => scene.robots.get(*robot),
                _ => None,
            };
            let Some(robot) = robot else {
                return Err(StepError::MalformedTrajectory { point: 0 });
            };
            let (lower, upper) = robot.limits();
            let rates = robot.rate_limits();
            for j in 0..robot.n_joints() {
                columns.push((e, robot.joint_names()[j].clone()));
                bounds.push(JointBounds {
                    lower: lower[j],
                    upper: upper[j],
                    velocity: rates.velocity.get(j).copied().unwrap_or(f64::INFINITY),
                    acceleration: rates.acceleration.get(j).copied().unwrap_or(f64::INFINITY),
                    jerk: rates.jerk.get(j).copied().flatten(),
                });
            }
            widths.push((e, robot.n_joints()));
        }
        let slack = Slack {
            position: self.tolerance.joint,
            rate: self.tolerance.rate,
        };
        let duration = playback::play(&trajectory.points, &bounds, slack).map_err(|f| match f {
            Fault::Malformed { point } => StepError::MalformedTrajectory { point },
            Fault::Limit {
                joint,
                quantity,
                value,
                limit,
                time,
            } => {
                let (arm, name) = columns[joint].clone();
                StepError::LimitExceeded {
                    arm,
                    joint: name,
                    quantity,
                    value,
                    limit,
                    time,
                }
            }
        })?;
        for point in trajectory.points.iter().map(|p| &p.positions) {
            let mut offset = 0;
            let mut configurations = Vec::new();
            for &(e, n) in &widths {
                configurations.push((e, point[offset..offset + n].to_vec()));
                offset += n;
            }
            self.set_arms(&configurations);
        }
        self.clock += duration;
        Ok(Some(duration))
    }

    /// Reaches the configurations a command states: by the motion when there is one
    /// (which must end there), by jumping when the plan has no motions.
    fn reach(
        &mut self,
        step: &Step,
        configurations: &[(EndEffectorId, Vec<f64>)],
    ) -> Result<(), StepError> {
        if step.motion.is_none() {
            self.set_arms(configurations);
            return Ok(());
        }
        for (e, q) in configurations {
            let Some(now) = self.arms.get(e.index()).and_then(|q| q.as_ref()) else {
                continue;
            };
            let joint_error = now
                .iter()
                .zip(q)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            if joint_error > self.tolerance.joint || now.len() != q.len() {
                return Err(StepError::MotionMismatch {
                    arm: *e,
                    joint_error,
                });
            }
        }
        Ok(())
    }

    /// An arm closes its hand with `grasp`: the object must be where that grasp puts it.
    fn check_grasp(&self, holder: EndEffectorId, grasp: GraspId) -> Result<Iso, StepError> {
        let (Some(tip), Some(expected), Some(pose)) = (
            self.tip(holder),
            self.held(holder, &self.grasp_pose(grasp)),
            self.pose,
        ) else {
            return Ok(Iso::identity());
        };
        let position_error = (expected.translation.vector - pose.translation.vector).norm();
        let symmetries = self
            .artifact
            .objects
            .get(self.object.index())
            .map_or(&[][..], |o| o.symmetries.as_slice());
        let rotation_error =
            crate::symmetry::residual(&(expected.rotation.inverse() * pose.rotation), symmetries);
        if position_error > self.tolerance.position || rotation_error > self.tolerance.rotation {
            return Err(StepError::GraspMissed {
                holder,
                position_error,
                rotation_error,
            });
        }
        Ok(tip.inverse() * pose)
    }

    /// The object is let go onto surface `surface` with its resting pose `rest`: it must
    /// lie on the top face in that resting pose (up to a turn about the vertical), or be
    /// above it by no more than a drop in that orientation. The pose it comes to rest in.
    fn check_rest(&self, surface: EndEffectorId, rest: GraspId) -> Result<Option<Iso>, StepError> {
        let (Some(scene), Some(pose)) = (self.scene, self.pose) else {
            return Ok(self.pose);
        };
        let Some(Holder::Surface { slab, .. }) = scene.holders.get(surface.index()) else {
            return Ok(Some(pose));
        };
        let symmetries = self
            .artifact
            .objects
            .get(self.object.index())
            .map_or(&[][..], |o| o.symmetries.as_slice());
        let rest = self.grasp_pose(rest);
        let (height_error, rotation_error) =
            crate::plan::locate::rest_error(&pose, &rest, slab.maxs.z, symmetries);
        // Above the resting height by more than the solvers' error (not inside the
        // surface): it falls that far. Within that error it rests where it was let go.
        let above = pose.translation.vector.z - slab.maxs.z - rest.translation.vector.z;
        let falls = above > self.tolerance.position && above <= self.tolerance.drop;
        if (height_error > self.tolerance.position && !falls)
            || rotation_error > self.tolerance.rotation
        {
            return Err(StepError::NotResting {
                surface,
                height_error,
                rotation_error,
            });
        }
        let mut settled = pose;
        if falls {
            settled.translation.vector.z -= above;
        }
        Ok(Some(settled))
    }
}

impl Executor for Simulator<'_> {
    fn execute(&mut self, step: &Step) -> Result<(), StepError> {
        let index = self.executed;
        self.executed += 1;
        if self.fail_at == Some(index) {
            self.log
                .push(format!("step {}: motion failed (injected)", index + 1));
            return Err(StepError::MotionFailed {
                reason: "injected failure".into(),
            });
        }
        let motion = match self.follow(step) {
            Ok(motion) => motion,
            Err(e) => {
                self.log.push(format!("step {}: failed: {e}", index + 1));
                return Err(e);
            }
        };
        let name = |e: EndEffectorId| {
            self.artifact
                .end_effectors
                .get(e.index())
                .map_or("?", |x| x.name.as_str())
                .to_string()
        };
        let outcome = match &step.command {
            Command::Move {
                holder,
                workspace,
                configurations,
                ..
            } => {
                if *holder != self.state.end_effector {
                    Err(StepError::NotHolding {
                        holder: *holder,
                        actual: self.state.end_effector,
                    })
                } else {
                    self.reach(step, configurations).map(|()| {
                        self.state.workspace = *workspace;
                        format!("{} moves", name(*holder))
                    })
                }
            }
            Command::Grasp {
                holder,
                grasp,
                workspace,
                configurations,
                ..
            } => self.reach(step, configurations).and_then(|()| {
                if self.is_arm(*holder) {
                    // Attach: the object stays where it is, in the new hand.
                    self.grasp_in_tip = Some(self.check_grasp(*holder, *grasp)?);
                } else {
                    // Put down: it stays where the giving hand left it, or falls the
                    // last millimetres onto the surface.
                    self.pose = self.check_rest(*holder, *grasp)?;
                    self.grasp_in_tip = None;
                }
                self.state = Node {
                    end_effector: *holder,
                    grasp: *grasp,
                    workspace: *workspace,
                };
                Ok(format!("{} grasps", name(*holder)))
            }),
            Command::Ungrasp { holder, .. } => Ok(format!("{} lets go", name(*holder))),
        };
        match outcome {
            Ok(line) => {
                let timed = match motion {
                    Some(seconds) => format!(" (motion {seconds:.3} s, clock {:.3} s)", self.clock),
                    None => String::new(),
                };
                self.log.push(format!("step {}: {line}{timed}", index + 1));
                Ok(())
            }
            Err(e) => {
                self.log.push(format!("step {}: failed: {e}", index + 1));
                Err(e)
            }
        }
    }

    fn object_state(&self) -> ObservedObject {
        ObservedObject {
            state: self.state,
            pose: self.pose,
        }
    }

    fn arms(&self) -> Vec<Option<Vec<f64>>> {
        self.arms.clone()
    }
}

/// Settings of an execution.
#[derive(Clone, Debug)]
pub struct ExecuteOptions {
    /// How many times a failure may be recovered from by planning again.
    pub max_replans: u32,
    /// Settings of those replans.
    pub plan: PlanOptions,
}

impl Default for ExecuteOptions {
    fn default() -> ExecuteOptions {
        ExecuteOptions {
            max_replans: 5,
            plan: PlanOptions::default(),
        }
    }
}

/// How an execution ended.
#[derive(Clone, Debug)]
pub struct Execution {
    /// Steps carried out, over all plans.
    pub steps_done: usize,
    /// Plans used: the first and one per replan.
    pub plans: Vec<Plan>,
    /// Final state of the object.
    pub final_state: Node,
    /// Final pose of the object, when known.
    pub final_pose: Option<Iso>,
}

/// Why an execution failed.
#[derive(Clone, Debug)]
#[non_exhaustive]
pub enum ExecutionError {
    /// A step failed before the object left its start: nothing to recover from.
    FailedAtStart {
        /// The executor's error.
        error: StepError,
    },
    /// Replanning from where the object was found no plan.
    Replan(PlanError),
    /// More failures than the replan budget allows.
    TooManyFailures {
        /// Replans done.
        replans: u32,
        /// The last failure.
        last: StepError,
    },
}

/// Executes `plan` towards the goal it carries, replanning from the object's current
/// state when a step fails (at most `options.max_replans` times).
pub(crate) fn execute(
    planner: &Planner<'_>,
    plan: Plan,
    executor: &mut dyn Executor,
    options: &ExecuteOptions,
) -> Result<Execution, ExecutionError> {
    let start = plan.states.first().copied();
    let goal = plan.goal.clone();
    let object = plan.object;
    let mut plans = vec![plan];
    let mut steps_done = 0;
    let mut replans = 0;
    let mut moved = false;
    loop {
        let current = plans.last().map(|p| p.steps.clone()).unwrap_or_default();
        let mut failure = None;
        for step in &current {
            match executor.execute(step) {
                Ok(()) => {
                    steps_done += 1;
                    if matches!(step.command, Command::Grasp { .. } | Command::Move { .. }) {
                        moved = true;
                    }
                }
                Err(error) => {
                    failure = Some(error);
                    break;
                }
            }
        }
        let observed = executor.object_state();
        let Some(error) = failure else {
            return Ok(Execution {
                steps_done,
                plans,
                final_state: observed.state,
                final_pose: observed.pose,
            });
        };
        if !moved || Some(observed.state) == start && steps_done == 0 {
            return Err(ExecutionError::FailedAtStart { error });
        }
        if replans >= options.max_replans {
            return Err(ExecutionError::TooManyFailures {
                replans,
                last: error,
            });
        }
        replans += 1;
        let state = WorldState {
            arms: executor.arms(),
            object: observed.pose,
            around: plans[0].around.clone(),
        };
        let next = planner
            .plan_from(object, observed.state, &goal, state, &options.plan)
            .map_err(ExecutionError::Replan)?;
        plans.push(next);
    }
}

impl std::fmt::Display for ExecutionError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ExecutionError::FailedAtStart { error } => {
                write!(f, "{error} before the object left its start")
            }
            ExecutionError::Replan(e) => write!(f, "replanning failed: {e}"),
            ExecutionError::TooManyFailures { replans, last } => {
                write!(
                    f,
                    "steps kept failing ({last}); gave up after {replans} replans"
                )
            }
        }
    }
}

impl std::error::Error for ExecutionError {}

impl std::error::Error for StepError {}
