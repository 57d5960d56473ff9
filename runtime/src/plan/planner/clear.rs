//! Clearing the way: when a move in a world fails because other objects are in its way
//! (one stands at its goal, or blocks every way there), each blocking object is first
//! moved to a free resting pose, then the move is planned in the world as those moves
//! leave it ([`World::after`]).
//!
//! Why a list of plans and not one plan: each move is an ordinary [`Plan`] of one object,
//! which a task planner already knows how to execute, check and replan
//! ([`crate::Cell::execute`] on each, in order, keeps the world up to date), and a
//! caller sees exactly what was added before its move (`plans[..n - 1]`, each naming the
//! object it moves). A flag on [`PlanOptions`] would have given `plan_move` two kinds of
//! answer.
//!
//! Where a blocking object goes: a resting pose of one of its surface states, sampled
//! from the workspace ([`RestRegions`], as put-downs are), clear of every other object of
//! the world and of the goal. Poses at least [`CLEARANCE`] from every place the blocked
//! move needs (the goal, the object's start, the places the failed steps needed, where
//! the blocking object stands) come first; then the same workspace (the cheapest move),
//! the same surface, any; then the farthest. A pose is taken only if the request, planned
//! without motions with the object standing there, is not blocked by it again ("not where
//! it blocks again"). The work is bounded: at most [`MAX_CLEARING_MOVES`] moves, a few
//! candidate poses checked and planned per blocking object with few backtracks, all
//! within the request's one time budget; every random draw comes from the request's
//! seed.

use std::time::Instant;

use cellc_schema::{EndEffectorId, Node, ObjectId};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use super::Planner;
use crate::math::{Iso, Vec3};
use crate::plan::{ArmConfigurations, Goal, Placement, Plan, PlanError, PlanOptions};
use crate::rest::RestRegions;
use crate::scene::{Holder, ObjectPlacement, Obstacle, SceneScratch};
use crate::validity::{SceneValidity, StateValidity};
use crate::world::{Whereabouts, World};

/// The most objects moved out of the way before the request (one object may count twice
/// when it blocks again where it was put).
pub const MAX_CLEARING_MOVES: usize = 3;

/// Resting poses drawn per surface state of a blocking object.
const CANDIDATES_PER_STATE: usize = 16;

/// Free poses checked for a blocking object, best first: would the move it blocks work
/// with the object standing there?
const CANDIDATES_EXAMINED: usize = 12;

/// Free poses (that pass the check) a blocking object is planned to, best first, before it
/// counts as immovable.
const CANDIDATES_TRIED: usize = 4;

/// Backtracks allowed to the plans made here before the request's own (moving a blocking
/// object, checking a pose for it).
const CLEARING_BACKTRACKS: u32 = 8;

/// How far (metres) a free pose should be from every place the blocked move needs (about
/// a hand's width): closer poses are tried only after all the farther ones.
const CLEARANCE: f64 = 0.15;

impl Planner<'_> {
    /// Plans moving `object` to `goal` in `world`, moving the objects in its way first.
    ///
    /// When the direct plan ([`Planner::plan_move`]) succeeds, that is the only plan. When it
    /// fails because of other objects ([`PlanError::blockers`]: the goal's occupant, or
    /// the objects that blocked its steps), the first of them that can be moved goes to a
    /// free resting pose, and the request is planned again in the world after that move;
    /// so on, at most [`MAX_CLEARING_MOVES`] times. The plans come in the order they are
    /// to be carried out, the request's last; each is planned in the world the ones before
    /// it leave, so executing them one after the other with [`crate::Cell::execute`]
    /// does the job.
    ///
    /// # Errors
    /// The direct plan's error when no object blocks it, when no blocking object can be
    /// moved, or when the moves allowed do not clear the way; [`PlanError::TimeBudget`]
    /// when the request's budget (shared by every plan made here) runs out.
    pub fn plan_clearing(
        &self,
        world: &World,
        object: ObjectId,
        goal: &Goal,
        options: &PlanOptions,
    ) -> Result<Vec<Plan>, PlanError> {
        let deadline = options.time_budget.map(|b| Instant::now() + b);
        let within = || PlanOptions {
            time_budget: deadline.map(|d| d.saturating_duration_since(Instant::now())),
            ..options.clone()
        };
        let direct = match self.plan_move(world, object, goal, &within()) {
            Ok(plan) => return Ok(vec![plan]),
            Err(error) => error,
        };
        let mut now = world.clone();
        let mut plans = Vec::new();
        let mut error = direct.clone();
        let mut keep_out = self.places_needed(world, object, goal);
        loop {
            if matches!(
                error,
                PlanError::TimeBudget { .. } | PlanError::InvalidOption { .. }
            ) {
                return Err(error);
            }
            let blockers: Vec<ObjectId> = error
                .blockers()
                .into_iter()
                .filter(|&b| b != object)
                .collect();
            if blockers.is_empty() || plans.len() >= MAX_CLEARING_MOVES {
                return Err(direct);
            }
            keep_out.extend(blocked_places(&error));
            keep_out.extend(
                blockers
                    .iter()
                    .filter_map(|&b| now.pose(self.artifact, self.scene, b))
                    .map(|p| p.translation.vector),
            );
            let mut cleared = None;
            for &blocker in &blockers {
                let way = (object, goal);
                if let Some(plan) = self.clear_away(&now, blocker, way, &keep_out, &within)? {
                    cleared = Some(plan);
                    break;
                }
            }
            let Some(plan) = cleared else {
                return Err(direct);
            };
            now = now.after(self.artifact, self.scene, &plan);
            plans.push(plan);
            match self.plan_move(&now, object, goal, &within()) {
                Ok(plan) => {
                    plans.push(plan);
                    return Ok(plans);
                }
                Err(again) => error = again,
            }
        }
    }

    /// A plan moving `blocker` to a free resting pose, clear of `object` at `goal` and
    /// away from `keep_out`, or `None` when none of the best few poses can be reached.
    ///
    /// # Errors
    /// [`PlanError::TimeBudget`] when the budget runs out.
    fn clear_away(
        &self,
        world: &World,
        blocker: ObjectId,
        (object, goal): (ObjectId, &Goal),
        keep_out: &[Vec3],
        within: &dyn Fn() -> PlanOptions,
    ) -> Result<Option<Plan>, PlanError> {
        let (Some(scene), Some(current)) = (
            self.scene.filter(|s| s.has_kinematics()),
            world.state(blocker),
        ) else {
            return Ok(None);
        };
        let options = within();
        // A move out of the way is a plain pick and place, or a handoff: one that needs
        // more backtracks is not worth waiting for. Checks plan no motions.
        let bounded = |motions: bool| {
            let now = within();
            PlanOptions {
                max_backtracks: now.max_backtracks.min(CLEARING_BACKTRACKS),
                motions: motions && now.motions,
                ..now
            }
        };
        let mut rng = ChaCha8Rng::seed_from_u64(
            options.seed ^ 0xC1EA_u64 ^ u64::from(blocker.0).wrapping_mul(0x9E37_79B9),
        );
        let others = world.obstacles(self.artifact, scene, blocker);
        // The arms where they stand (an object in a hand is where that hand is).
        let arms: ArmConfigurations = world
            .arms()
            .iter()
            .enumerate()
            .filter_map(|(e, q)| Some((EndEffectorId(e as u32), q.clone()?)))
            .collect();
        // The goal's place, as the moved object will take it.
        let goal_place: Vec<Obstacle> = match goal {
            Goal::Placement(Placement {
                holder,
                pose: Some(pose),
                ..
            }) if matches!(
                scene.holders.get(holder.index()),
                Some(Holder::Surface { .. })
            ) =>
            {
                vec![Obstacle {
                    object,
                    placement: ObjectPlacement::Resting {
                        on: *holder,
                        pose: *pose,
                        by: None,
                    },
                }]
            }
            _ => Vec::new(),
        };
        let graph = &self.artifact.objects[blocker.index()].graph;
        let mut candidates: Vec<(Node, Iso, f64)> = Vec::new();
        let mut scratch = SceneScratch::default();
        for &node in &graph.nodes {
            let Some(Holder::Surface { slab, .. }) = scene.holders.get(node.end_effector.index())
            else {
                continue;
            };
            let rest = self.artifact.grasp_pose(blocker, node.grasp);
            let regions = RestRegions::new(slab, &scene.workspaces[node.workspace.index()], &rest);
            for _ in 0..CANDIDATES_PER_STATE {
                let Some(pose) = regions.sample(&mut rng) else {
                    break;
                };
                let free = |obstacles: &[Obstacle], scratch: &mut SceneScratch| {
                    let placement = ObjectPlacement::Resting {
                        on: node.end_effector,
                        pose,
                        by: None,
                    };
                    SceneValidity::new(scene, &[], &arms, blocker, placement)
                        .map(|v| v.with_obstacles(obstacles))
                        .is_ok_and(|v| matches!(v.is_valid(&[], scratch), Ok(true)))
                };
                if free(&others, &mut scratch) && free(&goal_place, &mut scratch) {
                    let at = pose.translation.vector;
                    let distance = keep_out
                        .iter()
                        .map(|k| (at - k).norm())
                        .fold(f64::INFINITY, f64::min);
                    candidates.push((node, pose, distance));
                }
            }
        }
        // Far enough first, then the same workspace, the same surface, and the farthest.
        let rank = |(node, _, distance): &(Node, Iso, f64)| {
            (
                *distance < CLEARANCE,
                node.end_effector != current.end_effector,
                node.workspace != current.workspace,
            )
        };
        candidates.sort_by(|a, b| rank(a).cmp(&rank(b)).then_with(|| b.2.total_cmp(&a.2)));
        let mut planned = 0;
        for (node, pose, _) in candidates.into_iter().take(CANDIDATES_EXAMINED) {
            if planned == CANDIDATES_TRIED {
                break;
            }
            // Not where it blocks again: the move (its exchanges, without motions) planned
            // with the blocking object standing there.
            let mut there = world.clone();
            there.set_object(
                blocker,
                Whereabouts::Placed {
                    state: node,
                    pose: Some(pose),
                },
            );
            match self.plan_move(&there, object, goal, &bounded(false)) {
                Err(error @ (PlanError::TimeBudget { .. } | PlanError::InvalidOption { .. })) => {
                    return Err(error)
                }
                Err(error) if error.blockers().contains(&blocker) => continue,
                _ => {}
            }
            planned += 1;
            let goal = Goal::Placement(Placement {
                holder: node.end_effector,
                grasp: Some(node.grasp),
                workspace: Some(node.workspace),
                pose: Some(pose),
            });
            match self.plan_move(world, blocker, &goal, &bounded(true)) {
                Ok(plan) => return Ok(Some(plan)),
                Err(error @ (PlanError::TimeBudget { .. } | PlanError::InvalidOption { .. })) => {
                    return Err(error)
                }
                Err(_) => {}
            }
        }
        Ok(None)
    }

    /// The places the move of `object` needs in `world`: where it is, and its goal pose.
    fn places_needed(&self, world: &World, object: ObjectId, goal: &Goal) -> Vec<Vec3> {
        let start = world.pose(self.artifact, self.scene, object);
        let goal = match goal {
            Goal::Placement(p) => p.pose,
            Goal::Workspace { .. } => None,
        };
        [start, goal]
            .into_iter()
            .flatten()
            .map(|p| p.translation.vector)
            .collect()
    }
}

/// Where the steps that failed needed room (the exchanges' positions).
fn blocked_places(error: &PlanError) -> Vec<Vec3> {
    match error {
        PlanError::Unreachable(u) => u
            .blockers()
            .filter_map(|(_, b)| b.during.position())
            .map(|[x, y, z]| Vec3::new(x, y, z))
            .collect(),
        _ => Vec::new(),
    }
}
