//! The cellc runtime: everything that needs geometry and kinematics.
//!
//! It reads artifacts only (never the compiler's types), plus the robot models and meshes
//! they name, handed in as bytes through [`Files`] so the crate itself does no I/O.
#![warn(missing_docs)]

pub mod closed_chain;
pub mod collision;
pub mod execute;
pub mod explain;
pub mod kinematics;
pub mod math;
pub mod motion;
pub mod plan;
pub mod rest;
pub mod robot;
pub mod scene;
pub mod symmetry;
pub mod termination;
pub mod validity;
pub mod verify;

/// Supplies file contents (URDFs, meshes) to the runtime.
pub trait Files {
    /// The bytes of the file at `path`, or why it can't be read.
    fn read(&self, path: &str) -> Result<Vec<u8>, String>;
}
