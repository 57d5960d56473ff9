#![doc = include_str!("../README.md")]
#![warn(missing_docs)]

// The shared test fixtures name the crate by its name, as the integration tests do.
#[cfg(test)]
extern crate self as cellc_runtime;

pub mod cell;

#[doc(hidden)]
pub mod closed_chain;
#[doc(hidden)]
pub mod collada;
#[doc(hidden)]
pub mod collision;
#[doc(hidden)]
pub mod execute;
#[doc(hidden)]
pub mod explain;
#[doc(hidden)]
pub mod kinematics;
#[doc(hidden)]
pub mod math;
#[doc(hidden)]
pub mod mesh;
#[doc(hidden)]
pub mod motion;
#[doc(hidden)]
pub mod plan;
#[doc(hidden)]
pub mod reach;
#[doc(hidden)]
pub mod rest;
#[doc(hidden)]
pub mod robot;
#[doc(hidden)]
pub mod scene;
mod swept;
#[doc(hidden)]
pub mod symmetry;
/// Tasks: several moves in order in one world, planned or executed.
pub mod task;
#[doc(hidden)]
pub mod termination;
#[doc(hidden)]
pub mod validity;
#[doc(hidden)]
pub mod verify;
pub mod world;

pub use cell::{Cell, LoadError};
pub use cellc_schema::{
    Artifact, BlockedPart, BlockedStep, Blocker, EndEffectorId, GraspId, NodeId, ObjectId,
    WorkspaceId,
};
pub use execute::{
    ExecuteOptions, Execution, ExecutionError, Executor, ObservedObject, Simulator, StepError,
};
pub use explain::{Explanation, NoStates};
pub use math::Iso;
pub use plan::{
    Around, Command, Detour, Goal, GoalByName, LocateError, Placement, PlacementByName, Plan,
    PlanError, PlanGoal, PlanOptions, Request, Step, Strategy, Trajectory, Unreachable,
};
pub use task::{Executed, TaskError, TaskFailure, TaskOptions, TaskPlans, TaskRun};
pub use verify::{Checked, VerifyOptions};
pub use world::{Whereabouts, World, WorldError};

// The seams: plug in another state checker, motion validator or motion planner, and stop
// a long request from outside.
pub use motion::{MotionPlanner, MotionValidity};
pub use termination::Termination;
pub use validity::StateValidity;

pub use cellc_schema::files::{FileError, Files, MemoryFiles};
