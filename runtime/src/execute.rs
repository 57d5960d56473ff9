//! Executing plans: an [`Executor`] trait for real drivers, a kinematic [`Simulator`],
//! and the paper's recovery rule (step 7 of Algorithm 1): when a motion fails, if the
//! object is still where it started the request fails; otherwise the planner is asked
//! again from where the object is now.

use cellc_schema::{Artifact, Node};

use crate::math::Iso;
use crate::plan::planner::{Planner, WorldState};
use crate::plan::{Command, Plan, PlanError, PlanOptions, Step};
use crate::scene::{Holder, Scene};

/// Why an executor could not carry out a step.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum StepError {
    /// The motion leading to the command failed (blocked, a driver fault, ...).
    MotionFailed {
        /// What happened, for the report.
        reason: String,
    },
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

/// A kinematic simulator: arms jump along trajectories, the object is attached to the
/// holder that grasped it last and detached when let go, and its pose follows the holder.
pub struct Simulator<'a> {
    artifact: &'a Artifact,
    scene: Option<&'a Scene>,
    object: u32,
    state: Node,
    pose: Option<Iso>,
    /// Object pose in the holding arm's tip frame, while an arm holds it.
    grasp_in_tip: Option<Iso>,
    arms: Vec<Option<Vec<f64>>>,
    /// Step index (counted over the whole run) whose motion fails, for tests.
    fail_at: Option<usize>,
    executed: usize,
    /// What happened, one line per step.
    pub log: Vec<String>,
}

impl<'a> Simulator<'a> {
    /// A simulation of `object` starting in `state` at `pose`, arms at home.
    pub fn new(
        artifact: &'a Artifact,
        scene: Option<&'a Scene>,
        object: u32,
        state: Node,
        pose: Option<Iso>,
    ) -> Simulator<'a> {
        let arms = WorldState::at_home(scene, artifact.end_effectors.len(), None).arms;
        Simulator {
            artifact,
            scene,
            object,
            state,
            pose,
            grasp_in_tip: None,
            arms,
            fail_at: None,
            executed: 0,
            log: Vec::new(),
        }
    }

    /// Makes the motion of step number `index` (0-based, over the whole run) fail.
    pub fn fail_motion_at(mut self, index: usize) -> Self {
        self.fail_at = Some(index);
        self
    }

    /// The object's current pose.
    pub fn object_pose(&self) -> Option<Iso> {
        self.pose
    }

    fn tip(&self, e: u32) -> Option<Iso> {
        let scene = self.scene?;
        let Holder::Arm { robot, base, .. } = &scene.holders[e as usize] else {
            return None;
        };
        let q = self.arms.get(e as usize)?.as_ref()?;
        Some(scene.robots[*robot].tip_pose(base, q))
    }

    fn set_arms(&mut self, configurations: &[(u32, Vec<f64>)]) {
        for (e, q) in configurations {
            if let Some(slot) = self.arms.get_mut(*e as usize) {
                *slot = Some(q.clone());
            }
        }
        // A held object follows its arm.
        if let (Some(g), Some(tip)) = (self.grasp_in_tip, self.tip(self.state.end_effector)) {
            self.pose = Some(tip * g);
        }
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
        if let (Some(trajectory), Some(scene)) = (&step.motion, self.scene) {
            // Step through the trajectory; a held object follows its hand at every point.
            for (_, point) in &trajectory.points {
                let mut offset = 0;
                let mut configurations = Vec::new();
                for &e in &trajectory.arms {
                    let n = match &scene.holders[e as usize] {
                        Holder::Arm { robot, .. } => scene.robots[*robot].n_joints(),
                        _ => 0,
                    };
                    if let Some(q) = point.get(offset..offset + n) {
                        configurations.push((e, q.to_vec()));
                    }
                    offset += n;
                }
                self.set_arms(&configurations);
            }
        }
        let name = |e: u32| {
            self.artifact
                .end_effectors
                .get(e as usize)
                .map_or("?", |x| x.name.as_str())
                .to_string()
        };
        match &step.command {
            Command::Move {
                holder,
                workspace,
                object,
                configurations,
            } => {
                self.set_arms(configurations);
                if self.grasp_in_tip.is_none() {
                    if let Some(p) = object {
                        self.pose = Some(*p);
                    }
                }
                self.state.workspace = *workspace;
                self.log
                    .push(format!("step {}: {} moves", index + 1, name(*holder)));
            }
            Command::Grasp {
                holder,
                grasp,
                workspace,
                object,
                configurations,
            } => {
                self.set_arms(configurations);
                if let Some(p) = object {
                    self.pose = Some(*p);
                }
                self.state = Node {
                    end_effector: *holder,
                    grasp: *grasp,
                    workspace: *workspace,
                };
                // Attach: remember where the object sits in the new holder's hand.
                self.grasp_in_tip = match (self.tip(*holder), self.pose) {
                    (Some(tip), Some(pose)) => Some(tip.inverse() * pose),
                    _ => None,
                };
                self.log
                    .push(format!("step {}: {} grasps", index + 1, name(*holder)));
            }
            Command::Ungrasp { holder, .. } => {
                self.log
                    .push(format!("step {}: {} lets go", index + 1, name(*holder)));
            }
        }
        let _ = self.object;
        Ok(())
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
    /// A motion failed before the object left its start: nothing to recover from.
    FailedAtStart {
        /// The executor's reason.
        reason: String,
    },
    /// Replanning from where the object was found no plan.
    Replan(PlanError),
    /// More failures than the replan budget allows.
    TooManyFailures {
        /// Replans done.
        replans: u32,
    },
}

/// Executes `plan`, replanning from the object's current state when a motion fails (at
/// most `max_replans` times).
#[allow(clippy::too_many_arguments)]
pub fn execute(
    planner: &Planner<'_>,
    plan: Plan,
    goals: &[Node],
    goal_pose: Option<Iso>,
    executor: &mut dyn Executor,
    options: &PlanOptions,
    max_replans: u32,
) -> Result<Execution, ExecutionError> {
    let start = plan.states.first().copied();
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
                Err(StepError::MotionFailed { reason }) => {
                    failure = Some(reason);
                    break;
                }
            }
        }
        let observed = executor.object_state();
        let Some(reason) = failure else {
            return Ok(Execution {
                steps_done,
                plans,
                final_state: observed.state,
                final_pose: observed.pose,
            });
        };
        if !moved || Some(observed.state) == start && steps_done == 0 {
            return Err(ExecutionError::FailedAtStart { reason });
        }
        if replans >= max_replans {
            return Err(ExecutionError::TooManyFailures { replans });
        }
        replans += 1;
        let state = WorldState {
            arms: executor.arms(),
            object: observed.pose,
        };
        let object = plans[0].object;
        let next = planner
            .plan_from(object, observed.state, goals, goal_pose, state, options)
            .map_err(ExecutionError::Replan)?;
        plans.push(next);
    }
}
