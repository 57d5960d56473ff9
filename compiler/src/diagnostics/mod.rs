//! Every diagnostic the compiler produces, one named constructor per problem.
//!
//! Keeping them here (rather than formatting messages at each check) keeps wording
//! consistent and makes the list of codes easy to audit against `docs/diagnostics/`.

use cellc_lang::{Code, Diagnostic, FileId, Span};
use cellc_schema::FileError;
use cellc_urdf::ParseError;

use crate::model::Origin;

mod kinematics;
mod robots;
mod trust;
pub use kinematics::*;
pub use robots::*;
mod world;
pub use trust::*;
pub use world::*;

/// Codes of the compiler phases.
pub mod codes {
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
}

use codes::*;

/// The sorts of thing a name can denote, for messages.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sort {
    /// A workspace.
    Workspace,
    /// An end-effector.
    EndEffector,
    /// A hand kind or support kind.
    HolderKind,
    /// A robot model.
    Robot,
    /// An object.
    Object,
    /// A grasp or resting pose.
    Grasp,
    /// An obstacle.
    Obstacle,
    /// A named request.
    Request,
    /// A named task.
    Task,
}

impl Sort {
    /// With an article, for messages.
    pub fn describe(self) -> &'static str {
        match self {
            Sort::Workspace => "a workspace",
            Sort::EndEffector => "an end-effector",
            Sort::HolderKind => "a hand or support kind",
            Sort::Robot => "a robot model",
            Sort::Object => "an object",
            Sort::Grasp => "a grasp",
            Sort::Obstacle => "an obstacle",
            Sort::Request => "a request",
            Sort::Task => "a task",
        }
    }

    /// Bare noun.
    pub fn noun(self) -> &'static str {
        match self {
            Sort::Workspace => "workspace",
            Sort::EndEffector => "end-effector",
            Sort::HolderKind => "holder kind",
            Sort::Robot => "robot",
            Sort::Object => "object",
            Sort::Grasp => "grasp",
            Sort::Obstacle => "obstacle",
            Sort::Request => "request",
            Sort::Task => "task",
        }
    }
}

/// A name that is declared nowhere.
pub fn unknown_name(
    sort: Sort,
    name: &str,
    file: FileId,
    span: Span,
    suggestion: Option<&str>,
    context: &str,
) -> Diagnostic {
    let help = match suggestion {
        Some(s) => format!("did you mean `{s}`?"),
        None => format!("declare {} named `{name}`{context}", sort.describe()),
    };
    Diagnostic::error(UNKNOWN_NAME, format!("unknown {} `{name}`", sort.noun()))
        .primary(file, span, format!("no {} is called `{name}`", sort.noun()))
        .help(help)
}

/// The same name declared twice in one namespace.
pub fn duplicate_name(sort: Sort, name: &str, first: Origin, again: Origin) -> Diagnostic {
    Diagnostic::error(DUPLICATE_NAME, format!("`{name}` is declared twice"))
        .primary(
            again.file,
            again.name_span,
            format!("{} `{name}` declared again here", sort.noun()),
        )
        .secondary(first.file, first.name_span, "first declared here")
        .help(format!(
            "rename one of them or remove the second declaration of `{name}`"
        ))
}

/// A name of the wrong sort.
pub fn wrong_sort(
    name: &str,
    wanted: Sort,
    found: Sort,
    file: FileId,
    span: Span,
    declared: Origin,
) -> Diagnostic {
    Diagnostic::error(
        WRONG_SORT,
        format!(
            "`{name}` is {}, not {}",
            found.describe(),
            wanted.describe()
        ),
    )
    .primary(file, span, format!("{} is needed here", wanted.describe()))
    .secondary(
        declared.file,
        declared.name_span,
        format!("`{name}` is declared as {} here", found.describe()),
    )
    .help(format!("name {} here", wanted.describe()))
}

/// What a quantity should measure.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dimension {
    /// Metres.
    Length,
    /// Radians.
    Angle,
    /// A pure number (quaternion components).
    Number,
}

impl Dimension {
    fn describe(self) -> &'static str {
        match self {
            Dimension::Length => "a length",
            Dimension::Angle => "an angle",
            Dimension::Number => "a plain number",
        }
    }
}

/// A bare number where a unit is needed and the file declares no default.
pub fn missing_unit(dimension: Dimension, file: FileId, span: Span) -> Diagnostic {
    let (example, units) = match dimension {
        Dimension::Angle => ("90 deg", "units m, deg"),
        _ => ("0.5 m", "units m, deg"),
    };
    Diagnostic::error(
        MISSING_UNIT,
        format!("{} without a unit", dimension.describe()),
    )
    .primary(file, span, "which unit is this in?")
    .help(format!(
        "write the unit (`{example}`) or declare `{units}` at the top of the file"
    ))
}

/// A unit of the wrong dimension.
pub fn wrong_unit(dimension: Dimension, unit: &str, file: FileId, span: Span) -> Diagnostic {
    let fix = match dimension {
        Dimension::Length => "use `m`, `cm` or `mm`",
        Dimension::Angle => "use `deg` or `rad`",
        Dimension::Number => "remove the unit",
    };
    Diagnostic::error(
        WRONG_UNIT,
        format!("expected {}, found `{unit}`", dimension.describe()),
    )
    .primary(
        file,
        span,
        format!("`{unit}` is not {}", dimension.describe()),
    )
    .help(fix)
}

/// A quaternion of non-unit length.
pub fn not_a_rotation(norm: f64, file: FileId, span: Span) -> Diagnostic {
    Diagnostic::error(NOT_A_ROTATION, "this quaternion is not a rotation")
        .primary(
            file,
            span,
            format!("its length is {norm:.4}, a rotation's is 1"),
        )
        .help("normalise the quaternion (divide each part by its length), or use `rpy (r, p, y)`")
}

/// A non-positive size.
pub fn not_positive(what: &str, value: f64, file: FileId, span: Span) -> Diagnostic {
    Diagnostic::error(NOT_POSITIVE, format!("{what} must be positive"))
        .primary(file, span, format!("this is {value}"))
        .help(format!("use {what} greater than zero"))
}

/// A negative or non-finite weight.
pub fn bad_weight(value: f64, file: FileId, span: Span) -> Diagnostic {
    Diagnostic::error(BAD_WEIGHT, "arc weights must be finite and not negative")
        .primary(file, span, format!("this weight is {value}"))
        .help("use a weight of zero or more; the shortest-path search needs it")
}

/// `symmetry about z order 0`.
pub fn bad_symmetry_order(file: FileId, span: Span) -> Diagnostic {
    Diagnostic::error(BAD_SYMMETRY_ORDER, "a symmetry order must be at least 1")
        .primary(file, span, "order 0")
        .help("write `order N` for a symmetry under rotations by 360°/N, or drop `order` for any angle")
}

/// `1e999`.
pub fn not_finite(file: FileId, span: Span) -> Diagnostic {
    Diagnostic::error(NOT_FINITE, "this number is too large")
        .primary(file, span, "beyond the range of a 64-bit float")
        .help("write a number below 1e308 (cell dimensions are metres and radians)")
}

/// `weights move 0.1` twice (also across included files).
pub fn weight_set_twice(what: &str, file: FileId, span: Span, first: Origin) -> Diagnostic {
    Diagnostic::error(WEIGHT_SET_TWICE, format!("the {what} weight is set twice"))
        .primary(file, span, "set again here")
        .secondary(first.file, first.span, "first set here")
        .help(format!(
            "set the {what} weight once, in the cell (not in a library it includes)"
        ))
}

/// The same directed transition twice.
pub fn duplicate_transition(from: &str, to: &str, again: Origin, first: Origin) -> Diagnostic {
    let d = Diagnostic::warning(
        DUPLICATE_TRANSITION,
        format!("transition `{from}` -> `{to}` is declared twice"),
    )
    .primary(again.file, again.span, "declared again here");
    let d = if first.span != again.span {
        d.secondary(first.file, first.span, "first declared here")
    } else {
        d
    };
    d.help("remove the repeated transition; a transition adds its arcs once")
}

/// Two length units or two angle units.
pub fn conflicting_units(file: FileId, span: Span, first: Span, what: &str) -> Diagnostic {
    Diagnostic::error(CONFLICTING_UNITS, format!("the {what} unit is set twice"))
        .primary(file, span, "set again here")
        .secondary(file, first, "first set here")
        .help(format!("keep one {what} unit per file"))
}

/// A transition between two fixed end-effectors.
pub fn fixed_to_fixed(transition: Origin, from: (&str, Origin), to: (&str, Origin)) -> Diagnostic {
    Diagnostic::error(
        FIXED_TO_FIXED,
        format!("transition between `{}` and `{}`, which are both fixed", from.0, to.0),
    )
    .primary(transition.file, transition.span, "neither end-effector can move")
    .secondary(from.1.file, from.1.name_span, format!("`{}` is fixed", from.0))
    .secondary(to.1.file, to.1.name_span, format!("`{}` is fixed", to.0))
    .help("an object moves between two surfaces only through a hand: remove this transition and add transitions through a movable end-effector")
}

/// A grasp for a kind no end-effector has.
pub fn kind_without_holder(kind: &str, grasp: Origin, kind_origin: Origin) -> Diagnostic {
    Diagnostic::error(
        KIND_WITHOUT_HOLDER,
        format!("no end-effector is of kind `{kind}`, so this pose can never be used"),
    )
    .primary(grasp.file, grasp.span, format!("declared for `{kind}`"))
    .secondary(
        kind_origin.file,
        kind_origin.name_span,
        "kind declared here",
    )
    .help(format!(
        "add an end-effector of kind `{kind}` (`arm NAME = ROBOT at (x, y, z) with {kind}` or `surface NAME : {kind} box ...`), or declare this pose for a kind the cell has"
    ))
}

/// A transition that names a grasp of another object.
pub fn cross_object_transition(object: &str, other: &str, file: FileId, span: Span) -> Diagnostic {
    Diagnostic::error(
        CROSS_OBJECT_TRANSITION,
        format!("transition from a grasp of `{object}` to a grasp of `{other}`"),
    )
    .primary(file, span, format!("this grasp belongs to `{other}`"))
    .help("a transition exchanges one object between two grasps of that same object")
}

/// A workspace nobody reaches.
pub fn unreached_workspace(name: &str, origin: Origin) -> Diagnostic {
    Diagnostic::error(
        UNREACHED_WORKSPACE,
        format!("no end-effector reaches workspace `{name}`"),
    )
    .primary(origin.file, origin.name_span, "reached by nothing")
    .help(format!(
        "add `{name}` to the `reaches` list of an end-effector, or remove the workspace"
    ))
}

/// An adjacency no movable end-effector shares.
pub fn useless_adjacency(a: &str, b: &str, origin: Origin) -> Diagnostic {
    Diagnostic::error(
        USELESS_ADJACENCY,
        format!("no movable end-effector reaches both `{a}` and `{b}`"),
    )
    .primary(
        origin.file,
        origin.span,
        "nothing can move an object across this adjacency",
    )
    .help(format!(
        "let a movable end-effector reach both `{a}` and `{b}`, or remove this line"
    ))
}

/// Two declared workspaces overlap.
pub fn overlapping_workspaces(
    a: &str,
    a_origin: Origin,
    b: &str,
    b_origin: Origin,
    volume: f64,
) -> Diagnostic {
    Diagnostic::error(
        OVERLAPPING_WORKSPACES,
        format!("workspaces `{a}` and `{b}` overlap"),
    )
    .primary(
        b_origin.file,
        b_origin.span,
        format!("overlaps `{a}` by {volume:.4} m³"),
    )
    .secondary(a_origin.file, a_origin.span, format!("`{a}` declared here"))
    .help("workspaces must not overlap: shrink or split one of them so that they only touch")
}

/// An include cycle.
pub fn include_cycle(file: FileId, span: Span, chain: &[String]) -> Diagnostic {
    Diagnostic::error(INCLUDE_CYCLE, "this include makes a cycle")
        .primary(file, span, "included again while it is being read")
        .note(format!("cycle: {}", chain.join(" -> ")))
        .help("remove one of the includes in the cycle; shared items belong in a library both include")
}

/// A file that can't be read (one too large or not a regular file has its own code).
pub fn file_unreadable(path: &str, error: &FileError, at: Option<(FileId, Span)>) -> Diagnostic {
    if let Some(refused) = trust::refused_file("cell file", path, error, at) {
        return refused;
    }
    let d = Diagnostic::error(FILE_UNREADABLE, format!("cannot read `{path}`: {error}"));
    match at {
        Some((file, span)) => d
            .primary(file, span, "included here")
            .help("check the path: it is relative to the file that includes it"),
        None => d.help("check the path and that the file is readable"),
    }
}

/// `rest` on a hand.
pub fn rest_on_hand(holder: &str, origin: Origin, holder_span: Span) -> Diagnostic {
    Diagnostic::error(
        REST_ON_HAND,
        format!("`{holder}` is a hand; objects rest only on supports"),
    )
    .primary(origin.file, holder_span, "a hand holds with `grasp`")
    .help("write `grasp NAME by HAND`, or rest the object on a support kind or surface")
}

/// An `expect` that does not hold.
pub fn expectation_failed(text: &str, origin: Origin, why: &str) -> Diagnostic {
    Diagnostic::error(
        EXPECTATION_FAILED,
        format!("requirement does not hold: {text}"),
    )
    .primary(origin.file, origin.span, "this requirement fails")
    .note(why.to_string())
    .help("change the cell so that the requirement holds, or change the requirement")
}

/// An included cell.
pub fn included_cell(path: &str, file: FileId, span: Span) -> Diagnostic {
    Diagnostic::error(
        INCLUDED_CELL,
        format!("`{path}` is a cell; only libraries can be included"),
    )
    .primary(file, span, "included here")
    .help("write `library NAME { ... }` in the included file, or move what you need into a library")
}

/// A movable geometric end-effector without reach.
pub fn no_reach(name: &str, origin: Origin) -> Diagnostic {
    Diagnostic::error(NO_REACH, format!("arm `{name}` has no reach"))
        .primary(origin.file, origin.name_span, "reaches nothing")
        .help(format!(
            "add `reach {name} box center (x, y, z) size (dx, dy, dz)`"
        ))
}

/// `reach` on something whose reach comes from elsewhere.
pub fn misplaced_reach(name: &str, why: &str, origin: Origin, declared: Origin) -> Diagnostic {
    Diagnostic::error(
        MISPLACED_REACH,
        format!("`{name}` cannot take a reach box: {why}"),
    )
    .primary(origin.file, origin.span, "reach box here")
    .secondary(
        declared.file,
        declared.name_span,
        format!("`{name}` declared here"),
    )
    .help("remove this `reach` line")
}

/// `adjacent w w`.
pub fn self_adjacency(name: &str, origin: Origin) -> Diagnostic {
    Diagnostic::error(
        SELF_ADJACENCY,
        format!("workspace `{name}` is declared adjacent to itself"),
    )
    .primary(origin.file, origin.span, "both sides are the same")
    .help("name two different workspaces")
}

/// `workspaces from reach` with nothing to derive from, or twice.
pub fn derivation_conflict(message: &str, origin: Origin, help: &str) -> Diagnostic {
    Diagnostic::error(DERIVATION_CONFLICT, message.to_string())
        .primary(origin.file, origin.span, "here")
        .help(help.to_string())
}

/// `expect o: table.g4 in w1 -> ...` where `table` cannot hold `g4`.
pub fn placement_grasp_mismatch(holder: &str, grasp: &str, file: FileId, span: Span) -> Diagnostic {
    Diagnostic::error(
        PLACEMENT_GRASP_MISMATCH,
        format!("`{holder}` cannot hold grasp `{grasp}`"),
    )
    .primary(file, span, "no such state")
    .help(format!("name a grasp declared for `{holder}` or its kind"))
}

/// A URDF that can't be read (one too large or not a regular file has its own code).
pub fn urdf_unreadable(path: &str, error: &FileError, file: FileId, span: Span) -> Diagnostic {
    robot_file_unreadable("URDF", path, error, file, span)
}

/// A robot description file (`URDF` or `SRDF`) that can't be read.
pub fn robot_file_unreadable(
    what: &str,
    path: &str,
    error: &FileError,
    file: FileId,
    span: Span,
) -> Diagnostic {
    if let Some(refused) = trust::refused_file(what, path, error, Some((file, span))) {
        return refused;
    }
    Diagnostic::error(
        URDF_UNREADABLE,
        format!("cannot read {what} `{path}`: {error}"),
    )
    .primary(file, span, "referenced here")
    .help("check the path: it is relative to the file that declares the robot")
}

/// A URDF urdf-rs rejects.
pub fn urdf_invalid(path: &str, error: &ParseError, file: FileId, span: Span) -> Diagnostic {
    Diagnostic::error(URDF_INVALID, format!("`{path}` is not a valid URDF"))
        .primary(file, span, "this URDF")
        .note(format!("the URDF reader says: {error}"))
        .help("fix the URDF file (check it with `check_urdf` from ROS, or compare with a known-good model)")
}

/// A link or joint not in the URDF.
pub fn urdf_unknown_link(
    what: &str,
    name: &str,
    path: &str,
    file: FileId,
    span: Span,
    suggestion: Option<&str>,
) -> Diagnostic {
    let help = match suggestion {
        Some(s) => format!("did you mean `{s}`?"),
        None => format!("name a {what} of `{path}`"),
    };
    Diagnostic::error(
        URDF_UNKNOWN_LINK,
        format!("`{path}` has no {what} `{name}`"),
    )
    .primary(file, span, format!("not a {what} of this URDF"))
    .help(help)
}

/// A `home` joint that is not a movable joint of the chain.
pub fn unknown_home_joint(
    joint: &str,
    robot: &str,
    file: FileId,
    span: Span,
    suggestion: Option<&str>,
) -> Diagnostic {
    let help = match suggestion {
        Some(s) => format!("did you mean `{s}`?"),
        None => format!("name a revolute or prismatic joint between the base and tip of `{robot}`"),
    };
    Diagnostic::error(
        URDF_UNKNOWN_LINK,
        format!("`{joint}` is not a movable joint of robot `{robot}`"),
    )
    .primary(file, span, "no such joint between base and tip")
    .help(help)
}

/// No chain from base to tip.
pub fn urdf_no_chain(base: &str, tip: &str, path: &str, file: FileId, span: Span) -> Diagnostic {
    Diagnostic::error(
        URDF_NO_CHAIN,
        format!("in `{path}`, `{tip}` is not below `{base}`"),
    )
    .primary(file, span, "no chain of joints from the base to the tip")
    .help("the tip must be a descendant of the base: swap them or pick other links")
}

/// A chain with nothing to move between the base and the tip.
pub fn urdf_no_movable_joint(
    base: &str,
    tip: &str,
    path: &str,
    file: FileId,
    span: Span,
) -> Diagnostic {
    Diagnostic::error(
        URDF_NO_CHAIN,
        format!("in `{path}`, no movable joint lies between `{base}` and `{tip}`"),
    )
    .primary(file, span, "this robot cannot move its tip")
    .help("pick a base and tip with at least one revolute, continuous or prismatic joint between them")
}

/// A home value beyond a joint limit.
pub fn home_out_of_limits(
    joint: &str,
    value: f64,
    lower: f64,
    upper: f64,
    unit: &str,
    file: FileId,
    span: Span,
) -> Diagnostic {
    let show = |v: f64| {
        if unit == "deg" {
            format!("{:.1} deg", v.to_degrees())
        } else {
            format!("{v:.3} m")
        }
    };
    Diagnostic::error(
        HOME_OUT_OF_LIMITS,
        format!("home value of `{joint}` is outside its limits"),
    )
    .primary(
        file,
        span,
        format!(
            "{} is not in {} .. {}",
            show(value),
            show(lower),
            show(upper)
        ),
    )
    .help(format!(
        "give `{joint}` a value between {} and {}",
        show(lower),
        show(upper)
    ))
}

/// `a -> b` without `b -> a`.
pub fn asymmetric_transition(from: &str, to: &str, origin: Origin) -> Diagnostic {
    Diagnostic::warning(
        ASYMMETRIC_TRANSITION,
        format!("transition `{from}` -> `{to}` has no way back"),
    )
    .primary(origin.file, origin.span, "declared one way only")
    .help(format!(
        "write `transition {from} <-> {to}` if the exchange works both ways"
    ))
}

/// A state that can't be entered or left.
pub fn dead_end_state(state: &str, never: &str, origin: Origin) -> Diagnostic {
    Diagnostic::warning(DEAD_END_STATE, format!("state {state} can never be {never}"))
        .primary(origin.file, origin.span, format!("this grasp gives a state that can never be {never}"))
        .help("add a transition to or from this grasp, or let its holder reach a workspace it shares with others")
}

/// A grasp in no transition.
pub fn unused_grasp(name: &str, origin: Origin) -> Diagnostic {
    Diagnostic::warning(UNUSED_GRASP, format!("grasp `{name}` is in no transition"))
        .primary(origin.file, origin.name_span, "never used")
        .help(format!("add a transition with `{name}`, or remove it"))
}

/// A transition between two grasps of one end-effector.
pub fn same_holder_transition(holder: &str, from: &str, to: &str, origin: Origin) -> Diagnostic {
    Diagnostic::warning(
        SAME_HOLDER_TRANSITION,
        format!("transition `{from}` -> `{to}` regrasps within `{holder}`"),
    )
    .primary(origin.file, origin.span, format!("both grasps belong to `{holder}`"))
    .help("an end-effector cannot hand an object to itself: regrasp through a surface or another hand")
}

/// Unused, kept so every code constant is referenced from the constructors' module.
pub fn all_codes() -> &'static [Code] {
    ALL
}
