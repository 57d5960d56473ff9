//! Every diagnostic code has a documentation page and at least one UI test, and every
//! documented code exists (no stale pages).

#[test]
fn every_code_has_a_page_and_a_ui_test() {
    // UI inputs: cells in tests/ui, and other inputs (artifacts, databases) in its
    // sub-folders, each named CODE_what.
    let mut ui_files: Vec<String> = Vec::new();
    let mut folders = vec![std::path::PathBuf::from("tests/ui")];
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
            } else {
                ui_files.push(entry.file_name().to_string_lossy().to_string());
            }
        }
    }
    let mut missing = Vec::new();
    for code in cellc::all_codes() {
        let code = code.as_str();
        if cellc::docs::page(code).is_none() {
            missing.push(format!("{code}: no docs/diagnostics/{code}.md"));
        }
        if !ui_files
            .iter()
            .any(|f| f.starts_with(&format!("{code}_")) && !f.ends_with(".snap"))
        {
            missing.push(format!("{code}: no tests/ui/**/{code}_*"));
        }
    }
    assert!(missing.is_empty(), "{}", missing.join("\n"));
}

#[test]
fn every_page_belongs_to_a_code() {
    let codes: Vec<&str> = cellc::all_codes().iter().map(|c| c.as_str()).collect();
    for documented in cellc::docs::documented_codes() {
        assert!(
            codes.contains(&documented),
            "docs/diagnostics/{documented}.md has no code"
        );
    }
}

#[test]
fn codes_are_unique() {
    let mut codes: Vec<&str> = cellc::all_codes().iter().map(|c| c.as_str()).collect();
    let n = codes.len();
    codes.sort();
    codes.dedup();
    assert_eq!(codes.len(), n, "a code is defined twice");
}
