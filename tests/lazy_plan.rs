//! `cellc plan` on a sectioned binary reads the core and the requested object's nodes and
//! arcs, nothing else: damage to another object's sections, or to the requested object's
//! pruned arcs, does not stop a plan that does not need them, while every reader that
//! does need them (a whole load, the explanation of a failure) refuses them with their
//! code.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use cellc_runtime::{Cell, ObjectId};
use cellc_schema::partial::{Partial, Parts};
use cellc_schema::sections::{SectionKind, Sections};
use cellc_schema::{Artifact, Encoding, ReadError};

/// Two objects, each with its own graph; `part` has a resting pose nothing leads to, so
/// `stuck` is unreachable and its failure is explained.
const CELL: &str = "cell two_parts {
  workspace w0
  workspace w1
  adjacent w0 w1
  fixed bench0 reaches w0
  fixed bench1 reaches w1
  movable a0 reaches w0, w1
  object part {
    grasp r0 by bench0
    grasp r1 by bench1
    grasp lone by bench1
    grasp g by a0
    transition r0 <-> g
    transition r1 <-> g
  }
  object other {
    grasp r0 by bench0
    grasp r1 by bench1
    grasp g by a0
    transition r0 <-> g
    transition r1 <-> g
  }
  request across: part from bench0.r0 in w0 to bench1.r1 in w1
  request other_across: other from bench0.r0 in w0 to bench1.r1 in w1
  request stuck: part from bench0.r0 in w0 to bench1.lone in w1
}
";

fn cellc(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_cellc"))
        .args(args)
        .output()
        .expect("the cellc binary runs")
}

fn folder(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("cellc-lazy-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

/// The cell built as `cellc build --encoding bin` writes it, in a folder of its own.
fn built(name: &str) -> (PathBuf, Vec<u8>) {
    let dir = folder(name);
    let cell = dir.join("two_parts.cell");
    std::fs::write(&cell, CELL).expect("write the cell");
    let bin = dir.join("two_parts.bin");
    let out = cellc(&[
        "build",
        cell.to_str().unwrap(),
        "--encoding",
        "bin",
        "-o",
        bin.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let bytes = std::fs::read(&bin).expect("the artifact");
    (bin, bytes)
}

/// Where one section is in the file.
fn section(bytes: &[u8], kind: SectionKind, object: u32) -> (usize, usize) {
    let s = Sections::open(bytes).expect("opens");
    let row = s
        .table()
        .iter()
        .find(|r| r.kind == kind && r.object == object)
        .expect("the section");
    (row.offset, row.length)
}

/// Writes `bytes` with one bit of the given section flipped to a file next to `bin`.
fn damaged(bin: &Path, bytes: &[u8], kind: SectionKind, object: u32) -> PathBuf {
    let (offset, length) = section(bytes, kind, object);
    assert!(length > 0, "{kind:?} of {object} is empty");
    let mut b = bytes.to_vec();
    b[offset + length / 2] ^= 0x10;
    let path = bin.with_file_name(format!("damaged_{kind:?}_{object}.bin"));
    std::fs::write(&path, &b).expect("write");
    path
}

fn plan(path: &Path, request: &str) -> Output {
    cellc(&[
        "plan",
        path.to_str().unwrap(),
        "--request",
        request,
        "--format",
        "json",
    ])
}

fn text(out: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    )
}

#[test]
fn a_plan_does_not_read_another_objects_arcs() {
    let (bin, bytes) = built("other");
    let intact = plan(&bin, "across");
    assert!(intact.status.success(), "{}", text(&intact));
    let path = damaged(&bin, &bytes, SectionKind::Arcs, 1);
    // The request on `part` plans as before: `other`'s arcs are never read.
    let lazy = plan(&path, "across");
    assert!(lazy.status.success(), "{}", text(&lazy));
    assert_eq!(lazy.stdout, intact.stdout);
    // A request on `other` reads them and refuses them.
    let refused = plan(&path, "other_across");
    assert_eq!(refused.status.code(), Some(1), "{}", text(&refused));
    assert!(text(&refused).contains("E0503"), "{}", text(&refused));
    // A whole load refuses the file: `cellc info` and the library's reader.
    let info = cellc(&["info", path.to_str().unwrap()]);
    assert_eq!(info.status.code(), Some(1), "{}", text(&info));
    assert!(text(&info).contains("E0503"), "{}", text(&info));
    let damaged_bytes = std::fs::read(&path).expect("read");
    assert_eq!(
        Artifact::from_bytes(&damaged_bytes).map(drop),
        Err(ReadError::Damaged)
    );
    // In the library: the core and `part`'s graph read, `other`'s never.
    let sections = Sections::open(&damaged_bytes).expect("the table is intact");
    let cell = Cell::load_objects(
        &sections,
        &[ObjectId(0)],
        Parts::GRAPH,
        &cellc_driver::fs_files::FsFiles,
    )
    .expect("loads");
    assert_eq!(cell.parts(ObjectId(0)), Parts::GRAPH);
    assert_eq!(cell.parts(ObjectId(1)), Parts::NONE);
    assert!(cell.artifact().objects[1].graph.arcs.is_empty());
    let mut partial = Partial::open(&sections).expect("the core is intact");
    assert_eq!(
        partial.read(&sections, ObjectId(1), Parts::GRAPH),
        Err(ReadError::Damaged)
    );
    assert_eq!(partial.parts(ObjectId(1)), Parts::NONE);
}

#[test]
fn a_damaged_requested_section_is_refused_with_its_code() {
    let (bin, bytes) = built("requested");
    for kind in [SectionKind::Nodes, SectionKind::Arcs, SectionKind::Core] {
        let path = damaged(&bin, &bytes, kind, 0);
        let out = plan(&path, "across");
        assert_eq!(out.status.code(), Some(1), "{kind:?}: {}", text(&out));
        assert!(text(&out).contains("E0503"), "{kind:?}: {}", text(&out));
        assert!(!text(&out).contains("panicked"), "{}", text(&out));
    }
}

/// Rewrites one section and the checksums over it, as a forger would: the damage is
/// then found by validation, not by the checksum.
fn forged(bytes: &[u8], kind: SectionKind, object: u32, edit: impl Fn(&mut [u8])) -> Vec<u8> {
    let mut b = bytes.to_vec();
    let (offset, length) = section(bytes, kind, object);
    edit(&mut b[offset..offset + length]);
    let sum = xxhash_rust::xxh3::xxh3_64(&b[offset..offset + length]);
    let s = Sections::open(bytes).expect("opens");
    let row = s
        .table()
        .iter()
        .position(|r| r.kind == kind && r.object == object)
        .expect("row");
    let entry = 24 + row * 32;
    b[entry + 24..entry + 32].copy_from_slice(&sum.to_le_bytes());
    let count = s.table().len();
    let table_sum = xxhash_rust::xxh3::xxh3_64(&b[24..24 + count * 32]);
    b[16..24].copy_from_slice(&table_sum.to_le_bytes());
    b
}

#[test]
fn an_inconsistent_requested_section_is_refused_with_its_code() {
    let (bin, bytes) = built("inconsistent");
    // The first arc's head out of range, and a weight that is not a number.
    let head = forged(&bytes, SectionKind::Arcs, 0, |arcs| {
        arcs[4..8].copy_from_slice(&9999u32.to_le_bytes());
    });
    let weight = forged(&bytes, SectionKind::Arcs, 0, |arcs| {
        arcs[24..32].copy_from_slice(&f64::NAN.to_bits().to_le_bytes());
    });
    let node = forged(&bytes, SectionKind::Nodes, 0, |nodes| {
        nodes[8..12].copy_from_slice(&77u32.to_le_bytes());
    });
    for (what, b, path) in [
        (
            "head",
            head,
            "`objects[0].graph.arcs[0].to`: index 9999 out of range",
        ),
        (
            "weight",
            weight,
            "`objects[0].graph.arcs[0].weight`: NaN is not a finite number",
        ),
        (
            "node",
            node,
            "`objects[0].graph.nodes[0].workspace`: index 77 out of range",
        ),
    ] {
        let file = bin.with_file_name(format!("forged_{what}.bin"));
        std::fs::write(&file, &b).expect("write");
        let out = plan(&file, "across");
        assert_eq!(out.status.code(), Some(1), "{what}: {}", text(&out));
        assert!(text(&out).contains("E0504"), "{what}: {}", text(&out));
        assert!(text(&out).contains(path), "{what}: {}", text(&out));
        // The same finding as the whole validation's.
        let whole = Artifact::from_bytes(&b).map(drop).expect_err("refused");
        assert!(whole.to_string().contains(path), "{what}: {whole}");
        // Another object's request does not read the forged section.
        assert!(plan(&file, "other_across").status.success(), "{what}");
    }
}

#[test]
fn pruned_arcs_are_read_only_to_explain_a_failure() {
    let (bin, bytes) = built("pruned");
    // The pruned arcs of `part` (an empty list, one byte) damaged.
    let path = damaged(&bin, &bytes, SectionKind::Pruned, 0);
    let out = plan(&path, "across");
    assert!(out.status.success(), "{}", text(&out));
    let out = plan(&path, "stuck");
    assert_eq!(out.status.code(), Some(1), "{}", text(&out));
    assert!(text(&out).contains("E0503"), "{}", text(&out));
    // Intact, the failure is explained as from the JSON artifact.
    let json = bin.with_extension("json");
    let artifact = Artifact::from_bytes(&bytes).expect("reads").0;
    std::fs::write(&json, artifact.to_bytes(Encoding::Json)).expect("write");
    let from_bin = plan(&bin, "stuck");
    let from_json = plan(&json, "stuck");
    assert_eq!(from_bin.status.code(), Some(1), "{}", text(&from_bin));
    assert_eq!(text(&from_bin), text(&from_json));
}
