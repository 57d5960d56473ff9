//! The SQLite store: one file, WAL mode, one writer process.
//!
//! Why SQLite by default: the state of one cell is small (a world document of a few KiB,
//! a journal of a few MiB), is written by one service, and must survive `kill -9` and
//! power loss without an operator. An embedded database gives atomic, durable
//! transactions in a file that sits next to the artifact and is backed up with it, with
//! nothing to install or run. WAL mode lets `cellc plan --state` read while the service
//! writes.
//!
//! The file is marked as a cellc state file (`PRAGMA application_id`) with a layout
//! version (`PRAGMA user_version`), so another program's database is refused rather than
//! written into, and a newer layout is refused rather than misread. A second writer
//! process is refused by an advisory lock on the file (the journal's recovery assumes
//! that whatever was running when the store was opened is no longer running).

mod journal;
mod reader;

use std::fs::{File, TryLockError};
use std::path::Path;
use std::time::{Duration, SystemTime, UNIX_EPOCH};

use rusqlite::limits::Limit;
use rusqlite::{params, Connection, ErrorCode, OpenFlags, OptionalExtension, TransactionBehavior};

use crate::{
    Begun, Confirms, End, ExecutionId, ExecutionRecord, IdempotencyKey, InstanceId, NewExecution,
    Retention, Revision, Store, StoreError, StoredWorld, Uncertainty, WorldDocument,
    MAX_RECORD_BYTES,
};

/// The layout version this build writes and reads.
pub(crate) const LAYOUT: i64 = 1;

/// `"cell"` in ASCII: what marks a SQLite file as a cellc state file.
const APPLICATION_ID: i64 = 0x6365_6c6c;

/// How long a writer waits for a reader's lock before giving up, and a reader for the
/// writer's (`cellc plan --state` holds one for the length of a read).
const BUSY_TIMEOUT: Duration = Duration::from_secs(5);

const CREATE: &str = "
CREATE TABLE meta (
    key TEXT PRIMARY KEY,
    value TEXT NOT NULL
) STRICT;
CREATE TABLE world (
    id INTEGER PRIMARY KEY CHECK (id = 1),
    revision INTEGER NOT NULL,
    document TEXT NOT NULL,
    uncertain TEXT NOT NULL,
    updated_ms INTEGER NOT NULL
) STRICT;
CREATE TABLE executions (
    id INTEGER PRIMARY KEY AUTOINCREMENT,
    key TEXT UNIQUE,
    base INTEGER NOT NULL,
    intent TEXT NOT NULL,
    subjects TEXT NOT NULL,
    steps_total INTEGER NOT NULL,
    status TEXT NOT NULL,
    outcome TEXT,
    result INTEGER,
    started_ms INTEGER NOT NULL,
    finished_ms INTEGER
) STRICT;
CREATE INDEX executions_running ON executions (status) WHERE status = 'running';
CREATE TABLE steps (
    execution INTEGER NOT NULL REFERENCES executions (id) ON DELETE CASCADE,
    idx INTEGER NOT NULL,
    report TEXT NOT NULL,
    revision INTEGER NOT NULL,
    PRIMARY KEY (execution, idx)
) STRICT;
";

/// How far an acknowledged write survives.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Durability {
    /// A crash of the process loses nothing; a power loss may lose the last writes (never
    /// corrupts). SQLite's `synchronous=NORMAL`.
    Normal,
    /// A power loss loses nothing acknowledged: every commit waits for the disk.
    /// `synchronous=FULL`; the default.
    #[default]
    Full,
}

/// The world and the journal in one SQLite file.
pub struct SqliteStore {
    // Declared before the lock so that it is closed first: closing another descriptor of
    // the database file while SQLite holds its POSIX locks would drop them.
    conn: Connection,
    instance: InstanceId,
    recovered: Vec<ExecutionId>,
    retention: Retention,
    clock: fn() -> i64,
    /// For a reader of a file no writer had open: how to tell that it still has none.
    still: Option<reader::Still>,
    _lock: Option<File>,
}

fn wall_clock_ms() -> i64 {
    SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map(|d| i64::try_from(d.as_millis()).unwrap_or(i64::MAX))
        .unwrap_or(0)
}

impl SqliteStore {
    /// Opens the state file at `path`, creating it when absent, and recovers what was in
    /// flight when it was last closed.
    ///
    /// # Errors
    /// [`StoreError::InUse`] when another process has it open for writing,
    /// [`StoreError::Foreign`] / [`StoreError::TooNew`] / [`StoreError::Corrupt`] for a file
    /// that is not a state file this build can read, [`StoreError::ReadOnly`] /
    /// [`StoreError::Full`] / [`StoreError::Io`] when it cannot be written.
    pub fn open(
        path: &Path,
        durability: Durability,
        retention: Retention,
    ) -> Result<SqliteStore, StoreError> {
        SqliteStore::open_with_clock(path, durability, retention, wall_clock_ms)
    }

    /// [`SqliteStore::open`] with another clock (milliseconds since the Unix epoch), so
    /// that retention by age can be tested.
    ///
    /// # Errors
    /// As [`SqliteStore::open`].
    pub fn open_with_clock(
        path: &Path,
        durability: Durability,
        retention: Retention,
        clock: fn() -> i64,
    ) -> Result<SqliteStore, StoreError> {
        if path.is_dir() {
            return Err(StoreError::Io {
                reason: format!("`{}` is a directory", path.display()),
            });
        }
        let lock = lock(path)?;
        let conn = Connection::open_with_flags(
            path,
            OpenFlags::SQLITE_OPEN_READ_WRITE
                | OpenFlags::SQLITE_OPEN_CREATE
                | OpenFlags::SQLITE_OPEN_NO_MUTEX,
        )
        .map_err(sqlite_error)?;
        let mut store = SqliteStore::prepare(conn, Some(lock), retention, clock)?;
        store.configure(durability)?;
        store.recover()?;
        store.prune()?;
        Ok(store)
    }

    /// Opens the state file at `path` to read the world and the journal while a service
    /// may be writing it (`cellc plan --state`). Nothing is recovered or written.
    ///
    /// # Errors
    /// The file is absent, not a state file, or cannot be read.
    pub fn open_read_only(path: &Path) -> Result<SqliteStore, StoreError> {
        if !path.is_file() {
            return Err(StoreError::Io {
                reason: format!("no state file at `{}`", path.display()),
            });
        }
        // No lock is taken (a running service keeps its own), and nothing is made beside
        // a file no writer has open (`reader.rs`).
        let (conn, still) = match reader::open_still(path)? {
            Some((conn, still)) => (conn, Some(still)),
            None => (reader::open_live(path)?, None),
        };
        let mut store = SqliteStore::prepare(conn, None, Retention::default(), wall_clock_ms)?;
        if store.instance.as_str().is_empty() {
            return Err(StoreError::Foreign {
                reason: "an empty database".into(),
            });
        }
        store.still = still;
        Ok(store)
    }

    /// Runs a read; for a reader opened on a file no writer had open, checks that none
    /// came during it, and otherwise reads again as an ordinary reader.
    fn read<T>(
        &mut self,
        read: impl Fn(&Connection) -> Result<T, StoreError>,
    ) -> Result<T, StoreError> {
        let Some(still) = &self.still else {
            return read(&self.conn);
        };
        let first = read(&self.conn);
        if still.holds() {
            return first;
        }
        let live = reader::open_live(still.path())?;
        bound(&live)?;
        self.conn = live;
        self.still = None;
        read(&self.conn)
    }

    /// A store that lives in memory only (tests, and `cellc serve --state none`).
    ///
    /// # Errors
    /// SQLite could not allocate it.
    pub fn in_memory(retention: Retention) -> Result<SqliteStore, StoreError> {
        let conn = Connection::open_in_memory().map_err(sqlite_error)?;
        let mut store = SqliteStore::prepare(conn, None, retention, wall_clock_ms)?;
        store.configure(Durability::Normal)?;
        Ok(store)
    }

    /// Checks what the file is, creates the layout in an empty one, reads the instance.
    fn prepare(
        conn: Connection,
        lock: Option<File>,
        retention: Retention,
        clock: fn() -> i64,
    ) -> Result<SqliteStore, StoreError> {
        bound(&conn)?;
        let application: i64 = conn
            .query_row("PRAGMA application_id", [], |r| r.get(0))
            .map_err(sqlite_error)?;
        let version: i64 = conn
            .query_row("PRAGMA user_version", [], |r| r.get(0))
            .map_err(sqlite_error)?;
        let tables: i64 = conn
            .query_row("SELECT count(*) FROM sqlite_schema", [], |r| r.get(0))
            .map_err(sqlite_error)?;
        let readonly = conn.is_readonly(rusqlite::MAIN_DB).unwrap_or(true);
        if application == 0 && tables == 0 && !readonly {
            conn.execute_batch(&format!(
                "BEGIN IMMEDIATE;
                 {CREATE}
                 INSERT INTO meta (key, value) VALUES ('instance', lower(hex(randomblob(16))));
                 PRAGMA application_id = {APPLICATION_ID};
                 PRAGMA user_version = {LAYOUT};
                 COMMIT;"
            ))
            .map_err(sqlite_error)?;
        } else if application == 0 && tables == 0 {
            return Ok(SqliteStore {
                conn,
                instance: InstanceId(String::new()),
                recovered: Vec::new(),
                retention,
                clock,
                still: None,
                _lock: lock,
            });
        } else if application != APPLICATION_ID {
            return Err(StoreError::Foreign {
                reason: format!(
                    "an SQLite database of another program (application id {application:#x})"
                ),
            });
        } else if version > LAYOUT {
            return Err(StoreError::TooNew { version });
        } else if version < 1 {
            return Err(StoreError::Corrupt {
                reason: format!("layout version {version}"),
            });
        }
        let instance: Option<String> = conn
            .query_row("SELECT value FROM meta WHERE key = 'instance'", [], |r| {
                r.get(0)
            })
            .optional()
            .map_err(sqlite_error)?;
        let instance = match instance {
            Some(id) if id.len() == 32 && id.bytes().all(|b| b.is_ascii_hexdigit()) => id,
            other => {
                return Err(StoreError::Corrupt {
                    reason: format!("instance id {other:?}"),
                })
            }
        };
        Ok(SqliteStore {
            conn,
            instance: InstanceId(instance),
            recovered: Vec::new(),
            retention,
            clock,
            still: None,
            _lock: lock,
        })
    }

    fn configure(&mut self, durability: Durability) -> Result<(), StoreError> {
        let mode: String = self
            .conn
            .query_row("PRAGMA journal_mode = WAL", [], |r| r.get(0))
            .map_err(sqlite_error)?;
        // An in-memory database answers "memory": it has no journal file to lose.
        if mode != "wal" && mode != "memory" {
            return Err(StoreError::Io {
                reason: format!("SQLite would not use a write-ahead log (journal mode {mode})"),
            });
        }
        let synchronous = match durability {
            Durability::Normal => "NORMAL",
            Durability::Full => "FULL",
        };
        self.conn
            .execute_batch(&format!(
                "PRAGMA synchronous = {synchronous}; PRAGMA foreign_keys = ON;"
            ))
            .map_err(sqlite_error)
    }

    fn now(&self) -> i64 {
        (self.clock)()
    }
}

/// Bounds every value read back, so a hostile or damaged file cannot make a row take more
/// memory than the largest record the store writes, and sets how long to wait for a lock.
fn bound(conn: &Connection) -> Result<(), StoreError> {
    let longest = i32::try_from(MAX_RECORD_BYTES * 2).unwrap_or(i32::MAX);
    conn.set_limit(Limit::SQLITE_LIMIT_LENGTH, longest)
        .map_err(sqlite_error)?;
    conn.busy_timeout(BUSY_TIMEOUT).map_err(sqlite_error)
}

/// Takes the advisory lock that keeps a second service off the file, creating the file
/// when it is absent (SQLite treats an empty file as a new database).
fn lock(path: &Path) -> Result<File, StoreError> {
    let file = File::options()
        .read(true)
        .write(true)
        .create(true)
        .truncate(false)
        .open(path)
        .map_err(|e| io_error(path, &e))?;
    match file.try_lock() {
        Ok(()) => Ok(file),
        Err(TryLockError::WouldBlock) => Err(StoreError::InUse),
        Err(TryLockError::Error(e)) => Err(io_error(path, &e)),
    }
}

fn io_error(path: &Path, e: &std::io::Error) -> StoreError {
    match e.kind() {
        std::io::ErrorKind::PermissionDenied | std::io::ErrorKind::ReadOnlyFilesystem => {
            StoreError::ReadOnly
        }
        std::io::ErrorKind::StorageFull => StoreError::Full,
        _ => StoreError::Io {
            reason: format!("cannot open `{}`: {}", path.display(), e.kind()),
        },
    }
}

/// The extended I/O codes of a write the system refused: of the file, of growing it, of
/// the write-ahead log's shared index.
const WRITES_REFUSED: [i32; 3] = [
    rusqlite::ffi::SQLITE_IOERR_WRITE,
    rusqlite::ffi::SQLITE_IOERR_TRUNCATE,
    rusqlite::ffi::SQLITE_IOERR_SHMSIZE,
];

/// SQLite's result codes in the store's words. Messages are SQLite's own, never a row's
/// content.
pub(crate) fn sqlite_error(e: rusqlite::Error) -> StoreError {
    match &e {
        rusqlite::Error::SqliteFailure(failure, _) => match failure.code {
            ErrorCode::DiskFull => StoreError::Full,
            ErrorCode::ReadOnly | ErrorCode::PermissionDenied => StoreError::ReadOnly,
            ErrorCode::DatabaseCorrupt => StoreError::Corrupt {
                reason: "SQLite found the database damaged".into(),
            },
            ErrorCode::NotADatabase => StoreError::Foreign {
                reason: "not an SQLite database".into(),
            },
            ErrorCode::DatabaseBusy | ErrorCode::DatabaseLocked => StoreError::InUse,
            ErrorCode::TooBig => StoreError::TooLarge {
                bytes: MAX_RECORD_BYTES * 2,
            },
            // A write the system refused other than for want of space (`ENOSPC` is
            // `DiskFull` above): past the process's file-size limit (`EFBIG`), a quota,
            // or a failing disk. SQLite's own words, "Error code 778: disk I/O error",
            // would leave the operator guessing.
            ErrorCode::SystemIoFailure if WRITES_REFUSED.contains(&failure.extended_code) => {
                StoreError::Io {
                    reason: "SQLite could not write to it (the disk may be full, the file past this process's size limit, or the disk failing)".into(),
                }
            }
            _ => StoreError::Io {
                reason: format!("SQLite: {}", failure),
            },
        },
        _ => StoreError::Corrupt {
            reason: e.to_string(),
        },
    }
}

fn corrupt(what: &str, e: impl std::fmt::Display) -> StoreError {
    StoreError::Corrupt {
        reason: format!("{what}: {e}"),
    }
}

/// Reads the world row inside whatever transaction `conn` is in.
fn read_world(conn: &Connection) -> Result<Option<StoredWorld>, StoreError> {
    let row: Option<(i64, String, String)> = conn
        .query_row(
            "SELECT revision, document, uncertain FROM world WHERE id = 1",
            [],
            |r| Ok((r.get(0)?, r.get(1)?, r.get(2)?)),
        )
        .optional()
        .map_err(sqlite_error)?;
    let Some((revision, document, uncertain)) = row else {
        return Ok(None);
    };
    let revision = u64::try_from(revision)
        .ok()
        .filter(|r| *r > 0)
        .ok_or_else(|| corrupt("world revision", revision))?;
    let document = WorldDocument::from_json(document.as_bytes())
        .map_err(|e| corrupt("stored world", format!("{e:?}")))?;
    let uncertain: Vec<Uncertainty> =
        serde_json::from_str(&uncertain).map_err(|e| corrupt("stored uncertainty", e))?;
    Ok(Some(StoredWorld {
        revision: Revision(revision),
        document,
        uncertain,
    }))
}

/// Writes the world as the next revision; the caller has checked any precondition in the
/// same transaction.
fn write_world(
    conn: &Connection,
    current: Option<&StoredWorld>,
    document: &WorldDocument,
    uncertain: &[Uncertainty],
    now: i64,
) -> Result<Revision, StoreError> {
    let next = current.map_or(1, |w| w.revision.0 + 1);
    let text = serde_json::to_string(document).map_err(|e| corrupt("world", e))?;
    if text.len() > cellc_schema::world::MAX_WORLD_BYTES {
        return Err(StoreError::TooLarge { bytes: text.len() });
    }
    let uncertain = serde_json::to_string(uncertain).map_err(|e| corrupt("uncertainty", e))?;
    let next_sql = i64::try_from(next).map_err(|e| corrupt("revision", e))?;
    conn.execute(
        "INSERT INTO world (id, revision, document, uncertain, updated_ms)
         VALUES (1, ?1, ?2, ?3, ?4)
         ON CONFLICT (id) DO UPDATE SET revision = ?1, document = ?2, uncertain = ?3,
             updated_ms = ?4",
        params![next_sql, text, uncertain, now],
    )
    .map_err(sqlite_error)?;
    Ok(Revision(next))
}

fn check_expected(
    expect: Option<Revision>,
    current: Option<&StoredWorld>,
) -> Result<(), StoreError> {
    let at = current.map_or(Revision(0), |w| w.revision);
    match expect {
        Some(expected) if expected != at => Err(StoreError::Conflict {
            expected,
            current: at,
        }),
        _ => Ok(()),
    }
}

impl Store for SqliteStore {
    fn instance(&self) -> &InstanceId {
        &self.instance
    }

    fn recovered(&self) -> &[ExecutionId] {
        &self.recovered
    }

    fn world(&mut self) -> Result<Option<StoredWorld>, StoreError> {
        if self.instance.as_str().is_empty() {
            return Ok(None);
        }
        self.read(read_world)
    }

    fn put_world(
        &mut self,
        expect: Option<Revision>,
        document: &WorldDocument,
        confirms: &Confirms,
    ) -> Result<Revision, StoreError> {
        let now = self.now();
        let tx = self
            .conn
            .transaction_with_behavior(TransactionBehavior::Immediate)
            .map_err(sqlite_error)?;
        let current = read_world(&tx)?;
        check_expected(expect, current.as_ref())?;
        let uncertain = confirms.settle(
            current
                .as_ref()
                .map(|w| w.uncertain.clone())
                .unwrap_or_default(),
        );
        let revision = write_world(&tx, current.as_ref(), document, &uncertain, now)?;
        tx.commit().map_err(sqlite_error)?;
        Ok(revision)
    }

    fn begin(&mut self, execution: &NewExecution) -> Result<Begun, StoreError> {
        journal::begin(self, execution)
    }

    fn step(
        &mut self,
        id: ExecutionId,
        report: &str,
        world: &WorldDocument,
    ) -> Result<Revision, StoreError> {
        journal::step(self, id, report, world)
    }

    fn finish(
        &mut self,
        id: ExecutionId,
        end: End,
        outcome: &str,
        world: Option<&WorldDocument>,
    ) -> Result<Revision, StoreError> {
        journal::finish(self, id, end, outcome, world)
    }

    fn execution(&mut self, id: ExecutionId) -> Result<Option<ExecutionRecord>, StoreError> {
        self.read(|conn| journal::execution(conn, id))
    }

    fn recent(&mut self, limit: u32) -> Result<Vec<ExecutionRecord>, StoreError> {
        self.read(|conn| journal::recent(conn, limit))
    }

    fn in_flight(&mut self) -> Result<Vec<Uncertainty>, StoreError> {
        self.read(journal::in_flight)
    }

    fn keyed(&mut self, key: &IdempotencyKey) -> Result<Option<ExecutionRecord>, StoreError> {
        journal::keyed(&self.conn, key)
    }
}

#[cfg(test)]
mod tests;
