//! The scene's collision queries: one object placed as an [`ObjectPlacement`] (and the
//! world's other objects as [`Obstacle`]s), the arms asked about at the given joints and
//! every other arm at home; the state is built in a per-thread [`SceneScratch`] so that
//! the inner loops of planning never allocate.

use cellc_schema::{EndEffectorId, ObjectId};

use super::{Holder, Scene};
use crate::collision::{
    Collision, CollisionError, CollisionScratch, Configuration, Holder as CollisionHolder,
    ObjectState, Standing, SweepBounds,
};
use crate::math::Iso;

/// Where the checked object is in a collision query.
#[derive(Clone, Copy, Debug)]
pub enum ObjectPlacement {
    /// Held by one arm with a grasp (object pose in the hand frame).
    Held {
        /// End-effector.
        by: EndEffectorId,
        /// Grasp pose.
        grasp: Iso,
    },
    /// Held by an arm that is putting it down on a surface: the object follows the hand
    /// and may touch that surface.
    Placing {
        /// The arm.
        by: EndEffectorId,
        /// Its grasp.
        grasp: Iso,
        /// The surface it goes onto.
        on: EndEffectorId,
        /// Another arm's hand still on the object (it let go but could not retreat).
        also: Option<EndEffectorId>,
        /// The surface the carry lifted it from, when it also ends on another one (a
        /// carry from one bench straight onto the next starts touching the first and
        /// ends touching the second).
        from: Option<EndEffectorId>,
    },
    /// Held by two arms at once (a handoff); the pose follows the first.
    Handoff {
        /// End-effector whose grasp places the object.
        a: EndEffectorId,
        /// Its grasp.
        grasp_a: Iso,
        /// The other holder.
        b: EndEffectorId,
    },
    /// Resting on a surface at `pose`, possibly held by an arm too (a pick or a place).
    Resting {
        /// The surface end-effector.
        on: EndEffectorId,
        /// Object pose in the cell.
        pose: Iso,
        /// The arm holding it at the same time.
        by: Option<EndEffectorId>,
    },
    /// Left out of the check (motions with the object elsewhere, or none moved yet).
    Absent,
}

/// Another object as a collision query sees it: in the scene, not the one the query is
/// about (the world's other objects, during a plan for one of them).
#[derive(Clone, Copy, Debug)]
pub struct Obstacle {
    /// The object.
    pub object: ObjectId,
    /// Where it is: resting on a surface at a pose, or held by an arm.
    pub placement: ObjectPlacement,
}

/// The objects of one query: the one it is about, placed as `placement`, and the others.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Placed<'a> {
    pub(crate) object: ObjectId,
    pub(crate) placement: ObjectPlacement,
    pub(crate) obstacles: &'a [Obstacle],
}

/// Why a collision query could not be answered.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum QueryError {
    /// The end-effector is not an arm of the scene.
    NotAnArm(EndEffectorId),
    /// The end-effector is not a surface of the scene.
    NotASurface(EndEffectorId),
    /// The collision world refused the state.
    Collision(CollisionError),
    /// A configuration has the wrong number of joint values for the arms it is for.
    WrongLength {
        /// Values expected.
        expected: usize,
        /// Values given.
        found: usize,
    },
}

/// Whether `q` is `home`, bit for bit (so its frames are the home frames exactly).
pub(super) fn same_joints(q: &[f64], home: &[f64]) -> bool {
    q.len() == home.len() && q.iter().zip(home).all(|(a, b)| a.to_bits() == b.to_bits())
}

/// Robots whose frames one query lists without allocating (more fall back to a vector).
pub(super) const INLINE_ROBOTS: usize = 64;

/// Buffers for [`Scene::collision`], one per thread.
#[derive(Default)]
pub struct SceneScratch {
    pub(super) frames: Vec<Vec<Iso>>,
    pub(super) objects: Vec<ObjectState>,
    pub(super) collision: CollisionScratch,
    /// Per world robot: whether `frames` holds its home frames (so an arm left at home
    /// costs nothing), for the scene `scene`.
    at_home: Vec<bool>,
    scene: u64,
    /// Per world robot: whether the query gives its joints (its bodies are placed; the
    /// others stand at home, `collision::home`).
    pub(super) live: Vec<bool>,
    /// How far the bodies travel along the segment a sound motion check is certifying
    /// (`crate::swept`), kept here so that no query allocates.
    pub(crate) sweep: SweepBounds,
    /// The batched screen's verdicts (`validity.rs`), kept here so that no screen
    /// allocates.
    pub(crate) verdicts: Vec<Option<bool>>,
}

impl SceneScratch {
    /// Robot `r`'s frames were overwritten with another configuration than home.
    pub(super) fn mark_moved(&mut self, r: usize) {
        if let Some(h) = self.at_home.get_mut(r) {
            *h = false;
        }
    }
}

impl Scene {
    /// The first collision when `object` is placed as given, the arms in `arms` take the
    /// given joint values and every other arm stands at its home configuration. Other
    /// objects are left out: verification and planning move one object at a time.
    /// Returns the names of the colliding pair.
    pub fn collision(
        &self,
        arms: &[(EndEffectorId, &[f64])],
        object: ObjectId,
        placement: ObjectPlacement,
        obstacles: &[Obstacle],
        scratch: &mut SceneScratch,
    ) -> Result<Option<(String, String)>, QueryError> {
        let found = self.first_collision(arms, object, placement, obstacles, scratch)?;
        Ok(found.map(|c| {
            let (a, b) = self.world.names(&c);
            (a.to_string(), b.to_string())
        }))
    }

    /// Every colliding pair of the state [`Scene::collision`] describes, sorted (so reports
    /// that pick one pick the same whatever the sweep order), written to `out`.
    pub fn all_collisions(
        &self,
        arms: &[(EndEffectorId, &[f64])],
        object: ObjectId,
        placement: ObjectPlacement,
        scratch: &mut SceneScratch,
        out: &mut Vec<Collision>,
    ) -> Result<(), QueryError> {
        let at = Placed {
            object,
            placement,
            obstacles: &[],
        };
        self.with_configuration(arms, at, scratch, |state, scratch, _| {
            self.world.all_collisions(state, scratch, out)
        })
    }

    /// The colliding pairs of the state [`Scene::collision`] describes that involve a
    /// body it places (the arms given away from their homes, the object), sorted as
    /// [`Scene::all_collisions`] sorts them, written to `out`. What stands at home is not
    /// placed (`collision::home`), so the cost does not grow with the cell; pairs of two
    /// bodies at home (none in a built cell: `cellc build` refuses them) are not listed.
    pub fn live_collisions(
        &self,
        arms: &[(EndEffectorId, &[f64])],
        object: ObjectId,
        placement: ObjectPlacement,
        scratch: &mut SceneScratch,
        out: &mut Vec<Collision>,
    ) -> Result<(), QueryError> {
        let at = Placed {
            object,
            placement,
            obstacles: &[],
        };
        self.on_home(
            arms,
            at,
            scratch,
            |standing, state, scratch| match standing {
                Some(standing) => self.world.live_collisions(standing, state, scratch, out),
                None => self.world.all_collisions(state, scratch, out),
            },
        )
    }

    /// Whether the state [`Scene::collision`] describes is free, without naming anything
    /// (the inner loops of motion planning ask this millions of times). Only the arms
    /// given and the objects are placed; every other arm and the furniture stand at home
    /// (`collision::home`), so the cost does not grow with the cell.
    pub fn is_free(
        &self,
        arms: &[(EndEffectorId, &[f64])],
        object: ObjectId,
        placement: ObjectPlacement,
        obstacles: &[Obstacle],
        scratch: &mut SceneScratch,
    ) -> Result<bool, QueryError> {
        let at = Placed {
            object,
            placement,
            obstacles,
        };
        self.on_home(
            arms,
            at,
            scratch,
            |standing, state, scratch| match standing {
                Some(standing) => self.world.is_free_standing(standing, state, scratch),
                None => self.world.is_free(state, scratch),
            },
        )
    }

    /// The first colliding pair of the state [`Scene::collision`] describes, as body ids
    /// (an object's body is [`crate::collision::BodyId::Object`] with its object index):
    /// how the planner names the object that blocks a step (`plan::planner::blocking`).
    pub(crate) fn first_collision(
        &self,
        arms: &[(EndEffectorId, &[f64])],
        object: ObjectId,
        placement: ObjectPlacement,
        obstacles: &[Obstacle],
        scratch: &mut SceneScratch,
    ) -> Result<Option<Collision>, QueryError> {
        // Most states asked about are free, and a free one is proved so by the query
        // that stands on the home; a colliding one is asked again of the plain broad
        // phase, so that which pair it names does not depend on the query's order.
        if self.is_free(arms, object, placement, obstacles, scratch)? {
            return Ok(None);
        }
        let at = Placed {
            object,
            placement,
            obstacles,
        };
        self.with_configuration(arms, at, scratch, |state, scratch, _| {
            self.world.first_collision(state, scratch)
        })
    }

    /// How far the state [`Scene::collision`] describes can move along a segment whose
    /// bodies travel as `bounds` says before two bodies that may not touch could touch:
    /// [`CollisionWorld::free_radius`](crate::collision::CollisionWorld::free_radius)
    /// (in the segment's parameter, at most `horizon`).
    pub(crate) fn free_radius(
        &self,
        arms: &[(EndEffectorId, &[f64])],
        at: Placed<'_>,
        bounds: &SweepBounds,
        horizon: f64,
        scratch: &mut SceneScratch,
    ) -> Result<f64, QueryError> {
        self.on_home(
            arms,
            at,
            scratch,
            |standing, state, scratch| match standing {
                Some(standing) => self
                    .world
                    .free_radius_standing(standing, state, bounds, horizon, scratch),
                None => self.world.free_radius(state, bounds, horizon, scratch),
            },
        )
    }

    /// Asks `query` about the state [`Scene::with_configuration`] builds, standing on the
    /// scene's home (what stands at home is not placed: `collision::home`), or with `None`
    /// when the scene has none, for the plain broad phase.
    fn on_home<T>(
        &self,
        arms: &[(EndEffectorId, &[f64])],
        at: Placed<'_>,
        scratch: &mut SceneScratch,
        query: impl FnOnce(
            Option<&Standing<'_>>,
            &Configuration<'_>,
            &mut CollisionScratch,
        ) -> Result<T, CollisionError>,
    ) -> Result<T, QueryError> {
        let home = self.at_home();
        self.with_configuration(arms, at, scratch, |state, scratch, live| {
            let standing = home.map(|home| Standing {
                home,
                live,
                frozen: None,
            });
            query(standing.as_ref(), state, scratch)
        })
    }

    /// Builds the collision state the queries above describe (every arm's frames, the
    /// object placed) in `scratch` and asks `query` about it, with the world robots whose
    /// joints `arms` gives marked.
    pub(super) fn with_configuration<T>(
        &self,
        arms: &[(EndEffectorId, &[f64])],
        at: Placed<'_>,
        scratch: &mut SceneScratch,
        query: impl FnOnce(
            &Configuration<'_>,
            &mut CollisionScratch,
            &[bool],
        ) -> Result<T, CollisionError>,
    ) -> Result<T, QueryError> {
        let n = self.robot_holder.len();
        scratch.frames.resize_with(n, Vec::new);
        scratch.live.clear();
        scratch.live.resize(n, false);
        if scratch.scene != self.id || scratch.at_home.len() != n {
            scratch.at_home.clear();
            scratch.at_home.resize(n, false);
            scratch.scene = self.id;
        }
        for (r, &e) in self.robot_holder.iter().enumerate() {
            let Holder::Arm { robot, base, home } = &self.holders[e] else {
                continue;
            };
            // An arm given at its home joints is at home: the planner lists every arm
            // where it stands, and most stand at home.
            let given = arms
                .iter()
                .find(|(arm, _)| arm.index() == e)
                .filter(|(_, q)| !same_joints(q, home));
            match given {
                Some((_, q)) => {
                    self.robots[*robot].fk_frames(base, q, &mut scratch.frames[r]);
                    scratch.at_home[r] = false;
                    scratch.live[r] = true;
                }
                None if scratch.at_home[r] => {}
                None => {
                    scratch.frames[r].clone_from(&self.home_frames[r]);
                    scratch.at_home[r] = true;
                }
            }
        }
        scratch.objects.clear();
        scratch
            .objects
            .resize(self.object_shapes.len(), ObjectState::absent());
        let state = self.object_state(at.placement, &scratch.frames)?;
        if let Some(slot) = scratch.objects.get_mut(at.object.index()) {
            *slot = state;
        }
        for obstacle in at.obstacles {
            let state = self.object_state(obstacle.placement, &scratch.frames)?;
            if let Some(slot) = scratch.objects.get_mut(obstacle.object.index()) {
                *slot = state;
            }
        }
        // The frames as slices, listed without allocating for the usual handful of arms.
        let mut inline: [&[Iso]; INLINE_ROBOTS] = [&[]; INLINE_ROBOTS];
        let heap: Vec<&[Iso]>;
        let frames: &[&[Iso]] = if n <= INLINE_ROBOTS {
            for (slot, f) in inline.iter_mut().zip(&scratch.frames) {
                *slot = f;
            }
            &inline[..n]
        } else {
            heap = scratch.frames.iter().map(Vec::as_slice).collect();
            &heap
        };
        let configuration = Configuration {
            robots: frames,
            objects: &scratch.objects,
        };
        query(&configuration, &mut scratch.collision, &scratch.live).map_err(QueryError::Collision)
    }

    /// The collision state of an object placed as `placement`, the robots' frames being
    /// `frames` (a held object rides its arm's tip frame).
    pub(super) fn object_state<F: AsRef<[Iso]>>(
        &self,
        placement: ObjectPlacement,
        frames: &[F],
    ) -> Result<ObjectState, QueryError> {
        let robot_of = |e: EndEffectorId| self.world_robot(e);
        let state = match placement {
            ObjectPlacement::Held { by, grasp } => {
                let r = robot_of(by).ok_or(QueryError::NotAnArm(by))?;
                let tip = self
                    .world
                    .tip(r, frames[r].as_ref())
                    .ok_or(QueryError::NotAnArm(by))?;
                ObjectState::held(r, &tip, &grasp)
            }
            ObjectPlacement::Placing {
                by,
                grasp,
                on,
                also,
                from,
            } => {
                let r = robot_of(by).ok_or(QueryError::NotAnArm(by))?;
                let tip = self
                    .world
                    .tip(r, frames[r].as_ref())
                    .ok_or(QueryError::NotAnArm(by))?;
                let surface = self
                    .world_fixed
                    .get(on.index())
                    .copied()
                    .flatten()
                    .ok_or(QueryError::NotASurface(on))?;
                let mut state = ObjectState::held(r, &tip, &grasp)
                    .also_held_by(CollisionHolder::Fixed(surface));
                if let Some(lifted) = from {
                    let f = self
                        .world_fixed
                        .get(lifted.index())
                        .copied()
                        .flatten()
                        .ok_or(QueryError::NotASurface(lifted))?;
                    state = state.also_held_by(CollisionHolder::Fixed(f));
                }
                if let Some(other) = also {
                    let o = robot_of(other).ok_or(QueryError::NotAnArm(other))?;
                    state = state.also_held_by(CollisionHolder::Robot(o));
                }
                state
            }
            ObjectPlacement::Handoff { a, grasp_a, b } => {
                let ra = robot_of(a).ok_or(QueryError::NotAnArm(a))?;
                let rb = robot_of(b).ok_or(QueryError::NotAnArm(b))?;
                let tip = self
                    .world
                    .tip(ra, frames[ra].as_ref())
                    .ok_or(QueryError::NotAnArm(a))?;
                ObjectState::held(ra, &tip, &grasp_a).also_held_by(CollisionHolder::Robot(rb))
            }
            ObjectPlacement::Resting { on, pose, by } => {
                let surface = self
                    .world_fixed
                    .get(on.index())
                    .copied()
                    .flatten()
                    .ok_or(QueryError::NotASurface(on))?;
                let mut state = ObjectState::resting(pose, surface);
                if let Some(arm) = by {
                    let r = robot_of(arm).ok_or(QueryError::NotAnArm(arm))?;
                    state = state.also_held_by(CollisionHolder::Robot(r));
                }
                state
            }
            ObjectPlacement::Absent => ObjectState::absent(),
        };
        Ok(state)
    }
}
