//! Which diagnostics a human rendering shows in full, and which it only counts.
//!
//! A generated cell can have thousands of diagnostics of one code (the same unused grasp
//! on every object), and a reader learns everything from the first few: the rest bury the
//! one diagnostic of another code that matters. So the human form shows the first
//! [`SHOWN_PER_CODE`] of each code (and severity) in full and one line per code for the
//! rest; `--format short` and `--format json` still list every one.
//!
//! Two rules keep errors in sight: a code's errors and its warnings are counted apart (so
//! warnings never use up an error's places), and when the overall cap
//! ([`crate::render::MAX_HUMAN_DIAGNOSTICS`]) still cuts, errors keep their places before
//! any warning does. The choice is one pass over the diagnostics and one over the groups,
//! in the order the diagnostics came, so it is deterministic and linear.

use std::collections::HashMap;

use cellc_lang::{Code, Diagnostic, Severity};

/// Diagnostics of one code (and severity) shown in full.
pub const SHOWN_PER_CODE: usize = 3;

/// Diagnostics of one code and severity that were not shown.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Hidden {
    /// Their code.
    pub code: Code,
    /// Their severity.
    pub severity: Severity,
    /// How many were not shown.
    pub count: usize,
}

/// What a human rendering shows.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Selection {
    /// Indices of the diagnostics shown in full, in their order.
    pub shown: Vec<usize>,
    /// Per code and severity with some not shown: errors first, then warnings, each in
    /// the order of the code's first diagnostic.
    pub hidden: Vec<Hidden>,
}

/// The diagnostics of `diagnostics` to show in full (at most [`SHOWN_PER_CODE`] of each
/// code and severity, at most `cap` in all, errors before warnings when the cap cuts),
/// and how many of each code are left out.
pub fn select(diagnostics: &[Diagnostic], cap: usize) -> Selection {
    // Groups in order of first appearance: (code, severity, seen so far, not shown).
    let mut index: HashMap<(Code, Severity), usize> = HashMap::new();
    let mut groups: Vec<(Code, Severity, usize, usize)> = Vec::new();
    let mut group_of = Vec::with_capacity(diagnostics.len());
    let mut candidate = Vec::with_capacity(diagnostics.len());
    let (mut errors, mut warnings) = (0usize, 0usize);
    for d in diagnostics {
        let g = *index.entry((d.code, d.severity)).or_insert_with(|| {
            groups.push((d.code, d.severity, 0, 0));
            groups.len() - 1
        });
        let first_few = groups[g].2 < SHOWN_PER_CODE;
        groups[g].2 += 1;
        group_of.push(g);
        candidate.push(first_few);
        if first_few {
            match d.severity {
                Severity::Error => errors += 1,
                Severity::Warning => warnings += 1,
            }
        }
    }
    // Places under the cap: errors take theirs first.
    let mut error_places = errors.min(cap);
    let mut warning_places = warnings.min(cap - error_places);
    let mut shown = Vec::new();
    for (i, d) in diagnostics.iter().enumerate() {
        let places = match d.severity {
            Severity::Error => &mut error_places,
            Severity::Warning => &mut warning_places,
        };
        if candidate[i] && *places > 0 {
            *places -= 1;
            shown.push(i);
        } else {
            groups[group_of[i]].3 += 1;
        }
    }
    let hidden_of = |severity: Severity| {
        groups
            .iter()
            .filter(move |g| g.1 == severity && g.3 > 0)
            .map(|&(code, severity, _, count)| Hidden {
                code,
                severity,
                count,
            })
    };
    let hidden = hidden_of(Severity::Error)
        .chain(hidden_of(Severity::Warning))
        .collect();
    Selection { shown, hidden }
}

#[cfg(test)]
mod tests {
    use super::*;

    use cellc_lang::codes::compile::{
        ASYMMETRIC_TRANSITION, DEAD_END_STATE, DUPLICATE_NAME, DUPLICATE_TRANSITION, UNKNOWN_NAME,
        UNUSED_GRASP,
    };

    fn diagnostic(code: Code, severity: Severity) -> Diagnostic {
        let mut d = Diagnostic::error(code, "m");
        d.severity = severity;
        d
    }

    /// The first three of each code are shown in order; the rest are counted per code,
    /// errors first.
    #[test]
    fn groups_by_code_and_counts_the_rest() {
        let w = Severity::Warning;
        let e = Severity::Error;
        let ds: Vec<Diagnostic> = [
            (UNUSED_GRASP, w),
            (UNUSED_GRASP, w),
            (DUPLICATE_TRANSITION, w),
            (UNUSED_GRASP, w),
            (UNUSED_GRASP, w),
            (UNKNOWN_NAME, e),
            (UNUSED_GRASP, w),
            (UNKNOWN_NAME, e),
            (UNKNOWN_NAME, e),
            (UNKNOWN_NAME, e),
            (DUPLICATE_TRANSITION, w),
        ]
        .into_iter()
        .map(|(c, s)| diagnostic(c, s))
        .collect();
        let selection = select(&ds, 500);
        assert_eq!(selection.shown, vec![0, 1, 2, 3, 5, 7, 8, 10]);
        assert_eq!(
            selection.hidden,
            vec![
                Hidden {
                    code: UNKNOWN_NAME,
                    severity: e,
                    count: 1
                },
                Hidden {
                    code: UNUSED_GRASP,
                    severity: w,
                    count: 2
                },
            ]
        );
    }

    /// When the cap cuts, warnings give up their places to errors that come after them.
    #[test]
    fn the_cap_never_hides_an_error_behind_warnings() {
        let mut ds = Vec::new();
        for code in [ASYMMETRIC_TRANSITION, DEAD_END_STATE, UNUSED_GRASP] {
            for _ in 0..3 {
                ds.push(diagnostic(code, Severity::Warning));
            }
        }
        ds.push(diagnostic(UNKNOWN_NAME, Severity::Error));
        ds.push(diagnostic(DUPLICATE_NAME, Severity::Error));
        let selection = select(&ds, 4);
        assert_eq!(selection.shown, vec![0, 1, 9, 10]);
        let counts: Vec<(Code, usize)> =
            selection.hidden.iter().map(|h| (h.code, h.count)).collect();
        assert_eq!(
            counts,
            vec![
                (ASYMMETRIC_TRANSITION, 1),
                (DEAD_END_STATE, 3),
                (UNUSED_GRASP, 3)
            ]
        );
    }

    /// A code with an error and warnings keeps the error's place.
    #[test]
    fn a_codes_errors_and_warnings_are_counted_apart() {
        let mut ds: Vec<Diagnostic> = (0..5)
            .map(|_| diagnostic(UNKNOWN_NAME, Severity::Warning))
            .collect();
        ds.push(diagnostic(UNKNOWN_NAME, Severity::Error));
        let selection = select(&ds, 500);
        assert_eq!(selection.shown, vec![0, 1, 2, 5]);
        assert_eq!(selection.hidden.len(), 1);
        assert_eq!(selection.hidden[0].severity, Severity::Warning);
        assert_eq!(selection.hidden[0].count, 2);
    }
}
