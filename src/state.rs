//! The state file in words: where it lives by default, a stored world read back into the
//! cell, and every [`StoreError`] as a coded diagnostic. `cellc serve` keeps its world
//! there; `cellc plan`/`run --state` start from it. The store's facts live in
//! `cellc-store`; this module only says them.

use std::path::{Path, PathBuf};

use cellc_lang::Diagnostic;
use cellc_runtime::plan::PlanOptions;
use cellc_runtime::{Cell, World};
use cellc_store::{StoreError, StoredWorld, Subjects, Uncertainty};

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

/// Where a store error happened, which decides its code: an unusable file at start-up
/// (S0011) or a write that could not be stored (S0010).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum When {
    /// Opening the file.
    Opening,
    /// Writing (or reading) while serving.
    Serving,
}

/// A store error as a diagnostic naming the file at `path`. Only the store's own words
/// and SQLite's are quoted, never the file's content.
pub fn diagnostic(e: &StoreError, path: &str, when: When) -> Diagnostic {
    let shown = crate::render::escape(path).into_owned();
    let write = |message: String, help: &str| {
        let code = match when {
            When::Opening => codes::STATE_OPEN,
            When::Serving => codes::STATE_WRITE,
        };
        Diagnostic::error(code, message).help(help.to_string())
    };
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
    uncertain_of(&stored.uncertain, confirm)
}

/// [`uncertain`] of the interruptions themselves.
pub fn uncertain_of(interrupted: &[Uncertainty], confirm: &str) -> Diagnostic {
    let mut subjects = Subjects::default();
    for u in interrupted {
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
    d.help(confirm.to_string())
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
