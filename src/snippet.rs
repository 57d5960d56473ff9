//! Source text for human snippets at a cost that does not grow with the file.
//!
//! miette finds the lines around a label by scanning its source from the first byte, and
//! the renderer used to hand it a fresh copy of the whole file per diagnostic, so a cell
//! of 10 MB with 10⁵ diagnostics cost 10¹² steps. Here every file is neutralised and
//! indexed once per rendering ([`Sources`]), and each request for a snippet gives miette
//! only a few lines around the label, cut at line starts, so its own algorithm returns
//! exactly what it would have on the whole file, shifted back into file coordinates.
//!
//! A line longer than [`MAX_SHOWN_LINE_BYTES`] is not shown at all (a generated `reaches`
//! list of 10⁵ names is one line of half a megabyte, and every diagnostic on it would
//! print it): [`Sources::too_long`] tells the renderer to say where instead.

use std::sync::Arc;

use cellc_lang::span::LineIndex;
use cellc_lang::{FileId, SourceMap};
use miette::{MietteError, MietteSpanContents, SourceCode, SourceSpan, SpanContents};

/// The longest line a snippet shows, in bytes.
pub const MAX_SHOWN_LINE_BYTES: usize = 1000;

/// Lines of context miette shows around a label (its default, which the renderer keeps).
const CONTEXT_LINES: usize = 1;

/// One file's text as snippets show it, with its line index.
pub struct Indexed {
    text: String,
    lines: LineIndex,
}

/// A shared [`Indexed`] file, as miette's source for one report.
#[derive(Clone)]
pub struct Shared(Arc<Indexed>);

impl SourceCode for Shared {
    fn read_span<'a>(
        &'a self,
        span: &SourceSpan,
        context_lines_before: usize,
        context_lines_after: usize,
    ) -> Result<Box<dyn SpanContents<'a> + 'a>, MietteError> {
        let Indexed { text, lines } = &*self.0;
        let start = span.offset().min(text.len());
        let end = (span.offset() + span.len()).min(text.len());
        // A window of whole lines, one more on each side than miette asks for (it looks at
        // the byte before an empty span, and scans to the end of the last context line),
        // so its scan sees what it would have seen in the whole file.
        let first = lines
            .line_of(start)
            .saturating_sub(context_lines_before + 1);
        let last = lines.line_of(end) + context_lines_after + 2;
        let from = lines.line_start(first).unwrap_or(0);
        let to = lines.line_start(last).unwrap_or(text.len());
        let window = &text.as_bytes()[from..to];
        let local = SourceSpan::new((start - from).into(), span.len().min(to - start));
        let inner = window.read_span(&local, context_lines_before, context_lines_after)?;
        let inner_span = inner.span();
        Ok(Box::new(MietteSpanContents::new(
            inner.data(),
            SourceSpan::new((inner_span.offset() + from).into(), inner_span.len()),
            inner.line() + first,
            inner.column(),
            inner.line_count() + first,
        )))
    }
}

/// Every file of a rendering, neutralised and indexed on first use.
pub struct Sources<'s> {
    map: &'s SourceMap,
    files: Vec<Option<Shared>>,
    neutralize: fn(&str) -> String,
}

impl<'s> Sources<'s> {
    /// The files of `map`; `neutralize` turns a file's text into what snippets may show
    /// (same length, same line breaks).
    pub fn new(map: &'s SourceMap, neutralize: fn(&str) -> String) -> Sources<'s> {
        Sources {
            map,
            files: vec![None; map.iter().count()],
            neutralize,
        }
    }

    /// The source of `file`, indexed once.
    pub fn get(&mut self, file: FileId) -> Shared {
        let slot = &mut self.files[file.0 as usize];
        if let Some(shared) = slot {
            return shared.clone();
        }
        let text = (self.neutralize)(&self.map.get(file).text);
        let lines = LineIndex::new(&text);
        let shared = Shared(Arc::new(Indexed { text, lines }));
        *slot = Some(shared.clone());
        shared
    }

    /// The length of the longest line a snippet of `start..end` in `file` would show,
    /// when it is over [`MAX_SHOWN_LINE_BYTES`].
    pub fn too_long(&mut self, file: FileId, start: usize, end: usize) -> Option<usize> {
        let shared = self.get(file);
        let Indexed { text, lines } = &*shared.0;
        let first = lines
            .line_of(start.min(text.len()))
            .saturating_sub(CONTEXT_LINES);
        let last = lines.line_of(end.min(text.len())) + CONTEXT_LINES;
        (first..=last.min(lines.n_lines() - 1))
            .map(|line| {
                let from = lines.line_start(line).unwrap_or(text.len());
                let to = lines.line_start(line + 1).unwrap_or(text.len());
                to - from
            })
            .max()
            .filter(|&longest| longest > MAX_SHOWN_LINE_BYTES)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A window gives miette's answer on the whole text, in the whole text's coordinates.
    #[test]
    fn windows_read_as_the_whole_file_does() {
        let text = "cell c {\n  workspace w1\r\n  workspace w2\n\n  fixed t reaches w1\n}";
        let mut map = SourceMap::new();
        let id = map.add("c.cell", text);
        let mut sources = Sources::new(&map, str::to_string);
        let shared = sources.get(id);
        for start in 0..text.len() {
            for len in [0, 1, 5, 20] {
                let len = len.min(text.len() - start);
                let span = SourceSpan::new(start.into(), len);
                for (before, after) in [(0, 0), (1, 1), (2, 3)] {
                    let ours = shared.read_span(&span, before, after).expect("in range");
                    let theirs = text.read_span(&span, before, after).expect("in range");
                    assert_eq!(ours.data(), theirs.data(), "{start}+{len} {before}/{after}");
                    assert_eq!(ours.span(), theirs.span());
                    assert_eq!(ours.line(), theirs.line());
                    assert_eq!(ours.column(), theirs.column());
                    assert_eq!(ours.line_count(), theirs.line_count());
                }
            }
        }
        assert_eq!(sources.too_long(id, 3, 4), None);
        let long = format!("cell c {{\n  reaches {}\n}}", "w, ".repeat(400));
        let id = map.add("long.cell", long);
        let mut sources = Sources::new(&map, str::to_string);
        assert_eq!(sources.too_long(id, 0, 1), Some(1211));
    }
}
