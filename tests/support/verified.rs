//! A shipped cell as the tests that plan on it need it: built as `cellc build` builds it
//! (reach `auto` included, the scene checked, every arc verified with the default
//! options), clean, and loaded.

use cellc_driver::fs_files::FsFiles;
use cellc_runtime::Cell;

/// `path` built, checked clean (no compiler diagnostic) and loaded.
pub fn verified_cell(path: &str) -> Cell {
    let built = cellc_driver::build(&FsFiles, path, &Default::default());
    assert!(
        built.compilation.diagnostics.is_empty(),
        "{path} is not clean"
    );
    let artifact = built
        .artifact
        .unwrap_or_else(|| panic!("{path} has errors"));
    Cell::from_artifact(artifact, &FsFiles).expect("loads")
}
