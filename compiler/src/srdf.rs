//! A robot's MoveIt SRDF (`robot NAME urdf "..." srdf "..."`): read within the robot
//! files' budget, parsed and checked against its URDF by [`cellc_urdf::Srdf`], then used
//! for three things:
//!
//! - `<disable_collisions>`: link pairs recorded on the robot, never checked against each
//!   other (in the artifact, for the runtime's collision world);
//! - `<group>`: `group NAME` on the robot item takes the base and tip from the group's
//!   chain ([`group_chain`]);
//! - `<group_state>`: `home NAME` on an arm is that configuration ([`home_from_state`]).

use cellc_lang::ast::{Name, StringLit};
use cellc_lang::diagnostic::{did_you_mean, SuggestionBudget};
use cellc_lang::{Diagnostic, FileId};
use cellc_schema::sha256_hex;
use cellc_urdf::{Description, GroupChainError, Srdf};

use crate::diagnostics;
use crate::model::{Joint, Robot};
use crate::urdf::{Named, UrdfCache, MAX_URDF_PROBLEMS};

/// An SRDF read and found consistent with its URDF.
#[derive(Debug)]
pub(crate) struct SrdfRead {
    pub(crate) srdf: Srdf,
    pub(crate) path: String,
    pub(crate) sha256: String,
}

impl SrdfRead {
    /// The disabled pairs as link names, each once, in file order.
    pub(crate) fn disabled_pairs(&self) -> Vec<(String, String)> {
        let mut seen = std::collections::HashSet::new();
        self.srdf
            .disabled_collisions
            .iter()
            .map(|p| (p.link1.clone(), p.link2.clone()))
            .filter(|pair| seen.insert(pair.clone()))
            .collect()
    }
}

impl UrdfCache {
    /// Reads the SRDF written as `written` for the URDF at `urdf_path`.
    pub(crate) fn load_srdf(
        &mut self,
        named: &Named<'_>,
        written: &StringLit,
        urdf: &Description,
        urdf_path: &str,
        diagnostics: &mut Vec<Diagnostic>,
    ) -> Option<SrdfRead> {
        let path = named.path(written).map_err(|d| diagnostics.push(d)).ok()?;
        let text = self.read_text("SRDF", named, &path, written, diagnostics)?;
        let srdf = match Srdf::parse(&text) {
            Ok(srdf) => srdf,
            Err(error) => {
                diagnostics.push(diagnostics::srdf_invalid(
                    &path,
                    &error,
                    named.file,
                    written.span,
                ));
                return None;
            }
        };
        let problems = srdf.problems(urdf);
        if !problems.is_empty() {
            let shown = problems.len().min(MAX_URDF_PROBLEMS);
            for (i, problem) in problems.iter().take(shown).enumerate() {
                let more = if i + 1 == shown {
                    problems.len() - shown
                } else {
                    0
                };
                diagnostics.push(diagnostics::srdf_problem(
                    &path,
                    urdf_path,
                    problem,
                    named.file,
                    written.span,
                    more,
                ));
            }
            return None;
        }
        Some(SrdfRead {
            sha256: sha256_hex(text.as_bytes()),
            srdf,
            path,
        })
    }
}

/// The base and tip links that `group NAME` gives a robot item.
pub(crate) fn group_chain(
    srdf: Option<&SrdfRead>,
    group: &Name,
    urdf: &Description,
    robot: &str,
    file: FileId,
    suggestions: &mut SuggestionBudget,
    diagnostics: &mut Vec<Diagnostic>,
) -> Option<(String, String)> {
    let Some(srdf) = srdf else {
        diagnostics.push(diagnostics::unknown_srdf_name(
            "group",
            &group.text,
            robot,
            None,
            file,
            group.span,
            None,
        ));
        return None;
    };
    match srdf.srdf.group_chain(&group.text, urdf) {
        Ok(chain) => Some(chain),
        Err(GroupChainError::Unknown) => {
            let suggestion = suggestions.search(|| {
                did_you_mean(
                    &group.text,
                    srdf.srdf.groups.iter().map(|g| g.name.as_str()),
                )
            });
            diagnostics.push(diagnostics::unknown_srdf_name(
                "group",
                &group.text,
                robot,
                Some(&srdf.path),
                file,
                group.span,
                suggestion,
            ));
            None
        }
        Err(error) => {
            diagnostics.push(diagnostics::no_chain_given(
                robot,
                Some((&group.text, &error)),
                file,
                group.span,
            ));
            None
        }
    }
}

/// A joint value a group state sets, on the chain: its index and value.
pub(crate) type StateValue = (usize, f64);

/// The chain joint values of `home NAME`: the robot's group state of that name (the one
/// for the robot's group when several groups have one). Joints of the state that are not
/// on the chain (fingers, another arm) are left out; chain joints it does not set keep
/// their default. `None` (reported) when there is no such state, or it sets no joint of
/// the chain.
pub(crate) fn home_from_state(
    robot: &Robot,
    state: &Name,
    file: FileId,
    suggestions: &mut SuggestionBudget,
    diagnostics: &mut Vec<Diagnostic>,
) -> Option<Vec<StateValue>> {
    let Some((srdf_path, _)) = &robot.srdf else {
        diagnostics.push(diagnostics::unknown_srdf_name(
            "group state",
            &state.text,
            &robot.name,
            None,
            file,
            state.span,
            None,
        ));
        return None;
    };
    let named: Vec<&cellc_urdf::GroupState> = robot
        .group_states
        .iter()
        .filter(|s| s.name == state.text)
        .collect();
    let chosen = match named.as_slice() {
        [] => {
            let suggestion = suggestions.search(|| {
                did_you_mean(
                    &state.text,
                    robot.group_states.iter().map(|s| s.name.as_str()),
                )
            });
            diagnostics.push(diagnostics::unknown_srdf_name(
                "group state",
                &state.text,
                &robot.name,
                Some(srdf_path),
                file,
                state.span,
                suggestion,
            ));
            return None;
        }
        [only] => *only,
        several => match several
            .iter()
            .find(|s| Some(&s.group) == robot.group.as_ref())
        {
            Some(s) => *s,
            None => {
                let groups: Vec<&str> = several.iter().map(|s| s.group.as_str()).collect();
                diagnostics.push(diagnostics::ambiguous_group_state(
                    &state.text,
                    &groups,
                    &robot.name,
                    file,
                    state.span,
                ));
                return None;
            }
        },
    };
    let values = chain_values(&robot.chain_joints, &chosen.values);
    if values.is_empty() {
        diagnostics.push(diagnostics::state_sets_no_chain_joint(
            &state.text,
            &chosen.group,
            &robot.name,
            file,
            state.span,
        ));
        return None;
    }
    Some(values)
}

/// The values of `values` that set joints of `chain`, as (chain index, value).
fn chain_values(chain: &[Joint], values: &[(String, f64)]) -> Vec<StateValue> {
    values
        .iter()
        .filter_map(|(joint, v)| Some((chain.iter().position(|j| &j.name == joint)?, *v)))
        .collect()
}
