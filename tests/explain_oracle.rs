//! The causes an answer names are true of the cell: on generated small abstract cells,
//! every R0003 (the request does not fit the cell) and every R0004 (no path) is checked
//! against this file's own model of the cell, computed from the cell's description alone
//! (the paper's rules written out again here, not the shared graph rules the compiler and
//! the runtime use), and every R0003 help, applied to the description, removes its cause.
//!
//! The cells are `random_cell`'s (`runtime/tests/explain_cells/`), with an end-effector
//! that has no grasp and, sometimes, an object with no grasp at all. For each, requests are
//! drawn by name (a holder, a grasp or none, a workspace) and planned through
//! [`Cell::request`] and [`Cell::plan`], as `cellc plan` does; the cell's own request, with
//! its pruned and failed arcs, is explained as the planner's answer would be. Counts of
//! each kind of answer checked are asserted, so the test cannot pass by checking none.

#[path = "../runtime/tests/explain_cells/mod.rs"]
mod explain_cells;

use std::collections::{BTreeMap, BTreeSet, VecDeque};

use cellc_runtime::explain::{Cause, Explanation, Gap};
use cellc_runtime::plan::{GoalByName, LocateError, PlacementByName, PlanError, PlanOptions};
use cellc_runtime::Cell;
use cellc_schema::{Artifact, MemoryFiles, Node, NodeId};
use explain_cells::*;

/// The cell as this file reads its description: states and arcs by name.
struct Model {
    states: BTreeSet<St>,
    arcs: BTreeMap<St, Vec<St>>,
    back: BTreeMap<St, Vec<St>>,
}

/// The end-effectors that may hold grasp `g` (one, or each member of its hand kind), and
/// whether it was declared for one end-effector.
fn holders_of(d: &Desc, g: &str) -> (Vec<String>, bool) {
    let holder = &d.grasps.iter().find(|x| x.0 == g).expect("a grasp").1;
    match d.kinds.iter().find(|k| &k.0 == holder) {
        Some((_, members)) => (members.clone(), false),
        None => (vec![holder.clone()], true),
    }
}

fn reaches(d: &Desc, e: &str) -> BTreeSet<String> {
    let found = d.end_effectors.iter().find(|x| x.0 == e).expect("declared");
    found
        .2
        .iter()
        .filter(|w| d.workspaces.contains(w))
        .cloned()
        .collect()
}

fn movable(d: &Desc, e: &str) -> bool {
    d.end_effectors.iter().any(|x| x.0 == e && x.1)
}

fn adjacent(d: &Desc, a: &str, b: &str) -> bool {
    if a == b {
        return false;
    }
    if d.adjacent.is_empty() {
        return d.end_effectors.iter().any(|(e, m, _)| {
            let r = reaches(d, e);
            *m && r.contains(a) && r.contains(b)
        });
    }
    d.adjacent
        .iter()
        .any(|(x, y)| (x == a && y == b) || (x == b && y == a))
}

/// The paper's rules (Sec. IV-A), from the description: a state for each grasp, each of
/// its holders and each workspace that holder reaches; a move when a movable holder carries
/// a grasp between two adjacent workspaces it reaches; a transition for each declared
/// `from -> to`, between two holders that reach a workspace, never two fixed ones and never
/// one hand to itself with a kind's grasp. `lost` arcs (pruned or failed) are left out.
fn model(d: &Desc, lost: &BTreeSet<(St, St)>) -> Model {
    let mut states = BTreeSet::new();
    for (g, _) in &d.grasps {
        for e in holders_of(d, g).0 {
            for w in reaches(d, &e) {
                states.insert((e.clone(), g.clone(), w));
            }
        }
    }
    let mut arcs: BTreeMap<St, Vec<St>> = BTreeMap::new();
    let mut add = |a: St, b: St| {
        if !lost.contains(&(a.clone(), b.clone())) {
            let list = arcs.entry(a).or_default();
            if !list.contains(&b) {
                list.push(b);
            }
        }
    };
    for (e, g, w) in &states {
        if !movable(d, e) {
            continue;
        }
        for v in reaches(d, e) {
            if adjacent(d, w, &v) {
                add((e.clone(), g.clone(), w.clone()), (e.clone(), g.clone(), v));
            }
        }
    }
    for (gf, gt) in &d.transitions {
        let (givers, explicit_f) = holders_of(d, gf);
        let (takers, explicit_t) = holders_of(d, gt);
        for ei in &givers {
            for ej in &takers {
                if !movable(d, ei) && !movable(d, ej) {
                    continue;
                }
                if ei == ej && !(explicit_f && explicit_t) {
                    continue;
                }
                for w in reaches(d, ei).intersection(&reaches(d, ej)) {
                    add(
                        (ei.clone(), gf.clone(), w.clone()),
                        (ej.clone(), gt.clone(), w.clone()),
                    );
                }
            }
        }
    }
    let mut back: BTreeMap<St, Vec<St>> = BTreeMap::new();
    for (a, list) in &arcs {
        for b in list {
            back.entry(b.clone()).or_default().push(a.clone());
        }
    }
    Model { states, arcs, back }
}

/// States reachable from `from` over `edges`.
fn closure(edges: &BTreeMap<St, Vec<St>>, from: &[St]) -> BTreeSet<St> {
    let mut seen: BTreeSet<St> = from.iter().cloned().collect();
    let mut queue: VecDeque<St> = from.iter().cloned().collect();
    while let Some(u) = queue.pop_front() {
        for v in edges.get(&u).into_iter().flatten() {
            if seen.insert(v.clone()) {
                queue.push_back(v.clone());
            }
        }
    }
    seen
}

fn name_of(art: &Artifact, n: Node) -> St {
    (
        art.end_effectors[n.end_effector.index()].name.clone(),
        art.objects[0].grasps[n.grasp.index()].name.clone(),
        art.workspaces[n.workspace.index()].name.clone(),
    )
}

fn node_name(art: &Artifact, n: NodeId) -> St {
    name_of(art, art.objects[0].graph.nodes[n.index()])
}

/// Arcs by their end states.
type Arcs = BTreeSet<(St, St)>;

/// Counts of what was checked, by kind.
#[derive(Default, Debug)]
struct Checked(BTreeMap<String, usize>);

impl Checked {
    fn add(&mut self, what: &str) {
        *self.0.entry(what.to_string()).or_default() += 1;
    }
    fn get(&self, what: &str) -> usize {
        self.0.get(what).copied().unwrap_or(0)
    }
}

/// Checks an explanation of "no path from `start` to `goals`" against the model with the
/// `pruned` and `failed` arcs left out.
fn check_explanation(
    d: &Desc,
    art: &Artifact,
    (pruned, failed): (&Arcs, &Arcs),
    start: &St,
    goals: &[St],
    ex: &Explanation,
    seen: &mut Checked,
) {
    let lost: BTreeSet<(St, St)> = pruned.union(failed).cloned().collect();
    let m = model(d, &lost);
    let forward = closure(&m.arcs, std::slice::from_ref(start));
    let backward = closure(&m.back, goals);
    assert!(
        forward.is_disjoint(&backward),
        "the model connects {start:?} to {goals:?}, the planner said it does not"
    );
    // The cause: what restoring the lost arcs would do.
    let connects = |lost: &BTreeSet<(St, St)>| {
        let m = model(d, lost);
        let f = closure(&m.arcs, std::slice::from_ref(start));
        goals.iter().any(|g| f.contains(g))
    };
    match ex.cause {
        Cause::Missing => assert!(!connects(&BTreeSet::new()), "{:?}: Missing", ex.cause),
        Cause::Pruned => {
            assert!(
                connects(failed),
                "Pruned, but restoring the pruned arcs does not connect"
            );
        }
        Cause::Failed => {
            assert!(
                connects(&BTreeSet::new()),
                "Failed, but restoring every arc does not connect"
            );
            assert!(!failed.is_empty());
        }
        Cause::Connected => panic!("Connected, but the model says the goal is unreachable"),
    }
    seen.add(&format!("cause {:?}", ex.cause));
    // The sides are what the model says the start reaches and what leads to the goal.
    let side =
        |states: &[NodeId]| -> BTreeSet<St> { states.iter().map(|&n| node_name(art, n)).collect() };
    assert_eq!(side(&ex.start_side.states), forward, "the start's side");
    assert_eq!(side(&ex.goal_side.states), backward, "the goal's side");
    let ee = |e: cellc_schema::EndEffectorId| art.end_effectors[e.index()].name.clone();
    let ws = |w: cellc_schema::WorkspaceId| art.workspaces[w.index()].name.clone();
    let grasp = |g: cellc_schema::GraspId| art.objects[0].grasps[g.index()].name.clone();
    let holders =
        |side: &BTreeSet<St>| -> BTreeSet<String> { side.iter().map(|s| s.0.clone()).collect() };
    let places =
        |side: &BTreeSet<St>| -> BTreeSet<String> { side.iter().map(|s| s.2.clone()).collect() };
    let named = |v: &[cellc_schema::EndEffectorId]| -> BTreeSet<String> {
        v.iter().map(|&e| ee(e)).collect()
    };
    let wnamed = |v: &[cellc_schema::WorkspaceId]| -> BTreeSet<String> {
        v.iter().map(|&w| ws(w)).collect()
    };
    let lost_arc = |a: &cellc_runtime::explain::LostArc| {
        let pair = (node_name(art, a.from), node_name(art, a.to));
        let set = if a.failed { failed } else { pruned };
        assert!(set.contains(&pair), "{pair:?} is not a lost arc");
        pair
    };
    for item in &ex.cut {
        match &item.gap {
            Gap::NoTransition {
                near,
                far,
                workspaces,
                one_way,
            } => {
                for w in workspaces {
                    for h in near.iter().chain(far) {
                        assert!(
                            reaches(d, &ee(h.end_effector)).contains(&ws(*w)),
                            "NoTransition: `{}` does not reach `{}`",
                            ee(h.end_effector),
                            ws(*w)
                        );
                    }
                }
                for n in near {
                    for f in far {
                        for &a in &n.grasps {
                            for &b in &f.grasps {
                                let declared = d.transitions.contains(&(grasp(a), grasp(b)));
                                assert!(
                                    !declared,
                                    "NoTransition, but `{} -> {}` is declared",
                                    grasp(a),
                                    grasp(b)
                                );
                            }
                        }
                    }
                }
                for (b, a) in one_way {
                    assert!(d.transitions.contains(&(grasp(*b), grasp(*a))));
                    assert!(!d.transitions.contains(&(grasp(*a), grasp(*b))));
                }
                seen.add("NoTransition");
            }
            Gap::InfeasibleTransition { arcs, .. } => {
                assert!(!arcs.is_empty());
                for a in arcs {
                    let (from, to) = lost_arc(a);
                    assert!(
                        from.2 == to.2 && (&from.0, &from.1) != (&to.0, &to.1),
                        "a transition: {from:?} {to:?}"
                    );
                    assert!(
                        d.transitions.contains(&(from.1.clone(), to.1.clone())),
                        "InfeasibleTransition {from:?} -> {to:?} is not declared"
                    );
                }
                seen.add("InfeasibleTransition");
            }
            Gap::InfeasibleMove {
                hand,
                grasps,
                from,
                to,
                arcs,
            } => {
                assert!(movable(d, &ee(*hand)));
                assert!(adjacent(d, &ws(*from), &ws(*to)));
                // Each arc is a move of the hand between the two (either way), and the one
                // that would carry the object on is among them.
                let mut onward = false;
                for a in arcs {
                    let (x, y) = lost_arc(a);
                    assert!(x.0 == ee(*hand) && y.0 == ee(*hand), "{x:?} {y:?}");
                    let pair = BTreeSet::from([x.2.clone(), y.2.clone()]);
                    assert_eq!(pair, BTreeSet::from([ws(*from), ws(*to)]));
                    assert!(x.1 == y.1 && grasps.iter().any(|&g| grasp(g) == x.1));
                    onward |= x.2 == ws(*from);
                }
                assert!(
                    onward,
                    "InfeasibleMove: no lost move from `{}` to `{}`",
                    ws(*from),
                    ws(*to)
                );
                seen.add("InfeasibleMove");
            }
            Gap::NotAdjacent { hand, from, to } => {
                let (h, a, b) = (ee(*hand), ws(*from), ws(*to));
                assert!(movable(d, &h), "NotAdjacent: `{h}` is fixed");
                let r = reaches(d, &h);
                assert!(r.contains(&a) && r.contains(&b), "NotAdjacent: `{h}` reach");
                assert!(
                    !adjacent(d, &a, &b),
                    "NotAdjacent, but `{a}` `{b}` are adjacent"
                );
                seen.add("NotAdjacent");
            }
            Gap::NoCommonWorkspace { near, far } => {
                let (a, b) = (reaches(d, &ee(*near)), reaches(d, &ee(*far)));
                assert!(
                    a.is_disjoint(&b),
                    "NoCommonWorkspace, but they share {a:?} {b:?}"
                );
                seen.add("NoCommonWorkspace");
            }
            Gap::NoHand {
                near,
                far,
                workspaces,
            } => {
                for e in near.iter().chain(far) {
                    assert!(!movable(d, &ee(*e)), "NoHand: `{}` is movable", ee(*e));
                }
                // No movable end-effector that may hold the object reaches them.
                for (e, m, _) in &d.end_effectors {
                    let holds = d.grasps.iter().any(|(g, _)| holders_of(d, g).0.contains(e));
                    if *m && holds {
                        let r = reaches(d, e);
                        for w in workspaces {
                            assert!(
                                !r.contains(&ws(*w)),
                                "NoHand, but `{e}` reaches `{}`",
                                ws(*w)
                            );
                        }
                    }
                }
                seen.add("NoHand");
            }
            Gap::OnlyFixed {
                near,
                far,
                near_workspaces,
                far_workspaces,
            } => {
                assert_eq!(named(near), holders(&forward));
                assert_eq!(named(far), holders(&backward));
                assert!(holders(&forward).iter().all(|e| !movable(d, e)));
                assert!(holders(&backward).iter().all(|e| !movable(d, e)));
                assert_eq!(wnamed(near_workspaces), places(&forward));
                assert_eq!(wnamed(far_workspaces), places(&backward));
                seen.add("OnlyFixed");
            }
            Gap::Apart {
                near_workspaces,
                far_workspaces,
                shared,
                ..
            } => {
                assert_eq!(wnamed(near_workspaces), places(&forward));
                assert_eq!(wnamed(far_workspaces), places(&backward));
                let both: BTreeSet<String> = places(&forward)
                    .intersection(&places(&backward))
                    .cloned()
                    .collect();
                assert_eq!(wnamed(shared), both);
                seen.add("Apart");
            }
        }
    }
}

/// A cell's own request, with its pruned and failed arcs, explained.
fn check_declared_request(seed: u64, seen: &mut Checked) {
    let (d, req) = random_cell(seed);
    if req.goals.contains(&req.start) || connects(&d, &req) != Some(false) {
        return;
    }
    let art = d.build();
    let ex = cellc_runtime::explain::explain(&art, &unreachable(&d, &art, &req))
        .expect("the states exist");
    let pruned: BTreeSet<(St, St)> = d
        .pruned
        .iter()
        .map(|p| (p.0.clone(), p.1.clone()))
        .collect();
    let failed: BTreeSet<(St, St)> = req
        .failed
        .iter()
        .map(|f| (f.0.clone(), f.1.clone()))
        .collect();
    check_explanation(
        &d,
        &art,
        (&pruned, &failed),
        &req.start,
        &req.goals,
        &ex,
        seen,
    );
}

/// splitmix64, for the requests drawn on each cell.
struct Draw(u64);

impl Draw {
    fn next(&mut self, n: usize) -> usize {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) % n.max(1) as u64) as usize
    }
}

/// A placement drawn by name: a holder, a grasp of the object (any, not necessarily the
/// holder's) or none, a workspace.
fn draw_place(d: &Desc, draw: &mut Draw) -> PlacementByName {
    let e = &d.end_effectors[draw.next(d.end_effectors.len())].0;
    let grasp = (!d.grasps.is_empty() && draw.next(3) != 0)
        .then(|| d.grasps[draw.next(d.grasps.len())].0.clone());
    PlacementByName {
        holder: e.clone(),
        grasp,
        workspace: Some(d.workspaces[draw.next(d.workspaces.len())].clone()),
        pose: None,
    }
}

/// The model's states of a placement: the holder's in the workspace, with the grasp if
/// named.
fn states_of(d: &Desc, p: &PlacementByName) -> Vec<St> {
    model(d, &BTreeSet::new())
        .states
        .into_iter()
        .filter(|s| {
            s.0 == p.holder
                && Some(&s.2) == p.workspace.as_ref()
                && p.grasp.as_ref().is_none_or(|g| &s.1 == g)
        })
        .collect()
}

/// Checks a locate error's cause against the description, and returns the description
/// with the help applied when the help names a change to the cell.
fn check_locate(d: &Desc, error: &LocateError, seen: &mut Checked) -> Option<Desc> {
    match error {
        LocateError::NotReached {
            holder, workspace, ..
        } => {
            assert!(
                !reaches(d, holder).contains(workspace),
                "R0003 says `{holder}` does not reach `{workspace}`, but it does"
            );
            seen.add("R0003 NotReached");
            // "add `W` to what `H` reaches"
            let mut fixed = d.clone();
            let e = fixed.ee(holder).expect("declared");
            fixed.end_effectors[e].2.push(workspace.clone());
            Some(fixed)
        }
        LocateError::NothingToHoldBy {
            holder, surface, ..
        } => {
            assert!(!d.grasps.is_empty());
            assert!(
                d.grasps
                    .iter()
                    .all(|(g, _)| !holders_of(d, g).0.contains(holder)),
                "R0003 says `{holder}` has nothing to hold the object by, but it has"
            );
            assert_eq!(*surface, !movable(d, holder));
            seen.add("R0003 NothingToHoldBy");
            // "add a grasp of the object `by H`"
            let mut fixed = d.clone();
            fixed
                .grasps
                .push((format!("added_{holder}"), holder.clone()));
            Some(fixed)
        }
        LocateError::Ungraspable { .. } => {
            assert!(
                d.grasps.is_empty(),
                "R0003 says ungraspable, but it has grasps"
            );
            seen.add("R0003 Ungraspable");
            None
        }
        LocateError::UnknownGrasp {
            holder,
            name,
            known,
        } => {
            let holds = d
                .grasps
                .iter()
                .any(|(g, _)| g == name && holders_of(d, g).0.contains(holder));
            assert!(
                !holds,
                "R0003 says `{holder}` has no grasp `{name}`, but it has"
            );
            let theirs: BTreeSet<&String> = d
                .grasps
                .iter()
                .filter(|(g, _)| holders_of(d, g).0.contains(holder))
                .map(|(g, _)| g)
                .collect();
            assert!(
                known.iter().all(|k| theirs.contains(k)),
                "{known:?} vs {theirs:?}"
            );
            seen.add("R0003 UnknownGrasp");
            None
        }
        LocateError::GraspNeeded { holder, grasps } => {
            let theirs: BTreeSet<String> = d
                .grasps
                .iter()
                .filter(|(g, _)| holders_of(d, g).0.contains(holder))
                .map(|(g, _)| g.clone())
                .collect();
            assert!(
                theirs.len() > 1,
                "R0003 asks which grasp, but `{holder}` has one"
            );
            assert_eq!(grasps.iter().cloned().collect::<BTreeSet<_>>(), theirs);
            seen.add("R0003 GraspNeeded");
            None
        }
        LocateError::NoStateThere {
            holder, workspace, ..
        } => panic!(
            "R0003 says the graph has no state of `{holder}` in `{workspace}`, but the model has"
        ),
        other => panic!("an R0003 this test does not expect: {other:?}"),
    }
}

/// The result of planning one drawn request on `d`.
enum Answer {
    Planned,
    Locate(LocateError),
    Unreachable,
}

fn plan_drawn(
    d: &Desc,
    start: &PlacementByName,
    goal: &PlacementByName,
    seen: &mut Checked,
) -> Answer {
    let art = d.build();
    let cell = Cell::from_artifact(art.clone(), &MemoryFiles::default()).expect("loads");
    let request = match cell.request(
        "cylinder",
        start,
        &GoalByName::Placement(goal.clone()),
        PlanOptions::default(),
    ) {
        Ok(r) => r,
        Err(e) => return Answer::Locate(e),
    };
    match cell.plan(&cell.home_world(), &request) {
        Ok(plan) => {
            // Every step of the plan is an arc of the model, from the start to a goal.
            let m = model(d, &BTreeSet::new());
            let names: Vec<St> = plan.states.iter().map(|&n| name_of(&art, n)).collect();
            assert!(states_of(d, start).contains(&names[0]), "{names:?}");
            let last = names.last().expect("a state");
            assert!(states_of(d, goal).contains(last), "{names:?}");
            // The path is simplified (a run of moves of one hand is one move): each pair
            // is an arc, or moves of that hand with that grasp lead from one to the other.
            for pair in names.windows(2) {
                let (a, b) = (&pair[0], &pair[1]);
                let arc = m.arcs.get(a).into_iter().flatten().any(|s| s == b);
                let run = a.0 == b.0 && a.1 == b.1 && {
                    let moves: BTreeMap<St, Vec<St>> = m
                        .arcs
                        .iter()
                        .filter(|(s, _)| s.0 == a.0 && s.1 == a.1)
                        .map(|(s, next)| {
                            let same = next.iter().filter(|t| t.0 == a.0 && t.1 == a.1);
                            (s.clone(), same.cloned().collect())
                        })
                        .collect();
                    closure(&moves, std::slice::from_ref(a)).contains(b)
                };
                assert!(
                    arc || run,
                    "not an arc nor a run of moves: {pair:?} in {d:?}"
                );
            }
            seen.add("planned");
            Answer::Planned
        }
        Err(PlanError::Locate(e)) => Answer::Locate(e),
        Err(PlanError::Unreachable(un)) => {
            let ex = cell.explain(&un).expect("the states exist");
            let start_state = name_of(&art, un.start);
            let goals: Vec<St> = un.goals.iter().map(|&n| name_of(&art, n)).collect();
            assert_eq!(
                goals.iter().cloned().collect::<BTreeSet<_>>(),
                states_of(d, goal).into_iter().collect::<BTreeSet<_>>(),
                "the goal states"
            );
            if goals.contains(&start_state) {
                seen.add("must leave");
                return Answer::Unreachable;
            }
            let pruned: BTreeSet<(St, St)> = d
                .pruned
                .iter()
                .map(|p| (p.0.clone(), p.1.clone()))
                .collect();
            check_explanation(
                d,
                &art,
                (&pruned, &BTreeSet::new()),
                &start_state,
                &goals,
                &ex,
                seen,
            );
            seen.add("R0004");
            Answer::Unreachable
        }
        Err(other) => panic!("an abstract plan fails only to locate or reach: {other:?}"),
    }
}

/// Drawn requests on a cell: each answer's cause is checked, and each R0003 help applied
/// removes that cause.
fn check_drawn_requests(seed: u64, seen: &mut Checked) {
    let (mut d, _) = random_cell(seed);
    let mut draw = Draw(seed ^ 0x5eed);
    // An end-effector without any grasp of the object, and sometimes no grasps at all.
    let w = d.workspaces[draw.next(d.workspaces.len())].clone();
    d.end_effectors
        .push((s("bare"), draw.next(2) == 0, vec![w]));
    if draw.next(10) == 0 {
        d.grasps.clear();
        d.transitions.clear();
        d.pruned.clear();
        d.kinds.clear();
    }
    for _ in 0..4 {
        let (start, goal) = (draw_place(&d, &mut draw), draw_place(&d, &mut draw));
        let Answer::Locate(error) = plan_drawn(&d, &start, &goal, seen) else {
            continue;
        };
        let Some(fixed) = check_locate(&d, &error, seen) else {
            continue;
        };
        if let Answer::Locate(again) = plan_drawn(&fixed, &start, &goal, seen) {
            assert_ne!(again, error, "the help applied leaves the same cause");
            check_locate(&fixed, &again, seen);
        }
        seen.add("R0003 help applied");
    }
}

#[test]
fn every_cause_named_is_true_of_the_cell_and_every_help_removes_it() {
    let mut seen = Checked::default();
    for seed in 0..1500 {
        check_declared_request(seed, &mut seen);
        check_drawn_requests(seed, &mut seen);
    }
    println!("{:#?}", seen.0);
    for (what, at_least) in [
        ("planned", 100),
        ("R0004", 100),
        ("R0003 NotReached", 100),
        ("R0003 NothingToHoldBy", 50),
        ("R0003 Ungraspable", 10),
        ("R0003 UnknownGrasp", 100),
        ("R0003 GraspNeeded", 20),
        ("R0003 help applied", 100),
        ("cause Missing", 100),
        ("cause Pruned", 20),
        ("cause Failed", 10),
        ("NoTransition", 50),
        ("InfeasibleTransition", 10),
        ("NotAdjacent", 5),
        ("NoCommonWorkspace", 10),
        ("NoHand", 10),
        ("InfeasibleMove", 10),
        ("OnlyFixed", 2),
        ("Apart", 5),
    ] {
        assert!(
            seen.get(what) >= at_least,
            "only {} `{what}` checked (want {at_least}): {:#?}",
            seen.get(what),
            seen.0
        );
    }
}
