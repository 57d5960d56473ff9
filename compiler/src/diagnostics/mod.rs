//! Every diagnostic the compiler produces, one named constructor per problem.
//!
//! Keeping them here (rather than formatting messages at each check) keeps wording
//! consistent and makes the list of codes easy to audit against `docs/diagnostics/`.
//!
//! The codes are the registry's (`cellc_lang::codes::compile`, here as `codes`); the
//! constructors are grouped by phase: here names (E01xx), cell semantics (E03xx) and
//! warnings, `values.rs` units and values (E02xx), `urdf.rs` a robot's URDF (E04xx),
//! `kinematics.rs`, `robots.rs`, `trust.rs` and `world.rs` as their headers say.

use cellc_lang::{Diagnostic, FileId, Span};
use cellc_schema::FileError;

use crate::model::Origin;

/// The compiler's codes (the registry's `cellc_lang::codes::compile`).
pub use cellc_lang::codes::compile as codes;
mod families;
mod kinematics;
mod limits;
mod robots;
mod trust;
mod urdf;
mod values;
mod world;
pub use families::*;
pub use kinematics::*;
pub use limits::*;
pub use robots::*;
pub use trust::*;
pub use urdf::*;
pub use values::*;
pub use world::*;

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
