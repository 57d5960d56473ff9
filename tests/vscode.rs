//! The VS Code extension in `editors/vscode/`: its manifests are valid JSON naming files
//! that exist, and its TextMate grammar highlights every keyword of the language's
//! grammar (`lang/src/cell.pest`), so a keyword added there and forgotten here fails.

use serde_json::Value;

const ROOT: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/editors/vscode");

fn json(relative: &str) -> Value {
    let text = std::fs::read_to_string(format!("{ROOT}/{relative}")).expect("the file exists");
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("{relative}: {e}"))
}

#[test]
fn manifest_names_files_that_exist() {
    let manifest = json("package.json");
    let contributes = &manifest["contributes"];
    let grammar = contributes["grammars"][0]["path"]
        .as_str()
        .expect("a grammar");
    let configuration = contributes["languages"][0]["configuration"]
        .as_str()
        .expect("a language configuration");
    let main = manifest["main"].as_str().expect("a main script");
    for file in [grammar, configuration, main] {
        assert!(
            std::path::Path::new(&format!("{ROOT}/{file}")).is_file(),
            "{file}"
        );
    }
    json(configuration);
    assert_eq!(
        json(grammar)["scopeName"],
        contributes["grammars"][0]["scopeName"]
    );
    let client = std::fs::read_to_string(format!("{ROOT}/{main}")).expect("the client");
    assert!(client.contains("'lsp'"), "the client starts `cellc lsp`");
}

#[test]
fn grammar_highlights_every_keyword() {
    let pest = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/lang/src/cell.pest"))
        .expect("the grammar");
    let keywords: Vec<&str> = pest
        .lines()
        .filter(|l| l.starts_with("kw_"))
        .filter_map(|l| l.split('"').nth(1))
        .collect();
    assert!(keywords.len() > 40, "{keywords:?}");
    let grammar = json("syntaxes/cell.tmLanguage.json").to_string();
    for keyword in keywords {
        let alternatives = [
            format!("({keyword}|"),
            format!("|{keyword}|"),
            format!("|{keyword})"),
        ];
        assert!(
            alternatives.iter().any(|a| grammar.contains(a.as_str())),
            "`{keyword}` is not highlighted"
        );
    }
}

/// The grammar test of the extension (`editors/vscode/tests/*.cell`, assertions on the
/// scopes each token gets) through the pinned `vscode-tmgrammar-test`, installed by the
/// README's test command (`npm ci --prefix editors/vscode`).
#[test]
fn grammar_test_files_pass() {
    let bin = format!("{ROOT}/node_modules/.bin/vscode-tmgrammar-test");
    assert!(
        std::path::Path::new(&bin).exists(),
        "the grammar test needs its npm packages: run `npm ci --ignore-scripts --prefix editors/vscode`"
    );
    let out = std::process::Command::new(&bin)
        .arg("tests/*.cell")
        .current_dir(ROOT)
        .output()
        .expect("node runs the grammar test");
    assert!(
        out.status.success(),
        "grammar test failed:\n{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
}
