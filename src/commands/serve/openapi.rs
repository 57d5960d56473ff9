//! The OpenAPI 3.1 document of the service, written by hand: the endpoints of
//! `routes.rs`, their bodies and answers, and the diagnostics report every error is.

use serde_json::{json, Value};

/// A reference to a schema of `components`.
fn schema(name: &str) -> Value {
    json!({"$ref": format!("#/components/schemas/{name}")})
}

/// A JSON response of `schema`.
fn answer(description: &str, name: &str) -> Value {
    json!({"description": description, "content": {"application/json": {"schema": schema(name)}}})
}

/// The error answers every endpoint with a body may give.
fn errors(with_body: bool) -> Value {
    let mut e = json!({
        "404": answer("no such endpoint (S0003)", "Report"),
        "405": answer("the endpoint does not take this method (S0003)", "Report"),
        "408": answer("the request or its body took too long (S0004)", "Report"),
        "500": answer("the service failed on this request (S0005)", "Report"),
    });
    if with_body {
        e["400"] = answer(
            "the body is not what the endpoint takes (S0001; R0008 for world documents)",
            "Report",
        );
        e["413"] = answer("the body is too large (S0002)", "Report");
    }
    e
}

fn merge(mut a: Value, b: Value) -> Value {
    if let (Some(a), Value::Object(b)) = (a.as_object_mut(), b) {
        a.extend(b);
    }
    a
}

/// A POST endpoint taking `body` and answering `ok` (200) or a document with the
/// failure's status.
fn post(summary: &str, body: &str, ok: &str, failures: Value) -> Value {
    json!({"post": {
        "summary": summary,
        "requestBody": {"required": true, "content": {"application/json": {"schema": schema(body)}}},
        "responses": merge(merge(json!({"200": answer("done", ok)}), failures), errors(true)),
    }})
}

/// Failures of planning endpoints: the plan or run document with `ok: false`.
fn plan_failures(name: &str) -> Value {
    json!({
        "409": answer("the goal is taken or the object is absent (R0010)", name),
        "422": answer("names the cell lacks (R0003, with did-you-mean), no plan (R0004), a world that does not fit (R0009), execution failed (R0007)", name),
        "503": answer("the planning time budget ran out (R0006)", name),
    })
}

/// The document served at `GET /v1/openapi.json`.
pub fn document() -> Value {
    let get = |summary: &str, ok: &str| json!({"get": {"summary": summary, "responses": merge(json!({"200": answer("ok", ok)}), errors(false))}});
    let mut world = get(
        "The world: every object's whereabouts, every arm's joints",
        "World",
    );
    world["put"] = json!({
        "summary": "Replace the world with a world document (docs/world.md), at once",
        "requestBody": {"required": true, "content": {"application/json": {"schema": schema("WorldDocument")}}},
        "responses": merge(merge(json!({"200": answer("the new world", "World")}),
            json!({"422": answer("the document does not fit the cell (R0009)", "Report")})), errors(true)),
    });
    json!({
        "openapi": "3.1.0",
        "info": {
            "title": "cellc planning service",
            "version": env!("CARGO_PKG_VERSION"),
            "description": "A loaded cell and its world: plan, execute and explain move requests. Every error is a diagnostics report (docs/service.md).",
        },
        "paths": {
            "/v1/health": get("Liveness, and which cell is loaded", "Health"),
            "/v1/cell": get("The cell: objects, end-effectors, workspaces, arms", "Cell"),
            "/v1/world": world,
            "/v1/plan": post("Plan a move against a copy of the world (the world is not changed)", "MoveRequest", "PlanDocument", plan_failures("PlanDocument")),
            "/v1/execute": post("Plan and execute a move in the simulator; the world is updated, whether it succeeds or not", "MoveRequest", "RunDocument", plan_failures("RunDocument")),
            "/v1/tasks": post("Execute moves in order; stops at the first that fails, the moves before it stay done", "TaskRequest", "RunDocument", plan_failures("RunDocument")),
            "/v1/explain": post("Why a move has no plan (or its plan when it has one)", "MoveRequest", "Explained", json!({
                "409": answer("the goal is taken (R0010)", "Report"),
                "422": answer("names the cell lacks (R0003)", "Report"),
                "503": answer("the planning time budget ran out (R0006)", "Report"),
            })),
            "/v1/openapi.json": get("This document", "OpenApi"),
        },
        "components": {"schemas": schemas()},
    })
}

fn schemas() -> Value {
    let names =
        |what: &str| json!({"type": "array", "items": {"type": "string"}, "description": what});
    let state = json!({"type": "object", "properties": {
        "end_effector": {"type": "string"}, "grasp": {"type": "string"}, "workspace": {"type": "string"}}});
    let pose = json!({"type": "object", "description": "metres; quaternion (x, y, z, w)", "properties": {
        "position": {"type": "array", "items": {"type": "number"}, "minItems": 3, "maxItems": 3},
        "rotation": {"type": "array", "items": {"type": "number"}, "minItems": 4, "maxItems": 4}}});
    let joints = json!({"type": "object", "properties": {
        "arm": {"type": "string"}, "joints": {"type": "array", "items": {"type": "string"}},
        "positions": {"type": "array", "items": {"type": "number"}}}});
    let placement = json!({"type": "string", "description": "as `cellc plan --from/--to`: `HOLDER[.GRASP] in WORKSPACE` or `HOLDER at (x, y, z) [rpy (r, p, y)]`, metres and degrees unless written", "examples": ["bin in ws_right_bin", "table at (0.4, -0.3, 1.0)"]});
    let report_fields = json!({
        "version": {"type": "integer"},
        "diagnostics": {"type": "array", "items": {"$ref": "#/components/schemas/Diagnostic"}},
        "errors": {"type": "integer"}, "warnings": {"type": "integer"}});
    let s = json!({
        "Diagnostic": {"type": "object", "required": ["code", "severity", "message"], "properties": {
            "code": {"type": "string", "description": "stable code; `cellc explain CODE` prints its page", "examples": ["S0001", "R0003"]},
            "severity": {"type": "string", "enum": ["error", "warning"]},
            "message": {"type": "string"},
            "help": {"type": ["string", "null"]},
            "notes": {"type": "array", "items": {"type": "string"}},
            "labels": {"type": "array", "items": {"type": "object"}, "description": "places in the cell's sources"}}},
        "Report": {"type": "object", "description": "the diagnostics report of `cellc check --format json`", "properties": report_fields.clone()},
        "Health": {"type": "object", "properties": {"status": {"const": "ok"}, "cell": {"type": "string"}, "version": {"type": "string"}}},
        "Cell": {"type": "object", "properties": {
            "cell": {"type": "string"},
            "objects": {"type": "array", "items": {"type": "object", "properties": {
                "name": {"type": "string"},
                "grasps": {"type": "array", "items": {"$ref": "#/components/schemas/Grasp"}},
                "resting_poses": {"type": "array", "items": {"$ref": "#/components/schemas/Grasp"}},
                "states": {"type": "integer"}, "arcs": {"type": "integer"}}}},
            "end_effectors": {"type": "array", "items": {"type": "object", "properties": {
                "name": {"type": "string"}, "movable": {"type": "boolean"},
                "body": {"enum": ["arm", "surface", "abstract"]}, "kind": {"type": ["string", "null"]},
                "reaches": names("workspaces")}}},
            "workspaces": {"type": "array", "items": {"type": "object", "properties": {
                "name": {"type": "string"}, "label": {"type": ["string", "null"]},
                "boxes": {"type": "array", "items": {"type": "object", "properties": {
                    "min": {"type": "array", "items": {"type": "number"}}, "max": {"type": "array", "items": {"type": "number"}}}}},
                "derived": {"type": "boolean"}}}},
            "arms": {"type": "array", "items": {"type": "object", "properties": {
                "name": {"type": "string"}, "robot": {"type": "string"},
                "joints": {"type": "array", "items": {"type": "object", "properties": {
                    "name": {"type": "string"}, "prismatic": {"type": "boolean"},
                    "lower": {"type": ["number", "null"]}, "upper": {"type": ["number", "null"]}}}},
                "home": {"type": "array", "items": {"type": "number"}}}}},
            "requests": names("named requests"), "tasks": names("named tasks")}},
    });
    let s = merge(
        s,
        json!({
            "Grasp": {"type": "object", "properties": {"name": {"type": "string"}, "label": {"type": ["string", "null"]}, "holder": {"type": ["string", "null"], "description": "end-effector or holder kind"}}},
            "State": state,
            "Pose": pose,
            "Joints": joints,
            "World": {"type": "object", "properties": {
                "objects": {"type": "array", "items": {"type": "object", "properties": {
                    "object": {"type": "string"},
                    "state": {"oneOf": [{"$ref": "#/components/schemas/State"}, {"type": "null"}], "description": "null when absent"},
                    "pose": {"oneOf": [{"$ref": "#/components/schemas/Pose"}, {"type": "null"}]}}}},
                "arms": {"type": "array", "items": {"$ref": "#/components/schemas/Joints"}}}},
            "WorldDocument": {"type": "object", "description": "docs/world.md; at most 4 MiB", "additionalProperties": false, "properties": {
                "arms": {"type": "object", "additionalProperties": {"type": "object", "additionalProperties": {"type": "number"}}},
                "objects": {"type": "object", "additionalProperties": {"oneOf": [{"const": "absent"}, {"type": "object", "additionalProperties": false, "properties": {
                    "holder": {"type": "string"}, "grasp": {"type": "string"}, "workspace": {"type": "string"},
                    "at": {"type": "array", "items": {"type": "number"}}, "rpy": {"type": "array", "items": {"type": "number"}},
                    "quat": {"type": "array", "items": {"type": "number"}}}}]}}}},
        }),
    );
    let s = merge(
        s,
        json!({
            "Options": {"type": "object", "additionalProperties": false, "properties": {
                "seed": {"type": "integer", "minimum": 0, "description": "default: `cellc serve --seed`"},
                "motions": {"type": "boolean", "default": true},
                "time_budget_ms": {"type": "integer", "minimum": 0, "default": 10000, "description": "capped at 60000"},
                "clear": {"type": "boolean", "default": false, "description": "move objects in the way to free resting poses first"}}},
            "MoveRequest": {"type": "object", "required": ["object", "to"], "additionalProperties": false, "properties": {
                "object": {"type": "string"},
                "from": merge(placement.clone(), json!({"description": "where the object is; default: where the world has it"})),
                "to": placement.clone(),
                "options": {"$ref": "#/components/schemas/Options"}}},
            "TaskRequest": {"type": "object", "required": ["moves"], "additionalProperties": false, "properties": {
                "moves": {"type": "array", "items": {"type": "object", "required": ["object", "to"], "additionalProperties": false, "properties": {
                    "object": {"type": "string"}, "to": placement}}},
                "options": {"$ref": "#/components/schemas/Options"}}},
        }),
    );
    let s = merge(
        s,
        json!({
            "Plan": {"type": "object", "description": "a plan as `cellc plan --format json` writes it (docs/world.md)", "properties": {
                "request": {"type": "string"}, "object": {"type": "string"}, "strategy": {"type": "string"},
                "cost": {"type": "number"}, "backtracks": {"type": "integer"}, "holders": names("end-effectors in order"),
                "states": {"type": "array", "items": {"$ref": "#/components/schemas/State"}},
                "steps": {"type": "array", "items": {"type": "object"}},
                "detours": {"type": "array", "items": {"type": "object"}}}},
            "PlanDocument": {"type": "object", "description": "the document of `cellc plan --format json`", "properties": merge(report_fields.clone(), json!({
                "kind": {"const": "plan"}, "ok": {"type": "boolean"},
                "plans": {"type": "array", "items": {"$ref": "#/components/schemas/Plan"}},
                "world": {"$ref": "#/components/schemas/World"}}))},
        }),
    );
    let s = merge(
        s,
        json!({
            "RunDocument": {"type": "object", "description": "the document of `cellc run --format json`", "properties": merge(report_fields, json!({
                "kind": {"const": "run"}, "ok": {"type": "boolean"},
                "moves": {"type": "array", "items": {"type": "object", "properties": {
                    "object": {"type": "string"}, "clears": {"type": "string"},
                    "plans": {"type": "array", "items": {"$ref": "#/components/schemas/Plan"}},
                    "log": names("the simulator's log"), "done": {"type": "boolean"},
                    "final_state": {"$ref": "#/components/schemas/State"}, "final_pose": {"$ref": "#/components/schemas/Pose"},
                    "position_error": {"type": ["number", "null"]}, "rotation_error": {"type": ["number", "null"]}}}},
                "world": {"$ref": "#/components/schemas/World"}}))},
        }),
    );
    merge(
        s,
        json!({
            "Explained": {"type": "object", "properties": {
                "reachable": {"type": "boolean"},
                "plan": {"$ref": "#/components/schemas/Plan"},
                "explanation": {"type": ["object", "null"], "properties": {
                    "object": {"type": "string"}, "cause": {"enum": ["missing", "pruned", "failed", "connected"]},
                    "start": {"$ref": "#/components/schemas/State"},
                    "goals": {"type": "array", "items": {"$ref": "#/components/schemas/State"}},
                    "start_side": {"type": "array", "items": {"$ref": "#/components/schemas/State"}},
                    "goal_side": {"type": "array", "items": {"$ref": "#/components/schemas/State"}},
                    "must_leave": {"type": "boolean"},
                    "cut": {"type": "array", "items": {"type": "object", "properties": {"kind": {"type": "string"}, "text": {"type": "string"}}}},
                    "cut_omitted": {"type": "integer"},
                    "suggestions": {"type": "array", "items": {"type": "object", "properties": {"text": {"type": "string"}, "cost": {"type": "number"}}}},
                    "pruned": {"type": "array", "items": {"type": "object"}},
                    "pruned_omitted": {"type": "integer"}}},
                "diagnostic": {"$ref": "#/components/schemas/Report"}}},
            "OpenApi": {"type": "object"},
        }),
    )
}
