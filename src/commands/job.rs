//! What `cellc plan` and `cellc run` are asked to do, as one value: a world to start from
//! and the moves to carry out in it, one after the other.
//!
//! - A request (`--request NAME`, the first declared, or `--object/--from/--to`) is one
//!   move. It is a scenario of its own: its object where the request's start says, the
//!   arms at home (the hand holding the object where it holds it), and no other object,
//!   unless `--world FILE` gives the rest of the cell.
//! - A task (`--task NAME`, declared in the cell) or `--move` flags are several moves,
//!   starting from the cell's `world` (or `--world FILE`).
//!
//! `--state PATH` is `--world FILE` with the world a `cellc serve` state file holds: read,
//! never written back (the service owns the file; a command's moves are simulated from
//! that world, not carried out in the cell).

use std::fmt::Write as _;
use std::process::ExitCode;

use cellc_lang::Diagnostic;
use cellc_runtime::plan::{Goal, GoalByName};
use cellc_runtime::{Artifact, Cell, ObjectId, Whereabouts, World};

use cellc_runtime::plan::PlanOptions;

use super::plan::{placement_from_text, prepare, Loaded, Prepared};
use crate::plan_report::{self, codes};
use crate::world_report::{read_world, world_diagnostic};

/// What a command is asked to carry out, by the names the command line gives: a named
/// request, a request given by its object and placements, a task, or moves, in the
/// cell's world or one read from a file. `plan`, `run` and `view` share it.
#[derive(Clone, Debug, Default)]
pub struct JobArgs {
    /// A named request of the cell.
    pub request: Option<String>,
    /// Object, for a request given on the command line.
    pub object: Option<String>,
    /// Start placement text.
    pub from: Option<String>,
    /// Goal placement text.
    pub to: Option<String>,
    /// A task of the cell to carry out instead of a request.
    pub task: Option<String>,
    /// Moves given on the command line (`OBJECT to PLACEMENT`), instead of a request.
    pub moves: Vec<String>,
    /// A world document to start from.
    pub world: Option<String>,
    /// A state file whose world to start from (never with `world`: the parser refuses
    /// both).
    pub state: Option<String>,
}

/// How to confirm an uncertain world from the command line, S0007's help.
pub const CONFIRM: &str = "confirm where they are through the service (`PUT` or `PATCH /v1/world`), or start from a world file you checked with `--world FILE`";

/// The world `--world FILE` or `--state PATH` gives, `None` when neither is given.
///
/// # Errors
/// The diagnostic of a file that cannot be read or a world that does not fit the cell
/// (R0008, R0009, S0011), or of an uncertain stored world (S0007).
pub fn given_world(
    args: &JobArgs,
    cell: &Cell,
    options: &PlanOptions,
) -> Result<Option<World>, Diagnostic> {
    if let Some(path) = &args.world {
        return read_world(cell, path, options).map(Some);
    }
    let Some(path) = &args.state else {
        return Ok(None);
    };
    let stored = crate::state::read(path, CONFIRM)?;
    crate::state::world_of(cell, &stored, path).map(Some)
}

/// One move of a job.
pub struct Move {
    /// The object.
    pub object: ObjectId,
    /// Where it must go.
    pub goal: Goal,
    /// The request's span (for labels), when the move is a named request.
    pub span: Option<u32>,
}

/// A world and the moves to carry out in it.
pub struct Job {
    /// Where everything is before the first move.
    pub world: World,
    /// The moves, in order.
    pub moves: Vec<Move>,
    /// What the moves are, in words: "request `trash`", "task `clear_table`", "moves".
    pub title: String,
}

/// The job `args` ask for; reports what is wrong and gives the exit code otherwise.
pub fn job(args: &JobArgs, options: &PlanOptions, loaded: &Loaded) -> Result<Job, ExitCode> {
    let cell = &loaded.cell;
    let fail = |d: Diagnostic| {
        loaded.report(&[d]);
        ExitCode::from(1)
    };
    let given = given_world(args, cell, options).map_err(fail)?;
    let declared = || {
        cell.initial_world(options)
            .map_err(|e| world_diagnostic(&e, "the cell's `world`"))
            .map_err(fail)
    };
    if let Some(name) = &args.task {
        let moves = cell.task(name).ok_or_else(|| fail(no_task(cell, name)))?;
        return Ok(Job {
            world: match given {
                Some(w) => w,
                None => declared()?,
            },
            moves: moves
                .into_iter()
                .map(|(object, goal)| Move {
                    object,
                    goal,
                    span: None,
                })
                .collect(),
            title: format!("task `{name}`"),
        });
    }
    if !args.moves.is_empty() {
        let moves = args
            .moves
            .iter()
            .map(|text| parse_move(loaded, text))
            .collect::<Result<Vec<_>, _>>()?;
        return Ok(Job {
            world: match given {
                Some(w) => w,
                None => declared()?,
            },
            moves,
            title: "moves".to_string(),
        });
    }
    let Prepared {
        request,
        name,
        span,
    } = prepare(args, options, loaded)?;
    let base = given.unwrap_or_else(|| World::at_home(cell.artifact(), cell.scene()));
    let world = cell.request_world(&base, &request).map_err(|e| {
        fail(plan_report::plan_error(
            cell.artifact(),
            &e,
            Some(span).flatten(),
            Some(loaded.sources()),
        ))
    })?;
    Ok(Job {
        world,
        moves: vec![Move {
            object: request.object,
            goal: request.goal,
            span,
        }],
        title: format!("request `{name}`"),
    })
}

/// The objects the job of `args` can touch in a cell of this core: the one a request
/// moves (its world has no other object), or a task's and the declared world's. `None`
/// when that is not known before the job is read (a world document, a state file,
/// `--move` flags), so every object is needed. A name that matches nothing touches
/// nothing: the job reports it.
pub fn objects(args: &JobArgs, core: &Artifact) -> Option<Vec<ObjectId>> {
    if args.world.is_some() || args.state.is_some() || !args.moves.is_empty() {
        return None;
    }
    let mut touched: Vec<ObjectId> = Vec::new();
    if let Some(name) = &args.task {
        let steps = core.tasks.iter().filter(|t| &t.name == name);
        touched.extend(steps.flat_map(|t| t.steps.iter().map(|s| s.object)));
        touched.extend(core.world.iter().map(|p| p.object));
    } else if let Some(object) = &args.object {
        touched.extend(cellc_runtime::plan::names::object(core, object).ok());
    } else {
        let named = match &args.request {
            Some(n) => core.requests.iter().find(|r| &r.name == n),
            None => core.requests.first(),
        };
        touched.extend(named.map(|r| r.object));
    }
    touched.sort_unstable();
    touched.dedup();
    Some(touched)
}

/// `OBJECT to PLACEMENT`, as `--move` gives it; reports what is wrong.
fn parse_move(loaded: &Loaded, text: &str) -> Result<Move, ExitCode> {
    let cell = &loaded.cell;
    let Some((object, to)) = text.split_once(" to ") else {
        loaded.report(&[Diagnostic::error(
            codes::LOCATE,
            format!("`{}` is not a move", crate::render::escape(text)),
        )
        .help("write `OBJECT to PLACEMENT`, e.g. `ball to bin in ws_right_bin` or `cylinder to table at (0.4, -0.3, 1.0)`")]);
        return Err(ExitCode::from(2));
    };
    let placement = placement_from_text(to.trim(), "move").map_err(|failure| {
        let (d, sources) = *failure;
        crate::render::emit(loaded.style, &[d], &sources);
        ExitCode::from(2)
    })?;
    let object = object.trim();
    let request = cell
        .object(object)
        .and_then(|id| {
            cellc_runtime::plan::names::goal(cell.artifact(), id, &GoalByName::Placement(placement))
                .map(|goal| (id, goal))
        })
        .map_err(|e| {
            loaded.report(&[plan_report::plan_error(
                cell.artifact(),
                &cellc_runtime::plan::PlanError::Locate(e),
                None,
                None,
            )]);
            ExitCode::from(1)
        })?;
    Ok(Move {
        object: request.0,
        goal: request.1,
        span: None,
    })
}

fn no_task(cell: &Cell, name: &str) -> Diagnostic {
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
    Diagnostic::error(
        codes::NO_REQUEST,
        format!("the cell declares no task `{name}`"),
    )
    .help(help)
}

/// The world, one line per object.
pub fn world_text(cell: &Cell, world: &World) -> String {
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
