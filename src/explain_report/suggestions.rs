//! Suggestions in words: each change as the edit to make, with how the plan would use it.

use cellc_runtime::explain::{Change, Suggestion};
use cellc_schema::WorkspaceId;

use super::words::{list, metres, q, Words};

impl Words<'_> {
    /// A suggestion: its changes, "a, b, and c".
    pub fn suggestion_text(&self, s: &Suggestion) -> String {
        let mut texts: Vec<String> = s.changes.iter().map(|c| self.change_text(c)).collect();
        match texts.len() {
            1 => texts.remove(0),
            _ => {
                let last = texts.pop().unwrap_or_default();
                format!("{}, and {}", texts.join(", "), last)
            }
        }
    }

    /// One change: what to write, then what it lets the plan do.
    pub fn change_text(&self, change: &Change) -> String {
        match change {
            Change::AddTransition {
                from_grasp,
                to_grasp,
                reverse_of,
                exchanges,
            } => {
                let (from, to) = (self.grasp_name(*from_grasp), self.grasp_name(*to_grasp));
                let line = q(&format!("transition {from} <-> {to}"));
                let mut text = match reverse_of {
                    Some(_) => format!(
                        "make {} two-way ({line})",
                        q(&format!("transition {to} -> {from}"))
                    ),
                    None => format!("add {line} to {}", self.object_name()),
                };
                if !exchanges.is_empty() {
                    let how: Vec<String> = exchanges.iter().map(|x| self.exchange(x)).collect();
                    text.push_str(&format!(", so {}", how.join(", and ")));
                }
                text
            }
            Change::AddAdjacency { a, b, carrier } => {
                let mut text = format!(
                    "declare {}",
                    q(&format!(
                        "adjacent {} {}",
                        self.ws_name(*a),
                        self.ws_name(*b)
                    ))
                );
                if let Some(e) = carrier {
                    text.push_str(&format!(
                        ", so {} can carry it between {} and {}",
                        self.ee(*e),
                        self.ws(*a),
                        self.ws(*b)
                    ));
                }
                text
            }
            Change::ExtendReach {
                end_effector,
                workspace,
                distance,
                meets,
            } => {
                let mut text = format!(
                    "extend the reach of {} to cover {}",
                    self.ee(*end_effector),
                    self.ws(*workspace)
                );
                if let Some(d) = distance {
                    text.push_str(&format!(" ({} beyond it)", metres(*d)));
                }
                if !meets.is_empty() {
                    text.push_str(&format!(
                        ", where it meets {}",
                        list(meets.iter().map(|&m| self.ee(m)).collect(), "and")
                    ));
                }
                text
            }
            Change::RelaxPruned(arc) => {
                let (x, y) = (self.node(arc.from), self.node(arc.to));
                format!(
                    "make {} feasible ({}): {}",
                    self.arc_text(x, y, arc.kind),
                    self.reason_text(&arc.reason),
                    self.reason_hint(&arc.reason, WorkspaceId(y.workspace))
                )
            }
        }
    }
}
