//! The OpenAPI 3.1 document of the service. The schemas of what the service takes and
//! answers are generated from the documents' types (`cellc_driver::document::schemas`,
//! JSON Schema 2020-12, OpenAPI 3.1's own dialect), so the document cannot describe an
//! answer other than the one the handlers build; what is written here is the table of
//! endpoints (the router's, in `mod.rs`) and which status each failure answers with
//! (`errors::Failure`).

use axum::http::StatusCode;
use serde_json::{json, Map, Value};

use super::errors::Failure;

/// A reference to a schema of `components`.
fn schema(name: &str) -> Value {
    json!({"$ref": format!("#/components/schemas/{name}")})
}

/// A JSON response of schema `name`.
fn answer(description: &str, name: &str) -> Value {
    json!({"description": description, "content": {"application/json": {"schema": schema(name)}}})
}

/// The status of a failure as OpenAPI writes it ("422").
fn status(failure: Failure) -> String {
    failure.status().as_u16().to_string()
}

/// The error answers every endpoint may give (`with_body`: those that read a body).
fn errors(with_body: bool) -> Map<String, Value> {
    let mut e = Map::new();
    let mut add = |f: Failure, what: &str| {
        e.insert(status(f), answer(what, "Report"));
    };
    add(Failure::NoEndpoint, "no such endpoint (S0003)");
    add(
        Failure::WrongMethod,
        "the endpoint does not take this method (S0003)",
    );
    add(
        Failure::TimedOut,
        "the request or its body took too long (S0004)",
    );
    add(
        Failure::Internal,
        "the service failed on this request (S0005)",
    );
    if with_body {
        add(
            Failure::BadBody,
            "the body is not what the endpoint takes (S0001; R0008 for world documents; R0012 for a timing option out of range)",
        );
        add(Failure::TooLarge, "the body is too large (S0002)");
    }
    e
}

/// A JSON response of schema `name` or of a report (a request refused before planning,
/// e.g. names the cell lacks, is answered with the report alone).
fn document_or_report(description: &str, name: &str) -> Value {
    let schema = json!({"anyOf": [schema(name), schema("Report")]});
    json!({"description": description, "content": {"application/json": {"schema": schema}}})
}

/// Failures of planning endpoints, answered with `name` (the run document with
/// `ok: false`) or a report.
fn plan_failures(name: &str) -> Map<String, Value> {
    let answer = document_or_report;
    let mut e = Map::new();
    // A rate at which a motion would have too many points is found while planning.
    e.insert(
        status(Failure::BadBody),
        answer("the body is not what the endpoint takes (S0001), a timing option out of range, or a rate at which a motion would have too many points (R0012)", name),
    );
    e.insert(
        status(Failure::Conflict),
        answer("the goal is taken or the object is absent (R0010)", name),
    );
    e.insert(status(Failure::CannotDo), answer("names the cell lacks (R0003, with did-you-mean), no plan (R0004), a world that does not fit (R0009), execution failed (R0007)", name));
    e.insert(
        status(Failure::OutOfTime),
        answer("the planning time budget ran out (R0006)", name),
    );
    e
}

/// Failures of the endpoints that write the world or run executions: preconditions,
/// keys, the state file.
fn write_failures(failures: &mut Map<String, Value>) {
    failures.insert(
        status(Failure::Precondition),
        answer(
            "the world moved on from `If-Match` / `\"revision\"` (S0006)",
            "Report",
        ),
    );
    failures.insert(
        status(Failure::Storage),
        answer(
            "the state file could not take the write; nothing was done (S0010)",
            "Report",
        ),
    );
}

/// Failures of executions (besides planning's): the world is uncertain (S0007), a key
/// interrupted (S0012), a key reused (S0008, 422 among planning's).
fn execution_failures(name: &str) -> Map<String, Value> {
    let mut e = plan_failures(name);
    e.insert(status(Failure::Conflict), document_or_report("the goal is taken or the object is absent (R0010); the world is uncertain (S0007); the key's execution was interrupted (S0012)", name));
    e.insert(status(Failure::CannotDo), document_or_report("names the cell lacks (R0003), no plan (R0004), a world that does not fit (R0009), execution failed (R0007), an idempotency key used for another request (S0008)", name));
    write_failures(&mut e);
    e
}

/// `failures` with 409 also answering S0007 (the world is uncertain) as a report.
fn uncertain_too(mut failures: Map<String, Value>) -> Map<String, Value> {
    let conflict = status(Failure::Conflict);
    if let Some(existing) = failures.get(&conflict) {
        let schema = existing["content"]["application/json"]["schema"].clone();
        failures.insert(
            conflict,
            json!({"description": "the goal is taken or the object is absent (R0010); the world is uncertain (S0007)", "content": {"application/json": {"schema": schema}}}),
        );
    }
    failures
}

/// The responses: 200 with `ok`, the errors of every endpoint, and `failures` (which
/// say more of a status than the errors do, so they win).
fn responses(ok: Value, failures: Map<String, Value>, with_body: bool) -> Value {
    let mut r = Map::new();
    r.insert(StatusCode::OK.as_u16().to_string(), ok);
    r.extend(errors(with_body));
    r.extend(failures);
    Value::Object(r)
}

fn get(summary: &str, ok: &str) -> Value {
    json!({"summary": summary, "responses": responses(answer("ok", ok), Map::new(), false)})
}

/// A POST endpoint taking `body` and answering `ok` (200) or `failures`.
fn post(summary: &str, body: &str, ok: &str, failures: Map<String, Value>) -> Value {
    json!({"post": {
        "summary": summary,
        "requestBody": {"required": true, "content": {"application/json": {"schema": schema(body)}}},
        "responses": responses(answer("done", ok), failures, true),
    }})
}

/// The document served at `GET /v1/openapi.json`.
pub fn document() -> Value {
    let mut put_failures = Map::new();
    put_failures.insert(
        status(Failure::CannotDo),
        answer("the document does not fit the cell (R0009)", "Report"),
    );
    write_failures(&mut put_failures);
    let tagged = |description: &str| {
        let mut a = answer(description, "World");
        a["headers"] = json!({"ETag": {"description": "the world's entity tag, `\"INSTANCE-REVISION\"`", "schema": {"type": "string"}}});
        a
    };
    let if_match = json!({"name": "If-Match", "in": "header", "required": false, "description": "write only if the world is still at this ETag (412, S0006, otherwise)", "schema": {"type": "string"}});
    let key = json!({"name": "Idempotency-Key", "in": "header", "required": false, "description": "the same key again returns the first answer instead of executing again (S0008 for another request)", "schema": {"type": "string", "minLength": 1, "maxLength": 255}});
    let world = json!({
        "get": {"summary": "The world: every object's whereabouts, every arm's joints, its revision and what is uncertain", "responses": responses(tagged("ok"), Map::new(), false)},
        "put": {
            "summary": "Replace the world with a world document (docs/world.md), at once; confirms everything uncertain",
            "parameters": [if_match],
            "requestBody": {"required": true, "content": {"application/json": {"schema": schema("WorldDocument")}}},
            "responses": responses(tagged("the new world"), put_failures.clone(), true),
        },
        "patch": {
            "summary": "Change part of the world: a JSON Merge Patch (RFC 7396) or JSON Patch operations (RFC 6902) of the world document; confirms what it names",
            "parameters": [if_match],
            "requestBody": {"required": true, "content": {
                "application/merge-patch+json": {"schema": {"type": "object"}},
                "application/json-patch+json": {"schema": {"type": "array", "items": {"type": "object"}}},
            }},
            "responses": responses(tagged("the new world"), put_failures, true),
        },
    });
    let execution = |summary: &str, body: &str| {
        let mut p = post(summary, body, "Run", execution_failures("Run"));
        p["post"]["parameters"] = json!([if_match, key]);
        p
    };
    let mut not_found = Map::new();
    not_found.insert(
        status(Failure::NotFound),
        answer("no such execution in the journal (S0013)", "Report"),
    );
    let mut bad_limit = Map::new();
    bad_limit.insert(
        status(Failure::BadBody),
        answer("`limit` is not a number from 1 to 200 (S0001)", "Report"),
    );
    let mut schemas = cellc_driver::document::schemas();
    schemas.insert(
        "OpenApi".into(),
        json!({"type": "object", "description": "this document (OpenAPI 3.1)"}),
    );
    json!({
        "openapi": "3.1.0",
        "info": {
            "title": "cellc planning service",
            "version": env!("CARGO_PKG_VERSION"),
            "description": "A loaded cell and its world: plan, execute and explain move requests. Every error is a diagnostics report (docs/service.md).",
        },
        "paths": {
            "/v1/health": {"get": get("Liveness, and which cell is loaded", "Health")},
            "/v1/cell": {"get": get("The cell: objects, end-effectors, workspaces, arms", "Cell")},
            "/v1/world": world,
            "/v1/plan/follow_joint_trajectory": post("Plan a move as `/v1/plan` does and answer its motions as `control_msgs/action/FollowJointTrajectory` goals, one per arm per step (docs/service.md); a move with no plan is answered with its report", "MoveRequest", "ControllerGoals", uncertain_too(plan_failures("Report"))),
            "/v1/plan": post("Plan a move against a copy of the world (the world is not changed); refused while the world is uncertain (S0007)", "MoveRequest", "Run", uncertain_too(plan_failures("Run"))),
            "/v1/execute": execution("Plan and execute a move in the simulator, journaled step by step; the world is updated, whether it succeeds or not", "MoveRequest"),
            "/v1/tasks": execution("Execute moves in order, journaled step by step; stops at the first that fails, the moves before it stay done", "TaskRequest"),
            "/v1/executions": {"get": {"summary": "The journal's newest executions (`?limit=N`, default 50)", "parameters": [{"name": "limit", "in": "query", "required": false, "schema": {"type": "integer", "minimum": 1, "maximum": 200}}], "responses": responses(answer("ok", "Executions"), bad_limit, false)}},
            "/v1/executions/{id}": {"get": {"summary": "One execution of the journal, with its steps and outcome", "parameters": [{"name": "id", "in": "path", "required": true, "schema": {"type": "integer", "minimum": 1}}], "responses": responses(answer("ok", "Execution"), not_found, false)}},
            "/v1/explain": post("Why a move has no plan (or its plan when it has one); refused while the world is uncertain (S0007)", "MoveRequest", "Explained", uncertain_too(plan_failures("Report"))),
            "/v1/openapi.json": {"get": get("This document", "OpenApi")},
        },
        "components": {"schemas": schemas},
    })
}
