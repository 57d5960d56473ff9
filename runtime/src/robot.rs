//! A robot as the runtime sees it: one serial chain of movable joints from a base link to
//! a tip link, read from a URDF, with the collision solids carried by that chain.
//!
//! The data is deliberately flat (one array entry per movable joint, no tree, no locks):
//! forward kinematics is then a tight loop over a few arrays, and a [`Robot`] is plain
//! immutable data that is `Send + Sync`, so verification can share one model between
//! rayon workers without cloning it.
//!
//! Frames: frame 0 is the base link; frame `i` (1..=n) is the child link of movable joint
//! `i` (array index `i - 1`). Fixed joints never make a frame of their own: their
//! transforms are folded into the next joint's origin (or into the tip offset), and the
//! solids of links hanging off the chain through fixed joints only (a flange, a tool
//! plate) are attached to the frame they move with.

use std::fmt;

use cellc_schema::files::Files;
use cellc_urdf::{Description, Geometry, MeshPaths};
use parry3d_f64::shape::SharedShape;
use rand::Rng;

use crate::math::{Iso, Vec3};
use crate::mesh::{self, MeshError};

pub use cellc_urdf::{ChainError, JointError, JointKind, ParseError, Problem};

/// One collision solid of the robot, attached to a kinematic frame.
#[derive(Clone)]
pub struct LinkShape {
    /// The URDF link the solid belongs to.
    pub link: String,
    /// The frame it moves with (0 = base, `i` = child of movable joint `i`).
    pub frame: usize,
    /// Its pose in that frame (the URDF `<collision><origin>`, composed with any fixed
    /// joints between the frame's link and `link`, and with the turn that puts parry's
    /// y-aligned cylinders on URDF's z axis).
    pub local: Iso,
    /// The solid itself.
    pub shape: SharedShape,
}

impl fmt::Debug for LinkShape {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("LinkShape")
            .field("link", &self.link)
            .field("frame", &self.frame)
            .field("local", &self.local)
            .field("shape", &self.shape.shape_type())
            .finish()
    }
}

/// Why a URDF could not be turned into a [`Robot`].
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum RobotError {
    /// The URDF text is not a URDF the reader accepts.
    Parse(ParseError),
    /// The description is unsound: not one tree, or a value out of its domain (the first
    /// problem [`cellc_urdf::Description::problems`] finds).
    Unsound(Problem),
    /// The base or tip link is missing, or no chain of joints leads from one to the other.
    Chain(ChainError),
    /// A joint on the chain cannot be moved (its type, its axis or its limits).
    Joint(JointError),
    /// A mesh could not be read or turned into a convex solid.
    Mesh {
        /// The link whose collision uses the mesh.
        link: String,
        /// The mesh path as resolved (or as written, when it could not be resolved).
        path: String,
        /// What went wrong.
        reason: MeshError,
    },
    /// A collision primitive with impossible dimensions.
    UnsupportedGeometry {
        /// The link.
        link: String,
        /// The geometry as written.
        geometry: Geometry,
    },
}

impl From<ParseError> for RobotError {
    fn from(error: ParseError) -> RobotError {
        RobotError::Parse(error)
    }
}

impl From<ChainError> for RobotError {
    fn from(error: ChainError) -> RobotError {
        RobotError::Chain(error)
    }
}

impl From<JointError> for RobotError {
    fn from(error: JointError) -> RobotError {
        RobotError::Joint(error)
    }
}

impl fmt::Display for RobotError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RobotError::Parse(error) => write!(f, "the URDF does not parse: {error}"),
            RobotError::Unsound(problem) => write!(f, "{problem}"),
            RobotError::Chain(error) => write!(f, "{error}"),
            RobotError::Joint(error) => write!(f, "{error}"),
            RobotError::Mesh { link, path, reason } => {
                write!(f, "mesh `{path}` of link `{link}`: {reason}")
            }
            RobotError::UnsupportedGeometry { link, geometry } => {
                write!(f, "collision geometry of link `{link}`: ")?;
                match geometry {
                    Geometry::Box { size: [x, y, z] } => {
                        write!(f, "box size {x} {y} {z} is not positive")
                    }
                    Geometry::Cylinder { radius, length } => write!(
                        f,
                        "cylinder radius {radius} and length {length} are not positive"
                    ),
                    Geometry::Capsule { radius, length } => write!(
                        f,
                        "capsule radius {radius} and length {length} are not positive"
                    ),
                    Geometry::Sphere { radius } => {
                        write!(f, "sphere radius {radius} is not positive")
                    }
                    // Meshes are checked when read, and fail as `Mesh`.
                    Geometry::Mesh { filename, .. } => {
                        write!(f, "mesh `{filename}` is not a solid")
                    }
                }
            }
        }
    }
}

impl std::error::Error for RobotError {}

/// How fast each movable joint may go, base to tip: what a controller accepts and the
/// timing of every motion respects. From a URDF alone, the `<limit velocity>` (or
/// [`cellc_schema::Joint::DEFAULT_VELOCITY`]) and the default acceleration; from an
/// artifact, what the compiler resolved ([`Robot::set_rate_limits`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RateLimits {
    /// Largest speed (rad/s, or m/s).
    pub velocity: Vec<f64>,
    /// Largest acceleration (rad/s², or m/s²).
    pub acceleration: Vec<f64>,
    /// Largest jerk (rad/s³, or m/s³), where one is declared.
    pub jerk: Vec<Option<f64>>,
}

/// A serial chain from a URDF: the kinematic model plus its collision solids.
///
/// Immutable once built; cheap to share between threads (`Send + Sync`).
#[derive(Debug, Clone)]
pub struct Robot {
    name: String,
    base_link: String,
    tip_link: String,
    /// The link that defines each frame, 0..=n.
    frame_links: Vec<String>,
    joint_names: Vec<String>,
    kinds: Vec<JointKind>,
    /// `origins[j]`: frame `j` to joint `j`'s frame at q = 0 (fixed joints folded in).
    origins: Vec<Iso>,
    /// Unit joint axes in the joint's own frame.
    axes: Vec<Vec3>,
    lower: Vec<f64>,
    upper: Vec<f64>,
    /// What motions are timed with (see [`RateLimits`]).
    rates: RateLimits,
    /// Frame n to the tip link (fixed joints only).
    tip_offset: Iso,
    shapes: Vec<LinkShape>,
}

impl Robot {
    /// Reads the chain from `base_link` to `tip_link` of a URDF (walked by
    /// [`cellc_urdf`], the same walk the compiler checked).
    ///
    /// `urdf_path` is where the URDF lives (as `files` names it): mesh file names are
    /// resolved relative to its folder. Meshes are read through `files`; `package://`
    /// URIs are refused here ([`Robot::from_urdf_with`] takes the paths the compiler
    /// resolved them to).
    pub fn from_urdf(
        urdf_text: &str,
        urdf_path: &str,
        base_link: &str,
        tip_link: &str,
        files: &dyn Files,
    ) -> Result<Robot, RobotError> {
        let meshes = MeshPaths::RelativeTo(urdf_path);
        Robot::from_urdf_with(urdf_text, meshes, base_link, tip_link, files)
    }

    /// [`Robot::from_urdf`] with the mesh files where `meshes` says (an artifact's table
    /// of resolved paths, so `package://` meshes are read from where the compiler found
    /// them).
    pub fn from_urdf_with(
        urdf_text: &str,
        meshes: MeshPaths<'_>,
        base_link: &str,
        tip_link: &str,
        files: &dyn Files,
    ) -> Result<Robot, RobotError> {
        let description = Description::parse(urdf_text)?;
        // The same whole-file check as the compiler's: a description changed or damaged
        // since the build must not reach the kinematics with a NaN in it.
        if let Some(problem) = description.problems().into_iter().next() {
            return Err(RobotError::Unsound(problem));
        }
        let chain = description.chain(base_link, tip_link)?;
        let mut robot = Robot {
            name: description.name().to_string(),
            base_link: base_link.to_string(),
            tip_link: tip_link.to_string(),
            frame_links: vec![base_link.to_string()],
            joint_names: Vec::new(),
            kinds: Vec::new(),
            origins: Vec::new(),
            axes: Vec::new(),
            lower: Vec::new(),
            upper: Vec::new(),
            rates: RateLimits::default(),
            tip_offset: Iso::identity(),
            shapes: Vec::new(),
        };
        // Pose of the current link in the current frame (fixed joints accumulate here).
        let mut in_frame = Iso::identity();
        for joint in &chain.joints {
            let Some(motion) = joint.motion()? else {
                in_frame *= joint.origin;
                continue;
            };
            robot.joint_names.push(joint.name.clone());
            robot.kinds.push(motion.kind);
            robot.origins.push(in_frame * joint.origin);
            robot.axes.push(motion.axis);
            robot.lower.push(motion.lower);
            robot.upper.push(motion.upper);
            let velocity = if joint.velocity.is_finite() && joint.velocity > 0.0 {
                joint.velocity
            } else {
                cellc_schema::Joint::DEFAULT_VELOCITY
            };
            robot.rates.velocity.push(velocity);
            robot
                .rates
                .acceleration
                .push(cellc_schema::Joint::DEFAULT_ACCELERATION);
            robot.rates.jerk.push(None);
            robot.frame_links.push(joint.child.clone());
            in_frame = Iso::identity();
        }
        robot.tip_offset = in_frame;

        // Solids: every link that moves rigidly with a frame (the frame's own link, and
        // links fixed to it, on the chain or beside it), in a deterministic order.
        for frame in 0..robot.frame_links.len() {
            for (link, pose) in description.attached_links(&robot.frame_links[frame]) {
                for collision in description.collisions(link) {
                    let (shape, turn) = shape_of(link, &collision.geometry, meshes, files)?;
                    robot.shapes.push(LinkShape {
                        link: link.to_string(),
                        frame,
                        local: pose * collision.origin * turn,
                        shape,
                    });
                }
            }
        }
        Ok(robot)
    }

    /// The URDF's robot name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The number of movable joints on the chain (the length of a configuration).
    pub fn n_joints(&self) -> usize {
        self.kinds.len()
    }

    /// The movable joints' names, base to tip.
    pub fn joint_names(&self) -> &[String] {
        &self.joint_names
    }

    /// The movable joints' kinds, base to tip.
    pub fn joint_kinds(&self) -> &[JointKind] {
        &self.kinds
    }

    /// Lower and upper joint limits (continuous joints: -inf and +inf).
    pub fn limits(&self) -> (&[f64], &[f64]) {
        (&self.lower, &self.upper)
    }

    /// The speed, acceleration and jerk limits motions are timed with.
    pub fn rate_limits(&self) -> &RateLimits {
        &self.rates
    }

    /// Takes the rate limits an artifact resolved (the cell's declarations and
    /// `joint_limits.yaml` over the URDF's); false, and the limits unchanged, when
    /// `joints` does not give one positive, finite set per movable joint.
    pub fn set_rate_limits(&mut self, joints: &[cellc_schema::Joint]) -> bool {
        let positive = |v: f64| v.is_finite() && v > 0.0;
        if joints.len() != self.n_joints()
            || !joints.iter().all(|j| {
                positive(j.velocity) && positive(j.acceleration) && j.jerk.is_none_or(positive)
            })
        {
            return false;
        }
        self.rates = RateLimits {
            velocity: joints.iter().map(|j| j.velocity).collect(),
            acceleration: joints.iter().map(|j| j.acceleration).collect(),
            jerk: joints.iter().map(|j| j.jerk).collect(),
        };
        true
    }

    /// `origins()[j]`: the transform from frame `j` to joint `j`'s frame at q = 0.
    pub fn origins(&self) -> &[Iso] {
        &self.origins
    }

    /// Unit joint axes, each in its joint's frame.
    pub fn axes(&self) -> &[Vec3] {
        &self.axes
    }

    /// The transform from the last frame to the tip link.
    pub fn tip_offset(&self) -> &Iso {
        &self.tip_offset
    }

    /// The base link (frame 0).
    pub fn base_link(&self) -> &str {
        &self.base_link
    }

    /// The tip link.
    pub fn tip_link(&self) -> &str {
        &self.tip_link
    }

    /// The link that defines frame `frame` (0 = base link), if there is such a frame.
    pub fn frame_link(&self, frame: usize) -> Option<&str> {
        self.frame_links.get(frame).map(String::as_str)
    }

    /// The number of frames, `n_joints() + 1`.
    pub fn n_frames(&self) -> usize {
        self.frame_links.len()
    }

    /// Every collision solid of the chain, frame by frame, each link's in URDF order.
    pub fn shapes(&self) -> &[LinkShape] {
        &self.shapes
    }

    /// Whether two frames are the same or joined by one joint: their solids touch by
    /// construction (every URDF overlaps links at their joint), so self-collision checks
    /// skip such pairs.
    pub fn adjacent_frames(&self, a: usize, b: usize) -> bool {
        a.abs_diff(b) <= 1
    }

    /// Whether `q` has one value per joint, each finite and within its limits.
    pub fn within_limits(&self, q: &[f64]) -> bool {
        q.len() == self.n_joints()
            && q.iter()
                .zip(self.lower.iter().zip(&self.upper))
                .all(|(&v, (&lo, &hi))| v.is_finite() && lo <= v && v <= hi)
    }

    /// Clamps each value of `q` into its joint's limits (NaN becomes the lower limit,
    /// or 0 for an unlimited joint).
    pub fn clamp_to_limits(&self, q: &mut [f64]) {
        for ((v, &lo), &hi) in q.iter_mut().zip(&self.lower).zip(&self.upper) {
            if v.is_nan() {
                *v = if lo.is_finite() { lo } else { 0.0 };
            }
            *v = v.clamp(lo, hi);
        }
    }

    /// The range random configurations are drawn from for joint `j`: its limits, or
    /// [-pi, pi] for a joint without finite limits that turns (a prismatic joint without
    /// limits gets [-1, 1] m, an arbitrary but plausible stroke).
    pub fn sampling_range(&self, j: usize) -> (f64, f64) {
        let (lo, hi) = (self.lower[j], self.upper[j]);
        let span = if self.kinds[j].is_rotational() {
            std::f64::consts::PI
        } else {
            1.0
        };
        (
            if lo.is_finite() { lo } else { -span },
            if hi.is_finite() { hi } else { span },
        )
    }

    /// Fills `q` (one value per joint) with a configuration drawn uniformly inside
    /// [`Robot::sampling_range`].
    pub fn sample_configuration<R: Rng + ?Sized>(&self, rng: &mut R, q: &mut [f64]) {
        for (j, v) in q.iter_mut().enumerate().take(self.n_joints()) {
            let (lo, hi) = self.sampling_range(j);
            *v = lo + (hi - lo) * rng.random::<f64>();
        }
    }
}

/// The solid for one URDF geometry, plus the turn to apply after the collision origin.
fn shape_of(
    link: &str,
    geometry: &Geometry,
    meshes: MeshPaths<'_>,
    files: &dyn Files,
) -> Result<(SharedShape, Iso), RobotError> {
    let positive = |v: f64| v.is_finite() && v > 0.0;
    let bad = || RobotError::UnsupportedGeometry {
        link: link.to_string(),
        geometry: geometry.clone(),
    };
    match geometry {
        Geometry::Box { size: [x, y, z] } => {
            if !(positive(*x) && positive(*y) && positive(*z)) {
                return Err(bad());
            }
            Ok((
                SharedShape::cuboid(x / 2.0, y / 2.0, z / 2.0),
                Iso::identity(),
            ))
        }
        Geometry::Cylinder { radius, length } => {
            if !(positive(*radius) && positive(*length)) {
                return Err(bad());
            }
            // URDF cylinders run along z, parry's along y: turn y onto z.
            let turn = Iso::rotation(Vec3::x() * std::f64::consts::FRAC_PI_2);
            Ok((SharedShape::cylinder(length / 2.0, *radius), turn))
        }
        Geometry::Capsule { radius, length } => {
            if !(positive(*radius) && *length >= 0.0 && length.is_finite()) {
                return Err(bad());
            }
            Ok((
                SharedShape::capsule_z(length / 2.0, *radius),
                Iso::identity(),
            ))
        }
        Geometry::Sphere { radius } => {
            if !positive(*radius) {
                return Err(bad());
            }
            Ok((SharedShape::ball(*radius), Iso::identity()))
        }
        Geometry::Mesh { filename, scale } => {
            let error = |path: &str, reason| RobotError::Mesh {
                link: link.to_string(),
                path: path.to_string(),
                reason,
            };
            let path = meshes
                .path(filename)
                .map_err(|e| error(filename, MeshError::Path(e)))?;
            let shape = mesh::load(&path, *scale, files).map_err(|e| error(&path, e))?;
            Ok((shape, Iso::identity()))
        }
    }
}
