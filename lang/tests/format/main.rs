//! Tests of the canonical formatter: round trip (same tree up to spans), idempotence, and
//! that every comment survives exactly once, in order.
//!
//! This file holds the checks every case runs (and the comment oracle they use); the
//! modules hold the cases: `files.rs` the cells of the repository, `comments.rs` comments
//! in every position, `layout.rs` messy layouts made canonical (the `world` and `task`
//! blocks too), `random.rs` random layouts and mismatched sources.

use std::path::{Path, PathBuf};

use cellc_lang::{format, parse, FileId};

mod comments;
mod files;
mod layout;
mod random;

/// A tree dump without spans: `Span`'s Debug is `@start..end`, and two layouts of one
/// file differ only there.
fn strip_spans(dump: &str) -> String {
    let bytes = dump.as_bytes();
    let mut out = String::with_capacity(dump.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'@' {
            if let Some(len) = span_len(&bytes[i + 1..]) {
                i += 1 + len;
                continue;
            }
        }
        // Copy one whole character (the dump may hold non-ASCII names and labels).
        let len = dump[i..].chars().next().map_or(1, char::len_utf8);
        out.push_str(&dump[i..i + len]);
        i += len;
    }
    out
}

/// Length of `<digits>..<digits>` at the start of `bytes`, if it is there.
fn span_len(bytes: &[u8]) -> Option<usize> {
    let digits = |from: usize| {
        bytes[from..]
            .iter()
            .take_while(|b| b.is_ascii_digit())
            .count()
    };
    let first = digits(0);
    if first == 0 || bytes.get(first..first + 2) != Some(b"..".as_slice()) {
        return None;
    }
    let second = digits(first + 2);
    (second > 0).then_some(first + 2 + second)
}

/// The comments of a text, in order, as the formatter prints them (line comments without
/// trailing white space). Written independently of the formatter's scanner, as an oracle;
/// like the grammar, it ends strings and quoted names at the end of their line.
fn comments(text: &str) -> Vec<String> {
    let mut found = Vec::new();
    let mut rest = text;
    loop {
        let next = rest.find(['/', '"', '`']);
        let Some(at) = next else { break };
        let tail = &rest[at..];
        if tail.starts_with("//") {
            let end = tail.find('\n').unwrap_or(tail.len());
            found.push(tail[..end].trim_end().to_string());
            rest = &tail[end..];
        } else if let Some(body) = tail.strip_prefix("/*") {
            let end = body.find("*/").map_or(tail.len(), |e| e + 4);
            found.push(tail[..end].to_string());
            rest = &tail[end..];
        } else if tail.starts_with('"') {
            let mut end = 1;
            let b = tail.as_bytes();
            while end < b.len() && b[end] != b'"' && b[end] != b'\n' {
                end += if b[end] == b'\\' { 2 } else { 1 };
            }
            rest = tail.get(end + 1..).unwrap_or("");
        } else if let Some(body) = tail.strip_prefix('`') {
            let end = body.find(['`', '\n']).map_or(tail.len(), |e| e + 2);
            rest = &tail[end..];
        } else {
            rest = &tail[1..];
        }
    }
    found
}

/// Parses `text`, which must have no syntax errors, and returns the tree dump without
/// spans together with the formatted text.
fn parse_and_format(text: &str, what: &str) -> (String, String) {
    let parsed = parse(FileId(0), text);
    assert!(
        parsed.diagnostics.is_empty(),
        "{what}: unexpected diagnostics {:#?}\n--- text ---\n{text}",
        parsed.diagnostics
    );
    let file = parsed
        .file
        .unwrap_or_else(|| panic!("{what}: no tree without diagnostics"));
    (strip_spans(&format!("{file:#?}")), format(&file, text))
}

/// Formats `text` and checks everything the formatter promises: the result parses to the
/// same tree (up to spans), formatting it again changes nothing, and it holds exactly the
/// comments of the input, in order. Returns the formatted text.
fn check(text: &str, what: &str) -> String {
    let (tree, formatted) = parse_and_format(text, what);
    let (tree_again, formatted_again) =
        parse_and_format(&formatted, &format!("{what} (formatted)"));
    assert_eq!(
        tree, tree_again,
        "{what}: formatting changed the tree\n--- formatted ---\n{formatted}"
    );
    assert_eq!(
        formatted, formatted_again,
        "{what}: formatting is not idempotent"
    );
    assert_eq!(
        comments(text),
        comments(&formatted),
        "{what}: comments lost, duplicated or reordered\n--- formatted ---\n{formatted}"
    );
    formatted
}

/// Every `*.cell` file under `dir`, recursively, sorted (an absent directory has none).
fn cell_files(dir: &Path) -> Vec<PathBuf> {
    let mut found = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(dir) = stack.pop() {
        let Ok(entries) = std::fs::read_dir(&dir) else {
            continue;
        };
        for entry in entries.flatten() {
            let path = entry.path();
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|e| e == "cell") {
                found.push(path);
            }
        }
    }
    found.sort();
    found
}

fn manifest_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn all_constructs() -> String {
    read(&manifest_dir().join("tests/data/all_constructs.cell"))
}

fn fig3() -> String {
    read(&manifest_dir().join("../cells/fig3.cell"))
}
