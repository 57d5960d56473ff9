//! Geometry: the types and box comparisons shared with the runtime (defined once, in
//! [`cellc_schema::math`]), and the exact box-union cover test that reach needs.

pub use cellc_schema::math::*;

/// True when `target` is covered by the union of `boxes`. Exact: the target is cut along
/// every box face that crosses it, and each resulting cell must lie in some box.
pub fn covered_by_union(target: &Aabb, boxes: &[Aabb]) -> bool {
    let relevant: Vec<&Aabb> = boxes
        .iter()
        .filter(|b| overlap(b, target).is_some())
        .collect();
    if relevant.iter().any(|b| contains_box(b, target)) {
        return true;
    }
    let cuts: [Vec<f64>; 3] = [0, 1, 2].map(|axis| {
        let mut cuts = vec![target.mins[axis], target.maxs[axis]];
        for b in &relevant {
            for v in [b.mins[axis], b.maxs[axis]] {
                if v > target.mins[axis] + EPS && v < target.maxs[axis] - EPS {
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
                let center = Point::new(
                    (x[0] + x[1]) / 2.0,
                    (y[0] + y[1]) / 2.0,
                    (z[0] + z[1]) / 2.0,
                );
                if !relevant.iter().any(|b| contains_point(b, &center)) {
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
        let target = aabb_from_center_size([0.0, 0.0, 0.0], [2.0, 1.0, 1.0]);
        let left = aabb_from_center_size([-0.5, 0.0, 0.0], [1.0, 1.0, 1.0]);
        let right = aabb_from_center_size([0.5, 0.0, 0.0], [1.0, 1.0, 1.0]);
        assert!(covered_by_union(&target, &[left, right]));
        assert!(!covered_by_union(&target, &[left]));
        let short_right = aabb_from_center_size([0.5, 0.0, 0.0], [0.9, 1.0, 1.0]);
        assert!(!covered_by_union(&target, &[left, short_right]));
    }
}
