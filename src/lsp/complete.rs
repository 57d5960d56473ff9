//! Completion: item and member keywords where an item or member starts, and elsewhere
//! the names in scope, narrowed by the word before the cursor to the kinds the grammar
//! allows there (holder kinds after `with`, `by` and `on`, workspaces after `in` and
//! `reaches`, robots after `=`, an arm's joints in `home (...)`, its links after `ARM.`
//! in `allow contact`, an object's grasps after `HOLDER.` in placements and in
//! transitions).
//!
//! Names come from the last compilation of the document, so a name declared in an
//! include is offered and one being typed right now is not (yet).

use std::collections::BTreeMap;

use cellc_lang::ast::{GraspKeyword, Item, ObjectMember};
use cellc_lang::keywords;
use lsp_types::{CompletionItem, CompletionItemKind, CompletionParams, CompletionResponse};

use super::analysis::Analysis;
use super::analysis_for;
use super::documents::{path_of, Documents};
use super::position::Lines;
use cellc_compiler::names::{Key, Kind};

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
            keywords::MEMBER_KEYWORDS
        } else {
            keywords::ITEM_KEYWORDS
        };
        words
            .iter()
            .map(|k| CompletionItem {
                label: k.completion.to_string(),
                kind: Some(CompletionItemKind::KEYWORD),
                ..CompletionItem::default()
            })
            .collect()
    } else if let Some(words) = robot_words(analysis, typed) {
        words
    } else if let Some(words) = grasp_words(analysis, &text[..line_start], typed) {
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
    enclosing_header(before)?.first().copied()
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
        .names()
        .occurrences()
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

/// Grasps: after `HOLDER.` in a placement (a request's, an expectation's, a world
/// entry's, a task step's), the grasps of the placed object that `HOLDER` can hold; in a
/// transition, the grasps of the object being declared, or of `OBJECT` after `OBJECT.`.
/// `None` where no grasp is wanted.
fn grasp_words(
    analysis: Option<&Analysis>,
    before_line: &str,
    typed: &str,
) -> Option<Vec<CompletionItem>> {
    let analysis = analysis?;
    let words: Vec<&str> = typed
        .split(|c: char| c.is_whitespace() || c == ',')
        .filter(|w| !w.is_empty())
        .collect();
    let dotted = typed
        .strip_suffix('.')
        .map(|t| t.rsplit([' ', '\t', ',']).next().unwrap_or(""));
    let grasps_of = |object: &str| -> Vec<(String, Kind)> {
        analysis
            .names()
            .occurrences()
            .iter()
            .filter_map(|o| match (&o.key, o.declares) {
                (Key::Grasp { object: of, grasp }, Some(kind)) if of == object => {
                    Some((grasp.clone(), kind))
                }
                _ => None,
            })
            .collect()
    };
    let found = if words.first() == Some(&"transition") {
        // `transition a <-> b, OTHER.c`: a name alone is a grasp of this object.
        match dotted {
            Some(other) => grasps_of(other),
            None => {
                let object = enclosing_header(before_line)?;
                (object.first() == Some(&"object")).then_some(())?;
                grasps_of(object.get(1)?)
            }
        }
    } else {
        let holder = dotted?;
        let object = match words.first()? {
            &"request" => typed.split(':').nth(1)?.split_whitespace().next()?,
            &"expect" => words.get(1)?.trim_end_matches(':'),
            // A world entry (`OBJECT: ...`) or a task step (`OBJECT to ...`).
            first => first.trim_end_matches(':'),
        };
        holdable(analysis, object, holder).unwrap_or_else(|| grasps_of(object))
    };
    if found.is_empty() {
        return None;
    }
    let mut seen = std::collections::BTreeSet::new();
    Some(
        found
            .into_iter()
            .filter(|(name, _)| seen.insert(name.clone()))
            .map(|(name, kind)| CompletionItem {
                label: name,
                kind: Some(CompletionItemKind::FIELD),
                detail: Some(kind.noun().to_string()),
                ..CompletionItem::default()
            })
            .collect(),
    )
}

/// The grasps of `object` that end-effector `holder` can hold: those declared `by` it or
/// by its holder kind (an arm's `with`, a surface's `: KIND`), read from the trees so
/// that a cell with errors (the line being typed) is answered too; `None` when `holder`
/// is not an end-effector.
fn holdable(analysis: &Analysis, object: &str, holder: &str) -> Option<Vec<(String, Kind)>> {
    if !analysis
        .names()
        .kind_of(&Key::Global(holder.to_string()))?
        .is_end_effector()
    {
        return None;
    }
    let items = || {
        analysis
            .trees
            .iter()
            .filter_map(|(_, t)| t.as_ref())
            .flat_map(|t| t.items.iter())
    };
    let kind = items().find_map(|i| match i {
        Item::Arm(a) if a.name.text == holder => Some(a.kind.text.as_str()),
        Item::Surface(s) if s.name.text == holder => Some(s.kind.text.as_str()),
        _ => None,
    });
    let declared = items().find_map(|i| match i {
        Item::Object(o) if o.name.text == object => Some(o),
        _ => None,
    })?;
    Some(
        declared
            .members
            .iter()
            .filter_map(|m| match m {
                ObjectMember::Grasp(g)
                    if g.holder.text == holder || Some(g.holder.text.as_str()) == kind =>
                {
                    let kind = match g.keyword {
                        GraspKeyword::Grasp => Kind::Grasp,
                        GraspKeyword::Rest => Kind::Rest,
                    };
                    Some((g.name.text.clone(), kind))
                }
                _ => None,
            })
            .collect(),
    )
}

/// The words of the line that opened the innermost open block (`object cup {`).
fn enclosing_header(before: &str) -> Option<Vec<&str>> {
    let mut depth = 0;
    for (i, c) in before.char_indices().rev() {
        match c {
            '}' => depth += 1,
            '{' if depth > 0 => depth -= 1,
            '{' => {
                let start = before[..i].rfind('\n').map_or(0, |n| n + 1);
                return Some(before[start..i].split_whitespace().collect());
            }
            _ => {}
        }
    }
    None
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
