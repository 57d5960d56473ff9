//! Quick fixes, read from the diagnostics the client sends back: a "did you mean `x`?"
//! replaces the marked name with `x`, and an unknown name (E0101) of a sort that can be
//! declared without more facts gets a skeleton declaration before the closing brace of
//! the file it is used in.
//!
//! A skeleton is the shortest item of the sort that parses, in the formatter's layout (so
//! Format Document leaves it as it is), and that declares what the use needs:
//!
//! - a workspace: `workspace NAME`;
//! - a holder kind: `hand NAME` where a hand is named (after `with` and `by`), else
//!   `support NAME` (after `:` and `on`);
//! - an end-effector: `movable NAME reaches W`, with the first workspace the cell
//!   declares (the grammar needs one; without any, no skeleton is offered);
//! - an object: `object NAME {}`.
//!
//! Robots (a URDF), obstacles (a box) and grasps (a holder) need facts only the user
//! knows, so they get no skeleton.

use std::collections::BTreeMap;

use cellc_lang::written_name;
use lsp_types::{
    CodeAction, CodeActionKind, CodeActionOrCommand, CodeActionParams, Range, TextEdit,
    WorkspaceEdit,
};

use super::analysis::Analysis;
use super::analysis_for;
use super::position::Lines;
use cellc_compiler::names::Kind;

/// The quick fixes of the diagnostics in the request's context.
pub fn code_actions(
    analyses: &BTreeMap<String, Analysis>,
    params: CodeActionParams,
) -> Option<Vec<CodeActionOrCommand>> {
    let uri = params.text_document.uri;
    let found = analysis_for(analyses, &uri);
    let text = found
        .and_then(|(a, file)| a.source(file))
        .map(|(_, text)| text);
    let workspace = found.and_then(|(a, _)| {
        a.names()
            .occurrences()
            .iter()
            .find(|o| o.declares == Some(Kind::Workspace))
            .map(|o| o.key.name().to_string())
    });
    let mut actions = Vec::new();
    let mut action = |title: String, d: &lsp_types::Diagnostic, edit: TextEdit, preferred: bool| {
        actions.push(CodeActionOrCommand::CodeAction(CodeAction {
            title,
            kind: Some(CodeActionKind::QUICKFIX),
            diagnostics: Some(vec![d.clone()]),
            edit: Some(WorkspaceEdit {
                changes: Some([(uri.clone(), vec![edit])].into_iter().collect()),
                ..WorkspaceEdit::default()
            }),
            is_preferred: Some(preferred),
            ..CodeAction::default()
        }))
    };
    for d in &params.context.diagnostics {
        if let Some(suggestion) = did_you_mean(&d.message) {
            let edit = TextEdit::new(d.range, suggestion.to_string());
            action(format!("change to `{suggestion}`"), d, edit, true);
        }
        let Some(text) = text else { continue };
        let Some((sort, name)) = unknown(&d.message) else {
            continue;
        };
        let written = written_name(name);
        let line = match sort {
            "workspace" => format!("workspace {written}"),
            "holder kind" => match word_before(text, d.range) {
                Some("with" | "by") => format!("hand {written}"),
                _ => format!("support {written}"),
            },
            "end-effector" => match &workspace {
                Some(w) => format!("movable {written} reaches {}", written_name(w)),
                None => continue,
            },
            "object" => format!("object {written} {{}}"),
            _ => continue,
        };
        if let Some(edit) = insert_before_closing_brace(text, &line) {
            action(format!("declare `{line}`"), d, edit, false);
        }
    }
    Some(actions)
}

/// The word before `range` in `text` (`with` in `with softhnd`).
fn word_before(text: &str, range: Range) -> Option<&str> {
    let start = Lines::new(text).offset(range.start);
    text[..start]
        .split(|c: char| c.is_whitespace())
        .rfind(|w| !w.is_empty())
        .map(|w| {
            if w.ends_with(':') && w.len() > 1 {
                ":"
            } else {
                w
            }
        })
}

/// The sort and name of an "unknown SORT `NAME`" message (E0101).
fn unknown(message: &str) -> Option<(&str, &str)> {
    let rest = message.strip_prefix("unknown ")?;
    let (sort, rest) = rest.split_once(" `")?;
    let name = rest.split('`').next()?;
    Some((sort, name))
}

/// An edit that writes `line` (indented by two spaces) on its own line before the last
/// `}` of `text`, the cell's closing brace.
fn insert_before_closing_brace(text: &str, line: &str) -> Option<TextEdit> {
    let brace = text.rfind('}')?;
    let line_start = text[..brace].rfind('\n').map_or(0, |i| i + 1);
    let lines = Lines::new(text);
    if text[line_start..brace].trim().is_empty() {
        let at = lines.position(line_start);
        Some(TextEdit::new(Range::new(at, at), format!("  {line}\n")))
    } else {
        let at = lines.position(brace);
        Some(TextEdit::new(Range::new(at, at), format!("\n  {line}\n")))
    }
}

/// The name a diagnostic's help suggests (`help: did you mean `x`?`).
fn did_you_mean(message: &str) -> Option<&str> {
    let rest = message.split("did you mean `").nth(1)?;
    let name = rest.split('`').next()?;
    (!name.is_empty()).then_some(name)
}
