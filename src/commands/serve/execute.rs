//! Executions: moves planned and carried out in the simulator with the world's lock held
//! from planning to the last step, so executions are serialised. Each one is journaled
//! before it starts, after every step (with the world that step left) and when it ends;
//! its answer is stored with it, so a retry under the same `Idempotency-Key` gets that
//! answer instead of moving the object again.

use axum::body::Body;
use axum::extract::State;
use axum::http::{HeaderMap, HeaderValue, StatusCode};
use axum::response::{IntoResponse, Response};
use axum::Json;
use cellc_lang::Diagnostic;
use cellc_runtime::plan::{Goal, Step};
use cellc_runtime::{ExecutionError, ObjectId, StepObserver, TaskError, TaskOptions, World};
use cellc_store::{
    End, ExecutionId, ExecutionRecord, IdempotencyKey, NewExecution, Revision, Status, Store,
    StoreError, Subjects, Uncertainty,
};
use serde_json::json;

use super::durable::{etag, etag_header, Durable, Precondition};
use super::errors::{ApiError, Failure};
use super::routes::{
    blocking, locate, plan_error, task_options, MoveBody, OptionsBody, Shared, TaskBody,
};
use super::{read_json, Service, MAX_BODY};
use crate::plan_report::codes;
use crate::state::codes as state_codes;
use cellc_driver::document::plan::Step as StepDocument;
use cellc_driver::document::run::{Kind, Move, Run};
use cellc_driver::document::world::World as WorldAnswer;

/// The headers an execution reads: its key and its precondition.
pub(super) struct Asked {
    key: Option<IdempotencyKey>,
    precondition: Precondition,
}

impl Asked {
    /// Reads `Idempotency-Key` and `If-Match` (S0009 when malformed).
    pub(super) fn read(headers: &HeaderMap) -> Result<Asked, ApiError> {
        let bad_key = || {
            ApiError::new(
                Failure::BadBody,
                state_codes::BAD_HEADER,
                "`Idempotency-Key` must be 1 to 255 visible ASCII characters",
                "send a fresh UUID per logical request, and the same one only to retry it",
            )
        };
        let mut keys = headers.get_all("idempotency-key").iter();
        let key = match (keys.next(), keys.next()) {
            (None, _) => None,
            (Some(_), Some(_)) => return Err(bad_key()),
            (Some(value), None) => {
                let text = value.to_str().map_err(|_| bad_key())?;
                Some(IdempotencyKey::new(text).map_err(|_| bad_key())?)
            }
        };
        Ok(Asked {
            key,
            precondition: Precondition::from_headers(headers)?,
        })
    }
}

/// `POST /v1/execute`: plans and executes a move in the simulator, the world updated.
pub async fn execute(State(service): Shared, headers: HeaderMap, body: Body) -> Response {
    let asked = match Asked::read(&headers) {
        Ok(a) => a,
        Err(e) => return e.into_response(),
    };
    let body: MoveBody = match read_json(body, MAX_BODY).await {
        Ok(b) => b,
        Err(e) => return e.into_response(),
    };
    blocking(service, move |service, cancel| {
        // Refused (R0012) before anything else is looked at, as a body that does not parse.
        let options = match task_options(&body.options, service, cancel) {
            Ok(o) => o,
            Err(e) => return e.into_response(),
        };
        let mut request = body.clone();
        request.revision = None;
        let intent = json!({"endpoint": "/v1/execute", "request": request});
        let mut durable = service.lock_state();
        let expect = match admit(service, &mut durable, &asked, body.revision, &intent) {
            Ok(Admitted::Go(expect)) => expect,
            Ok(Admitted::Answered(r)) => return r,
            Err(e) => return e.into_response(),
        };
        let located = match locate(service, &body, &durable.world) {
            Ok(l) => l,
            Err(e) => return e.into_response(),
        };
        let run = Execution {
            key: asked.key,
            expect,
            intent,
            moves: vec![(located.object, located.goal)],
        };
        run.journaled(service, &mut durable, located.world, &options)
    })
    .await
}

/// `POST /v1/tasks`: moves executed in order, the world updated after each.
pub async fn tasks(State(service): Shared, headers: HeaderMap, body: Body) -> Response {
    let asked = match Asked::read(&headers) {
        Ok(a) => a,
        Err(e) => return e.into_response(),
    };
    let body: TaskBody = match read_json(body, MAX_BODY).await {
        Ok(b) => b,
        Err(e) => return e.into_response(),
    };
    blocking(service, move |service, cancel| {
        // Refused (R0012) before anything else is looked at, as a body that does not parse.
        let options = match task_options(&body.options, service, cancel) {
            Ok(o) => o,
            Err(e) => return e.into_response(),
        };
        let mut request = body.clone();
        request.revision = None;
        let intent = json!({"endpoint": "/v1/tasks", "request": request});
        let mut durable = service.lock_state();
        let expect = match admit(service, &mut durable, &asked, body.revision, &intent) {
            Ok(Admitted::Go(expect)) => expect,
            Ok(Admitted::Answered(r)) => return r,
            Err(e) => return e.into_response(),
        };
        let mut moves = Vec::new();
        for m in &body.moves {
            let as_move = MoveBody {
                object: m.object.clone(),
                from: None,
                to: m.to.clone(),
                options: OptionsBody::default(),
                revision: None,
            };
            match locate(service, &as_move, &durable.world) {
                Ok(l) => moves.push((l.object, l.goal)),
                Err(e) => return e.into_response(),
            }
        }
        let start = durable.world.clone();
        let run = Execution {
            key: asked.key,
            expect,
            intent,
            moves,
        };
        run.journaled(service, &mut durable, start, &options)
    })
    .await
}

/// Whether an execution may start.
enum Admitted {
    /// Yes, with the revision the store must still be at (when a precondition was given).
    Go(Option<Revision>),
    /// Its key's first answer, or why that cannot be given.
    Answered(Response),
}

/// What is checked before an execution starts, in this order: its key (a retry gets its
/// first answer, whatever the world is now), the world's certainty (S0007), its
/// precondition (S0006).
fn admit(
    service: &Service,
    durable: &mut Durable,
    asked: &Asked,
    revision: Option<u64>,
    intent: &serde_json::Value,
) -> Result<Admitted, ApiError> {
    if let Some(key) = &asked.key {
        let found = durable.store.keyed(key).map_err(|e| durable.failed(&e))?;
        if let Some(record) = found {
            if record.intent != intent.to_string().as_str() {
                return Err(key_reused(record.id));
            }
            return Ok(Admitted::Answered(replay(&record)));
        }
    }
    durable.refuse_uncertain(service.loaded.sources())?;
    let precondition = asked.precondition.clone().with_revision(revision);
    Ok(Admitted::Go(durable.check(&precondition)?))
}

/// S0008: the key names another request.
fn key_reused(execution: ExecutionId) -> ApiError {
    ApiError::new(
        Failure::CannotDo,
        state_codes::KEY_REUSED,
        format!("the idempotency key was used by execution {execution} for another request"),
        "use a new key (a UUID) for every logical request, and the same key only to retry it",
    )
}

/// The first answer of a journaled execution, marked as a replay; S0012 for one a stop
/// interrupted.
fn replay(record: &ExecutionRecord) -> Response {
    let stored = record
        .outcome
        .as_deref()
        .and_then(|o| serde_json::from_str::<serde_json::Value>(o).ok());
    match (record.status, stored) {
        (Status::Succeeded | Status::Failed | Status::Cancelled, Some(outcome)) => {
            let status = outcome["status"]
                .as_u64()
                .and_then(|s| u16::try_from(s).ok())
                .and_then(|s| StatusCode::from_u16(s).ok())
                .unwrap_or(StatusCode::OK);
            let world = &outcome["body"]["world"];
            let tag = match (world["instance"].as_str(), world["revision"].as_u64()) {
                (Some(instance), Some(revision)) => {
                    etag_header(&format!("\"{instance}-{revision}\""))
                }
                _ => None,
            };
            let mut response = (status, Json(outcome["body"].clone())).into_response();
            let headers = response.headers_mut();
            headers.insert("idempotent-replayed", HeaderValue::from_static("true"));
            if let Some(tag) = tag {
                // The ETag of the world the first answer produced, as it said then.
                headers.insert("etag", tag);
            }
            response
        }
        _ => ApiError::new(
            Failure::Conflict,
            state_codes::INTERRUPTED,
            format!(
                "execution {} with this key was interrupted after step {} of its plan",
                record.id, record.steps_done
            ),
            format!(
                "confirm where its objects and arms are (PUT or PATCH /v1/world), read GET /v1/executions/{} for what was done, and send what is left with a new key",
                record.id
            ),
        )
        .into_response(),
    }
}

/// An execution about to be journaled and run.
struct Execution {
    key: Option<IdempotencyKey>,
    expect: Option<Revision>,
    intent: serde_json::Value,
    moves: Vec<(ObjectId, Goal)>,
}

/// Journals every step the simulator carries out, with the world it left, before the
/// next one starts. A step that cannot be stored is kept as the error; later steps are
/// not journaled (the execution will be found uncertain).
struct Journal<'a> {
    store: &'a mut dyn Store,
    service: &'a Service,
    cell: &'a cellc_runtime::Cell,
    /// The store and uncertainty the published snapshots carry.
    instance: cellc_store::InstanceId,
    uncertain: Vec<Uncertainty>,
    id: ExecutionId,
    revision: Revision,
    steps: u32,
    /// The world as last stored, and its document.
    last: Option<(World, cellc_schema::WorldDocument)>,
    error: Option<StoreError>,
    /// `--sim-pace`: how many times a robot's time each step takes before it is done.
    pace: f64,
}

/// What a hand's open or close takes at pace 1, seconds.
const HAND_SECONDS: f64 = 0.3;

/// The time a robot takes for `step` at pace 1: its trajectory's, or a hand's.
fn robot_seconds(step: &Step) -> f64 {
    step.motion
        .as_ref()
        .and_then(|t| t.points.last())
        .map_or(HAND_SECONDS, |p| p.time.max(0.0))
}

impl StepObserver for Journal<'_> {
    fn stepped(&mut self, world: &World, object: ObjectId, step: &Step) {
        if self.error.is_some() {
            return;
        }
        if self.pace > 0.0 {
            // The step is under way for that long before it is reported done: a stop of
            // the service meanwhile finds it in flight, as with a real robot.
            let seconds = (robot_seconds(step) * self.pace).min(super::MAX_STEP_SECONDS);
            std::thread::sleep(std::time::Duration::from_secs_f64(seconds));
        }
        let artifact = self.cell.artifact();
        let mut shown = StepDocument::of(artifact, object, step);
        // The trajectory is in the outcome's plan; the journal keeps what was reached.
        shown.motion = None;
        let report = json!({"object": artifact.object_name(object), "step": shown});
        let document = self.cell.world_document(world);
        match self.store.step(self.id, &report.to_string(), &document) {
            Ok(r) => {
                self.revision = r;
                self.steps += 1;
                let stored = as_stored(self.cell, &document, world);
                self.last = Some((stored.clone(), document));
                self.service.publish(super::Snapshot {
                    world: stored,
                    revision: r,
                    instance: self.instance.clone(),
                    uncertain: self.uncertain.clone(),
                });
            }
            Err(e) => self.error = Some(e),
        }
    }
}

/// The world as the state file gives it back (`document` read into the cell), which the
/// service serves instead of the simulator's own: a pose read back from its document is
/// not always the same float as the simulator's (a quaternion's last digit), and an
/// answer, the published world and the world after a restart must be the same bit for
/// bit. A document that does not read back (which a restart would refuse, S0011) leaves
/// the simulator's world.
fn as_stored(
    cell: &cellc_runtime::Cell,
    document: &cellc_schema::WorldDocument,
    simulated: &World,
) -> World {
    cell.world(document, &cellc_runtime::plan::PlanOptions::default())
        .unwrap_or_else(|_| simulated.clone())
}

impl Execution {
    /// Journals the execution, runs it from `start`, journals its end, and answers.
    fn journaled(
        self,
        service: &Service,
        durable: &mut Durable,
        start: World,
        options: &TaskOptions,
    ) -> Response {
        let cell = &service.loaded.cell;
        let subjects = subjects(cell, &start, &self.moves, options.clear);
        let new = NewExecution {
            key: self.key.clone(),
            expect: self.expect,
            intent: self.intent.to_string(),
            subjects: subjects.clone(),
            // Plans are made as the task goes (and remade after a failure): the number of
            // steps is known only as they are done.
            steps: 0,
        };
        let id = match durable.store.begin(&new) {
            Ok(cellc_store::Begun::Started { id, .. }) => id,
            Ok(cellc_store::Begun::Repeated(record)) => return replay(&record),
            Err(StoreError::KeyReused { execution }) => {
                return key_reused(execution).into_response()
            }
            Err(e) => return durable.failed(&e).into_response(),
        };
        let stored_before = cell.world_document(&durable.world);
        let instance = durable.instance().clone();
        let mut journal = Journal {
            instance,
            uncertain: durable.uncertain.clone(),
            store: durable.store.as_mut(),
            service,
            cell,
            id,
            revision: durable.revision,
            steps: 0,
            last: None,
            error: None,
            pace: service.pace,
        };
        let mut simulated = start;
        let run = cell.run_task_observed(&mut simulated, &self.moves, options, Some(&mut journal));
        let (revision, steps, last, error) =
            (journal.revision, journal.steps, journal.last, journal.error);
        let finished = cell.world_document(&simulated);
        let last_stored = last.as_ref().map_or(&stored_before, |(_, d)| d);
        let changed = finished != *last_stored;
        // `finish` writes the world once more when it changed since the last step.
        let result = Revision(revision.0 + u64::from(changed));
        let simulated = as_stored(cell, &finished, &simulated);
        let (status, mut document) = run_document(service, &self.moves, &run, &simulated);
        document.execution = Some(id.0);
        if let Some(w) = document.world.as_mut() {
            w.instance = Some(durable.instance().to_string());
            w.revision = Some(result.0);
        }
        let outcome = json!({"status": status.as_u16(), "body": document});
        let end = if run.failure.is_none() {
            End::Succeeded
        } else {
            End::Failed
        };
        let finish = match error {
            Some(e) => Err(e),
            None => {
                durable
                    .store
                    .finish(id, end, &outcome.to_string(), changed.then_some(&finished))
            }
        };
        match finish {
            Ok(stored) => {
                debug_assert_eq!(
                    stored, result,
                    "finish wrote one revision past the last step"
                );
                durable.world = simulated;
                durable.revision = stored;
                service.publish(durable.snapshot());
                let mut response = (status, Json(document)).into_response();
                if let Some(tag) = etag_header(&etag(durable.instance(), stored)) {
                    response.headers_mut().insert("etag", tag);
                }
                response
            }
            Err(e) => {
                // The simulator went on, the store did not follow: what the store holds is
                // the world as of the last step it took, and this execution is still
                // running in its journal, so a restart finds it interrupted. The service
                // says the same now instead of serving a world the file does not have.
                if let Some((world, _)) = last {
                    durable.world = world;
                }
                durable.revision = revision;
                durable.uncertain.push(Uncertainty {
                    execution: id,
                    steps_done: steps,
                    subjects,
                });
                service.publish(durable.snapshot());
                let d = crate::state::diagnostic(&e, &durable.shown, crate::state::When::Serving)
                    .note(format!(
                        "execution {id} ran in the simulator, but only its first {steps} steps were stored: the world is uncertain for what it moves until confirmed (PUT or PATCH /v1/world)"
                    ));
                ApiError::from_diagnostic(Failure::Storage, &d, &cellc_lang::SourceMap::new())
                    .into_response()
            }
        }
    }
}

/// What an execution moves: the objects asked for (every object when objects in the way
/// may be cleared) and every arm (any may move in its plans). Uncertain if the service
/// stops during it.
fn subjects(
    cell: &cellc_runtime::Cell,
    world: &World,
    moves: &[(ObjectId, Goal)],
    clear: bool,
) -> Subjects {
    let artifact = cell.artifact();
    let mut subjects = Subjects::default();
    let objects: Vec<ObjectId> = if clear {
        (0..artifact.objects.len())
            .map(|i| ObjectId(i as u32))
            .collect()
    } else {
        moves.iter().map(|(o, _)| *o).collect()
    };
    subjects
        .objects
        .extend(objects.iter().map(|o| artifact.object_name(*o).to_string()));
    subjects.arms.extend(
        world
            .arms()
            .iter()
            .enumerate()
            .filter(|(_, q)| q.is_some())
            .map(|(e, _)| {
                artifact
                    .end_effector_name(cellc_schema::EndEffectorId(e as u32))
                    .to_string()
            }),
    );
    subjects
}

/// The run document of what the simulator did, with the status it is answered with.
fn run_document(
    service: &Service,
    moves: &[(ObjectId, Goal)],
    run: &cellc_runtime::TaskRun,
    world: &World,
) -> (StatusCode, Run) {
    let cell = &service.loaded.cell;
    let artifact = cell.artifact();
    let several = moves.len() > 1;
    let done: Vec<Move> = run
        .record
        .iter()
        .map(|executed| {
            let name = artifact.object_name(moves[executed.index].0);
            let label = match executed.clears {
                Some(_) => format!("clearing for {name}"),
                None if several => format!("move {} of {}", executed.index + 1, moves.len()),
                None => "request".to_string(),
            };
            Move::of(artifact, executed, &label)
        })
        .collect();
    let diagnostics: Vec<Diagnostic> = run
        .failure
        .iter()
        .map(|f| {
            let d = match &f.error {
                TaskError::Plan(e) => plan_error(artifact, e, None, Some(service.loaded.sources())),
                TaskError::Execute(e) => execution_error(artifact, e),
            };
            if several {
                d.note(format!(
                    "move {} of {} failed; the moves before it were carried out",
                    f.index + 1,
                    moves.len()
                ))
            } else {
                d
            }
        })
        .collect();
    let failure = run
        .failure
        .iter()
        .next()
        .map(|f| Failure::of_task(&f.error));
    let document = Run::new(
        Kind::Run,
        diagnostics.is_empty(),
        Vec::new(),
        done,
        Some(WorldAnswer::of(cell, world)),
        service.loaded.json_report(&diagnostics),
    );
    (failure.map_or(StatusCode::OK, Failure::status), document)
}

/// An execution that failed for good, as R0007 (or the replan's own error).
pub(super) fn execution_error(artifact: &cellc_schema::Artifact, e: &ExecutionError) -> Diagnostic {
    match e {
        ExecutionError::Replan(e) => plan_error(artifact, e, None, None),
        e => Diagnostic::error(codes::EXECUTION_FAILED, format!("execution failed: {e}"))
            .help("the world is where the simulator stopped (GET /v1/world); fix the cause and send the move again"),
    }
}
