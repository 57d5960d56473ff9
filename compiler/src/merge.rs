//! Merging the grid cells of a derived workspace into few boxes, in time `n log n`.
//!
//! The rule (kept from the first implementation, whose results artifacts record): take
//! the first pair of boxes, in index order, that share a whole face; replace the first by
//! their union and remove the second by swapping the last box into its place; repeat until
//! no two boxes share a face; sort. Found by scanning all pairs that costs `n²` per merge,
//! `n³` in all, and a cell of forty reach boxes took minutes.
//!
//! Here the same pairs are found through their faces. The boxes tile space without
//! overlapping and their coordinates come from one list of cut planes (distinct planes are
//! more than [`crate::math::EPS`] apart), so two boxes share a face exactly when the face's
//! plane and its four other coordinates are bit-for-bit equal, and each face belongs to
//! one box. A face index finds a box's partners (at most two per axis), and an ordered set
//! of the mergeable pairs gives the first one; each merge updates the few boxes it touches.

use std::collections::{BTreeSet, HashMap};

use crate::math::Aabb;

/// A face of a box: the axis across it, the side (`false` low, `true` high), its plane
/// and the box's extents on the other two axes, as bits.
type Face = (usize, bool, [u64; 5]);

fn bits(v: f64) -> u64 {
    // `+ 0.0` makes -0 and +0 one plane.
    (v + 0.0).to_bits()
}

fn face(b: &Aabb, axis: usize, high: bool) -> Face {
    let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
    let (u, v) = (u.min(v), u.max(v));
    let plane = if high { b.maxs[axis] } else { b.mins[axis] };
    (
        axis,
        high,
        [
            bits(plane),
            bits(b.mins[u]),
            bits(b.maxs[u]),
            bits(b.mins[v]),
            bits(b.maxs[v]),
        ],
    )
}

/// The face a partner across `f` has: the same plane and extents, the other side.
fn across(f: Face) -> Face {
    (f.0, !f.1, f.2)
}

struct Merger {
    boxes: Vec<Aabb>,
    /// Each face -> the box that has it.
    faces: HashMap<Face, usize>,
    /// Every pair `(i, j)`, `i < j`, of boxes that share a face.
    pairs: BTreeSet<(usize, usize)>,
}

impl Merger {
    fn faces_of(b: &Aabb) -> impl Iterator<Item = Face> + '_ {
        (0..3).flat_map(move |axis| [face(b, axis, false), face(b, axis, true)])
    }

    /// The boxes sharing a face with box `i`.
    fn partners(&self, i: usize) -> Vec<usize> {
        Merger::faces_of(&self.boxes[i])
            .filter_map(|f| self.faces.get(&across(f)).copied())
            .filter(|&j| j != i)
            .collect()
    }

    fn add(&mut self, i: usize) {
        for f in Merger::faces_of(&self.boxes[i]) {
            self.faces.insert(f, i);
        }
        for j in self.partners(i) {
            self.pairs.insert((i.min(j), i.max(j)));
        }
    }

    fn remove(&mut self, i: usize) {
        for j in self.partners(i) {
            self.pairs.remove(&(i.min(j), i.max(j)));
        }
        for f in Merger::faces_of(&self.boxes[i]) {
            if self.faces.get(&f) == Some(&i) {
                self.faces.remove(&f);
            }
        }
    }
}

/// Merges boxes that share a whole face until no two do, so that a workspace is
/// described by few boxes; sorted by their lower corners.
pub fn merge_boxes(boxes: Vec<Aabb>) -> Vec<Aabb> {
    let mut m = Merger {
        boxes,
        faces: HashMap::new(),
        pairs: BTreeSet::new(),
    };
    for i in 0..m.boxes.len() {
        for f in Merger::faces_of(&m.boxes[i]) {
            m.faces.insert(f, i);
        }
    }
    for i in 0..m.boxes.len() {
        for j in m.partners(i) {
            m.pairs.insert((i.min(j), i.max(j)));
        }
    }
    while let Some(&(i, j)) = m.pairs.iter().next() {
        let last = m.boxes.len() - 1;
        m.remove(i);
        m.remove(j);
        if last != j {
            m.remove(last);
        }
        let (a, b) = (m.boxes[i], m.boxes[j]);
        let mut union = a;
        union.mins = a.mins.inf(&b.mins);
        union.maxs = a.maxs.sup(&b.maxs);
        m.boxes[i] = union;
        m.boxes.swap_remove(j);
        m.add(i);
        if last != j {
            m.add(j);
        }
    }
    let mut boxes = m.boxes;
    sort_by_mins(&mut boxes);
    boxes
}

/// The order merged boxes are returned in: by smallest corner, x first (total order, so
/// the result does not depend on how the merge went).
fn sort_by_mins(boxes: &mut [Aabb]) {
    boxes.sort_by(|a, b| {
        a.mins
            .iter()
            .zip(b.mins.iter())
            .map(|(x, y)| x.total_cmp(y))
            .find(|o| o.is_ne())
            .unwrap_or(std::cmp::Ordering::Equal)
    });
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{Point, EPS};

    /// The rule as first written: scan all pairs for the first that shares a face.
    fn by_scanning(mut boxes: Vec<Aabb>) -> Vec<Aabb> {
        let same = |a: f64, b: f64| (a - b).abs() <= EPS;
        loop {
            let mut merged = false;
            'search: for i in 0..boxes.len() {
                for j in (i + 1)..boxes.len() {
                    let (a, b) = (boxes[i], boxes[j]);
                    for axis in 0..3 {
                        let others_equal = (0..3)
                            .filter(|&k| k != axis)
                            .all(|k| same(a.mins[k], b.mins[k]) && same(a.maxs[k], b.maxs[k]));
                        if others_equal
                            && (same(a.maxs[axis], b.mins[axis])
                                || same(b.maxs[axis], a.mins[axis]))
                        {
                            let mut union = a;
                            union.mins[axis] = a.mins[axis].min(b.mins[axis]);
                            union.maxs[axis] = a.maxs[axis].max(b.maxs[axis]);
                            boxes[i] = union;
                            boxes.swap_remove(j);
                            merged = true;
                            break 'search;
                        }
                    }
                }
            }
            if !merged {
                break;
            }
        }
        sort_by_mins(&mut boxes);
        boxes
    }

    proptest::proptest! {
        /// Any subset of a grid, in grid order (as derivation makes them): the same boxes
        /// as the scan.
        #[test]
        fn merges_as_the_scan_does(
            cuts in proptest::collection::vec(
                proptest::collection::btree_set(-20i32..20, 2..7), 3..=3),
            keep in proptest::collection::vec(proptest::bool::weighted(0.7), 216),
        ) {
            let cuts: Vec<Vec<f64>> =
                cuts.iter().map(|c| c.iter().map(|&v| f64::from(v) * 0.25).collect()).collect();
            let mut cells = Vec::new();
            let mut k = 0;
            for x in cuts[0].windows(2) {
                for y in cuts[1].windows(2) {
                    for z in cuts[2].windows(2) {
                        if keep[k % keep.len()] {
                            cells.push(Aabb::new(
                                Point::new(x[0], y[0], z[0]),
                                Point::new(x[1], y[1], z[1]),
                            ));
                        }
                        k += 1;
                    }
                }
            }
            proptest::prop_assert_eq!(merge_boxes(cells.clone()), by_scanning(cells));
        }
    }
}
