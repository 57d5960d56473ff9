//! The rows of a dual_manipulation database, checked against each other and written as
//! an abstract-form cell.
//!
//! The translation keeps every row: a workspace per `Workspaces` row, an `adjacent` line
//! per adjacent pair, an end-effector per `EndEffectors` row with its `Reachability`, an
//! object per `Objects` row, a grasp per `Grasps` row and exactly one directed transition
//! per `Grasp_transitions` row (a pair of rows A -> B and B -> A is written `A <-> B`).
//! Asymmetric transitions and transitions between two grasps of one end-effector are kept:
//! `cellc check` warns about them. Rows that no cell can hold without errors (a
//! transition between two objects or two fixed end-effectors, a workspace nobody
//! reaches, ...) are reported instead, with what to change in the database.
//!
//! Names: the database's names are kept where they can be (quoted with backticks when
//! they are not plain identifiers or are reserved words). Workspaces, end-effectors and
//! objects share one namespace in a cell: a name several of them have gets `_ws<Id>`,
//! `_ee<Id>` or `_obj<Id>` on each. A grasp name several grasps of one object have gets
//! `_<end-effector>` when that tells them apart, otherwise `_<Grasp_id>`. A generated
//! name never takes a name the database has; if it is taken anyway, `_2`, `_3`, ... follow.
//! Every declaration carries its row id in a trailing comment, and a workspace's and a
//! grasp's label is the database name, so the cell leads back to the rows.

mod checks;
mod names;
mod text;

use std::collections::BTreeMap;

use cellc_lang::Diagnostic;

use super::diagnostics as diag;
use super::Database;

pub use checks::check;

/// A cell made from a database, before formatting.
#[derive(Clone, Debug)]
pub struct Converted {
    /// The cell's name (without quotes).
    pub cell_name: String,
    /// The cell text (parses; not yet in the canonical layout).
    pub text: String,
    /// `Grasp_id` -> (object name, grasp name), as written in the cell.
    pub grasps: BTreeMap<i64, (String, String)>,
}

/// Checks the rows and writes the cell; `file_name` is the database's file name (the cell
/// is named after it and the header says where the cell came from).
pub fn convert(db: &Database, file_name: &str) -> Result<Converted, Vec<Diagnostic>> {
    let problems = check(db);
    if !problems.is_empty() {
        return Err(diag::limit(problems));
    }
    Ok(text::write(db, file_name))
}
