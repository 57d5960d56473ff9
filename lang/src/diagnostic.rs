//! The diagnostic type shared by every phase.
//!
//! It lives in the lowest crate so that the parser, the compiler and the runtime's
//! explanations all produce the same structure, and the binary renders them one way
//! (human, short or JSON). Rendering is not done here: this crate only describes.

use crate::span::{FileId, Span};

/// A stable diagnostic code such as `E0101`.
///
/// Codes are grouped by phase (E00xx syntax, E01xx names, E02xx units and values, E03xx
/// cell semantics, E04xx robot models, W0xxx warnings) and are never reused once shipped.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug, PartialOrd, Ord)]
pub struct Code(pub &'static str);

impl Code {
    /// The code as text.
    pub fn as_str(self) -> &'static str {
        self.0
    }
}

impl std::fmt::Display for Code {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.0)
    }
}

/// How bad a diagnostic is.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug, PartialOrd, Ord)]
pub enum Severity {
    /// The cell is wrong; `cellc check` exits 1.
    Error,
    /// The cell is legal but probably not what was meant.
    Warning,
}

impl Severity {
    /// Lowercase name as printed (`error`, `warning`).
    pub fn as_str(self) -> &'static str {
        match self {
            Severity::Error => "error",
            Severity::Warning => "warning",
        }
    }
}

/// A place in a source file with a message attached.
#[derive(Clone, Debug, PartialEq)]
pub struct Label {
    /// File the span is in.
    pub file: FileId,
    /// The marked text.
    pub span: Span,
    /// What the mark says (may be empty).
    pub message: String,
    /// The primary label is where the problem is; secondary ones show related places.
    pub primary: bool,
}

/// One problem found in a cell.
#[derive(Clone, Debug, PartialEq)]
pub struct Diagnostic {
    /// Stable code, documented in `docs/diagnostics/CODE.md`.
    pub code: Code,
    /// Error or warning.
    pub severity: Severity,
    /// One lowercase sentence without a trailing period; names in backticks.
    pub message: String,
    /// Primary label first, then secondary labels. Empty only for problems that have no
    /// place in any file (e.g. a file given on the command line that does not exist).
    pub labels: Vec<Label>,
    /// An imperative fix.
    pub help: Option<String>,
    /// Extra facts (e.g. why an `expect` does not hold).
    pub notes: Vec<String>,
}

impl Diagnostic {
    /// An error with a primary label.
    pub fn error(code: Code, message: impl Into<String>) -> Diagnostic {
        Diagnostic {
            code,
            severity: Severity::Error,
            message: message.into(),
            labels: Vec::new(),
            help: None,
            notes: Vec::new(),
        }
    }

    /// A warning.
    pub fn warning(code: Code, message: impl Into<String>) -> Diagnostic {
        Diagnostic {
            severity: Severity::Warning,
            ..Diagnostic::error(code, message)
        }
    }

    /// Adds the primary label.
    pub fn primary(mut self, file: FileId, span: Span, message: impl Into<String>) -> Self {
        self.labels.insert(
            0,
            Label {
                file,
                span,
                message: message.into(),
                primary: true,
            },
        );
        self
    }

    /// Adds a secondary label.
    pub fn secondary(mut self, file: FileId, span: Span, message: impl Into<String>) -> Self {
        self.labels.push(Label {
            file,
            span,
            message: message.into(),
            primary: false,
        });
        self
    }

    /// Sets the help line.
    pub fn help(mut self, help: impl Into<String>) -> Self {
        self.help = Some(help.into());
        self
    }

    /// Adds a note.
    pub fn note(mut self, note: impl Into<String>) -> Self {
        self.notes.push(note.into());
        self
    }

    /// The primary label, if any.
    pub fn primary_label(&self) -> Option<&Label> {
        self.labels.iter().find(|l| l.primary)
    }

    /// True for errors.
    pub fn is_error(&self) -> bool {
        self.severity == Severity::Error
    }
}

/// "did you mean" candidates: the closest name by edit distance, if close enough to be a
/// plausible typo (at most a third of the longer name's length, and at least one edit).
pub fn did_you_mean<'a>(
    wanted: &str,
    candidates: impl IntoIterator<Item = &'a str>,
) -> Option<&'a str> {
    let mut best: Option<(usize, &str)> = None;
    for candidate in candidates {
        // Optimal string alignment: a swapped pair of letters (`tabel`) is one edit.
        let distance = strsim::osa_distance(wanted, candidate);
        let limit = (wanted.chars().count().max(candidate.chars().count()) / 3).max(1);
        if distance <= limit
            && best.is_none_or(|(d, c)| distance < d || (distance == d && candidate < c))
        {
            best = Some((distance, candidate));
        }
    }
    best.map(|(_, c)| c)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn suggests_close_names_only() {
        let names = ["left_arm", "right_arm", "table"];
        assert_eq!(did_you_mean("left_amr", names), Some("left_arm"));
        assert_eq!(did_you_mean("tabel", names), Some("table"));
        assert_eq!(did_you_mean("conveyor", names), None);
    }
}
