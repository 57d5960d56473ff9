//! The endpoints. Bodies are read and parsed here (so that every refusal is a coded
//! report, not axum's text); the work runs on the blocking pool.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

use axum::body::Body;
use axum::extract::State;
use axum::http::StatusCode;
use axum::response::{IntoResponse, Response};
use axum::Json;
use cellc_lang::Diagnostic;
use cellc_runtime::plan::{Goal, GoalByName, PlanError, PlanOptions};
use cellc_runtime::{ObjectId, TaskError, TaskOptions, World};
use cellc_schema::world::WorldDocumentError;
use cellc_schema::WorldDocument;
use serde::Deserialize;

use super::errors::{status_of, ApiError};
use super::{read_body, read_json, Service, MAX_BODY, MAX_WORLD};
use crate::plan_json::{self, JsonRun};
use crate::plan_report::codes;

pub(super) type Shared = State<Arc<Service>>;

/// A move request: the object, where it is (default: where the world has it) and where
/// it must go, as `cellc plan --from/--to` write placements.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MoveBody {
    pub(super) object: String,
    pub(super) from: Option<String>,
    pub(super) to: String,
    #[serde(default)]
    pub(super) options: OptionsBody,
}

/// A task: moves in order.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TaskBody {
    pub(super) moves: Vec<TaskMove>,
    #[serde(default)]
    pub(super) options: OptionsBody,
}

/// One move of a task.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TaskMove {
    pub(super) object: String,
    pub(super) to: String,
}

/// Planning options; every field may be left out.
#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub struct OptionsBody {
    seed: Option<u64>,
    motions: Option<bool>,
    time_budget_ms: Option<u64>,
    clear: Option<bool>,
}

/// Sets a request's cancel flag when the request is dropped (its client went away or
/// it timed out), so that a plan nobody waits for stops.
struct CancelOnDrop(Arc<AtomicBool>);

impl Drop for CancelOnDrop {
    fn drop(&mut self) {
        self.0.store(true, Ordering::Relaxed);
    }
}

impl OptionsBody {
    pub(super) fn task(&self, service: &Service, cancel: &Arc<AtomicBool>) -> TaskOptions {
        let budget = self
            .time_budget_ms
            .map(std::time::Duration::from_millis)
            .unwrap_or(super::DEFAULT_BUDGET)
            .min(super::MAX_BUDGET);
        TaskOptions {
            plan: PlanOptions {
                seed: self.seed.unwrap_or(service.seed),
                motions: self.motions.unwrap_or(true),
                time_budget: Some(budget),
                cancel: Some(cancel.clone()),
                ..PlanOptions::default()
            },
            clear: self.clear.unwrap_or(false),
            ..TaskOptions::default()
        }
    }
}

/// Runs `work` on the blocking pool, with a cancel flag set if this request goes away.
pub(super) async fn blocking<F>(service: Arc<Service>, work: F) -> Response
where
    F: FnOnce(&Service, &Arc<AtomicBool>) -> Response + Send + 'static,
{
    let cancel = Arc::new(AtomicBool::new(false));
    let guard = CancelOnDrop(cancel.clone());
    let result = tokio::task::spawn_blocking(move || work(&service, &cancel)).await;
    drop(guard);
    result.unwrap_or_else(|e| super::errors::worker_failed(&e).into_response())
}

/// `GET /v1/health`.
pub async fn health(State(service): Shared) -> Response {
    Json(serde_json::json!({
        "status": "ok",
        "cell": service.loaded.cell.artifact().cell,
        "version": env!("CARGO_PKG_VERSION"),
    }))
    .into_response()
}

/// `GET /v1/cell`.
pub async fn cell(State(service): Shared) -> Response {
    Json(super::cell_json::cell(service.loaded.cell.artifact())).into_response()
}

/// `GET /v1/openapi.json`.
pub async fn openapi() -> Response {
    Json(super::openapi::document()).into_response()
}

/// `GET /v1/world`.
/// On the blocking pool: an execution holds the world's lock for as long as it runs, and
/// waiting for it must not stop a thread that serves connections.
pub async fn get_world(State(service): Shared) -> Response {
    blocking(service, |service, _| {
        let world = service.world_now();
        Json(plan_json::world(&service.loaded.cell, &world)).into_response()
    })
    .await
}

/// `PUT /v1/world`: a world document replacing the world at once.
pub async fn put_world(State(service): Shared, body: Body) -> Response {
    let bytes = match read_body(body, MAX_WORLD).await {
        Ok(b) => b,
        Err(e) => return e.into_response(),
    };
    blocking(service, move |service, _| {
        let fail = |d: Diagnostic| ApiError::from_diagnostic(&d, service.loaded.sources());
        let document = match WorldDocument::from_json(&bytes) {
            Ok(d) => d,
            Err(e) => return fail(document_error(e)).into_response(),
        };
        let cell = &service.loaded.cell;
        match cell.world(&document, &PlanOptions::default()) {
            Ok(world) => {
                let json = serde_json::to_value(plan_json::world(cell, &world));
                *service.lock_world() = world;
                Json(json.unwrap_or_default()).into_response()
            }
            Err(e) => fail(crate::world_report::world_diagnostic(
                &e,
                "the world document",
            ))
            .into_response(),
        }
    })
    .await
}

/// R0008 for a body that is not a world document.
fn document_error(e: WorldDocumentError) -> Diagnostic {
    let help = "a world document has `arms` (arm -> joint -> value) and `objects` (object -> placement or \"absent\"); see docs/world.md";
    match e {
        WorldDocumentError::TooLarge { bytes } => Diagnostic::error(
            codes::WORLD_DOCUMENT,
            format!("the world document has {bytes} bytes, more than one may have"),
        )
        .help(help),
        WorldDocumentError::Syntax {
            line,
            column,
            message,
        } => Diagnostic::error(
            codes::WORLD_DOCUMENT,
            format!("line {line}, column {column}: not a world document"),
        )
        .note(crate::render::escape(&message).into_owned())
        .help(help),
    }
}

/// A planning failure as `cellc plan` words it, its advice given in the service's terms
/// (the request's options instead of the command line's flags).
pub(super) fn plan_error(
    artifact: &cellc_schema::Artifact,
    error: &PlanError,
    span: Option<u32>,
    sources: Option<&cellc_lang::SourceMap>,
) -> Diagnostic {
    let mut d = crate::plan_report::plan_error(artifact, error, span, sources);
    if let Some(help) = &mut d.help {
        *help = help
            .replace("`--time-budget`", "`time_budget_ms`")
            .replace("`--clear`", "`\"clear\": true`");
    }
    d
}

/// A move located in the cell and the world it starts in.
pub(super) struct Located {
    pub(super) object: ObjectId,
    pub(super) goal: Goal,
    pub(super) world: World,
}

/// Locates a move body in `world`: its `from` (if given) puts the object there.
pub(super) fn locate(
    service: &Service,
    body: &MoveBody,
    world: &World,
) -> Result<Located, ApiError> {
    let cell = &service.loaded.cell;
    let artifact = cell.artifact();
    let locate_error = |e| {
        ApiError::from_diagnostic(
            &plan_error(artifact, &PlanError::Locate(e), None, None),
            service.loaded.sources(),
        )
    };
    let to = placement(&body.to, "to")?;
    let object = cell.object(&body.object).map_err(locate_error)?;
    match &body.from {
        Some(from) => {
            let from = placement(from, "from")?;
            let request = cell
                .request(
                    &body.object,
                    &from,
                    &GoalByName::Placement(to),
                    PlanOptions::default(),
                )
                .map_err(locate_error)?;
            let world = cell.request_world(world, &request).map_err(|e| {
                ApiError::from_diagnostic(
                    &plan_error(artifact, &e, None, None),
                    service.loaded.sources(),
                )
            })?;
            Ok(Located {
                object,
                goal: request.goal,
                world,
            })
        }
        None => {
            let goal =
                cellc_runtime::plan::names::goal(artifact, object, &GoalByName::Placement(to))
                    .map_err(locate_error)?;
            Ok(Located {
                object,
                goal,
                world: world.clone(),
            })
        }
    }
}

/// A placement in the CLI's words (`table at (0.4, -0.3, 1.0)`, `bin in ws_right_bin`).
fn placement(text: &str, what: &str) -> Result<cellc_runtime::PlacementByName, ApiError> {
    super::super::plan::placement_from_text(text, what).map_err(|failure| {
        let (d, sources) = *failure;
        ApiError::from_diagnostic(&d, &sources)
    })
}

/// `POST /v1/plan`: plans against a copy of the world; the world is not changed.
pub async fn plan(State(service): Shared, body: Body) -> Response {
    let body: MoveBody = match read_json(body, MAX_BODY).await {
        Ok(b) => b,
        Err(e) => return e.into_response(),
    };
    blocking(service, move |service, cancel| {
        let world = service.world_now();
        let located = match locate(service, &body, &world) {
            Ok(l) => l,
            Err(e) => return e.into_response(),
        };
        let options = body.options.task(service, cancel);
        let moves = [(located.object, located.goal)];
        let planned = service
            .loaded
            .cell
            .plan_task(&located.world, &moves, &options);
        plan_response(service, &planned)
    })
    .await
}

/// The plan document of `cellc plan --format json`, with the status of its error.
fn plan_response(service: &Service, planned: &cellc_runtime::TaskPlans) -> Response {
    let cell = &service.loaded.cell;
    let artifact = cell.artifact();
    let mut plans = Vec::new();
    for found in &planned.plans {
        let Some((own, clearing)) = found.split_last() else {
            continue;
        };
        for plan in clearing {
            let label = format!("clearing for {}", artifact.object_name(own.object));
            plans.extend(serde_json::to_value(plan_json::plan(artifact, &label, plan)).ok());
        }
        plans.extend(serde_json::to_value(plan_json::plan(artifact, "request", own)).ok());
    }
    let diagnostics: Vec<Diagnostic> = planned
        .failure
        .iter()
        .map(|f| match &f.error {
            TaskError::Plan(e) => plan_error(artifact, e, None, Some(service.loaded.sources())),
            TaskError::Execute(e) => super::execute::execution_error(artifact, e),
        })
        .collect();
    document(
        JsonRun {
            version: plan_json::VERSION,
            kind: "plan",
            ok: diagnostics.is_empty(),
            plans,
            moves: Vec::new(),
            world: Some(plan_json::world(cell, &planned.world)),
            report: service.loaded.json_report(&diagnostics),
        },
        &diagnostics,
    )
}

/// A plan or run document, answered 200 when it is ok and with its first error's
/// status otherwise.
pub(super) fn document(document: JsonRun, diagnostics: &[Diagnostic]) -> Response {
    let status = diagnostics
        .first()
        .map_or(StatusCode::OK, |d| status_of(d.code));
    let value: serde_json::Value =
        serde_json::from_str(&plan_json::to_text(&document)).unwrap_or_default();
    (status, Json(value)).into_response()
}

/// `POST /v1/explain`: why a move has no plan, or the plan when it has one.
pub async fn explain(State(service): Shared, body: Body) -> Response {
    let body: MoveBody = match read_json(body, MAX_BODY).await {
        Ok(b) => b,
        Err(e) => return e.into_response(),
    };
    blocking(service, move |service, cancel| {
        let world = service.world_now();
        let located = match locate(service, &body, &world) {
            Ok(l) => l,
            Err(e) => return e.into_response(),
        };
        let options = body.options.task(service, cancel).plan;
        let cell = &service.loaded.cell;
        let artifact = cell.artifact();
        match cell.plan_in(&located.world, located.object, &located.goal, &options) {
            Ok(plan) => Json(serde_json::json!({
                "reachable": true,
                "plan": plan_json::plan(artifact, "request", &plan),
            }))
            .into_response(),
            Err(PlanError::Unreachable(u)) => {
                let d = plan_error(
                    artifact,
                    &PlanError::Unreachable(u.clone()),
                    None,
                    Some(service.loaded.sources()),
                );
                let explanation = cell
                    .explain(&u)
                    .ok()
                    .map(|e| super::cell_json::explanation(artifact, &e));
                Json(serde_json::json!({
                    "reachable": false,
                    "explanation": explanation,
                    "diagnostic": service.loaded.json_report(&[d]),
                }))
                .into_response()
            }
            Err(e) => ApiError::from_diagnostic(
                &plan_error(artifact, &e, None, Some(service.loaded.sources())),
                service.loaded.sources(),
            )
            .into_response(),
        }
    })
    .await
}
