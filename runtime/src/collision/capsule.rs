//! Capsules around bodies, fitted once when the world is built, for distance lower bounds
//! that reject far-apart pairs before an exact (GJK) query.
//!
//! A capsule (a segment and a radius: every point within the radius of the segment)
//! fitted so that it contains a body's shape gives `distance(capsule_a, capsule_b) <=
//! distance(body_a, body_b)`, and the distance between two capsules is the distance
//! between their segments minus both radii: a dozen multiplications, where GJK on two
//! Panda links takes a dozen support points over hulls of a hundred vertices or more.
//! Robot links are long, so a capsule hugs them far closer than their bounding sphere
//! (which is as wide as the link is long) or their AABB (a box turned with the link).
//! Against a box (the cubes of a cage, a bench, a finger) the segment's distance to the
//! box itself is used, which is exact and hardly dearer.
//!
//! The fit: for a few candidate axes (the principal axes of the vertices, by PCA, and
//! the shape's own x, y and z), the line along the axis through the middle of the
//! vertices' footprint across it, the radius the largest distance of a vertex from that
//! line, then the segment ends pulled in as far as every vertex stays covered by the end
//! caps; the candidate of least volume wins. The radius is then measured again from the
//! final segment, so that containment does not rest on the arithmetic of the fit, and
//! grown by [`PAD`].

use nalgebra::{Matrix3, SymmetricEigen};
use parry3d_f64::query;
use parry3d_f64::shape::{SegmentPointLocation, Shape};

use crate::math::{Iso, Point, Vec3};

/// What every fitted radius is grown by (metres, a nanometre): the world pose of a body
/// and its capsule's segment are computed with different roundings, and a bound that
/// exceeded the true distance by a rounding error could make a touching pair look apart.
pub(super) const PAD: f64 = 1e-9;

/// A segment `a`–`b` and a radius, in the frame of the shape it contains.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Capsule {
    pub(crate) a: Point,
    pub(crate) b: Point,
    pub(crate) radius: f64,
}

impl Capsule {
    /// A capsule containing `shape` in its own frame: fitted to a convex polyhedron's
    /// vertices or a cuboid's corners, a cylinder's axis (its capsule is exact in
    /// radius), a ball's centre; `None` for other shapes (they keep the sphere and AABB
    /// bounds) and for non-finite geometry.
    pub(crate) fn of_shape(shape: &dyn Shape) -> Option<Capsule> {
        let capsule = if let Some(hull) = shape.as_convex_polyhedron() {
            Capsule::around(hull.points())
        } else if let Some(c) = shape.as_cuboid() {
            let h = c.half_extents;
            let corners: Vec<Point> = (0..8)
                .map(|k| {
                    let s = |bit: usize| if k & (1 << bit) == 0 { -1.0 } else { 1.0 };
                    Point::new(s(0) * h.x, s(1) * h.y, s(2) * h.z)
                })
                .collect();
            Capsule::around(&corners)
        } else if let Some(c) = shape.as_cylinder() {
            // A parry cylinder is along its local y; the capsule's caps reach past its
            // flat ends, but no sideways.
            let half = Vec3::y() * c.half_height;
            Some(Capsule {
                a: Point::from(-half),
                b: Point::from(half),
                radius: c.radius + PAD,
            })
        } else {
            shape.as_ball().map(|b| Capsule {
                a: Point::origin(),
                b: Point::origin(),
                radius: b.radius + PAD,
            })
        };
        capsule.filter(|c| {
            c.radius.is_finite()
                && c.a
                    .coords
                    .iter()
                    .chain(c.b.coords.iter())
                    .all(|v| v.is_finite())
        })
    }

    /// The least-volume capsule of the candidates (see [the module](self) documentation)
    /// containing every point of `points`; `None` for no points.
    pub(crate) fn around(points: &[Point]) -> Option<Capsule> {
        if points.is_empty() {
            return None;
        }
        let n = points.len() as f64;
        let centroid = Point::from(points.iter().map(|p| p.coords).sum::<Vec3>() / n);
        let mut covariance = Matrix3::zeros();
        for p in points {
            let d = p - centroid;
            covariance += d * d.transpose();
        }
        let eigen = SymmetricEigen::new(covariance / n);
        let mut axes: Vec<Vec3> = (0..3)
            .map(|k| eigen.eigenvectors.column(k).into())
            .collect();
        axes.extend([Vec3::x(), Vec3::y(), Vec3::z()]);
        axes.into_iter()
            .filter_map(|axis| axis.try_normalize(1e-12))
            .filter_map(|axis| fit_along(points, centroid, axis))
            .min_by(|x, y| volume(x).total_cmp(&volume(y)))
    }

    /// The segment's ends where `pose` puts the shape.
    #[inline]
    pub(crate) fn placed(&self, pose: &Iso) -> (Point, Point) {
        (pose * self.a, pose * self.b)
    }
}

fn volume(c: &Capsule) -> f64 {
    let r = c.radius;
    std::f64::consts::PI * r * r * ((c.b - c.a).norm() + 4.0 / 3.0 * r)
}

/// The capsule along unit `axis` (see [the module](self) documentation).
fn fit_along(points: &[Point], centroid: Point, axis: Vec3) -> Option<Capsule> {
    // Two directions across the axis, for the footprint.
    let v = axis
        .cross(&Vec3::x())
        .try_normalize(1e-6)
        .unwrap_or_else(|| axis.cross(&Vec3::y()).normalize());
    let w = axis.cross(&v);
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in points {
        let d = p - centroid;
        for (k, dir) in [v, w].iter().enumerate() {
            lo[k] = lo[k].min(d.dot(dir));
            hi[k] = hi[k].max(d.dot(dir));
        }
    }
    let origin = centroid + v * (0.5 * (lo[0] + hi[0])) + w * (0.5 * (lo[1] + hi[1]));
    // Along the axis (t) and away from it (rho), per point.
    let across = |p: &Point| {
        let d = p - origin;
        let t = d.dot(&axis);
        (t, (d - axis * t).norm())
    };
    let radius = points.iter().map(|p| across(p).1).fold(0.0, f64::max);
    // Each point is covered by the cap of an end at `e` when `|t - e| <= sqrt(r² - rho²)`:
    // the upper end can come down to `t - sqrt(..)` and the lower one up to `t + sqrt(..)`.
    let (mut top, mut bottom) = (f64::NEG_INFINITY, f64::INFINITY);
    for p in points {
        let (t, rho) = across(p);
        let reach = (radius * radius - rho * rho).max(0.0).sqrt();
        top = top.max(t - reach);
        bottom = bottom.min(t + reach);
    }
    if bottom > top {
        // Every point within the radius of one point of the line: a sphere.
        let mid = 0.5 * (bottom + top);
        (bottom, top) = (mid, mid);
    }
    let (a, b) = (origin + axis * bottom, origin + axis * top);
    let radius = points
        .iter()
        .map(|p| point_segment_distance(p, &a, &b))
        .fold(0.0, f64::max);
    radius.is_finite().then_some(Capsule {
        a,
        b,
        radius: radius + PAD,
    })
}

/// The distance from `p` to the segment `a`–`b`.
pub(crate) fn point_segment_distance(p: &Point, a: &Point, b: &Point) -> f64 {
    let ab = b - a;
    let len2 = ab.norm_squared();
    let t = if len2 > 0.0 {
        ((p - a).dot(&ab) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p - (a + ab * t)).norm()
}

/// The distance between segments `a0`–`a1` and `b0`–`b1` (parry's closest points).
pub(crate) fn segment_segment_distance(a: (Point, Point), b: (Point, Point)) -> f64 {
    let (la, lb) = query::details::closest_points_segment_segment_with_locations_nD(
        (&a.0, &a.1),
        (&b.0, &b.1),
    );
    let at = |(p, q): (Point, Point), l: SegmentPointLocation| match l {
        SegmentPointLocation::OnVertex(0) => p,
        SegmentPointLocation::OnVertex(_) => q,
        SegmentPointLocation::OnEdge([wp, wq]) => Point::from(p.coords * wp + q.coords * wq),
    };
    (at(a, la) - at(b, lb)).norm()
}

/// The distance between the segment `p0`–`p1` and the box of half extents `half` centred
/// at the origin, axis-aligned (the segment given in the box's frame); exact.
///
/// The squared distance from the point `p0 + t (p1 - p0)` to the box is
/// `sum_k max(0, |x_k(t)| - half_k)²`, convex in `t` and quadratic between the parameters
/// where a coordinate crosses a face's plane (at most six). So its minimum over `[0, 1]`
/// is the least of the minima of those quadratics over their intervals, each in closed
/// form.
pub(crate) fn segment_box_distance(p0: &Point, p1: &Point, half: &Vec3) -> f64 {
    let d = p1 - p0;
    let squared = |t: f64| {
        (0..3)
            .map(|k| {
                let out = (p0[k] + t * d[k]).abs() - half[k];
                if out > 0.0 {
                    out * out
                } else {
                    0.0
                }
            })
            .sum::<f64>()
    };
    let mut cuts = [0.0f64; 8];
    let mut n = 0;
    cuts[n] = 0.0;
    n += 1;
    for k in 0..3 {
        if d[k] != 0.0 {
            for plane in [-half[k], half[k]] {
                let t = (plane - p0[k]) / d[k];
                if t > 0.0 && t < 1.0 {
                    cuts[n] = t;
                    n += 1;
                }
            }
        }
    }
    cuts[n] = 1.0;
    n += 1;
    let cuts = &mut cuts[..n];
    cuts.sort_unstable_by(f64::total_cmp);
    let mut best = squared(0.0).min(squared(1.0));
    for pair in cuts.windows(2) {
        let (ta, tb) = (pair[0], pair[1]);
        if tb <= ta {
            continue;
        }
        // Which faces the point is outside of, throughout the interval.
        let tm = 0.5 * (ta + tb);
        let (mut num, mut den) = (0.0, 0.0);
        for k in 0..3 {
            let x = p0[k] + tm * d[k];
            let plane = if x > half[k] {
                half[k]
            } else if x < -half[k] {
                -half[k]
            } else {
                continue;
            };
            num += (p0[k] - plane) * d[k];
            den += d[k] * d[k];
        }
        let t = if den > 0.0 {
            (-num / den).clamp(ta, tb)
        } else {
            ta
        };
        best = best.min(squared(t));
    }
    best.sqrt()
}

/// A lower bound on the distance between two placed shapes from their capsules (`None`
/// when either has none): between the segments less both radii, or, when one shape is a
/// box (`half` extents, at `pose`), between the other's segment and the box less its
/// radius. Negative when the capsules overlap.
pub(crate) fn capsule_bound(
    (ci, pi, box_i): (&Capsule, &Iso, Option<&Vec3>),
    (cj, pj, box_j): (&Capsule, &Iso, Option<&Vec3>),
) -> f64 {
    let segment_box = |c: &Capsule, pose: &Iso, box_pose: &Iso, half: &Vec3| {
        // The segment in the box's frame.
        let to_box = box_pose.inv_mul(pose);
        segment_box_distance(&(to_box * c.a), &(to_box * c.b), half) - c.radius
    };
    match (box_i, box_j) {
        (_, Some(half)) => segment_box(ci, pi, pj, half),
        (Some(half), None) => segment_box(cj, pj, pi, half),
        (None, None) => {
            segment_segment_distance(ci.placed(pi), cj.placed(pj)) - ci.radius - cj.radius
        }
    }
}

#[cfg(test)]
mod tests;
