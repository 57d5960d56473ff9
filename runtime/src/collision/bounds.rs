//! How far the bodies of a segment's moving arms can travel ([`SweepBounds`]), the bound
//! behind every clearance certificate (`swept.rs`).
//!
//! A body's bound is a sum over the joints below it of the joint's change along the
//! segment times a reach radius: a bound on the distance from the joint's axis to any
//! point of the body. The runtime's `swept` module computes those radii once per body
//! from the chain alone, so they hold in every configuration, and are as long as the
//! stretched-out arm for the joints near the base. [`SweepBounds::pair_here`] tightens
//! them at the state being certified: the body's bounding sphere is where the state puts
//! it, so its distance from a joint's axis is measured, and over the certificate's window
//! (at most `horizon` of the segment's parameter either way) it can grow only by how far
//! the joints above that axis carry the body (joints below move axis and body rigidly
//! together, and the joint itself turns the body about the axis). The measured radius
//! plus that growth bounds the body's distance from the axis everywhere in the window, as
//! the fixed radius does, so it may replace it where smaller. A folded Panda keeps its
//! hand far nearer the base's axes than the fixed radii assume, and larger certificates
//! mean fewer of them per edge.

use crate::math::{Iso, Point, Vec3};

/// What every measured reach radius is grown by (metres, a nanometre), for the rounding
/// of the poses it is measured from.
const PAD: f64 = 1e-9;

/// Frames up to which bounds are tightened at the state (a longer chain keeps its fixed
/// radii): the stack buffers of [`SweepBounds::pair_here`] are this long.
const MAX_FRAMES: usize = 16;

/// A joint's axis, in the frame of a body that turns with the frame just above the joint
/// (so the axis is fixed there): the body's placed pose carries it into the world.
#[derive(Clone, Copy, Debug)]
pub(crate) struct AxisRef {
    /// Index of that body in the world.
    pub(crate) body: u32,
    /// A point of the axis, in that body's frame.
    pub(crate) point: Point,
    /// The axis's unit direction, in that body's frame.
    pub(crate) dir: Vec3,
}

/// One joint below a body, for [`SweepBounds::set`].
#[derive(Clone, Copy, Debug)]
pub(crate) struct JointReach {
    /// How much the segment changes the joint (radians or metres per unit of its
    /// parameter, not negative).
    pub(crate) speed: f64,
    /// How far any point of the body is from the joint's axis in every configuration (1
    /// for a prismatic joint), possibly less for the last joint (a body symmetric about
    /// it).
    pub(crate) reach: f64,
    /// The joint's axis, when it turns (a revolute joint) and a body of the frame above
    /// it can place it: then the reach can be measured at the state.
    pub(crate) axis: Option<AxisRef>,
}

/// How far each body of the world may travel along one segment, per unit of the
/// segment's parameter. Bodies not set are static (bound 0).
#[derive(Clone, Debug, Default)]
pub(crate) struct SweepBounds {
    /// Per body index.
    rides: Vec<Option<Ride>>,
    /// The bodies' bounds by joint, flat (see [`SweepBounds::set`]).
    suffix: Vec<f64>,
    /// The joints below each body, flat, in step with `suffix`.
    joints: Vec<JointReach>,
    /// The bodies set since the last reset, so that a reset costs what was set, not the
    /// size of the world (a motion in a line of fifty arms sets a dozen bodies of six
    /// hundred, once per certificate).
    set: Vec<u32>,
}

/// A body of a moving robot: the frame it rides on, where its bounds are, and how fast
/// the joint just above its frame can change its distance to the bodies above.
#[derive(Clone, Copy, Debug)]
struct Ride {
    robot: usize,
    frame: usize,
    start: usize,
    above: f64,
}

/// Where a body is in the state being certified, for [`SweepBounds::pair_here`]: its
/// bounding sphere, and the capsule that contains it when it has one (`capsule.rs`; a
/// long link's is far thinner than its sphere).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Extent {
    /// The sphere's centre, in the world.
    pub(crate) centre: Point,
    /// Its radius.
    pub(crate) radius: f64,
    /// The capsule's segment ends, in the world, and its radius.
    pub(crate) capsule: Option<(Point, Point, f64)>,
}

impl Extent {
    /// How far the body's farthest point can be from the line through `point` along
    /// unit `dir`: from the sphere, or from the capsule (the distance from a line is
    /// convex along a segment, so one of its ends is the farthest), whichever is less.
    fn farthest_from_line(&self, point: &Point, dir: &Vec3) -> f64 {
        let from = |p: &Point| (p - point).cross(dir).norm();
        let sphere = from(&self.centre) + self.radius;
        match &self.capsule {
            Some((a, b, r)) => sphere.min(from(a).max(from(b)) + r),
            None => sphere,
        }
    }
}

impl SweepBounds {
    /// Every one of `bodies` bodies static.
    pub(crate) fn reset(&mut self, bodies: usize) {
        if self.rides.len() == bodies {
            for &i in &self.set {
                self.rides[i as usize] = None;
            }
        } else {
            self.rides.clear();
            self.rides.resize(bodies, None);
        }
        self.set.clear();
        self.suffix.clear();
        self.joints.clear();
    }

    /// Body `body` (an index into the world's bodies) rides on frame `frame` of robot
    /// `robot`, moved by `joints`, the joints `0..frame` of that robot in order (fewer
    /// are taken as static, more are ignored). `above` bounds how far joint `frame` (the
    /// one just above the body) can change the body's distance to anything it carries,
    /// when less than those bodies' own travel through it (a body symmetric about that
    /// joint's axis: infinity when there is none). Returns the body's travel.
    pub(crate) fn set(
        &mut self,
        body: usize,
        robot: usize,
        frame: usize,
        above: f64,
        joints: impl IntoIterator<Item = JointReach>,
    ) -> f64 {
        let Some(slot) = self.rides.get_mut(body) else {
            return 0.0;
        };
        let start = self.suffix.len();
        self.set.push(body as u32);
        *slot = Some(Ride {
            robot,
            frame,
            start,
            above,
        });
        let still = JointReach {
            speed: 0.0,
            reach: 0.0,
            axis: None,
        };
        self.joints.extend(joints.into_iter().take(frame));
        self.joints.resize(start + frame, still);
        self.suffix.resize(start + frame, 0.0);
        let mut sum = 0.0;
        for g in (0..frame).rev() {
            let j = &self.joints[start + g];
            sum += j.speed * j.reach;
            self.suffix[start + g] = sum;
        }
        sum
    }

    /// How far body `i` travels through the joints of its robot from joint `g` up.
    fn travel_from(&self, i: usize, g: usize) -> f64 {
        match self.rides.get(i).copied().flatten() {
            Some(r) if g < r.frame => self.suffix[r.start + g],
            _ => 0.0,
        }
    }

    /// How far body `i` travels at most.
    pub(super) fn own(&self, i: usize) -> f64 {
        self.travel_from(i, 0)
    }

    /// How much the distance between bodies `i` and `j` can shrink at most.
    pub(super) fn pair(&self, i: usize, j: usize) -> f64 {
        pair_of(
            self.rides[i],
            self.rides[j],
            |g| self.travel_from(i, g),
            |g| self.travel_from(j, g),
        )
    }

    /// [`pair`](Self::pair) tightened at the state where every body's pose is `poses`
    /// and bodies `i` and `j` are `extents`, for a certificate of at most `horizon` either
    /// way (see [the module](self) documentation): never more than `pair`.
    pub(super) fn pair_here(
        &self,
        (i, j): (usize, usize),
        extents: (&Extent, &Extent),
        poses: &[Iso],
        horizon: f64,
    ) -> f64 {
        let (mut ti, mut tj) = ([0.0; MAX_FRAMES + 1], [0.0; MAX_FRAMES + 1]);
        let (Some(()), Some(())) = (
            self.travel_here(i, extents.0, poses, horizon, &mut ti),
            self.travel_here(j, extents.1, poses, horizon, &mut tj),
        ) else {
            return self.pair(i, j);
        };
        pair_of(self.rides[i], self.rides[j], |g| ti[g], |g| tj[g])
    }

    /// Body `i`'s travel from each joint up, tightened at `at` over the window: `out[g]`
    /// for joint `g` (0 from its frame up, and everywhere for a static body). `None` for
    /// a chain longer than [`MAX_FRAMES`].
    fn travel_here(
        &self,
        i: usize,
        extent: &Extent,
        poses: &[Iso],
        horizon: f64,
        out: &mut [f64; MAX_FRAMES + 1],
    ) -> Option<()> {
        let Some(ride) = self.rides.get(i).copied().flatten() else {
            return Some(());
        };
        if ride.frame > MAX_FRAMES {
            return None;
        }
        let mut sum = 0.0;
        for g in (0..ride.frame).rev() {
            let joint = &self.joints[ride.start + g];
            let mut reach = joint.reach;
            if let Some(axis) = &joint.axis {
                if let Some(pose) = poses.get(axis.body as usize) {
                    let (point, dir) = (pose * axis.point, pose * axis.dir);
                    // How far the body is from the axis now, plus how far the joints
                    // above the axis can carry it within the window (`sum`, this
                    // body's travel from joint g + 1 up, already tightened).
                    let measured = extent.farthest_from_line(&point, &dir) + horizon * sum + PAD;
                    // `min` keeps the fixed radius should the measure not be a number.
                    reach = reach.min(measured);
                }
            }
            sum += joint.speed * reach;
            out[g] = sum;
        }
        Some(())
    }
}

/// How much the distance between two bodies can shrink, from how far each travels from
/// each joint of its robot up (`from_i(g)`, `from_j(g)`).
fn pair_of(
    ri: Option<Ride>,
    rj: Option<Ride>,
    from_i: impl Fn(usize) -> f64,
    from_j: impl Fn(usize) -> f64,
) -> f64 {
    match (ri, rj) {
        (Some(a), Some(b)) if a.robot == b.robot => {
            // Seen from the lower body's frame `g`, only joints `g..` move the other;
            // joint `g` turns it about an axis fixed in that frame, which changes the
            // distance no faster than it moves the other body, nor than it would move the
            // lower body turned the opposite way.
            if a.frame == b.frame {
                return 0.0;
            }
            let (low, g) = if a.frame < b.frame {
                (a, a.frame)
            } else {
                (b, b.frame)
            };
            let (through, beyond) = if a.frame < b.frame {
                (from_j(g), from_j(g + 1))
            } else {
                (from_i(g), from_i(g + 1))
            };
            beyond + (through - beyond).min(low.above)
        }
        _ => from_i(0) + from_j(0),
    }
}

#[cfg(test)]
mod tests {
    //! The tightened reach radii against forward kinematics: over the whole window, every
    //! corner of every body (a box) stays within the tightened radius of each joint's
    //! axis.

    use parry3d_f64::shape::SharedShape;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    use super::super::{
        CollisionScratch, CollisionWorld, CollisionWorldBuilder, Configuration, Mount,
    };
    use super::*;
    use crate::robot::LinkShape;

    /// Joint g turns frame g + 1 about `AXES[g]` (in frame g + 1) through its origin,
    /// which sits at `OFFSETS[g]` in frame g.
    const AXES: [[f64; 3]; 3] = [[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [0.6, 0.0, 0.8]];
    const OFFSETS: [[f64; 3]; 3] = [[0.0, 0.0, 0.1], [0.0, 0.0, 0.3], [0.4, 0.1, 0.0]];
    /// A box on each moving frame, at this offset in it.
    const LINKS: [[f64; 3]; 3] = [[0.0, 0.05, 0.1], [0.2, 0.0, 0.0], [0.15, -0.05, 0.1]];

    /// The boxes' half extents, and their corners.
    const HALF: [f64; 3] = [0.08, 0.03, 0.02];
    const CORNERS: [Vec3; 8] = {
        let [x, y, z] = HALF;
        [
            Vec3::new(-x, -y, -z),
            Vec3::new(x, -y, -z),
            Vec3::new(-x, y, -z),
            Vec3::new(x, y, -z),
            Vec3::new(-x, -y, z),
            Vec3::new(x, -y, z),
            Vec3::new(-x, y, z),
            Vec3::new(x, y, z),
        ]
    };

    fn frames(q: &[f64]) -> Vec<Iso> {
        let mut frames = vec![Iso::identity()];
        for g in 0..3 {
            let axis = Vec3::from(AXES[g]).normalize();
            let turn = Iso::rotation(axis * q[g]);
            let last = frames[g];
            frames
                .push(last * Iso::translation(OFFSETS[g][0], OFFSETS[g][1], OFFSETS[g][2]) * turn);
        }
        frames
    }

    fn world() -> CollisionWorld {
        let mut b = CollisionWorldBuilder::new();
        let shapes = (0..3)
            .map(|k| LinkShape {
                link: format!("link{}", k + 1),
                frame: k + 1,
                local: Iso::translation(LINKS[k][0], LINKS[k][1], LINKS[k][2]),
                shape: SharedShape::cuboid(HALF[0], HALF[1], HALF[2]),
            })
            .collect();
        b.add_chain(
            "r",
            4,
            Iso::identity(),
            shapes,
            |a, c| a.abs_diff(c) <= 1,
            None,
        );
        b.build().expect("valid world")
    }

    #[test]
    fn tightened_radii_bound_the_distance_from_each_axis_over_the_window() {
        let world = world();
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let mut scratch = CollisionScratch::default();
        let mut bounds = SweepBounds::default();
        // A fixed radius far above any real one, so the tightened one is what is tested.
        const FIXED: f64 = 10.0;
        let mut tightened = 0;
        for _ in 0..300 {
            let q0: Vec<f64> = (0..3).map(|_| rng.random_range(-3.0..3.0)).collect();
            let delta: Vec<f64> = (0..3).map(|_| rng.random_range(-2.0..2.0)).collect();
            let horizon = rng.random_range(0.01..1.0);
            let at_q0 = frames(&q0);
            let robots: [&[Iso]; 1] = [&at_q0];
            let state = Configuration {
                robots: &robots,
                objects: &[],
            };
            world.place(&state, &mut scratch, |_| 0.0).expect("placed");
            bounds.reset(world.body_count());
            let geometry: Vec<_> = world.body_geometry().collect();
            for body in &geometry {
                let Mount::Frame { frame, .. } = body.mount else {
                    continue;
                };
                let reaches = (0..frame).map(|g| {
                    // Body g (on frame g + 1) carries joint g's axis.
                    let to_body = geometry[g].local.inverse();
                    JointReach {
                        speed: delta[g].abs(),
                        reach: FIXED,
                        axis: Some(AxisRef {
                            body: g as u32,
                            point: to_body * Point::origin(),
                            dir: to_body * Vec3::from(AXES[g]).normalize(),
                        }),
                    }
                });
                bounds.set(body.body, 0, frame, f64::INFINITY, reaches);
            }
            for body in &geometry {
                let Mount::Frame { frame, .. } = body.mount else {
                    continue;
                };
                let placed = &world.bodies[body.body];
                let extent = Extent {
                    centre: scratch.centres[body.body],
                    radius: body.radius,
                    capsule: placed.capsule.map(|c| {
                        let (a, b) = c.placed(&scratch.poses[body.body]);
                        (a, b, c.radius)
                    }),
                };
                assert!(extent.capsule.is_some());
                let mut out = [0.0; MAX_FRAMES + 1];
                bounds
                    .travel_here(body.body, &extent, &scratch.poses, horizon, &mut out)
                    .expect("a short chain");
                assert!(out[0] <= bounds.own(body.body));
                for g in 0..frame {
                    let reach = (out[g] - out[g + 1]) / delta[g].abs();
                    tightened += usize::from(reach < FIXED);
                    for k in -50..=50 {
                        let s = horizon * k as f64 / 50.0;
                        let q: Vec<f64> = q0.iter().zip(&delta).map(|(a, d)| a + s * d).collect();
                        let f = frames(&q);
                        let (point, dir) = (
                            f[g + 1] * Point::origin(),
                            f[g + 1] * Vec3::from(AXES[g]).normalize(),
                        );
                        let far = CORNERS
                            .iter()
                            .map(|c| {
                                let corner = f[frame] * body.local * Point::from(*c);
                                (corner - point).cross(&dir).norm()
                            })
                            .fold(0.0, f64::max);
                        assert!(
                            far <= reach * (1.0 + 1e-12),
                            "body {} joint {g} at {s} of {horizon}: {far} > {reach}",
                            body.body
                        );
                    }
                }
            }
        }
        assert!(tightened > 1000, "{tightened}");
    }
}
