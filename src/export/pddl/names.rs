//! PDDL names for an object's graph: valid identifiers, unique, and the same for the same
//! cell whatever is exported.
//!
//! PDDL names are case-insensitive (Fast Downward lowercases them) and made of letters,
//! digits, `-` and `_`, starting with a letter. A cell's names may be anything between
//! backticks, so each part is lowercased and every other character becomes `_`; parts
//! are joined with `__`. Two names that end up equal are told apart by a suffix `-2`,
//! `-3`, ... in declaration order (a sanitised name never contains `-`, so a suffixed name
//! never meets an unsuffixed one). Every allocation runs over all of the artifact's
//! objects, nodes, arcs or requests in order, so a name never depends on which part of
//! the cell is exported.

use std::collections::BTreeSet;

use cellc_schema::{ArcKind, Artifact, Node, ObjectId};

/// Words that no generated name may be: PDDL's own, and the names the encoding uses for
/// its types, predicates, action and files (`domain.pddl`).
const RESERVED: &[&str] = &[
    "and", "arrive", "arrived", "at", "define", "domain", "either", "exists", "forall", "imply",
    "item", "moved", "not", "number", "object", "or", "problem", "state", "target", "when",
];

/// The PDDL names of one object's graph.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Names {
    /// The domain: the cell and the object.
    pub domain: String,
    /// The object as a PDDL object of type `item` (also the folder of its files).
    pub item: String,
    /// Per graph node: the state constant, `EE__GRASP__WS`.
    pub states: Vec<String>,
    /// Per graph arc: the action, `move__EE__GRASP__FROM__TO` or
    /// `transition__EE__GRASP__EE__GRASP__WS`.
    pub actions: Vec<String>,
}

impl Names {
    /// The names of `object`'s graph in `artifact` (an id out of range gives empty lists).
    pub fn of(artifact: &Artifact, object: ObjectId) -> Names {
        let item = items(artifact)
            .into_iter()
            .nth(object.index())
            .unwrap_or_else(|| "x".to_string());
        let Some(o) = artifact.objects.get(object.index()) else {
            return Names {
                domain: identifier(&[&artifact.cell]),
                item,
                states: Vec::new(),
                actions: Vec::new(),
            };
        };
        let node_parts = |n: &Node| {
            [
                artifact.end_effector_name(n.end_effector).to_string(),
                artifact.grasp_name(object, n.grasp).to_string(),
                artifact.workspace_name(n.workspace).to_string(),
            ]
        };
        let mut taken = Allocator::new();
        taken.reserve(&item);
        let states = o
            .graph
            .nodes
            .iter()
            .map(|n| {
                let [e, g, w] = node_parts(n);
                taken.unique(identifier(&[&e, &g, &w]))
            })
            .collect();
        let mut taken = Allocator::new();
        let actions = o
            .graph
            .arcs
            .iter()
            .map(|arc| {
                let (Some(from), Some(to)) = (
                    o.graph.nodes.get(arc.from as usize),
                    o.graph.nodes.get(arc.to as usize),
                ) else {
                    return taken.unique(identifier(&["arc"]));
                };
                let [e1, g1, w1] = node_parts(from);
                let [e2, g2, w2] = node_parts(to);
                taken.unique(match arc.kind {
                    ArcKind::Move => identifier(&["move", &e1, &g1, &w1, &w2]),
                    ArcKind::Transition => identifier(&["transition", &e1, &g1, &e2, &g2, &w1]),
                })
            })
            .collect();
        Names {
            domain: identifier(&[&artifact.cell, &o.name]),
            item,
            states,
            actions,
        }
    }
}

/// The PDDL problem names of the requests of `object` the cell declares: (index into
/// `artifact.requests`, name), in declaration order.
pub fn problem_ids(artifact: &Artifact, object: ObjectId) -> Vec<(usize, String)> {
    let mut taken = Allocator::new();
    artifact
        .requests
        .iter()
        .enumerate()
        .filter(|(_, r)| r.object == object)
        .map(|(i, r)| (i, taken.unique(identifier(&[&r.name]))))
        .collect()
}

/// Every object's `item` name, in object order.
fn items(artifact: &Artifact) -> Vec<String> {
    let mut taken = Allocator::new();
    artifact
        .objects
        .iter()
        .map(|o| taken.unique(identifier(&[&o.name])))
        .collect()
}

/// `parts` sanitised and joined with `__`, starting with a letter.
fn identifier(parts: &[&str]) -> String {
    let joined = parts
        .iter()
        .map(|part| {
            part.chars()
                .map(|c| c.to_ascii_lowercase())
                .map(|c| {
                    if c.is_ascii_alphanumeric() || c == '_' {
                        c
                    } else {
                        '_'
                    }
                })
                .collect::<String>()
        })
        .collect::<Vec<String>>()
        .join("__");
    if joined.starts_with(|c: char| c.is_ascii_lowercase()) {
        joined
    } else {
        format!("x{joined}")
    }
}

/// Names handed out so far in one namespace, with the reserved words.
struct Allocator {
    taken: BTreeSet<String>,
}

impl Allocator {
    fn new() -> Allocator {
        Allocator {
            taken: RESERVED.iter().map(|w| w.to_string()).collect(),
        }
    }

    /// Marks a name of another namespace that shares this one's (the item beside the
    /// state constants).
    fn reserve(&mut self, name: &str) {
        self.taken.insert(name.to_string());
    }

    /// `base`, or `base-K` with the smallest K from 2 that is still free.
    fn unique(&mut self, base: String) -> String {
        if self.taken.insert(base.clone()) {
            return base;
        }
        let mut k = 2u64;
        loop {
            let candidate = format!("{base}-{k}");
            if self.taken.insert(candidate.clone()) {
                return candidate;
            }
            k += 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn identifiers_are_lowercase_pddl_names() {
        assert_eq!(identifier(&["Left Arm", "g1", "w1"]), "left_arm__g1__w1");
        assert_eq!(identifier(&["_hand", "é"]), "x_hand___");
        assert_eq!(identifier(&["2nd"]), "x2nd");
    }

    #[test]
    fn equal_names_get_suffixes_in_order() {
        let mut taken = Allocator::new();
        assert_eq!(taken.unique("box".into()), "box");
        assert_eq!(taken.unique("box".into()), "box-2");
        assert_eq!(taken.unique("box".into()), "box-3");
        assert_eq!(taken.unique("at".into()), "at-2");
        assert_eq!(taken.unique("domain".into()), "domain-2");
    }
}
