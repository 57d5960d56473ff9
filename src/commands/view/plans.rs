//! The plans a page animates, read from the plan document
//! ([`cellc_driver::document::plan::Plan`]) whatever they come from: the runtime's plans
//! (planned now, `--request`, `--task`, ..., made documents by `Plan::of`) or a plan
//! document written earlier by `cellc plan --format json` (`--plan FILE`, untrusted:
//! every name is looked up in the cell, every joint vector checked against its arm,
//! every number finite and bounded).

use cellc_driver::document::plan::{Plan as PlanDoc, Pose as PoseDoc, StepCommand};
use cellc_driver::document::run::{Kind, Run};
use cellc_lang::Diagnostic;
use cellc_runtime::math::{Iso, Quat, Vec3};
use cellc_runtime::scene::{Holder, Scene};
use cellc_runtime::{Files, World};
use cellc_schema::{Artifact, EndEffectorId, GraspId, Node, ObjectId, WorkspaceId};

use super::timeline::{PlanIn, Start, StepIn, Verb, Whereabouts};
use cellc_driver::fs_files::FsFiles;
use cellc_driver::runtime_codes as codes;

/// A plan document holds at most this many bytes (a long task's plans with motions are a
/// few MiB).
pub const MAX_PLAN_BYTES: u64 = 64 << 20;
/// A motion lasts at most this long, s.
const MAX_DURATION: f64 = 3600.0;

/// Where the world puts everything.
pub fn start_of(artifact: &Artifact, scene: Option<&Scene>, world: &World) -> Start {
    let objects = (0..artifact.objects.len())
        .map(|o| {
            let id = ObjectId(o as u32);
            match world.whereabouts(id) {
                cellc_runtime::Whereabouts::Absent => None,
                cellc_runtime::Whereabouts::Placed { state, pose } => {
                    match scene.and_then(|s| s.holders.get(state.end_effector.index())) {
                        Some(Holder::Arm { .. }) => Some(Whereabouts::Held(
                            state.end_effector,
                            artifact.grasp_pose(id, state.grasp),
                        )),
                        _ => world
                            .pose(artifact, scene, id)
                            .or(*pose)
                            .map(Whereabouts::Lying),
                    }
                }
            }
        })
        .collect();
    Start {
        arms: world.arms().to_vec(),
        objects,
    }
}

fn step_text(artifact: &Artifact, object: ObjectId, step: &StepIn, workspace: &str) -> String {
    let holder = artifact.end_effector_name(step.holder);
    let grasp = step.grasp.map(|g| artifact.grasp_name(object, g));
    match step.verb {
        Verb::Move => format!("{holder} carries it to {workspace}"),
        Verb::Grasp => format!(
            "{holder} takes it with {} in {workspace}",
            grasp.unwrap_or("?")
        ),
        Verb::Ungrasp => format!("{holder} lets go of {}", grasp.unwrap_or("?")),
    }
}

fn holders_of(plan_states: impl Iterator<Item = EndEffectorId>) -> Vec<EndEffectorId> {
    let mut out: Vec<EndEffectorId> = Vec::new();
    for e in plan_states {
        if out.last() != Some(&e) {
            out.push(e);
        }
    }
    out
}

/// Why a plan document is refused, as an R0011 diagnostic.
pub fn refused(path: &str, what: String) -> Diagnostic {
    Diagnostic::error(
        codes::PLAN_DOCUMENT,
        format!("`{}`: {what}", crate::render::escape(path)),
    )
    .help("give the output of `cellc plan CELL --format json` for this cell (docs/view.md)")
}

/// The plans of a document, and where their objects start.
pub type PlansAndStarts = (Vec<PlanIn>, Vec<(ObjectId, Whereabouts)>);

/// Reads a plan document and checks it against the cell.
pub fn read(
    artifact: &Artifact,
    scene: Option<&Scene>,
    path: &str,
) -> Result<PlansAndStarts, Diagnostic> {
    let bytes = FsFiles
        .read_at_most(path, MAX_PLAN_BYTES)
        .map_err(|e| refused(path, format!("cannot be read: {e}")))?;
    let doc: Run = serde_json::from_slice(&bytes).map_err(|e| {
        refused(
            path,
            format!(
                "not a plan document: {}",
                crate::render::escape(&e.to_string())
            ),
        )
    })?;
    if doc.kind != Kind::Plan {
        return Err(refused(
            path,
            "a document of kind `run`, not `plan`".to_string(),
        ));
    }
    if doc.plans.is_empty() {
        return Err(refused(path, "holds no plan".to_string()));
    }
    let mut plans = Vec::new();
    let mut starts = Vec::new();
    for (i, p) in doc.plans.iter().enumerate() {
        let at = |what: String| refused(path, format!("plan {}: {what}", i + 1));
        let (plan, start) = plan_of(artifact, scene, p).map_err(at)?;
        starts.push(start);
        plans.push(plan);
    }
    Ok((plans, starts.into_iter().flatten().collect()))
}

fn name_of(kind: &str, name: &str) -> String {
    format!("no {kind} `{}` in this cell", crate::render::escape(name))
}

fn ee_of(artifact: &Artifact, name: &str) -> Result<EndEffectorId, String> {
    artifact
        .end_effectors
        .iter()
        .position(|e| e.name == name)
        .map(|i| EndEffectorId(i as u32))
        .ok_or_else(|| name_of("end-effector", name))
}

fn workspace_of(artifact: &Artifact, name: &str) -> Result<WorkspaceId, String> {
    artifact
        .workspaces
        .iter()
        .position(|w| w.name == name)
        .map(|i| WorkspaceId(i as u32))
        .ok_or_else(|| name_of("workspace", name))
}

fn grasp_of(artifact: &Artifact, o: ObjectId, name: &str) -> Result<GraspId, String> {
    artifact.objects[o.index()]
        .grasps
        .iter()
        .position(|g| g.name == name)
        .map(|i| GraspId(i as u32))
        .ok_or_else(|| name_of("grasp", name))
}

/// Joints of arm `e` from a document: its chain's length, finite, within limits.
fn joints_of(scene: Option<&Scene>, e: EndEffectorId, q: &[f64]) -> Result<Vec<f64>, String> {
    let Some(scene) = scene else {
        return Err("joints given in a cell without robots".to_string());
    };
    let Some(Holder::Arm { robot, .. }) = scene.holders.get(e.index()) else {
        return Err("joints given for an end-effector that is not an arm".to_string());
    };
    let model = &scene.robots[*robot];
    if q.len() != model.n_joints() {
        return Err(format!(
            "{} joint values for an arm of {} joints",
            q.len(),
            model.n_joints()
        ));
    }
    let (lower, upper) = model.limits();
    for (j, v) in q.iter().enumerate() {
        if !v.is_finite() || *v < lower[j] - 1e-6 || *v > upper[j] + 1e-6 {
            return Err(format!(
                "joint `{}` at {v}, outside its limits",
                model.joint_names()[j]
            ));
        }
    }
    Ok(q.to_vec())
}

fn pose_of(p: &PoseDoc) -> Result<Iso, String> {
    let [x, y, z] = p.position;
    let [qx, qy, qz, qw] = p.rotation;
    let all = [x, y, z, qx, qy, qz, qw];
    if all.iter().any(|v| !v.is_finite() || v.abs() > 1e6) {
        return Err("a pose with a number that is not finite or too large".to_string());
    }
    let q = parry3d_f64::na::Quaternion::new(qw, qx, qy, qz);
    if (q.norm() - 1.0).abs() > 1e-3 {
        return Err("a pose whose rotation is not a unit quaternion".to_string());
    }
    Ok(Iso::from_parts(
        Vec3::new(x, y, z).into(),
        Quat::from_quaternion(q),
    ))
}

type PlanAndStart = (PlanIn, Option<(ObjectId, Whereabouts)>);

/// A plan document checked against the cell, in the page's form, and where its object
/// starts. Plans planned now come this way too (through
/// [`cellc_driver::document::plan::Plan::of`]), so there is one reading of a plan.
pub fn plan_of(
    artifact: &Artifact,
    scene: Option<&Scene>,
    p: &PlanDoc,
) -> Result<PlanAndStart, String> {
    let object = artifact
        .objects
        .iter()
        .position(|o| o.name == p.object)
        .map(|i| ObjectId(i as u32))
        .ok_or_else(|| name_of("object", &p.object))?;
    let mut steps = Vec::new();
    let mut start_arms: Vec<Option<Vec<f64>>> = vec![None; artifact.end_effectors.len()];
    for (k, s) in p.steps.iter().enumerate() {
        let at = |e: String| format!("step {}: {e}", k + 1);
        let verb = match s.command {
            StepCommand::Move => Verb::Move,
            StepCommand::Grasp => Verb::Grasp,
            StepCommand::Ungrasp => Verb::Ungrasp,
        };
        let holder = ee_of(artifact, &s.end_effector).map_err(at)?;
        let grasp = match &s.grasp {
            Some(g) => Some(grasp_of(artifact, object, g).map_err(at)?),
            None => None,
        };
        let workspace = workspace_of(artifact, &s.workspace).map_err(at)?;
        let pose = s.object.as_ref().map(pose_of).transpose().map_err(at)?;
        let mut configurations = Vec::new();
        for c in &s.configurations {
            let e = ee_of(artifact, &c.arm).map_err(at)?;
            configurations.push((e, joints_of(scene, e, &c.positions).map_err(at)?));
        }
        let motion = match &s.motion {
            Some(m) => {
                let arms: Vec<EndEffectorId> = m
                    .arms
                    .iter()
                    .map(|a| ee_of(artifact, &a.arm))
                    .collect::<Result<_, _>>()
                    .map_err(at)?;
                let mut points = Vec::new();
                let mut last = 0.0;
                for pt in &m.points {
                    if !pt.time_from_start.is_finite()
                        || pt.time_from_start < last
                        || pt.time_from_start > MAX_DURATION
                    {
                        return Err(at(format!(
                            "motion time {} out of order or beyond {MAX_DURATION} s",
                            pt.time_from_start
                        )));
                    }
                    last = pt.time_from_start;
                    // Each arm's share of the point, checked against its chain.
                    let mut offset = 0;
                    for &e in &arms {
                        let n = match scene.map(|s| (s, s.holders.get(e.index()))) {
                            Some((s, Some(Holder::Arm { robot, .. }))) => {
                                s.robots[*robot].n_joints()
                            }
                            _ => {
                                return Err(at(
                                    "a motion of an end-effector that is not an arm".into()
                                ))
                            }
                        };
                        let part = pt.positions.get(offset..offset + n).ok_or_else(|| {
                            at("a motion point shorter than its arms' joints".to_string())
                        })?;
                        let q = joints_of(scene, e, part).map_err(at)?;
                        if start_arms[e.index()].is_none() {
                            start_arms[e.index()] = Some(q);
                        }
                        offset += n;
                    }
                    if offset != pt.positions.len() {
                        return Err(at("a motion point longer than its arms' joints".into()));
                    }
                    points.push((pt.time_from_start, pt.positions.clone()));
                }
                Some((arms, points))
            }
            None => None,
        };
        let mut step = StepIn {
            verb,
            holder,
            grasp,
            workspace,
            object: pose,
            configurations,
            motion,
            text: String::new(),
        };
        step.text = step_text(artifact, object, &step, &s.workspace);
        steps.push(step);
    }
    let states: Vec<Node> = p
        .states
        .iter()
        .map(|s| {
            Ok(Node {
                end_effector: ee_of(artifact, &s.end_effector)?,
                grasp: grasp_of(artifact, object, &s.grasp)?,
                workspace: workspace_of(artifact, &s.workspace)?,
            })
        })
        .collect::<Result<_, String>>()?;
    // Where the object starts: in the first state's hand, or where the first command that
    // states a pose finds it.
    let start = match states.first() {
        Some(&Node {
            end_effector: e,
            grasp: g,
            ..
        }) if matches!(
            scene.and_then(|s| s.holders.get(e.index())),
            Some(Holder::Arm { .. })
        ) =>
        {
            Some((object, Whereabouts::Held(e, artifact.grasp_pose(object, g))))
        }
        _ => steps
            .iter()
            .find_map(|s| s.object)
            .map(|p| (object, Whereabouts::Lying(p))),
    };
    let label = p.request.clone();
    Ok((
        PlanIn {
            label,
            object,
            start_arms,
            holders: holders_of(states.iter().map(|s| s.end_effector)),
            first: states.first().copied(),
            steps,
        },
        start,
    ))
}
