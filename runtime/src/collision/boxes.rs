//! The boxes of the bodies that stand still during a query, indexed for "which of them
//! overlap this box": a flat scan for the few dozen of a typical cell, a hierarchy
//! (parry's [`Bvh`]) for the hundreds of a long line of arms.
//!
//! A query asks once per moving body (a Panda has ten), so the index is on the hot path
//! of every check. Walking a hierarchy costs a stack, a test per node and an indirect
//! call per leaf; over the 26 boxes of the cage cell (14 cubes, the floor, the pad, the
//! arm's own resting links) comparing every box, six numbers each in arrays of their
//! own, costs less (the profile of `cage_motions` had 13% in the hierarchy's traversal,
//! and about half of that in the scan). Past [`FLAT_MAX`] boxes the scan's linear cost loses
//! to the hierarchy's logarithmic one, so larger sets keep it. Both answer the same set,
//! each in its own fixed order; every caller either stops at the first pair that
//! intersects (a yes or no that does not depend on the order) or sorts what it gathers.

use parry3d_f64::bounding_volume::Aabb;
use parry3d_f64::partitioning::{Bvh, BvhBuildStrategy};

use super::world::Visit;

/// The most boxes scanned flat; more go into a hierarchy. The shipped cells' homes have
/// 16 to 26 boxes (the cage's plans 5 to 10% faster flat than with the hierarchy; the
/// others within noise); a generated line of arms has hundreds to thousands.
const FLAT_MAX: usize = 64;

/// Boxes numbered from 0 in the order given (see [the module](self) documentation).
#[derive(Clone, Debug)]
pub(super) enum BoxIndex {
    /// Lower corners and upper corners, one array per axis.
    Flat {
        lo: [Vec<f64>; 3],
        hi: [Vec<f64>; 3],
    },
    /// Leaf data is the box's number.
    Tree(Bvh),
}

impl BoxIndex {
    /// The index of `boxes`, numbered in order.
    pub(super) fn new(boxes: Vec<Aabb>) -> BoxIndex {
        if boxes.len() > FLAT_MAX {
            return BoxIndex::Tree(Bvh::from_iter(
                BvhBuildStrategy::Binned,
                boxes.into_iter().enumerate(),
            ));
        }
        let axis = |f: fn(&Aabb, usize) -> f64, k: usize| boxes.iter().map(|b| f(b, k)).collect();
        let (lo, hi) = (|b: &Aabb, k| b.mins[k], |b: &Aabb, k| b.maxs[k]);
        BoxIndex::Flat {
            lo: [axis(lo, 0), axis(lo, 1), axis(lo, 2)],
            hi: [axis(hi, 0), axis(hi, 1), axis(hi, 2)],
        }
    }

    /// Calls `visit` with the number of every box that overlaps `query` (touching
    /// counts), until it says stop (then [`Visit::Stop`]) or fails.
    #[inline]
    pub(super) fn overlapping<E>(
        &self,
        query: &Aabb,
        mut visit: impl FnMut(u32) -> Result<Visit, E>,
    ) -> Result<Visit, E> {
        match self {
            BoxIndex::Flat { lo, hi } => {
                let (qlo, qhi) = (query.mins, query.maxs);
                for k in 0..lo[0].len() {
                    // `&`, not `&&`: six comparisons without a branch between them.
                    let hit = (lo[0][k] <= qhi.x)
                        & (hi[0][k] >= qlo.x)
                        & (lo[1][k] <= qhi.y)
                        & (hi[1][k] >= qlo.y)
                        & (lo[2][k] <= qhi.z)
                        & (hi[2][k] >= qlo.z);
                    if hit {
                        if let Visit::Stop = visit(k as u32)? {
                            return Ok(Visit::Stop);
                        }
                    }
                }
            }
            BoxIndex::Tree(bvh) => {
                for leaf in bvh.intersect_aabb(query) {
                    if let Visit::Stop = visit(leaf)? {
                        return Ok(Visit::Stop);
                    }
                }
            }
        }
        Ok(Visit::Continue)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Point;
    use parry3d_f64::bounding_volume::BoundingVolume;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    fn random_box(rng: &mut ChaCha8Rng, size: f64) -> Aabb {
        let c = Point::new(
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
        );
        let h = Point::new(
            rng.random_range(0.0..size),
            rng.random_range(0.0..size),
            rng.random_range(0.0..size),
        )
        .coords;
        Aabb::new(c - h, c + h)
    }

    /// Both forms answer exactly the boxes that overlap the query, on sets either side
    /// of the threshold, and stop when told to.
    #[test]
    fn flat_and_tree_answer_the_overlapping_boxes() {
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        for n in [1, 7, 30, FLAT_MAX, FLAT_MAX + 1, 600] {
            let boxes: Vec<Aabb> = (0..n).map(|_| random_box(&mut rng, 0.2)).collect();
            let index = BoxIndex::new(boxes.clone());
            assert_eq!(matches!(index, BoxIndex::Flat { .. }), n <= FLAT_MAX);
            let mut found_some = 0;
            for _ in 0..200 {
                let query = random_box(&mut rng, 0.3);
                let mut found = Vec::new();
                let all = index.overlapping(&query, |k| {
                    found.push(k);
                    Ok::<_, ()>(Visit::Continue)
                });
                assert!(matches!(all, Ok(Visit::Continue)));
                found.sort_unstable();
                let expected: Vec<u32> = (0..n as u32)
                    .filter(|&k| boxes[k as usize].intersects(&query))
                    .collect();
                assert_eq!(found, expected, "{n} boxes");
                found_some += usize::from(!expected.is_empty());
                let mut calls = 0;
                let first = index.overlapping(&query, |_| {
                    calls += 1;
                    Ok::<_, ()>(Visit::Stop)
                });
                let stopped = matches!(first, Ok(Visit::Stop));
                assert_eq!(stopped, !expected.is_empty());
                assert_eq!(calls, usize::from(!expected.is_empty()));
            }
            // Not vacuous: queries do hit (most of them, past a few boxes).
            let least = if n < 30 { 1 } else { 40 };
            assert!(found_some >= least, "{n} boxes: {found_some} queries hit");
        }
    }
}
