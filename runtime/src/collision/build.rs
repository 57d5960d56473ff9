//! Building a collision world: bodies from robots, hands, fixed bodies and objects, names
//! checked, and the pairs that are never tested (the static rules and the cell's allowed
//! contacts) in a bit matrix.

use parry3d_f64::bounding_volume::Aabb;
use parry3d_f64::shape::SharedShape;

use super::broad_phase::aabb_finite;
use super::world::CollisionWorld;
use super::{BodyId, BuildError, Hand, Solid};
use crate::math::{Iso, Point, Vec3};
use crate::robot::{LinkShape, Robot};

/// Where a body's pose comes from.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Mount {
    /// `frames[frame] * local` of robot `robot`.
    Frame { robot: usize, frame: usize },
    /// `local` is the world pose.
    Fixed,
    /// `pose * local` of object `object`.
    Object { object: usize },
}

#[derive(Clone, Debug)]
pub(super) struct Body {
    pub(super) id: BodyId,
    pub(super) name: String,
    /// The robot this body belongs to (link or hand solid), for allowed names.
    pub(super) robot: Option<usize>,
    /// A held object may touch this body when its holders include this robot: the hand's
    /// solids and the tip frame's links.
    pub(super) grips_for: Option<usize>,
    pub(super) mount: Mount,
    pub(super) local: Iso,
    pub(super) shape: SharedShape,
    /// World AABB of a fixed body, computed once.
    pub(super) fixed_aabb: Option<Aabb>,
    /// Bounding sphere in the body's frame (`pose`, i.e. after `local`).
    pub(super) sphere_centre: Point,
    pub(super) sphere_radius: f64,
    /// Half height and radius when the shape is a cylinder, whose AABB is computed in
    /// closed form: parry's generic one takes six support-point queries, which made it
    /// most of the cost of a whole check.
    pub(super) cylinder: Option<(f64, f64)>,
    /// The shape's own AABB when it is a convex polyhedron (a mesh's hull): its world
    /// AABB is taken as that box's, turned, which contains the shape (so every use of
    /// the AABB, the broad phase's rejections and the distance lower bounds, stays
    /// sound) for twelve multiplications, where parry's exact one visits every vertex of
    /// the hull (a Panda link's has hundreds; it was most of the time of a motion).
    pub(super) hull_aabb: Option<Aabb>,
    /// The same hull's vertex graph, for support points by hill climbing (`hull.rs`).
    pub(super) hull: Option<std::sync::Arc<super::hull::HullSupport>>,
    /// A capsule containing the shape, in the body's frame (`capsule.rs`): the distance
    /// lower bound that rejects most pairs before an exact query.
    pub(super) capsule: Option<super::capsule::Capsule>,
    /// Half extents when the shape is a cuboid, whose distance to a capsule's segment is
    /// computed exactly.
    pub(super) half_extents: Option<Vec3>,
}

#[derive(Clone, Debug)]
pub(super) struct RobotInfo {
    pub(super) name: String,
    pub(super) frames: usize,
    pub(super) tip_offset: Iso,
}

/// A robot as the world needs it: frames, shapes on them, which frames are joined by a
/// joint, and the hand on the tip.
#[derive(Clone)]
struct PendingRobot {
    name: String,
    frames: usize,
    tip_offset: Iso,
    shapes: Vec<LinkShape>,
    /// `frames * frames`, row-major.
    adjacent: Vec<bool>,
    hand: Option<Hand>,
}

/// Collects the bodies of a cell, then [`build`](Self::build)s the world.
#[derive(Default, Clone)]
pub struct CollisionWorldBuilder {
    robots: Vec<PendingRobot>,
    fixed: Vec<(String, Iso, SharedShape)>,
    objects: Vec<(String, Vec<Solid>)>,
    allowed: Vec<(String, String)>,
    /// Link pairs of one robot that may touch: (robot index, link, link).
    allowed_links: Vec<(usize, String, String)>,
}

impl CollisionWorldBuilder {
    /// An empty builder.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds a robot instance named `name` (the cell's arm name, e.g. `left`) with its
    /// links as loaded from the URDF and the hand on its tip, and returns its index (the
    /// index of its frames in a [`Configuration`](super::Configuration)).
    pub fn add_robot(&mut self, name: &str, robot: &Robot, hand: Option<Hand>) -> usize {
        self.add_chain(
            name,
            robot.n_frames(),
            *robot.tip_offset(),
            robot.shapes().to_vec(),
            |a, b| robot.adjacent_frames(a, b),
            hand,
        )
    }

    /// Adds a kinematic chain given directly: `frames` frames, the tip link at
    /// `tip_offset` from the last frame, shapes attached to the frames, and
    /// `adjacent(a, b)` telling which frames are joined by a joint (their links overlap
    /// by construction). [`add_robot`](Self::add_robot) calls this with a URDF-loaded
    /// robot; tests can describe a chain by hand.
    pub fn add_chain(
        &mut self,
        name: &str,
        frames: usize,
        tip_offset: Iso,
        shapes: Vec<LinkShape>,
        adjacent: impl Fn(usize, usize) -> bool,
        hand: Option<Hand>,
    ) -> usize {
        let mut adj = vec![false; frames * frames];
        for a in 0..frames {
            for b in 0..frames {
                adj[a * frames + b] = a == b || adjacent(a, b) || adjacent(b, a);
            }
        }
        self.robots.push(PendingRobot {
            name: name.to_string(),
            frames,
            tip_offset,
            shapes,
            adjacent: adj,
            hand,
        });
        self.robots.len() - 1
    }

    /// Adds a fixed body (a surface slab, an obstacle) at world pose `pose`; returns its
    /// index (for [`Holder::Fixed`](super::Holder::Fixed)).
    pub fn add_fixed(&mut self, name: &str, pose: Iso, shape: SharedShape) -> usize {
        self.fixed.push((name.to_string(), pose, shape));
        self.fixed.len() - 1
    }

    /// Adds a fixed axis-aligned box given by its corners (how the artifact gives surface
    /// slabs); returns its index.
    pub fn add_fixed_box(&mut self, name: &str, min: [f64; 3], max: [f64; 3]) -> usize {
        let centre = Vec3::new(
            (min[0] + max[0]) / 2.0,
            (min[1] + max[1]) / 2.0,
            (min[2] + max[2]) / 2.0,
        );
        let half = [
            ((max[0] - min[0]) / 2.0).abs(),
            ((max[1] - min[1]) / 2.0).abs(),
            ((max[2] - min[2]) / 2.0).abs(),
        ];
        self.add_fixed(
            name,
            Iso::translation(centre.x, centre.y, centre.z),
            SharedShape::cuboid(half[0], half[1], half[2]),
        )
    }

    /// Adds an object made of `solids` (placed in the object frame); returns its index
    /// (of its [`ObjectState`](super::ObjectState) in a [`Configuration`](super::Configuration)(super::Configuration)). An object without solids (an
    /// abstract cell's) keeps its index but never collides.
    pub fn add_object(&mut self, name: &str, solids: Vec<Solid>) -> usize {
        self.objects.push((name.to_string(), solids));
        self.objects.len() - 1
    }

    /// Allows bodies named `a` to touch bodies named `b`. A name is a body's report name
    /// (`left/lwr_link_1`, `left/softhand`, `table`, `cylinder`) or a robot's name, which
    /// stands for all its links and its hand. Checked at [`build`](Self::build).
    pub fn allow(&mut self, a: &str, b: &str) {
        self.allowed.push((a.to_string(), b.to_string()));
    }

    /// Allows links `a` and `b` of robot `robot` (an index [`add_robot`](Self::add_robot)
    /// returned) to touch each other, as an SRDF's `<disable_collisions>` says. Unlike
    /// [`allow`](Self::allow), a link without collision solids is no error: an SRDF
    /// lists pairs of the whole robot, including links off the chain or without geometry.
    pub fn allow_links(&mut self, robot: usize, a: &str, b: &str) {
        self.allowed_links
            .push((robot, a.to_string(), b.to_string()));
    }

    /// Builds the world: names checked, fixed AABBs computed, the allowed-pair matrix
    /// filled.
    pub fn build(self) -> Result<CollisionWorld, BuildError> {
        let mut top: Vec<&str> = Vec::new();
        for n in self
            .robots
            .iter()
            .map(|r| r.name.as_str())
            .chain(self.fixed.iter().map(|f| f.0.as_str()))
            .chain(self.objects.iter().map(|o| o.0.as_str()))
        {
            if n.is_empty() || n.contains('/') {
                return Err(BuildError::BadName {
                    name: n.to_string(),
                });
            }
            top.push(n);
        }
        top.sort_unstable();
        if let Some(w) = top.windows(2).find(|w| w[0] == w[1]) {
            return Err(BuildError::DuplicateName {
                name: w[0].to_string(),
            });
        }

        let mut bodies = Vec::new();
        let mut robots = Vec::new();
        // Per body, for the static rules: (robot, frame) with the hand on the tip frame.
        let mut on_frame: Vec<Option<(usize, usize)>> = Vec::new();
        for (r, pr) in self.robots.iter().enumerate() {
            if pr.frames == 0 {
                return Err(BuildError::NoFrames {
                    robot: pr.name.clone(),
                });
            }
            let tip = pr.frames - 1;
            for (s, ls) in pr.shapes.iter().enumerate() {
                if ls.frame >= pr.frames {
                    return Err(BuildError::FrameOutOfRange {
                        robot: pr.name.clone(),
                        link: ls.link.clone(),
                        frame: ls.frame,
                        frames: pr.frames,
                    });
                }
                bodies.push(Body {
                    id: BodyId::Link { robot: r, shape: s },
                    name: format!("{}/{}", pr.name, ls.link),
                    robot: Some(r),
                    grips_for: (ls.frame == tip).then_some(r),
                    mount: Mount::Frame {
                        robot: r,
                        frame: ls.frame,
                    },
                    local: ls.local,
                    shape: ls.shape.clone(),
                    fixed_aabb: None,
                    sphere_centre: Point::origin(),
                    sphere_radius: 0.0,
                    cylinder: None,
                    hull_aabb: None,
                    hull: None,
                    capsule: None,
                    half_extents: None,
                });
                on_frame.push(Some((r, ls.frame)));
            }
            if let Some(hand) = &pr.hand {
                for (s, solid) in hand.solids.iter().enumerate() {
                    bodies.push(Body {
                        id: BodyId::Hand { robot: r, solid: s },
                        name: format!("{}/{}", pr.name, hand.name),
                        robot: Some(r),
                        grips_for: Some(r),
                        mount: Mount::Frame {
                            robot: r,
                            frame: tip,
                        },
                        local: pr.tip_offset * solid.local,
                        shape: solid.shape.clone(),
                        fixed_aabb: None,
                        sphere_centre: Point::origin(),
                        sphere_radius: 0.0,
                        cylinder: None,
                        hull_aabb: None,
                        hull: None,
                        capsule: None,
                        half_extents: None,
                    });
                    on_frame.push(Some((r, tip)));
                }
            }
            robots.push(RobotInfo {
                name: pr.name.clone(),
                frames: pr.frames,
                tip_offset: pr.tip_offset,
            });
        }
        let mut fixed = Vec::new();
        for (i, (name, pose, shape)) in self.fixed.into_iter().enumerate() {
            let aabb = shape.compute_aabb(&pose);
            if !aabb_finite(&aabb) {
                return Err(BuildError::NonFinitePose { name });
            }
            fixed.push(bodies.len());
            bodies.push(Body {
                id: BodyId::Fixed(i),
                name,
                robot: None,
                grips_for: None,
                mount: Mount::Fixed,
                local: pose,
                shape,
                fixed_aabb: Some(aabb),
                sphere_centre: Point::origin(),
                sphere_radius: 0.0,
                cylinder: None,
                hull_aabb: None,
                hull: None,
                capsule: None,
                half_extents: None,
            });
            on_frame.push(None);
        }
        let mut objects = Vec::new();
        let mut object_names = Vec::new();
        for (i, (name, solids)) in self.objects.into_iter().enumerate() {
            objects.push((!solids.is_empty()).then_some(bodies.len()));
            for solid in solids {
                bodies.push(Body {
                    id: BodyId::Object(i),
                    name: name.clone(),
                    robot: None,
                    grips_for: None,
                    mount: Mount::Object { object: i },
                    local: solid.local,
                    shape: solid.shape,
                    fixed_aabb: None,
                    sphere_centre: Point::origin(),
                    sphere_radius: 0.0,
                    cylinder: None,
                    hull_aabb: None,
                    hull: None,
                    capsule: None,
                    half_extents: None,
                });
                on_frame.push(None);
            }
            object_names.push(name);
        }

        for b in &mut bodies {
            let sphere = b.shape.compute_local_bounding_sphere();
            b.sphere_centre = sphere.center;
            b.sphere_radius = sphere.radius;
            b.cylinder = b.shape.as_cylinder().map(|c| (c.half_height, c.radius));
            b.hull_aabb = b.shape.as_convex_polyhedron().map(|c| c.local_aabb());
            b.hull = b
                .shape
                .as_convex_polyhedron()
                .and_then(super::hull::HullSupport::new)
                .map(std::sync::Arc::new);
            b.capsule = super::capsule::Capsule::of_shape(b.shape.as_ref());
            b.half_extents = b.shape.as_cuboid().map(|c| c.half_extents);
        }

        let n = bodies.len();
        let mut allowed = BitMatrix::new(n);
        for i in 0..n {
            for j in (i + 1)..n {
                let both_fixed = matches!(bodies[i].mount, Mount::Fixed)
                    && matches!(bodies[j].mount, Mount::Fixed);
                let same_body = match (on_frame[i], on_frame[j]) {
                    (Some((ra, fa)), Some((rb, fb))) if ra == rb => {
                        let pr = &self.robots[ra];
                        pr.adjacent[fa * pr.frames + fb]
                    }
                    _ => false,
                };
                if both_fixed || same_body {
                    allowed.set(i, j);
                }
            }
        }
        // Link pairs per robot: each robot's link bodies by link name, so a list of pairs
        // costs the bodies of its links, not a scan of every body per pair.
        if !self.allowed_links.is_empty() {
            let mut by_link: std::collections::HashMap<(usize, &str), Vec<usize>> =
                std::collections::HashMap::new();
            for (i, b) in bodies.iter().enumerate() {
                if let BodyId::Link { robot, shape } = b.id {
                    let link = self.robots[robot].shapes[shape].link.as_str();
                    by_link.entry((robot, link)).or_default().push(i);
                }
            }
            for (robot, a, b) in &self.allowed_links {
                let (Some(ia), Some(ib)) = (
                    by_link.get(&(*robot, a.as_str())),
                    by_link.get(&(*robot, b.as_str())),
                ) else {
                    continue;
                };
                for &i in ia {
                    for &j in ib {
                        if i != j {
                            allowed.set(i, j);
                        }
                    }
                }
            }
        }
        for (a, b) in &self.allowed {
            let ia = matching(&bodies, &robots, a)?;
            let ib = matching(&bodies, &robots, b)?;
            for &i in &ia {
                for &j in &ib {
                    if i != j {
                        allowed.set(i, j);
                    }
                }
            }
        }

        Ok(CollisionWorld {
            bodies,
            robots,
            fixed,
            objects,
            object_names,
            allowed,
        })
    }
}

/// The bodies a name in an allowed pair stands for.
fn matching(bodies: &[Body], robots: &[RobotInfo], name: &str) -> Result<Vec<usize>, BuildError> {
    let robot = robots.iter().position(|r| r.name == name);
    let found: Vec<usize> = bodies
        .iter()
        .enumerate()
        .filter(|(_, b)| b.name == name || (robot.is_some() && b.robot == robot))
        .map(|(i, _)| i)
        .collect();
    if found.is_empty() && robot.is_none() {
        return Err(BuildError::UnknownName {
            name: name.to_string(),
        });
    }
    Ok(found)
}

/// A symmetric boolean matrix over body indices (one bit per ordered pair; both halves are
/// set so a lookup needs no ordering).
#[derive(Clone, Debug)]
pub(super) struct BitMatrix {
    n: usize,
    words: Vec<u64>,
}

impl BitMatrix {
    fn new(n: usize) -> Self {
        BitMatrix {
            n,
            words: vec![0; (n * n).div_ceil(64)],
        }
    }

    fn set(&mut self, i: usize, j: usize) {
        for k in [i * self.n + j, j * self.n + i] {
            self.words[k / 64] |= 1 << (k % 64);
        }
    }

    #[inline]
    pub(super) fn get(&self, i: usize, j: usize) -> bool {
        let k = i * self.n + j;
        self.words[k / 64] & (1 << (k % 64)) != 0
    }
}
