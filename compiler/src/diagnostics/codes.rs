//! Codes of the compiler phases.

use cellc_lang::Code;

/// A name that is not declared.
pub const UNKNOWN_NAME: Code = Code("E0101");
/// A name declared twice.
pub const DUPLICATE_NAME: Code = Code("E0102");
/// A name of the wrong sort (a workspace where an end-effector is needed, ...).
pub const WRONG_SORT: Code = Code("E0103");
/// A second `world` item.
pub const SECOND_WORLD: Code = Code("E0104");
/// An object on two lines of the `world`.
pub const PLACED_TWICE: Code = Code("E0105");
/// A world line `HOLDER[.GRASP]` that says neither where the object is nor, for an
/// arm, which grasp holds it.
pub const WORLD_PLACEMENT_INCOMPLETE: Code = Code("E0106");
/// A `task` without steps.
pub const EMPTY_TASK: Code = Code("E0107");

/// A number without a unit where one is needed.
pub const MISSING_UNIT: Code = Code("E0201");
/// A unit of the wrong dimension (an angle where a length is needed, ...).
pub const WRONG_UNIT: Code = Code("E0202");
/// A quaternion that is not of unit length.
pub const NOT_A_ROTATION: Code = Code("E0203");
/// A size, radius or height that is not positive.
pub const NOT_POSITIVE: Code = Code("E0204");
/// A weight that is negative or not finite.
pub const BAD_WEIGHT: Code = Code("E0205");
/// A symmetry of order 0.
pub const BAD_SYMMETRY_ORDER: Code = Code("E0206");
/// A length (or angle) unit set twice in one file.
pub const CONFLICTING_UNITS: Code = Code("E0207");
/// A number too large to be finite (`1e999`).
pub const NOT_FINITE: Code = Code("E0208");
/// An arc weight set twice.
pub const WEIGHT_SET_TWICE: Code = Code("E0209");

/// A transition between two non-movable end-effectors.
pub const FIXED_TO_FIXED: Code = Code("E0301");
/// A grasp for a holder kind that no end-effector has.
pub const KIND_WITHOUT_HOLDER: Code = Code("E0302");
/// A transition between grasps of different objects.
pub const CROSS_OBJECT_TRANSITION: Code = Code("E0303");
/// A workspace no end-effector reaches.
pub const UNREACHED_WORKSPACE: Code = Code("E0304");
/// A declared adjacency that no movable end-effector can use.
pub const USELESS_ADJACENCY: Code = Code("E0305");
/// Two declared workspaces overlap.
pub const OVERLAPPING_WORKSPACES: Code = Code("E0306");
/// A file includes itself, directly or not.
pub const INCLUDE_CYCLE: Code = Code("E0307");
/// A cell or included file that can't be read.
pub const FILE_UNREADABLE: Code = Code("E0308");
/// A resting pose on a hand.
pub const REST_ON_HAND: Code = Code("E0309");
/// An `expect` requirement that does not hold.
pub const EXPECTATION_FAILED: Code = Code("E0310");
/// An included file that is a cell rather than a library.
pub const INCLUDED_CELL: Code = Code("E0311");
/// A movable end-effector of a geometric cell without any reach.
pub const NO_REACH: Code = Code("E0312");
/// A `reach` box for an end-effector that gets its reach otherwise.
pub const MISPLACED_REACH: Code = Code("E0313");
/// `adjacent w w`.
pub const SELF_ADJACENCY: Code = Code("E0314");
/// A geometric item (`workspace ... box`, derived workspaces) whose end-effectors
/// give no geometry to derive from, or `workspaces from reach` twice.
pub const DERIVATION_CONFLICT: Code = Code("E0315");
/// A grasp declared in a requirement for an end-effector that cannot hold it.
pub const PLACEMENT_GRASP_MISMATCH: Code = Code("E0316");
/// A cell, library or URDF larger than its size limit.
pub const FILE_TOO_LARGE: Code = Code("E0317");
/// A path that names a pipe, a device or a socket.
pub const NOT_A_REGULAR_FILE: Code = Code("E0318");
/// A file read as a cell or library that is not one (binary, or no cell outline).
pub const NOT_A_CELL_FILE: Code = Code("E0319");
/// Object-state graphs larger than the limit.
pub const GRAPH_TOO_LARGE: Code = Code("E0320");
/// `workspaces from reach` over more space cells than the limit.
pub const DERIVATION_TOO_LARGE: Code = Code("E0321");
/// `expect` requirements that would take too long to check.
pub const EXPECT_TOO_COSTLY: Code = Code("E0322");
/// A grasp or rest family that expands to no members.
pub const FAMILY_EMPTY: Code = Code("E0323");
/// A grasp or rest family of more members than the limit.
pub const FAMILY_TOO_LARGE: Code = Code("E0324");
/// `transition ... matching` between sides whose members do not pair up.
pub const FAMILY_MISMATCH: Code = Code("E0325");
/// A family named where one grasp or resting pose is needed.
pub const FAMILY_NOT_A_GRASP: Code = Code("E0326");
/// A grasp-set file with a row that is not a pose.
pub const BAD_GRASP_FILE: Code = Code("E0327");

/// A URDF (or SRDF) file that can't be read.
pub const URDF_UNREADABLE: Code = Code("E0401");
/// A URDF that urdf-rs cannot parse.
pub const URDF_INVALID: Code = Code("E0402");
/// A link or joint name not in the URDF.
pub const URDF_UNKNOWN_LINK: Code = Code("E0403");
/// No kinematic chain from the base link to the tip link.
pub const URDF_NO_CHAIN: Code = Code("E0404");
/// A home joint value outside the joint's limits.
pub const HOME_OUT_OF_LIMITS: Code = Code("E0405");
/// A URDF whose links and joints are not one tree.
pub const URDF_NOT_A_TREE: Code = Code("E0406");
/// A URDF number outside its domain (NaN, infinite, reversed or absurd).
pub const URDF_BAD_VALUE: Code = Code("E0407");
/// A `package://` file of a ROS package cellc cannot find.
pub const UNRESOLVED_PACKAGE: Code = Code("E0408");
/// A xacro file where a URDF is needed.
pub const XACRO_FILE: Code = Code("E0409");
/// An SRDF that does not parse or names what its URDF does not define.
pub const SRDF_INVALID: Code = Code("E0410");
/// A group or group state the robot's SRDF does not define.
pub const UNKNOWN_SRDF_NAME: Code = Code("E0411");
/// A robot item whose chain has no tip (none written, or a group that gives none).
pub const CHAIN_NOT_GIVEN: Code = Code("E0412");
/// A finger's prismatic joint on the chain between an arm's base and tip.
pub const FINGER_ON_CHAIN: Code = Code("E0422");
/// `reach auto` that cannot be computed, or finds nothing.
pub const REACH_AUTO_FAILED: Code = Code("E0423");

/// A transition declared one way only.
pub const ASYMMETRIC_TRANSITION: Code = Code("W0001");
/// A state that can never be entered, or never left.
pub const DEAD_END_STATE: Code = Code("W0002");
/// A grasp that is in no transition.
pub const UNUSED_GRASP: Code = Code("W0003");
/// A transition between two grasps of one end-effector.
pub const SAME_HOLDER_TRANSITION: Code = Code("W0004");
/// The same directed transition declared twice.
pub const DUPLICATE_TRANSITION: Code = Code("W0005");

/// Every code of the compiler.
pub const ALL: &[Code] = &[
    UNKNOWN_NAME,
    DUPLICATE_NAME,
    WRONG_SORT,
    SECOND_WORLD,
    PLACED_TWICE,
    WORLD_PLACEMENT_INCOMPLETE,
    EMPTY_TASK,
    MISSING_UNIT,
    WRONG_UNIT,
    NOT_A_ROTATION,
    NOT_POSITIVE,
    BAD_WEIGHT,
    BAD_SYMMETRY_ORDER,
    CONFLICTING_UNITS,
    NOT_FINITE,
    WEIGHT_SET_TWICE,
    FIXED_TO_FIXED,
    KIND_WITHOUT_HOLDER,
    CROSS_OBJECT_TRANSITION,
    UNREACHED_WORKSPACE,
    USELESS_ADJACENCY,
    OVERLAPPING_WORKSPACES,
    INCLUDE_CYCLE,
    FILE_UNREADABLE,
    REST_ON_HAND,
    EXPECTATION_FAILED,
    INCLUDED_CELL,
    NO_REACH,
    MISPLACED_REACH,
    SELF_ADJACENCY,
    DERIVATION_CONFLICT,
    PLACEMENT_GRASP_MISMATCH,
    FILE_TOO_LARGE,
    NOT_A_REGULAR_FILE,
    NOT_A_CELL_FILE,
    GRAPH_TOO_LARGE,
    DERIVATION_TOO_LARGE,
    EXPECT_TOO_COSTLY,
    FAMILY_EMPTY,
    FAMILY_TOO_LARGE,
    FAMILY_MISMATCH,
    FAMILY_NOT_A_GRASP,
    BAD_GRASP_FILE,
    URDF_UNREADABLE,
    URDF_INVALID,
    URDF_UNKNOWN_LINK,
    URDF_NO_CHAIN,
    HOME_OUT_OF_LIMITS,
    URDF_NOT_A_TREE,
    URDF_BAD_VALUE,
    UNRESOLVED_PACKAGE,
    XACRO_FILE,
    SRDF_INVALID,
    UNKNOWN_SRDF_NAME,
    CHAIN_NOT_GIVEN,
    FINGER_ON_CHAIN,
    REACH_AUTO_FAILED,
    ASYMMETRIC_TRANSITION,
    DEAD_END_STATE,
    UNUSED_GRASP,
    SAME_HOLDER_TRANSITION,
    DUPLICATE_TRANSITION,
];
