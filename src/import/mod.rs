//! `cellc import`: other systems' descriptions of a cell, turned into cell files.
//!
//! Only the reading is here (it is I/O): the SQLite database of the dual_manipulation
//! planner (Marino et al.) is read into plain row structs, every problem a coded
//! diagnostic ([`diagnostics`], E06xx) naming the table and row. [`dualmanip`] checks the
//! rows against each other and writes them as an abstract-form cell. [`dualmanip()`] runs
//! it all and, as a last guard, checks the generated cell with the compiler, so an import
//! that succeeds always gives a cell without errors.

pub mod diagnostics;
pub mod dualmanip;

use std::collections::BTreeMap;
use std::path::Path;

use cellc_lang::{Diagnostic, FileId, SourceMap};
use rusqlite::types::ValueRef;
use rusqlite::{Connection, OpenFlags};

/// A row of `Objects(Id, Name, MeshPath, ObjectCenter)`.
#[derive(Clone, Debug, PartialEq)]
pub struct ObjectRow {
    /// `Id`.
    pub id: i64,
    /// `Name` (`None` when NULL).
    pub name: Option<String>,
    /// `MeshPath`, when the table has that column and the row a value.
    pub mesh_path: Option<String>,
}

/// A row of `EndEffectors(Id, Name, Movable)`.
#[derive(Clone, Debug, PartialEq)]
pub struct EndEffectorRow {
    /// `Id`.
    pub id: i64,
    /// `Name` (`None` when NULL).
    pub name: Option<String>,
    /// `Movable`: 1 for a hand, 0 for a fixed surface (other values are reported later).
    pub movable: i64,
}

/// A row of `Workspaces(Id, Name)`.
#[derive(Clone, Debug, PartialEq)]
pub struct WorkspaceRow {
    /// `Id`.
    pub id: i64,
    /// `Name` (`None` when NULL).
    pub name: Option<String>,
}

/// A row of `WorkspacesAdjacency(id_source, id_target)`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct AdjacencyRow {
    /// `id_source`, a workspace id.
    pub source: i64,
    /// `id_target`, a workspace id.
    pub target: i64,
}

/// A row of `Reachability(EndEffector_id, Workspace_id)`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct ReachabilityRow {
    /// `EndEffector_id`.
    pub end_effector: i64,
    /// `Workspace_id`.
    pub workspace: i64,
}

/// A row of `Grasps(Object_id, EndEffector_id, Grasp_id, Grasp_info, Grasp_name)`.
/// `Grasp_info` (the grasp's geometry, in the original system a serialized message) is
/// not read: the abstract form has no geometry.
#[derive(Clone, Debug, PartialEq)]
pub struct GraspRow {
    /// `Object_id`.
    pub object: i64,
    /// `EndEffector_id`.
    pub end_effector: i64,
    /// `Grasp_id`.
    pub id: i64,
    /// `Grasp_name` (`None` when NULL).
    pub name: Option<String>,
}

/// A row of `Grasp_transitions(Source_id, Target_id)`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct TransitionRow {
    /// `Source_id`, a grasp id.
    pub source: i64,
    /// `Target_id`, a grasp id.
    pub target: i64,
}

/// Every row the import uses, each table sorted by its ids (so the output never depends
/// on the order rows happen to be stored in).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Database {
    /// `Objects`, by `Id`.
    pub objects: Vec<ObjectRow>,
    /// `EndEffectors`, by `Id`.
    pub end_effectors: Vec<EndEffectorRow>,
    /// `Workspaces`, by `Id`.
    pub workspaces: Vec<WorkspaceRow>,
    /// `WorkspacesAdjacency`, by (source, target).
    pub adjacency: Vec<AdjacencyRow>,
    /// `Reachability`, by (end-effector, workspace).
    pub reachability: Vec<ReachabilityRow>,
    /// `Grasps`, by `Grasp_id`.
    pub grasps: Vec<GraspRow>,
    /// `Grasp_transitions`, by (source, target).
    pub transitions: Vec<TransitionRow>,
}

/// A successful import.
#[derive(Clone, Debug)]
pub struct Imported {
    /// The cell, formatted (`cellc fmt --check` passes on it).
    pub text: String,
    /// Every grasp: `Grasp_id` -> (object name, grasp name) as written in the cell.
    pub grasps: BTreeMap<i64, (String, String)>,
}

/// A failed import: the diagnostics and the sources their labels point into (empty for
/// problems of the database, which have no place in any cell file).
#[derive(Debug)]
pub struct Failure {
    /// Every problem found (all errors).
    pub diagnostics: Vec<Diagnostic>,
    /// Files the labels point into.
    pub sources: SourceMap,
}

impl Failure {
    fn database(diagnostics: Vec<Diagnostic>) -> Failure {
        Failure {
            diagnostics,
            sources: SourceMap::new(),
        }
    }
}

/// Imports a dual_manipulation database as a cell. `db` is shown in messages as given.
pub fn dualmanip(db: &Path) -> Result<Imported, Failure> {
    let database = read_dualmanip(db).map_err(Failure::database)?;
    let file_name = db
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| db.to_string_lossy().into_owned());
    let converted = dualmanip::convert(&database, &file_name).map_err(Failure::database)?;
    let cell_path = format!("{}.cell", converted.cell_name);

    // The generated text is parsed and printed by the formatter, so the output is in the
    // canonical layout by construction.
    let parsed = cellc_lang::parse(FileId(0), &converted.text);
    let file = match parsed.file {
        Some(file) if parsed.diagnostics.is_empty() => file,
        _ => {
            let mut sources = SourceMap::new();
            sources.add(cell_path, converted.text);
            return Err(Failure {
                diagnostics: parsed.diagnostics,
                sources,
            });
        }
    };
    let text = cellc_lang::format(&file, &converted.text);

    // The last guard: the rows were checked above, so this finds nothing unless the
    // checks and the compiler disagree. Then the compiler's errors are shown against the
    // cell that would have been written, and nothing is written.
    let world = cellc_compiler::MemoryFiles::new([(cell_path.as_str(), text.as_str())]);
    let compilation = cellc_compiler::compile(&world, &cell_path);
    if compilation.has_errors() {
        return Err(Failure {
            diagnostics: compilation
                .diagnostics
                .into_iter()
                .filter(Diagnostic::is_error)
                .collect(),
            sources: compilation.sources,
        });
    }
    Ok(Imported {
        text,
        grasps: converted.grasps,
    })
}

/// Reads the tables of a dual_manipulation database. Every table is read, so one run
/// reports every missing table, column and mistyped value.
pub fn read_dualmanip(path: &Path) -> Result<Database, Vec<Diagnostic>> {
    let display = path.to_string_lossy().into_owned();
    let conn = open(path, &display).map_err(|d| vec![d])?;
    let mut reader = Reader {
        conn: &conn,
        path: &display,
        diagnostics: Vec::new(),
        fatal: false,
        missing_tables: 0,
    };
    let mut db = Database::default();

    if let Some(rows) = reader.table(
        "Objects",
        &[ID, TEXT, OPTIONAL_TEXT],
        &["Id", "Name", "MeshPath"],
    ) {
        db.objects = rows
            .into_iter()
            .map(|r| ObjectRow {
                id: r[0].id(),
                name: r[1].text(),
                mesh_path: r[2].text(),
            })
            .collect();
    }
    if let Some(rows) = reader.table("EndEffectors", &[ID, TEXT, ID], &["Id", "Name", "Movable"]) {
        db.end_effectors = rows
            .into_iter()
            .map(|r| EndEffectorRow {
                id: r[0].id(),
                name: r[1].text(),
                movable: r[2].id(),
            })
            .collect();
    }
    if let Some(rows) = reader.table("Workspaces", &[ID, TEXT], &["Id", "Name"]) {
        db.workspaces = rows
            .into_iter()
            .map(|r| WorkspaceRow {
                id: r[0].id(),
                name: r[1].text(),
            })
            .collect();
    }
    if let Some(rows) = reader.table(
        "WorkspacesAdjacency",
        &[ID, ID],
        &["id_source", "id_target"],
    ) {
        db.adjacency = rows
            .into_iter()
            .map(|r| AdjacencyRow {
                source: r[0].id(),
                target: r[1].id(),
            })
            .collect();
    }
    if let Some(rows) = reader.table(
        "Reachability",
        &[ID, ID],
        &["EndEffector_id", "Workspace_id"],
    ) {
        db.reachability = rows
            .into_iter()
            .map(|r| ReachabilityRow {
                end_effector: r[0].id(),
                workspace: r[1].id(),
            })
            .collect();
    }
    if let Some(rows) = reader.table(
        "Grasps",
        &[ID, ID, ID, TEXT],
        &["Object_id", "EndEffector_id", "Grasp_id", "Grasp_name"],
    ) {
        db.grasps = rows
            .into_iter()
            .map(|r| GraspRow {
                object: r[0].id(),
                end_effector: r[1].id(),
                id: r[2].id(),
                name: r[3].text(),
            })
            .collect();
    }
    if let Some(rows) = reader.table("Grasp_transitions", &[ID, ID], &["Source_id", "Target_id"]) {
        db.transitions = rows
            .into_iter()
            .map(|r| TransitionRow {
                source: r[0].id(),
                target: r[1].id(),
            })
            .collect();
    }
    if reader.missing_tables == TABLES {
        // An SQLite file of something else: one message, not one per table.
        return Err(vec![diagnostics::no_tables(&display)]);
    }
    if !reader.diagnostics.is_empty() {
        return Err(diagnostics::limit(reader.diagnostics));
    }
    db.objects.sort_by_key(|r| r.id);
    db.end_effectors.sort_by_key(|r| r.id);
    db.workspaces.sort_by_key(|r| r.id);
    db.adjacency.sort();
    db.reachability.sort();
    db.grasps.sort_by_key(|r| r.id);
    db.transitions.sort();
    Ok(db)
}

/// Opens the file read-only and makes sure it is an SQLite database (SQLite opens any
/// file lazily; the first query is what finds out).
fn open(path: &Path, display: &str) -> Result<Connection, Diagnostic> {
    // A pipe or a device would make SQLite wait for ever: only regular files are opened.
    if let Err(e) = cellc_driver::fs_files::regular_file(&path.to_string_lossy()) {
        return Err(diagnostics::cannot_open(display, &e.to_string()));
    }
    let flags = OpenFlags::SQLITE_OPEN_READ_ONLY | OpenFlags::SQLITE_OPEN_NO_MUTEX;
    let conn = Connection::open_with_flags(path, flags)
        .map_err(|e| diagnostics::cannot_open(display, &sqlite_reason(&e)))?;
    conn.query_row("SELECT count(*) FROM sqlite_master", [], |row| {
        row.get::<_, i64>(0)
    })
    .map_err(|e| match e.sqlite_error_code() {
        Some(rusqlite::ErrorCode::NotADatabase) => diagnostics::not_a_database(display),
        _ => diagnostics::cannot_open(display, &sqlite_reason(&e)),
    })?;
    Ok(conn)
}

/// SQLite's own words for an error, without rusqlite's decoration.
fn sqlite_reason(e: &rusqlite::Error) -> String {
    match e {
        rusqlite::Error::SqliteFailure(err, Some(message)) => {
            format!("{message} ({})", describe_code(err.code))
        }
        rusqlite::Error::SqliteFailure(err, None) => describe_code(err.code).to_string(),
        other => other.to_string(),
    }
}

fn describe_code(code: rusqlite::ErrorCode) -> &'static str {
    match code {
        rusqlite::ErrorCode::CannotOpen => "cannot open the file",
        rusqlite::ErrorCode::NotADatabase => "not a database",
        rusqlite::ErrorCode::DatabaseCorrupt => "the database is corrupt",
        rusqlite::ErrorCode::PermissionDenied => "permission denied",
        rusqlite::ErrorCode::DatabaseBusy | rusqlite::ErrorCode::DatabaseLocked => {
            "the database is locked"
        }
        _ => "SQLite error",
    }
}

/// What a column must hold.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Kind {
    /// An integer (an integral real is accepted as the integer it is).
    Id,
    /// Any value, read as text; NULL is kept as `None`.
    Text,
    /// Like `Text`, and the column may be missing.
    OptionalText,
}

const ID: Kind = Kind::Id;
const TEXT: Kind = Kind::Text;
const OPTIONAL_TEXT: Kind = Kind::OptionalText;

/// One value read from a cell of a row.
#[derive(Clone, Debug)]
enum Value {
    Id(i64),
    Text(Option<String>),
}

impl Value {
    fn id(&self) -> i64 {
        match self {
            Value::Id(i) => *i,
            Value::Text(_) => 0,
        }
    }

    fn text(&self) -> Option<String> {
        match self {
            Value::Text(t) => t.clone(),
            Value::Id(i) => Some(i.to_string()),
        }
    }
}

struct Reader<'a> {
    conn: &'a Connection,
    path: &'a str,
    diagnostics: Vec<Diagnostic>,
    /// A read error after which nothing more is read (the file is unreadable).
    fatal: bool,
    /// How many of the tables are missing altogether.
    missing_tables: usize,
}

/// How many tables the import reads.
const TABLES: usize = 7;

impl Reader<'_> {
    /// Reads `columns` of `table`; `None` when the table or a required column is missing
    /// or the file cannot be read. Rows with a value of the wrong type are reported and
    /// left out.
    fn table(&mut self, table: &str, kinds: &[Kind], columns: &[&str]) -> Option<Vec<Vec<Value>>> {
        if self.fatal {
            return None;
        }
        match self.try_table(table, kinds, columns) {
            Ok(rows) => rows,
            Err(e) => {
                self.fatal = true;
                self.diagnostics
                    .push(diagnostics::cannot_open(self.path, &sqlite_reason(&e)));
                None
            }
        }
    }

    fn try_table(
        &mut self,
        table: &str,
        kinds: &[Kind],
        columns: &[&str],
    ) -> rusqlite::Result<Option<Vec<Vec<Value>>>> {
        // Column names as the table spells them (SQLite compares them without case).
        let mut present: Vec<String> = Vec::new();
        {
            let mut stmt = self
                .conn
                .prepare("SELECT name FROM pragma_table_info(?1)")?;
            let mut rows = stmt.query([table])?;
            while let Some(row) = rows.next()? {
                present.push(row.get::<_, String>(0)?);
            }
        }
        if present.is_empty() {
            self.missing_tables += 1;
            self.diagnostics
                .push(diagnostics::missing_table(table, &expected_columns(table)));
            return Ok(None);
        }
        let mut selected: Vec<Option<&str>> = Vec::new();
        let mut missing = false;
        for (&column, &kind) in columns.iter().zip(kinds) {
            let found = present.iter().any(|p| p.eq_ignore_ascii_case(column));
            if found {
                selected.push(Some(column));
            } else if kind == Kind::OptionalText {
                selected.push(None);
            } else {
                missing = true;
                self.diagnostics
                    .push(diagnostics::missing_column(table, column, &present));
            }
        }
        if missing {
            return Ok(None);
        }
        let list: Vec<String> = selected
            .iter()
            .map(|c| match c {
                Some(c) => quote_identifier(c),
                None => "NULL".to_string(),
            })
            .collect();
        let sql = format!(
            "SELECT {} FROM {}",
            list.join(", "),
            quote_identifier(table)
        );
        let mut stmt = self.conn.prepare(&sql)?;
        let mut rows = stmt.query([])?;
        let mut out = Vec::new();
        while let Some(row) = rows.next()? {
            let mut values = Vec::with_capacity(kinds.len());
            let mut bad: Option<usize> = None;
            for (i, &kind) in kinds.iter().enumerate() {
                let raw = row.get_ref(i)?;
                match convert(raw, kind) {
                    Some(v) => values.push(v),
                    None => {
                        bad.get_or_insert(i);
                        values.push(Value::Id(0));
                    }
                }
            }
            if let Some(i) = bad {
                let shown = describe_row(row, columns, &selected)?;
                self.diagnostics.push(diagnostics::wrong_type(
                    table,
                    columns[i],
                    &literal(row.get_ref(i)?),
                    &shown,
                ));
                continue;
            }
            out.push(values);
        }
        Ok(Some(out))
    }
}

/// The columns the import reads from `table`, for messages.
fn expected_columns(table: &str) -> String {
    let columns = match table {
        "Objects" => "Id, Name",
        "EndEffectors" => "Id, Name, Movable",
        "Workspaces" => "Id, Name",
        "WorkspacesAdjacency" => "id_source, id_target",
        "Reachability" => "EndEffector_id, Workspace_id",
        "Grasps" => "Object_id, EndEffector_id, Grasp_id, Grasp_name",
        "Grasp_transitions" => "Source_id, Target_id",
        _ => "",
    };
    columns.to_string()
}

fn convert(raw: ValueRef<'_>, kind: Kind) -> Option<Value> {
    match kind {
        Kind::Id => match raw {
            ValueRef::Integer(i) => Some(Value::Id(i)),
            ValueRef::Real(f) if f.fract() == 0.0 && f.abs() < 9.0e15 => Some(Value::Id(f as i64)),
            _ => None,
        },
        Kind::Text | Kind::OptionalText => Some(Value::Text(match raw {
            ValueRef::Null => None,
            ValueRef::Integer(i) => Some(i.to_string()),
            ValueRef::Real(f) => Some(f.to_string()),
            ValueRef::Text(t) | ValueRef::Blob(t) => Some(String::from_utf8_lossy(t).into_owned()),
        })),
    }
}

/// `(Id = 3, Name = 'Left')`: a row shown by its values, so that it can be found with a
/// `WHERE` clause (the tables have no row number of their own).
fn describe_row(
    row: &rusqlite::Row<'_>,
    columns: &[&str],
    selected: &[Option<&str>],
) -> rusqlite::Result<String> {
    let mut parts = Vec::new();
    for (i, column) in columns.iter().enumerate() {
        if selected[i].is_none() {
            continue;
        }
        parts.push(format!("{column} = {}", literal(row.get_ref(i)?)));
    }
    Ok(format!("({})", parts.join(", ")))
}

/// A value as an SQL literal (`3`, `'text'`, `NULL`, `x'00ff'`), shortened when long.
pub(crate) fn literal(value: ValueRef<'_>) -> String {
    const MAX: usize = 40;
    match value {
        ValueRef::Null => "NULL".to_string(),
        ValueRef::Integer(i) => i.to_string(),
        ValueRef::Real(f) => format!("{f:?}"),
        ValueRef::Text(t) => {
            let text = String::from_utf8_lossy(t);
            let mut shown: String = text.chars().take(MAX).collect();
            if text.chars().count() > MAX {
                shown.push('…');
            }
            let shown: String = shown
                .chars()
                .map(|c| if c.is_control() { '?' } else { c })
                .collect();
            format!("'{}'", shown.replace('\'', "''"))
        }
        ValueRef::Blob(b) => {
            let hex: String = b.iter().take(MAX / 2).map(|x| format!("{x:02x}")).collect();
            let more = if b.len() > MAX / 2 { "…" } else { "" };
            format!("x'{hex}'{more}")
        }
    }
}

/// `"name"`, as SQL quotes an identifier.
fn quote_identifier(name: &str) -> String {
    format!("\"{}\"", name.replace('"', "\"\""))
}
