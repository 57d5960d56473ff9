//! The collision world of a cell: robot links, the hands on their tips, fixed surfaces and
//! obstacles, and the objects, checked against each other in one call.
//!
//! # Model
//!
//! A [`CollisionWorld`] is built once per cell by a [`CollisionWorldBuilder`] and never
//! changes afterwards; everything that moves is handed in per query as a
//! [`Configuration`] (the world poses of every robot's frames, as `Robot::fk_frames`
//! gives them, and the pose and holders of every object). A hand's solids are stored
//! composed with the robot's tip offset, so they move with the last frame like any link
//! and a state cannot give a tip that disagrees with its frames. The world is therefore
//! immutable and `Send + Sync`, and each thread keeps its own [`CollisionScratch`] for
//! the buffers a query needs, so rayon workers check states in parallel without locks and
//! without allocating per call.
//!
//! Every solid is a *body* ([`BodyId`]) with a human name for reports:
//! `left/lwr_link_4` (robot `left`, link `lwr_link_4`), `left/softhand` (a solid of the
//! hand on robot `left`'s tip), `table` (a fixed body), `cylinder` (an object).
//!
//! # Broad phase
//!
//! Sort and sweep: the world-space AABB of every body is computed (fixed bodies once, at
//! build), the bodies are sorted by the AABB's lower bound along the axis on which the
//! AABB centres spread the most in this state, and a sweep visits only pairs whose
//! intervals overlap on that axis; the other two axes are compared next, then the
//! allowed-collision rules, then the bodies' bounding spheres (which reject most of the
//! near-joint pairs of tilted cylinders whose AABBs overlap), and only the surviving pairs
//! reach the exact test (`parry3d_f64::query::intersection_test`). A cell has tens of
//! bodies, so a sort per query costs less than keeping a BVH up to date, and choosing the
//! axis per state keeps the sweep selective whether the arms stand side by side along x
//! or along y. Cylinders (every LWR link) get their AABB in closed form: parry's generic
//! support-map AABB was 70% of a check's time.
//!
//! # Allowed pairs
//!
//! A pair is never tested when:
//! - both bodies are fixed: the cell's furniture cannot move, so whatever it touches it
//!   touches in every state (a bin standing on a table is not a collision);
//! - both are links of one robot on the same frame or on frames joined by a joint
//!   (`adjacent` when the robot is added): adjacent links overlap at their joint by
//!   construction;
//! - one is a hand solid and the other a hand solid or a link of the same robot on the tip
//!   frame or a frame adjacent to it: the hand is bolted onto the tip frame, so it is
//!   treated as part of that frame's body;
//! - the cell allowed it by name ([`CollisionWorldBuilder::allow`]), e.g. an arm base
//!   standing on a bench;
//! - and, per state, an object and one of its holders ([`ObjectState::holders`]): an
//!   object held by a robot touches that robot's hand solids and its tip frame's links
//!   (for a conveyor, the carriage it rests on), never anything further up the arm; an
//!   object resting on a fixed surface touches that surface. A handoff lists both robots.
//!
//! Resting contact is handled by allowing the pair rather than by testing with a
//! negative margin: a rest pose puts the object's face exactly on the surface's top face,
//! where the exact test's answer is numerical noise, and no margin would be right for
//! both a box (face contact) and a tilted shape. The cost is that an object sunk into its
//! own support is not reported; its pose comes from the support and the resting pose, so
//! that is a modelling error for the compiler to catch, not a planning state.
//!
//! Two limits of the exact test are worth knowing: triangle meshes are surfaces to parry,
//! so a body entirely inside a mesh (without touching its triangles) is not reported; and
//! a pair of shapes parry has no algorithm for is an error
//! ([`CollisionError::Unsupported`]), never silently collision-free.

use std::fmt;

use parry3d_f64::bounding_volume::Aabb;
use parry3d_f64::query;
use parry3d_f64::shape::SharedShape;

use crate::math::{Iso, Point, Vec3};
use crate::robot::{LinkShape, Robot};

/// One solid of the collision world.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum BodyId {
    /// Shape `shape` of robot `robot`'s link list (the robot's `shapes()` order).
    Link {
        /// Robot index, in the order robots were added.
        robot: usize,
        /// Index into the robot's shape list.
        shape: usize,
    },
    /// Solid `solid` of the hand on robot `robot`'s tip.
    Hand {
        /// Robot index.
        robot: usize,
        /// Index into the hand's solids.
        solid: usize,
    },
    /// A fixed body (surface or obstacle), in the order added.
    Fixed(usize),
    /// An object, in the order added (any of its solids: an object is one body to
    /// reports, whatever it is made of).
    Object(usize),
}

/// A shape placed in a frame (a hand solid in the hand frame, for instance).
#[derive(Clone, Debug)]
pub struct Solid {
    /// Pose of the shape in the frame.
    pub local: Iso,
    /// The shape.
    pub shape: SharedShape,
}

/// The hand mounted on a robot's tip: its kind's name (for reports) and its solids in the
/// hand frame, which is the robot's tip link (`frames[n] * tip_offset`).
#[derive(Clone, Debug)]
pub struct Hand {
    /// Name of the hand kind, e.g. `softhand`; solids are reported as `robot/name`.
    pub name: String,
    /// Collision solids in the hand frame.
    pub solids: Vec<Solid>,
}

/// Who holds or supports an object in a state.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Holder {
    /// Robot `i`: the object may touch its hand's solids and the links on its last frame
    /// (the flange, or a conveyor's carriage), nothing further up the chain.
    Robot(usize),
    /// Fixed body `i` (the surface the object rests on).
    Fixed(usize),
}

/// Up to [`Holders::CAPACITY`] holders of one object, stored inline so a state costs no
/// allocation. Two cover every case of the method (one holder; a handoff, two hands; a
/// pick or place, a hand and the surface); the third is slack.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct Holders {
    items: [Option<Holder>; Holders::CAPACITY],
}

impl Holders {
    /// How many holders fit.
    pub const CAPACITY: usize = 3;

    /// No holder (an object lying free, e.g. a start pose given as a world pose).
    pub const NONE: Holders = Holders {
        items: [None; Holders::CAPACITY],
    };

    /// One holder.
    pub fn one(h: Holder) -> Holders {
        Holders::NONE.with(h)
    }

    /// These holders plus `h`. Adding a holder already present, or more than
    /// [`Holders::CAPACITY`], changes nothing.
    pub fn with(mut self, h: Holder) -> Holders {
        if self.contains(h) {
            return self;
        }
        if let Some(slot) = self.items.iter_mut().find(|s| s.is_none()) {
            *slot = Some(h);
        }
        self
    }

    /// Whether `h` is one of them.
    pub fn contains(&self, h: Holder) -> bool {
        self.items.contains(&Some(h))
    }

    /// The holders.
    pub fn iter(&self) -> impl Iterator<Item = Holder> + '_ {
        self.items.iter().flatten().copied()
    }
}

/// The moving part of a state for one object.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ObjectState {
    /// World pose of the object frame; `None` leaves the object out of the check (not in
    /// the cell yet, or irrelevant to the question asked).
    pub pose: Option<Iso>,
    /// Who holds or supports it; the object is allowed to touch them.
    pub holders: Holders,
}

impl ObjectState {
    /// Not in the scene.
    pub fn absent() -> ObjectState {
        ObjectState {
            pose: None,
            holders: Holders::NONE,
        }
    }

    /// At `pose`, touching nothing on purpose.
    pub fn free(pose: Iso) -> ObjectState {
        ObjectState {
            pose: Some(pose),
            holders: Holders::NONE,
        }
    }

    /// Resting at `pose` on fixed body `surface`.
    pub fn resting(pose: Iso, surface: usize) -> ObjectState {
        ObjectState {
            pose: Some(pose),
            holders: Holders::one(Holder::Fixed(surface)),
        }
    }

    /// Held by robot `robot` whose tip is at `tip`, in grasp `grasp` (the object pose in
    /// the hand frame): the object is at `tip * grasp`.
    pub fn held(robot: usize, tip: &Iso, grasp: &Iso) -> ObjectState {
        ObjectState {
            pose: Some(tip * grasp),
            holders: Holders::one(Holder::Robot(robot)),
        }
    }

    /// The same object, also touched by `h` (the second hand of a handoff, the surface
    /// of a pick).
    pub fn also_held_by(mut self, h: Holder) -> ObjectState {
        self.holders = self.holders.with(h);
        self
    }
}

/// A state to check, robots and objects in the order they were added to the world.
#[derive(Clone, Copy, Debug)]
pub struct Configuration<'a> {
    /// Per robot, the world poses of its frames `0..=n` (what `Robot::fk_frames` gives
    /// for the robot's base placement and joint values).
    pub robots: &'a [&'a [Iso]],
    /// Per object.
    pub objects: &'a [ObjectState],
}

/// Two bodies that intersect, `a < b` (so a pair has one spelling). Names:
/// [`CollisionWorld::name`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Collision {
    /// One body.
    pub a: BodyId,
    /// The other.
    pub b: BodyId,
}

/// The closest non-allowed pair found by [`CollisionWorld::clearance`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Proximity {
    /// One body.
    pub a: BodyId,
    /// The other.
    pub b: BodyId,
    /// Their distance in metres; 0 when they intersect.
    pub distance: f64,
}

/// Why a world cannot be built.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum BuildError {
    /// Two robots, fixed bodies or objects share a name, so reports and allowed pairs
    /// would be ambiguous.
    DuplicateName {
        /// The name.
        name: String,
    },
    /// A name is empty or contains `/`, which separates a robot from its link in reports.
    BadName {
        /// The name.
        name: String,
    },
    /// An allowed pair names no body and no robot.
    UnknownName {
        /// The name.
        name: String,
    },
    /// A robot's link shape is attached to a frame the robot does not have.
    FrameOutOfRange {
        /// Robot name.
        robot: String,
        /// Link name.
        link: String,
        /// The frame index.
        frame: usize,
        /// The robot's number of frames.
        frames: usize,
    },
    /// A robot with no frame at all (it needs at least its base frame).
    NoFrames {
        /// Robot name.
        robot: String,
    },
    /// A fixed body's pose is not finite.
    NonFinitePose {
        /// Body name.
        name: String,
    },
}

impl fmt::Display for BuildError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            BuildError::DuplicateName { name } => {
                write!(f, "two bodies of the collision world are named `{name}`")
            }
            BuildError::BadName { name } => write!(
                f,
                "`{name}` cannot name a body of the collision world (empty, or contains `/`)"
            ),
            BuildError::UnknownName { name } => write!(
                f,
                "the allowed collision names `{name}`, which is no body or robot of the cell"
            ),
            BuildError::FrameOutOfRange {
                robot,
                link,
                frame,
                frames,
            } => write!(
                f,
                "robot `{robot}`: link `{link}` is on frame {frame}, but the robot has {frames} frames"
            ),
            BuildError::NoFrames { robot } => write!(f, "robot `{robot}` has no frames"),
            BuildError::NonFinitePose { name } => {
                write!(f, "the pose of `{name}` is not finite")
            }
        }
    }
}

impl std::error::Error for BuildError {}

/// Why a state cannot be checked. These are caller mistakes or numerical failures,
/// never "collision" or "free".
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum CollisionError {
    /// The configuration does not list one state per robot.
    RobotCount {
        /// Robots in the world.
        expected: usize,
        /// Robot states given.
        found: usize,
    },
    /// A robot state does not have one pose per frame.
    FrameCount {
        /// Robot name.
        robot: String,
        /// Frames of the robot.
        expected: usize,
        /// Poses given.
        found: usize,
    },
    /// The configuration does not list one state per object.
    ObjectCount {
        /// Objects in the world.
        expected: usize,
        /// Object states given.
        found: usize,
    },
    /// An object's holder is no robot or fixed body of the world.
    UnknownHolder {
        /// Object name.
        object: String,
        /// The holder.
        holder: Holder,
    },
    /// A body's pose is not finite (NaN joint values, for instance), so it cannot be
    /// placed; reported rather than treated as collision-free.
    NonFinite {
        /// Body name.
        body: String,
    },
    /// parry has no intersection algorithm for this pair of shapes.
    Unsupported {
        /// Body name.
        a: String,
        /// Body name.
        b: String,
    },
}

impl fmt::Display for CollisionError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            CollisionError::RobotCount { expected, found } => write!(
                f,
                "collision check: {found} robot states given, the cell has {expected} robots"
            ),
            CollisionError::FrameCount {
                robot,
                expected,
                found,
            } => write!(
                f,
                "collision check: robot `{robot}` has {expected} frames, {found} poses given"
            ),
            CollisionError::ObjectCount { expected, found } => write!(
                f,
                "collision check: {found} object states given, the cell has {expected} objects"
            ),
            CollisionError::UnknownHolder { object, holder } => write!(
                f,
                "collision check: object `{object}` is held by {holder:?}, which is not in the cell"
            ),
            CollisionError::NonFinite { body } => {
                write!(f, "collision check: the pose of `{body}` is not finite")
            }
            CollisionError::Unsupported { a, b } => write!(
                f,
                "collision check: no intersection test between the shapes of `{a}` and `{b}`"
            ),
        }
    }
}

impl std::error::Error for CollisionError {}

/// Where a body's pose comes from.
#[derive(Clone, Copy, Debug)]
enum Mount {
    /// `frames[frame] * local` of robot `robot`.
    Frame { robot: usize, frame: usize },
    /// `local` is the world pose.
    Fixed,
    /// `pose * local` of object `object`.
    Object { object: usize },
}

#[derive(Clone, Debug)]
struct Body {
    id: BodyId,
    name: String,
    /// The robot this body belongs to (link or hand solid), for allowed names.
    robot: Option<usize>,
    /// A held object may touch this body when its holders include this robot: the hand's
    /// solids and the tip frame's links.
    grips_for: Option<usize>,
    mount: Mount,
    local: Iso,
    shape: SharedShape,
    /// World AABB of a fixed body, computed once.
    fixed_aabb: Option<Aabb>,
    /// Bounding sphere in the body's frame (`pose`, i.e. after `local`).
    sphere_centre: Point,
    sphere_radius: f64,
    /// Half height and radius when the shape is a cylinder, whose AABB is computed in
    /// closed form: parry's generic one takes six support-point queries, which made it
    /// most of the cost of a whole check.
    cylinder: Option<(f64, f64)>,
}

#[derive(Clone, Debug)]
struct RobotInfo {
    name: String,
    frames: usize,
    tip_offset: Iso,
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
}

impl CollisionWorldBuilder {
    /// An empty builder.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds a robot instance named `name` (the cell's arm name, e.g. `left`) with its
    /// links as loaded from the URDF and the hand on its tip, and returns its index (the
    /// index of its frames in a [`Configuration`]).
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
    /// index (for [`Holder::Fixed`]).
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
    /// (of its [`ObjectState`] in a [`Configuration`]). An object without solids (an
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
struct BitMatrix {
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
    fn get(&self, i: usize, j: usize) -> bool {
        let k = i * self.n + j;
        self.words[k / 64] & (1 << (k % 64)) != 0
    }
}

/// Buffers of one query, reused between calls (one per thread).
#[derive(Clone, Debug, Default)]
pub struct CollisionScratch {
    poses: Vec<Iso>,
    aabbs: Vec<Aabb>,
    /// World centres of the bodies' bounding spheres.
    centres: Vec<Point>,
    order: Vec<u32>,
    /// How much the AABBs and spheres were grown (half a clearance cutoff).
    margin: f64,
}

/// The collision world of a cell. Immutable after [`CollisionWorldBuilder::build`];
/// `Send + Sync`, so one world serves every thread.
#[derive(Clone, Debug)]
pub struct CollisionWorld {
    /// Robots' links and hands (robot by robot), then fixed bodies, then objects.
    bodies: Vec<Body>,
    robots: Vec<RobotInfo>,
    /// Body index of each fixed body.
    fixed: Vec<usize>,
    /// Body index of each object's first solid (`None`: no solids).
    objects: Vec<Option<usize>>,
    object_names: Vec<String>,
    allowed: BitMatrix,
}

/// What the sweep does with a candidate pair.
enum Visit {
    Continue,
    Stop,
}

impl CollisionWorld {
    /// The report name of a body (`left/lwr_link_4`, `left/softhand`, `table`).
    pub fn name(&self, id: BodyId) -> &str {
        if let BodyId::Object(i) = id {
            return self.object_names.get(i).map_or("?", String::as_str);
        }
        self.index(id)
            .map(|i| self.bodies[i].name.as_str())
            .unwrap_or("?")
    }

    /// Both names of a collision, `a` first.
    pub fn names(&self, c: &Collision) -> (&str, &str) {
        (self.name(c.a), self.name(c.b))
    }

    /// "`a` and `b`", for messages.
    pub fn describe(&self, c: &Collision) -> String {
        let (a, b) = self.names(c);
        format!("`{a}` and `{b}`")
    }

    /// Every solid with its body id and name (an object of several solids appears once
    /// per solid).
    pub fn bodies(&self) -> impl Iterator<Item = (BodyId, &str)> + '_ {
        self.bodies.iter().map(|b| (b.id, b.name.as_str()))
    }

    /// Number of robots (the length a [`Configuration`]'s `robots` must have).
    pub fn robot_count(&self) -> usize {
        self.robots.len()
    }

    /// Number of frames of robot `robot` (the length of its frame list in a
    /// [`Configuration`]).
    pub fn frame_count(&self, robot: usize) -> Option<usize> {
        self.robots.get(robot).map(|r| r.frames)
    }

    /// The world pose of robot `robot`'s tip (its hand frame) for its frame poses
    /// `frames`: where a held object's grasp is applied ([`ObjectState::held`]).
    pub fn tip(&self, robot: usize, frames: &[Iso]) -> Option<Iso> {
        let info = self.robots.get(robot)?;
        (frames.len() == info.frames).then(|| frames[info.frames - 1] * info.tip_offset)
    }

    /// Number of objects (the length a [`Configuration`]'s `objects` must have).
    pub fn object_count(&self) -> usize {
        self.objects.len()
    }

    /// Whether `a` and `b` are never tested (the static rules and the cell's allowed
    /// pairs; the per-state holder rule is not included).
    pub fn is_allowed(&self, a: BodyId, b: BodyId) -> bool {
        match (self.index(a), self.index(b)) {
            (Some(i), Some(j)) => i == j || self.allowed.get(i, j),
            _ => false,
        }
    }

    fn index(&self, id: BodyId) -> Option<usize> {
        match id {
            BodyId::Fixed(i) => self.fixed.get(i).copied(),
            BodyId::Object(i) => self.objects.get(i).copied().flatten(),
            // Robot bodies are few; a scan keeps the world free of per-robot offsets
            // that would have to be kept in step with the body list.
            _ => self.bodies.iter().position(|b| b.id == id),
        }
    }

    /// The first intersecting pair found in `state`, or `None` when it is collision-free.
    /// Which pair is found first depends on the sweep order; use
    /// [`all_collisions`](Self::all_collisions) for a complete, ordered report.
    pub fn first_collision(
        &self,
        state: &Configuration<'_>,
        scratch: &mut CollisionScratch,
    ) -> Result<Option<Collision>, CollisionError> {
        self.place(state, scratch, 0.0)?;
        let mut found = None;
        self.sweep(state, scratch, |i, j, scratch| {
            if self.intersect(i, j, scratch)? {
                found = Some(self.collision(i, j));
                return Ok(Visit::Stop);
            }
            Ok(Visit::Continue)
        })?;
        Ok(found)
    }

    /// Whether `state` is collision-free.
    pub fn is_free(
        &self,
        state: &Configuration<'_>,
        scratch: &mut CollisionScratch,
    ) -> Result<bool, CollisionError> {
        Ok(self.first_collision(state, scratch)?.is_none())
    }

    /// Every intersecting pair in `state`, written to `out` (cleared first) sorted, so
    /// reports are deterministic.
    pub fn all_collisions(
        &self,
        state: &Configuration<'_>,
        scratch: &mut CollisionScratch,
        out: &mut Vec<Collision>,
    ) -> Result<(), CollisionError> {
        out.clear();
        self.place(state, scratch, 0.0)?;
        self.sweep(state, scratch, |i, j, scratch| {
            if self.intersect(i, j, scratch)? {
                out.push(self.collision(i, j));
            }
            Ok(Visit::Continue)
        })?;
        out.sort_unstable();
        // An object of several solids is one body to reports.
        out.dedup();
        Ok(())
    }

    /// The closest pair that is not allowed to touch, if any is closer than `cutoff`
    /// metres (pairs farther apart are skipped by the broad phase, so a small cutoff keeps
    /// this nearly as cheap as [`first_collision`](Self::first_collision)). An
    /// intersecting pair has distance 0. Ties go to the smaller pair (`a`, `b`), so the answer does
    /// not depend on the sweep order.
    pub fn clearance(
        &self,
        state: &Configuration<'_>,
        scratch: &mut CollisionScratch,
        cutoff: f64,
    ) -> Result<Option<Proximity>, CollisionError> {
        let cutoff = if cutoff.is_finite() {
            cutoff.max(0.0)
        } else {
            0.0
        };
        self.place(state, scratch, cutoff / 2.0)?;
        let mut best: Option<(f64, Collision)> = None;
        self.sweep(state, scratch, |i, j, scratch| {
            let (bi, bj) = (&self.bodies[i], &self.bodies[j]);
            let d = query::distance(
                &scratch.poses[i],
                bi.shape.as_ref(),
                &scratch.poses[j],
                bj.shape.as_ref(),
            )
            .map_err(|_| self.unsupported(i, j))?;
            let pair = self.collision(i, j);
            if d <= cutoff && best.is_none_or(|(bd, bp)| d < bd || (d == bd && pair < bp)) {
                best = Some((d, pair));
            }
            Ok(Visit::Continue)
        })?;
        Ok(best.map(|(distance, pair)| Proximity {
            a: pair.a,
            b: pair.b,
            distance,
        }))
    }

    fn collision(&self, i: usize, j: usize) -> Collision {
        let (a, b) = (self.bodies[i].id, self.bodies[j].id);
        Collision {
            a: a.min(b),
            b: a.max(b),
        }
    }

    fn unsupported(&self, i: usize, j: usize) -> CollisionError {
        CollisionError::Unsupported {
            a: self.bodies[i].name.clone(),
            b: self.bodies[j].name.clone(),
        }
    }

    fn intersect(
        &self,
        i: usize,
        j: usize,
        scratch: &CollisionScratch,
    ) -> Result<bool, CollisionError> {
        query::intersection_test(
            &scratch.poses[i],
            self.bodies[i].shape.as_ref(),
            &scratch.poses[j],
            self.bodies[j].shape.as_ref(),
        )
        .map_err(|_| self.unsupported(i, j))
    }

    /// Checks the state's shape, then computes every present body's world pose and AABB
    /// (loosened by `margin`) into the scratch, and the list of present bodies.
    fn place(
        &self,
        state: &Configuration<'_>,
        scratch: &mut CollisionScratch,
        margin: f64,
    ) -> Result<(), CollisionError> {
        if state.robots.len() != self.robots.len() {
            return Err(CollisionError::RobotCount {
                expected: self.robots.len(),
                found: state.robots.len(),
            });
        }
        for (info, rs) in self.robots.iter().zip(state.robots) {
            if rs.len() != info.frames {
                return Err(CollisionError::FrameCount {
                    robot: info.name.clone(),
                    expected: info.frames,
                    found: rs.len(),
                });
            }
        }
        if state.objects.len() != self.objects.len() {
            return Err(CollisionError::ObjectCount {
                expected: self.objects.len(),
                found: state.objects.len(),
            });
        }
        for (o, os) in state.objects.iter().enumerate() {
            for h in os.holders.iter() {
                let known = match h {
                    Holder::Robot(r) => r < self.robots.len(),
                    Holder::Fixed(f) => f < self.fixed.len(),
                };
                if !known {
                    return Err(CollisionError::UnknownHolder {
                        object: self.object_names[o].clone(),
                        holder: h,
                    });
                }
            }
        }

        let n = self.bodies.len();
        scratch.poses.clear();
        scratch.aabbs.clear();
        scratch.centres.clear();
        scratch.order.clear();
        scratch.poses.reserve(n);
        scratch.aabbs.reserve(n);
        scratch.centres.reserve(n);
        scratch.order.reserve(n);
        scratch.margin = margin;
        for (i, b) in self.bodies.iter().enumerate() {
            let pose = match b.mount {
                Mount::Frame { robot, frame } => state.robots[robot][frame] * b.local,
                Mount::Fixed => b.local,
                Mount::Object { object } => match state.objects[object].pose {
                    Some(p) => p * b.local,
                    None => {
                        // Absent: kept in the buffers (indices stay body indices) but
                        // not in the sweep order.
                        scratch.poses.push(b.local);
                        scratch.aabbs.push(Aabb::new_invalid());
                        scratch.centres.push(Point::origin());
                        continue;
                    }
                },
            };
            let mut aabb = match (b.fixed_aabb, b.cylinder) {
                (Some(a), _) => a,
                (None, Some((h, r))) => cylinder_aabb(&pose, h, r),
                (None, None) => b.shape.compute_aabb(&pose),
            };
            if !aabb_finite(&aabb) {
                return Err(CollisionError::NonFinite {
                    body: b.name.clone(),
                });
            }
            if margin > 0.0 {
                aabb.mins -= Vec3::repeat(margin);
                aabb.maxs += Vec3::repeat(margin);
            }
            scratch.centres.push(pose * b.sphere_centre);
            scratch.poses.push(pose);
            scratch.aabbs.push(aabb);
            scratch.order.push(i as u32);
        }
        Ok(())
    }

    /// Sort and sweep over the placed bodies; calls `visit` for every pair whose AABBs
    /// overlap and that is not allowed, until it says stop.
    fn sweep(
        &self,
        state: &Configuration<'_>,
        scratch: &mut CollisionScratch,
        mut visit: impl FnMut(usize, usize, &CollisionScratch) -> Result<Visit, CollisionError>,
    ) -> Result<(), CollisionError> {
        let axis = spread_axis(&scratch.aabbs, &scratch.order);
        let (o1, o2) = ((axis + 1) % 3, (axis + 2) % 3);
        {
            let aabbs = &scratch.aabbs;
            scratch.order.sort_unstable_by(|&a, &b| {
                aabbs[a as usize].mins[axis].total_cmp(&aabbs[b as usize].mins[axis])
            });
        }
        let scratch = &*scratch;
        let order = &scratch.order;
        for (k, &i) in order.iter().enumerate() {
            let i = i as usize;
            let ai = &scratch.aabbs[i];
            for &j in &order[k + 1..] {
                let j = j as usize;
                let aj = &scratch.aabbs[j];
                if aj.mins[axis] > ai.maxs[axis] {
                    break;
                }
                if aj.mins[o1] > ai.maxs[o1]
                    || ai.mins[o1] > aj.maxs[o1]
                    || aj.mins[o2] > ai.maxs[o2]
                    || ai.mins[o2] > aj.maxs[o2]
                {
                    continue;
                }
                if self.allowed.get(i, j) || self.held_pair(state, i, j) {
                    continue;
                }
                // Bounding spheres last: links are long cylinders whose AABBs overlap
                // near every joint once tilted, and this rejects most of those pairs for
                // the price of a distance instead of a GJK run.
                let reach = self.bodies[i].sphere_radius
                    + self.bodies[j].sphere_radius
                    + 2.0 * scratch.margin;
                if (scratch.centres[i] - scratch.centres[j]).norm_squared() > reach * reach {
                    continue;
                }
                // Exact tests always see the pair in body order, so a borderline answer
                // (touching, a distance's last bits) does not depend on the sweep axis.
                if let Visit::Stop = visit(i.min(j), i.max(j), scratch)? {
                    return Ok(());
                }
            }
        }
        Ok(())
    }

    /// The per-state rule: an object may touch its holders.
    #[inline]
    fn held_pair(&self, state: &Configuration<'_>, i: usize, j: usize) -> bool {
        let check = |o: &Body, other: &Body| -> bool {
            let Mount::Object { object } = o.mount else {
                return false;
            };
            let holders = &state.objects[object].holders;
            match other.id {
                BodyId::Fixed(f) => holders.contains(Holder::Fixed(f)),
                _ => other
                    .grips_for
                    .is_some_and(|r| holders.contains(Holder::Robot(r))),
            }
        };
        let (bi, bj) = (&self.bodies[i], &self.bodies[j]);
        check(bi, bj) || check(bj, bi)
    }
}

/// The exact AABB of a parry cylinder (axis along its local y) at `pose`: along world
/// axis i it reaches `h |a_i| + r sqrt(1 - a_i²)` from its centre, for the unit axis `a`.
fn cylinder_aabb(pose: &Iso, half_height: f64, radius: f64) -> Aabb {
    let a = pose.rotation * Vec3::y();
    let c = Point::from(pose.translation.vector);
    let e = Vec3::from_fn(|i, _| {
        half_height * a[i].abs() + radius * (1.0 - a[i] * a[i]).max(0.0).sqrt()
    });
    Aabb::new(c - e, c + e)
}

fn aabb_finite(a: &Aabb) -> bool {
    a.mins.iter().chain(a.maxs.iter()).all(|v| v.is_finite())
}

/// The axis along which the AABB centres of the listed bodies spread the most (largest
/// variance), so the sweep along it separates the most pairs.
fn spread_axis(aabbs: &[Aabb], order: &[u32]) -> usize {
    if order.len() < 2 {
        return 0;
    }
    let mut sum = Vec3::zeros();
    let mut sq = Vec3::zeros();
    for &i in order {
        let a = &aabbs[i as usize];
        let c = (a.mins.coords + a.maxs.coords) / 2.0;
        sum += c;
        sq += c.component_mul(&c);
    }
    let n = order.len() as f64;
    let var = sq / n - (sum / n).component_mul(&(sum / n));
    let mut axis = 0;
    for k in 1..3 {
        if var[k] > var[axis] {
            axis = k;
        }
    }
    axis
}

#[cfg(test)]
mod tests {
    //! The broad phase against brute force, and the closed-form cylinder AABB against
    //! parry's.

    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    fn random_pose(rng: &mut ChaCha8Rng, spread: f64) -> Iso {
        let t = Vec3::from_fn(|_, _| rng.random_range(-spread..spread));
        let axis = Vec3::from_fn(|_, _| rng.random_range(-1.0..1.0));
        Iso::new(t, axis * rng.random_range(0.0..3.0))
    }

    fn random_shape(rng: &mut ChaCha8Rng) -> SharedShape {
        let s: [f64; 3] = std::array::from_fn(|_| rng.random_range(0.02..0.3));
        match rng.random_range(0..3) {
            0 => SharedShape::ball(s[0]),
            1 => SharedShape::cuboid(s[0], s[1], s[2]),
            _ => SharedShape::cylinder(s[0], s[1]),
        }
    }

    #[test]
    fn cylinder_aabb_is_parrys() {
        let mut rng = ChaCha8Rng::seed_from_u64(1);
        for _ in 0..1000 {
            let pose = random_pose(&mut rng, 2.0);
            let (h, r) = (rng.random_range(0.01..1.0), rng.random_range(0.01..1.0));
            let ours = cylinder_aabb(&pose, h, r);
            let parry = SharedShape::cylinder(h, r).compute_aabb(&pose);
            assert!((ours.mins - parry.mins).norm() < 1e-9, "{ours:?} {parry:?}");
            assert!((ours.maxs - parry.maxs).norm() < 1e-9, "{ours:?} {parry:?}");
        }
    }

    /// Every pair, no broad phase: the reference for the sweep.
    fn brute_force(
        world: &CollisionWorld,
        state: &Configuration<'_>,
        cutoff: Option<f64>,
    ) -> (Vec<Collision>, Option<(f64, Collision)>) {
        let mut scratch = CollisionScratch::default();
        world.place(state, &mut scratch, 0.0).expect("well-formed");
        let mut hits = Vec::new();
        let mut best: Option<(f64, Collision)> = None;
        for i in 0..world.bodies.len() {
            for j in (i + 1)..world.bodies.len() {
                let present = |k: usize| match world.bodies[k].mount {
                    Mount::Object { object } => state.objects[object].pose.is_some(),
                    _ => true,
                };
                if !present(i)
                    || !present(j)
                    || world.allowed.get(i, j)
                    || world.held_pair(state, i, j)
                {
                    continue;
                }
                let (pi, pj) = (&scratch.poses[i], &scratch.poses[j]);
                let (si, sj) = (
                    world.bodies[i].shape.as_ref(),
                    world.bodies[j].shape.as_ref(),
                );
                let pair = world.collision(i, j);
                if query::intersection_test(pi, si, pj, sj).expect("supported") {
                    hits.push(pair);
                }
                if let Some(cutoff) = cutoff {
                    let d = query::distance(pi, si, pj, sj).expect("supported");
                    if d <= cutoff && best.is_none_or(|(bd, bp)| d < bd || (d == bd && pair < bp)) {
                        best = Some((d, pair));
                    }
                }
            }
        }
        hits.sort_unstable();
        hits.dedup();
        (hits, best)
    }

    #[test]
    fn sweep_finds_what_brute_force_finds() {
        let mut rng = ChaCha8Rng::seed_from_u64(2);
        let mut scratch = CollisionScratch::default();
        let mut out = Vec::new();
        let mut collisions_seen = 0;
        for _ in 0..200 {
            let mut b = CollisionWorldBuilder::new();
            // A four-frame chain with two solids per frame and a hand.
            let shapes = (0..8)
                .map(|k| LinkShape {
                    link: format!("link_{}", k / 2),
                    frame: k / 2,
                    local: random_pose(&mut rng, 0.2),
                    shape: random_shape(&mut rng),
                })
                .collect();
            let hand = Hand {
                name: "hand".into(),
                solids: (0..2)
                    .map(|_| Solid {
                        local: random_pose(&mut rng, 0.1),
                        shape: random_shape(&mut rng),
                    })
                    .collect(),
            };
            b.add_chain(
                "arm",
                4,
                random_pose(&mut rng, 0.1),
                shapes,
                |a, c| a.abs_diff(c) <= 1,
                Some(hand),
            );
            for k in 0..4 {
                b.add_fixed(
                    &format!("f{k}"),
                    random_pose(&mut rng, 1.0),
                    random_shape(&mut rng),
                );
            }
            for k in 0..6 {
                // Object 5 has no solids; the others one or two.
                let solids = (0..[1, 2, 1, 2, 1, 0][k])
                    .map(|_| Solid {
                        local: random_pose(&mut rng, 0.1),
                        shape: random_shape(&mut rng),
                    })
                    .collect();
                b.add_object(&format!("o{k}"), solids);
            }
            b.allow("o0", "arm");
            let world = b.build().expect("valid world");
            let frames: Vec<Iso> = (0..4).map(|_| random_pose(&mut rng, 1.0)).collect();
            let objects: Vec<ObjectState> = (0..6)
                .map(|k| {
                    let pose = random_pose(&mut rng, 1.0);
                    match k {
                        0 => ObjectState::absent(),
                        1 => ObjectState::held(0, &frames[3], &pose),
                        2 => ObjectState::resting(pose, 1).also_held_by(Holder::Robot(0)),
                        _ => ObjectState::free(pose),
                    }
                })
                .collect();
            let robots: [&[Iso]; 1] = [&frames];
            let state = Configuration {
                robots: &robots,
                objects: &objects,
            };
            let (expected, closest) = brute_force(&world, &state, Some(0.3));
            world
                .all_collisions(&state, &mut scratch, &mut out)
                .expect("well-formed");
            assert_eq!(out, expected);
            let first = world
                .first_collision(&state, &mut scratch)
                .expect("well-formed");
            assert_eq!(first.is_some(), !expected.is_empty());
            if let Some(c) = first {
                assert!(expected.contains(&c));
            }
            let near = world
                .clearance(&state, &mut scratch, 0.3)
                .expect("well-formed");
            assert_eq!(near.map(|p| (p.a, p.b)), closest.map(|(_, p)| (p.a, p.b)));
            if let (Some(p), Some((d, _))) = (near, closest) {
                assert_eq!(p.distance, d);
            }
            collisions_seen += expected.len();
        }
        // The scenes are dense enough to exercise both answers.
        assert!(collisions_seen > 100, "{collisions_seen}");
    }
}
