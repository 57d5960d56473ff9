//! `cellc view INPUT [--request NAME | --task NAME | --plan PLAN.json]
//! [--world WORLD.json | --state PATH] -o VIEW.html`: one self-contained HTML page with the cell in 3D,
//! its workspaces, its object-state graphs and, with a plan, the plan animated.
//!
//! Everything is computed here, in Rust, by the runtime's own code: the collision
//! geometry (`geometry.rs`), forward kinematics of every trajectory sample and the object
//! following its holder (`timeline.rs`), plans from the planner or a plan document
//! (`plans.rs`), graphs laid out as SVG (`crate::graph_svg`), witnesses of states and the
//! explanation of an unreachable request (`panel.rs`). The page (`page.rs`, with its
//! script and style in `assets/` and three.js from `third_party/three/`) only draws that
//! one JSON document.

mod geometry;
mod page;
mod panel;
mod plans;
mod timeline;

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use cellc_lang::Diagnostic;
use cellc_runtime::plan::PlanError;
use cellc_runtime::World;
use serde::Serialize;

use super::job::JobArgs;
use super::plan::{LoadArgs, Loaded};

/// What `cellc view` was asked.
pub struct ViewArgs {
    /// How to load the cell (`style` is human: diagnostics on stderr).
    pub load: LoadArgs,
    /// What to plan and animate (no `moves`: the page has no `--move`).
    pub job: JobArgs,
    /// A plan document to show instead of planning.
    pub plan_file: Option<PathBuf>,
    /// Where the page goes.
    pub output: PathBuf,
}

/// A workspace or reach box set as the page lists it.
#[derive(Serialize)]
struct Region {
    name: String,
    /// `workspace` or `reach`.
    kind: &'static str,
    /// For reach: the end-effector; for a workspace: its label.
    label: String,
    derived: bool,
    boxes: Vec<[[f64; 3]; 2]>,
}

/// The page's document.
#[derive(Serialize)]
struct Document {
    version: u32,
    cell: String,
    title: String,
    geometry: geometry::Geometry,
    fixed: Vec<(usize, [f64; 7])>,
    regions: Vec<Region>,
    timeline: timeline::Timeline,
    graphs: Vec<panel::GraphOut>,
    snapshots: Vec<timeline::Poses>,
    /// The request's failure, in words, when it has no plan.
    failure: Option<String>,
    explanation: Option<panel::ExplanationOut>,
}

fn regions(artifact: &cellc_schema::Artifact) -> Vec<Region> {
    let boxes = |b: &[cellc_schema::Aabb]| -> Vec<[[f64; 3]; 2]> {
        b.iter()
            .map(|x| [x.min.map(geometry::round), x.max.map(geometry::round)])
            .collect()
    };
    let mut out: Vec<Region> = artifact
        .workspaces
        .iter()
        .filter(|w| !w.boxes.is_empty())
        .map(|w| Region {
            name: w.name.clone(),
            kind: "workspace",
            label: w.label.clone().unwrap_or_default(),
            derived: w.derived,
            boxes: boxes(&w.boxes),
        })
        .collect();
    out.extend(
        artifact
            .end_effectors
            .iter()
            .filter(|e| e.movable && !e.reach_boxes.is_empty())
            .map(|e| Region {
                name: format!("reach of {}", e.name),
                kind: "reach",
                label: e.name.clone(),
                derived: false,
                boxes: boxes(&e.reach_boxes),
            }),
    );
    out
}

/// The plans to show and the world they start in, or the failure (reported, with the
/// exit code) when the input is wrong.
struct Planned {
    world: World,
    plans: Vec<timeline::PlanIn>,
    /// Where a plan document's objects start (the first plan of each object says).
    starts: Vec<(cellc_schema::ObjectId, timeline::Whereabouts)>,
    failure: Option<(String, Option<Box<cellc_runtime::plan::Unreachable>>)>,
    title: String,
}

fn planned(args: &ViewArgs, loaded: &Loaded) -> Result<Planned, ExitCode> {
    let cell = &loaded.cell;
    let artifact = cell.artifact();
    let p = &args.job;
    // Joint motions always: the page animates them.
    let options = cellc_runtime::plan::PlanOptions {
        seed: args.load.options.seed,
        ..Default::default()
    };
    if let Some(path) = &args.plan_file {
        let path = path.to_string_lossy();
        let fail = |d: Diagnostic| {
            loaded.report(&[d]);
            ExitCode::from(1)
        };
        let world = super::job::given_world(p, cell, &options)
            .map_err(fail)?
            .unwrap_or_else(|| World::at_home(artifact, cell.scene()));
        let (plans, starts) = plans::read(artifact, cell.scene(), &path).map_err(fail)?;
        return Ok(Planned {
            world,
            plans,
            starts,
            failure: None,
            title: format!("plan file `{path}`"),
        });
    }
    let asked = p.request.is_some() || p.object.is_some() || p.task.is_some();
    if !asked {
        let given = super::job::given_world(p, cell, &options).map_err(|d| {
            loaded.report(&[d]);
            ExitCode::from(1)
        })?;
        let world = given.unwrap_or_else(|| {
            cell.initial_world(&options)
                .unwrap_or_else(|_| World::at_home(artifact, cell.scene()))
        });
        return Ok(Planned {
            world,
            plans: Vec::new(),
            starts: Vec::new(),
            failure: None,
            title: "the cell".to_string(),
        });
    }
    let super::job::Job {
        world,
        moves,
        title,
    } = super::job::job(p, &options, loaded)?;
    let options = cellc_runtime::TaskOptions {
        plan: options,
        ..Default::default()
    };
    let list: Vec<_> = moves.iter().map(|m| (m.object, m.goal.clone())).collect();
    let result = cell.plan_task(&world, &list, &options);
    let single = moves.len() == 1;
    let mut plans = Vec::new();
    for (i, found) in result.plans.iter().enumerate() {
        for plan in found {
            let label = if single {
                title.clone()
            } else {
                format!("move {} of {}", i + 1, moves.len())
            };
            // Read as a plan document is, so the page shows a plan planned now and
            // one saved by `cellc plan --format json` the same way.
            let document = cellc_driver::document::plan::Plan::of(artifact, &label, plan);
            let (plan, _) = plans::plan_of(artifact, cell.scene(), &document).map_err(|e| {
                loaded.report(&[plans::refused("the plan planned now", e)]);
                ExitCode::from(1)
            })?;
            plans.push(plan);
        }
    }
    let failure = result.failure.map(|f| {
        let unreachable = match &f.error {
            cellc_runtime::TaskError::Plan(PlanError::Unreachable(u)) => Some(u.clone()),
            _ => None,
        };
        let text = match &f.error {
            cellc_runtime::TaskError::Plan(e) => {
                let d = crate::plan_report::plan_error(artifact, e, moves[f.index].span, None);
                d.message.clone()
            }
            cellc_runtime::TaskError::Execute(_) => "the plan failed".to_string(),
        };
        (text, unreachable)
    });
    Ok(Planned {
        world,
        plans,
        starts: Vec::new(),
        failure,
        title,
    })
}

/// Writes the page.
pub fn run(args: &ViewArgs) -> ExitCode {
    let mut load = args.load.clone();
    load.style.format = crate::render::Format::Human;
    let loaded = match super::plan::load(&load) {
        Ok(l) => l,
        Err(code) => return code,
    };
    let planned = match planned(args, &loaded) {
        Ok(p) => p,
        Err(code) => return code,
    };
    let cell = &loaded.cell;
    let artifact = cell.artifact();
    let scene = cell.scene();
    let built = match scene {
        Some(s) => geometry::build(artifact, s),
        None => geometry::Built {
            geometry: geometry::Geometry::default(),
            arms: Vec::new(),
            objects: Vec::new(),
            fixed: Vec::new(),
        },
    };
    let mut start = plans::start_of(artifact, scene, &planned.world);
    let mut placed = Vec::new();
    for (o, w) in &planned.starts {
        if !placed.contains(o) {
            placed.push(*o);
            if let Some(slot) = start.objects.get_mut(o.index()) {
                *slot = Some(w.clone());
            }
        }
    }
    let timeline = timeline::timeline(artifact, scene, &built, &start, &planned.plans);
    let (graphs, snapshots) = panel::graphs(artifact, scene, &built, &start);
    let explanation = planned
        .failure
        .as_ref()
        .and_then(|(_, u)| u.as_ref())
        .and_then(|u| panel::explanation(artifact, u));
    let document = Document {
        version: 1,
        cell: artifact.cell.clone(),
        title: planned.title.clone(),
        fixed: built
            .fixed
            .iter()
            .map(|(b, p)| (*b, geometry::pose(p)))
            .collect(),
        geometry: built.geometry,
        regions: regions(artifact),
        timeline,
        graphs,
        snapshots,
        failure: planned.failure.as_ref().map(|f| f.0.clone()),
        explanation,
    };
    let html = page::html(&format!("{} — {}", artifact.cell, planned.title), &document);
    let inputs: Vec<&Path> = [Some(Path::new(&args.load.input)), args.plan_file.as_deref()]
        .into_iter()
        .flatten()
        .chain(args.job.world.as_deref().map(Path::new))
        .collect();
    if let Err(d) = crate::output::write(&args.output, html.as_bytes(), inputs) {
        loaded.report(&[d]);
        return ExitCode::from(1);
    }
    if let Some((text, _)) = &planned.failure {
        eprintln!("{} has no plan ({text}); the page shows why", planned.title);
    }
    eprintln!(
        "wrote `{}` ({} KiB)",
        args.output.display(),
        html.len().div_ceil(1024)
    );
    ExitCode::SUCCESS
}
