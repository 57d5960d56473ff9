//! Reads the main file and everything it includes, parsing each once.
//!
//! Every file is read within [`MAX_SOURCE_BYTES`] and screened before it is parsed: a file
//! that is not a cell at all (binary, not UTF-8, no `cell`/`library` outline) is reported
//! by what it is and never enters the source map, so no snippet can ever show its lines.

use std::collections::{HashMap, HashSet};

use cellc_lang::ast::{self, FileKind};
use cellc_lang::{Diagnostic, FileId, SourceMap, Span};
use cellc_schema::files::{join, normalize, FileError, Files, MAX_SOURCE_BYTES};

use crate::diagnostics::{self, NotCellReason};

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
    /// Grasp-set files (`grasp NAME by HAND from "FILE"`) read, by normalised path, each
    /// in the source map so that a bad row is shown in the file.
    pub grasp_files: HashMap<String, FileId>,
    /// Every `include` line of the files read, with the path it names (read or not).
    pub includes: Vec<crate::names::Include>,
}

/// How the loader turns a file's text into a tree.
///
/// [`Fresh`] parses every time. A language server compiles the same files after every
/// keystroke, most of them unchanged (the libraries a cell includes), so it passes a
/// parser that returns the tree it already has for the same path and text.
pub trait Parser {
    /// The tree and syntax diagnostics of `text`, read from `path`, as file `id` of the
    /// source map (the diagnostics' labels name `id`).
    fn parse(&self, id: FileId, path: &str, text: &str) -> cellc_lang::Parsed;
}

/// Parses every file as it is read.
pub struct Fresh;

impl Parser for Fresh {
    fn parse(&self, id: FileId, _path: &str, text: &str) -> cellc_lang::Parsed {
        cellc_lang::parse(id, text)
    }
}

/// The most source text one compilation reads, the main file and its includes together
/// (64 MiB): each file is also at most [`MAX_SOURCE_BYTES`].
pub const MAX_TOTAL_SOURCE_BYTES: u64 = 64 << 20;

/// Reads `path` and, depth first, every file it includes. A file included twice (a
/// diamond) is read once; a file that includes itself through a chain is an error.
///
/// The walk keeps its own stack rather than recursing, so a chain of thousands of
/// includes cannot overflow the thread's stack.
pub fn load(files: &dyn Files, path: &str) -> Loaded {
    load_with(files, &Fresh, path)
}

/// [`load`], with the trees made by `parser`.
pub fn load_with(files: &dyn Files, parser: &dyn Parser, path: &str) -> Loaded {
    let mut loader = Loader {
        files,
        parser,
        read: HashSet::new(),
        bytes_left: MAX_TOTAL_SOURCE_BYTES,
        loaded: Loaded::default(),
        grasp_failed: HashSet::new(),
    };
    let mut stack: Vec<Frame> = Vec::new();
    // Path -> its index in `stack`, for include cycles.
    let mut on_stack: HashMap<String, usize> = HashMap::new();
    if let Some(frame) = loader.read_file(&normalize(path), None) {
        on_stack.insert(frame.path.clone(), 0);
        stack.push(frame);
    }
    while let Some(top) = stack.last_mut() {
        let Some((include, span)) = top.includes.get(top.next).cloned() else {
            if let Some(done) = stack.pop() {
                on_stack.remove(&done.path);
            }
            continue;
        };
        top.next += 1;
        let including = top.id;
        if let Some(&start) = on_stack.get(&include) {
            let mut chain: Vec<String> = stack[start..].iter().map(|f| f.path.clone()).collect();
            chain.push(include);
            loader
                .loaded
                .diagnostics
                .push(diagnostics::include_cycle(including, span, &chain));
            continue;
        }
        if loader.read.contains(&include) {
            continue;
        }
        if let Some(frame) = loader.read_file(&include, Some((including, span))) {
            on_stack.insert(frame.path.clone(), stack.len());
            stack.push(frame);
        }
    }
    loader.loaded
}

/// Reads one cell or library as the loader does: at most `budget` bytes (refused as too
/// large for [`MAX_SOURCE_BYTES`], or for what [`MAX_TOTAL_SOURCE_BYTES`] leaves when
/// `budget` is smaller), and screened, so that a file that is not a cell is described and
/// its text dropped. `included_at` is the `include` that names it.
pub fn read_source(
    files: &dyn Files,
    path: &str,
    budget: u64,
    included_at: Option<(FileId, Span)>,
) -> Result<String, Diagnostic> {
    let bytes = match files.read_at_most(path, budget) {
        Ok(bytes) => bytes,
        Err(FileError::TooLarge { size, .. })
            if budget < MAX_SOURCE_BYTES && size <= MAX_SOURCE_BYTES =>
        {
            return Err(diagnostics::sources_too_large(
                path,
                MAX_TOTAL_SOURCE_BYTES,
                included_at,
            ));
        }
        Err(error) => return Err(diagnostics::file_unreadable(path, &error, included_at)),
    };
    let size = bytes.len();
    let not_a_cell = |reason| diagnostics::not_a_cell_file(path, size, reason, included_at);
    let text = String::from_utf8(bytes).map_err(|error| {
        not_a_cell(NotCellReason::NotUtf8 {
            offset: error.utf8_error().valid_up_to(),
        })
    })?;
    if let Some(reason) = cellc_lang::not_a_cell(&text) {
        return Err(not_a_cell(NotCellReason::Screen(reason)));
    }
    Ok(text)
}

/// A file being walked: its includes, and how many of them are done.
struct Frame {
    path: String,
    id: FileId,
    includes: Vec<(String, Span)>,
    next: usize,
}

struct Loader<'f> {
    files: &'f dyn Files,
    parser: &'f dyn Parser,
    /// Paths read and parsed.
    read: HashSet<String>,
    /// What [`MAX_TOTAL_SOURCE_BYTES`] leaves.
    bytes_left: u64,
    loaded: Loaded,
    /// Grasp-set files that could not be read (reported once).
    grasp_failed: HashSet<String>,
}

impl Loader<'_> {
    /// Reads, screens and parses one file; `None` when it is not read (the problem is
    /// reported).
    fn read_file(&mut self, path: &str, included_at: Option<(FileId, Span)>) -> Option<Frame> {
        let diagnostics = &mut self.loaded.diagnostics;
        let budget = MAX_SOURCE_BYTES.min(self.bytes_left);
        let text = match read_source(self.files, path, budget, included_at) {
            Ok(text) => text,
            Err(d) => {
                diagnostics.push(d);
                return None;
            }
        };
        self.bytes_left -= text.len() as u64;
        let id = self.loaded.sources.add(path, text);
        let parsed = self
            .parser
            .parse(id, path, &self.loaded.sources.get(id).text);
        diagnostics.extend(parsed.diagnostics);
        let grasp_files = grasp_files_named(path, parsed.file.as_ref());
        let includes: Vec<(String, Span)> = parsed
            .file
            .iter()
            .flat_map(|f| f.items.iter())
            .filter_map(|item| match item {
                ast::Item::Include(inc) => Some((join(path, &inc.path.value), inc.span)),
                _ => None,
            })
            .collect();
        for item in parsed.file.iter().flat_map(|f| f.items.iter()) {
            if let ast::Item::Include(inc) = item {
                self.loaded.includes.push(crate::names::Include {
                    file: id,
                    span: inc.path.span,
                    path: join(path, &inc.path.value),
                });
            }
        }
        if let (Some(file), Some(at)) = (&parsed.file, included_at) {
            if file.kind == FileKind::Cell {
                diagnostics.push(diagnostics::included_cell(path, at.0, at.1));
            }
        }
        self.loaded.files.push(LoadedFile {
            id,
            path: path.to_string(),
            ast: parsed.file,
        });
        self.read.insert(path.to_string());
        self.read_grasp_files(id, grasp_files);
        Some(Frame {
            path: path.to_string(),
            id,
            includes,
            next: 0,
        })
    }

    /// Reads the grasp-set files a cell file names (each once per compilation), within
    /// [`crate::grasp_file::MAX_GRASP_FILE_BYTES`] and the total budget; a file that is
    /// not text never enters the source map.
    fn read_grasp_files(&mut self, id: FileId, named: Vec<(String, Span)>) {
        for (grasps, span) in named {
            if self.loaded.grasp_files.contains_key(&grasps) || self.grasp_failed.contains(&grasps)
            {
                continue;
            }
            match self.read_grasp_file(&grasps, (id, span)) {
                Ok(text) => {
                    self.bytes_left -= text.len() as u64;
                    let fid = self.loaded.sources.add(grasps.clone(), text);
                    self.loaded.grasp_files.insert(grasps, fid);
                }
                Err(d) => {
                    self.loaded.diagnostics.push(d);
                    self.grasp_failed.insert(grasps);
                }
            }
        }
    }

    fn read_grasp_file(&self, path: &str, at: (FileId, Span)) -> Result<String, Diagnostic> {
        let budget = crate::grasp_file::MAX_GRASP_FILE_BYTES.min(self.bytes_left);
        let bytes = self.files.read_at_most(path, budget).map_err(|error| {
            diagnostics::refused_file("grasp-set file", path, &error, Some(at)).unwrap_or_else(
                || {
                    Diagnostic::error(
                        diagnostics::codes::FILE_UNREADABLE,
                        format!("cannot read grasp-set file `{path}`: {error}"),
                    )
                    .primary(at.0, at.1, "named here")
                    .help("check the path: it is relative to the file that names it")
                },
            )
        })?;
        let text = String::from_utf8(bytes).map_err(|e| {
            diagnostics::grasp_file_not_text(
                path,
                at,
                &format!("not UTF-8 at byte {}", e.utf8_error().valid_up_to()),
            )
        })?;
        if let Some(offset) =
            text.find(|c: char| c.is_control() && !matches!(c, '\n' | '\r' | '\t'))
        {
            return Err(diagnostics::grasp_file_not_text(
                path,
                at,
                &format!("a control character at byte {offset}"),
            ));
        }
        Ok(text)
    }
}

/// The grasp-set files (`grasp NAME by HAND from "FILE"`) a file names, each joined to the
/// file's path, with the span of its name.
fn grasp_files_named(path: &str, file: Option<&ast::File>) -> Vec<(String, Span)> {
    let objects = file
        .iter()
        .flat_map(|f| f.items.iter())
        .filter_map(|item| match item {
            ast::Item::Object(o) => Some(o),
            _ => None,
        });
    objects
        .flat_map(|o| o.members.iter())
        .filter_map(|member| match member {
            ast::ObjectMember::Grasp(g) => g.file.as_ref(),
            _ => None,
        })
        .map(|name| (join(path, &name.value), name.span))
        .collect()
}
