//! Executions: moves planned and carried out in the simulator with the world's lock held
//! from planning to the last step, so executions are serialised and the world is replaced
//! at once with where the simulator left everything.

use axum::body::Body;
use axum::extract::State;
use axum::response::{IntoResponse, Response};
use cellc_lang::Diagnostic;
use cellc_runtime::plan::Goal;
use cellc_runtime::{ExecutionError, ObjectId, TaskError, TaskOptions, World};

use super::errors::Failure;
use super::routes::{
    blocking, document, locate, plan_error, task_options, MoveBody, OptionsBody, Shared, TaskBody,
};
use super::{read_json, Service, MAX_BODY};
use crate::plan_report::codes;
use cellc_driver::document::run::{Kind, Move, Run};
use cellc_driver::document::world::World as WorldDocument;

/// `POST /v1/execute`: plans and executes a move in the simulator, the world updated.
pub async fn execute(State(service): Shared, body: Body) -> Response {
    let body: MoveBody = match read_json(body, MAX_BODY).await {
        Ok(b) => b,
        Err(e) => return e.into_response(),
    };
    blocking(service, move |service, cancel| {
        // Held from planning to the last step: executions are serialised, and no plan
        // is made in a world an execution is changing.
        let mut world = service.lock_world();
        let located = match locate(service, &body, &world) {
            Ok(l) => l,
            Err(e) => return e.into_response(),
        };
        let options = task_options(&body.options, service, cancel);
        run_moves(
            service,
            &mut world,
            located.world,
            &[(located.object, located.goal)],
            &options,
        )
    })
    .await
}

/// `POST /v1/tasks`: moves executed in order, the world updated after each.
pub async fn tasks(State(service): Shared, body: Body) -> Response {
    let body: TaskBody = match read_json(body, MAX_BODY).await {
        Ok(b) => b,
        Err(e) => return e.into_response(),
    };
    blocking(service, move |service, cancel| {
        let mut world = service.lock_world();
        let mut moves = Vec::new();
        for m in &body.moves {
            let as_move = MoveBody {
                object: m.object.clone(),
                from: None,
                to: m.to.clone(),
                options: OptionsBody::default(),
            };
            match locate(service, &as_move, &world) {
                Ok(l) => moves.push((l.object, l.goal)),
                Err(e) => return e.into_response(),
            }
        }
        let options = task_options(&body.options, service, cancel);
        let start = world.clone();
        run_moves(service, &mut world, start, &moves, &options)
    })
    .await
}

/// Executes `moves` from `start` in the simulator and replaces `world` with where the
/// simulator left everything, whether the moves succeeded or not.
fn run_moves(
    service: &Service,
    world: &mut World,
    start: World,
    moves: &[(ObjectId, Goal)],
    options: &TaskOptions,
) -> Response {
    let cell = &service.loaded.cell;
    let artifact = cell.artifact();
    let mut simulated = start;
    let run = cell.run_task(&mut simulated, moves, options);
    *world = simulated;
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
    document(
        Run::new(
            Kind::Run,
            diagnostics.is_empty(),
            Vec::new(),
            done,
            Some(WorldDocument::of(cell, world)),
            service.loaded.json_report(&diagnostics),
        ),
        run.failure
            .iter()
            .next()
            .map(|f| Failure::of_task(&f.error)),
    )
}

/// An execution that failed for good, as R0007 (or the replan's own error).
pub(super) fn execution_error(artifact: &cellc_schema::Artifact, e: &ExecutionError) -> Diagnostic {
    match e {
        ExecutionError::Replan(e) => plan_error(artifact, e, None, None),
        e => Diagnostic::error(codes::EXECUTION_FAILED, format!("execution failed: {e}"))
            .help("the world is where the simulator stopped (GET /v1/world); fix the cause and send the move again"),
    }
}
