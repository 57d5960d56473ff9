//! An artifact made geometric: robots loaded from their URDFs (refused when a URDF changed
//! since the build), arms placed, surfaces as slabs, hand and object shapes for collision
//! checks, workspaces as boxes.
//!
//! `load.rs` builds the scene (robots checked against the artifact's URDF hashes, shapes
//! read, the collision world with each arm's SRDF pairs) or says why not (`SceneError`);
//! `query.rs` answers the collision queries about one object placed so, these arms at
//! these joints and the others at home (`ObjectPlacement`, `Obstacle`, `SceneScratch`,
//! `QueryError`).

use cellc_schema::EndEffectorId;
use parry3d_f64::shape::SharedShape;

use crate::collision::{BodyId, CollisionWorld};
use crate::math::{Aabb, Iso};
use crate::robot::Robot;

mod frozen;
mod load;
mod query;
#[cfg(test)]
mod tests;
mod tip;

pub(crate) use frozen::FrozenScene;
pub use load::SceneError;
pub(crate) use query::Placed;
pub use query::{ObjectPlacement, Obstacle, QueryError, SceneScratch};

/// How an end-effector exists in the scene.
#[derive(Clone, Debug)]
pub enum Holder {
    /// No geometry (abstract cells): nothing to verify.
    Abstract,
    /// At the tip of a placed robot.
    Arm {
        /// Index into [`Scene::robots`].
        robot: usize,
        /// World pose of the robot's base.
        base: Iso,
        /// Home configuration.
        home: Vec<f64>,
    },
    /// A fixed slab; objects rest on its top face.
    Surface {
        /// The slab.
        slab: Aabb,
        /// Height of the space above the top face the surface reaches.
        reach_height: f64,
    },
}

/// A shape placed in a frame.
#[derive(Clone)]
pub struct PlacedShape {
    /// Pose in the parent frame.
    pub local: Iso,
    /// The shape.
    pub shape: SharedShape,
}

impl std::fmt::Debug for PlacedShape {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "PlacedShape({:?}, {:?})",
            self.local,
            self.shape.shape_type()
        )
    }
}

/// The geometric side of a cell.
pub struct Scene {
    /// Robot models, as in [`Artifact::robots`](cellc_schema::Artifact::robots).
    pub robots: Vec<Robot>,
    /// One per end-effector of the artifact.
    pub holders: Vec<Holder>,
    /// Collision solids of each holder kind, in the holder's (tip) frame.
    pub kind_solids: Vec<Vec<PlacedShape>>,
    /// Boxes of each workspace.
    pub workspaces: Vec<Vec<Aabb>>,
    /// Collision shape of each object, in the object frame.
    pub object_shapes: Vec<Vec<PlacedShape>>,
    /// Every body of the cell, for collision checks.
    pub world: CollisionWorld,
    /// Per end-effector: its robot index in `world`, for arms.
    world_robot: Vec<Option<usize>>,
    /// Per end-effector: its fixed-body index in `world`, for surfaces.
    world_fixed: Vec<Option<usize>>,
    /// Per `world` robot: its end-effector.
    robot_holder: Vec<usize>,
    /// Per `world` robot: its frames at its home configuration.
    home_frames: Vec<Vec<crate::math::Iso>>,
    /// The cell at home (every arm at home, the furniture), placed once, on the first
    /// query that needs it: what every collision query stands on (`collision::home`).
    /// `None` when the resting state cannot be placed (the plain queries then answer).
    at_home: std::sync::OnceLock<Option<crate::collision::Home>>,
    /// Tells scratches apart which scene their cached frames belong to.
    id: u64,
}

/// A fresh [`Scene::id`].
fn next_scene_id() -> u64 {
    use std::sync::atomic::{AtomicU64, Ordering};
    static NEXT: AtomicU64 = AtomicU64::new(1);
    NEXT.fetch_add(1, Ordering::Relaxed)
}

impl Scene {
    /// The end-effector whose arm (a link or its hand) `body` belongs to, if any.
    pub fn arm_of(&self, body: BodyId) -> Option<EndEffectorId> {
        let robot = match body {
            BodyId::Link { robot, .. } | BodyId::Hand { robot, .. } => robot,
            BodyId::Fixed(_) | BodyId::Object(_) => return None,
        };
        self.robot_holder
            .get(robot)
            .map(|&e| EndEffectorId(e as u32))
    }

    /// The world robot of end-effector `e`, for an arm.
    pub(crate) fn world_robot(&self, e: EndEffectorId) -> Option<usize> {
        self.world_robot.get(e.index()).copied().flatten()
    }

    /// The cell at home, built on first use (`None` when its state cannot be placed).
    pub(crate) fn at_home(&self) -> Option<&crate::collision::Home> {
        self.at_home
            .get_or_init(|| {
                let robots: Vec<&[crate::math::Iso]> =
                    self.home_frames.iter().map(Vec::as_slice).collect();
                let objects =
                    vec![crate::collision::ObjectState::absent(); self.object_shapes.len()];
                let home = crate::collision::Configuration {
                    robots: &robots,
                    objects: &objects,
                };
                self.world.at_home(&home).ok()
            })
            .as_ref()
    }

    /// True when the artifact has any arm, i.e. anything to verify kinematically.
    pub fn has_kinematics(&self) -> bool {
        self.holders.iter().any(|h| matches!(h, Holder::Arm { .. }))
    }
}
