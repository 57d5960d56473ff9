//! Building a scene from an artifact: every robot read from its URDF and checked against
//! the hash the artifact records, hand and object shapes made parry shapes (meshes read
//! where the compiler found them), and one collision world of every arm with its hand,
//! every surface, object and obstacle.

use cellc_schema::files::MAX_URDF_BYTES;
use cellc_schema::{self as schema, sha256_hex, Artifact};
use parry3d_f64::shape::SharedShape;

use super::{Holder, PlacedShape, Scene};
use crate::collision::{BuildError, CollisionWorldBuilder, Hand, Solid};
use crate::math::{aabb_from_schema, iso_from_schema, Iso, Vec3};
use crate::robot::{Robot, RobotError};
use crate::Files;

/// Why an artifact cannot be made into a scene.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum SceneError {
    /// A URDF or mesh file could not be read.
    Unreadable {
        /// Path.
        path: String,
        /// Why.
        reason: String,
    },
    /// A URDF changed since the artifact was built.
    StaleUrdf {
        /// Robot name.
        robot: String,
        /// Path.
        path: String,
    },
    /// A robot model could not be built from its URDF.
    Robot {
        /// Robot name.
        robot: String,
        /// The model's error.
        error: RobotError,
    },
    /// An object's mesh could not be used.
    Mesh {
        /// Object name.
        object: String,
        /// Why.
        reason: String,
    },
    /// A hand kind's solid (a mesh) could not be used.
    HandMesh {
        /// The hand kind.
        kind: String,
        /// Why.
        reason: String,
    },
    /// The URDF's chain has another number of movable joints than the artifact records
    /// (the artifact was edited, or built by another version).
    JointCount {
        /// Robot name.
        robot: String,
        /// Joints the artifact records.
        recorded: usize,
        /// Joints the URDF's chain has.
        found: usize,
    },
    /// The collision world could not be built (e.g. an allowed contact names no body).
    Collision {
        /// Why.
        reason: String,
    },
}

impl std::fmt::Display for SceneError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SceneError::Unreadable { path, reason } => write!(f, "cannot read `{path}`: {reason}"),
            SceneError::StaleUrdf { robot, path } => write!(
                f,
                "the URDF of robot `{robot}` (`{path}`) changed since the artifact was built"
            ),
            SceneError::Robot { robot, error } => write!(f, "robot `{robot}`: {error}"),
            SceneError::Mesh { object, reason } => write!(f, "object `{object}`: {reason}"),
            SceneError::HandMesh { kind, reason } => write!(f, "hand `{kind}`: {reason}"),
            SceneError::JointCount {
                robot,
                recorded,
                found,
            } => write!(
                f,
                "robot `{robot}`: the artifact records {recorded} movable joints, its URDF's \
                 chain has {found}"
            ),
            SceneError::Collision { reason } => write!(f, "collision world: {reason}"),
        }
    }
}

impl std::error::Error for SceneError {}

impl Scene {
    /// Builds the scene of an artifact, reading URDFs and meshes through `files`.
    pub fn load(artifact: &Artifact, files: &dyn Files) -> Result<Scene, SceneError> {
        let mut robots = Vec::with_capacity(artifact.robots.len());
        for r in &artifact.robots {
            let bytes = files
                .read_at_most(&r.urdf_path, MAX_URDF_BYTES)
                .map_err(|error| SceneError::Unreadable {
                    path: r.urdf_path.clone(),
                    reason: error.to_string(),
                })?;
            if sha256_hex(&bytes) != r.urdf_sha256 {
                return Err(SceneError::StaleUrdf {
                    robot: r.name.clone(),
                    path: r.urdf_path.clone(),
                });
            }
            let text = String::from_utf8_lossy(&bytes);
            // Meshes are read where the compiler resolved them (`package://` included).
            let meshes = cellc_urdf::MeshPaths::Resolved(&r.meshes);
            let mut robot = Robot::from_urdf_with(&text, meshes, &r.base_link, &r.tip_link, files)
                .map_err(|error| SceneError::Robot {
                    robot: r.name.clone(),
                    error,
                })?;
            // Every configuration in the artifact (homes, witnesses) has one value per
            // recorded joint; a model with another count would be indexed out of step.
            if robot.n_joints() != r.joints.len() {
                return Err(SceneError::JointCount {
                    robot: r.name.clone(),
                    recorded: r.joints.len(),
                    found: robot.n_joints(),
                });
            }
            // A validated artifact's limits are positive (`cellc_schema::validate`); one
            // that is not keeps the URDF's, which are.
            robot.set_rate_limits(&r.joints);
            robots.push(robot);
        }
        let holders = artifact
            .end_effectors
            .iter()
            .map(|e| match &e.body {
                schema::Body::Abstract => Holder::Abstract,
                schema::Body::Arm { robot, base, home } => Holder::Arm {
                    robot: *robot as usize,
                    base: iso_from_schema(base),
                    home: home.clone(),
                },
                schema::Body::Surface { slab, reach_height } => Holder::Surface {
                    slab: aabb_from_schema(slab),
                    reach_height: *reach_height,
                },
            })
            .collect();
        let mut kind_solids: Vec<Vec<PlacedShape>> =
            Vec::with_capacity(artifact.holder_kinds.len());
        for k in &artifact.holder_kinds {
            let mut solids = Vec::with_capacity(k.solids.len());
            for s in &k.solids {
                let solid =
                    placed(&s.shape, iso_from_schema(&s.pose), files).map_err(|reason| {
                        SceneError::HandMesh {
                            kind: k.name.clone(),
                            reason,
                        }
                    })?;
                solids.extend(solid);
            }
            kind_solids.push(solids);
        }
        let workspaces = artifact
            .workspaces
            .iter()
            .map(|w| w.boxes.iter().map(aabb_from_schema).collect())
            .collect();
        let mut object_shapes: Vec<Vec<PlacedShape>> = Vec::with_capacity(artifact.objects.len());
        for o in &artifact.objects {
            let shapes = match &o.shape {
                Some(shape) => placed(shape, Iso::identity(), files)
                    .map_err(|reason| SceneError::Mesh {
                        object: o.name.clone(),
                        reason,
                    })?
                    .into_iter()
                    .collect(),
                None => Vec::new(),
            };
            object_shapes.push(shapes);
        }
        let holders: Vec<Holder> = holders;
        let kind_solids: Vec<Vec<PlacedShape>> = kind_solids;
        // The collision world: every arm with its hand, every surface, every object.
        let mut builder = CollisionWorldBuilder::new();
        let mut world_robot = vec![None; holders.len()];
        let mut world_fixed = vec![None; holders.len()];
        let mut robot_holder = Vec::new();
        for (e, (holder, ee)) in holders.iter().zip(&artifact.end_effectors).enumerate() {
            match holder {
                Holder::Arm { robot, .. } => {
                    let hand = ee.kind.and_then(|k| {
                        let solids = kind_solids.get(k as usize)?;
                        (!solids.is_empty()).then(|| Hand {
                            name: artifact.holder_kinds[k as usize].name.clone(),
                            solids: solids
                                .iter()
                                .map(|s| Solid {
                                    local: s.local,
                                    shape: s.shape.clone(),
                                })
                                .collect(),
                        })
                    });
                    let index = builder.add_robot(&ee.name, &robots[*robot], hand);
                    // The SRDF's disabled pairs hold within each arm of that robot.
                    for (a, b) in &artifact.robots[*robot].disabled_collisions {
                        builder.allow_links(index, a, b);
                    }
                    world_robot[e] = Some(index);
                    robot_holder.push(e);
                }
                Holder::Surface { slab, .. } => {
                    world_fixed[e] = Some(builder.add_fixed_box(
                        &ee.name,
                        slab.mins.coords.into(),
                        slab.maxs.coords.into(),
                    ));
                }
                Holder::Abstract => {}
            }
        }
        for (o, shapes) in artifact.objects.iter().zip(&object_shapes) {
            builder.add_object(
                &o.name,
                shapes
                    .iter()
                    .map(|s| Solid {
                        local: s.local,
                        shape: s.shape.clone(),
                    })
                    .collect(),
            );
        }
        for (name, b) in &artifact.obstacles {
            builder.add_fixed_box(name, b.min, b.max);
        }
        // A body without collision geometry (an object with no shape, a link with no
        // `<collision>`) can touch nothing, so allowing its contacts is moot: those pairs
        // are dropped rather than refused.
        let mut allowed = artifact.allowed_contacts.clone();
        let world = loop {
            let mut attempt = builder.clone();
            for (a, b) in &allowed {
                attempt.allow(a, b);
            }
            match attempt.build() {
                Ok(world) => break world,
                Err(BuildError::UnknownName { name })
                    if allowed.iter().any(|(a, b)| *a == name || *b == name) =>
                {
                    allowed.retain(|(a, b)| *a != name && *b != name);
                }
                Err(e) => {
                    return Err(SceneError::Collision {
                        reason: e.to_string(),
                    })
                }
            }
        };
        // Every arm's frames at home, once: most queries leave most arms there, and a
        // line of fifty arms would otherwise run forward kinematics fifty times a check.
        let home_frames = robot_holder
            .iter()
            .map(|&e| {
                let mut frames = Vec::new();
                if let Holder::Arm { robot, base, home } = &holders[e] {
                    robots[*robot].fk_frames(base, home, &mut frames);
                }
                frames
            })
            .collect();
        Ok(Scene {
            id: super::next_scene_id(),
            home_frames,
            at_home: std::sync::OnceLock::new(),
            robots,
            holders,
            kind_solids,
            workspaces,
            object_shapes,
            world,
            world_robot,
            world_fixed,
            robot_holder,
        })
    }
}

/// A schema shape as a parry shape in `local` (cylinders are along z in cells and along
/// y in parry, hence the extra rotation).
fn placed(
    shape: &schema::Shape,
    local: Iso,
    files: &dyn Files,
) -> Result<Option<PlacedShape>, String> {
    let (extra, shape) = match shape {
        schema::Shape::Box { size } => (
            Iso::identity(),
            SharedShape::cuboid(size[0] / 2.0, size[1] / 2.0, size[2] / 2.0),
        ),
        schema::Shape::Cylinder { radius, height } => (
            Iso::rotation(Vec3::x() * std::f64::consts::FRAC_PI_2),
            SharedShape::cylinder(height / 2.0, *radius),
        ),
        schema::Shape::Sphere { radius } => (Iso::identity(), SharedShape::ball(*radius)),
        schema::Shape::Mesh { path } => {
            let hull = crate::mesh::load(path, [1.0; 3], files)
                .map_err(|reason| format!("mesh `{path}`: {reason}"))?;
            (Iso::identity(), hull)
        }
    };
    Ok(Some(PlacedShape {
        local: local * extra,
        shape,
    }))
}
