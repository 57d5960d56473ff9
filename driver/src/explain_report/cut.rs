//! The cut in words: one sentence per gap between the two sides.

use cellc_runtime::explain::{Gap, LostArc};
use cellc_schema::EndEffectorId;

use super::words::{list, q, Words};

impl Words<'_> {
    /// A gap in words.
    pub fn gap_text(&self, gap: &Gap) -> String {
        match gap {
            Gap::NoTransition {
                near,
                far,
                workspaces,
                one_way,
            } => {
                let mut text = format!(
                    "no transition joins {} with {} in {}",
                    self.holders_phrase(near),
                    self.holders_phrase(far),
                    self.ws_list(workspaces, "or")
                );
                if !one_way.is_empty() {
                    let lines: Vec<String> = one_way
                        .iter()
                        .map(|&(a, b)| {
                            q(&format!("{} -> {}", self.grasp_name(a), self.grasp_name(b)))
                        })
                        .collect();
                    text.push_str(&format!(
                        " (declared only the other way: {})",
                        list(lines, "and")
                    ));
                }
                text
            }
            Gap::InfeasibleTransition {
                near,
                far,
                workspaces,
                arcs,
            } => {
                let mut lines = Vec::new();
                for arc in arcs {
                    let line = self.grasp_line(self.node(arc.from), self.node(arc.to));
                    if !lines.contains(&line) {
                        lines.push(line);
                    }
                }
                let reasons = self.reasons(arcs);
                let found = if arcs.iter().any(|a| a.failed) {
                    "were infeasible (pruned, or failed during this request)"
                } else {
                    "were all pruned as infeasible"
                };
                let mut why = reasons[..reasons.len().min(2)].join("; ");
                if reasons.len() > 2 {
                    why.push_str(&format!("; and {} other reasons", reasons.len() - 2));
                }
                format!(
                    "the transitions declared from {} to {} in {} {found}: {} ({why})",
                    self.ee_list(near, "and"),
                    self.ee_list(far, "and"),
                    self.ws_list(workspaces, "or"),
                    list(lines, "and"),
                )
            }
            Gap::InfeasibleMove {
                hand,
                grasps,
                from,
                to,
                arcs,
            } => format!(
                "{} cannot carry it with {} from {} to {}: {}",
                self.ee(*hand),
                list(grasps.iter().map(|&g| self.grasp(g)).collect(), "or"),
                self.ws(*from),
                self.ws(*to),
                self.reasons(arcs).join("; ")
            ),
            Gap::NotAdjacent { hand, from, to } => format!(
                "{} and {} are not adjacent, so {} cannot carry it from one to the other",
                self.ws(*from),
                self.ws(*to),
                self.ee(*hand)
            ),
            Gap::NoCommonWorkspace { near, far } => format!(
                "{} and {} reach no common workspace ({} reaches {}; {} reaches {})",
                self.ee(*near),
                self.ee(*far),
                self.ee(*near),
                self.ws_list(self.reach(*near), "and"),
                self.ee(*far),
                self.ws_list(self.reach(*far), "and")
            ),
            Gap::NoHand {
                near,
                far,
                workspaces,
            } => {
                let what = match (near.is_empty(), far.is_empty()) {
                    (false, true) => format!("take it from {}", self.ee_list(near, "or")),
                    (true, false) => format!("bring it to {}", self.ee_list(far, "or")),
                    _ => format!(
                        "take it from {} nor bring it to {}",
                        self.ee_list(near, "or"),
                        self.ee_list(far, "or")
                    ),
                };
                format!(
                    "no movable end-effector that can hold {} reaches {}, so nothing can \
                     {what} there",
                    self.object_name(),
                    self.ws_list(workspaces, "or"),
                )
            }
            Gap::OnlyFixed {
                near,
                far,
                near_workspaces,
                far_workspaces,
            } => format!(
                "only fixed end-effectors hold it on either side ({}), and they neither move \
                 an object nor pass it to each other: a movable end-effector must take it in \
                 {} and bring it to {}",
                self.ee_list(&union(near, far), "and"),
                self.ws_list(near_workspaces, "or"),
                self.ws_list(far_workspaces, "or"),
            ),
            Gap::Apart {
                near,
                far,
                near_workspaces,
                far_workspaces,
                shared,
                holders_there,
            } => {
                if shared.is_empty() {
                    format!(
                        "what the start reaches ({} in {}) and what leads to the goal ({} in \
                         {}) lie in different workspaces, and no hand carries it from one to \
                         the other",
                        self.ee_list(near, "and"),
                        self.ws_list(near_workspaces, "and"),
                        self.ee_list(far, "and"),
                        self.ws_list(far_workspaces, "and")
                    )
                } else {
                    format!(
                        "where both sides hold it ({}), only {} do, and an end-effector never \
                         passes an object to itself, nor a fixed one to another",
                        self.ws_list(shared, "and"),
                        self.ee_list(holders_there, "and")
                    )
                }
            }
        }
    }

    /// The distinct reasons of some lost arcs, in order.
    fn reasons(&self, arcs: &[LostArc]) -> Vec<String> {
        let mut reasons: Vec<String> = Vec::new();
        for arc in arcs {
            let r = self.reason_text(&arc.reason);
            if !reasons.contains(&r) {
                reasons.push(r);
            }
        }
        reasons
    }

    /// A pruned or failed arc and its reason in words.
    pub fn lost_text(&self, arc: &LostArc) -> String {
        let when = if arc.failed {
            "failed during this request"
        } else {
            "was pruned at build time"
        };
        format!(
            "{} {when}: {}",
            self.arc_text(self.node(arc.from), self.node(arc.to), arc.kind),
            self.reason_text(&arc.reason)
        )
    }
}

/// Two sorted lists as one, sorted, without repeats.
fn union(a: &[EndEffectorId], b: &[EndEffectorId]) -> Vec<EndEffectorId> {
    let mut out: Vec<EndEffectorId> = a.iter().chain(b).copied().collect();
    out.sort_unstable();
    out.dedup();
    out
}
