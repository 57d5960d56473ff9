//! Rename: every place a name is written, in every file of every open cell that reads
//! the document, replaced by the new name as the language writes it (backticks when it
//! is not a plain identifier or is a reserved word, `cellc_lang::written_name`).
//!
//! What the name means is the resolver's answer (the compilation's table of names): a
//! grasp is renamed in its object only, a workspace in every file of the namespace, an
//! included library's declaration with the uses in the cells that include it.
//!
//! A rename that would change what the cell means is refused with a message rather than
//! made: a name declared nowhere (unknown, or derived by `workspaces from reach`, whose
//! names come from the surfaces), and a new name already declared in the same scope.
//! The members of a grasp family are named by index after the family (`g_0_1`); a
//! rename of the family renames the lines that name the family, not those members.

use std::collections::BTreeMap;

use cellc_compiler::names::Key;
use cellc_lang::written_name;
use lsp_types::{
    PrepareRenameResponse, RenameParams, TextDocumentPositionParams, TextEdit, Uri, WorkspaceEdit,
};

use super::analysis::Analysis;
use super::documents::path_of;
use super::navigate::{locate, location};
use super::position::Lines;

/// The range of the name under the cursor, if it can be renamed.
pub fn prepare(
    analyses: &BTreeMap<String, Analysis>,
    params: TextDocumentPositionParams,
) -> Result<Option<PrepareRenameResponse>, String> {
    let Some((analysis, file, offset)) = locate(analyses, &params) else {
        return Ok(None);
    };
    let Some(occurrence) = analysis.names().at(file, offset) else {
        return Ok(None);
    };
    declared(analysis, &occurrence.key)?;
    let Some((_, text)) = analysis.source(file) else {
        return Ok(None);
    };
    Ok(Some(PrepareRenameResponse::Range(
        Lines::new(text).range(occurrence.span),
    )))
}

/// The edits that rename the name under the cursor to `params.new_name`.
pub fn rename(
    analyses: &BTreeMap<String, Analysis>,
    params: RenameParams,
) -> Result<Option<WorkspaceEdit>, String> {
    let at = &params.text_document_position;
    let Some((analysis, file, offset)) = locate(analyses, at) else {
        return Ok(None);
    };
    let Some(occurrence) = analysis.names().at(file, offset) else {
        return Ok(None);
    };
    let key = occurrence.key.clone();
    declared(analysis, &key)?;
    let new = new_name(&params.new_name)?;
    if new == key.name() {
        return Ok(Some(WorkspaceEdit::default()));
    }
    let renamed = match &key {
        Key::Global(_) => Key::Global(new.to_string()),
        Key::Request(_) => Key::Request(new.to_string()),
        Key::Grasp { object, .. } => Key::Grasp {
            object: object.clone(),
            grasp: new.to_string(),
        },
    };
    let path = path_of(&at.text_document.uri).unwrap_or_default();
    let readers: Vec<&Analysis> = analyses
        .values()
        .filter(|a| a.file(&path).is_some())
        .collect();
    if let Some(kind) = readers.iter().find_map(|a| a.names().kind_of(&renamed)) {
        return Err(format!(
            "`{new}` is already declared as a {} in this scope",
            kind.noun()
        ));
    }
    let written = written_name(new);
    // By file, in the order first met (`Uri` is not a key clippy accepts in a map).
    let mut changes: Vec<(Uri, Vec<TextEdit>)> = Vec::new();
    for a in readers {
        for o in a.names().occurrences_of(&key) {
            let Some(l) = location(a, o.file, o.span) else {
                continue;
            };
            let at = match changes.iter().position(|(uri, _)| *uri == l.uri) {
                Some(at) => at,
                None => {
                    changes.push((l.uri, Vec::new()));
                    changes.len() - 1
                }
            };
            let edits = &mut changes[at].1;
            if !edits.iter().any(|e| e.range == l.range) {
                edits.push(TextEdit::new(l.range, written.clone()));
            }
        }
    }
    Ok(Some(WorkspaceEdit {
        changes: Some(changes.into_iter().collect()),
        ..WorkspaceEdit::default()
    }))
}

/// Refuses a name no file declares.
fn declared(analysis: &Analysis, key: &Key) -> Result<(), String> {
    if analysis.names().declarations(key).next().is_some() {
        return Ok(());
    }
    let derived = matches!(key, Key::Global(_))
        && analysis.compilation.cell.as_ref().is_some_and(|cell| {
            cell.workspaces
                .iter()
                .any(|(_, w)| w.derived && w.name == key.name())
        });
    Err(if derived {
        format!(
            "`{}` is derived by `workspaces from reach`; its name comes from the surfaces",
            key.name()
        )
    } else {
        format!(
            "`{}` is declared nowhere, so it cannot be renamed",
            key.name()
        )
    })
}

/// The new name as the resolver reads it: backticks the user typed are the quoting, not
/// the name; a name that cannot be written even in backticks is refused.
fn new_name(typed: &str) -> Result<&str, String> {
    let name = typed
        .strip_prefix('`')
        .and_then(|t| t.strip_suffix('`'))
        .unwrap_or(typed);
    if name.is_empty() || name.contains('`') || name.chars().any(char::is_control) {
        return Err(format!(
            "{typed:?} cannot be a name: a name is not empty and has no backtick or control character"
        ));
    }
    Ok(name)
}
