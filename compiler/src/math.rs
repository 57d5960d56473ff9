//! Geometry aliases and the axis-aligned box type.

use nalgebra as na;

/// A rigid transform (rotation + translation), in metres.
pub type Pose = na::Isometry3<f64>;
/// A point or vector in metres.
pub type Vector = na::Vector3<f64>;
/// A unit quaternion.
pub type Rotation = na::UnitQuaternion<f64>;

/// An axis-aligned box, in metres, in the cell frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// Smallest corner.
    pub min: [f64; 3],
    /// Largest corner.
    pub max: [f64; 3],
}

impl Aabb {
    /// From centre and edge lengths.
    pub fn from_center_size(center: [f64; 3], size: [f64; 3]) -> Aabb {
        Aabb {
            min: [0, 1, 2].map(|i| center[i] - size[i] / 2.0),
            max: [0, 1, 2].map(|i| center[i] + size[i] / 2.0),
        }
    }

    /// Centre point.
    pub fn center(&self) -> [f64; 3] {
        [0, 1, 2].map(|i| (self.min[i] + self.max[i]) / 2.0)
    }

    /// Edge lengths.
    pub fn size(&self) -> [f64; 3] {
        [0, 1, 2].map(|i| self.max[i] - self.min[i])
    }

    /// Volume in cubic metres.
    pub fn volume(&self) -> f64 {
        self.size().iter().product()
    }

    /// The overlap of two boxes, if it has positive volume (beyond `EPS` per axis, so
    /// boxes that only touch do not overlap).
    pub fn intersection(&self, other: &Aabb) -> Option<Aabb> {
        let min = [0, 1, 2].map(|i| self.min[i].max(other.min[i]));
        let max = [0, 1, 2].map(|i| self.max[i].min(other.max[i]));
        (0..3)
            .all(|i| max[i] - min[i] > EPS)
            .then_some(Aabb { min, max })
    }

    /// True when `point` is inside or on the boundary (within `EPS`).
    pub fn contains_point(&self, point: [f64; 3]) -> bool {
        (0..3).all(|i| point[i] >= self.min[i] - EPS && point[i] <= self.max[i] + EPS)
    }

    /// True when `other` lies inside this box (within `EPS`).
    pub fn contains(&self, other: &Aabb) -> bool {
        (0..3).all(|i| other.min[i] >= self.min[i] - EPS && other.max[i] <= self.max[i] + EPS)
    }
}

/// Geometric tolerance for box comparisons: 1 µm.
pub const EPS: f64 = 1e-6;

/// True when `target` is covered by the union of `boxes`. Exact: the target is cut along
/// every box face that crosses it, and each resulting cell must lie in some box.
pub fn covered_by_union(target: &Aabb, boxes: &[Aabb]) -> bool {
    let relevant: Vec<&Aabb> = boxes
        .iter()
        .filter(|b| b.intersection(target).is_some())
        .collect();
    if relevant.iter().any(|b| b.contains(target)) {
        return true;
    }
    let cuts: [Vec<f64>; 3] = [0, 1, 2].map(|axis| {
        let mut cuts = vec![target.min[axis], target.max[axis]];
        for b in &relevant {
            for v in [b.min[axis], b.max[axis]] {
                if v > target.min[axis] + EPS && v < target.max[axis] - EPS {
                    cuts.push(v);
                }
            }
        }
        cuts.sort_by(f64::total_cmp);
        cuts.dedup_by(|a, b| (*a - *b).abs() <= EPS);
        cuts
    });
    for x in cuts[0].windows(2) {
        for y in cuts[1].windows(2) {
            for z in cuts[2].windows(2) {
                let center = [
                    (x[0] + x[1]) / 2.0,
                    (y[0] + y[1]) / 2.0,
                    (z[0] + z[1]) / 2.0,
                ];
                if !relevant.iter().any(|b| b.contains_point(center)) {
                    return false;
                }
            }
        }
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn union_cover_is_exact() {
        let target = Aabb::from_center_size([0.0, 0.0, 0.0], [2.0, 1.0, 1.0]);
        let left = Aabb::from_center_size([-0.5, 0.0, 0.0], [1.0, 1.0, 1.0]);
        let right = Aabb::from_center_size([0.5, 0.0, 0.0], [1.0, 1.0, 1.0]);
        assert!(covered_by_union(&target, &[left, right]));
        assert!(!covered_by_union(&target, &[left]));
        let short_right = Aabb::from_center_size([0.5, 0.0, 0.0], [0.9, 1.0, 1.0]);
        assert!(!covered_by_union(&target, &[left, short_right]));
    }
}
