//! UI tests: every `tests/ui/*.cell` holds one problem, names the code it must produce
//! on its first line (`// expect: E0101`), and has an insta snapshot of its source plus
//! the rendered diagnostics. The harness fails when the codes produced differ from the
//! ones written, so a snapshot can never quietly bless a wrong diagnostic. A file about
//! how diagnostics are shown together (grouping by code) names every code it produces
//! (`// expect: W0003 W0005`).
//!
//! Files under `tests/ui/support/` are included or referenced by UI files, not tested
//! alone.

use std::collections::BTreeSet;

use cellc::render::{self, Color};
use cellc_driver::fs_files::FsFiles;

fn expected_codes(source: &str) -> Option<BTreeSet<&str>> {
    let codes: BTreeSet<&str> = source
        .lines()
        .next()?
        .trim()
        .strip_prefix("// expect:")?
        .split_whitespace()
        .collect();
    (!codes.is_empty()).then_some(codes)
}

#[test]
fn ui() {
    let mut failures = Vec::new();
    let mut count = 0;
    insta::glob!("ui/*.cell", |path| {
        count += 1;
        let relative = path
            .strip_prefix(std::path::Path::new(env!("CARGO_MANIFEST_DIR")))
            .unwrap_or(path)
            .to_string_lossy()
            .replace('\\', "/");
        let source = std::fs::read_to_string(path).unwrap_or_default();
        let Some(codes) = expected_codes(&source) else {
            failures.push(format!("{relative}: first line must be `// expect: CODE`"));
            return;
        };
        let compilation = cellc_driver::compile(&FsFiles, &relative, &Default::default());
        let produced: BTreeSet<&str> = compilation
            .diagnostics
            .iter()
            .map(|d| d.code.as_str())
            .collect();
        if produced != codes {
            failures.push(format!(
                "{relative}: expected only {codes:?}, got {produced:?}"
            ));
        }
        for d in &compilation.diagnostics {
            if d.severity != d.code.severity() {
                failures.push(format!(
                    "{relative}: {} reported as {:?}",
                    d.code, d.severity
                ));
            }
        }
        let rendered = render::human(&compilation.diagnostics, &compilation.sources, Color::Never);
        insta::assert_snapshot!(format!("{source}\n----- diagnostics -----\n{rendered}"));
    });
    assert!(count > 0, "no UI test files found");
    assert!(
        failures.is_empty(),
        "UI tests failed:\n{}",
        failures.join("\n")
    );
}
