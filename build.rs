//! Embeds `docs/diagnostics/*.md` so that `cellc explain` works from any directory.

use std::fmt::Write;

fn main() {
    // Read at run time, not with `env!`: a build script binary reused from another
    // checkout's target folder would otherwise embed that checkout's pages.
    let root = std::env::var_os("CARGO_MANIFEST_DIR").unwrap_or_default();
    let dir = std::path::Path::new(&root).join("docs/diagnostics");
    println!("cargo:rerun-if-changed={}", dir.display());
    let mut pages: Vec<(String, std::path::PathBuf)> = std::fs::read_dir(&dir)
        .map(|entries| {
            entries
                .filter_map(Result::ok)
                .map(|e| e.path())
                .filter(|p| p.extension().is_some_and(|x| x == "md"))
                .filter_map(|p| {
                    let stem = p.file_stem()?.to_str()?.to_string();
                    let is_code = stem.len() == 5 && stem[1..].chars().all(|c| c.is_ascii_digit());
                    is_code.then_some((stem, p))
                })
                .collect()
        })
        .unwrap_or_default();
    pages.sort();
    let mut out = String::from("/// (code, page) for every documented diagnostic code.\npub static DIAGNOSTIC_DOCS: &[(&str, &str)] = &[\n");
    for (code, path) in &pages {
        println!("cargo:rerun-if-changed={}", path.display());
        let _ = writeln!(
            out,
            "    ({code:?}, include_str!({:?})),",
            path.display().to_string()
        );
    }
    out.push_str("];\n");
    let target = std::path::Path::new(&std::env::var("OUT_DIR").expect("cargo sets OUT_DIR"))
        .join("diagnostic_docs.rs");
    std::fs::write(target, out).expect("OUT_DIR is writable");
}
