//! Plans and planning failures in words: numbered steps, the JSON document, and coded
//! diagnostics for requests that cannot be located, reached or planned in time.

use std::fmt::Write as _;

use cellc_driver::advice::{FrontEnd, PlanOption};
use cellc_lang::{Diagnostic, FileId, SourceMap};
use cellc_runtime::math::Iso;
use cellc_runtime::plan::{Command, LocateError, Plan, PlanError};
use cellc_schema::{Artifact, EndEffectorId, GraspId, WorkspaceId};

pub use cellc_driver::runtime_codes as codes;

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

/// A planning failure as a diagnostic, labelled at the request when it is a named one;
/// with the cell's sources, an unreachable goal's suggestions come with their edits.
pub fn plan_error(
    artifact: &Artifact,
    error: &PlanError,
    span: Option<u32>,
    sources: Option<&SourceMap>,
) -> Diagnostic {
    plan_error_for(FrontEnd::CommandLine, artifact, error, span, sources)
}

/// [`plan_error`], its advice naming `front_end`'s options (the service's request fields
/// instead of the command line's flags).
pub fn plan_error_for(
    front_end: FrontEnd,
    artifact: &Artifact,
    error: &PlanError,
    span: Option<u32>,
    sources: Option<&SourceMap>,
) -> Diagnostic {
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
        PlanError::Locate(e) => Diagnostic::error(codes::LOCATE, e.to_string()).help(
            did_you_mean(e).or_else(|| locate_help(e)).unwrap_or_else(|| "name a holder, grasp and workspace the cell has, or give a pose that lies in a workspace and matches a grasp".into()),
        ),
        PlanError::Unreachable(u) => {
            cellc_driver::explain_report::unreachable_for(front_end, artifact, u, sources)
        }
        PlanError::TimeBudget { searches } => Diagnostic::error(
            codes::TIME_BUDGET,
            format!("planning ran out of its time budget after {searches} backtracks"),
        )
        .help(format!(
            "give a larger {}, or none; a budget of 0 stops before the first search",
            front_end.option(PlanOption::TimeBudget)
        )),
        PlanError::GoalOccupied { by } => Diagnostic::error(
            codes::GOAL_OCCUPIED,
            format!("`{}` stands where the goal puts the object", artifact.object_name(*by)),
        )
        .help(format!(
            "choose a free goal, or move `{}` first ({} does, or a task in order)",
            artifact.object_name(*by),
            front_end.option(PlanOption::Clear)
        )),
        PlanError::Absent { object } => Diagnostic::error(
            codes::GOAL_OCCUPIED,
            format!("`{}` is not in the world", artifact.object_name(*object)),
        )
        .help("place it in the cell's `world` or in the world document before moving it"),
        PlanError::World(e) => crate::world_report::world_diagnostic(e, "the request's start"),
        PlanError::InvalidOption { name, value } => option_out_of_range(front_end, name, *value),
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

/// R0012: a timing option out of its range, or a rate in range at which a motion would
/// have more points than it may; `name` is the runtime's field (`velocity_scaling`,
/// `acceleration_scaling`, `rate`), worded as `front_end` writes it. The ranges are the
/// runtime's (`cellc_runtime::motion::check_timing`), which decided.
pub fn option_out_of_range(front_end: FrontEnd, name: &str, value: f64) -> Diagnostic {
    use cellc_runtime::motion::TimingOptions;
    let option = PlanOption::of_timing_field(name);
    let written = option.map_or_else(|| format!("`{name}`"), |o| front_end.option(o).to_string());
    let max_rate = TimingOptions::MAX_RATE;
    let (message, help) = match option {
        Some(PlanOption::Rate) if value.is_finite() && value > 0.0 && value <= max_rate => (
            format!(
                "at a {written} of {value} Hz a motion of this plan would have more than {} points",
                TimingOptions::MAX_POINTS
            ),
            "give a lower rate, or larger scalings (a slower motion has more points), or no rate for the knots of the time parameterisation".to_string(),
        ),
        Some(PlanOption::Rate) => (
            format!("{written} is {value} Hz, outside (0, {max_rate}]"),
            format!("give a control rate above 0 and at most {max_rate} Hz (e.g. 250), or none for the knots of the time parameterisation"),
        ),
        _ => (
            format!("{written} is {value}, outside (0, 1]"),
            "give a share of every joint's limits above 0 and at most 1 (0.5 for half of each limit), or leave it out for 1".to_string(),
        ),
    };
    Diagnostic::error(codes::OPTION_OUT_OF_RANGE, message).help(help)
}

/// R0011: a plan document whose motion cannot be sent to a controller. The plans the
/// runtime makes always can (each point as wide as its arms, times in order); this is
/// what a document made elsewhere gets.
pub fn goals_refused(error: &cellc_driver::document::controller::GoalsError) -> Diagnostic {
    Diagnostic::error(
        codes::PLAN_DOCUMENT,
        format!("the plans cannot be written as controller goals: {error}"),
    )
    .help("plan again: the runtime writes every point with a value per joint, in time order")
}

/// The fix of a cause that names a missing fact of the cell.
fn locate_help(error: &LocateError) -> Option<String> {
    Some(match error {
        LocateError::NotReached { holder, workspace, .. } => format!(
            "choose a holder that reaches `{workspace}`, or add `{workspace}` to what `{holder}` reaches"
        ),
        LocateError::NothingToHoldBy { holder, surface: true, .. } => format!(
            "add a resting pose of the object `by {holder}` (`grasp NAME by {holder}`), or choose a surface that has one"
        ),
        LocateError::NothingToHoldBy { holder, surface: false, .. } => format!(
            "add a grasp of the object `by {holder}` (`grasp NAME by {holder}`), or choose a hand that has one"
        ),
        LocateError::Ungraspable { object } => format!(
            "give `{object}` a grasp or resting pose (`grasp NAME by HOLDER`) and the transitions between them"
        ),
        LocateError::NoStateThere { holder, .. } => format!(
            "run `cellc build --explain` to see why the states of `{holder}` there were pruned, or add a transition to one of its grasps"
        ),
        _ => return None,
    })
}

/// "did you mean `x`?" for an unknown name close to a known one.
fn did_you_mean(error: &LocateError) -> Option<String> {
    let (name, known) = match error {
        LocateError::UnknownObject { name, known }
        | LocateError::UnknownHolder { name, known }
        | LocateError::UnknownWorkspace { name, known }
        | LocateError::UnknownGrasp { name, known, .. } => (name, known),
        _ => return None,
    };
    cellc_lang::diagnostic::did_you_mean(name, known.iter().map(String::as_str))
        .map(|s| format!("did you mean `{s}`?"))
}

fn ee(a: &Artifact, e: EndEffectorId) -> &str {
    a.end_effector_name(e)
}

fn ws(a: &Artifact, w: WorkspaceId) -> &str {
    a.workspace_name(w)
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
    let mut out = String::new();
    let _ = writeln!(out, "{}", headline(artifact, name, plan));
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
    for d in &plan.detours {
        let how = match d.around {
            cellc_runtime::plan::Around::OtherPose => "put down at another pose",
            _ => "another way found",
        };
        let _ = writeln!(
            out,
            "around: {} ({how})",
            cellc_driver::explain_report::words::blocked(artifact, &d.blocker)
        );
    }
    for (i, step) in plan.steps.iter().enumerate() {
        let (verb, text) = step_text(artifact, plan, step);
        let _ = writeln!(out, "{:>3}. {verb:<8} {text}", i + 1);
    }
    out
}

/// The plan in `--format short`: its headline, then one line per step, each line naming
/// the plan so that lines of several plans can be told apart (and grepped) on their own.
pub fn short(artifact: &Artifact, name: &str, plan: &Plan) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "{}", headline(artifact, name, plan));
    for (i, step) in plan.steps.iter().enumerate() {
        let (verb, text) = step_text(artifact, plan, step);
        let _ = writeln!(out, "plan `{name}` step {}: {verb} {text}", i + 1);
    }
    out
}

/// `plan `NAME` for `OBJECT`: STRATEGY (cost C, N steps)`.
fn headline(artifact: &Artifact, name: &str, plan: &Plan) -> String {
    let object = &artifact.objects[plan.object.index()];
    format!(
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
    )
}

/// One step: its command's verb, and the rest (who, where the object goes, how long its
/// joint motion takes).
fn step_text(
    artifact: &Artifact,
    plan: &Plan,
    step: &cellc_runtime::plan::Step,
) -> (&'static str, String) {
    let grasp = |g: GraspId| artifact.grasp_name(plan.object, g);
    let (verb, line) = match &step.command {
        Command::Move {
            holder,
            workspace,
            object: pose,
            ..
        } => (
            "move",
            format!(
                "`{}` carries it to `{}`{}",
                ee(artifact, *holder),
                ws(artifact, *workspace),
                pose_text(pose)
            ),
        ),
        Command::Grasp {
            holder,
            grasp: g,
            workspace,
            object: pose,
            ..
        } => (
            "grasp",
            format!(
                "`{}` takes it with `{}` in `{}`{}",
                ee(artifact, *holder),
                grasp(*g),
                ws(artifact, *workspace),
                pose_text(pose)
            ),
        ),
        Command::Ungrasp {
            holder, grasp: g, ..
        } => (
            "ungrasp",
            format!("`{}` lets go of `{}`", ee(artifact, *holder), grasp(*g)),
        ),
    };
    let motion = match &step.motion {
        Some(t) => format!(
            " [{:.2} s motion]",
            t.points.last().map_or(0.0, |p| p.time).max(0.0)
        ),
        None => String::new(),
    };
    (verb, format!("{line}{motion}"))
}
