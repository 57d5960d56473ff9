//! Reading and writing artifact files, with coded diagnostics for files that are not
//! artifacts, are of another format version, or are truncated.

use std::path::{Path, PathBuf};

use cellc_lang::{Code, Diagnostic, SourceMap};
use cellc_schema::files::{Files, MAX_ARTIFACT_BYTES};
use cellc_schema::partial::Partial;
use cellc_schema::sections::{Sections, Source};
use cellc_schema::{Artifact, ReadError, MAGIC};

use crate::render::{self, Color};
use cellc_driver::fs_files::{FsFiles, PieceFile};

/// Codes of artifact reading (the registry's `cellc_lang::codes::artifact`).
pub use cellc_lang::codes::artifact as codes;

/// The coded diagnostic of an artifact that cannot be read.
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

/// Reads an artifact file.
pub fn read(path: &str) -> Result<Artifact, Diagnostic> {
    // Looked at before it is read, like every input: a FIFO or a device never ends.
    let bytes = FsFiles
        .read_at_most(path, MAX_ARTIFACT_BYTES)
        .map_err(|e| cellc_compiler::diagnostics::input_unreadable("artifact", path, &e))?;
    let (mut artifact, _) = Artifact::from_bytes(&bytes).map_err(|e| diagnostic(path, &e))?;
    paths_from_input(&mut artifact, Path::new(path));
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
    paths_from_input(partial.artifact_mut(), Path::new(path));
    Ok(InPart::Sections { sections, partial })
}

/// The artifact of a `.cell` file (compiled now) or of an artifact file. On failure the
/// diagnostics are already printed to standard error.
pub fn cell_or_artifact(path: &str, options: &cellc_compiler::CompileOptions) -> Option<Artifact> {
    cell_or_artifact_reporting(path, Report::Human, options)
}

/// How [`cell_or_artifact_reporting`] reports failures.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Report {
    /// Human text on standard error.
    Human,
    /// The JSON diagnostics report on standard output (for commands whose output is JSON,
    /// so that it stays JSON on every path).
    Json,
}

impl Report {
    /// Writes `diagnostics` where this report goes (plain text, no colour).
    pub fn emit(self, diagnostics: &[Diagnostic], sources: &SourceMap) {
        match self {
            Report::Human => eprint!("{}", render::human(diagnostics, sources, Color::Never)),
            Report::Json => print!("{}", render::json(diagnostics, sources)),
        }
    }
}

/// [`cell_or_artifact`], reporting failures as `report` says.
pub fn cell_or_artifact_reporting(
    path: &str,
    report: Report,
    options: &cellc_compiler::CompileOptions,
) -> Option<Artifact> {
    if path.ends_with(".cell") {
        return compiled_cell(path, report, options).map(|(artifact, _)| artifact);
    }
    match read(path) {
        Ok(artifact) => Some(artifact),
        Err(d) => {
            report.emit(&[d], &SourceMap::new());
            None
        }
    }
}

/// A `.cell` file compiled now, with its compilation (for what only a compilation knows,
/// such as how long `reach auto` took), or `None` after reporting its errors as `report`
/// says (human text ends with a summary line).
pub fn compiled_cell(
    path: &str,
    report: Report,
    options: &cellc_compiler::CompileOptions,
) -> Option<(Artifact, cellc_compiler::Compilation)> {
    let options = cellc_driver::BuildOptions {
        compile: options.clone(),
        ..cellc_driver::BuildOptions::unverified()
    };
    let built = cellc_driver::build(&FsFiles, path, &options);
    let Some(artifact) = built.artifact else {
        let errors: Vec<Diagnostic> = built
            .diagnostics
            .into_iter()
            .filter(Diagnostic::is_error)
            .collect();
        report.emit(&errors, &built.compilation.sources);
        if report == Report::Human {
            eprintln!("{}", render::summary(&errors));
        }
        return None;
    };
    Some((artifact, built.compilation))
}

/// Applies `f` to every file path an artifact holds (sources, URDFs, SRDFs, meshes).
fn map_paths(artifact: &mut Artifact, f: &dyn Fn(&str) -> String) {
    for s in &mut artifact.sources {
        s.path = f(&s.path);
    }
    for r in &mut artifact.robots {
        r.urdf_path = f(&r.urdf_path);
        if let Some(srdf) = &mut r.srdf {
            srdf.path = f(&srdf.path);
        }
        for m in &mut r.meshes {
            m.path = f(&m.path);
        }
    }
    let mesh = |shape: &mut cellc_schema::Shape| {
        if let cellc_schema::Shape::Mesh { path } = shape {
            *path = f(path);
        }
    };
    for k in &mut artifact.holder_kinds {
        for s in &mut k.solids {
            mesh(&mut s.shape);
        }
    }
    for o in &mut artifact.objects {
        if let Some(shape) = &mut o.shape {
            mesh(shape);
        }
    }
}

/// `path` relative to the folder `base` (both as the file system sees them), so an
/// artifact keeps working wherever it and its cell are moved together.
fn relative_to(path: &str, base: &Path) -> String {
    let (Ok(path_abs), Ok(base_abs)) = (std::fs::canonicalize(path), std::fs::canonicalize(base))
    else {
        return path.to_string();
    };
    let p: Vec<_> = path_abs.components().collect();
    let b: Vec<_> = base_abs.components().collect();
    let common = p.iter().zip(&b).take_while(|(x, y)| x == y).count();
    let mut out = PathBuf::new();
    for _ in common..b.len() {
        out.push("..");
    }
    for c in &p[common..] {
        out.push(c);
    }
    out.to_string_lossy().replace('\\', "/")
}

/// Before writing to `output`: paths become relative to the artifact's folder.
pub fn paths_relative_to_output(artifact: &mut Artifact, output: &Path) {
    let folder = output
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    map_paths(artifact, &|p| relative_to(p, folder));
}

/// After reading from `input`: paths resolve against the artifact's folder.
fn paths_from_input(artifact: &mut Artifact, input: &Path) {
    let folder = input
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    map_paths(artifact, &|p| {
        if Path::new(p).is_absolute() {
            p.to_string()
        } else {
            cellc_schema::files::normalize(&folder.join(p).to_string_lossy().replace('\\', "/"))
        }
    });
}
