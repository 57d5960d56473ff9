//! The cellc compiler: from cell source files to a checked cell and its object-state
//! graphs.
//!
//! Pipeline: [`load`] (read and parse the main file and its includes) -> [`resolve`]
//! (names to typed ids, quantities to SI; [`reach`] for `reach ARM auto`, through a
//! [`reach::ReachSolver`]) -> [`workspaces`] (derive workspaces, compute
//! reach) -> [`checks`] -> [`budget`] (the graphs' size, counted) -> [`graph`] (one graph
//! per object) -> [`expect`] (the cell's own
//! requirements). [`compile`] runs it all. The compiler does no I/O: files come through
//! [`Files`] (defined in `cellc_schema`, shared with the runtime).
#![warn(missing_docs)]

pub mod artifact;
pub mod budget;
pub mod checks;
pub mod diagnostics;
pub mod expect;
pub mod graph;
pub mod grasp_file;
pub mod ids;
pub mod joint_limits;
pub mod load;
pub mod math;
pub mod merge;
pub mod model;
pub mod names;
pub mod reach;
pub mod resolve;
mod srdf;
pub mod units;
pub mod urdf;
pub mod workspaces;

use cellc_lang::{Diagnostic, SourceMap};

pub use cellc_schema::files::{Files, MemoryFiles};
pub use graph::ObjectGraph;
pub use model::Cell;

/// Everything a compilation produced.
#[derive(Debug)]
pub struct Compilation {
    /// Every file read (for rendering diagnostics).
    pub sources: SourceMap,
    /// The resolved cell, when the main file could be read and parsed.
    pub cell: Option<Cell>,
    /// One graph per object (empty when the cell has errors that make graphs
    /// meaningless).
    pub graphs: Vec<ObjectGraph>,
    /// Every problem found, in source order.
    pub diagnostics: Vec<Diagnostic>,
    /// Every name written in the files read, as the resolver scoped it, and every
    /// include line (what an editor's definition, references and rename read).
    pub names: names::Names,
}

impl Compilation {
    /// True when any diagnostic is an error.
    pub fn has_errors(&self) -> bool {
        self.diagnostics.iter().any(Diagnostic::is_error)
    }
}

/// What a compilation is told besides its files.
#[derive(Clone, Debug, Default)]
pub struct CompileOptions {
    /// Folders searched for ROS packages (`package://NAME/...`), in order, after the
    /// cell's own `package` items: `--package-path` folders, then `ROS_PACKAGE_PATH`'s.
    pub package_path: Vec<String>,
}

/// Compiles the cell at `path` without kinematics and with no package path besides the
/// cell's `package` items: `reach ARM auto` is an error (E0423) that says to compile with
/// `cellc`, which passes the runtime to [`compile_with`].
pub fn compile(files: &dyn Files, path: &str) -> Compilation {
    compile_with(
        files,
        &reach::NoReachSolver,
        path,
        &CompileOptions::default(),
    )
}

/// Compiles the cell at `path` with `options`, computing `reach ARM auto` with `reach`.
pub fn compile_with(
    files: &dyn Files,
    reach: &dyn reach::ReachSolver,
    path: &str,
    options: &CompileOptions,
) -> Compilation {
    compile_parsed_with(files, reach, &load::Fresh, path, options)
}

/// [`compile_with`], with the files' trees made by `parser` (a language server's cache
/// of unchanged files).
pub fn compile_parsed_with(
    files: &dyn Files,
    reach: &dyn reach::ReachSolver,
    parser: &dyn load::Parser,
    path: &str,
    options: &CompileOptions,
) -> Compilation {
    let loaded = load::load_with(files, parser, path);
    let mut diagnostics = loaded.diagnostics.clone();
    // Items that failed to parse are missing from the trees, so resolving anyway would
    // report every reference to them as unknown: syntax errors are reported alone.
    let main_parsed = loaded.files.first().is_some_and(|f| f.ast.is_some())
        && !diagnostics.iter().any(|d| {
            d.code == cellc_lang::phrases::codes::SYNTAX
                || d.code == cellc_lang::phrases::codes::TOO_DEEP
        });
    let mut cell = None;
    let mut graphs = Vec::new();
    let mut names = names::Names::default();
    let mut extra_sources = Vec::new();
    if main_parsed {
        let resolve::Resolved {
            cell: resolved,
            names: written,
            extra_sources: read,
        } = resolve::resolve(files, reach, &loaded, options, &mut diagnostics);
        names = written;
        extra_sources = read;
        checks::check_cell(&resolved, &mut diagnostics);
        // Graph-level findings on a cell that already has errors would mostly repeat
        // them in other words, so they wait until the cell is clean.
        if !diagnostics.iter().any(Diagnostic::is_error) {
            resolve::missing_limits(&resolved, &mut diagnostics);
            // Counted before built: a cell can ask for billions of arcs.
            let rules = graph::rules_of(&resolved);
            match budget::check(&resolved, &rules) {
                Ok(_) => {
                    graphs = graph::build(&resolved, &rules);
                    checks::check_graphs(&resolved, &graphs, &mut diagnostics);
                    expect::check(&resolved, &graphs, &mut diagnostics);
                }
                Err(too_large) => diagnostics.push(too_large_diagnostic(&resolved, &too_large)),
            }
        }
        cell = Some(resolved);
    } else if loaded.files.iter().any(|f| f.ast.is_some()) {
        // An editor still needs the names of a file being typed (a half-written line is
        // a syntax error): the trees the parser recovered are resolved for their names
        // alone, their findings and cell dropped. The syntax errors go in first, so no
        // `reach auto` is sampled for a cell that is not whole.
        let mut dropped = diagnostics.clone();
        names = resolve::resolve(files, reach, &loaded, options, &mut dropped).names;
    }
    for include in &loaded.includes {
        names.include(include.clone());
    }
    names.finish();
    sort(&mut diagnostics);
    let mut sources = loaded.sources;
    for (path, text) in extra_sources {
        sources.add(path, text);
    }
    Compilation {
        sources,
        cell,
        graphs,
        diagnostics,
        names,
    }
}

/// The diagnostic of graphs refused as too large, at the object whose graph crossed the
/// limit (or the end-effector whose reach alone makes too many adjacent pairs).
fn too_large_diagnostic(cell: &Cell, too_large: &budget::TooLarge) -> Diagnostic {
    let biggest = too_large
        .biggest_reach
        .map(|(e, n)| (cell.end_effectors[e].name.as_str(), n));
    let at = match (too_large.object, too_large.biggest_reach) {
        (Some(o), _) => Some(diagnostics::GraphAt::Object(
            cell.objects[o].name.as_str(),
            cell.objects[o].origin,
        )),
        (None, Some((e, _))) => Some(diagnostics::GraphAt::Reach(
            cell.end_effectors[e].name.as_str(),
            cell.end_effectors[e].origin,
        )),
        (None, None) => None,
    };
    let measure = if too_large.limit == budget::MAX_GRAPH_SIZE {
        diagnostics::GraphMeasure::Size
    } else {
        diagnostics::GraphMeasure::TransitionVisits
    };
    diagnostics::graph_too_large(at, measure, too_large.counted, too_large.limit, biggest)
}

/// Source order: by file, then position, then code; diagnostics without a place last.
fn sort(diagnostics: &mut [Diagnostic]) {
    diagnostics.sort_by_key(|d| {
        let place = d
            .primary_label()
            .map(|l| (l.file, l.span.start, l.span.end));
        (place.is_none(), place, d.code)
    });
}
