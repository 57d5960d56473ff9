//! The command line's shared surface, the same in every subcommand: the positional
//! argument is `INPUT`, `--format human|short|json` says how diagnostics are written,
//! `--color auto|always|never` is one global flag that `NO_COLOR` and `CLICOLOR_FORCE`
//! inform, and a build's artifact encoding is `--encoding`.

use std::path::PathBuf;
use std::process::{Command, Output};

/// A cell with one error (E0101), and one that plans in five steps without arms.
const BAD_CELL: &str = "tests/ui/E0101_unknown_grasp.cell";
const PICK: &str = "tests/ui/cli/support/pick.cell";
/// A cell with a syntax error, which `fmt` reports and never rewrites.
const BAD_SYNTAX: &str = "tests/ui/E0001_missing_reaches.cell";

/// `cellc ARGS` from the repository root, with the colour variables of the test's own
/// environment cleared and `env` set.
fn cellc_with(env: &[(&str, &str)], args: &[&str]) -> Output {
    let mut command = Command::new(env!("CARGO_BIN_EXE_cellc"));
    for name in ["NO_COLOR", "CLICOLOR", "CLICOLOR_FORCE"] {
        command.env_remove(name);
    }
    command
        .envs(env.iter().copied())
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("the cellc binary runs")
}

fn cellc(args: &[&str]) -> Output {
    cellc_with(&[], args)
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

fn folder(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("cellc-surface-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

/// Every subcommand that reads a file calls it `INPUT` in its usage line.
#[test]
fn the_positional_argument_is_input_everywhere() {
    let commands: &[&[&str]] = &[
        &["check"],
        &["fmt"],
        &["build"],
        &["info"],
        &["graph"],
        &["view"],
        &["plan"],
        &["run"],
        &["serve"],
        &["import", "dualmanip"],
        &["export", "pddl"],
    ];
    for command in commands {
        let mut args = command.to_vec();
        args.push("--help");
        let out = cellc(&args);
        assert_eq!(out.status.code(), Some(0), "{command:?}");
        let help = text(&out.stdout);
        let usage = help
            .lines()
            .find(|l| l.starts_with("Usage:"))
            .unwrap_or_else(|| panic!("{command:?}: no usage line in\n{help}"));
        assert!(usage.contains("<INPUT>"), "{command:?}: {usage}");
        for old in ["<CELL>", "<FILE>", "<FILES>", "<DB>"] {
            assert!(!help.contains(old), "{command:?} still says {old}");
        }
    }
}

/// `--format` takes `human`, `short` or `json` in every command that has it, and nothing
/// else (a build's `bin` is its `--encoding`).
#[test]
fn format_is_human_short_or_json_everywhere() {
    let commands: &[&[&str]] = &[
        &["check", BAD_CELL],
        &["build", BAD_CELL],
        &["plan", PICK],
        &["run", PICK],
        &["import", "dualmanip", "no.db", "-o", "no.cell"],
    ];
    for command in commands {
        for wrong in ["bin", "dot", "xml"] {
            let mut args = command.to_vec();
            args.extend(["--format", wrong]);
            let out = cellc(&args);
            assert_eq!(out.status.code(), Some(2), "{args:?}");
            let stderr = text(&out.stderr);
            assert!(
                stderr.contains("[possible values: human, short, json]"),
                "{args:?}: {stderr}"
            );
        }
    }
    let out = cellc(&["graph", PICK, "--object", "cylinder", "--format", "svg"]);
    assert_eq!(out.status.code(), Some(2), "graph's output is `--emit`");
}

/// `build --format json` writes exactly one JSON report on standard output whatever
/// happens: built, not built, or built and not writable.
#[test]
fn build_writes_one_json_report_on_every_path() {
    let dir = folder("json");
    let artifact = dir.join("pick.artifact.json");
    let missing = dir.join("no/such/folder/pick.artifact.json");
    let cases: [(&[&str], i32, &str); 3] = [
        (&[PICK, "-o", artifact.to_str().unwrap()], 0, ""),
        (&[BAD_CELL], 1, "E0101"),
        (&[PICK, "-o", missing.to_str().unwrap()], 1, "E0505"),
    ];
    for (args, status, code) in cases {
        let mut all = vec!["build", "--format", "json"];
        all.extend(args);
        let out = cellc(&all);
        assert_eq!(out.status.code(), Some(status), "{all:?}");
        let stdout = text(&out.stdout);
        let report: serde_json::Value =
            serde_json::from_str(&stdout).unwrap_or_else(|e| panic!("{all:?}: {e}\n{stdout}"));
        let codes: Vec<&str> = report["diagnostics"]
            .as_array()
            .expect("diagnostics")
            .iter()
            .filter_map(|d| d["code"].as_str())
            .collect();
        if code.is_empty() {
            assert_eq!(report["errors"], 0, "{all:?}: {report}");
        } else {
            assert_eq!(codes, [code], "{all:?}: {report}");
        }
    }
    assert!(artifact.exists(), "the first build wrote its artifact");
    assert!(!missing.exists());
}

/// `--format short` puts one line per diagnostic on standard output, as `check` does.
#[test]
fn build_short_lines_are_checks_short_lines() {
    let build = cellc(&["build", BAD_CELL, "--format", "short"]);
    let check = cellc(&["check", BAD_CELL, "--format", "short"]);
    assert_eq!(build.status.code(), Some(1));
    let lines = text(&build.stdout);
    assert!(lines.contains(": error[E0101]: "), "{lines}");
    assert_eq!(lines, text(&check.stdout));
}

/// The explanation is text on standard output, which the machine forms keep for
/// diagnostics: asking for both is a usage error, and nothing is built.
#[test]
fn build_explain_with_a_machine_format_is_a_usage_error() {
    let dir = folder("explain");
    let artifact = dir.join("pick.json");
    for format in ["short", "json"] {
        let out = cellc(&[
            "build",
            PICK,
            "--explain",
            "--format",
            format,
            "-o",
            artifact.to_str().unwrap(),
        ]);
        assert_eq!(out.status.code(), Some(2), "{format}");
        assert!(text(&out.stderr).contains("Usage: cellc build"), "{format}");
        assert!(!artifact.exists(), "{format}: built anyway");
    }
}

/// `--encoding bin` writes the binary artifact (the default name says so), `json` the
/// JSON one; both plan the same.
#[test]
fn build_encoding_chooses_the_artifact_encoding() {
    let dir = folder("encoding");
    let cell = dir.join("pick.cell");
    std::fs::copy(PICK, &cell).expect("copy the cell");
    let cell = cell.to_str().unwrap();
    for (encoding, name) in [("bin", "pick.artifact.bin"), ("json", "pick.artifact.json")] {
        let out = cellc(&["build", cell, "--encoding", encoding]);
        assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
        let bytes = std::fs::read(dir.join(name)).expect("the default output");
        assert_eq!(
            bytes.starts_with(cellc_schema::MAGIC),
            encoding == "bin",
            "{encoding}"
        );
    }
    let plan = |name: &str| {
        let path = dir.join(name);
        text(&cellc(&["plan", path.to_str().unwrap(), "--format", "short"]).stdout)
    };
    assert_eq!(plan("pick.artifact.bin"), plan("pick.artifact.json"));
}

/// `plan --format short`: a headline per plan, then one line per step, every line naming
/// the plan; as many step lines as the plan document has steps.
#[test]
fn plan_short_is_one_line_per_step() {
    let short = cellc(&["plan", "cells/fig3.cell", "--format", "short"]);
    assert_eq!(short.status.code(), Some(0));
    let short = text(&short.stdout);
    let json = text(&cellc(&["plan", "cells/fig3.cell", "--format", "json"]).stdout);
    let document: serde_json::Value = serde_json::from_str(&json).expect("a plan document");
    let plan = &document["plans"][0];
    let name = plan["request"].as_str().expect("a request name");
    let steps = plan["steps"].as_array().expect("steps").len();
    assert!(steps > 0);
    let lines: Vec<&str> = short.lines().collect();
    assert_eq!(lines.len(), steps + 1, "{short}");
    assert!(
        lines[0].starts_with(&format!("plan `{name}` for ")),
        "{short}"
    );
    for (i, line) in lines[1..].iter().enumerate() {
        assert!(
            line.starts_with(&format!("plan `{name}` step {}: ", i + 1)),
            "{short}"
        );
    }
}

/// `run --format short` and an injected failure: the failed step is in the simulation
/// lines, the replan is named as one, and the run ends with its `done` line.
#[test]
fn run_short_shows_the_failure_the_replan_and_the_outcome() {
    let out = cellc(&["run", PICK, "--fail-at", "3", "--format", "short"]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let stdout = text(&out.stdout);
    assert!(stdout.lines().all(|l| l.starts_with("plan `")), "{stdout}");
    assert!(
        stdout.contains("simulation: step 3: motion failed (injected)"),
        "{stdout}"
    );
    assert!(stdout.contains(", replan 1` for `cylinder`"), "{stdout}");
    assert!(
        stdout
            .lines()
            .last()
            .is_some_and(|l| l.contains("` done: `cylinder` held by")),
        "{stdout}"
    );
}

/// `--fail-at` from 1 to the plan's last step is taken; 0 and past the end are E0509
/// usage errors, and nothing of the run is printed.
#[test]
fn fail_at_is_checked_against_the_plan() {
    let steps = 5;
    let last = cellc(&["run", PICK, "--fail-at", &steps.to_string()]);
    assert_eq!(last.status.code(), Some(0), "{}", text(&last.stderr));
    assert!(text(&last.stdout).contains(&format!("step {steps}: motion failed (injected)")));
    for refused in ["0", &(steps + 1).to_string(), "1000000"] {
        for format in ["human", "short", "json"] {
            let out = cellc(&["run", PICK, "--fail-at", refused, "--format", format]);
            assert_eq!(out.status.code(), Some(2), "{refused} {format}");
            let all = text(&out.stdout) + &text(&out.stderr);
            assert!(all.contains("E0509"), "{refused} {format}: {all}");
            assert!(!all.contains("simulation"), "{refused} {format}: {all}");
            if format == "json" {
                let report: serde_json::Value =
                    serde_json::from_str(&text(&out.stdout)).expect("a JSON report");
                assert_eq!(report["errors"], 1);
            }
        }
    }
}

/// `--color` is one global flag: before or after the subcommand, in every command that
/// reports diagnostics; `always` colours even with `NO_COLOR`, `never` stays plain even
/// with `CLICOLOR_FORCE`, and `auto` (not a terminal here) follows the two variables.
#[test]
fn color_is_global_and_follows_no_color() {
    let escape = |out: &Output| text(&out.stderr).contains('\u{1b}');
    let commands: &[&[&str]] = &[
        &["check", BAD_CELL],
        &["build", BAD_CELL],
        &["info", BAD_CELL],
        &["graph", BAD_CELL, "--object", "cylinder"],
        &["plan", BAD_CELL],
        &["run", BAD_CELL],
        &["explain", "E9999"],
        &["fmt", "--check", BAD_SYNTAX],
    ];
    for command in commands {
        let mut after = command.to_vec();
        after.extend(["--color", "always"]);
        let mut before = vec!["--color", "always"];
        before.extend(command.iter());
        assert!(escape(&cellc(&after)), "{after:?}");
        assert!(
            escape(&cellc_with(&[("NO_COLOR", "1")], &before)),
            "{before:?}"
        );
        let mut never = command.to_vec();
        never.extend(["--color", "never"]);
        assert!(
            !escape(&cellc_with(&[("CLICOLOR_FORCE", "1")], &never)),
            "{never:?}"
        );
        assert!(
            !escape(&cellc(command)),
            "{command:?}: auto, not a terminal"
        );
        assert!(
            escape(&cellc_with(&[("CLICOLOR_FORCE", "1")], command)),
            "{command:?}"
        );
        let both = [("CLICOLOR_FORCE", "1"), ("NO_COLOR", "1")];
        assert!(
            !escape(&cellc_with(&both, command)),
            "{command:?}: NO_COLOR wins"
        );
        // An empty NO_COLOR is not set (no-color.org).
        let empty = [("CLICOLOR_FORCE", "1"), ("NO_COLOR", "")];
        assert!(
            escape(&cellc_with(&empty, command)),
            "{command:?}: NO_COLOR empty"
        );
    }
}
