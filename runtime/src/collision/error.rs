//! Why a collision world cannot be built, and why a state cannot be checked.

use std::fmt;

use super::Holder;

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
