//! The hostile cases: what each builds, runs and expects.

use std::path::Path;
use std::process::Command;

/// What a case builds and runs.
pub struct Case {
    pub name: &'static str,
    /// Writes the inputs into the folder and returns the command line (run there).
    pub setup: fn(&Path) -> Vec<String>,
    pub expect: Expect,
}

/// What must happen.
pub struct Expect {
    pub exit: i32,
    /// The code that must be reported (`None`: no diagnostic code is required).
    pub code: Option<&'static str>,
    /// Wall-clock bound, for the unoptimised test build on a busy machine.
    pub seconds: u64,
    /// Address-space bound of the child.
    pub memory_mib: u64,
    /// Texts that must not appear in standard output or standard error.
    pub never: &'static [&'static str],
    /// Bound on the length of the output.
    pub max_output_bytes: usize,
}

const SMALL: Expect = Expect {
    exit: 1,
    code: None,
    seconds: 20,
    memory_mib: 512,
    never: &[],
    max_output_bytes: 20_000,
};

fn repo(path: &str) -> String {
    format!("{}/{path}", env!("CARGO_MANIFEST_DIR"))
}

fn write(folder: &Path, name: &str, bytes: impl AsRef<[u8]>) {
    std::fs::write(folder.join(name), bytes).expect("input written");
}

fn fifo(folder: &Path, name: &str) {
    let made = Command::new("mkfifo")
        .arg(folder.join(name))
        .status()
        .expect("mkfifo runs");
    assert!(made.success(), "mkfifo {name}");
}

fn args(words: &[&str]) -> Vec<String> {
    words.iter().map(|w| w.to_string()).collect()
}

/// A small abstract cell, with `extra` lines inside it.
fn pick(extra: &str) -> String {
    format!(
        "cell pick {{\n{extra}  workspace w1\n  fixed table reaches w1\n  movable left_arm reaches w1\n\n  object cube {{\n    grasp on_table by table\n    grasp held by left_arm\n    transition on_table <-> held\n  }}\n}}\n"
    )
}

/// A task for [`pick`]'s cube, so `cellc run --task t` reads a world document first.
const WORLD_TASK: &str = "  task t {\n    cube to left_arm.held in w1\n  }\n";

/// A one-arm geometric cell on `urdf`, with `object` as its object's members.
fn geometric(urdf: &str, tip: &str, object: &str) -> String {
    format!(
        "cell pick {{\n  units m, deg\n  robot r urdf \"{urdf}\" base base tip {tip}\n  hand gripper\n  support tabletop\n  arm left = r at (0, 0, 1) with gripper\n  reach left box center (0.5, 0, 0.8) size (0.6, 0.8, 0.4)\n  surface table : tabletop box center (0.5, 0, 0.75) size (0.6, 0.8, 0.02)\n  workspaces from reach\n  object cube {{\n{object}    rest standing on tabletop at (0, 0, 0.05)\n    grasp top by gripper at (0, 0, 0.1) rpy (180, 0, 0)\n    transition standing <-> top\n  }}\n}}\n"
    )
}

/// A sound one-joint arm (base `base`, tip `boom`).
const ARM_URDF: &str = r#"<robot name="swinger">
  <link name="base"/>
  <link name="boom"><collision><geometry><cylinder radius="0.05" length="0.5"/></geometry></collision></link>
  <joint name="swing" type="revolute">
    <parent link="base"/><child link="boom"/><origin xyz="0 0 0.1"/><axis xyz="0 0 1"/>
    <limit lower="-1.5" upper="1.5" effort="10" velocity="1"/>
  </joint>
</robot>
"#;

/// A geometric cell whose object is the mesh `mesh`, built (the runtime reads the mesh
/// before it verifies anything).
fn build_with_mesh(folder: &Path, mesh: &str) -> Vec<String> {
    write(folder, "r.urdf", ARM_URDF);
    let shape = format!("    shape mesh \"{mesh}\"\n");
    write(folder, "pick.cell", geometric("r.urdf", "boom", &shape));
    args(&["build", "pick.cell", "-o", "pick.json"])
}

const SECRET: &str = "API_TOKEN=sk-live-do-not-print\nDB_PASSWORD=hunter2\n";

/// A word that a mesh holds and no message may quote.
const SECRET_WORD: &str = "hunter2secret";

/// A COLLADA file with one geometry named `id` whose accessor states `count` positions
/// (its array holds 1,000), instantiated `instances` times.
fn collada(id: &str, count: &str, instances: usize) -> String {
    let values: Vec<String> = (0..3000)
        .map(|i| format!("{}", (i % 7) as f64 * 0.01))
        .collect();
    let nodes = format!("<node><instance_geometry url=\"#{id}\"/></node>").repeat(instances);
    format!(
        r##"<?xml version="1.0"?>
<COLLADA version="1.4.1"><asset><unit meter="1"/><up_axis>Z_UP</up_axis></asset>
<library_geometries><geometry id="{id}"><mesh>
<source id="p"><float_array id="a" count="3000">{}</float_array>
<technique_common><accessor source="#a" count="{count}" stride="3"/></technique_common></source>
<vertices id="v"><input semantic="POSITION" source="#p"/></vertices>
</mesh></geometry></library_geometries>
<library_visual_scenes><visual_scene id="s">{nodes}</visual_scene></library_visual_scenes>
<scene><instance_visual_scene url="#s"/></scene></COLLADA>
"##,
        values.join(" ")
    )
}

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

pub fn cases() -> Vec<Case> {
    vec![
        // ---- files that are not regular or too large (E0317, E0318) ----
        Case {
            name: "fifo_cell",
            setup: |f| {
                fifo(f, "pick.cell");
                args(&["check", "pick.cell"])
            },
            expect: Expect {
                code: Some("E0318"),
                seconds: 10,
                ..SMALL
            },
        },
        Case {
            name: "fifo_include",
            setup: |f| {
                fifo(f, "lib.cell");
                write(f, "pick.cell", pick("  include \"lib.cell\"\n"));
                args(&["check", "pick.cell"])
            },
            expect: Expect {
                code: Some("E0318"),
                seconds: 10,
                ..SMALL
            },
        },
        Case {
            name: "fifo_urdf",
            setup: |f| {
                fifo(f, "r.urdf");
                write(f, "pick.cell", geometric("r.urdf", "boom", ""));
                args(&["check", "pick.cell"])
            },
            expect: Expect {
                code: Some("E0318"),
                seconds: 10,
                ..SMALL
            },
        },
        Case {
            name: "fifo_artifact",
            setup: |f| {
                fifo(f, "pick.json");
                args(&["info", "pick.json"])
            },
            expect: Expect {
                code: Some("E0318"),
                seconds: 10,
                ..SMALL
            },
        },
        Case {
            name: "fifo_database",
            setup: |f| {
                fifo(f, "grasps.db");
                args(&["import", "dualmanip", "grasps.db", "-o", "out.cell"])
            },
            expect: Expect {
                code: Some("E0601"),
                seconds: 10,
                ..SMALL
            },
        },
        Case {
            name: "endless_device",
            setup: |_| args(&["check", "/dev/zero"]),
            expect: Expect {
                code: Some("E0318"),
                seconds: 10,
                ..SMALL
            },
        },
        Case {
            name: "E0317_cell_over_16_mib",
            setup: |f| {
                let mut text = String::from("cell pick {\n");
                text.push_str(&" ".repeat(16 << 20));
                text.push_str("}\n");
                write(f, "huge.cell", text);
                args(&["check", "huge.cell"])
            },
            // Refused by its size alone: never read, so a small address space suffices.
            expect: Expect {
                code: Some("E0317"),
                memory_mib: 256,
                ..SMALL
            },
        },
        Case {
            name: "urdf_over_16_mib",
            setup: |f| {
                write(f, "r.urdf", vec![b' '; (16 << 20) + 1]);
                write(f, "pick.cell", geometric("r.urdf", "boom", ""));
                args(&["check", "pick.cell"])
            },
            expect: Expect {
                code: Some("E0317"),
                memory_mib: 256,
                ..SMALL
            },
        },
        // ---- files that are not cells are described, never quoted (E0319) ----
        Case {
            name: "include_a_secret",
            setup: |f| {
                write(f, "secrets.env", SECRET);
                write(f, "pick.cell", pick("  include \"secrets.env\"\n"));
                args(&["check", "pick.cell"])
            },
            expect: Expect {
                code: Some("E0319"),
                never: &["hunter2", "sk-live"],
                ..SMALL
            },
        },
        Case {
            name: "check_a_secret",
            setup: |f| {
                write(f, "secrets.env", SECRET);
                args(&["check", "secrets.env", "--format", "json"])
            },
            expect: Expect {
                code: Some("E0319"),
                never: &["hunter2", "sk-live"],
                ..SMALL
            },
        },
        Case {
            name: "format_a_secret",
            setup: |f| {
                write(f, "secrets.env", SECRET);
                args(&["fmt", "--check", "secrets.env"])
            },
            expect: Expect {
                code: Some("E0319"),
                never: &["hunter2", "sk-live"],
                ..SMALL
            },
        },
        Case {
            name: "secret_as_urdf",
            setup: |f| {
                write(
                    f,
                    "config.xml",
                    "<config><token>sk-live-do-not-print</token></config>",
                );
                write(f, "pick.cell", geometric("config.xml", "boom", ""));
                args(&["check", "pick.cell"])
            },
            expect: Expect {
                code: Some("E0402"),
                never: &["sk-live"],
                ..SMALL
            },
        },
        Case {
            name: "binary_cell",
            setup: |f| {
                write(f, "pick.cell", b"cell pick {\0\x01\x02 hunter2 }");
                args(&["check", "pick.cell"])
            },
            expect: Expect {
                code: Some("E0319"),
                never: &["hunter2"],
                ..SMALL
            },
        },
        Case {
            name: "latin1_cell",
            setup: |f| {
                write(f, "pick.cell", b"cell pick { workspace caf\xe9 hunter2 }");
                args(&["check", "pick.cell"])
            },
            expect: Expect {
                code: Some("E0319"),
                never: &["hunter2"],
                ..SMALL
            },
        },
        // ---- control characters are refused at their place (E0004), never printed ----
        Case {
            name: "escape_sequences",
            setup: |f| {
                let lines = "  workspace w\x1b]0;pwned\x07\x1b[2J\n".repeat(40);
                write(f, "pick.cell", pick(&lines));
                args(&["check", "pick.cell"])
            },
            expect: Expect {
                code: Some("E0004"),
                never: &["\x1b", "\x07"],
                ..SMALL
            },
        },
        // ---- size: memory with nodes + arcs, time in seconds, or a clear limit ----
        Case {
            name: "E0320_100k_workspaces",
            setup: |f| {
                write(f, "big.cell", many_workspaces(100_000, 2, false, 0));
                args(&["check", "big.cell"])
            },
            expect: Expect {
                code: Some("E0320"),
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
                code: Some("E0322"),
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
                code: Some("E0321"),
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
                code: Some("E0101"),
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
                code: Some("E0102"),
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
                code: Some("E0001"),
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
                code: Some("E0002"),
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
                code: Some("E0304"),
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
        // ---- robot descriptions (E0406, E0407) in check and build ----
        Case {
            name: "nan_limit_check",
            setup: |f| {
                write(
                    f,
                    "pick.cell",
                    geometric(&repo("tests/ui/support/nan_limit.urdf"), "boom", ""),
                );
                args(&["check", "pick.cell"])
            },
            expect: Expect {
                code: Some("E0407"),
                ..SMALL
            },
        },
        Case {
            name: "nan_limit_build",
            setup: |f| {
                write(
                    f,
                    "pick.cell",
                    geometric(&repo("tests/ui/support/nan_limit.urdf"), "boom", ""),
                );
                args(&["build", "pick.cell", "-o", "pick.json"])
            },
            expect: Expect {
                code: Some("E0407"),
                ..SMALL
            },
        },
        Case {
            name: "joint_cycle_build",
            setup: |f| {
                write(
                    f,
                    "pick.cell",
                    geometric(&repo("tests/ui/support/cycle.urdf"), "upper", ""),
                );
                args(&["build", "pick.cell", "-o", "pick.json"])
            },
            expect: Expect {
                code: Some("E0406"),
                ..SMALL
            },
        },
        Case {
            name: "absurd_urdf_values",
            setup: |f| {
                let urdf = std::fs::read_to_string(repo("tests/ui/support/nan_limit.urdf"))
                    .expect("readable")
                    .replace("lower=\"NaN\"", "lower=\"-1\"")
                    .replace("<axis xyz=\"0 0 1\"/>", "<axis xyz=\"0 0 0\"/>")
                    .replace("radius=\"0.05\"", "radius=\"1e9\"")
                    .replace("xyz=\"0 0 0.1\"", "xyz=\"0 0 inf\"");
                write(f, "r.urdf", urdf);
                write(f, "pick.cell", geometric("r.urdf", "boom", ""));
                args(&["check", "pick.cell"])
            },
            expect: Expect {
                code: Some("E0407"),
                ..SMALL
            },
        },
        // ---- meshes, read by the runtime when a build verifies (R0002) ----
        Case {
            name: "mesh_fifo",
            setup: |f| {
                fifo(f, "part.stl");
                build_with_mesh(f, "part.stl")
            },
            expect: Expect {
                code: Some("R0002"),
                seconds: 10,
                ..SMALL
            },
        },
        Case {
            name: "mesh_empty",
            setup: |f| {
                write(f, "part.stl", "");
                build_with_mesh(f, "part.stl")
            },
            expect: Expect {
                code: Some("R0002"),
                ..SMALL
            },
        },
        Case {
            name: "mesh_over_32_mib",
            setup: |f| {
                write(f, "part.stl", vec![0u8; (32 << 20) + 1]);
                build_with_mesh(f, "part.stl")
            },
            expect: Expect {
                code: Some("R0002"),
                memory_mib: 256,
                ..SMALL
            },
        },
        Case {
            name: "mesh_300k_vertices",
            setup: |f| {
                let mut obj = String::new();
                for i in 0..300_000u32 {
                    let t = f64::from(i) * 0.001;
                    obj.push_str(&format!(
                        "v {:.4} {:.4} {:.4}\n",
                        t.sin(),
                        t.cos(),
                        t * 0.001
                    ));
                }
                write(f, "part.obj", obj);
                build_with_mesh(f, "part.obj")
            },
            expect: Expect {
                code: Some("R0002"),
                seconds: 30,
                ..SMALL
            },
        },
        // ---- COLLADA meshes: read by cellc's own reader, which trusts no count ----
        Case {
            name: "mesh_dae_of_garbage",
            setup: |f| {
                let bytes: Vec<u8> = (0..100_000u32)
                    .map(|i| (i.wrapping_mul(2654435761) >> 13) as u8)
                    .collect();
                write(f, "part.dae", bytes);
                build_with_mesh(f, "part.dae")
            },
            expect: Expect {
                code: Some("R0002"),
                ..SMALL
            },
        },
        Case {
            name: "mesh_dae_counts_that_lie",
            setup: |f| {
                write(f, "part.dae", collada(SECRET_WORD, "4294967295", 1));
                build_with_mesh(f, "part.dae")
            },
            expect: Expect {
                code: Some("R0002"),
                never: &[SECRET_WORD],
                ..SMALL
            },
        },
        Case {
            name: "mesh_dae_instanced_past_the_budget",
            setup: |f| {
                // 1,000 positions instantiated 1,000 times: counted before computed.
                write(f, "part.dae", collada("cube", "1000", 1000));
                build_with_mesh(f, "part.dae")
            },
            expect: Expect {
                code: Some("R0002"),
                ..SMALL
            },
        },
        Case {
            name: "mesh_dae_nested_a_million_deep",
            setup: |f| {
                let depth = 1_000_000;
                let text = format!(
                    "<COLLADA>{}{}</COLLADA>",
                    "<node>".repeat(depth),
                    "</node>".repeat(depth)
                );
                write(f, "part.dae", text);
                build_with_mesh(f, "part.dae")
            },
            expect: Expect {
                code: Some("R0002"),
                ..SMALL
            },
        },
        Case {
            name: "mesh_of_garbage",
            setup: |f| {
                let bytes: Vec<u8> = (0..100_000u32)
                    .map(|i| (i.wrapping_mul(2654435761) >> 13) as u8)
                    .collect();
                write(f, "part.stl", bytes);
                build_with_mesh(f, "part.stl")
            },
            expect: Expect {
                code: Some("R0002"),
                ..SMALL
            },
        },
        // ---- world documents (`cellc run --world`, R0008, R0009) ----
        Case {
            name: "fifo_world",
            setup: |f| {
                fifo(f, "w.json");
                write(f, "pick.cell", pick(WORLD_TASK));
                args(&["run", "pick.cell", "--task", "t", "--world", "w.json"])
            },
            expect: Expect {
                code: Some("R0008"),
                seconds: 10,
                ..SMALL
            },
        },
        Case {
            name: "world_over_its_budget",
            setup: |f| {
                let mut text = String::from("{\"objects\": {");
                text.push_str(&" ".repeat(5 << 20));
                text.push_str("}}");
                write(f, "w.json", text);
                write(f, "pick.cell", pick(WORLD_TASK));
                args(&["run", "pick.cell", "--task", "t", "--world", "w.json"])
            },
            expect: Expect {
                code: Some("R0008"),
                ..SMALL
            },
        },
        Case {
            name: "world_nested_deep",
            setup: |f| {
                let depth = 1_000_000;
                let text = format!(
                    "{{\"objects\": {{\"cube\": {}{}}}}}",
                    "[".repeat(depth),
                    "]".repeat(depth)
                );
                write(f, "w.json", text);
                write(f, "pick.cell", pick(WORLD_TASK));
                args(&["run", "pick.cell", "--task", "t", "--world", "w.json"])
            },
            expect: Expect {
                code: Some("R0008"),
                ..SMALL
            },
        },
        Case {
            name: "world_of_many_unknown_objects",
            setup: |f| {
                let entries: Vec<String> = (0..100_000)
                    .map(|i| format!("\"ghost{i}\": \"absent\""))
                    .collect();
                let text = format!("{{\"objects\": {{{}}}}}", entries.join(", "));
                write(f, "w.json", text);
                write(f, "pick.cell", pick(WORLD_TASK));
                args(&["run", "pick.cell", "--task", "t", "--world", "w.json"])
            },
            expect: Expect {
                code: Some("R0009"),
                ..SMALL
            },
        },
    ]
}
