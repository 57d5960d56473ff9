//! Move requests: "move object O from this pose to that pose" (the paper's Algorithm 1).
//!
//! A request is located in the object's graph (Cartesian pose to state), the cheapest
//! state path is found (Dijkstra), consecutive moves are merged, and the path is turned
//! into `move`, `grasp` and `ungrasp` commands with concrete object poses and joint
//! configurations (reusing the build-time witnesses, solving the start and goal
//! specifically). A step that fails removes its arc and the search runs again, a bounded
//! number of times. The plan's strategy (pick-and-place, handoff, regrasp...) is read off
//! the path afterwards, never chosen in advance.

pub mod locate;
pub mod names;
pub mod planner;
pub mod search;
pub mod strategy;

use cellc_schema::{
    Blocker, EndEffectorId, GraspId, Infeasibility, Node, NodeId, ObjectId, WorkspaceId,
};

use crate::math::Iso;

pub use locate::LocateError;
pub use strategy::Strategy;

/// Where an object is: held or supported by `holder`, at `pose` (the object's pose in the
/// cell) or somewhere in `workspace` (abstract cells have no geometry). The grasp may be
/// given; otherwise it is inferred from the pose (surfaces) or from the holder having a
/// single grasp.
#[derive(Clone, Debug, PartialEq)]
pub struct Placement {
    /// The end-effector holding or supporting the object.
    pub holder: EndEffectorId,
    /// Grasp or resting pose, when known.
    pub grasp: Option<GraspId>,
    /// Workspace, when known (needed when there is no pose).
    pub workspace: Option<WorkspaceId>,
    /// Object pose in the cell.
    pub pose: Option<Iso>,
}

impl Placement {
    /// Exactly the state `node` (holder, grasp and workspace), without a pose: how a
    /// caller that already works on the graph names a placement.
    pub fn at_state(node: Node) -> Placement {
        Placement {
            holder: node.end_effector,
            grasp: Some(node.grasp),
            workspace: Some(node.workspace),
            pose: None,
        }
    }
}

/// Where the object must end.
#[derive(Clone, Debug, PartialEq)]
pub enum Goal {
    /// Exactly there (the holder is normally a fixed surface).
    Placement(Placement),
    /// Anywhere in a workspace, held by `holder` if given.
    Workspace {
        /// The workspace.
        workspace: WorkspaceId,
        /// The end-effector, if it matters.
        holder: Option<EndEffectorId>,
    },
}

/// A [`Placement`] written with names, as people and task planners give it; resolved to
/// ids once, by [`names::placement`], with did-you-mean errors.
#[derive(Clone, Debug, PartialEq)]
pub struct PlacementByName {
    /// End-effector name.
    pub holder: String,
    /// Grasp or resting pose name, when known.
    pub grasp: Option<String>,
    /// Workspace name, when known.
    pub workspace: Option<String>,
    /// Object pose in the cell.
    pub pose: Option<Iso>,
}

/// A [`Goal`] written with names.
#[derive(Clone, Debug, PartialEq)]
pub enum GoalByName {
    /// Exactly there.
    Placement(PlacementByName),
    /// Anywhere in a workspace, held by `holder` if given.
    Workspace {
        /// Workspace name.
        workspace: String,
        /// End-effector name.
        holder: Option<String>,
    },
}

/// Settings of a request.
#[derive(Clone, Debug)]
pub struct PlanOptions {
    /// Seed of every randomized solver.
    pub seed: u64,
    /// How many times a failed step may remove its arc and search again.
    pub max_backtracks: u32,
    /// Plan joint motions between commands (false: high level only).
    pub motions: bool,
    /// Position tolerance when matching a pose to a grasp or resting pose, metres.
    pub position_tolerance: f64,
    /// Orientation tolerance for the same, radians.
    pub rotation_tolerance: f64,
    /// Arc weights for this request (move, transition), instead of the cell's: e.g. the
    /// original planner's integer costs, or costs from failure statistics.
    pub weights: Option<(f64, f64)>,
    /// Give up (with [`PlanError::TimeBudget`]) when planning takes longer than this: the
    /// deadline of the request's [`Termination`](crate::termination::Termination), checked
    /// between searches and inside every IK and motion search.
    pub time_budget: Option<std::time::Duration>,
    /// Give up (with [`PlanError::TimeBudget`]) as soon as another thread raises this flag.
    pub cancel: Option<std::sync::Arc<std::sync::atomic::AtomicBool>>,
    /// How the motions are timed: scalings of the joints' limits, a control rate.
    pub timing: crate::motion::TimingOptions,
}

impl Default for PlanOptions {
    fn default() -> PlanOptions {
        PlanOptions {
            seed: 0,
            max_backtracks: 1000,
            motions: true,
            position_tolerance: 0.01,
            rotation_tolerance: 0.05,
            weights: None,
            time_budget: None,
            cancel: None,
            timing: crate::motion::TimingOptions::default(),
        }
    }
}

/// A move request.
#[derive(Clone, Debug)]
pub struct Request {
    /// The object to move.
    pub object: ObjectId,
    /// Where it is.
    pub start: Placement,
    /// Where it must go.
    pub goal: Goal,
    /// Settings.
    pub options: PlanOptions,
}

/// The typed request of a request the cell declares.
pub fn named_request(named: &cellc_schema::NamedRequest, options: PlanOptions) -> Request {
    Request {
        object: named.object,
        start: placement_of(&named.from),
        goal: Goal::Placement(placement_of(&named.to)),
        options,
    }
}

/// A placement as the artifact stores it (requests, the world, tasks), typed.
pub fn placement_of(p: &cellc_schema::RequestPlacement) -> Placement {
    Placement {
        holder: p.end_effector,
        grasp: p.grasp,
        workspace: p.workspace,
        pose: p.pose.as_ref().map(crate::math::iso_from_schema),
    }
}

/// Joint values of every arm at a moment: (end-effector, joints).
pub type ArmConfigurations = Vec<(EndEffectorId, Vec<f64>)>;

/// A time-parametrised joint trajectory of one or several arms moving together.
#[derive(Clone, Debug, PartialEq)]
pub struct Trajectory {
    /// The arms, in the order their joints are concatenated in each point.
    pub arms: Vec<EndEffectorId>,
    /// The points, in time order: the first at time 0 at the start, the last at the goal,
    /// both at rest.
    pub points: Vec<TrajectoryPoint>,
}

/// A point of a [`Trajectory`]: what a joint-trajectory controller is sent (ROS's
/// `trajectory_msgs/JointTrajectoryPoint`), every vector in the trajectory's joint order.
#[derive(Clone, Debug, PartialEq)]
pub struct TrajectoryPoint {
    /// Seconds from the start of the motion.
    pub time: f64,
    /// Joint positions (rad, or m).
    pub positions: Vec<f64>,
    /// Joint velocities (rad/s, or m/s).
    pub velocities: Vec<f64>,
    /// Joint accelerations (rad/s², or m/s²).
    pub accelerations: Vec<f64>,
}

impl TrajectoryPoint {
    /// Standing at `positions` at `time`.
    pub fn at_rest(time: f64, positions: &[f64]) -> TrajectoryPoint {
        TrajectoryPoint {
            time,
            positions: positions.to_vec(),
            velocities: vec![0.0; positions.len()],
            accelerations: vec![0.0; positions.len()],
        }
    }
}

/// One command of a plan.
#[derive(Clone, Debug)]
pub enum Command {
    /// The holder carries the object into another workspace (same grasp).
    Move {
        /// End-effector.
        holder: EndEffectorId,
        /// Workspace reached.
        workspace: WorkspaceId,
        /// Object pose at the end (`None` in abstract cells).
        object: Option<Iso>,
        /// Arm configurations at the end.
        configurations: ArmConfigurations,
    },
    /// The receiving end-effector takes hold of the object.
    Grasp {
        /// End-effector.
        holder: EndEffectorId,
        /// Grasp taken.
        grasp: GraspId,
        /// Workspace.
        workspace: WorkspaceId,
        /// Object pose during the exchange (`None` in abstract cells).
        object: Option<Iso>,
        /// Configurations of the arms involved.
        configurations: ArmConfigurations,
    },
    /// The giving end-effector lets go.
    Ungrasp {
        /// End-effector.
        holder: EndEffectorId,
        /// The grasp it had.
        grasp: GraspId,
        /// Workspace.
        workspace: WorkspaceId,
        /// Object pose (`None` in abstract cells).
        object: Option<Iso>,
    },
}

/// A command with the joint motion that leads to it (when motions are planned).
#[derive(Clone, Debug)]
pub struct Step {
    /// What happens.
    pub command: Command,
    /// How the arms get there.
    pub motion: Option<Trajectory>,
    /// The graph arc this command carries out (to remove it if the command fails).
    pub arc: Option<ArcRef>,
    /// What the motion was planned around, so it can be checked again independently.
    pub motion_context: Option<MotionContext>,
}

/// The world a motion was planned in: the arms that stood still and how the object
/// travelled.
#[derive(Clone, Debug)]
pub struct MotionContext {
    /// Arms not moving, at these joint values.
    pub stationary: ArmConfigurations,
    /// The object during the motion.
    pub placement: crate::scene::ObjectPlacement,
    /// The world's other objects during the motion.
    pub obstacles: Vec<crate::scene::Obstacle>,
}

/// The other objects a plan is made around: obstacles where they stand during the whole
/// plan (resting, or held by an arm that never moves in it), and the hands that hold them
/// (no state of the moved object may be held by one). Empty for a request planned alone.
#[derive(Clone, Debug, Default)]
pub struct Surroundings {
    /// The other objects in the scene, as collision queries place them.
    pub obstacles: Vec<crate::scene::Obstacle>,
    /// (hand, the object it holds).
    pub busy: Vec<(EndEffectorId, ObjectId)>,
}

/// What a plan must achieve: every state that satisfies the goal and, for a placement
/// goal with geometry, the exact pose. A plan carries it so that executing (and replanning
/// after a failure) needs nothing but the plan.
#[derive(Clone, Debug, PartialEq)]
pub struct PlanGoal {
    /// States that satisfy the goal.
    pub states: Vec<Node>,
    /// The object pose the goal asks for, when it asks for one.
    pub pose: Option<Iso>,
}

/// A planned request.
#[derive(Clone, Debug)]
pub struct Plan {
    /// The object moved.
    pub object: ObjectId,
    /// Where the object was when planning started (its pose, when known).
    pub start_pose: Option<Iso>,
    /// What the plan achieves.
    pub goal: PlanGoal,
    /// The other objects it was planned around (a replan keeps them).
    pub around: Surroundings,
    /// Every arm's joints when the plan starts (index = end-effector; `None` for what is
    /// not an arm): where an executor's arms must stand for the first motions to apply.
    pub start_arms: Vec<Option<Vec<f64>>>,
    /// The state path, simplified (one move per run of moves).
    pub states: Vec<Node>,
    /// Commands in order.
    pub steps: Vec<Step>,
    /// What the path amounts to.
    pub strategy: Strategy,
    /// Sum of arc weights.
    pub cost: f64,
    /// Arcs removed and searches repeated because a step failed.
    pub backtracks: u32,
    /// The world's other objects that were in the way, and how the plan went round each
    /// (empty when none was): what a task planner reads to know that a move only worked
    /// round another object, and the count behind "a direct plan was blocked".
    pub detours: Vec<Detour>,
}

/// One of the world's other objects in the way of a plan, and how the plan went round it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Detour {
    /// The arc whose step it blocked.
    pub arc: ArcRef,
    /// What it blocked.
    pub blocker: Blocker,
    /// How the plan went round it.
    pub around: Around,
}

/// How a plan went round an object in its way.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Around {
    /// The step was carried out at another resting pose of the same workspace (a put-down
    /// whose witnessed pose the object takes).
    OtherPose,
    /// The arc was given up and the search found a path without it.
    OtherPath,
}

/// How the detail of a step whose joint motion could not be planned begins (the arc fails
/// with [`Infeasibility::NoPlacement`] and this, then the motion planner's error), so
/// explanations can tell a blocked motion from a missing placement.
pub const NO_MOTION: &str = "no collision-free motion";

/// A graph arc identified by its endpoints (node indices of the object's graph).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct ArcRef {
    /// Tail node.
    pub from: NodeId,
    /// Head node.
    pub to: NodeId,
}

impl ArcRef {
    /// The endpoints of an arc of the artifact's graph.
    pub fn of(arc: &cellc_schema::Arc) -> ArcRef {
        ArcRef {
            from: NodeId(arc.from),
            to: NodeId(arc.to),
        }
    }
}

/// Why a request has no plan, with what explanations need.
#[derive(Clone, Debug)]
pub struct Unreachable {
    /// The object.
    pub object: ObjectId,
    /// Start state.
    pub start: Node,
    /// Every state that would satisfy the goal.
    pub goals: Vec<Node>,
    /// Node indices reachable from the start (after removing failed arcs).
    pub reachable: Vec<NodeId>,
    /// Arcs removed during this request because a step failed, with why.
    pub failed: Vec<(ArcRef, Infeasibility)>,
}

impl Unreachable {
    /// Every step that failed because one of the world's other objects stood in its way,
    /// in the order they failed.
    pub fn blockers(&self) -> impl Iterator<Item = (ArcRef, &Blocker)> + '_ {
        self.failed.iter().filter_map(|(arc, reason)| match reason {
            Infeasibility::Blocked(blocker) => Some((*arc, blocker)),
            _ => None,
        })
    }
}

impl Command {
    /// The end-effector that acts.
    pub fn holder(&self) -> EndEffectorId {
        match self {
            Command::Move { holder, .. }
            | Command::Grasp { holder, .. }
            | Command::Ungrasp { holder, .. } => *holder,
        }
    }
}

/// Why a request could not be planned.
#[derive(Clone, Debug)]
#[non_exhaustive]
pub enum PlanError {
    /// The request names something the artifact does not have, or a pose matches no
    /// state.
    Locate(LocateError),
    /// No path from the start to the goal.
    Unreachable(Box<Unreachable>),
    /// The request's start cannot be put into the world (its hand's arm cannot hold the
    /// object there, or the start matches no state).
    World(crate::world::WorldError),
    /// The object to move is not in the world.
    Absent {
        /// The object.
        object: ObjectId,
    },
    /// The goal pose is where another object of the world stands.
    GoalOccupied {
        /// The object standing there.
        by: ObjectId,
    },
    /// The request's time budget ran out (or it was cancelled) before a plan was found.
    TimeBudget {
        /// Searches started (the first, and one per backtrack).
        searches: u32,
    },
    /// A timing option of the request is out of its range
    /// ([`check_timing`](crate::motion::check_timing): a scaling not in (0, 1], a rate not
    /// in (0, [`TimingOptions::MAX_RATE`](crate::motion::TimingOptions::MAX_RATE)]), found
    /// before planning; or `rate` is in range but a motion of the plan would have more
    /// than [`TimingOptions::MAX_POINTS`](crate::motion::TimingOptions::MAX_POINTS) points
    /// at it. Refused whole: no other path would make the option right.
    InvalidOption {
        /// The field of [`TimingOptions`](crate::motion::TimingOptions)
        /// (`velocity_scaling`, `acceleration_scaling`, `rate`).
        name: &'static str,
        /// Its value.
        value: f64,
    },
}

impl PlanError {
    /// The world's objects this failure names as in the way, each once, in the order met:
    /// the object at the goal, or those that blocked the steps that failed. Moving them
    /// first may let the request succeed ([`planner::Planner::plan_clearing`]).
    pub fn blockers(&self) -> Vec<ObjectId> {
        let mut out = Vec::new();
        match self {
            PlanError::GoalOccupied { by } => out.push(*by),
            PlanError::Unreachable(u) => {
                for (_, blocker) in u.blockers() {
                    if !out.contains(&blocker.by) {
                        out.push(blocker.by);
                    }
                }
            }
            _ => {}
        }
        out
    }
}

impl std::fmt::Display for PlanError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            PlanError::Locate(e) => e.fmt(f),
            PlanError::Unreachable(u) => write!(
                f,
                "no plan reaches the goal ({} states reachable from the start)",
                u.reachable.len()
            ),
            PlanError::World(e) => write!(f, "the request's start: {e:?}"),
            PlanError::Absent { object } => write!(f, "{object} is not in the world"),
            PlanError::GoalOccupied { by } => write!(f, "{by} stands at the goal"),
            PlanError::TimeBudget { searches } => {
                write!(f, "the time budget ran out after {searches} searches")
            }
            PlanError::InvalidOption { name, value } => {
                write!(f, "request option `{name}` cannot be {value}")
            }
        }
    }
}

impl std::error::Error for PlanError {}
