//! Syntax of the cellc cell language: grammar, spans, syntax tree, parser and formatter.
//!
//! This crate knows text and nothing else: it does not resolve names, apply units or read
//! included files. [`parse`] turns one file's text into a [`ast::File`] plus every syntax
//! error found in it; [`format()`] prints a tree back in the one canonical layout.
#![warn(missing_docs)]

pub mod ast;
pub mod codes;
pub mod diagnostic;
pub mod format;
mod grammar;
pub mod keywords;
mod parser;
pub mod phrases;
pub mod screen;
pub mod span;

pub use diagnostic::{Code, Diagnostic, Family, Label, Severity};
pub use format::format;
pub use keywords::written_name;
pub use parser::{parse_placement, Parsed};
pub use screen::{not_a_cell, NotACell, MAX_NESTING};
pub use span::{FileId, SourceFile, SourceMap, Span};

/// Parses one file's text. Never panics: every problem is a diagnostic. Text the grammar
/// must not see is refused first (see [`screen`]): blocks nested too deep, and control
/// characters, each reported at its place.
pub fn parse(file: FileId, text: &str) -> Parsed {
    if let Some(offset) = screen::too_deep_at(text) {
        return Parsed {
            file: None,
            diagnostics: vec![phrases::too_deep(
                file,
                Span::new(offset, offset + 1),
                MAX_NESTING,
            )],
        };
    }
    let (controls, count) = screen::control_characters(text);
    if !controls.is_empty() {
        let mut diagnostics: Vec<Diagnostic> = controls
            .iter()
            .map(|&span| phrases::control_character(file, span, &text[span.range()]))
            .collect();
        if count > controls.len() {
            if let Some(last) = diagnostics.last_mut() {
                last.notes.push(format!(
                    "{} more runs of control characters are not shown",
                    count - controls.len()
                ));
            }
        }
        return Parsed {
            file: None,
            diagnostics,
        };
    }
    parser::parse(file, text)
}
