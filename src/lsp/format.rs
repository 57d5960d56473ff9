//! Document and range formatting: the formatter's output (`cellc fmt`) as edits. A
//! document that does not parse is left alone (no edits), as `cellc fmt` leaves a file
//! with syntax errors.
//!
//! Range formatting formats the items the range touches, whole (an item is the unit of
//! the layout; a range inside an object formats the object). The whole file is laid out
//! and parsed again; its items are the original's in the same order, so the lines the
//! touched items own in the layout (with the comments above them) replace the lines they
//! own in the text, in one edit of whole lines, and nothing outside them changes.

use cellc_lang::{FileId, Span};
use lsp_types::{
    DocumentFormattingParams, DocumentRangeFormattingParams, Position, Range, TextEdit,
};

use super::documents::{path_of, Documents};
use super::position::Lines;

/// The edits that format the document: none when it is formatted or does not parse.
pub fn format(documents: &Documents, params: DocumentFormattingParams) -> Option<Vec<TextEdit>> {
    let path = path_of(&params.text_document.uri)?;
    let text = documents.get(&path)?.text.as_str();
    Some(edits(text))
}

/// The edits that format the items `params.range` touches.
pub fn format_range(
    documents: &Documents,
    params: DocumentRangeFormattingParams,
) -> Option<Vec<TextEdit>> {
    let path = path_of(&params.text_document.uri)?;
    let text = documents.get(&path)?.text.as_str();
    Some(range_edits(text, params.range))
}

/// The edits that format `text`.
pub fn edits(text: &str) -> Vec<TextEdit> {
    let Some(formatted) = formatted(text) else {
        return Vec::new();
    };
    if formatted == text {
        return Vec::new();
    }
    vec![TextEdit::new(
        Range::new(Default::default(), Lines::new(text).end()),
        formatted,
    )]
}

/// The edits that format the items of `text` that `range` touches (an item touches it
/// when the two overlap or meet): none when they are formatted, no item is touched, or
/// the text does not parse.
pub fn range_edits(text: &str, range: Range) -> Vec<TextEdit> {
    let Some(file) = clean_tree(text) else {
        return Vec::new();
    };
    let Some(formatted) = formatted(text) else {
        return Vec::new();
    };
    let Some(laid_out) = clean_tree(&formatted) else {
        return Vec::new();
    };
    let (lines, new_lines) = (Lines::new(text), Lines::new(&formatted));
    let (start, end) = (lines.offset(range.start), lines.offset(range.end));
    let spans: Vec<Span> = file.items.iter().map(|i| i.span()).collect();
    let touches = |s: &Span| s.end as usize >= start && s.start as usize <= end;
    let (Some(mut first), Some(mut last)) = (
        spans.iter().position(touches),
        spans.iter().rposition(touches),
    ) else {
        return Vec::new();
    };
    // Items sharing a line with the touched ones are laid out with them: edits replace
    // whole lines.
    let line = |offset: u32| lines.position(offset as usize).line;
    while first > 0 && line(spans[first - 1].end) == line(spans[first].start) {
        first -= 1;
    }
    while last + 1 < spans.len() && line(spans[last + 1].start) == line(spans[last].end) {
        last += 1;
    }
    let new_spans: Vec<Span> = laid_out.items.iter().map(|i| i.span()).collect();
    if new_spans.len() != spans.len() {
        return Vec::new();
    }
    let (Some(old), Some(new)) = (
        region(text, &lines, &file, &spans, first, last),
        region(&formatted, &new_lines, &laid_out, &new_spans, first, last),
    ) else {
        return Vec::new();
    };
    if text[old.clone()] == formatted[new.clone()] {
        return Vec::new();
    }
    vec![TextEdit::new(
        Range::new(lines.position(old.start), lines.position(old.end)),
        formatted[new].to_string(),
    )]
}

/// The bytes of whole lines that items `first..=last` of `file` own: from the line after
/// the previous item (or after the file's `{`), so that comments above the first move
/// with it, to the end of the line the last one ends on.
fn region(
    text: &str,
    lines: &Lines<'_>,
    file: &cellc_lang::ast::File,
    spans: &[Span],
    first: usize,
    last: usize,
) -> Option<std::ops::Range<usize>> {
    let before = match first.checked_sub(1) {
        Some(previous) => spans[previous].end as usize,
        None => {
            let name_end = file.name.span.end as usize;
            name_end + text.get(name_end..)?.find('{')?
        }
    };
    let next_line = |offset: usize| {
        let line = lines.position(offset).line + 1;
        lines.offset(Position::new(line, 0))
    };
    let start = next_line(before);
    let end = next_line(spans[last].end as usize);
    (start <= spans[first].start as usize && start <= end).then_some(start..end)
}

/// The tree of `text`, when it parses without a diagnostic.
fn clean_tree(text: &str) -> Option<cellc_lang::ast::File> {
    let parsed = cellc_lang::parse(FileId(0), text);
    parsed.file.filter(|_| parsed.diagnostics.is_empty())
}

/// The formatter's layout of `text`, when it parses cleanly.
fn formatted(text: &str) -> Option<String> {
    Some(cellc_lang::format(&clean_tree(text)?, text))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `text` with `edits` applied (edits of whole lines, in order, not overlapping).
    fn apply(text: &str, edits: &[TextEdit]) -> String {
        let lines = Lines::new(text);
        let mut out = String::new();
        let mut at = 0;
        for e in edits {
            let (s, t) = (lines.offset(e.range.start), lines.offset(e.range.end));
            out.push_str(&text[at..s]);
            out.push_str(&e.new_text);
            at = t;
        }
        out.push_str(&text[at..]);
        out
    }

    const MESSY: &str = "cell m {\nworkspace   w1\n  workspace w2\n    fixed t reaches w1,w2\nobject o {\n grasp g by t\n    }\n}\n";

    #[test]
    fn a_range_formats_only_the_items_it_touches() {
        // The range is inside `fixed t ...` (line 3): only that line changes.
        let range = Range::new(Position::new(3, 6), Position::new(3, 8));
        let edits = range_edits(MESSY, range);
        assert_eq!(edits.len(), 1, "{edits:?}");
        let after = apply(MESSY, &edits);
        assert_eq!(
            after,
            MESSY.replace("    fixed t reaches w1,w2", "  fixed t reaches w1, w2")
        );
        // Inside the object: the whole object, and nothing else.
        let range = Range::new(Position::new(5, 2), Position::new(5, 2));
        let after = apply(MESSY, &range_edits(MESSY, range));
        assert!(after.contains("workspace   w1\n"), "{after}");
        assert!(
            after.contains("  object o {\n    grasp g by t\n  }\n"),
            "{after}"
        );
    }

    #[test]
    fn a_range_over_everything_is_the_whole_formatting() {
        let range = Range::new(Position::new(0, 0), Lines::new(MESSY).end());
        let after = apply(MESSY, &range_edits(MESSY, range));
        assert_eq!(Some(after), formatted(MESSY));
        // Formatted text, a range with no item, and a broken text: no edits.
        let clean = formatted(MESSY).unwrap_or_default();
        assert!(range_edits(&clean, range).is_empty());
        assert!(
            range_edits(MESSY, Range::new(Position::new(0, 0), Position::new(0, 2))).is_empty()
        );
        assert!(range_edits("cell x {\n  workspace\n}\n", range).is_empty());
    }

    #[test]
    fn comments_inside_a_formatted_item_are_kept() {
        let text = "cell c {\n  workspace w1 // first\n  fixed  t /* why */ reaches w1\n}\n";
        let range = Range::new(Position::new(2, 3), Position::new(2, 3));
        let after = apply(text, &range_edits(text, range));
        assert_eq!(after.matches("/* why */").count(), 1, "{after}");
        assert!(after.contains("  workspace w1 // first\n"), "{after}");
        assert!(after.contains("  fixed t reaches w1\n"), "{after}");
    }
}
