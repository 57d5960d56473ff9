//! `cellc plan`, `run` and `view --state PATH`: the world read from a state file of `cellc
//! serve` (the SQLite store), only read (the file's bytes and time stay as they were, and
//! no file is made), beside a writer that holds it, and refused when the file is no state
//! file, holds no world, holds one that does not fit the cell, or one an interrupted
//! execution left uncertain.
//!
//! `tests/ui/cli/support/uncertain.state.sqlite` is the fixture of
//! `tests/ui/cli/S0007_uncertain_state.args`; [`uncertain_store`] makes it with the store
//! API, and `the_uncertain_fixture_is_what_the_store_api_makes` checks that the committed
//! file holds what that makes (run with `UPDATE_FIXTURES=1` to write it again).

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use cellc_store::{
    Begun, Confirms, Durability, NewExecution, Retention, SqliteStore, Store, StoredWorld,
    Subjects, WorldDocument,
};

const FIXTURE: &str = "tests/ui/cli/support/uncertain.state.sqlite";
const PICK: &str = "tests/ui/cli/support/pick.cell";

/// A fresh folder of the test's own, removed when dropped.
struct Folder(PathBuf);

impl Folder {
    fn new(name: &str) -> Folder {
        let path = std::env::temp_dir().join(format!("cellc-state-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&path);
        std::fs::create_dir_all(&path).expect("a temporary folder");
        Folder(path)
    }

    fn path(&self) -> &Path {
        &self.0
    }
}

impl Drop for Folder {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

fn cellc(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_cellc"))
        .args(args)
        .env("NO_COLOR", "1")
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("cellc runs")
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

fn document(json: &str) -> WorldDocument {
    WorldDocument::from_json(json.as_bytes()).expect("a world document")
}

fn open(path: &Path) -> SqliteStore {
    SqliteStore::open(path, Durability::Full, Retention::default()).expect("the store opens")
}

fn stored(path: &Path) -> StoredWorld {
    SqliteStore::open_read_only(path)
        .expect("a state file")
        .world()
        .expect("readable")
        .expect("a world")
}

/// `pick.cell`'s world with the cylinder on the table in `w1`, then an execution moving
/// it with `arm1` that recorded its first step (the cylinder in the hand) and never
/// finished: the store is dropped as a killed service leaves it, and opened again, which
/// finds the execution interrupted and the cylinder and the arm uncertain.
fn uncertain_store(path: &Path) {
    {
        let mut store = open(path);
        store
            .put_world(
                None,
                &document(
                    r#"{"objects": {"cylinder": {"holder": "table", "grasp": "standing", "workspace": "w1"}}}"#,
                ),
                &Confirms::Everything,
            )
            .expect("the world is stored");
        let begun = store
            .begin(&NewExecution {
                key: None,
                expect: None,
                intent: r#"{"object": "cylinder", "to": "table.standing in w2"}"#.to_string(),
                subjects: Subjects {
                    objects: ["cylinder".to_string()].into(),
                    arms: ["arm1".to_string()].into(),
                },
                steps: 4,
            })
            .expect("journaled");
        let Begun::Started { id, .. } = begun else {
            panic!("a new store repeats nothing: {begun:?}");
        };
        store
            .step(
                id,
                r#"{"step": 1, "done": true}"#,
                &document(
                    r#"{"objects": {"cylinder": {"holder": "arm1", "grasp": "held", "workspace": "w1"}}}"#,
                ),
            )
            .expect("the first step is recorded");
        // Dropped without `finish`: the service stopped during the execution.
    }
    let store = open(path);
    assert_eq!(
        store.recovered().len(),
        1,
        "the execution is found interrupted"
    );
}

#[test]
fn the_uncertain_fixture_is_what_the_store_api_makes() {
    let dir = Folder::new("fixture");
    let made = dir.path().join("uncertain.state.sqlite");
    uncertain_store(&made);
    if std::env::var_os("UPDATE_FIXTURES").is_some() {
        std::fs::copy(&made, FIXTURE).expect("the fixture is written");
    }
    let (fixture, rebuilt) = (stored(Path::new(FIXTURE)), stored(&made));
    assert_eq!(fixture, rebuilt, "the fixture holds another world");
    assert_eq!(
        fixture.uncertain_subjects(),
        Subjects {
            objects: ["cylinder".to_string()].into(),
            arms: ["arm1".to_string()].into(),
        }
    );
    // Both are refused with the same words, naming what to confirm.
    let made_text = made.to_string_lossy().into_owned();
    let outputs =
        [FIXTURE, made_text.as_str()].map(|state| cellc(&["plan", PICK, "--state", state]));
    for out in &outputs {
        assert_eq!(out.status.code(), Some(1));
        let stderr = text(&out.stderr);
        assert!(stderr.contains("error[S0007]"), "{stderr}");
        assert!(
            stderr.contains("uncertain for object `cylinder` and arm `arm1`"),
            "{stderr}"
        );
        assert!(stderr.contains("interrupted after step 1"), "{stderr}");
    }
    assert_eq!(text(&outputs[0].stderr), text(&outputs[1].stderr));
    // `run` and `view` read the state file the same way.
    let out = cellc(&["run", PICK, "--state", FIXTURE]);
    assert!(text(&out.stderr).contains("error[S0007]"));
    let page = dir.path().join("view.html");
    let page_text = page.to_string_lossy().into_owned();
    let out = cellc(&["view", PICK, "--state", FIXTURE, "-o", &page_text]);
    assert!(text(&out.stderr).contains("error[S0007]"));
    assert!(!page.exists(), "no page of an uncertain world");
}

/// The file's bytes, its modification time, and the names in its folder.
fn snapshot(path: &Path) -> (Vec<u8>, std::time::SystemTime, Vec<PathBuf>) {
    let folder = path.parent().expect("a folder");
    let mut names: Vec<PathBuf> = std::fs::read_dir(folder)
        .expect("a folder")
        .map(|e| e.expect("an entry").path())
        .collect();
    names.sort();
    let modified = std::fs::metadata(path)
        .and_then(|m| m.modified())
        .expect("a time");
    (std::fs::read(path).expect("readable"), modified, names)
}

/// Vito's world with the ball where the cell's `world` does not put it.
const MOVED_BALL: &str = r#"{"objects": {
    "cylinder": {"holder": "table", "at": [0.45, 0.45, 1.0]},
    "pitcher": {"holder": "table", "at": [0.4, 0.05, 1.01]},
    "ball": {"holder": "table", "at": [0.4, -0.3, 0.95]}
}}"#;

fn first_grasp_position(out: &Output) -> Vec<f64> {
    let doc: serde_json::Value = serde_json::from_slice(&out.stdout)
        .unwrap_or_else(|e| panic!("{e}: {}", text(&out.stdout)));
    assert_eq!(doc["ok"], true, "{doc}");
    let step = &doc["plans"][0]["steps"][0];
    assert_eq!(step["command"], "grasp", "{step}");
    step["object"]["position"]
        .as_array()
        .expect("a position")
        .iter()
        .map(|v| v.as_f64().expect("a number"))
        .collect()
}

fn near(a: &[f64], b: [f64; 3]) -> bool {
    a.len() == 3 && a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-6)
}

#[test]
fn plan_and_run_start_from_the_stored_world_and_leave_the_file_alone() {
    let dir = Folder::new("vito");
    let path = dir.path().join("vito.state.sqlite");
    open(&path)
        .put_world(None, &document(MOVED_BALL), &Confirms::Everything)
        .expect("stored");
    let state = path.to_string_lossy().into_owned();
    let before = snapshot(&path);
    let ask = |command: &str, state: Option<&str>| {
        let mut args = vec![
            command,
            "cells/vito.cell",
            "--move",
            "ball to bin in ws_right_bin",
            "--no-motions",
            "--format",
            "json",
        ];
        args.extend(state.map(|s| ["--state", s]).into_iter().flatten());
        cellc(&args)
    };
    let from_state = first_grasp_position(&ask("plan", Some(&state)));
    assert!(near(&from_state, [0.4, -0.3, 0.95]), "{from_state:?}");
    let from_cell = first_grasp_position(&ask("plan", None));
    assert!(near(&from_cell, [0.45, -0.25, 0.95]), "{from_cell:?}");

    // A run ends with the ball in the bin, and the file still has it on the table.
    let out = ask("run", Some(&state));
    let doc: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON");
    assert_eq!(doc["ok"], true, "{doc}");
    let ball = doc["world"]["objects"]
        .as_array()
        .expect("objects")
        .iter()
        .find(|o| o["object"] == "ball")
        .expect("the ball")
        .clone();
    assert_eq!(ball["state"]["end_effector"], "bin", "{ball}");
    assert_eq!(snapshot(&path), before, "the state file was touched");
    assert_eq!(stored(&path).document, document(MOVED_BALL));
}

#[test]
fn a_reader_works_beside_the_writer_that_holds_the_file() {
    let dir = Folder::new("beside");
    let path = dir.path().join("pick.state.sqlite");
    let state = path.to_string_lossy().into_owned();
    // The writer stays open, as `cellc serve` keeps it, for the whole test.
    let mut writer = open(&path);
    writer
        .put_world(
            None,
            &document(
                r#"{"objects": {"cylinder": {"holder": "table", "grasp": "standing", "workspace": "w2"}}}"#,
            ),
            &Confirms::Everything,
        )
        .expect("stored");
    let plan = |to: &str| {
        cellc(&[
            "plan",
            PICK,
            "--state",
            &state,
            "--move",
            &format!("cylinder to {to}"),
            "--format",
            "json",
        ])
    };
    let out = plan("table.standing in w1");
    assert!(out.status.success(), "{}", text(&out.stdout));
    let doc: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON");
    let first = &doc["plans"][0]["states"][0];
    assert_eq!(
        (&first["end_effector"], &first["workspace"]),
        (&"table".into(), &"w2".into()),
        "the plan starts where the stored world has the cylinder: {doc}"
    );
    // The writer goes on writing while readers come and go, and they see its last write.
    writer
        .put_world(
            None,
            &document(
                r#"{"objects": {"cylinder": {"holder": "table", "grasp": "standing", "workspace": "w1"}}}"#,
            ),
            &Confirms::Everything,
        )
        .expect("the writer still writes");
    let out = plan("table.standing in w2");
    let doc: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON");
    assert_eq!(doc["plans"][0]["states"][0]["workspace"], "w1", "{doc}");

    // While the service executes a plan, what it moves is refused, and again once it
    // ended.
    let begun = writer
        .begin(&NewExecution {
            key: None,
            expect: None,
            intent: "{}".to_string(),
            subjects: Subjects {
                objects: ["cylinder".to_string()].into(),
                arms: ["arm1".to_string()].into(),
            },
            steps: 4,
        })
        .expect("journaled");
    let Begun::Started { id, .. } = begun else {
        panic!("nothing to repeat: {begun:?}");
    };
    let out = plan("table.standing in w2");
    let diagnostic =
        &serde_json::from_slice::<serde_json::Value>(&out.stdout).expect("JSON")["diagnostics"][0];
    assert_eq!(out.status.code(), Some(1));
    assert_eq!(diagnostic["code"], "S0007", "{diagnostic}");
    let note = diagnostic.to_string();
    assert!(
        note.contains("execution 1 is running, 0 of its steps recorded"),
        "{note}"
    );
    writer
        .finish(id, cellc_store::End::Cancelled, "{}", None)
        .expect("ended");
    assert!(plan("table.standing in w2").status.success());
}

/// The command fails with `code`, its message (one line: `--format short`) saying `words`.
fn refused(args: &[&str], code: &str, words: &str) {
    let mut args = args.to_vec();
    args.extend(["--format", "short"]);
    let out = cellc(&args);
    let stdout = text(&out.stdout);
    assert_eq!(out.status.code(), Some(1), "{args:?}: {stdout}");
    assert!(stdout.contains(&format!("error[{code}]")), "{stdout}");
    assert!(stdout.contains(words), "{args:?}: {stdout}");
    assert!(!text(&out.stderr).contains("panicked"));
}

#[test]
fn files_that_give_no_world_are_refused_and_never_made() {
    let dir = Folder::new("refused");
    let missing = dir.path().join("nothing.state.sqlite");
    let missing_text = missing.to_string_lossy().into_owned();
    refused(
        &["plan", PICK, "--state", &missing_text],
        "S0011",
        "cannot be read",
    );
    assert!(!missing.exists(), "a missing state file is not created");
    assert_eq!(std::fs::read_dir(dir.path()).expect("a folder").count(), 0);

    // A state file `cellc serve` made but stored no world in yet.
    let empty = dir.path().join("empty.state.sqlite");
    drop(open(&empty));
    let empty_text = empty.to_string_lossy().into_owned();
    refused(
        &["plan", PICK, "--state", &empty_text],
        "S0011",
        "holds no world yet",
    );

    // A world stored for another cell.
    let other = dir.path().join("other.state.sqlite");
    open(&other)
        .put_world(None, &document(MOVED_BALL), &Confirms::Everything)
        .expect("stored");
    let other_text = other.to_string_lossy().into_owned();
    refused(
        &["plan", PICK, "--state", &other_text],
        "S0011",
        "does not fit this cell",
    );

    // Another program's SQLite database is left as it was.
    let foreign = dir.path().join("foreign.db");
    rusqlite::Connection::open(&foreign)
        .and_then(|c| c.execute_batch("CREATE TABLE t (x); INSERT INTO t VALUES (1);"))
        .expect("another program's database");
    let before = snapshot(&foreign);
    let foreign_text = foreign.to_string_lossy().into_owned();
    refused(
        &["plan", PICK, "--state", &foreign_text],
        "S0011",
        "is not a cellc state file",
    );
    assert_eq!(snapshot(&foreign), before);
}

#[test]
fn a_state_file_and_a_world_file_do_not_go_together() {
    for command in ["plan", "run"] {
        let out = cellc(&[
            command,
            PICK,
            "--state",
            FIXTURE,
            "--world",
            "tests/ui/cli/support/goal_taken_world.json",
        ]);
        assert_eq!(out.status.code(), Some(2), "{command}: a usage error");
        let stderr = text(&out.stderr);
        assert!(stderr.contains("cannot be used with"), "{stderr}");
    }
    let out = cellc(&[
        "view",
        PICK,
        "--state",
        FIXTURE,
        "--world",
        "tests/ui/cli/support/goal_taken_world.json",
        "-o",
        "target/state-view.html",
    ]);
    assert_eq!(out.status.code(), Some(2));
}
