//! The run document of `cellc plan --format json`, `cellc run --format json` and the
//! service's `/v1/plan`, `/v1/execute` and `/v1/tasks`: the diagnostics report's fields
//! (`diagnostics`, `errors`, `warnings`) and what was planned or done.

use cellc_runtime::math::Iso;
use cellc_runtime::Executed;
use cellc_schema::{Artifact, Node, ObjectId};
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::plan::{Plan, Pose, State};
use super::report::{Diagnostic, Report};
use super::world::World;

/// The version of the run document (it extends the diagnostics report of
/// `cellc check --format json`, version 1, with more fields).
pub const VERSION: u32 = 1;

/// Which command wrote a run document.
#[derive(Serialize, Deserialize, JsonSchema, Clone, Copy, Debug, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum Kind {
    /// Plans, nothing executed (`cellc plan`, `POST /v1/plan`).
    Plan,
    /// Executions in the simulator (`cellc run`, `POST /v1/execute`, `POST /v1/tasks`).
    Run,
}

/// The whole document of `cellc plan` or `cellc run`.
#[derive(Serialize, Deserialize, JsonSchema, Clone, Debug, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Run {
    /// [`VERSION`].
    pub version: u32,
    /// Which command wrote it.
    pub kind: Kind,
    /// Whether every move was planned (and, for `run`, executed).
    pub ok: bool,
    /// `plan`: the plans, one per move (and one per object cleared out of the way).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub plans: Vec<Plan>,
    /// `run`: each move's execution.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub moves: Vec<Move>,
    /// The world at the end (`plan`: as the plans leave it; `run`: as the simulator did).
    pub world: Option<World>,
    /// The diagnostics (as in the diagnostics report).
    pub diagnostics: Vec<Diagnostic>,
    /// Number of errors among them.
    pub errors: usize,
    /// Number of warnings among them.
    pub warnings: usize,
    /// The service's execution journal entry of this run (`GET /v1/executions/{id}`);
    /// absent from the command line's documents and from plans.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub execution: Option<u64>,
}

impl Run {
    /// A document of `kind`; `ok` says whether every move was planned (or done).
    pub fn new(
        kind: Kind,
        ok: bool,
        plans: Vec<Plan>,
        moves: Vec<Move>,
        world: Option<World>,
        report: Report,
    ) -> Run {
        Run {
            version: VERSION,
            kind,
            ok,
            plans,
            moves,
            world,
            diagnostics: report.diagnostics,
            errors: report.errors,
            warnings: report.warnings,
            execution: None,
        }
    }

    /// The document as the command line writes it: pretty JSON with every object's keys
    /// in sorted order, as `serde_json::Value` keeps them (the form the documents have
    /// always had, so a saved document compares byte for byte).
    pub fn to_text(&self) -> String {
        serde_json::to_value(self)
            .and_then(|v| serde_json::to_string_pretty(&v))
            .unwrap_or_default()
    }
}

/// How one move of `cellc run` went.
#[derive(Serialize, Deserialize, JsonSchema, Clone, Debug, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Move {
    /// The object moved.
    pub object: String,
    /// For a move that takes an object out of the way (`--clear`, `"clear": true`): the
    /// object of the move it clears the way for.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub clears: Option<String>,
    /// The plans executed, in order: the first, then one per replan.
    pub plans: Vec<Plan>,
    /// The simulator's log, one line per step.
    pub log: Vec<String>,
    /// Seconds of motion the simulator played for this move, over every plan executed:
    /// its clock, each motion played by time against the joints' limits.
    #[serde(default)]
    pub motion_time: f64,
    /// Whether the move reached its goal.
    pub done: bool,
    /// Where the object ended, by the simulator.
    pub final_state: Option<State>,
    /// Its pose there.
    pub final_pose: Option<Pose>,
    /// Distance from the goal pose (metres), when the goal has one.
    pub position_error: Option<f64>,
    /// Angle from the goal pose up to the object's symmetries (radians).
    pub rotation_error: Option<f64>,
}

impl Move {
    /// One executed plan of a task: the plans executed (the first, then one per replan,
    /// each labelled `label`), the simulator's log, and where the object ended with its
    /// error from the goal.
    pub fn of(artifact: &Artifact, executed: &Executed, label: &str) -> Move {
        let plan = &executed.plan;
        let end = executed
            .result
            .as_ref()
            .ok()
            .map(|run| (run.final_state, run.final_pose));
        let place = final_place(artifact, plan.object, end, plan.goal.pose);
        let plans = match &executed.result {
            Ok(run) => run
                .plans
                .iter()
                .map(|p| Plan::of(artifact, label, p))
                .collect(),
            Err(_) => vec![Plan::of(artifact, label, plan)],
        };
        Move {
            object: artifact.object_name(plan.object).to_string(),
            clears: executed.clears.map(|o| artifact.object_name(o).to_string()),
            plans,
            log: executed.log.clone(),
            motion_time: executed.motion_time,
            done: executed.result.is_ok(),
            final_state: place.state,
            final_pose: place.pose,
            position_error: place.errors.map(|e| e.0),
            rotation_error: place.errors.map(|e| e.1),
        }
    }
}

/// Where a move left its object, and how far from the goal (metres, radians).
struct FinalPlace {
    state: Option<State>,
    pose: Option<Pose>,
    errors: Option<(f64, f64)>,
}

/// A move's result from what the simulator reports.
fn final_place(
    artifact: &Artifact,
    object: ObjectId,
    end: Option<(Node, Option<Iso>)>,
    goal: Option<Iso>,
) -> FinalPlace {
    let Some((s, p)) = end else {
        return FinalPlace {
            state: None,
            pose: None,
            errors: None,
        };
    };
    let errors = p.zip(goal).map(|(p, g)| {
        let d = g.inverse() * p;
        let symmetries = &artifact.objects[object.index()].symmetries;
        (
            (p.translation.vector - g.translation.vector).norm(),
            cellc_schema::symmetry::residual(&d.rotation, symmetries),
        )
    });
    FinalPlace {
        state: Some(State::of(artifact, object, s)),
        pose: p.as_ref().map(Pose::of),
        errors,
    }
}
