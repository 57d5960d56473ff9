//! A shipped cell as the tests that plan on it need it: compiled (reach `auto` included,
//! which `cellc` does and the bare compiler refuses), clean, loaded and verified with the
//! default options.

use cellc::fs_files::FsFiles;
use cellc_runtime::verify::VerifyOptions;
use cellc_runtime::Cell;

/// `path` compiled, checked clean, loaded and verified.
pub fn verified_cell(path: &str) -> Cell {
    let compilation = cellc::reach::compile(&FsFiles, path, &Default::default());
    assert!(compilation.diagnostics.is_empty(), "{path} is not clean");
    let artifact = cellc_compiler::artifact::lower(
        compilation.cell.as_ref().expect("resolved"),
        &compilation.graphs,
        &compilation.sources,
    );
    let mut cell = Cell::from_artifact(artifact, &FsFiles).expect("loads");
    cell.verify(&VerifyOptions::default());
    cell
}
