//! The error document: the diagnostics report of `cellc check --format json`, which every
//! failure of every front end is (the service's errors, the `diagnostics` of a plan or
//! run document).

use cellc_lang::{Diagnostic as LangDiagnostic, SourceMap};
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// The version of the report (bumped on any incompatible change).
pub const REPORT_VERSION: u32 = 1;

/// The diagnostics report.
#[derive(Serialize, Deserialize, JsonSchema, Clone, Debug, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Report {
    /// Schema version; bumped on any incompatible change.
    pub version: u32,
    /// Every diagnostic.
    pub diagnostics: Vec<Diagnostic>,
    /// Number of errors.
    pub errors: usize,
    /// Number of warnings.
    pub warnings: usize,
}

/// Whether a diagnostic stops the command.
#[derive(Serialize, Deserialize, JsonSchema, Clone, Copy, Debug, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum Severity {
    /// It does.
    Error,
    /// It does not.
    Warning,
}

/// One diagnostic.
#[derive(Serialize, Deserialize, JsonSchema, Clone, Debug, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Diagnostic {
    /// Stable code, e.g. `E0101` (its page is docs/diagnostics/CODE.md).
    pub code: String,
    /// `error` or `warning`.
    pub severity: Severity,
    /// The message.
    pub message: String,
    /// File of the primary label (null when the problem has no place).
    pub file: Option<String>,
    /// 1-based line of the primary label.
    pub line: Option<usize>,
    /// 1-based column (in characters) of the primary label.
    pub column: Option<usize>,
    /// Byte range of the primary label.
    pub span: Option<Span>,
    /// All labels, primary first.
    pub labels: Vec<Label>,
    /// The fix.
    pub help: Option<String>,
    /// Extra facts.
    pub notes: Vec<String>,
}

/// A byte range.
#[derive(Serialize, Deserialize, JsonSchema, Clone, Copy, Debug, PartialEq, Eq)]
#[serde(deny_unknown_fields)]
pub struct Span {
    /// First byte.
    pub start: u32,
    /// One past the last byte.
    pub end: u32,
}

/// A label: a place in a file and what it says there.
#[derive(Serialize, Deserialize, JsonSchema, Clone, Debug, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Label {
    /// File.
    pub file: String,
    /// 1-based line.
    pub line: usize,
    /// 1-based column.
    pub column: usize,
    /// Byte range.
    pub span: Span,
    /// Text of the label.
    pub message: String,
    /// Primary or secondary.
    pub primary: bool,
}

impl Report {
    /// The report of `diagnostics`, their labels placed in `sources`.
    pub fn new(diagnostics: &[LangDiagnostic], sources: &SourceMap) -> Report {
        Report {
            version: REPORT_VERSION,
            errors: diagnostics.iter().filter(|d| d.is_error()).count(),
            warnings: diagnostics.iter().filter(|d| !d.is_error()).count(),
            diagnostics: diagnostics
                .iter()
                .map(|d| Diagnostic::new(d, sources))
                .collect(),
        }
    }

    /// The code of the first diagnostic, if any.
    pub fn first_code(&self) -> Option<&str> {
        self.diagnostics.first().map(|d| d.code.as_str())
    }
}

impl Diagnostic {
    /// `d`, its labels placed in `sources`.
    pub fn new(d: &LangDiagnostic, sources: &SourceMap) -> Diagnostic {
        let labels: Vec<Label> = d
            .labels
            .iter()
            .map(|l| {
                let file = sources.get(l.file);
                let (line, column) = file.line_col(l.span.start);
                Label {
                    file: file.path.clone(),
                    line,
                    column,
                    span: Span {
                        start: l.span.start,
                        end: l.span.end,
                    },
                    message: l.message.clone(),
                    primary: l.primary,
                }
            })
            .collect();
        let primary = labels.iter().find(|l| l.primary);
        Diagnostic {
            code: d.code.as_str().to_string(),
            severity: if d.is_error() {
                Severity::Error
            } else {
                Severity::Warning
            },
            message: d.message.clone(),
            file: primary.map(|l| l.file.clone()),
            line: primary.map(|l| l.line),
            column: primary.map(|l| l.column),
            span: primary.map(|l| l.span),
            help: d.help.clone(),
            notes: d.notes.clone(),
            labels,
        }
    }
}
