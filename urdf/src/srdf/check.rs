//! An SRDF against its URDF: the names it uses that the URDF does not define, and the
//! base and tip a planning group gives.

use std::collections::{HashMap, HashSet};

use super::{GroupChainError, Srdf, SrdfProblem};
use crate::description::Description;

impl Srdf {
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
}
