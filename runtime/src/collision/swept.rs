//! The query behind sound motion checks: around a state, how far along a joint-space
//! segment the bodies can move before two that may not touch could touch.
//!
//! The caller describes the segment by a bound per body ([`SweepBounds`]): how far any
//! point of the body can travel per unit of the segment's parameter (the runtime's
//! `swept` module derives it from the joint deltas and per-joint reach radii). Two bodies
//! at distance `d` can then approach each other by at most `p |t|` over a parameter
//! change `t`, where `p` is the sum of their bounds, or, for two bodies of one robot, the
//! sum of what the joints between them contribute (the joints below both move them
//! rigidly together, which changes no distance). So no configuration within `|t| < d / p`
//! of the state brings that pair into contact, and the smallest such radius over all
//! pairs that may not touch holds for the whole state.

use parry3d_f64::query;

use super::build::Mount;
use super::world::{CollisionScratch, CollisionWorld, Visit};
use super::{CollisionError, Configuration};
use crate::math::Point;

/// Distances up to this (metres, a micrometre) count as contact in a swept query: a
/// certified configuration keeps every pair that may not touch at least this far apart,
/// far above the rounding of the distance computation and of the interpolation, so the
/// exact intersection test finds nothing there however finely it samples.
pub(crate) const CONTACT: f64 = 1e-6;

/// How far each body of the world may travel along one segment, per unit of the
/// segment's parameter. Bodies not set are static (bound 0).
#[derive(Clone, Debug, Default)]
pub(crate) struct SweepBounds {
    /// Per body index.
    rides: Vec<Option<Ride>>,
    /// The bodies' bounds by joint, flat (see [`SweepBounds::set`]).
    suffix: Vec<f64>,
}

/// A moving body: the robot frame it rides on and where its bounds are.
#[derive(Clone, Copy, Debug)]
struct Ride {
    robot: usize,
    frame: usize,
    start: usize,
}

impl SweepBounds {
    /// Every one of `bodies` bodies static.
    pub(crate) fn reset(&mut self, bodies: usize) {
        self.rides.clear();
        self.rides.resize(bodies, None);
        self.suffix.clear();
    }

    /// Body `body` (an index into the world's bodies) rides on frame `frame` of robot
    /// `robot`; `fill` writes its `frame` bounds, the `g`-th bounding how far it travels
    /// through joints `g..frame` of that robot (so non-increasing in `g`).
    pub(crate) fn set(
        &mut self,
        body: usize,
        robot: usize,
        frame: usize,
        fill: impl FnOnce(&mut [f64]),
    ) {
        let Some(slot) = self.rides.get_mut(body) else {
            return;
        };
        let start = self.suffix.len();
        *slot = Some(Ride {
            robot,
            frame,
            start,
        });
        self.suffix.resize(start + frame, 0.0);
        fill(&mut self.suffix[start..]);
    }

    /// How far body `i` travels through the joints of its robot from joint `g` up.
    fn from_joint(&self, i: usize, g: usize) -> f64 {
        match self.rides.get(i).copied().flatten() {
            Some(r) if g < r.frame => self.suffix[r.start + g],
            _ => 0.0,
        }
    }

    /// How far body `i` travels at most.
    fn own(&self, i: usize) -> f64 {
        self.from_joint(i, 0)
    }

    /// How much the distance between bodies `i` and `j` can shrink at most.
    fn pair(&self, i: usize, j: usize) -> f64 {
        match (self.rides[i], self.rides[j]) {
            (Some(a), Some(b)) if a.robot == b.robot => {
                let g = a.frame.min(b.frame);
                self.from_joint(i, g) + self.from_joint(j, g)
            }
            _ => self.own(i) + self.own(j),
        }
    }
}

/// A body's bounding sphere where it is mounted, for deriving [`SweepBounds`].
#[derive(Clone, Copy, Debug)]
pub(crate) struct BodySphere {
    /// Index of the body in the world (what [`SweepBounds::set`] takes).
    pub(crate) body: usize,
    /// What it moves with.
    pub(crate) mount: Mount,
    /// The sphere's centre in the mount's frame (a robot frame, the object frame, or
    /// the world for fixed bodies).
    pub(crate) centre: Point,
    /// Its radius.
    pub(crate) radius: f64,
}

impl CollisionWorld {
    /// Number of bodies (solids), the length [`SweepBounds::reset`] takes.
    pub(crate) fn body_count(&self) -> usize {
        self.bodies.len()
    }

    /// Every body's bounding sphere in the frame it is mounted on.
    pub(crate) fn body_spheres(&self) -> impl Iterator<Item = BodySphere> + '_ {
        self.bodies.iter().enumerate().map(|(body, b)| BodySphere {
            body,
            mount: b.mount,
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
    /// the segment's ends to be valid. The broad phase grows every body by how far it can
    /// travel within `horizon` (plus half of [`CONTACT`]), so a pair it separates stays
    /// apart for the whole horizon; bounding spheres then spare the exact distance of a
    /// pair whose spheres alone prove the current radius.
    pub(crate) fn free_radius(
        &self,
        state: &Configuration<'_>,
        bounds: &SweepBounds,
        horizon: f64,
        scratch: &mut CollisionScratch,
    ) -> Result<f64, CollisionError> {
        self.place(state, scratch, |i| bounds.own(i) * horizon + CONTACT / 2.0)?;
        let mut radius = horizon;
        self.sweep(state, scratch, |i, j, scratch| {
            let p = bounds.pair(i, j);
            if p <= 0.0 {
                return Ok(Visit::Continue);
            }
            let (bi, bj) = (&self.bodies[i], &self.bodies[j]);
            let gap = (scratch.centres[i] - scratch.centres[j]).norm()
                - bi.sphere_radius
                - bj.sphere_radius;
            if (gap - CONTACT) / p >= radius {
                return Ok(Visit::Continue);
            }

            let d = query::distance(
                &scratch.poses[i],
                bi.shape.as_ref(),
                &scratch.poses[j],
                bj.shape.as_ref(),
            )
            .map_err(|_| self.unsupported(i, j))?;
            let r = (d - CONTACT) / p;
            if r <= 0.0 {
                radius = 0.0;
                return Ok(Visit::Stop);
            }
            radius = radius.min(r);
            Ok(Visit::Continue)
        })?;
        Ok(radius)
    }
}

#[cfg(test)]
mod tests {
    //! The swept radius against brute force: configurations sampled densely within the
    //! radius never bring a pair closer than the contact distance.

    use std::f64::consts::FRAC_PI_2;

    use parry3d_f64::shape::SharedShape;

    use super::super::{CollisionWorldBuilder, ObjectState};
    use super::*;
    use crate::math::{Iso, Vec3};
    use crate::robot::LinkShape;

    /// A two-frame "robot" whose second frame turns about z by `angle`, with a box at
    /// `reach` along x, and a fixed ball in its way.
    fn world() -> CollisionWorld {
        let mut b = CollisionWorldBuilder::new();
        let shapes = vec![LinkShape {
            link: "arm".into(),
            frame: 1,
            local: Iso::translation(0.5, 0.0, 0.0),
            shape: SharedShape::cuboid(0.05, 0.05, 0.05),
        }];
        b.add_chain("r", 2, Iso::identity(), shapes, |a, c| a.abs_diff(c) <= 1, None);
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
        bounds.set(0, 0, 1, |s| s[0] = per_unit);
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
