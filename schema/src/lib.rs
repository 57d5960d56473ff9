//! The cellc artifact: what `cellc build` writes and the runtime reads.
//!
//! These are the only serialisable types of the project. The compiler lowers its
//! internal model into an [`Artifact`]; the runtime reads nothing else. Ids here are
//! plain indices into the artifact's own lists (`end_effectors[i]`, ...), so the file is
//! self-describing and language-neutral.
//!
//! Two encodings carry the same value: JSON (the default, readable) and a compact binary
//! form (`MAGIC`, the format version as little-endian `u32`, then postcard). Both are
//! deterministic: the same artifact value always gives the same bytes.
//!
//! Beside the artifact, this crate holds the small vocabulary both sides of it share, so
//! that each concept has one home below the compiler and the runtime: the geometry types
//! and their conversions to the file forms ([`math`]), the file-reading trait ([`files`])
//! and the content hash ([`hash`]).
#![warn(missing_docs)]

use serde::{Deserialize, Serialize};

pub mod files;
pub mod hash;
pub mod ids;
pub mod validate;
pub mod math;
pub use files::{FileError, Files, MemoryFiles};
pub use hash::sha256_hex;
pub use ids::{EndEffectorId, GraspId, NodeId, ObjectId, RobotId, SpanId, WorkspaceId};

/// The value of [`Artifact::format`], identifying the file type.
pub const FORMAT: &str = "cellc-artifact";
/// Bumped on every incompatible change of these types or of the encodings. Version 2
/// added the content checksum.
pub const FORMAT_VERSION: u32 = 2;
/// First bytes of the binary encoding.
pub const MAGIC: &[u8; 8] = b"CELLCART";

/// A compiled cell.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Artifact {
    /// Always [`FORMAT`].
    pub format: String,
    /// [`FORMAT_VERSION`] of the writer.
    pub format_version: u32,
    /// Version of the compiler that wrote it.
    pub compiler_version: String,
    /// Name of the cell.
    pub cell: String,
    /// Every source file read, with its hash.
    pub sources: Vec<SourceFile>,
    /// Arc weights used.
    pub weights: Weights,
    /// Robot models.
    pub robots: Vec<Robot>,
    /// Hand and support kinds.
    pub holder_kinds: Vec<HolderKind>,
    /// Workspaces.
    pub workspaces: Vec<Workspace>,
    /// End-effectors.
    pub end_effectors: Vec<EndEffector>,
    /// Objects with their grasps and graphs.
    pub objects: Vec<Object>,
    /// Source places that arcs and elements point to (indices into this list).
    pub spans: Vec<SourceSpan>,
    /// Which workspaces are adjacent, and whether the cell declared it (`None` in
    /// artifacts made by other tools that do not say).
    pub adjacency: Option<AdjacencyRecord>,
    /// Fixed solids that hold nothing (shelves, walls): (name, box).
    pub obstacles: Vec<(String, Aabb)>,
    /// Named example requests of the cell, in source order.
    pub requests: Vec<NamedRequest>,
    /// Pairs of collision bodies that may touch (`allow contact`): `left`,
    /// `left/lwr_link_7`, `left/softhand`, `table`, an object.
    pub allowed_contacts: Vec<(String, String)>,
    /// Present when every arc was checked kinematically (`cellc build --verify`).
    pub verification: Option<Verification>,
}

/// A request declared in the cell (`request NAME: OBJECT from ... to ...`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct NamedRequest {
    /// Name.
    pub name: String,
    /// Index into [`Artifact::objects`].
    pub object: u32,
    /// Where the object is.
    pub from: RequestPlacement,
    /// Where it must go.
    pub to: RequestPlacement,
    /// The `request` line.
    pub span: u32,
}

/// A placement in a request.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RequestPlacement {
    /// Index into [`Artifact::end_effectors`].
    pub end_effector: u32,
    /// Index into the object's grasps, when named.
    pub grasp: Option<u32>,
    /// Index into [`Artifact::workspaces`], when named.
    pub workspace: Option<u32>,
    /// Object pose, when given.
    pub pose: Option<Pose>,
}

/// The adjacency a graph was built with.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct AdjacencyRecord {
    /// Declared with `adjacent` (true) or derived from reach (false).
    pub declared: bool,
    /// The adjacent pairs (indices into [`Artifact::workspaces`]), each once.
    pub pairs: Vec<(u32, u32)>,
}

/// How the arcs were verified.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Verification {
    /// Seed of the randomized solvers; the same cell and seed give the same witnesses.
    pub seed: u64,
    /// Arcs checked, over all objects.
    pub n_checked: u64,
    /// Arcs found infeasible and removed.
    pub n_pruned: u64,
}

/// Evidence that an arc is feasible: an object pose and a joint configuration of every
/// arm involved, collision-free and within limits.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Witness {
    /// Object pose in the cell.
    pub object: Pose,
    /// One configuration per arm involved (a move: the holding arm; a handoff: both; a
    /// transition with a surface: the arm).
    pub configurations: Vec<ArmConfiguration>,
}

/// Joint values of one arm.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ArmConfiguration {
    /// Index into [`Artifact::end_effectors`].
    pub end_effector: u32,
    /// One value per joint of its robot's chain.
    pub joints: Vec<f64>,
}

/// Why an arc was found infeasible.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
#[non_exhaustive]
pub enum Infeasibility {
    /// No joint configuration reaches the needed pose.
    NoIkSolution {
        /// The arm (index into [`Artifact::end_effectors`]) that could not reach.
        end_effector: u32,
        /// Attempts made.
        tries: u32,
        /// Smallest position error reached, metres.
        position_error: f64,
        /// Smallest rotation error reached, radians.
        rotation_error: f64,
    },
    /// No configuration of two arms holds the object at once in the workspace (the closed
    /// chain of a handoff does not close).
    NoClosedChain {
        /// One arm (index into [`Artifact::end_effectors`]).
        a: u32,
        /// The other.
        b: u32,
        /// Attempts made.
        tries: u32,
        /// Smallest loop-closure position error reached, metres.
        position_error: f64,
        /// Smallest loop-closure rotation error reached, radians.
        rotation_error: f64,
    },
    /// Every reachable configuration found collides; the pair of the last attempt.
    Collision {
        /// One body.
        a: String,
        /// The other.
        b: String,
    },
    /// No object pose satisfies the arc's placement (e.g. the surface does not extend
    /// into the workspace).
    NoPlacement {
        /// Why.
        detail: String,
    },
}

/// An arc removed by verification, kept with its reason for explanations.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PrunedArc {
    /// The arc as it was.
    pub arc: Arc,
    /// Why it was removed.
    pub reason: Infeasibility,
}

/// A source file and its SHA-256.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SourceFile {
    /// Path as given to the compiler.
    pub path: String,
    /// Lowercase hex SHA-256 of the text.
    pub sha256: String,
}

/// A place in a source file.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct SourceSpan {
    /// Index into [`Artifact::sources`].
    pub file: u32,
    /// First byte.
    pub start: u32,
    /// One past the last byte.
    pub end: u32,
    /// 1-based line of `start`.
    pub line: u32,
}

/// Arc weights.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Weights {
    /// Per move arc.
    pub move_weight: f64,
    /// Per transition arc.
    pub transition_weight: f64,
}

/// A rigid transform: translation in metres, rotation as a unit quaternion `[x, y, z, w]`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Pose {
    /// Translation.
    pub translation: [f64; 3],
    /// Rotation `[x, y, z, w]`.
    pub rotation: [f64; 4],
}

/// An axis-aligned box in metres.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Aabb {
    /// Smallest corner.
    pub min: [f64; 3],
    /// Largest corner.
    pub max: [f64; 3],
}

/// A robot model.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Robot {
    /// Name.
    pub name: String,
    /// URDF path as resolved by the compiler.
    pub urdf_path: String,
    /// SHA-256 of the URDF text, so a stale artifact can be refused.
    pub urdf_sha256: String,
    /// Base link.
    pub base_link: String,
    /// Tip link.
    pub tip_link: String,
    /// Movable joints from base to tip.
    pub joints: Vec<Joint>,
    /// Declaration.
    pub span: u32,
}

/// A movable joint of a robot's chain.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Joint {
    /// URDF name.
    pub name: String,
    /// Prismatic (metres) rather than revolute (radians).
    pub prismatic: bool,
    /// Lower limit; `None` for continuous joints (JSON has no infinity).
    pub lower: Option<f64>,
    /// Upper limit; `None` for continuous joints.
    pub upper: Option<f64>,
}

/// A shape in metres.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Shape {
    /// Box with edge lengths.
    Box {
        /// Edge lengths.
        size: [f64; 3],
    },
    /// Cylinder along z, centred.
    Cylinder {
        /// Radius.
        radius: f64,
        /// Height.
        height: f64,
    },
    /// Sphere.
    Sphere {
        /// Radius.
        radius: f64,
    },
    /// Mesh file.
    Mesh {
        /// Path.
        path: String,
    },
}

/// A shape placed in a frame.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Solid {
    /// Shape.
    pub shape: Shape,
    /// Placement.
    pub pose: Pose,
}

/// Hand or support.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum HolderClass {
    /// Grasps.
    Hand,
    /// Resting poses.
    Support,
}

/// A hand model or support kind.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct HolderKind {
    /// Name.
    pub name: String,
    /// Hand or support.
    pub class: HolderClass,
    /// Collision shapes in the holder frame.
    pub solids: Vec<Solid>,
}

/// A workspace.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Workspace {
    /// Name.
    pub name: String,
    /// Label.
    pub label: Option<String>,
    /// Geometry (empty in abstract cells).
    pub boxes: Vec<Aabb>,
    /// Derived from reach rather than declared.
    pub derived: bool,
    /// Declaration (for derived ones, the `workspaces from reach` line).
    pub span: u32,
}

/// The physical body of an end-effector.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Body {
    /// Abstract (no geometry).
    Abstract,
    /// At the tip of a robot.
    Arm {
        /// Index into [`Artifact::robots`].
        robot: u32,
        /// Base placement in the cell.
        base: Pose,
        /// Home configuration, one value per joint of the robot's chain.
        home: Vec<f64>,
    },
    /// A fixed surface.
    Surface {
        /// The slab; objects rest on its top face.
        slab: Aabb,
        /// Height of the reach extrusion.
        reach_height: f64,
    },
}

/// An end-effector.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct EndEffector {
    /// Name.
    pub name: String,
    /// Movable or fixed.
    pub movable: bool,
    /// Index into [`Artifact::holder_kinds`].
    pub kind: Option<u32>,
    /// Body.
    pub body: Body,
    /// Reach cuboids.
    pub reach_boxes: Vec<Aabb>,
    /// Indices into [`Artifact::workspaces`], sorted.
    pub reaches: Vec<u32>,
    /// Declaration.
    pub span: u32,
}

/// A symmetry of an object.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Symmetry {
    /// Axis in the object frame.
    pub axis: [f64; 3],
    /// `None`: any angle; `Some(n)`: multiples of 360°/n.
    pub order: Option<u32>,
}

/// Who a grasp is declared for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Holder {
    /// Index into [`Artifact::end_effectors`].
    EndEffector(u32),
    /// Index into [`Artifact::holder_kinds`].
    Kind(u32),
}

/// A grasp or resting pose.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Grasp {
    /// Name, unique within the object.
    pub name: String,
    /// Label.
    pub label: Option<String>,
    /// Holder.
    pub holder: Holder,
    /// True for resting poses (`rest`).
    pub rest: bool,
    /// Object pose in the holder frame.
    pub pose: Option<Pose>,
    /// Declaration.
    pub span: u32,
}

/// An object with its graph.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Object {
    /// Name.
    pub name: String,
    /// Shape.
    pub shape: Option<Shape>,
    /// Symmetries.
    pub symmetries: Vec<Symmetry>,
    /// Grasps; graph nodes index into this list.
    pub grasps: Vec<Grasp>,
    /// Declared transitions between grasps (directed), whether or not any workspace made
    /// arcs of them: explanations of unreachable goals suggest from these.
    pub transitions: Vec<DeclaredTransition>,
    /// The object-state graph.
    pub graph: Graph,
    /// Declaration.
    pub span: u32,
}

/// A declared, directed grasp exchange.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct DeclaredTransition {
    /// Grasp given up (index into the object's `grasps`).
    pub from: u32,
    /// Grasp taken.
    pub to: u32,
    /// The `transition` line.
    pub span: u32,
}

/// A state S(end-effector, grasp, workspace).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct Node {
    /// Index into [`Artifact::end_effectors`].
    pub end_effector: u32,
    /// Index into the object's `grasps`.
    pub grasp: u32,
    /// Index into [`Artifact::workspaces`].
    pub workspace: u32,
}

/// Move or transition.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ArcKind {
    /// Same grasp, adjacent workspace.
    Move,
    /// Grasp change inside one workspace.
    Transition,
}

/// A directed arc.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Arc {
    /// Index into `nodes`.
    pub from: u32,
    /// Index into `nodes`.
    pub to: u32,
    /// Kind.
    pub kind: ArcKind,
    /// Cost.
    pub weight: f64,
    /// The declaration that made the arc (index into [`Artifact::spans`]): for a
    /// transition its `transition` line, for a move the grasp's line.
    pub source: u32,
    /// For a move over a declared adjacency, the `adjacent` line.
    pub via: Option<u32>,
    /// Index into the object's `witnesses`, when verified.
    pub witness: Option<u32>,
}

/// The graph of one object.
#[derive(Clone, Debug, PartialEq, Default, Serialize, Deserialize)]
pub struct Graph {
    /// States.
    pub nodes: Vec<Node>,
    /// Arcs.
    pub arcs: Vec<Arc>,
    /// Arcs removed by verification, with reasons.
    pub pruned: Vec<PrunedArc>,
    /// Witnesses of verified arcs.
    pub witnesses: Vec<Witness>,
}

impl Graph {
    /// Number of move arcs.
    pub fn n_moves(&self) -> usize {
        self.arcs.iter().filter(|a| a.kind == ArcKind::Move).count()
    }

    /// Number of transition arcs.
    pub fn n_transitions(&self) -> usize {
        self.arcs.len() - self.n_moves()
    }
}

/// Encoding of an artifact file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Encoding {
    /// Compact JSON.
    Json,
    /// `MAGIC`, version, postcard.
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
            ReadError::Damaged => f.write_str(
                "the artifact is damaged: its content does not match its checksum",
            ),
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
    /// Encodes the artifact, with a SHA-256 of the content so damage is detected.
    ///
    /// JSON: `{"checksum":"HEX",` followed by the artifact's fields; the checksum is over
    /// the artifact's own JSON (`{` and the rest). Binary: `MAGIC`, the version, the 32
    /// bytes of the checksum, then postcard.
    pub fn to_bytes(&self, encoding: Encoding) -> Vec<u8> {
        match encoding {
            Encoding::Json => {
                // Serialising plain data with string keys cannot fail.
                let mut content = serde_json::to_vec(self).unwrap_or_default();
                content.push(b'\n');
                let mut bytes = JSON_CHECKSUM.to_vec();
                bytes.extend_from_slice(sha256_hex(&content).as_bytes());
                bytes.extend_from_slice(b"\",");
                bytes.extend_from_slice(content.get(1..).unwrap_or_default());
                bytes
            }
            Encoding::Binary => {
                let content = postcard::to_stdvec(self).unwrap_or_default();
                let mut bytes = MAGIC.to_vec();
                bytes.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
                {
                    use sha2::Digest;
                    bytes.extend_from_slice(&sha2::Sha256::digest(&content));
                }
                bytes.extend(content);
                bytes
            }
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
        if let Some(rest) = bytes.strip_prefix(MAGIC.as_slice()) {
            let version = rest
                .get(..4)
                .and_then(|v| v.try_into().ok())
                .map(u32::from_le_bytes)
                .ok_or_else(|| corrupt("the file ends inside its header"))?;
            if version != FORMAT_VERSION {
                return Err(ReadError::WrongVersion {
                    found: version,
                    expected: FORMAT_VERSION,
                });
            }
            let checksum = rest
                .get(4..36)
                .ok_or_else(|| corrupt("the file ends inside its header"))?;
            let content = &rest[36..];
            {
                use sha2::Digest;
                if sha2::Sha256::digest(content).as_slice() != checksum {
                    return Err(ReadError::Damaged);
                }
            }
            let (artifact, left) = postcard::take_from_bytes::<Artifact>(content)
                .map_err(|e| corrupt(&e.to_string()))?;
            if !left.is_empty() {
                return Err(ReadError::Corrupt {
                    detail: format!("{} bytes after the end of the artifact", left.len()),
                });
            }
            return Ok((artifact, Encoding::Binary));
        }
        #[derive(Deserialize)]
        struct Header {
            format: String,
            format_version: u32,
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
        if header.format != FORMAT {
            return Err(ReadError::NotAnArtifact);
        }
        if header.format_version != FORMAT_VERSION {
            return Err(ReadError::WrongVersion {
                found: header.format_version,
                expected: FORMAT_VERSION,
            });
        }
        let content = content.ok_or_else(|| corrupt("the checksum is missing"))?;
        serde_json::from_slice(&content)
            .map(|a| (a, Encoding::Json))
            .map_err(|e| corrupt(&e.to_string()))
    }
}
