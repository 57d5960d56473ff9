//! A parsed URDF with the indexes the walks need.

use std::collections::HashMap;
use std::fmt;

use cellc_schema::math::{Iso, Quat};
use nalgebra as na;

/// Why a URDF text is not a robot description.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum ParseError {
    /// The reader refused the text.
    Invalid {
        /// The reader's explanation (its own words, without serde's category prefix).
        reason: String,
    },
    /// The reader crashed on the text (caught).
    ReaderFailed,
    /// The text has no `<robot` element at all, so it is not a URDF (and the reader's
    /// message, which may quote it, is not passed on).
    NotUrdf,
    /// The text is a xacro file (it has `<xacro:` elements): macros to expand into a URDF
    /// first.
    Xacro,
}

impl fmt::Display for ParseError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ParseError::Invalid { reason } => f.write_str(reason),
            ParseError::ReaderFailed => f.write_str("the reader failed on this file"),
            ParseError::NotUrdf => f.write_str("it has no `<robot>` element, so it is not a URDF"),
            ParseError::Xacro => {
                f.write_str("it is a xacro file (macros that expand into a URDF), not a URDF")
            }
        }
    }
}

impl std::error::Error for ParseError {}

/// A robot description: links, joints and collision geometry, as a URDF states them.
#[derive(Clone, Debug)]
pub struct Description {
    pub(crate) model: urdf_rs::Robot,
    /// Link name -> index into `model.links` (the last one, should a name repeat).
    link_index: HashMap<String, usize>,
    /// Child link -> index of the joint that carries it (a URDF is a tree: at most one;
    /// the last one, should a malformed file have several).
    pub(crate) parent_joint: HashMap<String, usize>,
    /// Parent link -> its fixed joints, in file order.
    pub(crate) fixed_children: HashMap<String, Vec<usize>>,
}

impl Description {
    /// Reads a URDF text.
    pub fn parse(text: &str) -> Result<Description, ParseError> {
        // Any file may be named as a URDF; one that is not even meant to be a robot
        // description is refused before the reader can quote it in an error.
        if !text.contains("<robot") {
            return Err(ParseError::NotUrdf);
        }
        // A URDF that xacro wrote keeps the `xmlns:xacro` declaration, so only xacro's
        // elements (includes, macros, properties) tell a file still to be expanded.
        if text.contains("<xacro:") {
            return Err(ParseError::Xacro);
        }
        // The URDF reader is a third-party XML stack: guard against it panicking on
        // hostile input so that a bad file can never take a checker or a planner down.
        let model = match std::panic::catch_unwind(|| urdf_rs::read_from_string(text)) {
            Ok(Ok(model)) => model,
            Ok(Err(error)) => {
                // The reader prefixes serde's own category ("custom: "), which means
                // nothing to a cell engineer.
                let reason = error.to_string();
                let reason = reason.strip_prefix("custom: ").unwrap_or(&reason);
                return Err(ParseError::Invalid {
                    reason: reason.to_string(),
                });
            }
            Err(_) => return Err(ParseError::ReaderFailed),
        };
        let link_index = model
            .links
            .iter()
            .enumerate()
            .map(|(i, l)| (l.name.clone(), i))
            .collect();
        let parent_joint = model
            .joints
            .iter()
            .enumerate()
            .map(|(i, j)| (j.child.link.clone(), i))
            .collect();
        let mut fixed_children: HashMap<String, Vec<usize>> = HashMap::new();
        for (i, joint) in model.joints.iter().enumerate() {
            if matches!(joint.joint_type, urdf_rs::JointType::Fixed) {
                fixed_children
                    .entry(joint.parent.link.clone())
                    .or_default()
                    .push(i);
            }
        }
        Ok(Description {
            model,
            link_index,
            parent_joint,
            fixed_children,
        })
    }

    /// The robot's name.
    pub fn name(&self) -> &str {
        &self.model.name
    }

    /// Every link's name, in file order.
    pub fn links(&self) -> impl Iterator<Item = &str> {
        self.model.links.iter().map(|l| l.name.as_str())
    }

    /// Every joint as (name, parent link, child link), in file order.
    pub fn joints(&self) -> impl Iterator<Item = (&str, &str, &str)> {
        self.model.joints.iter().map(|j| {
            (
                j.name.as_str(),
                j.parent.link.as_str(),
                j.child.link.as_str(),
            )
        })
    }

    /// Whether the description has a link of that name.
    pub fn has_link(&self, name: &str) -> bool {
        self.link_index.contains_key(name)
    }

    /// The root link: the first (in file order) that no joint carries.
    pub fn root(&self) -> Option<&str> {
        self.links().find(|l| !self.parent_joint.contains_key(*l))
    }

    pub(crate) fn link(&self, name: &str) -> Option<&urdf_rs::Link> {
        self.link_index.get(name).map(|&i| &self.model.links[i])
    }

    /// The link and every link fixed to it, directly or through other fixed joints, each
    /// with its pose in `link`'s frame: depth first, children in file order, `link` first.
    /// These are the links that move rigidly with `link`.
    pub fn attached_links<'a>(&'a self, link: &'a str) -> Vec<(&'a str, Iso)> {
        let mut found = Vec::new();
        let mut stack: Vec<(&str, Iso)> = vec![(link, Iso::identity())];
        while let Some((name, pose)) = stack.pop() {
            if found.len() >= self.model.links.len() {
                break; // a malformed cycle of fixed joints
            }
            found.push((name, pose));
            if let Some(children) = self.fixed_children.get(name) {
                // Reversed so that the stack pops them in file order.
                for &j in children.iter().rev() {
                    let joint = &self.model.joints[j];
                    stack.push((joint.child.link.as_str(), pose * iso(&joint.origin)));
                }
            }
        }
        found
    }
}

/// Whether a path names a xacro file by its extension (`.xacro`, `.urdf.xacro`).
pub fn is_xacro_path(path: &str) -> bool {
    path.to_ascii_lowercase().ends_with(".xacro")
}

/// A URDF `<origin xyz rpy>` as a transform. URDF's rpy are fixed-axis roll, pitch,
/// yaw (R = Rz(yaw) Ry(pitch) Rx(roll)), which is nalgebra's Euler-angle convention.
pub(crate) fn iso(pose: &urdf_rs::Pose) -> Iso {
    let [x, y, z] = pose.xyz.0;
    let [roll, pitch, yaw] = pose.rpy.0;
    Iso::from_parts(
        na::Translation3::new(x, y, z),
        Quat::from_euler_angles(roll, pitch, yaw),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn what_is_not_a_robot_is_not_quoted() {
        let secret = "<config><token>secret</token></config>";
        assert_eq!(
            Description::parse(secret).map(|_| ()),
            Err(ParseError::NotUrdf)
        );
    }

    #[test]
    fn xacro_files_are_named_and_expanded_urdfs_are_not() {
        let xacro = r#"<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">
            <xacro:include filename="arm.xacro"/><xacro:arm prefix=""/></robot>"#;
        assert_eq!(
            Description::parse(xacro).map(|_| ()),
            Err(ParseError::Xacro)
        );
        let expanded =
            r#"<robot name="r" xmlns:xacro="http://wiki.ros.org/xacro"><link name="a"/></robot>"#;
        assert!(Description::parse(expanded).is_ok());
        assert!(is_xacro_path("robots/ur5.urdf.xacro"));
        assert!(is_xacro_path("ur5.XACRO"));
        assert!(!is_xacro_path("ur5.urdf"));
    }

    #[test]
    fn reader_errors_lose_the_serde_prefix() {
        match Description::parse("<robot name='x'><link") {
            Err(ParseError::Invalid { reason }) => assert!(!reason.starts_with("custom: ")),
            other => panic!("expected a parse error, got {other:?}"),
        }
    }
}
