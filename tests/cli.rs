//! End-to-end tests of the `cellc` binary: exit codes, output formats, `fmt`, `explain`.

use std::process::{Command, Output};

fn cellc(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_cellc"))
        .args(args)
        .output()
        .expect("the cellc binary runs")
}

fn temp_file(name: &str, text: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("cellc-cli-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let path = dir.join(name);
    std::fs::write(&path, text).expect("write temp file");
    path
}

const WARNING_CELL: &str = "cell w {\n  workspace a\n  movable arm1 reaches a\n  object o {\n    grasp g by arm1\n  }\n}\n";

#[test]
fn clean_cells_exit_zero_silently() {
    let out = cellc(&["check", "cells/fig3.cell", "cells/vito.cell"]);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(out.stdout.is_empty() && out.stderr.is_empty());
}

#[test]
fn errors_exit_one_with_short_lines() {
    let path = temp_file(
        "bad.cell",
        "cell bad {\n  workspace w1\n  fixed t reaches w9\n}\n",
    );
    let out = cellc(&["check", "--format", "short", path.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(1));
    let stdout = String::from_utf8_lossy(&out.stdout);
    let expected = format!(
        "{}:3:19: error[E0101]: unknown workspace `w9`",
        path.display()
    );
    assert!(stdout.lines().any(|l| l == expected), "{stdout}");
}

#[test]
fn human_output_shows_code_snippet_and_help() {
    let path = temp_file(
        "typo.cell",
        "cell typo {\n  workspace w1\n  fixed table reaches w2\n}\n",
    );
    let out = cellc(&["check", "--color", "never", path.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("error[E0101]"), "{stderr}");
    assert!(stderr.contains("fixed table reaches w2"), "{stderr}");
    assert!(stderr.contains("help: did you mean `w1`?"), "{stderr}");
    assert!(stderr.contains("2 errors, 0 warnings"), "{stderr}");
}

#[test]
fn json_output_follows_the_schema() {
    let path = temp_file(
        "json.cell",
        "cell j {\n  workspace w1\n  workspace w1\n  fixed t reaches w1\n}\n",
    );
    let out = cellc(&["check", "--format", "json", path.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(1));
    let doc: serde_json::Value = serde_json::from_slice(&out.stdout).expect("valid JSON");
    assert_eq!(doc["version"], 1);
    assert_eq!(doc["errors"], 1);
    let d = &doc["diagnostics"][0];
    assert_eq!(d["code"], "E0102");
    assert_eq!(d["severity"], "error");
    assert_eq!(d["line"], 3);
    assert_eq!(d["column"], 13);
    assert_eq!(
        d["span"]["end"].as_u64().unwrap() - d["span"]["start"].as_u64().unwrap(),
        2
    );
    let labels = d["labels"].as_array().expect("labels");
    assert_eq!(labels.len(), 2);
    assert_eq!(labels[0]["primary"], true);
    assert_eq!(labels[1]["line"], 2);
    assert!(d["help"].as_str().is_some());
}

#[test]
fn warnings_pass_unless_denied() {
    let path = temp_file("warn.cell", WARNING_CELL);
    let path = path.to_str().unwrap();
    assert_eq!(cellc(&["check", path]).status.code(), Some(0));
    assert_eq!(
        cellc(&["check", "--deny-warnings", path]).status.code(),
        Some(1)
    );
}

#[test]
fn usage_errors_exit_two() {
    assert_eq!(cellc(&["check"]).status.code(), Some(2));
    assert_eq!(cellc(&["frobnicate"]).status.code(), Some(2));
    assert_eq!(
        cellc(&["check", "--format", "xml", "cells/fig3.cell"])
            .status
            .code(),
        Some(2)
    );
}

#[test]
fn missing_file_is_a_coded_error() {
    let out = cellc(&["check", "--format", "short", "no/such.cell"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stdout).contains("error[E0308]"));
}

#[test]
fn explain_prints_the_page() {
    let out = cellc(&["explain", "E0101"]);
    assert_eq!(out.status.code(), Some(0));
    assert!(String::from_utf8_lossy(&out.stdout).starts_with("# E0101"));
    assert_eq!(cellc(&["explain", "E9999"]).status.code(), Some(2));
}

#[test]
fn fmt_rewrites_checks_and_refuses_broken_files() {
    let messy = temp_file(
        "messy.cell",
        "cell   m{workspace w1 \"A\"   fixed t reaches w1,\n}",
    );
    let messy = messy.to_str().unwrap();
    assert_eq!(cellc(&["fmt", "--check", messy]).status.code(), Some(1));
    assert_eq!(cellc(&["fmt", messy]).status.code(), Some(0));
    assert_eq!(
        std::fs::read_to_string(messy).unwrap(),
        "cell m {\n  workspace w1 \"A\"\n  fixed t reaches w1\n}\n"
    );
    assert_eq!(cellc(&["fmt", "--check", messy]).status.code(), Some(0));

    let broken_text = "cell b {\n  workspace\n}\n";
    let broken = temp_file("broken.cell", broken_text);
    assert_eq!(
        cellc(&["fmt", broken.to_str().unwrap()]).status.code(),
        Some(1)
    );
    assert_eq!(std::fs::read_to_string(&broken).unwrap(), broken_text);
}

#[test]
fn shipped_cells_are_formatted() {
    let out = cellc(&["fmt", "--check", "cells/fig3.cell", "cells/vito.cell"]);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stdout)
    );
}

/// A source edited after the build: diagnostics about the artifact do not point at lines
/// of the new text (they would be the wrong ones); they say the file changed.
#[test]
fn a_source_changed_since_the_build_is_reported_not_misquoted() {
    let source = std::fs::read_to_string("tests/ui/plan/R0004_no_way_across.cell").expect("ui");
    let cell = temp_file("stale.cell", &source);
    let artifact = cell.with_extension("json");
    let built = cellc(&[
        "build",
        cell.to_str().unwrap(),
        "-o",
        artifact.to_str().unwrap(),
        "--no-verify",
    ]);
    assert!(built.status.success());
    let before = cellc(&["plan", artifact.to_str().unwrap()]);
    let before = String::from_utf8_lossy(&before.stderr).to_string();
    assert!(before.contains("movable left reaches w1"), "{before}");
    std::fs::write(&cell, format!("// edited\n// again\n{source}")).expect("edit");
    let after = cellc(&["plan", artifact.to_str().unwrap()]);
    let after = String::from_utf8_lossy(&after.stderr).to_string();
    assert!(after.contains("error[R0004]"), "{after}");
    assert!(!after.contains("movable left reaches w1"), "{after}");
    assert!(
        after.contains("changed since the artifact was built"),
        "{after}"
    );
}

/// A closed standard output ends `cellc` quietly (SIGPIPE), not with a panic message.
#[test]
fn a_closed_pipe_ends_quietly() {
    // A graph far larger than a pipe's buffer.
    let mut text = String::from("cell wide {\n");
    for i in 0..300 {
        text.push_str(&format!("  workspace w{i}\n"));
    }
    let all: Vec<String> = (0..300).map(|i| format!("w{i}")).collect();
    text.push_str(&format!("  fixed table reaches {}\n", all.join(", ")));
    text.push_str(&format!("  movable left_arm reaches {}\n", all.join(", ")));
    text.push_str("  object o {\n    grasp g1 by table\n    grasp g2 by left_arm\n    transition g1 <-> g2\n  }\n}\n");
    let cell = temp_file("wide.cell", &text);
    let script = format!(
        "{} graph {} --object o | head -c 100 > /dev/null; echo \"${{PIPESTATUS[0]}}\"",
        env!("CARGO_BIN_EXE_cellc"),
        cell.display()
    );
    let out = Command::new("bash")
        .args(["-c", &script])
        .output()
        .expect("bash runs");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!stderr.contains("panicked"), "{stderr}");
    let status = String::from_utf8_lossy(&out.stdout).trim().to_string();
    // 141 = 128 + SIGPIPE, what any Unix tool gives.
    assert_eq!(status, "141", "{stderr}");
}

/// `cellc plan` with `--format json` writes JSON on standard output on every path: the
/// plan, or a diagnostics report in the schema of `cellc check --format json`.
#[test]
fn json_output_is_json_on_every_path() {
    let cases: &[&[&str]] = &[
        &["plan", "cells/fig3.cell", "--format", "json"],
        &[
            "plan",
            "cells/fig3.cell",
            "--format",
            "json",
            "--request",
            "nope",
        ],
        &["plan", "no/such/file.json", "--format", "json"],
        &[
            "plan",
            "tests/ui/artifact/E0503_truncated.json",
            "--format",
            "json",
        ],
        &[
            "plan",
            "tests/ui/plan/R0004_no_way_across.cell",
            "--format",
            "json",
        ],
        &[
            "plan",
            "cells/fig3.cell",
            "--format",
            "json",
            "--object",
            "cylinder",
            "--from",
            "tabel in w1",
            "--to",
            "table in w3",
        ],
        &[
            "plan",
            "cells/fig3.cell",
            "--format",
            "json",
            "--object",
            "cylinder",
            "--from",
            "table at (",
            "--to",
            "table in w3",
        ],
    ];
    for args in cases {
        let out = cellc(args);
        let stdout = String::from_utf8_lossy(&out.stdout);
        let parsed: Result<serde_json::Value, _> = serde_json::from_str(&stdout);
        assert!(parsed.is_ok(), "{args:?}: not JSON:\n{stdout}");
        if !out.status.success() {
            let report = parsed.expect("json");
            assert!(report["errors"].as_u64() >= Some(1), "{args:?}: {report}");
        }
    }
}

/// `HOLDER in WS` names a set of states (`cellc plan --help`: `HOLDER[.GRASP] in WS`): the
/// plan ends in the cheapest grasp of that hand there, instead of asking which grasp.
#[test]
fn a_goal_without_a_grasp_plans_to_the_cheapest_grasp() {
    let plan_to = |to: &str, json: bool| {
        let mut args = vec![
            "plan",
            "cells/vito.cell",
            "--object",
            "cylinder",
            "--from",
            "table at (0.45, 0.45, 1.0)",
            "--to",
            to,
            "--no-motions",
        ];
        if json {
            args.extend(["--format", "json"]);
        }
        cellc(&args)
    };
    let out = plan_to("left in ws_left_table", true);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    let plan: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON");
    let states = plan["plans"][0]["states"].as_array().expect("states");
    let last = states.last().expect("a goal state");
    assert_eq!(last["end_effector"], "left", "{plan}");
    assert_eq!(last["workspace"], "ws_left_table", "{plan}");
    // The left hand has more than one grasp of the cylinder there, so one was chosen.
    for grasp in ["top", "side"] {
        let to = format!("left.{grasp} in ws_left_table");
        assert!(plan_to(&to, false).status.success(), "{to}");
    }
}

/// `include "."` from a cell in the current folder names the folder, not the empty name.
#[test]
fn an_include_of_the_current_folder_says_it_is_a_folder() {
    let out = Command::new(env!("CARGO_BIN_EXE_cellc"))
        .args(["check", "include_dot.cell"])
        .current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/ui/cli/support"))
        .output()
        .expect("cellc runs");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        stderr.contains("cannot read `.`: it is a directory"),
        "{stderr}"
    );
}

/// A robot that does not load is reported once, where it is: the arms built on it are not
/// also called "not an arm" by every allowed contact that names their links.
#[test]
fn a_robot_that_does_not_load_is_not_reported_again_by_contacts() {
    let dir = std::env::temp_dir().join(format!("cellc-cascade-{}", std::process::id()));
    let robots = dir.join("robots");
    std::fs::create_dir_all(&robots).expect("temp folder");
    std::fs::copy("cells/two_pandas.cell", dir.join("two_pandas.cell")).expect("copied");
    for entry in std::fs::read_dir("cells/robots").expect("listable") {
        let path = entry.expect("entry").path();
        if path.extension().is_some_and(|e| e == "cell") {
            let text = std::fs::read_to_string(&path).expect("readable");
            let text = text.replace("at \"example-robot-data\"", "at \"nowhere\"");
            std::fs::write(robots.join(path.file_name().expect("name")), text).expect("written");
        }
    }
    let cell = dir.join("two_pandas.cell");
    let out = cellc(&["check", &cell.to_string_lossy(), "--format", "short"]);
    let stderr = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(stderr.contains("error[E0401]"), "{stderr}");
    assert!(!stderr.contains("is not an arm"), "{stderr}");
    // The workspaces `workspaces from reach` would have derived from the arms' reach are
    // not "unknown": the arms' robots are.
    assert!(!stderr.contains("E0101"), "{stderr}");
    assert!(
        stderr.contains("a `package` item declares `example-robot-data` at"),
        "{stderr}"
    );
}

/// A folder the user may not write in (EACCES) is E0505 with a non-zero exit, and the
/// previous output there is left as it was. Tests here may run as root, whom permissions
/// do not stop: then the command runs as `nobody` (through `setpriv`, util-linux).
#[test]
fn a_folder_that_may_not_be_written_is_e0505_and_keeps_the_previous_file() {
    use std::os::unix::fs::PermissionsExt;
    let dir = std::env::temp_dir().join(format!("cellc-eacces-{}", std::process::id()));
    let (inputs, outputs) = (dir.join("in"), dir.join("out"));
    std::fs::create_dir_all(&inputs).expect("temp folder");
    std::fs::create_dir_all(&outputs).expect("temp folder");
    let cell = inputs.join("fig3.cell");
    std::fs::copy("cells/fig3.cell", &cell).expect("copied");
    let target = outputs.join("fig3.cellg");
    std::fs::write(&target, "previous").expect("written");
    let mode = |path: &std::path::Path, mode: u32| {
        std::fs::set_permissions(path, std::fs::Permissions::from_mode(mode)).expect("chmod");
    };
    for (path, m) in [
        (&dir, 0o755),
        (&inputs, 0o755),
        (&cell, 0o644),
        (&target, 0o644),
    ] {
        mode(path, m);
    }
    mode(&outputs, 0o555);
    // SAFETY: geteuid has no preconditions and cannot fail.
    let root = unsafe { libc::geteuid() } == 0;
    let mut command = if root {
        // A copy of the binary `nobody` may run wherever the checkout is.
        let binary = dir.join("cellc");
        std::fs::copy(env!("CARGO_BIN_EXE_cellc"), &binary).expect("copied");
        mode(&binary, 0o755);
        let mut c = Command::new("setpriv");
        c.args(["--reuid=65534", "--regid=65534", "--clear-groups"])
            .arg(&binary);
        c
    } else {
        Command::new(env!("CARGO_BIN_EXE_cellc"))
    };
    let out = command
        .arg("build")
        .arg(&cell)
        .arg("-o")
        .arg(&target)
        .output()
        .expect("cellc runs");
    let stderr = String::from_utf8_lossy(&out.stderr).to_string();
    mode(&outputs, 0o755);
    let kept = std::fs::read_to_string(&target).expect("readable");
    let _ = std::fs::remove_dir_all(&dir);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("error[E0505]"), "{stderr}");
    assert!(stderr.contains("permission denied"), "{stderr}");
    assert_eq!(kept, "previous");
}
