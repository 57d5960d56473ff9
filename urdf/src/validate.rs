//! What a robot description must be before anything walks or moves it: a tree of defined
//! links, and every number inside its domain.
//!
//! A URDF comes from anywhere (a pull request, a vendor download, a damaged disk), and the
//! third-party reader checks only that it is XML of the right shape: `NaN` limits, a joint
//! whose child is its own parent, or a 10⁹ m box all parse. [`Description::problems`]
//! checks the whole file once, in time linear in its size, so that the compiler can report
//! each problem and the runtime can refuse the robot, and neither ever computes with a
//! value that breaks its arithmetic (a NaN limit made `clamp` panic).
//!
//! Only what cellc uses is checked: joints (origins, axes of joints that move, limits of
//! revolute and prismatic joints), links' masses and inertial frames, and collision
//! geometry. Visual geometry, efforts and velocities are never read, so they are not.

use std::collections::{HashMap, HashSet};
use std::fmt;

use crate::chain::JointType;
use crate::description::Description;
use crate::geometry::Geometry;

/// The largest length a URDF may state, in metres: origin offsets, box sizes, radii,
/// cylinder lengths and prismatic joint limits. A cell is a room, not a city.
pub const MAX_LENGTH: f64 = 100.0;
/// The largest angle a URDF may state, in radians (about 16 turns): roll, pitch, yaw and
/// revolute joint limits.
pub const MAX_ANGLE: f64 = 100.0;
/// The largest mass of a link, in kilograms (ten tonnes).
pub const MAX_MASS: f64 = 10_000.0;
/// The largest factor of a mesh `scale`.
pub const MAX_SCALE: f64 = 1_000.0;
/// The shortest joint axis that still has a direction.
pub const MIN_AXIS_NORM: f64 = 1e-9;

/// Where in the file a pose (`<origin>`) is.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum PoseOf {
    /// A joint's origin.
    Joint(String),
    /// A link's inertial frame.
    Inertial(String),
    /// A collision solid of a link.
    Collision(String),
}

impl fmt::Display for PoseOf {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            PoseOf::Joint(joint) => write!(f, "the origin of joint `{joint}`"),
            PoseOf::Inertial(link) => write!(f, "the inertial origin of link `{link}`"),
            PoseOf::Collision(link) => write!(f, "a collision origin of link `{link}`"),
        }
    }
}

/// One thing wrong with a robot description.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum Problem {
    /// Two links with one name.
    DuplicateLink {
        /// The name.
        link: String,
    },
    /// Two joints with one name.
    DuplicateJoint {
        /// The name.
        joint: String,
    },
    /// A joint's parent or child is not a link of the file.
    UndefinedLink {
        /// The joint.
        joint: String,
        /// `parent` or `child`.
        role: &'static str,
        /// The name it gives.
        link: String,
    },
    /// A link carried by two joints (a tree gives each link at most one parent).
    TwoParents {
        /// The link.
        link: String,
        /// The first joint that carries it.
        first: String,
        /// Another one.
        second: String,
    },
    /// Joints that lead from a link back to itself.
    Cycle {
        /// The joints of the cycle, in order from parent to child.
        joints: Vec<String>,
    },
    /// More than one link that no joint carries.
    SeveralRoots {
        /// The root links, in file order.
        roots: Vec<String>,
    },
    /// The axis of a joint that moves is zero or not finite.
    BadAxis {
        /// The joint.
        joint: String,
        /// The axis as written.
        axis: [f64; 3],
    },
    /// The limits of a revolute or prismatic joint are not finite, reversed, or beyond
    /// [`MAX_ANGLE`] (or [`MAX_LENGTH`]).
    BadLimits {
        /// The joint.
        joint: String,
        /// Revolute or prismatic.
        joint_type: JointType,
        /// The lower limit as written.
        lower: f64,
        /// The upper limit as written.
        upper: f64,
    },
    /// A pose with a coordinate that is not finite or beyond [`MAX_LENGTH`] (or an angle
    /// beyond [`MAX_ANGLE`]).
    BadPose {
        /// Whose pose.
        of: PoseOf,
        /// The translation as written.
        xyz: [f64; 3],
        /// Roll, pitch and yaw as written.
        rpy: [f64; 3],
    },
    /// A mass that is negative, not finite or above [`MAX_MASS`].
    BadMass {
        /// The link.
        link: String,
        /// The mass as written.
        mass: f64,
    },
    /// An inertia tensor with a component that is not finite.
    BadInertia {
        /// The link.
        link: String,
    },
    /// A collision solid with a size that is not positive, not finite or beyond
    /// [`MAX_LENGTH`], or a mesh scale that is zero, not finite or beyond [`MAX_SCALE`].
    BadGeometry {
        /// The link.
        link: String,
        /// The solid as written.
        geometry: Geometry,
    },
}

impl Problem {
    /// Whether the problem is with the shape of the file (its links and joints do not
    /// make one tree) rather than with a value.
    pub fn is_structural(&self) -> bool {
        matches!(
            self,
            Problem::DuplicateLink { .. }
                | Problem::DuplicateJoint { .. }
                | Problem::UndefinedLink { .. }
                | Problem::TwoParents { .. }
                | Problem::Cycle { .. }
                | Problem::SeveralRoots { .. }
        )
    }
}

/// At most this many names in a list of a message, then "and N more".
const LISTED: usize = 4;

fn list(names: &[String], separator: &str) -> String {
    let mut text = names
        .iter()
        .take(LISTED)
        .map(|n| format!("`{n}`"))
        .collect::<Vec<_>>()
        .join(separator);
    if names.len() > LISTED {
        text.push_str(&format!(" and {} more", names.len() - LISTED));
    }
    text
}

fn triple(v: [f64; 3]) -> String {
    format!("({}, {}, {})", v[0], v[1], v[2])
}

impl fmt::Display for Problem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Problem::DuplicateLink { link } => write!(f, "link `{link}` is defined twice"),
            Problem::DuplicateJoint { joint } => write!(f, "joint `{joint}` is defined twice"),
            Problem::UndefinedLink { joint, role, link } => write!(
                f,
                "joint `{joint}` has {role} link `{link}`, which the file does not define"
            ),
            Problem::TwoParents {
                link,
                first,
                second,
            } => write!(
                f,
                "link `{link}` is the child of two joints, `{first}` and `{second}`"
            ),
            Problem::Cycle { joints } => write!(
                f,
                "joints {} lead from a link back to itself",
                list(joints, " -> ")
            ),
            Problem::SeveralRoots { roots } => write!(
                f,
                "{} links are carried by no joint ({}); a robot has one root link",
                roots.len(),
                list(roots, ", ")
            ),
            Problem::BadAxis { joint, axis } => write!(
                f,
                "joint `{joint}` has axis {}, which gives no direction",
                triple(*axis)
            ),
            Problem::BadLimits {
                joint,
                joint_type,
                lower,
                upper,
            } => {
                let (bound, unit) = if *joint_type == JointType::Prismatic {
                    (MAX_LENGTH, "m")
                } else {
                    (MAX_ANGLE, "rad")
                };
                write!(
                    f,
                    "{joint_type} joint `{joint}` has limits {lower} .. {upper}; they must be \
                     finite, lower <= upper, within ±{bound} {unit}"
                )
            }
            Problem::BadPose { of, xyz, rpy } => write!(
                f,
                "{of} is xyz {} rpy {}; coordinates must be finite, within ±{MAX_LENGTH} m \
                 and ±{MAX_ANGLE} rad",
                triple(*xyz),
                triple(*rpy)
            ),
            Problem::BadMass { link, mass } => write!(
                f,
                "link `{link}` has mass {mass} kg; a mass is between 0 and {MAX_MASS} kg"
            ),
            Problem::BadInertia { link } => {
                write!(f, "link `{link}` has an inertia that is not finite")
            }
            Problem::BadGeometry { link, geometry } => {
                write!(f, "a collision solid of link `{link}` is ")?;
                match geometry {
                    Geometry::Box { size } => write!(f, "a box of size {}", triple(*size))?,
                    Geometry::Cylinder { radius, length } => {
                        write!(f, "a cylinder of radius {radius} and length {length}")?
                    }
                    Geometry::Capsule { radius, length } => {
                        write!(f, "a capsule of radius {radius} and length {length}")?
                    }
                    Geometry::Sphere { radius } => write!(f, "a sphere of radius {radius}")?,
                    Geometry::Mesh { scale, .. } => {
                        return write!(
                            f,
                            "a mesh with scale {}; a scale factor is not zero, finite and \
                             within ±{MAX_SCALE}",
                            triple(*scale)
                        )
                    }
                }
                write!(f, "; sizes must be positive and at most {MAX_LENGTH} m")
            }
        }
    }
}

impl std::error::Error for Problem {}

fn length_ok(v: f64) -> bool {
    v.is_finite() && v.abs() <= MAX_LENGTH
}

fn size_ok(v: f64) -> bool {
    v > 0.0 && length_ok(v)
}

fn pose_ok(pose: &urdf_rs::Pose) -> bool {
    pose.xyz.0.iter().all(|&v| length_ok(v))
        && pose
            .rpy
            .0
            .iter()
            .all(|&v| v.is_finite() && v.abs() <= MAX_ANGLE)
}

fn geometry_ok(geometry: &Geometry) -> bool {
    match geometry {
        Geometry::Box { size } => size.iter().all(|&v| size_ok(v)),
        Geometry::Cylinder { radius, length } => size_ok(*radius) && size_ok(*length),
        Geometry::Capsule { radius, length } => {
            size_ok(*radius) && *length >= 0.0 && length_ok(*length)
        }
        Geometry::Sphere { radius } => size_ok(*radius),
        Geometry::Mesh { scale, .. } => scale
            .iter()
            .all(|&s| s.is_finite() && s != 0.0 && s.abs() <= MAX_SCALE),
    }
}

impl Description {
    /// Everything wrong with the description, in file order, structure first: names
    /// defined twice, joints naming undefined links, links with two parents, cycles,
    /// several roots, then values out of their domains. Empty for a sound file.
    pub fn problems(&self) -> Vec<Problem> {
        let mut problems = self.structure_problems();
        self.value_problems(&mut problems);
        problems
    }

    fn structure_problems(&self) -> Vec<Problem> {
        let model = &self.model;
        let mut problems = Vec::new();
        // Name -> the first link of that name; a repeat is reported and left out.
        let mut links: HashMap<&str, usize> = HashMap::new();
        let mut repeated = vec![false; model.links.len()];
        for (i, link) in model.links.iter().enumerate() {
            if links.contains_key(link.name.as_str()) {
                repeated[i] = true;
                problems.push(Problem::DuplicateLink {
                    link: link.name.clone(),
                });
            } else {
                links.insert(link.name.as_str(), i);
            }
        }
        let mut joints: HashSet<&str> = HashSet::new();
        // parent[link] = the first joint that carries it.
        let mut parent: Vec<Option<usize>> = vec![None; model.links.len()];
        for (j, joint) in model.joints.iter().enumerate() {
            if !joints.insert(joint.name.as_str()) {
                problems.push(Problem::DuplicateJoint {
                    joint: joint.name.clone(),
                });
            }
            for (role, link) in [("parent", &joint.parent.link), ("child", &joint.child.link)] {
                if !links.contains_key(link.as_str()) {
                    problems.push(Problem::UndefinedLink {
                        joint: joint.name.clone(),
                        role,
                        link: link.clone(),
                    });
                }
            }
            if let Some(&child) = links.get(joint.child.link.as_str()) {
                match parent[child] {
                    Some(first) => problems.push(Problem::TwoParents {
                        link: joint.child.link.clone(),
                        first: model.joints[first].name.clone(),
                        second: joint.name.clone(),
                    }),
                    None => parent[child] = Some(j),
                }
            }
        }
        // Cycles: follow parents from every link, colouring links on the current path;
        // each link is walked once, so this is linear.
        #[derive(Clone, Copy, PartialEq)]
        enum Seen {
            No,
            OnPath,
            Done,
        }
        let mut seen = vec![Seen::No; model.links.len()];
        let mut path: Vec<usize> = Vec::new();
        for start in 0..model.links.len() {
            let mut at = Some(start);
            while let Some(link) = at {
                match seen[link] {
                    Seen::Done => break,
                    Seen::OnPath => {
                        // The path from `link` onwards is the cycle, child to parent.
                        let from = path.iter().position(|&l| l == link).unwrap_or(0);
                        let mut cycle: Vec<String> = path[from..]
                            .iter()
                            .filter_map(|&l| parent[l].map(|j| model.joints[j].name.clone()))
                            .collect();
                        cycle.reverse();
                        problems.push(Problem::Cycle { joints: cycle });
                        break;
                    }
                    Seen::No => {
                        seen[link] = Seen::OnPath;
                        path.push(link);
                        at = parent[link]
                            .and_then(|j| links.get(model.joints[j].parent.link.as_str()))
                            .copied();
                    }
                }
            }
            for &l in &path {
                seen[l] = Seen::Done;
            }
            path.clear();
        }
        let roots: Vec<String> = model
            .links
            .iter()
            .zip(parent.iter().zip(&repeated))
            .filter(|(_, (p, repeated))| p.is_none() && !**repeated)
            .map(|(l, _)| l.name.clone())
            .collect();
        if roots.len() > 1 {
            problems.push(Problem::SeveralRoots { roots });
        }
        problems
    }

    fn value_problems(&self, problems: &mut Vec<Problem>) {
        for joint in &self.model.joints {
            let joint_type = JointType::from(&joint.joint_type);
            if !pose_ok(&joint.origin) {
                problems.push(bad_pose(PoseOf::Joint(joint.name.clone()), &joint.origin));
            }
            if joint_type != JointType::Fixed {
                let axis = joint.axis.xyz.0;
                let norm = axis.iter().map(|a| a * a).sum::<f64>().sqrt();
                if !norm.is_finite() || norm < MIN_AXIS_NORM {
                    problems.push(Problem::BadAxis {
                        joint: joint.name.clone(),
                        axis,
                    });
                }
            }
            let bound = match joint_type {
                JointType::Revolute => Some(MAX_ANGLE),
                JointType::Prismatic => Some(MAX_LENGTH),
                _ => None,
            };
            if let Some(bound) = bound {
                let (lower, upper) = (joint.limit.lower, joint.limit.upper);
                let within = |v: f64| v.is_finite() && v.abs() <= bound;
                if !(within(lower) && within(upper) && lower <= upper) {
                    problems.push(Problem::BadLimits {
                        joint: joint.name.clone(),
                        joint_type,
                        lower,
                        upper,
                    });
                }
            }
        }
        for link in &self.model.links {
            let inertial = &link.inertial;
            let mass = inertial.mass.value;
            if !(mass.is_finite() && (0.0..=MAX_MASS).contains(&mass)) {
                problems.push(Problem::BadMass {
                    link: link.name.clone(),
                    mass,
                });
            }
            let i = &inertial.inertia;
            if ![i.ixx, i.ixy, i.ixz, i.iyy, i.iyz, i.izz]
                .iter()
                .all(|v| v.is_finite())
            {
                problems.push(Problem::BadInertia {
                    link: link.name.clone(),
                });
            }
            if !pose_ok(&inertial.origin) {
                problems.push(bad_pose(
                    PoseOf::Inertial(link.name.clone()),
                    &inertial.origin,
                ));
            }
            for collision in &link.collision {
                if !pose_ok(&collision.origin) {
                    problems.push(bad_pose(
                        PoseOf::Collision(link.name.clone()),
                        &collision.origin,
                    ));
                }
                let geometry = Geometry::from(&collision.geometry);
                if !geometry_ok(&geometry) {
                    problems.push(Problem::BadGeometry {
                        link: link.name.clone(),
                        geometry,
                    });
                }
            }
        }
    }
}

fn bad_pose(of: PoseOf, pose: &urdf_rs::Pose) -> Problem {
    Problem::BadPose {
        of,
        xyz: pose.xyz.0,
        rpy: pose.rpy.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn problems(text: &str) -> Vec<Problem> {
        Description::parse(text).expect("parses").problems()
    }

    const ARM: &str = r#"<robot name="arm">
      <link name="base"><inertial><mass value="2"/>
        <inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial></link>
      <link name="upper"><collision><geometry><box size="0.1 0.1 0.5"/></geometry></collision></link>
      <joint name="shoulder" type="revolute">
        <parent link="base"/><child link="upper"/>
        <origin xyz="0 0 0.3"/><axis xyz="0 0 1"/>
        <limit lower="-1" upper="1" effort="1" velocity="1"/>
      </joint>
    </robot>"#;

    #[test]
    fn a_sound_file_has_no_problems() {
        assert_eq!(problems(ARM), []);
    }

    #[test]
    fn values_outside_their_domain_are_problems() {
        let nan = problems(&ARM.replace("lower=\"-1\"", "lower=\"NaN\""));
        assert!(matches!(&nan[..], [Problem::BadLimits { lower, .. }] if lower.is_nan()));
        let reversed = problems(&ARM.replace("lower=\"-1\"", "lower=\"2\""));
        assert!(matches!(&reversed[..], [Problem::BadLimits { .. }]));
        let infinite = problems(&ARM.replace("upper=\"1\"", "upper=\"inf\""));
        assert!(matches!(&infinite[..], [Problem::BadLimits { .. }]));
        let zero = problems(&ARM.replace("<axis xyz=\"0 0 1\"/>", "<axis xyz=\"0 0 0\"/>"));
        assert!(matches!(&zero[..], [Problem::BadAxis { .. }]));
        let heavy = problems(&ARM.replace("value=\"2\"", "value=\"1e9\""));
        assert!(matches!(&heavy[..], [Problem::BadMass { .. }]));
        let huge = problems(&ARM.replace("0.1 0.1 0.5", "0.1 0.1 1e9"));
        assert!(matches!(&huge[..], [Problem::BadGeometry { .. }]));
        let far = problems(&ARM.replace("xyz=\"0 0 0.3\"", "xyz=\"0 0 inf\""));
        assert!(matches!(&far[..], [Problem::BadPose { .. }]));
        assert!(nan.iter().all(|p| !p.is_structural()));
    }

    #[test]
    fn a_file_that_is_not_a_tree_is_refused() {
        let cycle = problems(
            r#"<robot name="r"><link name="a"/><link name="b"/>
              <joint name="ab" type="fixed"><parent link="a"/><child link="b"/></joint>
              <joint name="ba" type="fixed"><parent link="b"/><child link="a"/></joint>
            </robot>"#,
        );
        assert_eq!(
            cycle,
            [Problem::Cycle {
                joints: vec!["ab".into(), "ba".into()]
            }]
        );
        let own_parent = problems(
            r#"<robot name="r"><link name="a"/>
              <joint name="aa" type="fixed"><parent link="a"/><child link="a"/></joint>
            </robot>"#,
        );
        assert_eq!(
            own_parent,
            [Problem::Cycle {
                joints: vec!["aa".into()]
            }]
        );
        let undefined = problems(
            r#"<robot name="r"><link name="a"/>
              <joint name="ax" type="fixed"><parent link="a"/><child link="x"/></joint>
            </robot>"#,
        );
        assert!(matches!(
            &undefined[..],
            [Problem::UndefinedLink { role: "child", .. }]
        ));
        let forest = problems(r#"<robot name="r"><link name="a"/><link name="b"/></robot>"#);
        assert!(matches!(&forest[..], [Problem::SeveralRoots { roots }] if roots.len() == 2));
        let twice = problems(
            r#"<robot name="r"><link name="a"/><link name="b"/><link name="c"/>
              <joint name="ab" type="fixed"><parent link="a"/><child link="b"/></joint>
              <joint name="cb" type="fixed"><parent link="c"/><child link="b"/></joint>
            </robot>"#,
        );
        assert!(twice
            .iter()
            .any(|p| matches!(p, Problem::TwoParents { .. })));
        assert!(twice.iter().all(Problem::is_structural));
    }

    #[test]
    fn long_lists_are_cut_in_messages() {
        let roots: Vec<String> = (0..10).map(|i| format!("l{i}")).collect();
        let text = Problem::SeveralRoots { roots }.to_string();
        assert!(text.ends_with("(`l0`, `l1`, `l2`, `l3` and 6 more); a robot has one root link"));
    }
}
