//! Unreachable goals as diagnostics: what the start can reach, what the goal needs, the
//! cut between them and what to change, labelled at the cell's source lines. The analysis
//! is the runtime's (`cellc_runtime::explain`); this turns it into words and labels.

use cellc_lang::{Diagnostic, FileId, Span};
use cellc_runtime::plan::Unreachable;
use cellc_schema::Artifact;

use crate::runtime_codes as codes;

fn place(artifact: &Artifact, span: u32) -> Option<(FileId, Span)> {
    let s = artifact.spans.get(span as usize)?;
    Some((
        FileId(s.file),
        Span {
            start: s.start,
            end: s.end,
        },
    ))
}

/// The diagnostic of an unreachable goal.
pub fn unreachable(artifact: &Artifact, u: &Unreachable) -> Diagnostic {
    let explanation = cellc_runtime::explain::explain(artifact, u);
    let mut d = Diagnostic::error(codes::UNREACHABLE, explanation.summary.clone());
    // The object's declaration is the primary place; the lines that matter follow.
    if let Some(object) = artifact.objects.get(u.object as usize) {
        if let Some((file, span)) = place(artifact, object.span) {
            d = d.primary(file, span, "no path in this object's graph");
        }
    }
    for (span, label) in &explanation.spans {
        if let Some((file, at)) = place(artifact, *span) {
            if d.labels.iter().any(|l| l.file == file && l.span == at) {
                continue;
            }
            d = d.secondary(file, at, label.clone());
        }
    }
    d = d.note(format!("the start side: {}", explanation.start_side.text));
    d = d.note(format!("the goal side: {}", explanation.goal_side.text));
    for item in &explanation.cut {
        d = d.note(item.text.clone());
    }
    if explanation.cut_omitted > 0 {
        d = d.note(format!("and {} more cuts", explanation.cut_omitted));
    }
    for pruned in &explanation.pruned {
        d = d.note(pruned.text.clone());
    }
    if explanation.pruned_omitted > 0 {
        d = d.note(format!(
            "and {} more pruned or failed arcs",
            explanation.pruned_omitted
        ));
    }
    for note in &explanation.notes {
        d = d.note(note.clone());
    }
    let help = match explanation.suggestions.as_slice() {
        [] => "no single change joins the two sides: see the notes for where they are cut apart"
            .to_string(),
        [one] => one.text.clone(),
        many => many
            .iter()
            .enumerate()
            .map(|(i, s)| format!("{}) {}", i + 1, s.text))
            .collect::<Vec<_>>()
            .join("\n"),
    };
    d.help(help)
}
