//! The diagnostic type shared by every phase.
//!
//! It lives in the lowest crate so that the parser, the compiler and the runtime's
//! explanations all produce the same structure, and the binary renders them one way
//! (human, short or JSON). Rendering is not done here: this crate only describes.

use crate::span::{FileId, Span};

/// A stable diagnostic code such as `E0101`.
///
/// Every value is one of the constants of the registry, [`crate::codes`]: there is no
/// other way to make one, so a code cannot be misspelt, has a documentation page and is
/// known to `cellc explain`. Codes are grouped by phase and never reused once shipped.
#[derive(Clone, Copy)]
pub struct Code(&'static CodeInfo);

/// What the registry knows of a code. Only [`crate::codes`] writes these.
#[derive(Debug)]
pub(crate) struct CodeInfo {
    pub(crate) code: &'static str,
    pub(crate) name: &'static str,
    pub(crate) phase: &'static str,
    pub(crate) page: &'static str,
}

/// The four series of codes, by their letter.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
pub enum Family {
    /// `E`: the cell or another input is wrong.
    Error,
    /// `W`: legal, but probably not what was meant.
    Warning,
    /// `R`: a verification or planning request failed.
    Runtime,
    /// `S`: the service could not take a request.
    Service,
}

impl Code {
    /// A registry entry as a code (the registry's constants are made with this).
    pub(crate) const fn registered(info: &'static CodeInfo) -> Code {
        Code(info)
    }

    /// The code as text.
    pub const fn as_str(self) -> &'static str {
        self.0.code
    }

    /// The name of its constant in [`crate::codes`] (`UNKNOWN_NAME` for `E0101`).
    pub fn name(self) -> &'static str {
        self.0.name
    }

    /// The registry module of the phase that reports it (`compile`, `request`, ...).
    pub fn phase(self) -> &'static str {
        self.0.phase
    }

    /// Its documentation page, the text of `docs/diagnostics/CODE.md`.
    pub fn page(self) -> &'static str {
        self.0.page
    }

    /// Where its page is, relative to the repository root.
    pub fn page_path(self) -> String {
        format!("docs/diagnostics/{}.md", self.as_str())
    }

    /// Its series, from its letter.
    pub fn family(self) -> Family {
        match self.as_str().as_bytes().first() {
            Some(b'W') => Family::Warning,
            Some(b'R') => Family::Runtime,
            Some(b'S') => Family::Service,
            _ => Family::Error,
        }
    }

    /// The severity its diagnostics have: warnings for `W` codes, errors for the rest.
    pub fn severity(self) -> Severity {
        match self.family() {
            Family::Warning => Severity::Warning,
            Family::Error | Family::Runtime | Family::Service => Severity::Error,
        }
    }

    /// The registered code written `text` (exactly, e.g. `E0101`).
    pub fn find(text: &str) -> Option<Code> {
        crate::codes::ALL
            .iter()
            .copied()
            .find(|c| c.as_str() == text)
    }
}

// Identity is the text: two constants of one code are the same code.
impl PartialEq for Code {
    fn eq(&self, other: &Code) -> bool {
        self.as_str() == other.as_str()
    }
}

impl Eq for Code {}

impl std::hash::Hash for Code {
    fn hash<H: std::hash::Hasher>(&self, state: &mut H) {
        self.as_str().hash(state);
    }
}

impl PartialOrd for Code {
    fn partial_cmp(&self, other: &Code) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Code {
    fn cmp(&self, other: &Code) -> std::cmp::Ordering {
        self.as_str().cmp(other.as_str())
    }
}

impl std::fmt::Debug for Code {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_tuple("Code").field(&self.as_str()).finish()
    }
}

impl std::fmt::Display for Code {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
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

/// A name longer than this (in characters) gets no suggestion, and is never suggested:
/// comparing two names costs the product of their lengths.
pub const MAX_SUGGESTION_NAME_CHARS: usize = 64;

/// At most this many candidates are compared for one suggestion (after the cheap length
/// test), in the order given: callers pass candidates in a deterministic order.
pub const MAX_SUGGESTION_CANDIDATES: usize = 500;

/// "did you mean" candidates: the closest name by edit distance, if close enough to be a
/// plausible typo (at most a third of the longer name's length, and at least one edit).
///
/// The cost is bounded whatever the input: names longer than
/// [`MAX_SUGGESTION_NAME_CHARS`] are skipped, a candidate whose length alone puts it
/// too far is skipped without comparing, and at most [`MAX_SUGGESTION_CANDIDATES`] are
/// compared. A phase that may ask many times keeps a [`SuggestionBudget`].
pub fn did_you_mean<'a>(
    wanted: &str,
    candidates: impl IntoIterator<Item = &'a str>,
) -> Option<&'a str> {
    let wanted_chars = short_name_chars(wanted)?;
    let mut best: Option<(usize, &str)> = None;
    let mut compared = 0;
    for candidate in candidates {
        let Some(candidate_chars) = short_name_chars(candidate) else {
            continue;
        };
        let limit = (wanted_chars.max(candidate_chars) / 3).max(1);
        // The distance is at least the difference in length.
        if wanted_chars.abs_diff(candidate_chars) > limit {
            continue;
        }
        compared += 1;
        if compared > MAX_SUGGESTION_CANDIDATES {
            break;
        }
        // Optimal string alignment: a swapped pair of letters (`tabel`) is one edit.
        let distance = strsim::osa_distance(wanted, candidate);
        if distance <= limit
            && best.is_none_or(|(d, c)| distance < d || (distance == d && candidate < c))
        {
            best = Some((distance, candidate));
        }
    }
    best.map(|(_, c)| c)
}

/// The length of `name` in characters, when it is short enough to compare.
fn short_name_chars(name: &str) -> Option<usize> {
    // Four bytes a character at most: a longer byte string is too long without counting.
    if name.len() > 4 * MAX_SUGGESTION_NAME_CHARS {
        return None;
    }
    let chars = name.chars().count();
    (chars <= MAX_SUGGESTION_NAME_CHARS).then_some(chars)
}

/// How many "did you mean" searches one compilation may still run: each costs a pass over
/// the names it could suggest, so a cell with 10⁵ unknown names among 10⁵ known ones
/// would otherwise cost 10¹⁰. Past the budget, unknown names are still reported, without
/// a suggestion.
#[derive(Clone, Debug)]
pub struct SuggestionBudget {
    left: usize,
}

/// Searches a [`SuggestionBudget`] allows.
pub const MAX_SUGGESTION_SEARCHES: usize = 100;

impl Default for SuggestionBudget {
    fn default() -> SuggestionBudget {
        SuggestionBudget {
            left: MAX_SUGGESTION_SEARCHES,
        }
    }
}

impl SuggestionBudget {
    /// Runs `search` when the budget allows, counting it; `None` once it is spent.
    pub fn search<'a>(&mut self, search: impl FnOnce() -> Option<&'a str>) -> Option<&'a str> {
        if self.left == 0 {
            return None;
        }
        self.left -= 1;
        search()
    }
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

    #[test]
    fn suggestions_are_bounded_in_cost() {
        let long = "x".repeat(MAX_SUGGESTION_NAME_CHARS + 1);
        assert_eq!(did_you_mean(&long, [long.as_str()]), None);
        assert_eq!(
            did_you_mean("table", [long.as_str(), "tabel"]),
            Some("tabel")
        );
        // Only the first candidates that pass the length test are compared.
        let others: Vec<String> = (0..MAX_SUGGESTION_CANDIDATES)
            .map(|i| format!("zz{i:04}"))
            .collect();
        let few = others[1..].iter().map(String::as_str).chain(["tabel"]);
        assert_eq!(did_you_mean("table", few), Some("tabel"));
        let many = others.iter().map(String::as_str).chain(["tabel"]);
        assert_eq!(did_you_mean("table", many), None);
        let mut budget = SuggestionBudget::default();
        for _ in 0..MAX_SUGGESTION_SEARCHES {
            assert_eq!(budget.search(|| Some("a")), Some("a"));
        }
        assert_eq!(budget.search(|| Some("a")), None);
    }
}
