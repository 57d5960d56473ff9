//! Two hands on one object: in a handoff both hands hold the object rigidly, so whether
//! their solids overlap depends on the two grasps (and the symmetry turn of the second)
//! alone, not on the arms, their joints or the workspace. The closed-chain solver does not
//! know that: a pair of grasps that puts both palms in the same place converges to one
//! handoff pose after another, each refused by the collision check, until every placement
//! of the check is spent (in `vito_full.cell` a quarter of the failing handoffs, each
//! costing about 15 ms). Here each grasp pair is tested once, before any IK, and the turns
//! under which the hands overlap are left out; a pair with no turn left is pruned at once
//! with the two solids that overlap.
//!
//! Only overlaps deeper than [`OVERLAP_DEPTH`] count, so that a pose the solver's loop
//! tolerances would move by a fraction of a millimetre cannot be refused here while the
//! collision check would accept it: what is left out would have collided anyway.

use std::collections::BTreeMap;

use cellc_schema::{Artifact, EndEffectorId, GraspId, ObjectId};
use parry3d_f64::query;
use rayon::prelude::*;

use super::Check;
use crate::collision::BodyId;
use crate::math::{Iso, Quat};
use crate::scene::{PlacedShape, Scene};

/// Overlap (metres of penetration) from which two hands on one object are certain to
/// collide in every handoff: ten times the loop-closure position tolerance of the
/// handoff solver, and more than its rotation tolerance moves a point 20 cm away.
pub const OVERLAP_DEPTH: f64 = 1e-3;

/// What is known of a grasp pair before any IK.
#[derive(Clone, Debug)]
pub(super) enum Turns {
    /// The turns of the second grasp (in the order they are tried) under which the hands
    /// stay apart.
    Apart(Vec<Quat>),
    /// Every turn puts the hands into each other; these two solids overlap under the
    /// first one.
    Overlap { a: BodyId, b: BodyId },
}

/// A grasp pair of one object, on two hand kinds (`None`: a holder without solids).
type Key = (ObjectId, Option<u32>, GraspId, Option<u32>, GraspId);

/// The turns of every handoff check's grasp pair, computed once per pair.
pub(super) struct TurnTable {
    turns: BTreeMap<Key, Pair>,
}

/// A grasp pair's answer, for any two arms with those hands: the turns that keep the hands
/// apart, or the two hand solids (A's, B's) that overlap under every turn.
type Pair = Result<Vec<Quat>, (usize, usize)>;

impl TurnTable {
    /// Tests the grasp pair of every handoff among `checks`, in parallel.
    pub(super) fn new(artifact: &Artifact, scene: &Scene, checks: &[Check]) -> TurnTable {
        let kind = |e: EndEffectorId| artifact.end_effectors[e.index()].kind;
        let mut keys: BTreeMap<Key, (EndEffectorId, EndEffectorId)> = BTreeMap::new();
        for check in checks {
            if let Check::Handoff {
                object,
                a,
                ga,
                b,
                gb,
                ..
            } = *check
            {
                keys.entry((object, kind(a), ga, kind(b), gb))
                    .or_insert((a, b));
            }
        }
        let turns = keys
            .into_par_iter()
            .map(|(key, (a, b))| {
                let (object, _, ga, _, gb) = key;
                (key, grasp_pair(artifact, scene, object, (a, ga), (b, gb)))
            })
            .collect();
        TurnTable { turns }
    }

    /// The turns of the handoff of `object` from `a` with `ga` to `b` with `gb`. Names
    /// the solids of `a` and `b` themselves when they overlap (the table is shared by
    /// every pair of arms with the same hands).
    pub(super) fn get(
        &self,
        artifact: &Artifact,
        scene: &Scene,
        object: ObjectId,
        (a, ga): (EndEffectorId, GraspId),
        (b, gb): (EndEffectorId, GraspId),
    ) -> Turns {
        let kind = |e: EndEffectorId| artifact.end_effectors[e.index()].kind;
        let pair = match self.turns.get(&(object, kind(a), ga, kind(b), gb)) {
            Some(pair) => pair.clone(),
            None => grasp_pair(artifact, scene, object, (a, ga), (b, gb)),
        };
        match (pair, scene.world_robot(a), scene.world_robot(b)) {
            (Err((s, t)), Some(ra), Some(rb)) => Turns::Overlap {
                a: BodyId::Hand {
                    robot: ra,
                    solid: s,
                },
                b: BodyId::Hand {
                    robot: rb,
                    solid: t,
                },
            },
            (Ok(turns), ..) => Turns::Apart(turns),
            // An overlap is only ever found between two arms' hands.
            (Err(_), ..) => Turns::Apart(Vec::new()),
        }
    }
}

/// The turns tried for B's grasp: every symmetry of the object, and with the same grasp
/// on both sides only those that send the second hand round to the other side (over
/// 120°; the unturned grasp puts both hands in one place), unless there are none.
fn candidate_turns(artifact: &Artifact, object: ObjectId, same_grasp: bool) -> Vec<Quat> {
    let all = crate::symmetry::candidates(&artifact.objects[object.index()].symmetries);
    if same_grasp {
        let far: Vec<Quat> = all.iter().copied().filter(|t| t.angle() > 2.0).collect();
        if !far.is_empty() {
            return far;
        }
    }
    all
}

/// Which turns of `gb` keep B's hand out of A's, both holding the object.
fn grasp_pair(
    artifact: &Artifact,
    scene: &Scene,
    object: ObjectId,
    (a, ga): (EndEffectorId, GraspId),
    (b, gb): (EndEffectorId, GraspId),
) -> Pair {
    let turns = candidate_turns(artifact, object, ga == gb);
    let solids = |e: EndEffectorId| -> &[PlacedShape] {
        artifact.end_effectors[e.index()]
            .kind
            .and_then(|k| scene.kind_solids.get(k as usize))
            .map_or(&[], Vec::as_slice)
    };
    let (solids_a, solids_b) = (solids(a), solids(b));
    let (Some(ra), Some(rb)) = (scene.world_robot(a), scene.world_robot(b)) else {
        return Ok(turns);
    };
    if solids_a.is_empty() || solids_b.is_empty() {
        return Ok(turns);
    }
    // Hands the cell allows to touch are never refused.
    let allowed = |s: usize, t: usize| {
        scene.world.is_allowed(
            BodyId::Hand {
                robot: ra,
                solid: s,
            },
            BodyId::Hand {
                robot: rb,
                solid: t,
            },
        )
    };
    // Each hand in the object's frame: the grasp is the object in the hand's frame.
    let hand_a = artifact.grasp_pose(object, ga).inverse();
    let grasp_b = artifact.grasp_pose(object, gb);
    let mut first_overlap = None;
    let apart: Vec<Quat> = turns
        .iter()
        .copied()
        .filter(|turn| {
            let hand_b = (grasp_b * *turn).inverse();
            match overlap(solids_a, &hand_a, solids_b, &hand_b, &allowed) {
                Some(pair) => {
                    first_overlap.get_or_insert(pair);
                    false
                }
                None => true,
            }
        })
        .collect();
    match (apart.is_empty(), first_overlap) {
        (true, Some(solids)) => Err(solids),
        _ => Ok(apart),
    }
}

/// The first pair of solids (A's, B's) that overlap deeper than [`OVERLAP_DEPTH`].
fn overlap(
    solids_a: &[PlacedShape],
    at_a: &Iso,
    solids_b: &[PlacedShape],
    at_b: &Iso,
    allowed: &dyn Fn(usize, usize) -> bool,
) -> Option<(usize, usize)> {
    for (s, sa) in solids_a.iter().enumerate() {
        let pa = at_a * sa.local;
        for (t, sb) in solids_b.iter().enumerate() {
            if allowed(s, t) {
                continue;
            }
            let pb = at_b * sb.local;
            // A pair parry cannot measure is left to the collision check.
            if let Ok(Some(contact)) =
                query::contact(&pa, sa.shape.as_ref(), &pb, sb.shape.as_ref(), 0.0)
            {
                if contact.dist < -OVERLAP_DEPTH {
                    return Some((s, t));
                }
            }
        }
    }
    None
}
