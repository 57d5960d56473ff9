//! Reads the main file and everything it includes, parsing each once.

use cellc_lang::ast::{self, FileKind};
use cellc_lang::{Diagnostic, FileId, SourceMap};

use crate::diagnostics;
use cellc_schema::files::{join, normalize, Files};

/// One parsed file.
#[derive(Debug)]
pub struct LoadedFile {
    /// Its id in the source map.
    pub id: FileId,
    /// Normalised path.
    pub path: String,
    /// The tree, when the file's outline parsed.
    pub ast: Option<ast::File>,
}

/// The main file and its includes, in the order they were first read (main first).
#[derive(Debug, Default)]
pub struct Loaded {
    /// Every file read.
    pub sources: SourceMap,
    /// Parsed files.
    pub files: Vec<LoadedFile>,
    /// Syntax errors and include problems.
    pub diagnostics: Vec<Diagnostic>,
}

/// Reads `path` and, depth first, every file it includes. A file included twice (a
/// diamond) is read once; a file that includes itself through a chain is an error.
pub fn load(files: &dyn Files, path: &str) -> Loaded {
    let mut loaded = Loaded::default();
    let path = normalize(path);
    let mut stack = Vec::new();
    load_file(files, &path, None, &mut stack, &mut loaded);
    loaded
}

fn load_file(
    files: &dyn Files,
    path: &str,
    included_at: Option<(FileId, cellc_lang::Span)>,
    stack: &mut Vec<String>,
    loaded: &mut Loaded,
) {
    let text = match files.read_text(path) {
        Ok(text) => text,
        Err(error) => {
            loaded
                .diagnostics
                .push(diagnostics::file_unreadable(path, &error, included_at));
            return;
        }
    };
    let id = loaded.sources.add(path, text);
    let parsed = cellc_lang::parse(id, &loaded.sources.get(id).text);
    loaded.diagnostics.extend(parsed.diagnostics);
    let includes: Vec<(String, cellc_lang::Span)> = parsed
        .file
        .iter()
        .flat_map(|f| f.items.iter())
        .filter_map(|item| match item {
            ast::Item::Include(inc) => Some((join(path, &inc.path.value), inc.span)),
            _ => None,
        })
        .collect();
    if let (Some(file), Some(at)) = (&parsed.file, included_at) {
        if file.kind == FileKind::Cell {
            loaded
                .diagnostics
                .push(diagnostics::included_cell(path, at.0, at.1));
        }
    }
    loaded.files.push(LoadedFile {
        id,
        path: path.to_string(),
        ast: parsed.file,
    });
    stack.push(path.to_string());
    for (include, span) in includes {
        if let Some(start) = stack.iter().position(|p| *p == include) {
            let mut chain: Vec<String> = stack[start..].to_vec();
            chain.push(include.clone());
            loaded
                .diagnostics
                .push(diagnostics::include_cycle(id, span, &chain));
            continue;
        }
        if loaded.files.iter().any(|f| f.path == include) {
            continue;
        }
        load_file(files, &include, Some((id, span)), stack, loaded);
    }
    stack.pop();
}
