//! The scene's side of [`Frozen`]: the arms that stand still during a motion are put
//! through forward kinematics once, the objects that do not ride a moving hand are placed
//! once, and a query computes only the moving arms' frames and the object they carry.

use cellc_schema::EndEffectorId;

use super::query::INLINE_ROBOTS;
use super::{Holder, Placed, QueryError, Scene, SceneScratch};
use crate::collision::{Configuration, Frozen, ObjectState, SweepBounds};
use crate::math::Iso;
use crate::scene::ObjectPlacement;

/// A motion's standing part, for [`Scene::is_free_frozen`] and
/// [`Scene::free_radius_frozen`]: which arms move, every other arm's frames, every
/// object's state but the one a moving hand carries.
#[derive(Clone)]
pub(crate) struct FrozenScene {
    frozen: Frozen,
    /// Per world robot: its frames, for the robots that stand still.
    frames: Vec<Vec<Iso>>,
    /// Per world robot: whether it moves.
    moving: Vec<bool>,
    /// Per object: its state; the carried object's is recomputed per query.
    objects: Vec<ObjectState>,
    /// The object a moving hand carries, and how.
    carried: Option<(usize, ObjectPlacement)>,
}

impl Scene {
    /// Freezes every arm but `moving` at the joints `arms` gives (others at home) and
    /// every object placed as `at` says, except one that follows a moving hand;
    /// `known_free` as in [`CollisionWorld::freeze`](crate::collision::CollisionWorld).
    pub(crate) fn freeze(
        &self,
        arms: &[(EndEffectorId, &[f64])],
        moving: &[EndEffectorId],
        at: Placed<'_>,
        known_free: bool,
        scratch: &mut SceneScratch,
    ) -> Result<FrozenScene, QueryError> {
        let n = self.robot_holder.len();
        let mut frames = vec![Vec::new(); n];
        let mut moving_robot = vec![false; n];
        for (r, &e) in self.robot_holder.iter().enumerate() {
            let Holder::Arm { robot, base, home } = &self.holders[e] else {
                continue;
            };
            moving_robot[r] = moving.iter().any(|m| m.index() == e);
            let q = arms
                .iter()
                .find(|(arm, _)| arm.index() == e)
                .map_or(home.as_slice(), |(_, q)| *q);
            self.robots[*robot].fk_frames(base, q, &mut frames[r]);
        }
        let mut objects = vec![ObjectState::absent(); self.object_shapes.len()];
        let mut carried = None;
        let rides = |p: &ObjectPlacement| -> bool {
            let by = match *p {
                ObjectPlacement::Held { by, .. } | ObjectPlacement::Placing { by, .. } => by,
                ObjectPlacement::Handoff { a, .. } => a,
                ObjectPlacement::Resting { .. } | ObjectPlacement::Absent => return false,
            };
            moving.contains(&by)
        };
        let mut moving_object = vec![false; objects.len()];
        let placements = std::iter::once((at.object, at.placement))
            .chain(at.obstacles.iter().map(|o| (o.object, o.placement)));
        for (object, placement) in placements {
            let state = self.object_state(placement, &frames)?;
            if let Some(slot) = objects.get_mut(object.index()) {
                *slot = state;
                if rides(&placement) {
                    moving_object[object.index()] = true;
                    carried = Some((object.index(), placement));
                }
            }
        }
        let robots: Vec<&[Iso]> = frames.iter().map(Vec::as_slice).collect();
        let state = Configuration {
            robots: &robots,
            objects: &objects,
        };
        let frozen = self
            .world
            .freeze(
                &state,
                &moving_robot,
                &moving_object,
                known_free,
                &mut scratch.collision,
            )
            .map_err(QueryError::Collision)?;
        Ok(FrozenScene {
            frozen,
            frames,
            moving: moving_robot,
            objects,
            carried,
        })
    }

    /// Whether the state with the moving arms at `arms` (every moving arm listed) is
    /// free: [`Scene::is_free`] for the motion `frozen` was made for.
    pub(crate) fn is_free_frozen(
        &self,
        frozen: &FrozenScene,
        arms: &[(EndEffectorId, &[f64])],
        scratch: &mut SceneScratch,
    ) -> Result<bool, QueryError> {
        if frozen.frozen.blocked() {
            return Ok(false);
        }
        self.with_moving(frozen, arms, scratch, |state, scratch| {
            self.world.is_free_frozen(&frozen.frozen, state, scratch)
        })
    }

    /// [`Scene::free_radius`] for the motion `frozen` was made for.
    pub(crate) fn free_radius_frozen(
        &self,
        frozen: &FrozenScene,
        arms: &[(EndEffectorId, &[f64])],
        bounds: &SweepBounds,
        horizon: f64,
        scratch: &mut SceneScratch,
    ) -> Result<f64, QueryError> {
        self.with_moving(frozen, arms, scratch, |state, scratch| {
            self.world
                .free_radius_frozen(&frozen.frozen, state, bounds, horizon, scratch)
        })
    }

    /// The state with the moving arms at `arms`: their frames computed into the
    /// scratch, the standing robots' frames and the objects taken from `frozen`, the
    /// carried object placed on its hand.
    fn with_moving<T>(
        &self,
        frozen: &FrozenScene,
        arms: &[(EndEffectorId, &[f64])],
        scratch: &mut SceneScratch,
        query: impl FnOnce(
            &Configuration<'_>,
            &mut crate::collision::CollisionScratch,
        ) -> Result<T, crate::collision::CollisionError>,
    ) -> Result<T, QueryError> {
        let n = self.robot_holder.len();
        scratch.frames.resize_with(n, Vec::new);
        for &(e, q) in arms {
            let Some(r) = self.world_robot(e) else {
                return Err(QueryError::NotAnArm(e));
            };
            if !frozen.moving.get(r).copied().unwrap_or(false) {
                continue;
            }
            let Holder::Arm { robot, base, .. } = &self.holders[e.index()] else {
                return Err(QueryError::NotAnArm(e));
            };
            self.robots[*robot].fk_frames(base, q, &mut scratch.frames[r]);
            scratch.mark_moved(r);
        }
        scratch.objects.clear();
        scratch.objects.extend_from_slice(&frozen.objects);
        if let Some((object, placement)) = frozen.carried {
            scratch.objects[object] = self.object_state(placement, &scratch.frames)?;
        }
        let mut inline: [&[Iso]; INLINE_ROBOTS] = [&[]; INLINE_ROBOTS];
        let heap: Vec<&[Iso]>;
        let pick = |r: usize| -> &[Iso] {
            if frozen.moving[r] {
                &scratch.frames[r]
            } else {
                &frozen.frames[r]
            }
        };
        let frames: &[&[Iso]] = if n <= INLINE_ROBOTS {
            for (r, slot) in inline.iter_mut().enumerate().take(n) {
                *slot = pick(r);
            }
            &inline[..n]
        } else {
            heap = (0..n).map(pick).collect();
            &heap
        };
        let configuration = Configuration {
            robots: frames,
            objects: &scratch.objects,
        };
        query(&configuration, &mut scratch.collision).map_err(QueryError::Collision)
    }
}
