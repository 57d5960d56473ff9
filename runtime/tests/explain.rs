//! Explanations of unreachable goals, on small cells built directly as artifacts (the
//! runtime must not depend on the compiler, not even here).
//!
//! Every explanation is checked the same way: at most three suggestions, none a
//! transition between two fixed end-effectors, and each one, applied to the cell's
//! description and the graph rebuilt from scratch by this file's own rules, connects the
//! start to the goal (checked with this file's own search).

use std::collections::{BTreeSet, VecDeque};

use cellc_runtime::explain::{explain, Cause, Change, CutKind, Explanation};
use cellc_runtime::plan::{ArcRef, Unreachable};
use cellc_schema::{
    Aabb, Arc, ArcKind, Artifact, Body, DeclaredTransition, EndEffector, Graph, Grasp, Holder,
    HolderClass, HolderKind, Infeasibility, Node, Object, PrunedArc, SourceFile, SourceSpan,
    Verification, Weights, Workspace, FORMAT, FORMAT_VERSION,
};
use proptest::prelude::*;

/// A state by names: (end-effector, grasp, workspace).
type St = (String, String, String);

/// A cell in a few lines: what the compiler would read, without the compiler.
#[derive(Clone, Debug, Default)]
struct Desc {
    workspaces: Vec<String>,
    /// Declared adjacencies; empty: derived from reach, as the compiler does.
    adjacent: Vec<(String, String)>,
    /// (name, movable, reaches).
    end_effectors: Vec<(String, bool, Vec<String>)>,
    /// (grasp, holder) of the one object, `cylinder`.
    grasps: Vec<(String, String)>,
    /// Directed (from grasp, to grasp).
    transitions: Vec<(String, String)>,
    /// Arcs pruned at build time.
    pruned: Vec<(St, St, Infeasibility)>,
    /// Geometry, when the cell has some: (workspace or end-effector, box along x).
    boxes: Vec<(String, f64, f64)>,
    /// Hand kinds and their members; a grasp declared for a kind is held by each member.
    kinds: Vec<(String, Vec<String>)>,
}

fn s(x: &str) -> String {
    x.to_string()
}

fn st(e: &str, g: &str, w: &str) -> St {
    (s(e), s(g), s(w))
}

fn names(xs: &[&str]) -> Vec<String> {
    xs.iter().map(|x| s(x)).collect()
}

impl Desc {
    fn new(workspaces: &[&str]) -> Desc {
        Desc {
            workspaces: names(workspaces),
            ..Desc::default()
        }
    }

    fn adjacent(mut self, a: &str, b: &str) -> Desc {
        self.adjacent.push((s(a), s(b)));
        self
    }

    fn fixed(mut self, name: &str, reaches: &[&str]) -> Desc {
        self.end_effectors.push((s(name), false, names(reaches)));
        self
    }

    fn movable(mut self, name: &str, reaches: &[&str]) -> Desc {
        self.end_effectors.push((s(name), true, names(reaches)));
        self
    }

    fn grasps(mut self, holder: &str, grasps: &[&str]) -> Desc {
        for g in grasps {
            self.grasps.push((s(g), s(holder)));
        }
        self
    }

    /// `transition from -> to, ...`
    fn one_way(mut self, from: &str, to: &[&str]) -> Desc {
        for t in to {
            self.transitions.push((s(from), s(t)));
        }
        self
    }

    /// `transition from <-> to, ...`
    fn two_way(self, from: &str, to: &[&str]) -> Desc {
        let mut d = self.one_way(from, to);
        for t in to {
            d.transitions.push((s(t), s(from)));
        }
        d
    }

    /// A box from `x0` to `x1` along x (unit in y and z) for a workspace or a reach.
    fn boxed(mut self, name: &str, x0: f64, x1: f64) -> Desc {
        self.boxes.push((s(name), x0, x1));
        self
    }

    fn boxes_of(&self, name: &str) -> Vec<Aabb> {
        self.boxes
            .iter()
            .filter(|b| b.0 == name)
            .map(|b| Aabb {
                min: [b.1, 0.0, 0.0],
                max: [b.2, 1.0, 1.0],
            })
            .collect()
    }

    fn kind(mut self, name: &str, members: &[&str]) -> Desc {
        self.kinds.push((s(name), names(members)));
        self
    }

    fn kind_index(&self, name: &str) -> Option<usize> {
        self.kinds.iter().position(|k| k.0 == name)
    }

    /// End-effectors holding grasps declared for `holder` (an end-effector or a kind).
    fn holders(&self, holder: &str) -> Vec<usize> {
        match self.kind_index(holder) {
            Some(k) => {
                let mut v: Vec<usize> = self.kinds[k].1.iter().filter_map(|e| self.ee(e)).collect();
                v.sort_unstable();
                v
            }
            None => self.ee(holder).into_iter().collect(),
        }
    }

    fn ee(&self, name: &str) -> Option<usize> {
        self.end_effectors.iter().position(|e| e.0 == name)
    }

    fn ws(&self, name: &str) -> Option<usize> {
        self.workspaces.iter().position(|w| w == name)
    }

    fn grasp(&self, name: &str) -> Option<usize> {
        self.grasps.iter().position(|g| g.0 == name)
    }

    fn is_adjacent(&self, a: &str, b: &str) -> bool {
        if a == b {
            return false;
        }
        if self.adjacent.is_empty() {
            self.end_effectors
                .iter()
                .any(|e| e.1 && e.2.iter().any(|w| w == a) && e.2.iter().any(|w| w == b))
        } else {
            self.adjacent
                .iter()
                .any(|(x, y)| (x == a && y == b) || (x == b && y == a))
        }
    }

    /// The artifact, with the graph built by the method's rules: a node per grasp and
    /// reached workspace; moves of movable end-effectors between adjacent reached
    /// workspaces; transitions per declared pair in each workspace both holders reach,
    /// never between two fixed end-effectors.
    fn build(&self) -> Artifact {
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
        let mut nodes = Vec::new();
        for (g, (_, holder)) in self.grasps.iter().enumerate() {
            for e in self.holders(holder) {
                for &w in &end_effectors[e].reaches {
                    nodes.push(Node {
                        end_effector: e as u32,
                        grasp: g as u32,
                        workspace: w,
                    });
                }
            }
        }
        let index = |e: usize, g: usize, w: u32| {
            nodes
                .iter()
                .position(|n| n.end_effector == e as u32 && n.grasp == g as u32 && n.workspace == w)
        };
        let mut arcs = Vec::new();
        for (g, e) in self
            .grasps
            .iter()
            .enumerate()
            .flat_map(|(g, (_, holder))| self.holders(holder).into_iter().map(move |e| (g, e)))
        {
            if !self.end_effectors[e].1 {
                continue;
            }
            for &a in &end_effectors[e].reaches {
                for &b in &end_effectors[e].reaches {
                    let (na, nb) = (&self.workspaces[a as usize], &self.workspaces[b as usize]);
                    if !self.is_adjacent(na, nb) {
                        continue;
                    }
                    let via = self
                        .adjacent
                        .iter()
                        .position(|(x, y)| (x == na && y == nb) || (x == nb && y == na))
                        .map(|i| adjacency_spans[i]);
                    arcs.push(Arc {
                        from: index(e, g, a).expect("node") as u32,
                        to: index(e, g, b).expect("node") as u32,
                        kind: ArcKind::Move,
                        weight: 0.1,
                        source: grasps[g].span,
                        via,
                        witness: None,
                    });
                }
            }
        }
        for t in &transitions {
            let (a, b) = (
                &self.grasps[t.from as usize].1,
                &self.grasps[t.to as usize].1,
            );
            // A hand passes nothing to itself, except by an explicit same-hand transition
            // between grasps declared for it (kept by the compiler, with a warning).
            let explicit = self.kind_index(a).is_none() && self.kind_index(b).is_none();
            for ei in self.holders(a) {
                for ej in self.holders(b) {
                    if (ei == ej && !explicit)
                        || (!self.end_effectors[ei].1 && !self.end_effectors[ej].1)
                    {
                        continue;
                    }
                    for &w in &end_effectors[ei].reaches {
                        if !end_effectors[ej].reaches.contains(&w) {
                            continue;
                        }
                        arcs.push(Arc {
                            from: index(ei, t.from as usize, w).expect("node") as u32,
                            to: index(ej, t.to as usize, w).expect("node") as u32,
                            kind: ArcKind::Transition,
                            weight: 1.0,
                            source: t.span,
                            via: None,
                            witness: None,
                        });
                    }
                }
            }
        }
        let mut pruned = Vec::new();
        for (a, b, reason) in &self.pruned {
            let (Some(from), Some(to)) = (self.node(&nodes, a), self.node(&nodes, b)) else {
                continue;
            };
            if let Some(i) = arcs.iter().position(|x| x.from == from && x.to == to) {
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
            obstacles: Vec::new(),
            adjacency: None,
            allowed_contacts: Vec::new(),
            verification,
        }
    }

    fn node(&self, nodes: &[Node], (e, g, w): &St) -> Option<u32> {
        let n = Node {
            end_effector: self.ee(e)? as u32,
            grasp: self.grasp(g)? as u32,
            workspace: self.ws(w)? as u32,
        };
        nodes.iter().position(|x| *x == n).map(|i| i as u32)
    }
}

/// A request: start, goals, and arcs that failed during it.
#[derive(Clone, Debug)]
struct Req {
    start: St,
    goals: Vec<St>,
    failed: Vec<(St, St, Infeasibility)>,
}

impl Req {
    fn new(start: St, goals: Vec<St>) -> Req {
        Req {
            start,
            goals,
            failed: Vec::new(),
        }
    }

    fn failed_refs(&self, d: &Desc, art: &Artifact) -> Vec<(ArcRef, Infeasibility)> {
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
fn reachable(art: &Artifact, start: u32, failed: &[(ArcRef, Infeasibility)]) -> Vec<u32> {
    let g = &art.objects[0].graph;
    let mut seen = vec![false; g.nodes.len()];
    let mut queue = VecDeque::from([start]);
    seen[start as usize] = true;
    while let Some(u) = queue.pop_front() {
        for a in g.arcs.iter().filter(|a| a.from == u) {
            let gone = failed.iter().any(|(f, _)| f.from == a.from && f.to == a.to);
            if !gone && !seen[a.to as usize] {
                seen[a.to as usize] = true;
                queue.push_back(a.to);
            }
        }
    }
    (0..g.nodes.len() as u32)
        .filter(|&i| seen[i as usize])
        .collect()
}

/// Whether the request connects on the cell as described (None: a state is missing).
fn connects(d: &Desc, req: &Req) -> Option<bool> {
    let art = d.build();
    let nodes = &art.objects[0].graph.nodes;
    let start = d.node(nodes, &req.start)?;
    let failed = req.failed_refs(d, &art);
    let reach = reachable(&art, start, &failed);
    Some(
        req.goals
            .iter()
            .filter_map(|g| d.node(nodes, g))
            .any(|g| reach.contains(&g)),
    )
}

/// The planner's answer for an unreachable request, as the planner would give it.
fn unreachable(d: &Desc, art: &Artifact, req: &Req) -> Unreachable {
    let nodes = &art.objects[0].graph.nodes;
    let start = d.node(nodes, &req.start).expect("start state exists");
    let failed = req.failed_refs(d, art);
    let reach = reachable(art, start, &failed);
    let goals: Vec<Node> = req
        .goals
        .iter()
        .filter_map(|g| d.node(nodes, g))
        .map(|i| nodes[i as usize])
        .collect();
    Unreachable {
        object: 0,
        start: nodes[start as usize],
        goals,
        reachable: reach,
        failed,
    }
}

/// The description and request with one suggestion's changes made.
fn apply(d: &Desc, art: &Artifact, req: &Req, changes: &[Change]) -> (Desc, Req) {
    let (mut d, mut req) = (d.clone(), req.clone());
    let nodes = &art.objects[0].graph.nodes;
    let state = |i: u32| -> St {
        let n = nodes[i as usize];
        (
            art.end_effectors[n.end_effector as usize].name.clone(),
            art.objects[0].grasps[n.grasp as usize].name.clone(),
            art.workspaces[n.workspace as usize].name.clone(),
        )
    };
    for c in changes {
        match c {
            Change::AddTransition {
                from_grasp,
                to_grasp,
                ..
            } => {
                let a = d.grasps[*from_grasp as usize].0.clone();
                let b = d.grasps[*to_grasp as usize].0.clone();
                d.transitions.push((a.clone(), b.clone()));
                d.transitions.push((b, a));
            }
            Change::AddAdjacency { a, b } => {
                let (a, b) = (
                    d.workspaces[*a as usize].clone(),
                    d.workspaces[*b as usize].clone(),
                );
                d.adjacent.push((a, b));
            }
            Change::ExtendReach {
                end_effector,
                workspace,
                ..
            } => {
                let w = d.workspaces[*workspace as usize].clone();
                d.end_effectors[*end_effector as usize].2.push(w);
            }
            Change::RelaxPruned { arc, failed, .. } => {
                let (a, b) = (state(arc.from), state(arc.to));
                if *failed {
                    req.failed.retain(|(x, y, _)| !(*x == a && *y == b));
                } else {
                    d.pruned.retain(|(x, y, _)| !(*x == a && *y == b));
                }
            }
        }
    }
    (d, req)
}

/// Explains an unreachable request and checks what every explanation must satisfy.
fn check(d: &Desc, req: &Req) -> Explanation {
    assert_eq!(
        connects(d, req),
        Some(false),
        "the request must be unreachable"
    );
    let art = d.build();
    let ex = explain(&art, &unreachable(d, &art, req));
    show(&ex);
    assert!(!ex.summary.is_empty());
    assert!(
        ex.summary.starts_with(|c: char| c.is_lowercase()),
        "{}",
        ex.summary
    );
    assert!(ex.suggestions.len() <= 3);
    for item in &ex.cut {
        assert!(!item.text.is_empty());
        assert!(item.spans.iter().all(|&s| (s as usize) < art.spans.len()));
    }
    assert!(ex
        .spans
        .iter()
        .all(|(s, _)| (*s as usize) < art.spans.len()));
    let spans: BTreeSet<u32> = ex.spans.iter().map(|(s, _)| *s).collect();
    assert_eq!(spans.len(), ex.spans.len(), "one label per span");
    for sug in &ex.suggestions {
        assert!(!sug.changes.is_empty());
        for c in &sug.changes {
            if let Change::AddTransition {
                from_grasp,
                to_grasp,
                ..
            } = c
            {
                // Some pair of distinct holders, not both fixed, must exchange it.
                let holders = |g: u32| d.holders(&d.grasps[g as usize].1);
                let fine = holders(*from_grasp).iter().any(|&a| {
                    holders(*to_grasp)
                        .iter()
                        .any(|&b| a != b && (d.end_effectors[a].1 || d.end_effectors[b].1))
                });
                assert!(
                    fine,
                    "a transition no two end-effectors can make: {}",
                    sug.text
                );
            }
        }
        let (d2, req2) = apply(d, &art, req, &sug.changes);
        assert_eq!(
            connects(&d2, &req2),
            Some(true),
            "suggestion does not connect: {}",
            sug.text
        );
    }
    ex
}

fn show(ex: &Explanation) {
    println!("summary: {}", ex.summary);
    println!("  start side: {}", ex.start_side.text);
    println!("  goal side: {}", ex.goal_side.text);
    for c in &ex.cut {
        println!("  cut [{:?}]: {}", c.kind, c.text);
    }
    for s in &ex.suggestions {
        println!("  suggestion (cost {:.1}): {}", s.cost, s.text);
    }
    for p in &ex.pruned {
        println!("  pruned: {}", p.text);
    }
    for n in &ex.notes {
        println!("  note: {n}");
    }
    for (s, l) in &ex.spans {
        println!("  span {s}: {l}");
    }
}

/// The paper's Fig. 3 cell, with its transitions (directed, as listed in method.md).
fn fig3(keep: impl Fn(&str, &str) -> bool) -> Desc {
    let mut d = Desc::new(&["w1", "w2", "w3"])
        .adjacent("w1", "w2")
        .adjacent("w2", "w3")
        .fixed("table", &["w1", "w2", "w3"])
        .movable("left_arm", &["w1", "w2"])
        .movable("right_arm", &["w2", "w3"])
        .grasps("table", &["g1", "g2", "g3"])
        .grasps("left_arm", &["g4", "g5", "g6"])
        .grasps("right_arm", &["g7", "g8", "g9"]);
    let table: [(&str, &[&str]); 9] = [
        ("g1", &["g5", "g6", "g8", "g9"]),
        ("g2", &["g5", "g8"]),
        ("g3", &["g4", "g5", "g7", "g8"]),
        ("g4", &["g3", "g8", "g9"]),
        ("g5", &["g1", "g2", "g3", "g7", "g9"]),
        ("g6", &["g1", "g7", "g8"]),
        ("g7", &["g3", "g5", "g6"]),
        ("g8", &["g1", "g2", "g3", "g4", "g6"]),
        ("g9", &["g1", "g4", "g5"]),
    ];
    for (from, tos) in table {
        for to in tos {
            if keep(from, to) {
                d = d.one_way(from, &[to]);
            }
        }
    }
    d
}

fn right_grasp(g: &str) -> bool {
    matches!(g, "g7" | "g8" | "g9")
}

#[test]
fn fig3_is_connected_as_published() {
    let d = fig3(|_, _| true);
    let req = Req::new(st("table", "g1", "w1"), vec![st("table", "g1", "w3")]);
    assert_eq!(connects(&d, &req), Some(true));
}

#[test]
fn fig3_with_the_right_arm_unable_to_take_names_the_cut_and_reconnects() {
    // Nothing hands the cylinder to the right arm any more (it can still give it back).
    let d = fig3(|from, to| right_grasp(from) || !right_grasp(to));
    let req = Req::new(st("table", "g1", "w1"), vec![st("table", "g1", "w3")]);
    let ex = check(&d, &req);
    assert_eq!(ex.cause, Cause::Missing);
    assert!(ex.summary.contains("`cylinder`"), "{}", ex.summary);
    let first = &ex.cut[0];
    assert_eq!(first.kind, CutKind::NoTransition);
    assert_eq!(
        first.near,
        vec![0, 1],
        "`table` and `left_arm` on the start's side"
    );
    assert_eq!(first.far, vec![2], "`right_arm` on the goal's side");
    assert!(
        first.text.contains("any grasp of `table` or `left_arm`"),
        "{}",
        first.text
    );
    assert!(first.text.contains("`right_arm`"), "{}", first.text);
    assert!(first.text.contains("in `w2`"), "{}", first.text);
    assert!(
        first.text.contains("declared only the other way"),
        "{}",
        first.text
    );
    assert!(!ex.suggestions.is_empty());
    assert!(ex
        .suggestions
        .iter()
        .all(|s| matches!(s.changes.as_slice(), [Change::AddTransition { .. }])));
    assert!(
        ex.suggestions[0].text.contains("to `right_arm` in `w2`"),
        "{}",
        ex.suggestions[0].text
    );
}

#[test]
fn fig3_with_the_right_arm_isolated_explains_the_way_through_it() {
    // No transition involves the right arm at all: the goal, on the table in `w3`, can
    // only be entered from it.
    let d = fig3(|from, to| !right_grasp(from) && !right_grasp(to));
    let req = Req::new(st("table", "g1", "w1"), vec![st("table", "g1", "w3")]);
    let ex = check(&d, &req);
    assert_eq!(ex.cause, Cause::Missing);
    let texts: Vec<&str> = ex.cut.iter().map(|c| c.text.as_str()).collect();
    assert!(
        texts
            .iter()
            .any(|t| t.contains("`right_arm`") && t.contains("`table`")),
        "{texts:?}"
    );
    // One two-way transition between a table grasp and a right-arm grasp suffices: the
    // right arm takes it in `w2` and puts it back on the table in `w3`.
    assert!(!ex.suggestions.is_empty());
    assert!(ex.suggestions.iter().all(|s| s.changes.len() == 1));
    assert!(
        ex.suggestions[0].text.ends_with(
            "so `right_arm` can take it from `table` in `w2`, and `right_arm` can put it on \
             `table` in `w3`"
        ),
        "{}",
        ex.suggestions[0].text
    );
}

/// Two arms in a row with a table at each end; the arms reach no common workspace.
fn arms_apart() -> Desc {
    Desc::new(&["w1", "w2", "w3", "w4"])
        .fixed("table_a", &["w1"])
        .movable("left", &["w1", "w2"])
        .movable("right", &["w3", "w4"])
        .fixed("table_b", &["w4"])
        .grasps("table_a", &["a1"])
        .grasps("left", &["l1"])
        .grasps("right", &["r1"])
        .grasps("table_b", &["b1"])
        .two_way("a1", &["l1"])
        .two_way("l1", &["r1"])
        .two_way("r1", &["b1"])
}

#[test]
fn arms_without_a_common_workspace_get_the_nearest_reach_extension() {
    // Workspaces one metre wide in a row; each arm's reach stops 0.1 m short of the
    // other's first workspace.
    let d = arms_apart()
        .boxed("w1", 0.0, 1.0)
        .boxed("w2", 1.0, 2.0)
        .boxed("w3", 2.0, 3.0)
        .boxed("w4", 3.0, 4.0)
        .boxed("left", 0.0, 1.9)
        .boxed("right", 2.1, 4.0);
    let req = Req::new(st("table_a", "a1", "w1"), vec![st("table_b", "b1", "w4")]);
    let ex = check(&d, &req);
    assert_eq!(ex.cause, Cause::Missing);
    assert_eq!(ex.cut.len(), 1);
    assert_eq!(ex.cut[0].kind, CutKind::NoCommonWorkspace);
    assert!(ex.cut[0]
        .text
        .contains("`left` and `right` reach no common workspace"));
    let reach: Vec<(u32, u32)> = ex
        .suggestions
        .iter()
        .filter_map(|s| match s.changes.as_slice() {
            [Change::ExtendReach {
                end_effector,
                workspace,
                ..
            }] => Some((*end_effector, *workspace)),
            _ => None,
        })
        .collect();
    // `left` to `w3` and `right` to `w2` (0.1 m away) before the far workspaces.
    assert_eq!(reach[..2], [(1, 2), (2, 1)]);
    assert_eq!(
        ex.suggestions[0].text,
        "extend the reach of `left` to cover `w3` (0.10 m beyond it), where it meets `right`"
    );
}

#[test]
fn arms_without_a_common_workspace_in_a_cell_that_declares_adjacency() {
    // `adjacent w2 w3` joins two workspaces no hand spans, so the artifact keeps no trace
    // of it; the suggestion then also declares the adjacency it needs (harmless if it is
    // already there), and still connects.
    let d = arms_apart()
        .adjacent("w1", "w2")
        .adjacent("w2", "w3")
        .adjacent("w3", "w4");
    let req = Req::new(st("table_a", "a1", "w1"), vec![st("table_b", "b1", "w4")]);
    let ex = check(&d, &req);
    assert!(!ex.suggestions.is_empty());
    assert!(ex.suggestions.iter().all(|s| s
        .changes
        .iter()
        .any(|c| matches!(c, Change::ExtendReach { .. }))));
}

#[test]
fn hands_of_one_kind_get_a_handoff_of_their_kind_grasp() {
    let d = Desc::new(&["w1", "w2", "w3"])
        .fixed("table_a", &["w1"])
        .movable("left", &["w1", "w2"])
        .movable("right", &["w2", "w3"])
        .fixed("table_b", &["w3"])
        .kind("softhand", &["left", "right"])
        .grasps("table_a", &["ra"])
        .grasps("table_b", &["rb"])
        .grasps("softhand", &["pinch"])
        .two_way("ra", &["pinch"])
        .two_way("pinch", &["rb"]);
    let req = Req::new(st("table_a", "ra", "w1"), vec![st("table_b", "rb", "w3")]);
    let ex = check(&d, &req);
    let first = &ex.cut[0];
    assert_eq!(
        first.text,
        "no transition joins grasp `pinch` of `left` with grasp `pinch` of `right` in `w2`"
    );
    assert!(matches!(
        ex.suggestions[0].changes.as_slice(),
        [Change::AddTransition {
            from_grasp: 2,
            to_grasp: 2,
            ..
        }]
    ));
    assert_eq!(
        ex.suggestions[0].text,
        "add `transition pinch <-> pinch` to `cylinder`, so `left` can hand it to `right` in `w2`"
    );
}

/// A line of `n` arms, each reaching two consecutive workspaces, passing the object along
/// from a table at one end to a table at the other, every handoff declared except the one
/// between `arm{gap}` and the next arm.
fn line(n: usize, grasps: usize, gap: usize) -> Desc {
    let wss: Vec<String> = (0..=n).map(|i| format!("w{i}")).collect();
    let mut d = Desc {
        workspaces: wss.clone(),
        ..Desc::default()
    };
    d.end_effectors
        .push((s("start"), false, vec![wss[0].clone()]));
    d.end_effectors
        .push((s("end"), false, vec![wss[n].clone()]));
    d.grasps.push((s("s"), s("start")));
    d.grasps.push((s("e"), s("end")));
    let grasp = |i: usize, g: usize| format!("a{i}_{g}");
    for i in 0..n {
        d.end_effectors.push((
            format!("arm{i}"),
            true,
            vec![wss[i].clone(), wss[i + 1].clone()],
        ));
        for g in 0..grasps {
            d.grasps.push((grasp(i, g), format!("arm{i}")));
        }
    }
    for g in 0..grasps {
        d.transitions.push((s("s"), grasp(0, g)));
        d.transitions.push((grasp(n - 1, g), s("e")));
        for i in 0..n - 1 {
            if i == gap {
                continue;
            }
            for h in 0..grasps {
                d.transitions.push((grasp(i, g), grasp(i + 1, h)));
            }
        }
    }
    d
}

#[test]
fn a_line_of_arms_names_its_one_missing_handoff() {
    let d = line(10, 4, 4);
    let req = Req::new(st("start", "s", "w0"), vec![st("end", "e", "w10")]);
    let ex = check(&d, &req);
    assert_eq!(ex.cut.len(), 1);
    assert_eq!(
        ex.cut[0].text,
        "no transition joins any grasp of `arm4` with any grasp of `arm5` in `w5`"
    );
    assert_eq!(
        ex.suggestions.len(),
        1,
        "one idea: a handoff from `arm4` to `arm5`"
    );
    assert!(ex.suggestions[0]
        .text
        .ends_with("so `arm4` can hand it to `arm5` in `w5`"));
}

#[test]
fn pruned_handoffs_are_explained_with_their_reasons() {
    // Every transition into the right arm in `w2` was found infeasible at build time.
    let mut d = fig3(|_, _| true);
    let ik = Infeasibility::NoIkSolution {
        end_effector: 2,
        tries: 300,
        position_error: 0.21,
        rotation_error: 0.1,
    };
    let chain = Infeasibility::NoClosedChain {
        a: 1,
        b: 2,
        tries: 300,
        position_error: 0.05,
        rotation_error: 0.2,
    };
    let transitions = d.transitions.clone();
    for (from, to) in transitions {
        if !right_grasp(&to) || right_grasp(&from) {
            continue;
        }
        let holder = if matches!(from.as_str(), "g1" | "g2" | "g3") {
            "table"
        } else {
            "left_arm"
        };
        let reason = if holder == "table" { &ik } else { &chain };
        d.pruned.push((
            st(holder, &from, "w2"),
            st("right_arm", &to, "w2"),
            reason.clone(),
        ));
    }
    let req = Req::new(st("table", "g1", "w1"), vec![st("table", "g1", "w3")]);
    let ex = check(&d, &req);
    assert_eq!(ex.cause, Cause::Pruned);
    assert!(ex.summary.contains("pruned"), "{}", ex.summary);
    assert!(ex
        .cut
        .iter()
        .any(|c| c.kind == CutKind::InfeasibleTransition
            && c.text
                .contains("`right_arm` cannot reach the pose, closest 0.21 m")));
    assert!(ex
        .cut
        .iter()
        .any(|c| c.kind == CutKind::InfeasibleTransition
            && c.text
                .contains("`left_arm` and `right_arm` cannot hold it at once")));
    assert!(!ex.pruned.is_empty());
    assert!(ex.pruned.iter().all(|p| !p.failed));
    assert!(ex.pruned[0].text.contains("was pruned at build time"));
    // One suggestion per root cause, and no new transition where every declared one
    // between the same arms failed.
    assert_eq!(ex.suggestions.len(), 2);
    assert!(ex.suggestions.iter().all(|s| matches!(
        s.changes.as_slice(),
        [Change::RelaxPruned { failed: false, .. }]
    )));
}

#[test]
fn a_failed_move_of_the_one_hand_is_explained() {
    let d = Desc::new(&["w2", "w3"])
        .movable("right", &["w2", "w3"])
        .grasps("right", &["g7"]);
    let mut req = Req::new(st("right", "g7", "w2"), vec![st("right", "g7", "w3")]);
    req.failed.push((
        st("right", "g7", "w2"),
        st("right", "g7", "w3"),
        Infeasibility::NoIkSolution {
            end_effector: 0,
            tries: 100,
            position_error: 0.21,
            rotation_error: 0.0,
        },
    ));
    let ex = check(&d, &req);
    assert_eq!(ex.cause, Cause::Failed);
    assert_eq!(ex.cut[0].kind, CutKind::InfeasibleMove);
    assert!(ex.cut[0]
        .text
        .starts_with("`right` cannot carry it with `g7` from `w2` to `w3`: `right` cannot reach"));
    assert!(ex.pruned[0].text.contains("failed during this request"));
    assert!(matches!(
        ex.suggestions[0].changes.as_slice(),
        [Change::RelaxPruned { failed: true, .. }]
    ));
}

#[test]
fn a_pruned_move_of_the_one_hand_is_explained() {
    let mut d = Desc::new(&["w2", "w3"])
        .movable("right", &["w2", "w3"])
        .grasps("right", &["g7"]);
    d.pruned.push((
        st("right", "g7", "w2"),
        st("right", "g7", "w3"),
        Infeasibility::Collision {
            a: s("right/link_4"),
            b: s("shelf"),
        },
    ));
    let req = Req::new(st("right", "g7", "w2"), vec![st("right", "g7", "w3")]);
    let ex = check(&d, &req);
    assert_eq!(ex.cause, Cause::Pruned);
    assert!(ex.cut[0]
        .text
        .contains("`right/link_4` collides with `shelf`"));
    assert!(ex.suggestions[0]
        .text
        .contains("allow contact right.link_4 shelf"));
}

#[test]
fn two_surfaces_and_an_arm_need_two_transitions_never_a_surface_to_surface_one() {
    let d = Desc::new(&["w1"])
        .fixed("table_a", &["w1"])
        .fixed("table_b", &["w1"])
        .movable("arm", &["w1"])
        .grasps("table_a", &["a1"])
        .grasps("table_b", &["b1"])
        .grasps("arm", &["h1"]);
    let req = Req::new(st("table_a", "a1", "w1"), vec![st("table_b", "b1", "w1")]);
    let ex = check(&d, &req);
    assert_eq!(ex.cause, Cause::Missing);
    assert_eq!(ex.suggestions.len(), 1);
    assert_eq!(ex.suggestions[0].changes.len(), 2);
    assert!(ex
        .cut
        .iter()
        .any(|c| c.text.contains("`table_a`") && c.text.contains("`arm`")));
    assert!(ex
        .cut
        .iter()
        .any(|c| c.text.contains("`arm`") && c.text.contains("`table_b`")));
}

#[test]
fn surfaces_alone_cannot_be_helped_and_say_so() {
    let d = Desc::new(&["w1"])
        .fixed("table_a", &["w1"])
        .fixed("table_b", &["w1"])
        .grasps("table_a", &["a1"])
        .grasps("table_b", &["b1"]);
    let req = Req::new(st("table_a", "a1", "w1"), vec![st("table_b", "b1", "w1")]);
    let ex = check(&d, &req);
    assert!(ex.suggestions.is_empty());
    assert_eq!(ex.cut.len(), 1);
    assert_eq!(ex.cut[0].kind, CutKind::NoHand);
    assert_eq!(
        ex.cut[0].text,
        "no movable end-effector that can hold `cylinder` reaches `w1`, so nothing can take \
         it from `table_a` nor bring it to `table_b` there"
    );
    assert!(!ex.notes.is_empty());
}

#[test]
fn workspaces_that_are_not_adjacent_get_an_adjacency() {
    let d = Desc::new(&["w1", "w2", "w3"])
        .adjacent("w1", "w2")
        .fixed("table_a", &["w1"])
        .fixed("table_c", &["w3"])
        .movable("arm", &["w1", "w3"])
        .movable("other", &["w1", "w2"])
        .grasps("table_a", &["ta"])
        .grasps("table_c", &["tc"])
        .grasps("arm", &["h"])
        .grasps("other", &["o"])
        .two_way("ta", &["h"])
        .two_way("h", &["tc"]);
    let req = Req::new(st("table_a", "ta", "w1"), vec![st("table_c", "tc", "w3")]);
    let ex = check(&d, &req);
    assert_eq!(ex.cut[0].kind, CutKind::NotAdjacent);
    assert_eq!(
        ex.cut[0].text,
        "`w1` and `w3` are not adjacent, so `arm` cannot carry it from one to the other"
    );
    assert!(matches!(
        ex.suggestions[0].changes.as_slice(),
        [Change::AddAdjacency { a: 0, b: 2 }]
    ));
}

#[test]
fn a_reachable_goal_is_reported_as_connected() {
    let d = fig3(|_, _| true);
    let art = d.build();
    let req = Req::new(st("table", "g1", "w1"), vec![st("table", "g1", "w3")]);
    let ex = explain(&art, &unreachable(&d, &art, &req));
    assert_eq!(ex.cause, Cause::Connected);
    assert!(ex.suggestions.is_empty());
}

#[test]
fn a_request_outside_the_graph_is_reported_without_panicking() {
    let d = fig3(|_, _| true);
    let art = d.build();
    let mut un = unreachable(&d, &art, &Req::new(st("table", "g1", "w1"), vec![]));
    let ex = explain(&art, &un);
    assert_eq!(ex.cause, Cause::NoStates);
    un.object = 7;
    assert_eq!(explain(&art, &un).cause, Cause::NoStates);
}

/// A random small cell from a seed: 1-4 workspaces, 2-4 end-effectors, one or two grasps
/// each, random transitions, adjacency declared or derived, some arcs pruned.
fn random_cell(seed: u64) -> (Desc, Req) {
    // splitmix64
    let mut x = seed;
    let mut next = move |n: u64| {
        x = x.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = x;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        (z ^ (z >> 31)) % n.max(1)
    };
    let n_ws = 1 + next(4) as usize;
    let wss: Vec<String> = (0..n_ws).map(|i| format!("w{i}")).collect();
    let mut d = Desc {
        workspaces: wss.clone(),
        ..Desc::default()
    };
    if next(2) == 0 {
        for a in 0..n_ws {
            for b in a + 1..n_ws {
                if next(2) == 0 {
                    d.adjacent.push((wss[a].clone(), wss[b].clone()));
                }
            }
        }
    }
    let n_ee = 2 + next(3) as usize;
    for e in 0..n_ee {
        let mut reaches: Vec<String> = wss.iter().filter(|_| next(2) == 0).cloned().collect();
        if reaches.is_empty() {
            reaches.push(wss[next(n_ws as u64) as usize].clone());
        }
        d.end_effectors
            .push((format!("e{e}"), next(3) != 0, reaches));
        for g in 0..1 + next(2) {
            d.grasps.push((format!("g{e}_{g}"), format!("e{e}")));
        }
    }
    if next(3) == 0 {
        let hands: Vec<String> = d
            .end_effectors
            .iter()
            .filter(|e| e.1)
            .map(|e| e.0.clone())
            .collect();
        if !hands.is_empty() {
            d.kinds.push((s("hand"), hands));
            d.grasps.push((s("k0"), s("hand")));
        }
    }
    let n_g = d.grasps.len();
    for a in 0..n_g {
        for b in 0..n_g {
            if (a != b || d.grasps[a].1 == "hand") && next(4) == 0 {
                d.transitions
                    .push((d.grasps[a].0.clone(), d.grasps[b].0.clone()));
            }
        }
    }
    let art = d.build();
    let g = &art.objects[0].graph;
    let state = |i: u32| -> St {
        let n = g.nodes[i as usize];
        (
            art.end_effectors[n.end_effector as usize].name.clone(),
            art.objects[0].grasps[n.grasp as usize].name.clone(),
            art.workspaces[n.workspace as usize].name.clone(),
        )
    };
    for a in &g.arcs {
        if next(5) == 0 {
            d.pruned.push((
                state(a.from),
                state(a.to),
                Infeasibility::NoPlacement {
                    detail: s("the surface ends before the workspace"),
                },
            ));
        }
    }
    let n = g.nodes.len() as u64;
    let start = state(next(n) as u32);
    let goals = (0..1 + next(2)).map(|_| state(next(n) as u32)).collect();
    let mut req = Req::new(start, goals);
    // Failed arcs are arcs of the graph, never pruned ones.
    for a in &g.arcs {
        let (from, to) = (state(a.from), state(a.to));
        if next(8) == 0 && !d.pruned.iter().any(|p| p.0 == from && p.1 == to) {
            req.failed.push((
                from,
                to,
                Infeasibility::Collision {
                    a: s("e0"),
                    b: s("e1"),
                },
            ));
        }
    }
    (d, req)
}

proptest! {
    // About half the random requests are reachable and skipped.
    #![proptest_config(ProptestConfig {
        cases: 500,
        max_global_rejects: 1 << 20,
        ..ProptestConfig::default()
    })]

    /// On random cells, every explanation keeps its promises: few suggestions, never a
    /// surface-to-surface transition, and each one really connects.
    #[test]
    fn suggestions_on_random_cells_connect(seed in any::<u64>()) {
        let (d, req) = random_cell(seed);
        prop_assume!(connects(&d, &req) == Some(false));
        let ex = check(&d, &req);
        prop_assert!(ex.cause != Cause::Connected && ex.cause != Cause::NoStates);
        if ex.cause != Cause::Missing {
            prop_assert!(!ex.pruned.is_empty());
        }
    }
}
