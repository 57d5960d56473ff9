//! Errors of the service as HTTP responses: every one is the diagnostics report of
//! `cellc check --format json` (code, message, help, notes) with a status that says
//! whose fault it is, never plain text. The status comes from what failed (a
//! [`Failure`], chosen where the error is made from a typed error), not from the code's
//! text.

use axum::http::StatusCode;
use axum::response::{IntoResponse, Response};
use cellc_driver::document::report::Report;
use cellc_lang::{Code, Diagnostic, SourceMap};
use cellc_runtime::plan::PlanError;
use cellc_runtime::{ExecutionError, TaskError};

/// Codes of the service: requests it cannot take (the registry's `cellc_lang::codes::serve`).
pub use cellc_lang::codes::serve as codes;

/// What kind of failure a request met, which decides its HTTP status.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Failure {
    /// The body is not what the endpoint takes (S0001; R0008 for world documents).
    BadBody,
    /// The body is too large (S0002).
    TooLarge,
    /// No endpoint has this path (S0003).
    NoEndpoint,
    /// The endpoint does not take this method (S0003).
    WrongMethod,
    /// The request or its body took too long (S0004).
    TimedOut,
    /// The service failed (S0005).
    Internal,
    /// The goal is taken or the object is absent (R0010).
    Conflict,
    /// The planning time budget ran out (R0006).
    OutOfTime,
    /// The request is well-formed but cannot be done in this cell: names the cell lacks,
    /// unreachable goals, worlds that do not fit, failed executions.
    CannotDo,
    /// The world moved on from the request's precondition (S0006).
    Precondition,
    /// The state file could not take the write (S0010).
    Storage,
    /// No such execution in the journal (S0013).
    NotFound,
}

impl Failure {
    /// The HTTP status of this failure.
    pub fn status(self) -> StatusCode {
        match self {
            Failure::BadBody => StatusCode::BAD_REQUEST,
            Failure::TooLarge => StatusCode::PAYLOAD_TOO_LARGE,
            Failure::NoEndpoint => StatusCode::NOT_FOUND,
            Failure::WrongMethod => StatusCode::METHOD_NOT_ALLOWED,
            Failure::TimedOut => StatusCode::REQUEST_TIMEOUT,
            Failure::Internal => StatusCode::INTERNAL_SERVER_ERROR,
            Failure::Conflict => StatusCode::CONFLICT,
            Failure::OutOfTime => StatusCode::SERVICE_UNAVAILABLE,
            Failure::CannotDo => StatusCode::UNPROCESSABLE_ENTITY,
            Failure::Precondition => StatusCode::PRECONDITION_FAILED,
            Failure::Storage => StatusCode::INSUFFICIENT_STORAGE,
            Failure::NotFound => StatusCode::NOT_FOUND,
        }
    }

    /// The failure of a planning error.
    pub fn of_plan(e: &PlanError) -> Failure {
        match e {
            PlanError::TimeBudget { .. } => Failure::OutOfTime,
            PlanError::GoalOccupied { .. } | PlanError::Absent { .. } => Failure::Conflict,
            // The request's own option, whatever the cell: the caller's to change.
            PlanError::InvalidOption { .. } => Failure::BadBody,
            _ => Failure::CannotDo,
        }
    }

    /// The failure of a task's move (a replan's failure is its planning error's).
    pub fn of_task(e: &TaskError) -> Failure {
        match e {
            TaskError::Plan(e) | TaskError::Execute(ExecutionError::Replan(e)) => {
                Failure::of_plan(e)
            }
            _ => Failure::CannotDo,
        }
    }
}

/// A request that failed: what failed, and its diagnostics report.
#[derive(Debug)]
pub struct ApiError {
    /// What failed (its status).
    pub failure: Failure,
    /// The diagnostics report.
    pub report: Report,
}

impl ApiError {
    /// An error of the service itself (no source labels).
    pub fn new(
        failure: Failure,
        code: Code,
        message: impl Into<String>,
        help: impl Into<String>,
    ) -> ApiError {
        ApiError::from_diagnostic(
            failure,
            &Diagnostic::error(code, message).help(help),
            &SourceMap::new(),
        )
    }

    /// A diagnostic rendered against `sources`.
    pub fn from_diagnostic(failure: Failure, d: &Diagnostic, sources: &SourceMap) -> ApiError {
        ApiError {
            failure,
            report: Report::new(std::slice::from_ref(d), sources),
        }
    }
}

impl IntoResponse for ApiError {
    fn into_response(self) -> Response {
        (self.failure.status(), axum::Json(self.report)).into_response()
    }
}

/// The answer to a path no endpoint has.
pub fn no_endpoint(method: &str, path: &str, allowed: bool) -> ApiError {
    ApiError::new(
        if allowed {
            Failure::WrongMethod
        } else {
            Failure::NoEndpoint
        },
        codes::NO_ENDPOINT,
        if allowed {
            format!("`{path}` does not take {method}")
        } else {
            format!("no endpoint `{}`", crate::render::escape(path))
        },
        "the endpoints are listed in GET /v1/openapi.json (docs/service.md)",
    )
}

/// S0005: a planning worker stopped without an answer (it panicked).
pub fn worker_failed(e: &tokio::task::JoinError) -> ApiError {
    ApiError::new(
        Failure::Internal,
        codes::INTERNAL,
        format!(
            "the service failed on this request: {}",
            crate::render::escape(&e.to_string())
        ),
        "send it again; if it fails again, report it with the request",
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn failures_of_planning_answer_with_their_status() {
        let budget = PlanError::TimeBudget { searches: 3 };
        assert_eq!(
            Failure::of_plan(&budget).status(),
            StatusCode::SERVICE_UNAVAILABLE
        );
        let replan = TaskError::Execute(ExecutionError::Replan(budget));
        assert_eq!(Failure::of_task(&replan), Failure::OutOfTime);
        let rate = PlanError::InvalidOption {
            name: "rate",
            value: 1000.0,
        };
        assert_eq!(Failure::of_plan(&rate).status(), StatusCode::BAD_REQUEST);
    }
}
