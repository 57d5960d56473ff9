//! Size: memory with nodes and arcs, time in seconds, or a clear limit (E0320, E0321,
//! E0322).

use std::path::Path;

use super::{args, pick, repo, write, Case, Expect, SMALL};
use cellc_lang::codes;

/// `n` workspaces, a fixed table reaching all and a movable arm reaching every `step`-th,
/// one object with two grasps and a transition; `adjacent` pairs along the arm's row when
/// `chain`, and `expects` requirements.
fn many_workspaces(n: usize, step: usize, chain: bool, expects: usize) -> String {
    let mut s = String::from("cell big {\n");
    for i in 0..n {
        s.push_str(&format!("  workspace w{i}\n"));
    }
    let all: Vec<String> = (0..n).map(|i| format!("w{i}")).collect();
    let row: Vec<String> = (0..n).step_by(step).map(|i| format!("w{i}")).collect();
    s.push_str(&format!("  fixed table reaches {}\n", all.join(", ")));
    s.push_str(&format!("  movable left_arm reaches {}\n", row.join(", ")));
    if chain {
        for pair in row.windows(2) {
            s.push_str(&format!("  adjacent {} {}\n", pair[0], pair[1]));
        }
    }
    s.push_str("  object o {\n    grasp g1 by table\n    grasp g2 by left_arm\n    transition g1 <-> g2\n  }\n");
    for i in 0..expects {
        s.push_str(&format!(
            "  expect o: table in {} -> table in {}\n",
            row[i % row.len()],
            row[row.len() - 1 - i % row.len()]
        ));
    }
    s.push_str("}\n");
    s
}

/// `n` arms with reach boxes of their own sizes and places (a fixed pseudo-random walk).
fn scattered_arms(n: usize) -> String {
    let mut s = String::from(
        "cell arms {\n  units m, deg\n  include \"robots/kuka_lwr4.cell\"\n  hand gripper\n",
    );
    let mut seed: u64 = 1;
    let mut next = || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    for i in 0..n {
        s.push_str(&format!(
            "  arm a{i} = lwr4 at ({}, 0, 0) with gripper\n",
            i as f64 * 0.5
        ));
        let (x, y, z) = (next() * n as f64 * 0.5, next() * 2.0 - 1.0, 0.5 + next());
        let (dx, dy, dz) = (0.5 + 2.5 * next(), 0.5 + 1.5 * next(), 0.2 + 0.8 * next());
        s.push_str(&format!(
            "  reach a{i} box center ({x:.3}, {y:.3}, {z:.3}) size ({dx:.3}, {dy:.3}, {dz:.3})\n"
        ));
    }
    s.push_str("  workspaces from reach\n  object o {\n    grasp g by gripper at (0, 0, 0.1)\n    transition g <-> g\n  }\n}\n");
    s
}

fn kuka(folder: &Path) {
    std::fs::create_dir_all(folder.join("robots")).expect("robots folder");
    for file in ["kuka_lwr4.cell", "kuka_lwr4.urdf"] {
        std::fs::copy(
            repo(&format!("cells/robots/{file}")),
            folder.join("robots").join(file),
        )
        .expect("robot copied");
    }
}

/// The cases of this module, in the order they run.
pub(super) fn cases() -> Vec<Case> {
    vec![
        Case {
            name: "E0320_100k_workspaces",
            setup: |f| {
                write(f, "big.cell", many_workspaces(100_000, 2, false, 0));
                args(&["check", "big.cell"])
            },
            expect: Expect {
                code: Some(codes::compile::GRAPH_TOO_LARGE),
                seconds: 30,
                memory_mib: 1024,
                ..SMALL
            },
        },
        Case {
            name: "100k_workspaces_in_a_row",
            setup: |f| {
                write(f, "big.cell", many_workspaces(100_000, 1, true, 3));
                args(&["check", "big.cell"])
            },
            expect: Expect {
                exit: 0,
                seconds: 30,
                memory_mib: 1024,
                ..SMALL
            },
        },
        Case {
            name: "E0322_many_expects",
            setup: |f| {
                write(f, "big.cell", many_workspaces(100_000, 1, true, 200));
                args(&["check", "big.cell"])
            },
            expect: Expect {
                code: Some(codes::compile::EXPECT_TOO_COSTLY),
                seconds: 45,
                memory_mib: 1024,
                ..SMALL
            },
        },
        Case {
            name: "E0321_scattered_reach",
            setup: |f| {
                kuka(f);
                write(f, "arms.cell", scattered_arms(80));
                args(&["check", "arms.cell"])
            },
            expect: Expect {
                code: Some(codes::compile::DERIVATION_TOO_LARGE),
                seconds: 30,
                ..SMALL
            },
        },
        Case {
            name: "forty_scattered_arms",
            setup: |f| {
                kuka(f);
                write(f, "arms.cell", scattered_arms(40));
                args(&["check", "arms.cell"])
            },
            expect: Expect {
                exit: 0,
                seconds: 30,
                memory_mib: 1024,
                max_output_bytes: 100_000,
                ..SMALL
            },
        },
        Case {
            name: "unknown_names_10_mb",
            setup: |f| {
                let lines: String = (0..200_000)
                    .map(|i| format!("  adjacent unknown_name_{i} other_{i}\n"))
                    .collect();
                write(f, "pick.cell", pick(&lines));
                args(&["check", "pick.cell"])
            },
            // Every name is reported; a few get a suggestion; human output shows 500.
            expect: Expect {
                code: Some(codes::compile::UNKNOWN_NAME),
                seconds: 45,
                memory_mib: 1024,
                max_output_bytes: 1_000_000,
                ..SMALL
            },
        },
        Case {
            name: "one_name_300k_times",
            setup: |f| {
                write(f, "pick.cell", pick(&"  workspace w\n".repeat(300_000)));
                args(&["check", "pick.cell", "--format", "short"])
            },
            expect: Expect {
                code: Some(codes::compile::DUPLICATE_NAME),
                seconds: 30,
                memory_mib: 1024,
                max_output_bytes: 60_000_000,
                ..SMALL
            },
        },
        Case {
            name: "a_line_of_10_mb",
            setup: |f| {
                write(
                    f,
                    "pick.cell",
                    format!("cell pick {{\n  {}\n}}\n", "workspace ".repeat(1_000_000)),
                );
                args(&["check", "pick.cell"])
            },
            // The line is never printed: at most the place and its length.
            expect: Expect {
                code: Some(codes::parse::SYNTAX),
                seconds: 30,
                memory_mib: 1024,
                never: &["workspace workspace workspace"],
                ..SMALL
            },
        },
        Case {
            name: "nested_100k_deep",
            setup: |f| {
                write(
                    f,
                    "pick.cell",
                    format!("cell pick {{\n{}\n}}\n", "object o {".repeat(100_000)),
                );
                args(&["check", "pick.cell"])
            },
            expect: Expect {
                code: Some(codes::parse::TOO_DEEP),
                seconds: 20,
                ..SMALL
            },
        },
        Case {
            name: "includes_3000_deep",
            setup: |f| {
                let n = 3000;
                for i in 0..n {
                    let body = if i + 1 < n {
                        format!("  include \"l{}.cell\"\n", i + 1)
                    } else {
                        "  workspace w9\n".to_string()
                    };
                    write(
                        f,
                        &format!("l{i}.cell"),
                        format!("library l{i} {{\n{body}}}\n"),
                    );
                }
                write(f, "pick.cell", pick("  include \"l0.cell\"\n"));
                args(&["check", "pick.cell"])
            },
            // The walk keeps its own stack; `w9` is reached by nothing (E0304).
            expect: Expect {
                code: Some(codes::compile::UNREACHED_WORKSPACE),
                seconds: 30,
                ..SMALL
            },
        },
        Case {
            name: "a_robot_2000_times",
            setup: |f| {
                let robots: String = (0..2000)
                    .map(|i| {
                        format!(
                            "  robot r{i} urdf \"{}\" base lwr_base_link tip lwr_flange\n",
                            repo("cells/robots/kuka_lwr4.urdf")
                        )
                    })
                    .collect();
                write(f, "pick.cell", pick(&robots));
                args(&["check", "pick.cell"])
            },
            // The URDF is read and checked once; the robots are unused, which is legal.
            expect: Expect {
                exit: 0,
                seconds: 30,
                ..SMALL
            },
        },
    ]
}
