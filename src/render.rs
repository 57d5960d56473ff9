//! Renders diagnostics three ways: human (miette), short (one line each, for editors and
//! CI annotations) and JSON (a stable schema for programs).

use std::borrow::Cow;
use std::fmt;

use cellc_lang::{Diagnostic, FileId, Severity, SourceMap};
use miette::{GraphicalReportHandler, GraphicalTheme, LabeledSpan, NamedSource};

use crate::grouping;
use crate::snippet::{Shared, Sources};

/// Output style.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Format {
    /// Source snippets with labels (the default).
    Human,
    /// `file:line:col: severity[CODE]: message`, one per line.
    Short,
    /// A JSON document (schema in `docs/diagnostics/README.md`).
    Json,
}

/// Colour for human output.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Color {
    /// ANSI colours.
    Always,
    /// Plain text (files, snapshots, pipes).
    Never,
}

/// How a command reports its diagnostics: the `--format` it was given and the colour the
/// process decided once ([`crate::args::ColorChoice::decide`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Style {
    /// Human, short or JSON.
    pub format: Format,
    /// Colour of the human form.
    pub color: Color,
}

impl Style {
    /// Human and uncoloured: what a library caller or a test gets unless it asks.
    pub const PLAIN: Style = Style {
        format: Format::Human,
        color: Color::Never,
    };

    /// Whether this is the human form.
    pub fn is_human(self) -> bool {
        self.format == Format::Human
    }
}

/// Writes diagnostics where `style` puts them: the human form on standard error (no
/// summary line: a command that wants one adds it), the short form (one line each) and
/// the JSON report on standard output, so a program reads only what it asked for. Output
/// errors (a closed pipe) are ignored: the exit status still tells the result.
pub fn emit(style: Style, diagnostics: &[Diagnostic], sources: &SourceMap) {
    use std::io::Write;
    let _ = match style.format {
        Format::Human => std::io::stderr()
            .lock()
            .write_all(human(diagnostics, sources, style.color).as_bytes()),
        Format::Short => std::io::stdout()
            .lock()
            .write_all(short(diagnostics, sources).as_bytes()),
        Format::Json => std::io::stdout()
            .lock()
            .write_all(json(diagnostics, sources).as_bytes()),
    };
}

/// Characters that could drive a terminal or reorder what it shows: C0 controls but tab
/// and newline, DEL, C1 controls, and the bidirectional embeddings and overrides.
fn is_hostile(c: char) -> bool {
    (c.is_control() && c != '\n' && c != '\t')
        || matches!(c, '\u{200E}' | '\u{200F}' | '\u{202A}'..='\u{202E}' | '\u{2066}'..='\u{2069}')
}

/// Text for a terminal: hostile characters written as `\u{1b}`, so a name or a string
/// from an untrusted file is shown, never obeyed.
pub fn escape(text: &str) -> Cow<'_, str> {
    if !text.chars().any(is_hostile) {
        return Cow::Borrowed(text);
    }
    let mut out = String::with_capacity(text.len() + 8);
    for c in text.chars() {
        if is_hostile(c) {
            out.push_str(&format!("\\u{{{:x}}}", c as u32));
        } else {
            out.push(c);
        }
    }
    Cow::Owned(out)
}

/// Source text for snippets: each hostile character replaced by as many `?` as it has
/// bytes, so every span still points at the same bytes (a `\r` before `\n` is kept).
fn neutralize(text: &str) -> Cow<'_, str> {
    let hostile =
        |(i, c): (usize, char)| is_hostile(c) && !(c == '\r' && text[i + 1..].starts_with('\n'));
    if !text.char_indices().any(hostile) {
        return Cow::Borrowed(text);
    }
    let mut out = String::with_capacity(text.len());
    for (i, c) in text.char_indices() {
        if hostile((i, c)) {
            out.extend(std::iter::repeat_n('?', c.len_utf8()));
        } else {
            out.push(c);
        }
    }
    Cow::Owned(out)
}

/// The most diagnostics one human rendering shows in full, whatever their codes: nobody
/// reads more, and a hostile cell can have hundreds of thousands of many codes (the short
/// and JSON forms list them all). Grouping by code ([`grouping`]) usually shows far fewer.
pub const MAX_HUMAN_DIAGNOSTICS: usize = 500;

/// Human rendering of a list of diagnostics: the first [`grouping::SHOWN_PER_CODE`] of
/// each code in full (at most [`MAX_HUMAN_DIAGNOSTICS`], errors before warnings when that
/// cuts), then one line per code that counts the ones not shown. Only the diagnostics
/// shown are rendered, so the cost is linear in the list and bounded in snippets.
pub fn human(diagnostics: &[Diagnostic], sources: &SourceMap, color: Color) -> String {
    let theme = match color {
        Color::Always => GraphicalTheme::unicode(),
        Color::Never => GraphicalTheme::unicode_nocolor(),
    };
    let handler = GraphicalReportHandler::new_themed(theme)
        .with_width(100)
        .with_links(false)
        .without_syntax_highlighting();
    let mut out = String::new();
    let mut files = Sources::new(sources, |text| neutralize(text).into_owned());
    let selection = grouping::select(diagnostics, MAX_HUMAN_DIAGNOSTICS);
    for &i in &selection.shown {
        let diagnostic = &diagnostics[i];
        let report = Report::new(diagnostic, sources, &mut files);
        if handler.render_report(&mut out, &report).is_err() {
            // Rendering into a String cannot fail for I/O reasons; fall back to the short
            // form rather than lose the diagnostic.
            out.push_str(&short(std::slice::from_ref(diagnostic), sources));
        }
        out.push('\n');
    }
    for hidden in &selection.hidden {
        let noun = match (hidden.severity, hidden.count) {
            (Severity::Error, 1) => "error",
            (Severity::Error, _) => "errors",
            (Severity::Warning, 1) => "warning",
            (Severity::Warning, _) => "warnings",
        };
        out.push_str(&format!(
            "... and {} more {noun} {}, not shown\n",
            hidden.count, hidden.code
        ));
    }
    if !selection.hidden.is_empty() {
        out.push_str("(`cellc check --format short` or `--format json` lists every one)\n\n");
    }
    out
}

/// One line per diagnostic.
pub fn short(diagnostics: &[Diagnostic], sources: &SourceMap) -> String {
    let mut out = String::new();
    for d in diagnostics {
        match d.primary_label() {
            Some(label) => {
                let file = sources.get(label.file);
                let (line, col) = file.line_col(label.span.start);
                out.push_str(&format!(
                    "{}:{line}:{col}: {}[{}]: {}{}\n",
                    escape(&file.path),
                    d.severity.as_str(),
                    d.code,
                    escape(&d.message),
                    notes_suffix(d)
                ));
            }
            None => out.push_str(&format!(
                "{}[{}]: {}{}\n",
                d.severity.as_str(),
                d.code,
                escape(&d.message),
                notes_suffix(d)
            )),
        }
    }
    out
}

/// Notes in parentheses, so the one-line form still says why (e.g. why a requirement
/// fails).
fn notes_suffix(d: &Diagnostic) -> String {
    if d.notes.is_empty() {
        String::new()
    } else {
        format!(" ({})", escape(&d.notes.join("; ")))
    }
}

/// JSON rendering: the diagnostics report (`cellc_driver::document::report`).
pub fn json(diagnostics: &[Diagnostic], sources: &SourceMap) -> String {
    let report = cellc_driver::document::report::Report::new(diagnostics, sources);
    serde_json::to_string_pretty(&report).unwrap_or_else(|e| format!("{{\"error\": \"{e}\"}}"))
        + "\n"
}

/// A summary line like `2 errors, 1 warning`.
pub fn summary(diagnostics: &[Diagnostic]) -> String {
    let errors = diagnostics.iter().filter(|d| d.is_error()).count();
    let warnings = diagnostics.len() - errors;
    let plural = |n: usize, word: &str| format!("{n} {word}{}", if n == 1 { "" } else { "s" });
    format!(
        "{}, {}",
        plural(errors, "error"),
        plural(warnings, "warning")
    )
}

/// Adapter from our diagnostic to miette's trait. Labels in the primary label's file are
/// drawn on its snippet; labels in other files become related reports, each with its
/// own snippet.
struct Report<'a> {
    diagnostic: &'a Diagnostic,
    file: Option<FileId>,
    source: Option<NamedSource<Shared>>,
    labels: Vec<LabeledSpan>,
    related: Vec<Related>,
    help: Option<String>,
}

struct Related {
    message: String,
    source: NamedSource<Shared>,
    label: LabeledSpan,
}

impl<'a> Report<'a> {
    fn new(diagnostic: &'a Diagnostic, sources: &SourceMap, files: &mut Sources) -> Report<'a> {
        // Places whose lines are too long to show are said in words instead.
        let mut elsewhere: Vec<String> = Vec::new();
        let mut shown: Vec<&cellc_lang::Label> = Vec::new();
        for label in &diagnostic.labels {
            let (start, end) = (label.span.start as usize, label.span.end as usize);
            match files.too_long(label.file, start, end) {
                Some(length) => {
                    let file = sources.get(label.file);
                    let (line, col) = file.line_col(label.span.start);
                    elsewhere.push(format!(
                        "{} at {}:{line}:{col} (a line of {length} bytes, too long to show)",
                        if label.message.is_empty() {
                            "here"
                        } else {
                            &label.message
                        },
                        file.path
                    ));
                }
                None => shown.push(label),
            }
        }
        let mut named = |f: FileId| NamedSource::new(escape(&sources.get(f).path), files.get(f));
        let file = shown.iter().find(|l| l.primary).map(|l| l.file);
        let source = file.map(&mut named);
        let mut labels = Vec::new();
        let mut related = Vec::new();
        for label in shown {
            let span = label.span.start as usize..label.span.end as usize;
            let text = (!label.message.is_empty()).then(|| escape(&label.message).into_owned());
            let labeled = if label.primary {
                LabeledSpan::new_primary_with_span(text, span)
            } else {
                LabeledSpan::new_with_span(text, span)
            };
            if Some(label.file) == file {
                labels.push(labeled);
            } else {
                related.push(Related {
                    message: escape(&label.message).into_owned(),
                    source: named(label.file),
                    label: labeled,
                });
            }
        }
        let mut help = diagnostic.help.as_deref().map(|h| escape(h).into_owned());
        if !diagnostic.notes.is_empty() || !elsewhere.is_empty() {
            let notes = elsewhere
                .iter()
                .chain(&diagnostic.notes)
                .map(|n| format!("note: {}", escape(n)))
                .collect::<Vec<_>>()
                .join("\n");
            help = Some(match help {
                Some(h) => format!("{h}\n{notes}"),
                None => notes,
            });
        }
        Report {
            diagnostic,
            file,
            source,
            labels,
            related,
            help,
        }
    }
}

impl fmt::Debug for Report<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{:?}", self.diagnostic)
    }
}

impl fmt::Display for Report<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&escape(&self.diagnostic.message))
    }
}

impl std::error::Error for Report<'_> {}

impl miette::Diagnostic for Report<'_> {
    fn code<'b>(&'b self) -> Option<Box<dyn fmt::Display + 'b>> {
        // `error[E0101]`, as rustc writes it, so the severity reads in plain text too.
        Some(Box::new(format!(
            "{}[{}]",
            self.diagnostic.severity.as_str(),
            self.diagnostic.code
        )))
    }

    fn severity(&self) -> Option<miette::Severity> {
        Some(match self.diagnostic.severity {
            Severity::Error => miette::Severity::Error,
            Severity::Warning => miette::Severity::Warning,
        })
    }

    fn help<'b>(&'b self) -> Option<Box<dyn fmt::Display + 'b>> {
        self.help
            .as_ref()
            .map(|h| Box::new(h) as Box<dyn fmt::Display>)
    }

    fn source_code(&self) -> Option<&dyn miette::SourceCode> {
        let _ = self.file;
        self.source.as_ref().map(|s| s as &dyn miette::SourceCode)
    }

    fn labels(&self) -> Option<Box<dyn Iterator<Item = LabeledSpan> + '_>> {
        if self.labels.is_empty() {
            None
        } else {
            Some(Box::new(self.labels.iter().cloned()))
        }
    }

    fn related<'b>(&'b self) -> Option<Box<dyn Iterator<Item = &'b dyn miette::Diagnostic> + 'b>> {
        if self.related.is_empty() {
            None
        } else {
            Some(Box::new(
                self.related.iter().map(|r| r as &dyn miette::Diagnostic),
            ))
        }
    }
}

impl fmt::Debug for Related {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

impl fmt::Display for Related {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.message.is_empty() {
            f.write_str("related place")
        } else {
            f.write_str(&self.message)
        }
    }
}

impl std::error::Error for Related {}

impl miette::Diagnostic for Related {
    fn severity(&self) -> Option<miette::Severity> {
        Some(miette::Severity::Advice)
    }

    fn source_code(&self) -> Option<&dyn miette::SourceCode> {
        Some(&self.source)
    }

    fn labels(&self) -> Option<Box<dyn Iterator<Item = LabeledSpan> + '_>> {
        Some(Box::new(std::iter::once(self.label.clone())))
    }
}
