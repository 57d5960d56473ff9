//! Diagnostic documentation pages, embedded at build time from `docs/diagnostics/`.

include!(concat!(env!("OUT_DIR"), "/diagnostic_docs.rs"));

/// The page for a code, if it has one.
pub fn page(code: &str) -> Option<&'static str> {
    DIAGNOSTIC_DOCS
        .iter()
        .find(|(c, _)| *c == code)
        .map(|(_, text)| *text)
}

/// Every code that has a page.
pub fn documented_codes() -> impl Iterator<Item = &'static str> {
    DIAGNOSTIC_DOCS.iter().map(|(c, _)| *c)
}
