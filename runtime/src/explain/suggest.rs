//! The search for changes that connect the start to the goal: single changes first, then
//! the fewest changes along one path; each candidate verified on the overlay, ranked, one
//! per idea.

use std::cmp::Ordering;
use std::collections::{BTreeMap, BTreeSet, HashMap, VecDeque};

use cellc_schema::{Body, EndEffectorId, GraspId, Node, SpanId, WorkspaceId};

use super::context::{ordered, Ctx};
use super::overlay::{Key, Overlay, Route};
use super::{Change, Exchange, Suggestion, MAX_SUGGESTIONS};

/// Hypothetical changes tried at most per kind, so a huge cell cannot make the
/// explanation slower than the search it explains.
const MAX_TRIES: usize = 4000;
/// Reach extensions tried with the further changes they need, nearest first.
const MAX_REACH_SETS: usize = 32;

/// A verified set of changes.
pub(super) struct Candidate {
    pub keys: Vec<Key>,
    pub route: Route,
    pub overlay: Overlay,
    doubtful: bool,
    effort: f64,
}

impl Candidate {
    pub fn class(&self) -> u8 {
        self.keys.iter().map(|k| k.class()).max().unwrap_or(0)
    }

    fn rank(&self, other: &Candidate) -> Ordering {
        self.keys
            .len()
            .cmp(&other.keys.len())
            .then(self.doubtful.cmp(&other.doubtful))
            .then(self.class().cmp(&other.class()))
            .then(self.effort.total_cmp(&other.effort))
            .then(self.route.cost.total_cmp(&other.route.cost))
            .then(self.keys.cmp(&other.keys))
    }
}

/// What makes two suggestions the same idea (see [`Ctx::suggest`]).
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum Idea {
    /// A new exchange between two hands in a workspace: (giver, taker, workspace).
    Exchange(EndEffectorId, EndEffectorId, WorkspaceId),
    /// Anything else is its own idea (an allowed contact brings back every arc its
    /// collision removed, so one pair of bodies is one idea already).
    Keys(Vec<Key>),
}

impl Ctx<'_> {
    fn try_keys(&self, keys: Vec<Key>) -> Option<Candidate> {
        let overlay = self.apply(&keys);
        let route = self.connect(&overlay)?;
        let mut c = Candidate {
            keys,
            route,
            overlay,
            doubtful: false,
            effort: 0.0,
        };
        c.doubtful = self.doubtful(&c);
        c.effort = c
            .keys
            .iter()
            .map(|&k| match k {
                Key::Reach(e, w) => self.reach_distance(e, w).unwrap_or(0.0),
                _ => 0.0,
            })
            .sum();
        Some(c)
    }

    /// A new transition whose every use lies between two hands in a workspace where each
    /// transition declared between them was infeasible is likely to fail the same way.
    fn doubtful(&self, c: &Candidate) -> bool {
        if !c.keys.iter().all(|k| matches!(k, Key::Transition(..))) {
            return false;
        }
        let n = self.nodes.len();
        let mut uses = c
            .route
            .arcs
            .iter()
            .filter(|a| (a.from as usize) < n && (a.to as usize) < n)
            .peekable();
        if uses.peek().is_none() {
            return false;
        }
        uses.all(|a| {
            let (x, y) = (self.node(a.from), self.node(a.to));
            let key = (x.end_effector, y.end_effector, x.workspace);
            self.lost_exchanges.contains(&key) && !self.active_exchanges.contains(&key)
        })
    }

    /// Verified candidates, best first, chosen for the explanation.
    pub fn suggest(&self) -> Vec<Candidate> {
        let mut found = self.single_changes();
        if found.is_empty() {
            found = self.several_changes();
        }
        found.sort_by(|a, b| a.rank(b));
        // A transition likely to fail like its neighbours is worth showing only when
        // nothing better exists.
        if found.iter().any(|c| !c.doubtful) {
            found.retain(|c| !c.doubtful);
        }
        // Extending a reach means moving or replacing a robot: a last resort, shown only
        // when no declaration connects.
        let reach = Key::Reach(EndEffectorId(0), WorkspaceId(0)).class();
        if found.iter().any(|c| c.class() < reach) {
            found.retain(|c| c.class() < reach);
        }
        // One suggestion per idea: ten ways for the same two hands to exchange the object
        // in the same workspace are one.
        let mut seen = BTreeSet::new();
        found.retain(|c| seen.insert(self.idea(c)));
        found.truncate(MAX_SUGGESTIONS);
        found
    }

    fn idea(&self, c: &Candidate) -> Idea {
        match c.keys.as_slice() {
            [Key::Transition(..)] => {
                let ends = c.route.arcs.first().and_then(|arc| {
                    let x = self.overlay_node(&c.overlay, arc.from)?;
                    let y = self.overlay_node(&c.overlay, arc.to)?;
                    Some(Idea::Exchange(x.end_effector, y.end_effector, x.workspace))
                });
                ends.unwrap_or_else(|| Idea::Keys(c.keys.clone()))
            }
            _ => Idea::Keys(c.keys.clone()),
        }
    }

    fn single_changes(&self) -> Vec<Candidate> {
        let mut found = Vec::new();
        let mut in_g = vec![false; self.obj.grasps.len()];
        for (i, node) in self.nodes.iter().enumerate() {
            if let Some(slot) = in_g.get_mut(node.grasp.index()) {
                *slot |= self.in_g[i];
            }
        }
        let touches_g = |g: GraspId| in_g.get(g.index()).copied().unwrap_or(false);
        // A declaration helps only if one of its arcs leaves R (so it joins a state of R
        // to a state outside R in one workspace) and one enters G.
        let mut pairs = BTreeSet::new();
        for (u, nu) in self.nodes.iter().enumerate() {
            if !self.in_r[u] {
                continue;
            }
            for &v in self.at_ws.get(nu.workspace.index()).into_iter().flatten() {
                let nv = self.node(v);
                if self.in_r[v as usize]
                    || !self.may_exchange(nu.end_effector, nv.end_effector)
                    || self.declares(nu.grasp, nv.grasp)
                    || !(touches_g(nu.grasp) || touches_g(nv.grasp))
                {
                    continue;
                }
                pairs.insert(ordered(nu.grasp, nv.grasp));
            }
        }
        for (a, b) in pairs.into_iter().take(MAX_TRIES) {
            found.extend(self.try_keys(vec![Key::Transition(a, b)]));
        }
        if self.rules.declares_adjacency() {
            let n_ws = self.art.workspaces.len() as u32;
            for a in (0..n_ws).map(WorkspaceId) {
                for b in (a.0 + 1..n_ws).map(WorkspaceId) {
                    let spanned = self
                        .end_effector_ids()
                        .any(|e| self.is_hand(e) && self.reaches(e, a) && self.reaches(e, b));
                    if spanned && !self.is_adjacent(a, b) && self.adjacency_editable(a, b) {
                        found.extend(self.try_keys(vec![Key::Adjacency(a, b)]));
                    }
                }
            }
        }
        // An allowed contact helps if one of the arcs its collision removed leaves R.
        let mut contacts = BTreeSet::new();
        for (i, l) in self.lost.iter().enumerate() {
            if let (Some(g), true) = (self.contact_key(i), self.in_r[l.from as usize]) {
                contacts.insert(g);
            }
        }
        for g in contacts.into_iter().take(MAX_TRIES) {
            found.extend(self.try_keys(vec![Key::Contact(g)]));
        }
        // The new states of a reach extension join R by a move of the hand or a
        // transition in the new workspace, and G likewise.
        let mut sides: HashMap<(bool, u32), (bool, bool)> = HashMap::new();
        for (i, n) in self.nodes.iter().enumerate() {
            for key in [(true, n.end_effector.0), (false, n.workspace.0)] {
                let entry = sides.entry(key).or_default();
                entry.0 |= self.in_r[i];
                entry.1 |= self.in_g[i];
            }
        }
        let side = |key| sides.get(&key).copied().unwrap_or_default();
        let helps = |e: EndEffectorId, w: WorkspaceId| {
            let (hand, here) = (side((true, e.0)), side((false, w.0)));
            (hand.0 || here.0) && (hand.1 || here.1)
        };
        let reach = self
            .reach_candidates()
            .into_iter()
            .filter(|&(e, w)| helps(e, w));
        for (e, w) in reach.take(MAX_TRIES) {
            found.extend(self.try_keys(vec![Key::Reach(e, w)]));
        }
        found
    }

    /// True when a declared transition could pass the object from `a` to `b` (another
    /// end-effector, not both fixed), as the graph rules allow it between grasps declared
    /// for kinds.
    pub fn may_exchange(&self, a: EndEffectorId, b: EndEffectorId) -> bool {
        self.rules.may_exchange(a, b, false)
    }

    /// Every end-effector of the cell, in order.
    pub fn end_effector_ids(&self) -> impl Iterator<Item = EndEffectorId> {
        (0..self.art.end_effectors.len() as u32).map(EndEffectorId)
    }

    /// (movable end-effector, workspace it does not reach and could be made to reach by an
    /// edit), nearest first when the cell has geometry.
    fn reach_candidates(&self) -> Vec<(EndEffectorId, WorkspaceId)> {
        let n_ws = self.art.workspaces.len() as u32;
        let mut out: Vec<(f64, EndEffectorId, WorkspaceId)> = Vec::new();
        for e in self.end_effector_ids() {
            if !self.is_hand(e) {
                continue;
            }
            let candidates = (0..n_ws)
                .map(WorkspaceId)
                .filter(|&w| !self.reaches(e, w) && self.reach_editable(e, w));
            for w in candidates {
                let d = self.reach_distance(e, w).unwrap_or(0.0);
                out.push((d, e, w));
            }
        }
        out.sort_by(|a, b| a.0.total_cmp(&b.0).then((a.1, a.2).cmp(&(b.1, b.2))));
        out.into_iter().map(|(_, e, w)| (e, w)).collect()
    }

    /// When no single change connects: the change sets of paths needing the fewest
    /// hypothetical arcs, the first and the alternatives found by forbidding each of its
    /// changes in turn; plus, in cells that declare adjacency, a reach extension with the
    /// adjacency it needs.
    fn several_changes(&self) -> Vec<Candidate> {
        let mut sets: BTreeSet<Vec<Key>> = BTreeSet::new();
        if let Some(first) = self.fewest_changes(&BTreeSet::new(), &[]) {
            for &k in &first {
                if let Some(alt) = self.fewest_changes(&BTreeSet::from([k]), &[]) {
                    sets.insert(self.minimal(alt));
                }
            }
            sets.insert(self.minimal(first));
        }
        // A reach extension with what else it needs (a transition with the hand it now
        // meets, an adjacency), nearest workspaces first.
        for (e, w) in self.reach_candidates().into_iter().take(MAX_REACH_SETS) {
            if let Some(keys) = self.fewest_changes(&BTreeSet::new(), &[Key::Reach(e, w)]) {
                sets.insert(self.minimal(keys));
            }
        }
        sets.into_iter()
            .filter(|s| !s.is_empty())
            .filter_map(|s| self.try_keys(s))
            .collect()
    }

    /// Drops changes that are not needed.
    fn minimal(&self, mut keys: Vec<Key>) -> Vec<Key> {
        keys.sort();
        keys.dedup();
        let mut i = 0;
        while i < keys.len() && keys.len() > 1 {
            let mut rest = keys.clone();
            rest.remove(i);
            if self.connect(&self.apply(&rest)).is_some() {
                keys = rest;
            } else {
                i += 1;
            }
        }
        keys
    }

    /// A 0-1 breadth-first search from the start over the graph with the `base` changes
    /// made: existing arcs cost nothing, hypothetical ones (a transition between two
    /// grasps held in one workspace, an adjacency, an arc an allowed contact restores)
    /// cost one. Returns the distinct changes of the path found, `base` included. This is
    /// the one 0-1 search of the project: its successors are generated per state (every
    /// grasp pair that could be declared there), so no graph of them is ever built. When
    /// the start must be left, an arc back into it reaches `sink`, a goal of its own.
    fn fewest_changes(&self, banned: &BTreeSet<Key>, base: &[Key]) -> Option<Vec<Key>> {
        let ov = self.apply(base);
        let n = self.nodes.len();
        let total = n + ov.nodes.len();
        let node_of = |i: u32| -> Node {
            match (i as usize).checked_sub(n) {
                Some(k) => ov.nodes[k],
                None => self.node(i),
            }
        };
        let mut extra_at_ws: BTreeMap<WorkspaceId, Vec<u32>> = BTreeMap::new();
        for (k, node) in ov.nodes.iter().enumerate() {
            extra_at_ws
                .entry(node.workspace)
                .or_default()
                .push((n + k) as u32);
        }
        let mut extra_from: HashMap<u32, Vec<u32>> = HashMap::new();
        for a in &ov.arcs {
            extra_from.entry(a.from).or_default().push(a.to);
        }
        let sink = total as u32;
        let mut dist = vec![u32::MAX; total + 1];
        let mut pred: Vec<Option<(u32, Option<Key>)>> = vec![None; total + 1];
        let mut deque = VecDeque::new();
        dist[self.start as usize] = 0;
        deque.push_back((self.start, 0u32));
        let mut reached = None;
        while let Some((u, d)) = deque.pop_front() {
            let ui = u as usize;
            if d > dist[ui] {
                continue;
            }
            if u == sink || (ui < n && self.is_goal[ui] && !(self.must_leave && u == self.start)) {
                reached = Some(u);
                break;
            }
            let mut next: Vec<(u32, Option<Key>)> = Vec::new();
            if ui < n {
                next.extend(self.fwd[ui].iter().map(|&(v, _)| (v, None)));
                next.extend(self.lost_from[ui].iter().filter_map(|&i| {
                    let group = self.contact_key(i)?;
                    Some((self.lost[i].to, Some(Key::Contact(group))))
                }));
            }
            next.extend(extra_from.get(&u).into_iter().flatten().map(|&v| (v, None)));
            let nu = node_of(u);
            let hu = nu.end_effector;
            let here = self
                .at_ws
                .get(nu.workspace.index())
                .into_iter()
                .flatten()
                .chain(extra_at_ws.get(&nu.workspace).into_iter().flatten());
            for &v in here {
                let nv = node_of(v);
                if !self.may_exchange(hu, nv.end_effector)
                    || self.active.contains(&(u, v))
                    || self.declares(nu.grasp, nv.grasp)
                {
                    continue;
                }
                let key = Key::Transition(nu.grasp.min(nv.grasp), nu.grasp.max(nv.grasp));
                next.push((v, Some(key)));
            }
            if self.rules.declares_adjacency() && self.is_movable(hu) {
                let reach = self.reach(hu);
                let extended = base.iter().filter_map(|&k| match k {
                    Key::Reach(e, x) if e == hu => Some(x),
                    _ => None,
                });
                for x in reach.chain(extended) {
                    if x == nu.workspace
                        || self.is_adjacent(nu.workspace, x)
                        || !self.adjacency_editable(nu.workspace, x)
                    {
                        continue;
                    }
                    let pair = ordered(nu.workspace, x);
                    let to = Node { workspace: x, ..nu };
                    if let Some(v) = self.node_at(&ov, to) {
                        next.push((v, Some(Key::Adjacency(pair.0, pair.1))));
                    }
                }
            }
            for (v, key) in next {
                if key.is_some_and(|k| banned.contains(&k)) || v as usize >= total {
                    continue;
                }
                let v = if self.must_leave && v == self.start {
                    sink
                } else {
                    v
                };
                let step = u32::from(key.is_some());
                let nd = d + step;
                if nd < dist[v as usize] {
                    dist[v as usize] = nd;
                    pred[v as usize] = Some((u, key));
                    if step == 0 {
                        deque.push_front((v, nd));
                    } else {
                        deque.push_back((v, nd));
                    }
                }
            }
        }
        let mut u = reached?;
        let mut keys = base.to_vec();
        while let Some((p, key)) = pred[u as usize] {
            keys.extend(key);
            u = p;
        }
        keys.sort();
        keys.dedup();
        Some(keys)
    }

    /// A candidate as the public value: each change with how the plan would use it.
    pub fn suggestion(&self, c: &Candidate) -> Suggestion {
        let changes = c
            .keys
            .iter()
            .enumerate()
            .flat_map(|(ci, &key)| {
                let used: Vec<(Node, Node)> = c
                    .route
                    .arcs
                    .iter()
                    .filter(|a| a.change == ci)
                    .filter_map(|a| {
                        let x = self.overlay_node(&c.overlay, a.from)?;
                        Some((x, self.overlay_node(&c.overlay, a.to)?))
                    })
                    .collect();
                self.changes(key, &used)
            })
            .collect();
        Suggestion {
            changes,
            cost: c.route.cost,
        }
    }

    /// The changes a key stands for (one, or one `allow contact` per pair of its group),
    /// with the arcs they make that the plan would use.
    fn changes(&self, key: Key, used: &[(Node, Node)]) -> Vec<Change> {
        // The exchanges the plan would make: between two end-effectors in one workspace.
        let exchanges = || {
            let mut out: Vec<Exchange> = Vec::new();
            for (x, y) in used {
                let exchange = Exchange {
                    giver: x.end_effector,
                    taker: y.end_effector,
                    workspace: x.workspace,
                };
                if x.workspace == y.workspace
                    && x.end_effector != y.end_effector
                    && !out.contains(&exchange)
                {
                    out.push(exchange);
                }
            }
            out
        };
        match key {
            Key::Transition(a, b) => {
                let first = used
                    .iter()
                    .find(|(x, y)| x.workspace == y.workspace && x.end_effector != y.end_effector);
                let (from, to) = first.map_or((a, b), |(x, y)| (x.grasp, y.grasp));
                let reverse_of = self
                    .declared
                    .get(&(to, from))
                    .and_then(|s| s.first().copied());
                vec![Change::AddTransition {
                    from_grasp: from,
                    to_grasp: to,
                    reverse_of: reverse_of.map(SpanId),
                    exchanges: exchanges(),
                }]
            }
            Key::Adjacency(a, b) => vec![Change::AddAdjacency {
                a,
                b,
                carrier: used.first().map(|(x, _)| x.end_effector),
            }],
            Key::Reach(e, w) => {
                let meets: BTreeSet<EndEffectorId> = exchanges()
                    .iter()
                    .filter(|x| x.workspace == w)
                    .map(|x| if x.giver == e { x.taker } else { x.giver })
                    .collect();
                let meets = meets.into_iter().collect();
                let arm = self
                    .art
                    .end_effectors
                    .get(e.index())
                    .is_some_and(|x| matches!(x.body, Body::Arm { .. }));
                if !arm {
                    return vec![Change::ExtendReaches {
                        end_effector: e,
                        workspace: w,
                        meets,
                    }];
                }
                let (reach_box, grown) = self.grown_reach(e, w);
                vec![Change::GrowReach {
                    end_effector: e,
                    reach_box,
                    grown,
                    region: self
                        .art
                        .workspaces
                        .get(w.index())
                        .map(|x| x.boxes.clone())
                        .unwrap_or_default(),
                    workspace: w,
                    distance: self.reach_distance(e, w),
                    meets,
                }]
            }
            Key::Contact(g) => (0..self.contacts.len())
                .filter(|&p| self.contact_group[p] == g)
                .map(|p| {
                    let (a, b) = self.contacts[p].clone();
                    let arcs = (0..self.lost.len())
                        .filter(|&i| self.contact_of[i] == Some(p as u32))
                        .map(|i| self.lost_arc(i))
                        .collect();
                    Change::AllowContact { a, b, arcs }
                })
                .collect(),
        }
    }
}
