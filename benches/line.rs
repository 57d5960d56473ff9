//! A generated assembly line: `n_arms` arms of one robot model with one shared hand kind,
//! in a row, each reaching its neighbours' space, with a bench between each pair of arms.
//! Grasps are declared once per kind; every pair of hand grasps may be exchanged, so
//! the graph grows as n_arms x n_grasps² and reaches 10⁶ arcs at 50 arms, 100 grasps.

/// The cell's source text. It includes `robots/kuka_lwr4.cell` relative to itself.
pub fn line_cell(n_arms: usize, n_hand_grasps: usize, n_rests: usize) -> String {
    let mut s = String::new();
    s.push_str(&format!(
        "// Generated: {n_arms} arms, {n_hand_grasps} hand grasps, {n_rests} resting poses.\n"
    ));
    s.push_str("cell line {\n  units m, deg\n  include \"robots/kuka_lwr4.cell\"\n");
    s.push_str("  hand gripper\n  support bench_top\n");
    for i in 0..n_arms {
        let x = i as f64;
        s.push_str(&format!(
            "  arm a{i} = lwr4 at ({x}, 0, 0.8) with gripper\n"
        ));
        s.push_str(&format!(
            "  reach a{i} box center ({x}, 0.4, 1) size (1.6, 0.8, 0.6)\n"
        ));
        if i + 1 < n_arms {
            s.push_str(&format!(
                "  surface bench{i} : bench_top box center ({}, 0.5, 0.75) size (0.4, 0.4, 0.02)\n",
                x + 0.5
            ));
        }
    }
    s.push_str("  workspaces from reach\n  object part {\n    shape box size (0.05, 0.05, 0.1)\n");
    for r in 0..n_rests {
        s.push_str(&format!(
            "    rest r{r} on bench_top at (0, 0, 0.05) rpy (0, 0, {})\n",
            r * 90
        ));
    }
    for g in 0..n_hand_grasps {
        s.push_str(&format!(
            "    grasp h{g} by gripper at (0, 0, 0.1) rpy (180, 0, {})\n",
            g * 3
        ));
    }
    for g in 0..n_hand_grasps {
        let others: Vec<String> = (g..n_hand_grasps).map(|h| format!("h{h}")).collect();
        s.push_str(&format!("    transition h{g} <-> {}\n", others.join(", ")));
    }
    for r in 0..n_rests {
        let hands: Vec<String> = (0..n_hand_grasps).map(|h| format!("h{h}")).collect();
        s.push_str(&format!("    transition r{r} <-> {}\n", hands.join(", ")));
    }
    s.push_str("  }\n}\n");
    s
}
