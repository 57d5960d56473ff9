//! Robot models: reads a URDF through [`Files`], checks that the named links exist and
//! that a chain of joints leads from the base to the tip (the walk itself is
//! [`cellc_urdf`]'s, shared with the runtime).
//!
//! The file is read within [`MAX_URDF_BYTES`] (and all URDFs and SRDFs of a compilation
//! within [`MAX_TOTAL_URDF_BYTES`]), checked whole by [`Description::problems`] before
//! anything uses it, and read once however many robots name it. Files are named as ROS
//! names them: `package://NAME/...` through the [`PackagePath`], `file://`, or relative
//! to the naming file; the URDF's collision meshes are resolved here too, so the
//! artifact carries their paths and the runtime needs no package path. A robot's SRDF
//! (`crate::srdf`) may give its base and tip (a planning group), disabled collision pairs
//! and named configurations.
//!
//! The compiler only validates and records the chain; kinematics live in the runtime,
//! which reads the URDF again from the path and hash carried in the artifact.

use std::collections::HashMap;
use std::rc::Rc;

use cellc_lang::ast::{RobotItem, StringLit};
use cellc_lang::diagnostic::{did_you_mean, SuggestionBudget};
use cellc_lang::{Diagnostic, FileId};
use cellc_schema::files::{FileError, Files, MAX_URDF_BYTES};
use cellc_schema::{sha256_hex, MeshFile};
use cellc_urdf::package::{self, ResolveError};
use cellc_urdf::{is_xacro_path, Description, JointKind, PackagePath, ParseError};

use crate::diagnostics::{self, NamedBy};
use crate::model::{Joint, Origin, Robot};
use crate::srdf::SrdfRead;

/// At most this many problems of one URDF are reported (a broken file can have thousands);
/// the last one says how many more there are.
pub const MAX_URDF_PROBLEMS: usize = 5;

/// The most URDF text one compilation reads in all (64 MiB). A URDF that several robots
/// name is read once; one that failed is read again for each (and counts again).
pub const MAX_TOTAL_URDF_BYTES: u64 = 64 << 20;

/// A sound description read once, shared by every robot that names its path.
#[derive(Debug)]
pub(crate) struct Read {
    pub(crate) description: Description,
    sha256: String,
    meshes: Vec<MeshFile>,
}

/// Where a robot file is read from and how it is named in the cell.
pub(crate) struct Named<'a> {
    pub(crate) files: &'a dyn Files,
    pub(crate) packages: &'a PackagePath,
    pub(crate) declaring_path: &'a str,
    pub(crate) file: FileId,
}

impl Named<'_> {
    /// The path of a file the cell names as `written`, or the diagnostic of why none.
    pub(crate) fn path(&self, written: &StringLit) -> Result<String, Diagnostic> {
        package::resolve(
            self.declaring_path,
            &written.value,
            self.packages,
            self.files,
        )
        .map_err(|error| self.unresolved(&error, &written.value, NamedBy::Cell, written))
    }

    /// The diagnostic of a file name that gives no path.
    pub(crate) fn unresolved(
        &self,
        error: &ResolveError,
        uri: &str,
        named_by: NamedBy<'_>,
        at: &StringLit,
    ) -> Diagnostic {
        match error {
            ResolveError::UnknownPackage { package } => diagnostics::unresolved_package(
                package,
                uri,
                named_by,
                self.packages.search_folders(),
                self.file,
                at.span,
            ),
            _ => diagnostics::bad_package_uri(uri, self.file, at.span),
        }
    }
}

/// The URDFs one compilation has read, and what its budget leaves.
#[derive(Debug, Default)]
pub struct UrdfCache {
    read: HashMap<String, Rc<Read>>,
    bytes_read: u64,
    suggestions: SuggestionBudget,
}

impl UrdfCache {
    /// Loads the URDF (and SRDF) of a `robot` item, reporting every problem; `None` when
    /// the model is unusable.
    pub(crate) fn load_robot(
        &mut self,
        named: &Named<'_>,
        item: &RobotItem,
        origin: Origin,
        diagnostics: &mut Vec<Diagnostic>,
    ) -> Option<Robot> {
        let path = named
            .path(&item.urdf)
            .map_err(|d| diagnostics.push(d))
            .ok()?;
        if is_xacro_path(&path) {
            diagnostics.push(diagnostics::xacro_file(&path, named.file, item.urdf.span));
            return None;
        }
        let read = match self.read.get(&path) {
            Some(read) => Rc::clone(read),
            None => {
                let read = Rc::new(self.read_file(named, &path, item, diagnostics)?);
                self.read.insert(path.clone(), Rc::clone(&read));
                read
            }
        };
        let srdf = match &item.srdf {
            Some(written) => {
                Some(self.load_srdf(named, written, &read.description, &path, diagnostics)?)
            }
            None => None,
        };
        check_chain(
            &read,
            srdf.as_ref(),
            path,
            named.file,
            item,
            origin,
            &mut self.suggestions,
            diagnostics,
        )
    }

    /// The text of a robot file (`what`: URDF or SRDF) within what is left of the
    /// compilation's budget.
    pub(crate) fn read_text(
        &mut self,
        what: &str,
        named: &Named<'_>,
        path: &str,
        at: &StringLit,
        diagnostics: &mut Vec<Diagnostic>,
    ) -> Option<String> {
        let left = MAX_TOTAL_URDF_BYTES.saturating_sub(self.bytes_read);
        let budget = MAX_URDF_BYTES.min(left);
        let text = match named.files.read_text_at_most(path, budget) {
            Ok(text) => text,
            Err(FileError::TooLarge { size, .. })
                if budget < MAX_URDF_BYTES && size <= MAX_URDF_BYTES =>
            {
                diagnostics.push(diagnostics::urdfs_too_large(
                    path,
                    MAX_TOTAL_URDF_BYTES,
                    named.file,
                    at.span,
                ));
                return None;
            }
            Err(error) => {
                let package = match package::file_ref(&at.value) {
                    Ok(package::FileRef::Package { package, .. }) => {
                        named.packages.declared(package).map(|dir| (package, dir))
                    }
                    _ => None,
                };
                let d = diagnostics::robot_file_unreadable(
                    what, path, &error, package, named.file, at.span,
                );
                diagnostics.push(d);
                return None;
            }
        };
        self.bytes_read += text.len() as u64;
        Some(text)
    }

    /// Reads, parses and checks a URDF not read before, and resolves its meshes.
    fn read_file(
        &mut self,
        named: &Named<'_>,
        path: &str,
        item: &RobotItem,
        diagnostics: &mut Vec<Diagnostic>,
    ) -> Option<Read> {
        let file = named.file;
        let text = self.read_text("URDF", named, path, &item.urdf, diagnostics)?;
        let description = match Description::parse(&text) {
            Ok(description) => description,
            Err(ParseError::Xacro) => {
                diagnostics.push(diagnostics::xacro_file(path, file, item.urdf.span));
                return None;
            }
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
        // Mesh names are resolved against the URDF's own path, once; a package that cannot
        // be found is reported once per package.
        let mut meshes = Vec::new();
        let mut reported = Vec::new();
        for written in description.collision_meshes() {
            match package::resolve(path, written, named.packages, named.files) {
                Ok(resolved) => meshes.push(MeshFile {
                    written: written.to_string(),
                    path: resolved,
                }),
                Err(error) => {
                    if !reported.contains(&error) {
                        let at = NamedBy::Mesh(path);
                        diagnostics.push(named.unresolved(&error, written, at, &item.urdf));
                        reported.push(error);
                    }
                }
            }
        }
        if !reported.is_empty() {
            return None;
        }
        Some(Read {
            sha256: sha256_hex(text.as_bytes()),
            description,
            meshes,
        })
    }
}

/// Checks a robot item against its (sound) description: its links, and a chain with a
/// movable joint from the base to the tip.
#[allow(clippy::too_many_arguments)]
fn check_chain(
    read: &Read,
    srdf: Option<&SrdfRead>,
    path: String,
    file: FileId,
    item: &RobotItem,
    origin: Origin,
    suggestions: &mut SuggestionBudget,
    diagnostics: &mut Vec<Diagnostic>,
) -> Option<Robot> {
    let description = &read.description;
    // A planning group gives the links the item does not write.
    let group_chain = match &item.group {
        Some(group) => Some(crate::srdf::group_chain(
            srdf,
            group,
            description,
            &item.name.text,
            file,
            suggestions,
            diagnostics,
        )?),
        None => None,
    };
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
    let base = match (&item.base, &group_chain) {
        (Some(base), _) => {
            ok &= check_link(base);
            base.text.clone()
        }
        (None, Some((base, _))) => base.clone(),
        (None, None) => description.root().unwrap_or_default().to_string(),
    };
    let tip = match (&item.tip, &group_chain) {
        (Some(tip), _) => {
            ok &= check_link(tip);
            tip.text.clone()
        }
        (None, Some((_, tip))) => tip.clone(),
        (None, None) => {
            diagnostics.push(diagnostics::no_chain_given(
                &item.name.text,
                None,
                file,
                item.span,
            ));
            return None;
        }
    };
    if !ok {
        return None;
    }
    // The links exist (a file without a root gives the base "", which the walk refuses
    // too), so any failure means the tip does not descend from the base.
    let Ok(chain) = description.chain(&base, &tip) else {
        diagnostics.push(diagnostics::urdf_no_chain(
            &base, &tip, &path, file, item.span,
        ));
        return None;
    };
    // A tip on a finger would make the finger an axis of the arm.
    if let Some(finger) = chain.finger_joint() {
        diagnostics.push(diagnostics::finger_on_chain(
            &finger.joint.name,
            (finger.joint.upper - finger.joint.lower).abs(),
            finger.parent,
            &tip,
            file,
            item.tip.as_ref().map_or(item.span, |t| t.span),
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
                velocity: (joint.velocity.is_finite() && joint.velocity > 0.0).then_some(
                    crate::model::Limit {
                        value: joint.velocity,
                        source: crate::model::LimitSource::Urdf,
                    },
                ),
                acceleration: None,
                jerk: None,
            }
        })
        .collect();
    if chain_joints.is_empty() {
        diagnostics.push(diagnostics::urdf_no_movable_joint(
            &base, &tip, &path, file, item.span,
        ));
        return None;
    }
    Some(Robot {
        name: item.name.text.clone(),
        urdf_path: path,
        urdf_sha256: read.sha256.clone(),
        meshes: read.meshes.clone(),
        srdf: srdf.map(|s| (s.path.clone(), s.sha256.clone())),
        disabled_collisions: srdf.map_or_else(Vec::new, |s| s.disabled_pairs()),
        group_states: srdf.map_or_else(Vec::new, |s| s.srdf.group_states.clone()),
        group: item.group.as_ref().map(|g| g.text.clone()),
        base_link: base,
        tip_link: tip,
        chain_joints,
        links: description.links().map(str::to_string).collect(),
        origin,
    })
}
