//! Document formatting: the formatter's output as one edit of the whole document. A
//! document that does not parse is left alone (no edits), as `cellc fmt` leaves a file
//! with syntax errors.

use cellc_lang::FileId;
use lsp_types::{DocumentFormattingParams, Range, TextEdit};

use super::documents::{path_of, Documents};
use super::position::Lines;

/// The edits that format the document: none when it is formatted or does not parse.
pub fn format(documents: &Documents, params: DocumentFormattingParams) -> Option<Vec<TextEdit>> {
    let path = path_of(&params.text_document.uri)?;
    let text = documents.get(&path)?.text.as_str();
    Some(edits(text))
}

/// The edits that format `text`.
pub fn edits(text: &str) -> Vec<TextEdit> {
    let parsed = cellc_lang::parse(FileId(0), text);
    let (Some(file), true) = (parsed.file, parsed.diagnostics.is_empty()) else {
        return Vec::new();
    };
    let formatted = cellc_lang::format(&file, text);
    if formatted == text {
        return Vec::new();
    }
    vec![TextEdit::new(
        Range::new(Default::default(), Lines::new(text).end()),
        formatted,
    )]
}
