//! The documents that cross a boundary, in one home: what `cellc plan`/`run --format
//! json` write, what `cellc view --plan` reads back, what the service answers (and takes),
//! and what the Python client parses. Each is a Rust type with `Serialize + Deserialize`
//! and a JSON Schema derived from it ([`schemas`]), so the service's OpenAPI document is
//! generated from the very types it answers with and a test validates live answers
//! against it.
//!
//! - [`run::Run`]: the plan / run document (plans, executed moves, the world at the end,
//!   and the diagnostics report's fields at its top level).
//! - [`plan::Plan`]: one plan by names; [`world::World`]: the world by names.
//! - [`explain::Explained`]: why a move has no plan (`POST /v1/explain`).
//! - [`report::Report`]: the error document, the diagnostics report every failure is.
//! - [`cell`]: the service's own documents (the cell, health, request bodies).
//! - [`state`]: the durable state (interruptions, the execution journal).
//! - [`controller::ControllerGoals`]: plans' motions as
//!   `control_msgs/action/FollowJointTrajectory` goals (`cellc plan --emit`,
//!   `POST /v1/plan/follow_joint_trajectory`).
//!
//! Names instead of ids, metres and radians, every joint value next to its URDF joint
//! name, so a task planner reads a result without the artifact. The command line writes
//! keys sorted ([`run::Run::to_text`]); the service writes them in declaration order
//! (JSON objects are unordered; only the command line's saved documents are compared
//! byte for byte).

pub mod cell;
pub mod controller;
pub mod explain;
pub mod plan;
pub mod report;
pub mod run;
pub mod state;
pub mod world;

use schemars::generate::SchemaSettings;
use schemars::JsonSchema;

/// Where the schemas of the documents are, in the OpenAPI document.
pub const SCHEMAS_PATH: &str = "/components/schemas";

/// The JSON Schemas (2020-12, the dialect of OpenAPI 3.1) of every document, by name,
/// with references between them into [`SCHEMAS_PATH`]. The service's OpenAPI document is
/// made of these.
pub fn schemas() -> serde_json::Map<String, serde_json::Value> {
    let mut generator = SchemaSettings::draft2020_12()
        .with(|s| s.definitions_path = SCHEMAS_PATH.into())
        .into_generator();
    fn add<T: JsonSchema>(g: &mut schemars::SchemaGenerator) {
        // A named type is stored among the definitions and referenced from here.
        let _ = g.subschema_for::<T>();
    }
    add::<run::Run>(&mut generator);
    add::<plan::Plan>(&mut generator);
    add::<world::World>(&mut generator);
    add::<explain::Explained>(&mut generator);
    add::<report::Report>(&mut generator);
    add::<cell::Cell>(&mut generator);
    add::<cell::Health>(&mut generator);
    add::<cell::MoveRequest>(&mut generator);
    add::<cell::TaskRequest>(&mut generator);
    add::<cellc_schema::WorldDocument>(&mut generator);
    add::<state::Execution>(&mut generator);
    add::<state::Executions>(&mut generator);
    add::<controller::ControllerGoals>(&mut generator);
    generator.take_definitions(true)
}
