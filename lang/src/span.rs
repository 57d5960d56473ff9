//! Byte spans and the table of source files they point into.

use std::fmt;
use std::sync::OnceLock;

/// A half-open byte range `start..end` in one source file.
///
/// Spans are plain offsets rather than line/column pairs because every consumer
/// (miette, the JSON output, the formatter's comment placement) wants offsets, and
/// line/column is cheap to recompute from the text when a human needs it.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Default, PartialOrd, Ord)]
pub struct Span {
    /// First byte of the range.
    pub start: u32,
    /// One past the last byte of the range.
    pub end: u32,
}

impl Span {
    /// A span from byte offsets.
    pub fn new(start: usize, end: usize) -> Span {
        Span {
            start: start as u32,
            end: end as u32,
        }
    }

    /// The smallest span covering both.
    pub fn join(self, other: Span) -> Span {
        Span {
            start: self.start.min(other.start),
            end: self.end.max(other.end),
        }
    }

    /// Byte length of the span.
    pub fn len(self) -> usize {
        (self.end - self.start) as usize
    }

    /// True for a zero-width span (used for "expected here" positions).
    pub fn is_empty(self) -> bool {
        self.start == self.end
    }

    /// As a `Range<usize>` for slicing the source text.
    pub fn range(self) -> std::ops::Range<usize> {
        self.start as usize..self.end as usize
    }
}

// Debug prints `12..34` so that syntax-tree dumps stay short, and so the round-trip test
// can strip spans with one pattern when it compares trees that differ only in layout.
impl fmt::Debug for Span {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "@{}..{}", self.start, self.end)
    }
}

/// Index of a file in a [`SourceMap`].
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug, PartialOrd, Ord)]
pub struct FileId(pub u32);

/// One source file: the path it was read from (as the user wrote or the include resolved
/// it) and its full text.
#[derive(Clone, Debug)]
pub struct SourceFile {
    /// Path as displayed in diagnostics.
    pub path: String,
    /// Full text.
    pub text: String,
    /// Where lines start, built on first use.
    index: OnceLock<LineIndex>,
}

impl SourceFile {
    /// 1-based line and column (in characters) of a byte offset, in logarithmic time (a
    /// file with a hundred thousand diagnostics must not be scanned once for each).
    pub fn line_col(&self, offset: u32) -> (usize, usize) {
        self.lines().line_col(&self.text, offset as usize)
    }

    /// The file's line index.
    pub fn lines(&self) -> &LineIndex {
        self.index.get_or_init(|| LineIndex::new(&self.text))
    }
}

/// Bytes between two character-count checkpoints of a [`LineIndex`].
const CHECKPOINT_BYTES: usize = 1024;

/// The start of every line of a text, and how many characters precede every 1 KiB, so that
/// a line and a column (in characters, however long the line) cost a binary search and at
/// most 1 KiB of counting.
#[derive(Clone, Debug)]
pub struct LineIndex {
    /// Byte offset of each line's first byte; the first is 0.
    starts: Vec<usize>,
    /// `chars[k]` = characters before the char boundary at or below `k` KiB.
    chars: Vec<usize>,
}

impl LineIndex {
    /// Indexes `text` (one pass).
    pub fn new(text: &str) -> LineIndex {
        let mut starts = vec![0];
        starts.extend(
            text.bytes()
                .enumerate()
                .filter(|&(_, b)| b == b'\n')
                .map(|(i, _)| i + 1),
        );
        let mut chars = Vec::with_capacity(text.len() / CHECKPOINT_BYTES + 1);
        let mut count = 0;
        let mut at = 0;
        for k in 0..=text.len() / CHECKPOINT_BYTES {
            let boundary = floor_char_boundary(text, k * CHECKPOINT_BYTES);
            count += text[at..boundary].chars().count();
            at = boundary;
            chars.push(count);
        }
        LineIndex { starts, chars }
    }

    /// The 0-based line that holds byte `offset`.
    pub fn line_of(&self, offset: usize) -> usize {
        self.starts
            .partition_point(|&s| s <= offset)
            .saturating_sub(1)
    }

    /// The byte offset where 0-based `line` starts (the text's length past the last line).
    pub fn line_start(&self, line: usize) -> Option<usize> {
        self.starts.get(line).copied()
    }

    /// The number of lines (a text without a line break has one).
    pub fn n_lines(&self) -> usize {
        self.starts.len()
    }

    /// Characters of `text` (the indexed text) before byte `offset`.
    fn chars_before(&self, text: &str, offset: usize) -> usize {
        let k = (offset / CHECKPOINT_BYTES).min(self.chars.len().saturating_sub(1));
        let from = floor_char_boundary(text, k * CHECKPOINT_BYTES);
        self.chars.get(k).copied().unwrap_or(0) + text[from..offset.max(from)].chars().count()
    }

    /// 1-based line and column (in characters) of byte `offset` of `text` (the indexed
    /// text), clamped to the text and to a char boundary.
    pub fn line_col(&self, text: &str, offset: usize) -> (usize, usize) {
        let offset = floor_char_boundary(text, offset);
        let line = self.line_of(offset);
        let start = self.starts[line];
        let col = self.chars_before(text, offset) - self.chars_before(text, start) + 1;
        (line + 1, col)
    }
}

/// The largest char boundary at or below `offset` (spans from pest are always on
/// boundaries, but spans built by arithmetic in diagnostics might not be).
pub fn floor_char_boundary(text: &str, mut offset: usize) -> usize {
    offset = offset.min(text.len());
    while !text.is_char_boundary(offset) {
        offset -= 1;
    }
    offset
}

/// Every source file a compilation read, addressed by [`FileId`].
#[derive(Clone, Debug, Default)]
pub struct SourceMap {
    files: Vec<SourceFile>,
}

impl SourceMap {
    /// An empty map.
    pub fn new() -> SourceMap {
        SourceMap::default()
    }

    /// Adds a file and returns its id.
    pub fn add(&mut self, path: impl Into<String>, text: impl Into<String>) -> FileId {
        self.files.push(SourceFile {
            path: path.into(),
            text: text.into(),
            index: OnceLock::new(),
        });
        FileId(self.files.len() as u32 - 1)
    }

    /// How many files it holds (the next file added gets this id).
    pub fn len(&self) -> usize {
        self.files.len()
    }

    /// True when it holds no file.
    pub fn is_empty(&self) -> bool {
        self.files.is_empty()
    }

    /// The file behind an id.
    pub fn get(&self, id: FileId) -> &SourceFile {
        &self.files[id.0 as usize]
    }

    /// All files with their ids, in the order they were added.
    pub fn iter(&self) -> impl Iterator<Item = (FileId, &SourceFile)> {
        self.files
            .iter()
            .enumerate()
            .map(|(i, f)| (FileId(i as u32), f))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The plain count the index must agree with.
    fn naive(text: &str, offset: usize) -> (usize, usize) {
        let before = &text[..floor_char_boundary(text, offset)];
        let line = before.matches('\n').count() + 1;
        let start = before.rfind('\n').map_or(0, |i| i + 1);
        (line, before[start..].chars().count() + 1)
    }

    #[test]
    fn line_index_agrees_with_counting() {
        let long: String = "é∑x".repeat(900);
        let text = format!("cell c {{\n  // ünïcode\n{long}\n\nend");
        let mut map = SourceMap::new();
        let id = map.add("a.cell", text.clone());
        let file = map.get(id);
        for offset in (0..text.len() + 3).step_by(7).chain([text.len()]) {
            assert_eq!(
                file.line_col(offset as u32),
                naive(&text, offset),
                "{offset}"
            );
        }
        assert_eq!(file.lines().n_lines(), 5);
        assert_eq!(file.lines().line_start(1), Some(9));
    }
}
