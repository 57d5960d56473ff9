//! Reading a state file no service has open, without leaving anything beside it.
//!
//! A read-only SQLite connection to a WAL-mode file makes the `-wal` and `-shm` files
//! when they are absent (they are how readers and the writer share the log) and leaves
//! them when it closes, since only a writer may check the log back in and delete them.
//! `cellc plan --state` on a stopped service's file would so leave two files next to it,
//! and fail outright in a folder it may not write. When no `-wal` file exists, no writer
//! has the file open and everything is in the main file, so it is opened *immutable*
//! (no locks, no log, nothing made). Immutable is a promise that the file does not
//! change, so every read checks afterwards that it kept it: still no `-wal`, and the
//! file's size, time and identity as they were at the open. When a writer came since, the
//! store reopens as an ordinary reader (the writer's `-wal` and `-shm` exist by then) and
//! reads again.

use std::path::{Path, PathBuf};
use std::time::SystemTime;

use rusqlite::{Connection, OpenFlags};

use super::sqlite_error;
use crate::StoreError;

/// What the file was when it was opened immutable.
#[derive(Debug, PartialEq, Eq)]
pub(crate) struct Still {
    path: PathBuf,
    seen: Fingerprint,
}

/// A file's size, modification time and identity: what a writer's checkpoint into it,
/// or the file replaced, changes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Fingerprint {
    len: u64,
    modified: Option<SystemTime>,
    identity: (u64, u64),
}

fn fingerprint(path: &Path) -> Option<Fingerprint> {
    let meta = std::fs::metadata(path).ok()?;
    Some(Fingerprint {
        len: meta.len(),
        modified: meta.modified().ok(),
        identity: identity(&meta),
    })
}

#[cfg(unix)]
fn identity(meta: &std::fs::Metadata) -> (u64, u64) {
    use std::os::unix::fs::MetadataExt;
    (meta.dev(), meta.ino())
}

#[cfg(not(unix))]
fn identity(_: &std::fs::Metadata) -> (u64, u64) {
    (0, 0)
}

/// The file's write-ahead log: present while a writer has the file open (or after one
/// stopped without closing it).
fn log_of(path: &Path) -> PathBuf {
    let mut name = path.as_os_str().to_owned();
    name.push("-wal");
    PathBuf::from(name)
}

impl Still {
    /// Whether the file is still as it was opened: no writer's log, the same bytes (as
    /// far as size, time and identity tell).
    pub(crate) fn holds(&self) -> bool {
        !log_of(&self.path).exists() && fingerprint(&self.path) == Some(self.seen)
    }

    /// The path to reopen as an ordinary reader.
    pub(crate) fn path(&self) -> &Path {
        &self.path
    }
}

/// The file opened immutable, when no writer has it open; `None` when one has (or its
/// name cannot be written as a URI here), to be opened as an ordinary reader.
pub(crate) fn open_still(path: &Path) -> Result<Option<(Connection, Still)>, StoreError> {
    if log_of(path).exists() {
        return Ok(None);
    }
    let Some(seen) = fingerprint(path) else {
        return Ok(None);
    };
    let Some(uri) = immutable_uri(path) else {
        return Ok(None);
    };
    let conn = Connection::open_with_flags(
        uri,
        OpenFlags::SQLITE_OPEN_READ_ONLY
            | OpenFlags::SQLITE_OPEN_URI
            | OpenFlags::SQLITE_OPEN_NO_MUTEX,
    )
    .map_err(sqlite_error)?;
    let still = Still {
        path: path.to_path_buf(),
        seen,
    };
    Ok(Some((conn, still)))
}

/// An ordinary read-only connection: it shares the writer's log and locks.
pub(crate) fn open_live(path: &Path) -> Result<Connection, StoreError> {
    Connection::open_with_flags(
        path,
        OpenFlags::SQLITE_OPEN_READ_ONLY | OpenFlags::SQLITE_OPEN_NO_MUTEX,
    )
    .map_err(sqlite_error)
}

/// `file:/absolute/path?immutable=1`, every byte but unreserved ones and `/`
/// percent-encoded (SQLite's URI filenames end the path at `?` and `#`).
#[cfg(unix)]
fn immutable_uri(path: &Path) -> Option<PathBuf> {
    use std::ffi::OsString;
    use std::os::unix::ffi::{OsStrExt, OsStringExt};
    let absolute = std::fs::canonicalize(path).ok()?;
    let mut uri = b"file:".to_vec();
    for &b in absolute.as_os_str().as_bytes() {
        if b.is_ascii_alphanumeric() || b"-._~/".contains(&b) {
            uri.push(b);
        } else {
            uri.extend_from_slice(format!("%{b:02X}").as_bytes());
        }
    }
    uri.extend_from_slice(b"?immutable=1");
    Some(PathBuf::from(OsString::from_vec(uri)))
}

#[cfg(not(unix))]
fn immutable_uri(_: &Path) -> Option<PathBuf> {
    None
}
