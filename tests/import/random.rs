//! Random databases: random rows import or fail cleanly with the import's own codes;
//! databases built to break no rule always import, with exactly their rows.

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
