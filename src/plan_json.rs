//! Plans, executions and worlds as JSON (`--format json` of `cellc plan` and `cellc run`):
//! names instead of ids, metres and radians, and every joint value next to its URDF joint
//! name, so a task planner reads a result without the artifact.
//!
//! The schema is documented in docs/world.md (section "Machine-readable results"). A
//! document always has `version`, `ok` and `diagnostics` (the report of
//! `cellc check --format json`), whether the command succeeded or not.

use cellc_runtime::math::Iso;
use cellc_runtime::plan::{Command, Plan};
use cellc_runtime::{Cell, ObjectId, Whereabouts, World};
use cellc_schema::{Artifact, EndEffectorId, GraspId, Node};
use serde::Serialize;

/// The version of the documents written here (they extend the diagnostics report of
/// `cellc check --format json`, version 1, with more fields).
pub const VERSION: u32 = 1;

fn ee(a: &Artifact, e: EndEffectorId) -> &str {
    a.end_effector_name(e)
}

/// A pose as (position, quaternion x, y, z, w).
fn pose(p: &Iso) -> JsonPose {
    let s = cellc_runtime::math::iso_to_schema(p);
    JsonPose {
        position: s.translation,
        rotation: s.rotation,
    }
}

/// A pose: metres, and a unit quaternion (x, y, z, w).
#[derive(Serialize)]
pub struct JsonPose {
    position: [f64; 3],
    rotation: [f64; 4],
}

/// One arm's joints: names (URDF) and values, in the same order.
#[derive(Serialize)]
pub struct JsonJoints<'a> {
    arm: &'a str,
    joints: Vec<&'a str>,
    positions: Vec<f64>,
}

fn joints<'a>(a: &'a Artifact, e: EndEffectorId, q: &[f64]) -> JsonJoints<'a> {
    JsonJoints {
        arm: ee(a, e),
        joints: a.joint_names(e),
        positions: q.to_vec(),
    }
}

/// A state of an object's graph by name.
#[derive(Serialize)]
pub struct JsonState<'a> {
    end_effector: &'a str,
    grasp: &'a str,
    workspace: &'a str,
}

fn state(a: &Artifact, object: ObjectId, s: Node) -> JsonState<'_> {
    JsonState {
        end_effector: ee(a, s.end_effector),
        grasp: a.grasp_name(object, s.grasp),
        workspace: a.workspace_name(s.workspace),
    }
}

/// A plan.
#[derive(Serialize)]
pub struct JsonPlan<'a> {
    request: &'a str,
    object: &'a str,
    strategy: String,
    cost: f64,
    backtracks: u32,
    holders: Vec<&'a str>,
    states: Vec<JsonState<'a>>,
    steps: Vec<JsonStep<'a>>,
    /// The world's objects the plan went round: `object`, `blocked` (what it blocked, in
    /// words) and `around` (`other_pose` or `other_path`).
    detours: Vec<JsonDetour<'a>>,
}

#[derive(Serialize)]
struct JsonDetour<'a> {
    object: &'a str,
    blocked: String,
    around: &'static str,
}

#[derive(Serialize)]
struct JsonStep<'a> {
    command: &'static str,
    end_effector: &'a str,
    grasp: Option<&'a str>,
    workspace: &'a str,
    object: Option<JsonPose>,
    configurations: Vec<JsonJoints<'a>>,
    motion: Option<JsonTrajectory<'a>>,
}

/// A joint trajectory: the arms that move (each with its joint names), and points of
/// (time in s, positions of every moving arm's joints in `arms` order).
#[derive(Serialize)]
struct JsonTrajectory<'a> {
    arms: Vec<JsonArmJoints<'a>>,
    points: Vec<JsonPoint<'a>>,
}

#[derive(Serialize)]
struct JsonArmJoints<'a> {
    arm: &'a str,
    joints: Vec<&'a str>,
}

#[derive(Serialize)]
struct JsonPoint<'a> {
    time: f64,
    positions: &'a [f64],
}

/// `plan` as JSON; `name` is the request's name (or "command line").
pub fn plan<'a>(artifact: &'a Artifact, name: &'a str, plan: &'a Plan) -> JsonPlan<'a> {
    let object = plan.object;
    let grasp = |g: GraspId| artifact.grasp_name(object, g);
    let mut holders: Vec<&str> = Vec::new();
    for s in &plan.states {
        let h = ee(artifact, s.end_effector);
        if holders.last() != Some(&h) {
            holders.push(h);
        }
    }
    let steps = plan
        .steps
        .iter()
        .map(|step| {
            let (command, holder, g, w, p, configurations) = match &step.command {
                Command::Move {
                    holder,
                    workspace,
                    object,
                    configurations,
                } => (
                    "move",
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
                    "grasp",
                    *holder,
                    Some(grasp(*g)),
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
                    "ungrasp",
                    *holder,
                    Some(grasp(*g)),
                    *workspace,
                    object,
                    &[][..],
                ),
            };
            JsonStep {
                command,
                end_effector: ee(artifact, holder),
                grasp: g,
                workspace: artifact.workspace_name(w),
                object: p.as_ref().map(pose),
                configurations: configurations
                    .iter()
                    .map(|(e, q)| joints(artifact, *e, q))
                    .collect(),
                motion: step.motion.as_ref().map(|t| JsonTrajectory {
                    arms: t
                        .arms
                        .iter()
                        .map(|&e| JsonArmJoints {
                            arm: ee(artifact, e),
                            joints: artifact.joint_names(e),
                        })
                        .collect(),
                    points: t
                        .points
                        .iter()
                        .map(|(time, q)| JsonPoint {
                            time: *time,
                            positions: q,
                        })
                        .collect(),
                }),
            }
        })
        .collect();
    JsonPlan {
        request: name,
        object: artifact.object_name(object),
        strategy: plan.strategy.to_string(),
        cost: plan.cost,
        backtracks: plan.backtracks,
        holders,
        states: plan
            .states
            .iter()
            .map(|&s| state(artifact, object, s))
            .collect(),
        steps,
        detours: plan
            .detours
            .iter()
            .map(|d| JsonDetour {
                object: artifact.object_name(d.blocker.by),
                blocked: cellc_driver::explain_report::words::blocked(artifact, &d.blocker),
                around: match d.around {
                    cellc_runtime::plan::Around::OtherPose => "other_pose",
                    _ => "other_path",
                },
            })
            .collect(),
    }
}

/// The world: every object's whereabouts and every arm's joints.
#[derive(Serialize)]
pub struct JsonWorld<'a> {
    objects: Vec<JsonObject<'a>>,
    arms: Vec<JsonJoints<'a>>,
}

#[derive(Serialize)]
struct JsonObject<'a> {
    object: &'a str,
    /// `None` when the object is absent from the scene.
    state: Option<JsonState<'a>>,
    pose: Option<JsonPose>,
}

/// `world` as JSON.
pub fn world<'a>(cell: &'a Cell, world: &World) -> JsonWorld<'a> {
    let a = cell.artifact();
    let objects = (0..a.objects.len())
        .map(|i| {
            let id = ObjectId(i as u32);
            match world.whereabouts(id) {
                Whereabouts::Absent => JsonObject {
                    object: a.object_name(id),
                    state: None,
                    pose: None,
                },
                Whereabouts::Placed { state: s, .. } => JsonObject {
                    object: a.object_name(id),
                    state: Some(state(a, id, *s)),
                    pose: world.pose(a, cell.scene(), id).as_ref().map(pose),
                },
            }
        })
        .collect();
    let arms = world
        .arms()
        .iter()
        .enumerate()
        .filter_map(|(e, q)| Some(joints(a, EndEffectorId(e as u32), q.as_ref()?)))
        .collect();
    JsonWorld { objects, arms }
}

/// How one move of `cellc run` went.
#[derive(Serialize)]
pub struct JsonMove<'a> {
    /// The object moved.
    pub object: &'a str,
    /// For a move that takes an object out of the way (`--clear`): the object of the move
    /// it clears the way for.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub clears: Option<&'a str>,
    /// The plans executed, in order: the first, then one per replan (each a [`JsonPlan`]).
    pub plans: Vec<serde_json::Value>,
    /// The simulator's log, one line per step.
    pub log: Vec<String>,
    /// Whether the move reached its goal.
    pub done: bool,
    /// Where the object ended, by the simulator.
    pub final_state: Option<JsonState<'a>>,
    /// Its pose there.
    pub final_pose: Option<JsonPose>,
    /// Distance from the goal pose (metres), when the goal has one.
    pub position_error: Option<f64>,
    /// Angle from the goal pose up to the object's symmetries (radians).
    pub rotation_error: Option<f64>,
}

/// One executed plan of a task as `cellc run --format json` and `POST /v1/execute`
/// record it: the plans executed (the first, then one per replan), the simulator's log,
/// and where the object ended with its error from the goal.
pub fn executed<'a>(
    artifact: &'a Artifact,
    executed: &cellc_runtime::Executed,
    label: &str,
) -> JsonMove<'a> {
    let plan = &executed.plan;
    let end = executed
        .result
        .as_ref()
        .ok()
        .map(|run| (run.final_state, run.final_pose));
    let (final_state, final_pose, position_error, rotation_error) =
        final_place(artifact, plan.object, end, plan.goal.pose);
    let plans = match &executed.result {
        Ok(run) => run.plans.clone(),
        Err(_) => vec![plan.clone()],
    };
    JsonMove {
        object: artifact.object_name(plan.object),
        clears: executed.clears.map(|o| artifact.object_name(o)),
        plans: plans
            .iter()
            .filter_map(|p| serde_json::to_value(self::plan(artifact, label, p)).ok())
            .collect(),
        log: executed.log.clone(),
        done: executed.result.is_ok(),
        final_state,
        final_pose,
        position_error,
        rotation_error,
    }
}

/// A move's result from what the simulator reports.
fn final_place<'a>(
    artifact: &'a Artifact,
    object: ObjectId,
    end: Option<(Node, Option<Iso>)>,
    goal: Option<Iso>,
) -> (
    Option<JsonState<'a>>,
    Option<JsonPose>,
    Option<f64>,
    Option<f64>,
) {
    let Some((s, p)) = end else {
        return (None, None, None, None);
    };
    let errors = p.zip(goal).map(|(p, g)| {
        let d = g.inverse() * p;
        let symmetries = &artifact.objects[object.index()].symmetries;
        (
            (p.translation.vector - g.translation.vector).norm(),
            cellc_runtime::symmetry::residual(&d.rotation, symmetries),
        )
    });
    (
        Some(state(artifact, object, s)),
        p.as_ref().map(pose),
        errors.map(|e| e.0),
        errors.map(|e| e.1),
    )
}

/// The whole document of `cellc plan` or `cellc run`: the diagnostics report's fields
/// (`diagnostics`, `errors`, `warnings`) and what was planned or done.
#[derive(Serialize)]
pub struct JsonRun<'a> {
    /// [`VERSION`].
    pub version: u32,
    /// `"plan"` or `"run"`.
    pub kind: &'static str,
    /// Whether every move was planned (and, for `run`, executed).
    pub ok: bool,
    /// `plan`: the plans, one per move (each a [`JsonPlan`]).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub plans: Vec<serde_json::Value>,
    /// `run`: each move's execution.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub moves: Vec<JsonMove<'a>>,
    /// The world at the end (`plan`: as the plans leave it; `run`: as the simulator did).
    pub world: Option<JsonWorld<'a>>,
    /// The diagnostics report (merged into the document's top level).
    #[serde(skip)]
    pub report: serde_json::Value,
}

/// The document as pretty JSON, the report's fields at its top level.
pub fn to_text(document: &JsonRun) -> String {
    let mut value = serde_json::to_value(document).unwrap_or(serde_json::Value::Null);
    if let (Some(out), serde_json::Value::Object(report)) =
        (value.as_object_mut(), &document.report)
    {
        for key in ["diagnostics", "errors", "warnings"] {
            if let Some(v) = report.get(key) {
                out.insert(key.to_string(), v.clone());
            }
        }
    }
    serde_json::to_string_pretty(&value).unwrap_or_default()
}
