//! Bad input never panics the checker and never passes silently: random bytes and random
//! edits of the shipped cells always give either a clean result or at least one coded
//! diagnostic, and every diagnostic has a known code and, where it has a place, a span
//! inside its file.

use cellc_compiler::{compile, MemoryFiles};
use proptest::prelude::*;

fn shipped() -> Vec<(String, String)> {
    let mut cells = Vec::new();
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("cells");
    for entry in std::fs::read_dir(&root).expect("cells/ exists") {
        let path = entry.expect("readable entry").path();
        if path.extension().is_some_and(|e| e == "cell") {
            let text = std::fs::read_to_string(&path).expect("readable cell");
            cells.push((
                path.file_name().unwrap().to_string_lossy().to_string(),
                text,
            ));
        }
    }
    cells.sort();
    cells
}

/// The files a shipped cell may include, so edits of geometric cells reach the resolver.
fn library_files() -> Vec<(String, String)> {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("cells/robots");
    let mut files = Vec::new();
    for entry in std::fs::read_dir(root).expect("cells/robots exists") {
        let path = entry.expect("readable entry").path();
        let name = format!("robots/{}", path.file_name().unwrap().to_string_lossy());
        if let Ok(text) = std::fs::read_to_string(&path) {
            files.push((name, text));
        }
    }
    files
}

fn check_invariants(main: &str, text: &str) -> Result<(), TestCaseError> {
    let libraries = library_files();
    let mut files: Vec<(&str, &str)> = libraries
        .iter()
        .map(|(p, t)| (p.as_str(), t.as_str()))
        .collect();
    files.push((main, text));
    let world = MemoryFiles::new(files);
    let compilation = compile(&world, main);
    for d in &compilation.diagnostics {
        prop_assert_eq!(
            d.severity,
            d.code.severity(),
            "{} has the wrong severity",
            d.code
        );
        prop_assert!(!d.message.is_empty());
        prop_assert!(d.help.is_some(), "{} has no help", d.code);
        for label in &d.labels {
            let len = compilation.sources.get(label.file).text.len() as u32;
            prop_assert!(label.span.start <= label.span.end && label.span.end <= len);
        }
    }
    // Every render path must work on whatever came out.
    let _ = cellc::render::human(
        &compilation.diagnostics,
        &compilation.sources,
        cellc::render::Color::Never,
    );
    let _ = cellc::render::short(&compilation.diagnostics, &compilation.sources);
    let _ = cellc::render::json(&compilation.diagnostics, &compilation.sources);
    // Clean, or at least one coded diagnostic: a cell that did not parse cannot be clean.
    if compilation.cell.is_none() {
        prop_assert!(!compilation.diagnostics.is_empty());
    }
    Ok(())
}

#[derive(Debug, Clone)]
enum Edit {
    Delete { at: usize, len: usize },
    Insert { at: usize, text: String },
    Duplicate { at: usize, len: usize },
    Swap { a: usize, b: usize },
}

fn edit() -> impl Strategy<Value = Edit> {
    let token = prop_oneof![
        Just("{".to_string()),
        Just("}".to_string()),
        Just("(".to_string()),
        Just(",".to_string()),
        Just("->".to_string()),
        Just("<->".to_string()),
        Just(" mm".to_string()),
        Just(" deg".to_string()),
        Just("\n".to_string()),
        Just("`".to_string()),
        Just("\"".to_string()),
        Just("/*".to_string()),
        Just("quat (1, 1, 0, 0)".to_string()),
        "[a-z_]{1,8}",
        "-?[0-9]{1,4}(\\.[0-9]{1,3})?",
    ];
    prop_oneof![
        (any::<usize>(), 1usize..40).prop_map(|(at, len)| Edit::Delete { at, len }),
        (any::<usize>(), token).prop_map(|(at, text)| Edit::Insert { at, text }),
        (any::<usize>(), 1usize..80).prop_map(|(at, len)| Edit::Duplicate { at, len }),
        (any::<usize>(), any::<usize>()).prop_map(|(a, b)| Edit::Swap { a, b }),
    ]
}

fn boundary(text: &str, at: usize) -> usize {
    let mut at = at % (text.len() + 1);
    while !text.is_char_boundary(at) {
        at -= 1;
    }
    at
}

fn apply(text: &str, edit: &Edit) -> String {
    match edit {
        Edit::Delete { at, len } => {
            let a = boundary(text, *at);
            let b = boundary(text, (a + len).min(text.len()));
            format!("{}{}", &text[..a], &text[b.max(a)..])
        }
        Edit::Insert { at, text: t } => {
            let a = boundary(text, *at);
            format!("{}{}{}", &text[..a], t, &text[a..])
        }
        Edit::Duplicate { at, len } => {
            let a = boundary(text, *at);
            let b = boundary(text, (a + len).min(text.len())).max(a);
            format!("{}{}", &text[..b], &text[a..])
        }
        Edit::Swap { a, b } => {
            let lines: Vec<&str> = text.lines().collect();
            if lines.is_empty() {
                return text.to_string();
            }
            let mut lines = lines;
            let (i, j) = (a % lines.len(), b % lines.len());
            lines.swap(i, j);
            lines.join("\n")
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    #[test]
    fn random_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..400)) {
        let text = String::from_utf8_lossy(&bytes).to_string();
        check_invariants("fuzz.cell", &text)?;
    }

    #[test]
    fn random_text_in_a_cell_never_panics(body in "[ -~\n]{0,300}") {
        check_invariants("fuzz.cell", &format!("cell fuzz {{\n{body}\n}}\n"))?;
    }

    #[test]
    fn edited_shipped_cells_never_panic(
        which in any::<prop::sample::Index>(),
        edits in proptest::collection::vec(edit(), 1..6),
    ) {
        let cells = shipped();
        let (name, text) = which.get(&cells);
        let mut text = text.clone();
        for e in &edits {
            text = apply(&text, e);
        }
        check_invariants(name, &text)?;
    }
}

#[test]
fn deep_nesting_is_refused_not_overflowed() {
    let text = format!("cell deep {{ {} }}", "{".repeat(100_000));
    let world = MemoryFiles::new([("deep.cell", text.as_str())]);
    let compilation = compile(&world, "deep.cell");
    assert_eq!(
        compilation.diagnostics[0].code,
        cellc_lang::phrases::codes::TOO_DEEP
    );
}
