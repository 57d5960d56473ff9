//! The way in for a cell *or* an artifact: [`load`] gives a runtime [`Cell`] ready to
//! plan, with the diagnostics `cellc plan` shows when it cannot, whichever the input is.
//!
//! - A `.cell` file is compiled, checked and verified as `cellc build` does ([`build`]'s
//!   steps, with the runtime's kinematics for `reach auto`); the scene loaded to verify
//!   it is the one the cell plans with, so it is loaded once.
//! - An artifact file (JSON or binary, [`artifact`]) is read and validated; of a
//!   sectioned binary only the core and the sections of the objects [`Scope`] names, so
//!   a use reads in proportion to what it needs ([`Loaded::read_pruned`] reads more when
//!   a failure is explained).
//!
//! The cell's sources come with it, for rendering diagnostics: those of a cell compiled
//! now, or those an artifact records, read again when a diagnostic is first shown (a plan
//! that succeeds never needs them) and left out where they changed since the build
//! ([`Loaded::shown`]).
//!
//! [`build`]: crate::build()

pub mod artifact;
pub mod paths;

use std::sync::OnceLock;

use cellc_compiler::CompileOptions;
use cellc_lang::{Diagnostic, FileId, SourceMap};
use cellc_runtime::verify::VerifyOptions;
use cellc_runtime::{Cell, Files, LoadError};
use cellc_schema::partial::{Partial, Parts};
use cellc_schema::sections::Sections;
use cellc_schema::{Artifact, ObjectId, Robot, SourceSpan};

use crate::fs_files::{FsFiles, PieceFile};
use artifact::InPart;

/// What loading a cell or an artifact needs.
#[derive(Clone, Debug, Default)]
pub struct LoadOptions {
    /// What a compilation of a cell is told (the package path).
    pub compile: CompileOptions,
    /// Seed of the randomized solvers of verification, for a cell compiled now.
    pub seed: u64,
}

/// How much of a sectioned binary artifact [`load`] reads (a cell compiled now, or any
/// other artifact, is whole).
#[derive(Clone, Copy)]
pub enum Scope<'a> {
    /// Every object's graph (uses that show or export the whole cell).
    Whole,
    /// The graphs of the objects this function picks from the artifact's core (`None`:
    /// every object), with their witnesses when the cell has arms (the planner places
    /// exchanges at their witnessed poses even without joint motions). Pruned arcs and
    /// declared transitions are read when a failure is explained
    /// ([`Loaded::read_pruned`]).
    Objects(&'a dyn Fn(&Artifact) -> Option<Vec<ObjectId>>),
}

/// A cell that could not be loaded: the diagnostics (errors, and a compilation's
/// warnings) and the sources they are rendered against.
pub struct Failure {
    /// What is wrong.
    pub diagnostics: Vec<Diagnostic>,
    /// The sources the diagnostics' labels point into.
    pub sources: SourceMap,
}

impl Failure {
    fn of(diagnostic: Diagnostic, sources: SourceMap) -> Failure {
        Failure {
            diagnostics: vec![diagnostic],
            sources,
        }
    }
}

/// A loaded cell with what rendering diagnostics against it needs.
pub struct Loaded {
    /// The cell (verified when it has arms).
    pub cell: Cell,
    /// A sectioned binary artifact read in part, to read more of it later.
    pub sections: Option<Sections<PieceFile>>,
    /// The path the cell was loaded from, for diagnostics of reading more of it.
    path: String,
    /// Source files, for rendering, and those that changed since the artifact was built
    /// (their spans would point at the wrong lines, so labels in them are left out). Of
    /// an artifact they are read when a diagnostic is first shown: a plan that succeeds
    /// never needs them, and a 10^6-arc cell's source is megabytes to read and hash.
    sources: OnceLock<(SourceMap, Vec<FileId>)>,
}

/// The cell's sources as `files` records them, read again if still there and unchanged
/// (the artifact records each one's hash), with the ids of those that changed.
fn sources_of(files: &[cellc_schema::SourceFile]) -> (SourceMap, Vec<FileId>) {
    let mut sources = SourceMap::new();
    let mut stale = Vec::new();
    for s in files {
        let text = FsFiles.read_text(&s.path).unwrap_or_default();
        let same = cellc_schema::sha256_hex(text.as_bytes()) == s.sha256;
        let id = sources.add(s.path.clone(), if same { text } else { String::new() });
        if !same {
            stale.push(id);
        }
    }
    (sources, stale)
}

impl Loaded {
    /// The cell's source files, for rendering.
    pub fn sources(&self) -> &SourceMap {
        &self.read_sources().0
    }

    /// The sources that changed since the artifact was built.
    pub fn stale(&self) -> &[FileId] {
        &self.read_sources().1
    }

    fn read_sources(&self) -> &(SourceMap, Vec<FileId>) {
        self.sources
            .get_or_init(|| sources_of(&self.cell.artifact().sources))
    }

    /// Reads the pruned arcs and declared transitions of every object whose graph is
    /// read, for an explanation (nothing when the cell was read whole).
    ///
    /// # Errors
    /// The diagnostic of a damaged or inconsistent section.
    pub fn read_pruned(&mut self) -> Result<(), Diagnostic> {
        let Some(sections) = &self.sections else {
            return Ok(());
        };
        let n = self.cell.artifact().objects.len();
        let read: Vec<ObjectId> = (0..n)
            .map(|i| ObjectId(i as u32))
            .filter(|&o| self.cell.parts(o).graph)
            .collect();
        read.into_iter()
            .try_for_each(|o| self.cell.read_parts(sections, o, Parts::EXPLAIN))
            .map_err(|e| match e {
                LoadError::Artifact(e) => artifact::diagnostic(&self.path, &e),
                e => Diagnostic::error(crate::runtime_codes::UNREACHABLE, e.to_string()),
            })
    }

    /// The diagnostics as they are shown: labels in files that changed since the build
    /// replaced by a note saying so. No diagnostic, no label: the sources are then not
    /// read (hashing them is a few milliseconds of a plan on a large artifact).
    pub fn shown(&self, diagnostics: &[Diagnostic]) -> Vec<Diagnostic> {
        if diagnostics.is_empty() {
            return Vec::new();
        }
        diagnostics
            .iter()
            .map(|d| {
                let mut d = d.clone();
                let before = d.labels.len();
                d.labels.retain(|l| !self.stale().contains(&l.file));
                if d.labels.len() < before {
                    let paths: Vec<String> = self
                        .stale()
                        .iter()
                        .map(|f| format!("`{}`", self.sources().get(*f).path))
                        .collect();
                    d.notes.push(format!(
                        "{} changed since the artifact was built, so its lines are not shown; rebuild the artifact",
                        paths.join(", ")
                    ));
                }
                d
            })
            .collect()
    }

    /// The error document (the diagnostics report of `cellc check --format json`) of
    /// `diagnostics` as they are shown.
    pub fn report(&self, diagnostics: &[Diagnostic]) -> crate::document::report::Report {
        if diagnostics.is_empty() {
            crate::document::report::Report::new(&[], &SourceMap::new())
        } else {
            crate::document::report::Report::new(&self.shown(diagnostics), self.sources())
        }
    }
}

/// Loads the cell (`.cell`: compiled, checked and verified now) or the artifact at
/// `path` into the runtime, reading files from the file system through the hardened
/// reader; of a sectioned binary, what `scope` says.
///
/// # Errors
/// What is wrong, as `cellc plan` reports it: the build's diagnostics of a cell that
/// does not build, E0317/E0318/E0501–E0504 of a file that is not a readable artifact,
/// the scene's error of robot models that cannot be loaded.
pub fn load(path: &str, options: &LoadOptions, scope: Scope<'_>) -> Result<Loaded, Failure> {
    if path.ends_with(".cell") {
        let (cell, sources) = compiled(&FsFiles, path, options)?;
        return Ok(Loaded {
            cell,
            sections: None,
            path: path.to_string(),
            sources: OnceLock::from((sources, Vec::new())),
        });
    }
    let (partial, sections) = match artifact::read_in_part(path) {
        Ok(InPart::Whole(artifact)) => (
            Partial::whole(artifact)
                .map_err(|e| Failure::of(artifact::diagnostic(path, &e), SourceMap::new()))?,
            None,
        ),
        Ok(InPart::Sections {
            sections,
            mut partial,
        }) => {
            read_scope(&sections, &mut partial, scope).map_err(|e| {
                let (sources, _) = sources_of(&partial.artifact().sources);
                Failure::of(artifact::diagnostic(path, &e), sources)
            })?;
            (partial, Some(sections))
        }
        Err(d) => return Err(Failure::of(d, SourceMap::new())),
    };
    let artifact = partial.artifact();
    // Robot spans, to label a model that cannot be loaded.
    let (robots, spans) = (artifact.robots.clone(), artifact.spans.clone());
    let source_files = artifact.sources.clone();
    let cell = Cell::from_partial(partial, &FsFiles).map_err(|e| {
        let (sources, _) = sources_of(&source_files);
        Failure::of(load_error(path, &e, &robots, &spans), sources)
    })?;
    Ok(Loaded {
        cell,
        sections,
        path: path.to_string(),
        sources: OnceLock::new(),
    })
}

/// Reads of a sectioned binary the objects' graphs `scope` names.
fn read_scope(
    sections: &Sections<PieceFile>,
    partial: &mut Partial,
    scope: Scope<'_>,
) -> Result<(), cellc_schema::ReadError> {
    let (objects, parts) = match scope {
        Scope::Whole => (None, Parts::ALL),
        Scope::Objects(pick) => (
            pick(partial.artifact()),
            Parts {
                witnesses: crate::has_arms(partial.artifact()),
                ..Parts::GRAPH
            },
        ),
    };
    let objects = objects.unwrap_or_else(|| {
        (0..partial.artifact().objects.len())
            .map(|i| ObjectId(i as u32))
            .collect()
    });
    objects
        .iter()
        .try_for_each(|&o| partial.read(sections, o, parts))
}

/// The diagnostic of an artifact the runtime cannot load.
fn load_error(path: &str, e: &LoadError, robots: &[Robot], spans: &[SourceSpan]) -> Diagnostic {
    match e {
        LoadError::Scene(e) => crate::verify_report::scene_error_at(e, robots, spans),
        LoadError::Artifact(e) => artifact::diagnostic(path, e),
        e => Diagnostic::error(crate::verify_report::codes::MODEL_UNUSABLE, e.to_string())
            .help("rebuild the artifact with `cellc build` from a cell whose robot files load"),
    }
}

/// A cell compiled, checked and verified now, as [`build`](crate::build()) does, its
/// scene loaded once: the cell is made of the artifact as lowered, then verified in
/// place ([`Cell::verify`] runs the build's `check_and_verify`), so the scene that checks
/// the arcs is the one the cell plans with. The warnings a build prints are not a
/// plan's: on success only the cell and its sources are given.
fn compiled(
    files: &dyn Files,
    path: &str,
    options: &LoadOptions,
) -> Result<(Cell, SourceMap), Failure> {
    let compilation = crate::reach::compile(files, path, &options.compile);
    let mut diagnostics = compilation.diagnostics.clone();
    let fail = |diagnostics, compilation: cellc_compiler::Compilation| Failure {
        diagnostics,
        sources: compilation.sources,
    };
    let Some(artifact) = crate::build::lowered(&compilation) else {
        return Err(fail(diagnostics, compilation));
    };
    let (robots, spans) = (artifact.robots.clone(), artifact.spans.clone());
    let mut cell = match Cell::from_artifact(artifact, files) {
        Ok(cell) => cell,
        Err(e) => {
            diagnostics.push(load_error(path, &e, &robots, &spans));
            return Err(fail(diagnostics, compilation));
        }
    };
    let verify = VerifyOptions {
        seed: options.seed,
        ..VerifyOptions::default()
    };
    if let Some(checked) = cell.verify(&verify) {
        diagnostics.extend(crate::build::checked_diagnostics(
            cell.artifact(),
            &checked,
            &compilation.sources,
        ));
    }
    if diagnostics.iter().any(Diagnostic::is_error) {
        return Err(fail(diagnostics, compilation));
    }
    Ok((cell, compilation.sources))
}
