//! Exports of a cell's object-state graphs to other tools' formats, so that planners
//! written elsewhere can reason over the same states and arcs as `cellc plan`.
//!
//! An export reads the artifact (and, to place a request's start and goal, the runtime's
//! `Cell`); it never changes what the planner does.

pub mod pddl;
