//! The one canonical layout of cell files (`cellc fmt`).
//!
//! The layout is fixed so that diffs show changes of meaning, not of taste:
//!
//! - two spaces of indentation per block level, one item or object member per line;
//! - `cell NAME {` ... `}`, `object NAME {` ... `}` with the members inside, `world {` and
//!   `task NAME {` with one line per object or step inside, and an empty block written
//!   `{}`;
//! - `hand NAME { SOLID }` on one line when the hand has one solid, one solid per line
//!   inside the block when it has more;
//! - single spaces between tokens, lists as `a, b, c` (no trailing comma), vectors as
//!   `(x, y, z)`, a unit after its number and a space (`90 deg`), `: ` after an expectation's
//!   object and ` : ` around a surface's kind, as in the examples;
//! - numbers keep the spelling the user wrote (`0.10` stays `0.10`: the tree keeps the
//!   spelling precisely so that formatting never touches a value), strings are re-escaped,
//!   names that are not plain identifiers, or are reserved words, are written in backticks;
//! - items stay in the order written, and lines are never wrapped.
//!
//! The grammar drops comments, so they are recovered from the source text and placed by
//! byte position against the spans of the tree:
//!
//! - comments on their own lines before an item or member stay above it, at its
//!   indentation;
//! - comments on the line where an item, a member or a block's `{` or `}` ends stay at the
//!   end of that line;
//! - comments before a block's `}` stay at the end of the block, comments before `cell`
//!   stay at the top, comments after the last `}` stay at the bottom;
//! - comments inside an item (between its tokens) cannot keep their place when the item is
//!   laid out again, so they move to their own lines just above the item.
//!
//! Every comment is taken exactly once, by a cursor that only moves forward through the
//! comments in source order; whatever the walk of the tree did not claim (only possible
//! when the tree does not match the text) is printed at the end. So no comment is ever
//! lost or duplicated, whatever tree and text this is given.
//!
//! One blank line is kept where the source had one or more blank lines between two items,
//! members or own-line comments, so that users can group items; there is never a blank
//! line right after a `{` or right before a `}`.

mod text;
pub use text::string_literal;

use crate::ast::*;
use crate::span::Span;
use text::{item_text, member_text, name, solid, task_step_text, world_entry_text};

/// Formats a file in the canonical layout, keeping the comments of `source`.
///
/// `source` must be the text `file` was parsed from: it is where the comments come from,
/// and the tree's spans say where they go. Call this only on files that parsed without
/// diagnostics (a tree with recovered items would silently lose them); on any other tree
/// it still returns some text and never panics.
pub fn format(file: &File, source: &str) -> String {
    let mut printer = Printer::new(source);
    printer.file(file);
    printer.out
}

// ---- comments --------------------------------------------------------------------------

/// A comment in the source: byte range, and whether it is a `//` line comment (which must
/// end its output line).
#[derive(Clone, Copy, Debug)]
struct Comment {
    start: usize,
    end: usize,
    line: bool,
}

/// Every comment in `source`, in order. String literals and backtick-quoted names are
/// skipped so that `"http://host"` is not a comment. A string or quoted name also stops at
/// the end of its line (neither may span lines), so that broken text cannot hide the rest
/// of the file from the scan.
fn scan_comments(source: &str) -> Vec<Comment> {
    let bytes = source.as_bytes();
    let mut comments = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        match bytes[i] {
            b'/' if bytes.get(i + 1) == Some(&b'/') => {
                let start = i;
                while i < bytes.len() && bytes[i] != b'\n' {
                    i += 1;
                }
                comments.push(Comment {
                    start,
                    end: i,
                    line: true,
                });
            }
            b'/' if bytes.get(i + 1) == Some(&b'*') => {
                let start = i;
                i += 2;
                while i < bytes.len() && !(bytes[i] == b'*' && bytes.get(i + 1) == Some(&b'/')) {
                    i += 1;
                }
                i = (i + 2).min(bytes.len());
                comments.push(Comment {
                    start,
                    end: i,
                    line: false,
                });
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
            _ => i += 1,
        }
    }
    comments
}

// ---- the printer -----------------------------------------------------------------------

/// Walks the tree in source order, printing lines and claiming comments as it goes.
struct Printer<'s> {
    source: &'s str,
    comments: Vec<Comment>,
    /// The first comment not yet printed.
    next: usize,
    out: String,
    /// End in the source of the last thing printed (item, member, comment, `{`): blank
    /// lines are looked for between it and the next thing.
    last_end: usize,
    /// Nothing has been printed yet in the current block, so no blank line may come next.
    block_start: bool,
    /// The next line printed gets a blank line before it.
    blank_next: bool,
}

/// A block (the cell, an object, a multi-solid hand) as the printer needs it.
struct Block<'t, 's, T> {
    /// Indentation depth of the header and of the `}`.
    depth: usize,
    /// The header without its `{`.
    header: String,
    /// Where the `{` is in the source.
    open: usize,
    /// Where the `}` is in the source.
    close: usize,
    /// Just after the `}`: where the block's trailing comments start.
    end: usize,
    /// Trailing comments of the `}` line must start before this (the next sibling).
    limit: usize,
    children: &'t [T],
    span: fn(&T) -> Span,
    /// Prints one child at the given depth; its trailing comments start before the limit.
    print: fn(&mut Printer<'s>, &T, usize, usize),
}

impl<'s> Printer<'s> {
    fn new(source: &'s str) -> Printer<'s> {
        Printer {
            source,
            comments: scan_comments(source),
            next: 0,
            out: String::with_capacity(source.len() + 64),
            last_end: 0,
            block_start: true,
            blank_next: false,
        }
    }

    fn file(&mut self, file: &File) {
        let keyword = self.next_token(0);
        let open = self.next_token(file.name.span.end as usize);
        let close = (file.span.end as usize).saturating_sub(1);
        // Comments before `cell` are the file's header comments.
        let top = self.take_before(keyword);
        self.own_line_comments(0, top);
        self.group_blank(keyword);
        let kind = match file.kind {
            FileKind::Cell => "cell",
            FileKind::Library => "library",
        };
        self.block(Block {
            depth: 0,
            header: format!("{kind} {}", name(&file.name)),
            open,
            close,
            end: file.span.end as usize,
            limit: usize::MAX,
            children: &file.items,
            span: Item::span,
            print: Printer::item,
        });
        // Comments after the last `}`, and any the walk could not place.
        let rest = self.take_before(usize::MAX);
        self.own_line_comments(0, rest);
    }

    fn item(&mut self, item: &Item, depth: usize, limit: usize) {
        match item {
            Item::Object(object) => {
                let open = self.next_token(object.name.span.end as usize);
                self.block(Block {
                    depth,
                    header: format!("object {}", name(&object.name)),
                    open,
                    close: (object.span.end as usize).saturating_sub(1),
                    end: object.span.end as usize,
                    limit,
                    children: &object.members,
                    span: ObjectMember::span,
                    print: |printer, member, depth, limit| {
                        printer.simple(depth, member.span(), member_text(member), limit)
                    },
                });
            }
            Item::Hand(hand) if hand.solids.len() > 1 => {
                let open = self.next_token(hand.name.span.end as usize);
                self.block(Block {
                    depth,
                    header: format!("hand {}", name(&hand.name)),
                    open,
                    close: (hand.span.end as usize).saturating_sub(1),
                    end: hand.span.end as usize,
                    limit,
                    children: &hand.solids,
                    span: |solid| solid.span,
                    print: |printer, s, depth, limit| {
                        printer.simple(depth, s.span, solid(s), limit)
                    },
                });
            }
            Item::World(world) => {
                let open = self.next_token(world.span.start as usize + "world".len());
                self.block(Block {
                    depth,
                    header: "world".to_string(),
                    open,
                    close: (world.span.end as usize).saturating_sub(1),
                    end: world.span.end as usize,
                    limit,
                    children: &world.entries,
                    span: |entry| entry.span,
                    print: |printer, entry, depth, limit| {
                        printer.simple(depth, entry.span, world_entry_text(entry), limit)
                    },
                });
            }
            Item::Task(task) => {
                let open = self.next_token(task.name.span.end as usize);
                self.block(Block {
                    depth,
                    header: format!("task {}", name(&task.name)),
                    open,
                    close: (task.span.end as usize).saturating_sub(1),
                    end: task.span.end as usize,
                    limit,
                    children: &task.steps,
                    span: |step| step.span,
                    print: |printer, step, depth, limit| {
                        printer.simple(depth, step.span, task_step_text(step), limit)
                    },
                });
            }
            _ => self.simple(depth, item.span(), item_text(item), limit),
        }
    }

    /// Prints an item or member laid out on one line, with the comments inside it above it
    /// and the comments after it on its line.
    fn simple(&mut self, depth: usize, span: Span, text: String, limit: usize) {
        let end = span.end as usize;
        let inside = self.take_before(end);
        self.moved_comments(depth, inside);
        let trailing = self.take_trailing(end, limit);
        let text = self.with_trailing(text, &trailing);
        self.line(depth, &text);
        self.last_end = trailing.last().map_or(end, |c| c.end);
    }

    fn block<T>(&mut self, block: Block<'_, 's, T>) {
        let Block {
            depth,
            header,
            open,
            close,
            end,
            limit,
            children,
            span,
            print,
        } = block;
        // Comments between the keyword and the `{` cannot stay there.
        let inside_header = self.take_before(open);
        self.moved_comments(depth, inside_header);
        if children.is_empty() && !self.has_comment_before(close) {
            let trailing = self.take_trailing(end, limit);
            let text = self.with_trailing(format!("{header} {{}}"), &trailing);
            self.line(depth, &text);
            self.last_end = trailing.last().map_or(end, |c| c.end);
            return;
        }
        let first = children.first().map_or(close, |c| span(c).start as usize);
        let trailing = self.take_trailing(open + 1, first);
        let text = self.with_trailing(format!("{header} {{"), &trailing);
        self.line(depth, &text);
        self.last_end = trailing.last().map_or(open + 1, |c| c.end);
        self.block_start = true;
        for (i, child) in children.iter().enumerate() {
            let start = span(child).start as usize;
            let child_limit = children
                .get(i + 1)
                .map_or(close, |c| span(c).start as usize);
            let leading = self.take_before(start);
            self.own_line_comments(depth + 1, leading);
            self.group_blank(start);
            print(self, child, depth + 1, child_limit);
        }
        let at_end = self.take_before(close);
        self.own_line_comments(depth + 1, at_end);
        self.block_start = false;
        self.blank_next = false;
        let trailing = self.take_trailing(end, limit);
        let text = self.with_trailing("}".to_string(), &trailing);
        self.line(depth, &text);
        self.last_end = trailing.last().map_or(end, |c| c.end);
    }

    // ---- lines and blank lines ---------------------------------------------------------

    fn line(&mut self, depth: usize, text: &str) {
        if std::mem::take(&mut self.blank_next) && !self.out.is_empty() {
            self.out.push('\n');
        }
        for _ in 0..depth {
            self.out.push_str("  ");
        }
        self.out.push_str(text);
        self.out.push('\n');
    }

    /// Decides whether the thing starting at `start` gets a blank line before it: one where
    /// the source had a blank line since the last thing printed, never first in a block.
    fn group_blank(&mut self, start: usize) {
        if std::mem::take(&mut self.block_start) {
            return;
        }
        if self.blank_between(self.last_end, start) {
            self.blank_next = true;
        }
    }

    /// Comments that stood on their own lines: each keeps a blank line above it if it had
    /// one.
    fn own_line_comments(&mut self, depth: usize, comments: Vec<Comment>) {
        for comment in comments {
            self.group_blank(comment.start);
            let text = self.comment_text(comment).to_string();
            self.line(depth, &text);
            self.last_end = comment.end;
        }
    }

    /// Comments moved out of an item to just above it. They take the item's blank line
    /// (already decided) and add none: the next format sees them as leading comments and
    /// must lay them out the same way.
    fn moved_comments(&mut self, depth: usize, comments: Vec<Comment>) {
        for comment in comments {
            let text = self.comment_text(comment).to_string();
            self.line(depth, &text);
        }
    }

    fn with_trailing(&self, mut text: String, trailing: &[Comment]) -> String {
        for comment in trailing {
            text.push(' ');
            text.push_str(self.comment_text(*comment));
        }
        text
    }

    /// True when the source between `from` and `to`, comments aside, holds an empty line.
    fn blank_between(&self, from: usize, to: usize) -> bool {
        let bytes = self.source.as_bytes();
        let to = to.min(bytes.len());
        let mut k = self.comments.partition_point(|c| c.end <= from);
        let mut newlines = 0;
        let mut i = from;
        while i < to {
            if let Some(comment) = self.comments.get(k).filter(|c| c.start <= i) {
                i = i.max(comment.end);
                k += 1;
                newlines = 0;
                continue;
            }
            match bytes[i] {
                b'\n' => {
                    newlines += 1;
                    if newlines >= 2 {
                        return true;
                    }
                }
                b' ' | b'\t' | b'\r' => {}
                _ => newlines = 0,
            }
            i += 1;
        }
        false
    }

    // ---- claiming comments -------------------------------------------------------------

    /// Claims every unclaimed comment that starts before `pos`.
    fn take_before(&mut self, pos: usize) -> Vec<Comment> {
        let from = self.next;
        while self.comments.get(self.next).is_some_and(|c| c.start < pos) {
            self.next += 1;
        }
        self.comments[from..self.next].to_vec()
    }

    /// Claims the comments that start after `end` on the same line (and before `limit`,
    /// where the next thing starts).
    fn take_trailing(&mut self, end: usize, limit: usize) -> Vec<Comment> {
        let from = self.next;
        while let Some(comment) = self.comments.get(self.next) {
            let gap = self.source.get(end..comment.start);
            let same_line = gap.is_some_and(|gap| !gap.contains('\n'));
            if comment.start >= limit || !same_line {
                break;
            }
            self.next += 1;
        }
        self.comments[from..self.next].to_vec()
    }

    fn has_comment_before(&self, pos: usize) -> bool {
        self.comments.get(self.next).is_some_and(|c| c.start < pos)
    }

    /// The text of a comment as printed: line comments lose trailing white space (a `\r`
    /// of a CRLF file included), block comments are kept byte for byte.
    fn comment_text(&self, comment: Comment) -> &'s str {
        let text = self.source.get(comment.start..comment.end).unwrap_or("");
        if comment.line {
            text.trim_end()
        } else {
            text
        }
    }

    /// The first position at or after `pos` that is neither white space nor comment: where
    /// the next token starts (used to find `cell` and the `{` of blocks, which the tree
    /// has no spans for).
    fn next_token(&self, pos: usize) -> usize {
        let bytes = self.source.as_bytes();
        let mut k = self.comments.partition_point(|c| c.end <= pos);
        let mut i = pos;
        while i < bytes.len() {
            if let Some(comment) = self.comments.get(k).filter(|c| c.start <= i) {
                i = i.max(comment.end);
                k += 1;
                continue;
            }
            if !bytes[i].is_ascii_whitespace() {
                return i;
            }
            i += 1;
        }
        i.max(pos)
    }
}
