//! `cellc view` in a real browser: pages for every shipped cell, request and task (and a
//! plan file, and an unreachable request) opened in headless Chromium by
//! `tests/browser/view_test.mjs` (playwright-core, pinned in `tests/browser/package.json`).
//! Each page must load with no console error and no network request, get a WebGL context
//! (SwiftShader), draw a scene that is not blank, show a robot link, a surface and the
//! object where the page projects them, and (with a plan) show the arm elsewhere at two
//! times. The screenshots of the README and the tutorial (`docs/images/`) are taken here.
//!
//! Needs Chromium (`apt-get install -y chromium`, `/usr/bin/chromium`, or `CHROMIUM=path`)
//! and the test's npm package (`npm ci --prefix tests/browser`); `.ci/run` installs both.

use std::path::{Path, PathBuf};
use std::process::Command;

fn cellc(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_cellc"))
        .args(args)
        .output()
        .expect("run cellc")
}

fn ok(args: &[&str]) {
    let out = cellc(args);
    assert!(
        out.status.success(),
        "cellc {args:?} failed:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// Names declared by lines `KEYWORD NAME` (`request NAME:`, `task NAME {`) of a cell.
fn declared(text: &str, keyword: &str) -> Vec<String> {
    text.lines()
        .filter_map(|l| l.trim().strip_prefix(keyword)?.strip_prefix(' '))
        .filter_map(|rest| {
            let name: String = rest
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_')
                .collect();
            (!name.is_empty()).then_some(name)
        })
        .collect()
}

struct Page {
    page: PathBuf,
    screenshot: Option<&'static str>,
    animated: bool,
    abstract_cell: bool,
    object: Option<String>,
}

/// The object a request moves (`request NAME: OBJECT from ...`).
fn request_object(text: &str, request: &str) -> Option<String> {
    let line = text
        .lines()
        .find(|l| l.trim().starts_with(&format!("request {request}:")))?;
    let after = line.split_once(':')?.1.trim();
    Some(after.split_whitespace().next()?.to_string())
}

#[test]
fn view_pages_in_chromium() {
    let chromium = std::env::var("CHROMIUM").unwrap_or_else(|_| "/usr/bin/chromium".into());
    assert!(
        Path::new(&chromium).exists(),
        "the browser test needs Chromium at {chromium}: install it with `apt-get install -y chromium` (or set CHROMIUM)"
    );
    assert!(
        Path::new("tests/browser/node_modules/playwright-core").exists(),
        "the browser test needs its npm package: run `npm ci --prefix tests/browser`"
    );
    let dir = std::env::temp_dir().join(format!("cellc-view-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let shots: &[(&str, &str, &str)] = &[
        (
            "vito",
            "handoff_cylinder",
            "docs/images/view_vito_handoff.png",
        ),
        (
            "two_pandas",
            "handoff",
            "docs/images/view_two_pandas_handoff.png",
        ),
    ];
    let mut pages = Vec::new();
    let mut cells: Vec<PathBuf> = std::fs::read_dir("cells")
        .expect("cells")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "cell"))
        .collect();
    cells.sort();
    for cell in &cells {
        let name = cell.file_stem().unwrap().to_string_lossy().to_string();
        let text = std::fs::read_to_string(cell).expect("cell");
        let abstract_cell = !text.lines().any(|l| l.trim_start().starts_with("arm "));
        // Built once, so each page is planned without verifying the cell again.
        let artifact = dir.join(format!("{name}.artifact.json"));
        ok(&[
            "build",
            cell.to_str().unwrap(),
            "-o",
            artifact.to_str().unwrap(),
        ]);
        let art = artifact.to_str().unwrap();
        let page = dir.join(format!("{name}.html"));
        ok(&["view", art, "-o", page.to_str().unwrap()]);
        pages.push(Page {
            page,
            screenshot: None,
            animated: false,
            abstract_cell,
            object: None,
        });
        for request in declared(&text, "request") {
            let page = dir.join(format!("{name}-{request}.html"));
            ok(&[
                "view",
                art,
                "--request",
                &request,
                "-o",
                page.to_str().unwrap(),
            ]);
            let screenshot = shots
                .iter()
                .find(|(c, r, _)| *c == name && *r == request)
                .map(|s| s.2);
            pages.push(Page {
                page,
                screenshot,
                animated: !abstract_cell,
                abstract_cell,
                object: request_object(&text, &request),
            });
        }
        for task in declared(&text, "task") {
            let page = dir.join(format!("{name}-task-{task}.html"));
            ok(&["view", art, "--task", &task, "-o", page.to_str().unwrap()]);
            pages.push(Page {
                page,
                screenshot: None,
                animated: true,
                abstract_cell,
                object: None,
            });
        }
    }
    // A plan document written by `cellc plan --format json`, shown without planning.
    let vito = dir.join("vito.artifact.json");
    let out = cellc(&[
        "plan",
        vito.to_str().unwrap(),
        "--request",
        "trash",
        "--format",
        "json",
    ]);
    assert!(out.status.success(), "plan trash");
    let plan = dir.join("trash.json");
    std::fs::write(&plan, &out.stdout).expect("plan file");
    let page = dir.join("vito-plan-file.html");
    ok(&[
        "view",
        vito.to_str().unwrap(),
        "--plan",
        plan.to_str().unwrap(),
        "-o",
        page.to_str().unwrap(),
    ]);
    pages.push(Page {
        page,
        screenshot: None,
        animated: true,
        abstract_cell: false,
        object: Some("ball".into()),
    });
    // An unreachable request: the page shows the sides and the cut.
    let page = dir.join("unreachable.html");
    ok(&[
        "view",
        "tests/ui/plan/R0004_reach_box_too_small.cell",
        "--request",
        "handoff",
        "-o",
        page.to_str().unwrap(),
    ]);
    let html = std::fs::read_to_string(&page).expect("page");
    assert!(
        html.contains("\"start_side\":[") && html.contains("\"cut\":[\""),
        "no explanation in the page"
    );
    pages.push(Page {
        page,
        screenshot: Some("docs/images/view_unreachable.png"),
        animated: false,
        abstract_cell: false,
        object: Some("cylinder".into()),
    });

    let list: Vec<serde_json::Value> = pages
        .iter()
        .map(|p| {
            serde_json::json!({
                "page": p.page.canonicalize().expect("page path"),
                "screenshot": p.screenshot.map(|s| std::env::current_dir().unwrap().join(s)),
                "animated": p.animated,
                "abstract": p.abstract_cell,
                "object": p.object,
            })
        })
        .collect();
    let spec = dir.join("pages.json");
    std::fs::write(&spec, serde_json::to_string(&list).unwrap()).expect("spec");
    let run = Command::new("node")
        .arg("tests/browser/view_test.mjs")
        .arg(&spec)
        .env("CHROMIUM", &chromium)
        .output()
        .expect("run node (the browser test needs Node.js)");
    let stdout = String::from_utf8_lossy(&run.stdout);
    let mut failures = Vec::new();
    let mut seen = 0;
    for line in stdout.lines() {
        let Ok(result) = serde_json::from_str::<serde_json::Value>(line) else {
            continue;
        };
        seen += 1;
        let problems = result["problems"].as_array().cloned().unwrap_or_default();
        if !problems.is_empty() {
            failures.push(format!("{}: {problems:?}", result["page"]));
        }
    }
    assert_eq!(
        seen,
        pages.len(),
        "the browser script checked {seen} of {} pages:\n{stdout}\n{}",
        pages.len(),
        String::from_utf8_lossy(&run.stderr)
    );
    assert!(
        failures.is_empty(),
        "pages failed:\n{}",
        failures.join("\n")
    );
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let _ = std::fs::remove_dir_all(&dir);
}
