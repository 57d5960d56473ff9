//! One open cell compiled through the driver ([`cellc_driver::compile_reusing`]): the
//! compilation (sources, resolved cell, diagnostics, and the resolver's table of names,
//! [`cellc_compiler::names::Names`], which every request about a name reads), made again
//! only when a file it reads changed, and read by every request until then.
//!
//! The trees of unchanged files are kept ([`ParseCache`]): a keystroke in a cell parses
//! that cell again, not the libraries it includes, and the trees the requests read
//! (quantities under the cursor, what a holder can hold on a half-typed line) are the
//! ones the compiler just used, not parsed a second time.
//!
//! `reach ARM auto` samples kinematics for seconds; an edit that does not touch the
//! scene must not pay that again, so the runtime's answers are kept by the scene they
//! answered ([`ReachCache`], the driver's).

use std::cell::RefCell;
use std::collections::HashMap;

use cellc_compiler::load::Parser;
use cellc_compiler::names::Names;
use cellc_compiler::{Compilation, CompileOptions, Files};
use cellc_lang::{ast, Diagnostic, FileId, Parsed};

pub use cellc_driver::ReachCache;

/// The most source text the parse cache keeps (the most one compilation reads); past
/// this it starts again.
const MAX_CACHED_TEXT: usize = cellc_compiler::load::MAX_TOTAL_SOURCE_BYTES as usize;

/// The trees of files, by path, with the text each was parsed from: a file whose text
/// is the same as last time gets its tree back without being parsed.
#[derive(Default)]
pub struct ParseCache {
    trees: RefCell<HashMap<String, Parsing>>,
    /// How many texts were parsed (not found in the cache).
    pub misses: std::cell::Cell<usize>,
}

/// One file's text and what parsing it as file 0 gave.
struct Parsing {
    text: String,
    file: Option<ast::File>,
    diagnostics: Vec<Diagnostic>,
}

impl Parser for ParseCache {
    fn parse(&self, id: FileId, path: &str, text: &str) -> Parsed {
        // The tree has no file ids (spans are offsets); only the labels of the
        // diagnostics name the file, and are given this compilation's id.
        let with_id = |p: &Parsing| Parsed {
            file: p.file.clone(),
            diagnostics: p
                .diagnostics
                .iter()
                .cloned()
                .map(|mut d| {
                    d.labels.iter_mut().for_each(|l| l.file = id);
                    d
                })
                .collect(),
        };
        if let Some(p) = self.trees.borrow().get(path).filter(|p| p.text == text) {
            return with_id(p);
        }
        self.misses.set(self.misses.get() + 1);
        let parsed = cellc_lang::parse(FileId(0), text);
        let parsing = Parsing {
            text: text.to_string(),
            file: parsed.file,
            diagnostics: parsed.diagnostics,
        };
        let answer = with_id(&parsing);
        let mut trees = self.trees.borrow_mut();
        let kept: usize = trees.values().map(|p| p.text.len()).sum();
        if kept + text.len() > MAX_CACHED_TEXT {
            trees.clear();
        }
        trees.insert(path.to_string(), parsing);
        answer
    }
}

/// A cell compiled from its open document.
pub struct Analysis {
    /// The compilation, with every file it read and every name written in them.
    pub compilation: Compilation,
    /// Each cell file's syntax tree, when it parsed (the trees the compiler used).
    pub trees: Vec<(FileId, Option<ast::File>)>,
}

impl Analysis {
    /// Compiles the cell at `path` through `files`.
    pub fn new(
        files: &dyn Files,
        caches: (&ReachCache, &ParseCache),
        path: &str,
        options: &CompileOptions,
    ) -> Analysis {
        let (reach, parser) = caches;
        let compilation = cellc_driver::compile_reusing(files, path, options, parser, reach);
        // The files' trees, found in the cache the compiler just filled.
        let trees = compilation
            .sources
            .iter()
            .map(|(id, f)| (id, parser.parse(id, &f.path, &f.text).file))
            .collect();
        Analysis { compilation, trees }
    }

    /// Every name of the compilation's files, as the resolver scoped them.
    pub fn names(&self) -> &Names {
        &self.compilation.names
    }

    /// True when this compilation read (or tried to include) a file of `changed`, or is
    /// the compilation of one: it must be made again.
    pub fn reads_any(&self, path: &str, changed: &std::collections::BTreeSet<String>) -> bool {
        changed.contains(path)
            || self
                .compilation
                .sources
                .iter()
                .any(|(_, f)| changed.contains(&f.path))
            || self
                .names()
                .includes()
                .iter()
                .any(|i| changed.contains(&i.path))
    }

    /// The id of the file at `path` in this compilation.
    pub fn file(&self, path: &str) -> Option<FileId> {
        self.compilation
            .sources
            .iter()
            .find(|(_, f)| f.path == path)
            .map(|(id, _)| id)
    }

    /// The path and text of a file of this compilation.
    pub fn source(&self, file: FileId) -> Option<(&str, &str)> {
        self.compilation
            .sources
            .iter()
            .find(|(id, _)| *id == file)
            .map(|(_, f)| (f.path.as_str(), f.text.as_str()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use cellc_compiler::MemoryFiles;

    fn files() -> MemoryFiles {
        let mut files = MemoryFiles::default();
        files.insert(
            "/c/main.cell",
            "cell main {\n  include \"lib.cell\"\n  fixed t reaches w1\n}\n",
        );
        files.insert("/c/lib.cell", "library lib {\n  workspace w1\n}\n");
        files.insert("/c/other.cell", "cell other {\n  workspace w2\n}\n");
        files
    }

    #[test]
    fn unchanged_files_are_not_parsed_again() {
        let files = files();
        let (reach, trees) = (ReachCache::default(), ParseCache::default());
        let options = CompileOptions::default();
        let first = Analysis::new(&files, (&reach, &trees), "/c/main.cell", &options);
        assert_eq!(trees.misses.get(), 2, "main and lib, once each");
        assert!(
            first.compilation.diagnostics.is_empty(),
            "{:?}",
            first.compilation.diagnostics
        );
        assert_eq!(first.trees.len(), 2);
        // The cell edited (an error in it): only it is parsed again, and the error's
        // label names the cell's id.
        let mut edited = files;
        edited.insert(
            "/c/main.cell",
            "cell main {\n  include \"lib.cell\"\n  fixed t reaches w1 w2\n}\n",
        );
        let second = Analysis::new(&edited, (&reach, &trees), "/c/main.cell", &options);
        assert_eq!(trees.misses.get(), 3);
        let d = &second.compilation.diagnostics;
        assert!(!d.is_empty());
        assert!(
            d.iter()
                .all(|d| d.labels.iter().all(|l| l.file == FileId(0))),
            "{d:?}"
        );
        // The library alone, compiled as its own unit: its tree is found, with its id.
        let lib = Analysis::new(&edited, (&reach, &trees), "/c/lib.cell", &options);
        assert_eq!(trees.misses.get(), 3);
        assert_eq!(lib.file("/c/lib.cell"), Some(FileId(0)));
    }

    #[test]
    fn a_change_invalidates_the_compilations_that_read_it() {
        let files = files();
        let (reach, trees) = (ReachCache::default(), ParseCache::default());
        let options = CompileOptions::default();
        let main = Analysis::new(&files, (&reach, &trees), "/c/main.cell", &options);
        let other = Analysis::new(&files, (&reach, &trees), "/c/other.cell", &options);
        let changed: std::collections::BTreeSet<String> = ["/c/lib.cell".to_string()].into();
        assert!(main.reads_any("/c/main.cell", &changed));
        assert!(!other.reads_any("/c/other.cell", &changed));
        let itself: std::collections::BTreeSet<String> = ["/c/other.cell".to_string()].into();
        assert!(other.reads_any("/c/other.cell", &itself));
        assert!(!main.reads_any("/c/main.cell", &itself));
    }
}
