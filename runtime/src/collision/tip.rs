//! The bodies fixed to an arm's tip (its hand's solids and the links of the tip frame)
//! against the fixed bodies, for a tip pose alone. Where a hand must be to hold an object
//! is known before any inverse kinematics (the object's pose times the grasp), and so is
//! whether that hand sinks into the table: verification asks this first and spends no IK
//! restart on a pose that cannot be free whatever the arm's joints are.

use parry3d_f64::query;

use super::build::Mount;
use super::{Collision, CollisionWorld};
use crate::math::Iso;

impl CollisionWorld {
    /// A fixed body that a body of robot `robot`'s tip frame overlaps by more than
    /// `depth` metres when that frame (the robot's last frame, before its tip offset) is at
    /// `tip_frame`, if any. Pairs the cell allows are skipped, and a pair parry cannot
    /// measure counts as apart: this answers "surely colliding", never "surely free".
    pub fn tip_frame_hits_fixed(
        &self,
        robot: usize,
        tip_frame: &Iso,
        depth: f64,
    ) -> Option<Collision> {
        let tip = self.robots.get(robot)?.frames.checked_sub(1)?;
        for (i, body) in self.bodies.iter().enumerate() {
            if !matches!(body.mount, Mount::Frame { robot: r, frame } if r == robot && frame == tip)
            {
                continue;
            }
            let pose = tip_frame * body.local;
            let aabb = body.shape.compute_aabb(&pose);
            for &f in &self.fixed {
                let fixed = &self.bodies[f];
                if self.allowed.get(i, f) {
                    continue;
                }
                if let Some(fixed_aabb) = &fixed.fixed_aabb {
                    if !parry3d_f64::bounding_volume::BoundingVolume::intersects(&aabb, fixed_aabb)
                    {
                        continue;
                    }
                }
                if let Ok(Some(contact)) = query::contact(
                    &pose,
                    body.shape.as_ref(),
                    &fixed.local,
                    fixed.shape.as_ref(),
                    0.0,
                ) {
                    if contact.dist < -depth {
                        return Some(self.collision(i, f));
                    }
                }
            }
        }
        None
    }
}
