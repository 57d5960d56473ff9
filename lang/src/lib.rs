//! Syntax of the cellc cell language: grammar, spans, syntax tree, parser and formatter.
//!
//! This crate knows text and nothing else: it does not resolve names, apply units or read
//! included files. [`parse`] turns one file's text into a [`ast::File`] plus every syntax
//! error found in it; [`format()`] prints a tree back in the one canonical layout.
#![warn(missing_docs)]

pub mod ast;
pub mod diagnostic;
pub mod format;
mod parser;
pub mod phrases;
pub mod span;

pub use diagnostic::{Code, Diagnostic, Label, Severity};
pub use format::format;
pub use parser::Parsed;
pub use span::{FileId, SourceFile, SourceMap, Span};

/// How deep `{ ... }` blocks may nest before the parser refuses the file. Real cells nest
/// two levels; the limit only keeps hostile input from exhausting the stack.
pub const MAX_NESTING: usize = 64;

/// Parses one file's text. Never panics: every problem is a diagnostic.
pub fn parse(file: FileId, text: &str) -> Parsed {
    pest::set_error_detail(true);
    let mut depth = 0usize;
    for (offset, byte) in text.bytes().enumerate() {
        match byte {
            b'{' => {
                depth += 1;
                if depth > MAX_NESTING {
                    return Parsed {
                        file: None,
                        diagnostics: vec![phrases::too_deep(
                            file,
                            Span::new(offset, offset + 1),
                            MAX_NESTING,
                        )],
                    };
                }
            }
            b'}' => depth = depth.saturating_sub(1),
            _ => {}
        }
    }
    parser::parse(file, text)
}
