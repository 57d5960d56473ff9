//! The scene's side of [`Frozen`]: the arms that stand still away from home during a
//! motion are put through forward kinematics once and, with the objects that do not ride
//! a moving hand, placed once over the scene's home; a query computes only the moving
//! arms' frames and the object they carry.

use cellc_schema::EndEffectorId;

use super::query::{same_joints, INLINE_ROBOTS};
use super::{Holder, Placed, QueryError, Scene, SceneScratch};
use crate::collision::{Configuration, Frozen, ObjectState, Standing, SweepBounds};
use crate::math::Iso;
use crate::scene::ObjectPlacement;

/// A motion's standing part, for [`Scene::is_free_frozen`] and
/// [`Scene::free_radius_frozen`]: which arms move, the frames of the arms that stand
/// still away from home, every object's state but the one a moving hand carries.
#[derive(Clone)]
pub(crate) struct FrozenScene {
    frozen: Frozen,
    /// Per world robot: its frames, for the robots that stand still away from home
    /// (empty for the others).
    frames: Vec<Vec<Iso>>,
    /// Per world robot: whether it stands still away from home.
    away: Vec<bool>,
    /// Per object: its state; the carried object's is recomputed per query.
    objects: Vec<ObjectState>,
    /// The object a moving hand carries, and how.
    carried: Option<(usize, ObjectPlacement)>,
}

impl Scene {
    /// Freezes every arm but `moving` at the joints `arms` gives (others at home, where
    /// the scene's home already has them) and every object placed as `at` says, except
    /// one that follows a moving hand; `known_free` as in
    /// [`CollisionWorld::freeze`](crate::collision::CollisionWorld). Fails when the scene
    /// has no home (the plain queries answer then).
    pub(crate) fn freeze(
        &self,
        arms: &[(EndEffectorId, &[f64])],
        moving: &[EndEffectorId],
        at: Placed<'_>,
        known_free: bool,
        scratch: &mut SceneScratch,
    ) -> Result<FrozenScene, QueryError> {
        let home = self.frozen_home()?;
        let n = self.robot_holder.len();
        let mut frames = vec![Vec::new(); n];
        let mut moving_robot = vec![false; n];
        let mut away = vec![false; n];
        for (r, &e) in self.robot_holder.iter().enumerate() {
            let Holder::Arm { robot, base, home } = &self.holders[e] else {
                continue;
            };
            moving_robot[r] = moving.iter().any(|m| m.index() == e);
            if let Some((_, q)) = arms.iter().find(|(arm, _)| arm.index() == e) {
                // An arm standing at its home joints stands in the scene's home.
                if !moving_robot[r] && !same_joints(q, home) {
                    away[r] = true;
                    self.robots[*robot].fk_frames(base, q, &mut frames[r]);
                }
            }
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
        // Every robot's frames as the state needs them: home for those at home
        // (moving ones too: their entries are not read here).
        let robots: Vec<&[Iso]> = (0..n)
            .map(|r| {
                if away[r] {
                    frames[r].as_slice()
                } else {
                    self.home_frames[r].as_slice()
                }
            })
            .collect();
        for (object, placement) in placements {
            let state = self.object_state(placement, &robots)?;
            if let Some(slot) = objects.get_mut(object.index()) {
                *slot = state;
                if rides(&placement) {
                    moving_object[object.index()] = true;
                    carried = Some((object.index(), placement));
                }
            }
        }
        let state = Configuration {
            robots: robots.as_slice(),
            objects: &objects,
        };
        let frozen = self
            .world
            .freeze(
                home,
                &state,
                &moving_robot,
                &away,
                &moving_object,
                known_free,
                &mut scratch.collision,
            )
            .map_err(QueryError::Collision)?;
        Ok(FrozenScene {
            frozen,
            frames,
            away,
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
        self.with_moving(frozen, arms, scratch, |state, standing, scratch| {
            self.world.is_free_standing(standing, state, scratch)
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
        self.with_moving(frozen, arms, scratch, |state, standing, scratch| {
            self.world
                .free_radius_standing(standing, state, bounds, horizon, scratch)
        })
    }

    /// Starts a batch of states of the motion `frozen` was made for, for the batched
    /// screen (`collision/batch.rs`): [`Scene::screen_place`] each state, then
    /// [`Scene::screen_clear`].
    pub(crate) fn screen_begin(
        &self,
        frozen: &FrozenScene,
        scratch: &mut SceneScratch,
    ) -> Result<(), QueryError> {
        let standing = self.frozen_standing(frozen)?;
        self.world
            .batch_begin(&standing, &mut scratch.collision.batch);
        Ok(())
    }

    /// Adds the state with the moving arms at `arms` (every moving arm listed) to the
    /// batch: their forward kinematics into the scratch's frames (no allocation once
    /// they have grown), the carried object on its hand, the live bodies' capsules.
    pub(crate) fn screen_place(
        &self,
        frozen: &FrozenScene,
        arms: &[(EndEffectorId, &[f64])],
        scratch: &mut SceneScratch,
    ) -> Result<(), QueryError> {
        self.with_moving(frozen, arms, scratch, |state, standing, scratch| {
            self.world.batch_place(standing, state, &mut scratch.batch);
            Ok(())
        })
    }

    /// What the screen proves of each state placed since [`Scene::screen_begin`], in
    /// order (`out` has one verdict per state: free, colliding, or `None`, unknown; all
    /// unknown when the screen cannot judge).
    pub(crate) fn screen_clear(
        &self,
        frozen: &FrozenScene,
        scratch: &mut SceneScratch,
        out: &mut [Option<bool>],
    ) {
        out.fill(None);
        let Ok(standing) = self.frozen_standing(frozen) else {
            return;
        };
        self.world
            .batch_clear(&standing, &mut scratch.collision.batch, out);
    }

    /// The state with the moving arms at `arms`: their frames computed into the
    /// scratch, the standing robots' frames taken from `frozen` (away from home) or the
    /// scene (at home), the objects from `frozen`, the carried object placed on its hand.
    fn with_moving<T>(
        &self,
        frozen: &FrozenScene,
        arms: &[(EndEffectorId, &[f64])],
        scratch: &mut SceneScratch,
        query: impl FnOnce(
            &Configuration<'_>,
            &Standing<'_>,
            &mut crate::collision::CollisionScratch,
        ) -> Result<T, crate::collision::CollisionError>,
    ) -> Result<T, QueryError> {
        let standing = self.frozen_standing(frozen)?;
        let n = self.robot_holder.len();
        let moving = standing.live;
        scratch.frames.resize_with(n, Vec::new);
        for &(e, q) in arms {
            let Some(r) = self.world_robot(e) else {
                return Err(QueryError::NotAnArm(e));
            };
            if !moving.get(r).copied().unwrap_or(false) {
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
        let pick = |r: usize| -> &[Iso] {
            if moving.get(r).copied().unwrap_or(false) {
                &scratch.frames[r]
            } else if frozen.away.get(r).copied().unwrap_or(false) {
                &frozen.frames[r]
            } else {
                &self.home_frames[r]
            }
        };
        let mut inline: [&[Iso]; INLINE_ROBOTS] = [&[]; INLINE_ROBOTS];
        let heap: Vec<&[Iso]>;
        let frames: &[&[Iso]] = if n <= INLINE_ROBOTS {
            for (r, slot) in inline.iter_mut().enumerate().take(n) {
                *slot = pick(r);
            }
            &inline[..n]
        } else {
            heap = (0..n).map(pick).collect();
            &heap
        };
        if let Some((object, placement)) = frozen.carried {
            let state = self.object_state(placement, frames)?;
            scratch.objects[object] = state;
        }
        let configuration = Configuration {
            robots: frames,
            objects: &scratch.objects,
        };
        query(&configuration, &standing, &mut scratch.collision).map_err(QueryError::Collision)
    }

    /// What stands during `frozen`'s motion: the home, less the moving robots, and the
    /// motion's standing set.
    fn frozen_standing<'a>(&'a self, frozen: &'a FrozenScene) -> Result<Standing<'a>, QueryError> {
        Ok(Standing {
            home: self.frozen_home()?,
            live: frozen.frozen.moving(),
            frozen: Some(&frozen.frozen),
        })
    }

    /// The scene's home, which every frozen query stands on; a scene without one (its
    /// home state could not be placed) is refused as a world of the wrong shape, and the
    /// checker falls back to the plain queries.
    fn frozen_home(&self) -> Result<&crate::collision::Home, QueryError> {
        self.at_home().ok_or(QueryError::Collision(
            crate::collision::CollisionError::RobotCount {
                expected: self.robot_holder.len(),
                found: 0,
            },
        ))
    }
}
