//! The file system as the cores see it: the one [`Files`] implementation of the command
//! line, shared by the compiler (cell sources, URDFs) and the runtime (URDFs, meshes).
//!
//! A cell under review names whatever paths its author likes, so every read looks
//! before it reads: the path's metadata must say it is a regular file (a FIFO would make
//! `cellc check` wait for ever, `/dev/zero` would never end) no larger than the budget of
//! its kind; then at most one byte more than the budget is read, so a file that grows
//! between the two steps (or a `/proc` file whose size says 0) is still refused.

use std::collections::HashSet;
use std::io::Read;
use std::path::Path;
use std::sync::Mutex;

use cellc_schema::files::{FileError, Files, SpecialFile, MAX_MESH_BYTES};

/// Reads files from disk, relative to the current directory.
pub struct FsFiles;

impl Files for FsFiles {
    /// A read without a stated budget gets the largest one (that of meshes).
    fn read(&self, path: &str) -> Result<Vec<u8>, FileError> {
        self.read_at_most(path, MAX_MESH_BYTES)
    }

    fn read_at_most(&self, path: &str, max_bytes: u64) -> Result<Vec<u8>, FileError> {
        let (file, size) = open_at_most(path, max_bytes)?;
        let mut bytes = Vec::with_capacity(size as usize);
        file.take(max_bytes.saturating_add(1))
            .read_to_end(&mut bytes)?;
        let size = bytes.len() as u64;
        if size > max_bytes {
            return Err(FileError::TooLarge {
                size,
                limit: max_bytes,
            });
        }
        Ok(bytes)
    }
}

/// A file's identity on the file system: its device and inode, the same for every name
/// (hard link, symbolic link, relative spelling) of the same file.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
pub struct FileId {
    device: u64,
    inode: u64,
}

impl FileId {
    /// The identity of what `path` names, symbolic links followed; `None` when nothing
    /// is there.
    pub fn of(path: &Path) -> Option<FileId> {
        std::fs::metadata(path)
            .ok()
            .map(|m| FileId::from_metadata(&m))
    }

    /// The identity recorded in `metadata`.
    #[cfg(unix)]
    pub fn from_metadata(metadata: &std::fs::Metadata) -> FileId {
        use std::os::unix::fs::MetadataExt;
        FileId {
            device: metadata.dev(),
            inode: metadata.ino(),
        }
    }

    /// Without inodes, nothing is known to be the same file.
    #[cfg(not(unix))]
    pub fn from_metadata(_: &std::fs::Metadata) -> FileId {
        static NEXT: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(1);
        FileId {
            device: 0,
            inode: NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed),
        }
    }
}

/// The identities of the files this process has opened through [`open_at_most`], so an
/// output is never written over any of them (see [`crate::output`]). A process reads a
/// cell's files, not millions, but the set is capped so a long-lived service cannot grow
/// it without bound; past the cap, outputs are still checked against the inputs each
/// command names.
static READ: Mutex<Option<HashSet<FileId>>> = Mutex::new(None);

/// How many identities [`READ`] keeps.
const MAX_REMEMBERED: usize = 1 << 16;

fn remember(id: FileId) {
    let mut read = READ.lock().unwrap_or_else(|p| p.into_inner());
    let set = read.get_or_insert_with(HashSet::new);
    if set.len() < MAX_REMEMBERED {
        set.insert(id);
    }
}

/// Whether this process has read the file of identity `id`.
pub fn was_read(id: FileId) -> bool {
    let read = READ.lock().unwrap_or_else(|p| p.into_inner());
    read.as_ref().is_some_and(|s| s.contains(&id))
}

/// Opens the regular file at `path` of at most `max_bytes` bytes, with its length: the
/// path is looked at before it is opened (`metadata` follows symbolic links, so a link
/// to a FIFO is refused too, and it never opens the file, so it cannot block), and what
/// was opened is looked at again (the path may have been replaced in between).
fn open_at_most(path: &str, max_bytes: u64) -> Result<(std::fs::File, u64), FileError> {
    let too_large = |size: u64| {
        Err(FileError::TooLarge {
            size,
            limit: max_bytes,
        })
    };
    let size = regular_file(path)?;
    if size > max_bytes {
        return too_large(size);
    }
    let file = std::fs::File::open(path)?;
    let metadata = file.metadata()?;
    check_kind(&metadata)?;
    remember(FileId::from_metadata(&metadata));
    if metadata.len() > max_bytes {
        return too_large(metadata.len());
    }
    Ok((file, metadata.len()))
}

/// The size of the regular file at `path`, from its metadata (the file is not opened);
/// a folder, pipe, device or socket is refused.
pub fn regular_file(path: &str) -> Result<u64, FileError> {
    let metadata = std::fs::metadata(path)?;
    check_kind(&metadata)?;
    Ok(metadata.len())
}

/// Refuses what is not a regular file: folders, pipes, devices and sockets.
fn check_kind(metadata: &std::fs::Metadata) -> Result<(), FileError> {
    let kind = metadata.file_type();
    if kind.is_file() {
        return Ok(());
    }
    if kind.is_dir() {
        return Err(FileError::IsADirectory);
    }
    Err(FileError::NotRegular {
        what: special(&kind),
    })
}

#[cfg(unix)]
fn special(kind: &std::fs::FileType) -> SpecialFile {
    use std::os::unix::fs::FileTypeExt;
    if kind.is_fifo() {
        SpecialFile::Fifo
    } else if kind.is_char_device() {
        SpecialFile::CharDevice
    } else if kind.is_block_device() {
        SpecialFile::BlockDevice
    } else if kind.is_socket() {
        SpecialFile::Socket
    } else {
        SpecialFile::Other
    }
}

#[cfg(not(unix))]
fn special(_: &std::fs::FileType) -> SpecialFile {
    SpecialFile::Other
}

/// A regular file read a piece at a time, as a sectioned binary artifact is: only the
/// sections a use decodes are read, through a buffer as small as the piece.
///
/// Its length is taken once, when it is opened (and checked against a budget); a file cut
/// short later is reported as corrupt by the read that misses its bytes, and a file
/// changed later by the checksum of the section read, so nothing read is trusted for
/// being where it was.
pub struct PieceFile {
    file: std::sync::Mutex<std::fs::File>,
    length: u64,
}

impl PieceFile {
    /// Opens the regular file at `path`, of at most `max_bytes` bytes.
    pub fn open(path: &str, max_bytes: u64) -> Result<PieceFile, FileError> {
        let (file, length) = open_at_most(path, max_bytes)?;
        Ok(PieceFile {
            file: std::sync::Mutex::new(file),
            length,
        })
    }
}

impl cellc_schema::sections::Source for PieceFile {
    fn file_length(&self) -> u64 {
        self.length
    }

    fn bytes<'s>(
        &'s self,
        offset: u64,
        length: usize,
        buf: &'s mut Vec<u8>,
    ) -> Result<&'s [u8], cellc_schema::ReadError> {
        use std::io::Seek;
        let cut = |e: std::io::Error| cellc_schema::ReadError::Corrupt {
            detail: format!("the file cannot be read at byte {offset}: {e}"),
        };
        buf.resize(length, 0);
        // A poisoned lock only means another reader panicked; the file is still a file.
        let mut file = self.file.lock().unwrap_or_else(|p| p.into_inner());
        file.seek(std::io::SeekFrom::Start(offset)).map_err(cut)?;
        file.read_exact(buf).map_err(cut)?;
        Ok(buf)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn refuses_what_is_not_a_small_regular_file() {
        let folder = std::env::temp_dir().join(format!("cellc-fs-files-{}", std::process::id()));
        std::fs::create_dir_all(&folder).expect("temp folder");
        let file = folder.join("a.cell");
        std::fs::write(&file, "0123456789").expect("written");
        let path = file.to_string_lossy();
        assert_eq!(FsFiles.read_at_most(&path, 10).map(|b| b.len()), Ok(10));
        assert_eq!(
            FsFiles.read_at_most(&path, 9),
            Err(FileError::TooLarge { size: 10, limit: 9 })
        );
        assert_eq!(
            FsFiles.read(&folder.to_string_lossy()),
            Err(FileError::IsADirectory)
        );
        #[cfg(unix)]
        assert_eq!(
            FsFiles.read("/dev/zero"),
            Err(FileError::NotRegular {
                what: SpecialFile::CharDevice
            })
        );
        std::fs::remove_dir_all(&folder).expect("removed");
    }

    #[test]
    fn a_piece_file_reads_what_it_is_asked_and_reports_a_cut_as_corrupt() {
        use cellc_schema::sections::Source;
        let folder = std::env::temp_dir().join(format!("cellc-piece-file-{}", std::process::id()));
        std::fs::create_dir_all(&folder).expect("temp folder");
        let file = folder.join("a.bin");
        std::fs::write(&file, "0123456789").expect("written");
        let path = file.to_string_lossy();
        assert_eq!(
            PieceFile::open(&path, 9).map(drop),
            Err(FileError::TooLarge { size: 10, limit: 9 })
        );
        assert!(PieceFile::open(&folder.to_string_lossy(), 100).is_err());
        let piece = PieceFile::open(&path, 10).expect("opens");
        assert_eq!(piece.file_length(), 10);
        let mut buf = Vec::new();
        assert_eq!(piece.bytes(3, 4, &mut buf), Ok(b"3456".as_slice()));
        // Cut short after it was opened: the bytes that are gone are an error.
        std::fs::write(&file, "012").expect("cut");
        assert!(matches!(
            piece.bytes(3, 4, &mut buf),
            Err(cellc_schema::ReadError::Corrupt { .. })
        ));
        std::fs::remove_dir_all(&folder).expect("removed");
    }
}
