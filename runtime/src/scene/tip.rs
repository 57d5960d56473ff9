//! Where a hand must be to hold an object at a pose is known before any inverse
//! kinematics (the object's pose times the inverse grasp), and so is whether that hand
//! sinks into a table or an obstacle. Verification and the planner's screens ask this
//! first: a pose refused here costs one shape test instead of every IK restart.

use cellc_schema::EndEffectorId;

use super::Scene;
use crate::collision::Collision;
use crate::math::Iso;

/// Overlap (metres) of a body on an arm's tip with a fixed body from which a tip pose is
/// refused before IK: ten times the IK's position tolerance, so a pose the solver would
/// move out of contact by its tolerance is left to the full check.
pub const TIP_OVERLAP: f64 = 1e-3;

impl Scene {
    /// A fixed body that the hand (or a link of the tip frame) of arm `e` overlaps by more
    /// than `TIP_OVERLAP` (1 mm) with its tip at `tip`, whatever the arm's joints: such a pose
    /// is never free. `None` for a holder that is not an arm.
    pub fn tip_hits_fixed(&self, e: EndEffectorId, tip: &Iso) -> Option<Collision> {
        let robot = self.world_robot(e)?;
        let super::Holder::Arm { robot: model, .. } = self.holders.get(e.index())? else {
            return None;
        };
        let tip_frame = tip * self.robots.get(*model)?.tip_offset().inverse();
        self.world
            .tip_frame_hits_fixed(robot, &tip_frame, TIP_OVERLAP)
    }
}
