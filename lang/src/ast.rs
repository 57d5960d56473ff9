//! The syntax tree: what the user wrote, with a span on every node.
//!
//! The tree is deliberately close to the text (numbers keep their spelling, units are
//! kept as written) so that the formatter can print it back without changing meaning, and
//! so that diagnostics can point at exactly what the user typed. Meaning (units applied,
//! names resolved) is the compiler's business.

use crate::span::Span;

mod world;
pub use world::*;

/// A name as written: plain (`left_arm`) or quoted (`` `top_x- (copy)` ``).
#[derive(Clone, Debug, PartialEq)]
pub struct Name {
    /// The name without quotes.
    pub text: String,
    /// Span of the name including quotes.
    pub span: Span,
}

impl Name {
    /// True when the name must be quoted to be written back (it is not a plain
    /// identifier).
    pub fn needs_quotes(&self) -> bool {
        needs_quotes(&self.text)
    }
}

/// True when `text` is not a plain identifier (`[A-Za-z_][A-Za-z0-9_]*`).
pub fn needs_quotes(text: &str) -> bool {
    let mut chars = text.chars();
    match chars.next() {
        Some(c) if c.is_ascii_alphabetic() || c == '_' => {}
        _ => return true,
    }
    !chars.all(|c| c.is_ascii_alphanumeric() || c == '_')
}

/// `name` or `object.name` (a grasp of another object, in transitions).
#[derive(Clone, Debug, PartialEq)]
pub struct Qualified {
    /// The object part, when written.
    pub object: Option<Name>,
    /// The last part.
    pub name: Name,
    /// The whole reference.
    pub span: Span,
}

/// A unit of measure written after a number.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Unit {
    /// Metres.
    M,
    /// Centimetres.
    Cm,
    /// Millimetres.
    Mm,
    /// Degrees.
    Deg,
    /// Radians.
    Rad,
}

impl Unit {
    /// As written in the language.
    pub fn as_str(self) -> &'static str {
        match self {
            Unit::M => "m",
            Unit::Cm => "cm",
            Unit::Mm => "mm",
            Unit::Deg => "deg",
            Unit::Rad => "rad",
        }
    }

    /// True for length units.
    pub fn is_length(self) -> bool {
        matches!(self, Unit::M | Unit::Cm | Unit::Mm)
    }

    /// Factor to SI (metres or radians).
    pub fn to_si(self) -> f64 {
        match self {
            Unit::M | Unit::Rad => 1.0,
            Unit::Cm => 0.01,
            Unit::Mm => 0.001,
            Unit::Deg => std::f64::consts::PI / 180.0,
        }
    }

    /// Parses a unit as written.
    pub fn parse(text: &str) -> Option<Unit> {
        Some(match text {
            "m" => Unit::M,
            "cm" => Unit::Cm,
            "mm" => Unit::Mm,
            "deg" => Unit::Deg,
            "rad" => Unit::Rad,
            _ => return None,
        })
    }
}

/// A number with an optional unit, e.g. `0.6`, `600 mm`, `-90 deg`.
#[derive(Clone, Debug, PartialEq)]
pub struct Quantity {
    /// The number as written (kept so formatting never changes a value's spelling).
    pub number: String,
    /// The parsed value.
    pub value: f64,
    /// The unit, if one was written.
    pub unit: Option<Unit>,
    /// Span of number and unit.
    pub span: Span,
}

/// `(x, y, z)`.
#[derive(Clone, Debug, PartialEq)]
pub struct Vec3 {
    /// The three components.
    pub parts: [Quantity; 3],
    /// Span including parentheses.
    pub span: Span,
}

/// A rotation as written.
#[derive(Clone, Debug, PartialEq)]
pub enum Rotation {
    /// `rpy (roll, pitch, yaw)`: fixed-axis X, then Y, then Z.
    Rpy(Vec3, Span),
    /// `quat (w, x, y, z)`.
    Quat([Quantity; 4], Span),
}

impl Rotation {
    /// Span of the whole rotation clause.
    pub fn span(&self) -> Span {
        match self {
            Rotation::Rpy(_, s) | Rotation::Quat(_, s) => *s,
        }
    }
}

/// `at (x, y, z) [rpy (...) | quat (...)]`.
#[derive(Clone, Debug, PartialEq)]
pub struct Pose {
    /// Translation.
    pub at: Vec3,
    /// Rotation, identity when absent.
    pub rotation: Option<Rotation>,
    /// Whole pose.
    pub span: Span,
}

/// `box center (x, y, z) size (dx, dy, dz)`: an axis-aligned cuboid.
#[derive(Clone, Debug, PartialEq)]
pub struct Aabb {
    /// Centre.
    pub center: Vec3,
    /// Edge lengths.
    pub size: Vec3,
    /// Whole clause.
    pub span: Span,
}

/// A whole file: `cell NAME { ... }` or `library NAME { ... }`.
#[derive(Clone, Debug, PartialEq)]
pub struct File {
    /// Cell or library.
    pub kind: FileKind,
    /// Its name.
    pub name: Name,
    /// Items in source order.
    pub items: Vec<Item>,
    /// Whole file.
    pub span: Span,
}

/// What a file declares itself to be.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FileKind {
    /// A cell: the thing `cellc check` and `cellc build` compile.
    Cell,
    /// A library, meant to be included by cells.
    Library,
}

/// One top-level item.
// Items are built once per parse and walked a few times; boxing the large variants would
// cost more readability than the memory it saves.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Debug, PartialEq)]
pub enum Item {
    /// `units m, deg`.
    Units(UnitsItem),
    /// `weights move 0.1, transition 1.0`.
    Weights(WeightsItem),
    /// `include "path"`.
    Include(IncludeItem),
    /// `package NAME at "dir"`.
    Package(PackageItem),
    /// `workspaces from reach`.
    WorkspacesFromReach(Span),
    /// `workspace w1 "Left" [box ...]*`.
    Workspace(WorkspaceItem),
    /// `adjacent w1 w2`.
    Adjacent(AdjacentItem),
    /// `fixed table reaches w1, w2` or `movable arm reaches w1`.
    EndEffector(EndEffectorItem),
    /// `hand softhand [{ solids }]`.
    Hand(HandItem),
    /// `support tabletop`.
    Support(SupportItem),
    /// `robot lwr4 urdf "path" [base LINK] tip LINK`.
    Robot(RobotItem),
    /// `arm left = lwr4 at (...) with softhand`.
    Arm(ArmItem),
    /// `surface table : tabletop box center (...) size (...)`.
    Surface(SurfaceItem),
    /// `reach left box center (...) size (...)`.
    Reach(ReachItem),
    /// `object cylinder { ... }`.
    Object(ObjectItem),
    /// `expect ...`.
    Expect(ExpectItem),
    /// `allow contact A B`.
    Allow(AllowItem),
    /// `request NAME: OBJECT from PLACEMENT to PLACEMENT`.
    Request(RequestItem),
    /// `obstacle NAME box center (...) size (...)`.
    Obstacle(ObstacleItem),
    /// `world { OBJECT: PLACEMENT ... }`.
    World(WorldItem),
    /// `task NAME { OBJECT to PLACEMENT ... }`.
    Task(TaskItem),
}

impl Item {
    /// Span of the whole item.
    pub fn span(&self) -> Span {
        match self {
            Item::Units(i) => i.span,
            Item::Weights(i) => i.span,
            Item::Include(i) => i.span,
            Item::Package(i) => i.span,
            Item::WorkspacesFromReach(s) => *s,
            Item::Workspace(i) => i.span,
            Item::Adjacent(i) => i.span,
            Item::EndEffector(i) => i.span,
            Item::Hand(i) => i.span,
            Item::Support(i) => i.span,
            Item::Robot(i) => i.span,
            Item::Arm(i) => i.span,
            Item::Surface(i) => i.span,
            Item::Reach(i) => i.span,
            Item::Object(i) => i.span,
            Item::Expect(i) => i.span,
            Item::Allow(i) => i.span,
            Item::Request(i) => i.span,
            Item::Obstacle(i) => i.span,
            Item::World(i) => i.span,
            Item::Task(i) => i.span,
        }
    }
}

/// `units m, deg`: the units of bare numbers in this file.
#[derive(Clone, Debug, PartialEq)]
pub struct UnitsItem {
    /// Units as written, with their spans.
    pub units: Vec<(Unit, Span)>,
    /// Whole item.
    pub span: Span,
}

/// Which arc kind a weight applies to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ArcKind {
    /// Same grasp, adjacent workspace.
    Move,
    /// Grasp change inside one workspace.
    Transition,
}

/// `weights move 0.1, transition 1.0`.
#[derive(Clone, Debug, PartialEq)]
pub struct WeightsItem {
    /// Arc kind, number as written, value, span of the pair.
    pub weights: Vec<Weight>,
    /// Whole item.
    pub span: Span,
}

/// One `move 0.1` pair.
#[derive(Clone, Debug, PartialEq)]
pub struct Weight {
    /// Arc kind.
    pub kind: ArcKind,
    /// The number as written.
    pub number: String,
    /// Its value.
    pub value: f64,
    /// The pair.
    pub span: Span,
}

/// `include "path"`.
#[derive(Clone, Debug, PartialEq)]
pub struct IncludeItem {
    /// The path, relative to the including file.
    pub path: StringLit,
    /// Whole item.
    pub span: Span,
}

/// `package NAME at "dir"`: the folder of the ROS package `NAME`, relative to the
/// declaring file, where `package://NAME/...` paths are looked up first.
#[derive(Clone, Debug, PartialEq)]
pub struct PackageItem {
    /// The package name (ROS names may hold `-` and `.`, so this is not a [`Name`]).
    pub name: Name,
    /// The package's folder, relative to the declaring file.
    pub dir: StringLit,
    /// Whole item.
    pub span: Span,
}

/// A string literal: its value (escapes applied) and span (with quotes).
#[derive(Clone, Debug, PartialEq)]
pub struct StringLit {
    /// Value.
    pub value: String,
    /// Span including quotes.
    pub span: Span,
}

/// `workspace NAME ["label"] [box ...]*`.
#[derive(Clone, Debug, PartialEq)]
pub struct WorkspaceItem {
    /// Name.
    pub name: Name,
    /// Human label.
    pub label: Option<StringLit>,
    /// Geometry, in geometric cells.
    pub boxes: Vec<Aabb>,
    /// Whole item.
    pub span: Span,
}

/// `adjacent A B`.
#[derive(Clone, Debug, PartialEq)]
pub struct AdjacentItem {
    /// First workspace.
    pub a: Name,
    /// Second workspace.
    pub b: Name,
    /// Whole item.
    pub span: Span,
}

/// Movable or not.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Mobility {
    /// A fixed surface.
    Fixed,
    /// A hand at the tip of a kinematic chain.
    Movable,
}

/// `fixed NAME reaches ...` / `movable NAME reaches ...` (abstract end-effectors).
#[derive(Clone, Debug, PartialEq)]
pub struct EndEffectorItem {
    /// Fixed or movable.
    pub mobility: Mobility,
    /// Name.
    pub name: Name,
    /// Workspaces reached.
    pub reaches: Vec<Name>,
    /// Whole item.
    pub span: Span,
}

/// `hand NAME [{ solids }]`: a hand kind.
#[derive(Clone, Debug, PartialEq)]
pub struct HandItem {
    /// Name.
    pub name: Name,
    /// Collision shapes in the hand's frame.
    pub solids: Vec<Solid>,
    /// Whole item.
    pub span: Span,
}

/// `support NAME`: a kind of resting surface.
#[derive(Clone, Debug, PartialEq)]
pub struct SupportItem {
    /// Name.
    pub name: Name,
    /// Whole item.
    pub span: Span,
}

/// `robot NAME urdf "path" [srdf "path"] [group GROUP] [base LINK] [tip LINK]`.
#[derive(Clone, Debug, PartialEq)]
pub struct RobotItem {
    /// Name of the robot model.
    pub name: Name,
    /// URDF path relative to the declaring file (or a `package://` or `file://` URI).
    pub urdf: StringLit,
    /// MoveIt SRDF of the robot, written like the URDF's path.
    pub srdf: Option<StringLit>,
    /// SRDF planning group whose chain gives the base and tip not written here.
    pub group: Option<Name>,
    /// Base link of the chain (the group's, else the URDF root, when absent).
    pub base: Option<Name>,
    /// Tip link, where the hand is mounted (the group's when absent).
    pub tip: Option<Name>,
    /// Whole item.
    pub span: Span,
}

/// `arm NAME = ROBOT at POSE with KIND`.
#[derive(Clone, Debug, PartialEq)]
pub struct ArmItem {
    /// End-effector name.
    pub name: Name,
    /// Robot model.
    pub robot: Name,
    /// Pose of the robot's base in the cell.
    pub pose: Pose,
    /// Holder kind mounted at the tip.
    pub kind: Name,
    /// Joint values of the arm's home configuration (joints not named stay at zero).
    pub home: Vec<JointValue>,
    /// `home NAME`: the home is the SRDF group state of that name (then `home` is empty).
    pub home_state: Option<Name>,
    /// Whole item.
    pub span: Span,
}

/// `joint_2 30 deg` in a `home (...)` clause.
#[derive(Clone, Debug, PartialEq)]
pub struct JointValue {
    /// URDF joint name.
    pub joint: Name,
    /// Angle (revolute joints) or length (prismatic joints).
    pub value: Quantity,
    /// The pair.
    pub span: Span,
}

/// `surface NAME : KIND box center (...) size (...) [reach height H]`.
#[derive(Clone, Debug, PartialEq)]
pub struct SurfaceItem {
    /// End-effector name.
    pub name: Name,
    /// Support kind.
    pub kind: Name,
    /// The solid slab; objects rest on its top face.
    pub slab: Aabb,
    /// Height of the reach extrusion above the top face.
    pub reach_height: Option<Quantity>,
    /// Whole item.
    pub span: Span,
}

/// `allow contact A B`: two bodies that may touch without it counting as a collision.
/// A body is an end-effector (`left`: the whole arm and its hand), a link or hand of an
/// arm (`left.lwr_link_7`, `left.softhand`), a surface or an object.
#[derive(Clone, Debug, PartialEq)]
pub struct AllowItem {
    /// One body.
    pub a: Qualified,
    /// The other.
    pub b: Qualified,
    /// Whole item.
    pub span: Span,
}

/// `request NAME: OBJECT from PLACEMENT to PLACEMENT`: an example move request, planned by
/// `cellc plan CELL` (the first one when none is named).
#[derive(Clone, Debug, PartialEq)]
pub struct RequestItem {
    /// Request name.
    pub name: Name,
    /// The object.
    pub object: Name,
    /// Where it is.
    pub from: RequestPlacement,
    /// Where it must go.
    pub to: RequestPlacement,
    /// Whole item.
    pub span: Span,
}

/// `HOLDER[.GRASP] in WORKSPACE` or `HOLDER[.GRASP] at (x, y, z) [rotation]`.
#[derive(Clone, Debug, PartialEq)]
pub struct RequestPlacement {
    /// End-effector, optionally with a grasp.
    pub holder: Qualified,
    /// Where.
    pub place: PlaceSpec,
    /// Whole placement.
    pub span: Span,
}

/// The second half of a request placement.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Debug, PartialEq)]
pub enum PlaceSpec {
    /// Somewhere in a workspace.
    In(Name),
    /// Exactly at an object pose.
    At(Pose),
}

/// `obstacle NAME box center (...) size (...)`: a fixed solid that holds nothing (a shelf
/// board, a wall, a robot's torso); arms and objects must not collide with it.
#[derive(Clone, Debug, PartialEq)]
pub struct ObstacleItem {
    /// Name.
    pub name: Name,
    /// The solid.
    pub aabb: Aabb,
    /// Whole item.
    pub span: Span,
}

/// `reach NAME box center (...) size (...)` or `reach NAME auto`.
#[derive(Clone, Debug, PartialEq)]
pub struct ReachItem {
    /// End-effector.
    pub end_effector: Name,
    /// The box written, or `auto`.
    pub extent: ReachExtent,
    /// Whole item.
    pub span: Span,
}

/// What a `reach` line gives.
// As for `Item`: a box written is the common case, boxing it buys nothing.
#[derive(Clone, Debug, PartialEq)]
#[allow(clippy::large_enum_variant)]
pub enum ReachExtent {
    /// A box, as written.
    Box(Aabb),
    /// `auto`: boxes computed from the arm's kinematics and its grasps (the span of the
    /// word).
    Auto(Span),
}

/// `object NAME { members }`.
#[derive(Clone, Debug, PartialEq)]
pub struct ObjectItem {
    /// Name.
    pub name: Name,
    /// Members in source order.
    pub members: Vec<ObjectMember>,
    /// Whole item.
    pub span: Span,
}

/// One line inside an object block.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Debug, PartialEq)]
pub enum ObjectMember {
    /// `shape ...`.
    Shape(ShapeMember),
    /// `symmetry about z [order N]`.
    Symmetry(SymmetryMember),
    /// `grasp NAME ["label"] by HOLDER [at POSE]` or `rest NAME ["label"] on HOLDER [at POSE]`.
    Grasp(GraspMember),
    /// `transition A <-> B, C`.
    Transition(TransitionMember),
}

impl ObjectMember {
    /// Span of the member.
    pub fn span(&self) -> Span {
        match self {
            ObjectMember::Shape(m) => m.span,
            ObjectMember::Symmetry(m) => m.span,
            ObjectMember::Grasp(m) => m.span,
            ObjectMember::Transition(m) => m.span,
        }
    }
}

/// A primitive or mesh shape.
#[derive(Clone, Debug, PartialEq)]
pub enum Shape {
    /// `box size (dx, dy, dz)`, centred on the frame.
    Box {
        /// Edge lengths.
        size: Vec3,
    },
    /// `cylinder radius R height H`, axis along z, centred on the frame.
    Cylinder {
        /// Radius.
        radius: Quantity,
        /// Height.
        height: Quantity,
    },
    /// `sphere radius R`.
    Sphere {
        /// Radius.
        radius: Quantity,
    },
    /// `mesh "file.stl"`.
    Mesh {
        /// Path relative to the declaring file.
        path: StringLit,
    },
}

/// `shape SHAPE`.
#[derive(Clone, Debug, PartialEq)]
pub struct ShapeMember {
    /// The shape.
    pub shape: Shape,
    /// Whole member.
    pub span: Span,
}

/// A shape placed in a frame (hand collision bodies).
#[derive(Clone, Debug, PartialEq)]
pub struct Solid {
    /// The shape.
    pub shape: Shape,
    /// Where, in the parent frame (identity when absent).
    pub pose: Option<Pose>,
    /// Whole solid.
    pub span: Span,
}

/// A coordinate axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Axis {
    /// x.
    X,
    /// y.
    Y,
    /// z.
    Z,
}

impl Axis {
    /// As written.
    pub fn as_str(self) -> &'static str {
        match self {
            Axis::X => "x",
            Axis::Y => "y",
            Axis::Z => "z",
        }
    }
}

/// `symmetry about AXIS [order N]`: the object looks the same after any rotation about
/// the axis (no order) or after rotations by 360°/N.
#[derive(Clone, Debug, PartialEq)]
pub struct SymmetryMember {
    /// Axis in the object frame.
    pub axis: Axis,
    /// Discrete order, `None` for continuous symmetry.
    pub order: Option<(u32, Span)>,
    /// Whole member.
    pub span: Span,
}

/// Which keyword introduced a grasp.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GraspKeyword {
    /// `grasp NAME by HOLDER`.
    Grasp,
    /// `rest NAME on HOLDER`: a resting pose on a surface.
    Rest,
}

/// A grasp or resting pose.
#[derive(Clone, Debug, PartialEq)]
pub struct GraspMember {
    /// `grasp` or `rest`.
    pub keyword: GraspKeyword,
    /// Name, unique in the object.
    pub name: Name,
    /// Human label.
    pub label: Option<StringLit>,
    /// End-effector (abstract cells) or holder kind (geometric cells).
    pub holder: Name,
    /// Pose of the object in the holder's frame.
    pub pose: Option<Pose>,
    /// Whole member.
    pub span: Span,
}

/// `<->` or `->`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Direction {
    /// Both ways.
    Both,
    /// From the left grasp to each right grasp only.
    OneWay,
}

/// `transition A <-> B, C`.
#[derive(Clone, Debug, PartialEq)]
pub struct TransitionMember {
    /// Left side.
    pub from: Qualified,
    /// Arrow.
    pub direction: Direction,
    /// Right side.
    pub to: Vec<Qualified>,
    /// Whole member.
    pub span: Span,
}

/// `expect ...`: a requirement the cell states about itself.
#[derive(Clone, Debug, PartialEq)]
pub struct ExpectItem {
    /// What is required.
    pub requirement: Requirement,
    /// Whole item.
    pub span: Span,
}

/// Kinds of requirement.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Debug, PartialEq)]
pub enum Requirement {
    /// `expect OBJECT: HOLDER[.GRASP] in WS -> HOLDER[.GRASP] in WS`.
    Reach {
        /// The object.
        object: Name,
        /// Start placement.
        from: Placement,
        /// Goal placement.
        to: Placement,
    },
    /// `expect WS reached by at least N [movable|fixed]`.
    Coverage {
        /// The workspace.
        workspace: Name,
        /// Minimum count.
        at_least: (u32, Span),
        /// Count only this kind of end-effector.
        mobility: Option<Mobility>,
    },
    /// `expect no isolated states [for OBJECT]`.
    NoIsolatedStates {
        /// Limit to one object.
        object: Option<Name>,
    },
}

/// `HOLDER[.GRASP] in WORKSPACE`.
#[derive(Clone, Debug, PartialEq)]
pub struct Placement {
    /// End-effector, optionally with a grasp.
    pub holder: Qualified,
    /// Workspace.
    pub workspace: Name,
    /// Whole placement.
    pub span: Span,
}
