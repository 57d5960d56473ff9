//! The object follows the hand: where an object held by an arm is, from the arm's joints
//! and the grasp.
//!
//! An object in a hand has no pose of its own; it is where the arm's tip is, composed
//! with the grasp (the object's pose in the tip's frame, [`Artifact::grasp_pose`]). The
//! simulator (`execute.rs`), the world ([`World::pose`](super::World::pose), a held
//! object placed from a world document) and the viewer's timeline all ask here, so they
//! agree to the last bit: the composition is always `tip * grasp`, with the tip from the
//! robot's forward kinematics at the arm's base.
//!
//! [`Artifact::grasp_pose`]: cellc_schema::Artifact::grasp_pose

use cellc_schema::EndEffectorId;

use crate::math::Iso;
use crate::scene::{Holder, Scene};

/// The pose of the tip of arm `e` with joints `q`; `None` when `e` is not an arm of
/// `scene` or `q` does not have one value per joint of its chain.
pub fn arm_tip(scene: &Scene, e: EndEffectorId, q: &[f64]) -> Option<Iso> {
    let Some(Holder::Arm { robot, base, .. }) = scene.holders.get(e.index()) else {
        return None;
    };
    let robot = scene.robots.get(*robot)?;
    (q.len() == robot.n_joints()).then(|| robot.tip_pose(base, q))
}

/// The pose of an object held by arm `e` with joints `q` and `grasp` (the object in the
/// tip's frame): `tip * grasp`. `None` where [`arm_tip`] is.
pub fn held_pose(scene: &Scene, e: EndEffectorId, q: &[f64], grasp: &Iso) -> Option<Iso> {
    arm_tip(scene, e, q).map(|tip| tip * grasp)
}
