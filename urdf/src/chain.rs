//! The one walk of a serial chain, base link to tip link, and the facts of its joints.

use std::fmt;

use cellc_schema::math::{Iso, Vec3};

use crate::description::{iso, Description};

/// A URDF joint type.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum JointType {
    /// Turns about its axis within limits.
    Revolute,
    /// Turns about its axis without limits.
    Continuous,
    /// Slides along its axis within limits.
    Prismatic,
    /// Does not move.
    Fixed,
    /// Moves freely in space (six degrees of freedom).
    Floating,
    /// Moves in a plane.
    Planar,
    /// Turns about a point.
    Spherical,
}

impl fmt::Display for JointType {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            JointType::Revolute => "revolute",
            JointType::Continuous => "continuous",
            JointType::Prismatic => "prismatic",
            JointType::Fixed => "fixed",
            JointType::Floating => "floating",
            JointType::Planar => "planar",
            JointType::Spherical => "spherical",
        })
    }
}

impl From<&urdf_rs::JointType> for JointType {
    fn from(t: &urdf_rs::JointType) -> JointType {
        match t {
            urdf_rs::JointType::Revolute => JointType::Revolute,
            urdf_rs::JointType::Continuous => JointType::Continuous,
            urdf_rs::JointType::Prismatic => JointType::Prismatic,
            urdf_rs::JointType::Fixed => JointType::Fixed,
            urdf_rs::JointType::Floating => JointType::Floating,
            urdf_rs::JointType::Planar => JointType::Planar,
            urdf_rs::JointType::Spherical => JointType::Spherical,
        }
    }
}

/// The kind of a joint a serial chain can move: one degree of freedom along an axis.
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

/// One joint of a chain, as the URDF states it.
#[derive(Clone, Debug, PartialEq)]
pub struct ChainJoint {
    /// The joint's name.
    pub name: String,
    /// Its URDF type.
    pub joint_type: JointType,
    /// The parent link's frame to the joint's frame (at zero motion).
    pub origin: Iso,
    /// The axis as written, in the joint's frame (not normalised, possibly zero).
    pub axis: Vec3,
    /// The `<limit lower>` as written (0 when absent).
    pub lower: f64,
    /// The `<limit upper>` as written (0 when absent).
    pub upper: f64,
    /// The `<limit velocity>` as written (0 when absent, which the URDF format forbids for
    /// a joint that moves, but files in the wild omit).
    pub velocity: f64,
    /// The link it carries.
    pub child: String,
}

/// How a movable joint moves, validated.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Motion {
    /// Its kind.
    pub kind: JointKind,
    /// The unit axis, in the joint's frame.
    pub axis: Vec3,
    /// Lower limit (`-inf` for a continuous joint).
    pub lower: f64,
    /// Upper limit (`+inf` for a continuous joint).
    pub upper: f64,
}

impl ChainJoint {
    /// Its kind when a serial chain can move it; `None` for fixed joints and for the
    /// types with more than one degree of freedom.
    pub fn kind(&self) -> Option<JointKind> {
        match self.joint_type {
            JointType::Revolute => Some(JointKind::Revolute),
            JointType::Continuous => Some(JointKind::Continuous),
            JointType::Prismatic => Some(JointKind::Prismatic),
            _ => None,
        }
    }

    /// Lower and upper limits as they apply: a continuous joint has none (infinite),
    /// the others have the `<limit>` as written.
    pub fn limits(&self) -> (f64, f64) {
        match self.joint_type {
            JointType::Continuous => (f64::NEG_INFINITY, f64::INFINITY),
            _ => (self.lower, self.upper),
        }
    }

    /// How the joint moves: `None` for a fixed joint; an error for a type a serial chain
    /// cannot move, a zero axis, or limits that are not an interval.
    pub fn motion(&self) -> Result<Option<Motion>, JointError> {
        if self.joint_type == JointType::Fixed {
            return Ok(None);
        }
        let Some(kind) = self.kind() else {
            return Err(JointError::Unsupported {
                joint: self.name.clone(),
                joint_type: self.joint_type,
            });
        };
        let norm = self.axis.norm();
        if !norm.is_finite() || norm < 1e-9 {
            return Err(JointError::ZeroAxis {
                joint: self.name.clone(),
            });
        }
        let (lower, upper) = self.limits();
        // NaN compares as unordered, so it fails this test too.
        if lower.is_nan() || upper.is_nan() || lower > upper {
            return Err(JointError::BadLimits {
                joint: self.name.clone(),
                lower,
                upper,
            });
        }
        Ok(Some(Motion {
            kind,
            axis: self.axis / norm,
            lower,
            upper,
        }))
    }
}

/// Why a chain joint cannot be moved.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum JointError {
    /// A type with more than one degree of freedom (floating, planar, spherical).
    Unsupported {
        /// The joint.
        joint: String,
        /// Its type.
        joint_type: JointType,
    },
    /// The axis is zero or not finite.
    ZeroAxis {
        /// The joint.
        joint: String,
    },
    /// The limits are not an interval (`lower > upper`, or NaN).
    BadLimits {
        /// The joint.
        joint: String,
        /// The lower limit as written.
        lower: f64,
        /// The upper limit as written.
        upper: f64,
    },
}

impl fmt::Display for JointError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            JointError::Unsupported { joint, joint_type } => write!(
                f,
                "joint `{joint}` is {joint_type}; only revolute, continuous, prismatic and \
                 fixed joints can be on the chain"
            ),
            JointError::ZeroAxis { joint } => write!(f, "joint `{joint}` has a zero axis"),
            JointError::BadLimits {
                joint,
                lower,
                upper,
            } => write!(
                f,
                "joint `{joint}` has limits {lower} .. {upper}, which are not an interval"
            ),
        }
    }
}

impl std::error::Error for JointError {}

/// The joints from a base link down to a tip link, in order (fixed ones included).
#[derive(Clone, Debug, PartialEq)]
pub struct Chain {
    /// The base link.
    pub base: String,
    /// The tip link.
    pub tip: String,
    /// Base to tip; the first joint's parent is `base`, the last one's child is `tip`.
    pub joints: Vec<ChainJoint>,
}

impl Chain {
    /// The joints a serial chain moves, base to tip, with their kinds.
    pub fn movable(&self) -> impl Iterator<Item = (&ChainJoint, JointKind)> {
        self.joints.iter().filter_map(|j| Some((j, j.kind()?)))
    }

    /// The first joint of the chain that opens a gripper's finger rather than moving the
    /// arm: a prismatic joint after a turning one, with a stroke of at most
    /// [`MAX_FINGER_STROKE`], with the link it hangs from. A tip chosen on a finger
    /// (`panda_leftfinger`) puts such a joint on the chain, where inverse kinematics would
    /// slide it as if it were an axis of the arm. A linear axis under an arm (a rail, a
    /// conveyor) comes before the turning joints, and a SCARA's quill travels farther, so
    /// neither is taken for a finger.
    pub fn finger_joint(&self) -> Option<FingerJoint<'_>> {
        let first_turning = self
            .joints
            .iter()
            .position(|j| j.kind().is_some_and(JointKind::is_rotational))?;
        let i = (first_turning + 1..self.joints.len()).find(|&i| {
            let j = &self.joints[i];
            j.joint_type == JointType::Prismatic && (j.upper - j.lower).abs() <= MAX_FINGER_STROKE
        })?;
        let parent = match i {
            0 => self.base.as_str(),
            _ => self.joints[i - 1].child.as_str(),
        };
        Some(FingerJoint {
            joint: &self.joints[i],
            parent,
        })
    }
}

/// The longest stroke, metres, of a prismatic joint taken for a finger when it follows a
/// turning joint (a parallel gripper's finger travels a few centimetres; a SCARA's quill
/// or a telescoping axis more than ten).
pub const MAX_FINGER_STROKE: f64 = 0.1;

/// A finger joint found on a chain ([`Chain::finger_joint`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FingerJoint<'c> {
    /// The joint.
    pub joint: &'c ChainJoint,
    /// The link it hangs from: the last link of the arm above the finger, where the chain
    /// should end.
    pub parent: &'c str,
}

/// Why no chain could be walked.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum ChainError {
    /// The base or the tip is not a link of the description.
    UnknownLink {
        /// The missing link.
        link: String,
    },
    /// The tip does not descend from the base.
    NoChain {
        /// The requested base link.
        base: String,
        /// The requested tip link.
        tip: String,
    },
}

impl fmt::Display for ChainError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ChainError::UnknownLink { link } => write!(f, "the URDF has no link `{link}`"),
            ChainError::NoChain { base, tip } => {
                write!(f, "no chain of joints leads from `{base}` to `{tip}`")
            }
        }
    }
}

impl std::error::Error for ChainError {}

impl Description {
    /// The chain from `base` down to `tip`: walked up from the tip, parent by parent,
    /// until the base (a URDF is a tree, so the path is unique when it exists).
    pub fn chain(&self, base: &str, tip: &str) -> Result<Chain, ChainError> {
        for link in [base, tip] {
            if !self.has_link(link) {
                return Err(ChainError::UnknownLink {
                    link: link.to_string(),
                });
            }
        }
        let no_chain = || ChainError::NoChain {
            base: base.to_string(),
            tip: tip.to_string(),
        };
        let mut path: Vec<usize> = Vec::new();
        let mut at = tip;
        while at != base {
            let &j = self.parent_joint.get(at).ok_or_else(no_chain)?;
            path.push(j);
            if path.len() > self.model.joints.len() {
                // A cycle in a malformed file: no chain.
                return Err(no_chain());
            }
            at = self.model.joints[j].parent.link.as_str();
        }
        let joints = path
            .iter()
            .rev()
            .map(|&j| {
                let joint = &self.model.joints[j];
                ChainJoint {
                    name: joint.name.clone(),
                    joint_type: JointType::from(&joint.joint_type),
                    origin: iso(&joint.origin),
                    axis: Vec3::from(joint.axis.xyz.0),
                    lower: joint.limit.lower,
                    upper: joint.limit.upper,
                    velocity: joint.limit.velocity,
                    child: joint.child.link.clone(),
                }
            })
            .collect();
        Ok(Chain {
            base: base.to_string(),
            tip: tip.to_string(),
            joints,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const ARM: &str = r#"<robot name="arm">
      <link name="base"/><link name="upper"/><link name="flange"/><link name="tool"/>
      <joint name="shoulder" type="revolute">
        <parent link="base"/><child link="upper"/>
        <origin xyz="0 0 0.3"/><axis xyz="0 0 2"/>
        <limit lower="-1" upper="1" effort="1" velocity="1"/>
      </joint>
      <joint name="mount" type="fixed">
        <parent link="upper"/><child link="flange"/><origin xyz="0.1 0 0"/>
      </joint>
      <joint name="spin" type="continuous">
        <parent link="flange"/><child link="tool"/><axis xyz="1 0 0"/>
      </joint>
    </robot>"#;

    #[test]
    fn walks_base_to_tip_with_fixed_joints_in_place() {
        let d = Description::parse(ARM).expect("parses");
        assert_eq!(d.root(), Some("base"));
        let chain = d.chain("base", "tool").expect("a chain");
        let names: Vec<&str> = chain.joints.iter().map(|j| j.name.as_str()).collect();
        assert_eq!(names, ["shoulder", "mount", "spin"]);
        let movable: Vec<JointKind> = chain.movable().map(|(_, k)| k).collect();
        assert_eq!(movable, [JointKind::Revolute, JointKind::Continuous]);
        let shoulder = chain.joints[0].motion().expect("valid").expect("movable");
        assert_eq!(shoulder.axis, Vec3::z());
        assert_eq!((shoulder.lower, shoulder.upper), (-1.0, 1.0));
        assert_eq!(chain.joints[1].motion(), Ok(None));
        assert_eq!(chain.joints[2].limits(), (f64::NEG_INFINITY, f64::INFINITY));
    }

    #[test]
    fn finds_a_finger_after_the_arm_but_not_a_rail_under_it() {
        let gripper = ARM.replace(
            "</robot>",
            r#"<link name="finger"/>
          <joint name="finger_joint" type="prismatic">
            <parent link="tool"/><child link="finger"/><axis xyz="0 1 0"/>
            <limit lower="0" upper="0.04" effort="1" velocity="1"/>
          </joint></robot>"#,
        );
        let d = Description::parse(&gripper).expect("parses");
        let finger = d.chain("base", "finger").expect("a chain");
        let found = finger.finger_joint().expect("a finger");
        assert_eq!(
            (found.joint.name.as_str(), found.parent),
            ("finger_joint", "tool")
        );
        assert_eq!(
            d.chain("base", "tool").expect("a chain").finger_joint(),
            None
        );
        // A long stroke is an axis, not a finger.
        let quill = Description::parse(&gripper.replace("upper=\"0.04\"", "upper=\"0.2\""))
            .expect("parses");
        assert_eq!(
            quill
                .chain("base", "finger")
                .expect("a chain")
                .finger_joint(),
            None
        );
        // A rail under the arm comes before any turning joint.
        let rail = ARM
            .replace(
                r#"<joint name="shoulder" type="revolute">"#,
                r#"<joint name="shoulder" type="prismatic">"#,
            )
            .replace(r#"lower="-1" upper="1""#, r#"lower="0" upper="0.05""#);
        let rail = Description::parse(&rail).expect("parses");
        assert_eq!(
            rail.chain("base", "tool").expect("a chain").finger_joint(),
            None
        );
    }

    #[test]
    fn refuses_what_is_not_a_chain() {
        let d = Description::parse(ARM).expect("parses");
        assert_eq!(
            d.chain("tool", "base"),
            Err(ChainError::NoChain {
                base: "tool".into(),
                tip: "base".into()
            })
        );
        assert_eq!(
            d.chain("base", "hand"),
            Err(ChainError::UnknownLink {
                link: "hand".into()
            })
        );
        let bad = Description::parse(&ARM.replace("lower=\"-1\"", "lower=\"2\"")).expect("parses");
        let chain = bad.chain("base", "upper").expect("a chain");
        assert!(matches!(
            chain.joints[0].motion(),
            Err(JointError::BadLimits { .. })
        ));
    }
}
