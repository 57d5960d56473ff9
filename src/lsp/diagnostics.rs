//! A compilation's diagnostics as the protocol's, one list per file.
//!
//! Every diagnostic is published in the file of its primary label (an error in an
//! included library shows in that library), its secondary labels as related
//! information, its help and notes after the message as `cellc check` prints them, and
//! its code linked to the code's page when that page is on this machine.

use std::collections::BTreeMap;

use cellc_lang::{Diagnostic, Severity, SourceMap};
use lsp_types::{
    CodeDescription, DiagnosticRelatedInformation, DiagnosticSeverity, Location, NumberOrString,
    Uri,
};

use super::documents::uri_of;
use super::position::Lines;

/// The diagnostics of one compilation, by path; a diagnostic with no place is put at
/// the start of `root`. Every file of the compilation has an entry, empty when clean,
/// so that fixed problems disappear.
pub fn by_file(
    diagnostics: &[Diagnostic],
    sources: &SourceMap,
    root: &str,
) -> BTreeMap<String, Vec<lsp_types::Diagnostic>> {
    let mut out: BTreeMap<String, Vec<lsp_types::Diagnostic>> = sources
        .iter()
        .map(|(_, f)| (f.path.clone(), Vec::new()))
        .collect();
    out.entry(root.to_string()).or_default();
    let lines: Vec<(String, Lines<'_>)> = sources
        .iter()
        .map(|(_, f)| (f.path.clone(), Lines::new(&f.text)))
        .collect();
    for d in diagnostics {
        let primary = d.primary_label();
        let (path, range) = match primary.and_then(|l| lines.get(l.file.0 as usize).map(|f| (f, l)))
        {
            Some(((path, lines), label)) => (path.clone(), lines.range(label.span)),
            None => (root.to_string(), lsp_types::Range::default()),
        };
        let related: Vec<DiagnosticRelatedInformation> = d
            .labels
            .iter()
            .filter(|l| !l.primary)
            .filter_map(|l| {
                let (path, lines) = lines.get(l.file.0 as usize)?;
                Some(DiagnosticRelatedInformation {
                    location: Location::new(uri_of(path)?, lines.range(l.span)),
                    message: if l.message.is_empty() {
                        "related".to_string()
                    } else {
                        l.message.clone()
                    },
                })
            })
            .collect();
        out.entry(path).or_default().push(lsp_types::Diagnostic {
            range,
            severity: Some(match d.severity {
                Severity::Error => DiagnosticSeverity::ERROR,
                Severity::Warning => DiagnosticSeverity::WARNING,
            }),
            code: Some(NumberOrString::String(d.code.as_str().to_string())),
            code_description: page(d.code).map(|href| CodeDescription { href }),
            source: Some("cellc".to_string()),
            message: message(d),
            related_information: (!related.is_empty()).then_some(related),
            tags: None,
            data: None,
        });
    }
    out
}

/// The message with the primary label's words, the help and the notes.
fn message(d: &Diagnostic) -> String {
    let mut text = d.message.clone();
    if let Some(label) = d.primary_label().filter(|l| !l.message.is_empty()) {
        text.push_str(": ");
        text.push_str(&label.message);
    }
    if let Some(help) = &d.help {
        text.push_str("\nhelp: ");
        text.push_str(help);
    }
    for note in &d.notes {
        text.push_str("\nnote: ");
        text.push_str(note);
    }
    text
}

/// The page of `code` (`docs/diagnostics/CODE.md`, also shown by `cellc explain CODE`)
/// in the sources this binary was built from, when they are still there.
fn page(code: cellc_lang::Code) -> Option<Uri> {
    let path = format!("{}/{}", env!("CARGO_MANIFEST_DIR"), code.page_path());
    std::path::Path::new(&path)
        .is_file()
        .then(|| uri_of(&path))?
}
