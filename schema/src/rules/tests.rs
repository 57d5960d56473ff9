//! The rules on hand-made cells (the paper's Fig. 3 among them), against a brute-force
//! reading of the rules as `method.md` states them, and the arcs of edits against a
//! rebuild.

use std::collections::BTreeSet;

use super::*;
use crate::ids::ObjectId;

fn ee(e: u32) -> EndEffectorId {
    EndEffectorId(e)
}

fn ws(w: u32) -> WorkspaceId {
    WorkspaceId(w)
}

fn gr(g: u32) -> GraspId {
    GraspId(g)
}

/// (movable, reaches) per end-effector.
fn cell(n_ws: usize, ees: &[(bool, &[u32])], adjacency: Adjacency) -> CellRules {
    let facts = ees
        .iter()
        .map(|&(movable, reaches)| EndEffectorFacts {
            movable,
            reaches: reaches.iter().map(|&w| ws(w)).collect(),
        })
        .collect();
    CellRules::new(n_ws, facts, adjacency)
}

/// (holders, explicit) per grasp.
fn object(n_ee: usize, grasps: &[(&[u32], bool)], transitions: &[(u32, u32)]) -> ObjectRules {
    let grasps = grasps
        .iter()
        .map(|&(holders, explicit)| GraspFacts {
            holders: holders.iter().map(|&e| ee(e)).collect(),
            explicit,
        })
        .collect();
    let transitions = transitions.iter().map(|&(a, b)| (gr(a), gr(b))).collect();
    ObjectRules::new(n_ee, grasps, transitions)
}

type Arcs = Vec<(State, State, Provenance)>;

fn graph(rules: &CellRules, object: &ObjectRules) -> (Vec<State>, Arcs) {
    let states = rules.states(object);
    let mut arcs = Vec::new();
    rules.for_each_arc(object, |a, b, p| {
        arcs.push((states[a as usize], states[b as usize], p))
    });
    (states, arcs)
}

fn pairs(arcs: &Arcs) -> BTreeSet<(State, State)> {
    arcs.iter().map(|&(a, b, _)| (a, b)).collect()
}

/// The paper's Fig. 3: a table reaching w1..w3, the left arm w1 and w2, the right arm w2
/// and w3, three grasps each, and its transitions (both ways).
fn fig3() -> (CellRules, ObjectRules) {
    let rules = cell(
        3,
        &[(false, &[0, 1, 2]), (true, &[0, 1]), (true, &[1, 2])],
        Adjacency::Declared(vec![(ws(0), ws(1)), (ws(1), ws(2))]),
    );
    let grasps: Vec<(&[u32], bool)> = (0..9)
        .map(|g| (&[[0], [1], [2]][g / 3][..], true))
        .collect();
    let two_way = [
        (0, 4),
        (0, 5),
        (0, 7),
        (0, 8),
        (1, 4),
        (1, 7),
        (2, 3),
        (2, 4),
        (2, 6),
        (2, 7),
        (3, 7),
        (3, 8),
        (4, 6),
        (4, 8),
        (5, 6),
        (5, 7),
    ];
    let transitions: Vec<(u32, u32)> = two_way
        .iter()
        .flat_map(|&(a, b)| [(a, b), (b, a)])
        .collect();
    (rules, object(3, &grasps, &transitions))
}

#[test]
fn fig3_has_the_papers_states_and_arcs() {
    let (rules, obj) = fig3();
    let (states, arcs) = graph(&rules, &obj);
    assert_eq!(states.len(), 21);
    let moves = arcs
        .iter()
        .filter(|a| matches!(a.2, Provenance::Move { .. }))
        .count();
    assert_eq!(moves, 12, "each arm carries each of its grasps both ways");
    assert_eq!(arcs.len() - moves, 52);
    // The first move of the left arm with g4 uses `adjacent w1 w2`, the first declared.
    assert_eq!(
        arcs[0],
        (
            State {
                end_effector: ee(1),
                grasp: gr(3),
                workspace: ws(0)
            },
            State {
                end_effector: ee(1),
                grasp: gr(3),
                workspace: ws(1)
            },
            Provenance::Move { adjacency: Some(0) }
        )
    );
    for (a, b, p) in &arcs {
        match p {
            Provenance::Move { .. } => {
                assert_eq!((a.end_effector, a.grasp), (b.end_effector, b.grasp));
                assert_ne!(a.end_effector, ee(0), "the table never moves");
            }
            Provenance::Transition { .. } => {
                assert_eq!(a.workspace, b.workspace, "no arc changes both");
                assert_ne!(a.end_effector, b.end_effector);
            }
        }
    }
}

#[test]
fn kind_grasps_expand_but_no_hand_hands_an_object_to_itself() {
    // Two hands of one kind share `pinch`; `pinch -> pinch` is a handoff between them.
    let rules = cell(1, &[(true, &[0]), (true, &[0])], Adjacency::Derived);
    let obj = object(2, &[(&[0, 1], false)], &[(0, 0)]);
    let (states, arcs) = graph(&rules, &obj);
    assert_eq!(states.len(), 2);
    let handoffs: Vec<(u32, u32)> = arcs
        .iter()
        .map(|(a, b, _)| (a.end_effector.0, b.end_effector.0))
        .collect();
    assert_eq!(handoffs, [(0, 1), (1, 0)]);
}

#[test]
fn explicit_same_holder_transitions_are_kept_and_surfaces_never_exchange() {
    // A regrasp in one hand declared for that hand, as imported databases have; two
    // surfaces with a transition between them get none.
    let rules = cell(
        1,
        &[(true, &[0]), (false, &[0]), (false, &[0])],
        Adjacency::Derived,
    );
    let obj = object(
        3,
        &[(&[0], true), (&[0], true), (&[1], true), (&[2], true)],
        &[(0, 1), (2, 3)],
    );
    let (_, arcs) = graph(&rules, &obj);
    assert_eq!(arcs.len(), 1);
    assert_eq!((arcs[0].0.grasp, arcs[0].1.grasp), (gr(0), gr(1)));
    assert_eq!(arcs[0].2, Provenance::Transition { transition: 0 });
}

#[test]
fn declared_adjacency_limits_moves_and_derived_adjacency_joins_what_one_hand_reaches() {
    let hands: &[(bool, &[u32])] = &[(true, &[0, 1, 2]), (true, &[2, 3])];
    let grasps: &[(&[u32], bool)] = &[(&[0], true), (&[1], true)];
    let declared = cell(
        4,
        hands,
        Adjacency::Declared(vec![(ws(1), ws(0)), (ws(0), ws(1)), (ws(2), ws(3))]),
    );
    let (_, arcs) = graph(&declared, &object(2, grasps, &[]));
    let moves: Vec<(u32, u32, Option<usize>)> = arcs
        .iter()
        .map(|(a, b, p)| match p {
            Provenance::Move { adjacency } => (a.workspace.0, b.workspace.0, *adjacency),
            Provenance::Transition { .. } => unreachable!("no transitions declared"),
        })
        .collect();
    // The first declaration of a pair names it, whichever way round.
    assert_eq!(
        moves,
        [
            (0, 1, Some(0)),
            (1, 0, Some(0)),
            (2, 3, Some(2)),
            (3, 2, Some(2))
        ]
    );
    let derived = cell(4, hands, Adjacency::Derived);
    assert!(derived.is_adjacent(ws(0), ws(2)));
    assert!(
        !derived.is_adjacent(ws(0), ws(3)),
        "no one hand reaches both"
    );
    assert!(!derived.is_adjacent(ws(2), ws(2)));
    let (_, arcs) = graph(&derived, &object(2, grasps, &[]));
    assert_eq!(arcs.len(), 6 + 2);
}

/// The rules of a random cell, with what they were made from: (movable, reaches) per
/// end-effector, and the declared adjacent pairs (`None`: derived).
type RandomCell = (
    CellRules,
    ObjectRules,
    Vec<(bool, Vec<u32>)>,
    Option<Vec<(u32, u32)>>,
);

/// A random small cell from a seed (splitmix64): 1-4 workspaces, 1-4 end-effectors, one
/// or two grasps each, sometimes a kind grasp, random transitions, adjacency declared or
/// derived.
fn random(seed: u64) -> RandomCell {
    let mut x = seed;
    let mut next = move |n: u64| {
        x = x.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = x;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        (z ^ (z >> 31)) % n.max(1)
    };
    let n_ws = 1 + next(4) as u32;
    let n_ee = 1 + next(4) as u32;
    let ees: Vec<(bool, Vec<u32>)> = (0..n_ee)
        .map(|_| (next(3) != 0, (0..n_ws).filter(|_| next(2) == 0).collect()))
        .collect();
    let declared = (next(2) == 0).then(|| {
        (0..n_ws)
            .flat_map(|a| (0..n_ws).map(move |b| (a, b)))
            .filter(|&(a, b)| a != b && next(3) == 0)
            .collect::<Vec<_>>()
    });
    let mut grasps: Vec<(Vec<u32>, bool)> = Vec::new();
    for e in 0..n_ee {
        for _ in 0..1 + next(2) {
            grasps.push((vec![e], true));
        }
    }
    if next(2) == 0 {
        grasps.push(((0..n_ee).filter(|_| next(2) == 0).collect(), false));
    }
    let n_g = grasps.len() as u32;
    let transitions: Vec<(u32, u32)> = (0..n_g)
        .flat_map(|a| (0..n_g).map(move |b| (a, b)))
        .filter(|_| next(3) == 0)
        .collect();
    let adjacency = match &declared {
        Some(p) => Adjacency::Declared(p.iter().map(|&(a, b)| (ws(a), ws(b))).collect()),
        None => Adjacency::Derived,
    };
    let refs: Vec<(bool, &[u32])> = ees.iter().map(|(m, r)| (*m, r.as_slice())).collect();
    let rules = cell(n_ws as usize, &refs, adjacency);
    let grefs: Vec<(&[u32], bool)> = grasps.iter().map(|(h, x)| (h.as_slice(), *x)).collect();
    (
        rules,
        object(n_ee as usize, &grefs, &transitions),
        ees,
        declared,
    )
}

/// The arcs of a graph as `method.md` words the rules, by trying every pair of states.
fn brute_force(
    obj: &ObjectRules,
    ees: &[(bool, Vec<u32>)],
    declared: &Option<Vec<(u32, u32)>>,
) -> BTreeSet<(State, State)> {
    let reaches = |e: u32, w: u32| ees[e as usize].1.contains(&w);
    let movable = |e: u32| ees[e as usize].0;
    let adjacent = |a: u32, b: u32| {
        a != b
            && match declared {
                Some(p) => p.contains(&(a, b)) || p.contains(&(b, a)),
                None => (0..ees.len() as u32).any(|e| movable(e) && reaches(e, a) && reaches(e, b)),
            }
    };
    let mut states = Vec::new();
    for g in 0..obj.n_grasps() as u32 {
        for &e in obj.holders(gr(g)) {
            for w in (0..8).filter(|&w| reaches(e.0, w)) {
                states.push(State {
                    end_effector: e,
                    grasp: gr(g),
                    workspace: ws(w),
                });
            }
        }
    }
    let mut out = BTreeSet::new();
    for &s in &states {
        for &t in &states {
            let (es, et) = (s.end_effector.0, t.end_effector.0);
            let is_move = es == et
                && s.grasp == t.grasp
                && movable(es)
                && adjacent(s.workspace.0, t.workspace.0);
            let is_transition = s.workspace == t.workspace
                && obj.transitions().contains(&(s.grasp, t.grasp))
                && (movable(es) || movable(et))
                && (es != et || (obj.is_explicit(s.grasp) && obj.is_explicit(t.grasp)));
            if is_move || is_transition {
                out.insert((s, t));
            }
        }
    }
    out
}

#[test]
fn random_cells_have_exactly_the_arcs_the_rules_describe() {
    for seed in 0..2000 {
        let (rules, obj, ees, declared) = random(seed);
        let (states, arcs) = graph(&rules, &obj);
        assert_eq!(
            states.iter().collect::<BTreeSet<_>>().len(),
            states.len(),
            "seed {seed}: a state twice"
        );
        let expected = brute_force(&obj, &ees, &declared);
        assert_eq!(pairs(&arcs), expected, "seed {seed}");
        // Each declaration makes its own arcs: a transition declared twice, twice.
        let transitions = arcs
            .iter()
            .filter(|a| matches!(a.2, Provenance::Transition { .. }))
            .count();
        let per_declaration: usize = obj
            .transitions()
            .iter()
            .map(|&decl| {
                expected
                    .iter()
                    .filter(|(a, b)| a.workspace == b.workspace && (a.grasp, b.grasp) == decl)
                    .count()
            })
            .sum();
        assert_eq!(transitions, per_declaration, "seed {seed}");
    }
}

#[test]
fn an_edit_adds_the_arcs_a_rebuild_gains_and_no_others() {
    for seed in 0..2000 {
        let (before, obj, ees, _) = random(seed);
        let n_ws = before.n_workspaces() as u32;
        let n_g = obj.n_grasps() as u32;
        let (old_states, old_arcs) = graph(&before, &obj);
        let old = pairs(&old_arcs);
        let mut edits = vec![Edit::Transition(
            gr(seed as u32 % n_g),
            gr((seed / 7) as u32 % n_g),
        )];
        for e in 0..ees.len() as u32 {
            for w in (0..n_ws).filter(|&w| !before.reaches(ee(e), ws(w))) {
                edits.push(Edit::Reach(ee(e), ws(w)));
            }
        }
        if before.declares_adjacency() {
            for a in 0..n_ws {
                for b in a + 1..n_ws {
                    edits.push(Edit::Adjacency(ws(a), ws(b)));
                }
            }
        }
        for edit in edits {
            let mut after = before.clone();
            let mut obj_after = obj.clone();
            match edit {
                Edit::Transition(a, b) => {
                    let mut t = obj.transitions().to_vec();
                    t.push((a, b));
                    obj_after = ObjectRules::new(ees.len(), obj.grasps.clone(), t);
                }
                Edit::Adjacency(a, b) => after.declare_adjacency(a, b),
                Edit::Reach(e, w) => after.extend_reach(e, w),
            }
            let (new_states, new_arcs) = graph(&after, &obj_after);
            let new = pairs(&new_arcs);
            let added: BTreeSet<(State, State)> = after.added_by(&obj, edit).into_iter().collect();
            let gained: BTreeSet<(State, State)> = new.difference(&old).copied().collect();
            assert!(gained.is_subset(&added), "seed {seed} {edit:?}: missed");
            assert!(added.is_subset(&new), "seed {seed} {edit:?}: invented");
            if let Edit::Reach(e, w) = edit {
                let grown: BTreeSet<State> = new_states
                    .iter()
                    .filter(|s| !old_states.contains(s))
                    .copied()
                    .collect();
                let at: BTreeSet<State> = after.states_at(&obj, e, w).collect();
                assert_eq!(grown, at, "seed {seed} {edit:?}");
            }
        }
    }
}

#[test]
fn out_of_range_data_is_dropped_not_indexed() {
    let rules = cell(2, &[(true, &[1, 0, 7, 1])], Adjacency::Derived);
    assert_eq!(rules.reach(ee(0)), [ws(0), ws(1)]);
    assert!(rules.reach(ee(5)).is_empty());
    let obj = object(1, &[(&[3, 0], true)], &[(0, 9)]);
    assert_eq!(obj.holders(gr(0)), [ee(0)]);
    let (states, arcs) = graph(&rules, &obj);
    assert_eq!(states.len(), 2);
    assert_eq!(
        arcs.len(),
        2,
        "the two moves; the transition names no grasp"
    );
}

/// The adjacent pairs as `method.md` words adjacency, by trying every pair.
fn brute_force_pairs(
    ees: &[(bool, Vec<u32>)],
    declared: &Option<Vec<(u32, u32)>>,
    n_ws: u32,
) -> Vec<(WorkspaceId, WorkspaceId)> {
    let adjacent = |a: u32, b: u32| match declared {
        Some(p) => p.contains(&(a, b)) || p.contains(&(b, a)),
        None => ees
            .iter()
            .any(|(movable, reach)| *movable && reach.contains(&a) && reach.contains(&b)),
    };
    (0..n_ws)
        .flat_map(|a| (a + 1..n_ws).map(move |b| (a, b)))
        .filter(|&(a, b)| adjacent(a, b))
        .map(|(a, b)| (ws(a), ws(b)))
        .collect()
}

const NO_LIMITS: Limits = Limits {
    size: u64::MAX,
    visits: u64::MAX,
};

#[test]
fn the_count_is_what_the_graph_holds() {
    for seed in 0..2000 {
        let (rules, obj, ees, declared) = random(seed);
        let (states, arcs) = graph(&rules, &obj);
        let pairs = rules.adjacent_pairs(u64::MAX).expect("no limit");
        let n_ws = rules.n_workspaces() as u32;
        assert_eq!(
            pairs,
            brute_force_pairs(&ees, &declared, n_ws),
            "seed {seed}"
        );
        let objects = [obj.clone(), obj];
        let size = 2 * (states.len() + arcs.len()) + pairs.len();
        assert_eq!(
            rules.count(&objects, NO_LIMITS),
            Ok(size as u64),
            "seed {seed}"
        );
    }
    let (rules, obj) = fig3();
    assert_eq!(rules.count(&[obj], NO_LIMITS), Ok(2 + 21 + 12 + 52));
}

#[test]
fn counting_stops_at_the_limit() {
    // One arm reaching 10^5 workspaces with derived adjacency: 5 * 10^9 pairs, counted by
    // formula, never listed.
    let n = 100_000u32;
    let reach: Vec<u32> = (0..n).collect();
    let rules = cell(n as usize, &[(true, &reach)], Adjacency::Derived);
    let obj = object(1, &[(&[0], true)], &[]);
    let pairs = u64::from(n) * u64::from(n - 1) / 2;
    let limits = Limits {
        size: 1000,
        visits: 1000,
    };
    let exceeded = Exceeded {
        limit: Limit::Size,
        counted: pairs,
        object: None,
    };
    assert_eq!(rules.adjacent_pairs(1000), Err(pairs));
    assert_eq!(
        rules.count(std::slice::from_ref(&obj), limits),
        Err(exceeded)
    );
    // The same reach along a declared chain: the moves of the first holder and grasp
    // cross the limit, in the first object.
    let chain = (0..n - 1).map(|w| (ws(w), ws(w + 1))).collect();
    let rules = cell(n as usize, &[(true, &reach)], Adjacency::Declared(chain));
    let counted = (n - 1) as u64 + (n as u64 + 2 * (n - 1) as u64);
    assert_eq!(
        rules.count(
            &[obj],
            Limits {
                size: 300_000,
                ..limits
            }
        ),
        Err(Exceeded {
            limit: Limit::Size,
            counted,
            object: Some(ObjectId(0)),
        })
    );
    // Transitions between two hands' grasps in 10^5 shared workspaces: visits counted
    // before the arcs are, stopping at the limit.
    let both = cell(
        n as usize,
        &[(true, &reach), (true, &reach)],
        Adjacency::Declared(vec![]),
    );
    let obj = object(2, &[(&[0], true), (&[1], true)], &[(0, 1)]);
    let exceeded = both.count(
        &[obj],
        Limits {
            size: u64::MAX,
            ..limits
        },
    );
    assert_eq!(
        exceeded,
        Err(Exceeded {
            limit: Limit::Visits,
            counted: 2 * n as u64,
            object: Some(ObjectId(0)),
        })
    );
}
