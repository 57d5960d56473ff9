//! The syntax tree: what the user wrote, with a span on every node.
//!
//! The tree is deliberately close to the text (numbers keep their spelling, units are
//! kept as written) so that the formatter can print it back without changing meaning, and
//! so that diagnostics can point at exactly what the user typed. Meaning (units applied,
//! names resolved) is the compiler's business.
//!
//! This file has the file and its items; `values.rs` what they are written with (names,
//! quantities, vectors, poses, boxes, strings, shapes); `object.rs` an object's block and
//! its members; `world.rs` the `world` and `task` items.

use crate::span::Span;

mod object;
mod values;
mod world;
pub use object::*;
pub use values::*;
pub use world::*;

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
    /// `limits ROBOT[.JOINT] [from "FILE"] [velocity V] [acceleration A] [jerk J]`.
    Limits(LimitsItem),
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
            Item::Limits(i) => i.span,
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

/// `limits ROBOT [from "FILE"] LIMIT*` or `limits ROBOT.JOINT LIMIT+`: the velocity,
/// acceleration and jerk limits of a robot's joints. A robot's line holds for every joint
/// of its chain; a joint's own line wins over it, the cell's lines over the file, the file
/// over the URDF.
#[derive(Clone, Debug, PartialEq)]
pub struct LimitsItem {
    /// The robot (`object` empty) or `ROBOT.JOINT` (the robot in `object`, the joint in
    /// `name`).
    pub target: Qualified,
    /// `from "FILE"`: a MoveIt `joint_limits.yaml` (robot lines only).
    pub file: Option<StringLit>,
    /// The limits written, in source order.
    pub values: Vec<LimitValue>,
    /// Whole item.
    pub span: Span,
}

impl LimitsItem {
    /// The robot's name as written.
    pub fn robot(&self) -> &Name {
        self.target.object.as_ref().unwrap_or(&self.target.name)
    }

    /// The joint's name, for a joint's line.
    pub fn joint(&self) -> Option<&Name> {
        self.target.object.as_ref().map(|_| &self.target.name)
    }
}

/// Which limit a value sets.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum LimitKind {
    /// Speed (`/s`).
    Velocity,
    /// Acceleration (`/s2`).
    Acceleration,
    /// Jerk (`/s3`).
    Jerk,
}

impl LimitKind {
    /// Every kind, in the order they are written.
    pub const ALL: [LimitKind; 3] = [
        LimitKind::Velocity,
        LimitKind::Acceleration,
        LimitKind::Jerk,
    ];

    /// As written in the language.
    pub fn as_str(self) -> &'static str {
        match self {
            LimitKind::Velocity => "velocity",
            LimitKind::Acceleration => "acceleration",
            LimitKind::Jerk => "jerk",
        }
    }

    /// The power of the second in its unit (`rad/s2` for an acceleration).
    pub fn order(self) -> u8 {
        match self {
            LimitKind::Velocity => 1,
            LimitKind::Acceleration => 2,
            LimitKind::Jerk => 3,
        }
    }
}

/// `acceleration 4 rad/s2`.
#[derive(Clone, Debug, PartialEq)]
pub struct LimitValue {
    /// Which limit.
    pub kind: LimitKind,
    /// Its value as written.
    pub rate: Rate,
    /// The pair.
    pub span: Span,
}
