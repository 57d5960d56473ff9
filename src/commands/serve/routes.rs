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
use cellc_runtime::motion::{check_timing, MotionError, TimingOptions};
use cellc_runtime::plan::{Goal, GoalByName, PlanError, PlanOptions};
use cellc_runtime::{ObjectId, TaskError, TaskOptions, World};
use cellc_schema::world::WorldDocumentError;
use cellc_schema::WorldDocument;

use super::durable::Precondition;
use super::errors::{ApiError, Failure};
use super::{read_body, read_json, Service, Snapshot, MAX_BODY, MAX_WORLD};
use crate::plan_report::codes;
use axum::http::HeaderMap;
use cellc_driver::advice::FrontEnd;
use cellc_driver::document::explain::{Explained, Explanation};
use cellc_driver::document::plan::Plan as PlanDocument;
use cellc_driver::document::run::{Kind, Run};
use cellc_driver::document::world::World as WorldAnswer;
use cellc_store::Confirms;

pub(super) type Shared = State<Arc<Service>>;

pub use cellc_driver::document::cell::{
    MoveRequest as MoveBody, Options as OptionsBody, TaskRequest as TaskBody,
};

/// Sets a request's cancel flag when the request is dropped (its client went away or
/// it timed out), so that a plan nobody waits for stops.
struct CancelOnDrop(Arc<AtomicBool>);

impl Drop for CancelOnDrop {
    fn drop(&mut self) {
        self.0.store(true, Ordering::Relaxed);
    }
}

/// A request's options as the runtime takes them, or R0012 (400) for a timing option out
/// of range (the runtime's check, so the service and the command line refuse alike).
pub(super) fn task_options(
    body: &OptionsBody,
    service: &Service,
    cancel: &Arc<AtomicBool>,
) -> Result<TaskOptions, ApiError> {
    let defaults = TimingOptions::default();
    let timing = TimingOptions {
        velocity_scaling: body.velocity_scaling.unwrap_or(defaults.velocity_scaling),
        acceleration_scaling: body
            .acceleration_scaling
            .unwrap_or(defaults.acceleration_scaling),
        rate: body.rate,
    };
    if let Err(MotionError::InvalidOption { name, value }) = check_timing(&timing) {
        return Err(ApiError::from_diagnostic(
            Failure::BadBody,
            &crate::plan_report::option_out_of_range(FrontEnd::Service, name, value),
            &cellc_lang::SourceMap::new(),
        ));
    }
    let budget = body
        .time_budget_ms
        .map(std::time::Duration::from_millis)
        .unwrap_or(super::DEFAULT_BUDGET)
        .min(super::MAX_BUDGET);
    Ok(TaskOptions {
        plan: PlanOptions {
            seed: body.seed.unwrap_or(service.seed),
            motions: body.motions.unwrap_or(true),
            time_budget: Some(budget),
            cancel: Some(cancel.clone()),
            timing,
            ..PlanOptions::default()
        },
        clear: body.clear.unwrap_or(false),
        ..TaskOptions::default()
    })
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

/// `GET /v1/health`: liveness, and which store and revision the world is at, with any
/// interruption a client must confirm.
/// On the blocking pool: an execution holds the world's lock while it runs.
pub async fn health(State(service): Shared) -> Response {
    blocking(service, |service, _| {
        let now = service.snapshot();
        Json(cellc_driver::document::cell::Health {
            status: "ok".to_string(),
            cell: service.loaded.cell.artifact().cell.clone(),
            version: env!("CARGO_PKG_VERSION").to_string(),
            instance: now.instance.to_string(),
            revision: now.revision.0,
            durability: service.durability.to_string(),
            interrupted: now.interrupted(),
        })
        .into_response()
    })
    .await
}

/// `GET /v1/cell`.
pub async fn cell(State(service): Shared) -> Response {
    Json(cellc_driver::document::cell::Cell::of(
        service.loaded.cell.artifact(),
    ))
    .into_response()
}

/// `GET /v1/openapi.json`.
pub async fn openapi() -> Response {
    Json(super::openapi::document()).into_response()
}

/// The world answer of a snapshot: the world by names, its instance, revision and
/// uncertainty, and its `ETag`.
pub(super) fn world_answer(service: &Service, now: &Snapshot) -> Response {
    let mut answer = WorldAnswer::of(&service.loaded.cell, &now.world);
    answer.instance = Some(now.instance.to_string());
    answer.revision = Some(now.revision.0);
    answer.uncertain = now.interrupted();
    let mut response = Json(answer).into_response();
    if let Some(tag) = super::durable::etag_header(&now.etag()) {
        response.headers_mut().insert("etag", tag);
    }
    response
}

/// `GET /v1/world`.
/// On the blocking pool: an execution holds the world's lock for as long as it runs, and
/// waiting for it must not stop a thread that serves connections.
pub async fn get_world(State(service): Shared) -> Response {
    blocking(service, |service, _| {
        world_answer(service, &service.snapshot())
    })
    .await
}

/// `PUT /v1/world`: a world document replacing the world at once, stored before it is
/// answered. It confirms everything an interruption left uncertain.
pub async fn put_world(State(service): Shared, headers: HeaderMap, body: Body) -> Response {
    let precondition = match Precondition::from_headers(&headers) {
        Ok(p) => p,
        Err(e) => return e.into_response(),
    };
    let bytes = match read_body(body, MAX_WORLD).await {
        Ok(b) => b,
        Err(e) => return e.into_response(),
    };
    blocking(service, move |service, _| {
        let document = match WorldDocument::from_json(&bytes) {
            Ok(d) => d,
            Err(e) => {
                return ApiError::from_diagnostic(
                    Failure::BadBody,
                    &document_error(e),
                    service.loaded.sources(),
                )
                .into_response()
            }
        };
        store_world(service, &precondition, &document, &Confirms::Everything)
    })
    .await
}

/// Checks `document` against the cell (R0009), then stores it under `precondition` and
/// makes it the world. `confirms` says which uncertainty it settles.
pub(super) fn store_world(
    service: &Service,
    precondition: &Precondition,
    document: &WorldDocument,
    confirms: &Confirms,
) -> Response {
    let cell = &service.loaded.cell;
    let world = match cell.world(document, &PlanOptions::default()) {
        Ok(w) => w,
        Err(e) => {
            return ApiError::from_diagnostic(
                Failure::CannotDo,
                &crate::world_report::world_diagnostic(&e, "the world document"),
                service.loaded.sources(),
            )
            .into_response()
        }
    };
    let mut state = service.lock_state();
    let expect = match state.check(precondition) {
        Ok(e) => e,
        Err(e) => return e.into_response(),
    };
    // What is stored is the document as the world reads back, so the file and the
    // service hold the same world bit for bit.
    let stored = cell.world_document(&world);
    match state.store.put_world(expect, &stored, confirms) {
        Ok(revision) => {
            state.world = world;
            state.revision = revision;
            state.uncertain = confirms.settle(std::mem::take(&mut state.uncertain));
            let now = state.snapshot();
            service.publish(state.snapshot());
            drop(state);
            world_answer(service, &now)
        }
        Err(e) => state.failed(&e).into_response(),
    }
}

/// R0008 for a body that is not a world document.
pub(super) fn document_error(e: WorldDocumentError) -> Diagnostic {
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
    crate::plan_report::plan_error_for(FrontEnd::Service, artifact, error, span, sources)
}

/// A planning failure as the service answers it.
fn plan_failure(service: &Service, error: &PlanError) -> ApiError {
    let artifact = service.loaded.cell.artifact();
    ApiError::from_diagnostic(
        Failure::of_plan(error),
        &plan_error(artifact, error, None, Some(service.loaded.sources())),
        service.loaded.sources(),
    )
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
            Failure::CannotDo,
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
                    Failure::of_plan(&e),
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
        ApiError::from_diagnostic(Failure::CannotDo, &d, &sources)
    })
}

/// The world as last stored, or S0007 when an interruption left it uncertain.
pub(super) fn certain(service: &Service) -> Result<std::sync::Arc<Snapshot>, ApiError> {
    let now = service.snapshot();
    now.refuse_uncertain(service.loaded.sources())?;
    Ok(now)
}

/// A move's body planned against a copy of the world, for `POST /v1/plan` and its
/// controller goals. The options are refused (R0012) before anything else is looked at,
/// as a body that does not parse.
pub(super) fn plan_body(
    service: &Service,
    body: &MoveBody,
    cancel: &Arc<AtomicBool>,
) -> Result<cellc_runtime::TaskPlans, ApiError> {
    let options = task_options(&body.options, service, cancel)?;
    let now = certain(service)?;
    let located = locate(service, body, &now.world)?;
    let moves = [(located.object, located.goal)];
    Ok(service
        .loaded
        .cell
        .plan_task(&located.world, &moves, &options))
}

/// `POST /v1/plan`: plans against a copy of the world; the world is not changed.
pub async fn plan(State(service): Shared, body: Body) -> Response {
    let body: MoveBody = match read_json(body, MAX_BODY).await {
        Ok(b) => b,
        Err(e) => return e.into_response(),
    };
    blocking(service, move |service, cancel| {
        match plan_body(service, &body, cancel) {
            Ok(planned) => plan_response(service, &planned),
            Err(e) => e.into_response(),
        }
    })
    .await
}

/// The plan document of `cellc plan --format json`, with the status of its error.
fn plan_response(service: &Service, planned: &cellc_runtime::TaskPlans) -> Response {
    let cell = &service.loaded.cell;
    let diagnostics: Vec<Diagnostic> = planned
        .failure
        .iter()
        .map(|f| task_failure(service, &f.error))
        .collect();
    document(
        Run::new(
            Kind::Plan,
            diagnostics.is_empty(),
            plan_documents(service, planned),
            Vec::new(),
            Some(WorldAnswer::of(cell, &planned.world)),
            service.loaded.json_report(&diagnostics),
        ),
        planned
            .failure
            .iter()
            .next()
            .map(|f| Failure::of_task(&f.error)),
    )
}

/// The plans of a move as documents, in order: those clearing the way first (`clearing
/// for OBJECT`), the move's own (`request`).
pub(super) fn plan_documents(
    service: &Service,
    planned: &cellc_runtime::TaskPlans,
) -> Vec<PlanDocument> {
    let artifact = service.loaded.cell.artifact();
    let mut plans = Vec::new();
    for found in &planned.plans {
        let Some((own, clearing)) = found.split_last() else {
            continue;
        };
        for plan in clearing {
            let label = format!("clearing for {}", artifact.object_name(own.object));
            plans.push(PlanDocument::of(artifact, &label, plan));
        }
        plans.push(PlanDocument::of(artifact, "request", own));
    }
    plans
}

/// The diagnostic of a move that failed, in the service's terms.
pub(super) fn task_failure(service: &Service, error: &TaskError) -> Diagnostic {
    let artifact = service.loaded.cell.artifact();
    match error {
        TaskError::Plan(e) => plan_error(artifact, e, None, Some(service.loaded.sources())),
        TaskError::Execute(e) => super::execute::execution_error(artifact, e),
    }
}

/// A plan or run document, answered 200 when nothing failed and with its failure's
/// status otherwise.
pub(super) fn document(document: Run, failure: Option<Failure>) -> Response {
    let status = failure.map_or(StatusCode::OK, Failure::status);
    (status, Json(document)).into_response()
}

/// `POST /v1/explain`: why a move has no plan, or the plan when it has one.
pub async fn explain(State(service): Shared, body: Body) -> Response {
    let body: MoveBody = match read_json(body, MAX_BODY).await {
        Ok(b) => b,
        Err(e) => return e.into_response(),
    };
    blocking(service, move |service, cancel| {
        // Refused (R0012) before anything else is looked at, as a body that does not parse.
        let options = match task_options(&body.options, service, cancel) {
            Ok(o) => o.plan,
            Err(e) => return e.into_response(),
        };
        let now = match certain(service) {
            Ok(n) => n,
            Err(e) => return e.into_response(),
        };
        let located = match locate(service, &body, &now.world) {
            Ok(l) => l,
            Err(e) => return e.into_response(),
        };
        let cell = &service.loaded.cell;
        let artifact = cell.artifact();
        match cell.plan_move(&located.world, located.object, &located.goal, &options) {
            Ok(plan) => Json(Explained::Reachable {
                reachable: true,
                plan: PlanDocument::of(artifact, "request", &plan),
            })
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
                    .and_then(|e| Explanation::of(artifact, &e, FrontEnd::Service));
                Json(Explained::Unreachable {
                    reachable: false,
                    explanation,
                    diagnostic: service.loaded.json_report(&[d]),
                })
                .into_response()
            }
            Err(e) => plan_failure(service, &e).into_response(),
        }
    })
    .await
}
