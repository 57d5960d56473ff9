//! Queries that place only what is not standing: the cell at home ([`Home`], once per
//! scene), less the robots away from home, plus what stands still elsewhere during one
//! motion ([`Frozen`], once per motion).
//!
//! A motion moves one or two arms (and the object a moving hand holds); everything else
//! keeps its pose for the whole motion: the arms at home and the furniture (the
//! [`Home`]), and, away from home, an arm that stands by holding something, the world's
//! other objects, an object resting on a surface. A [`Frozen`] places those once and
//! keeps their boxes in an index of their own (`boxes.rs`). A query ([`Standing`] says what
//! stands) then places only the *live* bodies (the moving robots' and the objects not
//! standing), sweeps them against each other as the plain broad phase does, and asks
//! both indexes for the standing bodies near each of them: its cost follows the
//! moving bodies and what is near them, not the size of the cell. A plain question about
//! one state (`Scene::is_free`) is the same query with the arms it names live and no
//! [`Frozen`].
//!
//! The answers are the plain queries' answers: the same pairs pass the same filters
//! (grown AABBs compared on every axis, the allowed pairs, an object's holders, the
//! bounding spheres) before the same exact tests; pairs of two standing bodies, which a
//! swept query skips anyway (their distance does not change), are tested once, when the
//! home or the motion's standing set is built (`Home::hits`, [`Frozen::blocked`]).
//!
//! A scratch keeps the resting bodies in its buffers, tagged with the home they came
//! from; a query first puts back the entries the previous one overwrote (its live bodies,
//! and another motion's standing set), so switching between motions, or from motions to
//! plain questions, costs what changed.

use parry3d_f64::bounding_volume::Aabb;

use super::boxes::BoxIndex;
use super::broad_phase::{grow, PlacedBody};
use super::home::{next_tag, Home};
use super::swept::CONTACT;
use super::world::{CollisionScratch, CollisionWorld, Visit};
use super::{Collision, CollisionError, Configuration, SweepBounds};

/// What stands during a query: the home less the robots away from home, and a motion's
/// standing set.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Standing<'a> {
    /// The cell at home.
    pub(crate) home: &'a Home,
    /// Per robot: placed by the query (its frames are the query's).
    pub(crate) live: &'a [bool],
    /// The motion's bodies standing away from home, when the query is one of a motion's.
    pub(crate) frozen: Option<&'a Frozen>,
}

impl Standing<'_> {
    /// Per robot: whether its resting bodies are skipped (it is live, or stands away from
    /// home in the motion's set).
    pub(super) fn away(&self) -> &[bool] {
        self.frozen.map_or(self.live, |f| &f.away)
    }
}

/// The bodies that stand still during one motion away from home (see [the
/// module](self) documentation). Built by [`CollisionWorld::freeze`].
#[derive(Clone, Debug)]
pub(crate) struct Frozen {
    pub(super) tag: u64,
    /// The tag of the home it was built over.
    home: u64,
    /// Per robot: moving during the motion.
    moving: Vec<bool>,
    /// Per robot: moving, or standing away from home (its bodies are in `extra`).
    away: Vec<bool>,
    /// Per object: placed per query (it rides a moving hand); a present object that does
    /// not is in `extra`.
    pub(super) moving_object: Vec<bool>,
    /// The standing bodies away from home, in body order.
    pub(super) extra: Vec<(u32, PlacedBody)>,
    /// Their boxes, numbered as `extra`.
    pub(super) boxes: BoxIndex,
    /// Whether two standing bodies that may not touch intersect (every state collides).
    blocked: bool,
}

impl Frozen {
    /// Whether two standing bodies already intersect, so that no state of the motion is
    /// free.
    pub(crate) fn blocked(&self) -> bool {
        self.blocked
    }

    /// Per robot: the robots that move (the live ones of the motion's queries).
    pub(crate) fn moving(&self) -> &[bool] {
        &self.moving
    }
}

impl CollisionWorld {
    /// Freezes, over `home`, the bodies of `state` that stand away from home: those of
    /// the robots `away` marks and `moving_robot` does not, and of the present objects
    /// `moving_object` does not mark. The moving bodies' entries in `state` are ignored
    /// here and given per query. `known_free` says that a state of this motion was
    /// already found free, which proves that no two standing bodies intersect (they are
    /// the same in every state) and spares checking it.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn freeze(
        &self,
        home: &Home,
        state: &Configuration<'_>,
        moving_robot: &[bool],
        away: &[bool],
        moving_object: &[bool],
        known_free: bool,
        scratch: &mut CollisionScratch,
    ) -> Result<Frozen, CollisionError> {
        self.check_state(state)?;
        self.check_standing(home, moving_robot)?;
        self.check_standing(home, away)?;
        let moving_object: Vec<bool> = (0..self.objects.len())
            .map(|o| moving_object.get(o).copied().unwrap_or(false))
            .collect();
        let mut extra = Vec::new();
        self.place_owned(
            home,
            state,
            |r| away[r] && !moving_robot[r],
            |o| !moving_object[o],
            |_| 0.0,
            |i, p| extra.push((i as u32, *p)),
        )?;
        extra.sort_unstable_by_key(|&(i, _)| i);
        let boxes = BoxIndex::new(extra.iter().map(|(_, p)| p.aabb).collect());
        let mut frozen = Frozen {
            tag: next_tag(),
            home: home.tag,
            moving: moving_robot.to_vec(),
            away: away
                .iter()
                .zip(moving_robot)
                .map(|(&a, &m)| a || m)
                .collect(),
            moving_object,
            extra,
            boxes,
            blocked: false,
        };
        if !known_free {
            frozen.blocked = self.standing_collide(home, &frozen, state, scratch)?;
        }
        Ok(frozen)
    }

    /// Whether two standing bodies of a motion that may not touch intersect: a resting
    /// pair with neither robot away, or a standing body away from home against a resting
    /// one or another such body.
    fn standing_collide(
        &self,
        home: &Home,
        frozen: &Frozen,
        state: &Configuration<'_>,
        scratch: &mut CollisionScratch,
    ) -> Result<bool, CollisionError> {
        if home.touches(self, &frozen.away) {
            return Ok(true);
        }
        let standing = Standing {
            home,
            live: &frozen.moving,
            frozen: Some(frozen),
        };
        // The scratch holds the home and the standing set; the live bodies it places are
        // not looked at.
        self.place_live(&standing, state, scratch, |_| 0.0)?;
        let scratch = &*scratch;
        for (k, (i, pi)) in frozen.extra.iter().enumerate() {
            let i = *i as usize;
            let mut hit = false;
            self.near_standing(&standing, state, i, pi, 0.0, |j| {
                // Each pair of the standing set once, from its first member (the set is
                // in body order).
                if frozen.extra[..=k]
                    .binary_search_by_key(&(j as u32), |&(e, _)| e)
                    .is_ok()
                {
                    return Ok(Visit::Continue);
                }
                if self.intersect(i.min(j), i.max(j), scratch)? {
                    hit = true;
                    return Ok(Visit::Stop);
                }
                Ok(Visit::Continue)
            })?;
            if hit {
                return Ok(true);
            }
        }
        Ok(false)
    }

    /// Refuses a per-robot mask of the wrong length, or a home of another world.
    fn check_standing(&self, home: &Home, mask: &[bool]) -> Result<(), CollisionError> {
        if mask.len() != self.robots.len()
            || home.robot_bodies.len() != self.robots.len()
            || home.placed.len() != self.bodies.len()
        {
            return Err(CollisionError::RobotCount {
                expected: self.robots.len(),
                found: mask.len(),
            });
        }
        Ok(())
    }

    /// Whether `state` is free, what stands being `standing`'s (only the live bodies of
    /// `state` are read, and the holders of every object). Resting pairs that touch
    /// count only when neither robot is away; a motion's standing set counts when it is
    /// [blocked](Frozen::blocked).
    pub(crate) fn is_free_standing(
        &self,
        standing: &Standing<'_>,
        state: &Configuration<'_>,
        scratch: &mut CollisionScratch,
    ) -> Result<bool, CollisionError> {
        if standing.frozen.is_some_and(Frozen::blocked) {
            return Ok(false);
        }
        if standing.frozen.is_none() && standing.home.touches(self, standing.live) {
            return Ok(false);
        }
        self.place_live(standing, state, scratch, |_| 0.0)?;
        let mut free = true;
        self.visit_live(standing, state, scratch, 0.0, |i, j, scratch| {
            if self.intersect(i, j, scratch)? {
                free = false;
                return Ok(Visit::Stop);
            }
            Ok(Visit::Continue)
        })?;
        Ok(free)
    }

    /// Every intersecting pair of `state` that involves a live body, sorted and with an
    /// object's solids as one body, as [`all_collisions`](CollisionWorld::all_collisions)
    /// reports them: what names a colliding state without placing the cell's resting
    /// bodies (a 50-arm line's pruned handoffs spent a quarter of their verification
    /// placing every arm to name the pair).
    pub(crate) fn live_collisions(
        &self,
        standing: &Standing<'_>,
        state: &Configuration<'_>,
        scratch: &mut CollisionScratch,
        out: &mut Vec<Collision>,
    ) -> Result<(), CollisionError> {
        out.clear();
        self.place_live(standing, state, scratch, |_| 0.0)?;
        self.visit_live(standing, state, scratch, 0.0, |i, j, scratch| {
            if self.intersect(i, j, scratch)? {
                out.push(self.collision(i, j));
            }
            Ok(Visit::Continue)
        })?;
        out.sort_unstable();
        out.dedup();
        Ok(())
    }

    /// [`free_radius`](CollisionWorld::free_radius) with `standing` standing: `bounds`
    /// must leave every standing body static.
    pub(crate) fn free_radius_standing(
        &self,
        standing: &Standing<'_>,
        state: &Configuration<'_>,
        bounds: &SweepBounds,
        horizon: f64,
        scratch: &mut CollisionScratch,
    ) -> Result<f64, CollisionError> {
        self.place_live(standing, state, scratch, |i| {
            bounds.own(i) * horizon + CONTACT / 2.0
        })?;
        let mut candidates = std::mem::take(&mut scratch.candidates);
        candidates.clear();
        let found = self.visit_live(standing, state, scratch, CONTACT / 2.0, |i, j, scratch| {
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

    /// Brings the scratch to `standing`'s home and standing set (copying the home once
    /// per scratch, then putting back only what the previous query changed), and writes
    /// the live bodies of `state` (pose, AABB grown by `margin`, sphere centre), listed in
    /// its sweep order. Standing bodies are written grown by half of [`CONTACT`], as a
    /// swept query grows static bodies.
    fn place_live(
        &self,
        standing: &Standing<'_>,
        state: &Configuration<'_>,
        scratch: &mut CollisionScratch,
        margin: impl Fn(usize) -> f64,
    ) -> Result<(), CollisionError> {
        self.check_state(state)?;
        let home = standing.home;
        self.check_standing(home, standing.live)?;
        if standing
            .frozen
            .is_some_and(|f| f.home != home.tag || f.away.len() != self.robots.len())
        {
            return Err(CollisionError::RobotCount {
                expected: self.robots.len(),
                found: standing.live.len(),
            });
        }
        let n = self.bodies.len();
        if scratch.frozen != home.tag || scratch.poses.len() != n {
            scratch.poses.clear();
            scratch.aabbs.clear();
            scratch.centres.clear();
            scratch.margins.clear();
            scratch.poses.resize(n, crate::math::Iso::identity());
            scratch.aabbs.resize(n, Aabb::new_invalid());
            scratch.centres.resize(n, crate::math::Point::origin());
            scratch.margins.resize(n, 0.0);
            for i in 0..n {
                self.write_home(home, i, scratch);
            }
            scratch.frozen = home.tag;
            scratch.extra = 0;
            scratch.overlay.clear();
        } else {
            // Put back what the previous query's live bodies overwrote.
            for k in 0..scratch.order.len() {
                let i = scratch.order[k] as usize;
                self.write_home(home, i, scratch);
            }
        }
        scratch.order.clear();
        let extra = standing.frozen.map_or(0, |f| f.tag);
        if scratch.extra != extra {
            let mut overlay = std::mem::take(&mut scratch.overlay);
            for &i in &overlay {
                self.write_home(home, i as usize, scratch);
            }
            overlay.clear();
            if let Some(f) = standing.frozen {
                for (i, p) in &f.extra {
                    write_standing(scratch, *i as usize, p);
                    overlay.push(*i);
                }
            }
            scratch.overlay = overlay;
            scratch.extra = extra;
        }
        self.place_owned(
            home,
            state,
            |r| standing.live[r],
            |o| standing.frozen.is_none_or(|f| f.moving_object[o]),
            margin,
            |i, p| {
                write_placed(scratch, i, p);
                scratch.order.push(i as u32);
            },
        )
    }

    /// Places the bodies of the robots `robot` marks and of the present objects `object`
    /// marks (AABBs grown by `margin`), handing each to `placed`, robots first, in body
    /// order within each.
    fn place_owned(
        &self,
        home: &Home,
        state: &Configuration<'_>,
        robot: impl Fn(usize) -> bool,
        object: impl Fn(usize) -> bool,
        margin: impl Fn(usize) -> f64,
        mut placed: impl FnMut(usize, &PlacedBody),
    ) -> Result<(), CollisionError> {
        let robots = (home.robot_bodies.iter().enumerate()).filter(|&(r, _)| robot(r));
        let objects = (home.object_bodies.iter().enumerate())
            .filter(|&(o, _)| state.objects[o].pose.is_some() && object(o));
        for (_, bodies) in robots.chain(objects) {
            for &i in bodies {
                let i = i as usize;
                if let Some(p) = self.place_body(state, i, margin(i))? {
                    placed(i, &p);
                }
            }
        }
        Ok(())
    }

    /// Writes body `i`'s resting entry into the scratch (an absent body's for objects).
    fn write_home(&self, home: &Home, i: usize, scratch: &mut CollisionScratch) {
        match &home.placed[i] {
            Some(p) => write_standing(scratch, i, p),
            None => {
                scratch.poses[i] = self.bodies[i].local;
                scratch.aabbs[i] = Aabb::new_invalid();
                scratch.centres[i] = crate::math::Point::origin();
                scratch.margins[i] = 0.0;
            }
        }
    }

    /// Calls `visit` for every pair with a live body that the plain broad phase would
    /// hand the exact test: the live bodies among themselves by the plain sweep, then
    /// each against the standing bodies the indexes find near it, standing bodies
    /// grown by `standing_margin` (what the plain placement would have grown them by).
    fn visit_live(
        &self,
        standing: &Standing<'_>,
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
            let live = PlacedBody {
                pose: scratch.poses[i],
                aabb: scratch.aabbs[i],
                centre: scratch.centres[i],
                margin: scratch.margins[i],
            };
            self.near_standing(standing, state, i, &live, standing_margin, |j| {
                if let Visit::Stop = visit(i.min(j), i.max(j), scratch)? {
                    stopped = true;
                    return Ok(Visit::Stop);
                }
                Ok(Visit::Continue)
            })?;
            if stopped {
                return Ok(());
            }
        }
        Ok(())
    }

    /// Calls `visit` with every standing body `j` (resting, its robot not away, or in the
    /// motion's standing set) that passes the plain sweep's filters against body `i`
    /// placed as `pi` (its box already grown by its own margin): boxes overlapping on
    /// every axis with `j`'s grown by `standing_margin`, not an allowed pair nor an object
    /// and its holder, bounding spheres within reach. Stops when `visit` says so.
    #[allow(clippy::too_many_arguments)]
    fn near_standing(
        &self,
        standing: &Standing<'_>,
        state: &Configuration<'_>,
        i: usize,
        pi: &PlacedBody,
        standing_margin: f64,
        mut visit: impl FnMut(usize) -> Result<Visit, CollisionError>,
    ) -> Result<(), CollisionError> {
        // A hair wider than the exact filter below, so that rounding in the index's
        // own boxes never drops a pair the filter would keep.
        let query = grow(&pi.aabb, standing_margin + 1e-9);
        let away = standing.away();
        let home = standing.home;
        let near_home = home.boxes.overlapping(&query, |leaf| {
            let Some(&j) = home.leaves.get(leaf as usize) else {
                return Ok(Visit::Continue);
            };
            let j = j as usize;
            if j == i || self.on_away_robot(j, away) {
                return Ok(Visit::Continue);
            }
            let Some(sj) = &home.placed[j] else {
                return Ok(Visit::Continue);
            };
            if self.standing_pair(state, i, pi, j, sj, standing_margin) {
                return visit(j);
            }
            Ok(Visit::Continue)
        })?;
        if let (Visit::Continue, Some(f)) = (near_home, standing.frozen) {
            f.boxes.overlapping(&query, |leaf| {
                let Some((j, sj)) = f.extra.get(leaf as usize) else {
                    return Ok(Visit::Continue);
                };
                let j = *j as usize;
                if j != i && self.standing_pair(state, i, pi, j, sj, standing_margin) {
                    return visit(j);
                }
                Ok(Visit::Continue)
            })?;
        }
        Ok(())
    }

    /// The plain sweep's filters for body `i` placed as `pi` and standing body `j`
    /// placed as `sj`, grown by `margin` (with no margin, those of any two placed bodies:
    /// the batched screen's live pairs use them too).
    #[inline]
    pub(super) fn standing_pair(
        &self,
        state: &Configuration<'_>,
        i: usize,
        pi: &PlacedBody,
        j: usize,
        sj: &PlacedBody,
        margin: f64,
    ) -> bool {
        let ai = &pi.aabb;
        let aj = grow(&sj.aabb, margin);
        if (0..3).any(|k| aj.mins[k] > ai.maxs[k] || ai.mins[k] > aj.maxs[k]) {
            return false;
        }
        if self.allowed.get(i, j) || self.held_pair(state, i, j) {
            return false;
        }
        let reach =
            self.bodies[i].sphere_radius + self.bodies[j].sphere_radius + pi.margin + margin;
        (pi.centre - sj.centre).norm_squared() <= reach * reach
    }
}

/// Writes a standing body's entry, grown by half of [`CONTACT`] as a swept query grows
/// static bodies.
fn write_standing(scratch: &mut CollisionScratch, i: usize, p: &PlacedBody) {
    scratch.poses[i] = p.pose;
    scratch.aabbs[i] = grow(&p.aabb, CONTACT / 2.0);
    scratch.centres[i] = p.centre;
    scratch.margins[i] = CONTACT / 2.0;
}

/// Writes a live body's entry as placed.
fn write_placed(scratch: &mut CollisionScratch, i: usize, p: &PlacedBody) {
    scratch.poses[i] = p.pose;
    scratch.aabbs[i] = p.aabb;
    scratch.centres[i] = p.centre;
    scratch.margins[i] = p.margin;
}
