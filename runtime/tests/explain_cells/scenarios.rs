//! The cells and requests the explanation tests explain: the paper's Fig. 3 with parts
//! taken away, arms too far apart, a line of arms with a gap, pruned and failed arcs,
//! surfaces without hands, and random small cells.

use super::{s, st, Desc, Req, St};
use cellc_schema::{EndEffectorId, Infeasibility};

/// The paper's Fig. 3 cell, with its transitions (directed, as listed in method.md).
pub fn fig3(keep: impl Fn(&str, &str) -> bool) -> Desc {
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

pub fn right_grasp(g: &str) -> bool {
    matches!(g, "g7" | "g8" | "g9")
}

/// Two arms in a row with a table at each end; the arms reach no common workspace.
pub fn arms_apart() -> Desc {
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

/// from a table at one end to a table at the other, every handoff declared except the one
/// between `arm{gap}` and the next arm.
pub fn line(n: usize, grasps: usize, gap: usize) -> Desc {
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

/// A random small cell from a seed: 1-4 workspaces, 2-4 end-effectors, one or two grasps
/// each, random transitions, adjacency declared or derived, some arcs pruned.
pub fn random_cell(seed: u64) -> (Desc, Req) {
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
            art.end_effectors[n.end_effector.index()].name.clone(),
            art.objects[0].grasps[n.grasp.index()].name.clone(),
            art.workspaces[n.workspace.index()].name.clone(),
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

/// The Fig. 3 request: from the table in `w1` to the table in `w3`.
fn fig3_request() -> Req {
    Req::new(st("table", "g1", "w1"), vec![st("table", "g1", "w3")])
}

/// Fig. 3 as published: connected.
pub fn fig3_connected() -> (Desc, Req) {
    (fig3(|_, _| true), fig3_request())
}

/// Nothing hands the cylinder to the right arm any more (it can still give it back).
pub fn fig3_right_arm_cannot_take() -> (Desc, Req) {
    (
        fig3(|from, to| right_grasp(from) || !right_grasp(to)),
        fig3_request(),
    )
}

/// No transition involves the right arm at all: the goal, on the table in `w3`, can only
/// be entered from it.
pub fn fig3_right_arm_isolated() -> (Desc, Req) {
    (
        fig3(|from, to| !right_grasp(from) && !right_grasp(to)),
        fig3_request(),
    )
}

/// Every transition into the right arm in `w2` was found infeasible at build time: from
/// the table because the right arm cannot reach, from the left arm because the closed
/// chain does not close.
pub fn fig3_handoffs_pruned() -> (Desc, Req) {
    let mut d = fig3(|_, _| true);
    let ik = Infeasibility::NoIkSolution {
        end_effector: EndEffectorId(2),
        tries: 300,
        position_error: 0.21,
        rotation_error: 0.1,
    };
    let chain = Infeasibility::NoClosedChain {
        a: EndEffectorId(1),
        b: EndEffectorId(2),
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
    (d, fig3_request())
}

/// The request across [`arms_apart`].
fn apart_request() -> Req {
    Req::new(st("table_a", "a1", "w1"), vec![st("table_b", "b1", "w4")])
}

/// [`arms_apart`] with geometry: workspaces one metre wide in a row; each arm's reach
/// stops 0.1 m short of the other's first workspace.
pub fn arms_apart_with_boxes() -> (Desc, Req) {
    let d = arms_apart()
        .boxed("w1", 0.0, 1.0)
        .boxed("w2", 1.0, 2.0)
        .boxed("w3", 2.0, 3.0)
        .boxed("w4", 3.0, 4.0)
        .boxed("left", 0.0, 1.9)
        .boxed("right", 2.1, 4.0);
    (d, apart_request())
}

/// [`arms_apart`] in a cell that declares adjacency: `adjacent w2 w3` joins two
/// workspaces no hand spans, so the artifact keeps no trace of it.
pub fn arms_apart_declaring_adjacency() -> (Desc, Req) {
    let d = arms_apart()
        .adjacent("w1", "w2")
        .adjacent("w2", "w3")
        .adjacent("w3", "w4");
    (d, apart_request())
}

/// Two hands of one kind share the grasp `pinch`, and no `pinch <-> pinch` is declared.
pub fn hands_of_one_kind() -> (Desc, Req) {
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
    (d, req)
}

/// A line of ten arms with four grasps each, the handoff from `arm4` to `arm5` missing.
pub fn line_with_a_gap() -> (Desc, Req) {
    let req = Req::new(st("start", "s", "w0"), vec![st("end", "e", "w10")]);
    (line(10, 4, 4), req)
}

/// One hand in two workspaces, asked to carry its grasp from one to the other.
fn one_hand() -> (Desc, Req) {
    let d = Desc::new(&["w2", "w3"])
        .movable("right", &["w2", "w3"])
        .grasps("right", &["g7"]);
    let req = Req::new(st("right", "g7", "w2"), vec![st("right", "g7", "w3")]);
    (d, req)
}

/// [`one_hand`] whose move failed during the request.
pub fn one_hand_move_failed() -> (Desc, Req) {
    let (d, mut req) = one_hand();
    req.failed.push((
        st("right", "g7", "w2"),
        st("right", "g7", "w3"),
        Infeasibility::NoIkSolution {
            end_effector: EndEffectorId(0),
            tries: 100,
            position_error: 0.21,
            rotation_error: 0.0,
        },
    ));
    (d, req)
}

/// [`one_hand`] whose move was pruned at build time: the arm hits a shelf.
pub fn one_hand_move_pruned() -> (Desc, Req) {
    let (d, req) = one_hand();
    let mut d = d.obstacle("shelf");
    d.pruned.push((
        st("right", "g7", "w2"),
        st("right", "g7", "w3"),
        Infeasibility::Collision {
            a: s("right/link_4"),
            b: s("shelf"),
        },
    ));
    (d, req)
}

/// From one table to another in one workspace: an arm could take it between them, but no
/// transition is declared.
pub fn two_surfaces_and_an_arm() -> (Desc, Req) {
    let d = Desc::new(&["w1"])
        .fixed("table_a", &["w1"])
        .fixed("table_b", &["w1"])
        .movable("arm", &["w1"])
        .grasps("table_a", &["a1"])
        .grasps("table_b", &["b1"])
        .grasps("arm", &["h1"]);
    let req = Req::new(st("table_a", "a1", "w1"), vec![st("table_b", "b1", "w1")]);
    (d, req)
}

/// From one table to another, with no hand at all.
pub fn surfaces_alone() -> (Desc, Req) {
    let d = Desc::new(&["w1"])
        .fixed("table_a", &["w1"])
        .fixed("table_b", &["w1"])
        .grasps("table_a", &["a1"])
        .grasps("table_b", &["b1"]);
    let req = Req::new(st("table_a", "a1", "w1"), vec![st("table_b", "b1", "w1")]);
    (d, req)
}

/// An arm reaching `w1` and `w3`, which the cell does not declare adjacent.
pub fn workspaces_not_adjacent() -> (Desc, Req) {
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
    (d, req)
}

/// A table and an arm in one workspace, asked to move the object to another pose on the
/// table (the start is the goal state): the arm cannot take it (`one_way: false`), or can
/// take it but not put it back (`one_way: true`).
pub fn back_to_the_table(one_way: bool) -> (Desc, Req) {
    let mut d = Desc::new(&["w1"])
        .fixed("table", &["w1"])
        .movable("arm", &["w1"])
        .grasps("table", &["standing"])
        .grasps("arm", &["top"]);
    if one_way {
        d = d.one_way("standing", &["top"]);
    }
    let here = st("table", "standing", "w1");
    (d, Req::new(here.clone(), vec![here]))
}

/// Fig. 3 as published, where one handoff failed during the request and the planner gave
/// up (its limit of backtracks) while other paths remained.
pub fn fig3_gave_up() -> (Desc, Req) {
    let (d, mut req) = fig3_connected();
    req.failed.push((
        st("left_arm", "g5", "w2"),
        st("right_arm", "g7", "w2"),
        Infeasibility::NoPlacement {
            detail: s(
                "no collision-free motion: no collision-free motion found in 10000 iterations",
            ),
        },
    ));
    (d, req)
}
