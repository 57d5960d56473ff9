//! Resting poses of an object on a surface inside a workspace: the one routine both
//! verification (the witness of an arm-and-surface arc) and planning (a put-down that
//! another arm picks up again) draw them from.
//!
//! An object rests on a surface's top face in one of its resting poses (the object's
//! pose in the surface frame: how high its centre is, how it is tilted), anywhere on the
//! face and turned any way about the vertical, as long as its centre lies in the
//! workspace. [`RestRegions`] is the part of the face where that holds (the face cut by
//! each of the workspace's boxes whose height range contains the centre, within
//! [`HEIGHT_SLACK`]), and [`RestRegions::sample`] draws a pose uniformly from it.
//!
//! Before this routine was shared, planning compared heights exactly and picked a box
//! uniformly whatever its size. The shipped cells' named requests never sample a shared
//! put-down (a witnessed pose always serves), so they plan the same either way, and
//! planning now draws as verification does.

use rand::Rng;
use rand_chacha::ChaCha8Rng;

use crate::math::Aabb;
use crate::math::{Iso, Point, Quat, Vec3};

/// How far (metres) the object's centre may lie above or below a workspace box's height
/// range and still count as inside it: the slack of [`contains_point`](crate::math::contains_point), with which a
/// witness is re-checked, so a resting height equal to a box's top or bottom (derived
/// workspaces are cut at surface heights) does not depend on rounding.
pub const HEIGHT_SLACK: f64 = 1e-6;

/// Where on a surface's top face an object resting in a given pose has its centre inside
/// a workspace.
#[derive(Clone, Debug)]
pub struct RestRegions {
    /// Height of the top face.
    top: f64,
    /// The resting pose (object in the surface frame at the face).
    rest: Iso,
    /// Parts of the face (flat boxes at `top`), one per workspace box that meets it, in
    /// the boxes' order.
    regions: Vec<Aabb>,
}

impl RestRegions {
    /// The parts of the top face of `slab` where an object resting as `rest` has its
    /// centre inside one of the `workspace` boxes.
    pub fn new(slab: &Aabb, workspace: &[Aabb], rest: &Iso) -> RestRegions {
        let top = slab.maxs.z;
        let center_z = top + rest.translation.vector.z;
        let regions = workspace
            .iter()
            .filter(|b| b.mins.z <= center_z + HEIGHT_SLACK && b.maxs.z >= center_z - HEIGHT_SLACK)
            .map(|b| Aabb {
                mins: Point::new(b.mins.x.max(slab.mins.x), b.mins.y.max(slab.mins.y), top),
                maxs: Point::new(b.maxs.x.min(slab.maxs.x), b.maxs.y.min(slab.maxs.y), top),
            })
            .filter(|r| r.maxs.x > r.mins.x && r.maxs.y > r.mins.y)
            .collect();
        RestRegions {
            top,
            rest: *rest,
            regions,
        }
    }

    /// True when no resting pose has its centre in the workspace.
    pub fn is_empty(&self) -> bool {
        self.regions.is_empty()
    }

    /// Height of the object's centre when it rests so.
    pub fn center_height(&self) -> f64 {
        self.top + self.rest.translation.vector.z
    }

    /// A resting pose drawn uniformly from the regions (a part chosen by area, a point of
    /// it, a turn about the vertical); `None`, drawing nothing, when they are empty.
    pub fn sample(&self, rng: &mut ChaCha8Rng) -> Option<Iso> {
        let last = self.regions.last()?;
        let area = |r: &Aabb| (r.maxs.x - r.mins.x) * (r.maxs.y - r.mins.y);
        let mut pick = rng.random::<f64>() * self.regions.iter().map(area).sum::<f64>();
        let region = self
            .regions
            .iter()
            .find(|r| {
                pick -= area(r);
                pick <= 0.0
            })
            .unwrap_or(last);
        let x = region.mins.x + rng.random::<f64>() * (region.maxs.x - region.mins.x);
        let y = region.mins.y + rng.random::<f64>() * (region.maxs.y - region.mins.y);
        let yaw = rng.random::<f64>() * std::f64::consts::TAU;
        let frame = Iso::from_parts(
            nalgebra::Translation3::new(x, y, self.top),
            Quat::from_axis_angle(&Vec3::z_axis(), yaw),
        );
        Some(frame * self.rest)
    }
}

#[cfg(test)]
mod tests {
    use rand::SeedableRng;

    use super::*;

    fn aabb(min: [f64; 3], max: [f64; 3]) -> Aabb {
        Aabb {
            mins: Point::from(min),
            maxs: Point::from(max),
        }
    }

    #[test]
    fn poses_rest_on_the_face_with_the_centre_in_the_workspace() {
        let slab = aabb([0.0, 0.0, 0.7], [1.0, 1.0, 0.75]);
        // Two boxes over the table, one too high for the object's centre.
        let workspace = [
            aabb([0.5, 0.5, 0.7], [2.0, 2.0, 1.0]),
            aabb([-1.0, -1.0, 0.76], [0.2, 0.2, 1.0]),
            aabb([0.0, 0.0, 1.0], [1.0, 1.0, 1.5]),
        ];
        let rest = Iso::translation(0.0, 0.0, 0.05);
        let regions = RestRegions::new(&slab, &workspace, &rest);
        assert_eq!(regions.regions.len(), 2);
        assert!((regions.center_height() - 0.8).abs() < 1e-12);
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let mut in_first = 0;
        for _ in 0..400 {
            let pose = regions.sample(&mut rng).expect("a region");
            let centre = Point::from(pose.translation.vector);
            assert!((centre.z - 0.8).abs() < 1e-12);
            assert!(workspace[..2]
                .iter()
                .any(|b| crate::math::contains_point(b, &centre)));
            assert!((0.0..=1.0).contains(&centre.x) && (0.0..=1.0).contains(&centre.y));
            // Upright: only turned about the vertical.
            let up = pose.rotation * Vec3::z();
            assert!((up.z - 1.0).abs() < 1e-12);
            if crate::math::contains_point(&workspace[0], &centre) {
                in_first += 1;
            }
        }
        // By area: the first part (0.25 m²) is 6.25 times the second (0.04 m²).
        assert!((300..400).contains(&in_first), "{in_first} of 400");
    }

    #[test]
    fn a_centre_on_a_box_boundary_is_inside_within_the_slack() {
        let slab = aabb([0.0, 0.0, 0.7], [1.0, 1.0, 0.75]);
        let rest = Iso::translation(0.0, 0.0, 0.05);
        let hair_above = [aabb([0.0, 0.0, 0.8 + 1e-7], [1.0, 1.0, 1.0])];
        assert!(!RestRegions::new(&slab, &hair_above, &rest).is_empty());
        let above = [aabb([0.0, 0.0, 0.8 + 1e-5], [1.0, 1.0, 1.0])];
        let regions = RestRegions::new(&slab, &above, &rest);
        assert!(regions.is_empty());
        assert!(regions.sample(&mut ChaCha8Rng::seed_from_u64(0)).is_none());
    }
}
