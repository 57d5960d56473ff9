//! `GET /v1/executions` and `GET /v1/executions/{id}`: the journal, read back. What a
//! client whose request timed out reads to learn whether it ran, and what a restarted
//! service says about the execution it found in flight.

use axum::extract::{Path, Query, State};
use axum::response::{IntoResponse, Response};
use axum::Json;
use cellc_store::{ExecutionId, ExecutionRecord, Status};
use serde::Deserialize;

use super::errors::{ApiError, Failure};
use super::routes::{blocking, Shared};
use crate::state::codes;
use cellc_driver::document::state::{
    Execution, ExecutionStatus, ExecutionStep, ExecutionSummary, Executions,
};

/// How many executions a list gives when the query says nothing, and at most.
const DEFAULT_LIMIT: u32 = 50;
const MOST_LISTED: u32 = 200;

/// `?limit=N`.
#[derive(Deserialize)]
pub struct ListQuery {
    limit: Option<String>,
}

/// `GET /v1/executions?limit=N`: the newest first.
pub async fn list(State(service): Shared, Query(query): Query<ListQuery>) -> Response {
    let limit = match query.limit.as_deref().map(str::parse::<u32>) {
        None => DEFAULT_LIMIT,
        Some(Ok(n)) if (1..=MOST_LISTED).contains(&n) => n,
        Some(_) => {
            return ApiError::new(
                Failure::BadBody,
                codes::BAD_BODY,
                format!("`limit` must be a whole number from 1 to {MOST_LISTED}"),
                "leave it out for the newest 50",
            )
            .into_response()
        }
    };
    blocking(service, move |service, _| {
        match service.read_journal(|store| store.recent(limit)) {
            Ok(records) => Json(Executions {
                executions: records.iter().map(summary).collect(),
            })
            .into_response(),
            Err(e) => e.into_response(),
        }
    })
    .await
}

/// `GET /v1/executions/{id}`: one execution with its steps and outcome.
pub async fn one(State(service): Shared, Path(id): Path<String>) -> Response {
    let unknown = |shown: &str| {
        ApiError::new(
            Failure::NotFound,
            codes::UNKNOWN_EXECUTION,
            format!("no execution {shown} in the journal"),
            "list the journal with GET /v1/executions; it keeps the newest 10,000 ended executions and none older than 30 days",
        )
    };
    let Ok(number) = id.parse::<u64>() else {
        let shown = crate::render::escape(&id)
            .chars()
            .take(40)
            .collect::<String>();
        return unknown(&format!("`{shown}`")).into_response();
    };
    blocking(service, move |service, _| {
        match service.read_journal(|store| store.execution(ExecutionId(number))) {
            Ok(Some(record)) => Json(Execution {
                summary: summary(&record),
                steps: record
                    .steps
                    .iter()
                    .map(|s| ExecutionStep {
                        index: s.index,
                        revision: s.revision.0,
                        report: parsed(&s.report),
                    })
                    .collect(),
                outcome: record.outcome.as_deref().map(parsed),
            })
            .into_response(),
            Ok(None) => unknown(&number.to_string()).into_response(),
            Err(e) => e.into_response(),
        }
    })
    .await
}

/// A record's JSON text as a value (the store keeps what the service wrote; text that
/// does not parse, from a damaged file, is shown as a string rather than refused).
fn parsed(text: &str) -> serde_json::Value {
    serde_json::from_str(text).unwrap_or_else(|_| serde_json::Value::String(text.to_string()))
}

fn summary(record: &ExecutionRecord) -> ExecutionSummary {
    ExecutionSummary {
        id: record.id.0,
        key: record.key.as_ref().map(|k| k.as_str().to_string()),
        status: match record.status {
            Status::Running => ExecutionStatus::Running,
            Status::Succeeded => ExecutionStatus::Succeeded,
            Status::Failed => ExecutionStatus::Failed,
            Status::Cancelled => ExecutionStatus::Cancelled,
            Status::Interrupted => ExecutionStatus::Interrupted,
        },
        base: record.base.0,
        result: record.result.map(|r| r.0),
        steps_done: record.steps_done,
        objects: record.subjects.objects.iter().cloned().collect(),
        arms: record.subjects.arms.iter().cloned().collect(),
        started_ms: record.started_ms,
        finished_ms: record.finished_ms,
        intent: parsed(&record.intent),
    }
}
