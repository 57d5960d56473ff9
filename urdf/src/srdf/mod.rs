//! MoveIt SRDF: the semantic description that comes with a URDF. cellc reads three of its
//! facts: `<disable_collisions>` (link pairs never checked against each other),
//! `<group>` (a planning group, whose chain can give a robot's base and tip) and
//! `<group_state>` (named configurations, usable as an arm's home). Everything else in
//! the file (end-effectors, virtual and passive joints, sphere approximations) is
//! skipped.
//!
//! An SRDF is untrusted input like a URDF: it is read with a streaming XML reader (no DTD,
//! no entity expansion beyond XML's five, no recursion, so nesting costs memory linear in
//! the file and nothing else), checked against its URDF in linear time
//! ([`Srdf::problems`]), and an error names the element and its line, never quoting
//! the text around it.
//!
//! `parse.rs` reads the text into the facts below, `check.rs` checks them against the
//! URDF and finds a group's chain.

use std::fmt;

mod check;
mod parse;
#[cfg(test)]
mod tests;

/// A planning group: what it is made of, as written.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Group {
    /// Its name.
    pub name: String,
    /// Line of its `<group>` element (from 1).
    pub line: usize,
    /// `<chain base_link tip_link>` members.
    pub chains: Vec<(String, String)>,
    /// `<joint name>` members.
    pub joints: Vec<String>,
    /// `<link name>` members.
    pub links: Vec<String>,
    /// `<group name>` members (other groups).
    pub subgroups: Vec<String>,
}

/// A named configuration of a group.
#[derive(Clone, Debug, PartialEq)]
pub struct GroupState {
    /// Its name.
    pub name: String,
    /// The group it configures.
    pub group: String,
    /// Line of its `<group_state>` element.
    pub line: usize,
    /// Joint values (radians or metres), in file order.
    pub values: Vec<(String, f64)>,
}

/// Two links whose collisions are never checked.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DisabledPair {
    /// One link.
    pub link1: String,
    /// The other.
    pub link2: String,
    /// Line of the element.
    pub line: usize,
}

/// The facts cellc reads from an SRDF.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Srdf {
    /// The `<robot name>`.
    pub name: String,
    /// Planning groups, in file order.
    pub groups: Vec<Group>,
    /// Named configurations, in file order.
    pub group_states: Vec<GroupState>,
    /// Disabled collision pairs, in file order.
    pub disabled_collisions: Vec<DisabledPair>,
}

/// Why a text is not an SRDF cellc can read.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum SrdfError {
    /// The text is not well-formed XML.
    NotXml {
        /// The line where the reader stopped.
        line: usize,
    },
    /// The outermost element is not `<robot>`.
    NotSrdf,
    /// An element lacks an attribute it needs.
    MissingAttribute {
        /// The element.
        element: &'static str,
        /// The attribute.
        attribute: &'static str,
        /// Its line.
        line: usize,
    },
    /// A `<group_state>` joint value that is not one number.
    BadValue {
        /// The joint.
        joint: String,
        /// Its line.
        line: usize,
    },
    /// A member element outside the element it belongs in (`<chain>` outside a group).
    Misplaced {
        /// The element.
        element: &'static str,
        /// Its line.
        line: usize,
    },
}

impl fmt::Display for SrdfError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SrdfError::NotXml { line } => write!(f, "line {line}: not well-formed XML"),
            SrdfError::NotSrdf => f.write_str("its outermost element is not `<robot>`"),
            SrdfError::MissingAttribute {
                element,
                attribute,
                line,
            } => write!(f, "line {line}: `<{element}>` has no `{attribute}`"),
            SrdfError::BadValue { joint, line } => write!(
                f,
                "line {line}: the value of joint `{joint}` is not one finite number"
            ),
            SrdfError::Misplaced { element, line } => {
                write!(
                    f,
                    "line {line}: `<{element}>` is not inside the element it belongs to"
                )
            }
        }
    }
}

impl std::error::Error for SrdfError {}

/// What an SRDF says that its URDF contradicts.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum SrdfProblem {
    /// A link or joint the URDF does not define.
    Unknown {
        /// `link` or `joint`.
        what: &'static str,
        /// The name.
        name: String,
        /// The element that names it.
        element: &'static str,
        /// Its line.
        line: usize,
    },
    /// A group or group state that names a group the SRDF does not define.
    UnknownGroup {
        /// The group name.
        group: String,
        /// Its line.
        line: usize,
    },
    /// Two groups with one name.
    DuplicateGroup {
        /// The name.
        group: String,
        /// The second one's line.
        line: usize,
    },
}

impl fmt::Display for SrdfProblem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SrdfProblem::Unknown {
                what,
                name,
                element,
                line,
            } => write!(
                f,
                "line {line}: `<{element}>` names {what} `{name}`, which the URDF does not define"
            ),
            SrdfProblem::UnknownGroup { group, line } => {
                write!(f, "line {line}: no group `{group}` is defined")
            }
            SrdfProblem::DuplicateGroup { group, line } => {
                write!(f, "line {line}: group `{group}` is defined twice")
            }
        }
    }
}

/// Why a group gives no base and tip.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum GroupChainError {
    /// The SRDF has no group of that name.
    Unknown,
    /// The group has neither a `<chain>` nor joints.
    NoChainOrJoints,
    /// The group's joints do not form one path from a link down to another.
    NotASerialChain,
}

impl fmt::Display for GroupChainError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            GroupChainError::Unknown => "the SRDF defines no such group",
            GroupChainError::NoChainOrJoints => {
                "the group has no `<chain>` and no `<joint>` members (only links or other groups)"
            }
            GroupChainError::NotASerialChain => {
                "the group's joints do not form one serial chain from a base link to a tip link"
            }
        })
    }
}

impl Srdf {
    /// The group of that name.
    pub fn group(&self, name: &str) -> Option<&Group> {
        self.groups.iter().find(|g| g.name == name)
    }

    /// The states named `name`, each with the group it configures.
    pub fn states_named<'a>(&'a self, name: &'a str) -> impl Iterator<Item = &'a GroupState> {
        self.group_states.iter().filter(move |s| s.name == name)
    }
}
