//! Robot models: reads a URDF through [`Files`], checks that the named links exist and
//! that a chain of joints leads from the base to the tip (the walk itself is
//! [`cellc_urdf`]'s, shared with the runtime).
//!
//! The file is read within [`MAX_URDF_BYTES`] (and all URDFs of a compilation within
//! [`MAX_TOTAL_URDF_BYTES`]), checked whole by [`Description::problems`] before anything
//! uses it, and read once however many robots name it.
//!
//! The compiler only validates and records the chain; kinematics live in the runtime,
//! which reads the URDF again from the path and hash carried in the artifact.

use std::collections::HashMap;
use std::rc::Rc;

use cellc_lang::ast::RobotItem;
use cellc_lang::diagnostic::{did_you_mean, SuggestionBudget};
use cellc_lang::{Diagnostic, FileId};
use cellc_schema::files::{join, FileError, Files, MAX_URDF_BYTES};
use cellc_schema::sha256_hex;
use cellc_urdf::{Description, JointKind};

use crate::diagnostics;
use crate::model::{Joint, Origin, Robot};

/// At most this many problems of one URDF are reported (a broken file can have thousands);
/// the last one says how many more there are.
pub const MAX_URDF_PROBLEMS: usize = 5;

/// The most URDF text one compilation reads in all (64 MiB). A URDF that several robots
/// name is read once; one that failed is read again for each (and counts again).
pub const MAX_TOTAL_URDF_BYTES: u64 = 64 << 20;

/// A sound description read once, shared by every robot that names its path.
#[derive(Debug)]
struct Read {
    description: Description,
    sha256: String,
}

/// The URDFs one compilation has read, and what its budget leaves.
#[derive(Debug, Default)]
pub struct UrdfCache {
    read: HashMap<String, Rc<Read>>,
    bytes_read: u64,
    suggestions: SuggestionBudget,
}

impl UrdfCache {
    /// Loads the URDF of a `robot` item, reporting every problem; `None` when the model
    /// is unusable.
    pub fn load_robot(
        &mut self,
        files: &dyn Files,
        declaring_path: &str,
        file: FileId,
        item: &RobotItem,
        origin: Origin,
        diagnostics: &mut Vec<Diagnostic>,
    ) -> Option<Robot> {
        let path = join(declaring_path, &item.urdf.value);
        let read = match self.read.get(&path) {
            Some(read) => Rc::clone(read),
            None => {
                let read = Rc::new(self.read_file(files, &path, file, item, diagnostics)?);
                self.read.insert(path.clone(), Rc::clone(&read));
                read
            }
        };
        check_chain(
            &read,
            path,
            file,
            item,
            origin,
            &mut self.suggestions,
            diagnostics,
        )
    }

    /// Reads, parses and checks a URDF not read before.
    fn read_file(
        &mut self,
        files: &dyn Files,
        path: &str,
        file: FileId,
        item: &RobotItem,
        diagnostics: &mut Vec<Diagnostic>,
    ) -> Option<Read> {
        let left = MAX_TOTAL_URDF_BYTES.saturating_sub(self.bytes_read);
        let budget = MAX_URDF_BYTES.min(left);
        let text = match files.read_text_at_most(path, budget) {
            Ok(text) => text,
            Err(FileError::TooLarge { size, .. })
                if budget < MAX_URDF_BYTES && size <= MAX_URDF_BYTES =>
            {
                diagnostics.push(diagnostics::urdfs_too_large(
                    path,
                    MAX_TOTAL_URDF_BYTES,
                    file,
                    item.urdf.span,
                ));
                return None;
            }
            Err(error) => {
                diagnostics.push(diagnostics::urdf_unreadable(
                    path,
                    &error,
                    file,
                    item.urdf.span,
                ));
                return None;
            }
        };
        self.bytes_read += text.len() as u64;
        let description = match Description::parse(&text) {
            Ok(description) => description,
            Err(error) => {
                diagnostics.push(diagnostics::urdf_invalid(
                    path,
                    &error,
                    file,
                    item.urdf.span,
                ));
                return None;
            }
        };
        // A robot description is untrusted input: an unsound one (not a tree, or a value
        // out of its domain) is refused whole, so nothing downstream computes with it.
        let problems = description.problems();
        if !problems.is_empty() {
            let shown = problems.len().min(MAX_URDF_PROBLEMS);
            for (i, problem) in problems.iter().take(shown).enumerate() {
                let more = if i + 1 == shown {
                    problems.len() - shown
                } else {
                    0
                };
                diagnostics.push(diagnostics::urdf_problem(
                    path,
                    problem,
                    file,
                    item.urdf.span,
                    more,
                ));
            }
            return None;
        }
        Some(Read {
            sha256: sha256_hex(text.as_bytes()),
            description,
        })
    }
}

/// Checks a robot item against its (sound) description: its links, and a chain with a
/// movable joint from the base to the tip.
fn check_chain(
    read: &Read,
    path: String,
    file: FileId,
    item: &RobotItem,
    origin: Origin,
    suggestions: &mut SuggestionBudget,
    diagnostics: &mut Vec<Diagnostic>,
) -> Option<Robot> {
    let description = &read.description;
    // Both links are checked before walking, so that an unknown base and an unknown tip
    // are reported together, each with its own suggestion.
    let mut ok = true;
    let mut check_link = |name: &cellc_lang::ast::Name| {
        if description.has_link(&name.text) {
            true
        } else {
            let suggestion = suggestions.search(|| did_you_mean(&name.text, description.links()));
            diagnostics.push(diagnostics::urdf_unknown_link(
                "link", &name.text, &path, file, name.span, suggestion,
            ));
            false
        }
    };
    let base = match &item.base {
        Some(base) => {
            ok &= check_link(base);
            base.text.clone()
        }
        None => description.root().unwrap_or_default().to_string(),
    };
    ok &= check_link(&item.tip);
    if !ok {
        return None;
    }
    // The links exist (a file without a root gives the base "", which the walk refuses
    // too), so any failure means the tip does not descend from the base.
    let Ok(chain) = description.chain(&base, &item.tip.text) else {
        diagnostics.push(diagnostics::urdf_no_chain(
            &base,
            &item.tip.text,
            &path,
            file,
            item.span,
        ));
        return None;
    };
    // A tip on a finger would make the finger an axis of the arm.
    if let Some(finger) = chain.finger_joint() {
        diagnostics.push(diagnostics::finger_on_chain(
            &finger.joint.name,
            (finger.joint.upper - finger.joint.lower).abs(),
            finger.parent,
            &item.tip.text,
            file,
            item.tip.span,
        ));
        return None;
    }
    // The compiler records the joints the runtime will move; their axes and limits are
    // sound (checked with the whole file above), so the limits are intervals.
    let chain_joints: Vec<Joint> = chain
        .movable()
        .map(|(joint, kind)| {
            let (lower, upper) = joint.limits();
            Joint {
                name: joint.name.clone(),
                prismatic: kind == JointKind::Prismatic,
                lower,
                upper,
            }
        })
        .collect();
    if chain_joints.is_empty() {
        diagnostics.push(diagnostics::urdf_no_movable_joint(
            &base,
            &item.tip.text,
            &path,
            file,
            item.span,
        ));
        return None;
    }
    Some(Robot {
        name: item.name.text.clone(),
        urdf_path: path,
        urdf_sha256: read.sha256.clone(),
        base_link: base,
        tip_link: item.tip.text.clone(),
        chain_joints,
        links: description.links().map(str::to_string).collect(),
        origin,
    })
}
