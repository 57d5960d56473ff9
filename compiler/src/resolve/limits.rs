//! Joint limits (`limits` items, MoveIt's `joint_limits.yaml`): what each joint of each
//! robot is timed with, and where that came from.
//!
//! The lines are collected while references are resolved (pass 3) and applied once every
//! line is known ([`Resolver::apply_limits`]), so their order never matters. Precedence,
//! last wins: the URDF's `<limit velocity>`, the robot's `joint_limits.yaml`, the robot's
//! `limits ROBOT` line (for every joint of its chain), the joint's `limits ROBOT.JOINT`
//! line. Names in the file that are not joints of the chain are ignored: a MoveIt
//! package's file lists every joint of the robot (fingers, other groups); a chain joint
//! the file does not cover still gets W0007 when it has no acceleration limit.

use cellc_lang::ast::{self, LimitKind};
use cellc_lang::diagnostic::did_you_mean;
use cellc_lang::{FileId, Span};

use super::{Entry, Resolver};
use crate::diagnostics::{self, Sort};
use crate::ids::RobotId;
use crate::joint_limits::{self, MAX_LIMITS_FILE_BYTES};
use crate::model::{Joint, Limit, LimitSource, Origin};
use crate::units::FileUnits;

/// One `limits` line, resolved to its robot (and joint).
pub(super) struct LimitsLine<'a> {
    robot: RobotId,
    joint: Option<usize>,
    file: FileId,
    units: FileUnits,
    item: &'a ast::LimitsItem,
}

/// A joint limits file read (by resolved path): its id in the source map and its joints,
/// or `None` when it was refused (reported once).
pub(super) type ReadLimitsFile = Option<(FileId, Vec<joint_limits::JointEntry>)>;

fn origin_of(file: FileId, item: &ast::LimitsItem) -> Origin {
    Origin {
        file,
        span: item.span,
        name_span: item.target.span,
    }
}

impl<'a> Resolver<'a, '_> {
    /// Resolves a `limits` line's robot and joint and keeps it for [`Self::apply_limits`].
    pub(super) fn resolve_limits(
        &mut self,
        file: FileId,
        units: FileUnits,
        item: &'a ast::LimitsItem,
    ) {
        let Some(Entry::Robot(robot)) = self.lookup(file, item.robot(), Sort::Robot, "") else {
            return;
        };
        // A robot whose URDF did not load was reported where it is declared.
        if robot.0 == u32::MAX {
            return;
        }
        let joint = match item.joint() {
            None => None,
            Some(name) => {
                let joints = &self.cell.robots[robot].chain_joints;
                match joints.iter().position(|j| j.name == name.text) {
                    Some(i) => Some(i),
                    None => {
                        let suggestion = self.suggestions.search(|| {
                            did_you_mean(&name.text, joints.iter().map(|j| j.name.as_str()))
                        });
                        self.diagnostics.push(diagnostics::unknown_limits_joint(
                            &name.text,
                            &item.robot().text,
                            file,
                            name.span,
                            suggestion,
                        ));
                        return;
                    }
                }
            }
        };
        self.limits_lines.push(LimitsLine {
            robot,
            joint,
            file,
            units,
            item,
        });
    }

    /// Applies every `limits` line and file to the robots' joints, then warns of joints
    /// left to a default.
    pub(super) fn apply_limits(&mut self) {
        let lines = std::mem::take(&mut self.limits_lines);
        // Given twice at one level: the second is refused (which should win would
        // depend on include order).
        let mut first: rustc_hash::FxHashMap<(RobotId, Option<usize>, Option<LimitKind>), Origin> =
            Default::default();
        let mut kept: Vec<(&LimitsLine<'_>, Vec<&ast::LimitValue>, bool)> = Vec::new();
        for line in &lines {
            let here = origin_of(line.file, line.item);
            let mut file_kept = false;
            if let Some(written) = &line.item.file {
                match first.get(&(line.robot, None, None)) {
                    Some(f) => {
                        let what = format!("the joint limits file of `{}`", line.item.robot().text);
                        self.diagnostics.push(diagnostics::limit_set_twice(
                            &what,
                            line.file,
                            written.span,
                            *f,
                        ));
                    }
                    None => {
                        first.insert((line.robot, None, None), here);
                        file_kept = true;
                    }
                }
            }
            let mut values = Vec::new();
            for v in &line.item.values {
                let key = (line.robot, line.joint, Some(v.kind));
                if let Some(f) = first.get(&key) {
                    let what = format!(
                        "the {} limit of `{}`",
                        v.kind.as_str(),
                        target_text(line.item)
                    );
                    self.diagnostics
                        .push(diagnostics::limit_set_twice(&what, line.file, v.span, *f));
                    continue;
                }
                first.insert(key, here);
                values.push(v);
            }
            kept.push((line, values, file_kept));
        }
        // Files, then robot lines, then joint lines: each overwrites the one before.
        for (line, _, file_kept) in &kept {
            if *file_kept {
                self.apply_limits_file(line);
            }
        }
        for (line, values, _) in kept.iter().filter(|(l, _, _)| l.joint.is_none()) {
            let mut joint_lines: Vec<(usize, LimitKind)> = Vec::new();
            for (l, vs, _) in kept.iter().filter(|(l, _, _)| l.robot == line.robot) {
                if let Some(j) = l.joint {
                    joint_lines.extend(vs.iter().map(|v| (j, v.kind)));
                }
            }
            let origin = origin_of(line.file, line.item);
            for v in values {
                // Evaluated once per joint kind, so a unit error is reported once.
                let mut by_kind: [Option<Option<f64>>; 2] = [None, None];
                let n = self.cell.robots[line.robot].chain_joints.len();
                for i in 0..n {
                    if joint_lines.contains(&(i, v.kind)) {
                        continue;
                    }
                    let joint = &self.cell.robots[line.robot].chain_joints[i];
                    let (prismatic, name) = (joint.prismatic, joint.name.clone());
                    let slot = &mut by_kind[usize::from(prismatic)];
                    let value = match slot {
                        Some(value) => *value,
                        None => {
                            let before = self.diagnostics.len();
                            let value = self
                                .eval(line.file, line.units)
                                .limit(&v.rate, v.kind, prismatic);
                            if self.diagnostics.len() > before {
                                let wrong_unit = self
                                    .diagnostics
                                    .last()
                                    .is_some_and(|d| d.code == diagnostics::codes::WRONG_UNIT);
                                if wrong_unit {
                                    if let Some(d) = self.diagnostics.pop() {
                                        let robot = &line.item.robot().text;
                                        self.diagnostics.push(
                                            diagnostics::robot_limit_does_not_fit(
                                                d, robot, &name, prismatic,
                                            ),
                                        );
                                    }
                                }
                            }
                            by_kind[usize::from(prismatic)] = Some(value);
                            value
                        }
                    };
                    if let Some(value) = value {
                        let joint = &mut self.cell.robots[line.robot].chain_joints[i];
                        set(joint, v.kind, value, LimitSource::Robot(origin));
                    }
                }
            }
        }
        for (line, values, _) in &kept {
            let Some(i) = line.joint else {
                continue;
            };
            let origin = origin_of(line.file, line.item);
            let prismatic = self.cell.robots[line.robot].chain_joints[i].prismatic;
            for v in values {
                if let Some(value) = self
                    .eval(line.file, line.units)
                    .limit(&v.rate, v.kind, prismatic)
                {
                    let joint = &mut self.cell.robots[line.robot].chain_joints[i];
                    set(joint, v.kind, value, LimitSource::Joint(origin));
                }
            }
        }
    }

    /// Reads the robot's `joint_limits.yaml` (once per path per compilation) and sets
    /// the limits it enables on the chain's joints it names.
    fn apply_limits_file(&mut self, line: &LimitsLine<'_>) {
        let Some(written) = &line.item.file else {
            return;
        };
        let declaring = self
            .loaded
            .files
            .iter()
            .find(|f| f.id == line.file)
            .map_or("", |f| f.path.as_str());
        let named = crate::urdf::Named {
            files: self.files,
            packages: &self.packages,
            declaring_path: declaring,
            file: line.file,
        };
        let path = match named.path(written) {
            Ok(path) => path,
            Err(d) => {
                self.diagnostics.push(d);
                return;
            }
        };
        let origin = origin_of(line.file, line.item);
        if !self.limits_files.contains_key(&path) {
            let read = self.read_limits_file(&path, written, origin);
            self.limits_files.insert(path.clone(), read);
        }
        let Some((_, entries)) = &self.limits_files[&path] else {
            return;
        };
        let entries = entries.clone();
        for entry in entries {
            let joints = &mut self.cell.robots[line.robot].chain_joints;
            let Some(joint) = joints.iter_mut().find(|j| j.name == entry.joint) else {
                continue;
            };
            for (kind, value, _) in entry.limits {
                set(joint, kind, value, LimitSource::File(path.clone(), origin));
            }
        }
    }

    fn read_limits_file(
        &mut self,
        path: &str,
        written: &ast::StringLit,
        origin: Origin,
    ) -> ReadLimitsFile {
        let bytes = match self.files.read_at_most(path, MAX_LIMITS_FILE_BYTES) {
            Ok(bytes) => bytes,
            Err(error) => {
                self.diagnostics.push(diagnostics::limits_file_unreadable(
                    path,
                    &error,
                    origin.file,
                    written.span,
                ));
                return None;
            }
        };
        let text = match String::from_utf8(bytes) {
            Ok(text) => text,
            Err(e) => {
                let why = format!("not UTF-8 at byte {}", e.utf8_error().valid_up_to());
                self.diagnostics.push(diagnostics::limits_file_not_text(
                    path,
                    &why,
                    origin.file,
                    written.span,
                ));
                return None;
            }
        };
        if let Some(offset) =
            text.find(|c: char| c.is_control() && !matches!(c, '\n' | '\r' | '\t'))
        {
            let why = format!("a control character at byte {offset}");
            self.diagnostics.push(diagnostics::limits_file_not_text(
                path,
                &why,
                origin.file,
                written.span,
            ));
            return None;
        }
        let parsed = joint_limits::parse(&text);
        let id = FileId(self.first_extra_source + self.extra_sources.len() as u32);
        self.extra_sources.push((path.to_string(), text));
        match parsed {
            Ok(entries) => Some((id, entries)),
            Err(problem) => {
                let span = Span::new(problem.span.0, problem.span.1.max(problem.span.0));
                self.diagnostics.push(diagnostics::bad_limits_file(
                    path,
                    &problem.message,
                    (id, span),
                    origin,
                ));
                None
            }
        }
    }
}

/// W0007, once per robot and limit: the joints left without an acceleration limit, and
/// those without a velocity limit anywhere (URDF, file, cell). Reported, like the graph's
/// warnings, only for a cell without errors.
pub fn missing_limits(cell: &crate::model::Cell, diagnostics: &mut Vec<cellc_lang::Diagnostic>) {
    {
        for (_, robot) in cell.robots.iter() {
            let name = &robot.name;
            for (limit, missing, default, help) in [
                (
                    "acceleration",
                    robot
                        .chain_joints
                        .iter()
                        .filter(|j| j.acceleration.is_none())
                        .collect::<Vec<_>>(),
                    Joint::DEFAULT_ACCELERATION,
                    format!(
                        "declare one for the robot (`limits {name} acceleration 4 rad/s2`), per joint (`limits {name}.JOINT acceleration ...`), or read MoveIt's file (`limits {name} from \"joint_limits.yaml\"`)"
                    ),
                ),
                (
                    "velocity",
                    robot
                        .chain_joints
                        .iter()
                        .filter(|j| j.velocity.is_none())
                        .collect(),
                    Joint::DEFAULT_VELOCITY,
                    format!(
                        "the URDF's `<limit velocity>` is missing or zero: declare one (`limits {name} velocity 1.5 rad/s`, or per joint `limits {name}.JOINT velocity ...`)"
                    ),
                ),
            ] {
                if missing.is_empty() {
                    continue;
                }
                let order = if limit == "velocity" { "" } else { "²" };
                let revolute = missing.iter().any(|j| !j.prismatic);
                let prismatic = missing.iter().any(|j| j.prismatic);
                let defaults = match (revolute, prismatic) {
                    (true, true) => format!("{default} rad/s{order} (m/s{order} when prismatic)"),
                    (false, true) => format!("{default} m/s{order}"),
                    _ => format!("{default} rad/s{order}"),
                };
                let names: Vec<&str> = missing.iter().map(|j| j.name.as_str()).collect();
                diagnostics.push(diagnostics::missing_limits(
                    limit,
                    name,
                    &names,
                    &defaults,
                    robot.origin,
                    help,
                ));
            }
        }
    }
}

fn set(joint: &mut Joint, kind: LimitKind, value: f64, source: LimitSource) {
    let limit = Some(Limit { value, source });
    match kind {
        LimitKind::Velocity => joint.velocity = limit,
        LimitKind::Acceleration => joint.acceleration = limit,
        LimitKind::Jerk => joint.jerk = limit,
    }
}

/// `ROBOT` or `ROBOT.JOINT`, as written.
fn target_text(item: &ast::LimitsItem) -> String {
    match item.joint() {
        Some(joint) => format!("{}.{}", item.robot().text, joint.text),
        None => item.robot().text.clone(),
    }
}
