//! The grid of a region and the largest box of columns that count.

use super::{MAX_BOXES_PER_REGION, MAX_POINTS_PER_AXIS, MIN_STEPS};
use crate::math::{Aabb, Point};

/// Points from `lo` to `hi`, both included, evenly spaced at most `spacing` apart (and
/// at most [`MAX_POINTS_PER_AXIS`] of them; two at least).
pub(super) fn points(lo: f64, hi: f64, spacing: f64) -> Vec<f64> {
    let length = (hi - lo).max(0.0);
    let steps = if spacing > 0.0 && spacing.is_finite() {
        (length / spacing).ceil() as usize
    } else {
        1
    };
    let steps = steps.clamp(1, MAX_POINTS_PER_AXIS - 1);
    (0..=steps)
        .map(|i| lo + length * i as f64 / steps as f64)
        .collect()
}

/// Boxes covering the columns that count: the largest (see [`largest`]), then the
/// largest of what it leaves, and so on, up to [`MAX_BOXES_PER_REGION`], keeping each
/// next box only while it is [`MIN_STEPS`] grid steps wide at least along x and y.
/// Boxes may share faces, never volume.
pub(super) fn cover(
    xs: &[f64],
    ys: &[f64],
    zs: &[f64],
    spans: &[Option<(usize, usize)>],
) -> Vec<Aabb> {
    let cells = xs.len().saturating_sub(1) * ys.len().saturating_sub(1);
    let mut taken = vec![false; cells];
    let mut found: Vec<Aabb> = Vec::new();
    while found.len() < MAX_BOXES_PER_REGION {
        let Some(Found {
            aabb: b,
            cells_x: (i0, i1),
            cells_y: (j0, j1),
        }) = largest(xs, ys, zs, spans, &taken)
        else {
            break;
        };
        // A later box must be worth a workspace: no sliver narrower than MIN_STEPS.
        if !found.is_empty() && (i1 - i0).min(j1 - j0) < MIN_STEPS {
            break;
        }
        for j in j0..j1 {
            for i in i0..i1 {
                taken[i + j * (xs.len() - 1)] = true;
            }
        }
        found.push(b);
    }
    found
}

/// A box of grid cells: its corners, and its cells' ranges along x and y (first, one past
/// the last).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Found {
    aabb: Aabb,
    cells_x: (usize, usize),
    cells_y: (usize, usize),
}

/// The largest box by volume, from `zs[0]` up to some `zs[t]`, over grid cells none of
/// which is `taken` and whose corner columns all count at `t`: column
/// `spans[i + j * xs.len()]` is `None` when it does not count at all, and
/// `Some((lo, hi))` when it counts for a box whose top is at `zs[lo]` to `zs[hi]` (every
/// grasp has held by `lo`; some grasp holds at every height up to `hi`). Ties go to the
/// first found (lowest top, then lowest y, then lowest x), so the answer is the same on
/// every run.
fn largest(
    xs: &[f64],
    ys: &[f64],
    zs: &[f64],
    spans: &[Option<(usize, usize)>],
    taken: &[bool],
) -> Option<Found> {
    let (nx, ny) = (xs.len(), ys.len());
    if spans.len() != nx * ny || nx < 2 || ny < 2 || zs.len() < 2 {
        return None;
    }
    let (cx, cy) = (nx - 1, ny - 1);
    let mut best: Option<(f64, Found)> = None;
    let mut strip = vec![false; cx];
    for t in 1..zs.len() {
        let height = zs[t] - zs[0];
        let counts =
            |i: usize, j: usize| spans[i + j * nx].is_some_and(|(lo, hi)| lo <= t && t <= hi);
        let good = |i: usize, j: usize| {
            !taken[i + j * cx]
                && counts(i, j)
                && counts(i + 1, j)
                && counts(i, j + 1)
                && counts(i + 1, j + 1)
        };
        for j0 in 0..cy {
            strip.fill(true);
            for j1 in j0..cy {
                for (i, s) in strip.iter_mut().enumerate() {
                    *s &= good(i, j1);
                }
                let width = ys[j1 + 1] - ys[j0];
                // Each longest run of good cells in every row j0..=j1.
                let mut run_start = None;
                for i in 0..=cx {
                    match (i < cx && strip[i], run_start) {
                        (true, None) => run_start = Some(i),
                        (false, Some(i0)) => {
                            run_start = None;
                            let volume = (xs[i] - xs[i0]) * width * height;
                            if best.is_none_or(|(v, _)| volume > v) {
                                let b = Aabb::new(
                                    Point::new(xs[i0], ys[j0], zs[0]),
                                    Point::new(xs[i], ys[j1 + 1], zs[t]),
                                );
                                let found = Found {
                                    aabb: b,
                                    cells_x: (i0, i),
                                    cells_y: (j0, j1 + 1),
                                };
                                best = Some((volume, found));
                            }
                        }
                        _ => {}
                    }
                }
            }
        }
    }
    best.map(|(_, found)| found)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn points_cover_both_ends_at_most_a_spacing_apart() {
        let p = points(0.0, 1.0, 0.3);
        assert_eq!(p.len(), 5);
        assert_eq!((p[0], p[4]), (0.0, 1.0));
        assert!(p.windows(2).all(|w| w[1] - w[0] <= 0.3 + 1e-12));
        assert_eq!(points(0.0, 100.0, 0.05).len(), MAX_POINTS_PER_AXIS);
        assert_eq!(points(2.0, 2.0, 0.05).len(), 2);
    }

    #[test]
    fn the_largest_box_of_counting_columns_wins_then_the_largest_of_the_rest() {
        let xs = [0.0, 1.0, 2.0, 3.0];
        let ys = [0.0, 1.0, 2.0];
        let zs = [0.0, 0.5, 1.0];
        // Row by row (y = 0, 1, 2), x = 0..3: a tall 2 x 2 block at x 0..1, y 0..1 and a
        // low 4 x 3 block under it.
        let (tall, low) = (Some((1, 2)), Some((1, 1)));
        #[rustfmt::skip]
        let spans = [
            tall, tall, low, low,
            tall, tall, low, low,
            low, low, low, low,
        ];
        let none = [false; 6];
        // Tall: 1 x 1 x 1 = 1; low: 3 x 2 x 0.5 = 3.
        let b = largest(&xs, &ys, &zs, &spans, &none).expect("a box").aabb;
        assert_eq!(
            (b.mins, b.maxs),
            (Point::new(0.0, 0.0, 0.0), Point::new(3.0, 2.0, 0.5))
        );
        // A column that does not count splits the block.
        let mut holed = spans;
        holed[1 + 4] = None;
        let b = largest(&xs, &ys, &zs, &holed, &none).expect("a box").aabb;
        assert_eq!(
            (b.mins, b.maxs),
            (Point::new(2.0, 0.0, 0.0), Point::new(3.0, 2.0, 0.5))
        );
        // Nothing else is left whole: every other cell has the hole at a corner.
        let boxes = cover(&xs, &ys, &zs, &holed);
        assert_eq!(boxes.len(), 1, "{boxes:?}");
        assert_eq!(largest(&xs, &ys, &zs, &[None; 12], &none), None);
        // A column whose grasps have not all held by a height does not count below it.
        let late = [Some((2, 2)); 12];
        let b = largest(&xs, &ys, &zs, &late, &none).expect("a box").aabb;
        assert_eq!(b.maxs.z, 1.0);
    }

    #[test]
    fn an_l_shaped_reach_is_two_boxes_sharing_a_face_and_slivers_are_left_out() {
        // Two steps make the narrowest box kept after the first.
        let h = 0.05;
        let xs = [0.0, h, 2.0 * h, 3.0 * h, 4.0 * h];
        let ys = xs;
        let zs = [0.0, 1.0];
        let (o, c) = (None, Some((1, 1)));
        // An L: y 0..2 steps along all of x, and x 0..2 steps up to y 4 steps.
        #[rustfmt::skip]
        let spans = [
            c, c, c, c, c,
            c, c, c, c, c,
            c, c, c, c, c,
            c, c, c, o, o,
            c, c, c, o, o,
        ];
        let boxes = cover(&xs, &ys, &zs, &spans);
        let corners: Vec<_> = boxes.iter().map(|b| (b.mins, b.maxs)).collect();
        assert_eq!(
            corners,
            [
                (Point::new(0.0, 0.0, 0.0), Point::new(4.0 * h, 2.0 * h, 1.0)),
                (
                    Point::new(0.0, 2.0 * h, 0.0),
                    Point::new(2.0 * h, 4.0 * h, 1.0)
                ),
            ]
        );
        // One step narrower, the L's upright is a sliver.
        let mut thin = spans;
        for j in 3..5 {
            thin[2 + j * 5] = None;
        }
        assert_eq!(cover(&xs, &ys, &zs, &thin).len(), 1);
    }
}
