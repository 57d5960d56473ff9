//! Replays every committed fuzz input through the body of its fuzz target, so CI keeps
//! every past finding fixed without running the fuzzer: the seeds `fuzz/seeds/TARGET/` and
//! the findings `fuzz/findings/TARGET/` (inputs that once crashed, hung or exhausted memory,
//! kept after their fix). The corpus the fuzzer grows from them, `fuzz/corpus/TARGET/`, is
//! not in git (`scripts/fuzz-corpus` regenerates it) and is not replayed here.
//!
//! Each target names how many seeds and findings it has: a missing folder or a deleted
//! input fails the test instead of quietly replaying less.

use std::path::Path;

/// One fuzz target's committed inputs: its name (the folder under `fuzz/seeds/` and
/// `fuzz/findings/`), its body, and how many seeds and findings it has today (lower
/// bounds; a target with no finding yet has no findings folder).
struct Target {
    name: &'static str,
    body: fn(&[u8]),
    seeds: usize,
    findings: usize,
}

/// Replays the files of `fuzz/FOLDER/TARGET/` (sorted, so a failure names the same file
/// every run) and returns how many there were; the folder must exist.
fn replay(folder: &str, target: &Target) -> usize {
    let dir = Path::new("fuzz").join(folder).join(target.name);
    let entries = std::fs::read_dir(&dir).unwrap_or_else(|e| {
        panic!(
            "{}: {} cannot be read ({e}); the committed fuzz inputs are missing",
            target.name,
            dir.display()
        )
    });
    let mut paths: Vec<_> = entries
        .map(|e| e.expect("a readable folder entry").path())
        .collect();
    paths.sort();
    for path in &paths {
        let data = std::fs::read(path).expect("readable");
        let outcome = std::panic::catch_unwind(|| (target.body)(&data));
        assert!(
            outcome.is_ok(),
            "{}: {} panics",
            target.name,
            path.display()
        );
    }
    paths.len()
}

fn replay_all(name: &str) {
    let target = TARGETS
        .iter()
        .find(|t| t.name == name)
        .expect("a target of TARGETS");
    let seeds = replay("seeds", target);
    assert!(
        seeds >= target.seeds,
        "{}: {seeds} seeds replayed, {} expected",
        target.name,
        target.seeds
    );
    let findings = if target.findings == 0 {
        0
    } else {
        replay("findings", target)
    };
    assert!(
        findings >= target.findings,
        "{}: {findings} findings replayed, {} expected",
        target.name,
        target.findings
    );
}

/// Every target of `fuzz/Cargo.toml`, with its input counts today.
const TARGETS: [Target; 6] = [
    Target {
        name: "parse_check",
        body: cellc::fuzzing::parse_check,
        seeds: 52,
        findings: 0,
    },
    Target {
        name: "format",
        body: cellc::fuzzing::format,
        seeds: 52,
        findings: 0,
    },
    Target {
        name: "artifact_plan",
        body: cellc::fuzzing::artifact_plan,
        seeds: 3,
        findings: 0,
    },
    Target {
        name: "urdf_mesh",
        body: cellc::fuzzing::urdf_mesh,
        seeds: 7,
        findings: 0,
    },
    Target {
        name: "world_document",
        body: cellc::fuzzing::world_document,
        seeds: 7,
        findings: 0,
    },
    Target {
        name: "lsp_frames",
        body: cellc::fuzzing::lsp_frames,
        seeds: 7,
        findings: 0,
    },
];

/// `fuzz/findings/` exists (its README says how a finding gets there), and each folder in
/// it belongs to a target counted with findings, so no committed finding goes unreplayed.
/// The targets are those of `fuzz/Cargo.toml`, so a new target cannot go unreplayed either.
#[test]
fn every_target_and_findings_folder_is_replayed() {
    let entries = std::fs::read_dir("fuzz/findings").expect("fuzz/findings/ exists");
    for entry in entries {
        let path = entry.expect("a readable folder entry").path();
        if !path.is_dir() {
            continue;
        }
        let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("");
        assert!(
            TARGETS.iter().any(|t| t.name == name && t.findings > 0),
            "{} holds findings that no test replays: count them in TARGETS",
            path.display()
        );
    }
    let manifest = std::fs::read_to_string("fuzz/Cargo.toml").expect("fuzz/Cargo.toml");
    let mut bins: Vec<&str> = manifest
        .lines()
        .filter_map(|l| l.strip_prefix("name = \""))
        .filter_map(|l| l.strip_suffix('"'))
        .filter(|n| *n != "cellc-fuzz")
        .collect();
    let mut names: Vec<&str> = TARGETS.iter().map(|t| t.name).collect();
    names.sort_unstable();
    bins.sort_unstable();
    assert_eq!(names, bins, "the fuzz targets of fuzz/Cargo.toml");
}

#[test]
fn parse_check_inputs() {
    replay_all("parse_check");
}

#[test]
fn format_inputs() {
    replay_all("format");
}

#[test]
fn artifact_plan_inputs() {
    replay_all("artifact_plan");
}

#[test]
fn urdf_mesh_inputs() {
    replay_all("urdf_mesh");
}

#[test]
fn world_document_inputs() {
    replay_all("world_document");
}

#[test]
fn lsp_frames_inputs() {
    replay_all("lsp_frames");
}
