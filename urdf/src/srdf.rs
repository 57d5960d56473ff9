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

use std::collections::{HashMap, HashSet};
use std::fmt;

use quick_xml::events::{BytesStart, Event};
use quick_xml::Reader;

use crate::description::Description;

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

/// Line numbers of byte offsets that only grow, counted incrementally (linear in all).
struct Lines<'a> {
    text: &'a str,
    offset: usize,
    line: usize,
}

impl Lines<'_> {
    fn at(&mut self, offset: u64) -> usize {
        let offset = usize::try_from(offset)
            .unwrap_or(self.text.len())
            .min(self.text.len());
        if offset > self.offset {
            let bytes = self.text.as_bytes();
            self.line += bytes[self.offset..offset]
                .iter()
                .filter(|&&b| b == b'\n')
                .count();
            self.offset = offset;
        }
        self.line
    }
}

/// The attribute `name` of an element, unescaped; `None` when absent or undecodable.
fn attribute(element: &BytesStart<'_>, name: &[u8], reader: &Reader<&[u8]>) -> Option<String> {
    element
        .attributes()
        .flatten()
        .find(|a| a.key.as_ref() == name)
        .and_then(|a| a.decode_and_unescape_value(reader.decoder()).ok())
        .map(|v| v.into_owned())
}

impl Srdf {
    /// Reads an SRDF text.
    pub fn parse(text: &str) -> Result<Srdf, SrdfError> {
        let mut reader = Reader::from_reader(text.as_bytes());
        let mut lines = Lines {
            text,
            offset: 0,
            line: 1,
        };
        let mut srdf = Srdf::default();
        // Open elements, outermost first (local names; members are known by their parent).
        let mut open: Vec<Vec<u8>> = Vec::new();
        let mut seen_root = false;
        loop {
            let start = reader.buffer_position();
            let event = reader.read_event().map_err(|_| SrdfError::NotXml {
                line: lines.at(reader.error_position()),
            })?;
            let (element, empty) = match event {
                Event::Start(e) => (e, false),
                Event::Empty(e) => (e, true),
                Event::End(_) => {
                    open.pop();
                    continue;
                }
                Event::Eof => break,
                _ => continue,
            };
            let line = lines.at(start);
            let name = element.local_name().as_ref().to_vec();
            if open.is_empty() {
                if seen_root || name != b"robot" {
                    return Err(SrdfError::NotSrdf);
                }
                seen_root = true;
                srdf.name = attribute(&element, b"name", &reader).unwrap_or_default();
            } else {
                let parent = open.last().map(Vec::as_slice);
                srdf.element(&name, parent, open.len(), &element, &reader, line)?;
            }
            if !empty {
                open.push(name);
            }
        }
        if !seen_root {
            return Err(SrdfError::NotSrdf);
        }
        Ok(srdf)
    }

    /// One element at `depth` (1 = a child of `<robot>`) inside `parent`.
    fn element(
        &mut self,
        name: &[u8],
        parent: Option<&[u8]>,
        depth: usize,
        element: &BytesStart<'_>,
        reader: &Reader<&[u8]>,
        line: usize,
    ) -> Result<(), SrdfError> {
        let need = |element_name: &'static str, attribute_name: &'static str| {
            attribute(element, attribute_name.as_bytes(), reader).ok_or(
                SrdfError::MissingAttribute {
                    element: element_name,
                    attribute: attribute_name,
                    line,
                },
            )
        };
        let in_group = depth == 2 && parent == Some(b"group".as_slice());
        let in_state = depth == 2 && parent == Some(b"group_state".as_slice());
        fn last_group<'s>(
            srdf: &'s mut Srdf,
            element: &'static str,
            line: usize,
        ) -> Result<&'s mut Group, SrdfError> {
            srdf.groups
                .last_mut()
                .ok_or(SrdfError::Misplaced { element, line })
        }
        match (depth, name) {
            (1, b"group") => self.groups.push(Group {
                name: need("group", "name")?,
                line,
                ..Group::default()
            }),
            (1, b"group_state") => self.group_states.push(GroupState {
                name: need("group_state", "name")?,
                group: need("group_state", "group")?,
                line,
                values: Vec::new(),
            }),
            (1, b"disable_collisions") => self.disabled_collisions.push(DisabledPair {
                link1: need("disable_collisions", "link1")?,
                link2: need("disable_collisions", "link2")?,
                line,
            }),
            (2, b"chain") if in_group => {
                let pair = (need("chain", "base_link")?, need("chain", "tip_link")?);
                last_group(self, "chain", line)?.chains.push(pair);
            }
            (2, b"joint") if in_group => {
                let joint = need("joint", "name")?;
                last_group(self, "joint", line)?.joints.push(joint);
            }
            (2, b"link") if in_group => {
                let link = need("link", "name")?;
                last_group(self, "link", line)?.links.push(link);
            }
            (2, b"group") if in_group => {
                let group = need("group", "name")?;
                last_group(self, "group", line)?.subgroups.push(group);
            }
            (2, b"joint") if in_state => {
                let joint = need("joint", "name")?;
                let value = need("joint", "value")?;
                let value = value
                    .trim()
                    .parse::<f64>()
                    .ok()
                    .filter(|v| v.is_finite())
                    .ok_or(SrdfError::BadValue {
                        joint: joint.clone(),
                        line,
                    })?;
                let state = self.group_states.last_mut().ok_or(SrdfError::Misplaced {
                    element: "joint",
                    line,
                })?;
                state.values.push((joint, value));
            }
            (_, b"chain") => {
                return Err(SrdfError::Misplaced {
                    element: "chain",
                    line,
                })
            }
            // Everything else (end-effectors, virtual joints, ...) says nothing cellc uses.
            _ => {}
        }
        Ok(())
    }

    /// Everything the SRDF names that its URDF (or the SRDF itself) does not define, in
    /// file order of kind: groups, group states, disabled pairs. Linear in both files.
    pub fn problems(&self, urdf: &Description) -> Vec<SrdfProblem> {
        let links: HashSet<&str> = urdf.links().collect();
        let joints: HashSet<&str> = urdf.joints().map(|(name, _, _)| name).collect();
        let mut problems = Vec::new();
        let mut unknown = |what, name: &str, element, line, known: &HashSet<&str>| {
            if !known.contains(name) {
                problems.push(SrdfProblem::Unknown {
                    what,
                    name: name.to_string(),
                    element,
                    line,
                });
            }
        };
        let mut groups: HashSet<&str> = HashSet::new();
        let mut duplicates = Vec::new();
        for group in &self.groups {
            if !groups.insert(group.name.as_str()) {
                duplicates.push(SrdfProblem::DuplicateGroup {
                    group: group.name.clone(),
                    line: group.line,
                });
            }
            for (base, tip) in &group.chains {
                unknown("link", base, "chain", group.line, &links);
                unknown("link", tip, "chain", group.line, &links);
            }
            for joint in &group.joints {
                unknown("joint", joint, "group", group.line, &joints);
            }
            for link in &group.links {
                unknown("link", link, "group", group.line, &links);
            }
        }
        for state in &self.group_states {
            for (joint, _) in &state.values {
                unknown("joint", joint, "group_state", state.line, &joints);
            }
        }
        for pair in &self.disabled_collisions {
            unknown("link", &pair.link1, "disable_collisions", pair.line, &links);
            unknown("link", &pair.link2, "disable_collisions", pair.line, &links);
        }
        problems.extend(duplicates);
        for group in &self.groups {
            for sub in &group.subgroups {
                if !groups.contains(sub.as_str()) {
                    problems.push(SrdfProblem::UnknownGroup {
                        group: sub.clone(),
                        line: group.line,
                    });
                }
            }
        }
        for state in &self.group_states {
            if !groups.contains(state.group.as_str()) {
                problems.push(SrdfProblem::UnknownGroup {
                    group: state.group.clone(),
                    line: state.line,
                });
            }
        }
        problems
    }

    /// The group of that name.
    pub fn group(&self, name: &str) -> Option<&Group> {
        self.groups.iter().find(|g| g.name == name)
    }

    /// The base and tip links of a group: its first `<chain>`, or else the path its
    /// joints make (the parent link of the first joint down to the child of the last).
    pub fn group_chain(
        &self,
        name: &str,
        urdf: &Description,
    ) -> Result<(String, String), GroupChainError> {
        let group = self.group(name).ok_or(GroupChainError::Unknown)?;
        if let Some((base, tip)) = group.chains.first() {
            return Ok((base.clone(), tip.clone()));
        }
        if group.joints.is_empty() {
            return Err(GroupChainError::NoChainOrJoints);
        }
        let ends: HashMap<&str, (&str, &str)> = urdf
            .joints()
            .map(|(joint, parent, child)| (joint, (parent, child)))
            .collect();
        let mut parents = HashSet::new();
        let mut children = HashSet::new();
        for joint in &group.joints {
            let &(parent, child) = ends
                .get(joint.as_str())
                .ok_or(GroupChainError::NotASerialChain)?;
            parents.insert(parent);
            children.insert(child);
        }
        // The base is the one parent no group joint carries; the tip the one child that
        // carries no group joint.
        let mut bases = parents.difference(&children);
        let mut tips = children.difference(&parents);
        let (Some(base), None, Some(tip), None) =
            (bases.next(), bases.next(), tips.next(), tips.next())
        else {
            return Err(GroupChainError::NotASerialChain);
        };
        let chain = urdf
            .chain(base, tip)
            .map_err(|_| GroupChainError::NotASerialChain)?;
        let on_chain: HashSet<&str> = chain.joints.iter().map(|j| j.name.as_str()).collect();
        if group.joints.iter().all(|j| on_chain.contains(j.as_str())) {
            Ok((base.to_string(), tip.to_string()))
        } else {
            Err(GroupChainError::NotASerialChain)
        }
    }

    /// The states named `name`, each with the group it configures.
    pub fn states_named<'a>(&'a self, name: &'a str) -> impl Iterator<Item = &'a GroupState> {
        self.group_states.iter().filter(move |s| s.name == name)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const URDF: &str = r#"<robot name="r">
      <link name="l0"/><link name="l1"/><link name="l2"/><link name="hand"/>
      <joint name="j1" type="revolute"><parent link="l0"/><child link="l1"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
      <joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
      <joint name="j3" type="fixed"><parent link="l2"/><child link="hand"/></joint>
    </robot>"#;

    const SRDF: &str = r#"<?xml version="1.0"?>
    <!-- a comment -->
    <robot name="r">
      <group name="arm"><joint name="j1"/><joint name="j2"/></group>
      <group name="tool"><chain base_link="l0" tip_link="hand"/></group>
      <group name="both"><group name="arm"/><group name="tool"/></group>
      <group_state name="ready" group="arm">
        <joint name="j1" value="0.5"/>
        <joint name="j2" value="-0.25"/>
      </group_state>
      <end_effector name="ee" parent_link="hand" group="arm"/>
      <disable_collisions link1="l0" link2="l2" reason="Never"/>
    </robot>"#;

    #[test]
    fn reads_groups_states_and_disabled_pairs() {
        let srdf = Srdf::parse(SRDF).expect("parses");
        assert_eq!(srdf.name, "r");
        assert_eq!(srdf.groups.len(), 3);
        assert_eq!(srdf.groups[0].joints, ["j1", "j2"]);
        assert_eq!(srdf.groups[2].subgroups, ["arm", "tool"]);
        let ready: Vec<_> = srdf.states_named("ready").collect();
        assert_eq!(ready[0].values, [("j1".into(), 0.5), ("j2".into(), -0.25)]);
        assert_eq!(ready[0].line, 7);
        assert_eq!(
            srdf.disabled_collisions,
            [DisabledPair {
                link1: "l0".into(),
                link2: "l2".into(),
                line: 12
            }]
        );
        let urdf = Description::parse(URDF).expect("urdf");
        assert!(srdf.problems(&urdf).is_empty());
        assert_eq!(
            srdf.group_chain("arm", &urdf),
            Ok(("l0".into(), "l2".into()))
        );
        assert_eq!(
            srdf.group_chain("tool", &urdf),
            Ok(("l0".into(), "hand".into()))
        );
        assert_eq!(
            srdf.group_chain("both", &urdf),
            Err(GroupChainError::NoChainOrJoints)
        );
        assert_eq!(srdf.group_chain("x", &urdf), Err(GroupChainError::Unknown));
    }

    #[test]
    fn names_the_urdf_does_not_define_are_problems() {
        let srdf = Srdf::parse(
            r#"<robot name="r">
              <group name="arm"><joint name="j9"/></group>
              <group name="arm"><link name="l0"/></group>
              <group_state name="s" group="nope"><joint name="j1" value="0"/></group_state>
              <disable_collisions link1="l0" link2="ghost"/>
            </robot>"#,
        )
        .expect("parses");
        let urdf = Description::parse(URDF).expect("urdf");
        let problems: Vec<String> = srdf.problems(&urdf).iter().map(|p| p.to_string()).collect();
        assert_eq!(
            problems,
            [
                "line 2: `<group>` names joint `j9`, which the URDF does not define",
                "line 5: `<disable_collisions>` names link `ghost`, which the URDF does not define",
                "line 3: group `arm` is defined twice",
                "line 4: no group `nope` is defined",
            ]
        );
        assert_eq!(
            srdf.group_chain("arm", &urdf),
            Err(GroupChainError::NotASerialChain)
        );
    }

    #[test]
    fn malformed_files_are_errors_with_lines_and_no_quotes() {
        let err = |text: &str| Srdf::parse(text).map(|_| ()).unwrap_err().to_string();
        assert_eq!(
            err("<robot>\n<group name='a'>\n</robot>"),
            "line 3: not well-formed XML"
        );
        assert_eq!(
            err("<config>secret</config>"),
            "its outermost element is not `<robot>`"
        );
        assert_eq!(err(""), "its outermost element is not `<robot>`");
        assert_eq!(
            err("<robot>\n<disable_collisions link1='a'/></robot>"),
            "line 2: `<disable_collisions>` has no `link2`"
        );
        assert_eq!(
            err("<robot><group_state name='s' group='g'><joint name='j' value='NaN'/></group_state></robot>"),
            "line 1: the value of joint `j` is not one finite number"
        );
        assert_eq!(
            err("<robot><chain base_link='a' tip_link='b'/></robot>"),
            "line 1: `<chain>` is not inside the element it belongs to"
        );
        // A DTD's entities are not expanded: the name that needs one is not read.
        let entity = Srdf::parse("<!DOCTYPE r [<!ENTITY e 'x'>]><robot name='&e;'/>");
        assert_eq!(entity.map(|s| s.name), Ok(String::new()));
    }
}
