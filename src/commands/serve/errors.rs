//! Errors of the service as HTTP responses: every one is the diagnostics report of
//! `cellc check --format json` (code, message, help, notes) with a status that says
//! whose fault it is, never plain text.

use axum::http::StatusCode;
use axum::response::{IntoResponse, Response};
use cellc_lang::{Code, Diagnostic, SourceMap};

/// Codes of the service: requests it cannot take.
pub mod codes {
    use cellc_lang::Code;
    /// The body is not what the endpoint takes (not JSON, wrong fields or types).
    pub const BAD_BODY: Code = Code("S0001");
    /// The body is larger than the endpoint accepts.
    pub const TOO_LARGE: Code = Code("S0002");
    /// No endpoint has this path, or not with this method.
    pub const NO_ENDPOINT: Code = Code("S0003");
    /// The request took longer than the service gives one.
    pub const TIMED_OUT: Code = Code("S0004");
    /// The service failed on this request (a bug): the request may be sent again.
    pub const INTERNAL: Code = Code("S0005");
    /// Every code of the service.
    pub const ALL: &[Code] = &[BAD_BODY, TOO_LARGE, NO_ENDPOINT, TIMED_OUT, INTERNAL];
}

/// The status a diagnostic's code answers with.
pub fn status_of(code: Code) -> StatusCode {
    match code.as_str() {
        "S0001" | "R0008" => StatusCode::BAD_REQUEST,
        "S0002" => StatusCode::PAYLOAD_TOO_LARGE,
        "S0003" => StatusCode::NOT_FOUND,
        "S0004" => StatusCode::REQUEST_TIMEOUT,
        "S0005" => StatusCode::INTERNAL_SERVER_ERROR,
        "R0010" => StatusCode::CONFLICT,
        "R0006" => StatusCode::SERVICE_UNAVAILABLE,
        // Names the cell lacks, unreachable goals, worlds that do not fit, failed
        // executions: the request is well-formed but cannot be done in this cell.
        _ => StatusCode::UNPROCESSABLE_ENTITY,
    }
}

/// A request that failed: its diagnostic and the sources its labels point into.
pub struct ApiError {
    /// The status (by default the code's, [`status_of`]).
    pub status: StatusCode,
    /// The diagnostics report.
    pub report: serde_json::Value,
}

impl ApiError {
    /// An error of the service itself (no source labels).
    pub fn new(code: Code, message: impl Into<String>, help: impl Into<String>) -> ApiError {
        ApiError::from_diagnostic(
            &Diagnostic::error(code, message).help(help),
            &SourceMap::new(),
        )
    }

    /// A diagnostic rendered against `sources`.
    pub fn from_diagnostic(d: &Diagnostic, sources: &SourceMap) -> ApiError {
        ApiError::with_report(d.code, report(std::slice::from_ref(d), sources))
    }

    /// A report already rendered, answered with `code`'s status.
    pub fn with_report(code: Code, report: serde_json::Value) -> ApiError {
        ApiError {
            status: status_of(code),
            report,
        }
    }
}

/// The diagnostics report of `diagnostics` as a JSON value.
pub fn report(diagnostics: &[Diagnostic], sources: &SourceMap) -> serde_json::Value {
    serde_json::from_str(&crate::render::json(diagnostics, sources))
        .unwrap_or(serde_json::Value::Null)
}

impl IntoResponse for ApiError {
    fn into_response(self) -> Response {
        (self.status, axum::Json(self.report)).into_response()
    }
}

/// The answer to a path no endpoint has.
pub fn no_endpoint(method: &str, path: &str, allowed: bool) -> ApiError {
    let mut e = ApiError::new(
        codes::NO_ENDPOINT,
        if allowed {
            format!("`{path}` does not take {method}")
        } else {
            format!("no endpoint `{}`", crate::render::escape(path))
        },
        "the endpoints are listed in GET /v1/openapi.json (docs/service.md)",
    );
    if allowed {
        e.status = StatusCode::METHOD_NOT_ALLOWED;
    }
    e
}

/// S0005: a planning worker stopped without an answer (it panicked).
pub fn worker_failed(e: &tokio::task::JoinError) -> ApiError {
    ApiError::new(
        codes::INTERNAL,
        format!(
            "the service failed on this request: {}",
            crate::render::escape(&e.to_string())
        ),
        "send it again; if it fails again, report it with the request",
    )
}
