//! The registry of diagnostic codes: every code any crate reports, in one table.
//!
//! Each code is a constant here, in the module of the phase that reports it, with the
//! name it is known by in code and its documentation page (`docs/diagnostics/CODE.md`,
//! embedded when this crate is built, so a code without its page does not compile). A
//! [`Code`] cannot be made anywhere else: the compiler, the driver, the CLI, the service
//! and the language server all name codes through these constants, and `cellc explain`
//! looks text up with [`Code::find`]. The other crates' `codes` modules are aliases of
//! their phase's module here (`cellc_compiler::diagnostics::codes` is [`compile`]).
//!
//! To register a new code: write its page `docs/diagnostics/CODE.md` and its row in
//! `docs/diagnostics/README.md`, add `NAME = "CODE";` with a doc comment to its phase's
//! block below (the next free number of its series; numbers are never reused), and add a
//! UI test `tests/ui/**/CODE_what.*` that produces it. `tests/codes.rs` checks all four;
//! a code written twice fails to compile.
//!
//! Codes are grouped by series: E00xx syntax, E01xx names, E02xx units and values, E03xx
//! cell semantics, E04xx robot models, E05xx artifacts and outputs, E06xx import, R0xxx
//! planning and verification, S0xxx the service, W0xxx warnings.

use crate::diagnostic::{Code, CodeInfo};

/// Declares the phases' modules of constants and [`ALL`], and checks at compile time that
/// every code is well formed and written once.
macro_rules! registry {
    ($(
        $(#[doc = $phase_doc:literal])*
        $phase:ident {
            $( $(#[doc = $doc:literal])* $name:ident = $code:literal; )*
        }
    )*) => {
        $(
            $(#[doc = $phase_doc])*
            pub mod $phase {
                use super::{Code, CodeInfo};
                $(
                    $(#[doc = $doc])*
                    pub const $name: Code = Code::registered(&CodeInfo {
                        code: $code,
                        name: stringify!($name),
                        phase: stringify!($phase),
                        page: include_str!(concat!("../../docs/diagnostics/", $code, ".md")),
                    });
                )*
                /// Every code of this phase.
                pub const ALL: &[Code] = &[$($name),*];
            }
        )*
        /// Every registered code, phase by phase.
        pub const ALL: &[Code] = &[$($($phase::$name,)*)*];
    };
}

registry! {
    /// The syntax phase (`cellc_lang::parse`).
    parse {
        /// The text does not follow the grammar.
        SYNTAX = "E0001";
        /// Blocks nested deeper than any cell needs.
        TOO_DEEP = "E0002";
        /// A whole number too large to represent.
        INTEGER_TOO_LARGE = "E0003";
        /// A control character (other than tab and line breaks) in a cell file.
        CONTROL_CHARACTER = "E0004";
    }
    /// The compiler: names, units and values, cell semantics, robot models, graph warnings.
    compile {
        /// A name that is not declared.
        UNKNOWN_NAME = "E0101";
        /// A name declared twice.
        DUPLICATE_NAME = "E0102";
        /// A name of the wrong sort (a workspace where an end-effector is needed, ...).
        WRONG_SORT = "E0103";
        /// A second `world` item.
        SECOND_WORLD = "E0104";
        /// An object on two lines of the `world`.
        PLACED_TWICE = "E0105";
        /// A world line `HOLDER[.GRASP]` that says neither where the object is nor, for an
        /// arm, which grasp holds it.
        WORLD_PLACEMENT_INCOMPLETE = "E0106";
        /// A `task` without steps.
        EMPTY_TASK = "E0107";
        /// A number without a unit where one is needed.
        MISSING_UNIT = "E0201";
        /// A unit of the wrong dimension (an angle where a length is needed, ...).
        WRONG_UNIT = "E0202";
        /// A quaternion that is not of unit length.
        NOT_A_ROTATION = "E0203";
        /// A size, radius, height or joint limit that is not positive.
        NOT_POSITIVE = "E0204";
        /// A weight that is negative or not finite.
        BAD_WEIGHT = "E0205";
        /// A symmetry of order 0.
        BAD_SYMMETRY_ORDER = "E0206";
        /// A length (or angle) unit set twice in one file.
        CONFLICTING_UNITS = "E0207";
        /// A number too large to be finite (`1e999`).
        NOT_FINITE = "E0208";
        /// An arc weight set twice.
        WEIGHT_SET_TWICE = "E0209";
        /// A joint limit (or a robot's joint limits file) given twice at one level.
        LIMIT_SET_TWICE = "E0210";
        /// A transition between two non-movable end-effectors.
        FIXED_TO_FIXED = "E0301";
        /// A grasp for a holder kind that no end-effector has.
        KIND_WITHOUT_HOLDER = "E0302";
        /// A transition between grasps of different objects.
        CROSS_OBJECT_TRANSITION = "E0303";
        /// A workspace no end-effector reaches.
        UNREACHED_WORKSPACE = "E0304";
        /// A declared adjacency that no movable end-effector can use.
        USELESS_ADJACENCY = "E0305";
        /// Two declared workspaces overlap.
        OVERLAPPING_WORKSPACES = "E0306";
        /// A file includes itself, directly or not.
        INCLUDE_CYCLE = "E0307";
        /// A cell or included file that can't be read.
        FILE_UNREADABLE = "E0308";
        /// A resting pose on a hand.
        REST_ON_HAND = "E0309";
        /// An `expect` requirement that does not hold.
        EXPECTATION_FAILED = "E0310";
        /// An included file that is a cell rather than a library.
        INCLUDED_CELL = "E0311";
        /// A movable end-effector of a geometric cell without any reach.
        NO_REACH = "E0312";
        /// A `reach` box for an end-effector that gets its reach otherwise.
        MISPLACED_REACH = "E0313";
        /// `adjacent w w`.
        SELF_ADJACENCY = "E0314";
        /// A geometric item (`workspace ... box`, derived workspaces) whose end-effectors
        /// give no geometry to derive from, or `workspaces from reach` twice.
        DERIVATION_CONFLICT = "E0315";
        /// A grasp declared in a requirement for an end-effector that cannot hold it.
        PLACEMENT_GRASP_MISMATCH = "E0316";
        /// A cell, library or URDF larger than its size limit.
        FILE_TOO_LARGE = "E0317";
        /// A path that names a pipe, a device or a socket.
        NOT_A_REGULAR_FILE = "E0318";
        /// A file read as a cell or library that is not one (binary, or no cell outline).
        NOT_A_CELL_FILE = "E0319";
        /// Object-state graphs larger than the limit.
        GRAPH_TOO_LARGE = "E0320";
        /// `workspaces from reach` over more space cells than the limit.
        DERIVATION_TOO_LARGE = "E0321";
        /// `expect` requirements that would take too long to check.
        EXPECT_TOO_COSTLY = "E0322";
        /// A grasp or rest family that expands to no members.
        FAMILY_EMPTY = "E0323";
        /// A grasp or rest family of more members than the limit.
        FAMILY_TOO_LARGE = "E0324";
        /// `transition ... matching` between sides whose members do not pair up.
        FAMILY_MISMATCH = "E0325";
        /// A family named where one grasp or resting pose is needed.
        FAMILY_NOT_A_GRASP = "E0326";
        /// A grasp-set file with a row that is not a pose.
        BAD_GRASP_FILE = "E0327";
        /// A `joint_limits.yaml` that is not YAML of MoveIt's shape, or a bad value in it.
        BAD_LIMITS_FILE = "E0328";
        /// A URDF (or SRDF) file that can't be read.
        URDF_UNREADABLE = "E0401";
        /// A URDF that urdf-rs cannot parse.
        URDF_INVALID = "E0402";
        /// A link or joint name not in the URDF.
        URDF_UNKNOWN_LINK = "E0403";
        /// No kinematic chain from the base link to the tip link.
        URDF_NO_CHAIN = "E0404";
        /// A home joint value outside the joint's limits.
        HOME_OUT_OF_LIMITS = "E0405";
        /// A URDF whose links and joints are not one tree.
        URDF_NOT_A_TREE = "E0406";
        /// A URDF number outside its domain (NaN, infinite, reversed or absurd).
        URDF_BAD_VALUE = "E0407";
        /// A `package://` file of a ROS package cellc cannot find.
        UNRESOLVED_PACKAGE = "E0408";
        /// A xacro file where a URDF is needed.
        XACRO_FILE = "E0409";
        /// An SRDF that does not parse or names what its URDF does not define.
        SRDF_INVALID = "E0410";
        /// A group or group state the robot's SRDF does not define.
        UNKNOWN_SRDF_NAME = "E0411";
        /// A robot item whose chain has no tip (none written, or a group that gives none).
        CHAIN_NOT_GIVEN = "E0412";
        /// A finger's prismatic joint on the chain between an arm's base and tip.
        FINGER_ON_CHAIN = "E0422";
        /// `reach auto` that cannot be computed, or finds nothing.
        REACH_AUTO_FAILED = "E0423";
        /// A transition declared one way only.
        ASYMMETRIC_TRANSITION = "W0001";
        /// A state that can never be entered, or never left.
        DEAD_END_STATE = "W0002";
        /// A grasp that is in no transition.
        UNUSED_GRASP = "W0003";
        /// A transition between two grasps of one end-effector.
        SAME_HOLDER_TRANSITION = "W0004";
        /// The same directed transition declared twice.
        DUPLICATE_TRANSITION = "W0005";
        /// Joints timed with a default limit: no acceleration limit declared, or no usable
        /// velocity limit anywhere.
        MISSING_LIMITS = "W0007";
    }
    /// The preflight scene check of a geometric cell (`cellc_driver::scene_report`).
    scene {
        /// An arm's home configuration collides.
        HOME_COLLIDES = "E0420";
        /// A link touches a fixed body in every configuration tried.
        PERMANENT_CONTACT = "E0421";
        /// A grasp puts its object away from every solid of the hand, or inside one.
        GRASP_OFF_HAND = "W0010";
    }
    /// Verification and loading a scene (`cellc_driver::verify_report`).
    verify {
        /// An arc found kinematically infeasible and removed from the graph.
        PRUNED_ARC = "W0006";
        /// A URDF changed since the artifact was built.
        STALE_URDF = "R0001";
        /// A robot model or mesh cannot be loaded for kinematics.
        MODEL_UNUSABLE = "R0002";
    }
    /// Planning requests, worlds, executions and plan documents.
    request {
        /// The request names something the cell does not have, or a pose matches no state.
        LOCATE = "R0003";
        /// No plan reaches the goal.
        UNREACHABLE = "R0004";
        /// No request to plan: the cell declares none, or none of that name.
        NO_REQUEST = "R0005";
        /// The request's time budget ran out.
        TIME_BUDGET = "R0006";
        /// Executing a plan failed for good: before the object left its start, or too often.
        EXECUTION_FAILED = "R0007";
        /// A world document that cannot be read (not JSON of its shape, or too large).
        WORLD_DOCUMENT = "R0008";
        /// A world that names what the cell lacks, a joint out of limits, or a placement that
        /// matches no state.
        WORLD = "R0009";
        /// The goal is where another object of the world stands, or the object is absent.
        GOAL_OCCUPIED = "R0010";
        /// A plan document (`cellc view --plan FILE`) that cannot be read or does not fit the
        /// cell.
        PLAN_DOCUMENT = "R0011";
        /// A request's timing option out of range: a scaling not in (0, 1], a control
        /// rate not in (0, 1000] Hz, or a rate that would give a motion too many points.
        OPTION_OUT_OF_RANGE = "R0012";
    }
    /// Reading artifacts.
    artifact {
        /// The file is not a cellc artifact.
        NOT_AN_ARTIFACT = "E0501";
        /// The artifact is of another format version.
        WRONG_VERSION = "E0502";
        /// The artifact is truncated, corrupted or damaged (its checksum does not match).
        CORRUPT = "E0503";
        /// The artifact decodes and matches its checksum but is inconsistent.
        INVALID = "E0504";
    }
    /// Writing outputs, and `cellc explain`.
    output {
        /// An output file cannot be written.
        UNWRITABLE = "E0505";
        /// The output file is one of the command's inputs.
        OVERWRITES_INPUT = "E0506";
        /// `cellc explain` was asked about a code that does not exist.
        UNKNOWN_CODE = "E0507";
        /// `cellc run --fail-at N` names no step of the first plan executed (0, or past
        /// its last step).
        FAIL_AT_OUT_OF_RANGE = "E0509";
    }
    /// The PDDL export.
    export {
        /// Arc weights too large for whole-number PDDL costs.
        COSTS_TOO_LARGE = "E0508";
    }
    /// The import of DualManip databases.
    import {
        /// The file cannot be opened or read as an SQLite database.
        CANNOT_OPEN = "E0601";
        /// A table or column is missing, or a value has the wrong type.
        BAD_SCHEMA = "E0602";
        /// A row refers to an id that no row of the referred table has.
        UNKNOWN_ID = "E0603";
        /// A transition between grasps of two different objects.
        CROSS_OBJECT_TRANSITION = "E0604";
        /// Two rows of one table with the same id.
        DUPLICATE_ID = "E0605";
        /// An end-effector whose `Movable` is neither 0 nor 1.
        BAD_MOVABLE = "E0606";
        /// A transition between grasps of two fixed end-effectors.
        FIXED_TO_FIXED = "E0607";
        /// A workspace no end-effector reaches, or an end-effector that reaches nothing.
        REACH_GAP = "E0608";
        /// Adjacency rows a cell cannot keep as they are.
        BAD_ADJACENCY = "E0609";
    }
    /// The service: requests it cannot take.
    serve {
        /// The body is not what the endpoint takes (not JSON, wrong fields or types).
        BAD_BODY = "S0001";
        /// The body is larger than the endpoint accepts.
        TOO_LARGE = "S0002";
        /// No endpoint has this path, or not with this method.
        NO_ENDPOINT = "S0003";
        /// The request took longer than the service gives one.
        TIMED_OUT = "S0004";
        /// The service failed on this request (a bug): the request may be sent again.
        INTERNAL = "S0005";
        /// A write or execution whose precondition (`If-Match`, `"revision"`) names a
        /// world revision the world has moved on from, or another store's.
        PRECONDITION_FAILED = "S0006";
        /// An interrupted execution left objects or arms uncertain: planning waits until a
        /// client confirms where they are.
        WORLD_UNCERTAIN = "S0007";
        /// An `Idempotency-Key` already used for a different request.
        KEY_REUSED = "S0008";
        /// A header the service reads (`If-Match`, `Idempotency-Key`) is malformed.
        BAD_HEADER = "S0009";
        /// The state file cannot take a write (disk full, read-only, damaged): nothing of
        /// the request was stored or done.
        STATE_WRITE = "S0010";
        /// The state file cannot be used at all: another process has it, it is not a
        /// cellc state file, a newer cellc wrote it, or its world does not fit the cell.
        STATE_OPEN = "S0011";
        /// The execution an `Idempotency-Key` names was interrupted by a stop of the
        /// service: it is not run again under that key.
        INTERRUPTED = "S0012";
        /// No journaled execution has that number (never, or pruned by retention).
        UNKNOWN_EXECUTION = "S0013";
    }

}

/// Two codes with the same text, or a code not of the form letter and four digits, stop
/// the build here.
const _: () = {
    let mut i = 0;
    while i < ALL.len() {
        assert!(
            well_formed(ALL[i].as_str().as_bytes()),
            "a code is not LETTER + 4 digits"
        );
        let mut j = i + 1;
        while j < ALL.len() {
            assert!(
                !same(ALL[i].as_str().as_bytes(), ALL[j].as_str().as_bytes()),
                "a code is registered twice"
            );
            j += 1;
        }
        i += 1;
    }
};

/// `E`, `R`, `S` or `W` and four digits.
const fn well_formed(code: &[u8]) -> bool {
    if code.len() != 5 || !matches!(code[0], b'E' | b'R' | b'S' | b'W') {
        return false;
    }
    let mut i = 1;
    while i < 5 {
        if !code[i].is_ascii_digit() {
            return false;
        }
        i += 1;
    }
    true
}

/// Byte equality, which `const fn` cannot spell `==` yet.
const fn same(a: &[u8], b: &[u8]) -> bool {
    if a.len() != b.len() {
        return false;
    }
    let mut i = 0;
    while i < a.len() {
        if a[i] != b[i] {
            return false;
        }
        i += 1;
    }
    true
}
