//! The two encodings of an artifact and how a file is read back: format and version
//! first, then the checksum, then the content, then validation (see
//! [`Artifact::from_bytes`]).

use serde::Deserialize;

use crate::hash::sha256_hex;
use crate::{validate, Artifact, FORMAT, FORMAT_VERSION, MAGIC};

/// Encoding of an artifact file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Encoding {
    /// Compact JSON.
    Json,
    /// `MAGIC`, version, a table of checksummed sections ([`crate::sections`]).
    Binary,
}

/// Why bytes are not a usable artifact.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum ReadError {
    /// Neither a cellc JSON artifact nor the binary magic.
    NotAnArtifact,
    /// Written by an incompatible version of the format.
    WrongVersion {
        /// Version in the file.
        found: u32,
        /// Version this reader understands.
        expected: u32,
    },
    /// The header is right but the content does not decode (truncated or corrupted).
    Corrupt {
        /// What the decoder said.
        detail: String,
    },
    /// The content is not what was written: its checksum does not match.
    Damaged,
    /// The content decodes and its checksum matches, but it is inconsistent (an index out
    /// of range, a number outside its domain): not written by cellc as it is.
    Invalid(validate::Invalid),
}

impl std::fmt::Display for ReadError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ReadError::NotAnArtifact => f.write_str("not a cellc artifact"),
            ReadError::WrongVersion { found, expected } => {
                write!(
                    f,
                    "artifact format version {found}, this cellc reads version {expected}"
                )
            }
            ReadError::Corrupt { detail } => {
                write!(f, "the artifact is truncated or corrupted: {detail}")
            }
            ReadError::Damaged => {
                f.write_str("the artifact is damaged: its content does not match its checksum")
            }
            ReadError::Invalid(invalid) => write!(f, "the artifact is inconsistent: {invalid}"),
        }
    }
}

impl std::error::Error for ReadError {}

/// Prefix of a JSON artifact: the checksum comes first so that it can be checked on the
/// exact bytes that follow, whatever they contain.
const JSON_CHECKSUM: &[u8] = b"{\"checksum\":\"";
/// Hex digits of a SHA-256.
const HEX_LEN: usize = 64;

impl Artifact {
    /// Encodes the artifact, with checksums of the content so damage is detected.
    ///
    /// JSON: `{"checksum":"HEX",` followed by the artifact's fields; the checksum is over
    /// the artifact's own JSON (`{` and the rest). Binary: the sectioned layout of
    /// [`crate::sections`], each section with its own XXH3-64.
    pub fn to_bytes(&self, encoding: Encoding) -> Vec<u8> {
        match encoding {
            Encoding::Json => {
                // One buffer: the content is written after room for the checksum field,
                // its `{` then becomes the field's `,`, so an artifact of a hundred
                // megabytes is not copied once more to put its checksum in front.
                let content_at = JSON_CHECKSUM.len() + HEX_LEN + 1;
                let mut bytes = vec![0; content_at];
                // Serialising plain data with string keys cannot fail; if it did, the
                // content would be empty, as before.
                if serde_json::to_writer(&mut bytes, self).is_err() {
                    bytes.truncate(content_at);
                }
                bytes.push(b'\n');
                let checksum = sha256_hex(&bytes[content_at..]);
                bytes[..JSON_CHECKSUM.len()].copy_from_slice(JSON_CHECKSUM);
                bytes[JSON_CHECKSUM.len()..content_at - 1].copy_from_slice(checksum.as_bytes());
                bytes[content_at - 1] = b'"';
                bytes[content_at] = b',';
                bytes
            }
            Encoding::Binary => crate::sections::write(self),
        }
    }

    /// Decodes an artifact in either encoding and validates it. The format and version are
    /// read first, so that an old file is reported as old, not as damaged; then the
    /// checksum, so that damage is reported as damage; then the content is decoded and
    /// [`validate::validate`]d, so that nothing downstream indexes unchecked data.
    pub fn from_bytes(bytes: &[u8]) -> Result<(Artifact, Encoding), ReadError> {
        let (artifact, encoding) = Artifact::decode(bytes)?;
        validate::validate(&artifact).map_err(ReadError::Invalid)?;
        Ok((artifact, encoding))
    }

    fn decode(bytes: &[u8]) -> Result<(Artifact, Encoding), ReadError> {
        let corrupt = |detail: &str| ReadError::Corrupt {
            detail: detail.to_string(),
        };
        if bytes.starts_with(MAGIC.as_slice()) {
            let artifact = crate::sections::Sections::open(bytes)?.artifact()?;
            return Ok((artifact, Encoding::Binary));
        }
        // Each field optional, so that a file that says it is an artifact is judged as
        // one (a damaged or other version) even when a field has the wrong type.
        #[derive(Deserialize)]
        struct Header {
            #[serde(default)]
            format: Option<serde_json::Value>,
            #[serde(default)]
            format_version: Option<serde_json::Value>,
            #[serde(default)]
            checksum: Option<serde_json::Value>,
        }
        // With a checksum, the content is checked before anything is parsed, so a damaged
        // file is reported as damaged whatever the damage did to its syntax.
        let content = match bytes.strip_prefix(JSON_CHECKSUM) {
            Some(after) => {
                let (hex, rest) = (after.get(..HEX_LEN), after.get(HEX_LEN..));
                let (Some(hex), Some(rest)) = (hex, rest.and_then(|r| r.strip_prefix(b"\",")))
                else {
                    return Err(corrupt("the checksum is malformed or cut short"));
                };
                let mut content = Vec::with_capacity(rest.len() + 1);
                content.push(b'{');
                content.extend_from_slice(rest);
                if sha256_hex(&content).as_bytes() != hex {
                    return Err(ReadError::Damaged);
                }
                Some(content)
            }
            None => None,
        };
        let header: Header = match serde_json::from_slice(content.as_deref().unwrap_or(bytes)) {
            Ok(h) => h,
            Err(e) if content.is_some() => return Err(corrupt(&e.to_string())),
            Err(_) => return Err(ReadError::NotAnArtifact),
        };
        if header.format.as_ref().and_then(|f| f.as_str()) != Some(FORMAT) {
            return Err(ReadError::NotAnArtifact);
        }
        match header.format_version.as_ref().map(|v| v.as_u64()) {
            Some(Some(v)) if v == u64::from(FORMAT_VERSION) => {}
            Some(Some(v)) => {
                return Err(ReadError::WrongVersion {
                    found: u32::try_from(v).unwrap_or(u32::MAX),
                    expected: FORMAT_VERSION,
                })
            }
            Some(None) => return Err(corrupt("`format_version` is not a whole number")),
            None => return Err(corrupt("`format_version` is missing")),
        }
        let Some(content) = content else {
            return Artifact::decode_reformatted(bytes, header.checksum.as_ref());
        };
        serde_json::from_slice(&content)
            .map(|a| (a, Encoding::Json))
            .map_err(|e| corrupt(&e.to_string()))
    }

    /// A JSON artifact whose checksum is not its first field: the file was rewritten by
    /// another tool (`json.dumps(indent=2)`, a formatter, an editor). The checksum is over
    /// the canonical encoding, so the content is decoded, encoded again and compared: the
    /// same content in another layout is accepted, a changed one is damaged.
    fn decode_reformatted(
        bytes: &[u8],
        checksum: Option<&serde_json::Value>,
    ) -> Result<(Artifact, Encoding), ReadError> {
        let corrupt = |detail: &str| ReadError::Corrupt {
            detail: detail.to_string(),
        };
        let Some(checksum) = checksum else {
            return Err(corrupt("the checksum is missing"));
        };
        let Some(checksum) = checksum.as_str().filter(|c| c.len() == HEX_LEN) else {
            return Err(corrupt("the checksum is not 64 hexadecimal digits"));
        };
        let artifact: Artifact = serde_json::from_slice(bytes).map_err(|_| ReadError::Damaged)?;
        let canonical = artifact.to_bytes(Encoding::Json);
        let at = JSON_CHECKSUM.len();
        if canonical.get(at..at + HEX_LEN) != Some(checksum.to_ascii_lowercase().as_bytes()) {
            return Err(ReadError::Damaged);
        }
        Ok((artifact, Encoding::Json))
    }
}
