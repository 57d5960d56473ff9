//! Syntax of the cellc cell language: grammar, spans, syntax tree, parser and formatter.
//!
//! This crate knows text and nothing else: it does not resolve names, apply units or read
//! included files. [`parse`] turns one file's text into a [`ast::File`] plus every syntax
//! error found in it; [`format()`] prints a tree back in the one canonical layout.
#![warn(missing_docs)]

pub mod ast;
pub mod diagnostic;
pub mod format;
mod grammar;
mod parser;
pub mod phrases;
pub mod span;

pub use diagnostic::{Code, Diagnostic, Label, Severity};
pub use format::format;
pub use parser::{parse_placement, Parsed};
pub use span::{FileId, SourceFile, SourceMap, Span};

/// How deep `{ ... }` blocks may nest before the parser refuses the file. Real cells nest
/// two levels; the limit only keeps hostile input from exhausting the stack.
pub const MAX_NESTING: usize = 64;

/// Parses one file's text. Never panics: every problem is a diagnostic.
pub fn parse(file: FileId, text: &str) -> Parsed {
    pest::set_error_detail(true);
    if let Some(offset) = too_deep_at(text) {
        return Parsed {
            file: None,
            diagnostics: vec![phrases::too_deep(
                file,
                Span::new(offset, offset + 1),
                MAX_NESTING,
            )],
        };
    }
    parser::parse(file, text)
}

/// The offset of the first `{` nested deeper than [`MAX_NESTING`], ignoring braces in
/// comments, strings and quoted names.
fn too_deep_at(text: &str) -> Option<usize> {
    let bytes = text.as_bytes();
    let mut depth = 0usize;
    let mut i = 0;
    while i < bytes.len() {
        match bytes[i] {
            b'/' if bytes.get(i + 1) == Some(&b'/') => {
                while i < bytes.len() && bytes[i] != b'\n' {
                    i += 1;
                }
            }
            b'/' if bytes.get(i + 1) == Some(&b'*') => {
                i += 2;
                while i < bytes.len() && !(bytes[i] == b'*' && bytes.get(i + 1) == Some(&b'/')) {
                    i += 1;
                }
                i += 2;
            }
            quote @ (b'"' | b'`') => {
                i += 1;
                while i < bytes.len() && bytes[i] != quote && bytes[i] != b'\n' {
                    if quote == b'"' && bytes[i] == b'\\' {
                        i += 1;
                    }
                    i += 1;
                }
                i += 1;
            }
            b'{' => {
                depth += 1;
                if depth > MAX_NESTING {
                    return Some(i);
                }
                i += 1;
            }
            b'}' => {
                depth = depth.saturating_sub(1);
                i += 1;
            }
            _ => i += 1,
        }
    }
    None
}
