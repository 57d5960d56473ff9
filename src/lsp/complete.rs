//! Completion: item and member keywords where an item or member starts, and elsewhere
//! the names in scope, narrowed by the word before the cursor to the kinds the grammar
//! allows there (holder kinds after `with`, `by` and `on`, workspaces after `in` and
//! `reaches`, robots after `=`, an arm's joints in `home (...)`, its links after `ARM.`
//! in `allow contact`).
//!
//! Names come from the last compilation of the document, so a name declared in an
//! include is offered and one being typed right now is not (yet).

use std::collections::BTreeMap;

use lsp_types::{CompletionItem, CompletionItemKind, CompletionParams, CompletionResponse};

use super::analysis::Analysis;
use super::analysis_for;
use super::documents::{path_of, Documents};
use super::index::{Key, Kind};
use super::position::Lines;

/// Words that start an item (the grammar's `item` rule).
const ITEM_KEYWORDS: &[&str] = &[
    "units",
    "weights",
    "include",
    "package",
    "workspaces from reach",
    "workspace",
    "adjacent",
    "fixed",
    "movable",
    "hand",
    "support",
    "robot",
    "arm",
    "surface",
    "reach",
    "object",
    "expect",
    "allow contact",
    "request",
    "obstacle",
    "world",
    "task",
];

/// Words that start an object's member.
const MEMBER_KEYWORDS: &[&str] = &["shape", "symmetry", "grasp", "rest", "transition"];

/// What may follow the cursor.
pub fn complete(
    analyses: &BTreeMap<String, Analysis>,
    documents: &Documents,
    params: CompletionParams,
) -> Option<CompletionResponse> {
    let at = &params.text_document_position;
    let path = path_of(&at.text_document.uri)?;
    let text = documents.get(&path)?.text.as_str();
    let offset = Lines::new(text).offset(at.position);
    let line_start = text[..offset].rfind('\n').map_or(0, |i| i + 1);
    let line = &text[line_start..offset];
    let typed = line.trim_end_matches(|c: char| c.is_ascii_alphanumeric() || c == '_');
    let analysis = analysis_for(analyses, &at.text_document.uri).map(|(a, _)| a);
    let items = if typed.trim().is_empty() {
        let depth = text[..line_start].matches('{').count() as i64
            - text[..line_start].matches('}').count() as i64;
        let in_object = depth >= 2 && enclosing_block(&text[..line_start]) == Some("object");
        let words = if in_object {
            MEMBER_KEYWORDS
        } else {
            ITEM_KEYWORDS
        };
        words
            .iter()
            .map(|w| CompletionItem {
                label: w.to_string(),
                kind: Some(CompletionItemKind::KEYWORD),
                ..CompletionItem::default()
            })
            .collect()
    } else if let Some(words) = robot_words(analysis, typed) {
        words
    } else {
        // In a list (`reaches w1, w2, `), what the list follows decides.
        let previous = typed
            .split_whitespace()
            .rev()
            .find(|w| !w.ends_with(','))
            .unwrap_or("");
        names(analysis, wanted(previous))
    };
    Some(CompletionResponse::Array(items))
}

/// The first word of the line that opened the innermost open block.
fn enclosing_block(before: &str) -> Option<&str> {
    let mut depth = 0;
    for (i, c) in before.char_indices().rev() {
        match c {
            '}' => depth += 1,
            '{' if depth > 0 => depth -= 1,
            '{' => {
                let start = before[..i].rfind('\n').map_or(0, |n| n + 1);
                return before[start..i].split_whitespace().next();
            }
            _ => {}
        }
    }
    None
}

/// Which names fit after `previous`, the word before the cursor.
fn wanted(previous: &str) -> fn(Kind) -> bool {
    match previous {
        "in" | "reaches" | "adjacent" => |k| k == Kind::Workspace,
        "with" | "on" | ":" => Kind::is_holder_kind,
        "by" => |k| k.is_holder_kind() || k.is_end_effector(),
        "=" => |k| k == Kind::Robot,
        "reach" => |k| k == Kind::Arm,
        "for" => |k| k == Kind::Object,
        _ => |k| !matches!(k, Kind::Request | Kind::Task | Kind::Grasp | Kind::Rest),
    }
}

/// The declared names whose kind `fits`, with their kinds.
fn names(analysis: Option<&Analysis>, fits: fn(Kind) -> bool) -> Vec<CompletionItem> {
    let Some(analysis) = analysis else {
        return Vec::new();
    };
    let mut seen = std::collections::BTreeSet::new();
    analysis
        .index
        .occurrences
        .iter()
        .filter_map(|o| Some((o, o.declares?)))
        .filter(|(o, kind)| fits(*kind) && matches!(o.key, Key::Global(_)))
        .filter(|(o, _)| seen.insert(o.key.name().to_string()))
        .map(|(o, kind)| CompletionItem {
            label: o.key.name().to_string(),
            kind: Some(item_kind(kind)),
            detail: Some(kind.noun().to_string()),
            ..CompletionItem::default()
        })
        .collect()
}

/// An arm's joints inside `home (`, or its links after `allow contact ... ARM.`; `None`
/// where neither applies.
fn robot_words(analysis: Option<&Analysis>, typed: &str) -> Option<Vec<CompletionItem>> {
    let cell = analysis?.compilation.cell.as_ref()?;
    let robot_named = |name: &str| {
        cell.robots
            .iter()
            .find(|(_, r)| r.name == name)
            .map(|(_, r)| r)
    };
    let words: Vec<String> =
        if let Some(home) = typed.rfind("home (").filter(|&i| !typed[i..].contains(')')) {
            // `arm NAME = ROBOT at ...`: the robot is the word after `=`.
            let robot = typed[..home].split('=').nth(1)?.split_whitespace().next()?;
            robot_named(robot)?
                .chain_joints
                .iter()
                .map(|j| j.name.clone())
                .collect()
        } else if typed.trim_start().starts_with("allow contact") && typed.ends_with('.') {
            let arm = typed[..typed.len() - 1].split_whitespace().last()?;
            let (_, e) = cell.end_effectors.iter().find(|(_, e)| e.name == arm)?;
            let cellc_compiler::model::Body::Arm {
                robot: Some(robot), ..
            } = &e.body
            else {
                return None;
            };
            cell.robots.get(*robot)?.links.iter().cloned().collect()
        } else {
            return None;
        };
    Some(
        words
            .into_iter()
            .map(|w| CompletionItem {
                label: w,
                kind: Some(CompletionItemKind::FIELD),
                ..CompletionItem::default()
            })
            .collect(),
    )
}

fn item_kind(kind: Kind) -> CompletionItemKind {
    match kind {
        Kind::Workspace => CompletionItemKind::MODULE,
        Kind::Fixed | Kind::Movable | Kind::Arm | Kind::Surface => CompletionItemKind::CLASS,
        Kind::Hand | Kind::Support => CompletionItemKind::STRUCT,
        Kind::Robot => CompletionItemKind::UNIT,
        Kind::Object => CompletionItemKind::VARIABLE,
        Kind::Grasp | Kind::Rest => CompletionItemKind::FIELD,
        Kind::Obstacle => CompletionItemKind::CONSTANT,
        Kind::Request | Kind::Task => CompletionItemKind::FUNCTION,
    }
}
