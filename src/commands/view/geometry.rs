//! The cell's solids as the page draws them: the same collision geometry the planner
//! checks (robot links from their URDF `<collision>` elements, hand solids, surfaces as
//! slabs, obstacles, object shapes), each shape once in a table and every body a list of
//! (shape, pose in the body's frame). Meshes are sent as the convex hulls the collision
//! checks use, so what is seen is what is checked.

use cellc_runtime::math::{Iso, Vec3};
use cellc_runtime::scene::{Holder, Scene};
use cellc_schema::{Artifact, EndEffectorId};
use parry3d_f64::shape::{SharedShape, TypedShape};
use serde::Serialize;

/// Rounds to 0.1 mm (or 1e-4 of a quaternion component): the page needs no more, and the
/// file stays small.
pub fn round(x: f64) -> f64 {
    (x * 1e4).round() / 1e4
}

/// A pose as `[x, y, z, qx, qy, qz, qw]`.
pub fn pose(p: &Iso) -> [f64; 7] {
    let t = p.translation.vector;
    let q = p.rotation.coords;
    [t.x, t.y, t.z, q.x, q.y, q.z, q.w].map(round)
}

/// A shape in the page's terms (three.js primitives are centred like parry's, cylinders
/// along y in both).
#[derive(Serialize)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum Geom {
    /// Full sizes.
    Box { size: [f64; 3] },
    /// Radius.
    Sphere { radius: f64 },
    /// Along y.
    Cylinder { radius: f64, height: f64 },
    /// Triangles: flat positions and indices.
    Mesh {
        positions: Vec<f64>,
        indices: Vec<u32>,
    },
}

/// One shape of a body, in the body's frame.
#[derive(Serialize)]
pub struct Part {
    /// Index into [`Geometry::geoms`].
    pub geom: usize,
    /// Pose in the body's frame.
    pub local: [f64; 7],
}

/// What a body is, for colours, labels and the checks of the browser test.
#[derive(Serialize, Clone, Copy, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum BodyKind {
    /// A robot link (moves with one frame of an arm's chain).
    Link,
    /// The solids of a hand, at the arm's tip.
    Hand,
    /// A fixed surface (a slab).
    Surface,
    /// A fixed obstacle.
    Obstacle,
    /// An object.
    Object,
}

/// A rigid body: its parts and where it is at the start (moving bodies get their poses
/// from the timeline too).
#[derive(Serialize)]
pub struct BodyOut {
    /// Name shown on hover and used by `cellcView.project`.
    pub name: String,
    /// What it is.
    pub kind: BodyKind,
    /// The end-effector or object it belongs to.
    pub owner: String,
    /// Its solids.
    pub parts: Vec<Part>,
}

/// Every body and shape of the cell.
#[derive(Default, Serialize)]
pub struct Geometry {
    /// Shapes.
    pub geoms: Vec<Geom>,
    /// Bodies.
    pub bodies: Vec<BodyOut>,
}

/// Where the bodies of one arm are among [`Geometry::bodies`].
#[derive(Clone, Debug)]
pub struct ArmBodies {
    /// The end-effector.
    pub end_effector: EndEffectorId,
    /// Index of the robot in the scene.
    pub robot: usize,
    /// Pose of the base.
    pub base: Iso,
    /// One body per frame (0 = base), index into the bodies.
    pub frames: Vec<usize>,
    /// The hand's body (at the tip), when it has solids.
    pub hand: Option<usize>,
}

/// The geometry and which bodies move how.
pub struct Built {
    /// Bodies and shapes.
    pub geometry: Geometry,
    /// Per arm, its bodies.
    pub arms: Vec<ArmBodies>,
    /// Per object (index = object id), its body.
    pub objects: Vec<usize>,
    /// Fixed bodies (surfaces, obstacles) with their poses.
    pub fixed: Vec<(usize, Iso)>,
}

/// Triangles of a convex shape, or the primitive.
fn geom(shape: &SharedShape) -> Geom {
    match shape.as_typed_shape() {
        TypedShape::Cuboid(c) => Geom::Box {
            size: (c.half_extents * 2.0).into(),
        },
        TypedShape::Ball(b) => Geom::Sphere { radius: b.radius },
        TypedShape::Cylinder(c) => Geom::Cylinder {
            radius: c.radius,
            height: c.half_height * 2.0,
        },
        TypedShape::Capsule(c) => mesh(c.to_trimesh(16, 8)),
        TypedShape::ConvexPolyhedron(c) => mesh(c.to_trimesh()),
        TypedShape::TriMesh(t) => mesh((t.vertices().to_vec(), t.indices().to_vec())),
        // Any other solid is drawn as its bounding box.
        _ => {
            let aabb = shape.compute_local_aabb();
            Geom::Box {
                size: aabb.extents().into(),
            }
        }
    }
}

fn mesh((points, triangles): (Vec<parry3d_f64::math::Point<f64>>, Vec<[u32; 3]>)) -> Geom {
    Geom::Mesh {
        positions: points
            .iter()
            .flat_map(|p| [p.x, p.y, p.z])
            .map(round)
            .collect(),
        indices: triangles.into_iter().flatten().collect(),
    }
}

impl Geometry {
    fn add_geom(&mut self, shape: &SharedShape) -> usize {
        self.geoms.push(geom(shape));
        self.geoms.len() - 1
    }

    fn add_body(&mut self, name: String, kind: BodyKind, owner: &str, parts: Vec<Part>) -> usize {
        self.bodies.push(BodyOut {
            name,
            kind,
            owner: owner.to_string(),
            parts,
        });
        self.bodies.len() - 1
    }
}

/// The cell's geometry. Shapes shared by several bodies (a robot model used by two arms)
/// are listed once per robot model.
pub fn build(artifact: &Artifact, scene: &Scene) -> Built {
    let mut g = Geometry::default();
    // One geom table per robot model, so two arms of the same robot share shapes.
    let robot_geoms: Vec<Vec<usize>> = scene
        .robots
        .iter()
        .map(|r| r.shapes().iter().map(|s| g.add_geom(&s.shape)).collect())
        .collect();
    let kind_geoms: Vec<Vec<usize>> = scene
        .kind_solids
        .iter()
        .map(|solids| solids.iter().map(|s| g.add_geom(&s.shape)).collect())
        .collect();
    let mut arms = Vec::new();
    let mut fixed = Vec::new();
    for (e, ee) in artifact.end_effectors.iter().enumerate() {
        match scene.holders.get(e) {
            Some(Holder::Arm { robot, base, .. }) => {
                let model = &scene.robots[*robot];
                let shapes = model.shapes();
                let mut frames = Vec::new();
                for frame in 0..=model.n_joints() {
                    let parts: Vec<Part> = shapes
                        .iter()
                        .enumerate()
                        .filter(|(_, s)| s.frame == frame)
                        .map(|(i, s)| Part {
                            geom: robot_geoms[*robot][i],
                            local: pose(&s.local),
                        })
                        .collect();
                    let link = model.frame_link(frame).unwrap_or_default();
                    frames.push(g.add_body(
                        format!("{}/{}", ee.name, link),
                        BodyKind::Link,
                        &ee.name,
                        parts,
                    ));
                }
                let hand = ee
                    .kind
                    .and_then(|k| scene.kind_solids.get(k as usize).map(|s| (k, s)))
                    .filter(|(_, solids)| !solids.is_empty())
                    .map(|(k, solids)| {
                        let parts = solids
                            .iter()
                            .enumerate()
                            .map(|(i, s)| Part {
                                geom: kind_geoms[k as usize][i],
                                local: pose(&s.local),
                            })
                            .collect();
                        g.add_body(format!("{}/hand", ee.name), BodyKind::Hand, &ee.name, parts)
                    });
                arms.push(ArmBodies {
                    end_effector: EndEffectorId(e as u32),
                    robot: *robot,
                    base: *base,
                    frames,
                    hand,
                });
            }
            Some(Holder::Surface { slab, .. }) => {
                let size = slab.maxs - slab.mins;
                let centre = slab.center();
                let shape = SharedShape::cuboid(size.x / 2.0, size.y / 2.0, size.z / 2.0);
                let geom = g.add_geom(&shape);
                let body = g.add_body(
                    ee.name.clone(),
                    BodyKind::Surface,
                    &ee.name,
                    vec![Part {
                        geom,
                        local: pose(&Iso::identity()),
                    }],
                );
                fixed.push((body, Iso::translation(centre.x, centre.y, centre.z)));
            }
            Some(Holder::Abstract) | None => {}
        }
    }
    for (name, b) in &artifact.obstacles {
        let size = Vec3::new(
            b.max[0] - b.min[0],
            b.max[1] - b.min[1],
            b.max[2] - b.min[2],
        );
        let geom = g.add_geom(&SharedShape::cuboid(
            size.x / 2.0,
            size.y / 2.0,
            size.z / 2.0,
        ));
        let body = g.add_body(
            name.clone(),
            BodyKind::Obstacle,
            name,
            vec![Part {
                geom,
                local: pose(&Iso::identity()),
            }],
        );
        let c = |i: usize| (b.max[i] + b.min[i]) / 2.0;
        fixed.push((body, Iso::translation(c(0), c(1), c(2))));
    }
    let mut objects = Vec::new();
    for (o, object) in artifact.objects.iter().enumerate() {
        let parts = scene
            .object_shapes
            .get(o)
            .map(|shapes| {
                shapes
                    .iter()
                    .map(|s| Part {
                        geom: g.add_geom(&s.shape),
                        local: pose(&s.local),
                    })
                    .collect()
            })
            .unwrap_or_default();
        objects.push(g.add_body(object.name.clone(), BodyKind::Object, &object.name, parts));
    }
    Built {
        geometry: g,
        arms,
        objects,
        fixed,
    }
}
