#![doc = include_str!("../README.md")]
#![warn(missing_docs)]

// The shared test fixtures name the crate by its name, as the integration tests do.
#[cfg(test)]
extern crate self as cellc_runtime;

// Each public module says why it is public (also in README.md's surface table); its own
// docs are its `//!` text.
pub mod cell;
// A world's objects as one screened collision world (parry), with allowed pairs and a
// per-thread scratch: public for collision benches and tools that query a cell's bodies
// directly, below [`scene`].
pub mod collision;
// Why a request has no plan: the [`Explanation`]'s parts (sides, cut, lost arcs, causes,
// suggested changes) are public because the driver and the service render them.
pub mod explain;
// Forward and inverse kinematics of a [`robot::Robot`], and the closed chain of a
// handoff: public for tools and benches that solve poses the way the planner does (the
// PDDL exporter, the kinematics benches).
pub mod kinematics;
// The geometry types of every public signature ([`Iso`] and its kin), the same ones
// `cellc_schema::math` defines.
pub mod math;
// Mesh files (STL, OBJ, COLLADA) as convex hulls, read within fixed budgets: public so
// that a tool (and the fuzzer) reads a mesh exactly as a cell's loader does.
pub mod mesh;
// Joint-space motion planning: the [`MotionPlanner`] and [`MotionValidity`] seams, the
// default RRT-Connect, and the independent re-check of a trajectory.
pub mod motion;
// Planning requests: the request, goal and plan types (re-exported at the root), the
// [`plan::planner::Planner`] a [`Cell`] lends (to plug another motion planner in), and
// the search graph and locators the benches and the command line's edge reuse.
pub mod plan;
// Reach spaces of arms over surfaces, the solver behind `reach auto`: public because the
// build pipeline (`cellc-driver`) runs it before verification.
pub mod reach;
// Robot models: a URDF serial chain with its collision shapes, what [`kinematics`] and
// [`collision`] work on.
pub mod robot;
// A cell's geometry: its robots, holders, objects' shapes and collision world
// ([`Cell::scene`]), and the state queries every checker asks.
pub mod scene;
// Tasks: several moves in order in one world, planned or executed.
pub mod task;
// Whether a state is valid: the [`StateValidity`] seam and its default,
// [`validity::SceneValidity`].
pub mod validity;
// Verification of a cell's arcs (witnesses, pruned arcs) and the scene's preflight:
// public because the build pipeline (`cellc-driver`) runs them, as [`Cell::verify`]
// does.
pub mod verify;
pub mod world;

// Internal: reached through the items re-exported below, or not at all.
mod collada;
mod execute;
mod observe;
mod rest;
mod swept;
mod symmetry;
mod termination;

pub use cell::{Cell, LoadError};
pub use cellc_schema::{
    Artifact, BlockedPart, BlockedStep, Blocker, EndEffectorId, GraspId, NodeId, ObjectId,
    WorkspaceId,
};
pub use execute::{
    ExecuteOptions, Execution, ExecutionError, Executor, ObservedObject, Quantity, Simulator,
    SimulatorTolerance, StepError,
};
pub use explain::{Explanation, NoStates};
pub use math::Iso;
pub use observe::StepObserver;
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
