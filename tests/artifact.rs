//! The artifact: deterministic bytes, both encodings carry the same value, damaged files
//! are refused with coded diagnostics (never a panic), and arcs point back at the lines
//! that made them.

use cellc_driver::fs_files::FsFiles;
use cellc_driver::BuildOptions;
use cellc_schema::{ArcKind, Artifact, Encoding, ReadError};

fn build(path: &str) -> Artifact {
    cellc_driver::build(&FsFiles, path, &BuildOptions::unverified())
        .artifact
        .unwrap_or_else(|| panic!("{path} has errors"))
}

#[test]
fn same_cell_same_bytes() {
    for cell in ["cells/fig3.cell", "cells/vito.cell"] {
        for encoding in [Encoding::Json, Encoding::Binary] {
            assert_eq!(
                build(cell).to_bytes(encoding),
                build(cell).to_bytes(encoding),
                "{cell}"
            );
        }
    }
}

#[test]
fn both_encodings_round_trip() {
    for cell in ["cells/fig3.cell", "cells/vito.cell"] {
        let artifact = build(cell);
        for encoding in [Encoding::Json, Encoding::Binary] {
            let (back, found) =
                Artifact::from_bytes(&artifact.to_bytes(encoding)).expect("decodes");
            assert_eq!(found, encoding);
            assert_eq!(back, artifact);
        }
    }
}

#[test]
fn every_truncation_is_refused_without_panic() {
    let artifact = build("cells/fig3.cell");
    for encoding in [Encoding::Json, Encoding::Binary] {
        let bytes = artifact.to_bytes(encoding);
        // The JSON artifact ends with a newline, which a reader may do without.
        let whole = if encoding == Encoding::Json {
            bytes.len() - 1
        } else {
            bytes.len()
        };
        for cut in 0..whole {
            let result = Artifact::from_bytes(&bytes[..cut]);
            assert!(
                result.is_err(),
                "{encoding:?} cut at {cut} of {} decoded",
                bytes.len()
            );
        }
    }
}

/// Every single-bit flip of an artifact, in either encoding, is refused: the checksum
/// covers every byte of the content, and the header is checked on its own.
#[test]
fn every_bit_flip_is_refused() {
    let artifact = build("cells/fig3.cell");
    for encoding in [Encoding::Json, Encoding::Binary] {
        let bytes = artifact.to_bytes(encoding);
        let mut accepted = Vec::new();
        // Every bit of the binary form; every bit of every 7th byte of the larger JSON.
        let step = if encoding == Encoding::Json { 7 } else { 1 };
        for i in (0..bytes.len()).step_by(step) {
            for bit in 0..8 {
                let mut flipped = bytes.clone();
                flipped[i] ^= 1 << bit;
                if Artifact::from_bytes(&flipped).is_ok() {
                    accepted.push((i, bit));
                }
            }
        }
        assert!(
            accepted.is_empty(),
            "{encoding:?}: flips accepted at {accepted:?}"
        );
    }
}

/// A JSON artifact whose content was edited and whose checksum was recomputed (what an
/// attacker would do) is refused by validation, one class of damage at a time.
#[test]
fn inconsistent_artifacts_with_valid_checksums_are_refused() {
    let base = build("cells/vito.cell");
    type Damage = Box<dyn Fn(&mut Artifact)>;
    let cases: Vec<(&str, Damage)> = vec![
        (
            "arc to a node that does not exist",
            Box::new(|a| a.objects[0].graph.arcs[0].to = 10_000),
        ),
        (
            "negative cylinder height",
            Box::new(|a| {
                a.objects[0].shape = Some(cellc_schema::Shape::Cylinder {
                    radius: 0.03,
                    height: -0.1,
                })
            }),
        ),
        (
            "NaN in a grasp pose",
            Box::new(|a| {
                a.objects[0].grasps[0]
                    .pose
                    .as_mut()
                    .expect("posed")
                    .translation[0] = f64::NAN
            }),
        ),
        (
            "home of the wrong length",
            Box::new(|a| {
                for e in &mut a.end_effectors {
                    if let cellc_schema::Body::Arm { home, .. } = &mut e.body {
                        home.pop();
                    }
                }
            }),
        ),
        (
            "limits in the wrong order",
            Box::new(|a| {
                let j = &mut a.robots[0].joints[0];
                j.lower = Some(1.0);
                j.upper = Some(-1.0);
            }),
        ),
        (
            "a negative weight",
            Box::new(|a| a.objects[0].graph.arcs[0].weight = -1.0),
        ),
        (
            "a reach into no workspace",
            Box::new(|a| a.end_effectors[0].reaches.push(999)),
        ),
        (
            "a span past the table",
            Box::new(|a| a.objects[0].span = 1 << 30),
        ),
    ];
    for (what, damage) in cases {
        let mut a = base.clone();
        damage(&mut a);
        // NaN cannot be written as JSON: the binary form carries it.
        for encoding in [Encoding::Binary, Encoding::Json] {
            let result = Artifact::from_bytes(&a.to_bytes(encoding));
            assert!(
                matches!(
                    result,
                    Err(ReadError::Invalid(_)) | Err(ReadError::Corrupt { .. })
                ),
                "{what} ({encoding:?}): {result:?}"
            );
        }
        assert!(
            matches!(
                Artifact::from_bytes(&a.to_bytes(Encoding::Binary)),
                Err(ReadError::Invalid(_))
            ),
            "{what}"
        );
    }
}

#[test]
fn other_versions_and_other_files_are_told_apart() {
    let mut artifact = build("cells/fig3.cell");
    artifact.format_version = 999;
    for encoding in [Encoding::Json, Encoding::Binary] {
        let mut bytes = artifact.to_bytes(encoding);
        if encoding == Encoding::Binary {
            bytes[8..12].copy_from_slice(&999u32.to_le_bytes());
        }
        assert!(matches!(
            Artifact::from_bytes(&bytes),
            Err(ReadError::WrongVersion { found: 999, .. })
        ));
    }
    assert_eq!(
        Artifact::from_bytes(b"cell x {}"),
        Err(ReadError::NotAnArtifact)
    );
    assert_eq!(Artifact::from_bytes(b""), Err(ReadError::NotAnArtifact));
}

#[test]
fn fig3_artifact_has_the_fig6_graph_with_provenance() {
    let artifact = build("cells/fig3.cell");
    let source = std::fs::read_to_string("cells/fig3.cell").expect("fig3 exists");
    let graph = &artifact.objects[0].graph;
    assert_eq!(
        (graph.nodes.len(), graph.n_moves(), graph.n_transitions()),
        (21, 12, 52)
    );
    for arc in &graph.arcs {
        let span = artifact.spans[arc.source as usize];
        let text = &source[span.start as usize..span.end as usize];
        match arc.kind {
            ArcKind::Transition => assert!(text.starts_with("transition"), "{text}"),
            ArcKind::Move => {
                assert!(text.starts_with("grasp"), "{text}");
                let via = artifact.spans[arc.via.expect("fig3 declares adjacency") as usize];
                assert!(source[via.start as usize..via.end as usize].starts_with("adjacent"));
            }
        }
        // Moves keep the grasp and change the workspace; transitions the reverse.
        let (a, b) = (graph.nodes[arc.from as usize], graph.nodes[arc.to as usize]);
        match arc.kind {
            ArcKind::Move => assert!(
                a.grasp == b.grasp
                    && a.end_effector == b.end_effector
                    && a.workspace != b.workspace
            ),
            ArcKind::Transition => assert!(a.grasp != b.grasp && a.workspace == b.workspace),
        }
    }
    assert_eq!(artifact.sources.len(), 1);
    assert_eq!(artifact.sources[0].sha256.len(), 64);
}

#[test]
fn vito_artifact_hashes_its_urdf() {
    let artifact = build("cells/vito.cell");
    let urdf = std::fs::read("cells/robots/kuka_lwr4.urdf").expect("urdf exists");
    assert_eq!(
        artifact.robots[0].urdf_sha256,
        cellc_schema::sha256_hex(&urdf)
    );
    assert!(artifact
        .sources
        .iter()
        .any(|s| s.path == "cells/robots/kuka_lwr4.cell"));
}

#[test]
fn dot_output_has_a_cluster_per_workspace() {
    let artifact = build("cells/fig3.cell");
    let dot = cellc::commands::graph::dot(&artifact, &artifact.objects[0]);
    assert_eq!(dot.matches("subgraph").count(), 3);
    assert_eq!(dot.matches("[style=solid]").count(), 52);
    assert_eq!(dot.matches("[style=dashed]").count(), 12);
}

/// UI tests for artifact files: `tests/ui/artifact/CODE_what.*` must be refused with
/// exactly that code; the rendered diagnostic is snapshotted.
#[test]
fn damaged_artifacts_ui() {
    let mut checked = 0;
    insta::glob!("ui/artifact/*", |path| {
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        let code = name.split('_').next().unwrap_or_default().to_string();
        let shown = format!("tests/ui/artifact/{name}");
        let diagnostic =
            cellc_driver::load::artifact::read(&shown).expect_err("damaged artifact is refused");
        assert_eq!(diagnostic.code.as_str(), code, "{name}");
        let rendered = cellc::render::human(
            std::slice::from_ref(&diagnostic),
            &cellc_lang::SourceMap::new(),
            cellc::render::Color::Never,
        );
        insta::assert_snapshot!(rendered);
        checked += 1;
    });
    assert_eq!(checked, 7);
}

/// The same content in another layout (keys reordered, indented, as `json.dumps(indent=2)`
/// or a formatter writes it) is the same artifact; a changed value is damage, named so,
/// not a missing checksum.
#[test]
fn a_reformatted_artifact_is_accepted_and_a_changed_one_is_damaged() {
    let artifact = build("cells/fig3.cell");
    let bytes = artifact.to_bytes(Encoding::Json);
    let mut value: serde_json::Value = serde_json::from_slice(&bytes).expect("JSON");
    let pretty = serde_json::to_vec_pretty(&value).expect("serialises");
    assert!(!pretty.starts_with(b"{\"checksum\""), "the checksum moved");
    let (read, _) = Artifact::from_bytes(&pretty).expect("the same content");
    assert_eq!(read.to_bytes(Encoding::Json), bytes);
    value["cell"] = serde_json::json!("fig4");
    let changed = serde_json::to_vec_pretty(&value).expect("serialises");
    let error = Artifact::from_bytes(&changed).expect_err("changed");
    assert_eq!(error, cellc_schema::ReadError::Damaged);
}
