//! Support points of a convex hull by hill climbing over its edges.
//!
//! GJK, behind every exact test and distance of the collision world, asks each shape for
//! its support point (the point farthest along a direction) a dozen times or more per
//! query. parry's `ConvexPolyhedron` answers by visiting every vertex; a Panda link's
//! hull has 100 to 150, and those visits were a third of the time of a motion in the
//! cage of `cells/panda_cage.cell`. On a convex polytope a linear function has no local
//! maximum over the vertices that is not a global one (the simplex method's argument),
//! so walking from a vertex to any neighbour that lies farther along the direction, until
//! none does, ends at a support point after visiting a few vertices and their
//! neighbours. The point is a vertex of the hull, as parry's is, so every answer built
//! on it (intersections, distances, the clearance certificates) is as exact as before;
//! only ties between equally far vertices may be broken differently.

use parry3d_f64::shape::{ConvexPolyhedron, SupportMap};

use crate::math::{Point, Vec3};

/// A convex hull's vertices and their neighbours along its edges, for
/// [`SupportMap::local_support_point`] by hill climbing.
#[derive(Clone, Debug)]
pub(crate) struct HullSupport {
    points: Vec<Point>,
    /// Neighbours of vertex `v`: `neighbours[offsets[v]..offsets[v + 1]]`.
    offsets: Vec<u32>,
    neighbours: Vec<u32>,
    /// Where climbs start: the vertices farthest along +x, -x, +y, -y, +z and -z, so a
    /// climb begins near the answer and takes a few steps.
    starts: [u32; 6],
}

impl HullSupport {
    /// The hull's vertex graph; `None` for a hull without vertices or with an edge that
    /// names a vertex it does not have (then parry's own support point is used).
    pub(crate) fn new(hull: &ConvexPolyhedron) -> Option<HullSupport> {
        let points = hull.points().to_vec();
        let n = points.len();
        if n == 0 {
            return None;
        }
        let mut degree = vec![0u32; n + 1];
        for e in hull.edges() {
            let [a, b] = [e.vertices.x as usize, e.vertices.y as usize];
            if a >= n || b >= n {
                return None;
            }
            degree[a + 1] += 1;
            degree[b + 1] += 1;
        }
        let mut offsets = degree;
        for v in 0..n {
            offsets[v + 1] += offsets[v];
        }
        let mut fill = offsets.clone();
        let mut neighbours = vec![0u32; offsets[n] as usize];
        for e in hull.edges() {
            let (a, b) = (e.vertices.x, e.vertices.y);
            neighbours[fill[a as usize] as usize] = b;
            fill[a as usize] += 1;
            neighbours[fill[b as usize] as usize] = a;
            fill[b as usize] += 1;
        }
        let mut starts = [0u32; 6];
        for (k, start) in starts.iter_mut().enumerate() {
            let (axis, sign) = (k / 2, if k % 2 == 0 { 1.0 } else { -1.0 });
            let best = (0..n)
                .max_by(|&i, &j| (sign * points[i][axis]).total_cmp(&(sign * points[j][axis])))
                .unwrap_or(0);
            *start = best as u32;
        }
        Some(HullSupport {
            points,
            offsets,
            neighbours,
            starts,
        })
    }

    /// The index of a vertex farthest along `dir`.
    fn climb(&self, dir: &Vec3) -> usize {
        let mut best = self.starts[0] as usize;
        let mut best_dot = self.points[best].coords.dot(dir);
        for &s in &self.starts[1..] {
            let d = self.points[s as usize].coords.dot(dir);
            if d > best_dot {
                best = s as usize;
                best_dot = d;
            }
        }
        // Every move goes strictly farther, so no vertex is visited twice; the bound only
        // guards against a direction that is not a number.
        for _ in 0..self.points.len() {
            let mut moved = false;
            let (from, to) = (self.offsets[best], self.offsets[best + 1]);
            for &v in &self.neighbours[from as usize..to as usize] {
                let d = self.points[v as usize].coords.dot(dir);
                if d > best_dot {
                    best = v as usize;
                    best_dot = d;
                    moved = true;
                }
            }
            if !moved {
                break;
            }
        }
        best
    }
}

impl SupportMap for HullSupport {
    fn local_support_point(&self, dir: &Vec3) -> Point {
        self.points[self.climb(dir)]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use parry3d_f64::utils::point_cloud_support_point;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// On random hulls and directions, the climb reaches a point exactly as far along the
    /// direction as the farthest vertex.
    #[test]
    fn the_climb_finds_the_farthest_vertex() {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        for _ in 0..50 {
            let cloud: Vec<Point> = (0..200)
                .map(|_| {
                    Point::new(
                        rng.random_range(-1.0..1.0),
                        rng.random_range(-0.3..0.3),
                        rng.random_range(-2.0..2.0),
                    )
                })
                .collect();
            let hull = ConvexPolyhedron::from_convex_hull(&cloud).expect("a hull");
            let climb = HullSupport::new(&hull).expect("a vertex graph");
            for _ in 0..200 {
                let dir = Vec3::new(
                    rng.random_range(-1.0..1.0),
                    rng.random_range(-1.0..1.0),
                    rng.random_range(-1.0..1.0),
                );
                let ours = climb.local_support_point(&dir).coords.dot(&dir);
                let all = point_cloud_support_point(&dir, hull.points())
                    .coords
                    .dot(&dir);
                assert_eq!(ours, all, "{dir:?}");
            }
        }
    }
}
