//! Plans as joint-trajectory controllers take them: per plan, one
//! `control_msgs/action/FollowJointTrajectory` goal per arm per step that moves, in the
//! shape of the ROS 2 messages (`trajectory_msgs/JointTrajectory`,
//! `builtin_interfaces/Duration`), so a bridge fills the action's goal field by field
//! (`rosidl_runtime_py.set_message_fields`) and sends each arm's goal to its own
//! controller (ros2_control's `joint_trajectory_controller`).
//!
//! Made from the plan document ([`Plan`]), not from the runtime's plan: a plan read back
//! from a file exports the same goals as the plan made now, and the one home of "a
//! trajectory by names" stays the plan document.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::plan::{Plan, Trajectory};

/// The goals of plans, in the order they are carried out.
#[derive(Serialize, Deserialize, JsonSchema, Clone, Debug, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ControllerGoals {
    /// One entry per plan (with `clear`, those moving what is in the way first).
    pub plans: Vec<PlanGoals>,
}

/// One plan's motions as goals.
#[derive(Serialize, Deserialize, JsonSchema, Clone, Debug, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct PlanGoals {
    /// The plan's request (as the plan document names it).
    pub request: String,
    /// The object it moves.
    pub object: String,
    /// The goals, step by step, and within a step in the trajectory's arm order.
    pub goals: Vec<StepGoal>,
}

/// The goal of one arm in one step. The goals of one step start together: the arms of a
/// handoff move at once, each following its own goal on the same clock.
#[derive(Serialize, Deserialize, JsonSchema, Clone, Debug, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct StepGoal {
    /// The step's index in the plan's `steps` (0 for the first).
    pub step: usize,
    /// The arm (its end-effector's name).
    pub arm: String,
    /// What to send to that arm's controller.
    pub goal: FollowJointTrajectoryGoal,
}

/// `control_msgs/action/FollowJointTrajectory`'s goal: the trajectory alone (the
/// tolerances and the multi-DOF trajectory are left to the controller's defaults).
#[derive(Serialize, Deserialize, JsonSchema, Clone, Debug, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct FollowJointTrajectoryGoal {
    /// The arm's trajectory.
    pub trajectory: JointTrajectory,
}

/// `trajectory_msgs/JointTrajectory` (without its header: a zero stamp, which means "start
/// now", is what a bridge fills in).
#[derive(Serialize, Deserialize, JsonSchema, Clone, Debug, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct JointTrajectory {
    /// The arm's movable joints' URDF names, base to tip.
    pub joint_names: Vec<String>,
    /// The points, strictly increasing in time, the first at 0.
    pub points: Vec<JointTrajectoryPoint>,
}

/// `trajectory_msgs/JointTrajectoryPoint` (without `effort`, which nothing plans).
#[derive(Serialize, Deserialize, JsonSchema, Clone, Debug, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct JointTrajectoryPoint {
    /// Joint positions (rad, or m), in `joint_names` order.
    pub positions: Vec<f64>,
    /// Their velocities (rad/s, or m/s).
    pub velocities: Vec<f64>,
    /// Their accelerations (rad/s², or m/s²).
    pub accelerations: Vec<f64>,
    /// Time from the start of the step's motion.
    pub time_from_start: Duration,
}

/// `builtin_interfaces/Duration`: whole seconds and the nanoseconds after them.
#[derive(
    Serialize, Deserialize, JsonSchema, Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord,
)]
#[serde(deny_unknown_fields)]
pub struct Duration {
    /// Whole seconds.
    pub sec: i32,
    /// Nanoseconds, from 0 to 999 999 999.
    pub nanosec: u32,
}

const NANOS_PER_SECOND: i64 = 1_000_000_000;

impl Duration {
    /// `seconds` to the nearest nanosecond, or `None` when it is negative, not finite or
    /// past what `sec` holds. Rounding to the nearest is monotonic, so times in order stay
    /// in order (two may become equal: [`ControllerGoals::of`] parts them).
    pub fn of_seconds(seconds: f64) -> Option<Duration> {
        if !(seconds.is_finite() && seconds >= 0.0 && seconds < f64::from(i32::MAX)) {
            return None;
        }
        Duration::of_nanoseconds((seconds * NANOS_PER_SECOND as f64).round() as i64)
    }

    /// Nanoseconds in all.
    pub fn nanoseconds(self) -> i64 {
        i64::from(self.sec) * NANOS_PER_SECOND + i64::from(self.nanosec)
    }

    /// `nanoseconds` in all, or `None` when negative or past what `sec` holds.
    pub fn of_nanoseconds(nanoseconds: i64) -> Option<Duration> {
        if nanoseconds < 0 {
            return None;
        }
        Some(Duration {
            sec: i32::try_from(nanoseconds / NANOS_PER_SECOND).ok()?,
            nanosec: u32::try_from(nanoseconds % NANOS_PER_SECOND).ok()?,
        })
    }
}

/// Why a plan document's motion cannot be sent to a controller: it does not hold what the
/// runtime writes (a document edited or made elsewhere). Indices are 0-based.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum GoalsError {
    /// A point has another number of positions, velocities or accelerations than the
    /// arms have joints.
    Width {
        /// The plan.
        plan: usize,
        /// The step.
        step: usize,
        /// The point.
        point: usize,
    },
    /// A point's time is negative, not finite, too large for a `Duration`, or before the
    /// point before it.
    Time {
        /// The plan.
        plan: usize,
        /// The step.
        step: usize,
        /// The point.
        point: usize,
    },
}

impl std::fmt::Display for GoalsError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let (what, plan, step, point) = match self {
            GoalsError::Width { plan, step, point } => {
                ("has the wrong number of values", plan, step, point)
            }
            GoalsError::Time { plan, step, point } => ("is out of time order", plan, step, point),
        };
        write!(f, "plan {plan}, step {step}: point {point} {what}")
    }
}

impl std::error::Error for GoalsError {}

impl ControllerGoals {
    /// The document as the command line writes it: pretty JSON in the messages' field
    /// order (the order ROS declares them in).
    pub fn to_text(&self) -> String {
        serde_json::to_string_pretty(self).unwrap_or_default()
    }

    /// The goals of `plans`: for each step with a motion, for each arm in it (in the
    /// trajectory's order), that arm's columns of every point, times to the nearest
    /// nanosecond. A controller refuses times that do not increase, so a point whose time
    /// rounds to the nanosecond of the point before (a resampled motion's last sample a
    /// hair before its end) is put one nanosecond after it: every point is kept, none
    /// moves by more than a nanosecond per point that shares its time.
    ///
    /// # Errors
    /// [`GoalsError`] for a motion the runtime would not write.
    pub fn of(plans: &[Plan]) -> Result<ControllerGoals, GoalsError> {
        let mut out = Vec::with_capacity(plans.len());
        for (p, plan) in plans.iter().enumerate() {
            let mut goals = Vec::new();
            for (s, step) in plan.steps.iter().enumerate() {
                if let Some(motion) = &step.motion {
                    goals.extend(step_goals(motion, s).map_err(|at| at.of(p, s))?);
                }
            }
            out.push(PlanGoals {
                request: plan.request.clone(),
                object: plan.object.clone(),
                goals,
            });
        }
        Ok(ControllerGoals { plans: out })
    }
}

/// Where in a step a motion went wrong, before the plan is known.
enum Fault {
    Width(usize),
    Time(usize),
}

impl Fault {
    fn of(self, plan: usize, step: usize) -> GoalsError {
        match self {
            Fault::Width(point) => GoalsError::Width { plan, step, point },
            Fault::Time(point) => GoalsError::Time { plan, step, point },
        }
    }
}

/// One goal per arm of `motion`, the step's index `step`.
fn step_goals(motion: &Trajectory, step: usize) -> Result<Vec<StepGoal>, Fault> {
    let width: usize = motion.arms.iter().map(|a| a.joints.len()).sum();
    // Every point's time, checked once for every arm.
    let mut times: Vec<Duration> = Vec::with_capacity(motion.points.len());
    let mut before = 0.0;
    for (i, point) in motion.points.iter().enumerate() {
        if [&point.positions, &point.velocities, &point.accelerations]
            .iter()
            .any(|v| v.len() != width)
        {
            return Err(Fault::Width(i));
        }
        let seconds = point.time_from_start;
        let rounded = Duration::of_seconds(seconds)
            .filter(|_| i == 0 || seconds >= before)
            .ok_or(Fault::Time(i))?;
        let time = match times.last() {
            Some(last) if rounded <= *last => {
                Duration::of_nanoseconds(last.nanoseconds() + 1).ok_or(Fault::Time(i))?
            }
            _ => rounded,
        };
        times.push(time);
        before = seconds;
    }
    let mut start = 0;
    let mut goals = Vec::with_capacity(motion.arms.len());
    for arm in &motion.arms {
        let columns = start..start + arm.joints.len();
        start = columns.end;
        let points = motion
            .points
            .iter()
            .zip(&times)
            .map(|(p, &time_from_start)| JointTrajectoryPoint {
                positions: p.positions[columns.clone()].to_vec(),
                velocities: p.velocities[columns.clone()].to_vec(),
                accelerations: p.accelerations[columns.clone()].to_vec(),
                time_from_start,
            })
            .collect();
        goals.push(StepGoal {
            step,
            arm: arm.arm.clone(),
            goal: FollowJointTrajectoryGoal {
                trajectory: JointTrajectory {
                    joint_names: arm.joints.clone(),
                    points,
                },
            },
        });
    }
    Ok(goals)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::document::plan::{ArmJoints, Point, Step, StepCommand};

    fn point(time: f64, q: [f64; 3]) -> Point {
        Point {
            time_from_start: time,
            positions: q.to_vec(),
            velocities: q.iter().map(|v| v * 10.0).collect(),
            accelerations: q.iter().map(|v| v * 100.0).collect(),
        }
    }

    fn plan(points: Vec<Point>) -> Plan {
        let motion = Trajectory {
            arms: vec![
                ArmJoints {
                    arm: "left".into(),
                    joints: vec!["a1".into(), "a2".into()],
                },
                ArmJoints {
                    arm: "right".into(),
                    joints: vec!["b1".into()],
                },
            ],
            points,
        };
        let step = |motion| Step {
            command: StepCommand::Move,
            end_effector: "left".into(),
            grasp: None,
            workspace: "w".into(),
            object: None,
            configurations: Vec::new(),
            motion,
        };
        Plan {
            request: "r".into(),
            object: "o".into(),
            strategy: "s".into(),
            cost: 1.0,
            backtracks: 0,
            holders: Vec::new(),
            states: Vec::new(),
            steps: vec![step(None), step(Some(motion))],
            detours: Vec::new(),
        }
    }

    #[test]
    fn each_arm_gets_its_columns_and_the_step_its_index() {
        let goals = ControllerGoals::of(&[plan(vec![
            point(0.0, [0.0, 0.1, 0.2]),
            point(1.25, [1.0, 1.1, 1.2]),
        ])])
        .unwrap();
        let goals = &goals.plans[0].goals;
        assert_eq!(goals.len(), 2);
        assert_eq!((goals[0].step, goals[0].arm.as_str()), (1, "left"));
        assert_eq!(goals[1].arm, "right");
        let left = &goals[0].goal.trajectory;
        assert_eq!(left.joint_names, ["a1", "a2"]);
        assert_eq!(left.points[1].positions, [1.0, 1.1]);
        assert_eq!(left.points[1].velocities, [10.0, 11.0]);
        let right = &goals[1].goal.trajectory;
        assert_eq!(right.points[1].accelerations, [120.0]);
        assert_eq!(
            right.points[1].time_from_start,
            Duration {
                sec: 1,
                nanosec: 250_000_000
            }
        );
    }

    #[test]
    fn times_round_to_the_nanosecond_and_keep_increasing() {
        assert_eq!(
            Duration::of_seconds(2.9999999996),
            Some(Duration { sec: 3, nanosec: 0 })
        );
        assert_eq!(
            Duration::of_seconds(0.1 + 0.2),
            Some(Duration {
                sec: 0,
                nanosec: 300_000_000
            })
        );
        for bad in [-1e-3, f64::NAN, f64::INFINITY, 3e9] {
            assert_eq!(Duration::of_seconds(bad), None, "{bad}");
        }
        // A resampled motion's last sample a hair before its end: the end 1 ns later.
        let goals = ControllerGoals::of(&[plan(vec![
            point(0.0, [0.0; 3]),
            point(0.004, [0.1; 3]),
            point(0.008 - 1e-13, [0.2; 3]),
            point(0.008, [0.3; 3]),
        ])])
        .unwrap();
        let points = &goals.plans[0].goals[0].goal.trajectory.points;
        let times: Vec<i64> = points
            .iter()
            .map(|p| p.time_from_start.nanoseconds())
            .collect();
        assert_eq!(times, [0, 4_000_000, 8_000_000, 8_000_001]);
        assert_eq!(points[3].positions, [0.3, 0.3]);
    }

    #[test]
    fn motions_the_runtime_would_not_write_are_refused() {
        let mut short = point(0.5, [0.0; 3]);
        short.velocities.pop();
        assert_eq!(
            ControllerGoals::of(&[plan(vec![point(0.0, [0.0; 3]), short])]),
            Err(GoalsError::Width {
                plan: 0,
                step: 1,
                point: 1
            })
        );
        assert_eq!(
            ControllerGoals::of(&[plan(vec![point(1.0, [0.0; 3]), point(0.5, [0.0; 3])])]),
            Err(GoalsError::Time {
                plan: 0,
                step: 1,
                point: 1
            })
        );
    }
}
