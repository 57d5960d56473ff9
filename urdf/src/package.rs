//! Files named the way ROS names them: `package://NAME/path`, `file:///abs/path`, or a
//! path relative to the file that names it.
//!
//! A ROS package is a folder; `package://NAME/rest` is `rest` inside the folder of the
//! package `NAME`. Where that folder is comes from, in this order:
//!
//! 1. a declared root ([`PackagePath::declare`]: a cell's `package NAME at "DIR"`);
//! 2. each search folder in turn ([`PackagePath::search`]: `--package-path DIR`, then the
//!    entries of `ROS_PACKAGE_PATH`). A search folder `DIR` holds package `NAME` when
//!    `DIR/NAME/package.xml` is a file (a folder of packages, like a workspace's `src` or
//!    an install's `share`), or when `DIR` is itself named `NAME` and holds a
//!    `package.xml` (the entry is the package).
//!
//! ROS's own tools crawl every search folder recursively and read each `package.xml` for
//! its name; this looks at two files per search folder and package, so resolving costs a
//! bounded number of file look-ups whatever the folders hold, and the folder's name is
//! taken as the package's name (true of nearly every package). The crate does no I/O:
//! look-ups go through [`Files`].

use std::fmt;

use cellc_schema::files::{join, normalize, FileError, Files};

/// How a file name in a robot description refers to a file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FileRef<'a> {
    /// `package://NAME/path`.
    Package {
        /// The package name.
        package: &'a str,
        /// The path inside the package (without the leading `/`).
        path: &'a str,
    },
    /// A path: relative to the naming file unless absolute (a `file://` prefix dropped).
    Path(&'a str),
}

/// A `package://` URI without a package name or without a path inside the package.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct BadPackageUri;

impl fmt::Display for BadPackageUri {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("a `package://` URI is `package://NAME/path/in/package`")
    }
}

impl std::error::Error for BadPackageUri {}

/// What a written file name refers to.
pub fn file_ref(written: &str) -> Result<FileRef<'_>, BadPackageUri> {
    if let Some(rest) = written.strip_prefix("package://") {
        return match rest.split_once('/') {
            Some((package, path)) if !package.is_empty() && !path.is_empty() => {
                Ok(FileRef::Package { package, path })
            }
            _ => Err(BadPackageUri),
        };
    }
    Ok(FileRef::Path(
        written.strip_prefix("file://").unwrap_or(written),
    ))
}

/// Where packages are looked for: declared roots first, then search folders, in order.
#[derive(Clone, Debug, Default)]
pub struct PackagePath {
    declared: Vec<(String, String)>,
    search: Vec<String>,
}

impl PackagePath {
    /// No package known.
    pub fn new() -> PackagePath {
        PackagePath::default()
    }

    /// Declares that package `name` is the folder `dir`. The first declaration of a name
    /// wins (a caller that must refuse a second one checks [`PackagePath::declared`]).
    pub fn declare(&mut self, name: &str, dir: &str) {
        if self.declared(name).is_none() {
            self.declared.push((name.to_string(), normalize(dir)));
        }
    }

    /// The folder declared for `name`, if any.
    pub fn declared(&self, name: &str) -> Option<&str> {
        self.declared
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, d)| d.as_str())
    }

    /// Adds a folder to search after those already added.
    pub fn search(&mut self, dir: &str) {
        self.search.push(normalize(dir));
    }

    /// The search folders, in order.
    pub fn search_folders(&self) -> &[String] {
        &self.search
    }

    /// The folder of package `name`: the declared one, else the first search folder that
    /// holds it (see the module documentation).
    pub fn find(&self, name: &str, files: &dyn Files) -> Option<String> {
        if let Some(dir) = self.declared(name) {
            return Some(dir.to_string());
        }
        for dir in &self.search {
            let inside = join_folder(dir, name);
            let itself = dir.rsplit('/').next() == Some(name);
            if is_file(files, &join_folder(&inside, "package.xml")) {
                return Some(inside);
            }
            if itself && is_file(files, &join_folder(dir, "package.xml")) {
                return Some(dir.clone());
            }
        }
        None
    }
}

/// `dir/name`, for a folder (rather than [`join`]'s "beside this file").
fn join_folder(dir: &str, name: &str) -> String {
    if dir.is_empty() || dir == "." {
        normalize(name)
    } else {
        normalize(&format!("{dir}/{name}"))
    }
}

/// Whether `path` is a regular file, asked without reading it: a zero-byte budget makes
/// the file system implementation answer from the metadata alone.
fn is_file(files: &dyn Files, path: &str) -> bool {
    matches!(
        files.read_at_most(path, 0),
        Ok(_) | Err(FileError::TooLarge { .. })
    )
}

/// Why a written file name gives no path.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum ResolveError {
    /// A malformed `package://` URI.
    BadUri(BadPackageUri),
    /// No folder holds the package.
    UnknownPackage {
        /// Its name.
        package: String,
    },
}

impl fmt::Display for ResolveError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ResolveError::BadUri(e) => write!(f, "{e}"),
            ResolveError::UnknownPackage { package } => {
                write!(f, "no folder of the package path holds package `{package}`")
            }
        }
    }
}

impl std::error::Error for ResolveError {}

/// The path of a file written as `written` in the file at `naming_file`: a package's
/// file in its folder, a `file://` or absolute path as is, anything else relative to
/// `naming_file`'s folder; normalised like every path.
pub fn resolve(
    naming_file: &str,
    written: &str,
    packages: &PackagePath,
    files: &dyn Files,
) -> Result<String, ResolveError> {
    match file_ref(written).map_err(ResolveError::BadUri)? {
        FileRef::Path(path) => Ok(join(naming_file, path)),
        FileRef::Package { package, path } => {
            let root =
                packages
                    .find(package, files)
                    .ok_or_else(|| ResolveError::UnknownPackage {
                        package: package.to_string(),
                    })?;
            Ok(join_folder(&root, path))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use cellc_schema::MemoryFiles;

    #[test]
    fn uris_are_read_as_ros_writes_them() {
        assert_eq!(
            file_ref("package://p/meshes/a.stl"),
            Ok(FileRef::Package {
                package: "p",
                path: "meshes/a.stl"
            })
        );
        assert_eq!(
            file_ref("file:///abs/a.stl"),
            Ok(FileRef::Path("/abs/a.stl"))
        );
        assert_eq!(file_ref("meshes/a.stl"), Ok(FileRef::Path("meshes/a.stl")));
        assert_eq!(file_ref("package://p"), Err(BadPackageUri));
        assert_eq!(file_ref("package:///a.stl"), Err(BadPackageUri));
    }

    #[test]
    fn declared_roots_come_before_search_folders_in_order() {
        let files = MemoryFiles::new([
            ("ws1/p/package.xml", "<package/>"),
            ("ws2/p/package.xml", "<package/>"),
            ("ws2/q/package.xml", "<package/>"),
            ("lone/r/package.xml", "<package/>"),
        ]);
        let mut path = PackagePath::new();
        path.search("ws1");
        path.search("./ws2");
        path.search("lone/r");
        let found = |path: &PackagePath, name| path.find(name, &files);
        assert_eq!(found(&path, "p").as_deref(), Some("ws1/p"));
        assert_eq!(found(&path, "q").as_deref(), Some("ws2/q"));
        // A search entry that is the package itself.
        assert_eq!(found(&path, "r").as_deref(), Some("lone/r"));
        assert_eq!(found(&path, "s"), None);
        path.declare("q", "cells/robots/q/");
        path.declare("q", "elsewhere");
        assert_eq!(path.find("q", &files).as_deref(), Some("cells/robots/q"));
        assert_eq!(
            resolve("a/r.urdf", "package://q/m/x.stl", &path, &files).as_deref(),
            Ok("cells/robots/q/m/x.stl")
        );
        assert_eq!(
            resolve("a/r.urdf", "m/x.stl", &path, &files).as_deref(),
            Ok("a/m/x.stl")
        );
        assert_eq!(
            resolve("a/r.urdf", "package://s/x.stl", &path, &files),
            Err(ResolveError::UnknownPackage {
                package: "s".into()
            })
        );
    }

    #[test]
    fn a_folder_without_package_xml_holds_no_package() {
        let files = MemoryFiles::new([("ws/p/meshes/a.stl", "solid")]);
        let mut path = PackagePath::new();
        path.search("ws");
        assert_eq!(path.find("p", &files), None);
    }
}
