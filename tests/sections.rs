//! The sectioned binary artifact: every shipped cell round-trips, a damaged section is
//! found when (and only when) it is read, and a hostile header or table is a diagnostic,
//! never a panic or an allocation the file's length does not bound.

use cellc_driver::fs_files::FsFiles;
use cellc_driver::BuildOptions;
use cellc_schema::sections::{SectionKind, Sections};
use cellc_schema::{
    ArmConfiguration, Artifact, Encoding, EndEffectorId, Infeasibility, Pose, PrunedArc, ReadError,
    Witness,
};

fn build(path: &str) -> Artifact {
    cellc_driver::build(&FsFiles, path, &BuildOptions::unverified())
        .artifact
        .unwrap_or_else(|| panic!("{path} has errors"))
}

/// fig3 with a witness and a pruned arc on its first object, so that every kind of
/// section has content to damage.
fn fig3_with_every_section() -> Artifact {
    let mut a = build("cells/fig3.cell");
    let g = &mut a.objects[0].graph;
    let arc = g.arcs[0];
    g.pruned.push(PrunedArc {
        arc,
        reason: Infeasibility::NoPlacement {
            detail: "test".into(),
        },
    });
    g.witnesses.push(Witness {
        object: Pose {
            translation: [0.1, 0.2, 0.3],
            rotation: [0.0, 0.0, 0.0, 1.0],
        },
        configurations: vec![ArmConfiguration {
            end_effector: EndEffectorId(0),
            joints: vec![0.5, -0.25],
        }],
    });
    a
}

#[test]
fn every_shipped_cell_round_trips_through_the_sections() {
    let mut cells: Vec<_> = std::fs::read_dir("cells")
        .expect("cells/")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "cell"))
        .collect();
    cells.sort();
    assert!(cells.len() >= 8, "{cells:?}");
    for cell in cells {
        // As `cellc build` compiles it (`reach auto` cells need the compile options).
        let (artifact, _) = cellc::artifact_io::compiled_cell(
            &cell.to_string_lossy(),
            cellc::render::Style::PLAIN,
            &cellc_compiler::CompileOptions::default(),
        )
        .expect("compiles");
        let bytes = artifact.to_bytes(Encoding::Binary);
        let (back, encoding) = Artifact::from_bytes(&bytes).expect("decodes");
        assert_eq!(encoding, Encoding::Binary);
        assert_eq!(back, artifact, "{}", cell.display());
    }
    let artifact = fig3_with_every_section();
    let back = Sections::open(&artifact.to_bytes(Encoding::Binary))
        .and_then(|s| s.artifact())
        .expect("decodes");
    assert_eq!(back, artifact);
}

/// Reads one section of `s` by kind and object, discarding its value.
fn read(s: &Sections<&[u8]>, kind: SectionKind, object: usize) -> Result<(), ReadError> {
    match kind {
        SectionKind::Core => s.core().map(drop),
        SectionKind::Nodes => s.nodes(object).map(drop),
        SectionKind::Arcs => s.arcs(object).map(drop),
        SectionKind::Pruned => s.pruned(object).map(drop),
        SectionKind::Witnesses => s.witnesses(object).map(drop),
        SectionKind::Transitions => s.transitions(object).map(drop),
    }
}

#[test]
fn a_flipped_byte_is_found_when_and_only_when_its_section_is_read() {
    let bytes = fig3_with_every_section().to_bytes(Encoding::Binary);
    let table = Sections::open(&bytes).expect("opens").table().to_vec();
    let mut kinds_damaged = Vec::new();
    for (row, damaged) in table.iter().enumerate() {
        if damaged.length == 0 {
            continue;
        }
        for at in [0, damaged.length / 2, damaged.length - 1] {
            let mut flipped = bytes.clone();
            flipped[damaged.offset + at] ^= 0x08;
            let s = Sections::open(&flipped).expect("the table is intact");
            for (other, section) in table.iter().enumerate() {
                let result = read(&s, section.kind, section.object as usize);
                if other == row {
                    assert_eq!(result, Err(ReadError::Damaged), "{damaged:?} at {at}");
                } else {
                    assert_eq!(
                        result,
                        Ok(()),
                        "{section:?} read after damage to {damaged:?}"
                    );
                }
            }
            assert!(Artifact::from_bytes(&flipped).is_err());
        }
        kinds_damaged.push(damaged.kind);
    }
    for kind in [
        SectionKind::Core,
        SectionKind::Nodes,
        SectionKind::Arcs,
        SectionKind::Pruned,
        SectionKind::Witnesses,
        SectionKind::Transitions,
    ] {
        assert!(kinds_damaged.contains(&kind), "{kind:?} never damaged");
    }
}

/// Rewrites the table's checksum after an edit of the table, as a forger would.
fn reseal(bytes: &mut [u8]) {
    let count = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    let end = (24 + count * 32).min(bytes.len());
    let sum = xxhash_rust::xxh3::xxh3_64(&bytes[24..end]);
    bytes[16..24].copy_from_slice(&sum.to_le_bytes());
}

fn corrupt(result: Result<Sections<&[u8]>, ReadError>) -> bool {
    matches!(result, Err(ReadError::Corrupt { .. }))
}

#[test]
fn tables_out_of_the_file_overlapping_or_absurd_are_corrupt() {
    let bytes = build("cells/fig3.cell").to_bytes(Encoding::Binary);
    let entry = |row: usize| 24 + row * 32;
    // A length past the end of the file, and an absurd one.
    for length in [bytes.len() as u64, u64::MAX, u64::MAX / 2] {
        let mut b = bytes.clone();
        b[entry(2) + 16..entry(2) + 24].copy_from_slice(&length.to_le_bytes());
        reseal(&mut b);
        assert!(corrupt(Sections::open(&b)), "length {length}");
    }
    // A section starting inside the one before it (overlap), or past the file.
    for offset in [0u64, 24, bytes.len() as u64 + 1, u64::MAX] {
        let mut b = bytes.clone();
        b[entry(1) + 8..entry(1) + 16].copy_from_slice(&offset.to_le_bytes());
        reseal(&mut b);
        assert!(corrupt(Sections::open(&b)), "offset {offset}");
    }
    // An absurd number of sections: refused before anything is allocated for them.
    for count in [u32::MAX, 1 << 28, 0] {
        let mut b = bytes.clone();
        b[12..16].copy_from_slice(&count.to_le_bytes());
        reseal(&mut b);
        assert!(corrupt(Sections::open(&b)), "count {count}");
    }
    // A row of the wrong kind.
    let mut b = bytes.clone();
    b[entry(1)..entry(1) + 4].copy_from_slice(&9u32.to_le_bytes());
    reseal(&mut b);
    assert!(corrupt(Sections::open(&b)));
}

#[test]
fn mutated_headers_are_refused_without_panic() {
    let bytes = fig3_with_every_section().to_bytes(Encoding::Binary);
    let count = Sections::open(&bytes).expect("opens").table().len();
    let header = 24 + count * 32;
    // A small deterministic generator, so a failure is reproducible.
    let mut state = 0x9e37_79b9_7f4a_7c15u64;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    };
    let mut refused = 0;
    for _ in 0..20_000 {
        let mut b = bytes.clone();
        for _ in 0..1 + next() % 4 {
            let at = (next() as usize) % header;
            b[at] = next() as u8;
        }
        if next() % 2 == 0 {
            reseal(&mut b);
        }
        if b == bytes {
            continue;
        }
        let result = Artifact::from_bytes(&b);
        assert!(result.is_err(), "a mutated header was accepted");
        refused += 1;
    }
    assert!(refused > 19_000);
}
