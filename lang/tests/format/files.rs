//! The cells of the repository: the examples and the UI cells that parse round trip, and
//! the hand-written ones are already canonical.

use cellc_lang::{parse, FileId};

use super::{all_constructs, cell_files, check, fig3, manifest_dir, parse_and_format, read};

#[test]
fn example_cells_round_trip() {
    let dir = manifest_dir().join("../cells");
    let files = cell_files(&dir);
    assert!(!files.is_empty(), "no cells found under {}", dir.display());
    for path in files {
        check(&read(&path), &path.display().to_string());
    }
}

#[test]
fn ui_cells_that_parse_round_trip() {
    for path in cell_files(&manifest_dir().join("../tests/ui")) {
        let text = read(&path);
        let parsed = parse(FileId(0), &text);
        if parsed.file.is_none() || !parsed.diagnostics.is_empty() {
            continue;
        }
        check(&text, &path.display().to_string());
    }
}

#[test]
fn all_constructs_round_trip() {
    check(&all_constructs(), "all_constructs.cell");
}

/// The test data is written in the canonical layout, so it is a fixed point.
#[test]
fn all_constructs_is_canonical() {
    let text = all_constructs();
    let (_, formatted) = parse_and_format(&text, "all_constructs.cell");
    assert_eq!(formatted, text);
}

/// The canonical layout is the one the hand-written example already uses.
#[test]
fn fig3_is_canonical() {
    let text = fig3();
    let (_, formatted) = parse_and_format(&text, "fig3.cell");
    assert_eq!(formatted, text);
}
