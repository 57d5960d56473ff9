//! Byte offsets to LSP positions and back.
//!
//! Spans are byte offsets into UTF-8 text; the protocol counts lines from 0 and columns
//! in UTF-16 code units (its default position encoding, the only one every client
//! supports). A character outside the Basic Multilingual Plane is one `char`, four bytes
//! and two UTF-16 units, so neither bytes nor chars would do.

use cellc_lang::Span;
use lsp_types::{Position, Range};

/// Where each line of a text starts, to convert offsets in logarithmic time.
pub struct Lines<'a> {
    text: &'a str,
    starts: Vec<usize>,
}

impl<'a> Lines<'a> {
    /// Indexes `text` (one pass).
    pub fn new(text: &'a str) -> Lines<'a> {
        let mut starts = vec![0];
        starts.extend(
            text.bytes()
                .enumerate()
                .filter(|&(_, b)| b == b'\n')
                .map(|(i, _)| i + 1),
        );
        Lines { text, starts }
    }

    /// The position of byte `offset` (clamped to the text, and down to a char boundary).
    pub fn position(&self, offset: usize) -> Position {
        let mut offset = offset.min(self.text.len());
        while !self.text.is_char_boundary(offset) {
            offset -= 1;
        }
        let line = self.starts.partition_point(|&s| s <= offset) - 1;
        let start = self.starts[line];
        let character: usize = self.text[start..offset].chars().map(char::len_utf16).sum();
        Position::new(line as u32, character as u32)
    }

    /// The range of a byte span.
    pub fn range(&self, span: Span) -> Range {
        Range::new(
            self.position(span.start as usize),
            self.position(span.end as usize),
        )
    }

    /// The byte offset of `position`: a line past the end is the end of the text, a
    /// column past the end of its line is the line's end (as the protocol asks).
    pub fn offset(&self, position: Position) -> usize {
        let Some(&start) = self.starts.get(position.line as usize) else {
            return self.text.len();
        };
        let end = self
            .starts
            .get(position.line as usize + 1)
            .map_or(self.text.len(), |&next| next - 1);
        let mut units = 0;
        for (i, c) in self.text[start..end].char_indices() {
            if units >= position.character as usize {
                return start + i;
            }
            units += c.len_utf16();
        }
        end
    }

    /// The position just past the last character.
    pub fn end(&self) -> Position {
        self.position(self.text.len())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn columns_count_utf16_units() {
        // `é` is 2 bytes and 1 unit; `𝔸` is 4 bytes and 2 units.
        let text = "ab\né𝔸x\n";
        let lines = Lines::new(text);
        assert_eq!(lines.position(0), Position::new(0, 0));
        assert_eq!(lines.position(2), Position::new(0, 2));
        assert_eq!(lines.position(3), Position::new(1, 0));
        assert_eq!(lines.position(5), Position::new(1, 1));
        let x = text.find('x').unwrap_or_default();
        assert_eq!(lines.position(x), Position::new(1, 3));
        assert_eq!(lines.offset(Position::new(1, 3)), x);
        assert_eq!(lines.offset(Position::new(1, 1)), 5);
        assert_eq!(lines.end(), Position::new(2, 0));
    }

    #[test]
    fn out_of_range_positions_are_clamped() {
        let text = "ab\ncd";
        let lines = Lines::new(text);
        assert_eq!(lines.offset(Position::new(0, 99)), 2);
        assert_eq!(lines.offset(Position::new(9, 0)), text.len());
        assert_eq!(lines.position(99), Position::new(1, 2));
        // Inside a multi-byte character: the character's start.
        assert_eq!(Lines::new("é").position(1), Position::new(0, 0));
    }

    #[test]
    fn round_trips_every_char_boundary() {
        let text = "cell c {\n  // ü 𝔸\n  workspace w box (0, 0, 0) .. (1, 1, 1)\n}\n";
        let lines = Lines::new(text);
        for (i, _) in text.char_indices() {
            assert_eq!(lines.offset(lines.position(i)), i);
        }
    }
}
