//! Fast Downward for the round trip: where its driver is, and an optimal solve.

use std::path::{Path, PathBuf};
use std::process::Command;

/// How to run the driver: the program and the arguments before Fast Downward's own.
fn driver() -> (PathBuf, Vec<PathBuf>) {
    let run_driver = |driver: PathBuf, python: PathBuf| {
        if driver.extension().is_some_and(|e| e == "py") {
            (python, vec![driver])
        } else {
            (driver, Vec::new())
        }
    };
    if let Some(driver) = std::env::var_os("CELLC_FAST_DOWNWARD") {
        let driver = PathBuf::from(driver);
        assert!(
            driver.is_file(),
            "CELLC_FAST_DOWNWARD is `{}`, which is no file",
            driver.display()
        );
        return run_driver(driver, PathBuf::from("python3"));
    }
    let venv = Path::new(env!("CARGO_MANIFEST_DIR")).join(".venv");
    let driver = std::fs::read_dir(venv.join("lib"))
        .ok()
        .and_then(|pythons| {
            pythons
                .filter_map(Result::ok)
                .map(|p| {
                    p.path()
                        .join("site-packages/up_fast_downward/downward/fast-downward.py")
                })
                .find(|d| d.is_file())
        });
    match driver {
        Some(driver) => run_driver(driver, venv.join("bin/python")),
        None => panic!(
            "Fast Downward is not installed, and the PDDL round trip needs it: run `python3 -m \
             venv .venv && .venv/bin/pip install up-fast-downward==1.0.0` in the repository \
             (as .ci/run does), or set CELLC_FAST_DOWNWARD to the path of a Fast Downward \
             driver (fast-downward.py)"
        ),
    }
}

/// Solves a problem optimally; returns the plan's actions (name and arguments) and cost.
pub fn solve(domain: &Path, problem: &Path, work: &Path) -> (Vec<Vec<String>>, u64) {
    let (program, prefix) = driver();
    let plan_file = work.join("plan.txt");
    let _ = std::fs::remove_file(&plan_file);
    let out = Command::new(&program)
        .args(&prefix)
        .arg("--plan-file")
        .arg(&plan_file)
        .arg(domain)
        .arg(problem)
        .args(["--search", "astar(lmcut())"])
        .current_dir(work)
        .output()
        .expect("Fast Downward runs");
    assert!(
        out.status.success(),
        "Fast Downward on {}: {}\n{}",
        problem.display(),
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    let text = std::fs::read_to_string(&plan_file).expect("a plan file");
    let mut steps = Vec::new();
    let mut cost = None;
    for line in text.lines() {
        if let Some(c) = line.strip_prefix("; cost = ") {
            cost = c.split_whitespace().next().and_then(|n| n.parse().ok());
        } else if let Some(step) = line.strip_prefix('(').and_then(|l| l.strip_suffix(')')) {
            steps.push(step.split_whitespace().map(str::to_string).collect());
        }
    }
    (steps, cost.expect("the plan states its cost"))
}
