//! The service's durable state as a client sees it: which store and revision a world is
//! (`instance`, `revision`, the `ETag`), what interrupted executions left uncertain, and
//! the execution journal (`GET /v1/executions[/{id}]`). The facts come from
//! `cellc-store`; these are their words on the wire.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// An execution the service found in flight when it started again: the world holds what
/// its last recorded step left, and its objects and arms are uncertain until confirmed.
#[derive(Serialize, Deserialize, JsonSchema, Clone, Debug, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Interrupted {
    /// The execution's id in the journal.
    pub execution: u64,
    /// Steps it had finished and recorded (0: none).
    pub steps_done: u32,
    /// Objects to confirm.
    pub objects: Vec<String>,
    /// Arms to confirm.
    pub arms: Vec<String>,
}

/// How an execution of the journal stands.
#[derive(Serialize, Deserialize, JsonSchema, Clone, Copy, Debug, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum ExecutionStatus {
    /// Started and not ended.
    Running,
    /// Every step done.
    Succeeded,
    /// Ended by a failure (its outcome says which).
    Failed,
    /// Stopped by a caller.
    Cancelled,
    /// The service stopped while it ran.
    Interrupted,
}

/// One execution of the journal, without its steps (`GET /v1/executions`).
#[derive(Serialize, Deserialize, JsonSchema, Clone, Debug, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ExecutionSummary {
    /// Its id.
    pub id: u64,
    /// The `Idempotency-Key` it was sent with.
    pub key: Option<String>,
    /// How it stands.
    pub status: ExecutionStatus,
    /// The world revision it started from.
    pub base: u64,
    /// The world revision its end left (`null` while running or interrupted).
    pub result: Option<u64>,
    /// Steps recorded.
    pub steps_done: u32,
    /// Objects it moves (uncertain if it is interrupted).
    pub objects: Vec<String>,
    /// Arms it moves.
    pub arms: Vec<String>,
    /// When it started, milliseconds since the Unix epoch.
    pub started_ms: i64,
    /// When it ended.
    pub finished_ms: Option<i64>,
    /// What was asked: `{"endpoint": …, "request": …}`.
    pub intent: serde_json::Value,
}

/// One recorded step of an execution.
#[derive(Serialize, Deserialize, JsonSchema, Clone, Debug, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ExecutionStep {
    /// 1 for the first step.
    pub index: u32,
    /// The world revision the step left.
    pub revision: u64,
    /// What the executor reported: `{"move": i, "object": …, "step": <plan step>}`.
    pub report: serde_json::Value,
}

/// One execution with its steps and outcome (`GET /v1/executions/{id}`).
// No `deny_unknown_fields`: serde does not support it with a flattened field.
#[derive(Serialize, Deserialize, JsonSchema, Clone, Debug, PartialEq)]
pub struct Execution {
    /// The execution.
    #[serde(flatten)]
    pub summary: ExecutionSummary,
    /// Its recorded steps, in order.
    pub steps: Vec<ExecutionStep>,
    /// The answer it was given (`{"status": HTTP status, "body": run document}`), once
    /// it ended.
    pub outcome: Option<serde_json::Value>,
}

/// `GET /v1/executions`: the newest executions first.
#[derive(Serialize, Deserialize, JsonSchema, Clone, Debug, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Executions {
    /// At most `limit` (default 50) of them.
    pub executions: Vec<ExecutionSummary>,
}
