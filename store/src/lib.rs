//! cellc's durable state: where every object is and every arm stands (the world, with a
//! revision), and what was executed (the journal).
//!
//! A cell's runtime is the system of record for where things are, so it must lose nothing
//! it acknowledged and never let two callers overwrite each other unknowingly. This crate
//! holds the *facts* of that: revisions, compare-and-set writes, executions written
//! before they start, after every step and when they end, recovery after a crash, and
//! idempotency keys. It knows nothing of HTTP or diagnostics; the service turns its typed
//! errors into coded answers.
//!
//! [`Store`] is the seam; [`SqliteStore`] the implementation every `cellc serve` uses by
//! default (one file next to the artifact, WAL mode). A site that keeps all cells' state
//! in one server database implements [`Store`] over it (ARCHITECTURE.md says how).
//!
//! Documents the store does not interpret (an execution's intent, each step's report, the
//! outcome) are JSON text chosen by the caller; the world is the typed
//! [`WorldDocument`], so a stored world is re-read with the same bounded, strict reader as
//! one sent over the wire.

#![warn(missing_docs)]

mod sqlite;

use std::collections::BTreeSet;
use std::fmt;

use serde::{Deserialize, Serialize};

pub use cellc_schema::WorldDocument;
pub use sqlite::{Durability, SqliteStore};

/// The most bytes an execution's intent, one step's report or an outcome may have. A plan
/// of a thousand steps with joint paths is a few MiB; more is refused, not stored.
pub const MAX_RECORD_BYTES: usize = 16 << 20;

/// The longest idempotency key accepted (the IETF draft's keys are UUIDs; Stripe allows
/// 255 characters).
pub const MAX_KEY_CHARS: usize = 255;

/// A world's revision: 1 for the first world a store holds, one more for every write.
/// Never reused within a store ([`InstanceId`] tells stores apart).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(transparent)]
pub struct Revision(pub u64);

impl fmt::Display for Revision {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.0)
    }
}

/// A store's identity, made once when the store is created (32 hex digits). A client that
/// sees another instance knows the revisions it remembers mean nothing here.
#[derive(Clone, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(transparent)]
pub struct InstanceId(String);

impl InstanceId {
    /// The id as text.
    pub fn as_str(&self) -> &str {
        &self.0
    }
}

impl fmt::Display for InstanceId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

/// An execution's number in the journal, increasing, never reused within a store.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(transparent)]
pub struct ExecutionId(pub u64);

impl fmt::Display for ExecutionId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.0)
    }
}

/// A caller's key for one logical execute: the same key again returns the first outcome
/// instead of moving the object a second time.
#[derive(Clone, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(transparent)]
pub struct IdempotencyKey(String);

impl IdempotencyKey {
    /// A key of 1 to [`MAX_KEY_CHARS`] visible ASCII characters (what an HTTP header can
    /// carry without quoting).
    ///
    /// # Errors
    /// Empty, too long, or with a character outside `!`..=`~`.
    pub fn new(key: &str) -> Result<IdempotencyKey, StoreError> {
        let visible = key.bytes().all(|b| b.is_ascii_graphic());
        if key.is_empty() || key.len() > MAX_KEY_CHARS || !visible {
            return Err(StoreError::BadKey {
                length: key.chars().count(),
            });
        }
        Ok(IdempotencyKey(key.to_string()))
    }

    /// The key as text.
    pub fn as_str(&self) -> &str {
        &self.0
    }
}

/// Objects and arms, by name: what an execution moves, what is uncertain, what a write
/// confirms.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Subjects {
    /// Object names.
    #[serde(default)]
    pub objects: BTreeSet<String>,
    /// Arm names.
    #[serde(default)]
    pub arms: BTreeSet<String>,
}

impl Subjects {
    /// Nothing named.
    pub fn is_empty(&self) -> bool {
        self.objects.is_empty() && self.arms.is_empty()
    }
}

/// What an interrupted execution leaves unknown: the objects and arms it was moving when
/// the service stopped. The world holds the state its last recorded step was known to
/// leave; the real cell may be anywhere between that step and the next.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Uncertainty {
    /// The execution that was in flight.
    pub execution: ExecutionId,
    /// Steps it had finished (the world is as step `steps_done` left it; 0: as before it
    /// started).
    pub steps_done: u32,
    /// What to confirm before planning with it again.
    pub subjects: Subjects,
}

/// The world as the store holds it.
#[derive(Clone, Debug, PartialEq)]
pub struct StoredWorld {
    /// Its revision.
    pub revision: Revision,
    /// Where everything is.
    pub document: WorldDocument,
    /// What interrupted executions left unknown, oldest first; empty when the world is
    /// certain.
    pub uncertain: Vec<Uncertainty>,
}

impl StoredWorld {
    /// Every object and arm some interruption left unknown.
    pub fn uncertain_subjects(&self) -> Subjects {
        let mut all = Subjects::default();
        for u in &self.uncertain {
            all.objects.extend(u.subjects.objects.iter().cloned());
            all.arms.extend(u.subjects.arms.iter().cloned());
        }
        all
    }
}

/// What a world write confirms of what interruptions left unknown.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Confirms {
    /// Everything: a whole world document from sensing.
    Everything,
    /// What the write names (an incremental update); the rest stays unknown.
    Only(Subjects),
}

impl Confirms {
    /// What is still uncertain of `uncertain` once this write confirmed its part: the
    /// one rule the store applies and the service mirrors in memory.
    pub fn settle(&self, uncertain: Vec<Uncertainty>) -> Vec<Uncertainty> {
        match self {
            Confirms::Everything => Vec::new(),
            Confirms::Only(confirmed) => uncertain
                .into_iter()
                .filter_map(|mut u| {
                    u.subjects
                        .objects
                        .retain(|o| !confirmed.objects.contains(o));
                    u.subjects.arms.retain(|a| !confirmed.arms.contains(a));
                    (!u.subjects.is_empty()).then_some(u)
                })
                .collect(),
        }
    }
}

/// An execution about to start.
#[derive(Clone, Debug, PartialEq)]
pub struct NewExecution {
    /// The caller's key, when it gave one.
    pub key: Option<IdempotencyKey>,
    /// The revision the plan was made against: the start is refused when the world has
    /// moved on. `None`: whatever the world is now.
    pub expect: Option<Revision>,
    /// What is executed (the plan or task as JSON), so a recovered service can say what
    /// was in flight.
    pub intent: String,
    /// What it moves: uncertain if the service stops during it.
    pub subjects: Subjects,
    /// How many steps it has.
    pub steps: u32,
}

/// How an execution ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Status {
    /// Started and not finished.
    Running,
    /// Every step done.
    Succeeded,
    /// Ended by a failure the executor reported (the outcome says which).
    Failed,
    /// Stopped by a caller.
    Cancelled,
    /// The service stopped while it ran; found so at the next start.
    Interrupted,
}

impl Status {
    fn as_str(self) -> &'static str {
        match self {
            Status::Running => "running",
            Status::Succeeded => "succeeded",
            Status::Failed => "failed",
            Status::Cancelled => "cancelled",
            Status::Interrupted => "interrupted",
        }
    }

    fn parse(text: &str) -> Option<Status> {
        [
            Status::Running,
            Status::Succeeded,
            Status::Failed,
            Status::Cancelled,
            Status::Interrupted,
        ]
        .into_iter()
        .find(|s| s.as_str() == text)
    }
}

/// How the service ended an execution (an interruption is found, not declared).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum End {
    /// Every step done.
    Succeeded,
    /// The executor reported a failure it could not recover from.
    Failed,
    /// A caller stopped it.
    Cancelled,
}

impl End {
    /// The status it leaves.
    pub fn status(self) -> Status {
        match self {
            End::Succeeded => Status::Succeeded,
            End::Failed => Status::Failed,
            End::Cancelled => Status::Cancelled,
        }
    }
}

/// One recorded step of an execution.
#[derive(Clone, Debug, PartialEq)]
pub struct StepRecord {
    /// 1 for the first step.
    pub index: u32,
    /// What the executor reported (JSON).
    pub report: String,
    /// The world revision the step left.
    pub revision: Revision,
}

/// An execution as the journal holds it.
#[derive(Clone, Debug, PartialEq)]
pub struct ExecutionRecord {
    /// Its number.
    pub id: ExecutionId,
    /// The caller's key.
    pub key: Option<IdempotencyKey>,
    /// The world revision it started from.
    pub base: Revision,
    /// What was executed (JSON, as given).
    pub intent: String,
    /// What it moves.
    pub subjects: Subjects,
    /// Steps in the plan.
    pub steps_total: u32,
    /// Steps recorded, in order (empty in [`Store::recent`]'s list).
    pub steps: Vec<StepRecord>,
    /// How many steps are recorded (also in a list).
    pub steps_done: u32,
    /// Where it is.
    pub status: Status,
    /// The outcome document (JSON), once ended by the service.
    pub outcome: Option<String>,
    /// The revision its end left, once ended.
    pub result: Option<Revision>,
    /// When it started, milliseconds since the Unix epoch.
    pub started_ms: i64,
    /// When it ended.
    pub finished_ms: Option<i64>,
}

/// What [`Store::begin`] did.
#[derive(Clone, Debug, PartialEq)]
pub enum Begun {
    /// Journaled; execute it.
    Started {
        /// Its number.
        id: ExecutionId,
        /// The revision it starts from.
        base: Revision,
    },
    /// The key was used before with the same intent: this is that execution, in whatever
    /// state it is. Do not execute again.
    Repeated(Box<ExecutionRecord>),
}

/// How long the journal keeps ended executions. Running ones, and the ones an
/// uncertainty names, are always kept.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Retention {
    /// At most this many ended executions (the newest).
    pub max_executions: u32,
    /// And none older than this, milliseconds; `None`: no age limit.
    pub max_age_ms: Option<i64>,
}

impl Default for Retention {
    /// 10,000 executions and 30 days: a busy cell's month, a few tens of MiB.
    fn default() -> Retention {
        Retention {
            max_executions: 10_000,
            max_age_ms: Some(30 * 24 * 3600 * 1000),
        }
    }
}

/// Why the store refused or failed. The service maps each to a coded diagnostic.
#[derive(Clone, Debug, PartialEq)]
pub enum StoreError {
    /// The write expected a revision the world no longer has.
    Conflict {
        /// What the caller expected.
        expected: Revision,
        /// What the world is at.
        current: Revision,
    },
    /// An idempotency key seen before with a different intent.
    KeyReused {
        /// The execution that has the key.
        execution: ExecutionId,
    },
    /// An idempotency key that is empty, too long or not visible ASCII.
    BadKey {
        /// Its length in characters.
        length: usize,
    },
    /// No execution of that number (never, or pruned), or it has already ended.
    UnknownExecution {
        /// The number asked for.
        id: ExecutionId,
    },
    /// A record over [`MAX_RECORD_BYTES`].
    TooLarge {
        /// Its size.
        bytes: usize,
    },
    /// Another process has the state file open for writing.
    InUse,
    /// The disk is full: nothing of this write was stored.
    Full,
    /// The file or its directory cannot be written.
    ReadOnly,
    /// The file is not a cellc state file (another program's database, or not one).
    Foreign {
        /// What was found.
        reason: String,
    },
    /// Written by a newer cellc, with a layout this one does not know.
    TooNew {
        /// The file's layout version.
        version: i64,
    },
    /// The file is damaged: SQLite's words, or what does not read back.
    Corrupt {
        /// What is wrong.
        reason: String,
    },
    /// [`Store::begin`] before the store holds any world.
    NoWorld,
    /// The file cannot be opened or read (permissions, a directory, an I/O error).
    Io {
        /// What the system said.
        reason: String,
    },
}

impl fmt::Display for StoreError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            StoreError::Conflict { expected, current } => write!(
                f,
                "the world is at revision {current}, not the expected {expected}"
            ),
            StoreError::KeyReused { execution } => write!(
                f,
                "the idempotency key was used by execution {execution} for another request"
            ),
            StoreError::BadKey { length } => write!(
                f,
                "an idempotency key must be 1 to {MAX_KEY_CHARS} visible ASCII characters \
                 (this one has {length})"
            ),
            StoreError::UnknownExecution { id } => {
                write!(f, "no running execution {id} in the journal")
            }
            StoreError::TooLarge { bytes } => write!(
                f,
                "a record of {bytes} bytes is over the journal's {MAX_RECORD_BYTES}"
            ),
            StoreError::InUse => f.write_str("another process has the state file open"),
            StoreError::Full => f.write_str("the disk is full"),
            StoreError::ReadOnly => f.write_str("the state file cannot be written"),
            StoreError::Foreign { reason } => write!(f, "not a cellc state file: {reason}"),
            StoreError::TooNew { version } => write!(
                f,
                "the state file has layout {version}, newer than this cellc's {}",
                sqlite::LAYOUT
            ),
            StoreError::Corrupt { reason } => write!(f, "the state file is damaged: {reason}"),
            StoreError::NoWorld => f.write_str("the store holds no world yet"),
            StoreError::Io { reason } => f.write_str(reason),
        }
    }
}

impl std::error::Error for StoreError {}

/// Where the world and the journal are kept.
///
/// Every method is one transaction: it happens entirely or not at all, and once it
/// returns `Ok` it survives a crash of the process (and, with [`Durability::Full`], of
/// the machine). Writers are serialised by the store; a precondition (an expected
/// [`Revision`]) turns a lost update into [`StoreError::Conflict`].
pub trait Store: Send {
    /// The store's identity.
    fn instance(&self) -> &InstanceId;

    /// The executions found in flight when the store was opened, now marked
    /// [`Status::Interrupted`] (empty after a clean stop).
    fn recovered(&self) -> &[ExecutionId];

    /// The world, or `None` before the first write.
    ///
    /// # Errors
    /// The file cannot be read, or what it holds does not read back.
    fn world(&mut self) -> Result<Option<StoredWorld>, StoreError>;

    /// Replaces the world when it is at `expect` (or whatever it is, for `None`), and
    /// clears what `confirms` confirms of the uncertainty. Returns the new revision.
    ///
    /// # Errors
    /// [`StoreError::Conflict`], or the file cannot be written.
    fn put_world(
        &mut self,
        expect: Option<Revision>,
        document: &WorldDocument,
        confirms: &Confirms,
    ) -> Result<Revision, StoreError>;

    /// Journals an execution before it runs, or finds the one its key names.
    ///
    /// # Errors
    /// [`StoreError::Conflict`] when the world moved on from `expect`,
    /// [`StoreError::KeyReused`], a record too large, or the file cannot be written.
    fn begin(&mut self, execution: &NewExecution) -> Result<Begun, StoreError>;

    /// Records a finished step and the world it left, in one transaction. Returns the
    /// world's new revision.
    ///
    /// # Errors
    /// [`StoreError::UnknownExecution`] when `id` is not running, or the file cannot be
    /// written.
    fn step(
        &mut self,
        id: ExecutionId,
        report: &str,
        world: &WorldDocument,
    ) -> Result<Revision, StoreError>;

    /// Ends an execution with its outcome, and the world it left when that differs from
    /// its last step's. Returns the world's revision after it.
    ///
    /// # Errors
    /// [`StoreError::UnknownExecution`] when `id` is not running, or the file cannot be
    /// written.
    fn finish(
        &mut self,
        id: ExecutionId,
        end: End,
        outcome: &str,
        world: Option<&WorldDocument>,
    ) -> Result<Revision, StoreError>;

    /// One execution.
    ///
    /// # Errors
    /// The file cannot be read.
    fn execution(&mut self, id: ExecutionId) -> Result<Option<ExecutionRecord>, StoreError>;

    /// The newest executions, newest first, without their steps and outcomes.
    ///
    /// # Errors
    /// The file cannot be read.
    fn recent(&mut self, limit: u32) -> Result<Vec<ExecutionRecord>, StoreError>;

    /// The execution journaled under `key`, with its steps: a retry finds its first
    /// outcome here before anything else is checked (a retry of a move that succeeded
    /// must not fail on the revision that very move produced).
    ///
    /// # Errors
    /// The file cannot be read.
    fn keyed(&mut self, key: &IdempotencyKey) -> Result<Option<ExecutionRecord>, StoreError>;

    /// What the executions still `running` leave unknown, oldest first: for a reader
    /// beside the service (`cellc plan --state`), whose world is as their last recorded
    /// steps left it while the cell may be further on (or, when their service stopped
    /// and was not started again, as recovery will find them). Empty for a writer after
    /// [`Store::recovered`] unless it has begun one since.
    ///
    /// The default reads [`Store::recent`] and each running execution; an
    /// implementation with an index of running executions does better.
    ///
    /// # Errors
    /// The file cannot be read.
    fn in_flight(&mut self) -> Result<Vec<Uncertainty>, StoreError> {
        let mut out = Vec::new();
        for listed in self.recent(u32::MAX)? {
            if listed.status != Status::Running {
                continue;
            }
            let Some(record) = self.execution(listed.id)? else {
                continue;
            };
            out.push(Uncertainty {
                execution: record.id,
                steps_done: u32::try_from(record.steps.len()).unwrap_or(u32::MAX),
                subjects: record.subjects,
            });
        }
        out.reverse();
        Ok(out)
    }
}
