//! Suggestions in words: each change as the edit to make, with how the plan would use it,
//! and an edit of the sources ([`crate::fixes`]) as a line to write.

use cellc_lang::SourceMap;
use cellc_runtime::explain::{BodyName, Change, Suggestion};
use cellc_schema::{Aabb, EndEffectorId};

use super::words::{list, metres, q, Words};
use crate::fixes::SourceEdit;

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
            Change::ExtendReaches {
                end_effector,
                workspace,
                meets,
            } => {
                let mut text = format!(
                    "add {} to the `reaches` list of {}",
                    self.ws(*workspace),
                    self.ee(*end_effector)
                );
                text.push_str(&self.meets(meets));
                text
            }
            Change::GrowReach {
                end_effector,
                reach_box,
                grown,
                region,
                workspace,
                distance,
                meets,
            } => {
                let e = self.ee(*end_effector);
                let old = reach_box.and_then(|i| {
                    let e = self.art.end_effectors.get(end_effector.index())?;
                    e.reach_boxes.get(i as usize)
                });
                let mut text = match old {
                    Some(old) => format!(
                        "grow the reach box of {e} from {} to {}",
                        box_text(old),
                        box_text(grown)
                    ),
                    None => format!("give {e} the reach box {}", box_text(grown)),
                };
                // A derived workspace is named by its region: its name goes with the edit.
                let declared = self
                    .art
                    .workspaces
                    .get(workspace.index())
                    .filter(|w| !w.derived);
                let cover = list(region.iter().map(box_text).collect(), "and");
                let away = distance
                    .filter(|d| *d > 0.0)
                    .map_or_else(String::new, |d| format!(", {} away", metres(d)));
                match declared {
                    Some(_) => text.push_str(&format!(
                        ", so that it covers {} ({cover}{away})",
                        self.ws(*workspace)
                    )),
                    None => {
                        let reachers: Vec<EndEffectorId> = self
                            .art
                            .end_effectors
                            .iter()
                            .enumerate()
                            .filter(|(_, x)| x.reaches.contains(&workspace.0))
                            .map(|(i, _)| EndEffectorId(i as u32))
                            .collect();
                        text.push_str(&format!(
                            ", so that it covers {cover} (where {} reach{away})",
                            self.ee_list(&reachers, "and")
                        ));
                    }
                }
                text.push_str(&self.meets(meets));
                text
            }
            Change::AllowContact { a, b, arcs } => {
                let line = q(&format!("allow contact {} {}", body(a), body(b)));
                let what = match arcs.as_slice() {
                    [one] => self.arc_text(self.node(one.from), self.node(one.to), one.kind),
                    [one, ..] => format!(
                        "{} arcs, e.g. {}",
                        arcs.len(),
                        self.arc_text(self.node(one.from), self.node(one.to), one.kind)
                    ),
                    [] => "arcs".to_string(),
                };
                format!("declare {line} if they may touch (their collision removed {what})")
            }
        }
    }

    /// ", where it meets `right`".
    fn meets(&self, meets: &[EndEffectorId]) -> String {
        if meets.is_empty() {
            String::new()
        } else {
            format!(", where it meets {}", self.ee_list(meets, "and"))
        }
    }
}

/// A body as `allow contact` writes it.
fn body(b: &BodyName) -> String {
    match &b.part {
        Some(part) => format!("{}.{part}", b.owner),
        None => b.owner.clone(),
    }
}

/// "x 0.25..0.6, y -0.1..0.1, z 0.9..1.5 m", as `cellc info` writes boxes.
pub fn box_text(b: &Aabb) -> String {
    let r = |k: usize| format!("{}..{}", round(b.min[k]), round(b.max[k]));
    format!("x {}, y {}, z {} m", r(0), r(1), r(2))
}

/// Millimetres at most, without trailing zeros.
fn round(x: f64) -> String {
    let text = format!("{x:.3}");
    let text = text.trim_end_matches('0').trim_end_matches('.');
    if text == "-0" {
        "0".to_string()
    } else {
        text.to_string()
    }
}

/// An edit in words: "write `...` on line 6 of `pick.cell`", "add `...` after line 13 of
/// `pick.cell`" (`None` when the edit does not fit its file).
pub fn fix_text(edit: &SourceEdit, sources: &SourceMap) -> Option<String> {
    let (_, file) = sources.iter().find(|(id, _)| *id == edit.file)?;
    let text = file.text.as_str();
    let (start, end) = (edit.span.start as usize, edit.span.end as usize);
    let line_start = text.get(..start)?.rfind('\n').map_or(0, |i| i + 1);
    let line_end = text.get(end..)?.find('\n').map_or(text.len(), |i| end + i);
    let old = &text[line_start..line_end];
    let new = format!(
        "{}{}{}",
        &text[line_start..start],
        edit.text,
        &text[end..line_end]
    );
    let line = text[..line_start].matches('\n').count() + 1;
    let path = q(&file.path);
    let lines: Vec<&str> = new.split('\n').collect();
    let added = |lines: &[&str]| {
        let written: Vec<String> = lines.iter().map(|l| q(l.trim())).collect();
        written.join(", ")
    };
    Some(match lines.as_slice() {
        [first, rest @ ..] if !rest.is_empty() && *first == old => {
            format!("add {} after line {line} of {path}", added(rest))
        }
        [rest @ .., last] if !rest.is_empty() && *last == old => {
            format!("add {} before line {line} of {path}", added(rest))
        }
        _ => format!("write {} on line {line} of {path}", added(&lines)),
    })
}
