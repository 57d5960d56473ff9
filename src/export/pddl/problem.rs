//! A request as a PDDL problem's facts: the start state and the goal states exactly as
//! `cellc plan` finds them, so that an optimal PDDL plan costs what cellc's plan costs.

use cellc_runtime::plan::locate::goal_states;
use cellc_runtime::plan::{Goal, PlanError, Request};
use cellc_runtime::{Cell, World};
use cellc_schema::{Node, NodeId, ObjectId};

/// What one problem says: where the object starts and which states end it.
#[derive(Clone, Debug, PartialEq)]
pub struct Problem {
    /// The problem's PDDL name, also its file name (a named request's from
    /// [`super::names::problem_ids`]).
    pub id: String,
    /// What the problem is, for its header comment (e.g. "request `fig8`").
    pub title: String,
    /// The start state (index into the object's graph nodes).
    pub start: NodeId,
    /// Every state that satisfies the goal (several in an abstract cell when the goal
    /// names no grasp).
    pub goals: Vec<NodeId>,
    /// The start is a goal state but not the goal's pose (a pick-and-place within one
    /// resting pose and workspace): the object must take at least one arc.
    pub must_leave: bool,
}

/// Why a request gives no problem.
#[derive(Clone, Debug)]
pub enum ProblemError {
    /// The request cannot be located, as `cellc plan` would report it.
    Plan(PlanError),
    /// The start is no node of the object's graph (an artifact made by another tool).
    StartNotInGraph {
        /// The object.
        object: ObjectId,
        /// The state the start was located in.
        state: Node,
    },
}

impl Problem {
    /// The problem of `request` in `cell`, located as [`Cell::plan`] locates it: the
    /// object put at the request's start in a world with every arm at home
    /// ([`Cell::request_world`]), the goal's states from the planner's `goal_states`.
    pub fn of_request(
        cell: &Cell,
        request: &Request,
        id: String,
        title: String,
    ) -> Result<Problem, ProblemError> {
        let artifact = cell.artifact();
        let object = request.object;
        let empty = World::at_home(artifact, cell.scene());
        let world = cell
            .request_world(&empty, request)
            .map_err(ProblemError::Plan)?;
        let graph = &artifact.objects[object.index()].graph;
        let index = |n: &Node| {
            graph
                .nodes
                .iter()
                .position(|m| m == n)
                .map(|i| NodeId(i as u32))
        };
        let Some(state) = world.state(object) else {
            return Err(ProblemError::Plan(PlanError::Absent { object }));
        };
        let start = index(&state).ok_or(ProblemError::StartNotInGraph { object, state })?;
        let geometric = cell.scene().filter(|s| s.has_kinematics());
        let goals: Vec<NodeId> =
            goal_states(artifact, geometric, object, &request.goal, &request.options)
                .map_err(|e| ProblemError::Plan(PlanError::Locate(e)))?
                .iter()
                .filter_map(index)
                .collect();
        // The planner's rule (`Planner::plan_from`): a start that is a goal state must
        // be left and entered again when the goal asks for another pose.
        let goal_pose = match &request.goal {
            Goal::Placement(p) => p.pose,
            Goal::Workspace { .. } => None,
        };
        let another_pose = match (world.pose(artifact, cell.scene(), object), goal_pose) {
            (Some(now), Some(wanted)) => {
                let (position, rotation) = cellc_runtime::kinematics::pose_error(&now, &wanted);
                position > request.options.position_tolerance
                    || rotation > request.options.rotation_tolerance
            }
            _ => false,
        };
        Ok(Problem {
            id,
            title,
            start,
            must_leave: another_pose && goals.contains(&start),
            goals,
        })
    }
}
