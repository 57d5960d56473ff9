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

use std::collections::HashMap;
use std::fmt;

use nalgebra as na;
use parry3d_f64::shape::SharedShape;
use rand::Rng;

use crate::math::{Iso, Point, Quat, Vec3};
use crate::Files;

/// The kind of a movable joint.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum JointKind {
    /// Turns about its axis within limits (radians).
    Revolute,
    /// Turns about its axis without limits (radians).
    Continuous,
    /// Slides along its axis within limits (metres).
    Prismatic,
}

impl JointKind {
    /// Whether the joint turns (revolute or continuous) rather than slides.
    pub fn is_rotational(self) -> bool {
        !matches!(self, JointKind::Prismatic)
    }
}

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
    Parse {
        /// The reader's explanation.
        reason: String,
    },
    /// The base or tip link is not in the model.
    UnknownLink {
        /// The missing link.
        link: String,
    },
    /// No chain of joints leads from the base link down to the tip link.
    NoChain {
        /// The requested base link.
        base: String,
        /// The requested tip link.
        tip: String,
    },
    /// A joint on the chain is of a kind the runtime cannot move (floating, planar...).
    UnsupportedJoint {
        /// The joint.
        joint: String,
        /// Its URDF type.
        kind: String,
    },
    /// A movable joint has a zero (or non-finite) axis.
    BadAxis {
        /// The joint.
        joint: String,
    },
    /// A joint's limits are not an interval (`lower > upper`, or NaN).
    BadLimits {
        /// The joint.
        joint: String,
        /// The lower limit as written.
        lower: f64,
        /// The upper limit as written.
        upper: f64,
    },
    /// A mesh could not be read or turned into a convex solid.
    Mesh {
        /// The link whose collision uses the mesh.
        link: String,
        /// The mesh path as resolved (or as written, for `package://` paths).
        path: String,
        /// What went wrong.
        reason: String,
    },
    /// A collision geometry the runtime does not model, or with impossible dimensions.
    UnsupportedGeometry {
        /// The link.
        link: String,
        /// What is wrong with it.
        what: String,
    },
}

impl fmt::Display for RobotError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RobotError::Parse { reason } => write!(f, "the URDF does not parse: {reason}"),
            RobotError::UnknownLink { link } => write!(f, "the URDF has no link `{link}`"),
            RobotError::NoChain { base, tip } => {
                write!(f, "no chain of joints leads from `{base}` to `{tip}`")
            }
            RobotError::UnsupportedJoint { joint, kind } => write!(
                f,
                "joint `{joint}` is {kind}; only revolute, continuous, prismatic and fixed \
                 joints can be on the chain"
            ),
            RobotError::BadAxis { joint } => write!(f, "joint `{joint}` has a zero axis"),
            RobotError::BadLimits {
                joint,
                lower,
                upper,
            } => write!(
                f,
                "joint `{joint}` has limits {lower} .. {upper}, which are not an interval"
            ),
            RobotError::Mesh { link, path, reason } => {
                write!(f, "mesh `{path}` of link `{link}`: {reason}")
            }
            RobotError::UnsupportedGeometry { link, what } => {
                write!(f, "collision geometry of link `{link}`: {what}")
            }
        }
    }
}

impl std::error::Error for RobotError {}

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
    /// Frame n to the tip link (fixed joints only).
    tip_offset: Iso,
    shapes: Vec<LinkShape>,
}

impl Robot {
    /// Reads the chain from `base_link` to `tip_link` of a URDF.
    ///
    /// `urdf_path` is where the URDF lives (as `files` names it): mesh file names are
    /// resolved relative to its folder. Meshes are read through `files`; `package://`
    /// URIs are refused, since there is no ROS package path to resolve them against.
    pub fn from_urdf(
        urdf_text: &str,
        urdf_path: &str,
        base_link: &str,
        tip_link: &str,
        files: &dyn Files,
    ) -> Result<Robot, RobotError> {
        // The URDF reader is a third-party XML stack: a panic on hostile input must not
        // take the runtime down.
        let model = match std::panic::catch_unwind(|| urdf_rs::read_from_string(urdf_text)) {
            Ok(Ok(model)) => model,
            Ok(Err(error)) => {
                let reason = error.to_string();
                let reason = reason.strip_prefix("custom: ").unwrap_or(&reason);
                return Err(RobotError::Parse {
                    reason: reason.to_string(),
                });
            }
            Err(_) => {
                return Err(RobotError::Parse {
                    reason: "the URDF reader failed on this text".to_string(),
                })
            }
        };
        let links: HashMap<&str, &urdf_rs::Link> =
            model.links.iter().map(|l| (l.name.as_str(), l)).collect();
        for link in [base_link, tip_link] {
            if !links.contains_key(link) {
                return Err(RobotError::UnknownLink {
                    link: link.to_string(),
                });
            }
        }
        // child link -> the joint that carries it (a URDF is a tree: at most one).
        let parent_joint: HashMap<&str, &urdf_rs::Joint> = model
            .joints
            .iter()
            .map(|j| (j.child.link.as_str(), j))
            .collect();

        // Walk up from the tip to the base; the chain is the reversed path.
        let mut path: Vec<&urdf_rs::Joint> = Vec::new();
        let mut at = tip_link;
        while at != base_link {
            let Some(joint) = parent_joint.get(at) else {
                return Err(RobotError::NoChain {
                    base: base_link.to_string(),
                    tip: tip_link.to_string(),
                });
            };
            path.push(joint);
            at = joint.parent.link.as_str();
            if path.len() > model.joints.len() {
                // A cycle in a malformed file: no chain.
                return Err(RobotError::NoChain {
                    base: base_link.to_string(),
                    tip: tip_link.to_string(),
                });
            }
        }
        path.reverse();

        let mut robot = Robot {
            name: model.name.clone(),
            base_link: base_link.to_string(),
            tip_link: tip_link.to_string(),
            frame_links: vec![base_link.to_string()],
            joint_names: Vec::new(),
            kinds: Vec::new(),
            origins: Vec::new(),
            axes: Vec::new(),
            lower: Vec::new(),
            upper: Vec::new(),
            tip_offset: Iso::identity(),
            shapes: Vec::new(),
        };
        // Pose of the current link in the current frame (fixed joints accumulate here).
        let mut in_frame = Iso::identity();
        for joint in &path {
            let origin = pose_to_iso(&joint.origin);
            let kind = match &joint.joint_type {
                urdf_rs::JointType::Fixed => {
                    in_frame *= origin;
                    continue;
                }
                urdf_rs::JointType::Revolute => JointKind::Revolute,
                urdf_rs::JointType::Continuous => JointKind::Continuous,
                urdf_rs::JointType::Prismatic => JointKind::Prismatic,
                other => {
                    return Err(RobotError::UnsupportedJoint {
                        joint: joint.name.clone(),
                        kind: format!("{other:?}").to_lowercase(),
                    })
                }
            };
            let axis = Vec3::from(joint.axis.xyz.0);
            let norm = axis.norm();
            if !norm.is_finite() || norm < 1e-9 {
                return Err(RobotError::BadAxis {
                    joint: joint.name.clone(),
                });
            }
            let (lower, upper) = match kind {
                JointKind::Continuous => (f64::NEG_INFINITY, f64::INFINITY),
                _ => (joint.limit.lower, joint.limit.upper),
            };
            // NaN compares as unordered, so it fails this test too.
            if lower.is_nan() || upper.is_nan() || lower > upper {
                return Err(RobotError::BadLimits {
                    joint: joint.name.clone(),
                    lower,
                    upper,
                });
            }
            robot.joint_names.push(joint.name.clone());
            robot.kinds.push(kind);
            robot.origins.push(in_frame * origin);
            robot.axes.push(axis / norm);
            robot.lower.push(lower);
            robot.upper.push(upper);
            robot.frame_links.push(joint.child.link.clone());
            in_frame = Iso::identity();
        }
        robot.tip_offset = in_frame;

        // Solids: every link that moves rigidly with a frame, found by following fixed
        // joints down from the frame's own link (this covers fixed links on the chain and
        // fixed attachments beside it). Joints are visited in file order, so the order of
        // `shapes` is deterministic.
        let mut fixed_children: HashMap<&str, Vec<&urdf_rs::Joint>> = HashMap::new();
        for joint in &model.joints {
            if matches!(joint.joint_type, urdf_rs::JointType::Fixed) {
                fixed_children
                    .entry(joint.parent.link.as_str())
                    .or_default()
                    .push(joint);
            }
        }
        let dir = parent_dir(urdf_path);
        for frame in 0..robot.frame_links.len() {
            let mut stack: Vec<(&str, Iso)> =
                vec![(robot.frame_links[frame].as_str(), Iso::identity())];
            let mut visited = 0usize;
            while let Some((link_name, pose)) = stack.pop() {
                visited += 1;
                if visited > model.links.len() {
                    break; // a malformed cycle of fixed joints
                }
                if let Some(link) = links.get(link_name) {
                    for collision in &link.collision {
                        let local = pose * pose_to_iso(&collision.origin);
                        let (shape, turn) = shape_of(link_name, &collision.geometry, &dir, files)?;
                        robot.shapes.push(LinkShape {
                            link: link_name.to_string(),
                            frame,
                            local: local * turn,
                            shape,
                        });
                    }
                }
                if let Some(children) = fixed_children.get(link_name) {
                    // Reversed so that the stack pops them in file order.
                    for joint in children.iter().rev() {
                        stack.push((joint.child.link.as_str(), pose * pose_to_iso(&joint.origin)));
                    }
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

/// A URDF `<origin xyz rpy>` as a transform. URDF's rpy are fixed-axis roll, pitch,
/// yaw (R = Rz(yaw) Ry(pitch) Rx(roll)), which is nalgebra's Euler-angle convention.
pub(crate) fn pose_to_iso(pose: &urdf_rs::Pose) -> Iso {
    let [x, y, z] = pose.xyz.0;
    let [roll, pitch, yaw] = pose.rpy.0;
    Iso::from_parts(
        na::Translation3::new(x, y, z),
        Quat::from_euler_angles(roll, pitch, yaw),
    )
}

/// The solid for one URDF geometry, plus the turn to apply after the collision origin.
fn shape_of(
    link: &str,
    geometry: &urdf_rs::Geometry,
    dir: &str,
    files: &dyn Files,
) -> Result<(SharedShape, Iso), RobotError> {
    let positive = |v: f64| v.is_finite() && v > 0.0;
    let bad = |what: String| RobotError::UnsupportedGeometry {
        link: link.to_string(),
        what,
    };
    match geometry {
        urdf_rs::Geometry::Box { size } => {
            let [x, y, z] = size.0;
            if !(positive(x) && positive(y) && positive(z)) {
                return Err(bad(format!("box size {x} {y} {z} is not positive")));
            }
            Ok((
                SharedShape::cuboid(x / 2.0, y / 2.0, z / 2.0),
                Iso::identity(),
            ))
        }
        urdf_rs::Geometry::Cylinder { radius, length } => {
            if !(positive(*radius) && positive(*length)) {
                return Err(bad(format!(
                    "cylinder radius {radius} and length {length} are not positive"
                )));
            }
            // URDF cylinders run along z, parry's along y: turn y onto z.
            let turn = Iso::rotation(Vec3::x() * std::f64::consts::FRAC_PI_2);
            Ok((SharedShape::cylinder(length / 2.0, *radius), turn))
        }
        urdf_rs::Geometry::Capsule { radius, length } => {
            if !(positive(*radius) && *length >= 0.0 && length.is_finite()) {
                return Err(bad(format!(
                    "capsule radius {radius} and length {length} are not positive"
                )));
            }
            Ok((
                SharedShape::capsule_z(length / 2.0, *radius),
                Iso::identity(),
            ))
        }
        urdf_rs::Geometry::Sphere { radius } => {
            if !positive(*radius) {
                return Err(bad(format!("sphere radius {radius} is not positive")));
            }
            Ok((SharedShape::ball(*radius), Iso::identity()))
        }
        urdf_rs::Geometry::Mesh { filename, scale } => {
            let scale = scale.as_ref().map_or([1.0; 3], |s| s.0);
            let shape = load_mesh(link, filename, scale, dir, files)?;
            Ok((shape, Iso::identity()))
        }
    }
}

/// Reads a mesh and returns its convex hull, scaled.
fn load_mesh(
    link: &str,
    filename: &str,
    scale: [f64; 3],
    dir: &str,
    files: &dyn Files,
) -> Result<SharedShape, RobotError> {
    let error = |path: &str, reason: String| RobotError::Mesh {
        link: link.to_string(),
        path: path.to_string(),
        reason,
    };
    if filename.starts_with("package://") {
        return Err(error(
            filename,
            "`package://` paths need a ROS package path, which cellc does not have; \
             write the mesh path relative to the URDF file"
                .to_string(),
        ));
    }
    let path = resolve(dir, filename.strip_prefix("file://").unwrap_or(filename));
    if !scale.iter().all(|s| s.is_finite() && *s != 0.0) {
        return Err(error(
            &path,
            format!(
                "scale {} {} {} has a zero or non-finite factor",
                scale[0], scale[1], scale[2]
            ),
        ));
    }
    let bytes = files.read(&path).map_err(|reason| error(&path, reason))?;
    mesh_hull(&path, &bytes, scale).map_err(|reason| error(&path, reason))
}

/// The convex hull of an STL or OBJ mesh (chosen by extension), scaled. Shared by robot
/// links and object shapes.
pub fn mesh_hull(path: &str, bytes: &[u8], scale: [f64; 3]) -> Result<SharedShape, String> {
    let lower = path.to_ascii_lowercase();
    let vertices = if lower.ends_with(".stl") {
        read_stl_vertices(bytes)?
    } else if lower.ends_with(".obj") {
        read_obj_vertices(bytes)?
    } else {
        return Err("only STL and OBJ meshes are supported (by file extension)".to_string());
    };
    let points: Vec<Point> = vertices
        .iter()
        .map(|v| Point::new(v[0] * scale[0], v[1] * scale[1], v[2] * scale[2]))
        .collect();
    if points.len() < 4 {
        return Err(format!("{} vertices cannot bound a solid", points.len()));
    }
    if points
        .iter()
        .any(|p| !p.coords.iter().all(|c| c.is_finite()))
    {
        return Err("a vertex is not a finite number".to_string());
    }
    if !spans_a_volume(&points) {
        return Err(
            "its vertices lie on a plane, a line or a point, so their hull has no volume"
                .to_string(),
        );
    }
    // parry's hull code may panic on nearly degenerate input; report that as a bad mesh.
    match std::panic::catch_unwind(|| SharedShape::convex_hull(&points)) {
        Ok(Some(shape)) => Ok(shape),
        _ => Err("its vertices have no convex hull (a degenerate mesh)".to_string()),
    }
}

/// Whether the points have four corners that are not coplanar (relative to the points'
/// size): a flat mesh would give a hull with no volume, on which contact queries are
/// meaningless.
fn spans_a_volume(points: &[Point]) -> bool {
    let Some(first) = points.first() else {
        return false;
    };
    let farthest = |key: &dyn Fn(&Point) -> f64| {
        points
            .iter()
            .map(|p| (key(p), p))
            .fold((0.0, first), |best, x| if x.0 > best.0 { x } else { best })
    };
    let (size, second) = farthest(&|p| (p - first).norm());
    if size <= 0.0 {
        return false;
    }
    let along = (second - first) / size;
    let (off_line, third) = farthest(&|p| (p - first).cross(&along).norm());
    if off_line <= 1e-9 * size {
        return false;
    }
    let normal = (second - first).cross(&(third - first)).normalize();
    let (off_plane, _) = farthest(&|p| (p - first).dot(&normal).abs());
    off_plane > 1e-9 * size
}

/// The vertices of an STL file, ASCII or binary.
fn read_stl_vertices(bytes: &[u8]) -> Result<Vec<[f64; 3]>, String> {
    let read = |bytes: &[u8]| -> std::io::Result<Vec<[f64; 3]>> {
        let mut cursor = std::io::Cursor::new(bytes);
        let mesh = stl_io::read_stl(&mut cursor)?;
        Ok(mesh
            .vertices
            .iter()
            .map(|v| [f64::from(v[0]), f64::from(v[1]), f64::from(v[2])])
            .collect())
    };
    match read(bytes) {
        Ok(vertices) => Ok(vertices),
        Err(first) => {
            // Many exporters write binary STL with a header that starts with "solid",
            // which makes the reader take it for ASCII. When the size matches the binary
            // layout exactly (84-byte header, 50 bytes a triangle), blank the header
            // (binary readers ignore it) and read it again.
            if bytes.len() >= 84 {
                let count = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]);
                if bytes.len() as u64 == 84 + 50 * u64::from(count) {
                    let mut copy = bytes.to_vec();
                    copy[..80].fill(0);
                    return read(&copy).map_err(|e| format!("not a readable STL file: {e}"));
                }
            }
            Err(format!("not a readable STL file: {first}"))
        }
    }
}

/// The vertices of a Wavefront OBJ file: its `v x y z [w]` lines; everything else (faces,
/// normals, materials) is irrelevant to a convex hull.
fn read_obj_vertices(bytes: &[u8]) -> Result<Vec<[f64; 3]>, String> {
    let text = std::str::from_utf8(bytes).map_err(|_| "not a text OBJ file".to_string())?;
    let mut vertices = Vec::new();
    for (number, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        if words.next() != Some("v") {
            continue;
        }
        let mut xyz = [0.0; 3];
        for c in &mut xyz {
            *c = words
                .next()
                .and_then(|w| w.parse::<f64>().ok())
                .ok_or_else(|| format!("line {}: a vertex needs three numbers", number + 1))?;
        }
        vertices.push(xyz);
    }
    Ok(vertices)
}

/// The folder part of a path ("" for a bare file name).
fn parent_dir(path: &str) -> String {
    match path.rfind('/') {
        Some(i) => path[..=i].to_string(),
        None => String::new(),
    }
}

/// `name` relative to `dir` (which ends in `/` or is empty), with `.` and `..` resolved
/// lexically; absolute names stay as they are.
fn resolve(dir: &str, name: &str) -> String {
    let joined = if name.starts_with('/') {
        name.to_string()
    } else {
        format!("{dir}{name}")
    };
    let absolute = joined.starts_with('/');
    let mut parts: Vec<&str> = Vec::new();
    for part in joined.split('/') {
        match part {
            "" | "." => {}
            ".." if parts.last().is_some_and(|p| *p != "..") => {
                parts.pop();
            }
            ".." if absolute => {}
            _ => parts.push(part),
        }
    }
    let body = parts.join("/");
    if absolute {
        format!("/{body}")
    } else {
        body
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn resolves_relative_paths() {
        assert_eq!(resolve("robots/", "meshes/a.stl"), "robots/meshes/a.stl");
        assert_eq!(resolve("robots/", "../meshes/a.stl"), "meshes/a.stl");
        assert_eq!(resolve("", "./a.stl"), "a.stl");
        assert_eq!(resolve("/x/y/", "../a.stl"), "/x/a.stl");
        assert_eq!(resolve("robots/", "/abs/a.stl"), "/abs/a.stl");
        assert_eq!(resolve("", "../a.stl"), "../a.stl");
        assert_eq!(parent_dir("cells/robots/r.urdf"), "cells/robots/");
        assert_eq!(parent_dir("r.urdf"), "");
    }

    #[test]
    fn reads_obj_vertices() {
        let text = b"# cube corner\nv 0 0 0\nv 1 0 0\nvn 0 0 1\nv 0 1 0 1.0\nf 1 2 3\n";
        let v = read_obj_vertices(text).unwrap();
        assert_eq!(v, vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
        assert!(read_obj_vertices(b"v 1 2\n").is_err());
    }
}
