//! `cellc view` and `cellc graph --emit svg` without a browser: what the page's
//! document says (read back from the written HTML), that it follows the plan and the
//! graph, that the same input gives the same bytes, and that bad plan files are refused.

use std::path::{Path, PathBuf};
use std::process::Command;

fn cellc(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_cellc"))
        .args(args)
        .output()
        .expect("run cellc")
}

fn temp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("cellc-view-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir.join(name)
}

/// The page's JSON document, read back from its script element.
fn document(page: &Path) -> serde_json::Value {
    let html = std::fs::read_to_string(page).expect("page written");
    let start = html
        .find("<script id=\"cellc-data\" type=\"application/json\">")
        .expect("data element")
        + "<script id=\"cellc-data\" type=\"application/json\">".len();
    let end = start + html[start..].find("</script>").expect("end of data");
    serde_json::from_str(&html[start..end]).expect("the document is JSON")
}

fn view(args: &[&str], name: &str) -> serde_json::Value {
    let page = temp(name);
    let mut all = vec!["view"];
    all.extend_from_slice(args);
    all.extend_from_slice(&["-o", page.to_str().unwrap()]);
    let out = cellc(&all);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    document(&page)
}

#[test]
fn svg_draws_every_state_and_arc_pair() {
    let out = cellc(&[
        "graph",
        "cells/fig3.cell",
        "--object",
        "cylinder",
        "--emit",
        "svg",
    ]);
    assert!(out.status.success());
    let svg = String::from_utf8(out.stdout).unwrap();
    let json = cellc(&[
        "graph",
        "cells/fig3.cell",
        "--object",
        "cylinder",
        "--emit",
        "json",
    ]);
    let graph: serde_json::Value = serde_json::from_slice(&json.stdout).unwrap();
    let nodes = graph["nodes"].as_array().unwrap().len();
    assert_eq!(svg.matches("class=\"state\"").count(), nodes);
    // Arcs both ways are one line: as many lines as unordered pairs.
    let mut pairs: Vec<(u64, u64)> = graph["arcs"]
        .as_array()
        .unwrap()
        .iter()
        .map(|a| {
            let (f, t) = (a["from"].as_u64().unwrap(), a["to"].as_u64().unwrap());
            (f.min(t), f.max(t))
        })
        .collect();
    pairs.sort_unstable();
    pairs.dedup();
    assert_eq!(svg.matches("<path class=\"arc").count(), pairs.len());
    // One cluster per workspace, as in the DOT output.
    assert_eq!(svg.matches("class=\"cluster\"").count(), 3);
    assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
}

#[test]
fn an_abstract_plan_follows_its_steps_and_the_page_is_deterministic() {
    let a = view(&["cells/fig3.cell", "--request", "fig9"], "fig9-a.html");
    let b_page = temp("fig9-b.html");
    let out = cellc(&[
        "view",
        "cells/fig3.cell",
        "--request",
        "fig9",
        "-o",
        b_page.to_str().unwrap(),
    ]);
    assert!(out.status.success());
    assert_eq!(
        std::fs::read(temp("fig9-a.html")).unwrap(),
        std::fs::read(&b_page).unwrap(),
        "same cell, same page"
    );
    let steps = a["timeline"]["steps"].as_array().unwrap();
    assert_eq!(steps.len(), 6, "{steps:?}");
    assert_eq!(
        a["timeline"]["plans"][0]["holders"],
        serde_json::json!(["left_arm", "table", "right_arm"])
    );
    // The last step's state is the goal: right_arm holding g9 in w3.
    let last = steps.last().unwrap()["state"].as_u64().unwrap() as usize;
    let state = &a["graphs"][0]["states"][last];
    assert_eq!(
        (
            state["end_effector"].as_str(),
            state["grasp"].as_str(),
            state["workspace"].as_str()
        ),
        (Some("right_arm"), Some("g9"), Some("w3"))
    );
    // No geometry in an abstract cell.
    assert!(a["geometry"]["bodies"].as_array().unwrap().is_empty());
}

#[test]
fn the_object_ends_where_the_request_puts_it() {
    let doc = view(
        &["cells/vito.cell", "--request", "handoff_cylinder"],
        "handoff.html",
    );
    let bodies = doc["geometry"]["bodies"].as_array().unwrap();
    let cylinder = bodies
        .iter()
        .position(|b| b["name"] == "cylinder" && b["kind"] == "object")
        .expect("the cylinder is a body");
    let moving: Vec<u64> = doc["timeline"]["moving"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_u64().unwrap())
        .collect();
    let slot = moving.iter().position(|&b| b as usize == cylinder).unwrap();
    let frames = doc["timeline"]["frames"].as_array().unwrap();
    let at = |f: &serde_json::Value| -> [f64; 3] {
        let p = f["poses"][slot]
            .as_array()
            .expect("the cylinder is in the scene");
        [0, 1, 2].map(|i| p[i].as_f64().unwrap())
    };
    let (first, last) = (at(&frames[0]), at(frames.last().unwrap()));
    // `handoff_cylinder`: from (0.45, 0.45, 1.0) to (0.4, -0.3, 1.0) on the table.
    let near = |p: [f64; 3], q: [f64; 3]| (0..3).all(|i| (p[i] - q[i]).abs() < 0.01);
    assert!(near(first, [0.45, 0.45, 1.0]), "start {first:?}");
    assert!(near(last, [0.4, -0.3, 1.0]), "end {last:?}");
    // In between it is carried: somewhere it is well above the table.
    assert!(frames.iter().any(|f| at(f)[2] > 1.1), "never lifted");
    // Frames are in time order, 25 a second while the arms move.
    let times: Vec<f64> = frames.iter().map(|f| f["t"].as_f64().unwrap()).collect();
    assert!(times.windows(2).all(|w| w[0] <= w[1]));
    assert!(frames.len() as f64 > 20.0 * times.last().unwrap());
}

#[test]
fn plan_files_that_do_not_fit_are_refused() {
    let plan = cellc(&[
        "plan",
        "cells/fig3.cell",
        "--request",
        "fig8",
        "--format",
        "json",
    ]);
    assert!(plan.status.success());
    let good = temp("fig8.json");
    std::fs::write(&good, &plan.stdout).unwrap();
    let doc = view(
        &["cells/fig3.cell", "--plan", good.to_str().unwrap()],
        "fig8.html",
    );
    assert_eq!(doc["timeline"]["steps"].as_array().unwrap().len(), 4);
    let text = String::from_utf8(plan.stdout).unwrap();
    for (name, bad) in [
        ("grasp", text.replacen("\"g7\"", "\"g77\"", 1)),
        ("kind", text.replacen("\"plan\"", "\"run\"", 1)),
        ("command", text.replacen("\"ungrasp\"", "\"throw\"", 1)),
    ] {
        let path = temp(&format!("bad-{name}.json"));
        std::fs::write(&path, bad).unwrap();
        let page = temp(&format!("bad-{name}.html"));
        let out = cellc(&[
            "view",
            "cells/fig3.cell",
            "--plan",
            path.to_str().unwrap(),
            "-o",
            page.to_str().unwrap(),
        ]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(
            !out.status.success() && stderr.contains("error[R0011]"),
            "{name}: {stderr}"
        );
        assert!(!page.exists(), "{name}: a page was written");
    }
}

#[test]
fn joints_in_a_plan_file_are_checked_against_the_arm() {
    let plan = cellc(&[
        "plan",
        "cells/vito.cell",
        "--request",
        "trash",
        "--format",
        "json",
    ]);
    assert!(plan.status.success());
    let mut doc: serde_json::Value = serde_json::from_slice(&plan.stdout).unwrap();
    // One joint value too many in the first configuration given.
    let steps = doc["plans"][0]["steps"].as_array_mut().unwrap();
    let with = steps
        .iter_mut()
        .find(|s| !s["configurations"].as_array().unwrap().is_empty())
        .expect("a step with a configuration");
    with["configurations"][0]["positions"]
        .as_array_mut()
        .unwrap()
        .push(serde_json::json!(0.0));
    let path = temp("long.json");
    std::fs::write(&path, serde_json::to_string(&doc).unwrap()).unwrap();
    let page = temp("long.html");
    let out = cellc(&[
        "view",
        "cells/vito.cell",
        "--plan",
        path.to_str().unwrap(),
        "-o",
        page.to_str().unwrap(),
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("error[R0011]") && stderr.contains("joint values for an arm of 7 joints"),
        "{stderr}"
    );
}
