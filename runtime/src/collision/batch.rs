//! Several states of one motion judged at once: the states placed first (forward
//! kinematics done by the caller, then each live body's capsule in the world), the
//! standing bodies near each live body looked up once for all of them, and the pairs
//! tested state by state, cheapest first, so that the exact test runs only for the pairs
//! the capsules cannot settle.
//!
//! The sampled screen of a shortcut (`motion/segment.rs`) and the lazy trees' node and
//! midpoint (`motion/tree.rs`) ask about a few to forty configurations at a time. One by
//! one, each paid for the whole query of `frozen.rs`: putting back the previous state's
//! live entries, placing every live body with its AABB and sphere, the sort and sweep, a
//! box-index scan and the pair filters per live body, although the capsule bound then
//! settled nearly every pair. Here the index is asked once per live body with the union
//! of its capsule's boxes over the batch, the allowed pairs and an object's holders are
//! filtered out of its candidates once, and per state each candidate costs six
//! comparisons over arrays (one per axis, no branch between them) unless its box meets
//! the capsule's; then the capsule bound (`capsule.rs`), then the exact test,
//! as `CollisionWorld::intersect` runs them. The live bodies' own pairs (an arm against
//! itself, against the object it carries) are listed once per motion and tested the same
//! way. A state is free when every pair is apart; it collides when a pair intersects
//! that the full check would also visit (its box and sphere filters passed); the states
//! after the first colliding one are not judged (the caller stops there).
//!
//! The verdicts are the full check's: a capsule contains its body and a standing body's
//! box contains it, so a pair settled by them cannot intersect; a pair they do not settle
//! gets the full check's own exact test on the same poses, computed by the same
//! operations, so the same answer. Anything the screen cannot measure (a body with no
//! capsule, a non-finite pose, an exact test that fails, a motion whose standing bodies
//! already intersect) leaves the state unjudged, for the full check.
//! `collision/batch/tests.rs` holds the verdicts to brute force (and shows that capsules
//! taken too small are caught); `tests/batched_screen.rs` holds the sampled check to the
//! one-by-one check on the shipped cells.

use parry3d_f64::bounding_volume::Aabb;

use super::broad_phase::PlacedBody;
use super::build::Mount;
#[cfg(test)]
use super::capsule::capsule_bound;
use super::frozen::{Frozen, Standing};
use super::world::{CollisionWorld, Visit};
use super::Configuration;
use crate::math::{Iso, Point};

/// Buffers of the batched screen, reused between calls (one per thread, inside the
/// [`CollisionScratch`](super::CollisionScratch)).
#[derive(Clone, Debug, Default)]
pub(crate) struct BatchScratch {
    /// The tag of the motion's standing set the live lists below were made for (0:
    /// none).
    tag: u64,
    /// The live bodies, robots' then objects', in body order within each.
    live: Vec<u32>,
    /// Whether `live`, `pairs` and `objects` are those of the standing set `tag`.
    listed: bool,
    /// Whether every live body has a capsule (otherwise nothing is cleared).
    usable: bool,
    /// The pairs of live bodies that may not touch (positions in `live`).
    pairs: Vec<(u32, u32)>,
    /// The objects' states of the first state placed (their holders, for the pair
    /// rules, which do not change during a motion).
    objects: Vec<super::ObjectState>,
    /// States placed since [`CollisionWorld::batch_begin`].
    states: usize,
    /// Per state, per live body (`state * live + body`): its pose and the box around its
    /// capsule in the world.
    poses: Vec<Iso>,
    lo: Vec<[f64; 3]>,
    hi: Vec<[f64; 3]>,
    /// Per live body, the range of its standing candidates in the arrays below.
    starts: Vec<u32>,
    /// Standing candidates: body, box corners one array per axis (the loop over them
    /// compares six arrays, no branch between the comparisons), where they stand.
    near: Vec<u32>,
    near_lo: [Vec<f64>; 3],
    near_hi: [Vec<f64>; 3],
    near_placed: Vec<PlacedBody>,
    /// Test-only: every live capsule's radius is taken this much smaller, to show that
    /// the tests catch an unsound screen.
    #[cfg(test)]
    pub(super) shrink: f64,
}

impl CollisionWorld {
    /// Starts a batch for the motion `standing` stands for (which must have a standing
    /// set): the live bodies and their pairs are listed once per standing set, the states
    /// placed are forgotten.
    pub(crate) fn batch_begin(&self, standing: &Standing<'_>, batch: &mut BatchScratch) {
        batch.states = 0;
        batch.poses.clear();
        batch.lo.clear();
        batch.hi.clear();
        let Some(frozen) = standing.frozen else {
            batch.tag = 0;
            batch.usable = false;
            return;
        };
        if batch.tag != frozen.tag {
            batch.tag = frozen.tag;
            batch.listed = false;
        }
    }

    /// Adds one state of the motion (only its live bodies are read) to the batch.
    pub(crate) fn batch_place(
        &self,
        standing: &Standing<'_>,
        state: &Configuration<'_>,
        batch: &mut BatchScratch,
    ) {
        let Some(frozen) = standing.frozen else {
            return;
        };
        if !batch.listed {
            self.list_live(standing.home, frozen, state, batch);
            batch.listed = true;
        }
        batch.states += 1;
        #[cfg(test)]
        let shrink = batch.shrink;
        #[cfg(not(test))]
        let shrink = 0.0;
        for &i in &batch.live {
            let b = &self.bodies[i as usize];
            let frame = match b.mount {
                Mount::Frame { robot, frame } => state.robots.get(robot).and_then(|f| f.get(frame)),
                Mount::Object { object } => state.objects.get(object).and_then(|o| o.pose.as_ref()),
                Mount::Fixed => None,
            };
            let (Some(frame), Some(c)) = (frame, &b.capsule) else {
                // Nothing to measure (a live body not in this state, or without a
                // capsule): the batch judges nothing.
                batch.usable = false;
                return;
            };
            let pose = frame * b.local;
            let (a, e) = c.placed(&pose);
            let r = c.radius - shrink;
            batch.poses.push(pose);
            batch.lo.push(std::array::from_fn(|k| a[k].min(e[k]) - r));
            batch.hi.push(std::array::from_fn(|k| a[k].max(e[k]) + r));
        }
    }

    /// Lists the live bodies of `frozen`'s motion and the pairs among them that may not
    /// touch, with the holders of `state`'s objects.
    fn list_live(
        &self,
        home: &super::Home,
        frozen: &Frozen,
        state: &Configuration<'_>,
        batch: &mut BatchScratch,
    ) {
        batch.objects.clear();
        batch.objects.extend_from_slice(state.objects);
        batch.live.clear();
        let robots = home.robot_bodies.iter().enumerate();
        let robots = robots.filter(|&(r, _)| frozen.moving().get(r).copied().unwrap_or(false));
        let objects = home.object_bodies.iter().enumerate().filter(|&(o, _)| {
            frozen.moving_object.get(o).copied().unwrap_or(false)
                && state.objects.get(o).is_some_and(|s| s.pose.is_some())
        });
        for (_, bodies) in robots.chain(objects) {
            batch.live.extend_from_slice(bodies);
        }
        batch.usable = batch
            .live
            .iter()
            .all(|&i| self.bodies[i as usize].capsule.is_some());
        batch.pairs.clear();
        for (x, &i) in batch.live.iter().enumerate() {
            for (y, &j) in batch.live.iter().enumerate().skip(x + 1) {
                let (i, j) = (i as usize, j as usize);
                if !self.allowed.get(i, j) && !self.held_pair(state, i, j) {
                    batch.pairs.push((x as u32, y as u32));
                }
            }
        }
    }

    /// Writes into `out` (one verdict per state placed, in order) what the screen
    /// proves of each state: `Some(true)` free, `Some(false)` colliding (a pair that
    /// the full check would visit, its filters passed, intersects by the full check's
    /// own exact test), `None` unknown. States after the first colliding one are left
    /// unknown (the check that asks stops there). Every verdict is `None` when the
    /// screen cannot judge the motion.
    pub(crate) fn batch_clear(
        &self,
        standing: &Standing<'_>,
        batch: &mut BatchScratch,
        out: &mut [Option<bool>],
    ) {
        out.fill(None);
        let Some(frozen) = standing.frozen else {
            return;
        };
        if frozen.blocked() || !batch.usable || out.len() != batch.states || batch.states == 0 {
            return;
        }
        let n_live = batch.live.len();
        if !self.gather_near(standing, frozen, batch) {
            return;
        }
        for (s, verdict) in out.iter_mut().enumerate() {
            *verdict = self.judge_state(batch, s * n_live);
            if *verdict == Some(false) {
                break;
            }
        }
    }

    /// Gathers, per live body, the standing bodies whose boxes meet the union of its
    /// boxes over the batch, less the pairs that may touch; `false` when a union is not
    /// finite (nothing can be cleared then).
    fn gather_near(
        &self,
        standing: &Standing<'_>,
        frozen: &Frozen,
        batch: &mut BatchScratch,
    ) -> bool {
        let n_live = batch.live.len();
        batch.starts.clear();
        batch.near.clear();
        batch.near_placed.clear();
        for k in 0..3 {
            batch.near_lo[k].clear();
            batch.near_hi[k].clear();
        }
        let state = Configuration {
            robots: &[],
            objects: &batch.objects,
        };
        let away = standing.away();
        let home = standing.home;
        for l in 0..n_live {
            batch.starts.push(batch.near.len() as u32);
            let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
            for s in 0..batch.states {
                let (a, b) = (&batch.lo[s * n_live + l], &batch.hi[s * n_live + l]);
                // `min` and `max` pass NaN over: a box that cannot be measured must
                // stop the screen here, not shrink the union.
                if !a.iter().chain(b).all(|v| v.is_finite()) {
                    return false;
                }
                for k in 0..3 {
                    lo[k] = lo[k].min(a[k]);
                    hi[k] = hi[k].max(b[k]);
                }
            }
            // A hair wider, so that rounding in the index's own boxes never drops a body.
            let query = Aabb::new(
                Point::from(lo.map(|v| v - 1e-9)),
                Point::from(hi.map(|v| v + 1e-9)),
            );
            let i = batch.live[l] as usize;
            let mut found = |j: usize, p: &PlacedBody| {
                if j == i || self.allowed.get(i, j) || self.held_pair(&state, i, j) {
                    return;
                }
                batch.near.push(j as u32);
                for k in 0..3 {
                    batch.near_lo[k].push(p.aabb.mins[k]);
                    batch.near_hi[k].push(p.aabb.maxs[k]);
                }
                batch.near_placed.push(*p);
            };
            let _ = home.boxes.overlapping(&query, |leaf| {
                if let Some(&j) = home.leaves.get(leaf as usize) {
                    let j = j as usize;
                    if !self.on_away_robot(j, away) {
                        if let Some(p) = &home.placed[j] {
                            found(j, p);
                        }
                    }
                }
                Ok::<_, ()>(Visit::Continue)
            });
            let _ = frozen.boxes.overlapping(&query, |leaf| {
                if let Some((j, p)) = frozen.extra.get(leaf as usize) {
                    found(*j as usize, p);
                }
                Ok::<_, ()>(Visit::Continue)
            });
        }
        batch.starts.push(batch.near.len() as u32);
        true
    }

    /// What the screen proves of the state whose live bodies start at `at` in the
    /// batch (see [`CollisionWorld::batch_clear`]).
    fn judge_state(&self, batch: &BatchScratch, at: usize) -> Option<bool> {
        let n_live = batch.live.len();
        let mut known = true;
        for l in 0..n_live {
            let (lo, hi) = (&batch.lo[at + l], &batch.hi[at + l]);
            let range = batch.starts[l] as usize..batch.starts[l + 1] as usize;
            let (nlo, nhi) = (&batch.near_lo, &batch.near_hi);
            for c in range {
                // `|`, not `||`: six comparisons without a branch between them. NaN
                // compares false, so a box that cannot be measured is never apart.
                let apart = (nlo[0][c] > hi[0])
                    | (lo[0] > nhi[0][c])
                    | (nlo[1][c] > hi[1])
                    | (lo[1] > nhi[1][c])
                    | (nlo[2][c] > hi[2])
                    | (lo[2] > nhi[2][c]);
                if apart {
                    continue;
                }
                let (i, j) = (batch.live[l] as usize, batch.near[c] as usize);
                let sj = &batch.near_placed[c];
                match self.pair_apart(batch, i, at + l, j, &sj.pose) {
                    Some(true) => {}
                    Some(false) => {
                        let state = Configuration {
                            robots: &[],
                            objects: &batch.objects,
                        };
                        let pi = self.placed_at(i, batch.poses[at + l], 0.0);
                        match pi {
                            Ok(pi) if self.standing_pair(&state, i, &pi, j, sj, 0.0) => {
                                return Some(false)
                            }
                            _ => known = false,
                        }
                    }
                    None => known = false,
                }
            }
        }
        for &(x, y) in &batch.pairs {
            let (x, y) = (x as usize, y as usize);
            let (a, b) = (at + x, at + y);
            let (la, ha, lb, hb) = (&batch.lo[a], &batch.hi[a], &batch.lo[b], &batch.hi[b]);
            let apart = (0..3).any(|k| la[k] > hb[k] || lb[k] > ha[k]);
            if apart {
                continue;
            }
            let (i, j) = (batch.live[x] as usize, batch.live[y] as usize);
            match self.pair_apart(batch, i, a, j, &batch.poses[b]) {
                Some(true) => {}
                Some(false) => {
                    // The sweep's filters for the two, placed with no margin (the pair
                    // rules were applied when the pairs were listed): a pair the screen
                    // finds intersecting counts only when the full check would visit it.
                    let state = Configuration {
                        robots: &[],
                        objects: &batch.objects,
                    };
                    let pi = self.placed_at(i, batch.poses[a], 0.0);
                    let pj = self.placed_at(j, batch.poses[b], 0.0);
                    match (pi, pj) {
                        (Ok(pi), Ok(pj)) if self.standing_pair(&state, i, &pi, j, &pj, 0.0) => {
                            return Some(false)
                        }
                        _ => known = false,
                    }
                }
                None => known = false,
            }
        }
        known.then_some(true)
    }

    /// Whether live body `i` (entry `entry` of the batch) and body `j` at `pose_j` are
    /// apart (`Some(true)`) or intersect (`Some(false)`): by their capsules, else by the
    /// exact test, as the full check would test them (the same poses, bit for bit, so
    /// the same answer). `None` when the pair cannot be tested.
    fn pair_apart(
        &self,
        batch: &BatchScratch,
        i: usize,
        entry: usize,
        j: usize,
        pose_j: &Iso,
    ) -> Option<bool> {
        let pose_i = &batch.poses[entry];
        #[cfg(test)]
        if batch.shrink > 0.0 {
            // The unsound screen of the tests: capsules taken smaller than their bodies.
            let (bi, bj) = (&self.bodies[i], &self.bodies[j]);
            if let (Some(ci), Some(cj)) = (&bi.capsule, &bj.capsule) {
                let ci = super::capsule::Capsule {
                    radius: ci.radius - batch.shrink,
                    ..*ci
                };
                let gap = capsule_bound(
                    (&ci, pose_i, bi.half_extents.as_ref()),
                    (cj, pose_j, bj.half_extents.as_ref()),
                );
                if gap > 0.0 {
                    return Some(true);
                }
            }
        }
        self.intersect_at(i, pose_i, j, pose_j, || ())
            .ok()
            .map(|hit| !hit)
    }
}

#[cfg(test)]
mod tests;
