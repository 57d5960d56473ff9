//! The file system as the cores see it: the one [`Files`] implementation of the command
//! line, shared by the compiler (cell sources, URDFs) and the runtime (URDFs, meshes).

use cellc_schema::{FileError, Files};

/// Reads files from disk, relative to the current directory.
pub struct FsFiles;

impl Files for FsFiles {
    fn read(&self, path: &str) -> Result<Vec<u8>, FileError> {
        Ok(std::fs::read(path)?)
    }
}
