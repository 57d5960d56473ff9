//! The resolved cell: every name replaced by a typed id, every quantity in SI units.
//!
//! This is what the checks, workspace derivation and graph generation work on. It keeps
//! an [`Origin`] on everything so that any later finding (an unreachable goal, a pruned
//! arc) can point back at the line that caused it.

use cellc_lang::ast::{GraspKeyword, Mobility};
use cellc_lang::{FileId, Span};

use crate::ids::*;
use crate::math::{Aabb, Iso};

/// Where something was declared.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Origin {
    /// File.
    pub file: FileId,
    /// Span of the declaring item or member.
    pub span: Span,
    /// Span of the declared name (the best place for a label).
    pub name_span: Span,
}

/// Arc weights: the cost Dijkstra pays per move and per grasp transition.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Weights {
    /// Same grasp, adjacent workspace.
    pub move_weight: f64,
    /// Grasp change inside one workspace.
    pub transition_weight: f64,
}

impl Default for Weights {
    /// The paper's text: a move is cheap (0.1); a change of end-effector is more likely to
    /// fail (1.0).
    fn default() -> Weights {
        Weights {
            move_weight: 0.1,
            transition_weight: 1.0,
        }
    }
}

/// A region of the cell.
#[derive(Clone, Debug)]
pub struct Workspace {
    /// Name (declared, or derived from who reaches it).
    pub name: String,
    /// Human label.
    pub label: Option<String>,
    /// Geometry: the union of these boxes (empty in abstract cells).
    pub boxes: Vec<Aabb>,
    /// Declaration, or for derived workspaces the `workspaces from reach` item.
    pub origin: Origin,
    /// True when computed from reach rather than declared.
    pub derived: bool,
}

/// What kind of holder a holder kind is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HolderClass {
    /// A hand model: grasps.
    Hand,
    /// A kind of support surface: resting poses.
    Support,
}

/// A primitive or mesh shape, in metres.
#[derive(Clone, Debug, PartialEq)]
pub enum Shape {
    /// Box with edge lengths.
    Box {
        /// Edge lengths.
        size: [f64; 3],
    },
    /// Cylinder along z.
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
    /// Mesh file, path resolved against the declaring file.
    Mesh {
        /// Path.
        path: String,
    },
}

/// A shape placed in a frame.
#[derive(Clone, Debug, PartialEq)]
pub struct Solid {
    /// Shape.
    pub shape: Shape,
    /// Placement in the parent frame.
    pub pose: Iso,
}

/// A hand model or support kind: what grasps and resting poses are declared for, so that
/// identical hardware shares one set of them.
#[derive(Clone, Debug)]
pub struct HolderKind {
    /// Name.
    pub name: String,
    /// Hand or support.
    pub class: HolderClass,
    /// Collision shapes (hands).
    pub solids: Vec<Solid>,
    /// Declaration.
    pub origin: Origin,
}

/// A robot model read from a URDF: the serial chain from base to tip.
#[derive(Clone, Debug)]
pub struct Robot {
    /// Name.
    pub name: String,
    /// URDF path, resolved against the declaring file.
    pub urdf_path: String,
    /// SHA-256 of the URDF text, recorded in the artifact so the runtime can tell a
    /// changed file.
    pub urdf_sha256: String,
    /// The URDF's collision meshes with their resolved paths (`package://` included).
    pub meshes: Vec<cellc_schema::MeshFile>,
    /// The SRDF read, as (path, SHA-256).
    pub srdf: Option<(String, String)>,
    /// Link pairs never checked for collision (the SRDF's `<disable_collisions>`).
    pub disabled_collisions: Vec<(String, String)>,
    /// The SRDF's named configurations (for `home NAME`).
    pub group_states: Vec<cellc_urdf::GroupState>,
    /// The SRDF planning group the robot item names.
    pub group: Option<String>,
    /// Base link.
    pub base_link: String,
    /// Tip link.
    pub tip_link: String,
    /// The movable joints from base to tip, in order.
    pub chain_joints: Vec<Joint>,
    /// Every link of the URDF (for `allow contact` names), sorted.
    pub links: std::collections::BTreeSet<String>,
    /// Declaration.
    pub origin: Origin,
}

/// A movable joint of a robot's chain.
#[derive(Clone, Debug, PartialEq)]
pub struct Joint {
    /// URDF name.
    pub name: String,
    /// Revolute (radians) or prismatic (metres).
    pub prismatic: bool,
    /// Lower limit (`-inf` for continuous joints).
    pub lower: f64,
    /// Upper limit (`inf` for continuous joints).
    pub upper: f64,
    /// Speed limit (rad/s or m/s): the URDF's `<limit velocity>` (`None` when absent,
    /// zero, or not finite) unless the cell or its `joint_limits.yaml` gives one.
    pub velocity: Option<Limit>,
    /// Acceleration limit (rad/s² or m/s²), declared in the cell or its
    /// `joint_limits.yaml` (a URDF has none).
    pub acceleration: Option<Limit>,
    /// Jerk limit (rad/s³ or m/s³), declared likewise; `None` is no jerk limit.
    pub jerk: Option<Limit>,
}

/// One limit of a joint and where it came from (`cellc info` shows it; the artifact
/// carries the value only).
#[derive(Clone, Debug, PartialEq)]
pub struct Limit {
    /// In SI units.
    pub value: f64,
    /// Where it was read.
    pub source: LimitSource,
}

/// Where a joint's limit came from, in the order of precedence, last wins.
#[derive(Clone, Debug, PartialEq)]
pub enum LimitSource {
    /// The URDF's `<limit velocity>`.
    Urdf,
    /// A `joint_limits.yaml` named by `limits ROBOT from "FILE"` (its path, and the line).
    File(String, Origin),
    /// A `limits ROBOT ...` line (every joint of the robot).
    Robot(Origin),
    /// A `limits ROBOT.JOINT ...` line.
    Joint(Origin),
}

impl Joint {
    /// Speed limit a joint without one is timed with (the artifact's one home of it).
    pub const DEFAULT_VELOCITY: f64 = cellc_schema::Joint::DEFAULT_VELOCITY;
    /// Acceleration limit a joint without one is timed with.
    pub const DEFAULT_ACCELERATION: f64 = cellc_schema::Joint::DEFAULT_ACCELERATION;
}

/// How an end-effector exists physically.
#[derive(Clone, Debug)]
pub enum Body {
    /// Declared in the abstract form (`fixed`/`movable NAME reaches ...`).
    Abstract,
    /// A hand or conveyor carriage at the tip of a robot placed in the cell.
    Arm {
        /// Robot model (`None` when its name did not resolve).
        robot: Option<RobotId>,
        /// Pose of the robot base in the cell.
        base: Iso,
        /// Home configuration, one value per chain joint.
        home: Vec<f64>,
    },
    /// A fixed surface: objects rest on the slab's top face.
    Surface {
        /// The slab.
        slab: Aabb,
        /// Height of the reach extrusion above the top face.
        reach_height: f64,
    },
}

/// Something that can hold or support an object.
#[derive(Clone, Debug)]
pub struct EndEffector {
    /// Name.
    pub name: String,
    /// Movable (a hand, a conveyor) or fixed (a surface).
    pub mobility: Mobility,
    /// Holder kind, for geometric end-effectors.
    pub kind: Option<HolderKindId>,
    /// Physical body.
    pub body: Body,
    /// Reach cuboids (geometric cells): declared, and computed for `reach auto`.
    pub reach_boxes: Vec<Aabb>,
    /// The `reach NAME auto` line, when the arm's reach is computed from its kinematics.
    pub reach_auto: Option<Origin>,
    /// Workspaces this end-effector reaches, sorted.
    pub reaches: Vec<WorkspaceId>,
    /// Declaration.
    pub origin: Origin,
}

impl EndEffector {
    /// True for hands and conveyors.
    pub fn is_movable(&self) -> bool {
        self.mobility == Mobility::Movable
    }
}

/// Continuous or discrete symmetry of an object about an axis of its frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Symmetry {
    /// Axis in the object frame.
    pub axis: [f64; 3],
    /// `None`: any angle; `Some(n)`: multiples of 360°/n.
    pub order: Option<u32>,
}

/// An object.
#[derive(Clone, Debug)]
pub struct Object {
    /// Name.
    pub name: String,
    /// Collision shape.
    pub shape: Option<Shape>,
    /// Symmetries.
    pub symmetries: Vec<Symmetry>,
    /// Grasps and resting poses declared for it, in source order.
    pub grasps: Vec<GraspId>,
    /// Declaration.
    pub origin: Origin,
}

/// Who a grasp is declared for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Holder {
    /// One end-effector (abstract cells, or a grasp particular to one arm).
    EndEffector(EndEffectorId),
    /// Every end-effector of a holder kind.
    Kind(HolderKindId),
}

/// A grasp or resting pose of one object.
#[derive(Clone, Debug)]
pub struct Grasp {
    /// Name, unique within the object.
    pub name: String,
    /// Human label.
    pub label: Option<String>,
    /// The object.
    pub object: ObjectId,
    /// Who holds it (`None` when the holder's name did not resolve).
    pub holder: Option<Holder>,
    /// `grasp` or `rest`.
    pub keyword: GraspKeyword,
    /// Pose of the object in the holder's frame.
    pub pose: Option<Iso>,
    /// Declaration.
    pub origin: Origin,
}

/// A declared, directed grasp exchange (`a <-> b` declares two).
#[derive(Clone, Debug)]
pub struct Transition {
    /// Grasp given up.
    pub from: GraspId,
    /// Grasp taken.
    pub to: GraspId,
    /// The `transition` member.
    pub origin: Origin,
}

/// A declared adjacency between two workspaces.
#[derive(Clone, Debug)]
pub struct Adjacency {
    /// One workspace.
    pub a: WorkspaceId,
    /// The other.
    pub b: WorkspaceId,
    /// Declaration.
    pub origin: Origin,
}

/// A resolved `expect`.
#[derive(Clone, Debug)]
pub enum Requirement {
    /// The object can go from one placement to the other.
    Reach {
        /// Object.
        object: ObjectId,
        /// Start.
        from: Placement,
        /// Goal.
        to: Placement,
    },
    /// A workspace is reached by at least `at_least` end-effectors (of one mobility).
    Coverage {
        /// Workspace.
        workspace: WorkspaceId,
        /// Minimum.
        at_least: u32,
        /// Only count these.
        mobility: Option<Mobility>,
    },
    /// No state of the object (or of any object) is isolated.
    NoIsolatedStates {
        /// Limit to one object.
        object: Option<ObjectId>,
    },
}

/// Where an object is held in a requirement.
#[derive(Clone, Copy, Debug)]
pub struct Placement {
    /// Holder.
    pub end_effector: EndEffectorId,
    /// A particular grasp, or any grasp of that end-effector.
    pub grasp: Option<GraspId>,
    /// Workspace.
    pub workspace: WorkspaceId,
    /// The placement as written.
    pub span: Span,
}

/// A resolved `request`.
#[derive(Clone, Debug)]
pub struct NamedRequest {
    /// Its name.
    pub name: String,
    /// The object.
    pub object: ObjectId,
    /// Where it is.
    pub from: RequestPlacement,
    /// Where it must go.
    pub to: RequestPlacement,
    /// The `request` item.
    pub origin: Origin,
}

/// A resolved placement of a request.
#[derive(Clone, Debug)]
pub struct RequestPlacement {
    /// Holder.
    pub end_effector: EndEffectorId,
    /// Grasp, when named.
    pub grasp: Option<GraspId>,
    /// Workspace, when given by name.
    pub workspace: Option<WorkspaceId>,
    /// Object pose, when given.
    pub pose: Option<Iso>,
}

/// A resolved line of the cell's `world`: where an object starts.
#[derive(Clone, Debug)]
pub struct InitialPlacement {
    /// The object.
    pub object: ObjectId,
    /// Where it is: a workspace or a pose, or neither for an object held by an arm (its
    /// pose follows from the arm's joints).
    pub placement: RequestPlacement,
    /// The line (name span: the object's name).
    pub origin: Origin,
}

/// A resolved `task`: moves in order.
#[derive(Clone, Debug)]
pub struct NamedTask {
    /// Its name (shared with requests: no task and request have the same one).
    pub name: String,
    /// The moves, in order; never empty.
    pub steps: Vec<TaskStep>,
    /// The `task` item.
    pub origin: Origin,
}

/// One move of a task: the object and where it must go.
#[derive(Clone, Debug)]
pub struct TaskStep {
    /// The object moved.
    pub object: ObjectId,
    /// Where it must go.
    pub to: RequestPlacement,
    /// The step's line (name span: the object's name).
    pub origin: Origin,
}

/// A resolved `expect` with its origin.
#[derive(Clone, Debug)]
pub struct Expectation {
    /// What is required.
    pub requirement: Requirement,
    /// The `expect` item, and the text of the requirement for messages.
    pub origin: Origin,
    /// The requirement as written (for messages).
    pub text: String,
}

/// The resolved cell.
#[derive(Clone, Debug, Default)]
pub struct Cell {
    /// Name from `cell NAME`.
    pub name: String,
    /// Workspaces, declared then derived.
    pub workspaces: Arena<WorkspaceId, Workspace>,
    /// End-effectors.
    pub end_effectors: Arena<EndEffectorId, EndEffector>,
    /// Holder kinds.
    pub holder_kinds: Arena<HolderKindId, HolderKind>,
    /// Robot models.
    pub robots: Arena<RobotId, Robot>,
    /// Objects.
    pub objects: Arena<ObjectId, Object>,
    /// Grasps of all objects.
    pub grasps: Arena<GraspId, Grasp>,
    /// Declared transitions, directed.
    pub transitions: Vec<Transition>,
    /// Declared adjacencies.
    pub adjacencies: Vec<Adjacency>,
    /// Arc weights.
    pub weights: Weights,
    /// Requirements.
    pub expectations: Vec<Expectation>,
    /// True when the cell says `workspaces from reach`.
    pub derive_workspaces: Option<Origin>,
    /// Fixed solids that hold nothing: (name, box, declaration).
    pub obstacles: Vec<(String, Aabb, Origin)>,
    /// Named example requests, in source order.
    pub requests: Vec<NamedRequest>,
    /// Where the objects start (the `world` item's lines, in source order); objects not
    /// listed are absent.
    pub world: Vec<InitialPlacement>,
    /// The `world` item, when the cell (or a library it includes) has one.
    pub world_origin: Option<Origin>,
    /// Named tasks, in source order.
    pub tasks: Vec<NamedTask>,
    /// Pairs of bodies that may touch (`allow contact`), by collision-body name
    /// (`left`, `left/lwr_link_7`, `table`).
    pub allowed_contacts: Vec<(String, String, Origin)>,
    /// What `reach auto` computed, per arm that asked (for `cellc info`; its boxes are in
    /// the arms' `reach_boxes`).
    pub auto_reach: Vec<crate::reach::AutoReach>,
    /// Objects with a grasp or rest family that did not expand (reported where it is
    /// declared): whether their other grasps are used is not judged, since the
    /// transitions naming the family are missing.
    pub incomplete_objects: Vec<ObjectId>,
}

impl Cell {
    /// True when end-effector `e` can hold grasp `g`.
    pub fn holds(&self, e: EndEffectorId, g: GraspId) -> bool {
        match self.grasps[g].holder {
            Some(Holder::EndEffector(holder)) => holder == e,
            Some(Holder::Kind(kind)) => self.end_effectors[e].kind == Some(kind),
            None => false,
        }
    }

    /// Who can hold each grasp (see [`Holders`]).
    pub fn holders(&self) -> Holders {
        let mut of_kind: Vec<Vec<EndEffectorId>> = vec![Vec::new(); self.holder_kinds.len()];
        for (e, ee) in self.end_effectors.iter() {
            if let Some(kind) = ee.kind {
                of_kind[kind.index()].push(e);
            }
        }
        let grasps = self.grasps.iter().map(|(_, g)| g.holder).collect();
        Holders { of_kind, grasps }
    }
}

/// For every grasp, the end-effectors that can hold it, in id order. Built in one pass
/// over the end-effectors (grouped by kind) and one over the grasps, and a kind's list is
/// shared by all its grasps, so a cell with many hands and many grasps costs their sum,
/// not their product.
#[derive(Clone, Debug)]
pub struct Holders {
    of_kind: Vec<Vec<EndEffectorId>>,
    grasps: Vec<Option<Holder>>,
}

impl Holders {
    /// The end-effectors that can hold grasp `g`, in id order.
    pub fn of(&self, g: GraspId) -> &[EndEffectorId] {
        match &self.grasps[g.index()] {
            Some(Holder::EndEffector(e)) => std::slice::from_ref(e),
            Some(Holder::Kind(kind)) => &self.of_kind[kind.index()],
            None => &[],
        }
    }
}
