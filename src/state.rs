//! The state file in words: where it lives by default, a stored world read back into the
//! cell, and every [`StoreError`] as a coded diagnostic. `cellc serve` keeps its world
//! there; `cellc plan`/`run --state` start from it. The store's facts live in
//! `cellc-store`; this module only says them, and reads a state file for the command
//! line ([`read`]).

use std::path::{Path, PathBuf};

use cellc_lang::Diagnostic;
use cellc_runtime::plan::PlanOptions;
use cellc_runtime::{Cell, World};
use cellc_store::{SqliteStore, Store, StoreError, StoredWorld, Subjects, Uncertainty};

pub use cellc_lang::codes::serve as codes;

/// The state file `cellc serve INPUT` uses when `--state` gives none: next to the input,
/// named after it (`cells/vito.cell` keeps `cells/vito.state.sqlite`). SQLite adds
/// `-wal` and `-shm` beside it while it is open.
pub fn default_path(input: &Path) -> PathBuf {
    let stem = input
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "cell".to_string());
    input.with_file_name(format!("{stem}.state.sqlite"))
}

/// Where a store error happened, which decides its code (an unusable file at start-up or
/// read by the command line, S0011; a write that could not be stored, S0010) and what
/// its help says to do.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum When {
    /// Opening the file.
    Opening,
    /// Writing (or reading) while serving.
    Serving,
    /// Reading the world, read-only, for `cellc plan`/`run`/`view --state` (the file is
    /// never created nor written, so the helps name no writable path).
    Reading,
}

/// A store error as a diagnostic naming the file at `path`. Only the store's own words
/// and SQLite's are quoted, never the file's content.
pub fn diagnostic(e: &StoreError, path: &str, when: When) -> Diagnostic {
    let shown = crate::render::escape(path).into_owned();
    let write = |message: String, help: &str| {
        let code = match when {
            When::Opening | When::Reading => codes::STATE_OPEN,
            When::Serving => codes::STATE_WRITE,
        };
        Diagnostic::error(code, message).help(help.to_string())
    };
    if when == When::Reading {
        if let Some(d) = reading(e, &shown) {
            return d;
        }
    }
    match e {
        StoreError::Full => write(
            format!("the disk holding `{shown}` is full: nothing of this write was stored"),
            "free space on that disk; the world is as its last acknowledged write left it",
        ),
        StoreError::ReadOnly => write(
            format!("`{shown}` cannot be written (a read-only file, folder or disk)"),
            "give a writable path with `--state PATH`, or make this one writable",
        ),
        StoreError::Io { reason } => write(
            format!(
                "`{shown}` cannot be used: {}",
                crate::render::escape(reason)
            ),
            "give a state file this process can read and write with `--state PATH`",
        ),
        StoreError::Corrupt { reason } => write(
            format!("`{shown}` is damaged: {}", crate::render::escape(reason)),
            "restore it from a backup, or move it away to start from the cell's initial world",
        ),
        StoreError::InUse => Diagnostic::error(
            codes::STATE_OPEN,
            format!("another process has `{shown}` open for writing"),
        )
        .help("stop the other `cellc serve` of this cell, or give this one its own `--state PATH`"),
        StoreError::Foreign { reason } => Diagnostic::error(
            codes::STATE_OPEN,
            format!(
                "`{shown}` is not a cellc state file: {}",
                crate::render::escape(reason)
            ),
        )
        .help("give the path of a cellc state file, or a new path, with `--state PATH`"),
        StoreError::TooNew { .. } => {
            Diagnostic::error(codes::STATE_OPEN, format!("`{shown}`: {e}"))
                .help("open it with the cellc that wrote it, or a newer one")
        }
        other => write(
            format!("`{shown}`: {other}"),
            "report this with the state file; the world is as its last acknowledged write left it",
        ),
    }
}

/// What is said differently when the command line reads a state file: it never creates
/// nor writes one, so its helps point at the service that keeps the file, or at leaving
/// `--state` out. `None`: as when opening.
fn reading(e: &StoreError, shown: &str) -> Option<Diagnostic> {
    let error = |message: String, help: &str| {
        Some(Diagnostic::error(codes::STATE_OPEN, message).help(help.to_string()))
    };
    match e {
        StoreError::Io { reason } => error(
            format!("`{shown}` cannot be read: {}", crate::render::escape(reason)),
            "give the path of the state file `cellc serve` keeps for this cell (`--state PATH`), or leave `--state` out to start from the cell's world",
        ),
        StoreError::Foreign { reason } => error(
            format!(
                "`{shown}` is not a cellc state file: {}",
                crate::render::escape(reason)
            ),
            "give the path of the state file `cellc serve` keeps for this cell (by default `CELL.state.sqlite` next to the cell), or a world document with `--world FILE`",
        ),
        StoreError::Corrupt { reason } => error(
            format!("`{shown}` is damaged: {}", crate::render::escape(reason)),
            "restore it from a backup; meanwhile leave `--state` out to start from the cell's world, or give a world document with `--world FILE`",
        ),
        StoreError::InUse => error(
            format!("`{shown}` stayed locked by its writer for longer than a reader waits"),
            "try again: `cellc serve` holds its lock only for the length of one write",
        ),
        StoreError::ReadOnly => error(
            format!("`{shown}` cannot be read here: permission denied (to it, or to the files SQLite keeps beside it while `cellc serve` has it open)"),
            "read it as a user who may read the file and its folder, or leave `--state` out to start from the cell's world",
        ),
        StoreError::NoWorld => error(
            format!("`{shown}` holds no world yet"),
            "`cellc serve` stores the cell's world in it when it starts with this file; until then leave `--state` out to start from the cell's world",
        ),
        _ => None,
    }
}

/// The world the state file at `path` holds, for the command line (`--state PATH`):
/// opened read-only (never created nor written, and without the writer's lock, so a
/// running `cellc serve` keeps the file and this reads beside it), refused (S0011) when
/// it is absent, not a state file, newer, damaged or holds no world yet, and (S0007,
/// with `confirm` in its help) when that world is uncertain or an execution is running
/// in it (the service may be moving what it reads).
pub fn read(path: &str, confirm: &str) -> Result<StoredWorld, Diagnostic> {
    let refused = |e: StoreError| diagnostic(&e, path, When::Reading);
    let mut store = SqliteStore::open_read_only(Path::new(path)).map_err(refused)?;
    // An execution running before or after the world is read may be moving what it
    // holds (or its service stopped during it and has not found it interrupted yet).
    let mut running = store.in_flight().map_err(refused)?;
    let stored = store
        .world()
        .map_err(refused)?
        .ok_or(StoreError::NoWorld)
        .map_err(refused)?;
    for u in store.in_flight().map_err(refused)? {
        if !running.iter().any(|r| r.execution == u.execution) {
            running.push(u);
        }
    }
    if !stored.uncertain.is_empty() || !running.is_empty() {
        return Err(refusal(&stored.uncertain, &running, confirm));
    }
    Ok(stored)
}

/// The stored world as the cell's [`World`], or S0011 when it does not fit the cell
/// (the cell changed since the world was stored).
pub fn world_of(cell: &Cell, stored: &StoredWorld, path: &str) -> Result<World, Diagnostic> {
    cell.world(&stored.document, &PlanOptions::default())
        .map_err(|e| {
            let shown = crate::render::escape(path).into_owned();
            let d = crate::world_report::world_diagnostic(&e, &format!("the world stored in `{shown}`"));
            Diagnostic::error(
                codes::STATE_OPEN,
                format!(
                    "the world stored in `{shown}` (revision {}) does not fit this cell",
                    stored.revision
                ),
            )
            .note(d.message.clone())
            .help("the cell changed since the world was stored: move the state file away to start from the cell's initial world, or give another with `--state PATH`")
        })
}

/// S0007: the world has objects or arms an interrupted execution left unknown. `confirm`
/// says how to confirm them where this is said (the service's PUT/PATCH, or a world file).
pub fn uncertain(stored: &StoredWorld, confirm: &str) -> Diagnostic {
    refusal(&stored.uncertain, &[], confirm)
}

/// [`uncertain`] of the interruptions themselves (the service's own, in memory).
pub fn uncertain_of(interrupted: &[Uncertainty], confirm: &str) -> Diagnostic {
    refusal(interrupted, &[], confirm)
}

/// S0007 for what interruptions left unknown and what `running` executions are moving,
/// for a reader beside the service: they must end (or be found interrupted and confirmed)
/// before their objects and arms are planned with.
fn refusal(interrupted: &[Uncertainty], running: &[Uncertainty], confirm: &str) -> Diagnostic {
    let mut subjects = Subjects::default();
    for u in interrupted.iter().chain(running) {
        subjects.objects.extend(u.subjects.objects.iter().cloned());
        subjects.arms.extend(u.subjects.arms.iter().cloned());
    }
    let mut d = Diagnostic::error(
        codes::WORLD_UNCERTAIN,
        format!(
            "the world is uncertain for {}: planning from it is refused",
            names(&subjects)
        ),
    );
    for u in interrupted {
        d = d.note(format!(
            "execution {} was interrupted after step {}; it was moving {}",
            u.execution,
            u.steps_done,
            names(&u.subjects)
        ));
    }
    for u in running {
        d = d.note(format!(
            "execution {} is running, {} of its steps recorded; it is moving {} (a service \
             that stopped during it finds it interrupted when it starts again)",
            u.execution,
            u.steps_done,
            names(&u.subjects)
        ));
    }
    let help = match running {
        [] => confirm.to_string(),
        [u] => format!(
            "wait for execution {} to end (`GET /v1/executions/{}`) and plan again; \
             when it was interrupted, {confirm}",
            u.execution, u.execution
        ),
        _ => format!(
            "wait for those executions to end and plan again; when they were interrupted, \
             {confirm}"
        ),
    };
    d.help(help)
}

/// `object `ball`, arm `left`` and the like.
pub fn names(subjects: &Subjects) -> String {
    let mut parts: Vec<String> = Vec::new();
    for o in &subjects.objects {
        parts.push(format!("object `{}`", crate::render::escape(o)));
    }
    for a in &subjects.arms {
        parts.push(format!("arm `{}`", crate::render::escape(a)));
    }
    match parts.len() {
        0 => "nothing".to_string(),
        1 => parts.remove(0),
        _ => {
            let last = parts.pop().unwrap_or_default();
            format!("{} and {last}", parts.join(", "))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_default_state_file_sits_next_to_the_input() {
        assert_eq!(
            default_path(Path::new("cells/vito.cell")),
            PathBuf::from("cells/vito.state.sqlite")
        );
        assert_eq!(
            default_path(Path::new("out/vito.bin")),
            PathBuf::from("out/vito.state.sqlite")
        );
    }

    #[test]
    fn names_are_listed_in_words() {
        let mut s = Subjects::default();
        assert_eq!(names(&s), "nothing");
        s.objects.insert("ball".into());
        assert_eq!(names(&s), "object `ball`");
        s.arms.insert("left".into());
        s.objects.insert("box".into());
        assert_eq!(names(&s), "object `ball`, object `box` and arm `left`");
    }
}
