//! Reading the sectioned layout: the header and table first, checked whole, then a
//! section at a time, each checked against its checksum.
//!
//! The bytes come from a [`Source`]: the whole file in memory (`&[u8]`), or a file read a
//! piece at a time. With a file, a reader holds only the sections it decodes, and the
//! fixed-width sections (nodes, arcs) pass through a small buffer on their way into
//! records: a plan on a 10^6-arc artifact then never holds its 37 MiB, which cost more
//! to read and fault in than to decode.

use super::{
    corrupt, u32_at, u64_at, Section, SectionKind, ARC_BYTES, BINARY_VERSION, ENTRY_BYTES,
    FIXED_HEADER, FLAG_TRANSITION, FLAG_VIA, FLAG_WITNESS, NODE_BYTES, TRANSITION_BYTES,
};
use crate::encoding::ReadError;
use crate::{Arc, ArcKind, Artifact, DeclaredTransition, Graph, Node, PrunedArc, Witness, MAGIC};
use crate::{EndEffectorId, GraspId, WorkspaceId};

/// Where the bytes of a sectioned file come from.
pub trait Source {
    /// The file's length in bytes.
    fn file_length(&self) -> u64;

    /// The `length` bytes at `offset`, which [`Sections`] asks for only inside the file:
    /// borrowed from the source, or read into `buf`.
    ///
    /// # Errors
    /// The file cannot be read there (it was cut short since its table was read).
    fn bytes<'s>(
        &'s self,
        offset: u64,
        length: usize,
        buf: &'s mut Vec<u8>,
    ) -> Result<&'s [u8], ReadError>;
}

impl Source for &[u8] {
    fn file_length(&self) -> u64 {
        self.len() as u64
    }

    fn bytes<'s>(
        &'s self,
        offset: u64,
        length: usize,
        _: &'s mut Vec<u8>,
    ) -> Result<&'s [u8], ReadError> {
        usize::try_from(offset)
            .ok()
            .and_then(|at| self.get(at..at.checked_add(length)?))
            .ok_or_else(|| corrupt("a section ends after the file"))
    }
}

/// Bytes of fixed-width records decoded per piece: a multiple of both record widths,
/// small enough to stay in cache.
const PIECE_BYTES: usize = 96 * 4096;

/// A binary artifact whose header and section table have been checked, and whose
/// sections are decoded (and their checksums checked) only when asked for.
#[derive(Debug)]
pub struct Sections<S> {
    source: S,
    table: Vec<Section>,
    n_objects: usize,
}

impl<'a> Sections<&'a [u8]> {
    /// Reads the header and the section table of `bytes` (which start with `MAGIC`), as
    /// [`Sections::from_source`] does.
    pub fn open(bytes: &'a [u8]) -> Result<Sections<&'a [u8]>, ReadError> {
        Sections::from_source(bytes)
    }
}

impl<S: Source> Sections<S> {
    /// Reads the header and the section table of `source`. Every row is checked before
    /// anything is decoded: the table's checksum, every section inside the file, in order
    /// without overlap, of a known kind, the core first and then the five sections of
    /// each object in turn. Nothing is allocated in proportion to a number of the file
    /// that the file's length does not bound.
    pub fn from_source(source: S) -> Result<Sections<S>, ReadError> {
        let file_length = source.file_length();
        let mut buf = Vec::new();
        let head_length = file_length.min(FIXED_HEADER as u64) as usize;
        let head = source.bytes(0, head_length, &mut buf)?;
        let rest = head
            .strip_prefix(MAGIC.as_slice())
            .ok_or(ReadError::NotAnArtifact)?;
        if rest.len() < 4 {
            return Err(corrupt("the file ends inside its header"));
        }
        let version = u32_at(rest, 0);
        if version != BINARY_VERSION {
            return Err(ReadError::WrongVersion {
                found: version,
                expected: BINARY_VERSION,
            });
        }
        if head.len() < FIXED_HEADER {
            return Err(corrupt("the file ends inside its header"));
        }
        let count = u32_at(head, 12) as usize;
        let table_checksum = u64_at(head, 16);
        let table_end = count
            .checked_mul(ENTRY_BYTES)
            .and_then(|t| t.checked_add(FIXED_HEADER))
            .filter(|&end| end as u64 <= file_length)
            .ok_or_else(|| {
                corrupt(format!(
                    "a table of {count} sections does not fit in the file"
                ))
            })?;
        let mut buf = Vec::new();
        let table_bytes = source.bytes(FIXED_HEADER as u64, table_end - FIXED_HEADER, &mut buf)?;
        if xxhash_rust::xxh3::xxh3_64(table_bytes) != table_checksum {
            return Err(ReadError::Damaged);
        }
        if count == 0 || !(count - 1).is_multiple_of(SectionKind::PER_OBJECT.len()) {
            return Err(corrupt(format!(
                "{count} sections: not a core and five per object"
            )));
        }
        let n_objects = (count - 1) / SectionKind::PER_OBJECT.len();
        let table = check_table(table_bytes, table_end as u64, file_length)?;
        Ok(Sections {
            source,
            table,
            n_objects,
        })
    }

    /// The section table, in file order.
    pub fn table(&self) -> &[Section] {
        &self.table
    }

    /// How many objects the file has graphs for.
    pub fn n_objects(&self) -> usize {
        self.n_objects
    }

    /// The table's row of one section.
    fn row(&self, kind: SectionKind, object: usize) -> Result<Section, ReadError> {
        let row = match kind {
            SectionKind::Core => 0,
            _ if object >= self.n_objects => {
                return Err(corrupt(format!("no object {object} in the file")))
            }
            _ => {
                1 + object * SectionKind::PER_OBJECT.len()
                    + SectionKind::PER_OBJECT
                        .iter()
                        .position(|&k| k == kind)
                        .unwrap_or(0)
            }
        };
        Ok(self.table[row])
    }

    /// Passes the bytes of one section to `decode` a piece at a time (each a whole
    /// number of `width`-byte records), then checks the section's checksum. Damage is
    /// reported as damage even when it made a record undecodable: after the first error
    /// of `decode` the rest is still read and hashed.
    fn pieces(
        &self,
        kind: SectionKind,
        object: usize,
        width: usize,
        mut decode: impl FnMut(&[u8]) -> Result<(), ReadError>,
    ) -> Result<(), ReadError> {
        let s = self.row(kind, object)?;
        let piece = PIECE_BYTES - PIECE_BYTES % width;
        let mut hasher = xxhash_rust::xxh3::Xxh3::new();
        let mut failed = None;
        let mut buf = Vec::new();
        let mut at = 0;
        while at < s.length {
            let length = piece.min(s.length - at);
            let bytes = self
                .source
                .bytes((s.offset + at) as u64, length, &mut buf)?;
            hasher.update(bytes);
            if failed.is_none() {
                failed = decode(bytes).err();
            }
            at += length;
        }
        if hasher.digest() != s.checksum {
            return Err(ReadError::Damaged);
        }
        failed.map_or(Ok(()), Err)
    }

    fn postcard<T: serde::de::DeserializeOwned>(
        &self,
        kind: SectionKind,
        object: usize,
    ) -> Result<T, ReadError> {
        let s = self.row(kind, object)?;
        let mut buf = Vec::new();
        let body = self.source.bytes(s.offset as u64, s.length, &mut buf)?;
        if xxhash_rust::xxh3::xxh3_64(body) != s.checksum {
            return Err(ReadError::Damaged);
        }
        let (value, left) = postcard::take_from_bytes::<T>(body)
            .map_err(|e| corrupt(format!("{}: {e}", kind.name())))?;
        if !left.is_empty() {
            return Err(corrupt(format!(
                "{} bytes after the end of the {} section",
                left.len(),
                kind.name()
            )));
        }
        Ok(value)
    }

    /// The artifact without its objects' graphs. Its object count must be the table's.
    pub fn core(&self) -> Result<Artifact, ReadError> {
        let core: Artifact = self.postcard(SectionKind::Core, 0)?;
        if core.objects.len() != self.n_objects {
            return Err(corrupt(format!(
                "the core has {} objects, the section table {}",
                core.objects.len(),
                self.n_objects
            )));
        }
        Ok(core)
    }

    /// The nodes of object `o`.
    pub fn nodes(&self, o: usize) -> Result<Vec<Node>, ReadError> {
        let s = self.row(SectionKind::Nodes, o)?;
        let mut nodes = Vec::with_capacity(s.length / NODE_BYTES);
        self.pieces(SectionKind::Nodes, o, NODE_BYTES, |bytes| {
            nodes.extend(bytes.chunks_exact(NODE_BYTES).map(|r| Node {
                end_effector: EndEffectorId(u32_at(r, 0)),
                grasp: GraspId(u32_at(r, 4)),
                workspace: WorkspaceId(u32_at(r, 8)),
            }));
            Ok(())
        })?;
        Ok(nodes)
    }

    /// The arcs of object `o`. A plain loop into a list of the exact length (the length
    /// is the section's, which the file holds): collecting results through an iterator
    /// adapter took three times as long on 10^6 arcs.
    pub fn arcs(&self, o: usize) -> Result<Vec<Arc>, ReadError> {
        self.arcs_testing(o, |_| true).map(|(arcs, _)| arcs)
    }

    /// The arcs of object `o`, and whether every one passed `test`, which is applied to
    /// each as it is decoded: a check made then costs no second pass over 10^6 arcs
    /// (see [`crate::validate::graph::arc_test`]).
    pub fn arcs_testing(
        &self,
        o: usize,
        test: impl Fn(&Arc) -> bool,
    ) -> Result<(Vec<Arc>, bool), ReadError> {
        let mut passed = true;
        let s = self.row(SectionKind::Arcs, o)?;
        let mut arcs = crate::huge::with_capacity(s.length / ARC_BYTES);
        self.pieces(SectionKind::Arcs, o, ARC_BYTES, |bytes| {
            for r in bytes.chunks_exact(ARC_BYTES) {
                let flags = u32_at(r, 20);
                if flags & !(FLAG_TRANSITION | FLAG_VIA | FLAG_WITNESS) != 0 {
                    let i = arcs.len();
                    return Err(corrupt(format!("arc {i} of object {o} has unknown flags")));
                }
                let some = |flag: u32, v: u32| (flags & flag != 0).then_some(v);
                let arc = Arc {
                    from: u32_at(r, 0),
                    to: u32_at(r, 4),
                    source: u32_at(r, 8),
                    via: some(FLAG_VIA, u32_at(r, 12)),
                    witness: some(FLAG_WITNESS, u32_at(r, 16)),
                    kind: if flags & FLAG_TRANSITION != 0 {
                        ArcKind::Transition
                    } else {
                        ArcKind::Move
                    },
                    weight: f64::from_bits(u64_at(r, 24)),
                };
                passed &= test(&arc);
                arcs.push(arc);
            }
            Ok(())
        })?;
        Ok((arcs, passed))
    }

    /// The pruned arcs of object `o`.
    pub fn pruned(&self, o: usize) -> Result<Vec<PrunedArc>, ReadError> {
        self.postcard(SectionKind::Pruned, o)
    }

    /// The witnesses of object `o`.
    pub fn witnesses(&self, o: usize) -> Result<Vec<Witness>, ReadError> {
        self.postcard(SectionKind::Witnesses, o)
    }

    /// The declared transitions of object `o`.
    pub fn transitions(&self, o: usize) -> Result<Vec<DeclaredTransition>, ReadError> {
        let s = self.row(SectionKind::Transitions, o)?;
        let mut transitions = Vec::with_capacity(s.length / TRANSITION_BYTES);
        self.pieces(SectionKind::Transitions, o, TRANSITION_BYTES, |bytes| {
            transitions.extend(
                bytes
                    .chunks_exact(TRANSITION_BYTES)
                    .map(|r| DeclaredTransition {
                        from: u32_at(r, 0),
                        to: u32_at(r, 4),
                        span: u32_at(r, 8),
                    }),
            );
            Ok(())
        })?;
        Ok(transitions)
    }

    /// Every section, assembled into the artifact (not yet validated).
    pub fn artifact(&self) -> Result<Artifact, ReadError> {
        let mut a = self.core()?;
        for (i, o) in a.objects.iter_mut().enumerate() {
            o.graph = Graph {
                nodes: self.nodes(i)?,
                arcs: self.arcs(i)?,
                pruned: self.pruned(i)?,
                witnesses: self.witnesses(i)?,
            };
            o.transitions = self.transitions(i)?;
        }
        Ok(a)
    }
}

/// The rows of a table whose checksum matched, each checked: in order, of the kind its
/// place says, inside the file without gap or overlap, a whole number of records.
fn check_table(
    table_bytes: &[u8],
    table_end: u64,
    file_length: u64,
) -> Result<Vec<Section>, ReadError> {
    let count = table_bytes.len() / ENTRY_BYTES;
    let mut table = Vec::with_capacity(count);
    let mut next = table_end as usize;
    for (row, entry) in table_bytes.chunks_exact(ENTRY_BYTES).enumerate() {
        let (kind, object) = if row == 0 {
            (SectionKind::Core, 0)
        } else {
            let per = SectionKind::PER_OBJECT.len();
            (
                SectionKind::PER_OBJECT[(row - 1) % per],
                ((row - 1) / per) as u32,
            )
        };
        if u32_at(entry, 0) != kind.code() || u32_at(entry, 4) != object {
            return Err(corrupt(format!(
                "section {row} should be the {} of object {object}",
                kind.name()
            )));
        }
        let offset = u64_at(entry, 8);
        let length = u64_at(entry, 16);
        if offset != next as u64 {
            return Err(corrupt(format!(
                "section {row} starts at {offset}, not where the one before it ends ({next})"
            )));
        }
        let end = offset
            .checked_add(length)
            .filter(|&e| e <= file_length)
            .ok_or_else(|| {
                corrupt(format!(
                    "section {row} ({length} bytes at {offset}) ends after the file"
                ))
            })?;
        let width = match kind {
            SectionKind::Nodes => NODE_BYTES as u64,
            SectionKind::Arcs => ARC_BYTES as u64,
            SectionKind::Transitions => TRANSITION_BYTES as u64,
            _ => 1,
        };
        if !length.is_multiple_of(width) {
            return Err(corrupt(format!(
                "section {row} ({}) is {length} bytes, not a whole number of records",
                kind.name()
            )));
        }
        table.push(Section {
            kind,
            object,
            offset: offset as usize,
            length: length as usize,
            checksum: u64_at(entry, 24),
        });
        next = end as usize;
    }
    if next != file_length as usize {
        return Err(corrupt(format!(
            "{} bytes after the last section",
            file_length as usize - next
        )));
    }
    Ok(table)
}
