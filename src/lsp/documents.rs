//! The documents the editor has open, and the file system the compiler sees through them.
//!
//! An open buffer is what the user is looking at, saved or not, so [`Overlay`] serves it
//! before the disk: a cell's includes then resolve against unsaved text, and a library
//! being edited is checked as part of every open cell that includes it. Paths are the
//! normalised absolute paths of `file:` URIs, the names the compiler's source map uses.

use std::collections::BTreeMap;
use std::str::FromStr;

use cellc_schema::files::{normalize, FileError, Files};
use lsp_types::Uri;

use cellc_driver::fs_files::FsFiles;

/// One open document.
pub struct Document {
    /// As the client named it (answers name it the same way).
    pub uri: Uri,
    /// The client's version of the text.
    pub version: i32,
    /// The whole text (full synchronisation).
    pub text: String,
}

/// Every open document, by path.
#[derive(Default)]
pub struct Documents {
    open: BTreeMap<String, Document>,
}

impl Documents {
    /// Opens or replaces a document; `None` when the URI is not a `file:` URI.
    pub fn open(&mut self, uri: Uri, version: i32, text: String) -> Option<String> {
        let path = path_of(&uri)?;
        self.open
            .insert(path.clone(), Document { uri, version, text });
        Some(path)
    }

    /// Closes a document.
    pub fn close(&mut self, uri: &Uri) -> Option<String> {
        let path = path_of(uri)?;
        self.open.remove(&path).map(|_| path)
    }

    /// The open document at `path`.
    pub fn get(&self, path: &str) -> Option<&Document> {
        self.open.get(path)
    }

    /// Every open document, by path.
    pub fn iter(&self) -> impl Iterator<Item = (&str, &Document)> {
        self.open.iter().map(|(p, d)| (p.as_str(), d))
    }

    /// The compiler's view of files: these documents over the disk.
    pub fn overlay(&self) -> Overlay<'_> {
        Overlay { documents: self }
    }
}

/// Open documents first, then the disk.
pub struct Overlay<'a> {
    documents: &'a Documents,
}

impl Files for Overlay<'_> {
    fn read(&self, path: &str) -> Result<Vec<u8>, FileError> {
        match self.documents.get(&normalize(path)) {
            Some(d) => Ok(d.text.as_bytes().to_vec()),
            None => FsFiles.read(path),
        }
    }

    fn read_at_most(&self, path: &str, max_bytes: u64) -> Result<Vec<u8>, FileError> {
        match self.documents.get(&normalize(path)) {
            Some(d) if d.text.len() as u64 > max_bytes => Err(FileError::TooLarge {
                size: d.text.len() as u64,
                limit: max_bytes,
            }),
            Some(d) => Ok(d.text.as_bytes().to_vec()),
            None => FsFiles.read_at_most(path, max_bytes),
        }
    }
}

/// The normalised path of a `file:` URI, percent-decoded; `None` for other schemes or a
/// path that is not UTF-8.
pub fn path_of(uri: &Uri) -> Option<String> {
    if !uri
        .scheme()
        .is_some_and(|s| s.as_str().eq_ignore_ascii_case("file"))
    {
        return None;
    }
    let raw = uri.path().as_str();
    let mut bytes = Vec::with_capacity(raw.len());
    let mut rest = raw.as_bytes();
    while let Some((&b, tail)) = rest.split_first() {
        if b == b'%' && tail.len() >= 2 {
            let hex = std::str::from_utf8(&tail[..2]).ok()?;
            bytes.push(u8::from_str_radix(hex, 16).ok()?);
            rest = &tail[2..];
        } else {
            bytes.push(b);
            rest = tail;
        }
    }
    Some(normalize(&String::from_utf8(bytes).ok()?))
}

/// The `file:` URI of an absolute path, percent-encoding what a URI path cannot hold.
pub fn uri_of(path: &str) -> Option<Uri> {
    let mut text = String::from("file://");
    if !path.starts_with('/') {
        text.push('/');
    }
    for b in path.bytes() {
        if b.is_ascii_alphanumeric() || b"/-._~".contains(&b) {
            text.push(b as char);
        } else {
            text.push_str(&format!("%{b:02X}"));
        }
    }
    Uri::from_str(&text).ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn file_uris_round_trip_with_escapes() {
        let path = "/home/a b/cells/ü.cell";
        let uri = uri_of(path).expect("a URI");
        assert_eq!(uri.as_str(), "file:///home/a%20b/cells/%C3%BC.cell");
        assert_eq!(path_of(&uri).as_deref(), Some(path));
        let other = Uri::from_str("untitled:Untitled-1").expect("a URI");
        assert_eq!(path_of(&other), None);
    }

    #[test]
    fn open_buffers_come_before_the_disk() {
        let mut documents = Documents::default();
        let uri = uri_of("/nowhere/x.cell").expect("a URI");
        documents.open(uri, 1, "cell x {}".to_string());
        let overlay = documents.overlay();
        assert_eq!(
            overlay.read_text("/nowhere/./x.cell").ok().as_deref(),
            Some("cell x {}")
        );
        assert!(overlay.read_text("/nowhere/y.cell").is_err());
        assert!(matches!(
            overlay.read_at_most("/nowhere/x.cell", 3),
            Err(FileError::TooLarge { .. })
        ));
    }
}
