//! How the cores read files: the one trait through which the compiler (cell sources,
//! URDFs) and the runtime (URDFs, meshes) reach the outside world.
//!
//! Neither core does I/O. The CLI implements [`Files`] on the file system; tests, the
//! importer and an editor server use [`MemoryFiles`]. Files are bytes (meshes are
//! binary); [`Files::read_text_at_most`] is the one place that decides what "not text"
//! means.
//!
//! Paths are `/`-separated strings as [`join`] and [`normalize`] produce them, so one file
//! always has one name (include cycles are found by comparing names).
//!
//! Every read names its budget ([`MAX_SOURCE_BYTES`], [`MAX_URDF_BYTES`],
//! [`MAX_MESH_BYTES`]): a cell under review may name any path, and a 10 GB file or a FIFO
//! that never ends must be refused before it is read, not after the machine runs out of
//! memory (the file-system implementation looks at the file's metadata first).

use std::collections::BTreeMap;
use std::fmt;

/// The largest cell or library source file read, in bytes (16 MiB).
pub const MAX_SOURCE_BYTES: u64 = 16 << 20;
/// The largest URDF file read, in bytes (16 MiB).
pub const MAX_URDF_BYTES: u64 = 16 << 20;
/// The largest mesh file read, in bytes (32 MiB: a binary STL of 670,000 triangles).
pub const MAX_MESH_BYTES: u64 = 32 << 20;
/// The largest artifact read, in bytes (1 GiB: graphs at the compiler's size limit, with
/// a witness for every arc).
pub const MAX_ARTIFACT_BYTES: u64 = 1 << 30;

/// Supplies file contents to the compiler and the runtime.
pub trait Files {
    /// The bytes of the file at `path`, or why it can't be read.
    fn read(&self, path: &str) -> Result<Vec<u8>, FileError>;

    /// The bytes of the file at `path`, refused (as [`FileError::TooLarge`]) when there
    /// are more than `max_bytes`. The default reads and then measures, which is right for
    /// files already in memory; an implementation that reads from a disk must look
    /// before it reads.
    fn read_at_most(&self, path: &str, max_bytes: u64) -> Result<Vec<u8>, FileError> {
        let bytes = self.read(path)?;
        let size = bytes.len() as u64;
        if size > max_bytes {
            return Err(FileError::TooLarge {
                size,
                limit: max_bytes,
            });
        }
        Ok(bytes)
    }

    /// The text of the file at `path`: at most `max_bytes` bytes, refused when they are
    /// not UTF-8.
    fn read_text_at_most(&self, path: &str, max_bytes: u64) -> Result<String, FileError> {
        String::from_utf8(self.read_at_most(path, max_bytes)?).map_err(|e| FileError::NotUtf8 {
            valid_up_to: e.utf8_error().valid_up_to(),
        })
    }

    /// The text of a source file at `path` ([`Files::read_text_at_most`] with
    /// [`MAX_SOURCE_BYTES`]).
    fn read_text(&self, path: &str) -> Result<String, FileError> {
        self.read_text_at_most(path, MAX_SOURCE_BYTES)
    }
}

/// What a path names when it is neither a regular file nor a folder.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum SpecialFile {
    /// A named pipe: reading it waits for a writer, possibly for ever.
    Fifo,
    /// A character device (`/dev/zero`, a terminal): possibly endless.
    CharDevice,
    /// A block device (a disk).
    BlockDevice,
    /// A Unix socket.
    Socket,
    /// Anything else the system knows that is not a file.
    Other,
}

impl fmt::Display for SpecialFile {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            SpecialFile::Fifo => "a named pipe (FIFO)",
            SpecialFile::CharDevice => "a character device",
            SpecialFile::BlockDevice => "a block device",
            SpecialFile::Socket => "a socket",
            SpecialFile::Other => "not a regular file",
        })
    }
}

/// Why a file could not be read.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum FileError {
    /// Nothing is at that path.
    NotFound,
    /// The file exists but may not be read.
    PermissionDenied,
    /// The path names a folder.
    IsADirectory,
    /// The path names a pipe, a device or a socket, which is never read (it may not end).
    NotRegular {
        /// What it is.
        what: SpecialFile,
    },
    /// The file is larger than the budget of its kind.
    TooLarge {
        /// Its size in bytes (at least `limit + 1` when it grew while being read).
        size: u64,
        /// The budget, in bytes.
        limit: u64,
    },
    /// Text was asked for and the bytes are not UTF-8.
    NotUtf8 {
        /// Length of the valid prefix: the offset of the first invalid byte.
        valid_up_to: usize,
    },
    /// Any other failure, in the operating system's own words.
    Other {
        /// The system's message.
        message: String,
    },
}

impl fmt::Display for FileError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            FileError::NotFound => f.write_str("no such file"),
            FileError::PermissionDenied => f.write_str("permission denied"),
            FileError::IsADirectory => f.write_str("it is a directory"),
            FileError::NotRegular { what } => {
                write!(f, "it is {what}; only regular files are read")
            }
            FileError::TooLarge { size, limit } => write!(
                f,
                "it has {size} bytes, over the limit of {limit} ({})",
                human_bytes(*limit)
            ),
            FileError::NotUtf8 { valid_up_to } => {
                write!(f, "not UTF-8 text (invalid byte at offset {valid_up_to})")
            }
            FileError::Other { message } => f.write_str(message),
        }
    }
}

impl std::error::Error for FileError {}

/// A byte count for people: `512 bytes`, `3.2 KiB`, `16.0 MiB`, `2.5 GiB`.
pub fn human_bytes(bytes: u64) -> String {
    const UNITS: [&str; 4] = ["KiB", "MiB", "GiB", "TiB"];
    if bytes < 1024 {
        return format!("{bytes} bytes");
    }
    let mut value = bytes as f64 / 1024.0;
    let mut unit = 0;
    while value >= 1024.0 && unit + 1 < UNITS.len() {
        value /= 1024.0;
        unit += 1;
    }
    format!("{value:.1} {}", UNITS[unit])
}

impl From<std::io::Error> for FileError {
    fn from(error: std::io::Error) -> FileError {
        match error.kind() {
            std::io::ErrorKind::NotFound => FileError::NotFound,
            std::io::ErrorKind::PermissionDenied => FileError::PermissionDenied,
            std::io::ErrorKind::IsADirectory => FileError::IsADirectory,
            _ => FileError::Other {
                message: error.to_string(),
            },
        }
    }
}

/// Files held in memory: normalised path -> bytes.
#[derive(Clone, Debug, Default)]
pub struct MemoryFiles {
    files: BTreeMap<String, Vec<u8>>,
}

impl MemoryFiles {
    /// Files with the given paths and contents (text or bytes).
    pub fn new<P: AsRef<str>, B: Into<Vec<u8>>>(
        files: impl IntoIterator<Item = (P, B)>,
    ) -> MemoryFiles {
        let mut memory = MemoryFiles::default();
        for (path, bytes) in files {
            memory.insert(path.as_ref(), bytes);
        }
        memory
    }

    /// Adds or replaces the file at `path`.
    pub fn insert(&mut self, path: &str, bytes: impl Into<Vec<u8>>) {
        self.files.insert(normalize(path), bytes.into());
    }
}

impl Files for MemoryFiles {
    fn read(&self, path: &str) -> Result<Vec<u8>, FileError> {
        self.files
            .get(&normalize(path))
            .cloned()
            .ok_or(FileError::NotFound)
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

/// Removes `.` and resolves `..` lexically, so that one file always has one name. A `..`
/// above the root of an absolute path is dropped; above a relative path it is kept. A
/// relative path that names the current folder is `.`, never the empty name.
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
    } else if joined.is_empty() {
        ".".to_string()
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
        assert_eq!(join("/x/y/r.urdf", "../a.stl"), "/x/a.stl");
        assert_eq!(join("r.urdf", "../a.stl"), "../a.stl");
        assert_eq!(join("/r.urdf", "../a.stl"), "/a.stl");
        assert_eq!(normalize("../../a"), "../../a");
        assert_eq!(join("a.cell", "."), ".");
        assert_eq!(join("x/a.cell", ".."), ".");
    }

    #[test]
    fn memory_files_read_by_normalised_path() {
        let files = MemoryFiles::new([("cells/a.cell", "text"), ("cells/b.bin", "\u{0}")]);
        assert_eq!(
            files.read_text("cells/./x/../a.cell").as_deref(),
            Ok("text")
        );
        assert_eq!(files.read("nothing"), Err(FileError::NotFound));
        let mut bytes = MemoryFiles::default();
        bytes.insert("m.stl", vec![0xff, 0x00]);
        assert_eq!(
            bytes.read_text("m.stl"),
            Err(FileError::NotUtf8 { valid_up_to: 0 })
        );
        assert_eq!(
            files.read_text_at_most("cells/a.cell", 3),
            Err(FileError::TooLarge { size: 4, limit: 3 })
        );
        assert_eq!(
            FileError::TooLarge {
                size: 20 << 20,
                limit: MAX_SOURCE_BYTES
            }
            .to_string(),
            "it has 20971520 bytes, over the limit of 16777216 (16.0 MiB)"
        );
        assert_eq!(human_bytes(1000), "1000 bytes");
        assert_eq!(human_bytes(1536), "1.5 KiB");
        assert_eq!(
            FileError::NotUtf8 { valid_up_to: 3 }.to_string(),
            "not UTF-8 text (invalid byte at offset 3)"
        );
    }
}
