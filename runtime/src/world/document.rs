//! The world as a world document: what a durable store keeps and what a restarted
//! service reads back with [`World::from_document`].
//!
//! The document is the world by name, so a stored world stays meaningful when the cell
//! is rebuilt (ids may change; names are what the engineer wrote), and it is checked
//! again on the way back in like any document from a client. Poses are written as the
//! runtime holds them (position and the unit quaternion's four numbers, in full
//! precision), and held objects without a pose (it follows from the arm's joints), so
//! reading the document back gives the same world, bit for bit.

use std::collections::BTreeMap;

use cellc_schema::world::{AbsentWord, ObjectEntry, PlacedEntry};
use cellc_schema::{Artifact, ObjectId, WorldDocument};

use super::{Whereabouts, World};
use crate::scene::{Holder, Scene};

impl World {
    /// Every arm's joints (by URDF joint name) and every object's whereabouts, absent
    /// ones included, so the document says everything the world knows.
    pub fn to_document(&self, artifact: &Artifact, scene: Option<&Scene>) -> WorldDocument {
        let mut arms = BTreeMap::new();
        for (e, q) in self.arms.iter().enumerate() {
            let Some(q) = q else { continue };
            let robot = match scene.and_then(|s| s.holders.get(e)) {
                Some(Holder::Arm { robot, .. }) => scene.and_then(|s| s.robots.get(*robot)),
                _ => None,
            };
            let Some(robot) = robot else { continue };
            let joints = robot
                .joint_names()
                .iter()
                .zip(q)
                .map(|(name, &value)| (name.clone(), value))
                .collect();
            let name = artifact.end_effector_name(cellc_schema::EndEffectorId(e as u32));
            arms.insert(name.to_string(), joints);
        }
        let mut objects = BTreeMap::new();
        for (o, whereabouts) in self.objects.iter().enumerate() {
            let object = ObjectId(o as u32);
            let entry = match whereabouts {
                Whereabouts::Absent => ObjectEntry::Absent(AbsentWord::Absent),
                Whereabouts::Placed { state, pose } => {
                    let (at, quat) = match pose {
                        Some(p) => {
                            let t = p.translation.vector;
                            let q = p.rotation.quaternion();
                            (Some([t.x, t.y, t.z]), Some([q.w, q.i, q.j, q.k]))
                        }
                        None => (None, None),
                    };
                    ObjectEntry::Placed(PlacedEntry {
                        holder: artifact.end_effector_name(state.end_effector).to_string(),
                        grasp: Some(artifact.grasp_name(object, state.grasp).to_string()),
                        workspace: Some(artifact.workspace_name(state.workspace).to_string()),
                        at,
                        rpy: None,
                        quat,
                    })
                }
            };
            objects.insert(artifact.object_name(object).to_string(), entry);
        }
        WorldDocument { arms, objects }
    }
}
