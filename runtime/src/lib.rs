//! The cellc runtime: everything that needs geometry and kinematics.
//!
//! It reads artifacts only (never the compiler's types), plus the robot models and meshes
//! they name, handed in as bytes through [`Files`] (the trait the compiler reads through
//! too) so the crate itself does no I/O.
#![warn(missing_docs)]

pub mod closed_chain;
pub mod collision;
pub mod execute;
pub mod explain;
pub mod kinematics;
pub mod math;
pub mod mesh;
pub mod motion;
pub mod plan;
pub mod robot;
pub mod scene;
pub mod symmetry;
pub mod verify;

pub use cellc_schema::files::{FileError, Files, MemoryFiles};
