//! `cellc import dualmanip`.
//!
//! - UI tests (here): every `tests/ui/import/*.db` is a small database with one problem
//!   (made by `tests/ui/import/make_dbs.py`); the import must fail with exactly the code its
//!   file name starts with, and the rendered diagnostics are snapshotted with a dump of the
//!   database.
//! - Names (here): a database with every awkward name (reserved words, shared names,
//!   backticks, NULL) still gives a cell without errors (snapshotted).
//! - `golden.rs`: the original system's databases (`tests/data/dualmanip/`): the cell
//!   compiles without errors, its graphs have the sizes of the paper's Table I (also
//!   through `cellc info`), the output is canonical and deterministic, and the transitions
//!   are exactly the database's rows.
//! - `command.rs`: the command line (what it writes, and nothing on errors) and the doc
//!   pages of the import's codes against its real output.
//! - `random.rs`: random rows import or fail cleanly; valid random databases always import.
//!
//! This file also has what they share: importing and compiling, and the checks that a
//! cell keeps its database's rows.

mod command;
mod golden;
mod random;

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::process::Command;

use cellc::import::Imported;
use cellc::render::{self, Color};
use cellc_compiler::{Compilation, MemoryFiles};
use rusqlite::Connection;

fn relative(path: &Path) -> String {
    path.strip_prefix(Path::new(env!("CARGO_MANIFEST_DIR")))
        .unwrap_or(path)
        .to_string_lossy()
        .replace('\\', "/")
}

/// Every table of a database and its rows, as text (for snapshots).
fn dump(path: &Path) -> String {
    let dump = || -> rusqlite::Result<String> {
        let conn = Connection::open_with_flags(path, rusqlite::OpenFlags::SQLITE_OPEN_READ_ONLY)?;
        let mut out = String::new();
        let tables: Vec<String> = conn
            .prepare("SELECT name FROM sqlite_master WHERE type = 'table' ORDER BY name")?
            .query_map([], |r| r.get(0))?
            .collect::<Result<_, _>>()?;
        for table in tables {
            let mut stmt = conn.prepare(&format!("SELECT * FROM \"{table}\" ORDER BY rowid"))?;
            let columns: Vec<String> = stmt.column_names().map(|c| c.to_string()).collect();
            out.push_str(&format!("{table}({})\n", columns.join(", ")));
            let mut rows = stmt.query([])?;
            while let Some(row) = rows.next()? {
                let mut values = Vec::new();
                for i in 0..columns.len() {
                    values.push(match row.get_ref(i)? {
                        rusqlite::types::ValueRef::Null => "NULL".to_string(),
                        rusqlite::types::ValueRef::Integer(n) => n.to_string(),
                        rusqlite::types::ValueRef::Real(f) => f.to_string(),
                        rusqlite::types::ValueRef::Text(t) => {
                            format!("'{}'", String::from_utf8_lossy(t))
                        }
                        rusqlite::types::ValueRef::Blob(b) => format!("<{} bytes>", b.len()),
                    });
                }
                out.push_str(&format!("  ({})\n", values.join(", ")));
            }
        }
        Ok(out)
    };
    dump().unwrap_or_else(|e| format!("(not readable as a database: {e})\n"))
}

/// Snapshots go with the other UI snapshots, in `tests/snapshots/`.
fn snapshot_settings() -> insta::Settings {
    let mut settings = insta::Settings::clone_current();
    settings.set_snapshot_path("../snapshots");
    settings
}

#[test]
fn ui() {
    let mut failures = Vec::new();
    let mut count = 0;
    let _snapshots = snapshot_settings().bind_to_scope();
    insta::glob!("../ui/import", "*.db", |path| {
        count += 1;
        let relative = relative(path);
        let file_name = path.file_name().unwrap().to_string_lossy().to_string();
        let code = file_name.split('_').next().unwrap_or_default().to_string();
        let failure = match cellc::import::dualmanip(Path::new(&relative)) {
            Ok(_) => {
                failures.push(format!("{relative}: imported without errors"));
                return;
            }
            Err(failure) => failure,
        };
        let produced: BTreeSet<&str> = failure
            .diagnostics
            .iter()
            .map(|d| d.code.as_str())
            .collect();
        if produced != BTreeSet::from([code.as_str()]) {
            failures.push(format!(
                "{relative}: expected only {code}, got {produced:?}"
            ));
        }
        if let Some(d) = failure.diagnostics.iter().find(|d| d.help.is_none()) {
            failures.push(format!("{relative}: `{}` has no help", d.message));
        }
        let rendered = render::human(&failure.diagnostics, &failure.sources, Color::Never);
        insta::assert_snapshot!(format!("{}----- diagnostics -----\n{rendered}", dump(path)));
    });
    assert!(count > 0, "no tests/ui/import/*.db found");
    assert!(
        failures.is_empty(),
        "import UI tests failed:\n{}",
        failures.join("\n")
    );
}

// ---- shared by the tests of every module ---------------------------------------------

const VITO: &str = "tests/data/dualmanip/vito_full.db";
const FACTORY: &str = "tests/data/dualmanip/simple_factory.db";

fn import(path: &str) -> Imported {
    match cellc::import::dualmanip(Path::new(path)) {
        Ok(imported) => imported,
        Err(failure) => panic!(
            "{path} did not import:\n{}",
            render::human(&failure.diagnostics, &failure.sources, Color::Never)
        ),
    }
}

fn compile(name: &str, text: &str) -> Compilation {
    cellc_compiler::compile(&MemoryFiles::new([(name, text)]), name)
}

fn assert_no_errors(compilation: &Compilation) {
    let errors: Vec<_> = compilation
        .diagnostics
        .iter()
        .filter(|d| d.is_error())
        .collect();
    assert!(
        errors.is_empty(),
        "{}",
        render::human(&compilation.diagnostics, &compilation.sources, Color::Never)
    );
}

/// (nodes, arcs) of each object's graph, by object name.
fn graph_sizes(compilation: &Compilation) -> BTreeMap<String, (usize, usize)> {
    let cell = compilation.cell.as_ref().expect("the cell resolves");
    compilation
        .graphs
        .iter()
        .map(|g| {
            (
                cell.objects[g.object].name.clone(),
                (g.graph.node_count(), g.graph.edge_count()),
            )
        })
        .collect()
}

/// The rows of `Grasp_transitions`, read straight from the database.
fn transition_rows(path: &str) -> Vec<(i64, i64)> {
    let conn = Connection::open(path).unwrap();
    let mut stmt = conn
        .prepare("SELECT Source_id, Target_id FROM Grasp_transitions")
        .unwrap();
    let rows = stmt.query_map([], |r| Ok((r.get(0)?, r.get(1)?))).unwrap();
    rows.collect::<Result<_, _>>().unwrap()
}

/// The compiled cell's transitions as (source Grasp_id, target Grasp_id), through the
/// import's mapping of grasps.
fn compiled_transitions(imported: &Imported, compilation: &Compilation) -> Vec<(i64, i64)> {
    let cell = compilation.cell.as_ref().expect("the cell resolves");
    let ids: BTreeMap<(&str, &str), i64> = imported
        .grasps
        .iter()
        .map(|(id, (object, grasp))| ((object.as_str(), grasp.as_str()), *id))
        .collect();
    let id = |g: cellc_compiler::ids::GraspId| {
        let grasp = &cell.grasps[g];
        let object = &cell.objects[grasp.object].name;
        ids[&(object.as_str(), grasp.name.as_str())]
    };
    cell.transitions
        .iter()
        .map(|t| (id(t.from), id(t.to)))
        .collect()
}

/// Every database row is exactly one directed transition of the cell, and the reverse.
fn assert_transitions_are_the_rows(path: &str, imported: &Imported, compilation: &Compilation) {
    let mut rows = transition_rows(path);
    rows.sort();
    rows.dedup();
    let mut compiled = compiled_transitions(imported, compilation);
    let n = compiled.len();
    compiled.sort();
    compiled.dedup();
    assert_eq!(n, compiled.len(), "a transition is declared twice");
    assert_eq!(rows, compiled);
}

/// A scratch directory for this test process.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("cellc-import-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

const SCHEMA: &str = "
CREATE TABLE Objects (Id INTEGER PRIMARY KEY, Name TEXT, MeshPath TEXT, ObjectCenter TEXT);
CREATE TABLE EndEffectors (Id INTEGER PRIMARY KEY, Name TEXT, Movable NUMERIC);
CREATE TABLE Workspaces (Id INTEGER PRIMARY KEY, Name TEXT);
CREATE TABLE WorkspacesAdjacency (id_source NUMERIC, id_target NUMERIC);
CREATE TABLE Reachability (EndEffector_id NUMERIC, Workspace_id NUMERIC);
CREATE TABLE Grasps (Object_id NUMERIC, EndEffector_id NUMERIC, Grasp_id INTEGER PRIMARY KEY, Grasp_info BLOB, Grasp_name TEXT);
CREATE TABLE Grasp_transitions (Source_id NUMERIC, Target_id NUMERIC);
";

// ---- awkward names ---------------------------------------------------------------------

/// Names that are reserved words, shared across sorts and within one, not identifiers,
/// with a backtick, empty and NULL; grasp names shared within an object (by one hand and
/// by two); a self transition, a duplicate row and adjacency rows both ways.
const AWKWARD: &str = "
INSERT INTO Workspaces VALUES (1, 'object'), (2, 'table'), (3, 'Left'), (4, 'Left'), (5, NULL);
INSERT INTO WorkspacesAdjacency VALUES (1, 2), (2, 1), (2, 3), (3, 4), (4, 5);
INSERT INTO EndEffectors VALUES (1, 'hand `one`', 1), (2, 'table', 0), (3, 'by', 1), (4, '', 1);
INSERT INTO Reachability VALUES (1, 1), (1, 2), (1, 3), (2, 1), (2, 2), (2, 3), (2, 4), (2, 5),
  (3, 3), (3, 4), (4, 4), (4, 5), (4, 5);
INSERT INTO Objects VALUES (7, 'table', NULL, NULL), (8, 'grasp', 'a \"mesh\"', NULL), (9, NULL, NULL, NULL);
INSERT INTO Grasps VALUES
  (7, 1, 701, '', 'top'), (7, 2, 702, '', 'top'), (7, 3, 703, '', 'top (copy)'),
  (7, 3, 704, '', 'top (copy)'), (7, 4, 705, '', 'top_table'), (7, 2, 706, '', 'reaches'),
  (8, 1, 801, '', 'transition'), (8, 2, 802, '', NULL), (8, 2, 803, '', ''),
  (9, 1, 901, '', 'x'), (9, 2, 902, '', 'line
break');
INSERT INTO Grasp_transitions VALUES (701, 702), (702, 701), (701, 701), (703, 704),
  (702, 703), (702, 703), (705, 706), (706, 705), (801, 802), (802, 801), (803, 801),
  (901, 902), (902, 901);
";

#[test]
fn awkward_names_still_give_a_clean_cell() {
    let dir = scratch("awkward");
    let db = dir.join("awkward names.db");
    let conn = Connection::open(&db).unwrap();
    conn.execute_batch(SCHEMA).unwrap();
    conn.execute_batch(AWKWARD).unwrap();
    drop(conn);
    let path = db.to_string_lossy().to_string();
    let imported = import(&path);
    let compilation = compile("awkward.cell", &imported.text);
    assert_no_errors(&compilation);
    assert_transitions_are_the_rows(&path, &imported, &compilation);
    let _snapshots = snapshot_settings().bind_to_scope();
    insta::assert_snapshot!(imported.text);
    let _ = std::fs::remove_dir_all(dir);
}
