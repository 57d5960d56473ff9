//! `cellc plan INPUT [--request NAME | --object O --from P --to P]`

use cellc_driver::document;
use cellc_driver::document::report::Report;
use std::process::ExitCode;
use std::sync::OnceLock;

use cellc_lang::ast::{PlaceSpec, RequestPlacement as AstPlacement};
use cellc_lang::{Diagnostic, FileId, SourceMap};
use cellc_runtime::plan::{GoalByName, PlacementByName, PlanError, PlanOptions, Request};
use cellc_runtime::{Cell, Files, LoadError, ObjectId};
use cellc_schema::partial::{Partial, Parts};
use cellc_schema::sections::Sections;

use crate::artifact_io::{self, InPart};
use crate::plan_report::{self, codes};
use crate::render::{self, Format, Style};
use cellc_driver::fs_files::FsFiles;
use cellc_driver::fs_files::PieceFile;

/// What `cellc plan` was asked.
#[derive(Clone, Debug)]
pub struct PlanArgs {
    /// Cell or artifact.
    pub input: String,
    /// A named request of the cell.
    pub request: Option<String>,
    /// Object, for a request given on the command line.
    pub object: Option<String>,
    /// Start placement text.
    pub from: Option<String>,
    /// Goal placement text.
    pub to: Option<String>,
    /// Output style and colour.
    pub style: Style,
    /// Seed.
    pub seed: u64,
    /// Plan joint motions too.
    pub motions: bool,
    /// Arc weights replacing the cell's.
    pub weights: Option<(f64, f64)>,
    /// Planning time limit.
    pub time_budget: Option<std::time::Duration>,
    /// What a compilation of the cell is told (the package path).
    pub compile: cellc_compiler::CompileOptions,
    /// A task of the cell to carry out instead of a request.
    pub task: Option<String>,
    /// Moves given on the command line (`OBJECT to PLACEMENT`), instead of a request.
    pub moves: Vec<String>,
    /// A world document to start from.
    pub world: Option<String>,
    /// Move objects in the way first.
    pub clear: bool,
}

/// What loading a cell or artifact needs, and no more: the commands that only load one
/// (`serve`, `export`) say this, not a plan's flags.
#[derive(Clone, Debug)]
pub struct LoadArgs {
    /// Cell or artifact.
    pub input: String,
    /// Seed of verification, for a cell compiled now.
    pub seed: u64,
    /// How diagnostics are reported.
    pub style: Style,
    /// What a compilation of the cell is told (the package path).
    pub compile: cellc_compiler::CompileOptions,
}

impl PlanArgs {
    /// What loading the cell of this plan needs.
    pub fn load_args(&self) -> LoadArgs {
        LoadArgs {
            input: self.input.clone(),
            seed: self.seed,
            style: self.style,
            compile: self.compile.clone(),
        }
    }

    /// From the command line's request flags, with the colour the process decided.
    pub fn new(request: &crate::args::RequestArgs, color: render::Color) -> PlanArgs {
        PlanArgs {
            input: request.input.to_string_lossy().to_string(),
            request: request.request.clone(),
            object: request.object.clone(),
            from: request.from.clone(),
            to: request.to.clone(),
            style: Style {
                format: request.format,
                color,
            },
            seed: request.seed,
            motions: !request.no_motions,
            weights: request.weights,
            time_budget: request.time_budget.map(std::time::Duration::from_millis),
            compile: crate::packages::compile_options(&request.packages),
            task: request.task.clone(),
            moves: request.moves.clone(),
            clear: request.clear,
            world: request
                .world
                .as_ref()
                .map(|p| p.to_string_lossy().into_owned()),
        }
    }

    /// The planning options these flags ask for.
    pub fn options(&self) -> PlanOptions {
        PlanOptions {
            seed: self.seed,
            motions: self.motions,
            weights: self.weights,
            time_budget: self.time_budget,
            ..PlanOptions::default()
        }
    }
}

/// A loaded cell with what rendering diagnostics against it needs.
pub struct Loaded {
    /// The cell (verified when it has arms).
    pub cell: Cell,
    /// Source files, for rendering, and those that changed since the artifact was built
    /// (their spans would point at the wrong lines, so labels in them are left out). Of
    /// an artifact they are read when a diagnostic is first shown: a plan that succeeds
    /// never needs them, and a 10^6-arc cell's source is megabytes to read and hash.
    sources: OnceLock<(SourceMap, Vec<FileId>)>,
    /// How diagnostics are reported: human text on standard error, or (with short or
    /// JSON output) on standard output, so that output stays in its form on every path.
    pub style: Style,
    /// A sectioned binary artifact read in part, to read more of it later.
    pub sections: Option<Sections<PieceFile>>,
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
    pub fn read_pruned(&mut self, input: &str) -> Result<(), Diagnostic> {
        let Some(sections) = &self.sections else {
            return Ok(());
        };
        let n = self.cell.artifact().objects.len();
        let read: Vec<ObjectId> = (0..n)
            .map(|i| ObjectId(i as u32))
            .filter(|&o| self.cell.parts(o).graph)
            .collect();
        let parts = Parts::EXPLAIN;
        read.into_iter()
            .try_for_each(|o| self.cell.read_parts(sections, o, parts))
            .map_err(|e| match e {
                LoadError::Artifact(e) => artifact_io::diagnostic(input, &e),
                e => Diagnostic::error(codes::UNREACHABLE, e.to_string()),
            })
    }

    /// Prints diagnostics against the cell's sources; a label in a file that changed
    /// since the build is replaced by a note saying so.
    pub fn report(&self, diagnostics: &[Diagnostic]) {
        // No diagnostic, no label: the sources are not read (hashing them is a few
        // milliseconds of a plan on a large artifact).
        if diagnostics.is_empty() {
            render::emit(self.style, &[], &SourceMap::new());
            return;
        }
        render::emit(self.style, &self.shown(diagnostics), self.sources());
    }

    /// The diagnostics as they are shown: labels in files that changed since the build
    /// replaced by a note.
    pub fn shown(&self, diagnostics: &[Diagnostic]) -> Vec<Diagnostic> {
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

    /// The JSON report of `diagnostics` (the schema of `cellc check --format json`) as a
    /// value, to embed in a plan's or run's document.
    pub fn json_report(&self, diagnostics: &[Diagnostic]) -> Report {
        if diagnostics.is_empty() {
            Report::new(&[], &SourceMap::new())
        } else {
            Report::new(&self.shown(diagnostics), self.sources())
        }
    }
}

/// How much of a sectioned binary artifact [`load_in`] reads.
#[derive(Clone, Copy, Debug)]
pub enum Scope<'a> {
    /// Every object's graph (commands that show or export the whole cell).
    Whole,
    /// The graphs of the objects the job of these arguments moves or finds in its world
    /// ([`super::job::objects`]), and of those their witnesses only when the cell has
    /// arms; pruned arcs and declared transitions are read when a failure is explained
    /// ([`Loaded::read_pruned`]).
    Job(&'a PlanArgs),
}

/// Compiles (and verifies) a cell, or reads an artifact, and loads it into the runtime.
pub fn load(args: &LoadArgs) -> Result<Loaded, ExitCode> {
    load_in(args, Scope::Whole)
}

/// [`load`], reading of a sectioned binary what `scope` says.
pub fn load_in(args: &LoadArgs, scope: Scope<'_>) -> Result<Loaded, ExitCode> {
    let (input, seed, style) = (args.input.as_str(), args.seed, args.style);
    let mut file = None;
    let fail = |d: Diagnostic, sources: &SourceMap| {
        render::emit(style, &[d], sources);
        ExitCode::from(1)
    };
    let (partial, sources) = if input.ends_with(".cell") {
        // Compiled, checked and verified as `cellc build` does; the warnings a build
        // prints are not a plan's.
        let built = cellc_driver::build(
            &FsFiles,
            input,
            &cellc_driver::BuildOptions {
                compile: args.compile.clone(),
                seed,
                ..Default::default()
            },
        );
        let Some(artifact) = built.artifact else {
            render::emit(style, &built.diagnostics, &built.compilation.sources);
            return Err(ExitCode::from(1));
        };
        let partial = Partial::whole(artifact).map_err(|e| {
            fail(
                artifact_io::diagnostic(input, &e),
                &built.compilation.sources,
            )
        })?;
        (
            partial,
            OnceLock::from((built.compilation.sources, Vec::new())),
        )
    } else {
        let mut partial = match artifact_io::read_in_part(input) {
            Ok(InPart::Whole(artifact)) => Partial::whole(artifact)
                .map_err(|e| fail(artifact_io::diagnostic(input, &e), &SourceMap::new()))?,
            Ok(InPart::Sections { sections, partial }) => {
                file = Some(sections);
                partial
            }
            Err(d) => return Err(fail(d, &SourceMap::new())),
        };
        if let Some(sections) = &file {
            let has_arms = partial
                .artifact()
                .end_effectors
                .iter()
                .any(|e| matches!(e.body, cellc_schema::Body::Arm { .. }));
            let (objects, parts) = match scope {
                Scope::Whole => (None, Parts::ALL),
                Scope::Job(job) => (
                    super::job::objects(job, partial.artifact()),
                    // The planner places exchanges at their witnessed poses even without
                    // joint motions, so a cell with arms needs its witnesses.
                    Parts {
                        witnesses: has_arms,
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
                .map_err(|e| {
                    let (sources, _) = sources_of(&partial.artifact().sources);
                    fail(artifact_io::diagnostic(input, &e), &sources)
                })?;
        }
        (partial, OnceLock::new())
    };
    let artifact = partial.artifact();
    // Robot spans, to label a model that cannot be loaded.
    let robots = artifact.robots.clone();
    let spans = artifact.spans.clone();
    let source_files = artifact.sources.clone();
    let sources_now = || &sources.get_or_init(|| sources_of(&source_files)).0;
    let cell = match Cell::from_partial(partial, &FsFiles) {
        Ok(cell) => cell,
        Err(LoadError::Scene(e)) => {
            render::emit(
                style,
                &[cellc_driver::verify_report::scene_error_at(
                    &e, &robots, &spans,
                )],
                sources_now(),
            );
            return Err(ExitCode::from(1));
        }
        Err(LoadError::Artifact(e)) => {
            render::emit(
                style,
                &[crate::artifact_io::diagnostic(input, &e)],
                sources_now(),
            );
            return Err(ExitCode::from(1));
        }
        Err(e) => {
            let d = Diagnostic::error(
                cellc_driver::verify_report::codes::MODEL_UNUSABLE,
                e.to_string(),
            )
            .help("rebuild the artifact with `cellc build` from a cell whose robot files load");
            render::emit(style, &[d], sources_now());
            return Err(ExitCode::from(1));
        }
    };
    Ok(Loaded {
        cell,
        sources,
        style,
        sections: file,
    })
}

/// A placement given on the command line; numbers without units are metres and degrees.
pub fn placement_from_text(
    text: &str,
    what: &str,
) -> Result<PlacementByName, Box<(Diagnostic, SourceMap)>> {
    let mut sources = SourceMap::new();
    let file = sources.add(format!("<{what}>"), text);
    let ast: AstPlacement =
        cellc_lang::parse_placement(file, text).map_err(|d| Box::new((d, sources.clone())))?;
    let (holder, grasp) = match &ast.holder.object {
        Some(h) => (h.text.clone(), Some(ast.holder.name.text.clone())),
        None => (ast.holder.name.text.clone(), None),
    };
    let (workspace, pose) = match &ast.place {
        PlaceSpec::In(w) => (Some(w.text.clone()), None),
        PlaceSpec::At(pose) => {
            let mut diagnostics = Vec::new();
            let mut eval = cellc_compiler::units::Eval {
                file: FileId(0),
                units: cellc_compiler::units::FileUnits {
                    length: Some(cellc_lang::ast::Unit::M),
                    angle: Some(cellc_lang::ast::Unit::Deg),
                },
                diagnostics: &mut diagnostics,
            };
            match eval.pose(pose) {
                Some(p) => (None, Some(p)),
                None => {
                    let d = diagnostics.pop().unwrap_or_else(|| {
                        Diagnostic::error(codes::LOCATE, "this pose cannot be read")
                            .help("write `at (x, y, z) rpy (r, p, y)`")
                    });
                    return Err(Box::new((d, sources)));
                }
            }
        }
    };
    Ok(PlacementByName {
        holder,
        grasp,
        workspace,
        pose,
    })
}

/// A request ready to plan, with its name and (for named requests) its source line.
pub struct Prepared {
    /// The request.
    pub request: Request,
    /// Its name, or "command line".
    pub name: String,
    /// Span index of the `request` line.
    pub span: Option<u32>,
}

/// The request `args` asks for: named, first declared, or from the command line.
pub fn prepare(args: &PlanArgs, loaded: &Loaded) -> Result<Prepared, ExitCode> {
    let artifact = loaded.cell.artifact();
    let options = args.options();
    match (&args.object, &args.from, &args.to) {
        (Some(object), Some(from), Some(to)) => {
            let parsed = placement_from_text(from, "from")
                .and_then(|f| placement_from_text(to, "to").map(|t| (f, t)));
            let (from, to) = match parsed {
                Ok(placements) => placements,
                Err(failure) => {
                    let (d, sources) = *failure;
                    render::emit(args.style, &[d], &sources);
                    return Err(ExitCode::from(2));
                }
            };
            match loaded
                .cell
                .request(object, &from, &GoalByName::Placement(to), options)
            {
                Ok(request) => Ok(Prepared {
                    request,
                    name: "command line".to_string(),
                    span: None,
                }),
                Err(e) => {
                    let d = plan_report::plan_error(artifact, &PlanError::Locate(e), None, None);
                    loaded.report(&[d]);
                    Err(ExitCode::from(1))
                }
            }
        }
        (None, None, None) => {
            let named = match &args.request {
                Some(n) => artifact.requests.iter().find(|r| &r.name == n),
                None => artifact.requests.first(),
            };
            let Some(named) = named else {
                loaded.report(&[plan_report::no_request(artifact, args.request.as_deref())]);
                return Err(ExitCode::from(1));
            };
            Ok(Prepared {
                request: cellc_runtime::plan::named_request(named, options),
                name: named.name.clone(),
                span: Some(named.span),
            })
        }
        // The argument parser requires --object, --from and --to together.
        _ => Err(ExitCode::from(2)),
    }
}

/// Plans each move of the job `args` ask for, in the world, and prints the plans: the
/// world after one move (as its plan leaves it) is where the next is planned.
pub fn run(args: &PlanArgs) -> ExitCode {
    let mut loaded = match load_in(&args.load_args(), Scope::Job(args)) {
        Ok(l) => l,
        Err(code) => return code,
    };
    let super::job::Job {
        mut world,
        moves,
        title,
    } = match super::job::job(args, &loaded) {
        Ok(j) => j,
        Err(code) => return code,
    };
    let format = args.style.format;
    let human = format == Format::Human;
    let single = moves.len() == 1 && title.starts_with("request");
    let options = cellc_runtime::TaskOptions {
        plan: args.options(),
        clear: args.clear,
        ..Default::default()
    };
    let list: Vec<_> = moves.iter().map(|m| (m.object, m.goal.clone())).collect();
    let cellc_runtime::TaskPlans {
        plans: planned,
        world: after,
        failure: stopped,
    } = loaded.cell.plan_task(&world, &list, &options);
    // A failure is explained with the arcs verification pruned and the declared
    // transitions, read only now.
    if stopped.is_some() {
        if let Err(d) = loaded.read_pruned(&args.input) {
            loaded.report(&[d]);
            return ExitCode::from(1);
        }
    }
    let cell = &loaded.cell;
    let artifact = cell.artifact();
    world = after;
    let mut plans = Vec::new();
    let label = |i: usize| {
        if single {
            title
                .trim_start_matches("request `")
                .trim_end_matches('`')
                .to_string()
        } else {
            format!("move {} of {}", i + 1, moves.len())
        }
    };
    let header = |i: usize| {
        if human && !single {
            println!(
                "{title}, move {} of {}: `{}`",
                i + 1,
                moves.len(),
                artifact.object_name(moves[i].object)
            );
        }
    };
    for (i, found) in planned.iter().enumerate() {
        header(i);
        let count = found.len();
        for (k, plan) in found.iter().enumerate() {
            let label = if k + 1 < count {
                if human {
                    println!(
                        "`{}` is in the way: moving it to a free place first",
                        artifact.object_name(plan.object)
                    );
                }
                format!("clearing for {}", artifact.object_name(moves[i].object))
            } else {
                label(i)
            };
            match format {
                Format::Human => print!("{}", plan_report::describe(artifact, &label, plan)),
                Format::Short => print!("{}", plan_report::short(artifact, &label, plan)),
                Format::Json => plans.push(document::plan::Plan::of(artifact, &label, plan)),
            }
        }
    }
    let failure = stopped.map(|f| {
        header(f.index);
        let cellc_runtime::TaskError::Plan(error) = &f.error else {
            return Diagnostic::error(codes::UNREACHABLE, "no plan").help("check the request");
        };
        let d =
            plan_report::plan_error(artifact, error, moves[f.index].span, Some(loaded.sources()));
        if single {
            d
        } else {
            d.note(format!(
                "move {} of {} of the {title} has no plan; the moves before it were planned",
                f.index + 1,
                moves.len()
            ))
        }
    });
    let ok = failure.is_none();
    let diagnostics: Vec<Diagnostic> = failure.into_iter().collect();
    if format != Format::Json {
        loaded.report(&diagnostics);
    } else {
        let document = document::run::Run::new(
            document::run::Kind::Plan,
            ok,
            plans,
            Vec::new(),
            Some(document::world::World::of(cell, &world)),
            loaded.json_report(&diagnostics),
        );
        println!("{}", document.to_text());
    }
    if ok {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    }
}
