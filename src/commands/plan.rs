//! `cellc plan CELL_OR_ARTIFACT [--request NAME | --object O --from P --to P]`

use std::fmt::Write as _;
use std::io::IsTerminal;
use std::process::ExitCode;

use cellc_lang::ast::{PlaceSpec, RequestPlacement as AstPlacement};
use cellc_lang::{Diagnostic, FileId, SourceMap};
use cellc_runtime::math::{iso_from_schema, Iso};
use cellc_runtime::plan::planner::Planner;
use cellc_runtime::plan::{Command, Goal, Placement, Plan, PlanError, PlanOptions, Request};
use cellc_runtime::scene::Scene;
use cellc_schema::{Artifact, Body};
use serde::Serialize;

use crate::fs_files::FsFiles;
use crate::render::{self, Color};

/// Codes of planning requests.
pub mod codes {
    use cellc_lang::Code;
    /// The request names something the cell does not have, or a pose matches no state.
    pub const LOCATE: Code = Code("R0003");
    /// No plan reaches the goal.
    pub const UNREACHABLE: Code = Code("R0004");
    /// No request to plan: the cell declares none, or none of that name.
    pub const NO_REQUEST: Code = Code("R0005");
    /// The request's time budget ran out.
    pub const TIME_BUDGET: Code = Code("R0006");
    /// Every code of this phase.
    pub const ALL: &[Code] = &[LOCATE, UNREACHABLE, NO_REQUEST, TIME_BUDGET];
}

/// Output style of `cellc plan`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum PlanFormat {
    /// Numbered steps.
    Human,
    /// A JSON document.
    Json,
}

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
    /// Output.
    pub format: PlanFormat,
    /// Seed.
    pub seed: u64,
    /// Plan joint motions too.
    pub motions: bool,
    /// Arc weights replacing the cell's.
    pub weights: Option<(f64, f64)>,
    /// Planning time limit.
    pub time_budget: Option<std::time::Duration>,
}

impl PlanArgs {
    /// From the command line's request flags.
    pub fn new(request: &crate::args::RequestArgs, format: PlanFormat) -> PlanArgs {
        PlanArgs {
            input: request.input.to_string_lossy().to_string(),
            request: request.request.clone(),
            object: request.object.clone(),
            from: request.from.clone(),
            to: request.to.clone(),
            format,
            seed: request.seed,
            motions: !request.no_motions,
            weights: request.weights,
            time_budget: request.time_budget.map(std::time::Duration::from_millis),
        }
    }
}

/// A loaded artifact with what rendering diagnostics against it needs.
pub struct Loaded {
    /// The artifact (verified when it has arms).
    pub artifact: Artifact,
    /// Its geometry, when it has arms.
    pub scene: Option<Scene>,
    /// Source files, for rendering.
    pub sources: SourceMap,
}

/// Prints diagnostics to standard error.
pub fn print(diagnostics: &[Diagnostic], sources: &SourceMap) {
    let color = if std::io::stderr().is_terminal() {
        Color::Always
    } else {
        Color::Never
    };
    eprint!("{}", render::human(diagnostics, sources, color));
}

/// Compiles (and verifies) a cell, or reads an artifact; loads its scene when it has arms.
pub fn load(input: &str, seed: u64) -> Result<Loaded, ExitCode> {
    let (mut artifact, sources, fresh) = if input.ends_with(".cell") {
        let compilation = cellc_compiler::compile(&FsFiles, input);
        if compilation.has_errors() || compilation.cell.is_none() {
            print(&compilation.diagnostics, &compilation.sources);
            return Err(ExitCode::from(1));
        }
        let cell = compilation.cell.as_ref().ok_or(ExitCode::from(1))?;
        let artifact =
            cellc_compiler::artifact::lower(cell, &compilation.graphs, &compilation.sources);
        (artifact, compilation.sources, true)
    } else {
        match crate::artifact_io::read(input) {
            Ok(artifact) => {
                // Diagnostics point into the cell's sources, read again if still there.
                let mut sources = SourceMap::new();
                for s in &artifact.sources {
                    sources.add(
                        s.path.clone(),
                        std::fs::read_to_string(&s.path).unwrap_or_default(),
                    );
                }
                (artifact, sources, false)
            }
            Err(d) => {
                print(&[d], &SourceMap::new());
                return Err(ExitCode::from(1));
            }
        }
    };
    let has_arms = artifact
        .end_effectors
        .iter()
        .any(|e| matches!(e.body, Body::Arm { .. }));
    let scene = if has_arms {
        match Scene::load(&artifact, &FsFiles) {
            Ok(scene) => Some(scene),
            Err(e) => {
                print(
                    &[crate::verify_report::scene_error_at(&e, &artifact)],
                    &sources,
                );
                return Err(ExitCode::from(1));
            }
        }
    } else {
        None
    };
    if let (Some(scene), true) = (&scene, fresh) {
        let options = cellc_runtime::verify::VerifyOptions {
            seed,
            ..Default::default()
        };
        cellc_runtime::verify::verify(&mut artifact, scene, &options, &|_, _| {});
    }
    Ok(Loaded {
        artifact,
        scene,
        sources,
    })
}

fn placement_from_schema(
    artifact: &Artifact,
    object: u32,
    p: &cellc_schema::RequestPlacement,
) -> Placement {
    let obj = &artifact.objects[object as usize];
    Placement {
        holder: artifact.end_effectors[p.end_effector as usize].name.clone(),
        grasp: p.grasp.map(|g| obj.grasps[g as usize].name.clone()),
        workspace: p
            .workspace
            .map(|w| artifact.workspaces[w as usize].name.clone()),
        pose: p.pose.as_ref().map(iso_from_schema),
    }
}

/// A placement given on the command line; numbers without units are metres and degrees.
fn placement_from_text(text: &str, what: &str) -> Result<Placement, Box<(Diagnostic, SourceMap)>> {
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
    Ok(Placement {
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
    let artifact = &loaded.artifact;
    let options = PlanOptions {
        seed: args.seed,
        motions: args.motions,
        weights: args.weights,
        time_budget: args.time_budget,
        ..PlanOptions::default()
    };
    let (request, name, span) = match (&args.object, &args.from, &args.to) {
        (Some(object), Some(from), Some(to)) => {
            let parsed = placement_from_text(from, "from")
                .and_then(|f| placement_from_text(to, "to").map(|t| (f, t)));
            match parsed {
                Ok((from, to)) => (
                    Request {
                        object: object.clone(),
                        start: from,
                        goal: Goal::Placement(to),
                        options,
                    },
                    "command line".to_string(),
                    None,
                ),
                Err(failure) => {
                    let (d, sources) = *failure;
                    print(&[d], &sources);
                    return Err(ExitCode::from(2));
                }
            }
        }
        (None, None, None) => {
            let named = match &args.request {
                Some(n) => artifact.requests.iter().find(|r| &r.name == n),
                None => artifact.requests.first(),
            };
            let Some(named) = named else {
                print(
                    &[no_request(artifact, args.request.as_deref())],
                    &loaded.sources,
                );
                return Err(ExitCode::from(1));
            };
            (
                Request {
                    object: artifact.objects[named.object as usize].name.clone(),
                    start: placement_from_schema(artifact, named.object, &named.from),
                    goal: Goal::Placement(placement_from_schema(artifact, named.object, &named.to)),
                    options,
                },
                named.name.clone(),
                Some(named.span),
            )
        }
        _ => {
            eprintln!("error: give --object, --from and --to together, or --request NAME");
            return Err(ExitCode::from(2));
        }
    };
    Ok(Prepared {
        request,
        name,
        span,
    })
}

/// Plans a request and prints the plan.
pub fn run(args: &PlanArgs) -> ExitCode {
    let loaded = match load(&args.input, args.seed) {
        Ok(l) => l,
        Err(code) => return code,
    };
    let Prepared {
        request,
        name,
        span,
    } = match prepare(args, &loaded) {
        Ok(p) => p,
        Err(code) => return code,
    };
    let artifact = &loaded.artifact;
    let planner = Planner::new(artifact, loaded.scene.as_ref());
    match planner.plan(&request) {
        Ok(plan) => {
            match args.format {
                PlanFormat::Human => print!("{}", describe(artifact, &name, &plan)),
                PlanFormat::Json => println!(
                    "{}",
                    serde_json::to_string_pretty(&json(artifact, &name, &plan)).unwrap_or_default()
                ),
            }
            ExitCode::SUCCESS
        }
        Err(error) => {
            let d = plan_error(artifact, &error, span);
            print(&[d], &loaded.sources);
            ExitCode::from(1)
        }
    }
}

/// No request to plan: none declared, or none of that name.
pub fn no_request(artifact: &Artifact, wanted: Option<&str>) -> Diagnostic {
    let known: Vec<String> = artifact
        .requests
        .iter()
        .map(|r| format!("`{}`", r.name))
        .collect();
    let message = match wanted {
        Some(n) => format!("the cell declares no request `{n}`"),
        None => "the cell declares no request".to_string(),
    };
    let help = if known.is_empty() {
        "declare one (`request NAME: OBJECT from HOLDER in WS to HOLDER in WS`) or give --object, --from and --to".to_string()
    } else {
        format!("its requests are {}", known.join(", "))
    };
    Diagnostic::error(codes::NO_REQUEST, message).help(help)
}

/// A planning failure as a diagnostic, labelled at the request when it is a named one.
pub fn plan_error(artifact: &Artifact, error: &PlanError, span: Option<u32>) -> Diagnostic {
    let place = span.and_then(|s| artifact.spans.get(s as usize)).map(|s| {
        (
            FileId(s.file),
            cellc_lang::Span {
                start: s.start,
                end: s.end,
            },
        )
    });
    let mut d = match error {
        PlanError::Locate(e) => Diagnostic::error(codes::LOCATE, e.to_string())
            .help("name a holder, grasp and workspace the cell has, or give a pose that lies in a workspace and matches a grasp"),
        PlanError::Unreachable(u) => crate::explain_report::unreachable(artifact, u),
        PlanError::TimeBudget { searches } => Diagnostic::error(
            codes::TIME_BUDGET,
            format!("planning ran out of its time budget after {searches} backtracks"),
        )
        .help("give a larger `--time-budget`, or none; a budget of 0 stops before the first search"),
        _ => Diagnostic::error(codes::UNREACHABLE, "no plan").help("check the request"),
    };
    if let Some((file, at)) = place {
        if d.labels.is_empty() {
            d = d.primary(file, at, "this request");
        } else {
            d = d.secondary(file, at, "this request");
        }
    }
    d
}

fn ee(a: &Artifact, e: u32) -> &str {
    a.end_effectors
        .get(e as usize)
        .map_or("?", |x| x.name.as_str())
}

fn ws(a: &Artifact, w: u32) -> &str {
    a.workspaces
        .get(w as usize)
        .map_or("?", |x| x.name.as_str())
}

fn pose_text(p: &Option<Iso>) -> String {
    match p {
        Some(p) => {
            let t = p.translation.vector;
            format!(" at ({:.3}, {:.3}, {:.3})", t.x, t.y, t.z)
        }
        None => String::new(),
    }
}

/// The plan as numbered steps.
pub fn describe(artifact: &Artifact, name: &str, plan: &Plan) -> String {
    let object = &artifact.objects[plan.object as usize];
    let grasp = |g: u32| {
        object
            .grasps
            .get(g as usize)
            .map_or("?", |x| x.name.as_str())
    };
    let mut out = String::new();
    let _ = writeln!(
        out,
        "plan `{name}` for `{}`: {} (cost {:.2}, {} steps{})",
        object.name,
        plan.strategy,
        plan.cost,
        plan.steps.len(),
        if plan.backtracks > 0 {
            format!(", {} backtracks", plan.backtracks)
        } else {
            String::new()
        }
    );
    let holders: Vec<&str> = {
        let mut v: Vec<&str> = Vec::new();
        for s in &plan.states {
            let h = ee(artifact, s.end_effector);
            if v.last() != Some(&h) {
                v.push(h);
            }
        }
        v
    };
    let _ = writeln!(out, "holders: {}", holders.join(" -> "));
    for (i, step) in plan.steps.iter().enumerate() {
        let line = match &step.command {
            Command::Move {
                holder,
                workspace,
                object: pose,
                ..
            } => format!(
                "move     `{}` carries it to `{}`{}",
                ee(artifact, *holder),
                ws(artifact, *workspace),
                pose_text(pose)
            ),
            Command::Grasp {
                holder,
                grasp: g,
                workspace,
                object: pose,
                ..
            } => format!(
                "grasp    `{}` takes it with `{}` in `{}`{}",
                ee(artifact, *holder),
                grasp(*g),
                ws(artifact, *workspace),
                pose_text(pose)
            ),
            Command::Ungrasp {
                holder, grasp: g, ..
            } => {
                format!(
                    "ungrasp  `{}` lets go of `{}`",
                    ee(artifact, *holder),
                    grasp(*g)
                )
            }
        };
        let motion = match &step.motion {
            Some(t) => format!(
                " [{:.2} s motion]",
                t.points.last().map_or(0.0, |p| p.0).max(0.0)
            ),
            None => String::new(),
        };
        let _ = writeln!(out, "{:>3}. {line}{motion}", i + 1);
    }
    out
}

#[derive(Serialize)]
struct JsonPlan<'a> {
    request: &'a str,
    object: &'a str,
    strategy: String,
    cost: f64,
    backtracks: u32,
    holders: Vec<&'a str>,
    states: Vec<JsonState<'a>>,
    steps: Vec<JsonStep<'a>>,
}

#[derive(Serialize)]
struct JsonState<'a> {
    end_effector: &'a str,
    grasp: &'a str,
    workspace: &'a str,
}

#[derive(Serialize)]
struct JsonStep<'a> {
    command: &'static str,
    end_effector: &'a str,
    grasp: Option<&'a str>,
    workspace: &'a str,
    object_position: Option<[f64; 3]>,
    object_rotation: Option<[f64; 4]>,
    configurations: Vec<(&'a str, Vec<f64>)>,
    motion: Option<JsonTrajectory<'a>>,
}

#[derive(Serialize)]
struct JsonTrajectory<'a> {
    arms: Vec<&'a str>,
    /// (time in s, concatenated joints of `arms`).
    points: &'a [(f64, Vec<f64>)],
}

fn json<'a>(artifact: &'a Artifact, name: &'a str, plan: &'a Plan) -> impl Serialize + 'a {
    let object = &artifact.objects[plan.object as usize];
    let grasp = |g: u32| {
        object
            .grasps
            .get(g as usize)
            .map_or("?", |x| x.name.as_str())
    };
    let mut holders: Vec<&str> = Vec::new();
    for s in &plan.states {
        let h = ee(artifact, s.end_effector);
        if holders.last() != Some(&h) {
            holders.push(h);
        }
    }
    let pose = |p: &Option<Iso>| {
        p.as_ref().map(|p| {
            let s = cellc_runtime::math::iso_to_schema(p);
            (s.translation, s.rotation)
        })
    };
    JsonPlan {
        request: name,
        object: &object.name,
        strategy: plan.strategy.to_string(),
        cost: plan.cost,
        backtracks: plan.backtracks,
        holders,
        states: plan
            .states
            .iter()
            .map(|s| JsonState {
                end_effector: ee(artifact, s.end_effector),
                grasp: grasp(s.grasp),
                workspace: ws(artifact, s.workspace),
            })
            .collect(),
        steps: plan
            .steps
            .iter()
            .map(|step| {
                let (command, holder, g, w, p, configurations) = match &step.command {
                    Command::Move {
                        holder,
                        workspace,
                        object,
                        configurations,
                    } => (
                        "move",
                        *holder,
                        None,
                        *workspace,
                        pose(object),
                        configurations.clone(),
                    ),
                    Command::Grasp {
                        holder,
                        grasp: g,
                        workspace,
                        object,
                        configurations,
                    } => (
                        "grasp",
                        *holder,
                        Some(grasp(*g)),
                        *workspace,
                        pose(object),
                        configurations.clone(),
                    ),
                    Command::Ungrasp {
                        holder,
                        grasp: g,
                        workspace,
                        object,
                    } => (
                        "ungrasp",
                        *holder,
                        Some(grasp(*g)),
                        *workspace,
                        pose(object),
                        Vec::new(),
                    ),
                };
                JsonStep {
                    command,
                    end_effector: ee(artifact, holder),
                    grasp: g,
                    workspace: ws(artifact, w),
                    object_position: p.map(|p| p.0),
                    object_rotation: p.map(|p| p.1),
                    configurations: configurations
                        .into_iter()
                        .map(|(e, q)| (ee(artifact, e), q))
                        .collect(),
                    motion: step.motion.as_ref().map(|t| JsonTrajectory {
                        arms: t.arms.iter().map(|&e| ee(artifact, e)).collect(),
                        points: &t.points,
                    }),
                }
            })
            .collect(),
    }
}
