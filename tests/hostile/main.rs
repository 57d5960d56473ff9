//! Hostile inputs, as a pull request or a damaged disk would bring them: each case builds
//! its files in a fresh folder, runs the `cellc` binary on them as a child process, and
//! states what must happen: the exit status, the code of the diagnostic, no panic, a wall
//! clock bound and a memory bound. The time bound is a wait with a deadline (the child is
//! killed past it), the memory bound an address-space limit set on the child
//! (`ulimit -v`), so a regression to quadratic time or memory fails a case instead of
//! hanging or killing CI. Texts that must never appear (secrets in a file that is not a
//! cell, raw escape sequences, a megabyte line) are checked in the output.
//!
//! Cases named after a code (`E0320_...`) are also that code's UI test: their output is
//! snapshotted, and `tests/ui/hostile/NAME.md` says what the input is.

mod cases;

use std::fs::File;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use cases::{cases, Expect};

/// The outcome of running a case's command line.
struct Outcome {
    exit: Option<i32>,
    elapsed: Duration,
    stdout: String,
    stderr: String,
}

/// Runs `cellc` in `folder` under an address-space limit, killing it past `seconds`.
fn run(folder: &Path, args: &[String], expect: &Expect) -> Result<Outcome, String> {
    let out = folder.join("stdout.txt");
    let err = folder.join("stderr.txt");
    let kib = expect.memory_mib * 1024;
    // Output goes to files, not pipes: a child that writes much never blocks on us.
    let mut child = Command::new("sh")
        .arg("-c")
        .arg(format!("ulimit -v {kib} && exec \"$0\" \"$@\""))
        .arg(env!("CARGO_BIN_EXE_cellc"))
        .args(args)
        .current_dir(folder)
        .env("RUST_BACKTRACE", "0")
        .stdin(Stdio::null())
        .stdout(File::create(&out).map_err(|e| e.to_string())?)
        .stderr(File::create(&err).map_err(|e| e.to_string())?)
        .spawn()
        .map_err(|e| format!("cannot start cellc: {e}"))?;
    let start = Instant::now();
    let deadline = Duration::from_secs(expect.seconds);
    let status = loop {
        if let Some(status) = child.try_wait().map_err(|e| e.to_string())? {
            break status;
        }
        if start.elapsed() > deadline {
            let _ = child.kill();
            let _ = child.wait();
            return Err(format!("still running after {} s: killed", expect.seconds));
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let read =
        |p: &PathBuf| String::from_utf8_lossy(&std::fs::read(p).unwrap_or_default()).into_owned();
    Ok(Outcome {
        exit: status.code(),
        elapsed: start.elapsed(),
        stdout: read(&out),
        stderr: read(&err),
    })
}

/// What is wrong with an outcome, if anything.
fn judge(outcome: &Outcome, expect: &Expect) -> Vec<String> {
    let mut wrong = Vec::new();
    let all = format!("{}{}", outcome.stdout, outcome.stderr);
    if outcome.exit != Some(expect.exit) {
        wrong.push(format!("exit {:?}, expected {}", outcome.exit, expect.exit));
    }
    if all.contains("panicked") || all.contains("memory allocation") {
        wrong.push("panicked or ran out of memory".into());
    }
    if let Some(code) = expect.code {
        let human = format!("error[{code}]");
        let short = format!("[{code}]:");
        let json = format!("\"code\": \"{code}\"");
        if !(all.contains(&human) || all.contains(&short) || all.contains(&json)) {
            wrong.push(format!("no {code}"));
        }
    }
    for text in expect.never {
        if all.contains(text) {
            wrong.push(format!("the output contains {text:?}"));
        }
    }
    if all.len() > expect.max_output_bytes {
        wrong.push(format!(
            "{} bytes of output, more than {}",
            all.len(),
            expect.max_output_bytes
        ));
    }
    wrong
}

#[test]
fn hostile_inputs_are_refused_in_bounded_time_and_memory() {
    let root = std::env::temp_dir().join(format!("cellc-hostile-{}", std::process::id()));
    let mut failures = Vec::new();
    for case in cases() {
        let folder = root.join(case.name);
        std::fs::create_dir_all(&folder).expect("case folder");
        let args = (case.setup)(&folder);
        match run(&folder, &args, &case.expect) {
            Err(why) => failures.push(format!("{}: {why}", case.name)),
            Ok(outcome) => {
                // Shown with `--nocapture`, to see how close a case runs to its bound.
                eprintln!(
                    "{}: {:?} of {} s",
                    case.name, outcome.elapsed, case.expect.seconds
                );
                for wrong in judge(&outcome, &case.expect) {
                    failures.push(format!(
                        "{}: {wrong} (after {:?})",
                        case.name, outcome.elapsed
                    ));
                }
                if case.name.starts_with('E') {
                    // With the other UI snapshots.
                    let mut settings = insta::Settings::clone_current();
                    settings.set_snapshot_path("../snapshots");
                    let _guard = settings.bind_to_scope();
                    insta::assert_snapshot!(
                        format!("hostile_{}", case.name),
                        format!(
                            "$ cellc {}\nexit: {:?}\n----- stdout -----\n{}----- stderr -----\n{}",
                            args.join(" "),
                            outcome.exit,
                            outcome.stdout,
                            outcome.stderr
                        )
                    );
                }
            }
        }
        let _ = std::fs::remove_dir_all(&folder);
    }
    let _ = std::fs::remove_dir_all(&root);
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// Every case named after a code says what its input is in `tests/ui/hostile/NAME.md`,
/// and every page there has its case: these are those codes' UI tests.
#[test]
fn coded_cases_are_described() {
    let named: Vec<String> = cases()
        .iter()
        .filter(|c| c.name.starts_with('E'))
        .map(|c| format!("{}.md", c.name))
        .collect();
    let folder = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/ui/hostile");
    let mut pages: Vec<String> = std::fs::read_dir(&folder)
        .expect("tests/ui/hostile exists")
        .filter_map(Result::ok)
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    pages.sort();
    let mut expected = named.clone();
    expected.sort();
    assert_eq!(pages, expected);
}

/// An artifact that records another number of joints than its URDF's chain has is refused
/// when the scene is loaded, not indexed out of step.
#[test]
fn an_artifact_with_the_wrong_joint_count_is_refused() {
    let path = "tests/ui/E0405_home_out_of_limits.cell";
    let text = std::fs::read_to_string(path).expect("readable");
    // The same cell with a home inside the limits.
    let fixed = text
        .replace("// expect: E0405\n", "")
        .replace(", lwr_a4_joint 150 deg", "");
    let files = cellc_compiler::MemoryFiles::new([
        ("pick.cell", fixed.as_str()),
        (
            "support/kuka_lwr4.urdf",
            std::fs::read_to_string("tests/ui/support/kuka_lwr4.urdf")
                .expect("readable")
                .as_str(),
        ),
    ]);
    let built = cellc_driver::build(
        &files,
        "pick.cell",
        &cellc_driver::BuildOptions::unverified(),
    );
    let mut artifact = built
        .artifact
        .unwrap_or_else(|| panic!("{:?}", built.diagnostics));
    artifact.robots[0].joints.pop();
    match cellc_runtime::scene::Scene::load(&artifact, &files) {
        Err(cellc_runtime::scene::SceneError::JointCount {
            recorded: 6,
            found: 7,
            ..
        }) => {}
        Err(other) => panic!("wrong error: {other}"),
        Ok(_) => panic!("a scene was built"),
    }
}
