//! An artifact made geometric: robots loaded from their URDFs (refused when a URDF changed
//! since the build), arms placed, surfaces as slabs, hand and object shapes for collision
//! checks, workspaces as boxes.

use cellc_schema::files::MAX_URDF_BYTES;
use cellc_schema::{self as schema, sha256_hex, Artifact, EndEffectorId, ObjectId};
use parry3d_f64::shape::SharedShape;

use crate::collision::{
    BodyId, BuildError, Collision, CollisionError, CollisionScratch, CollisionWorld,
    CollisionWorldBuilder, Configuration, Hand, Holder as CollisionHolder, ObjectState, Solid,
    SweepBounds,
};
use crate::math::{aabb_from_schema, iso_from_schema, Aabb, Iso, Vec3};
use crate::robot::{Robot, RobotError};
use crate::Files;

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

/// The geometric side of a cell.
pub struct Scene {
    /// Robot models, as in [`Artifact::robots`].
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
}

/// Where the checked object is in a collision query.
#[derive(Clone, Copy, Debug)]
pub enum ObjectPlacement {
    /// Held by one arm with a grasp (object pose in the hand frame).
    Held {
        /// End-effector.
        by: EndEffectorId,
        /// Grasp pose.
        grasp: Iso,
    },
    /// Held by an arm that is putting it down on a surface: the object follows the hand
    /// and may touch that surface.
    Placing {
        /// The arm.
        by: EndEffectorId,
        /// Its grasp.
        grasp: Iso,
        /// The surface it goes onto.
        on: EndEffectorId,
        /// Another arm's hand still on the object (it let go but could not retreat).
        also: Option<EndEffectorId>,
    },
    /// Held by two arms at once (a handoff); the pose follows the first.
    Handoff {
        /// End-effector whose grasp places the object.
        a: EndEffectorId,
        /// Its grasp.
        grasp_a: Iso,
        /// The other holder.
        b: EndEffectorId,
    },
    /// Resting on a surface at `pose`, possibly held by an arm too (a pick or a place).
    Resting {
        /// The surface end-effector.
        on: EndEffectorId,
        /// Object pose in the cell.
        pose: Iso,
        /// The arm holding it at the same time.
        by: Option<EndEffectorId>,
    },
    /// Left out of the check (motions with the object elsewhere, or none moved yet).
    Absent,
}

/// Another object as a collision query sees it: in the scene, not the one the query is
/// about (the world's other objects, during a plan for one of them).
#[derive(Clone, Copy, Debug)]
pub struct Obstacle {
    /// The object.
    pub object: ObjectId,
    /// Where it is: resting on a surface at a pose, or held by an arm.
    pub placement: ObjectPlacement,
}

/// The objects of one query: the one it is about, placed as `placement`, and the others.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Placed<'a> {
    pub(crate) object: ObjectId,
    pub(crate) placement: ObjectPlacement,
    pub(crate) obstacles: &'a [Obstacle],
}

/// Why a collision query could not be answered.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum QueryError {
    /// The end-effector is not an arm of the scene.
    NotAnArm(EndEffectorId),
    /// The end-effector is not a surface of the scene.
    NotASurface(EndEffectorId),
    /// The collision world refused the state.
    Collision(CollisionError),
    /// A configuration has the wrong number of joint values for the arms it is for.
    WrongLength {
        /// Values expected.
        expected: usize,
        /// Values given.
        found: usize,
    },
}

/// Robots whose frames one query lists without allocating (more fall back to a vector).
const INLINE_ROBOTS: usize = 16;

/// Buffers for [`Scene::collision`], one per thread.
#[derive(Default)]
pub struct SceneScratch {
    frames: Vec<Vec<Iso>>,
    objects: Vec<ObjectState>,
    collision: CollisionScratch,
    /// How far the bodies travel along the segment a sound motion check is certifying
    /// (`crate::swept`), kept here so that no query allocates.
    pub(crate) sweep: SweepBounds,
}

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
            let robot = Robot::from_urdf_with(&text, meshes, &r.base_link, &r.tip_link, files)
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
        Ok(Scene {
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

    /// The first collision when `object` is placed as given, the arms in `arms` take the
    /// given joint values and every other arm stands at its home configuration. Other
    /// objects are left out: verification and planning move one object at a time.
    /// Returns the names of the colliding pair.
    pub fn collision(
        &self,
        arms: &[(EndEffectorId, &[f64])],
        object: ObjectId,
        placement: ObjectPlacement,
        obstacles: &[Obstacle],
        scratch: &mut SceneScratch,
    ) -> Result<Option<(String, String)>, QueryError> {
        let found = self.first_collision(arms, object, placement, obstacles, scratch)?;
        Ok(found.map(|c| {
            let (a, b) = self.world.names(&c);
            (a.to_string(), b.to_string())
        }))
    }

    /// Every colliding pair of the state [`Scene::collision`] describes, sorted (so reports
    /// that pick one pick the same whatever the sweep order), written to `out`.
    pub fn all_collisions(
        &self,
        arms: &[(EndEffectorId, &[f64])],
        object: ObjectId,
        placement: ObjectPlacement,
        scratch: &mut SceneScratch,
        out: &mut Vec<Collision>,
    ) -> Result<(), QueryError> {
        let at = Placed {
            object,
            placement,
            obstacles: &[],
        };
        self.with_configuration(arms, at, scratch, |state, scratch| {
            self.world.all_collisions(state, scratch, out)
        })
    }

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

    /// Whether the state [`Scene::collision`] describes is free, without naming anything
    /// (the inner loops of motion planning ask this millions of times).
    pub fn is_free(
        &self,
        arms: &[(EndEffectorId, &[f64])],
        object: ObjectId,
        placement: ObjectPlacement,
        obstacles: &[Obstacle],
        scratch: &mut SceneScratch,
    ) -> Result<bool, QueryError> {
        Ok(self
            .first_collision(arms, object, placement, obstacles, scratch)?
            .is_none())
    }

    /// The first colliding pair of the state [`Scene::collision`] describes, as body ids.
    fn first_collision(
        &self,
        arms: &[(EndEffectorId, &[f64])],
        object: ObjectId,
        placement: ObjectPlacement,
        obstacles: &[Obstacle],
        scratch: &mut SceneScratch,
    ) -> Result<Option<Collision>, QueryError> {
        let at = Placed {
            object,
            placement,
            obstacles,
        };
        self.with_configuration(arms, at, scratch, |state, scratch| {
            self.world.first_collision(state, scratch)
        })
    }

    /// How far the state [`Scene::collision`] describes can move along a segment whose
    /// bodies travel as `bounds` says before two bodies that may not touch could touch:
    /// [`CollisionWorld::free_radius`] (in the segment's parameter, at most `horizon`).
    pub(crate) fn free_radius(
        &self,
        arms: &[(EndEffectorId, &[f64])],
        at: Placed<'_>,
        bounds: &SweepBounds,
        horizon: f64,
        scratch: &mut SceneScratch,
    ) -> Result<f64, QueryError> {
        self.with_configuration(arms, at, scratch, |state, scratch| {
            self.world.free_radius(state, bounds, horizon, scratch)
        })
    }

    /// The world robot of end-effector `e`, for an arm.
    pub(crate) fn world_robot(&self, e: EndEffectorId) -> Option<usize> {
        self.world_robot.get(e.index()).copied().flatten()
    }

    /// Builds the collision state the queries above describe (every arm's frames, the
    /// object placed) in `scratch` and asks `query` about it.
    fn with_configuration<T>(
        &self,
        arms: &[(EndEffectorId, &[f64])],
        at: Placed<'_>,
        scratch: &mut SceneScratch,
        query: impl FnOnce(&Configuration<'_>, &mut CollisionScratch) -> Result<T, CollisionError>,
    ) -> Result<T, QueryError> {
        let n = self.robot_holder.len();
        scratch.frames.resize_with(n, Vec::new);
        for (r, &e) in self.robot_holder.iter().enumerate() {
            let Holder::Arm { robot, base, home } = &self.holders[e] else {
                continue;
            };
            let q = arms
                .iter()
                .find(|(arm, _)| arm.index() == e)
                .map_or(home.as_slice(), |(_, q)| *q);
            self.robots[*robot].fk_frames(base, q, &mut scratch.frames[r]);
        }
        scratch.objects.clear();
        scratch
            .objects
            .resize(self.object_shapes.len(), ObjectState::absent());
        let state = self.object_state(at.placement, &scratch.frames)?;
        if let Some(slot) = scratch.objects.get_mut(at.object.index()) {
            *slot = state;
        }
        for obstacle in at.obstacles {
            let state = self.object_state(obstacle.placement, &scratch.frames)?;
            if let Some(slot) = scratch.objects.get_mut(obstacle.object.index()) {
                *slot = state;
            }
        }
        // The frames as slices, listed without allocating for the usual handful of arms.
        let mut inline: [&[Iso]; INLINE_ROBOTS] = [&[]; INLINE_ROBOTS];
        let heap: Vec<&[Iso]>;
        let frames: &[&[Iso]] = if n <= INLINE_ROBOTS {
            for (slot, f) in inline.iter_mut().zip(&scratch.frames) {
                *slot = f;
            }
            &inline[..n]
        } else {
            heap = scratch.frames.iter().map(Vec::as_slice).collect();
            &heap
        };
        let configuration = Configuration {
            robots: frames,
            objects: &scratch.objects,
        };
        query(&configuration, &mut scratch.collision).map_err(QueryError::Collision)
    }

    /// The collision state of an object placed as `placement`, the robots' frames being
    /// `frames` (a held object rides its arm's tip frame).
    fn object_state(
        &self,
        placement: ObjectPlacement,
        frames: &[Vec<Iso>],
    ) -> Result<ObjectState, QueryError> {
        let robot_of = |e: EndEffectorId| self.world_robot(e);
        let state = match placement {
            ObjectPlacement::Held { by, grasp } => {
                let r = robot_of(by).ok_or(QueryError::NotAnArm(by))?;
                let tip = self
                    .world
                    .tip(r, &frames[r])
                    .ok_or(QueryError::NotAnArm(by))?;
                ObjectState::held(r, &tip, &grasp)
            }
            ObjectPlacement::Placing {
                by,
                grasp,
                on,
                also,
            } => {
                let r = robot_of(by).ok_or(QueryError::NotAnArm(by))?;
                let tip = self
                    .world
                    .tip(r, &frames[r])
                    .ok_or(QueryError::NotAnArm(by))?;
                let surface = self
                    .world_fixed
                    .get(on.index())
                    .copied()
                    .flatten()
                    .ok_or(QueryError::NotASurface(on))?;
                let mut state = ObjectState::held(r, &tip, &grasp)
                    .also_held_by(CollisionHolder::Fixed(surface));
                if let Some(other) = also {
                    let o = robot_of(other).ok_or(QueryError::NotAnArm(other))?;
                    state = state.also_held_by(CollisionHolder::Robot(o));
                }
                state
            }
            ObjectPlacement::Handoff { a, grasp_a, b } => {
                let ra = robot_of(a).ok_or(QueryError::NotAnArm(a))?;
                let rb = robot_of(b).ok_or(QueryError::NotAnArm(b))?;
                let tip = self
                    .world
                    .tip(ra, &frames[ra])
                    .ok_or(QueryError::NotAnArm(a))?;
                ObjectState::held(ra, &tip, &grasp_a).also_held_by(CollisionHolder::Robot(rb))
            }
            ObjectPlacement::Resting { on, pose, by } => {
                let surface = self
                    .world_fixed
                    .get(on.index())
                    .copied()
                    .flatten()
                    .ok_or(QueryError::NotASurface(on))?;
                let mut state = ObjectState::resting(pose, surface);
                if let Some(arm) = by {
                    let r = robot_of(arm).ok_or(QueryError::NotAnArm(arm))?;
                    state = state.also_held_by(CollisionHolder::Robot(r));
                }
                state
            }
            ObjectPlacement::Absent => ObjectState::absent(),
        };
        Ok(state)
    }

    /// True when the artifact has any arm, i.e. anything to verify kinematically.
    pub fn has_kinematics(&self) -> bool {
        self.holders.iter().any(|h| matches!(h, Holder::Arm { .. }))
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

/// Collision queries by body id, for callers that name what collides by its ids (the
/// planner's blocking objects, `plan::planner::blocking`) rather than by the names
/// [`Scene::collision`] gives.
impl Scene {
    /// The first colliding pair of the state [`Scene::collision`] describes, as body ids
    /// (an object's body is [`BodyId::Object`] with its object index).
    pub(crate) fn first_collision_ids(
        &self,
        arms: &[(EndEffectorId, &[f64])],
        object: ObjectId,
        placement: ObjectPlacement,
        obstacles: &[Obstacle],
        scratch: &mut SceneScratch,
    ) -> Result<Option<Collision>, QueryError> {
        self.first_collision(arms, object, placement, obstacles, scratch)
    }
}
