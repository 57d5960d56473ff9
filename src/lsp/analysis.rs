//! One open cell compiled: the compilation (sources, resolved cell, diagnostics) and the
//! index of its names, made once per change and read by every request until the next.
//!
//! `reach ARM auto` samples kinematics for seconds; an edit that does not touch the
//! scene (a comment, a request, a grasp's label) must not pay that again, so the
//! runtime's answers are kept by the scene they answered ([`ReachCache`]).

use std::cell::RefCell;
use std::collections::HashMap;

use cellc_compiler::diagnostics::ReachAutoProblem;
use cellc_compiler::reach::{ReachFound, ReachQuery, ReachSolver};
use cellc_compiler::{Compilation, CompileOptions, Files};
use cellc_lang::{Diagnostic, FileId, SourceMap};
use cellc_schema::Artifact;

use super::index::Index;
use crate::reach::RuntimeReach;

/// Scenes remembered at most; past this the cache starts again.
const MAX_CACHED_SCENES: usize = 16;

/// The answers of one scene's reach.
type Answers = Vec<Result<ReachFound, ReachAutoProblem>>;

/// The runtime's reach answers, by the scene and queries they answer.
#[derive(Default)]
pub struct ReachCache {
    answers: RefCell<HashMap<String, Answers>>,
}

/// The runtime's solver in front of the cache.
struct CachedReach<'a> {
    solver: RuntimeReach<'a>,
    cache: &'a ReachCache,
}

impl ReachSolver for CachedReach<'_> {
    fn solve(
        &self,
        scene: &Artifact,
        sources: &SourceMap,
        queries: &[ReachQuery],
    ) -> Result<Answers, Vec<Diagnostic>> {
        // Where the items are written (spans, source hashes) changes with every edit
        // and changes no reach: the key is the scene without them.
        let mut geometry = scene.clone();
        geometry.sources.clear();
        geometry.spans.clear();
        let key = match serde_json::to_string(&geometry) {
            Ok(json) => format!("{json}{queries:?}"),
            Err(_) => return self.solver.solve(scene, sources, queries),
        };
        if let Some(answers) = self.cache.answers.borrow().get(&key) {
            return Ok(answers.clone());
        }
        // Diagnostics point into this compilation's sources, so only answers are kept.
        let answers = self.solver.solve(scene, sources, queries)?;
        let mut cache = self.cache.answers.borrow_mut();
        if cache.len() >= MAX_CACHED_SCENES {
            cache.clear();
        }
        cache.insert(key, answers.clone());
        Ok(answers)
    }
}

/// A cell compiled from its open document, and its names.
pub struct Analysis {
    /// The compilation, with every file it read.
    pub compilation: Compilation,
    /// Every name of those files.
    pub index: Index,
}

impl Analysis {
    /// Compiles the cell at `path` through `files`.
    pub fn new(
        files: &dyn Files,
        cache: &ReachCache,
        path: &str,
        options: &CompileOptions,
    ) -> Analysis {
        let solver = CachedReach {
            solver: RuntimeReach { files },
            cache,
        };
        let compilation = cellc_compiler::compile_with(files, &solver, path, options);
        let index = Index::build(&compilation.sources);
        Analysis { compilation, index }
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
