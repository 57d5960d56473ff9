//! Hypothetical changes to the cell, as the nodes and arcs they would add on top of the
//! object's graph (by the shared graph rules, [`cellc_schema::rules`]), and the cheapest
//! start-to-goal path through them.

use std::borrow::Cow;
use std::collections::HashMap;

use cellc_schema::rules::Edit;
use cellc_schema::{EndEffectorId, GraspId, Node, WorkspaceId};

use super::context::Ctx;
use crate::plan::search::{cheapest_exit, Visit};

/// A hypothetical change, as an orderable key (the public [`super::Change`] holds reasons
/// with floats, which cannot be ordered).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub(super) enum Key {
    /// Unordered grasp pair (smaller first), declared both ways.
    Transition(GraspId, GraspId),
    /// Unordered workspace pair.
    Adjacency(WorkspaceId, WorkspaceId),
    /// (end-effector, workspace).
    Reach(EndEffectorId, WorkspaceId),
    /// `allow contact` for a group of pairs of bodies (see [`Ctx::contact_group`]): every
    /// arc lost for their collisions comes back.
    Contact(u32),
}

impl Key {
    /// Rank of the kind of edit: a transition is one line in the object, an adjacency one
    /// line in the cell, an allowed contact accepts a collision the geometry has, a reach
    /// extension needs a robot moved or replaced.
    pub fn class(self) -> u8 {
        match self {
            Key::Transition(..) => 0,
            Key::Adjacency(..) => 1,
            Key::Contact(_) => 2,
            Key::Reach(..) => 3,
        }
    }
}

/// Hypothetical nodes and arcs on top of the graph. New nodes are numbered after the
/// graph's.
#[derive(Default)]
pub(super) struct Overlay {
    pub nodes: Vec<Node>,
    pub index: HashMap<Node, u32>,
    pub arcs: Vec<NewArc>,
}

/// A hypothetical arc and the change (index into the change list) that makes it.
#[derive(Clone, Copy)]
pub(super) struct NewArc {
    pub from: u32,
    pub to: u32,
    pub weight: f64,
    pub change: usize,
}

/// A start-to-goal path through hypothetical arcs.
pub(super) struct Route {
    pub cost: f64,
    /// The hypothetical arcs used, in path order.
    pub arcs: Vec<NewArc>,
}

impl Ctx<'_> {
    pub fn node_at(&self, ov: &Overlay, n: Node) -> Option<u32> {
        self.index.get(&n).or_else(|| ov.index.get(&n)).copied()
    }

    /// A node of the graph or of the overlay.
    pub fn overlay_node(&self, ov: &Overlay, i: u32) -> Option<Node> {
        match (i as usize).checked_sub(self.nodes.len()) {
            Some(k) => ov.nodes.get(k).copied(),
            None => Some(self.node(i)),
        }
    }

    /// Every node and arc that `changes` would add, by the graph rules: the rules are
    /// edited with every change first (a transition declared together with a reach
    /// extension is also made in the new workspace), then each change contributes the arcs
    /// the rules give for it. A declaration never brings back an arc that was pruned or
    /// failed (the same check would remove it again); only [`Key::Contact`] does, for the
    /// arcs its collision removed.
    pub fn apply(&self, changes: &[Key]) -> Overlay {
        let mut ov = Overlay::default();
        // Most hypotheses only declare transitions: the rules are copied only to edit them.
        let mut rules = Cow::Borrowed(&self.rules);
        for &key in changes {
            match key {
                Key::Reach(e, w) => rules.to_mut().extend_reach(e, w),
                Key::Adjacency(a, b) => rules.to_mut().declare_adjacency(a, b),
                Key::Transition(..) | Key::Contact(_) => {}
            }
        }
        let base = self.nodes.len() as u32;
        for &key in changes {
            if let Key::Reach(e, w) = key {
                for n in rules.states_at(&self.object_rules, e, w) {
                    if !self.index.contains_key(&n) && !ov.index.contains_key(&n) {
                        ov.index.insert(n, base + ov.nodes.len() as u32);
                        ov.nodes.push(n);
                    }
                }
            }
        }
        for (ci, &key) in changes.iter().enumerate() {
            let edits = match key {
                Key::Transition(a, b) if a != b => {
                    vec![Edit::Transition(a, b), Edit::Transition(b, a)]
                }
                Key::Transition(a, _) => vec![Edit::Transition(a, a)],
                Key::Adjacency(a, b) => vec![Edit::Adjacency(a, b)],
                Key::Reach(e, w) => vec![Edit::Reach(e, w)],
                Key::Contact(g) => {
                    for (i, l) in self.lost.iter().enumerate() {
                        if self.contact_key(i) == Some(g) {
                            ov.arcs.push(NewArc {
                                from: l.from,
                                to: l.to,
                                weight: l.weight,
                                change: ci,
                            });
                        }
                    }
                    Vec::new()
                }
            };
            for edit in edits {
                for (x, y) in rules.added_by(&self.object_rules, edit) {
                    // A move changes workspace, a transition never does.
                    let weight = if x.workspace != y.workspace {
                        self.art.weights.move_weight
                    } else {
                        self.art.weights.transition_weight
                    };
                    if let (Some(from), Some(to)) = (self.node_at(&ov, x), self.node_at(&ov, y)) {
                        if !self.lost_pairs.contains(&(from, to)) {
                            ov.arcs.push(NewArc {
                                from,
                                to,
                                weight,
                                change: ci,
                            });
                        }
                    }
                }
            }
        }
        ov
    }

    /// The cheapest start-to-goal path through the overlay, if any. R and G are already
    /// known, so the search starts at the tails of hypothetical arcs inside R (at their
    /// distance from the start) and ends on entering G (adding the distance to the goal);
    /// only the states in between are explored. G is tested first: when the start must be
    /// left, it lies in both, and coming back to it is reaching the goal.
    pub fn connect(&self, ov: &Overlay) -> Option<Route> {
        let n = self.nodes.len();
        let total = n + ov.nodes.len();
        // Sparse: the search rarely leaves the few states between R and G.
        let mut extra: HashMap<u32, Vec<usize>> = HashMap::new();
        for (i, a) in ov.arcs.iter().enumerate() {
            extra.entry(a.from).or_default().push(i);
        }
        let sources = ov.arcs.iter().filter_map(|a| {
            let f = a.from as usize;
            (f < n && self.in_r[f]).then(|| (a.from, self.d_s[f]))
        });
        let arcs = |u: u32, out: &mut Vec<(u32, f64, Option<usize>)>| {
            let ui = u as usize;
            if ui < n && !self.in_r[ui] {
                out.extend(self.fwd[ui].iter().map(|&(v, w)| (v, w, None)));
            }
            let new = extra.get(&u).into_iter().flatten();
            out.extend(new.map(|&i| (ov.arcs[i].to, ov.arcs[i].weight, Some(i))));
        };
        let visit = |v: u32| {
            let vi = v as usize;
            if vi < n && self.in_g[vi] {
                Visit::Exit(self.d_g[vi])
            } else if vi >= total || (vi < n && self.in_r[vi]) {
                Visit::Skip
            } else {
                Visit::Enter
            }
        };
        let (cost, labels) = cheapest_exit(sources, arcs, visit)?;
        let arcs = labels.into_iter().flatten().map(|i| ov.arcs[i]).collect();
        Some(Route { cost, arcs })
    }
}
