//! The service's world as the state file keeps it: the world, its revision and what
//! interruptions left uncertain, mirrored in memory from the store under one lock, so a
//! write is acknowledged only once it is stored and readers never see a world the store
//! does not hold. Preconditions (`If-Match`, `"revision"`) and the refusals that guard
//! planning (S0006, S0007) are here too.

use std::path::{Path, PathBuf};

use axum::http::{HeaderMap, HeaderValue};
use cellc_lang::{Diagnostic, SourceMap};
use cellc_runtime::World;
use cellc_store::{
    Confirms, Durability, InstanceId, Retention, Revision, SqliteStore, Store, StoreError,
    Uncertainty,
};

use super::errors::{ApiError, Failure};
use crate::state::{self, codes, When};
use cellc_driver::document::state::Interrupted;

/// Where the service keeps its world.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum StateAt {
    /// In a state file, created when absent.
    File(PathBuf, Durability),
    /// In memory only (`--ephemeral`): revisions and the journal as usual, and nothing
    /// survives a stop.
    Memory,
}

/// The world as a reader sees it at one instant: as the store holds it.
pub struct Snapshot {
    /// Where everything is.
    pub world: World,
    /// Its revision.
    pub revision: Revision,
    /// The store's identity.
    pub instance: InstanceId,
    /// What interruptions left unknown.
    pub uncertain: Vec<Uncertainty>,
}

impl Snapshot {
    /// The world's `ETag`.
    pub fn etag(&self) -> String {
        etag(&self.instance, self.revision)
    }

    /// The uncertainty in the documents' words.
    pub fn interrupted(&self) -> Vec<Interrupted> {
        self.uncertain.iter().map(interrupted).collect()
    }

    /// S0007 when an interruption left anything unknown: nothing is planned from a world
    /// that may not be the cell's.
    pub fn refuse_uncertain(&self, sources: &SourceMap) -> Result<(), ApiError> {
        refuse(&self.uncertain, sources)
    }
}

fn refuse(uncertain: &[Uncertainty], sources: &SourceMap) -> Result<(), ApiError> {
    if uncertain.is_empty() {
        return Ok(());
    }
    let d = state::uncertain_of(
        uncertain,
        "confirm where they are: PUT /v1/world with the whole world, or PATCH /v1/world naming them (docs/service.md)",
    );
    Err(ApiError::from_diagnostic(Failure::Conflict, &d, sources))
}

/// The world and its store, behind the service's one lock.
pub struct Durable {
    /// The world plans start from.
    pub world: World,
    /// Its revision in the store.
    pub revision: Revision,
    /// What interrupted executions left unknown.
    pub uncertain: Vec<Uncertainty>,
    /// Where it is kept.
    pub store: Box<dyn Store>,
    /// The state file's path as the operator gave it (`memory` for `--ephemeral`), for
    /// messages.
    pub shown: String,
}

impl Durable {
    /// Opens the store and reads its world back, or stores `initial` as revision 1 in a
    /// new store. Errors are S0011 diagnostics.
    pub fn open(
        at: &StateAt,
        retention: Retention,
        cell: &cellc_runtime::Cell,
        initial: impl FnOnce() -> Result<World, Diagnostic>,
    ) -> Result<Durable, Diagnostic> {
        let (store, shown): (Box<dyn Store>, String) = match at {
            StateAt::File(path, durability) => {
                let shown = path.display().to_string();
                let store = SqliteStore::open(path, *durability, retention)
                    .map_err(|e| state::diagnostic(&e, &shown, When::Opening))?;
                (Box::new(store), shown)
            }
            StateAt::Memory => {
                let store = SqliteStore::in_memory(retention)
                    .map_err(|e| state::diagnostic(&e, "memory", When::Opening))?;
                (Box::new(store), "memory".to_string())
            }
        };
        let mut store = store;
        let stored = store
            .world()
            .map_err(|e| state::diagnostic(&e, &shown, When::Opening))?;
        match stored {
            Some(stored) => {
                let world = state::world_of(cell, &stored, &shown)?;
                Ok(Durable {
                    world,
                    revision: stored.revision,
                    uncertain: stored.uncertain,
                    store,
                    shown,
                })
            }
            None => {
                let world = initial()?;
                let revision = store
                    .put_world(None, &cell.world_document(&world), &Confirms::Everything)
                    .map_err(|e| state::diagnostic(&e, &shown, When::Opening))?;
                Ok(Durable {
                    world,
                    revision,
                    uncertain: Vec::new(),
                    store,
                    shown,
                })
            }
        }
    }

    /// The store's identity.
    pub fn instance(&self) -> &InstanceId {
        self.store.instance()
    }

    /// The world's entity tag: `"INSTANCE-REVISION"`.
    pub fn etag(&self) -> String {
        etag(self.instance(), self.revision)
    }

    /// The uncertainty in the documents' words.
    pub fn interrupted(&self) -> Vec<Interrupted> {
        self.uncertain.iter().map(interrupted).collect()
    }

    /// S0007 when an interruption left anything unknown.
    pub fn refuse_uncertain(&self, sources: &SourceMap) -> Result<(), ApiError> {
        refuse(&self.uncertain, sources)
    }

    /// What readers see of it now.
    pub fn snapshot(&self) -> Snapshot {
        Snapshot {
            world: self.world.clone(),
            revision: self.revision,
            instance: self.instance().clone(),
            uncertain: self.uncertain.clone(),
        }
    }

    /// Checks a request's precondition against the world now: S0006 when it names
    /// another revision or another store. Returns the revision to hand the store as
    /// its own compare-and-set.
    pub fn check(&self, precondition: &Precondition) -> Result<Option<Revision>, ApiError> {
        let fail = |message: String| {
            Err(ApiError::new(
                Failure::Precondition,
                codes::PRECONDITION_FAILED,
                message,
                format!(
                    "read the world again (GET /v1/world: ETag {}) and decide whether the request still holds",
                    self.etag()
                ),
            ))
        };
        if let Some(tags) = &precondition.if_match {
            let matches = tags.iter().any(|t| match t {
                Tag::Any => true,
                Tag::Of { instance, revision } => {
                    instance == self.instance().as_str() && *revision == self.revision.0
                }
                Tag::Other => false,
            });
            if !matches {
                let other_store = tags.iter().all(|t| match t {
                    Tag::Of { instance, .. } => instance != self.instance().as_str(),
                    Tag::Other => true,
                    Tag::Any => false,
                });
                return fail(if other_store {
                    "`If-Match` names another store's world: the service's state was replaced, its revisions are not these".to_string()
                } else {
                    format!(
                        "the world is at revision {}, not the one `If-Match` expects",
                        self.revision
                    )
                });
            }
        }
        if let Some(expected) = precondition.revision {
            if expected != self.revision.0 {
                return fail(format!(
                    "the world is at revision {}, not the expected {expected}",
                    self.revision
                ));
            }
        }
        Ok(precondition.given().then_some(self.revision))
    }

    /// A store error while serving: S0010 (507) for what could not be stored, S0006 for
    /// a compare-and-set the store refused.
    pub fn failed(&self, e: &StoreError) -> ApiError {
        match e {
            StoreError::Conflict { expected, current } => ApiError::new(
                Failure::Precondition,
                codes::PRECONDITION_FAILED,
                format!("the world is at revision {current}, not the expected {expected}"),
                "read the world again (GET /v1/world) and decide whether the request still holds",
            ),
            e => serving_error(e, &self.shown),
        }
    }
}

/// A store error while serving (not a conflict): S0010, 507.
pub fn serving_error(e: &StoreError, shown: &str) -> ApiError {
    ApiError::from_diagnostic(
        Failure::Storage,
        &state::diagnostic(e, shown, When::Serving),
        &SourceMap::new(),
    )
}

/// `"INSTANCE-REVISION"`, quotes included, as `ETag` and `If-Match` carry it.
pub fn etag(instance: &InstanceId, revision: Revision) -> String {
    format!("\"{instance}-{revision}\"")
}

/// An `ETag` header value (instance ids and revisions are hex digits and numbers, always
/// a valid header).
pub fn etag_header(tag: &str) -> Option<HeaderValue> {
    HeaderValue::from_str(tag).ok()
}

fn interrupted(u: &Uncertainty) -> Interrupted {
    Interrupted {
        execution: u.execution.0,
        steps_done: u.steps_done,
        objects: u.subjects.objects.iter().cloned().collect(),
        arms: u.subjects.arms.iter().cloned().collect(),
    }
}

/// One entity tag of `If-Match`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Tag {
    /// `*`: any current world.
    Any,
    /// One of this service's tags.
    Of {
        /// The store it names.
        instance: String,
        /// The revision.
        revision: u64,
    },
    /// A well-formed tag this service never gave (weak, or of another form): it matches
    /// nothing.
    Other,
}

/// What a request expects of the world before it may write.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Precondition {
    /// `If-Match`, when sent.
    pub if_match: Option<Vec<Tag>>,
    /// `"revision"` of the body, when given.
    pub revision: Option<u64>,
}

impl Precondition {
    /// Reads `If-Match` (S0009 when it is not a list of entity tags or `*`).
    pub fn from_headers(headers: &HeaderMap) -> Result<Precondition, ApiError> {
        let mut tags = Vec::new();
        let mut any = false;
        for value in headers.get_all(axum::http::header::IF_MATCH) {
            any = true;
            let text = value.to_str().map_err(|_| bad_if_match())?;
            tags.extend(parse_if_match(text).ok_or_else(bad_if_match)?);
        }
        Ok(Precondition {
            if_match: any.then_some(tags),
            revision: None,
        })
    }

    /// With the body's `"revision"`.
    pub fn with_revision(mut self, revision: Option<u64>) -> Precondition {
        self.revision = revision;
        self
    }

    /// Whether the request gave any precondition.
    pub fn given(&self) -> bool {
        self.if_match.is_some() || self.revision.is_some()
    }
}

fn bad_if_match() -> ApiError {
    ApiError::new(
        Failure::BadBody,
        codes::BAD_HEADER,
        "`If-Match` is not a list of entity tags",
        "send the ETag exactly as GET /v1/world gave it, quotes included (`If-Match: \"…-3\"`), or `*`",
    )
}

/// `*`, or entity tags separated by commas (RFC 9110 §13.1.1). `None` when malformed.
fn parse_if_match(text: &str) -> Option<Vec<Tag>> {
    let text = text.trim();
    if text == "*" {
        return Some(vec![Tag::Any]);
    }
    let mut tags = Vec::new();
    let mut rest = text;
    loop {
        rest = rest.trim_start();
        let weak = rest.starts_with("W/");
        if weak {
            rest = &rest[2..];
        }
        let inner = rest.strip_prefix('"')?;
        let end = inner.find('"')?;
        let opaque = &inner[..end];
        if !opaque
            .bytes()
            .all(|b| b == 0x21 || (0x23..=0x7e).contains(&b))
        {
            return None;
        }
        tags.push(if weak { Tag::Other } else { ours(opaque) });
        rest = inner[end + 1..].trim_start();
        if rest.is_empty() {
            return Some(tags);
        }
        rest = rest.strip_prefix(',')?;
    }
}

/// `INSTANCE-REVISION` as this service writes it, or [`Tag::Other`].
fn ours(opaque: &str) -> Tag {
    match opaque.split_once('-') {
        Some((instance, revision))
            if instance.len() == 32 && instance.bytes().all(|b| b.is_ascii_hexdigit()) =>
        {
            match revision.parse::<u64>() {
                Ok(revision) => Tag::Of {
                    instance: instance.to_string(),
                    revision,
                },
                Err(_) => Tag::Other,
            }
        }
        _ => Tag::Other,
    }
}

/// The state file `input` gets without `--state`.
pub fn default_state(input: &str) -> PathBuf {
    state::default_path(Path::new(input))
}

#[cfg(test)]
mod tests {
    use super::*;

    const ID: &str = "0123456789abcdef0123456789abcdef";

    #[test]
    fn if_match_reads_lists_stars_and_weak_tags() {
        assert_eq!(parse_if_match("*"), Some(vec![Tag::Any]));
        assert_eq!(
            parse_if_match(&format!("\"{ID}-3\", W/\"{ID}-4\" ,\"x\"")),
            Some(vec![
                Tag::Of {
                    instance: ID.into(),
                    revision: 3
                },
                Tag::Other,
                Tag::Other
            ])
        );
        assert_eq!(parse_if_match("3"), None);
        assert_eq!(parse_if_match("\"a\" \"b\""), None);
        assert_eq!(parse_if_match("\"unterminated"), None);
        assert_eq!(parse_if_match("\"a\","), None);
        assert_eq!(
            parse_if_match(&format!("\"{ID}-x\"")),
            Some(vec![Tag::Other])
        );
    }
}
