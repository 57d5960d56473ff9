//! The planner: Algorithm 1 on an artifact.
//!
//! Search, simplify, realise the commands, and on a failed step remove that arc and search
//! again. Realising reuses the build-time witnesses (an exchange in a workspace is the
//! same whatever the request), and solves specifically only what depends on the request:
//! picking the object where it actually is, and placing it where the goal says.

mod blocking;
mod clear;
mod exchange;
mod motions;
mod realise;

use std::collections::HashSet;

use cellc_schema::{Artifact, EndEffectorId, Infeasibility, Node, NodeId, ObjectId};

use super::locate::{goal_states, locate, locate_abstract};
use super::search::{simplify, Scratch, SearchGraph};
use super::strategy::classify;
use super::{
    ArcRef, ArmConfigurations, Plan, PlanError, PlanGoal, PlanOptions, Request, Step, Surroundings,
    Unreachable,
};
use crate::kinematics::IkOptions;
use crate::math::Iso;
use crate::motion::{check_timing, MotionError, MotionPlanner, RrtConnect};
use crate::scene::{Holder, Scene};
use crate::termination::Termination;
use crate::world::World;

pub use clear::MAX_CLEARING_MOVES;

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
    /// The world's other objects.
    pub around: Surroundings,
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
        WorldState {
            arms,
            object,
            around: Surroundings::default(),
        }
    }

    /// The state a plan for `object` starts from in `world`: its arms, the object's pose
    /// (resting, or where its hand holds it), and every other object.
    pub fn of_world(
        artifact: &Artifact,
        scene: Option<&Scene>,
        world: &World,
        object: ObjectId,
    ) -> WorldState {
        let busy = (0..artifact.end_effectors.len() as u32)
            .map(EndEffectorId)
            .filter(|&e| artifact.end_effectors[e.index()].movable)
            .filter_map(|e| world.held_by(e).filter(|&o| o != object).map(|o| (e, o)))
            .collect();
        WorldState {
            arms: world.arms().to_vec(),
            object: world.pose(artifact, scene, object),
            around: Surroundings {
                obstacles: scene.map_or_else(Vec::new, |s| world.obstacles(artifact, s, object)),
                busy,
            },
        }
    }
}

/// A step that could not be realised: the arc to remove and why.
struct Failure {
    arc: ArcRef,
    reason: Infeasibility,
}

/// Why realising a path stopped: a step failed (its arc is removed and the search runs
/// again), or the request itself is refused, whatever the path (a timing option that no
/// motion can meet).
enum Setback {
    Failed(Failure),
    Refused(PlanError),
}

impl From<Failure> for Setback {
    fn from(failure: Failure) -> Setback {
        Setback::Failed(failure)
    }
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

    /// Executes `plan` on `executor` towards the goal it carries, replanning with this
    /// planner from the object's current state when a step fails (at most
    /// `options.max_replans` times). [`crate::Cell::execute`] does the same with the
    /// cell's planner and brings a world up to date.
    pub fn execute(
        &self,
        plan: Plan,
        executor: &mut dyn crate::Executor,
        options: &crate::ExecuteOptions,
    ) -> Result<crate::Execution, crate::ExecutionError> {
        crate::execute::execute(self, plan, executor, options)
    }

    /// Plans a request from scratch (arms at home).
    pub fn plan(&self, request: &Request) -> Result<Plan, PlanError> {
        super::names::check_request(self.artifact, request).map_err(PlanError::Locate)?;
        let object = request.object;
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

    /// Plans moving `object` to `goal` in `world`: from where the object is, with the arms
    /// where they stand and every other object an obstacle at its current pose.
    ///
    /// # Errors
    /// The object is absent; the goal names something the artifact lacks or lies where
    /// another object stands ([`PlanError::GoalOccupied`]); or no plan, as for
    /// [`Planner::plan`].
    pub fn plan_move(
        &self,
        world: &World,
        object: ObjectId,
        goal: &super::Goal,
        options: &PlanOptions,
    ) -> Result<Plan, PlanError> {
        let Some(start) = world.state(object) else {
            return Err(PlanError::Absent { object });
        };
        let request = Request {
            object,
            start: super::Placement::at_state(start),
            goal: goal.clone(),
            options: options.clone(),
        };
        super::names::check_request(self.artifact, &request).map_err(PlanError::Locate)?;
        let scene = self.scene.filter(|s| s.has_kinematics());
        let goals =
            goal_states(self.artifact, scene, object, goal, options).map_err(PlanError::Locate)?;
        let goal = PlanGoal {
            states: goals,
            pose: match goal {
                super::Goal::Placement(p) => p.pose,
                super::Goal::Workspace { .. } => None,
            },
        };
        let state = WorldState::of_world(self.artifact, self.scene, world, object);
        if let (Some(scene), Some(pose), Some(&node)) = (scene, goal.pose, goal.states.first()) {
            if let Some(by) = occupant(self.artifact, scene, object, node, pose, &state) {
                return Err(PlanError::GoalOccupied { by });
            }
        }
        self.plan_from(object, start, &goal, state, options)
    }

    /// Plans from a given state towards `goal` (used again when execution fails part way).
    pub fn plan_from(
        &self,
        object: ObjectId,
        start: Node,
        goal: &PlanGoal,
        state: WorldState,
        options: &PlanOptions,
    ) -> Result<Plan, PlanError> {
        // Before anything is searched: an option out of range fails every motion alike.
        // (`check_timing` gives no other error.)
        if let Err(MotionError::InvalidOption { name, value }) = check_timing(&options.timing) {
            return Err(PlanError::InvalidOption { name, value });
        }
        let goals = goal.states.as_slice();
        let goal_pose = goal.pose;
        let start_pose = state.object;
        let graph = &self.artifact.objects[object.index()].graph;
        let index_of = |n: &Node| {
            graph
                .nodes
                .iter()
                .position(|m| m == n)
                .map(|i| NodeId(i as u32))
        };
        let start_index = index_of(&start);
        let goal_indices: Vec<NodeId> = goals.iter().filter_map(index_of).collect();
        let mut removed: HashSet<ArcRef> = HashSet::new();
        let mut failed: Vec<(ArcRef, Infeasibility)> = Vec::new();
        // A hand that holds another object holds nothing else: every arc into its states
        // is out for this plan, and says why. (With no hand busy there is nothing to find:
        // the pass over 10^6 arcs is skipped.)
        let busy = !state.around.busy.is_empty();
        for arc in graph.arcs.iter().filter(|_| busy) {
            let holder = graph.nodes[arc.to as usize].end_effector;
            if let Some(&(hand, holds)) = state.around.busy.iter().find(|(e, _)| *e == holder) {
                let arc = ArcRef::of(arc);
                removed.insert(arc);
                failed.push((arc, Infeasibility::HandBusy { hand, holds }));
            }
        }
        let unreachable = |removed: &HashSet<ArcRef>, failed: Vec<(ArcRef, Infeasibility)>| {
            PlanError::Unreachable(Box::new(Unreachable {
                object,
                start,
                goals: goals.to_vec(),
                reachable: start_index
                    .map(|s| self.search[object.index()].reachable(s, removed))
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
            .map(|w| self.search[object.index()].reweighted(graph, w));
        // One search's working memory for every search of this request.
        let mut scratch = Scratch::default();
        loop {
            if stop.should_stop() {
                return Err(PlanError::TimeBudget {
                    searches: backtracks,
                });
            }
            let search = reweighted.as_ref().unwrap_or(&self.search[object.index()]);
            let found = if must_move && goal_indices.contains(&start_index) {
                search.shortest_leaving(&mut scratch, start_index, &goal_indices, &removed)
            } else {
                search.shortest(&mut scratch, start_index, &goal_indices, &removed)
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
                Ok((steps, resampled)) => {
                    let kept = simplify(graph, &path);
                    // Arcs given up because an object stood in the way, then the poses
                    // moved off the places objects take.
                    let detours = failed
                        .iter()
                        .filter_map(|(arc, reason)| match reason {
                            Infeasibility::Blocked(blocker) => Some(super::Detour {
                                arc: *arc,
                                blocker: *blocker,
                                around: super::Around::OtherPath,
                            }),
                            _ => None,
                        })
                        .chain(resampled)
                        .collect();
                    let states: Vec<Node> = kept.iter().map(|&i| graph.nodes[i.index()]).collect();
                    return Ok(Plan {
                        object,
                        start_pose,
                        goal: goal.clone(),
                        around: state.around.clone(),
                        start_arms: state.arms.clone(),
                        strategy: classify(self.artifact, &states),
                        states,
                        steps,
                        cost: path.cost,
                        backtracks,
                        detours,
                    });
                }
                Err(Setback::Refused(error)) => return Err(error),
                Err(Setback::Failed(failure)) => {
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
}

/// The arc a step realises, recorded when the step was made (for failing it).
fn step_arc(step: &Step) -> Option<ArcRef> {
    step.arc
}

/// The object pose and arm configurations at an exchange, and the object that took its
/// witnessed place, when it was carried out elsewhere.
#[derive(Clone, Debug, Default)]
struct Exchange {
    object: Option<Iso>,
    configurations: ArmConfigurations,
    detour: Option<cellc_schema::Blocker>,
}

fn apply(state: &mut WorldState, configurations: &ArmConfigurations, object: Option<Iso>) {
    for (e, q) in configurations {
        if let Some(slot) = state.arms.get_mut(e.index()) {
            *slot = Some(q.clone());
        }
    }
    if object.is_some() {
        state.object = object;
    }
}

/// The object standing where `object` would rest at `pose` in goal state `node` (on its
/// surface), if any: the pose alone, no arm, against the world's other objects.
fn occupant(
    artifact: &Artifact,
    scene: &Scene,
    object: ObjectId,
    node: Node,
    pose: Iso,
    state: &WorldState,
) -> Option<ObjectId> {
    use crate::validity::{StateFault, StateValidity};
    if state.around.obstacles.is_empty()
        || !matches!(
            scene.holders.get(node.end_effector.index()),
            Some(Holder::Surface { .. })
        )
    {
        return None;
    }
    let placement = crate::scene::ObjectPlacement::Resting {
        on: node.end_effector,
        pose,
        by: None,
    };
    let validity = crate::validity::SceneValidity::new(scene, &[], &[], object, placement)
        .ok()?
        .with_obstacles(&state.around.obstacles);
    let Ok(Some(StateFault::Collision { a, b })) =
        validity.check(&[], &mut crate::scene::SceneScratch::default())
    else {
        return None;
    };
    let moved = artifact.object_name(object);
    let other = if a == moved { b } else { a };
    state
        .around
        .obstacles
        .iter()
        .map(|o| o.object)
        .find(|&o| artifact.object_name(o) == other)
}
