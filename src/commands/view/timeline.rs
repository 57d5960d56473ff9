//! Plans as frames: every trajectory sampled at a fixed rate, forward kinematics of each
//! sample giving every link's world pose, the object following whichever arm holds it (or
//! lying where it was put down). The page only interpolates between neighbouring frames,
//! so what it shows is the runtime's kinematics, not a re-implementation in JavaScript.

use cellc_runtime::math::Iso;
use cellc_runtime::scene::{Holder, Scene};
use cellc_runtime::world::held_pose;
use cellc_schema::{Artifact, EndEffectorId, GraspId, Node, ObjectId, WorkspaceId};
use serde::Serialize;

use super::geometry::{pose, round, Built};

/// Time between frames, s (25 frames a second).
pub const DT: f64 = 0.04;
/// How long a step without a motion is shown, s.
const PAUSE: f64 = 0.4;
/// Frames at most in one page (about 13 minutes of motion, a page of some 40 MiB for two
/// 7-joint arms): a longer plan is cut there, and the page says so.
pub const MAX_FRAMES: usize = 20_000;

/// What a step does, as the page names it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Verb {
    /// Carry the object to another workspace.
    Move,
    /// Take hold.
    Grasp,
    /// Let go.
    Ungrasp,
}

/// One step of a plan, from a runtime plan or a plan file.
#[derive(Clone, Debug)]
pub struct StepIn {
    /// The command.
    pub verb: Verb,
    /// Its end-effector.
    pub holder: EndEffectorId,
    /// The grasp taken or given up.
    pub grasp: Option<GraspId>,
    /// The workspace it happens in.
    pub workspace: WorkspaceId,
    /// The object's pose the command states.
    pub object: Option<Iso>,
    /// Arms' joints at the end of the step.
    pub configurations: Vec<(EndEffectorId, Vec<f64>)>,
    /// The motion before the command: the arms in joint order, and (time, joints) points.
    pub motion: Option<Motion>,
    /// The step in words.
    pub text: String,
}

/// One plan.
#[derive(Clone, Debug)]
pub struct PlanIn {
    /// What it is called (the request, "move 2 of 3").
    pub label: String,
    /// Its object.
    pub object: ObjectId,
    /// Arms' joints where the plan starts (`None`: unchanged).
    pub start_arms: Vec<Option<Vec<f64>>>,
    /// The holders in order.
    pub holders: Vec<EndEffectorId>,
    /// The object's state before the first step.
    pub first: Option<Node>,
    /// Its steps.
    pub steps: Vec<StepIn>,
}

/// Where everything is at the start.
#[derive(Clone, Debug)]
pub struct Start {
    /// Every end-effector's joints (`None`: not an arm).
    pub arms: Vec<Option<Vec<f64>>>,
    /// Per object: held by an arm (and the object's pose in its tip frame), or lying at a
    /// pose, or absent (`None`).
    pub objects: Vec<Option<Whereabouts>>,
}

/// Where one object is.
#[derive(Clone, Debug)]
pub enum Whereabouts {
    /// In an arm's hand: the object's pose in the tip frame.
    Held(EndEffectorId, Iso),
    /// At a pose in the cell.
    Lying(Iso),
}

/// The poses of the moving bodies (one per entry of [`Timeline::moving`], `None` for an
/// absent object), as `[x, y, z, qx, qy, qz, qw]`.
pub type Poses = Vec<Option<[f64; 7]>>;

/// A joint motion: the arms in joint order, and (time, concatenated joints) points.
pub type Motion = (Vec<EndEffectorId>, Vec<(f64, Vec<f64>)>);

/// A frame: a time, the step shown, and the pose of every moving body.
#[derive(Serialize)]
pub struct Frame {
    /// Time, s.
    pub t: f64,
    /// Index into [`Timeline::steps`] (`None` before the first).
    pub step: Option<usize>,
    /// One pose per entry of [`Timeline::moving`]; `None` for an absent object.
    pub poses: Poses,
}

/// A step as the timeline lists it.
#[derive(Serialize)]
pub struct StepOut {
    /// Index into [`Timeline::plans`].
    pub plan: usize,
    /// The command.
    pub verb: Verb,
    /// Its end-effector.
    pub holder: String,
    /// In words.
    pub text: String,
    /// The object's state once it is done (index into its graph's nodes), when a state
    /// of the graph.
    pub state: Option<usize>,
    /// When it starts and ends, s.
    pub start: f64,
    /// End, s.
    pub end: f64,
}

/// A plan as the timeline lists it.
#[derive(Serialize)]
pub struct PlanOut {
    /// Its name.
    pub label: String,
    /// Its object.
    pub object: String,
    /// The holder chain.
    pub holders: Vec<String>,
    /// Its object's state at the start (index into the graph's nodes).
    pub first: Option<usize>,
}

/// Everything that moves, over time.
#[derive(Serialize)]
pub struct Timeline {
    /// The bodies whose poses the frames give (indices into the geometry's bodies).
    pub moving: Vec<usize>,
    /// Frames in time order; the first is the start.
    pub frames: Vec<Frame>,
    /// Plans.
    pub plans: Vec<PlanOut>,
    /// Steps.
    pub steps: Vec<StepOut>,
    /// Frames were cut at [`MAX_FRAMES`].
    pub truncated: bool,
}

/// The moving bodies, in the order of every frame's poses.
pub fn moving(built: &Built) -> Vec<usize> {
    let mut out = Vec::new();
    for arm in &built.arms {
        out.extend(&arm.frames);
        out.extend(arm.hand);
    }
    out.extend(&built.objects);
    out
}

/// Poses of the moving bodies with the arms at `arms` and the objects where `objects` say.
pub fn poses(
    built: &Built,
    scene: Option<&Scene>,
    arms: &[Option<Vec<f64>>],
    objects: &[Option<Whereabouts>],
) -> Poses {
    let mut out = Vec::new();
    let mut frames = Vec::new();
    for arm in built.arms.iter().filter(|_| scene.is_some()) {
        let Some(model) = scene.and_then(|s| s.robots.get(arm.robot)) else {
            continue;
        };
        let q = arms
            .get(arm.end_effector.index())
            .and_then(|q| q.as_ref())
            .filter(|q| q.len() == model.n_joints());
        match q {
            Some(q) => {
                model.fk_frames(&arm.base, q, &mut frames);
                out.extend(frames.iter().map(|f| Some(pose(f))));
                if arm.hand.is_some() {
                    let last = frames.last().copied().unwrap_or(arm.base);
                    out.push(Some(pose(&(last * model.tip_offset()))));
                }
            }
            None => {
                out.extend(arm.frames.iter().map(|_| None));
                out.extend(arm.hand.map(|_| None));
            }
        }
    }
    for w in objects.iter().take(built.objects.len()) {
        let p = match w {
            Some(Whereabouts::Held(e, local)) => arms
                .get(e.index())
                .and_then(|q| q.as_deref())
                .and_then(|q| held_pose(scene?, *e, q, local)),
            Some(Whereabouts::Lying(p)) => Some(*p),
            None => None,
        };
        out.push(p.as_ref().map(pose));
    }
    out
}

/// Joints of a trajectory at time `t`, by its points' `time_from_start`: linear between
/// them, which on screen is the planned motion, since its points are the time
/// parameterisation's knots (at most [`MotionOptions::grid_step`] of the path apart) or
/// a control rate's samples; the simulator holds the same points to the joints' limits
/// by the cubic a controller follows. Points are in time order (the planner's, and a plan
/// document's checked), so the point after `t` is found by bisection.
///
/// [`MotionOptions::grid_step`]: cellc_runtime::motion::MotionOptions::grid_step
fn sample(points: &[(f64, Vec<f64>)], t: f64) -> Option<Vec<f64>> {
    let after = points.partition_point(|(s, _)| *s < t);
    match (after < points.len()).then_some(after) {
        Some(0) => points.first().map(|p| p.1.clone()),
        Some(i) => {
            let (t0, a) = &points[i - 1];
            let (t1, b) = &points[i];
            let f = if t1 > t0 { (t - t0) / (t1 - t0) } else { 1.0 };
            Some(a.iter().zip(b).map(|(x, y)| x + (y - x) * f).collect())
        }
        None => points.last().map(|p| p.1.clone()),
    }
}

/// The arms' joints from a trajectory's concatenated point.
fn spread(scene: Option<&Scene>, arms: &[EndEffectorId], q: &[f64], into: &mut [Option<Vec<f64>>]) {
    let Some(scene) = scene else {
        return;
    };
    let mut at = 0;
    for e in arms {
        let Some(Holder::Arm { robot, .. }) = scene.holders.get(e.index()) else {
            return;
        };
        let n = scene.robots[*robot].n_joints();
        let Some(part) = q.get(at..at + n) else {
            return;
        };
        if let Some(slot) = into.get_mut(e.index()) {
            *slot = Some(part.to_vec());
        }
        at += n;
    }
}

/// The object's pose now (from its arm or where it lies).
fn object_pose(scene: Option<&Scene>, arms: &[Option<Vec<f64>>], w: &Whereabouts) -> Option<Iso> {
    match w {
        Whereabouts::Held(e, local) => arms
            .get(e.index())
            .and_then(|q| q.as_deref())
            .and_then(|q| held_pose(scene?, *e, q, local)),
        Whereabouts::Lying(p) => Some(*p),
    }
}

/// The timeline of `plans` from `start`.
pub fn timeline(
    artifact: &Artifact,
    scene: Option<&Scene>,
    built: &Built,
    start: &Start,
    plans: &[PlanIn],
) -> Timeline {
    let mut arms = start.arms.clone();
    let mut objects = start.objects.clone();
    let mut frames = vec![Frame {
        t: 0.0,
        step: None,
        poses: poses(built, scene, &arms, &objects),
    }];
    let mut steps = Vec::new();
    let mut plans_out = Vec::new();
    let mut t = 0.0;
    let mut truncated = false;
    let is_arm = |e: EndEffectorId| {
        matches!(
            scene.and_then(|s| s.holders.get(e.index())),
            Some(Holder::Arm { .. })
        )
    };
    'plans: for (p, plan) in plans.iter().enumerate() {
        plans_out.push(PlanOut {
            label: plan.label.clone(),
            object: artifact.object_name(plan.object).to_string(),
            holders: plan
                .holders
                .iter()
                .map(|&e| artifact.end_effector_name(e).to_string())
                .collect(),
            first: plan.first.and_then(|n| {
                artifact
                    .objects
                    .get(plan.object.index())
                    .and_then(|x| x.graph.nodes.iter().position(|m| *m == n))
            }),
        });
        for (e, q) in plan.start_arms.iter().enumerate() {
            if let (Some(q), Some(slot)) = (q, arms.get_mut(e)) {
                *slot = Some(q.clone());
            }
        }
        let o = plan.object.index();
        // Holders of the plan's object other than the one the world records: a handoff
        // has two at once until the giver lets go.
        let mut also: Vec<(EndEffectorId, Iso)> = Vec::new();
        // The states the object is in, one per holder while two hold it.
        let mut held: Vec<Node> = plan.first.into_iter().collect();
        let nodes = artifact
            .objects
            .get(o)
            .map(|x| x.graph.nodes.as_slice())
            .unwrap_or_default();
        for step in &plan.steps {
            match step.verb {
                Verb::Grasp => held.extend(step.grasp.map(|grasp| Node {
                    end_effector: step.holder,
                    grasp,
                    workspace: step.workspace,
                })),
                Verb::Move => {
                    for n in held.iter_mut().filter(|n| n.end_effector == step.holder) {
                        n.workspace = step.workspace;
                    }
                }
                Verb::Ungrasp => held.retain(|n| n.end_effector != step.holder),
            }
            let state = held.last().and_then(|n| nodes.iter().position(|m| m == n));
            let index = steps.len();
            let begin = t;
            if let Some((moving, points)) = &step.motion {
                let duration = points.last().map_or(0.0, |p| p.0).max(0.0);
                let n = (duration / DT).ceil() as usize;
                for k in 1..=n.max(1) {
                    if frames.len() >= MAX_FRAMES {
                        truncated = true;
                        break 'plans;
                    }
                    let s = (k as f64 * DT).min(duration);
                    if let Some(q) = sample(points, s) {
                        spread(scene, moving, &q, &mut arms);
                    }
                    frames.push(Frame {
                        t: round(begin + s),
                        step: Some(index),
                        poses: poses(built, scene, &arms, &objects),
                    });
                }
                t = begin + duration.max(DT);
            }
            for (e, q) in &step.configurations {
                if let Some(slot) = arms.get_mut(e.index()) {
                    *slot = Some(q.clone());
                }
            }
            let now = objects
                .get(o)
                .and_then(|w| w.as_ref())
                .and_then(|w| object_pose(scene, &arms, w))
                .or(step.object);
            match step.verb {
                Verb::Move => {}
                Verb::Grasp => {
                    let local = step.grasp.map(|g| artifact.grasp_pose(plan.object, g));
                    if let (true, Some(local)) = (is_arm(step.holder), local) {
                        let held = Whereabouts::Held(step.holder, local);
                        match objects.get(o).and_then(|w| w.as_ref()) {
                            // Already in another hand: both hold it until one lets go.
                            Some(Whereabouts::Held(..)) => also.push((step.holder, local)),
                            _ => objects[o] = Some(held),
                        }
                    } else if let Some(p) = step.object.or(now) {
                        // A surface takes it: it lies where the command says once the
                        // arm lets go.
                        if !matches!(
                            objects.get(o).and_then(|w| w.as_ref()),
                            Some(Whereabouts::Held(..))
                        ) {
                            objects[o] = Some(Whereabouts::Lying(p));
                        }
                    }
                }
                Verb::Ungrasp => {
                    also.retain(|(e, _)| *e != step.holder);
                    if let Some(Some(Whereabouts::Held(e, _))) = objects.get(o) {
                        if *e == step.holder {
                            objects[o] = match also.pop() {
                                Some((next, local)) => Some(Whereabouts::Held(next, local)),
                                None => step.object.or(now).map(Whereabouts::Lying),
                            };
                        }
                    }
                }
            }
            if step.motion.is_none() {
                t = begin + PAUSE;
            }
            if frames.len() >= MAX_FRAMES {
                truncated = true;
                break 'plans;
            }
            frames.push(Frame {
                t: round(t),
                step: Some(index),
                poses: poses(built, scene, &arms, &objects),
            });
            steps.push(StepOut {
                plan: p,
                verb: step.verb,
                holder: artifact.end_effector_name(step.holder).to_string(),
                text: step.text.clone(),
                state,
                start: round(begin),
                end: round(t),
            });
        }
    }
    Timeline {
        moving: moving(built),
        frames,
        plans: plans_out,
        steps,
        truncated,
    }
}
