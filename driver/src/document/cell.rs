//! The service's own documents: the cell as a client sees it (`GET /v1/cell`), its
//! health (`GET /v1/health`), and the bodies the service takes.

use cellc_schema::{Artifact, Body, Holder};
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// `GET /v1/health`.
#[derive(Serialize, Deserialize, JsonSchema, Clone, Debug, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Health {
    /// Always `ok`.
    pub status: String,
    /// The loaded cell's name.
    pub cell: String,
    /// The service's version.
    pub version: String,
    /// The store the world is kept in (32 hex digits, made when the state file was
    /// created): a client that sees another one knows the service lost its state.
    pub instance: String,
    /// The world's revision.
    pub revision: u64,
    /// Whether the world survives a stop: `file` (the state file) or `memory`
    /// (`--ephemeral`).
    pub durability: String,
    /// Executions found in flight at start-up whose objects and arms are still
    /// uncertain; empty when the world is certain.
    pub interrupted: Vec<super::state::Interrupted>,
}

/// `GET /v1/cell`: what a client needs to form its requests, by names.
#[derive(Serialize, Deserialize, JsonSchema, Clone, Debug, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Cell {
    /// The cell's name.
    pub cell: String,
    /// Its objects.
    pub objects: Vec<Object>,
    /// Its end-effectors (arms, surfaces, abstract holders).
    pub end_effectors: Vec<EndEffector>,
    /// Its workspaces.
    pub workspaces: Vec<Workspace>,
    /// Its arms and their joints.
    pub arms: Vec<Arm>,
    /// Its named requests.
    pub requests: Vec<String>,
    /// Its named tasks.
    pub tasks: Vec<String>,
}

/// An object.
#[derive(Serialize, Deserialize, JsonSchema, Clone, Debug, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Object {
    /// Its name.
    pub name: String,
    /// Its grasps (by hands).
    pub grasps: Vec<Grasp>,
    /// Its resting poses (on surfaces).
    pub resting_poses: Vec<Grasp>,
    /// States of its graph.
    pub states: usize,
    /// Arcs of its graph.
    pub arcs: usize,
}

/// A grasp or resting pose.
#[derive(Serialize, Deserialize, JsonSchema, Clone, Debug, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Grasp {
    /// Its name.
    pub name: String,
    /// Its label, when it has one.
    pub label: Option<String>,
    /// The end-effector or holder kind it is by.
    pub holder: Option<String>,
}

/// What an end-effector is.
#[derive(Serialize, Deserialize, JsonSchema, Clone, Copy, Debug, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum BodyKind {
    /// A robot arm's hand.
    Arm,
    /// A surface.
    Surface,
    /// A holder without a body.
    Abstract,
}

/// An end-effector.
#[derive(Serialize, Deserialize, JsonSchema, Clone, Debug, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct EndEffector {
    /// Its name.
    pub name: String,
    /// Whether it moves.
    pub movable: bool,
    /// What it is.
    pub body: BodyKind,
    /// Its holder kind.
    pub kind: Option<String>,
    /// The workspaces it reaches.
    pub reaches: Vec<String>,
}

/// A workspace.
#[derive(Serialize, Deserialize, JsonSchema, Clone, Debug, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Workspace {
    /// Its name.
    pub name: String,
    /// Its label.
    pub label: Option<String>,
    /// Its boxes (metres).
    pub boxes: Vec<Box3>,
    /// Whether it was derived from reach (rather than declared).
    pub derived: bool,
}

/// An axis-aligned box (metres).
#[derive(Serialize, Deserialize, JsonSchema, Clone, Debug, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Box3 {
    /// Smallest corner.
    pub min: [f64; 3],
    /// Largest corner.
    pub max: [f64; 3],
}

/// An arm.
#[derive(Serialize, Deserialize, JsonSchema, Clone, Debug, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Arm {
    /// Its end-effector's name.
    pub name: String,
    /// Its robot.
    pub robot: String,
    /// Its movable joints, base to tip.
    pub joints: Vec<Joint>,
    /// Its home configuration.
    pub home: Vec<f64>,
}

/// A movable joint.
#[derive(Serialize, Deserialize, JsonSchema, Clone, Debug, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Joint {
    /// Its URDF name.
    pub name: String,
    /// Whether it slides (metres) rather than turns (radians).
    pub prismatic: bool,
    /// Its lower limit.
    pub lower: Option<f64>,
    /// Its upper limit.
    pub upper: Option<f64>,
    /// The speed it is timed with (rad/s, m/s when prismatic): the cell's, its
    /// `joint_limits.yaml`'s, its URDF's, or the default (`cellc info CELL` says which).
    pub velocity: f64,
    /// The acceleration it is timed with (rad/s², m/s² when prismatic).
    pub acceleration: f64,
    /// Its jerk limit (rad/s³, m/s³ when prismatic), when one is declared.
    pub jerk: Option<f64>,
}

impl Cell {
    /// The cell of artifact `a`.
    pub fn of(a: &Artifact) -> Cell {
        let holder = |h: Holder| match h {
            Holder::EndEffector(e) => a.end_effectors.get(e as usize).map(|e| e.name.clone()),
            Holder::Kind(k) => a.holder_kinds.get(k as usize).map(|k| k.name.clone()),
        };
        let objects = a
            .objects
            .iter()
            .map(|o| {
                let poses = |rest: bool| {
                    o.grasps
                        .iter()
                        .filter(|g| g.rest == rest)
                        .map(|g| Grasp {
                            name: g.name.clone(),
                            label: g.label.clone(),
                            holder: holder(g.holder),
                        })
                        .collect()
                };
                Object {
                    name: o.name.clone(),
                    grasps: poses(false),
                    resting_poses: poses(true),
                    states: o.graph.nodes.len(),
                    arcs: o.graph.arcs.len(),
                }
            })
            .collect();
        let end_effectors = a
            .end_effectors
            .iter()
            .map(|e| EndEffector {
                name: e.name.clone(),
                movable: e.movable,
                body: match e.body {
                    Body::Arm { .. } => BodyKind::Arm,
                    Body::Surface { .. } => BodyKind::Surface,
                    _ => BodyKind::Abstract,
                },
                kind: e
                    .kind
                    .and_then(|k| a.holder_kinds.get(k as usize))
                    .map(|k| k.name.clone()),
                reaches: e
                    .reaches
                    .iter()
                    .filter_map(|&w| a.workspaces.get(w as usize))
                    .map(|w| w.name.clone())
                    .collect(),
            })
            .collect();
        let workspaces = a
            .workspaces
            .iter()
            .map(|w| Workspace {
                name: w.name.clone(),
                label: w.label.clone(),
                boxes: w
                    .boxes
                    .iter()
                    .map(|b| Box3 {
                        min: b.min,
                        max: b.max,
                    })
                    .collect(),
                derived: w.derived,
            })
            .collect();
        let arms = a
            .end_effectors
            .iter()
            .filter_map(|e| match &e.body {
                Body::Arm { robot, home, .. } => {
                    let robot = a.robots.get(*robot as usize)?;
                    Some(Arm {
                        name: e.name.clone(),
                        robot: robot.name.clone(),
                        joints: robot
                            .joints
                            .iter()
                            .map(|j| Joint {
                                name: j.name.clone(),
                                prismatic: j.prismatic,
                                lower: j.lower,
                                upper: j.upper,
                                velocity: j.velocity,
                                acceleration: j.acceleration,
                                jerk: j.jerk,
                            })
                            .collect(),
                        home: home.clone(),
                    })
                }
                _ => None,
            })
            .collect();
        Cell {
            cell: a.cell.clone(),
            objects,
            end_effectors,
            workspaces,
            arms,
            requests: a.requests.iter().map(|r| r.name.clone()).collect(),
            tasks: a.tasks.iter().map(|t| t.name.clone()).collect(),
        }
    }
}

/// A move request: the object, where it is (default: where the world has it) and where
/// it must go, as `cellc plan --from/--to` write placements.
#[derive(Serialize, Deserialize, JsonSchema, Clone, Debug, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct MoveRequest {
    /// The object.
    pub object: String,
    /// Where it is (`HOLDER in WORKSPACE`, `HOLDER at (x, y, z)`, ...).
    #[serde(default)]
    pub from: Option<String>,
    /// Where it must go.
    pub to: String,
    /// Planning options.
    #[serde(default)]
    pub options: Options,
    /// The world revision the request was made against (as `If-Match` says it): an
    /// execute is refused with S0006 when the world has moved on.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub revision: Option<u64>,
}

/// A task: moves in order.
#[derive(Serialize, Deserialize, JsonSchema, Clone, Debug, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct TaskRequest {
    /// The moves.
    pub moves: Vec<TaskMove>,
    /// Planning options.
    #[serde(default)]
    pub options: Options,
    /// The world revision the task was made against: refused with S0006 when the world
    /// has moved on.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub revision: Option<u64>,
}

/// One move of a task.
#[derive(Serialize, Deserialize, JsonSchema, Clone, Debug, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct TaskMove {
    /// The object.
    pub object: String,
    /// Where it must go.
    pub to: String,
}

/// Planning options; every field may be left out.
#[derive(Serialize, Deserialize, JsonSchema, Clone, Debug, Default, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Options {
    /// The seed of sampling (default: the service's `--seed`).
    #[serde(default)]
    pub seed: Option<u64>,
    /// Whether to plan joint trajectories (default `true`).
    #[serde(default)]
    pub motions: Option<bool>,
    /// The planning time budget in milliseconds (default 10 000, at most 60 000).
    #[serde(default)]
    pub time_budget_ms: Option<u64>,
    /// Whether to move objects in the way out of it first (default `false`).
    #[serde(default)]
    pub clear: Option<bool>,
    // The timing options are left out when not given, so an execution's intent (which an
    // idempotency key is held to) is written as it was before they existed.
    /// The share of every joint's velocity limit the motions use, above 0 and at most 1
    /// (default 1; out of range: R0012).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub velocity_scaling: Option<f64>,
    /// The share of every joint's acceleration (and jerk) limit the motions use, above 0
    /// and at most 1 (default 1; out of range: R0012).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub acceleration_scaling: Option<f64>,
    /// Trajectory points every 1/`rate` seconds (Hz, above 0 and at most 1000), the last
    /// at the motion's end, instead of the time parameterisation's knots (default: the
    /// knots; out of range: R0012).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rate: Option<f64>,
}
