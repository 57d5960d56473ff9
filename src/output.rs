//! Writing output files without losing data: never over one of the inputs, and never
//! half-written, with every failure a coded diagnostic.
//!
//! A regular file (or a name that does not exist yet) is written to a temporary file in
//! the target's own folder (a rename across file systems is not atomic), flushed, synced
//! to disk and renamed over the target, then the folder is synced so the rename itself
//! survives a power cut; any failure removes the temporary file and leaves the old target
//! as it was. A target that exists and is not a regular file (`/dev/stdout`, `/dev/null`,
//! a pipe) is written in place, since renaming over a device would replace it, and every
//! write to it is checked (`/dev/full` says the disk is full).
//!
//! An input is recognised by its identity on the file system (device and inode), not by
//! its name: a hard link, a symbolic link or `./a/../b` spelling of a URDF the cell reads
//! is still that URDF. Besides the inputs a command names, every file the process read
//! through the hardened reader ([`cellc_driver::fs_files::was_read`]) is an input.

use std::io::Write;
use std::path::Path;

use cellc_lang::Diagnostic;

use cellc_driver::fs_files::FileId;

/// Codes of writing outputs (the registry's `cellc_lang::codes::output`).
pub use cellc_lang::codes::output as codes;

/// Writes `bytes` to `output`, refusing when `output` is one of `inputs` or any file the
/// process has read.
pub fn write<'a>(
    output: &Path,
    bytes: &[u8],
    inputs: impl IntoIterator<Item = &'a Path>,
) -> Result<(), Diagnostic> {
    if let Some(target) = FileId::of(output) {
        let named = inputs
            .into_iter()
            .find(|i| FileId::of(i) == Some(target))
            .map(|i| i.to_string_lossy().into_owned());
        let read = || cellc_driver::fs_files::was_read(target).then(|| "read by it".to_string());
        if let Some(input) = named.or_else(read) {
            return Err(overwrites_input(output, &input));
        }
    }
    write_whole(output, bytes).map_err(|e| unwritable(output, &e))
}

/// Writes `bytes` over `source`, a file the command read and rewrites on purpose
/// (`cellc fmt`), whole or not at all.
pub fn rewrite(source: &Path, bytes: &[u8]) -> Result<(), Diagnostic> {
    write_whole(source, bytes).map_err(|e| unwritable(source, &e))
}

/// The diagnostic of an output that is one of the inputs.
fn overwrites_input(output: &Path, input: &str) -> Diagnostic {
    let output = output.to_string_lossy();
    let output = crate::render::escape(&output);
    let message = if input == "read by it" {
        format!("`{output}` is a file this command read; it is not overwritten")
    } else {
        let input = crate::render::escape(input);
        format!("`{output}` is an input of this command (`{input}`); it is not overwritten")
    };
    Diagnostic::error(codes::OVERWRITES_INPUT, message)
        .help("write the output to another file with `-o OUT`")
}

/// The diagnostic of an output that cannot be written.
pub fn unwritable(output: &Path, error: &std::io::Error) -> Diagnostic {
    Diagnostic::error(
        codes::UNWRITABLE,
        format!(
            "cannot write `{}`: {}",
            crate::render::escape(&output.to_string_lossy()),
            error_kind(error)
        ),
    )
    .help("check that the folder exists and is writable, and that the disk is not full")
}

/// An I/O error in words that do not depend on the platform's message catalogue.
fn error_kind(error: &std::io::Error) -> String {
    use std::io::ErrorKind;
    match error.kind() {
        ErrorKind::NotFound => "its folder does not exist".into(),
        ErrorKind::PermissionDenied => "permission denied".into(),
        ErrorKind::IsADirectory => "it is a folder".into(),
        ErrorKind::NotADirectory => "a file stands where its folder should be".into(),
        ErrorKind::StorageFull => "the disk is full".into(),
        ErrorKind::ReadOnlyFilesystem => "the file system is read-only".into(),
        ErrorKind::QuotaExceeded => "the disk quota is exceeded".into(),
        ErrorKind::FileTooLarge => "the file is larger than the file system allows".into(),
        _ => error.to_string(),
    }
}

/// Writes `bytes` to `path` whole or not at all (see the module's documentation).
fn write_whole(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    match std::fs::metadata(path) {
        Ok(m) if m.is_dir() => Err(std::io::ErrorKind::IsADirectory.into()),
        Ok(m) if !m.is_file() => write_in_place(path, bytes),
        _ => write_by_rename(path, bytes),
    }
}

/// Writes to a device or pipe that already exists, checking every write.
fn write_in_place(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let mut file = std::fs::OpenOptions::new().write(true).open(path)?;
    file.write_all(bytes)?;
    file.flush()
}

/// Writes a temporary file beside `path`, syncs it and renames it over `path`.
fn write_by_rename(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let name = path
        .file_name()
        .ok_or_else(|| std::io::Error::from(std::io::ErrorKind::IsADirectory))?
        .to_string_lossy()
        .into_owned();
    let folder = match path.parent() {
        Some(f) if !f.as_os_str().is_empty() => f.to_path_buf(),
        _ => Path::new(".").to_path_buf(),
    };
    if !std::fs::metadata(&folder)?.is_dir() {
        return Err(std::io::ErrorKind::NotADirectory.into());
    }
    let (temp, mut file) = temporary_beside(&folder, &name)?;
    let written = (|| {
        if let Ok(old) = std::fs::metadata(path) {
            file.set_permissions(old.permissions())?;
        }
        file.write_all(bytes)?;
        file.flush()?;
        file.sync_all()?;
        drop(file);
        std::fs::rename(&temp, path)
    })();
    if written.is_err() {
        let _ = std::fs::remove_file(&temp);
        return written;
    }
    // The rename is durable once the folder's entry is on disk; a file system that cannot
    // sync a folder (some network ones) has still renamed, so a failure here is not one.
    if let Ok(dir) = std::fs::File::open(&folder) {
        let _ = dir.sync_all();
    }
    Ok(())
}

/// Creates a new temporary file in `folder` named after `name`, never reusing one that
/// exists (another `cellc` may be writing beside it).
fn temporary_beside(
    folder: &Path,
    name: &str,
) -> std::io::Result<(std::path::PathBuf, std::fs::File)> {
    static COUNTER: std::sync::atomic::AtomicU32 = std::sync::atomic::AtomicU32::new(0);
    loop {
        let n = COUNTER.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        let temp = folder.join(format!(".{name}.cellc-{}-{n}", std::process::id()));
        match std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&temp)
        {
            Ok(file) => return Ok((temp, file)),
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => continue,
            Err(e) => return Err(e),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn folder(name: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("cellc-output-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("temp folder");
        dir
    }

    #[test]
    fn a_full_device_is_a_coded_failure() {
        let d = write(Path::new("/dev/full"), b"artifact", []).expect_err("/dev/full is full");
        assert_eq!(d.code, codes::UNWRITABLE);
        assert!(d.message.contains("disk is full"), "{}", d.message);
        let still = std::fs::metadata("/dev/full").expect("still there");
        assert!(!still.file_type().is_file(), "the device was replaced");
    }

    #[test]
    fn a_failed_write_leaves_the_old_file_and_no_temporary() {
        let dir = folder("keep");
        let target = dir.join("out.json");
        std::fs::write(&target, "old").expect("written");
        // A folder where the file's folder should be: the write fails before renaming.
        let d = write(&dir.join("out.json/inner"), b"new", []).expect_err("not a folder");
        assert_eq!(d.code, codes::UNWRITABLE);
        write(&dir, b"new", []).expect_err("a folder is no file");
        assert_eq!(std::fs::read_to_string(&target).expect("readable"), "old");
        assert_eq!(std::fs::read_dir(&dir).expect("listable").count(), 1);
        // `write_whole`, not `write`: tests run side by side in one process, and an inode
        // another test read and deleted may be this file's.
        write_whole(&target, b"new").expect("writable");
        assert_eq!(std::fs::read_to_string(&target).expect("readable"), "new");
        assert_eq!(std::fs::read_dir(&dir).expect("listable").count(), 1);
    }

    #[cfg(unix)]
    #[test]
    fn an_input_is_known_by_identity_not_by_name() {
        let dir = folder("identity");
        let input = dir.join("robot.urdf");
        std::fs::write(&input, "<robot/>").expect("written");
        let link = dir.join("other-name.urdf");
        std::fs::hard_link(&input, &link).expect("linked");
        let d = write(&link, b"<html>", [input.as_path()]).expect_err("the same file");
        assert_eq!(d.code, codes::OVERWRITES_INPUT);
        let spelled = dir.join("sub").join("..").join("robot.urdf");
        std::fs::create_dir(dir.join("sub")).expect("folder");
        write(&spelled, b"<html>", [link.as_path()]).expect_err("the same file");
        assert_eq!(
            std::fs::read_to_string(&input).expect("readable"),
            "<robot/>"
        );
    }

    #[test]
    fn a_file_the_process_read_is_an_input() {
        use cellc_schema::files::Files;
        let dir = folder("read");
        let mesh = dir.join("part.stl");
        std::fs::write(&mesh, "solid").expect("written");
        let unread = dir.join("unread.stl");
        std::fs::write(&unread, "solid").expect("written");
        cellc_driver::fs_files::FsFiles
            .read(&mesh.to_string_lossy())
            .expect("readable");
        let d = write(&mesh, b"<html>", []).expect_err("read by this process");
        assert_eq!(d.code, codes::OVERWRITES_INPUT);
        write(&unread, b"new", []).expect("never read");
    }

    #[test]
    fn errors_are_in_words_of_their_kind() {
        let e = std::io::Error::from(std::io::ErrorKind::PermissionDenied);
        assert_eq!(error_kind(&e), "permission denied");
        let e = std::io::Error::from_raw_os_error(28);
        assert_eq!(error_kind(&e), "the disk is full");
    }
}
