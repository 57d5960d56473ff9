//! `cellc run CELL --task NAME [--world FILE]` and `cellc run CELL --world FILE`: moves
//! planned and executed one after the other in a world that persists between them.
//!
//! The world starts as the cell declares it (`world { ... }`) or as a world document says
//! (`docs/world.md`). Each move is planned from where the world has its object, with the
//! arms where they stand and every other object in the way, executed in the simulator,
//! and the world updated from what the simulator reports. A failing move is reported with
//! its place in the task, and the world is printed as it really is: the objects moved so
//! far stay moved.

use std::fmt::Write as _;
use std::process::ExitCode;

use cellc_lang::Diagnostic;
use cellc_runtime::plan::{Goal, PlanOptions};
use cellc_runtime::{Cell, ExecuteOptions, ObjectId, Whereabouts, World, WorldError};
use cellc_schema::world::WorldDocumentError;
use cellc_schema::{Files, WorldDocument};

use super::plan::{load, prepare, Loaded, PlanArgs, Prepared};
use crate::fs_files::FsFiles;
use crate::plan_report::{codes, describe, plan_error};

/// Runs a task (or the request `args` names) in a world.
pub fn run(args: &PlanArgs, task: Option<&str>, world_file: Option<&std::path::Path>) -> ExitCode {
    let loaded = match load(args) {
        Ok(l) => l,
        Err(code) => return code,
    };
    let cell = &loaded.cell;
    let options = args.options();
    let world = match world_file {
        Some(path) => read_world(cell, &path.to_string_lossy(), &options),
        None => cell
            .initial_world(&options)
            .map_err(|e| world_diagnostic(&e, "the cell's `world`")),
    };
    let mut world = match world {
        Ok(w) => w,
        Err(d) => {
            loaded.report(&[d]);
            return ExitCode::from(1);
        }
    };
    let (moves, title) = match task {
        Some(name) => match cell.task(name) {
            Some(moves) => (moves, format!("task `{name}`")),
            None => {
                let known: Vec<&str> = cell
                    .artifact()
                    .tasks
                    .iter()
                    .map(|t| t.name.as_str())
                    .collect();
                let help = cellc_lang::diagnostic::did_you_mean(name, known.iter().copied())
                    .map(|s| format!("did you mean `{s}`?"))
                    .unwrap_or_else(|| {
                        if known.is_empty() {
                            "declare one: `task NAME { OBJECT to PLACEMENT ... }`".to_string()
                        } else {
                            format!("the cell's tasks are {}", quoted(&known))
                        }
                    });
                loaded.report(&[Diagnostic::error(
                    codes::NO_REQUEST,
                    format!("the cell declares no task `{name}`"),
                )
                .help(help)]);
                return ExitCode::from(1);
            }
        },
        None => match prepare(args, &loaded) {
            Ok(Prepared { request, name, .. }) => (
                vec![(request.object, request.goal)],
                format!("request `{name}`"),
            ),
            Err(code) => return code,
        },
    };
    let outcome = run_moves(&loaded, &mut world, &moves, &options, &title);
    print!("{}", world_text(cell, &world));
    outcome
}

/// Plans and executes each move in turn; stops at the first that fails.
fn run_moves(
    loaded: &Loaded,
    world: &mut World,
    moves: &[(ObjectId, Goal)],
    options: &PlanOptions,
    title: &str,
) -> ExitCode {
    let cell = &loaded.cell;
    let artifact = cell.artifact();
    for (i, (object, goal)) in moves.iter().enumerate() {
        let name = artifact.object_name(*object);
        println!("{title}, move {} of {}: `{name}`", i + 1, moves.len());
        let failed_here = |d: Diagnostic| {
            d.note(format!(
                "move {} of {} of the {title} failed; the moves before it were carried out",
                i + 1,
                moves.len()
            ))
        };
        let plan = match cell.plan_in(world, *object, goal, options) {
            Ok(plan) => plan,
            Err(e) => {
                loaded.report(&[failed_here(plan_error(
                    artifact,
                    &e,
                    None,
                    Some(&loaded.sources),
                ))]);
                return ExitCode::from(1);
            }
        };
        print!("{}", describe(artifact, name, &plan));
        let mut simulator = cell.simulator_in(world, &plan);
        let execute = ExecuteOptions {
            max_replans: 5,
            plan: options.clone(),
        };
        let result = cell.execute_in(world, plan, &mut simulator, &execute);
        for line in &simulator.log {
            println!("  {line}");
        }
        if let Err(e) = result {
            let d = Diagnostic::error(codes::EXECUTION_FAILED, format!("execution failed: {e}"))
                .help("see the simulation log above; the world below is where it stopped");
            loaded.report(&[failed_here(d)]);
            return ExitCode::from(1);
        }
    }
    ExitCode::SUCCESS
}

/// Reads and checks a world document.
fn read_world(cell: &Cell, path: &str, options: &PlanOptions) -> Result<World, Diagnostic> {
    let max = cellc_schema::world::MAX_WORLD_BYTES as u64;
    let bytes = FsFiles.read_at_most(path, max).map_err(|e| {
        Diagnostic::error(codes::WORLD_DOCUMENT, format!("cannot read `{path}`: {e}"))
            .help("give the path of a world document (JSON, see docs/world.md)")
    })?;
    let document = WorldDocument::from_json(&bytes).map_err(|e| match e {
        WorldDocumentError::TooLarge { bytes } => Diagnostic::error(
            codes::WORLD_DOCUMENT,
            format!("`{path}` has {bytes} bytes, more than a world document may have"),
        )
        .help(format!(
            "a world document holds at most {} MiB",
            cellc_schema::world::MAX_WORLD_BYTES >> 20
        )),
        WorldDocumentError::Syntax {
            line,
            column,
            message,
        } => Diagnostic::error(
            codes::WORLD_DOCUMENT,
            format!("`{path}` line {line}, column {column}: not a world document"),
        )
        .note(crate::render::escape(&message).into_owned())
        .help("a world document has `arms` (arm -> joint -> value) and `objects` (object -> placement or \"absent\"); see docs/world.md"),
    })?;
    cell.world(&document, options)
        .map_err(|e| world_diagnostic(&e, &format!("`{path}`")))
}

/// A world error in words.
fn world_diagnostic(e: &WorldError, source: &str) -> Diagnostic {
    let (what, help) = match e {
        WorldError::Name(e) => (
            e.to_string(),
            "name an arm, object, holder, grasp and workspace the cell has".to_string(),
        ),
        WorldError::NotAnArm { name } => (
            format!("`{name}` is not an arm, so it has no joints"),
            "give joints for the cell's arms only".to_string(),
        ),
        WorldError::UnknownJoint { arm, joint, known } => (
            format!("`{arm}`'s chain has no joint `{joint}`"),
            cellc_lang::diagnostic::did_you_mean(joint, known.iter().map(String::as_str))
                .map(|s| format!("did you mean `{s}`?"))
                .unwrap_or_else(|| format!("its joints are {}", quoted(&known.iter().map(String::as_str).collect::<Vec<_>>()))),
        ),
        WorldError::JointOutOfLimits {
            arm,
            joint,
            value,
            lower,
            upper,
        } => (
            format!("`{arm}`'s joint `{joint}` is {value}, outside its limits [{lower}, {upper}]"),
            "joint values are radians (metres for prismatic joints), within the URDF's limits"
                .to_string(),
        ),
        WorldError::Placement { object, error } => (
            format!("`{object}`: {error}"),
            "place it on a surface at a pose its resting poses match, or in a hand with a grasp where the arm's joints put it in a workspace".to_string(),
        ),
        WorldError::PoseNeeded { object, holder } => (
            format!("`{object}` rests on `{holder}` but has no pose"),
            "give `at` (and `rpy` or `quat` when it is turned): an obstacle needs a place".to_string(),
        ),
        WorldError::Orientation { object, detail } => (
            format!("`{object}`: {detail}"),
            "`rpy` is degrees about fixed x, y, z; `quat` is (w, x, y, z) of unit length".to_string(),
        ),
        WorldError::PoseDisagrees {
            object,
            holder,
            position_error,
            rotation_error,
        } => (
            format!(
                "`{object}` is given {:.1} mm and {:.2} deg away from where `{holder}`'s joints hold it",
                position_error * 1000.0,
                rotation_error.to_degrees()
            ),
            "leave the pose out (it follows from the joints), or give the joints that put the hand there".to_string(),
        ),
        WorldError::HandFull {
            hand,
            first,
            second,
        } => (
            format!("`{hand}` would hold both `{first}` and `{second}`"),
            "a hand holds one object: put one of them elsewhere".to_string(),
        ),
        _ => (e_debug(e), "see docs/world.md".to_string()),
    };
    Diagnostic::error(codes::WORLD, format!("{source}: {what}")).help(help)
}

/// Words for a world error this version does not know (the type is non-exhaustive).
fn e_debug(e: &WorldError) -> String {
    crate::render::escape(&format!("{e:?}")).into_owned()
}

/// The world, one line per object and per arm that is not at home.
fn world_text(cell: &Cell, world: &World) -> String {
    let a = cell.artifact();
    let mut out = String::from("world:\n");
    for (i, o) in a.objects.iter().enumerate() {
        let id = ObjectId(i as u32);
        match world.whereabouts(id) {
            Whereabouts::Absent => {
                let _ = writeln!(out, "  `{}`: absent", o.name);
            }
            Whereabouts::Placed { state, .. } => {
                let _ = write!(
                    out,
                    "  `{}`: `{}`.`{}` in `{}`",
                    o.name,
                    a.end_effector_name(state.end_effector),
                    a.grasp_name(id, state.grasp),
                    a.workspace_name(state.workspace)
                );
                if let Some(p) = world.pose(a, cell.scene(), id) {
                    let t = p.translation.vector;
                    let _ = write!(out, " at ({:.3}, {:.3}, {:.3})", t.x, t.y, t.z);
                }
                out.push('\n');
            }
        }
    }
    out
}

fn quoted(names: &[&str]) -> String {
    names
        .iter()
        .map(|n| format!("`{n}`"))
        .collect::<Vec<_>>()
        .join(", ")
}
