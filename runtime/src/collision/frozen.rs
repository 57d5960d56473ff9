//! The bodies that stand still during one motion, placed once.
//!
//! A motion moves one or two arms (and the object a moving hand holds); everything else
//! (the idle arms, the furniture, the world's other objects, an object resting on a
//! surface) keeps its pose for the whole motion. The plain queries place every body and
//! sort them all on every call, so each check of a motion paid for every body of the
//! cell, and a line of 50 arms checked 50 arms to move one. A [`Frozen`] places the
//! standing bodies once, keeps their AABBs in a bounding-volume hierarchy (parry's
//! [`Bvh`]), and learns once whether two of them already intersect (then every state of
//! the motion collides). A query then places only the moving bodies, sweeps them against
//! each other as the plain broad phase does, and asks the hierarchy for the standing
//! bodies near each of them: its cost follows the moving bodies and what is near them,
//! not the size of the cell.
//!
//! The answers are the plain queries' answers: the same pairs pass the same filters
//! (grown AABBs compared on every axis, the allowed pairs, an object's holders, the
//! bounding spheres) before the same exact tests, and pairs of two standing bodies are
//! the ones a swept query skips anyway (their distance does not change).

use std::sync::atomic::{AtomicU64, Ordering};

use parry3d_f64::bounding_volume::Aabb;
use parry3d_f64::partitioning::{Bvh, BvhBuildStrategy};

use super::broad_phase::{grow, PlacedBody};
use super::build::Mount;
use super::swept::CONTACT;
use super::world::{CollisionScratch, CollisionWorld, Visit};
use super::{CollisionError, Configuration, SweepBounds};

/// Tags a [`Frozen`] so a scratch knows whether it already holds its standing bodies.
static NEXT_TAG: AtomicU64 = AtomicU64::new(1);

/// The standing part of a motion's states (see [the module](self) documentation).
/// Built by [`CollisionWorld::freeze`] for one world; queries with another world's
/// states are refused by the state check.
#[derive(Clone, Debug)]
pub(crate) struct Frozen {
    tag: u64,
    /// Per body: whether it moves during the motion.
    moving: Vec<bool>,
    /// Per body: where a standing body is (`None` for moving and absent bodies).
    standing: Vec<Option<PlacedBody>>,
    /// The standing bodies' AABBs; leaf data is the index into `leaves`.
    bvh: Bvh,
    /// Body index of each leaf. Leaves are numbered densely from 0 rather than by body
    /// index: parry's builder assumes leaf 0 (and 1) exist when a tree has one or two.
    leaves: Vec<u32>,
    /// Whether two standing bodies that may not touch intersect (every state collides).
    blocked: bool,
}

impl Frozen {
    /// Whether two standing bodies already intersect, so that no state of the motion is
    /// free.
    pub(crate) fn blocked(&self) -> bool {
        self.blocked
    }
}

impl CollisionWorld {
    /// Freezes the bodies of `state` that do not ride on a robot `moving_robot` marks
    /// nor on an object `moving_object` marks (indices as in the state). The moving
    /// bodies' entries in `state` are ignored here and given per query. `known_free`
    /// says that a state of this motion was already found free, which proves that no
    /// two standing bodies intersect (they are the same in every state) and spares
    /// checking it.
    pub(crate) fn freeze(
        &self,
        state: &Configuration<'_>,
        moving_robot: &[bool],
        moving_object: &[bool],
        known_free: bool,
        scratch: &mut CollisionScratch,
    ) -> Result<Frozen, CollisionError> {
        self.check_state(state)?;
        let n = self.bodies.len();
        let moving: Vec<bool> = self
            .bodies
            .iter()
            .map(|b| match b.mount {
                Mount::Frame { robot, .. } => moving_robot.get(robot).copied().unwrap_or(false),
                Mount::Object { object } => moving_object.get(object).copied().unwrap_or(false),
                Mount::Fixed => false,
            })
            .collect();
        let mut standing = vec![None; n];
        for i in 0..n {
            if !moving[i] {
                standing[i] = self.place_body(state, i, 0.0)?;
            }
        }
        let leaves: Vec<u32> = (0..n as u32)
            .filter(|&i| standing[i as usize].is_some())
            .collect();
        let bvh = Bvh::from_iter(
            BvhBuildStrategy::Binned,
            leaves
                .iter()
                .enumerate()
                .filter_map(|(leaf, &i)| standing[i as usize].map(|p| (leaf, p.aabb))),
        );
        // Two standing bodies that intersect do so in every state of the motion: found
        // once with the plain broad phase, restricted to those pairs.
        let mut blocked = false;
        if !known_free {
            self.place(state, scratch, |_| 0.0)?;
            self.sweep(state, scratch, |i, j, scratch| {
                if !moving[i] && !moving[j] && self.intersect(i, j, scratch)? {
                    blocked = true;
                    return Ok(Visit::Stop);
                }
                Ok(Visit::Continue)
            })?;
        }
        Ok(Frozen {
            tag: NEXT_TAG.fetch_add(1, Ordering::Relaxed),
            moving,
            standing,
            bvh,
            leaves,
            blocked,
        })
    }

    /// Whether `state` is free, its standing bodies being `frozen`'s (only the moving
    /// bodies of `state` are read, and the holders of every object).
    pub(crate) fn is_free_frozen(
        &self,
        frozen: &Frozen,
        state: &Configuration<'_>,
        scratch: &mut CollisionScratch,
    ) -> Result<bool, CollisionError> {
        if frozen.blocked {
            return Ok(false);
        }
        self.place_moving(frozen, state, scratch, |_| 0.0)?;
        let mut free = true;
        self.visit_frozen(frozen, state, scratch, 0.0, |i, j, scratch| {
            if self.intersect(i, j, scratch)? {
                free = false;
                return Ok(Visit::Stop);
            }
            Ok(Visit::Continue)
        })?;
        Ok(free)
    }

    /// [`free_radius`](CollisionWorld::free_radius) with the standing bodies frozen:
    /// `bounds` must leave every standing body static.
    pub(crate) fn free_radius_frozen(
        &self,
        frozen: &Frozen,
        state: &Configuration<'_>,
        bounds: &SweepBounds,
        horizon: f64,
        scratch: &mut CollisionScratch,
    ) -> Result<f64, CollisionError> {
        self.place_moving(frozen, state, scratch, |i| {
            bounds.own(i) * horizon + CONTACT / 2.0
        })?;
        let mut candidates = std::mem::take(&mut scratch.candidates);
        candidates.clear();
        let found = self.visit_frozen(frozen, state, scratch, CONTACT / 2.0, |i, j, scratch| {
            let p = bounds.pair(i, j);
            if p > 0.0 {
                let gap = super::swept::lower_bound(self, scratch, i, j);
                candidates.push(((gap - CONTACT) / p, i as u32, j as u32));
            }
            Ok(Visit::Continue)
        });
        let result =
            found.and_then(|()| self.nearest_radius(scratch, bounds, &mut candidates, horizon));
        scratch.candidates = candidates;
        result
    }

    /// Writes the moving bodies of `state` into the scratch (pose, AABB grown by
    /// `margin`, sphere centre) and lists the present ones in its sweep order; copies
    /// the standing bodies in too, grown as a swept query grows static bodies, when the
    /// scratch last served another frozen set or a plain query.
    fn place_moving(
        &self,
        frozen: &Frozen,
        state: &Configuration<'_>,
        scratch: &mut CollisionScratch,
        margin: impl Fn(usize) -> f64,
    ) -> Result<(), CollisionError> {
        self.check_state(state)?;
        let n = self.bodies.len();
        if frozen.moving.len() != n {
            return Err(CollisionError::RobotCount {
                expected: self.robots.len(),
                found: state.robots.len(),
            });
        }
        if scratch.frozen != frozen.tag || scratch.poses.len() != n {
            scratch.poses.clear();
            scratch.aabbs.clear();
            scratch.centres.clear();
            scratch.margins.clear();
            for (i, s) in frozen.standing.iter().enumerate() {
                match s {
                    Some(p) => {
                        let grown = grow(&p.aabb, CONTACT / 2.0);
                        scratch.poses.push(p.pose);
                        scratch.aabbs.push(grown);
                        scratch.centres.push(p.centre);
                        scratch.margins.push(CONTACT / 2.0);
                    }
                    None => {
                        scratch.poses.push(self.bodies[i].local);
                        scratch.aabbs.push(Aabb::new_invalid());
                        scratch.centres.push(crate::math::Point::origin());
                        scratch.margins.push(0.0);
                    }
                }
            }
            scratch.frozen = frozen.tag;
        }
        scratch.order.clear();
        for i in 0..n {
            if !frozen.moving[i] {
                continue;
            }
            if let Some(p) = self.place_body(state, i, margin(i))? {
                scratch.poses[i] = p.pose;
                scratch.aabbs[i] = p.aabb;
                scratch.centres[i] = p.centre;
                scratch.margins[i] = p.margin;
                scratch.order.push(i as u32);
            }
        }
        Ok(())
    }

    /// Calls `visit` for every pair with a moving body that the plain broad phase would
    /// hand the exact test: the moving bodies among themselves by the plain sweep, then
    /// each against the standing bodies the hierarchy finds near it, standing bodies
    /// grown by `standing_margin` (what the plain placement would have grown them by).
    fn visit_frozen(
        &self,
        frozen: &Frozen,
        state: &Configuration<'_>,
        scratch: &mut CollisionScratch,
        standing_margin: f64,
        mut visit: impl FnMut(usize, usize, &CollisionScratch) -> Result<Visit, CollisionError>,
    ) -> Result<(), CollisionError> {
        let mut stopped = false;
        self.sweep(state, scratch, |i, j, scratch| {
            let v = visit(i, j, scratch)?;
            stopped = matches!(v, Visit::Stop);
            Ok(v)
        })?;
        if stopped {
            return Ok(());
        }
        let scratch = &*scratch;
        for &i in &scratch.order {
            let i = i as usize;
            let ai = &scratch.aabbs[i];
            // A hair wider than the exact filter below, so that rounding in the
            // hierarchy's own boxes never drops a pair the filter would keep.
            let query = grow(ai, standing_margin + 1e-9);
            for leaf in frozen.bvh.intersect_aabb(&query) {
                let Some(&j) = frozen.leaves.get(leaf as usize) else {
                    continue;
                };
                let j = j as usize;
                let Some(sj) = &frozen.standing[j] else {
                    continue;
                };
                let aj = grow(&sj.aabb, standing_margin);
                if (0..3).any(|k| aj.mins[k] > ai.maxs[k] || ai.mins[k] > aj.maxs[k]) {
                    continue;
                }
                if self.allowed.get(i, j) || self.held_pair(state, i, j) {
                    continue;
                }
                let reach = self.bodies[i].sphere_radius
                    + self.bodies[j].sphere_radius
                    + scratch.margins[i]
                    + standing_margin;
                if (scratch.centres[i] - sj.centre).norm_squared() > reach * reach {
                    continue;
                }
                if let Visit::Stop = visit(i.min(j), i.max(j), scratch)? {
                    return Ok(());
                }
            }
        }
        Ok(())
    }
}
