//! Reading artifact files (JSON or binary), with the coded diagnostics of files that are
//! not artifacts, are of another format version, or are damaged (E0501–E0504).

use std::path::Path;

use cellc_lang::{Code, Diagnostic};
use cellc_schema::files::{Files, MAX_ARTIFACT_BYTES};
use cellc_schema::partial::Partial;
use cellc_schema::sections::{Sections, Source};
use cellc_schema::{Artifact, ReadError, MAGIC};

use crate::fs_files::{FsFiles, PieceFile};

/// Codes of artifact reading (the registry's `cellc_lang::codes::artifact`).
pub use cellc_lang::codes::artifact as codes;

/// The coded diagnostic of the artifact at `path` that cannot be read.
pub fn diagnostic(path: &str, error: &ReadError) -> Diagnostic {
    let (code, help): (Code, String) = match error {
        ReadError::NotAnArtifact => (
            codes::NOT_AN_ARTIFACT,
            "give a file written by `cellc build`, or a `.cell` file to compile".into(),
        ),
        ReadError::WrongVersion { .. } => (
            codes::WRONG_VERSION,
            "rebuild the artifact from its cell with this cellc: `cellc build CELL -o OUT`".into(),
        ),
        ReadError::Corrupt { .. } | ReadError::Damaged => (
            codes::CORRUPT,
            "rebuild the artifact with `cellc build`; the file was cut short or changed after it was written".into(),
        ),
        ReadError::Invalid(_) => (
            codes::INVALID,
            "rebuild the artifact with `cellc build`; a file that matches its checksum but not the format was not written by cellc as it is".into(),
        ),
        _ => (codes::CORRUPT, "rebuild the artifact with `cellc build`".into()),
    };
    Diagnostic::error(code, format!("`{path}`: {error}")).help(help)
}

/// Reads the artifact file at `path` whole, its paths resolved against the file's folder.
///
/// # Errors
/// The diagnostic of a file that cannot be read (E0317, E0318) or is not a readable
/// artifact (E0501–E0504).
pub fn read(path: &str) -> Result<Artifact, Diagnostic> {
    // Looked at before it is read, like every input: a FIFO or a device never ends.
    let bytes = FsFiles
        .read_at_most(path, MAX_ARTIFACT_BYTES)
        .map_err(|e| cellc_compiler::diagnostics::input_unreadable("artifact", path, &e))?;
    let (mut artifact, _) = Artifact::from_bytes(&bytes).map_err(|e| diagnostic(path, &e))?;
    super::paths::from_input(&mut artifact, Path::new(path));
    Ok(artifact)
}

/// An artifact file as [`read_in_part`] gives it.
pub enum InPart {
    /// A sectioned binary: its table (to read the sections of the objects needed from)
    /// and its core, validated, with paths resolved against the file's folder; no graph
    /// read yet.
    Sections {
        /// The file, its table checked.
        sections: Sections<PieceFile>,
        /// The core.
        partial: Partial,
    },
    /// Any other artifact, read and validated whole.
    Whole(Artifact),
}

/// Reads an artifact file; of a sectioned binary only its header, table and core, so
/// that a use reads the sections of the objects it needs ([`Partial::read`]) and nothing
/// else.
///
/// # Errors
/// As [`read`].
pub fn read_in_part(path: &str) -> Result<InPart, Diagnostic> {
    let unreadable = |e| cellc_compiler::diagnostics::input_unreadable("artifact", path, &e);
    let file = PieceFile::open(path, MAX_ARTIFACT_BYTES).map_err(unreadable)?;
    let magic = MAGIC.len().min(file.file_length() as usize);
    let binary = file.bytes(0, magic, &mut Vec::new()) == Ok(MAGIC.as_slice());
    if !binary {
        drop(file);
        return read(path).map(InPart::Whole);
    }
    let sections = Sections::from_source(file).map_err(|e| diagnostic(path, &e))?;
    let mut partial = Partial::open(&sections).map_err(|e| diagnostic(path, &e))?;
    super::paths::from_input(partial.artifact_mut(), Path::new(path));
    Ok(InPart::Sections { sections, partial })
}
