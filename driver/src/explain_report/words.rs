//! Names and phrases: the artifact's ids in words (names in backticks), lists, counts,
//! distances, states, arcs and the reasons arcs are infeasible.

use std::collections::BTreeSet;

use crate::advice::{FrontEnd, PlanOption};
use cellc_runtime::explain::{Exchange, HeldWith, Side};
use cellc_runtime::plan::NO_MOTION;
use cellc_schema::rules::{Adjacency, CellRules, ObjectRules};
use cellc_schema::{
    ArcKind, Artifact, BlockedPart, BlockedStep, Blocker, EndEffectorId, GraspId, Infeasibility,
    Node, NodeId, Object, WorkspaceId,
};

/// Names listed in one sentence before "and N more".
const MAX_LISTED: usize = 4;

/// What wording an explanation needs of the artifact: names, and who reaches and holds
/// what (the graph rules' reading of it, so the words agree with the analysis).
pub struct Words<'a> {
    pub art: &'a Artifact,
    pub obj: &'a Object,
    rules: CellRules,
    object_rules: ObjectRules,
    /// Whose options the advice names.
    front_end: FrontEnd,
}

impl<'a> Words<'a> {
    /// The same words, their advice naming `front_end`'s options.
    pub fn for_front_end(self, front_end: FrontEnd) -> Words<'a> {
        Words { front_end, ..self }
    }

    pub fn new(art: &'a Artifact, obj: &'a Object) -> Words<'a> {
        Words {
            art,
            obj,
            rules: CellRules::new(
                art.workspaces.len(),
                CellRules::end_effectors_of(art),
                Adjacency::Derived,
            ),
            object_rules: ObjectRules::from_artifact(art, obj),
            front_end: FrontEnd::CommandLine,
        }
    }

    pub fn ee(&self, e: EndEffectorId) -> String {
        ee_name(self.art, e)
    }

    pub fn ws(&self, w: WorkspaceId) -> String {
        self.art
            .workspaces
            .get(w.index())
            .map_or_else(|| format!("`workspace #{}`", w.0), |x| q(&x.name))
    }

    pub fn grasp(&self, g: GraspId) -> String {
        self.obj
            .grasps
            .get(g.index())
            .map_or_else(|| format!("`grasp #{}`", g.0), |x| q(&x.name))
    }

    /// A grasp's name without backticks, for quoting inside a declaration.
    pub fn grasp_name(&self, g: GraspId) -> String {
        self.obj
            .grasps
            .get(g.index())
            .map_or_else(|| format!("#{}", g.0), |x| x.name.clone())
    }

    /// A workspace's name without backticks.
    pub fn ws_name(&self, w: WorkspaceId) -> String {
        self.art
            .workspaces
            .get(w.index())
            .map_or_else(|| format!("#{}", w.0), |x| x.name.clone())
    }

    pub fn object_name(&self) -> String {
        q(&self.obj.name)
    }

    /// A state of the object's graph (the explanation's node ids are valid).
    pub fn node(&self, i: NodeId) -> Node {
        self.obj.graph.nodes[i.index()]
    }

    pub fn is_movable(&self, e: EndEffectorId) -> bool {
        self.rules.is_movable(e)
    }

    pub fn reach(&self, e: EndEffectorId) -> &[WorkspaceId] {
        self.rules.reach(e)
    }

    pub fn ee_list(&self, set: &[EndEffectorId], conj: &str) -> String {
        list(set.iter().map(|&e| self.ee(e)).collect(), conj)
    }

    pub fn ws_list(&self, set: &[WorkspaceId], conj: &str) -> String {
        list(set.iter().map(|&w| self.ws(w)).collect(), conj)
    }

    /// "`table` with `g1` in `w1`".
    pub fn state_text(&self, n: Node) -> String {
        format!(
            "{} with {} in {}",
            self.ee(n.end_effector),
            self.grasp(n.grasp),
            self.ws(n.workspace)
        )
    }

    /// The goal states: "`table` with `g1` in `w3`", or by holder and workspace when they
    /// have more than three grasps.
    pub fn goals_text(&self, goals: &[NodeId]) -> String {
        let mut holders = BTreeSet::new();
        let mut grasps = BTreeSet::new();
        let mut wss = BTreeSet::new();
        for &g in goals {
            let n = self.node(g);
            holders.insert(n.end_effector);
            grasps.insert(n.grasp);
            wss.insert(n.workspace);
        }
        let holders = list(holders.iter().map(|&e| self.ee(e)).collect(), "or");
        let wss = list(wss.iter().map(|&w| self.ws(w)).collect(), "or");
        if grasps.len() <= 3 {
            let grasps = list(grasps.iter().map(|&g| self.grasp(g)).collect(), "or");
            format!("{holders} with {grasps} in {wss}")
        } else {
            format!("{holders} in {wss}")
        }
    }

    /// "41 states: `arm4` with ... in `w4` and `w5`; ... and 6 more end-effectors", the
    /// end-effectors in `first` (those the cut names) before the others.
    pub fn side_text(&self, side: &Side, first: &BTreeSet<EndEffectorId>) -> String {
        let mut holdings: Vec<_> = side.holdings.iter().collect();
        holdings.sort_by_key(|h| (!first.contains(&h.end_effector), h.end_effector));
        let mut parts: Vec<String> = holdings
            .iter()
            .take(MAX_LISTED)
            .map(|h| {
                format!(
                    "{} with {} in {}",
                    self.ee(h.end_effector),
                    list(h.grasps.iter().map(|&g| self.grasp(g)).collect(), "and"),
                    self.ws_list(&h.workspaces, "and")
                )
            })
            .collect();
        if holdings.len() > MAX_LISTED {
            let more = holdings.len() - MAX_LISTED;
            let noun = if more == 1 {
                "end-effector"
            } else {
                "end-effectors"
            };
            parts.push(format!("and {more} more {noun}"));
        }
        format!(
            "{}: {}",
            count(side.states.len(), "state"),
            parts.join("; ")
        )
    }

    /// "any grasp of `left_arm`", "grasp `g4` of `left_arm`", "grasps `g4`, `g5` of ...".
    fn grasps_phrase(&self, held: &HeldWith) -> String {
        let all = self.object_rules.grasps_of(held.end_effector);
        let e = self.ee(held.end_effector);
        match held.grasps.as_slice() {
            [one] => format!("grasp {} of {e}", self.grasp(*one)),
            grasps if grasps.len() > 1 && grasps == all => format!("any grasp of {e}"),
            grasps => format!(
                "grasps {} of {e}",
                list(grasps.iter().map(|&g| self.grasp(g)).collect(), "and")
            ),
        }
    }

    /// The grasps of several end-effectors: "any grasp of `left_arm` or `table`".
    pub fn holders_phrase(&self, side: &[HeldWith]) -> String {
        let all_any = side.len() > 1
            && side.iter().all(|h| {
                h.grasps.len() > 1
                    && self.object_rules.grasps_of(h.end_effector).len() == h.grasps.len()
            });
        if all_any {
            let ees: Vec<EndEffectorId> = side.iter().map(|h| h.end_effector).collect();
            format!("any grasp of {}", self.ee_list(&ees, "or"))
        } else {
            list(side.iter().map(|h| self.grasps_phrase(h)).collect(), "or")
        }
    }

    /// "the transition `g1 -> g8` from `table` to `right_arm` in `w2`" or "the move of
    /// `right_arm` with `g7` from `w2` to `w3`".
    pub fn arc_text(&self, from: Node, to: Node, kind: ArcKind) -> String {
        let ee = |n: Node| self.ee(n.end_effector);
        let ws = |n: Node| self.ws(n.workspace);
        match kind {
            ArcKind::Move => format!(
                "the move of {} with {} from {} to {}",
                ee(from),
                self.grasp(from.grasp),
                ws(from),
                ws(to)
            ),
            ArcKind::Transition => format!(
                "the transition {} from {} to {} in {}",
                self.grasp_line(from, to),
                ee(from),
                ee(to),
                ws(from)
            ),
        }
    }

    /// "`g1 -> g8`": the grasps of a transition arc.
    pub fn grasp_line(&self, from: Node, to: Node) -> String {
        q(&format!(
            "{} -> {}",
            self.grasp_name(from.grasp),
            self.grasp_name(to.grasp)
        ))
    }

    /// Why an arc is infeasible, in words ([`infeasibility`]).
    pub fn reason_text(&self, reason: &Infeasibility) -> String {
        infeasibility(self.art, reason)
    }

    /// What would make an infeasible arc into `workspace` feasible (the help when nothing
    /// is suggested).
    pub fn reason_hint(&self, reason: &Infeasibility, workspace: WorkspaceId) -> String {
        match reason {
            Infeasibility::NoIkSolution { end_effector, .. } => format!(
                "move {}'s base or {} closer together, or choose a grasp it can reach",
                self.ee(*end_effector),
                self.ws(workspace)
            ),
            Infeasibility::NoClosedChain { .. } => "move the arms closer together, or choose \
                 grasps that leave room for both hands"
                .to_string(),
            // Collision bodies are named `arm/link`; the cell language writes `arm.link`.
            Infeasibility::Collision { a, b } => format!(
                "move one of them, or declare `allow contact {} {}` if the contact is harmless",
                a.replace('/', "."),
                b.replace('/', ".")
            ),
            Infeasibility::NoPlacement { detail } if detail.starts_with(NO_MOTION) => {
                format!(
                    "move what blocks the motion, or the arms' home configurations, or plan \
                     again with another {}",
                    self.front_end.option(PlanOption::Seed)
                )
            }
            Infeasibility::NoPlacement { .. } => format!(
                "extend the surface into {}, or choose another resting pose",
                self.ws(workspace)
            ),
            Infeasibility::Blocked(blocker) => blocked_hint(self.art, blocker, self.front_end),
            _ => "change the geometry so it becomes feasible".to_string(),
        }
    }

    /// "`left_arm` can hand it to `right_arm` in `w2`", "... put it on `table` ...".
    pub fn exchange(&self, x: &Exchange) -> String {
        let (a, b, w) = (self.ee(x.giver), self.ee(x.taker), self.ws(x.workspace));
        match (self.is_movable(x.giver), self.is_movable(x.taker)) {
            (true, true) => format!("{a} can hand it to {b} in {w}"),
            (true, false) => format!("{a} can put it on {b} in {w}"),
            _ => format!("{b} can take it from {a} in {w}"),
        }
    }
}

/// An end-effector's name in backticks (its index, for one the artifact does not have).
pub fn ee_name(art: &Artifact, e: EndEffectorId) -> String {
    art.end_effectors
        .get(e.index())
        .map_or_else(|| format!("`end-effector #{}`", e.0), |x| q(&x.name))
}

/// Why an arc is infeasible (the runtime's reason it was pruned at build time, or failed
/// during a request), in words: the one wording of the W0006 warnings and of the R0004
/// explanations. One clause without parentheses, so that it reads alone (a label), after
/// a colon and inside the parentheses the explanations list reasons in: "`right` cannot
/// reach the pose, closest 0.21 m and 12.0 deg off over 40 tries".
pub fn infeasibility(art: &Artifact, reason: &Infeasibility) -> String {
    match reason {
        Infeasibility::NoIkSolution {
            end_effector,
            tries,
            position_error,
            rotation_error,
        } => format!(
            "{} cannot reach the pose, closest {} and {:.1} deg off over {tries} tries",
            ee_name(art, *end_effector),
            metres(*position_error),
            rotation_error.to_degrees()
        ),
        Infeasibility::NoClosedChain {
            a,
            b,
            tries,
            position_error,
            rotation_error,
        } => format!(
            "{} and {} cannot hold the object at once, closest {} and {:.1} deg apart over \
             {tries} tries",
            ee_name(art, *a),
            ee_name(art, *b),
            metres(*position_error),
            rotation_error.to_degrees()
        ),
        Infeasibility::Collision { a, b } => format!("{} collides with {}", q(a), q(b)),
        // A blocked motion says so itself (`no collision-free motion: ...`), once.
        Infeasibility::NoPlacement { detail } if detail.starts_with(NO_MOTION) => {
            let error = detail[NO_MOTION.len()..].trim_start_matches(": ");
            if error.starts_with(NO_MOTION) {
                error.to_string()
            } else {
                detail.clone()
            }
        }
        // Verification words these as whole clauses ("the workspace has no volume").
        Infeasibility::NoPlacement { detail } => detail.clone(),
        Infeasibility::HandBusy { hand, holds } => format!(
            "{} is holding {}",
            ee_name(art, *hand),
            q(art.object_name(*holds))
        ),
        Infeasibility::Blocked(blocker) => blocked(art, blocker),
        _ => "found infeasible".to_string(),
    }
}

/// What to do about another object in the way.
pub fn blocked_hint(art: &Artifact, blocker: &Blocker, front_end: FrontEnd) -> String {
    format!(
        "move {} out of the way first (a move before this one, or plan with {}), or \
         choose a goal that leaves room for it",
        q(art.object_name(blocker.by)),
        front_end.option(PlanOption::Clear)
    )
}

/// Another object in the way: "`ball` blocks the put-down at (0.500, -0.644, 0.960), in
/// the way of the object", "`ball` blocks the path of `left`'s hand".
pub fn blocked(art: &Artifact, blocker: &Blocker) -> String {
    let by = q(art.object_name(blocker.by));
    let part = match blocker.part {
        BlockedPart::Object => "the object".to_string(),
        BlockedPart::Arm(e) => format!("{}'s arm", ee_name(art, e)),
        BlockedPart::Hand(e) => format!("{}'s hand", ee_name(art, e)),
    };
    let step = match blocker.during {
        BlockedStep::Pick { .. } => "pick",
        BlockedStep::PutDown { .. } => "put-down",
        BlockedStep::Handoff { .. } => "handoff",
        BlockedStep::Motion => return format!("{by} blocks the path of {part}"),
    };
    match blocker.during.position() {
        Some([x, y, z]) => {
            format!("{by} blocks the {step} at ({x:.3}, {y:.3}, {z:.3}), in the way of {part}")
        }
        None => format!("{by} blocks the {step}, in the way of {part}"),
    }
}

/// A name in backticks.
pub fn q(name: &str) -> String {
    format!("`{name}`")
}

/// "0.21 m", or millimetres below a centimetre.
pub fn metres(x: f64) -> String {
    if x.abs() < 0.01 {
        format!("{:.1} mm", x * 1000.0)
    } else {
        format!("{x:.2} m")
    }
}

/// "1 state", "10 states".
pub fn count(n: usize, noun: &str) -> String {
    if n == 1 {
        format!("1 {noun}")
    } else {
        format!("{n} {noun}s")
    }
}

/// "`a`", "`a` or `b`", "`a`, `b` or `c`", "`a`, `b`, `c`, `d` or 3 more".
pub fn list(items: Vec<String>, conj: &str) -> String {
    let n = items.len();
    if n > MAX_LISTED + 1 {
        return format!(
            "{} {conj} {} more",
            items[..MAX_LISTED].join(", "),
            n - MAX_LISTED
        );
    }
    match n {
        0 => String::new(),
        1 => items[0].clone(),
        _ => format!("{} {conj} {}", items[..n - 1].join(", "), items[n - 1]),
    }
}

/// The first clause of a text, for a label.
pub fn short(text: &str) -> String {
    let cut = [", so ", ", where ", ":", " ("]
        .iter()
        .filter_map(|m| text.find(m))
        .min()
        .unwrap_or(text.len());
    text[..cut].to_string()
}
