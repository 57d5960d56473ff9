//! Which of the world's objects blocks a step: the typed fact behind "`ball` blocks the
//! put-down at ...".
//!
//! A step planned in a world is checked with the world's other objects in the scene. When
//! it fails, the same check without them says whether they are the cause: a state that is
//! valid without them and collides with them is blocked, and the first collision names
//! the object and the part of the plan (the moved object, an arm's link, its hand) by
//! body id. A state that is not valid even without them (the arm in the torso, a joint out
//! of its limits) is not blocked by anything the world could move, and is reported as it
//! was before.

use cellc_schema::{BlockedPart, ObjectId};

use crate::collision::BodyId;
use crate::scene::{Scene, SceneScratch};
use crate::validity::{SceneValidity, StateFault, StateValidity};

/// The object of the world that makes `q` invalid, with the part of the plan that runs
/// into it: `q` must be valid in `without` (the check with no other object) and collide
/// with one of the objects `with` has (the same check with them).
pub(super) fn blocker_at(
    scene: &Scene,
    object: ObjectId,
    (without, with): (&SceneValidity<'_>, &SceneValidity<'_>),
    q: &[f64],
    scratch: &mut SceneScratch,
) -> Option<(ObjectId, BlockedPart)> {
    if !matches!(without.check(q, scratch), Ok(None)) {
        return None;
    }
    let contact = with.first_contact(q, scratch).ok()??;
    // One body is another object, the other a part of the plan.
    let other = |body: BodyId| match body {
        BodyId::Object(i) if i != object.index() => Some(ObjectId(i as u32)),
        _ => None,
    };
    let (blocker, hit) = match (other(contact.a), other(contact.b)) {
        (Some(o), None) => (o, contact.b),
        (None, Some(o)) => (o, contact.a),
        _ => return None,
    };
    let part = match hit {
        BodyId::Object(i) if i == object.index() => BlockedPart::Object,
        BodyId::Hand { .. } => BlockedPart::Hand(scene.arm_of(hit)?),
        BodyId::Link { .. } => BlockedPart::Arm(scene.arm_of(hit)?),
        BodyId::Object(_) | BodyId::Fixed(_) => return None,
    };
    Some((blocker, part))
}

/// Why a configuration is not valid in a world.
pub(super) enum Fault {
    /// Free but for this object of the world, which this part of the plan runs into.
    Blocked(ObjectId, BlockedPart),
    /// Not valid even without the world's objects (or with none of them to name): the
    /// fault the check without them finds, or the one found with them.
    Own(StateFault),
}

/// Why `q`, found invalid (`found`) in `with`, is so: the object of the world that blocks
/// it, or the fault it has without the world's objects.
pub(super) fn fault_of(
    scene: &Scene,
    object: ObjectId,
    (without, with): (&SceneValidity<'_>, &SceneValidity<'_>),
    q: &[f64],
    found: StateFault,
    scratch: &mut SceneScratch,
) -> Fault {
    match without.check(q, scratch) {
        Ok(Some(own)) => Fault::Own(own),
        Ok(None) => match blocker_at(scene, object, (without, with), q, scratch) {
            Some((by, part)) => Fault::Blocked(by, part),
            None => Fault::Own(found),
        },
        Err(_) => Fault::Own(found),
    }
}

/// The object of the world that blocks a motion from `from` to `to` that the motion
/// planner could not find: one that makes either end invalid (valid without it), or else
/// one on the straight joint-space path (checked every `resolution` of the joint that
/// moves most) when that whole path is valid without the world's objects. `None` when the
/// ends are free and the straight path is blocked by something else too: the failure is
/// then not the world's doing, as far as this cheap test can tell.
pub(super) fn blocker_on_path(
    scene: &Scene,
    object: ObjectId,
    (without, with): (&SceneValidity<'_>, &SceneValidity<'_>),
    (from, to): (&[f64], &[f64]),
    resolution: f64,
    scratch: &mut SceneScratch,
) -> Option<(ObjectId, BlockedPart)> {
    let longest = from
        .iter()
        .zip(to)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    if !(longest.is_finite() && resolution > 0.0) {
        return None;
    }
    for end in [from, to] {
        if let Some(found) = blocker_at(scene, object, (without, with), end, scratch) {
            return Some(found);
        }
    }
    let n = ((longest / resolution).ceil() as usize).max(1);
    let mut q = from.to_vec();
    let mut found = None;
    for i in 0..=n {
        let t = i as f64 / n as f64;
        for ((x, a), b) in q.iter_mut().zip(from).zip(to) {
            *x = a + (b - a) * t;
        }
        if !matches!(without.check(&q, scratch), Ok(None)) {
            return None;
        }
        if found.is_none() && !matches!(with.is_valid(&q, scratch), Ok(true)) {
            // Invalid with the objects but not blocked by one (two of them touching).
            match blocker_at(scene, object, (without, with), &q, scratch) {
                Some(blocker) => found = Some(blocker),
                None => return None,
            }
        }
    }
    found
}
