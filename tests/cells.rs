//! The shipped cells: every file in `cells/` checks clean (no errors, no warnings), as
//! the binary compiles it (with the runtime's kinematics for `reach auto`), and the
//! paper's Fig. 3 cell compiles to the paper's Fig. 6 graph.

use cellc_compiler::{compile, Compilation};
use cellc_driver::fs_files::FsFiles;

/// A cell compiled as the `cellc` binary compiles it.
fn compile_as_the_binary(path: &str) -> Compilation {
    cellc_driver::compile(&FsFiles, path, &Default::default())
}

fn shipped_cells() -> Vec<String> {
    let mut cells: Vec<String> = std::fs::read_dir("cells")
        .expect("run from the package root")
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == "cell"))
        .map(|p| p.to_string_lossy().replace('\\', "/"))
        .collect();
    cells.sort();
    cells
}

#[test]
fn every_shipped_cell_is_clean() {
    let cells = shipped_cells();
    assert!(cells.len() >= 2, "expected shipped cells, found {cells:?}");
    for cell in cells {
        let compilation = compile_as_the_binary(&cell);
        let rendered = cellc::render::short(&compilation.diagnostics, &compilation.sources);
        assert!(
            compilation.diagnostics.is_empty(),
            "{cell} is not clean:\n{rendered}"
        );
        assert!(!compilation.graphs.is_empty(), "{cell} has no object graph");
    }
}

#[test]
fn every_shipped_library_is_clean() {
    for entry in std::fs::read_dir("cells/robots").expect("cells/robots exists") {
        let path = entry.expect("entry").path();
        if path.extension().is_some_and(|e| e == "cell") {
            let path = path.to_string_lossy().replace('\\', "/");
            let compilation = compile(&FsFiles, &path);
            let rendered = cellc::render::short(&compilation.diagnostics, &compilation.sources);
            assert!(compilation.diagnostics.is_empty(), "{path}:\n{rendered}");
        }
    }
}

#[test]
fn fig3_compiles_to_the_papers_fig6_graph() {
    let compilation = compile(&FsFiles, "cells/fig3.cell");
    let [graph] = compilation.graphs.as_slice() else {
        panic!("fig3 has one object");
    };
    assert_eq!(graph.graph.node_count(), 21);
    assert_eq!(graph.n_moves(), 12);
    assert_eq!(graph.n_transitions(), 52);
    assert_eq!(graph.graph.edge_count(), 64);
}

#[test]
fn vito_derives_disjoint_workspaces_from_reach() {
    let compilation = compile(&FsFiles, "cells/vito.cell");
    let cell = compilation.cell.expect("vito resolves");
    let names: Vec<&str> = cell
        .workspaces
        .iter()
        .map(|(_, w)| w.name.as_str())
        .collect();
    assert!(names.contains(&"ws_left_right_table"), "{names:?}");
    assert!(names.contains(&"ws_right_bin"), "{names:?}");
    let boxes: Vec<(usize, cellc_compiler::math::Aabb)> = cell
        .workspaces
        .iter()
        .flat_map(|(id, w)| w.boxes.iter().map(move |b| (id.0 as usize, *b)))
        .collect();
    for (i, (wa, a)) in boxes.iter().enumerate() {
        for (wb, b) in &boxes[i + 1..] {
            assert!(
                cellc_compiler::math::overlap(a, b).is_none(),
                "workspaces {wa} and {wb} overlap"
            );
        }
    }
    // The shared workspace over the table is reached by both arms and the table.
    let shared = cell
        .workspaces
        .iter()
        .find(|(_, w)| w.name == "ws_left_right_table")
        .map(|(id, _)| id)
        .expect("shared workspace");
    let reachers: Vec<&str> = cell
        .end_effectors
        .iter()
        .filter(|(_, e)| e.reaches.contains(&shared))
        .map(|(_, e)| e.name.as_str())
        .collect();
    assert_eq!(reachers, ["left", "right", "table"]);
}
