//! How far the bodies of moving arms can travel along a straight joint-space segment: the
//! bound that makes motion checks sound ([`crate::motion::CertifiedMotion`]).
//!
//! # The bound
//!
//! Along `q(s) = a + s (b - a)`, `s` in [0, 1], a point `p` carried by frame `f` of an arm
//! moves with
//!
//! ```text
//! dp/ds = sum over joints j < f of  (b_j - a_j) * axis_j x (p - o_j)   (revolute j)
//!                                   (b_j - a_j) * axis_j               (prismatic j)
//! ```
//!
//! where `o_j` is any point of joint `j`'s axis. Hence `|dp/ds| <= sum_j |b_j - a_j| R_j`
//! with `R_j` an upper bound, over every configuration, on the distance from axis `j` to
//! any point the joint moves (1 for a prismatic joint), and over a parameter change `t`
//! the point moves at most `|t|` times that sum: a bound that holds for every point of
//! the body and every configuration on the segment, whatever the joints in between do.
//!
//! # The reach radii
//!
//! `R_j` is computed once per body (link solid, hand solid, held object solid) from its
//! bounding sphere (centre `c` in its frame, radius `r`) by walking the chain with the
//! triangle inequality. Frame `j + 1` turns about joint `j`'s axis through its own
//! origin, so for a body on frame `f = j + 1` the distance is exact: the distance from
//! `c` to the axis line, plus `r`. Further out, the next joint's origin sits at a fixed
//! offset `t_(j+1)` in frame `j + 1` (`Robot::origins`), so the distance is at most the
//! distance of `t_(j+1)` from the axis plus a bound on the distance from that joint's
//! origin to `c`: the lengths `|t_k|` of the links in between, each prismatic joint's
//! largest stroke, and `|c|`; plus `r`. Joint values never enter, so the radii are
//! bounds over all configurations, computed from the collision shapes alone (a held
//! object's with its grasp, as the collision world places it).
//!
//! Bodies of the arm's base frame, of arms that do not move and fixed bodies travel 0.
//! An arm with a prismatic joint of unlimited stroke has no finite bound, and the check
//! falls back to sampling.

use parry3d_f64::shape::SharedShape;

use cellc_schema::ObjectId;

use crate::collision::{AxisRef, JointReach, Mount, SweepBounds};
use crate::math::{Iso, Point, Vec3};
use crate::robot::Robot;
use crate::scene::{ObjectPlacement, Scene};
use crate::validity::ArmSlice;

/// How far ahead (metres of travel for the fastest body) one swept query looks: the
/// broad phase grows each body by its travel over the horizon, and a pair it cannot
/// separate gets a lower bound at least, so a long horizon costs pairs (all of a
/// five-arm line's at once) and a short one costs queries. Half a metre measured best on
/// the motion benchmarks (two or three queries per tree edge).
pub(crate) const LOOKAHEAD: f64 = 0.5;

/// The reach radii of the bodies that move with a set of arms (and a held object), from
/// which [`SweptBodies::fill`] bounds each body's travel along one segment.
#[derive(Clone, Debug, Default)]
pub(crate) struct SweptBodies {
    moving: Vec<Moving>,
    /// Per moving body, one radius per joint below its frame, flat.
    radii: Vec<f64>,
    /// In step with `radii`: each of those joints' axis as a body of the frame above it
    /// carries it, for tightening the radius at the state being certified
    /// ([`SweepBounds::set`]).
    axes: Vec<Option<AxisRef>>,
    /// Whether every radius is finite (no unlimited prismatic stroke).
    finite: bool,
}

/// A body that moves with an arm.
#[derive(Clone, Copy, Debug)]
struct Moving {
    /// Index in the collision world.
    body: usize,
    /// The world robot it rides on.
    robot: usize,
    /// The frame of that robot it rides on.
    frame: usize,
    /// Where the robot's joints start in the combined configuration.
    offset: usize,
    /// Where its radii start in [`SweptBodies::radii`].
    start: usize,
    /// How fast turning the joint above its frame moves it as a set (infinite when that
    /// joint does not turn or the body has no symmetry about its axis).
    above: f64,
}

impl SweptBodies {
    /// The moving bodies of the arms `slices` (joints concatenated in that order), with
    /// `object` placed as `placement` (riding the hand that holds it, if that arm moves).
    pub(crate) fn new(
        scene: &Scene,
        slices: &[ArmSlice],
        object: ObjectId,
        placement: &ObjectPlacement,
    ) -> SweptBodies {
        let mut swept = SweptBodies {
            finite: true,
            ..SweptBodies::default()
        };
        // The arm that carries the object, and the object's pose in its hand frame.
        let carrier = match *placement {
            ObjectPlacement::Held { by, grasp } | ObjectPlacement::Placing { by, grasp, .. } => {
                Some((by, grasp))
            }
            ObjectPlacement::Handoff { a, grasp_a, .. } => Some((a, grasp_a)),
            ObjectPlacement::Resting { .. } | ObjectPlacement::Absent => None,
        };
        for slice in slices {
            let Some(world_robot) = scene.world_robot(slice.end_effector) else {
                continue;
            };
            let robot = &scene.robots[slice.robot];
            let n = robot.n_joints();
            let carried = carrier
                .filter(|(by, _)| *by == slice.end_effector)
                .map(|(_, grasp)| robot.tip_offset() * grasp);
            // Joint g's axis runs through the origin of frame g + 1 along `axes()[g]`
            // there; any body of that frame carries it.
            let joint_axes: Vec<Option<AxisRef>> = (0..n)
                .map(|g| {
                    if !robot.joint_kinds()[g].is_rotational() {
                        return None;
                    }
                    let dir = robot.axes()[g].try_normalize(1e-12)?;
                    let body = scene.world.body_geometry().find(|b| {
                        matches!(b.mount, Mount::Frame { robot, frame }
                            if robot == world_robot && frame == g + 1)
                    })?;
                    let to_body = body.local.inverse();
                    Some(AxisRef {
                        body: u32::try_from(body.body).ok()?,
                        point: to_body * Point::origin(),
                        dir: to_body * dir,
                    })
                })
                .collect();
            for body in scene.world.body_geometry() {
                let (frame, local, centre) = match body.mount {
                    Mount::Frame { robot: r, frame } if r == world_robot => {
                        (frame, body.local, body.centre)
                    }
                    Mount::Object { object: o } if o == object.index() => match &carried {
                        Some(in_hand) => (n, in_hand * body.local, in_hand * body.centre),
                        None => continue,
                    },
                    _ => continue,
                };
                let start = swept.radii.len();
                reach_radii(robot, frame, &centre, body.radius, &mut swept.radii);
                swept
                    .axes
                    .extend((0..frame).map(|g| joint_axes.get(g).copied().flatten()));
                // The joint below the body's frame turns it about an axis fixed in that
                // frame: a body symmetric about it hardly moves as a set.
                if frame > 0 && robot.joint_kinds()[frame - 1].is_rotational() {
                    let axis = (Point::origin(), robot.axes()[frame - 1]);
                    if let Some(spin) = spin_radius(body.shape, &local, &axis) {
                        let last = &mut swept.radii[start + frame - 1];
                        *last = last.min(spin);
                    }
                }
                // The joint above it, likewise, for the bodies it carries.
                let above = (frame < n && robot.joint_kinds()[frame].is_rotational())
                    .then(|| {
                        let origin = &robot.origins()[frame];
                        let axis = (
                            Point::from(origin.translation.vector),
                            origin.rotation * robot.axes()[frame],
                        );
                        spin_radius(body.shape, &local, &axis)
                    })
                    .flatten()
                    .unwrap_or(f64::INFINITY);
                swept.finite &= swept.radii[start..].iter().all(|r| r.is_finite());
                swept.moving.push(Moving {
                    body: body.body,
                    robot: world_robot,
                    frame,
                    offset: slice.offset,
                    start,
                    above,
                });
            }
        }
        swept
    }

    /// Fills `bounds` (for a world of `bodies` bodies) with how far each body travels
    /// per unit of the parameter of a segment whose joints change by `delta` (the
    /// combined configuration's `b - a`); returns the largest travel, or `None` when the
    /// arms have no finite bound.
    pub(crate) fn fill(
        &self,
        delta: &[f64],
        bounds: &mut SweepBounds,
        bodies: usize,
    ) -> Option<f64> {
        if !self.finite {
            return None;
        }
        bounds.reset(bodies);
        let mut largest: f64 = 0.0;
        for m in &self.moving {
            let radii = &self.radii[m.start..m.start + m.frame];
            let joints = &delta[m.offset..m.offset + m.frame];
            let above = match delta.get(m.offset + m.frame) {
                Some(d) if m.above.is_finite() => d.abs() * m.above,
                _ => f64::INFINITY,
            };
            let axes = &self.axes[m.start..m.start + m.frame];
            let reaches = (0..m.frame).map(|g| JointReach {
                speed: joints[g].abs(),
                reach: radii[g],
                axis: axes[g],
            });
            largest = largest.max(bounds.set(m.body, m.robot, m.frame, above, reaches));
        }
        Some(largest)
    }
}

/// Appends, for joints `0..frame` of `robot`, a bound on the distance from the joint's
/// axis to any point of the sphere (`centre` in frame `frame`, `radius`), over every
/// configuration; 1 for a prismatic joint (see [the module](self) documentation).
fn reach_radii(robot: &Robot, frame: usize, centre: &Point, radius: f64, out: &mut Vec<f64>) {
    let (origins, axes, kinds) = (robot.origins(), robot.axes(), robot.joint_kinds());
    let (lower, upper) = robot.limits();
    let stroke = |k: usize| {
        if kinds[k].is_rotational() {
            0.0
        } else {
            lower[k].abs().max(upper[k].abs())
        }
    };
    let offset = |k: usize| origins[k].translation.vector;
    let from_axis = |v: &Vec3, axis: &Vec3| (v - axis * v.dot(axis)).norm();
    // Joints from the top down, `reach` bounding the distance from the origin of joint
    // `j + 1` to `centre` (unused for the top joint, whose frame carries the sphere).
    let start = out.len();
    out.resize(start + frame, 0.0);
    let mut reach = 0.0;
    for j in (0..frame).rev() {
        out[start + j] = if !kinds[j].is_rotational() {
            1.0
        } else if j + 1 == frame {
            from_axis(&centre.coords, &axes[j]) + radius
        } else {
            from_axis(&offset(j + 1), &axes[j]) + reach + radius
        };
        // Now the distance from joint j's origin: through frame j + 1's origin (its
        // stroke away for a prismatic joint), then the sphere's frame or joint j + 1.
        reach = stroke(j)
            + if j + 1 == frame {
                centre.coords.norm()
            } else {
                offset(j + 1).norm() + reach
            };
    }
}

/// How far points of the set a solid occupies (`shape` at `local`) can move per radian
/// of a turn about `axis` (a point and a unit direction, in the same frame), when the
/// solid is a ball, capsule or cylinder: its distance from the axis, plus what its own
/// axis's tilt from the turning one adds. A solid symmetric about the axis gives 0 (it
/// occupies the same space however far it turns), one merely close to symmetric (a
/// URDF's `1.5707963`) almost 0. `None` for other shapes.
///
/// A turn by `t` moves a point `x` by at most `|t|` times its distance from the axis, and
/// the solid's own axis direction `w` by at most `|t| |w x u|`; a cylinder's points are
/// `c + s w + r v` (`|s| <= h`, `v` a unit vector across `w`), and the turned point is
/// within `|t| (dist(c) + (h + 2 r) |w x u|)` of such a point of the unturned cylinder
/// (the turned `v` leaves the plane across `w` by at most `|t| |w x u|`). A capsule is a
/// segment grown by its radius, so its segment's ends bound it.
fn spin_radius(shape: &SharedShape, local: &Iso, axis: &(Point, Vec3)) -> Option<f64> {
    let (on, u) = axis;
    let from_axis = |p: &Point| (p - on).cross(u).norm();
    if shape.as_ball().is_some() {
        return Some(from_axis(&Point::from(local.translation.vector)));
    }
    if let Some(capsule) = shape.as_capsule() {
        let (a, b) = (local * capsule.segment.a, local * capsule.segment.b);
        return Some(from_axis(&a).max(from_axis(&b)));
    }
    let cylinder = shape.as_cylinder()?;
    let w = local.rotation * Vec3::y();
    let tilt = w.cross(u).norm();
    let centre = Point::from(local.translation.vector);
    Some(from_axis(&centre) + (cylinder.half_height + 2.0 * cylinder.radius) * tilt)
}

#[cfg(test)]
mod tests {
    //! The radii bound what forward kinematics shows: points of a robot's solids, moved
    //! along random segments, never travel farther than the bound says.

    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    use super::*;
    use crate::MemoryFiles;

    fn robot(urdf: &str, base: &str, tip: &str) -> Robot {
        Robot::from_urdf(urdf, "robot.urdf", base, tip, &MemoryFiles::default())
            .expect("the URDF loads")
    }

    /// Points on a sphere of `radius` about `centre`: the centre, and 26 directions.
    fn sphere_points(centre: &Point, radius: f64) -> Vec<Point> {
        let mut points = vec![*centre];
        for x in -1..=1 {
            for y in -1..=1 {
                for z in -1..=1 {
                    let d = Vec3::new(x as f64, y as f64, z as f64);
                    if d != Vec3::zeros() {
                        points.push(centre + d.normalize() * radius);
                    }
                }
            }
        }
        points
    }

    fn check(robot: &Robot, seed: u64) {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let base = Iso::translation(0.3, -0.2, 0.5);
        let n = robot.n_joints();
        let (mut a, mut b) = (vec![0.0; n], vec![0.0; n]);
        let (mut frames, mut q) = (Vec::new(), vec![0.0; n]);
        let mut radii = Vec::new();
        for _ in 0..200 {
            robot.sample_configuration(&mut rng, &mut a);
            robot.sample_configuration(&mut rng, &mut b);
            // Short segments too, where the bound is tightest relative to the motion.
            let scale = rng.random_range(0.01..1.0);
            for (bj, aj) in b.iter_mut().zip(&a) {
                *bj = aj + (*bj - aj) * scale;
            }
            for shape in robot.shapes().iter().filter(|s| s.frame > 0) {
                let sphere = shape.shape.compute_local_bounding_sphere();
                let centre = shape.local * sphere.center;
                radii.clear();
                reach_radii(robot, shape.frame, &centre, sphere.radius(), &mut radii);
                let bound: f64 = (0..shape.frame)
                    .map(|j| (b[j] - a[j]).abs() * radii[j])
                    .sum();
                let points = sphere_points(&centre, sphere.radius());
                robot.fk_frames(&base, &a, &mut frames);
                let start: Vec<Point> = points.iter().map(|p| frames[shape.frame] * p).collect();
                for k in 1..=50 {
                    let s = k as f64 / 50.0;
                    for (v, (x, y)) in q.iter_mut().zip(a.iter().zip(&b)) {
                        *v = x + (y - x) * s;
                    }
                    robot.fk_frames(&base, &q, &mut frames);
                    for (p, p0) in points.iter().zip(&start) {
                        let moved = (frames[shape.frame] * p - p0).norm();
                        assert!(
                            moved <= s * bound + 1e-12,
                            "{}: {moved} m at s = {s}, bound {}",
                            shape.link,
                            s * bound
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn an_lwr_never_moves_farther_than_its_bound() {
        let urdf = include_str!("../../cells/robots/kuka_lwr4.urdf");
        check(&robot(urdf, "lwr_base_link", "lwr_flange"), 1);
    }

    #[test]
    fn a_conveyor_never_moves_farther_than_its_bound() {
        let urdf = include_str!("../../cells/robots/conveyor.urdf");
        check(&robot(urdf, "conveyor_base", "conveyor_top"), 2);
    }

    #[test]
    fn the_bound_is_not_wildly_loose() {
        // The flange of a stretched LWR turning about A1 alone: the radius is its
        // distance from the axis plus the solid's sphere, not the arm's whole length.
        let urdf = include_str!("../../cells/robots/kuka_lwr4.urdf");
        let robot = robot(urdf, "lwr_base_link", "lwr_flange");
        let last = robot.shapes().last().expect("solids");
        let sphere = last.shape.compute_local_bounding_sphere();
        let mut radii = Vec::new();
        reach_radii(
            &robot,
            last.frame,
            &(last.local * sphere.center),
            sphere.radius(),
            &mut radii,
        );
        // A1 sees the flange from up to the whole arm above the shoulder; A7 turns it about
        // its own axis.
        assert!(radii[0] < 1.2, "{radii:?}");
        assert!(radii[last.frame - 1] < 0.1, "{radii:?}");
    }

    #[test]
    fn a_turned_solid_stays_within_its_spin_radius() {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let mut seen_small = false;
        for k in 0..300 {
            let shape = match k % 3 {
                0 => SharedShape::ball(rng.random_range(0.01..0.2)),
                1 => {
                    SharedShape::capsule_y(rng.random_range(0.01..0.2), rng.random_range(0.01..0.1))
                }
                _ => {
                    SharedShape::cylinder(rng.random_range(0.01..0.2), rng.random_range(0.01..0.1))
                }
            };
            // Axes from exactly the solid's own to far from it.
            let off = [0.0, 1e-8, 0.01, 0.3][k % 4];
            let local = Iso::new(
                Vec3::from_fn(|_, _| rng.random_range(-off..=off)),
                Vec3::from_fn(|_, _| rng.random_range(-off..=off)),
            );
            let axis = (Point::origin(), Vec3::y());
            let spin = spin_radius(&shape, &local, &axis).expect("a round solid");
            seen_small |= spin < 1e-6;
            for _ in 0..20 {
                let t: f64 = rng.random_range(-1.0..1.0);
                let turn = Iso::rotation(Vec3::y() * t);
                // A point of the solid: its support point in a random direction, pulled
                // towards the centre by a random fraction.
                let dir = Vec3::from_fn(|_, _| rng.random_range(-1.0..1.0));
                let surface = shape
                    .as_support_map()
                    .expect("a convex solid")
                    .support_point(&local, &dir);
                let x = Point::from(local.translation.vector).lerp(&surface, rng.random());
                let d = shape.distance_to_point(&local, &(turn * x), true);
                assert!(d <= t.abs() * spin + 1e-12, "{k}: {d} > {}", t.abs() * spin);
            }
        }
        assert!(seen_small);
    }
}
