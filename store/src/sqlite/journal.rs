//! The execution journal: written before an execution starts, after every step (with the
//! world that step left, in the same transaction), and when it ends; read back after a
//! crash to say what was in flight.

use rusqlite::{params, Connection, OptionalExtension, Row, TransactionBehavior};

use super::{check_expected, corrupt, read_world, sqlite_error, write_world, SqliteStore};
use crate::{
    Begun, End, ExecutionId, ExecutionRecord, IdempotencyKey, NewExecution, Revision, Status,
    StepRecord, StoreError, Uncertainty, WorldDocument, MAX_RECORD_BYTES,
};

/// The most executions [`crate::Store::recent`] lists at once.
const MOST_LISTED: u32 = 1000;

fn bounded(text: &str) -> Result<(), StoreError> {
    if text.len() > MAX_RECORD_BYTES {
        return Err(StoreError::TooLarge { bytes: text.len() });
    }
    Ok(())
}

fn sql_id(id: ExecutionId) -> i64 {
    i64::try_from(id.0).unwrap_or(i64::MAX)
}

fn sql_revision(r: Revision) -> i64 {
    i64::try_from(r.0).unwrap_or(i64::MAX)
}

pub(super) fn begin(store: &mut SqliteStore, new: &NewExecution) -> Result<Begun, StoreError> {
    bounded(&new.intent)?;
    let now = store.now();
    let subjects = serde_json::to_string(&new.subjects).map_err(|e| corrupt("subjects", e))?;
    let tx = store
        .conn
        .transaction_with_behavior(TransactionBehavior::Immediate)
        .map_err(sqlite_error)?;
    if let Some(key) = &new.key {
        let seen: Option<(i64, String)> = tx
            .query_row(
                "SELECT id, intent FROM executions WHERE key = ?1",
                [key.as_str()],
                |r| Ok((r.get(0)?, r.get(1)?)),
            )
            .optional()
            .map_err(sqlite_error)?;
        if let Some((id, intent)) = seen {
            let id = ExecutionId(u64::try_from(id).map_err(|e| corrupt("execution id", e))?);
            if intent != new.intent {
                return Err(StoreError::KeyReused { execution: id });
            }
            let record = execution(&tx, id)?.ok_or(StoreError::UnknownExecution { id })?;
            return Ok(Begun::Repeated(Box::new(record)));
        }
    }
    let world = read_world(&tx)?;
    check_expected(new.expect, world.as_ref())?;
    let Some(world) = world else {
        return Err(StoreError::NoWorld);
    };
    tx.execute(
        "INSERT INTO executions (key, base, intent, subjects, steps_total, status, started_ms)
         VALUES (?1, ?2, ?3, ?4, ?5, 'running', ?6)",
        params![
            new.key.as_ref().map(IdempotencyKey::as_str),
            sql_revision(world.revision),
            new.intent,
            subjects,
            new.steps,
            now
        ],
    )
    .map_err(sqlite_error)?;
    let id = ExecutionId(u64::try_from(tx.last_insert_rowid()).unwrap_or(0));
    tx.commit().map_err(sqlite_error)?;
    Ok(Begun::Started {
        id,
        base: world.revision,
    })
}

/// The steps recorded so far for a running execution, or why it cannot take another.
fn running_steps(conn: &Connection, id: ExecutionId) -> Result<u32, StoreError> {
    let status: Option<String> = conn
        .query_row(
            "SELECT status FROM executions WHERE id = ?1",
            [sql_id(id)],
            |r| r.get(0),
        )
        .optional()
        .map_err(sqlite_error)?;
    if status.as_deref() != Some(Status::Running.as_str()) {
        return Err(StoreError::UnknownExecution { id });
    }
    conn.query_row(
        "SELECT count(*) FROM steps WHERE execution = ?1",
        [sql_id(id)],
        |r| r.get(0),
    )
    .map_err(sqlite_error)
}

pub(super) fn step(
    store: &mut SqliteStore,
    id: ExecutionId,
    report: &str,
    document: &WorldDocument,
) -> Result<Revision, StoreError> {
    bounded(report)?;
    let now = store.now();
    let tx = store
        .conn
        .transaction_with_behavior(TransactionBehavior::Immediate)
        .map_err(sqlite_error)?;
    let done = running_steps(&tx, id)?;
    let world = read_world(&tx)?;
    let uncertain = world
        .as_ref()
        .map(|w| w.uncertain.clone())
        .unwrap_or_default();
    let revision = write_world(&tx, world.as_ref(), document, &uncertain, now)?;
    tx.execute(
        "INSERT INTO steps (execution, idx, report, revision) VALUES (?1, ?2, ?3, ?4)",
        params![sql_id(id), done + 1, report, sql_revision(revision)],
    )
    .map_err(sqlite_error)?;
    tx.commit().map_err(sqlite_error)?;
    Ok(revision)
}

pub(super) fn finish(
    store: &mut SqliteStore,
    id: ExecutionId,
    end: End,
    outcome: &str,
    document: Option<&WorldDocument>,
) -> Result<Revision, StoreError> {
    bounded(outcome)?;
    let now = store.now();
    let tx = store
        .conn
        .transaction_with_behavior(TransactionBehavior::Immediate)
        .map_err(sqlite_error)?;
    running_steps(&tx, id)?;
    let world = read_world(&tx)?;
    let revision = match (document, &world) {
        (Some(document), _) => {
            let uncertain = world
                .as_ref()
                .map(|w| w.uncertain.clone())
                .unwrap_or_default();
            write_world(&tx, world.as_ref(), document, &uncertain, now)?
        }
        (None, Some(world)) => world.revision,
        (None, None) => return Err(StoreError::NoWorld),
    };
    tx.execute(
        "UPDATE executions SET status = ?2, outcome = ?3, result = ?4, finished_ms = ?5
         WHERE id = ?1",
        params![
            sql_id(id),
            end.status().as_str(),
            outcome,
            sql_revision(revision),
            now
        ],
    )
    .map_err(sqlite_error)?;
    tx.commit().map_err(sqlite_error)?;
    // The end is committed: a prune that fails now (a full disk) must not make the caller
    // think it was not. What is left to prune goes at the next end or open.
    let _ = store.prune();
    Ok(revision)
}

impl SqliteStore {
    /// Marks every execution still `running` as interrupted and the objects and arms it
    /// moves as uncertain, in one transaction. The lock taken at open guarantees that no
    /// other process is running them.
    pub(super) fn recover(&mut self) -> Result<(), StoreError> {
        let now = self.now();
        let tx = self
            .conn
            .transaction_with_behavior(TransactionBehavior::Immediate)
            .map_err(sqlite_error)?;
        let running = in_flight(&tx)?;
        if running.is_empty() {
            return Ok(());
        }
        let world = read_world(&tx)?.ok_or_else(|| {
            corrupt(
                "journal",
                "an execution is in flight but no world is stored",
            )
        })?;
        let mut uncertain = world.uncertain.clone();
        for found in running {
            let id = found.execution;
            uncertain.push(found);
            tx.execute(
                "UPDATE executions SET status = 'interrupted', finished_ms = ?2,
                     result = ?3 WHERE id = ?1",
                params![sql_id(id), now, sql_revision(world.revision)],
            )
            .map_err(sqlite_error)?;
            self.recovered.push(id);
        }
        write_world(&tx, Some(&world), &world.document, &uncertain, now)?;
        tx.commit().map_err(sqlite_error)
    }

    /// Forgets ended executions past the retention, keeping any an uncertainty names.
    pub(super) fn prune(&mut self) -> Result<(), StoreError> {
        let kept: Vec<u64> = read_world(&self.conn)?
            .map(|w| w.uncertain.iter().map(|u| u.execution.0).collect())
            .unwrap_or_default();
        let kept = serde_json::to_string(&kept).map_err(|e| corrupt("kept", e))?;
        let cutoff = self
            .retention
            .max_age_ms
            .map_or(i64::MIN, |age| self.now().saturating_sub(age));
        self.conn
            .execute(
                "DELETE FROM executions
                 WHERE status != 'running'
                   AND id NOT IN (SELECT value FROM json_each(?1))
                   AND (finished_ms < ?2 OR id NOT IN (
                        SELECT id FROM executions WHERE status != 'running'
                        ORDER BY id DESC LIMIT ?3))",
                params![kept, cutoff, self.retention.max_executions],
            )
            .map_err(sqlite_error)?;
        Ok(())
    }
}

const COLUMNS: &str = "id, key, base, intent, subjects, steps_total, status, outcome, result,
                       started_ms, finished_ms,
                       (SELECT count(*) FROM steps s WHERE s.execution = executions.id)";

/// [`COLUMNS`] without the outcome, which a list does not show (an outcome holds a whole
/// run document; a thousand of them need not be read to list their executions).
const LISTED: &str = "id, key, base, intent, subjects, steps_total, status, NULL, result,
                      started_ms, finished_ms,
                      (SELECT count(*) FROM steps s WHERE s.execution = executions.id)";

fn record(row: &Row<'_>) -> rusqlite::Result<RawRecord> {
    Ok(RawRecord {
        id: row.get(0)?,
        key: row.get(1)?,
        base: row.get(2)?,
        intent: row.get(3)?,
        subjects: row.get(4)?,
        steps_total: row.get(5)?,
        status: row.get(6)?,
        outcome: row.get(7)?,
        result: row.get(8)?,
        started_ms: row.get(9)?,
        finished_ms: row.get(10)?,
        steps_done: row.get(11)?,
    })
}

/// A row as SQLite has it, before the store checks that it reads back as a record.
struct RawRecord {
    id: i64,
    key: Option<String>,
    base: i64,
    intent: String,
    subjects: String,
    steps_total: u32,
    status: String,
    outcome: Option<String>,
    result: Option<i64>,
    started_ms: i64,
    finished_ms: Option<i64>,
    steps_done: u32,
}

fn revision_of(value: i64) -> Result<Revision, StoreError> {
    u64::try_from(value)
        .map(Revision)
        .map_err(|e| corrupt("revision", e))
}

impl RawRecord {
    fn check(self, steps: Vec<StepRecord>) -> Result<ExecutionRecord, StoreError> {
        Ok(ExecutionRecord {
            id: ExecutionId(u64::try_from(self.id).map_err(|e| corrupt("execution id", e))?),
            key: self.key.as_deref().map(IdempotencyKey::new).transpose()?,
            base: revision_of(self.base)?,
            intent: self.intent,
            subjects: serde_json::from_str(&self.subjects).map_err(|e| corrupt("subjects", e))?,
            steps_total: self.steps_total,
            steps,
            status: Status::parse(&self.status)
                .ok_or_else(|| corrupt("execution status", &self.status))?,
            outcome: self.outcome,
            result: self.result.map(revision_of).transpose()?,
            started_ms: self.started_ms,
            finished_ms: self.finished_ms,
            steps_done: self.steps_done,
        })
    }
}

/// The execution journaled under `key`, if any.
pub(super) fn keyed(
    conn: &Connection,
    key: &IdempotencyKey,
) -> Result<Option<ExecutionRecord>, StoreError> {
    let id: Option<i64> = conn
        .query_row(
            "SELECT id FROM executions WHERE key = ?1",
            [key.as_str()],
            |r| r.get(0),
        )
        .optional()
        .map_err(sqlite_error)?;
    match id {
        None => Ok(None),
        Some(id) => {
            let id = ExecutionId(u64::try_from(id).map_err(|e| corrupt("execution id", e))?);
            execution(conn, id)
        }
    }
}

pub(super) fn execution(
    conn: &Connection,
    id: ExecutionId,
) -> Result<Option<ExecutionRecord>, StoreError> {
    let raw = conn
        .query_row(
            &format!("SELECT {COLUMNS} FROM executions WHERE id = ?1"),
            [sql_id(id)],
            record,
        )
        .optional()
        .map_err(sqlite_error)?;
    let Some(raw) = raw else {
        return Ok(None);
    };
    let mut statement = conn
        .prepare("SELECT idx, report, revision FROM steps WHERE execution = ?1 ORDER BY idx")
        .map_err(sqlite_error)?;
    let rows = statement
        .query_map([sql_id(id)], |r| {
            Ok((
                r.get::<_, u32>(0)?,
                r.get::<_, String>(1)?,
                r.get::<_, i64>(2)?,
            ))
        })
        .map_err(sqlite_error)?;
    let mut steps = Vec::new();
    for row in rows {
        let (index, report, revision) = row.map_err(sqlite_error)?;
        steps.push(StepRecord {
            index,
            report,
            revision: revision_of(revision)?,
        });
    }
    raw.check(steps).map(Some)
}

/// What the running executions leave unknown, oldest first (what [`SqliteStore::recover`]
/// would mark uncertain).
pub(super) fn in_flight(conn: &Connection) -> Result<Vec<Uncertainty>, StoreError> {
    let mut statement = conn
        .prepare(
            "SELECT e.id, e.subjects,
                    (SELECT count(*) FROM steps s WHERE s.execution = e.id)
             FROM executions e WHERE e.status = 'running' ORDER BY e.id",
        )
        .map_err(sqlite_error)?;
    let rows = statement
        .query_map([], |r| {
            Ok((
                r.get::<_, i64>(0)?,
                r.get::<_, String>(1)?,
                r.get::<_, u32>(2)?,
            ))
        })
        .map_err(sqlite_error)?;
    let mut out = Vec::new();
    for row in rows {
        let (id, subjects, steps_done) = row.map_err(sqlite_error)?;
        out.push(Uncertainty {
            execution: ExecutionId(u64::try_from(id).map_err(|e| corrupt("execution id", e))?),
            steps_done,
            subjects: serde_json::from_str(&subjects).map_err(|e| corrupt("subjects", e))?,
        });
    }
    Ok(out)
}

pub(super) fn recent(conn: &Connection, limit: u32) -> Result<Vec<ExecutionRecord>, StoreError> {
    let mut statement = conn
        .prepare(&format!(
            "SELECT {LISTED} FROM executions ORDER BY id DESC LIMIT ?1"
        ))
        .map_err(sqlite_error)?;
    let rows = statement
        .query_map([limit.min(MOST_LISTED)], record)
        .map_err(sqlite_error)?;
    let mut out = Vec::new();
    for row in rows {
        out.push(row.map_err(sqlite_error)?.check(Vec::new())?);
    }
    Ok(out)
}
