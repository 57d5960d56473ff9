//! Go to definition, find references, rename, the outline and workspace symbols, all
//! read from the compilation's table of names (the resolver's scoping,
//! [`cellc_compiler::names`]).

use std::collections::BTreeMap;

use cellc_lang::{FileId, Span};
use lsp_types::{
    DocumentSymbol, DocumentSymbolParams, DocumentSymbolResponse, GotoDefinitionParams,
    GotoDefinitionResponse, Location, OneOf, Range, ReferenceParams, SymbolKind, WorkspaceSymbol,
    WorkspaceSymbolParams, WorkspaceSymbolResponse,
};

use super::analysis::Analysis;
use super::analysis_for;
use super::documents::{path_of, uri_of};
use super::position::Lines;
use cellc_compiler::names::{Key, Kind, Occurrence};

/// The location of `span` in `file` of `analysis`.
pub fn location(analysis: &Analysis, file: FileId, span: Span) -> Option<Location> {
    let (path, text) = analysis.source(file)?;
    Some(Location::new(uri_of(path)?, Lines::new(text).range(span)))
}

/// The analysis, file and byte offset of a position in a document.
pub fn locate<'a>(
    analyses: &'a BTreeMap<String, Analysis>,
    at: &lsp_types::TextDocumentPositionParams,
) -> Option<(&'a Analysis, FileId, usize)> {
    let (analysis, file) = analysis_for(analyses, &at.text_document.uri)?;
    let (_, text) = analysis.source(file)?;
    Some((analysis, file, Lines::new(text).offset(at.position)))
}

/// Where the name under the cursor is declared; an include's path goes to the file.
pub fn definition(
    analyses: &BTreeMap<String, Analysis>,
    params: GotoDefinitionParams,
) -> Option<GotoDefinitionResponse> {
    let (analysis, file, offset) = locate(analyses, &params.text_document_position_params)?;
    if let Some(include) = analysis.names().include_at(file, offset) {
        let uri = uri_of(&include.path)?;
        return Some(GotoDefinitionResponse::Scalar(Location::new(
            uri,
            Range::default(),
        )));
    }
    let occurrence = analysis.names().at(file, offset)?;
    let mut found: Vec<Location> = analysis
        .names()
        .declarations(&occurrence.key)
        .filter_map(|d| location(analysis, d.file, d.span))
        .collect();
    if found.is_empty() {
        // A derived workspace is declared by the `workspaces from reach` line.
        let cell = analysis.compilation.cell.as_ref()?;
        let derived = cell
            .workspaces
            .iter()
            .any(|(_, w)| w.derived && w.name == occurrence.key.name());
        if derived && matches!(occurrence.key, Key::Global(_)) {
            let origin = cell.derive_workspaces?;
            found.extend(location(analysis, origin.file, origin.span));
        }
    }
    match found.len() {
        0 => None,
        1 => found.pop().map(GotoDefinitionResponse::Scalar),
        _ => Some(GotoDefinitionResponse::Array(found)),
    }
}

/// Every place the name under the cursor is written, in every open cell that reads the
/// file (a library's name is used by the cells that include it).
pub fn references(
    analyses: &BTreeMap<String, Analysis>,
    params: ReferenceParams,
) -> Option<Vec<Location>> {
    let at = &params.text_document_position;
    let (analysis, file, offset) = locate(analyses, at)?;
    let key = analysis.names().at(file, offset)?.key.clone();
    let path = path_of(&at.text_document.uri)?;
    let mut found: Vec<Location> = Vec::new();
    for a in analyses.values().filter(|a| a.file(&path).is_some()) {
        let places = a
            .names()
            .occurrences_of(&key)
            .filter(|o| params.context.include_declaration || o.declares.is_none());
        for o in places {
            if let Some(l) = location(a, o.file, o.span) {
                if !found.contains(&l) {
                    found.push(l);
                }
            }
        }
    }
    Some(found)
}

/// The protocol's kind of symbol for a declaration.
pub fn symbol_kind(kind: Kind) -> SymbolKind {
    match kind {
        Kind::Workspace => SymbolKind::NAMESPACE,
        Kind::Fixed | Kind::Movable | Kind::Arm | Kind::Surface => SymbolKind::CLASS,
        Kind::Hand | Kind::Support => SymbolKind::STRUCT,
        Kind::Robot => SymbolKind::PACKAGE,
        Kind::Object => SymbolKind::OBJECT,
        Kind::Grasp | Kind::Rest => SymbolKind::FIELD,
        Kind::Obstacle => SymbolKind::CONSTANT,
        Kind::Request => SymbolKind::FUNCTION,
        Kind::Task => SymbolKind::EVENT,
    }
}

/// The outline: the items that declare a name, an object's grasps under it.
pub fn document_symbols(
    analyses: &BTreeMap<String, Analysis>,
    params: DocumentSymbolParams,
) -> Option<DocumentSymbolResponse> {
    let (analysis, file) = analysis_for(analyses, &params.text_document.uri)?;
    let (_, text) = analysis.source(file)?;
    let lines = Lines::new(text);
    let declared: Vec<&Occurrence> = analysis
        .names()
        .occurrences()
        .iter()
        .filter(|o| o.file == file && o.declares.is_some())
        .collect();
    let symbol = |o: &Occurrence, children: Option<Vec<DocumentSymbol>>| {
        let kind = o.declares.unwrap_or(Kind::Object);
        #[allow(deprecated)] // `deprecated` is a field the type still requires.
        DocumentSymbol {
            name: o.key.name().to_string(),
            detail: Some(kind.noun().to_string()),
            kind: symbol_kind(kind),
            tags: None,
            deprecated: None,
            range: lines.range(o.item),
            selection_range: lines.range(o.span),
            children,
        }
    };
    let symbols = declared
        .iter()
        .filter(|o| !matches!(o.key, Key::Grasp { .. }))
        .map(|o| {
            let children: Vec<DocumentSymbol> = declared
                .iter()
                .filter(|g| matches!(&g.key, Key::Grasp { object, .. } if o.declares == Some(Kind::Object) && object == o.key.name()))
                .map(|g| symbol(g, None))
                .collect();
            symbol(o, (!children.is_empty()).then_some(children))
        })
        .collect();
    Some(DocumentSymbolResponse::Nested(symbols))
}

/// Every declaration of every open cell whose name contains the query (ignoring case).
pub fn workspace_symbols(
    analyses: &BTreeMap<String, Analysis>,
    params: WorkspaceSymbolParams,
) -> Option<WorkspaceSymbolResponse> {
    let query = params.query.to_lowercase();
    let mut found: Vec<WorkspaceSymbol> = Vec::new();
    for a in analyses.values() {
        for o in a.names().occurrences().iter() {
            let Some(kind) = o.declares else { continue };
            if !o.key.name().to_lowercase().contains(&query) {
                continue;
            }
            let Some(l) = location(a, o.file, o.span) else {
                continue;
            };
            if found.iter().any(|s| s.location == OneOf::Left(l.clone())) {
                continue;
            }
            found.push(WorkspaceSymbol {
                name: o.key.name().to_string(),
                kind: symbol_kind(kind),
                tags: None,
                container_name: match &o.key {
                    Key::Grasp { object, .. } => Some(object.clone()),
                    _ => None,
                },
                location: OneOf::Left(l),
                data: None,
            });
        }
    }
    Some(WorkspaceSymbolResponse::Nested(found))
}
