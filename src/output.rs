//! Writing output files without losing data: never over one of the inputs, and never
//! half-written (a temporary file beside the target, renamed over it once complete), with
//! every failure a coded diagnostic.

use std::path::{Path, PathBuf};

use cellc_lang::Diagnostic;

/// Codes of writing outputs.
pub mod codes {
    use cellc_lang::Code;
    /// An output file cannot be written.
    pub const UNWRITABLE: Code = Code("E0505");
    /// The output file is one of the command's inputs.
    pub const OVERWRITES_INPUT: Code = Code("E0506");
    /// `cellc explain` was asked about a code that does not exist.
    pub const UNKNOWN_CODE: Code = Code("E0507");
    /// Every code of this phase.
    pub const ALL: &[Code] = &[UNWRITABLE, OVERWRITES_INPUT, UNKNOWN_CODE];
}

/// The same file, as far as the file system can tell (symbolic links and `..` resolved);
/// a path that does not exist yet is compared by its folder and name.
fn same_file(a: &Path, b: &Path) -> bool {
    let canonical = |p: &Path| -> Option<PathBuf> {
        if let Ok(c) = p.canonicalize() {
            return Some(c);
        }
        let folder = match p.parent() {
            Some(f) if !f.as_os_str().is_empty() => f.canonicalize().ok()?,
            _ => std::env::current_dir().ok()?,
        };
        Some(folder.join(p.file_name()?))
    };
    match (canonical(a), canonical(b)) {
        (Some(x), Some(y)) => x == y,
        _ => a == b,
    }
}

/// Writes `bytes` to `output`, refusing when `output` is one of `inputs`.
pub fn write<'a>(
    output: &Path,
    bytes: &[u8],
    inputs: impl IntoIterator<Item = &'a Path>,
) -> Result<(), Diagnostic> {
    if let Some(input) = inputs.into_iter().find(|i| same_file(output, i)) {
        return Err(Diagnostic::error(
            codes::OVERWRITES_INPUT,
            format!(
                "`{}` is an input of this command (`{}`); it is not overwritten",
                crate::render::escape(&output.to_string_lossy()),
                crate::render::escape(&input.to_string_lossy())
            ),
        )
        .help("write the output to another file with `-o OUT`"));
    }
    write_whole(output, bytes).map_err(|e| unwritable(output, &e))
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
        _ => error.to_string(),
    }
}

/// Writes `bytes` to a temporary file beside `path` and renames it over `path`, so that
/// `path` is never left half written and a failure leaves the old file as it was.
fn write_whole(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    if path.is_dir() {
        return Err(std::io::Error::from(std::io::ErrorKind::IsADirectory));
    }
    let file_name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let temp = path.with_file_name(format!(".{file_name}.cellc-{}", std::process::id()));
    let result = std::fs::write(&temp, bytes).and_then(|()| std::fs::rename(&temp, path));
    if result.is_err() {
        let _ = std::fs::remove_file(&temp);
    }
    result
}
