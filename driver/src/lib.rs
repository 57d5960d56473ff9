//! cellc's way in: what every front end (the `cellc` command line, the service, the
//! language server, the viewer, the exporters, tests and benches) needs to turn a cell's
//! source into a checked artifact and a runtime [`Cell`](cellc_runtime::Cell), and the
//! diagnostics it shows on the way.
//!
//! The cores stay free of policy: the compiler resolves and builds graphs without
//! kinematics or a file system, the runtime verifies and plans what it is given. The
//! pipeline between them (read files through a bounded reader, find `package://` files,
//! compute `reach ARM auto` with the runtime's kinematics, lower, check the scene as a
//! whole, verify every arc) and the words for what the runtime finds (a scene that cannot
//! be verified, pruned arcs, an unreachable goal's explanation) live here, once, so that
//! an embedder gets the answer `cellc build` gives. See [`build()`], and [`load()`] for a
//! cell or an artifact loaded ready to plan, with the diagnostics `cellc plan` gives.

pub mod advice;
pub mod build;
pub mod document;
pub mod explain_report;
pub mod fixes;
pub mod fs_files;
pub mod load;
pub mod reach;
/// Codes of planning requests (the registry's `cellc_lang::codes::request`).
pub use cellc_lang::codes::request as runtime_codes;
pub mod scene_report;
pub mod verify_report;

pub use build::{build, has_arms, BuildOptions, Built};
pub use load::{load, LoadOptions, Loaded};
pub use reach::{compile, compile_reusing, ReachCache};
