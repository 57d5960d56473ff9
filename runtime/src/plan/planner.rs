//! The planner: Algorithm 1 on an artifact.
//!
//! Search, simplify, realise the commands, and on a failed step remove that arc and search
//! again. Realising reuses the build-time witnesses (an exchange in a workspace is the
//! same whatever the request), and solves specifically only what depends on the request:
//! picking the object where it actually is, and placing it where the goal says.

use std::collections::HashSet;

use cellc_schema::{ArcKind, Artifact, Infeasibility, Node};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use super::locate::{goal_states, locate, locate_abstract};
use super::search::{simplify, Path, SearchGraph};
use super::strategy::classify;
use super::{
    ArcRef, ArmConfigurations, Command, Plan, PlanError, PlanGoal, PlanOptions, Request, Step,
    Unreachable,
};
use crate::kinematics::{solve_ik, IkError, IkOptions, IkTarget};
use crate::math::{iso_from_schema, Iso};
use crate::motion::{MotionError, MotionPlanner, MotionProblem, RrtConnect};
use crate::rest::RestRegions;
use crate::scene::{Holder, ObjectPlacement, Scene, SceneScratch};
use crate::termination::Termination;
use crate::validity::{SceneValidity, StateFault, StateValidity};

/// IK settings for request-specific solves: each call is one of several attempts (other
/// symmetric grasps, other candidate poses), so a few restarts per call find reachable
/// poses while keeping unreachable ones cheap.
const SCREENING: IkOptions = IkOptions {
    max_iterations: 100,
    restarts: 6,
    position_tolerance: 1e-4,
    rotation_tolerance: 1e-3,
    damping: 0.1,
    max_step: 1.0,
};

/// Plans requests on one artifact. Cheap to keep: it holds the search graphs.
pub struct Planner<'a> {
    artifact: &'a Artifact,
    scene: Option<&'a Scene>,
    search: std::borrow::Cow<'a, [SearchGraph]>,
    /// Plans the joint motion of each command ([`RrtConnect`] unless replaced).
    motion_planner: Box<dyn MotionPlanner + Send + Sync + 'a>,
}

/// Where the plan stands while commands are realised.
#[derive(Clone, Debug)]
pub struct WorldState {
    /// Current joint values of every arm (index = end-effector).
    pub arms: Vec<Option<Vec<f64>>>,
    /// Current object pose, when known.
    pub object: Option<Iso>,
}

impl WorldState {
    /// Every arm at home, the object where given.
    pub fn at_home(
        scene: Option<&Scene>,
        n_end_effectors: usize,
        object: Option<Iso>,
    ) -> WorldState {
        let arms = (0..n_end_effectors)
            .map(|e| match scene.map(|s| &s.holders[e]) {
                Some(Holder::Arm { home, .. }) => Some(home.clone()),
                _ => None,
            })
            .collect();
        WorldState { arms, object }
    }
}

/// A step that could not be realised: the arc to remove and why.
struct Failure {
    arc: ArcRef,
    reason: Infeasibility,
}

impl<'a> Planner<'a> {
    /// A planner over an artifact; `scene` gives geometry (None: abstract cells, high level
    /// only).
    pub fn new(artifact: &'a Artifact, scene: Option<&'a Scene>) -> Planner<'a> {
        Planner {
            artifact,
            scene,
            search: std::borrow::Cow::Owned(SearchGraph::for_artifact(artifact)),
            motion_planner: Box::new(RrtConnect::default()),
        }
    }

    /// A planner that borrows search graphs built earlier (one per object, from
    /// [`SearchGraph::for_artifact`] on the same artifact), so a long-lived cell does not
    /// index its graphs again for every request.
    pub fn with_search(
        artifact: &'a Artifact,
        scene: Option<&'a Scene>,
        search: &'a [SearchGraph],
    ) -> Planner<'a> {
        Planner {
            artifact,
            scene,
            search: std::borrow::Cow::Borrowed(search),
            motion_planner: Box::new(RrtConnect::default()),
        }
    }

    /// The same planner with joint motions planned by `motion_planner`.
    pub fn with_motion_planner(
        mut self,
        motion_planner: impl MotionPlanner + Send + Sync + 'a,
    ) -> Planner<'a> {
        self.motion_planner = Box::new(motion_planner);
        self
    }

    /// The artifact planned on.
    pub fn artifact(&self) -> &'a Artifact {
        self.artifact
    }

    /// Plans a request from scratch (arms at home).
    pub fn plan(&self, request: &Request) -> Result<Plan, PlanError> {
        super::names::check_request(self.artifact, request).map_err(PlanError::Locate)?;
        let object = request.object.0;
        let scene = self.scene.filter(|s| s.has_kinematics());
        let start = match scene {
            Some(scene) => locate(
                self.artifact,
                scene,
                object,
                &request.start,
                &request.options,
            ),
            None => locate_abstract(self.artifact, object, &request.start),
        }
        .map_err(PlanError::Locate)?;
        let goals = goal_states(
            self.artifact,
            scene,
            object,
            &request.goal,
            &request.options,
        )
        .map_err(PlanError::Locate)?;
        let goal = PlanGoal {
            states: goals,
            pose: match &request.goal {
                super::Goal::Placement(p) => p.pose,
                super::Goal::Workspace { .. } => None,
            },
        };
        let state = WorldState::at_home(
            self.scene,
            self.artifact.end_effectors.len(),
            request.start.pose,
        );
        self.plan_from(object, start, &goal, state, &request.options)
    }

    /// Plans from a given state towards `goal` (used again when execution fails part way).
    pub fn plan_from(
        &self,
        object: u32,
        start: Node,
        goal: &PlanGoal,
        state: WorldState,
        options: &PlanOptions,
    ) -> Result<Plan, PlanError> {
        let goals = goal.states.as_slice();
        let goal_pose = goal.pose;
        let start_pose = state.object;
        let graph = &self.artifact.objects[object as usize].graph;
        let index_of = |n: &Node| graph.nodes.iter().position(|m| m == n).map(|i| i as u32);
        let start_index = index_of(&start);
        let goal_indices: Vec<u32> = goals.iter().filter_map(index_of).collect();
        let mut removed: HashSet<ArcRef> = HashSet::new();
        let mut failed: Vec<(ArcRef, Infeasibility)> = Vec::new();
        let unreachable = |removed: &HashSet<ArcRef>, failed: Vec<(ArcRef, Infeasibility)>| {
            PlanError::Unreachable(Box::new(Unreachable {
                object,
                start,
                goals: goals.to_vec(),
                reachable: start_index
                    .map(|s| self.search[object as usize].reachable(s, removed))
                    .unwrap_or_default(),
                failed,
            }))
        };
        let Some(start_index) = start_index else {
            return Err(unreachable(&removed, failed));
        };
        // When the goal is the start state but another pose (a pick-and-place within one
        // workspace), the object must leave the state and come back: at least one arc.
        let must_move = match (state.object, goal_pose) {
            (Some(a), Some(b)) => {
                let d = a.inverse() * b;
                d.translation.vector.norm() > options.position_tolerance
                    || d.rotation.angle() > options.rotation_tolerance
            }
            _ => false,
        };
        let mut backtracks = 0;
        // Checked between searches and inside every IK and motion search of this request.
        let mut stop = Termination::after(options.time_budget);
        if let Some(flag) = &options.cancel {
            stop = stop.with_cancel(flag.clone());
        }
        let reweighted = options
            .weights
            .map(|w| self.search[object as usize].reweighted(w));
        loop {
            if stop.should_stop() {
                return Err(PlanError::TimeBudget {
                    searches: backtracks,
                });
            }
            let search = reweighted.as_ref().unwrap_or(&self.search[object as usize]);
            let found = if must_move && goal_indices.contains(&start_index) {
                search.shortest_leaving(start_index, &goal_indices, &removed)
            } else {
                search.shortest(start_index, &goal_indices, &removed)
            };
            let Some(path) = found else {
                return Err(unreachable(&removed, failed));
            };
            let realised = self.realise(object, &path, goal_pose, &state, options, &stop);
            // A step decided by a search that was cut short is not the plan an unhurried
            // search would give: out of time, whatever came of it.
            if stop.fired() {
                return Err(PlanError::TimeBudget {
                    searches: backtracks + 1,
                });
            }
            match realised {
                Ok(steps) => {
                    let kept = simplify(graph, &path);
                    let states: Vec<Node> = kept.iter().map(|&i| graph.nodes[i as usize]).collect();
                    return Ok(Plan {
                        object,
                        start_pose,
                        goal: goal.clone(),
                        strategy: classify(self.artifact, &states),
                        states,
                        steps,
                        cost: path.cost,
                        backtracks,
                    });
                }
                Err(failure) => {
                    removed.insert(failure.arc);
                    failed.push((failure.arc, failure.reason));
                    backtracks += 1;
                    if backtracks > options.max_backtracks {
                        return Err(unreachable(&removed, failed));
                    }
                }
            }
        }
    }

    /// Turns a path into commands, or says which arc failed.
    fn realise(
        &self,
        object: u32,
        path: &Path,
        goal_pose: Option<Iso>,
        state: &WorldState,
        options: &PlanOptions,
        stop: &Termination,
    ) -> Result<Vec<Step>, Failure> {
        let graph = &self.artifact.objects[object as usize].graph;
        let kept = simplify(graph, path);
        // The arc that ends at each kept node (after the first): the last arc of a run of
        // moves, or the transition.
        let mut arc_into: Vec<usize> = Vec::new();
        let mut position = 0;
        for &k in &kept[1..] {
            while path.nodes[position + 1] != k {
                position += 1;
            }
            arc_into.push(path.arcs[position]);
            position += 1;
        }
        let mut rng =
            ChaCha8Rng::seed_from_u64(options.seed ^ u64::from(object).wrapping_mul(0x9E37_79B9));
        let state_at_start = state.clone();
        let mut state = state.clone();
        let mut steps = Vec::new();
        let n_transitions = arc_into
            .iter()
            .filter(|&&a| graph.arcs[a].kind == ArcKind::Transition)
            .count();
        let mut transitions_seen = 0;
        // Exchanges are computed first, so that a move can end where the next exchange
        // starts.
        // They are computed in order, following the object: a pick happens where the
        // object lies now (the start pose, or where an earlier step put it down).
        let mut exchanges: Vec<Option<Exchange>> = vec![None; arc_into.len()];
        let mut object_now = state.object;
        for (i, &a) in arc_into.iter().enumerate() {
            if graph.arcs[a].kind != ArcKind::Transition {
                continue;
            }
            transitions_seen += 1;
            let from = graph.nodes[graph.arcs[a].from as usize];
            let to = graph.nodes[graph.arcs[a].to as usize];
            let last = transitions_seen == n_transitions && i + 1 == arc_into.len();
            // A put-down followed by a pick from the same surface needs a resting pose
            // both arms reach: the two witnesses are tried, then sampled poses.
            let next_pick = arc_into[i + 1..]
                .iter()
                .find(|&&b| graph.arcs[b].kind == ArcKind::Transition)
                .filter(|&&b| {
                    graph.nodes[graph.arcs[b].from as usize].end_effector == to.end_effector
                })
                .copied();
            let shared_pose = match next_pick {
                Some(b) if !last => {
                    let picker = graph.nodes[graph.arcs[b].to as usize];
                    self.shared_rest_pose(object, (from, a), (picker, b), &mut rng, stop)
                }
                _ => None,
            };
            let place_at = if last { goal_pose } else { shared_pose };
            let exchange =
                match self.exchange(object, a, from, to, object_now, place_at, &mut rng, stop) {
                    Err(_) if !last && place_at.is_some() => {
                        self.exchange(object, a, from, to, object_now, None, &mut rng, stop)?
                    }
                    other => other?,
                };
            if exchange.object.is_some() {
                object_now = exchange.object;
            }
            exchanges[i] = Some(exchange);
        }
        for (i, &a) in arc_into.iter().enumerate() {
            let arc = &graph.arcs[a];
            let to = graph.nodes[arc.to as usize];
            match arc.kind {
                ArcKind::Move => {
                    // End where the next exchange needs the mover, or at the move's witness.
                    let (object_pose, configurations) =
                        match exchanges.get(i + 1).and_then(|e| e.clone()) {
                            Some(next) => (
                                next.object,
                                next.configurations
                                    .into_iter()
                                    .filter(|(e, _)| *e == to.end_effector)
                                    .collect(),
                            ),
                            None => self.witness_of(object, a),
                        };
                    apply(&mut state, &configurations, object_pose);
                    steps.push(Step {
                        command: Command::Move {
                            holder: to.end_effector,
                            workspace: to.workspace,
                            object: object_pose,
                            configurations,
                        },
                        motion: None,
                        arc: Some(ArcRef {
                            from: arc.from,
                            to: arc.to,
                        }),
                        motion_context: None,
                    });
                }
                ArcKind::Transition => {
                    let from = graph.nodes[arc.from as usize];
                    let Some(exchange) = exchanges[i].clone() else {
                        continue;
                    };
                    apply(&mut state, &exchange.configurations, exchange.object);
                    steps.push(Step {
                        command: Command::Grasp {
                            holder: to.end_effector,
                            grasp: to.grasp,
                            workspace: to.workspace,
                            object: exchange.object,
                            configurations: exchange.configurations.clone(),
                        },
                        motion: None,
                        arc: Some(ArcRef {
                            from: arc.from,
                            to: arc.to,
                        }),
                        motion_context: None,
                    });
                    steps.push(Step {
                        command: Command::Ungrasp {
                            holder: from.end_effector,
                            grasp: from.grasp,
                            workspace: from.workspace,
                            object: exchange.object,
                        },
                        motion: None,
                        arc: Some(ArcRef {
                            from: arc.from,
                            to: arc.to,
                        }),
                        motion_context: None,
                    });
                }
            }
        }
        if options.motions {
            let start = graph.nodes[path.nodes[0] as usize];
            self.add_motions(object, start, &mut steps, &state_at_start, &mut rng, stop)?;
        }
        Ok(steps)
    }

    /// Plans the joint motion that leads to each command: the arms whose configuration
    /// changes move together in their combined space, every other arm stands where it is,
    /// a held object travels with its hand, and an arm that lets go returns home. A motion
    /// that cannot be found fails the arc of its command, so the search tries another way.
    fn add_motions(
        &self,
        object: u32,
        start_state: Node,
        steps: &mut [Step],
        start: &WorldState,
        rng: &mut ChaCha8Rng,
        stop: &Termination,
    ) -> Result<(), Failure> {
        let Some(scene) = self.scene.filter(|s| s.has_kinematics()) else {
            return Ok(());
        };
        let obj = &self.artifact.objects[object as usize];
        let grasp_pose = |g: u32| {
            obj.grasps
                .get(g as usize)
                .and_then(|g| g.pose.as_ref())
                .map(iso_from_schema)
                .unwrap_or_else(Iso::identity)
        };
        let is_arm = |e: u32| matches!(scene.holders.get(e as usize), Some(Holder::Arm { .. }));
        let mut arms = start.arms.clone();
        let mut object_pose = start.object;
        // Who holds the object now, and with which grasp.
        let mut holder: Option<(u32, u32)> = Some((start_state.end_effector, start_state.grasp));
        let mut scratch = SceneScratch::default();
        // A carry begins where a pick left the object (still touching that surface) and
        // may end where a put-down needs it (touching the next one): at those ends the
        // object touches a surface, which the carry's checks must allow.
        let put_down_after: Vec<Option<u32>> = (0..steps.len())
            .map(|i| match steps.get(i + 1).map(|s| &s.command) {
                Some(Command::Grasp { holder, .. }) if !is_arm(*holder) => Some(*holder),
                _ => None,
            })
            .collect();
        // An arm that let go but could not retreat still has its hand on the object: the
        // next carry may touch it while it moves the object away.
        let mut lingering: Option<u32> = None;
        let mut lifted_from: Option<u32> =
            (!is_arm(start_state.end_effector)).then_some(start_state.end_effector);
        for (index, step) in steps.iter_mut().enumerate() {
            let (targets, placement, fail_arc) = match &step.command {
                Command::Move {
                    holder: e,
                    configurations,
                    object: pose,
                    ..
                } => {
                    let touching = lifted_from.take().or(put_down_after[index]);
                    let placement = match (holder, touching) {
                        (Some((_, g)), Some(surface)) if is_arm(*e) => ObjectPlacement::Placing {
                            by: *e,
                            grasp: grasp_pose(g),
                            on: surface,
                            also: lingering.filter(|l| l != e),
                        },
                        (Some((_, g)), None) if is_arm(*e) => match lingering.filter(|l| l != e) {
                            Some(l) => ObjectPlacement::Handoff {
                                a: *e,
                                grasp_a: grasp_pose(g),
                                b: l,
                            },
                            None => ObjectPlacement::Held {
                                by: *e,
                                grasp: grasp_pose(g),
                            },
                        },
                        _ => ObjectPlacement::Absent,
                    };
                    if pose.is_some() {
                        object_pose = *pose;
                    }
                    (configurations.clone(), placement, step_arc(step))
                }
                Command::Grasp {
                    holder: receiver,
                    grasp,
                    configurations,
                    object: pose,
                    ..
                } => {
                    // Before the exchange the object is where the giver has it; the
                    // receiver's hand reaches it at the end.
                    let placement = match (holder, pose.or(object_pose)) {
                        (Some((giver, g)), _) if is_arm(giver) && is_arm(*receiver) => {
                            ObjectPlacement::Handoff {
                                a: giver,
                                grasp_a: grasp_pose(g),
                                b: *receiver,
                            }
                        }
                        (Some((giver, g)), _) if is_arm(giver) => ObjectPlacement::Placing {
                            by: giver,
                            grasp: grasp_pose(g),
                            on: *receiver,
                            also: lingering.filter(|l| *l != giver),
                        },
                        (Some((giver, _)), Some(p)) => ObjectPlacement::Resting {
                            on: giver,
                            pose: p,
                            by: is_arm(*receiver).then_some(*receiver),
                        },
                        _ => ObjectPlacement::Absent,
                    };
                    if pose.is_some() {
                        object_pose = *pose;
                    }
                    let targets = configurations.clone();
                    // Taken from a surface: the next carry starts touching it.
                    lifted_from = match holder {
                        Some((giver, _)) if !is_arm(giver) && is_arm(*receiver) => Some(giver),
                        _ => None,
                    };
                    holder = Some((*receiver, *grasp));
                    (targets, placement, step_arc(step))
                }
                Command::Ungrasp { holder: giver, .. } => {
                    // The arm that let go returns home, around the object's new holder.
                    if !is_arm(*giver) {
                        continue;
                    }
                    let Holder::Arm { home, .. } = &scene.holders[*giver as usize] else {
                        continue;
                    };
                    // It starts with its hand on the object it just let go of: that contact
                    // is allowed while it leaves.
                    let placement = match (holder, object_pose) {
                        (Some((now, g)), _) if is_arm(now) => ObjectPlacement::Handoff {
                            a: now,
                            grasp_a: grasp_pose(g),
                            b: *giver,
                        },
                        (Some((now, _)), Some(p)) => ObjectPlacement::Resting {
                            on: now,
                            pose: p,
                            by: Some(*giver),
                        },
                        _ => ObjectPlacement::Absent,
                    };
                    (vec![(*giver, home.clone())], placement, None)
                }
            };
            let moving: Vec<(u32, Vec<f64>, Vec<f64>)> = targets
                .iter()
                .filter(|(e, _)| is_arm(*e))
                .filter_map(|(e, goal)| {
                    let now = arms.get(*e as usize)?.clone()?;
                    let changes = now.iter().zip(goal).any(|(a, b)| (a - b).abs() > 1e-9);
                    changes.then(|| (*e, now, goal.clone()))
                })
                .collect();
            if moving.is_empty() {
                continue;
            }
            let stationary: Vec<(u32, Vec<f64>)> = arms
                .iter()
                .enumerate()
                .filter_map(|(e, q)| Some((e as u32, q.clone()?)))
                .filter(|(e, _)| !moving.iter().any(|m| m.0 == *e))
                .collect();
            let moving_arms: Vec<u32> = moving.iter().map(|m| m.0).collect();
            let from: Vec<f64> = moving.iter().flat_map(|m| m.1.iter().copied()).collect();
            let to: Vec<f64> = moving.iter().flat_map(|m| m.2.iter().copied()).collect();
            let motion = SceneValidity::new(scene, &moving_arms, &stationary, object, placement)
                .map_err(MotionError::from)
                .and_then(|validity| {
                    let problem = MotionProblem {
                        scene,
                        arms: &moving_arms,
                        start: &from,
                        goal: &to,
                        validity: &validity,
                    };
                    self.motion_planner.solve(&problem, rng, stop, &mut scratch)
                });
            match motion {
                Ok(trajectory) => {
                    for (e, _, goal) in &moving {
                        arms[*e as usize] = Some(goal.clone());
                    }
                    if !matches!(step.command, Command::Ungrasp { .. }) {
                        lingering = None;
                    }
                    step.motion = Some(trajectory);
                    step.motion_context = Some(super::MotionContext {
                        stationary,
                        placement,
                    });
                }
                Err(error) => {
                    // A retreat that cannot be planned leaves the arm where it is.
                    let Some(arc) = fail_arc else {
                        if let Command::Ungrasp { holder: giver, .. } = &step.command {
                            lingering = Some(*giver);
                        }
                        continue;
                    };
                    return Err(Failure {
                        arc,
                        reason: Infeasibility::NoPlacement {
                            detail: format!("{}: {error}", super::NO_MOTION),
                        },
                    });
                }
            }
        }
        Ok(())
    }

    /// A resting pose on the surface between a put-down (`giver`, arc `put`) and a pick
    /// (`picker`, arc `pick`) that both arms reach collision-free with their grasps.
    fn shared_rest_pose(
        &self,
        object: u32,
        giver: (Node, usize),
        picker: (Node, usize),
        rng: &mut ChaCha8Rng,
        stop: &Termination,
    ) -> Option<Iso> {
        let scene = self.scene.filter(|s| s.has_kinematics())?;
        let graph = &self.artifact.objects[object as usize].graph;
        let (giver, put) = giver;
        let (picker, pick) = picker;
        let rest_node = graph.nodes[graph.arcs[put].to as usize];
        let Holder::Surface { slab, .. } = &scene.holders[rest_node.end_effector as usize] else {
            return None;
        };
        let obj = &self.artifact.objects[object as usize];
        let pose_of = |g: u32| {
            obj.grasps[g as usize]
                .pose
                .as_ref()
                .map(iso_from_schema)
                .unwrap_or_else(Iso::identity)
        };
        let rest = pose_of(rest_node.grasp);
        let turns = crate::symmetry::candidates(&obj.symmetries);
        let works = |pose: &Iso, rng: &mut ChaCha8Rng| -> bool {
            [giver, picker].iter().all(|arm| {
                let Holder::Arm { robot, base, home } = &scene.holders[arm.end_effector as usize]
                else {
                    return false;
                };
                // Either arm may hold a symmetric object with its grasp turned.
                // Many candidates are screened, so each gets a few restarts only.
                let found = turns.iter().find_map(|turn| {
                    let tip = pose * (pose_of(arm.grasp) * turn).inverse();
                    solve_ik(
                        &scene.robots[*robot],
                        base,
                        &IkTarget::Pose(tip),
                        home,
                        rng,
                        &SCREENING,
                        stop,
                    )
                    .ok()
                });
                let Some(q) = found else {
                    return false;
                };
                let placement = ObjectPlacement::Resting {
                    on: rest_node.end_effector,
                    pose: *pose,
                    by: Some(arm.end_effector),
                };
                SceneValidity::new(scene, &[arm.end_effector], &[], object, placement)
                    .is_ok_and(|v| matches!(v.is_valid(&q, &mut SceneScratch::default()), Ok(true)))
            })
        };
        let witnessed = [
            self.witness_of(object, pick).0,
            self.witness_of(object, put).0,
        ];
        for pose in witnessed.into_iter().flatten() {
            if works(&pose, rng) {
                return Some(pose);
            }
        }
        // Sampled resting poses: anywhere on the top face with the centre in the workspace.
        let workspace = &scene.workspaces[rest_node.workspace as usize];
        let regions = RestRegions::new(slab, workspace, &rest);
        for _ in 0..100 {
            if stop.should_stop() {
                return None;
            }
            let pose = regions.sample(rng)?;
            if works(&pose, rng) {
                return Some(pose);
            }
        }
        None
    }

    /// The object pose and arm configurations of a witnessed arc.
    fn witness_of(&self, object: u32, arc: usize) -> (Option<Iso>, ArmConfigurations) {
        let graph = &self.artifact.objects[object as usize].graph;
        match graph.arcs[arc]
            .witness
            .and_then(|w| graph.witnesses.get(w as usize))
        {
            Some(w) => (
                Some(iso_from_schema(&w.object)),
                w.configurations
                    .iter()
                    .map(|c| (c.end_effector, c.joints.clone()))
                    .collect(),
            ),
            None => (None, Vec::new()),
        }
    }

    /// How a transition arc is carried out: from its witness, except a first pick (the
    /// object is where the request says) and a last place (where the goal says), which are
    /// solved for this request.
    #[allow(clippy::too_many_arguments)]
    fn exchange(
        &self,
        object: u32,
        arc: usize,
        from: Node,
        to: Node,
        lying_at: Option<Iso>,
        place_at: Option<Iso>,
        rng: &mut ChaCha8Rng,
        stop: &Termination,
    ) -> Result<Exchange, Failure> {
        let graph = &self.artifact.objects[object as usize].graph;
        let arc_ref = ArcRef {
            from: graph.arcs[arc].from,
            to: graph.arcs[arc].to,
        };
        let Some(scene) = self.scene.filter(|s| s.has_kinematics()) else {
            return Ok(Exchange::default());
        };
        let surface_and_arm = match (
            &scene.holders[from.end_effector as usize],
            &scene.holders[to.end_effector as usize],
        ) {
            (Holder::Surface { .. }, Holder::Arm { .. }) => Some((from, to)),
            (Holder::Arm { .. }, Holder::Surface { .. }) => Some((to, from)),
            _ => None,
        };
        let specific_pose = match (surface_and_arm, lying_at, place_at) {
            (Some((surface, _)), Some(pose), _) if surface == from => Some(pose),
            (Some((surface, _)), _, Some(goal)) if surface == to => Some(goal),
            _ => None,
        };
        if let (Some((surface, arm)), Some(pose)) = (surface_and_arm, specific_pose) {
            let obj = &self.artifact.objects[object as usize];
            let grasp = obj.grasps[arm.grasp as usize]
                .pose
                .as_ref()
                .map(iso_from_schema)
                .unwrap_or_else(Iso::identity);
            let Holder::Arm { robot, base, home } = &scene.holders[arm.end_effector as usize]
            else {
                return Err(Failure {
                    arc: arc_ref,
                    reason: Infeasibility::NoPlacement {
                        detail: "not an arm".into(),
                    },
                });
            };
            let robot = &scene.robots[*robot];
            // A symmetric object may be taken with the grasp turned by a symmetry.
            let turns = crate::symmetry::candidates(&obj.symmetries);
            let mut last_collision = None;
            let mut best: Option<IkError> = None;
            let mut scratch = SceneScratch::default();
            for attempt in 0..8 {
                if stop.should_stop() {
                    break;
                }
                let tip = pose * (grasp * turns[attempt % turns.len()]).inverse();
                match solve_ik(
                    robot,
                    base,
                    &IkTarget::Pose(tip),
                    home,
                    rng,
                    &SCREENING,
                    stop,
                ) {
                    Ok(q) => {
                        let placement = ObjectPlacement::Resting {
                            on: surface.end_effector,
                            pose,
                            by: Some(arm.end_effector),
                        };
                        let checked =
                            SceneValidity::new(scene, &[arm.end_effector], &[], object, placement)
                                .map_err(|e| format!("{e:?}"))
                                .and_then(|v| {
                                    v.check(&q, &mut scratch).map_err(|e| format!("{e:?}"))
                                });
                        match checked {
                            Ok(None) => {
                                return Ok(Exchange {
                                    object: Some(pose),
                                    configurations: vec![(arm.end_effector, q)],
                                })
                            }
                            Ok(Some(StateFault::Collision { a, b })) => {
                                last_collision = Some((a, b))
                            }
                            Ok(Some(fault)) => {
                                last_collision = Some(("joint limits".into(), fault.to_string()))
                            }
                            Err(e) => last_collision = Some(("collision query".into(), e)),
                        }
                    }
                    Err(e) => best = Some(e),
                }
            }
            let reason = match (last_collision, best) {
                (Some((a, b)), _) => Infeasibility::Collision { a, b },
                (
                    None,
                    Some(IkError::NotConverged {
                        tries,
                        position_error,
                        rotation_error,
                    }),
                ) => Infeasibility::NoIkSolution {
                    end_effector: arm.end_effector,
                    tries: tries as u32,
                    position_error,
                    rotation_error,
                },
                _ => Infeasibility::NoPlacement {
                    detail: "no configuration".into(),
                },
            };
            return Err(Failure {
                arc: arc_ref,
                reason,
            });
        }
        let (object_pose, configurations) = self.witness_of(object, arc);
        if object_pose.is_none() {
            return Err(Failure {
                arc: arc_ref,
                reason: Infeasibility::NoPlacement {
                    detail: "the arc has no witness (build with verification)".into(),
                },
            });
        }
        Ok(Exchange {
            object: object_pose,
            configurations,
        })
    }
}

/// The arc a step realises, recorded when the step was made (for failing it).
fn step_arc(step: &Step) -> Option<ArcRef> {
    step.arc
}

/// The object pose and arm configurations at an exchange.
#[derive(Clone, Debug, Default)]
struct Exchange {
    object: Option<Iso>,
    configurations: ArmConfigurations,
}

fn apply(state: &mut WorldState, configurations: &ArmConfigurations, object: Option<Iso>) {
    for (e, q) in configurations {
        if let Some(slot) = state.arms.get_mut(*e as usize) {
            *slot = Some(q.clone());
        }
    }
    if object.is_some() {
        state.object = object;
    }
}
