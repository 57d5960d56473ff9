//! Small cells built directly as artifacts, for the explanation tests of the runtime
//! (`runtime/tests/explain.rs`, on the structure) and of the CLI (`tests/explain.rs`, on
//! the words): what the compiler would read, without the compiler (the runtime must not
//! depend on it, not even in tests), with the graph built by the shared graph rules
//! ([`cellc_schema::rules`], the compiler's), and the request's reachability checked by
//! this file's own search.
// Each of the two test files uses part of this.
#![allow(dead_code)]

mod scenarios;

pub use scenarios::*;

use std::collections::VecDeque;

use cellc_runtime::explain::{BodyName, Change};
use cellc_runtime::plan::{ArcRef, Unreachable};
use cellc_schema::rules::{
    Adjacency, CellRules, EndEffectorFacts, GraspFacts, ObjectRules, Provenance,
};
use cellc_schema::{
    Aabb, Arc, ArcKind, Artifact, Body, DeclaredTransition, EndEffector, EndEffectorId, Graph,
    Grasp, GraspId, Holder, HolderClass, HolderKind, Infeasibility, Node, NodeId, Object, ObjectId,
    PrunedArc, SourceFile, SourceSpan, Verification, Weights, Workspace, WorkspaceId, FORMAT,
    FORMAT_VERSION,
};

/// A state by names: (end-effector, grasp, workspace).
pub type St = (String, String, String);

/// A cell in a few lines: what the compiler would read, without the compiler.
#[derive(Clone, Debug, Default)]
pub struct Desc {
    pub workspaces: Vec<String>,
    /// Declared adjacencies; empty: derived from reach, as the compiler does.
    pub adjacent: Vec<(String, String)>,
    /// (name, movable, reaches).
    pub end_effectors: Vec<(String, bool, Vec<String>)>,
    /// (grasp, holder) of the one object, `cylinder`.
    pub grasps: Vec<(String, String)>,
    /// Directed (from grasp, to grasp).
    pub transitions: Vec<(String, String)>,
    /// Arcs pruned at build time.
    pub pruned: Vec<(St, St, Infeasibility)>,
    /// Geometry, when the cell has some: (workspace or end-effector, box along x).
    pub boxes: Vec<(String, f64, f64)>,
    /// Hand kinds and their members; a grasp declared for a kind is held by each member.
    pub kinds: Vec<(String, Vec<String>)>,
    /// Obstacles (names only: collisions with them are given, not computed).
    pub obstacles: Vec<String>,
}

pub fn s(x: &str) -> String {
    x.to_string()
}

pub fn st(e: &str, g: &str, w: &str) -> St {
    (s(e), s(g), s(w))
}

pub fn names(xs: &[&str]) -> Vec<String> {
    xs.iter().map(|x| s(x)).collect()
}

impl Desc {
    pub fn new(workspaces: &[&str]) -> Desc {
        Desc {
            workspaces: names(workspaces),
            ..Desc::default()
        }
    }

    pub fn adjacent(mut self, a: &str, b: &str) -> Desc {
        self.adjacent.push((s(a), s(b)));
        self
    }

    pub fn fixed(mut self, name: &str, reaches: &[&str]) -> Desc {
        self.end_effectors.push((s(name), false, names(reaches)));
        self
    }

    pub fn movable(mut self, name: &str, reaches: &[&str]) -> Desc {
        self.end_effectors.push((s(name), true, names(reaches)));
        self
    }

    pub fn grasps(mut self, holder: &str, grasps: &[&str]) -> Desc {
        for g in grasps {
            self.grasps.push((s(g), s(holder)));
        }
        self
    }

    /// `transition from -> to, ...`
    pub fn one_way(mut self, from: &str, to: &[&str]) -> Desc {
        for t in to {
            self.transitions.push((s(from), s(t)));
        }
        self
    }

    /// `transition from <-> to, ...`
    pub fn two_way(self, from: &str, to: &[&str]) -> Desc {
        let mut d = self.one_way(from, to);
        for t in to {
            d.transitions.push((s(t), s(from)));
        }
        d
    }

    /// A box from `x0` to `x1` along x (unit in y and z) for a workspace or a reach.
    pub fn boxed(mut self, name: &str, x0: f64, x1: f64) -> Desc {
        self.boxes.push((s(name), x0, x1));
        self
    }

    pub fn boxes_of(&self, name: &str) -> Vec<Aabb> {
        self.boxes
            .iter()
            .filter(|b| b.0 == name)
            .map(|b| Aabb {
                min: [b.1, 0.0, 0.0],
                max: [b.2, 1.0, 1.0],
            })
            .collect()
    }

    pub fn obstacle(mut self, name: &str) -> Desc {
        self.obstacles.push(s(name));
        self
    }

    pub fn kind(mut self, name: &str, members: &[&str]) -> Desc {
        self.kinds.push((s(name), names(members)));
        self
    }

    pub fn kind_index(&self, name: &str) -> Option<usize> {
        self.kinds.iter().position(|k| k.0 == name)
    }

    /// End-effectors holding grasps declared for `holder` (an end-effector or a kind).
    pub fn holders(&self, holder: &str) -> Vec<usize> {
        match self.kind_index(holder) {
            Some(k) => {
                let mut v: Vec<usize> = self.kinds[k].1.iter().filter_map(|e| self.ee(e)).collect();
                v.sort_unstable();
                v
            }
            None => self.ee(holder).into_iter().collect(),
        }
    }

    pub fn ee(&self, name: &str) -> Option<usize> {
        self.end_effectors.iter().position(|e| e.0 == name)
    }

    pub fn ws(&self, name: &str) -> Option<usize> {
        self.workspaces.iter().position(|w| w == name)
    }

    pub fn grasp(&self, name: &str) -> Option<usize> {
        self.grasps.iter().position(|g| g.0 == name)
    }

    /// The artifact, with the graph built by the shared graph rules (moves cost 0.1,
    /// transitions 1), and the pruned arcs moved out of it.
    pub fn build(&self) -> Artifact {
        let mut spans = Vec::new();
        let mut span = || {
            let i = spans.len() as u32;
            spans.push(SourceSpan {
                file: 0,
                start: i * 10,
                end: i * 10 + 9,
                line: i + 1,
            });
            i
        };
        let workspaces: Vec<Workspace> = self
            .workspaces
            .iter()
            .map(|w| Workspace {
                name: w.clone(),
                label: None,
                boxes: self.boxes_of(w),
                derived: false,
                span: span(),
            })
            .collect();
        let adjacency_spans: Vec<u32> = self.adjacent.iter().map(|_| span()).collect();
        let end_effectors: Vec<EndEffector> = self
            .end_effectors
            .iter()
            .map(|(name, movable, reaches)| {
                let mut r: Vec<u32> = reaches
                    .iter()
                    .filter_map(|w| self.ws(w).map(|i| i as u32))
                    .collect();
                r.sort_unstable();
                r.dedup();
                EndEffector {
                    name: name.clone(),
                    movable: *movable,
                    kind: self
                        .kinds
                        .iter()
                        .position(|k| k.1.contains(name))
                        .map(|k| k as u32),
                    body: Body::Abstract,
                    reach_boxes: self.boxes_of(name),
                    reaches: r,
                    span: span(),
                }
            })
            .collect();
        let object_span = span();
        let grasps: Vec<Grasp> = self
            .grasps
            .iter()
            .map(|(name, holder)| {
                let (holder, rest) = match self.kind_index(holder) {
                    Some(k) => (Holder::Kind(k as u32), false),
                    None => {
                        let e = self.ee(holder).expect("holder declared");
                        (Holder::EndEffector(e as u32), !self.end_effectors[e].1)
                    }
                };
                Grasp {
                    name: name.clone(),
                    label: None,
                    holder,
                    rest,
                    pose: None,
                    span: span(),
                }
            })
            .collect();
        let transitions: Vec<DeclaredTransition> = self
            .transitions
            .iter()
            .map(|(a, b)| DeclaredTransition {
                from: self.grasp(a).expect("grasp declared") as u32,
                to: self.grasp(b).expect("grasp declared") as u32,
                span: span(),
            })
            .collect();
        // The graph, by the shared rules.
        let facts = end_effectors
            .iter()
            .map(|e| EndEffectorFacts {
                movable: e.movable,
                reaches: e.reaches.iter().map(|&w| WorkspaceId(w)).collect(),
            })
            .collect();
        let adjacency = if self.adjacent.is_empty() {
            Adjacency::Derived
        } else {
            Adjacency::Declared(
                self.adjacent
                    .iter()
                    .filter_map(|(a, b)| {
                        Some((
                            WorkspaceId(self.ws(a)? as u32),
                            WorkspaceId(self.ws(b)? as u32),
                        ))
                    })
                    .collect(),
            )
        };
        let rules = CellRules::new(workspaces.len(), facts, adjacency);
        let object_rules = ObjectRules::new(
            end_effectors.len(),
            self.grasps
                .iter()
                .map(|(_, holder)| GraspFacts {
                    holders: self
                        .holders(holder)
                        .into_iter()
                        .map(|e| EndEffectorId(e as u32))
                        .collect(),
                    explicit: self.kind_index(holder).is_none(),
                })
                .collect(),
            transitions
                .iter()
                .map(|t| (GraspId(t.from), GraspId(t.to)))
                .collect(),
        );
        let nodes: Vec<Node> = rules.states(&object_rules);
        let mut arcs = Vec::new();
        rules.for_each_arc(&object_rules, |from, to, provenance| {
            let (kind, weight, source, via) = match provenance {
                Provenance::Move { adjacency } => (
                    ArcKind::Move,
                    0.1,
                    grasps[nodes[from as usize].grasp.index()].span,
                    adjacency.map(|i| adjacency_spans[i]),
                ),
                Provenance::Transition { transition } => {
                    (ArcKind::Transition, 1.0, transitions[transition].span, None)
                }
            };
            arcs.push(Arc {
                from,
                to,
                kind,
                weight,
                source,
                via,
                witness: None,
            });
        });
        let mut pruned = Vec::new();
        for (a, b, reason) in &self.pruned {
            let (Some(from), Some(to)) = (self.node(&nodes, a), self.node(&nodes, b)) else {
                continue;
            };
            if let Some(i) = arcs.iter().position(|x| x.from == from.0 && x.to == to.0) {
                pruned.push(PrunedArc {
                    arc: arcs.remove(i),
                    reason: reason.clone(),
                });
            }
        }
        let verification = (!self.pruned.is_empty()).then(|| Verification {
            seed: 0,
            n_checked: (arcs.len() + pruned.len()) as u64,
            n_pruned: pruned.len() as u64,
        });
        Artifact {
            format: FORMAT.to_string(),
            format_version: FORMAT_VERSION,
            compiler_version: s("test"),
            cell: s("test"),
            sources: vec![SourceFile {
                path: s("test.cell"),
                sha256: String::new(),
            }],
            weights: Weights {
                move_weight: 0.1,
                transition_weight: 1.0,
            },
            robots: Vec::new(),
            holder_kinds: self
                .kinds
                .iter()
                .map(|k| HolderKind {
                    name: k.0.clone(),
                    class: HolderClass::Hand,
                    solids: Vec::new(),
                })
                .collect(),
            workspaces,
            end_effectors,
            objects: vec![Object {
                name: s("cylinder"),
                shape: None,
                symmetries: Vec::new(),
                grasps,
                transitions,
                graph: Graph {
                    nodes,
                    arcs,
                    pruned,
                    witnesses: Vec::new(),
                },
                span: object_span,
            }],
            spans,
            requests: Vec::new(),
            world: Vec::new(),
            tasks: Vec::new(),
            obstacles: self
                .obstacles
                .iter()
                .map(|o| {
                    let unit = Aabb {
                        min: [0.0; 3],
                        max: [1.0; 3],
                    };
                    (o.clone(), unit)
                })
                .collect(),
            adjacency: None,
            allowed_contacts: Vec::new(),
            verification,
        }
    }

    pub fn node(&self, nodes: &[Node], (e, g, w): &St) -> Option<NodeId> {
        let n = Node {
            end_effector: EndEffectorId(self.ee(e)? as u32),
            grasp: GraspId(self.grasp(g)? as u32),
            workspace: WorkspaceId(self.ws(w)? as u32),
        };
        nodes.iter().position(|x| *x == n).map(|i| NodeId(i as u32))
    }
}

/// A request: start, goals, and arcs that failed during it.
#[derive(Clone, Debug)]
pub struct Req {
    pub start: St,
    pub goals: Vec<St>,
    pub failed: Vec<(St, St, Infeasibility)>,
}

impl Req {
    pub fn new(start: St, goals: Vec<St>) -> Req {
        Req {
            start,
            goals,
            failed: Vec::new(),
        }
    }

    pub fn failed_refs(&self, d: &Desc, art: &Artifact) -> Vec<(ArcRef, Infeasibility)> {
        let nodes = &art.objects[0].graph.nodes;
        self.failed
            .iter()
            .filter_map(|(a, b, r)| {
                Some((
                    ArcRef {
                        from: d.node(nodes, a)?,
                        to: d.node(nodes, b)?,
                    },
                    r.clone(),
                ))
            })
            .collect()
    }
}

/// This file's own search: node indices reachable from `start` over the arcs minus the
/// failed ones.
pub fn reachable(art: &Artifact, start: NodeId, failed: &[(ArcRef, Infeasibility)]) -> Vec<NodeId> {
    let g = &art.objects[0].graph;
    let mut seen = vec![false; g.nodes.len()];
    let mut queue = VecDeque::from([start]);
    seen[start.index()] = true;
    while let Some(u) = queue.pop_front() {
        for a in g.arcs.iter().filter(|a| a.from == u.0) {
            let gone = failed.iter().any(|(f, _)| *f == ArcRef::of(a));
            if !gone && !seen[a.to as usize] {
                seen[a.to as usize] = true;
                queue.push_back(NodeId(a.to));
            }
        }
    }
    (0..g.nodes.len() as u32)
        .filter(|&i| seen[i as usize])
        .map(NodeId)
        .collect()
}

/// Whether the request connects on the cell as described (None: a state is missing).
/// When the start is a goal (another pose in the same state, as the planner reads it),
/// the object must leave it and come back: a path of at least one arc.
pub fn connects(d: &Desc, req: &Req) -> Option<bool> {
    let art = d.build();
    let nodes = &art.objects[0].graph.nodes;
    let start = d.node(nodes, &req.start)?;
    let failed = req.failed_refs(d, &art);
    let goals: Vec<NodeId> = req.goals.iter().filter_map(|g| d.node(nodes, g)).collect();
    let leads = |from: NodeId| {
        let reach = reachable(&art, from, &failed);
        goals.iter().any(|g| reach.contains(g))
    };
    if !goals.contains(&start) {
        return Some(leads(start));
    }
    let gone = |a: &Arc| failed.iter().any(|(f, _)| *f == ArcRef::of(a));
    Some(
        art.objects[0]
            .graph
            .arcs
            .iter()
            .any(|a| a.from == start.0 && !gone(a) && leads(NodeId(a.to))),
    )
}

/// The planner's answer for an unreachable request, as the planner would give it.
pub fn unreachable(d: &Desc, art: &Artifact, req: &Req) -> Unreachable {
    let nodes = &art.objects[0].graph.nodes;
    let start = d.node(nodes, &req.start).expect("start state exists");
    let failed = req.failed_refs(d, art);
    let reach = reachable(art, start, &failed);
    let goals: Vec<Node> = req
        .goals
        .iter()
        .filter_map(|g| d.node(nodes, g))
        .map(|i| nodes[i.index()])
        .collect();
    Unreachable {
        object: ObjectId(0),
        start: nodes[start.index()],
        goals,
        reachable: reach,
        failed,
    }
}

/// The description and request with one suggestion's changes made.
pub fn apply(d: &Desc, art: &Artifact, req: &Req, changes: &[Change]) -> (Desc, Req) {
    let (mut d, mut req) = (d.clone(), req.clone());
    for c in changes {
        match c {
            Change::AddTransition {
                from_grasp,
                to_grasp,
                ..
            } => {
                let a = d.grasps[from_grasp.index()].0.clone();
                let b = d.grasps[to_grasp.index()].0.clone();
                d.transitions.push((a.clone(), b.clone()));
                d.transitions.push((b, a));
            }
            Change::AddAdjacency { a, b, .. } => {
                let (a, b) = (
                    d.workspaces[a.index()].clone(),
                    d.workspaces[b.index()].clone(),
                );
                d.adjacent.push((a, b));
            }
            Change::ExtendReaches {
                end_effector,
                workspace,
                ..
            }
            | Change::GrowReach {
                end_effector,
                workspace,
                ..
            } => {
                let w = d.workspaces[workspace.index()].clone();
                d.end_effectors[end_effector.index()].2.push(w);
            }
            Change::AllowContact { a, b, .. } => {
                // Every arc lost for that collision, pruned or failed, is possible again.
                let pair = |r: &Infeasibility| match r {
                    Infeasibility::Collision { a: x, b: y } => {
                        let (x, y) = (BodyName::of(art, x), BodyName::of(art, y));
                        (x.as_ref(), y.as_ref()) == (Some(a), Some(b))
                            || (x.as_ref(), y.as_ref()) == (Some(b), Some(a))
                    }
                    _ => false,
                };
                d.pruned.retain(|(_, _, r)| !pair(r));
                req.failed.retain(|(_, _, r)| !pair(r));
            }
        }
    }
    (d, req)
}
