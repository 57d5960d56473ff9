//! The plan document: one plan by names (holders, grasps, workspaces), metres and
//! radians, every joint value next to its URDF joint name, so a task planner reads it
//! without the artifact.

use cellc_runtime::math::Iso;
use cellc_runtime::plan::{Around, Command, Plan as RuntimePlan, Step as RuntimeStep};
use cellc_schema::{Artifact, EndEffectorId, GraspId, Node, ObjectId};
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// A pose: metres, and a unit quaternion (x, y, z, w).
#[derive(Serialize, Deserialize, JsonSchema, Clone, Debug, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Pose {
    /// Metres, in the cell's frame.
    pub position: [f64; 3],
    /// A unit quaternion (x, y, z, w).
    pub rotation: [f64; 4],
}

impl Pose {
    /// The pose of `p`.
    pub fn of(p: &Iso) -> Pose {
        let s = cellc_runtime::math::iso_to_schema(p);
        Pose {
            position: s.translation,
            rotation: s.rotation,
        }
    }
}

/// One arm's joints: names (URDF) and values, in the same order.
#[derive(Serialize, Deserialize, JsonSchema, Clone, Debug, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Joints {
    /// The arm (its end-effector's name).
    pub arm: String,
    /// Its movable joints' URDF names, base to tip.
    pub joints: Vec<String>,
    /// Their values (radians or metres), in `joints` order.
    pub positions: Vec<f64>,
}

impl Joints {
    /// The joints of arm `e` at `q`.
    pub fn of(a: &Artifact, e: EndEffectorId, q: &[f64]) -> Joints {
        Joints {
            arm: a.end_effector_name(e).to_string(),
            joints: names(a, e),
            positions: q.to_vec(),
        }
    }
}

fn names(a: &Artifact, e: EndEffectorId) -> Vec<String> {
    a.joint_names(e).into_iter().map(str::to_string).collect()
}

/// A state of an object's graph by name.
#[derive(Serialize, Deserialize, JsonSchema, Clone, Debug, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct State {
    /// Who holds the object.
    pub end_effector: String,
    /// How (a grasp or resting pose of the object).
    pub grasp: String,
    /// Where.
    pub workspace: String,
}

impl State {
    /// State `s` of `object`.
    pub fn of(a: &Artifact, object: ObjectId, s: Node) -> State {
        State {
            end_effector: a.end_effector_name(s.end_effector).to_string(),
            grasp: a.grasp_name(object, s.grasp).to_string(),
            workspace: a.workspace_name(s.workspace).to_string(),
        }
    }
}

/// A plan.
#[derive(Serialize, Deserialize, JsonSchema, Clone, Debug, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Plan {
    /// The request's name (`command line`, `request`, `clearing for OBJECT`, ...).
    pub request: String,
    /// The object moved.
    pub object: String,
    /// How the plan was found (`graph search`, ...).
    pub strategy: String,
    /// The plan's cost (the sum of its arcs' weights).
    pub cost: f64,
    /// Searches that failed before this plan was found.
    pub backtracks: u32,
    /// The holders in turn (one entry per change of holder).
    pub holders: Vec<String>,
    /// The object's states, start to goal.
    pub states: Vec<State>,
    /// The commands, in order.
    pub steps: Vec<Step>,
    /// The world's objects the plan went round.
    pub detours: Vec<Detour>,
}

/// A world's object that the plan went round.
#[derive(Serialize, Deserialize, JsonSchema, Clone, Debug, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Detour {
    /// The object in the way.
    pub object: String,
    /// What it blocked, in words.
    pub blocked: String,
    /// How the plan went round it.
    pub around: Detoured,
}

/// How a plan went round an object in the way.
#[derive(Serialize, Deserialize, JsonSchema, Clone, Copy, Debug, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum Detoured {
    /// Another grasp or placement.
    OtherPose,
    /// Another path.
    OtherPath,
}

/// What a step does.
#[derive(Serialize, Deserialize, JsonSchema, Clone, Copy, Debug, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum StepCommand {
    /// The holder moves (with the object, if it holds it) to a workspace.
    Move,
    /// The holder takes the object.
    Grasp,
    /// The holder lets the object go.
    Ungrasp,
}

/// One command of a plan.
#[derive(Serialize, Deserialize, JsonSchema, Clone, Debug, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Step {
    /// What the step does.
    pub command: StepCommand,
    /// Who does it.
    pub end_effector: String,
    /// The grasp taken or let go (`null` for a move).
    pub grasp: Option<String>,
    /// Where.
    pub workspace: String,
    /// The object's pose after the step, when it has one.
    pub object: Option<Pose>,
    /// The arms' joints at the end of the step.
    pub configurations: Vec<Joints>,
    /// The joint trajectory of the step, when motions were planned.
    pub motion: Option<Trajectory>,
}

/// A joint trajectory: the arms that move (each with its joint names), and points with
/// the time from the step's start and every moving arm's joints' positions, velocities
/// and accelerations, in `arms` order: what a joint-trajectory controller takes.
#[derive(Serialize, Deserialize, JsonSchema, Clone, Debug, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Trajectory {
    /// The arms that move.
    pub arms: Vec<ArmJoints>,
    /// The points, in time order.
    pub points: Vec<Point>,
}

/// An arm and its joints' names.
#[derive(Serialize, Deserialize, JsonSchema, Clone, Debug, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ArmJoints {
    /// The arm.
    pub arm: String,
    /// Its movable joints' URDF names.
    pub joints: Vec<String>,
}

/// A point of a trajectory.
#[derive(Serialize, Deserialize, JsonSchema, Clone, Debug, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Point {
    /// Seconds from the step's start (`trajectory_msgs/JointTrajectoryPoint`'s name).
    pub time_from_start: f64,
    /// Every moving arm's joint positions, in `arms` order (rad, or m).
    pub positions: Vec<f64>,
    /// Their velocities (rad/s, or m/s).
    pub velocities: Vec<f64>,
    /// Their accelerations (rad/s², or m/s²).
    pub accelerations: Vec<f64>,
}

impl Step {
    /// One step of a plan for `object`, by names.
    pub fn of(artifact: &Artifact, object: ObjectId, step: &RuntimeStep) -> Step {
        let grasp = |g: GraspId| Some(artifact.grasp_name(object, g).to_string());
        let (command, holder, g, w, p, configurations) = match &step.command {
            Command::Move {
                holder,
                workspace,
                object,
                configurations,
            } => (
                StepCommand::Move,
                *holder,
                None,
                *workspace,
                object,
                configurations.as_slice(),
            ),
            Command::Grasp {
                holder,
                grasp: g,
                workspace,
                object,
                configurations,
            } => (
                StepCommand::Grasp,
                *holder,
                grasp(*g),
                *workspace,
                object,
                configurations.as_slice(),
            ),
            Command::Ungrasp {
                holder,
                grasp: g,
                workspace,
                object,
            } => (
                StepCommand::Ungrasp,
                *holder,
                grasp(*g),
                *workspace,
                object,
                &[][..],
            ),
        };
        Step {
            command,
            end_effector: artifact.end_effector_name(holder).to_string(),
            grasp: g,
            workspace: artifact.workspace_name(w).to_string(),
            object: p.as_ref().map(Pose::of),
            configurations: configurations
                .iter()
                .map(|(e, q)| Joints::of(artifact, *e, q))
                .collect(),
            motion: step.motion.as_ref().map(|t| Trajectory {
                arms: t
                    .arms
                    .iter()
                    .map(|&e| ArmJoints {
                        arm: artifact.end_effector_name(e).to_string(),
                        joints: names(artifact, e),
                    })
                    .collect(),
                points: t
                    .points
                    .iter()
                    .map(|p| Point {
                        time_from_start: p.time,
                        positions: p.positions.clone(),
                        velocities: p.velocities.clone(),
                        accelerations: p.accelerations.clone(),
                    })
                    .collect(),
            }),
        }
    }
}

impl Plan {
    /// `plan` by names; `name` is the request's name (or "command line").
    pub fn of(artifact: &Artifact, name: &str, plan: &RuntimePlan) -> Plan {
        let object = plan.object;
        let mut holders: Vec<String> = Vec::new();
        for s in &plan.states {
            let h = artifact.end_effector_name(s.end_effector);
            if holders.last().map(String::as_str) != Some(h) {
                holders.push(h.to_string());
            }
        }
        let steps = plan
            .steps
            .iter()
            .map(|step| Step::of(artifact, object, step))
            .collect();
        Plan {
            request: name.to_string(),
            object: artifact.object_name(object).to_string(),
            strategy: plan.strategy.to_string(),
            cost: plan.cost,
            backtracks: plan.backtracks,
            holders,
            states: plan
                .states
                .iter()
                .map(|&s| State::of(artifact, object, s))
                .collect(),
            steps,
            detours: plan
                .detours
                .iter()
                .map(|d| Detour {
                    object: artifact.object_name(d.blocker.by).to_string(),
                    blocked: crate::explain_report::words::blocked(artifact, &d.blocker),
                    around: match d.around {
                        Around::OtherPose => Detoured::OtherPose,
                        _ => Detoured::OtherPath,
                    },
                })
                .collect(),
        }
    }
}
