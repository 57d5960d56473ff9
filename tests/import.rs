//! `cellc import dualmanip`.
//!
//! - UI tests: every `tests/ui/import/*.db` is a small database with one problem (made by
//!   `tests/ui/import/make_dbs.py`); the import must fail with exactly the code its file
//!   name starts with, and the rendered diagnostics are snapshotted with a dump of the
//!   database.
//! - Golden tests on the original system's databases (`tests/data/dualmanip/`): the cell
//!   compiles without errors, its graphs have the sizes of the paper's Table I, the output
//!   is canonical and deterministic, and the transitions are exactly the database's rows.
//! - Names: a database with every awkward name (reserved words, shared names, backticks,
//!   NULL) still gives a cell without errors.

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

#[test]
fn ui() {
    let mut failures = Vec::new();
    let mut count = 0;
    insta::glob!("ui/import/*.db", |path| {
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

// ---- the original databases ------------------------------------------------------------

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

/// Each `grasp` line ends with `// Grasp_id N` for the grasp the mapping says it is, and
/// its label is the database's `Grasp_name`.
fn assert_grasp_comments(path: &str, imported: &Imported) {
    let conn = Connection::open(path).unwrap();
    let names: BTreeMap<i64, String> = conn
        .prepare("SELECT Grasp_id, Grasp_name FROM Grasps")
        .unwrap()
        .query_map([], |r| Ok((r.get(0)?, r.get(1)?)))
        .unwrap()
        .collect::<Result<_, _>>()
        .unwrap();
    let mut seen = 0;
    for line in imported.text.lines().map(str::trim) {
        if !line.starts_with("grasp ") {
            continue;
        }
        let (_, id) = line
            .rsplit_once("// Grasp_id ")
            .expect("grasp line has its id");
        let id: i64 = id.parse().unwrap();
        let (_, grasp) = &imported.grasps[&id];
        let written = if cellc_lang::ast::needs_quotes(grasp) {
            format!("grasp `{grasp}` ")
        } else {
            format!("grasp {grasp} ")
        };
        assert!(line.starts_with(&written), "{line}: not grasp {grasp}");
        let label = format!("\"{}\"", names[&id]);
        assert!(line.contains(&label), "{line}: label is not {label}");
        seen += 1;
    }
    assert_eq!(seen, names.len());
}

const VITO: &str = "tests/data/dualmanip/vito_full.db";
const FACTORY: &str = "tests/data/dualmanip/simple_factory.db";

#[test]
fn vito_has_the_papers_graphs() {
    let imported = import(VITO);
    let compilation = compile("vito_full.cell", &imported.text);
    assert_no_errors(&compilation);
    let sizes = graph_sizes(&compilation);
    // Table I of Marino et al.: the pitcher and the colander.
    assert_eq!(sizes["containerA"], (108, 1609));
    assert_eq!(sizes["containerB"], (144, 3426));
    assert_eq!(sizes.len(), 9);
}

#[test]
fn vito_keeps_every_row() {
    let imported = import(VITO);
    let compilation = compile("vito_full.cell", &imported.text);
    assert_transitions_are_the_rows(VITO, &imported, &compilation);
    assert_grasp_comments(VITO, &imported);
    assert_eq!(transition_rows(VITO).len(), 3098);
    assert_eq!(imported.grasps.len(), 208);
}

#[test]
fn vito_warnings_are_the_databases_oddities() {
    let imported = import(VITO);
    let compilation = compile("vito_full.cell", &imported.text);
    let mut counts: BTreeMap<&str, usize> = BTreeMap::new();
    for d in &compilation.diagnostics {
        *counts.entry(d.code.as_str()).or_default() += 1;
    }
    // 116 rows have no reverse row; two of them are also within one hand (Cylinder's
    // `top_kuka1 -> bottom_kuka` and `top -> bot`), reported as W0004 instead.
    assert_eq!(counts.get("W0001"), Some(&114));
    assert_eq!(counts.get("W0004"), Some(&2));
}

#[test]
fn simple_factory_imports_cleanly() {
    let imported = import(FACTORY);
    let compilation = compile("simple_factory.cell", &imported.text);
    assert_no_errors(&compilation);
    assert_transitions_are_the_rows(FACTORY, &imported, &compilation);
    assert_grasp_comments(FACTORY, &imported);
    let sizes = graph_sizes(&compilation);
    assert_eq!(sizes.len(), 3);
}

#[test]
fn output_is_deterministic_and_canonical() {
    for path in [VITO, FACTORY] {
        let first = import(path).text;
        let second = import(path).text;
        assert_eq!(first, second, "{path}: two imports differ");
        let parsed = cellc_lang::parse(cellc_lang::FileId(0), &first);
        assert!(
            parsed.diagnostics.is_empty(),
            "{path}: {:?}",
            parsed.diagnostics
        );
        let formatted = cellc_lang::format(&parsed.file.unwrap(), &first);
        assert_eq!(formatted, first, "{path}: not in the canonical layout");
    }
}

// ---- awkward names ---------------------------------------------------------------------

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
    insta::assert_snapshot!(imported.text);
    let _ = std::fs::remove_dir_all(dir);
}

// ---- the command ----------------------------------------------------------------------

fn cellc(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_cellc"))
        .args(args)
        .output()
        .expect("cellc runs")
}

#[test]
fn command_writes_a_cell_that_checks() {
    let dir = scratch("command");
    let out = dir.join("vito_full.cell");
    let out_s = out.to_string_lossy().to_string();
    let run = cellc(&["import", "dualmanip", VITO, "-o", &out_s]);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    assert!(String::from_utf8_lossy(&run.stdout).contains("cellc check"));
    assert_eq!(std::fs::read_to_string(&out).unwrap(), import(VITO).text);
    assert!(cellc(&["fmt", "--check", &out_s]).status.success());
    assert!(cellc(&["check", &out_s]).status.success());
    // Only the output file is left in the directory (no temporary file).
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 1);
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn command_writes_nothing_on_errors() {
    let dir = scratch("errors");
    let out = dir.join("out.cell");
    let out_s = out.to_string_lossy().to_string();
    let run = cellc(&[
        "import",
        "dualmanip",
        "tests/ui/import/E0604_cross_object.db",
        "-o",
        &out_s,
    ]);
    assert_eq!(run.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&run.stderr).contains("error[E0604]"));
    assert!(!out.exists());
    let run = cellc(&[
        "import",
        "dualmanip",
        "tests/data/dualmanip/no_such.db",
        "-o",
        &out_s,
    ]);
    assert_eq!(run.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&run.stderr).contains("error[E0601]"));
    assert!(!out.exists());
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0);
    let _ = std::fs::remove_dir_all(dir);
}

/// The doc pages of the import's codes show real output: the output pasted under
/// `$ cellc import dualmanip cell.db -o cell.cell` is what the command prints for the UI
/// database the page's example was made from.
#[test]
fn pages_show_real_output() {
    const PAGES: &[(&str, &str)] = &[
        ("E0601", "E0601_not_sqlite.db"),
        ("E0602", "E0602_missing_column.db"),
        ("E0603", "E0603_unknown_grasp.db"),
        ("E0604", "E0604_cross_object.db"),
        ("E0605", "E0605_duplicate_id.db"),
        ("E0606", "E0606_movable_two.db"),
        ("E0607", "E0607_fixed_to_fixed.db"),
        ("E0608", "E0608_unreached_workspace.db"),
        ("E0609", "E0609_useless_adjacency.db"),
    ];
    const COMMAND: &str = "$ cellc import dualmanip cell.db -o cell.cell\n";
    let codes: Vec<&str> = cellc::import::diagnostics::codes::ALL
        .iter()
        .map(|c| c.as_str())
        .collect();
    assert_eq!(codes, PAGES.iter().map(|(c, _)| *c).collect::<Vec<_>>());
    let mut stale = Vec::new();
    for (code, db) in PAGES {
        let page = std::fs::read_to_string(format!("docs/diagnostics/{code}.md")).unwrap();
        let start = page.find(COMMAND).expect("page shows the command") + COMMAND.len();
        let end = start + page[start..].find("```").unwrap();
        let dir = scratch(&format!("page-{code}"));
        std::fs::copy(format!("tests/ui/import/{db}"), dir.join("cell.db")).unwrap();
        let run = Command::new(env!("CARGO_BIN_EXE_cellc"))
            .args(["import", "dualmanip", "cell.db", "-o", "cell.cell"])
            .current_dir(&dir)
            .output()
            .unwrap();
        let printed = format!(
            "{}{}",
            String::from_utf8_lossy(&run.stdout),
            String::from_utf8_lossy(&run.stderr)
        );
        if printed.trim_end() != page[start..end].trim_end() {
            stale.push(format!(
                "docs/diagnostics/{code}.md: the command prints\n{printed}"
            ));
        }
        let _ = std::fs::remove_dir_all(dir);
    }
    assert!(stale.is_empty(), "{}", stale.join("\n"));
}

// ---- random databases ------------------------------------------------------------------

mod random {
    use super::*;
    use proptest::prelude::*;

    /// The schema without primary keys, so that ids can repeat too.
    const LOOSE: &str = "
CREATE TABLE Objects (Id, Name, MeshPath, ObjectCenter);
CREATE TABLE EndEffectors (Id, Name, Movable);
CREATE TABLE Workspaces (Id, Name);
CREATE TABLE WorkspacesAdjacency (id_source, id_target);
CREATE TABLE Reachability (EndEffector_id, Workspace_id);
CREATE TABLE Grasps (Object_id, EndEffector_id, Grasp_id, Grasp_info, Grasp_name);
CREATE TABLE Grasp_transitions (Source_id, Target_id);
";

    /// A value for an id column: mostly small integers (so references often hit), now
    /// and then something else.
    fn id() -> impl Strategy<Value = rusqlite::types::Value> {
        use rusqlite::types::Value;
        prop_oneof![
            400 => (1i64..4).prop_map(Value::Integer),
            1 => Just(Value::Null),
            1 => Just(Value::Text("x".into())),
            1 => Just(Value::Real(2.5)),
        ]
    }

    fn name() -> impl Strategy<Value = rusqlite::types::Value> {
        use rusqlite::types::Value;
        prop_oneof![
            Just(Value::Text("a".into())),
            Just(Value::Text("b".into())),
            Just(Value::Text("table".into())),
            Just(Value::Text("object".into())),
            Just(Value::Text("a b".into())),
            Just(Value::Text("x`y\n".into())),
            Just(Value::Text(String::new())),
            Just(Value::Null),
        ]
    }

    fn movable() -> impl Strategy<Value = rusqlite::types::Value> {
        use rusqlite::types::Value;
        prop_oneof![
            30 => (0i64..2).prop_map(Value::Integer),
            1 => Just(Value::Integer(2)),
        ]
    }

    type Rows = Vec<Vec<rusqlite::types::Value>>;

    fn rows(
        n: usize,
        columns: Vec<BoxedStrategy<rusqlite::types::Value>>,
    ) -> impl Strategy<Value = Rows> {
        prop::collection::vec(columns, 0..n)
    }

    fn database() -> impl Strategy<Value = Vec<(&'static str, Rows)>> {
        (
            rows(4, vec![id().boxed(), name().boxed()]),
            rows(4, vec![id().boxed(), name().boxed(), movable().boxed()]),
            rows(4, vec![id().boxed(), id().boxed()]),
            rows(12, vec![id().boxed(), id().boxed()]),
            rows(3, vec![id().boxed(), name().boxed()]),
            rows(
                8,
                vec![id().boxed(), id().boxed(), id().boxed(), name().boxed()],
            ),
            rows(10, vec![id().boxed(), id().boxed()]),
            prop::bool::weighted(0.2),
        )
            .prop_map(|(mut w, mut e, a, r, mut o, mut g, t, random_ids)| {
                // Mostly give the id columns distinct ids, or every case is an E0605.
                if !random_ids {
                    for (rows, column) in [(&mut w, 0), (&mut e, 0), (&mut o, 0), (&mut g, 2)] {
                        for (i, row) in rows.iter_mut().enumerate() {
                            row[column] = rusqlite::types::Value::Integer(i as i64 + 1);
                        }
                    }
                }
                vec![
                    ("Workspaces(Id, Name)", w),
                    ("EndEffectors(Id, Name, Movable)", e),
                    ("WorkspacesAdjacency(id_source, id_target)", a),
                    ("Reachability(EndEffector_id, Workspace_id)", r),
                    ("Objects(Id, Name)", o),
                    ("Grasps(Object_id, EndEffector_id, Grasp_id, Grasp_name)", g),
                    ("Grasp_transitions(Source_id, Target_id)", t),
                ]
            })
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(200))]

        /// Whatever the rows, the import does not panic, reports only its own codes (the
        /// compiler's last check never has to speak), each with a help line, and a cell it
        /// writes has no errors and keeps every transition row.
        #[test]
        fn random_rows_import_or_fail_cleanly(tables in database()) {
            let dir = scratch("random");
            let db = dir.join("random.db");
            let conn = Connection::open(&db).unwrap();
            conn.execute_batch(LOOSE).unwrap();
            for (table, rows) in &tables {
                for row in rows {
                    let marks = vec!["?"; row.len()].join(", ");
                    conn.execute(
                        &format!("INSERT INTO {table} VALUES ({marks})"),
                        rusqlite::params_from_iter(row.iter()),
                    )
                    .unwrap();
                }
            }
            drop(conn);
            let path = db.to_string_lossy().to_string();
            match cellc::import::dualmanip(&db) {
                Ok(imported) => {
                    let compilation = compile("random.cell", &imported.text);
                    prop_assert!(!compilation.has_errors());
                    assert_transitions_are_the_rows(&path, &imported, &compilation);
                }
                Err(failure) => {
                    prop_assert!(!failure.diagnostics.is_empty());
                    for d in &failure.diagnostics {
                        prop_assert!(
                            d.code.as_str().starts_with("E06"),
                            "{}: {}",
                            d.code,
                            d.message
                        );
                        prop_assert!(d.help.is_some());
                    }
                }
            }
            let _ = std::fs::remove_dir_all(dir);
        }
    }

    /// A tiny deterministic random generator (xorshift), for databases built to be valid.
    struct Rng(u64);

    impl Rng {
        fn next(&mut self) -> u64 {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 7;
            self.0 ^= self.0 << 17;
            self.0
        }

        fn below(&mut self, n: usize) -> usize {
            (self.next() % n as u64) as usize
        }

        fn chance(&mut self, percent: u64) -> bool {
            self.next() % 100 < percent
        }
    }

    const NAMES: &[Option<&str>] = &[
        Some("a"),
        Some("b"),
        Some("table"),
        Some("object"),
        Some("grasp"),
        Some("by"),
        Some("a b"),
        Some("a_b"),
        Some("x`y"),
        Some("line\nbreak"),
        Some(""),
        None,
    ];

    /// Builds a database that breaks no rule: every workspace reached, every end-effector
    /// reaching, adjacency only where a movable end-effector reaches both sides, no
    /// transition between objects or between fixed end-effectors. Names, same-hand
    /// transitions, self transitions and repeated rows are left to chance.
    fn valid_database(path: &Path, seed: u64) {
        let mut rng = Rng(seed | 1);
        let name = |rng: &mut Rng| NAMES[rng.below(NAMES.len())].map(str::to_string);
        let conn = Connection::open(path).unwrap();
        conn.execute_batch(SCHEMA).unwrap();
        let nw = 1 + rng.below(4);
        let ne = 1 + rng.below(4);
        let no = 1 + rng.below(3);
        for w in 1..=nw {
            conn.execute(
                "INSERT INTO Workspaces VALUES (?1, ?2)",
                rusqlite::params![w as i64, name(&mut rng)],
            )
            .unwrap();
        }
        let mut movable = Vec::new();
        let mut reach: Vec<Vec<usize>> = Vec::new();
        for e in 1..=ne {
            let m = rng.chance(60);
            movable.push(m);
            conn.execute(
                "INSERT INTO EndEffectors VALUES (?1, ?2, ?3)",
                rusqlite::params![e as i64, name(&mut rng), m as i64],
            )
            .unwrap();
            let mut reached: Vec<usize> = (1..=nw).filter(|_| rng.chance(50)).collect();
            if reached.is_empty() {
                reached.push(1 + rng.below(nw));
            }
            reach.push(reached);
        }
        for w in 1..=nw {
            if !reach.iter().any(|r| r.contains(&w)) {
                let e = rng.below(ne);
                reach[e].push(w);
            }
        }
        for (e, reached) in reach.iter().enumerate() {
            for &w in reached {
                let times = if rng.chance(10) { 2 } else { 1 };
                for _ in 0..times {
                    conn.execute(
                        "INSERT INTO Reachability VALUES (?1, ?2)",
                        rusqlite::params![e as i64 + 1, w as i64],
                    )
                    .unwrap();
                }
            }
        }
        let mut usable = Vec::new();
        for a in 1..=nw {
            for b in 1..=nw {
                if a != b
                    && (0..ne).any(|e| movable[e] && reach[e].contains(&a) && reach[e].contains(&b))
                {
                    usable.push((a, b));
                }
            }
        }
        let mut adjacency: Vec<(usize, usize)> =
            usable.iter().copied().filter(|_| rng.chance(40)).collect();
        if adjacency.is_empty() && !usable.is_empty() {
            adjacency.push(usable[rng.below(usable.len())]);
        }
        for (a, b) in adjacency {
            conn.execute(
                "INSERT INTO WorkspacesAdjacency VALUES (?1, ?2)",
                rusqlite::params![a as i64, b as i64],
            )
            .unwrap();
        }
        let mut grasp_id = 100;
        for o in 1..=no {
            conn.execute(
                "INSERT INTO Objects VALUES (?1, ?2, NULL, NULL)",
                rusqlite::params![o as i64, name(&mut rng)],
            )
            .unwrap();
            let mut grasps: Vec<(i64, usize)> = Vec::new();
            for _ in 0..rng.below(7) {
                grasp_id += 1 + rng.below(3) as i64;
                let e = rng.below(ne);
                conn.execute(
                    "INSERT INTO Grasps VALUES (?1, ?2, ?3, '', ?4)",
                    rusqlite::params![o as i64, e as i64 + 1, grasp_id, name(&mut rng)],
                )
                .unwrap();
                grasps.push((grasp_id, e));
            }
            for &(g, e) in &grasps {
                for &(h, f) in &grasps {
                    if (movable[e] || movable[f]) && rng.chance(35) {
                        let times = if rng.chance(5) { 2 } else { 1 };
                        for _ in 0..times {
                            conn.execute(
                                "INSERT INTO Grasp_transitions VALUES (?1, ?2)",
                                rusqlite::params![g, h],
                            )
                            .unwrap();
                        }
                    }
                }
            }
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(200))]

        /// A database that breaks no rule always imports, whatever its names, into a cell
        /// without errors, in the canonical layout, with exactly its transition rows.
        #[test]
        fn valid_rows_always_import(seed in any::<u64>()) {
            let dir = scratch("valid");
            let db = dir.join("valid.db");
            valid_database(&db, seed);
            let path = db.to_string_lossy().to_string();
            let imported = match cellc::import::dualmanip(&db) {
                Ok(imported) => imported,
                Err(failure) => {
                    return Err(TestCaseError::fail(render::human(
                        &failure.diagnostics,
                        &failure.sources,
                        Color::Never,
                    )));
                }
            };
            let compilation = compile("valid.cell", &imported.text);
            prop_assert!(!compilation.has_errors());
            assert_transitions_are_the_rows(&path, &imported, &compilation);
            let _ = std::fs::remove_dir_all(dir);
        }
    }
}

/// The paper's Table I figures come out of `cellc info` on the imported database, and
/// survive a round trip through the binary artifact.
#[test]
fn table_one_figures_from_cellc_info() {
    let dir = std::env::temp_dir().join(format!("cellc-table1-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let cell = dir.join("vito_full.cell");
    let artifact = dir.join("vito_full.artifact.bin");
    let run = |args: &[&str]| {
        let out = Command::new(env!("CARGO_BIN_EXE_cellc"))
            .args(args)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{args:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        String::from_utf8_lossy(&out.stdout).to_string()
    };
    run(&[
        "import",
        "dualmanip",
        "tests/data/dualmanip/vito_full.db",
        "-o",
        cell.to_str().unwrap(),
    ]);
    run(&[
        "build",
        cell.to_str().unwrap(),
        "--format",
        "bin",
        "-o",
        artifact.to_str().unwrap(),
    ]);
    for source in [&cell, &artifact] {
        let info = run(&["info", source.to_str().unwrap()]);
        assert!(
            info.contains("  containerA: 108 nodes, 1609 arcs"),
            "{info}"
        );
        assert!(
            info.contains("  containerB: 144 nodes, 3426 arcs"),
            "{info}"
        );
    }
}
