//! An embedder that verifies through `Cell::verify` gets the answer `cellc build` gives:
//! the same artifact to the byte for a sound scene, the same refusal for a scene wrong
//! whatever the arc.

use cellc_driver::fs_files::FsFiles;
use cellc_driver::scene_report;
use cellc_driver::BuildOptions;
use cellc_lang::Code;
use cellc_runtime::{Cell, VerifyOptions};

#[test]
fn a_sound_cell_is_verified_to_the_same_artifact_by_both() {
    let built = cellc_driver::build(&FsFiles, "../cells/vito.cell", &Default::default());
    let by_build = built.artifact.expect("builds");
    let compiled = cellc_driver::build(&FsFiles, "../cells/vito.cell", &BuildOptions::unverified());
    let compiled = compiled.artifact.expect("compiles");
    let mut cell = Cell::from_artifact(compiled, &FsFiles).expect("loads");
    let checked = cell
        .verify(&VerifyOptions::default())
        .expect("vito has arms");
    assert_eq!(
        checked.preflight,
        Default::default(),
        "vito's scene is sound"
    );
    let report = checked.report.expect("a sound scene is verified");
    assert!(report.n_checked > 0, "{report:?}");
    let by_cell = cell.artifact();
    assert_eq!(
        by_cell.to_bytes(cellc_schema::Encoding::Json),
        by_build.to_bytes(cellc_schema::Encoding::Json)
    );
}

/// A scene wrong whatever the arc (a guard on the base that touches the upper arm at the
/// home): the build refuses it with E0420, and `Cell::verify` leaves every arc as compiled
/// and reports the same colliding home, instead of pruning every arc for it.
#[test]
fn a_scene_the_build_refuses_is_not_verified_by_the_cell_either() {
    let path = "../tests/data/srdf/without_srdf.cell";
    let built = cellc_driver::build(&FsFiles, path, &Default::default());
    assert!(built.artifact.is_none());
    let codes: Vec<Code> = built.diagnostics.iter().map(|d| d.code).collect();
    assert_eq!(codes, [scene_report::codes::HOME_COLLIDES]);
    let compiled = cellc_driver::build(&FsFiles, path, &BuildOptions::unverified())
        .artifact
        .expect("compiles");
    let arcs = compiled.objects[0].graph.arcs.len();
    assert!(arcs > 0);
    let mut cell = Cell::from_artifact(compiled, &FsFiles).expect("loads");
    let checked = cell
        .verify(&VerifyOptions::default())
        .expect("the cell has an arm");
    assert!(checked.preflight.blocks_verification());
    assert_eq!(checked.preflight.homes.len(), 1, "{:?}", checked.preflight);
    assert!(checked.report.is_none());
    let graph = &cell.artifact().objects[0].graph;
    assert_eq!(graph.arcs.len(), arcs);
    assert!(graph.pruned.is_empty());
}
