//! A path made into commands: exchanges first (following the object), then the moves
//! between them, then (optionally) the joint motions.

use cellc_schema::{ArcKind, ObjectId};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use super::{apply, Exchange, Planner, Setback, WorldState};
use crate::math::Iso;
use crate::plan::search::{simplify, Path};
use crate::plan::{ArcRef, Around, Command, Detour, PlanOptions, Step};
use crate::termination::Termination;

impl Planner<'_> {
    /// Turns a path into commands (with the put-downs moved off poses the world's other
    /// objects take), or says which arc failed (or that the request is refused).
    pub(super) fn realise(
        &self,
        object: ObjectId,
        path: &Path,
        goal_pose: Option<Iso>,
        state: &WorldState,
        options: &PlanOptions,
        stop: &Termination,
    ) -> Result<(Vec<Step>, Vec<Detour>), Setback> {
        let graph = &self.artifact.objects[object.index()].graph;
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
            ChaCha8Rng::seed_from_u64(options.seed ^ u64::from(object.0).wrapping_mul(0x9E37_79B9));
        let state_at_start = state.clone();
        let obstacles = &state.around.obstacles;
        let mut state = state.clone();
        let mut steps = Vec::new();
        let mut detours = Vec::new();
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
                    self.shared_rest_pose(object, (from, a), (picker, b), obstacles, &mut rng, stop)
                }
                _ => None,
            };
            let place_at = if last { goal_pose } else { shared_pose };
            let exchange = match self.exchange(
                object, a, from, to, object_now, place_at, obstacles, &mut rng, stop,
            ) {
                Err(_) if !last && place_at.is_some() => self.exchange(
                    object, a, from, to, object_now, None, obstacles, &mut rng, stop,
                )?,
                other => other?,
            };
            if exchange.object.is_some() {
                object_now = exchange.object;
            }
            if let Some(blocker) = exchange.detour {
                detours.push(Detour {
                    arc: ArcRef::of(&graph.arcs[a]),
                    blocker,
                    around: Around::OtherPose,
                });
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
                        arc: Some(ArcRef::of(arc)),
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
                        arc: Some(ArcRef::of(arc)),
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
                        arc: Some(ArcRef::of(arc)),
                        motion_context: None,
                    });
                }
            }
        }
        if options.motions {
            let start = graph.nodes[path.nodes[0].index()];
            let timing = &options.timing;
            self.add_motions(
                object,
                start,
                &mut steps,
                &state_at_start,
                timing,
                &mut rng,
                stop,
            )?;
        }
        Ok((steps, detours))
    }
}
