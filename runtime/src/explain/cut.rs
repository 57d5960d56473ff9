//! The cut: why the start's side and the goal's side do not meet, grouped the way the cell
//! is written (per pair of end-effectors and workspace), with the fallbacks when no two of
//! them meet anywhere.

use std::collections::{BTreeMap, BTreeSet};

use cellc_schema::{ArcKind, EndEffectorId, GraspId, Node, SpanId, WorkspaceId};

use super::context::Ctx;
use super::overlay::Key;
use super::suggest::Candidate;
use super::{CutItem, CutKind, Gap, HeldWith, MAX_CUT};

/// A gap before merging into cut items.
#[derive(Clone)]
struct Pending {
    kind: CutKind,
    workspaces: BTreeSet<WorkspaceId>,
    /// (end-effector, grasps) on the start's side.
    near: Vec<(EndEffectorId, BTreeSet<GraspId>)>,
    /// (end-effector, grasps) on the goal's side.
    far: Vec<(EndEffectorId, BTreeSet<GraspId>)>,
    /// Indices into [`Ctx::lost`].
    lost: BTreeSet<usize>,
    /// Declared transitions the other way: (from grasp, to grasp).
    reverse: BTreeSet<(GraspId, GraspId)>,
    /// A move's (from, to) workspaces, in the direction the object would go (kept here:
    /// `workspaces` is a set, and on the way through a hand of neither side no end of
    /// the move is on the start's side to tell the direction by).
    ends: Option<(WorkspaceId, WorkspaceId)>,
}

/// Gaps keyed by (kind, near end-effector, far end-effector or first workspace (its
/// index), workspace).
type Gaps = BTreeMap<(CutKind, EndEffectorId, u32, WorkspaceId), Pending>;

fn ees(set: &BTreeSet<EndEffectorId>) -> Vec<EndEffectorId> {
    set.iter().copied().collect()
}

fn wss(set: &BTreeSet<WorkspaceId>) -> Vec<WorkspaceId> {
    set.iter().copied().collect()
}

fn spans(list: impl IntoIterator<Item = u32>) -> Vec<SpanId> {
    list.into_iter().map(SpanId).collect()
}

impl Ctx<'_> {
    /// The cut items, most telling first, and how many were left out.
    pub fn cut(&self, best: Option<&Candidate>) -> (Vec<CutItem>, usize) {
        let mut gaps: Gaps = BTreeMap::new();
        self.border_gaps(&mut gaps);
        if let Some(c) = best {
            if !c.keys.iter().any(|k| matches!(k, Key::Reach(..))) {
                self.route_gaps(c, &mut gaps);
            }
        }
        let mut items = self.merge(gaps.into_values().collect());
        if items.is_empty() {
            items = self.fallback_items();
        }
        let omitted = items.len().saturating_sub(MAX_CUT);
        items.truncate(MAX_CUT);
        (items, omitted)
    }

    /// Gaps between states of R and states of G that share a workspace.
    fn border_gaps(&self, gaps: &mut Gaps) {
        for (w, states) in self.at_ws.iter().enumerate() {
            let w = WorkspaceId(w as u32);
            let mut near: BTreeMap<EndEffectorId, BTreeSet<GraspId>> = BTreeMap::new();
            let mut far: BTreeMap<EndEffectorId, BTreeSet<GraspId>> = BTreeMap::new();
            for &i in states {
                let n = self.node(i);
                if self.in_r[i as usize] {
                    near.entry(n.end_effector).or_default().insert(n.grasp);
                }
                if self.in_g[i as usize] {
                    far.entry(n.end_effector).or_default().insert(n.grasp);
                }
            }
            for (&a, ng) in &near {
                for (&b, fg) in &far {
                    if self.may_exchange(a, b) {
                        self.transition_gap(gaps, w, (a, ng.clone()), (b, fg.clone()));
                    }
                }
            }
        }
        // One hand on both sides with one grasp: a move that is missing or infeasible.
        for (i, n) in self.nodes.iter().enumerate() {
            if !self.in_r[i] || !self.is_movable(n.end_effector) {
                continue;
            }
            for x in self.reach(n.end_effector) {
                let other = Node { workspace: x, ..*n };
                let Some(&j) = self.index.get(&other) else {
                    continue;
                };
                if x != n.workspace && self.in_g[j as usize] {
                    self.move_gap(gaps, i as u32, j);
                }
            }
        }
    }

    /// A gap between `near` grasps of one end-effector and `far` grasps of another in `w`.
    fn transition_gap(
        &self,
        gaps: &mut Gaps,
        w: WorkspaceId,
        near: (EndEffectorId, BTreeSet<GraspId>),
        far: (EndEffectorId, BTreeSet<GraspId>),
    ) {
        let (a, b) = (near.0, far.0);
        let mut lost = BTreeSet::new();
        for (li, l) in self.lost.iter().enumerate() {
            let (x, y) = (self.node(l.from), self.node(l.to));
            if l.kind == ArcKind::Transition
                && x.workspace == w
                && y.workspace == w
                && x.end_effector == a
                && y.end_effector == b
                && near.1.contains(&x.grasp)
                && far.1.contains(&y.grasp)
            {
                lost.insert(li);
            }
        }
        let mut reverse = BTreeSet::new();
        for &g in &far.1 {
            for &h in &near.1 {
                if self.declares(g, h) && !self.declares(h, g) {
                    reverse.insert((g, h));
                }
            }
        }
        let kind = if lost.is_empty() {
            CutKind::NoTransition
        } else {
            CutKind::InfeasibleTransition
        };
        let gap = gaps.entry((kind, a, b.0, w)).or_insert_with(|| Pending {
            kind,
            workspaces: BTreeSet::from([w]),
            near: vec![(a, BTreeSet::new())],
            far: vec![(b, BTreeSet::new())],
            lost: BTreeSet::new(),
            reverse: BTreeSet::new(),
            ends: None,
        });
        gap.near[0].1.extend(near.1);
        gap.far[0].1.extend(far.1);
        gap.lost.extend(lost);
        gap.reverse.extend(reverse);
    }

    /// A gap between two states of one hand with one grasp in two workspaces.
    fn move_gap(&self, gaps: &mut Gaps, i: u32, j: u32) {
        let (x, y) = (self.node(i), self.node(j));
        let lost: BTreeSet<usize> = self.lost_from[i as usize]
            .iter()
            .copied()
            .filter(|&l| self.lost[l].to == j)
            .collect();
        let kind = if !lost.is_empty() {
            CutKind::InfeasibleMove
        } else if !self.is_adjacent(x.workspace, y.workspace) {
            CutKind::NotAdjacent
        } else {
            return;
        };
        let gap = gaps
            .entry((kind, x.end_effector, x.workspace.0, y.workspace))
            .or_insert_with(|| Pending {
                kind,
                workspaces: BTreeSet::from([x.workspace, y.workspace]),
                near: vec![(x.end_effector, BTreeSet::new())],
                far: vec![(y.end_effector, BTreeSet::new())],
                lost: BTreeSet::new(),
                reverse: BTreeSet::new(),
                ends: Some((x.workspace, y.workspace)),
            });
        gap.near[0].1.insert(x.grasp);
        gap.far[0].1.insert(y.grasp);
        gap.lost.extend(lost);
    }

    /// Gaps on the best suggestion's path that do not join R to G directly: the object
    /// must pass through a hand that belongs to neither side.
    fn route_gaps(&self, c: &Candidate, gaps: &mut Gaps) {
        let n = self.nodes.len();
        for a in &c.route.arcs {
            let (u, v) = (a.from as usize, a.to as usize);
            if u >= n || v >= n || (self.in_r[u] && self.in_g[v]) {
                continue;
            }
            let (x, y) = (self.node(a.from), self.node(a.to));
            if x.end_effector == y.end_effector && x.grasp == y.grasp {
                if x.workspace != y.workspace {
                    self.move_gap(gaps, a.from, a.to);
                }
                continue;
            }
            let w = x.workspace;
            // The near side: R if the arc leaves it (R is closed, so no arc joins any of
            // its grasps there to the other hand), otherwise what is not in G (G is closed
            // the other way).
            let side = |e: EndEffectorId, pick: &dyn Fn(usize) -> bool| -> BTreeSet<GraspId> {
                self.at_ws
                    .get(w.index())
                    .into_iter()
                    .flatten()
                    .filter(|&&i| self.node(i).end_effector == e && pick(i as usize))
                    .map(|&i| self.node(i).grasp)
                    .collect()
            };
            let near = if self.in_r[u] {
                side(x.end_effector, &|i| self.in_r[i])
            } else if self.in_g[v] {
                side(x.end_effector, &|i| !self.in_g[i])
            } else {
                BTreeSet::from([x.grasp])
            };
            let far = if self.in_g[v] {
                side(y.end_effector, &|i| self.in_g[i])
            } else if self.in_r[u] {
                side(y.end_effector, &|i| !self.in_r[i])
            } else {
                BTreeSet::from([y.grasp])
            };
            self.transition_gap(gaps, w, (x.end_effector, near), (y.end_effector, far));
        }
    }

    /// Merges gaps that say the same thing in several workspaces, then transition gaps to
    /// one goal-side hand from several start-side hands; orders them.
    fn merge(&self, gaps: Vec<Pending>) -> Vec<CutItem> {
        let mut by_pair: Vec<Pending> = Vec::new();
        for g in gaps {
            let same = by_pair.iter_mut().find(|m| {
                m.kind == g.kind
                    && m.near == g.near
                    && m.far == g.far
                    && matches!(
                        g.kind,
                        CutKind::NoTransition | CutKind::InfeasibleTransition
                    )
            });
            match same {
                Some(m) => {
                    m.workspaces.extend(g.workspaces);
                    m.lost.extend(g.lost);
                    m.reverse.extend(g.reverse);
                }
                None => by_pair.push(g),
            }
        }
        let mut merged: Vec<Pending> = Vec::new();
        for g in by_pair {
            let same = merged.iter_mut().find(|m| {
                m.kind == CutKind::NoTransition
                    && g.kind == CutKind::NoTransition
                    && m.far == g.far
                    && m.workspaces == g.workspaces
            });
            match same {
                Some(m) => {
                    m.near.extend(g.near);
                    m.reverse.extend(g.reverse);
                }
                None => merged.push(g),
            }
        }
        for g in &mut merged {
            g.near.sort();
            g.near.dedup();
        }
        merged.sort_by(|a, b| {
            (a.kind, &a.near, &a.far, &a.workspaces).cmp(&(b.kind, &b.near, &b.far, &b.workspaces))
        });
        merged.iter().map(|g| self.item(g)).collect()
    }

    fn item(&self, g: &Pending) -> CutItem {
        let near_ee: Vec<EndEffectorId> = g.near.iter().map(|(e, _)| *e).collect();
        let far_ee: Vec<EndEffectorId> = g.far.iter().map(|(e, _)| *e).collect();
        let mut spans: Vec<u32> = near_ee
            .iter()
            .chain(&far_ee)
            .filter_map(|&e| self.ee_span(e))
            .collect();
        let held = |side: &[(EndEffectorId, BTreeSet<GraspId>)]| -> Vec<HeldWith> {
            side.iter()
                .map(|(e, grasps)| HeldWith {
                    end_effector: *e,
                    grasps: grasps.iter().copied().collect(),
                })
                .collect()
        };
        let hand = near_ee.first().copied().unwrap_or(EndEffectorId(0));
        let gap = match g.kind {
            CutKind::NoTransition => {
                for r in &g.reverse {
                    spans.extend(self.declared.get(r).into_iter().flatten().copied());
                }
                Gap::NoTransition {
                    near: held(&g.near),
                    far: held(&g.far),
                    workspaces: wss(&g.workspaces),
                    one_way: g.reverse.iter().copied().collect(),
                }
            }
            CutKind::InfeasibleTransition => {
                spans.extend(g.lost.iter().filter_map(|&i| self.lost[i].source));
                Gap::InfeasibleTransition {
                    near: near_ee,
                    far: far_ee,
                    workspaces: wss(&g.workspaces),
                    arcs: g.lost.iter().map(|&i| self.lost_arc(i)).collect(),
                }
            }
            CutKind::InfeasibleMove => {
                spans.extend(g.lost.iter().filter_map(|&i| self.lost[i].source));
                let (from, to) = self.move_ends(g);
                Gap::InfeasibleMove {
                    hand,
                    grasps: g.near.iter().flat_map(|(_, s)| s).copied().collect(),
                    from,
                    to,
                    arcs: g.lost.iter().map(|&i| self.lost_arc(i)).collect(),
                }
            }
            _ => {
                let (from, to) = self.move_ends(g);
                spans.extend([from, to].into_iter().filter_map(|w| self.ws_span(w)));
                Gap::NotAdjacent { hand, from, to }
            }
        };
        spans.sort_unstable();
        spans.dedup();
        CutItem {
            gap,
            spans: self::spans(spans),
        }
    }

    /// The two workspaces of a move gap, in the direction the object would go.
    fn move_ends(&self, g: &Pending) -> (WorkspaceId, WorkspaceId) {
        g.ends.unwrap_or_else(|| {
            let first = g.workspaces.first().copied().unwrap_or(WorkspaceId(0));
            (first, first)
        })
    }

    /// When no two end-effectors of the sides share a workspace where they hold it: a
    /// side that no hand can reach, else pairs of end-effectors that reach no common
    /// workspace (pairs of hands first), else sides held by fixed end-effectors only.
    fn fallback_items(&self) -> Vec<CutItem> {
        type Sides = (BTreeSet<EndEffectorId>, BTreeSet<WorkspaceId>);
        let side = |pick: &dyn Fn(usize) -> bool| -> Sides {
            let picked = (0..self.nodes.len()).filter(|&i| pick(i));
            let holders = picked.clone().map(|i| self.nodes[i].end_effector).collect();
            let wss = picked.map(|i| self.nodes[i].workspace).collect();
            (holders, wss)
        };
        let (near, near_ws) = side(&|i| self.in_r[i]);
        let (far, far_ws) = side(&|i| self.in_g[i]);
        let mut items = Vec::new();
        if near_ws == far_ws {
            items.extend(self.no_hand(&near, &far, &near_ws));
        } else {
            items.extend(self.no_hand(&near, &BTreeSet::new(), &near_ws));
            items.extend(self.no_hand(&BTreeSet::new(), &far, &far_ws));
        }
        if !items.is_empty() {
            return items;
        }
        let mut pairs: Vec<(EndEffectorId, EndEffectorId, u8)> = Vec::new();
        for &a in &near {
            for &b in &far {
                let (ma, mb) = (self.is_movable(a), self.is_movable(b));
                if !self.may_exchange(a, b) {
                    continue;
                }
                if self.reach(a).any(|w| self.reaches(b, w)) {
                    continue;
                }
                pairs.push((a, b, u8::from(ma) + u8::from(mb)));
            }
        }
        let most = pairs.iter().map(|p| p.2).max().unwrap_or(0);
        items.extend(
            pairs
                .iter()
                .filter(|p| p.2 == most)
                .map(|&(a, b, _)| CutItem {
                    gap: Gap::NoCommonWorkspace { near: a, far: b },
                    spans: spans([self.ee_span(a), self.ee_span(b)].into_iter().flatten()),
                }),
        );
        let all: Vec<EndEffectorId> = near.union(&far).copied().collect();
        let all_spans = || spans(all.iter().filter_map(|&e| self.ee_span(e)));
        if items.is_empty() && all.iter().all(|&e| !self.is_movable(e)) {
            items.push(CutItem {
                gap: Gap::OnlyFixed {
                    near: ees(&near),
                    far: ees(&far),
                    near_workspaces: wss(&near_ws),
                    far_workspaces: wss(&far_ws),
                },
                spans: all_spans(),
            });
        }
        if items.is_empty() {
            // The last resort: where each side is, and who holds it where both do.
            let shared: BTreeSet<WorkspaceId> = near_ws.intersection(&far_ws).copied().collect();
            let holders_there: BTreeSet<EndEffectorId> = (0..self.nodes.len())
                .filter(|&i| {
                    (self.in_r[i] || self.in_g[i]) && shared.contains(&self.nodes[i].workspace)
                })
                .map(|i| self.nodes[i].end_effector)
                .collect();
            items.push(CutItem {
                gap: Gap::Apart {
                    near: ees(&near),
                    far: ees(&far),
                    near_workspaces: wss(&near_ws),
                    far_workspaces: wss(&far_ws),
                    shared: wss(&shared),
                    holders_there: ees(&holders_there),
                },
                spans: all_spans(),
            });
        }
        items
    }

    /// Sides held by fixed end-effectors only (`near` on the start's, `far` on the goal's;
    /// one may be empty), in workspaces out of every hand's reach: nothing can take the
    /// object from them or bring it to them.
    fn no_hand(
        &self,
        near: &BTreeSet<EndEffectorId>,
        far: &BTreeSet<EndEffectorId>,
        workspaces: &BTreeSet<WorkspaceId>,
    ) -> Option<CutItem> {
        let holders: Vec<EndEffectorId> = near.union(far).copied().collect();
        if holders.is_empty() || holders.iter().any(|&e| self.is_movable(e)) {
            return None;
        }
        let hand_reaches = |w: WorkspaceId| {
            (0..self.art.end_effectors.len() as u32)
                .map(EndEffectorId)
                .any(|e| self.is_hand(e) && self.reaches(e, w))
        };
        if workspaces.iter().any(|&w| hand_reaches(w)) {
            return None;
        }
        let places = holders
            .iter()
            .filter_map(|&e| self.ee_span(e))
            .chain(workspaces.iter().filter_map(|&w| self.ws_span(w)));
        Some(CutItem {
            gap: Gap::NoHand {
                near: ees(near),
                far: ees(far),
                workspaces: wss(workspaces),
            },
            spans: spans(places),
        })
    }
}
