//! World documents and world errors in words: reading `--world FILE` (bounded, untrusted)
//! and turning a [`WorldError`] into an R0009 diagnostic that names what is wrong.

use cellc_lang::Diagnostic;
use cellc_runtime::plan::PlanOptions;
use cellc_runtime::{Cell, World, WorldError};
use cellc_schema::world::WorldDocumentError;
use cellc_schema::{Files, WorldDocument};

use crate::plan_report::codes;
use cellc_driver::fs_files::FsFiles;

/// Reads and checks a world document.
pub fn read_world(cell: &Cell, path: &str, options: &PlanOptions) -> Result<World, Diagnostic> {
    let max = cellc_schema::world::MAX_WORLD_BYTES as u64;
    let bytes = FsFiles.read_at_most(path, max).map_err(|e| {
        Diagnostic::error(codes::WORLD_DOCUMENT, format!("cannot read `{path}`: {e}"))
            .help("give the path of a world document (JSON, see docs/world.md)")
    })?;
    let document = WorldDocument::from_json(&bytes).map_err(|e| match e {
        WorldDocumentError::TooLarge { bytes } => Diagnostic::error(
            codes::WORLD_DOCUMENT,
            format!("`{path}` has {bytes} bytes, more than a world document may have"),
        )
        .help(format!(
            "a world document holds at most {} MiB",
            cellc_schema::world::MAX_WORLD_BYTES >> 20
        )),
        WorldDocumentError::Syntax {
            line,
            column,
            message,
        } => Diagnostic::error(
            codes::WORLD_DOCUMENT,
            format!("`{path}` line {line}, column {column}: not a world document"),
        )
        .note(crate::render::escape(&message).into_owned())
        .help("a world document has `arms` (arm -> joint -> value) and `objects` (object -> placement or \"absent\"); see docs/world.md"),
    })?;
    cell.world(&document, options)
        .map_err(|e| world_diagnostic(&e, &format!("`{path}`")))
}

/// A world error in words.
pub fn world_diagnostic(e: &WorldError, source: &str) -> Diagnostic {
    let (what, help) = match e {
        WorldError::Name(e) => (
            e.to_string(),
            "name an arm, object, holder, grasp and workspace the cell has".to_string(),
        ),
        WorldError::NotAnArm { name } => (
            format!("`{name}` is not an arm, so it has no joints"),
            "give joints for the cell's arms only".to_string(),
        ),
        WorldError::UnknownJoint { arm, joint, known } => (
            format!("`{arm}`'s chain has no joint `{joint}`"),
            cellc_lang::diagnostic::did_you_mean(joint, known.iter().map(String::as_str))
                .map(|s| format!("did you mean `{s}`?"))
                .unwrap_or_else(|| format!("its joints are {}", quoted(&known.iter().map(String::as_str).collect::<Vec<_>>()))),
        ),
        WorldError::JointOutOfLimits {
            arm,
            joint,
            value,
            lower,
            upper,
        } => (
            format!("`{arm}`'s joint `{joint}` is {value}, outside its limits [{lower}, {upper}]"),
            "joint values are radians (metres for prismatic joints), within the URDF's limits"
                .to_string(),
        ),
        WorldError::Placement { object, error } => (
            format!("`{object}`: {error}"),
            "place it on a surface at a pose its resting poses match, or in a hand with a grasp where the arm's joints put it in a workspace".to_string(),
        ),
        WorldError::PoseNeeded { object, holder } => (
            format!("`{object}` rests on `{holder}` but has no pose"),
            "give `at` (and `rpy` or `quat` when it is turned): an obstacle needs a place".to_string(),
        ),
        WorldError::Orientation { object, detail } => (
            format!("`{object}`: {detail}"),
            "`rpy` is degrees about fixed x, y, z; `quat` is (w, x, y, z) of unit length".to_string(),
        ),
        WorldError::PoseDisagrees {
            object,
            holder,
            position_error,
            rotation_error,
        } => (
            format!(
                "`{object}` is given {:.1} mm and {:.2} deg away from where `{holder}`'s joints hold it",
                position_error * 1000.0,
                rotation_error.to_degrees()
            ),
            "leave the pose out (it follows from the joints), or give the joints that put the hand there".to_string(),
        ),
        WorldError::HandFull {
            hand,
            first,
            second,
        } => (
            format!("`{hand}` would hold both `{first}` and `{second}`"),
            "a hand holds one object: put one of them elsewhere".to_string(),
        ),
        WorldError::NoHold { object, holder } => (
            format!("no configuration of `{holder}` found holds `{object}` there clear of the rest of the cell"),
            "give a pose the hand reaches with that grasp, or a workspace where the cell's build found it held".to_string(),
        ),
        _ => (e_debug(e), "see docs/world.md".to_string()),
    };
    Diagnostic::error(codes::WORLD, format!("{source}: {what}")).help(help)
}

/// Words for a world error this version does not know (the type is non-exhaustive).
fn e_debug(e: &WorldError) -> String {
    crate::render::escape(&format!("{e:?}")).into_owned()
}

fn quoted(names: &[&str]) -> String {
    names
        .iter()
        .map(|n| format!("`{n}`"))
        .collect::<Vec<_>>()
        .join(", ")
}
