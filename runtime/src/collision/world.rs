//! The queries of a built collision world: names, counts, the first collision, all
//! collisions, and the clearance of a state.

use std::sync::atomic::{AtomicU64, Ordering};

use parry3d_f64::bounding_volume::Aabb;
use parry3d_f64::query;
use parry3d_f64::shape::SupportMap;

use super::build::{BitMatrix, Body, RobotInfo};
use super::capsule::capsule_bound;
use super::{BodyId, Collision, CollisionError, Configuration, Proximity};
use crate::math::{Iso, Point};

/// Buffers of one query, reused between calls (one per thread).
#[derive(Clone, Debug, Default)]
pub struct CollisionScratch {
    pub(super) poses: Vec<Iso>,
    pub(super) aabbs: Vec<Aabb>,
    /// World centres of the bodies' bounding spheres.
    pub(super) centres: Vec<Point>,
    pub(super) order: Vec<u32>,
    /// How much each body's AABB and sphere were grown (half a clearance cutoff, or how
    /// far the body may travel in a swept query), by body index.
    pub(super) margins: Vec<f64>,
    /// Pairs a swept query has yet to measure, with the radius a cheap bound proves.
    pub(super) candidates: Vec<(f64, u32, u32)>,
    /// The tag of the [`Home`](super::Home) whose resting bodies the buffers hold (0:
    /// none; a plain query overwrites them).
    pub(super) frozen: u64,
    /// The tag of the motion's standing set ([`Frozen`](super::Frozen)) written over the
    /// home (0: none), and the bodies it wrote.
    pub(super) extra: u64,
    pub(super) overlay: Vec<u32>,
    /// Exact queries (GJK or parry) run through these buffers, for tests and profiles of
    /// the cheap rejections.
    pub(super) exact_queries: QueryCount,
    /// The batched screen's buffers (`batch.rs`).
    pub(crate) batch: super::BatchScratch,
}

impl CollisionScratch {
    /// How many exact queries (intersection tests and distances of pairs the cheap
    /// bounds did not settle) the queries through this scratch have run.
    pub fn exact_queries(&self) -> u64 {
        self.exact_queries.0.load(Ordering::Relaxed)
    }

    pub(super) fn count_exact(&self) {
        // A load and a store, not an atomic add: one thread uses a scratch at a time (the
        // sweep hands its visitors the scratch shared, hence the atomic), and a plain
        // store costs nothing next to the query it counts.
        let n = self.exact_queries.0.load(Ordering::Relaxed);
        self.exact_queries.0.store(n + 1, Ordering::Relaxed);
    }
}

/// A count that a shared scratch can advance and that keeps the scratch `Sync`.
#[derive(Debug, Default)]
pub(super) struct QueryCount(AtomicU64);

impl Clone for QueryCount {
    fn clone(&self) -> Self {
        QueryCount(AtomicU64::new(self.0.load(Ordering::Relaxed)))
    }
}

/// The collision world of a cell. Immutable after [`CollisionWorldBuilder::build`](super::CollisionWorldBuilder::build);
/// `Send + Sync`, so one world serves every thread.
#[derive(Clone, Debug)]
pub struct CollisionWorld {
    /// Robots' links and hands (robot by robot), then fixed bodies, then objects.
    pub(super) bodies: Vec<Body>,
    pub(super) robots: Vec<RobotInfo>,
    /// Body index of each fixed body.
    pub(super) fixed: Vec<usize>,
    /// Body index of each object's first solid (`None`: no solids).
    pub(super) objects: Vec<Option<usize>>,
    pub(super) object_names: Vec<String>,
    pub(super) allowed: BitMatrix,
}

/// What the sweep does with a candidate pair.
pub(super) enum Visit {
    Continue,
    Stop,
}

impl CollisionWorld {
    /// The report name of a body (`left/lwr_link_4`, `left/softhand`, `table`).
    pub fn name(&self, id: BodyId) -> &str {
        if let BodyId::Object(i) = id {
            return self.object_names.get(i).map_or("?", String::as_str);
        }
        self.index(id)
            .map(|i| self.bodies[i].name.as_str())
            .unwrap_or("?")
    }

    /// Both names of a collision, `a` first.
    pub fn names(&self, c: &Collision) -> (&str, &str) {
        (self.name(c.a), self.name(c.b))
    }

    /// "`a` and `b`", for messages.
    pub fn describe(&self, c: &Collision) -> String {
        let (a, b) = self.names(c);
        format!("`{a}` and `{b}`")
    }

    /// Every solid with its body id and name (an object of several solids appears once
    /// per solid).
    pub fn bodies(&self) -> impl Iterator<Item = (BodyId, &str)> + '_ {
        self.bodies.iter().map(|b| (b.id, b.name.as_str()))
    }

    /// Number of robots (the length a [`Configuration`]'s `robots` must have).
    pub fn robot_count(&self) -> usize {
        self.robots.len()
    }

    /// Number of frames of robot `robot` (the length of its frame list in a
    /// [`Configuration`]).
    pub fn frame_count(&self, robot: usize) -> Option<usize> {
        self.robots.get(robot).map(|r| r.frames)
    }

    /// The world pose of robot `robot`'s tip (its hand frame) for its frame poses
    /// `frames`: where a held object's grasp is applied ([`ObjectState::held`](super::ObjectState::held)).
    pub fn tip(&self, robot: usize, frames: &[Iso]) -> Option<Iso> {
        let info = self.robots.get(robot)?;
        (frames.len() == info.frames).then(|| frames[info.frames - 1] * info.tip_offset)
    }

    /// Number of objects (the length a [`Configuration`]'s `objects` must have).
    pub fn object_count(&self) -> usize {
        self.objects.len()
    }

    /// Whether `a` and `b` are never tested (the static rules and the cell's allowed
    /// pairs; the per-state holder rule is not included).
    pub fn is_allowed(&self, a: BodyId, b: BodyId) -> bool {
        match (self.index(a), self.index(b)) {
            (Some(i), Some(j)) => i == j || self.allowed.get(i, j),
            _ => false,
        }
    }

    fn index(&self, id: BodyId) -> Option<usize> {
        match id {
            BodyId::Fixed(i) => self.fixed.get(i).copied(),
            BodyId::Object(i) => self.objects.get(i).copied().flatten(),
            // Robot bodies are few; a scan keeps the world free of per-robot offsets
            // that would have to be kept in step with the body list.
            _ => self.bodies.iter().position(|b| b.id == id),
        }
    }

    /// The first intersecting pair found in `state`, or `None` when it is collision-free.
    /// Which pair is found first depends on the sweep order; use
    /// [`all_collisions`](Self::all_collisions) for a complete, ordered report.
    pub fn first_collision(
        &self,
        state: &Configuration<'_>,
        scratch: &mut CollisionScratch,
    ) -> Result<Option<Collision>, CollisionError> {
        self.place(state, scratch, |_| 0.0)?;
        let mut found = None;
        self.sweep(state, scratch, |i, j, scratch| {
            if self.intersect(i, j, scratch)? {
                found = Some(self.collision(i, j));
                return Ok(Visit::Stop);
            }
            Ok(Visit::Continue)
        })?;
        Ok(found)
    }

    /// Whether `state` is collision-free.
    pub fn is_free(
        &self,
        state: &Configuration<'_>,
        scratch: &mut CollisionScratch,
    ) -> Result<bool, CollisionError> {
        Ok(self.first_collision(state, scratch)?.is_none())
    }

    /// Every intersecting pair in `state`, written to `out` (cleared first) sorted, so
    /// reports are deterministic.
    pub fn all_collisions(
        &self,
        state: &Configuration<'_>,
        scratch: &mut CollisionScratch,
        out: &mut Vec<Collision>,
    ) -> Result<(), CollisionError> {
        out.clear();
        self.place(state, scratch, |_| 0.0)?;
        self.sweep(state, scratch, |i, j, scratch| {
            if self.intersect(i, j, scratch)? {
                out.push(self.collision(i, j));
            }
            Ok(Visit::Continue)
        })?;
        out.sort_unstable();
        // An object of several solids is one body to reports.
        out.dedup();
        Ok(())
    }

    /// The closest pair that is not allowed to touch, if any is closer than `cutoff`
    /// metres (pairs farther apart are skipped by the broad phase, so a small cutoff keeps
    /// this nearly as cheap as [`first_collision`](Self::first_collision)). An
    /// intersecting pair has distance 0. Ties go to the smaller pair (`a`, `b`), so the answer does
    /// not depend on the sweep order.
    pub fn clearance(
        &self,
        state: &Configuration<'_>,
        scratch: &mut CollisionScratch,
        cutoff: f64,
    ) -> Result<Option<Proximity>, CollisionError> {
        let cutoff = if cutoff.is_finite() {
            cutoff.max(0.0)
        } else {
            0.0
        };
        self.place(state, scratch, |_| cutoff / 2.0)?;
        let mut best: Option<(f64, Collision)> = None;
        self.sweep(state, scratch, |i, j, scratch| {
            if self
                .capsule_gap(scratch, i, j)
                .is_some_and(|gap| gap > cutoff)
            {
                return Ok(Visit::Continue);
            }
            scratch.count_exact();
            let (bi, bj) = (&self.bodies[i], &self.bodies[j]);
            let d = query::distance(
                &scratch.poses[i],
                bi.shape.as_ref(),
                &scratch.poses[j],
                bj.shape.as_ref(),
            )
            .map_err(|_| self.unsupported(i, j))?;
            let pair = self.collision(i, j);
            if d <= cutoff && best.is_none_or(|(bd, bp)| d < bd || (d == bd && pair < bp)) {
                best = Some((d, pair));
            }
            Ok(Visit::Continue)
        })?;
        Ok(best.map(|(distance, pair)| Proximity {
            a: pair.a,
            b: pair.b,
            distance,
        }))
    }

    pub(super) fn collision(&self, i: usize, j: usize) -> Collision {
        let (a, b) = (self.bodies[i].id, self.bodies[j].id);
        Collision {
            a: a.min(b),
            b: a.max(b),
        }
    }

    pub(super) fn unsupported(&self, i: usize, j: usize) -> CollisionError {
        CollisionError::Unsupported {
            a: self.bodies[i].name.clone(),
            b: self.bodies[j].name.clone(),
        }
    }

    pub(super) fn intersect(
        &self,
        i: usize,
        j: usize,
        scratch: &CollisionScratch,
    ) -> Result<bool, CollisionError> {
        self.intersect_at(i, &scratch.poses[i], j, &scratch.poses[j], || {
            scratch.count_exact()
        })
    }

    /// Whether bodies `i` at `pi` and `j` at `pj` intersect: apart when their capsules
    /// are, else the exact test (`exact` is called before it runs, to count it).
    pub(super) fn intersect_at(
        &self,
        i: usize,
        pi: &Iso,
        j: usize,
        pj: &Iso,
        exact: impl FnOnce(),
    ) -> Result<bool, CollisionError> {
        let (bi, bj) = (&self.bodies[i], &self.bodies[j]);
        // Capsules apart: the bodies inside them are too.
        if let (Some(ci), Some(cj)) = (&bi.capsule, &bj.capsule) {
            let gap = capsule_bound(
                (ci, pi, bi.half_extents.as_ref()),
                (cj, pj, bj.half_extents.as_ref()),
            );
            if gap > 0.0 {
                return Ok(false);
            }
        }
        exact();
        if bi.hull.is_some() || bj.hull.is_some() {
            if let (Some(gi), Some(gj)) = (self.support_map(i), self.support_map(j)) {
                return Ok(query::details::intersection_test_support_map_support_map(
                    &pi.inv_mul(pj),
                    gi,
                    gj,
                ));
            }
        }
        query::intersection_test(pi, bi.shape.as_ref(), pj, bj.shape.as_ref())
            .map_err(|_| self.unsupported(i, j))
    }

    /// A lower bound on the distance between placed bodies `i` and `j` from their
    /// capsules (`capsule.rs`), `None` when one has no capsule.
    #[inline]
    pub(super) fn capsule_gap(
        &self,
        scratch: &CollisionScratch,
        i: usize,
        j: usize,
    ) -> Option<f64> {
        let (bi, bj) = (&self.bodies[i], &self.bodies[j]);
        let (ci, cj) = (bi.capsule.as_ref()?, bj.capsule.as_ref()?);
        Some(capsule_bound(
            (ci, &scratch.poses[i], bi.half_extents.as_ref()),
            (cj, &scratch.poses[j], bj.half_extents.as_ref()),
        ))
    }

    /// Body `i`'s shape as GJK sees it: a hull's vertex graph when it has one (support
    /// points by hill climbing, `hull.rs`), else parry's own support map, if any.
    pub(super) fn support_map(&self, i: usize) -> Option<&dyn SupportMap> {
        let b = &self.bodies[i];
        match &b.hull {
            Some(h) => Some(h.as_ref()),
            None => b.shape.as_support_map(),
        }
    }
}
