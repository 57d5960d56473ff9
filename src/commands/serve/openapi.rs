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
            "the body is not what the endpoint takes (S0001; R0008 for world documents)",
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

/// The responses: 200 with `ok`, then `failures`, then the errors of every endpoint.
fn responses(ok: Value, failures: Map<String, Value>, with_body: bool) -> Value {
    let mut r = Map::new();
    r.insert(StatusCode::OK.as_u16().to_string(), ok);
    r.extend(failures);
    r.extend(errors(with_body));
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
    let world = json!({
        "get": get("The world: every object's whereabouts, every arm's joints", "World"),
        "put": {
            "summary": "Replace the world with a world document (docs/world.md), at once",
            "requestBody": {"required": true, "content": {"application/json": {"schema": schema("WorldDocument")}}},
            "responses": responses(answer("the new world", "World"), put_failures, true),
        },
    });
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
            "/v1/plan": post("Plan a move against a copy of the world (the world is not changed)", "MoveRequest", "Run", plan_failures("Run")),
            "/v1/execute": post("Plan and execute a move in the simulator; the world is updated, whether it succeeds or not", "MoveRequest", "Run", plan_failures("Run")),
            "/v1/tasks": post("Execute moves in order; stops at the first that fails, the moves before it stay done", "TaskRequest", "Run", plan_failures("Run")),
            "/v1/explain": post("Why a move has no plan (or its plan when it has one)", "MoveRequest", "Explained", plan_failures("Report")),
            "/v1/openapi.json": {"get": get("This document", "OpenApi")},
        },
        "components": {"schemas": schemas},
    })
}
