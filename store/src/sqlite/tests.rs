//! The store against real files: reopen, conflicts, the journal, recovery, retention,
//! foreign and damaged files, a torn write-ahead log, a full disk.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicI64, Ordering};

use super::*;
use crate::{IdempotencyKey, Status, Subjects, MAX_KEY_CHARS};

fn world(ball_holder: &str, a1: f64) -> WorldDocument {
    let text = format!(
        r#"{{"arms": {{"left": {{"a1": {a1}}}}},
            "objects": {{"ball": {{"holder": "{ball_holder}", "workspace": "ws"}}}}}}"#
    );
    WorldDocument::from_json(text.as_bytes()).expect("a world document")
}

fn subjects(objects: &[&str], arms: &[&str]) -> Subjects {
    Subjects {
        objects: objects.iter().map(|s| s.to_string()).collect(),
        arms: arms.iter().map(|s| s.to_string()).collect(),
    }
}

fn open(path: &Path) -> SqliteStore {
    SqliteStore::open(path, Durability::Full, Retention::default()).expect("the store opens")
}

fn state_file(dir: &tempfile::TempDir) -> PathBuf {
    dir.path().join("cell.state")
}

fn new_execution(key: Option<&str>, intent: &str) -> NewExecution {
    NewExecution {
        key: key.map(|k| IdempotencyKey::new(k).expect("a key")),
        expect: None,
        intent: intent.to_string(),
        subjects: subjects(&["ball"], &["left"]),
        steps: 2,
    }
}

fn started(begun: Begun) -> ExecutionId {
    match begun {
        Begun::Started { id, .. } => id,
        Begun::Repeated(record) => panic!("expected a new execution, got {record:?}"),
    }
}

#[test]
fn the_world_and_its_revision_survive_a_reopen() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let path = state_file(&dir);
    let instance = {
        let mut store = open(&path);
        assert_eq!(store.world().expect("readable"), None);
        let r1 = store
            .put_world(
                Some(Revision(0)),
                &world("table", 0.0),
                &Confirms::Everything,
            )
            .expect("the first write");
        let r2 = store
            .put_world(None, &world("bin", 0.5), &Confirms::Everything)
            .expect("the second write");
        assert_eq!((r1, r2), (Revision(1), Revision(2)));
        store.instance().clone()
    };
    assert_eq!(instance.as_str().len(), 32);
    let mut store = open(&path);
    assert_eq!(store.instance(), &instance);
    let stored = store.world().expect("readable").expect("a world");
    assert_eq!(stored.revision, Revision(2));
    assert_eq!(stored.document, world("bin", 0.5));
    assert!(store.recovered().is_empty());
    let other = SqliteStore::in_memory(Retention::default()).expect("in memory");
    assert_ne!(
        other.instance(),
        &instance,
        "each store has its own instance id"
    );
}

#[test]
fn a_write_against_an_old_revision_is_a_conflict_and_changes_nothing() {
    let mut store = SqliteStore::in_memory(Retention::default()).expect("in memory");
    store
        .put_world(None, &world("table", 0.0), &Confirms::Everything)
        .expect("written");
    store
        .put_world(Some(Revision(1)), &world("bin", 0.0), &Confirms::Everything)
        .expect("the expected revision");
    let refused = store.put_world(
        Some(Revision(1)),
        &world("shelf", 0.0),
        &Confirms::Everything,
    );
    assert_eq!(
        refused,
        Err(StoreError::Conflict {
            expected: Revision(1),
            current: Revision(2)
        })
    );
    let stored = store.world().expect("readable").expect("a world");
    assert_eq!(
        (stored.revision, stored.document),
        (Revision(2), world("bin", 0.0))
    );
    let mut late = new_execution(None, "{}");
    late.expect = Some(Revision(1));
    assert!(matches!(
        store.begin(&late),
        Err(StoreError::Conflict {
            current: Revision(2),
            ..
        })
    ));
}

#[test]
fn an_execution_is_journaled_step_by_step_with_the_world_each_step_left() {
    let mut store = SqliteStore::in_memory(Retention::default()).expect("in memory");
    assert_eq!(
        store.begin(&new_execution(None, "{}")),
        Err(StoreError::NoWorld)
    );
    store
        .put_world(None, &world("table", 0.0), &Confirms::Everything)
        .expect("written");
    let id = started(
        store
            .begin(&new_execution(Some("k-1"), r#"{"plan":1}"#))
            .expect("begun"),
    );
    let r2 = store
        .step(id, r#"{"step":1}"#, &world("left", 0.3))
        .expect("step 1");
    let r3 = store
        .step(id, r#"{"step":2}"#, &world("bin", 0.6))
        .expect("step 2");
    let end = store
        .finish(id, End::Succeeded, r#"{"ok":true}"#, None)
        .expect("finished");
    assert_eq!((r2, r3, end), (Revision(2), Revision(3), Revision(3)));
    let record = store.execution(id).expect("readable").expect("journaled");
    assert_eq!(record.status, Status::Succeeded);
    assert_eq!(record.base, Revision(1));
    assert_eq!(record.result, Some(Revision(3)));
    let indices: Vec<u32> = record.steps.iter().map(|s| s.index).collect();
    assert_eq!(indices, [1, 2]);
    assert_eq!(record.steps[1].revision, Revision(3));
    assert_eq!(record.outcome.as_deref(), Some(r#"{"ok":true}"#));
    assert_eq!(
        store.step(id, "{}", &world("bin", 0.6)),
        Err(StoreError::UnknownExecution { id }),
        "an ended execution takes no more steps"
    );
    let world_now = store.world().expect("readable").expect("a world");
    assert_eq!(world_now.document, world("bin", 0.6));
}

#[test]
fn a_repeated_key_returns_the_first_execution_and_a_reused_one_is_refused() {
    let mut store = SqliteStore::in_memory(Retention::default()).expect("in memory");
    store
        .put_world(None, &world("table", 0.0), &Confirms::Everything)
        .expect("written");
    let id = started(
        store
            .begin(&new_execution(Some("same"), "A"))
            .expect("begun"),
    );
    store
        .finish(id, End::Failed, "{}", Some(&world("table", 0.1)))
        .expect("finished");
    match store
        .begin(&new_execution(Some("same"), "A"))
        .expect("answered")
    {
        Begun::Repeated(record) => {
            assert_eq!((record.id, record.status), (id, Status::Failed));
        }
        other => panic!("a repeated key must not start again: {other:?}"),
    }
    let key = IdempotencyKey::new("same").expect("a key");
    let found = store.keyed(&key).expect("readable").expect("journaled");
    assert_eq!((found.id, found.intent.as_str()), (id, "A"));
    let unused = IdempotencyKey::new("unused").expect("a key");
    assert_eq!(store.keyed(&unused).expect("readable"), None);
    assert_eq!(
        store.begin(&new_execution(Some("same"), "B")),
        Err(StoreError::KeyReused { execution: id })
    );
    assert!(IdempotencyKey::new("").is_err());
    assert!(IdempotencyKey::new("has space").is_err());
    assert!(IdempotencyKey::new(&"k".repeat(MAX_KEY_CHARS + 1)).is_err());
    assert!(IdempotencyKey::new(&"k".repeat(MAX_KEY_CHARS)).is_ok());
}

#[test]
fn an_execution_in_flight_at_a_crash_is_interrupted_and_leaves_its_subjects_uncertain() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let path = state_file(&dir);
    let id = {
        let mut store = open(&path);
        store
            .put_world(None, &world("table", 0.0), &Confirms::Everything)
            .expect("written");
        let id = started(store.begin(&new_execution(None, "plan")).expect("begun"));
        store.step(id, "{}", &world("left", 0.4)).expect("step 1");
        id
        // Dropped without finishing: what a SIGKILL leaves in the file.
    };
    let mut store = open(&path);
    assert_eq!(store.recovered(), [id]);
    let record = store.execution(id).expect("readable").expect("journaled");
    assert_eq!(record.status, Status::Interrupted);
    assert_eq!(record.steps.len(), 1);
    let stored = store.world().expect("readable").expect("a world");
    assert_eq!(stored.document, world("left", 0.4), "as step 1 left it");
    assert_eq!(
        stored.revision,
        Revision(3),
        "marking it uncertain is a write"
    );
    assert_eq!(
        stored.uncertain,
        [Uncertainty {
            execution: id,
            steps_done: 1,
            subjects: subjects(&["ball"], &["left"]),
        }]
    );
    // Opening again recovers nothing more.
    drop(store);
    let mut store = open(&path);
    assert!(store.recovered().is_empty());
    let confirmed = Confirms::Only(subjects(&["ball"], &[]));
    store
        .put_world(None, &world("left", 0.4), &confirmed)
        .expect("the ball confirmed");
    let stored = store.world().expect("readable").expect("a world");
    assert_eq!(stored.uncertain_subjects(), subjects(&[], &["left"]));
    store
        .put_world(None, &world("left", 0.4), &Confirms::Everything)
        .expect("everything confirmed");
    let stored = store.world().expect("readable").expect("a world");
    assert!(stored.uncertain.is_empty());
}

#[test]
fn a_second_writer_is_refused_while_readers_see_the_latest_commit() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let path = state_file(&dir);
    let mut store = open(&path);
    store
        .put_world(None, &world("table", 0.0), &Confirms::Everything)
        .expect("written");
    assert!(matches!(
        SqliteStore::open(&path, Durability::Full, Retention::default()),
        Err(StoreError::InUse)
    ));
    let mut reader = SqliteStore::open_read_only(&path).expect("a reader");
    assert_eq!(reader.instance(), store.instance());
    store
        .put_world(None, &world("bin", 0.0), &Confirms::Everything)
        .expect("written");
    let seen = reader.world().expect("readable").expect("a world");
    assert_eq!(
        (seen.revision, seen.document),
        (Revision(2), world("bin", 0.0))
    );
    assert_eq!(
        reader.put_world(None, &world("x", 0.0), &Confirms::Everything),
        Err(StoreError::ReadOnly)
    );
}

#[test]
fn files_that_are_not_state_files_are_refused_untouched() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let text = dir.path().join("notes.txt");
    let content = b"these are not the rows you are looking for\n".repeat(200);
    std::fs::write(&text, &content).expect("written");
    assert!(matches!(
        SqliteStore::open(&text, Durability::Full, Retention::default()),
        Err(StoreError::Foreign { .. })
    ));
    assert_eq!(
        std::fs::read(&text).expect("readable"),
        content,
        "not written"
    );

    let other = dir.path().join("other.db");
    Connection::open(&other)
        .and_then(|c| c.execute_batch("CREATE TABLE t (x); INSERT INTO t VALUES (1);"))
        .expect("another program's database");
    assert!(matches!(
        SqliteStore::open(&other, Durability::Full, Retention::default()),
        Err(StoreError::Foreign { .. })
    ));

    let newer = state_file(&dir);
    drop(open(&newer));
    Connection::open(&newer)
        .and_then(|c| c.execute_batch("PRAGMA user_version = 99;"))
        .expect("a newer layout");
    assert_eq!(
        SqliteStore::open(&newer, Durability::Full, Retention::default()).err(),
        Some(StoreError::TooNew { version: 99 })
    );
    assert!(matches!(
        SqliteStore::open(dir.path(), Durability::Full, Retention::default()),
        Err(StoreError::Io { .. })
    ));
}

/// A write the system refused for another reason than space (`EFBIG` past a file-size
/// limit comes out of SQLite as `SQLITE_IOERR_WRITE`) is said as such, not as SQLite's
/// bare "Error code 778"; other I/O errors keep SQLite's words.
#[test]
fn a_refused_write_is_worded_as_one() {
    let failure = |code: i32| {
        sqlite_error(rusqlite::Error::SqliteFailure(
            rusqlite::ffi::Error::new(code),
            None,
        ))
    };
    for code in WRITES_REFUSED {
        match failure(code) {
            StoreError::Io { reason } => {
                assert!(reason.contains("could not write"), "{code}: {reason}")
            }
            other => panic!("{code}: {other:?}"),
        }
    }
    match failure(rusqlite::ffi::SQLITE_IOERR_READ) {
        StoreError::Io { reason } => assert!(!reason.contains("could not write"), "{reason}"),
        other => panic!("{other:?}"),
    }
    assert_eq!(failure(rusqlite::ffi::SQLITE_FULL), StoreError::Full);
}

#[test]
fn a_full_disk_is_a_coded_error_and_the_last_commit_stands() {
    let mut store = SqliteStore::in_memory(Retention::default()).expect("in memory");
    store
        .put_world(None, &world("table", 0.0), &Confirms::Everything)
        .expect("written");
    let pages: i64 = store
        .conn
        .query_row("PRAGMA page_count", [], |r| r.get(0))
        .expect("page count");
    // SQLite's own cap on the file's size: writes past it fail as a full disk does.
    store
        .conn
        .execute_batch(&format!("PRAGMA max_page_count = {pages};"))
        .expect("capped");
    let big = "x".repeat(64 * 1024);
    let id = started(store.begin(&new_execution(None, "small")).expect("begun"));
    assert_eq!(
        store.step(id, &big, &world("left", 0.2)),
        Err(StoreError::Full)
    );
    let stored = store.world().expect("readable").expect("a world");
    assert_eq!(
        (stored.revision, stored.document),
        (Revision(1), world("table", 0.0))
    );
    let record = store.execution(id).expect("readable").expect("journaled");
    assert!(record.steps.is_empty(), "the failed step left nothing");
}

static NOW: AtomicI64 = AtomicI64::new(1_000_000);

fn test_clock() -> i64 {
    NOW.load(Ordering::SeqCst)
}

#[test]
fn the_journal_keeps_what_its_retention_says_and_every_uncertain_execution() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let path = state_file(&dir);
    let retention = Retention {
        max_executions: 3,
        max_age_ms: Some(60_000),
    };
    let reopen = || {
        SqliteStore::open_with_clock(&path, Durability::Normal, retention, test_clock)
            .expect("opens")
    };
    let mut store = reopen();
    store
        .put_world(None, &world("table", 0.0), &Confirms::Everything)
        .expect("written");
    let interrupted = started(store.begin(&new_execution(None, "lost")).expect("begun"));
    drop(store);
    let mut store = reopen();
    let mut ended = Vec::new();
    for i in 0..5 {
        let id = started(
            store
                .begin(&new_execution(None, &format!("{i}")))
                .expect("begun"),
        );
        store.finish(id, End::Succeeded, "{}", None).expect("ended");
        ended.push(id);
    }
    let listed: Vec<ExecutionId> = store
        .recent(100)
        .expect("listed")
        .iter()
        .map(|r| r.id)
        .collect();
    assert_eq!(listed, [ended[4], ended[3], ended[2], interrupted]);
    NOW.fetch_add(120_000, Ordering::SeqCst);
    let id = started(store.begin(&new_execution(None, "late")).expect("begun"));
    store.finish(id, End::Cancelled, "{}", None).expect("ended");
    let listed: Vec<ExecutionId> = store
        .recent(100)
        .expect("listed")
        .iter()
        .map(|r| r.id)
        .collect();
    assert_eq!(
        listed,
        [id, interrupted],
        "the old ones aged out; the uncertain one stays"
    );
}

/// Copies the file and its write-ahead log as a crash leaves them (the service still
/// running, nothing checkpointed), then cuts the log at many lengths: every copy opens to
/// a world some acknowledged write left, or is refused with a coded error.
#[test]
fn a_torn_write_ahead_log_opens_to_an_acknowledged_world_or_a_refusal() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let path = state_file(&dir);
    let mut store = open(&path);
    let mut acknowledged = BTreeMap::new();
    for i in 0..12 {
        let doc = world(
            if i % 2 == 0 { "table" } else { "bin" },
            f64::from(i) / 10.0,
        );
        let revision = store
            .put_world(None, &doc, &Confirms::Everything)
            .expect("written");
        acknowledged.insert(revision, doc);
    }
    let wal = std::fs::read(path.with_extension("state-wal")).expect("a write-ahead log");
    let main = std::fs::read(&path).expect("the database");
    assert!(
        wal.len() > 4096,
        "the writes are in the log, not checkpointed"
    );
    let mut opened = 0;
    let mut newest = 0;
    let mut seen_revisions = std::collections::BTreeSet::new();
    for cut in (0..=wal.len()).step_by(997).chain([wal.len()]) {
        let copy = dir.path().join(format!("copy{cut}.state"));
        std::fs::write(&copy, &main).expect("copied");
        std::fs::write(copy.with_extension("state-wal"), &wal[..cut]).expect("copied");
        match SqliteStore::open(&copy, Durability::Full, Retention::default()) {
            Ok(mut torn) => match torn.world() {
                Ok(Some(seen)) => {
                    assert_eq!(Some(&seen.document), acknowledged.get(&seen.revision));
                    newest = newest.max(seen.revision.0);
                    seen_revisions.insert(seen.revision.0);
                    opened += 1;
                }
                Ok(None) => opened += 1,
                Err(e) => assert!(matches!(e, StoreError::Corrupt { .. }), "{e:?}"),
            },
            Err(e) => assert!(
                matches!(e, StoreError::Corrupt { .. } | StoreError::Foreign { .. }),
                "{e:?}"
            ),
        }
    }
    assert!(opened > 10, "most cuts open to an earlier state ({opened})");
    assert_eq!(
        newest, 12,
        "the whole log gives the last acknowledged write"
    );
    assert!(
        seen_revisions.len() >= 6,
        "shorter logs give earlier acknowledged worlds: {seen_revisions:?}"
    );
    drop(store);
}

fn folder_listing(dir: &Path) -> Vec<PathBuf> {
    let mut names: Vec<PathBuf> = std::fs::read_dir(dir)
        .expect("a folder")
        .map(|e| e.expect("an entry").path())
        .collect();
    names.sort();
    names
}

#[test]
fn a_reader_of_a_file_no_writer_has_open_leaves_nothing_beside_it() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let path = state_file(&dir);
    {
        let mut store = open(&path);
        store
            .put_world(None, &world("table", 0.0), &Confirms::Everything)
            .expect("written");
    }
    let listing = folder_listing(dir.path());
    assert_eq!(listing, vec![path.clone()], "a closed store is one file");
    let bytes = std::fs::read(&path).expect("readable");
    let modified = std::fs::metadata(&path)
        .and_then(|m| m.modified())
        .expect("a time");
    {
        let mut reader = SqliteStore::open_read_only(&path).expect("a reader");
        let seen = reader.world().expect("readable").expect("a world");
        assert_eq!(seen.document, world("table", 0.0));
        assert!(reader.recent(10).expect("readable").is_empty());
        assert!(reader.still.is_some(), "read as a file no writer has open");
    }
    assert_eq!(folder_listing(dir.path()), listing, "no -wal or -shm made");
    assert_eq!(std::fs::read(&path).expect("readable"), bytes);
    assert_eq!(
        std::fs::metadata(&path)
            .and_then(|m| m.modified())
            .expect("a time"),
        modified
    );
}

#[test]
fn a_reader_opened_before_a_writer_came_reads_what_the_writer_wrote() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let path = state_file(&dir);
    open(&path)
        .put_world(None, &world("table", 0.0), &Confirms::Everything)
        .expect("written");
    // A writer that comes while the reader is open, and is still there.
    let mut reader = SqliteStore::open_read_only(&path).expect("a reader");
    assert!(reader.still.is_some());
    let mut writer = open(&path);
    writer
        .put_world(None, &world("bin", 0.0), &Confirms::Everything)
        .expect("written");
    let seen = reader.world().expect("readable").expect("a world");
    assert_eq!(
        (seen.revision, seen.document),
        (Revision(2), world("bin", 0.0))
    );
    assert!(reader.still.is_none(), "reopened as an ordinary reader");
    drop(writer);
    drop(reader);
    // The log the live reader kept from being checked in, checked in by a writer alone.
    drop(open(&path));
    assert!(!dir.path().join("cell.state-wal").exists());

    // A writer that came, wrote and went (checking its log into the file) between the
    // reader's open and its read.
    let mut reader = SqliteStore::open_read_only(&path).expect("a reader");
    assert!(reader.still.is_some());
    {
        let mut writer = open(&path);
        writer
            .put_world(None, &world("left", 0.2), &Confirms::Everything)
            .expect("written");
    }
    assert!(
        !dir.path().join("cell.state-wal").exists(),
        "the log was checked in"
    );
    let seen = reader.world().expect("readable").expect("a world");
    assert_eq!(
        (seen.revision, seen.document),
        (Revision(3), world("left", 0.2))
    );
    assert!(reader.still.is_none(), "the file changed since the open");
}

/// A store with the trait's own [`Store::in_flight`], to hold it to SQLite's.
struct Defaults(SqliteStore);

impl Store for Defaults {
    fn instance(&self) -> &InstanceId {
        self.0.instance()
    }
    fn recovered(&self) -> &[ExecutionId] {
        self.0.recovered()
    }
    fn world(&mut self) -> Result<Option<StoredWorld>, StoreError> {
        self.0.world()
    }
    fn put_world(
        &mut self,
        expect: Option<Revision>,
        document: &WorldDocument,
        confirms: &Confirms,
    ) -> Result<Revision, StoreError> {
        self.0.put_world(expect, document, confirms)
    }
    fn begin(&mut self, execution: &NewExecution) -> Result<Begun, StoreError> {
        self.0.begin(execution)
    }
    fn step(
        &mut self,
        id: ExecutionId,
        report: &str,
        world: &WorldDocument,
    ) -> Result<Revision, StoreError> {
        self.0.step(id, report, world)
    }
    fn finish(
        &mut self,
        id: ExecutionId,
        end: End,
        outcome: &str,
        world: Option<&WorldDocument>,
    ) -> Result<Revision, StoreError> {
        self.0.finish(id, end, outcome, world)
    }
    fn execution(&mut self, id: ExecutionId) -> Result<Option<ExecutionRecord>, StoreError> {
        self.0.execution(id)
    }
    fn recent(&mut self, limit: u32) -> Result<Vec<ExecutionRecord>, StoreError> {
        self.0.recent(limit)
    }

    fn keyed(&mut self, key: &IdempotencyKey) -> Result<Option<ExecutionRecord>, StoreError> {
        self.0.keyed(key)
    }
}

#[test]
fn a_reader_sees_what_running_executions_leave_unknown() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let path = state_file(&dir);
    let mut writer = open(&path);
    writer
        .put_world(None, &world("table", 0.0), &Confirms::Everything)
        .expect("written");
    let mut reader = SqliteStore::open_read_only(&path).expect("a reader");
    assert_eq!(reader.in_flight().expect("readable"), Vec::new());
    let done = started(writer.begin(&new_execution(None, "first")).expect("begun"));
    writer
        .finish(done, End::Succeeded, "{}", None)
        .expect("finished");
    let id = started(writer.begin(&new_execution(None, "second")).expect("begun"));
    writer.step(id, "{}", &world("left", 0.1)).expect("a step");
    let expected = vec![Uncertainty {
        execution: id,
        steps_done: 1,
        subjects: subjects(&["ball"], &["left"]),
    }];
    assert_eq!(reader.in_flight().expect("readable"), expected);
    let mut defaults = Defaults(SqliteStore::open_read_only(&path).expect("a reader"));
    assert_eq!(defaults.in_flight().expect("readable"), expected);
    // Its service stopped: still running for a reader until a writer opens the file.
    drop(writer);
    assert_eq!(reader.in_flight().expect("readable"), expected);
    let mut writer = open(&path);
    assert_eq!(writer.recovered(), &[id]);
    assert_eq!(writer.in_flight().expect("readable"), Vec::new());
    assert_eq!(reader.in_flight().expect("readable"), Vec::new());
    assert_eq!(defaults.in_flight().expect("readable"), Vec::new());
    let stored = reader.world().expect("readable").expect("a world");
    assert_eq!(
        stored.uncertain, expected,
        "recovery found what the reader saw"
    );
}
