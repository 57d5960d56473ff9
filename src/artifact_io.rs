//! Reading and writing artifact files, with coded diagnostics for files that are not
//! artifacts, are of another format version, or are truncated.

use cellc_lang::{Code, Diagnostic, SourceMap};
use cellc_schema::{Artifact, ReadError};

use crate::fs_world::FsWorld;
use crate::render::{self, Color};

/// Codes of artifact reading.
pub mod codes {
    use cellc_lang::Code;
    /// The file is not a cellc artifact.
    pub const NOT_AN_ARTIFACT: Code = Code("E0501");
    /// The artifact is of another format version.
    pub const WRONG_VERSION: Code = Code("E0502");
    /// The artifact is truncated or corrupted.
    pub const CORRUPT: Code = Code("E0503");
    /// Every code of this phase.
    pub const ALL: &[Code] = &[NOT_AN_ARTIFACT, WRONG_VERSION, CORRUPT];
}

fn diagnostic(path: &str, error: &ReadError) -> Diagnostic {
    let (code, help): (Code, String) = match error {
        ReadError::NotAnArtifact => (
            codes::NOT_AN_ARTIFACT,
            "give a file written by `cellc build`, or a `.cell` file to compile".into(),
        ),
        ReadError::WrongVersion { .. } => (
            codes::WRONG_VERSION,
            "rebuild the artifact from its cell with this cellc: `cellc build CELL -o OUT`".into(),
        ),
        ReadError::Corrupt { .. } => (
            codes::CORRUPT,
            "rebuild the artifact with `cellc build`; the file was cut short or changed after it was written".into(),
        ),
        _ => (codes::CORRUPT, "rebuild the artifact with `cellc build`".into()),
    };
    Diagnostic::error(code, format!("`{path}`: {error}")).help(help)
}

/// Reads an artifact file.
pub fn read(path: &str) -> Result<Artifact, Diagnostic> {
    let bytes = std::fs::read(path).map_err(|e| {
        Diagnostic::error(
            cellc_compiler::diagnostics::codes::FILE_UNREADABLE,
            format!("cannot read `{path}`: {e}"),
        )
        .help("check the path and that the file is readable")
    })?;
    Artifact::from_bytes(&bytes)
        .map(|(artifact, _)| artifact)
        .map_err(|e| diagnostic(path, &e))
}

/// The artifact of a `.cell` file (compiled now) or of an artifact file. On failure the
/// diagnostics are already printed to standard error.
pub fn cell_or_artifact(path: &str) -> Option<Artifact> {
    if path.ends_with(".cell") {
        let compilation = cellc_compiler::compile(&FsWorld, path);
        let errors: Vec<Diagnostic> = compilation
            .diagnostics
            .iter()
            .filter(|d| d.is_error())
            .cloned()
            .collect();
        if !errors.is_empty() || compilation.cell.is_none() {
            eprint!(
                "{}",
                render::human(&errors, &compilation.sources, Color::Never)
            );
            eprintln!("{}", render::summary(&errors));
            return None;
        }
        let cell = compilation.cell.as_ref()?;
        return Some(cellc_compiler::artifact::lower(
            cell,
            &compilation.graphs,
            &compilation.sources,
        ));
    }
    match read(path) {
        Ok(artifact) => Some(artifact),
        Err(d) => {
            eprint!("{}", render::human(&[d], &SourceMap::new(), Color::Never));
            None
        }
    }
}
