//! How the compiler reaches files.
//!
//! The compiler does no I/O itself: it asks a [`World`] for the text of a path. The CLI
//! implements it on the file system; tests and an editor server implement it on memory.

use std::collections::HashMap;

/// Supplies file contents to the compiler.
pub trait World {
    /// The text of the file at `path` (as produced by [`join`]), or why it can't be read.
    fn read(&self, path: &str) -> Result<String, String>;
}

/// A world held in memory: path -> text.
#[derive(Clone, Debug, Default)]
pub struct MemoryWorld {
    /// The files.
    pub files: HashMap<String, String>,
}

impl MemoryWorld {
    /// A world with the given files.
    pub fn new<'a>(files: impl IntoIterator<Item = (&'a str, &'a str)>) -> MemoryWorld {
        MemoryWorld {
            files: files
                .into_iter()
                .map(|(p, t)| (normalize(p), t.to_string()))
                .collect(),
        }
    }
}

impl World for MemoryWorld {
    fn read(&self, path: &str) -> Result<String, String> {
        self.files
            .get(&normalize(path))
            .cloned()
            .ok_or_else(|| "no such file".to_string())
    }
}

/// The path of `relative` as seen from the file `base` (relative to `base`'s folder,
/// unless absolute), normalised.
pub fn join(base: &str, relative: &str) -> String {
    if relative.starts_with('/') {
        return normalize(relative);
    }
    let folder = match base.rfind('/') {
        Some(i) => &base[..=i],
        None => "",
    };
    normalize(&format!("{folder}{relative}"))
}

/// Removes `.` and resolves `..` lexically, so that one file always has one name (include
/// cycles are found by comparing names).
pub fn normalize(path: &str) -> String {
    let absolute = path.starts_with('/');
    let mut parts: Vec<&str> = Vec::new();
    for part in path.split('/') {
        match part {
            "" | "." => {}
            ".." => {
                if matches!(parts.last(), Some(p) if *p != "..") {
                    parts.pop();
                } else if !absolute {
                    parts.push("..");
                }
            }
            other => parts.push(other),
        }
    }
    let joined = parts.join("/");
    if absolute {
        format!("/{joined}")
    } else {
        joined
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn joins_relative_to_the_including_file() {
        assert_eq!(
            join("cells/vito.cell", "robots/lwr.cell"),
            "cells/robots/lwr.cell"
        );
        assert_eq!(join("cells/robots/a.cell", "../b.cell"), "cells/b.cell");
        assert_eq!(join("a.cell", "./b.cell"), "b.cell");
        assert_eq!(join("/x/a.cell", "/y/b.cell"), "/y/b.cell");
        assert_eq!(normalize("../../a"), "../../a");
    }
}
