//! The registry of diagnostic codes (`cellc_lang::codes`) held to the documentation and
//! the UI tests: every registered code has its page, its row in the index and a UI test
//! that produces it, every page belongs to a registered code, and no code is written twice.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use cellc_lang::codes::ALL;
use cellc_lang::Code;

/// The repository root (tests run from the package root, which is it).
fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

#[test]
fn every_code_has_its_page_as_embedded() {
    let mut wrong = Vec::new();
    for &code in ALL {
        let path = root().join(code.page_path());
        match std::fs::read_to_string(&path) {
            Err(e) => wrong.push(format!("{code}: {} unreadable: {e}", path.display())),
            Ok(text) => {
                if text != code.page() {
                    wrong.push(format!("{code}: the embedded page is not the file's text"));
                }
                if !text.starts_with(&format!("# {code}: ")) {
                    wrong.push(format!("{code}: its page does not start with `# {code}: `"));
                }
            }
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

#[test]
fn every_page_belongs_to_a_registered_code() {
    let mut pages = 0;
    let mut orphans = Vec::new();
    for entry in std::fs::read_dir(root().join("docs/diagnostics"))
        .expect("docs/diagnostics exists")
        .filter_map(Result::ok)
    {
        let name = entry.file_name().to_string_lossy().into_owned();
        if name == "README.md" {
            continue;
        }
        pages += 1;
        let stem = name.strip_suffix(".md").unwrap_or(&name);
        if Code::find(stem).is_none() {
            orphans.push(format!(
                "docs/diagnostics/{name} belongs to no registered code"
            ));
        }
    }
    assert!(orphans.is_empty(), "{}", orphans.join("\n"));
    assert_eq!(pages, ALL.len(), "one page per registered code");
}

/// The index in `docs/diagnostics/README.md` has one row per code, with the severity
/// its diagnostics have, and names UI test files that exist.
#[test]
fn the_index_lists_every_code_with_its_severity() {
    let index = std::fs::read_to_string(root().join("docs/diagnostics/README.md"))
        .expect("docs/diagnostics/README.md exists");
    let mut rows: BTreeMap<String, Vec<String>> = BTreeMap::new();
    let mut wrong = Vec::new();
    for line in index.lines().filter(|l| l.starts_with("| [")) {
        let cells: Vec<&str> = line.trim_matches('|').split(" | ").map(str::trim).collect();
        let Some(text) = cells[0].strip_prefix('[').and_then(|c| c.split(']').next()) else {
            continue;
        };
        match Code::find(text) {
            None => wrong.push(format!("the index lists {text}, which is not registered")),
            Some(code) => {
                if cells.get(1) != Some(&code.severity().as_str()) {
                    wrong.push(format!(
                        "{code}: the index says {:?}, its diagnostics are {}",
                        cells.get(1),
                        code.severity().as_str()
                    ));
                }
                for file in cells.get(3).unwrap_or(&"").split('`').skip(1).step_by(2) {
                    if !root().join("tests/ui").join(file).is_file() {
                        wrong.push(format!("{code}: the index names tests/ui/{file}, missing"));
                    }
                }
            }
        }
        rows.entry(text.to_string())
            .or_default()
            .push(line.to_string());
    }
    for &code in ALL {
        match rows.get(code.as_str()).map(Vec::len) {
            Some(1) => {}
            Some(n) => wrong.push(format!("{code}: {n} rows in the index")),
            None => wrong.push(format!("{code}: no row in docs/diagnostics/README.md")),
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

/// Every file under `tests/ui` (but `support/` folders and snapshots), by path.
fn ui_files() -> Vec<PathBuf> {
    let mut files = Vec::new();
    let mut folders = vec![root().join("tests/ui")];
    while let Some(folder) = folders.pop() {
        for entry in std::fs::read_dir(&folder)
            .expect("tests/ui exists")
            .filter_map(Result::ok)
        {
            let path = entry.path();
            if path.is_dir() {
                if !path.ends_with("support") {
                    folders.push(path);
                }
            } else if path.extension().is_none_or(|x| x != "snap") {
                files.push(path);
            }
        }
    }
    files
}

/// The codes a UI file says it produces. Each folder's harness fails when the file does
/// not produce them: `tests/ui/*.cell` name theirs on the first line (`// expect: CODES`),
/// `serve/*.http` after the status on the request line (`POST /v1/plan 400 S0001`), and the
/// other folders' harnesses take the code from the file name (`cli/E0505_*.args`).
fn declared_codes(path: &Path) -> Vec<String> {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let first = std::fs::read_to_string(path)
        .ok()
        .and_then(|t| t.lines().next().map(str::to_string))
        .unwrap_or_default();
    let top_level = path.parent() == Some(root().join("tests/ui").as_path());
    if top_level && name.ends_with(".cell") {
        first
            .strip_prefix("// expect:")
            .map(|codes| codes.split_whitespace().map(str::to_string).collect())
            .unwrap_or_default()
    } else if name.ends_with(".http") {
        first
            .split_whitespace()
            .nth(3)
            .map(str::to_string)
            .into_iter()
            .collect()
    } else {
        name.split('_')
            .next()
            .filter(|_| name.contains('_'))
            .map(str::to_string)
            .into_iter()
            .collect()
    }
}

#[test]
fn every_code_has_a_ui_test_that_declares_it() {
    let files = ui_files();
    assert!(files.len() > ALL.len(), "tests/ui holds too few files");
    let mut missing = Vec::new();
    for &code in ALL {
        let named = format!("{code}_");
        let tests: Vec<&PathBuf> = files
            .iter()
            .filter(|p| {
                p.file_name()
                    .is_some_and(|n| n.to_string_lossy().starts_with(&named))
            })
            .collect();
        if tests.is_empty() {
            missing.push(format!("{code}: no tests/ui/**/{code}_*"));
        }
        for path in tests {
            if !declared_codes(path).iter().any(|c| c == code.as_str()) {
                missing.push(format!(
                    "{}: named after {code} but does not expect it",
                    path.display()
                ));
            }
        }
    }
    assert!(missing.is_empty(), "{}", missing.join("\n"));
}

#[test]
fn every_declared_code_is_registered() {
    let mut unknown = Vec::new();
    for path in ui_files() {
        if path.extension().is_some_and(|x| x == "py") {
            continue;
        }
        for code in declared_codes(&path) {
            if Code::find(&code).is_none() {
                unknown.push(format!("{}: {code} is not registered", path.display()));
            }
        }
    }
    assert!(unknown.is_empty(), "{}", unknown.join("\n"));
}

#[test]
fn codes_are_unique_and_found_by_their_text() {
    let mut texts: Vec<&str> = ALL.iter().map(|c| c.as_str()).collect();
    texts.sort_unstable();
    texts.dedup();
    assert_eq!(texts.len(), ALL.len(), "a code is registered twice");
    let mut names: Vec<(&str, &str)> = ALL.iter().map(|c| (c.phase(), c.name())).collect();
    names.sort_unstable();
    names.dedup();
    assert_eq!(
        names.len(),
        ALL.len(),
        "a constant name is used twice in a phase"
    );
    for &code in ALL {
        assert_eq!(Code::find(code.as_str()), Some(code));
        assert_eq!(Code::find(&code.as_str().to_ascii_lowercase()), None);
    }
    assert_eq!(Code::find("E0999"), None);
    assert_eq!(Code::find(""), None);
}

#[test]
fn the_phases_hold_every_code_once() {
    use cellc_lang::codes::*;
    let phases: &[&[Code]] = &[
        parse::ALL,
        compile::ALL,
        scene::ALL,
        verify::ALL,
        request::ALL,
        artifact::ALL,
        output::ALL,
        export::ALL,
        import::ALL,
        serve::ALL,
    ];
    let joined: Vec<Code> = phases.iter().flat_map(|p| p.iter().copied()).collect();
    assert_eq!(joined, ALL.to_vec());
    assert_eq!(compile::UNKNOWN_NAME.as_str(), "E0101");
    assert_eq!(compile::UNKNOWN_NAME.name(), "UNKNOWN_NAME");
    assert_eq!(request::UNREACHABLE.phase(), "request");
    assert_eq!(
        compile::UNUSED_GRASP.severity(),
        cellc_lang::Severity::Warning
    );
    assert_eq!(serve::BAD_BODY.family(), cellc_lang::Family::Service);
}
