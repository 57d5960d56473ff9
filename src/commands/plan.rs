//! `cellc plan INPUT [--request NAME | --object O --from P --to P]`

use cellc_driver::advice::FrontEnd;
use cellc_driver::document;
use cellc_driver::document::report::Report;
use std::process::ExitCode;

use cellc_driver::load::Scope;
use cellc_lang::ast::{PlaceSpec, RequestPlacement as AstPlacement};
use cellc_lang::{Diagnostic, FileId, SourceMap};
use cellc_runtime::plan::{GoalByName, PlacementByName, PlanError, PlanOptions, Request};

use super::job::JobArgs;
use crate::plan_report::{self, codes};
use crate::render::{self, Format, Style};

/// What `cellc plan` and `cellc run` were asked.
#[derive(Clone, Debug)]
pub struct PlanArgs {
    /// The cell or artifact and how to load it (and how diagnostics are reported).
    pub load: LoadArgs,
    /// What to plan: a request, a task or moves, in a world.
    pub job: JobArgs,
    /// Plan joint motions too.
    pub motions: bool,
    /// Arc weights replacing the cell's.
    pub weights: Option<(f64, f64)>,
    /// Planning time limit.
    pub time_budget: Option<std::time::Duration>,
    /// Move objects in the way first.
    pub clear: bool,
    /// How the motions are timed: the scalings of the joints' limits, a control rate.
    pub timing: cellc_runtime::motion::TimingOptions,
    /// What `cellc plan` writes instead of the plans (`--emit`; `cellc run` has none).
    pub emit: Option<crate::args::PlanEmit>,
}

/// What loading a cell or artifact for a command needs, and no more: every command that
/// loads one (`plan`, `run`, `view`, `serve`, `export`) says this, not a plan's flags.
#[derive(Clone, Debug)]
pub struct LoadArgs {
    /// Cell or artifact.
    pub input: String,
    /// What the driver is told: the package path, the seed of verification.
    pub options: cellc_driver::LoadOptions,
    /// How diagnostics are reported.
    pub style: Style,
}

impl LoadArgs {
    /// Loading `input` with these package flags and seed, diagnostics as `style` says.
    pub fn new(
        input: &std::path::Path,
        packages: &crate::args::PackageArgs,
        seed: u64,
        style: Style,
    ) -> LoadArgs {
        LoadArgs {
            input: input.to_string_lossy().into_owned(),
            options: cellc_driver::LoadOptions {
                compile: crate::packages::compile_options(packages),
                seed,
            },
            style,
        }
    }
}

impl PlanArgs {
    /// From the command line's request flags, with the colour the process decided.
    pub fn new(request: &crate::args::RequestArgs, color: render::Color) -> PlanArgs {
        PlanArgs {
            load: LoadArgs::new(
                &request.input,
                &request.packages,
                request.seed,
                Style {
                    format: request.format,
                    color,
                },
            ),
            job: JobArgs {
                request: request.request.clone(),
                object: request.object.clone(),
                from: request.from.clone(),
                to: request.to.clone(),
                task: request.task.clone(),
                moves: request.moves.clone(),
                world: request
                    .world
                    .as_ref()
                    .map(|p| p.to_string_lossy().into_owned()),
                state: request
                    .state
                    .as_ref()
                    .map(|p| p.to_string_lossy().into_owned()),
            },
            motions: !request.no_motions,
            weights: request.weights,
            time_budget: request.time_budget.map(std::time::Duration::from_millis),
            clear: request.clear,
            timing: cellc_runtime::motion::TimingOptions {
                velocity_scaling: request.velocity_scaling,
                acceleration_scaling: request.acceleration_scaling,
                rate: request.rate,
            },
            emit: None,
        }
    }

    /// R0012 for a timing option out of range, by the runtime's own check, before the
    /// cell is read: the runtime would refuse every plan for it.
    pub fn refused_timing(&self) -> Option<Diagnostic> {
        match cellc_runtime::motion::check_timing(&self.timing) {
            Err(cellc_runtime::motion::MotionError::InvalidOption { name, value }) => Some(
                plan_report::option_out_of_range(FrontEnd::CommandLine, name, value),
            ),
            _ => None,
        }
    }

    /// The planning options these flags ask for.
    pub fn options(&self) -> PlanOptions {
        PlanOptions {
            seed: self.load.options.seed,
            motions: self.motions,
            weights: self.weights,
            time_budget: self.time_budget,
            timing: self.timing,
            ..PlanOptions::default()
        }
    }
}

/// A loaded cell ([`cellc_driver::Loaded`]: the cell and its sources) with the way this
/// command reports diagnostics against it.
pub struct Loaded {
    /// The cell, its sources and the file to read more of.
    pub loaded: cellc_driver::Loaded,
    /// How diagnostics are reported: human text on standard error, or (with short or
    /// JSON output) on standard output, so that output stays in its form on every path.
    pub style: Style,
}

impl std::ops::Deref for Loaded {
    type Target = cellc_driver::Loaded;
    fn deref(&self) -> &cellc_driver::Loaded {
        &self.loaded
    }
}

impl std::ops::DerefMut for Loaded {
    fn deref_mut(&mut self) -> &mut cellc_driver::Loaded {
        &mut self.loaded
    }
}

impl Loaded {
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

    /// The JSON report of `diagnostics` (the schema of `cellc check --format json`) as a
    /// value, to embed in a plan's or run's document.
    pub fn json_report(&self, diagnostics: &[Diagnostic]) -> Report {
        self.loaded.report(diagnostics)
    }
}

/// Compiles (and verifies) a cell, or reads an artifact, and loads it into the runtime
/// ([`cellc_driver::load`]), every object's graph; reports a failure as `args` says.
pub fn load(args: &LoadArgs) -> Result<Loaded, ExitCode> {
    load_in(args, Scope::Whole)
}

/// [`load`], reading of a sectioned binary what `scope` says.
pub fn load_in(args: &LoadArgs, scope: Scope<'_>) -> Result<Loaded, ExitCode> {
    match cellc_driver::load(&args.input, &args.options, scope) {
        Ok(loaded) => Ok(Loaded {
            loaded,
            style: args.style,
        }),
        Err(failure) => {
            render::emit(args.style, &failure.diagnostics, &failure.sources);
            Err(ExitCode::from(1))
        }
    }
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
pub fn prepare(
    args: &JobArgs,
    options: &PlanOptions,
    loaded: &Loaded,
) -> Result<Prepared, ExitCode> {
    let artifact = loaded.cell.artifact();
    let options = options.clone();
    match (&args.object, &args.from, &args.to) {
        (Some(object), Some(from), Some(to)) => {
            let parsed = placement_from_text(from, "from")
                .and_then(|f| placement_from_text(to, "to").map(|t| (f, t)));
            let (from, to) = match parsed {
                Ok(placements) => placements,
                Err(failure) => {
                    let (d, sources) = *failure;
                    render::emit(loaded.style, &[d], &sources);
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
    if let Some(d) = args.refused_timing() {
        render::emit(args.load.style, &[d], &SourceMap::new());
        return ExitCode::from(1);
    }
    // The graphs of the objects the job moves or finds in its world.
    let objects = |core: &cellc_schema::Artifact| super::job::objects(&args.job, core);
    let mut loaded = match load_in(&args.load, Scope::Objects(&objects)) {
        Ok(l) => l,
        Err(code) => return code,
    };
    let super::job::Job {
        mut world,
        moves,
        title,
    } = match super::job::job(&args.job, &args.options(), &loaded) {
        Ok(j) => j,
        Err(code) => return code,
    };
    let format = args.load.style.format;
    // `--emit` keeps standard output for its document: the plans are made documents, and
    // nothing else is printed.
    let emit = args.emit.is_some();
    let human = format == Format::Human && !emit;
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
        if let Err(d) = loaded.read_pruned() {
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
                _ if emit => plans.push(document::plan::Plan::of(artifact, &label, plan)),
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
    if emit {
        loaded.report(&diagnostics);
        if !ok {
            return ExitCode::from(1);
        }
        return match document::controller::ControllerGoals::of(&plans) {
            Ok(goals) => {
                println!("{}", goals.to_text());
                ExitCode::SUCCESS
            }
            Err(e) => {
                loaded.report(&[plan_report::goals_refused(&e)]);
                ExitCode::from(1)
            }
        };
    }
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
