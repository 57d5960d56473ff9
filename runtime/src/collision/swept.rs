//! The query behind sound motion checks: around a state, how far along a joint-space
//! segment the bodies can move before two that may not touch could touch.
//!
//! The caller describes the segment by a bound per body ([`SweepBounds`]): how far any
//! point of the body can travel per unit of the segment's parameter (the runtime's
//! `swept` module derives it from the joint deltas and per-joint reach radii). Two bodies
//! at distance `d` can then approach each other by at most `p |t|` over a parameter
//! change `t`, where `p` is the sum of their bounds, or, for two bodies of one robot, the
//! sum of what the joints between them contribute (the joints below both move them
//! rigidly together, which changes no distance), the first of those counting no more than
//! it would move the lower body turned the other way (little, for a link shaft turning
//! about its own axis). So no configuration within `|t| < d / p` of the state brings
//! that pair into contact, and the smallest such radius over all pairs that may not touch
//! holds for the whole state.
//!
//! Most pairs are far enough apart that a cheap lower bound on their distance already
//! proves more than the radius needs; exact distances (GJK, stopped as soon as it proves
//! a pair farther than needed) are computed nearest bound first, only for the rest.

use parry3d_f64::query;
use parry3d_f64::query::details::closest_points_support_map_support_map_with_params;
use parry3d_f64::query::gjk::{CSOPoint, GJKResult, VoronoiSimplex};
use parry3d_f64::shape::SharedShape;

use super::bounds::Extent;
use super::build::Mount;
use super::world::{CollisionScratch, CollisionWorld, Visit};
use super::{CollisionError, Configuration, SweepBounds};
use crate::math::{Iso, Point};

/// Distances up to this (metres, a micrometre) count as contact in a swept query: a
/// certified configuration keeps every pair that may not touch at least this far apart,
/// far above the rounding of the distance computation and of the interpolation, so the
/// exact intersection test finds nothing there however finely it samples.
pub(crate) const CONTACT: f64 = 1e-6;

/// A body's shape and bounding sphere where it is mounted, for deriving [`SweepBounds`].
#[derive(Clone, Copy)]
pub(crate) struct BodyGeometry<'w> {
    /// Index of the body in the world (what [`SweepBounds::set`] takes).
    pub(crate) body: usize,
    /// What it moves with.
    pub(crate) mount: Mount,
    /// The shape's pose in the mount's frame (a robot frame, the object frame, or the
    /// world for fixed bodies).
    pub(crate) local: Iso,
    /// The shape.
    pub(crate) shape: &'w SharedShape,
    /// The bounding sphere's centre in the mount's frame.
    pub(crate) centre: Point,
    /// Its radius.
    pub(crate) radius: f64,
}

impl CollisionWorld {
    /// Number of bodies (solids), the length [`SweepBounds::reset`] takes.
    pub(crate) fn body_count(&self) -> usize {
        self.bodies.len()
    }

    /// Every body's shape and bounding sphere in the frame it is mounted on.
    pub(crate) fn body_geometry(&self) -> impl Iterator<Item = BodyGeometry<'_>> + '_ {
        self.bodies
            .iter()
            .enumerate()
            .map(|(body, b)| BodyGeometry {
                body,
                mount: b.mount,
                local: b.local,
                shape: &b.shape,
                centre: b.local * b.sphere_centre,
                radius: b.sphere_radius,
            })
    }

    /// The largest `t <= horizon` such that no configuration within `t` of `state` along
    /// the segment `bounds` describes (either way) brings a pair that may not touch
    /// within [`CONTACT`] of each other; 0 when a pair already is that close. `bounds`
    /// must have one entry per body of the world.
    ///
    /// Pairs that are both static keep their distance and are skipped: the caller knows
    /// the segment's start to be valid. The broad phase grows every body by how far it
    /// can travel within `horizon` (plus half of [`CONTACT`]), so a pair it separates
    /// stays apart for the whole horizon; the others are measured, lazily (see [the
    /// module](self) documentation).
    pub(crate) fn free_radius(
        &self,
        state: &Configuration<'_>,
        bounds: &SweepBounds,
        horizon: f64,
        scratch: &mut CollisionScratch,
    ) -> Result<f64, CollisionError> {
        self.place(state, scratch, |i| bounds.own(i) * horizon + CONTACT / 2.0)?;
        // First every candidate pair with the radius a cheap lower bound on its distance
        // proves (the gap between bounding spheres, or between AABBs, which is tight for
        // the boxes of the furniture)...
        let mut candidates = std::mem::take(&mut scratch.candidates);
        candidates.clear();
        self.sweep(state, scratch, |i, j, scratch| {
            let p = bounds.pair(i, j);
            if p > 0.0 {
                let gap = lower_bound(self, scratch, i, j);
                candidates.push(((gap - CONTACT) / p, i as u32, j as u32));
            }
            Ok(Visit::Continue)
        })?;
        let result = self.nearest_radius(scratch, bounds, &mut candidates, horizon);
        scratch.candidates = candidates;
        result
    }

    /// The radius the candidate pairs allow: the exact test, nearest cheap bound first,
    /// only while a pair's cheap bound is below the radius found so far, and only as far
    /// as that radius needs (most pairs never need one, and GJK stops as soon as it
    /// proves a pair far enough apart). Sorts `candidates`.
    ///
    /// A pair it measures is bounded by [`SweepBounds::pair_here`], the fixed bounds
    /// tightened at this state for a window of `horizon` (`bounds.rs`); the cheap radii
    /// the candidates carry were computed with the fixed bounds, so they stay below what
    /// the tightened ones prove and still order and cut the loop soundly.
    pub(super) fn nearest_radius(
        &self,
        scratch: &CollisionScratch,
        bounds: &SweepBounds,
        candidates: &mut [(f64, u32, u32)],
        horizon: f64,
    ) -> Result<f64, CollisionError> {
        candidates.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then((a.1, a.2).cmp(&(b.1, b.2))));
        let mut radius = horizon;
        let extent = |k: usize| {
            let body = &self.bodies[k];
            Extent {
                centre: scratch.centres[k],
                radius: body.sphere_radius,
                capsule: body.capsule.map(|c| {
                    let (a, b) = c.placed(&scratch.poses[k]);
                    (a, b, c.radius)
                }),
            }
        };
        for &(cheap, i, j) in candidates.iter() {
            if cheap >= radius {
                break;
            }
            let (i, j) = (i as usize, j as usize);
            // The cheap bound was divided by the pair's fixed bound; the bound tightened
            // at this state is never larger, so it proves at least as much.
            let fixed = bounds.pair(i, j);
            let p = bounds.pair_here((i, j), (&extent(i), &extent(j)), &scratch.poses, horizon);
            if p <= 0.0 {
                continue;
            }
            if cheap > 0.0 && cheap * (fixed / p) * (1.0 - 1e-12) >= radius {
                continue;
            }
            if let Some(d) = self.distance_within(scratch, i, j, CONTACT + p * radius)? {
                let r = (d - CONTACT) / p;
                if r <= 0.0 {
                    return Ok(0.0);
                }
                radius = radius.min(r);
            }
        }
        Ok(radius)
    }

    /// The distance between placed bodies `i` and `j` when it is at most `threshold`
    /// (GJK's, which is within a relative 5e-8 of the true one), `None` when they are
    /// proven farther apart.
    fn distance_within(
        &self,
        scratch: &CollisionScratch,
        i: usize,
        j: usize,
        threshold: f64,
    ) -> Result<Option<f64>, CollisionError> {
        scratch.count_exact();
        let (pi, pj) = (&scratch.poses[i], &scratch.poses[j]);
        let (si, sj) = (self.bodies[i].shape.as_ref(), self.bodies[j].shape.as_ref());
        let exact = || {
            query::distance(pi, si, pj, sj)
                .map(|d| (d <= threshold).then_some(d))
                .map_err(|_| self.unsupported(i, j))
        };
        let (Some(gi), Some(gj)) = (self.support_map(i), self.support_map(j)) else {
            return exact();
        };
        let pos12 = pi.inv_mul(pj);
        let mut simplex = VoronoiSimplex::new();
        match closest_points_support_map_support_map_with_params(
            &pos12,
            gi,
            gj,
            threshold,
            &mut simplex,
            None,
        ) {
            GJKResult::Intersection => Ok(Some(0.0)),
            GJKResult::ClosestPoints(a, b, _) => Ok(Some((a - b).norm())),
            GJKResult::NoIntersection(dir) => {
                // GJK also says this when it gives up: believe it only with a separating
                // direction that proves the gap.
                let support = CSOPoint::from_shapes(&pos12, gi, gj, &dir);
                if -dir.dot(&support.point.coords) > threshold {
                    Ok(None)
                } else {
                    exact()
                }
            }
            GJKResult::Proximity(_) => exact(),
        }
    }
}

/// A lower bound on the distance between placed bodies `i` and `j`: the largest of the
/// gaps between their bounding spheres, between their AABBs (as placed, without the
/// margins the broad phase grew them by), and between the capsules that contain them
/// (`capsule.rs`; a capsule hugs a long link far closer than its sphere or box).
pub(super) fn lower_bound(
    world: &CollisionWorld,
    scratch: &CollisionScratch,
    i: usize,
    j: usize,
) -> f64 {
    let (bi, bj) = (&world.bodies[i], &world.bodies[j]);
    let spheres =
        (scratch.centres[i] - scratch.centres[j]).norm() - bi.sphere_radius - bj.sphere_radius;
    let (a, b) = (&scratch.aabbs[i], &scratch.aabbs[j]);
    let (ma, mb) = (scratch.margins[i], scratch.margins[j]);
    let mut boxes = 0.0;
    for k in 0..3 {
        let apart = (b.mins[k] + mb - (a.maxs[k] - ma)).max(a.mins[k] + ma - (b.maxs[k] - mb));
        if apart > 0.0 {
            boxes += apart * apart;
        }
    }
    let bound = spheres.max(boxes.sqrt());
    world
        .capsule_gap(scratch, i, j)
        .map_or(bound, |gap| bound.max(gap))
}

#[cfg(test)]
mod tests {
    //! The swept radius against dense sampling: configurations within the radius never
    //! bring a pair closer than the contact distance.

    use std::f64::consts::FRAC_PI_2;

    use super::super::{CollisionWorldBuilder, ObjectState};
    use super::*;
    use crate::math::Vec3;
    use crate::robot::LinkShape;

    /// A two-frame "robot" whose second frame turns about z, with a box half a metre
    /// out along its x axis, and a fixed ball in the box's way.
    fn world() -> CollisionWorld {
        let mut b = CollisionWorldBuilder::new();
        let shapes = vec![LinkShape {
            link: "arm".into(),
            frame: 1,
            local: Iso::translation(0.5, 0.0, 0.0),
            shape: SharedShape::cuboid(0.05, 0.05, 0.05),
        }];
        b.add_chain(
            "r",
            2,
            Iso::identity(),
            shapes,
            |a, c| a.abs_diff(c) <= 1,
            None,
        );
        b.add_fixed(
            "ball",
            Iso::translation(0.0, 0.5, 0.0),
            SharedShape::ball(0.1),
        );
        b.build().expect("valid world")
    }

    fn distance_at(world: &CollisionWorld, angle: f64) -> f64 {
        let frames = [Iso::identity(), Iso::rotation(Vec3::z() * angle)];
        let robots: [&[Iso]; 1] = [&frames];
        let state = Configuration {
            robots: &robots,
            objects: &[] as &[ObjectState],
        };
        let mut scratch = CollisionScratch::default();
        world
            .clearance(&state, &mut scratch, 10.0)
            .expect("well-formed")
            .map_or(f64::INFINITY, |p| p.distance)
    }

    #[test]
    fn nothing_within_the_radius_comes_closer_than_contact() {
        let world = world();
        let mut bounds = SweepBounds::default();
        bounds.reset(world.bodies.len());
        // The box's farthest point is 0.553 m from the axis: 0.6 m per radian bounds it,
        // for a segment of 2 rad.
        let per_unit = 0.6 * 2.0;
        let joint = super::super::JointReach {
            speed: 1.0,
            reach: per_unit,
            axis: None,
        };
        bounds.set(0, 0, 1, f64::INFINITY, [joint]);
        let mut scratch = CollisionScratch::default();
        let mut certified = 0;
        for k in 0..40 {
            let angle = k as f64 * 0.05;
            let frames = [Iso::identity(), Iso::rotation(Vec3::z() * angle)];
            let robots: [&[Iso]; 1] = [&frames];
            let state = Configuration {
                robots: &robots,
                objects: &[],
            };
            let t = world
                .free_radius(&state, &bounds, 1.0, &mut scratch)
                .expect("well-formed");
            assert!((0.0..=1.0).contains(&t));
            if t == 0.0 {
                // Refused only in contact.
                assert!(distance_at(&world, angle) <= CONTACT, "angle {angle}");
                continue;
            }
            certified += 1;
            for i in -100..=100 {
                let s = t * i as f64 / 100.0;
                let d = distance_at(&world, angle + 2.0 * s);
                assert!(d >= CONTACT, "angle {angle}, step {s}: {d}");
            }
        }
        assert!(certified > 10, "{certified}");
        // Turned onto the ball, nothing is certified.
        let frames = [Iso::identity(), Iso::rotation(Vec3::z() * FRAC_PI_2)];
        let robots: [&[Iso]; 1] = [&frames];
        let state = Configuration {
            robots: &robots,
            objects: &[],
        };
        let t = world
            .free_radius(&state, &bounds, 1.0, &mut scratch)
            .expect("well-formed");
        assert_eq!(t, 0.0);
    }
}
