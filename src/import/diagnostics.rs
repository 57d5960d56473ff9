//! Every problem `cellc import` reports, one named constructor per problem (E06xx).
//!
//! The input is a database, not a cell, so these diagnostics have no source label: the
//! message names the table and the row (by its values, so it can be found with a
//! `WHERE` clause), and the help says what to change in the database.

use cellc_lang::Diagnostic;

/// Codes of the import phase (the registry's `cellc_lang::codes::import`).
pub use cellc_lang::codes::import as codes;

use codes::*;

/// At most this many diagnostics of one code are shown; the last one shown says how many
/// more there are (a table of 3,000 mistyped rows would otherwise bury everything else).
pub const SHOWN_PER_CODE: usize = 20;

/// The tables the import reads, for messages.
const TABLES: &str =
    "Objects, EndEffectors, Workspaces, WorkspacesAdjacency, Reachability, Grasps, Grasp_transitions";

/// Keeps the first [`SHOWN_PER_CODE`] diagnostics of each code, in order.
pub fn limit(diagnostics: Vec<Diagnostic>) -> Vec<Diagnostic> {
    let mut counts: Vec<(cellc_lang::Code, usize)> = Vec::new();
    for d in &diagnostics {
        match counts.iter_mut().find(|(c, _)| *c == d.code) {
            Some((_, n)) => *n += 1,
            None => counts.push((d.code, 1)),
        }
    }
    let mut seen: Vec<(cellc_lang::Code, usize)> = Vec::new();
    let mut out = Vec::new();
    for mut d in diagnostics {
        let index = match seen.iter().position(|(c, _)| *c == d.code) {
            Some(i) => i,
            None => {
                seen.push((d.code, 0));
                seen.len() - 1
            }
        };
        seen[index].1 += 1;
        let shown = seen[index].1;
        let total = counts
            .iter()
            .find(|(c, _)| *c == d.code)
            .map_or(0, |(_, n)| *n);
        if shown > SHOWN_PER_CODE {
            continue;
        }
        if shown == SHOWN_PER_CODE && total > SHOWN_PER_CODE {
            d = d.note(format!(
                "{} more problems of this kind are not shown",
                total - SHOWN_PER_CODE
            ));
        }
        out.push(d);
    }
    out
}

/// A name from the database made safe for a one-line message.
pub fn shown(name: Option<&str>) -> String {
    match name {
        None => "NULL".to_string(),
        Some(name) => {
            let mut out: String = name
                .chars()
                .take(60)
                .map(|c| if c.is_control() { '?' } else { c })
                .collect();
            if name.chars().count() > 60 {
                out.push('…');
            }
            out
        }
    }
}

/// E0601: the file cannot be opened or read.
pub fn cannot_open(path: &str, reason: &str) -> Diagnostic {
    Diagnostic::error(CANNOT_OPEN, format!("cannot read `{path}`: {reason}"))
        .help("give the path of the SQLite database file of the dual_manipulation planner")
}

/// E0601: the file is not an SQLite database.
pub fn not_a_database(path: &str) -> Diagnostic {
    Diagnostic::error(CANNOT_OPEN, format!("`{path}` is not an SQLite database"))
        .help("give the grasp database of the dual_manipulation planner (an SQLite 3 file, usually `*.db`)")
}

/// E0602: an SQLite database without any of the tables.
pub fn no_tables(path: &str) -> Diagnostic {
    Diagnostic::error(
        BAD_SCHEMA,
        format!("`{path}` has none of the tables of a dual_manipulation database"),
    )
    .help("give the grasp database of the dual_manipulation planner")
    .note(format!("the import reads the tables {TABLES}"))
}

/// E0602: a table is missing.
pub fn missing_table(table: &str, columns: &str) -> Diagnostic {
    Diagnostic::error(BAD_SCHEMA, format!("table `{table}` is missing"))
        .help(format!(
            "add the table `{table}` with the columns {columns} (it may be empty when there is nothing to list)"
        ))
}

/// E0602: a column is missing.
pub fn missing_column(table: &str, column: &str, present: &[String]) -> Diagnostic {
    Diagnostic::error(
        BAD_SCHEMA,
        format!("table `{table}` has no column `{column}`"),
    )
    .help(format!("add the column `{column}` to `{table}`"))
    .note(format!("`{table}` has the columns {}", present.join(", ")))
}

/// E0602: a value that is not an integer where an id (or `Movable`) is needed.
pub fn wrong_type(table: &str, column: &str, value: &str, row: &str) -> Diagnostic {
    Diagnostic::error(
        BAD_SCHEMA,
        format!("`{table}.{column}` is {value}, not an integer, in the row {row}"),
    )
    .help(format!(
        "store an integer in `{table}.{column}`, or delete the row"
    ))
}

/// E0603: a row refers to an id that does not exist.
pub fn unknown_id(table: &str, row: &str, sort: &str, id: i64, target: &str) -> Diagnostic {
    Diagnostic::error(
        UNKNOWN_ID,
        format!("the `{table}` row {row} refers to {sort} {id}, which `{target}` does not have"),
    )
    .help(format!(
        "add the {sort} with id {id} to `{target}`, or delete this row"
    ))
}

/// E0604: a transition between grasps of two objects.
pub fn cross_object_transition(row: &str, from: (i64, &str), to: (i64, &str)) -> Diagnostic {
    Diagnostic::error(
        CROSS_OBJECT_TRANSITION,
        format!(
            "the `Grasp_transitions` row {row} joins a grasp of object `{}` to a grasp of object `{}`",
            from.1, to.1
        ),
    )
    .help("a transition passes one object between two of its own grasps: delete this row")
    .note(format!(
        "the grasps are of the objects with Id {} and Id {} in `Objects`",
        from.0, to.0
    ))
}

/// E0605: two rows with the same id.
pub fn duplicate_id(table: &str, column: &str, id: i64, count: usize) -> Diagnostic {
    Diagnostic::error(
        DUPLICATE_ID,
        format!("`{table}` has {count} rows with {column} = {id}"),
    )
    .help(format!(
        "give every row of `{table}` its own `{column}`: the other tables refer to rows by it"
    ))
}

/// E0606: `Movable` neither 0 nor 1.
pub fn bad_movable(id: i64, name: &str, value: i64) -> Diagnostic {
    Diagnostic::error(
        BAD_MOVABLE,
        format!("end-effector `{name}` (Id = {id}) has Movable = {value}"),
    )
    .help("set `Movable` to 1 for an end-effector that moves (a hand, a conveyor) or to 0 for a fixed one (a table, a bin)")
}

/// E0607: a transition between two fixed end-effectors.
pub fn fixed_to_fixed(row: &str, from: &str, to: &str) -> Diagnostic {
    let between = if from == to {
        format!("two grasps of `{from}`, which is fixed")
    } else {
        format!("`{from}` and `{to}`, which are both fixed")
    };
    Diagnostic::error(
        FIXED_TO_FIXED,
        format!("the `Grasp_transitions` row {row} is a transition between {between}"),
    )
    .help("an object goes from one surface to another only through a hand: delete this row and keep transitions through a movable end-effector")
    .note("fixed end-effectors have Movable = 0 in `EndEffectors`")
}

/// E0608: a workspace nobody reaches.
pub fn unreached_workspace(id: i64, name: &str) -> Diagnostic {
    Diagnostic::error(
        REACH_GAP,
        format!("workspace `{name}` (Id = {id}) is reached by no end-effector"),
    )
    .help(format!(
        "add a `Reachability` row with Workspace_id = {id} for each end-effector that reaches it, or delete the workspace"
    ))
}

/// E0608: an end-effector that reaches no workspace.
pub fn reaches_nothing(id: i64, name: &str) -> Diagnostic {
    Diagnostic::error(
        REACH_GAP,
        format!("end-effector `{name}` (Id = {id}) reaches no workspace"),
    )
    .help(format!(
        "add a `Reachability` row with EndEffector_id = {id} for each workspace it reaches, or delete the end-effector and its grasps"
    ))
}

/// E0609: `WorkspacesAdjacency` row from a workspace to itself.
pub fn self_adjacency(row: &str, name: &str) -> Diagnostic {
    Diagnostic::error(
        BAD_ADJACENCY,
        format!("the `WorkspacesAdjacency` row {row} makes workspace `{name}` adjacent to itself"),
    )
    .help("delete this row: moving within one workspace is not a move")
}

/// E0609: an adjacency no movable end-effector can use.
pub fn useless_adjacency(row: &str, a: &str, b: &str) -> Diagnostic {
    Diagnostic::error(
        BAD_ADJACENCY,
        format!(
            "the `WorkspacesAdjacency` row {row} joins `{a}` and `{b}`, but no movable end-effector reaches both"
        ),
    )
    .help("add `Reachability` rows so that a movable end-effector reaches both workspaces, or delete this row")
    .note("an object crosses from one workspace to the next only in a movable end-effector; cellc rejects an adjacency nothing can use")
}

/// E0609: no adjacency rows, where a cell would derive some.
pub fn no_adjacency(example: (i64, i64), shared: &str) -> Diagnostic {
    Diagnostic::error(
        BAD_ADJACENCY,
        "`WorkspacesAdjacency` is empty, so the cell would make workspaces adjacent on its own",
    )
    .help(format!(
        "add a `WorkspacesAdjacency` row for each pair of workspaces an object may be moved between (e.g. id_source = {}, id_target = {})",
        example.0, example.1
    ))
    .note(format!(
        "a cell that declares no adjacency derives it from reach, and {shared}: the cell's graphs would have moves that the database does not"
    ))
}
