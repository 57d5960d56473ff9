//! The sectioned binary encoding: a header with a table of sections, each checksummed on
//! its own, so a reader decodes (and checks) only the sections it asks for.
//!
//! Layout, all numbers little-endian:
//!
//! ```text
//! MAGIC (8) | BINARY_VERSION u32 | section count u32 | xxh3 of the table u64
//! table: count x (kind u32, object u32, offset u64, length u64, xxh3 of the section u64)
//! sections, in table order, without gaps or overlaps
//! ```
//!
//! The sections are the core (postcard of the artifact with every object's graph and
//! declared transitions emptied: names, geometry, requests, spans; small), and per
//! object its nodes and its arcs in fixed-width records that need no general decoder
//! ([`NODE_BYTES`], [`ARC_BYTES`]), its pruned arcs and its witnesses (postcard; only
//! explanations and the placing of exchanges need them), and its declared transitions
//! (fixed-width, [`TRANSITION_BYTES`]; only explanations need them). A 10^6-arc artifact
//! is mostly its arcs section; it declares 10^6 transitions too, which in the core took a
//! quarter of a plan's time to decode and check.
//!
//! The checksum is XXH3-64, not SHA-256: it detects damage (a cut, a flipped bit) as well
//! for that purpose and costs a small fraction of SHA-256 even with the CPU's SHA
//! instructions (see docs/performance.md). Nothing uses the binary checksum as the
//! artifact's identity: world documents and the service identify an artifact by its
//! cell's name and content, and the JSON encoding keeps its SHA-256 as before.

use crate::encoding::ReadError;
use crate::{Arc, ArcKind, Artifact, DeclaredTransition, Graph, Node, Object, MAGIC};

mod read;
pub use read::{Sections, Source};

/// Version of the binary encoding (the JSON encoding and the artifact's own
/// `format_version` stay at [`crate::FORMAT_VERSION`]). Version 5 moved each object's
/// declared transitions out of the core into a section of their own; version 4 was the
/// first sectioned one; version 3 was one postcard body behind one SHA-256.
pub const BINARY_VERSION: u32 = 5;

/// Bytes of one node record: end-effector, grasp, workspace (`u32` each).
pub const NODE_BYTES: usize = 12;
/// Bytes of one arc record: from, to, source, via, witness (`u32` each), flags (`u32`:
/// bit 0 transition, bit 1 `via` present, bit 2 `witness` present), weight (`f64`).
pub const ARC_BYTES: usize = 32;
/// Bytes of one declared transition record: from, to, span (`u32` each).
pub const TRANSITION_BYTES: usize = 12;

const FIXED_HEADER: usize = 8 + 4 + 4 + 8;
const ENTRY_BYTES: usize = 32;
const FLAG_TRANSITION: u32 = 1;
const FLAG_VIA: u32 = 2;
const FLAG_WITNESS: u32 = 4;

/// What a section holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SectionKind {
    /// The artifact without its objects' graphs.
    Core,
    /// One object's nodes.
    Nodes,
    /// One object's arcs.
    Arcs,
    /// One object's pruned arcs.
    Pruned,
    /// One object's witnesses.
    Witnesses,
    /// One object's declared transitions.
    Transitions,
}

impl SectionKind {
    const PER_OBJECT: [SectionKind; 5] = [
        SectionKind::Nodes,
        SectionKind::Arcs,
        SectionKind::Pruned,
        SectionKind::Witnesses,
        SectionKind::Transitions,
    ];

    fn code(self) -> u32 {
        match self {
            SectionKind::Core => 0,
            SectionKind::Nodes => 1,
            SectionKind::Arcs => 2,
            SectionKind::Pruned => 3,
            SectionKind::Witnesses => 4,
            SectionKind::Transitions => 5,
        }
    }

    fn name(self) -> &'static str {
        match self {
            SectionKind::Core => "core",
            SectionKind::Nodes => "nodes",
            SectionKind::Arcs => "arcs",
            SectionKind::Pruned => "pruned arcs",
            SectionKind::Witnesses => "witnesses",
            SectionKind::Transitions => "declared transitions",
        }
    }
}

/// One row of the section table.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Section {
    /// What it holds.
    pub kind: SectionKind,
    /// The object it belongs to (0 for the core).
    pub object: u32,
    /// Where it starts in the file.
    pub offset: usize,
    /// Its length in bytes.
    pub length: usize,
    /// XXH3-64 of its bytes.
    pub checksum: u64,
}

fn corrupt(detail: impl Into<String>) -> ReadError {
    ReadError::Corrupt {
        detail: detail.into(),
    }
}

fn put_u32(out: &mut Vec<u8>, v: u32) {
    out.extend_from_slice(&v.to_le_bytes());
}

fn put_u64(out: &mut Vec<u8>, v: u64) {
    out.extend_from_slice(&v.to_le_bytes());
}

fn u32_at(b: &[u8], at: usize) -> u32 {
    let mut x = [0; 4];
    x.copy_from_slice(&b[at..at + 4]);
    u32::from_le_bytes(x)
}

fn u64_at(b: &[u8], at: usize) -> u64 {
    let mut x = [0; 8];
    x.copy_from_slice(&b[at..at + 8]);
    u64::from_le_bytes(x)
}

/// The artifact without its objects' graphs and declared transitions, field by field so that a new field of
/// [`Artifact`] or [`Object`] cannot be forgotten here.
fn core_of(a: &Artifact) -> Artifact {
    Artifact {
        format: a.format.clone(),
        format_version: a.format_version,
        compiler_version: a.compiler_version.clone(),
        cell: a.cell.clone(),
        sources: a.sources.clone(),
        weights: a.weights,
        robots: a.robots.clone(),
        holder_kinds: a.holder_kinds.clone(),
        workspaces: a.workspaces.clone(),
        end_effectors: a.end_effectors.clone(),
        objects: a
            .objects
            .iter()
            .map(|o| Object {
                name: o.name.clone(),
                shape: o.shape.clone(),
                symmetries: o.symmetries.clone(),
                grasps: o.grasps.clone(),
                transitions: Vec::new(),
                graph: Graph::default(),
                span: o.span,
            })
            .collect(),
        spans: a.spans.clone(),
        adjacency: a.adjacency.clone(),
        obstacles: a.obstacles.clone(),
        requests: a.requests.clone(),
        world: a.world.clone(),
        tasks: a.tasks.clone(),
        allowed_contacts: a.allowed_contacts.clone(),
        verification: a.verification.clone(),
    }
}

fn nodes_bytes(nodes: &[Node]) -> Vec<u8> {
    let mut out = Vec::with_capacity(nodes.len() * NODE_BYTES);
    for n in nodes {
        put_u32(&mut out, n.end_effector.0);
        put_u32(&mut out, n.grasp.0);
        put_u32(&mut out, n.workspace.0);
    }
    out
}

fn arcs_bytes(arcs: &[Arc]) -> Vec<u8> {
    let mut out = Vec::with_capacity(arcs.len() * ARC_BYTES);
    for a in arcs {
        let mut flags = 0;
        if a.kind == ArcKind::Transition {
            flags |= FLAG_TRANSITION;
        }
        if a.via.is_some() {
            flags |= FLAG_VIA;
        }
        if a.witness.is_some() {
            flags |= FLAG_WITNESS;
        }
        put_u32(&mut out, a.from);
        put_u32(&mut out, a.to);
        put_u32(&mut out, a.source);
        put_u32(&mut out, a.via.unwrap_or(0));
        put_u32(&mut out, a.witness.unwrap_or(0));
        put_u32(&mut out, flags);
        put_u64(&mut out, a.weight.to_bits());
    }
    out
}

fn transitions_bytes(transitions: &[DeclaredTransition]) -> Vec<u8> {
    let mut out = Vec::with_capacity(transitions.len() * TRANSITION_BYTES);
    for t in transitions {
        put_u32(&mut out, t.from);
        put_u32(&mut out, t.to);
        put_u32(&mut out, t.span);
    }
    out
}

/// Encodes `a` in the sectioned binary layout. Deterministic: the same artifact gives the
/// same bytes.
pub fn write(a: &Artifact) -> Vec<u8> {
    // Serialising plain data cannot fail; if it did the section would be empty and the
    // reader would report it as corrupt, never panic.
    let mut bodies: Vec<(SectionKind, u32, Vec<u8>)> = vec![(
        SectionKind::Core,
        0,
        postcard::to_stdvec(&core_of(a)).unwrap_or_default(),
    )];
    for (i, o) in a.objects.iter().enumerate() {
        let i = i as u32;
        let g = &o.graph;
        bodies.push((SectionKind::Nodes, i, nodes_bytes(&g.nodes)));
        bodies.push((SectionKind::Arcs, i, arcs_bytes(&g.arcs)));
        bodies.push((
            SectionKind::Pruned,
            i,
            postcard::to_stdvec(&g.pruned).unwrap_or_default(),
        ));
        bodies.push((
            SectionKind::Witnesses,
            i,
            postcard::to_stdvec(&g.witnesses).unwrap_or_default(),
        ));
        bodies.push((
            SectionKind::Transitions,
            i,
            transitions_bytes(&o.transitions),
        ));
    }
    let data_at = FIXED_HEADER + bodies.len() * ENTRY_BYTES;
    let total = data_at + bodies.iter().map(|b| b.2.len()).sum::<usize>();
    let mut table = Vec::with_capacity(bodies.len() * ENTRY_BYTES);
    let mut offset = data_at;
    for (kind, object, body) in &bodies {
        put_u32(&mut table, kind.code());
        put_u32(&mut table, *object);
        put_u64(&mut table, offset as u64);
        put_u64(&mut table, body.len() as u64);
        put_u64(&mut table, xxhash_rust::xxh3::xxh3_64(body));
        offset += body.len();
    }
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(MAGIC);
    put_u32(&mut out, BINARY_VERSION);
    put_u32(&mut out, bodies.len() as u32);
    put_u64(&mut out, xxhash_rust::xxh3::xxh3_64(&table));
    out.extend(table);
    for (_, _, body) in bodies {
        out.extend(body);
    }
    out
}
