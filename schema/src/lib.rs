//! The cellc artifact: what `cellc build` writes and the runtime reads.
//!
//! These are the only serialisable types of the project. The compiler lowers its
//! internal model into an [`Artifact`]; the runtime reads nothing else. Ids here are
//! plain indices into the artifact's own lists (`end_effectors[i]`, ...), so the file is
//! self-describing and language-neutral.
//!
//! Two encodings carry the same value: JSON (the default, readable) and a binary form
//! in checksummed sections that a reader decodes one at a time ([`sections`]). Both are
//! deterministic: the same artifact value always gives the same bytes.
//!
//! Beside the artifact, this crate holds the small vocabulary both sides of it share, so
//! that each concept has one home below the compiler and the runtime: the geometry types
//! and their conversions to the file forms ([`math`]), the file-reading trait ([`files`])
//! and the content hash ([`hash`]).
#![warn(missing_docs)]

use serde::{Deserialize, Serialize};

pub mod blocked;
pub mod files;
pub mod hash;
pub mod huge;
pub mod ids;
pub mod validate;

mod encoding;
pub use encoding::{Encoding, ReadError};
pub mod math;
pub mod partial;
pub use files::{FileError, Files, MemoryFiles};
pub use hash::sha256_hex;
pub mod rules;
pub mod sections;
/// Object symmetries: which rotations leave an object looking the same.
pub mod symmetry;
pub mod world;
pub use blocked::{BlockedPart, BlockedStep, Blocker};
pub use ids::{EndEffectorId, GraspId, NodeId, ObjectId, RobotId, SpanId, WorkspaceId};
pub use world::{InitialPlacement, NamedTask, TaskStep, WorldDocument};

/// The value of [`Artifact::format`], identifying the file type.
pub const FORMAT: &str = "cellc-artifact";
/// Bumped on every incompatible change of these types or of the encodings. Version 2
/// added the content checksum; version 3 the robots' resolved mesh paths, SRDF and
/// disabled collision pairs, the world and tasks; version 4 each joint's velocity,
/// acceleration and jerk limits.
pub const FORMAT_VERSION: u32 = 4;
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
    /// Where the objects start (the cell's `world` item; empty: no object is placed).
    pub world: Vec<InitialPlacement>,
    /// Named tasks of the cell, in source order.
    pub tasks: Vec<NamedTask>,
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
    /// The object.
    pub object: ObjectId,
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
    /// The holder.
    pub end_effector: EndEffectorId,
    /// The object's grasp, when named.
    pub grasp: Option<GraspId>,
    /// The workspace, when named.
    pub workspace: Option<WorkspaceId>,
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
    /// The arm.
    pub end_effector: EndEffectorId,
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
        /// The arm that could not reach.
        end_effector: EndEffectorId,
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
        /// One arm.
        a: EndEffectorId,
        /// The other.
        b: EndEffectorId,
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
    /// The hand is holding another object (planning in a world: no state of this object
    /// may be held by it until it lets that one go).
    HandBusy {
        /// The hand.
        hand: EndEffectorId,
        /// What it holds.
        holds: ObjectId,
    },
    /// Another object of the world is in the way (planning in a world): the step is
    /// feasible without it.
    Blocked(Blocker),
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
    /// Every collision mesh the URDF names, with the path the compiler resolved it to
    /// (`package://` URIs included), so the runtime needs no package path.
    pub meshes: Vec<MeshFile>,
    /// The MoveIt SRDF the compiler read (its facts are recorded here: the runtime does not
    /// read it again).
    pub srdf: Option<SourceFile>,
    /// Link pairs never checked against each other (the SRDF's `<disable_collisions>`),
    /// as URDF link names.
    pub disabled_collisions: Vec<(String, String)>,
    /// Base link.
    pub base_link: String,
    /// Tip link.
    pub tip_link: String,
    /// Movable joints from base to tip.
    pub joints: Vec<Joint>,
    /// Declaration.
    pub span: u32,
}

/// A mesh file named in a URDF, and where it was found.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MeshFile {
    /// The file name as the URDF writes it (`package://...`, `file://...` or a path).
    pub written: String,
    /// Its path, as the compiler resolved it.
    pub path: String,
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
    /// Largest speed the runtime times motions with (rad/s, or m/s): the URDF's
    /// `<limit velocity>`, a cell's `limits` or `joint_limits.yaml`, or the default, as the
    /// compiler resolved it (the runtime never guesses one).
    pub velocity: f64,
    /// Largest acceleration (rad/s², or m/s²), resolved the same way (URDFs have none).
    pub acceleration: f64,
    /// Largest jerk (rad/s³, or m/s³) where the cell or `joint_limits.yaml` declares one.
    pub jerk: Option<f64>,
}

impl Joint {
    /// Speed limit of a joint that has none (rad/s or m/s): about half an industrial arm's
    /// rated joint speed, a safe pace for a first run.
    pub const DEFAULT_VELOCITY: f64 = 1.0;
    /// Acceleration limit of a joint that has none (rad/s² or m/s²); URDFs give none.
    pub const DEFAULT_ACCELERATION: f64 = 2.0;
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

/// A state S(end-effector, grasp, workspace). Ordered by end-effector, then grasp, then
/// workspace, the order the graph rules list states in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub struct Node {
    /// Which end-effector holds the object.
    pub end_effector: EndEffectorId,
    /// Which of the object's grasps (or resting poses).
    pub grasp: GraspId,
    /// Which workspace.
    pub workspace: WorkspaceId,
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

/// Names of the artifact's elements by id, the one lookup every report uses. An id out of
/// range (a bug, or an artifact edited by hand) reads `?` rather than panicking: reports
/// run on what validation already accepted, but never trust that alone.
impl Artifact {
    /// The URDF names of an arm's chain joints, base to tip, in the order its joint values
    /// are given everywhere (empty for what is not an arm).
    pub fn joint_names(&self, e: EndEffectorId) -> Vec<&str> {
        match self.end_effectors.get(e.index()).map(|x| &x.body) {
            Some(Body::Arm { robot, .. }) => self
                .robots
                .get(*robot as usize)
                .map(|r| r.joints.iter().map(|j| j.name.as_str()).collect())
                .unwrap_or_default(),
            _ => Vec::new(),
        }
    }

    /// The end-effector's name.
    pub fn end_effector_name(&self, e: EndEffectorId) -> &str {
        self.end_effectors
            .get(e.index())
            .map_or("?", |x| x.name.as_str())
    }

    /// The workspace's name.
    pub fn workspace_name(&self, w: WorkspaceId) -> &str {
        self.workspaces
            .get(w.index())
            .map_or("?", |x| x.name.as_str())
    }

    /// The object's name.
    pub fn object_name(&self, o: ObjectId) -> &str {
        self.objects.get(o.index()).map_or("?", |x| x.name.as_str())
    }

    /// The pose of grasp (or resting pose) `g` of object `o` in its holder's frame; the
    /// identity when it has none (abstract cells).
    pub fn grasp_pose(&self, o: ObjectId, g: GraspId) -> math::Iso {
        self.objects
            .get(o.index())
            .and_then(|x| x.grasps.get(g.index()))
            .and_then(|x| x.pose.as_ref())
            .map(math::iso_from_schema)
            .unwrap_or_else(math::Iso::identity)
    }

    /// The name of grasp (or resting pose) `g` of object `o`.
    pub fn grasp_name(&self, o: ObjectId, g: GraspId) -> &str {
        self.objects
            .get(o.index())
            .and_then(|x| x.grasps.get(g.index()))
            .map_or("?", |x| x.name.as_str())
    }
}
