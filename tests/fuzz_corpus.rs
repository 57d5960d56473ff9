//! Replays every committed fuzz input (`fuzz/seeds/TARGET/`, the minimised corpus
//! `fuzz/corpus/TARGET/`, and past findings `fuzz/artifacts/TARGET/`) through the body of
//! its fuzz target, so CI keeps every past finding fixed without running the fuzzer.

use std::path::Path;

fn replay(target: &str, body: fn(&[u8])) -> usize {
    let mut count = 0;
    for folder in ["seeds", "corpus", "artifacts"] {
        let dir = Path::new("fuzz").join(folder).join(target);
        let Ok(entries) = std::fs::read_dir(&dir) else {
            continue;
        };
        let mut paths: Vec<_> = entries.filter_map(Result::ok).map(|e| e.path()).collect();
        paths.sort();
        for path in paths {
            let data = std::fs::read(&path).expect("readable");
            let outcome = std::panic::catch_unwind(|| body(&data));
            assert!(outcome.is_ok(), "{target}: {} panics", path.display());
            count += 1;
        }
    }
    count
}

#[test]
fn parse_check_corpus() {
    assert!(replay("parse_check", cellc::fuzzing::parse_check) >= 10);
}

#[test]
fn format_corpus() {
    assert!(replay("format", cellc::fuzzing::format) >= 10);
}

#[test]
fn artifact_plan_corpus() {
    assert!(replay("artifact_plan", cellc::fuzzing::artifact_plan) >= 3);
}

#[test]
fn urdf_mesh_corpus() {
    assert!(replay("urdf_mesh", cellc::fuzzing::urdf_mesh) >= 3);
}

#[test]
fn world_document_corpus() {
    assert!(replay("world_document", cellc::fuzzing::world_document) >= 5);
}

#[test]
fn lsp_frames_corpus() {
    assert!(replay("lsp_frames", cellc::fuzzing::lsp_frames) >= 7);
}
