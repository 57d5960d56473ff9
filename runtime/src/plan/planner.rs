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

use super::locate::{goal_states, locate, object_index};
use super::search::{simplify, Path, SearchGraph};
use super::strategy::classify;
use super::{
    ArcRef, ArmConfigurations, Command, Plan, PlanError, PlanOptions, Request, Step, Unreachable,
};
use crate::kinematics::{solve_ik, IkError, IkOptions, IkTarget};
use crate::math::{iso_from_schema, Iso};
use crate::scene::{Holder, ObjectPlacement, Scene, SceneScratch};

/// Plans requests on one artifact. Cheap to keep: it holds the search graphs.
pub struct Planner<'a> {
    artifact: &'a Artifact,
    scene: Option<&'a Scene>,
    search: Vec<SearchGraph>,
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
        let search = artifact
            .objects
            .iter()
            .map(|o| SearchGraph::new(&o.graph))
            .collect();
        Planner {
            artifact,
            scene,
            search,
        }
    }

    /// The artifact planned on.
    pub fn artifact(&self) -> &'a Artifact {
        self.artifact
    }

    /// Plans a request from scratch (arms at home).
    pub fn plan(&self, request: &Request) -> Result<Plan, PlanError> {
        let object = object_index(self.artifact, &request.object).map_err(PlanError::Locate)?;
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
        let goals = match scene {
            Some(scene) => goal_states(
                self.artifact,
                scene,
                object,
                &request.goal,
                &request.options,
            ),
            None => goal_states_abstract(self.artifact, object, &request.goal),
        }
        .map_err(PlanError::Locate)?;
        let goal_pose = match &request.goal {
            super::Goal::Placement(p) => p.pose,
            super::Goal::Workspace { .. } => None,
        };
        let state = WorldState::at_home(
            self.scene,
            self.artifact.end_effectors.len(),
            request.start.pose,
        );
        self.plan_from(object, start, &goals, goal_pose, state, &request.options)
    }

    /// Plans from a given state (used again when execution fails part way).
    pub fn plan_from(
        &self,
        object: u32,
        start: Node,
        goals: &[Node],
        goal_pose: Option<Iso>,
        state: WorldState,
        options: &PlanOptions,
    ) -> Result<Plan, PlanError> {
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
        let mut backtracks = 0;
        loop {
            let Some(path) =
                self.search[object as usize].shortest(start_index, &goal_indices, &removed)
            else {
                return Err(unreachable(&removed, failed));
            };
            match self.realise(object, &path, goal_pose, &state, options) {
                Ok(steps) => {
                    let kept = simplify(graph, &path);
                    let states: Vec<Node> = kept.iter().map(|&i| graph.nodes[i as usize]).collect();
                    return Ok(Plan {
                        object,
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
        let mut state = state.clone();
        let mut steps = Vec::new();
        let n_transitions = arc_into
            .iter()
            .filter(|&&a| graph.arcs[a].kind == ArcKind::Transition)
            .count();
        let mut transitions_seen = 0;
        // Exchanges are computed first, so that a move can end where the next exchange
        // starts.
        let mut exchanges: Vec<Option<Exchange>> = vec![None; arc_into.len()];
        for (i, &a) in arc_into.iter().enumerate() {
            if graph.arcs[a].kind != ArcKind::Transition {
                continue;
            }
            transitions_seen += 1;
            let from = graph.nodes[graph.arcs[a].from as usize];
            let to = graph.nodes[graph.arcs[a].to as usize];
            let first_pick = i == 0 && state.object.is_some();
            let last = transitions_seen == n_transitions && i + 1 == arc_into.len();
            let exchange = self.exchange(
                object,
                a,
                from,
                to,
                first_pick.then_some(&state),
                last.then_some(goal_pose).flatten(),
                &mut rng,
            )?;
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
                    });
                    steps.push(Step {
                        command: Command::Ungrasp {
                            holder: from.end_effector,
                            grasp: from.grasp,
                            workspace: from.workspace,
                            object: exchange.object,
                        },
                        motion: None,
                    });
                }
            }
        }
        let _ = IkOptions::default();
        Ok(steps)
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
        pick_at: Option<&WorldState>,
        place_at: Option<Iso>,
        rng: &mut ChaCha8Rng,
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
        let specific_pose = match (surface_and_arm, pick_at, place_at) {
            (Some((surface, _)), Some(state), _) if surface == from => state.object,
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
            let tip = pose * grasp.inverse();
            let mut last_collision = None;
            let mut best: Option<IkError> = None;
            let mut scratch = SceneScratch::default();
            for _ in 0..8 {
                match solve_ik(
                    robot,
                    base,
                    &IkTarget::Pose(tip),
                    home,
                    rng,
                    &IkOptions::default(),
                ) {
                    Ok(q) => {
                        let placement = ObjectPlacement::Resting {
                            on: surface.end_effector,
                            pose,
                            by: Some(arm.end_effector),
                        };
                        match scene.collision(
                            &[(arm.end_effector, &q)],
                            object,
                            placement,
                            &mut scratch,
                        ) {
                            Ok(None) => {
                                return Ok(Exchange {
                                    object: Some(pose),
                                    configurations: vec![(arm.end_effector, q)],
                                })
                            }
                            Ok(Some(pair)) => last_collision = Some(pair),
                            Err(e) => {
                                last_collision = Some(("collision query".into(), format!("{e:?}")))
                            }
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

/// Locating in an abstract cell: the holder, grasp and workspace must be named.
fn locate_abstract(
    artifact: &Artifact,
    object: u32,
    p: &super::Placement,
) -> Result<Node, super::LocateError> {
    use super::LocateError;
    let e = artifact
        .end_effectors
        .iter()
        .position(|x| x.name == p.holder)
        .ok_or_else(|| LocateError::UnknownHolder {
            name: p.holder.clone(),
            known: artifact
                .end_effectors
                .iter()
                .map(|x| x.name.clone())
                .collect(),
        })? as u32;
    let Some(ws_name) = &p.workspace else {
        return Err(LocateError::NoWhere {
            holder: p.holder.clone(),
        });
    };
    let w = artifact
        .workspaces
        .iter()
        .position(|x| &x.name == ws_name)
        .ok_or_else(|| LocateError::UnknownWorkspace {
            name: ws_name.clone(),
            known: artifact.workspaces.iter().map(|x| x.name.clone()).collect(),
        })? as u32;
    let candidates: Vec<Node> = artifact.objects[object as usize]
        .graph
        .nodes
        .iter()
        .copied()
        .filter(|n| n.end_effector == e && n.workspace == w)
        .collect();
    let names = |ns: &[Node]| {
        ns.iter()
            .map(|n| {
                artifact.objects[object as usize].grasps[n.grasp as usize]
                    .name
                    .clone()
            })
            .collect::<Vec<_>>()
    };
    match &p.grasp {
        Some(g) => candidates
            .iter()
            .copied()
            .find(|n| artifact.objects[object as usize].grasps[n.grasp as usize].name == *g)
            .ok_or_else(|| LocateError::UnknownGrasp {
                holder: p.holder.clone(),
                name: g.clone(),
                known: names(&candidates),
            }),
        None if candidates.len() == 1 => Ok(candidates[0]),
        None if candidates.is_empty() => Err(LocateError::NotReached {
            holder: p.holder.clone(),
            workspace: ws_name.clone(),
        }),
        None => Err(LocateError::GraspNeeded {
            holder: p.holder.clone(),
            grasps: names(&candidates),
        }),
    }
}

fn goal_states_abstract(
    artifact: &Artifact,
    object: u32,
    goal: &super::Goal,
) -> Result<Vec<Node>, super::LocateError> {
    match goal {
        super::Goal::Placement(p) if p.grasp.is_some() => {
            Ok(vec![locate_abstract(artifact, object, p)?])
        }
        super::Goal::Placement(p) => {
            // Any grasp of that holder in that workspace.
            let probe = super::Placement {
                grasp: None,
                ..p.clone()
            };
            match locate_abstract(artifact, object, &probe) {
                Ok(n) => Ok(vec![n]),
                Err(super::LocateError::GraspNeeded { .. }) => {
                    let e = artifact
                        .end_effectors
                        .iter()
                        .position(|x| x.name == p.holder)
                        .unwrap_or(usize::MAX) as u32;
                    let w = artifact
                        .workspaces
                        .iter()
                        .position(|x| Some(&x.name) == p.workspace.as_ref())
                        .unwrap_or(usize::MAX) as u32;
                    Ok(artifact.objects[object as usize]
                        .graph
                        .nodes
                        .iter()
                        .copied()
                        .filter(|n| n.end_effector == e && n.workspace == w)
                        .collect())
                }
                Err(e) => Err(e),
            }
        }
        super::Goal::Workspace { workspace, holder } => {
            let w = artifact
                .workspaces
                .iter()
                .position(|x| &x.name == workspace)
                .ok_or_else(|| super::LocateError::UnknownWorkspace {
                    name: workspace.clone(),
                    known: artifact.workspaces.iter().map(|x| x.name.clone()).collect(),
                })? as u32;
            let e = holder.as_ref().map(|h| {
                artifact
                    .end_effectors
                    .iter()
                    .position(|x| &x.name == h)
                    .map(|i| i as u32)
            });
            Ok(artifact.objects[object as usize]
                .graph
                .nodes
                .iter()
                .copied()
                .filter(|n| n.workspace == w && e.is_none_or(|e| Some(n.end_effector) == e))
                .collect())
        }
    }
}
