//! Text to syntax tree, reporting every syntax error it can in one run.
//!
//! pest stops at the first error, so recovery is built into the grammar: an item that
//! does not parse is swallowed by the `recover` rule (to the end of its line, or over a
//! whole `{ ... }` block) and the parse goes on. Each recovered region is then parsed
//! again alone with a probe rule, and pest's report of what it expected there is turned
//! into words by [`crate::phrases`].

use std::sync::{Mutex, PoisonError};

use pest::iterators::Pair;
use pest::Parser as _;

use crate::ast::*;
use crate::diagnostic::Diagnostic;
use crate::grammar::{CellParser, Rule};
use crate::phrases;
use crate::span::{FileId, Span};

mod items;
mod values;
mod world;

/// The result of parsing one file: the tree (absent only when the file's outline
/// `cell NAME { ... }` itself is broken) and every syntax diagnostic.
#[derive(Debug)]
pub struct Parsed {
    /// The syntax tree, with the items that parsed.
    pub file: Option<File>,
    /// Syntax errors, in source order.
    pub diagnostics: Vec<Diagnostic>,
}

/// Serialises the parses that need pest's error detail (see [`detailed`]).
static DETAIL: Mutex<()> = Mutex::new(());

/// Runs `parse` with pest's error detail on: the rules attempted at the farthest position,
/// which [`phrases`] words an error with. Recording them costs about a quarter of a parse,
/// and only a parse that fails needs them, so a file is parsed without them first and a
/// failing parse is run again with them. The switch is global to the process (threads of
/// `cellc lsp` and `cellc serve` parse at once), so it is only ever turned on and off
/// under [`DETAIL`]; a parse on another thread meanwhile is the same parse, only slower:
/// the detail changes what an error records, never whether a text parses.
fn detailed<T>(parse: impl FnOnce() -> T) -> T {
    let _only_one = DETAIL.lock().unwrap_or_else(PoisonError::into_inner);
    pest::set_error_detail(true);
    let out = parse();
    pest::set_error_detail(false);
    out
}

/// Parses one file's text.
pub fn parse(file_id: FileId, text: &str) -> Parsed {
    let mut diagnostics = Vec::new();
    let parsed = CellParser::parse(Rule::file, text)
        .or_else(|_| detailed(|| CellParser::parse(Rule::file, text)));
    let pairs = match parsed {
        Ok(pairs) => pairs,
        Err(error) => {
            diagnostics.push(phrases::syntax_error(file_id, text, 0, &error));
            return Parsed {
                file: None,
                diagnostics,
            };
        }
    };
    let mut builder = Builder {
        file_id,
        text,
        diagnostics: &mut diagnostics,
    };
    let file = pairs.into_iter().next().and_then(|pair| builder.file(pair));
    if file.is_none() && diagnostics.is_empty() {
        diagnostics.push(phrases::internal(file_id, Span::new(0, text.len())));
    }
    diagnostics.sort_by_key(|d| d.primary_label().map(|l| l.span.start));
    Parsed { file, diagnostics }
}

/// Parses a placement on its own (`table.g1 in w1`, `table at (0.5, 0, 0.8) rpy (0, 0,
/// 90)`), as given on the command line.
pub fn parse_placement(file_id: FileId, text: &str) -> Result<RequestPlacement, Diagnostic> {
    let pairs = detailed(|| CellParser::parse(Rule::placement_arg, text))
        .map_err(|error| phrases::syntax_error(file_id, text, 0, &error))?;
    let mut diagnostics = Vec::new();
    let mut builder = Builder {
        file_id,
        text,
        diagnostics: &mut diagnostics,
    };
    let placement = pairs
        .into_iter()
        .next()
        .and_then(|p| p.into_inner().next())
        .and_then(|p| builder.request_placement(p));
    match (placement, diagnostics.pop()) {
        (Some(p), None) => Ok(p),
        (_, Some(d)) => Err(d),
        (None, None) => Err(phrases::internal(file_id, Span::new(0, text.len()))),
    }
}

/// The span of a pair without the white space and comments pest's implicit skipping
/// leaves at its end (a rule ending in an optional part swallows the trivia before the
/// part it did not find). Spans must end at the last real token: the formatter attaches
/// comments by position, and labels should not underline blank lines.
fn span_of(pair: &Pair<'_, Rule>) -> Span {
    let s = pair.as_span();
    Span::new(s.start(), s.start() + content_len(s.as_str()))
}

/// Length of `text` up to the end of its last token that is not white space or a comment.
fn content_len(text: &str) -> usize {
    let bytes = text.as_bytes();
    let mut end = 0;
    let mut i = 0;
    while i < bytes.len() {
        match bytes[i] {
            b' ' | b'\t' | b'\r' | b'\n' => i += 1,
            // The UTF-8 byte-order mark (EF BB BF) is white space too.
            0xEF if bytes.get(i + 1) == Some(&0xBB) && bytes.get(i + 2) == Some(&0xBF) => i += 3,
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
                i = (i + 2).min(bytes.len());
            }
            quote @ (b'"' | b'`') => {
                i += 1;
                while i < bytes.len() && bytes[i] != quote {
                    if quote == b'"' && bytes[i] == b'\\' {
                        i += 1;
                    }
                    i += 1;
                }
                i = (i + 1).min(bytes.len());
                end = i;
            }
            _ => {
                i += 1;
                end = i;
            }
        }
    }
    end
}

struct Builder<'t, 'd> {
    file_id: FileId,
    text: &'t str,
    diagnostics: &'d mut Vec<Diagnostic>,
}

impl Builder<'_, '_> {
    fn file(&mut self, pair: Pair<'_, Rule>) -> Option<File> {
        let span = span_of(&pair);
        let mut inner = pair.into_inner();
        let kind = match inner.next()?.into_inner().next()?.as_rule() {
            Rule::kw_cell => FileKind::Cell,
            _ => FileKind::Library,
        };
        let name = self.name(inner.next()?)?;
        let body = inner.next()?;
        let mut items: Vec<Item> = Vec::new();
        for pair in body.into_inner() {
            if pair.as_rule() == Rule::recover {
                let previous = items.last().map(Item::span);
                self.recovered(&pair, previous, Rule::item_probe, Rule::item_line);
                continue;
            }
            match self.item(pair) {
                Some(item) => items.push(item),
                None => self.diagnostics.push(phrases::internal(self.file_id, span)),
            }
        }
        Some(File {
            kind,
            name,
            items,
            span,
        })
    }

    /// Re-parses a recovered region alone to learn what was expected there. When the
    /// region starts on the line where the previous item ended, the junk is most likely
    /// the unparsed tail of that item (`at (0, 0)` after `grasp g1 by table`), so the
    /// previous item is re-parsed together with it to find the real mistake.
    fn recovered(
        &mut self,
        pair: &Pair<'_, Rule>,
        previous: Option<Span>,
        probe: Rule,
        line_probe: Rule,
    ) {
        let start = pair.as_span().start();
        if let Some(previous) = previous {
            let between = &self.text[previous.end as usize..start];
            if !between.contains('\n') {
                let from = previous.start as usize;
                if let Err(error) = detailed(|| CellParser::parse(line_probe, &self.text[from..])) {
                    let diagnostic = phrases::syntax_error(self.file_id, self.text, from, &error);
                    if diagnostic
                        .primary_label()
                        .is_some_and(|l| l.span.start as usize >= start)
                    {
                        self.diagnostics.push(diagnostic);
                        return;
                    }
                }
            }
        }
        let rest = &self.text[start..];
        match detailed(|| CellParser::parse(probe, rest)) {
            Err(error) => self.diagnostics.push(phrases::syntax_error(
                self.file_id,
                self.text,
                start,
                &error,
            )),
            Ok(_) => self
                .diagnostics
                .push(phrases::unexpected_text(self.file_id, span_of(pair))),
        }
    }
}
