//! The world: where every arm stands and where every object is, kept from one request to
//! the next.
//!
//! A plan starts from the world (the arms' current joints, the moved object where it
//! lies) and treats every other object as an obstacle at its current pose, moving with
//! the hand that holds it. After a plan is carried out the world is what the executor
//! reports, so the next request starts from the cell as it really is.
//!
//! Who holds what is the world's one invariant: an object is absent or in exactly one
//! state of its graph (holder, grasp, workspace), and a hand holds at most one object. An
//! object held by an arm has no stored pose: its pose is the arm's forward kinematics
//! times the grasp, so it can never disagree with the joints. A resting object keeps its
//! pose (the state says only which resting pose and workspace).
//!
//! `build.rs` turns the cell's `world` item and world documents (names, untrusted) into a
//! world, with [`WorldError`]s that carry names and values for the caller to word;
//! `after.rs` is the world a plan leaves ([`World::after`]), before it is carried out;
//! `held.rs` where a held object is ([`held_pose`]), the one answer for everyone.

mod after;
mod build;
mod document;
mod held;
mod request;

use cellc_schema::{Artifact, EndEffectorId, Node, ObjectId};

use crate::math::Iso;
use crate::scene::{Holder, ObjectPlacement, Obstacle, Scene};

pub use build::WorldError;
pub use held::{arm_tip, held_pose};

/// Where one object is.
#[derive(Clone, Debug, PartialEq)]
pub enum Whereabouts {
    /// Not in the scene: invisible to collision checks, and no request can move it.
    Absent,
    /// In a state of its graph.
    Placed {
        /// Holder, grasp (or resting pose) and workspace.
        state: Node,
        /// The object's pose when it rests on a surface (a held object's pose follows
        /// from its arm; abstract cells have none).
        pose: Option<Iso>,
    },
}

/// The state of the whole cell.
#[derive(Clone, Debug, PartialEq)]
pub struct World {
    /// Joint values of every end-effector that is an arm (index = end-effector id).
    pub(crate) arms: Vec<Option<Vec<f64>>>,
    /// Where each object is (index = object id).
    pub(crate) objects: Vec<Whereabouts>,
}

impl World {
    /// Every arm at home, no object in the scene.
    pub fn at_home(artifact: &Artifact, scene: Option<&Scene>) -> World {
        let arms = (0..artifact.end_effectors.len())
            .map(|e| match scene.and_then(|s| s.holders.get(e)) {
                Some(Holder::Arm { home, .. }) => Some(home.clone()),
                _ => None,
            })
            .collect();
        World {
            arms,
            objects: vec![Whereabouts::Absent; artifact.objects.len()],
        }
    }

    /// The joint values of arm `e` (`None`: not an arm).
    pub fn arm(&self, e: EndEffectorId) -> Option<&[f64]> {
        self.arms.get(e.index())?.as_deref()
    }

    /// Joint values of every end-effector, `None` for those that are not arms.
    pub fn arms(&self) -> &[Option<Vec<f64>>] {
        &self.arms
    }

    /// Where object `o` is.
    pub fn whereabouts(&self, o: ObjectId) -> &Whereabouts {
        self.objects.get(o.index()).unwrap_or(&Whereabouts::Absent)
    }

    /// The state object `o` is in, when it is in the scene.
    pub fn state(&self, o: ObjectId) -> Option<Node> {
        match self.whereabouts(o) {
            Whereabouts::Placed { state, .. } => Some(*state),
            Whereabouts::Absent => None,
        }
    }

    /// The object held by hand `e`, if any (surfaces hold many; this is for arms).
    pub fn held_by(&self, e: EndEffectorId) -> Option<ObjectId> {
        self.objects.iter().enumerate().find_map(|(o, w)| match w {
            Whereabouts::Placed { state, .. } if state.end_effector == e => {
                Some(ObjectId(o as u32))
            }
            _ => None,
        })
    }

    /// The pose of object `o`: stored when it rests, the holding arm's forward kinematics
    /// times the grasp when it is held. `None` when absent or in an abstract cell.
    pub fn pose(&self, artifact: &Artifact, scene: Option<&Scene>, o: ObjectId) -> Option<Iso> {
        let Whereabouts::Placed { state, pose } = self.whereabouts(o) else {
            return None;
        };
        let scene = scene.filter(|s| {
            matches!(
                s.holders.get(state.end_effector.index()),
                Some(Holder::Arm { .. })
            )
        });
        match scene {
            Some(scene) => held_pose(
                scene,
                state.end_effector,
                self.arm(state.end_effector)?,
                &artifact.grasp_pose(o, state.grasp),
            ),
            None => *pose,
        }
    }

    /// Sets arm `e`'s joints (the caller checked them against the arm's chain).
    pub(crate) fn set_arm(&mut self, e: EndEffectorId, q: Vec<f64>) {
        if let Some(slot) = self.arms.get_mut(e.index()) {
            *slot = Some(q);
        }
    }

    /// Puts object `o` somewhere (the caller checked the state against its graph).
    pub(crate) fn set_object(&mut self, o: ObjectId, whereabouts: Whereabouts) {
        if let Some(slot) = self.objects.get_mut(o.index()) {
            *slot = whereabouts;
        }
    }

    /// Every object but `except`, as obstacles: resting ones at their poses, held ones
    /// with the arm that holds them. Absent objects are not in the scene.
    pub fn obstacles(&self, artifact: &Artifact, scene: &Scene, except: ObjectId) -> Vec<Obstacle> {
        let mut out = Vec::new();
        for (i, w) in self.objects.iter().enumerate() {
            let object = ObjectId(i as u32);
            let Whereabouts::Placed { state, pose } = w else {
                continue;
            };
            if object == except {
                continue;
            }
            let placement = match (scene.holders.get(state.end_effector.index()), pose) {
                (Some(Holder::Arm { .. }), _) => ObjectPlacement::Held {
                    by: state.end_effector,
                    grasp: artifact.grasp_pose(object, state.grasp),
                },
                (Some(Holder::Surface { .. }), Some(pose)) => ObjectPlacement::Resting {
                    on: state.end_effector,
                    pose: *pose,
                    by: None,
                },
                _ => continue,
            };
            out.push(Obstacle { object, placement });
        }
        out
    }
}
