//! What is refused before the grammar sees a text: files that are not cells at all,
//! control characters, and nesting deep enough to exhaust the stack.
//!
//! A cell under review may include any path (`include "/etc/passwd"`), and a syntax error
//! shows the lines around it, so a file that is not a cell must be recognised as such
//! before it is parsed, and described by what it is, never by what it holds. The tests
//! here are cheap (one pass over the bytes) and conservative: a file that begins with the
//! word `cell` or `library` is a cell with mistakes in it, and its errors are shown as
//! usual.

use crate::span::Span;

/// How deep `{ ... }` blocks may nest before the parser refuses the file. Real cells nest
/// two levels; the limit only keeps hostile input from exhausting the stack.
pub const MAX_NESTING: usize = 64;

/// At most this many control characters are reported in one file; the first ones are
/// enough to find the problem (a file full of them is not a cell, and is refused whole).
pub const MAX_REPORTED_CONTROLS: usize = 16;

/// Why a text is not a cell file at all.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum NotACell {
    /// Nothing but blanks and comments.
    Empty,
    /// A NUL byte: binary data, not text.
    Binary {
        /// The offset of the first NUL byte.
        nul_at: usize,
    },
    /// Text that does not begin with `cell NAME {` or `library NAME {`.
    NoOutline,
}

/// Whether `text` is something other than a cell file (see [`NotACell`]); `None` for a
/// text that is meant to be one, mistakes and all.
pub fn not_a_cell(text: &str) -> Option<NotACell> {
    if let Some(nul_at) = text.bytes().position(|b| b == 0) {
        return Some(NotACell::Binary { nul_at });
    }
    let rest = skip_trivia(text);
    if rest.is_empty() {
        return Some(NotACell::Empty);
    }
    let word_end = rest
        .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
        .unwrap_or(rest.len());
    match &rest[..word_end] {
        "cell" | "library" => None,
        _ => Some(NotACell::NoOutline),
    }
}

/// The text after leading blanks, byte-order marks and comments.
fn skip_trivia(mut text: &str) -> &str {
    loop {
        let trimmed = text.trim_start_matches([' ', '\t', '\r', '\n', '\u{FEFF}']);
        if let Some(comment) = trimmed.strip_prefix("//") {
            text = comment.find('\n').map_or("", |i| &comment[i..]);
        } else if let Some(comment) = trimmed.strip_prefix("/*") {
            text = comment.find("*/").map_or("", |i| &comment[i + 2..]);
        } else {
            return trimmed;
        }
    }
}

/// The control characters of a text, each as the span of one run of them: every C0 and C1
/// control and DEL, except tab, line feed, and a carriage return before a line feed. At
/// most [`MAX_REPORTED_CONTROLS`] runs; the count of all runs comes second.
pub fn control_characters(text: &str) -> (Vec<Span>, usize) {
    let mut runs: Vec<Span> = Vec::new();
    let mut count = 0;
    let mut run: Option<(usize, usize)> = None;
    let mut chars = text.char_indices().peekable();
    while let Some((i, c)) = chars.next() {
        let allowed = match c {
            '\t' | '\n' => true,
            '\r' => chars.peek().is_some_and(|&(_, next)| next == '\n'),
            _ => !c.is_control(),
        };
        if allowed {
            if let Some((start, end)) = run.take() {
                count += 1;
                if runs.len() < MAX_REPORTED_CONTROLS {
                    runs.push(Span::new(start, end));
                }
            }
            continue;
        }
        let end = i + c.len_utf8();
        run = Some(match run {
            Some((start, _)) => (start, end),
            None => (i, end),
        });
    }
    if let Some((start, end)) = run {
        count += 1;
        if runs.len() < MAX_REPORTED_CONTROLS {
            runs.push(Span::new(start, end));
        }
    }
    (runs, count)
}

/// The offset of the first `{` nested deeper than [`MAX_NESTING`], ignoring braces in
/// comments, strings and quoted names.
pub(crate) fn too_deep_at(text: &str) -> Option<usize> {
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tells_cells_from_other_files() {
        assert_eq!(not_a_cell("cell c {}"), None);
        assert_eq!(
            not_a_cell("\u{FEFF}// a comment\n/* x */ library l { oops"),
            None
        );
        assert_eq!(not_a_cell("cel c {}"), Some(NotACell::NoOutline));
        assert_eq!(
            not_a_cell("root:x:0:0:root:/root:/bin/bash\n"),
            Some(NotACell::NoOutline)
        );
        assert_eq!(not_a_cell("cellar {}"), Some(NotACell::NoOutline));
        assert_eq!(not_a_cell("  // only a comment"), Some(NotACell::Empty));
        assert_eq!(not_a_cell("/* unclosed"), Some(NotACell::Empty));
        assert_eq!(
            not_a_cell("cell c {\0}"),
            Some(NotACell::Binary { nul_at: 8 })
        );
    }

    #[test]
    fn finds_runs_of_control_characters() {
        let (runs, count) = control_characters("a\tb\r\nc\x1b[31md\re\u{85}");
        assert_eq!(
            runs,
            [Span::new(6, 7), Span::new(12, 13), Span::new(14, 16)]
        );
        assert_eq!(count, 3);
        let many = "\x07 ".repeat(40);
        let (runs, count) = control_characters(&many);
        assert_eq!((runs.len(), count), (MAX_REPORTED_CONTROLS, 40));
    }
}
