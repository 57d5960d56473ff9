//! Robot descriptions, read once for the compiler and the runtime.
//!
//! The compiler reads a URDF to check a `robot` item (do the links exist, does a chain
//! lead from the base to the tip) and records the chain's movable joints in the artifact;
//! the runtime reads the same file to build kinematics and collision solids. Both go
//! through this crate, so the two can never disagree on which joints make up a chain:
//!
//! - [`Description::parse`]: the text as a typed description (the third-party reader runs
//!   under `catch_unwind`, so a hostile file is an error, never a crash);
//! - [`Description::chain`]: the joints from the base link down to the tip link, in order,
//!   each with its typed facts ([`ChainJoint`]); [`ChainJoint::motion`] validates a
//!   movable joint (supported type, non-zero axis, limits that are an interval);
//! - [`Description::problems`]: everything that makes the file unsound, checked whole and
//!   in linear time (links and joints that do not make one tree; NaN, infinite, reversed or
//!   absurd numbers, with the bounds in [`MAX_LENGTH`], [`MAX_ANGLE`], [`MAX_MASS`] and
//!   [`MAX_SCALE`]), so neither the compiler nor the runtime computes with them;
//! - [`Description::attached_links`] and [`Description::collisions`]: the solids that move
//!   with each link, [`Description::collision_meshes`] the files their meshes name, and
//!   [`MeshPaths`] where those are ([`mesh_path`]: relative to the URDF);
//! - [`package`]: files named as ROS names them (`package://NAME/...`, `file://`), found
//!   through a [`PackagePath`];
//! - [`Srdf`]: the MoveIt semantic description (disabled collision pairs, planning groups,
//!   group states), checked against its URDF;
//! - xacro files are recognised ([`is_xacro_path`], [`ParseError::Xacro`]) so that they
//!   are named as such rather than failing as broken URDFs.
//!
//! Every error is a `#[non_exhaustive]` enum with structured fields; callers turn them
//! into diagnostics (the compiler) or refuse the robot (the runtime). The crate does no
//! I/O: it reads text it is given and resolves paths as strings.
#![warn(missing_docs)]

mod chain;
mod description;
mod geometry;
pub mod package;
mod srdf;
mod validate;

pub use chain::{
    Chain, ChainError, ChainJoint, FingerJoint, JointError, JointKind, JointType, Motion,
    MAX_FINGER_STROKE,
};
pub use description::{is_xacro_path, Description, ParseError};
pub use geometry::{mesh_path, Collision, Geometry, MeshPathError, MeshPaths};
pub use package::{PackagePath, ResolveError};
pub use srdf::{DisabledPair, Group, GroupChainError, GroupState, Srdf, SrdfError, SrdfProblem};
pub use validate::{PoseOf, Problem, MAX_ANGLE, MAX_LENGTH, MAX_MASS, MAX_SCALE, MIN_AXIS_NORM};
