//! An embedder that verifies through `Cell::verify` gets the artifact `cellc build`
//! gives, to the byte.

use cellc_driver::fs_files::FsFiles;
use cellc_driver::BuildOptions;
use cellc_runtime::{Cell, VerifyOptions};

#[test]
fn a_sound_cell_is_verified_to_the_same_artifact_by_both() {
    let built = cellc_driver::build(&FsFiles, "../cells/vito.cell", &Default::default());
    let by_build = built.artifact.expect("builds");
    let unverified = BuildOptions {
        no_verify: true,
        ..Default::default()
    };
    let compiled = cellc_driver::build(&FsFiles, "../cells/vito.cell", &unverified);
    let compiled = compiled.artifact.expect("compiles");
    let mut cell = Cell::from_artifact(compiled, &FsFiles).expect("loads");
    let report = cell
        .verify(&VerifyOptions::default())
        .expect("vito has arms");
    assert!(report.n_checked > 0, "{report:?}");
    let by_cell = cell.artifact();
    assert_eq!(
        by_cell.to_bytes(cellc_schema::Encoding::Json),
        by_build.to_bytes(cellc_schema::Encoding::Json)
    );
}
