//! `cellc export pddl`: an object's graph as a PDDL domain, and requests as problems.
//!
//! The encoding (docs/pddl.md): the object is a PDDL object of type `item`, each graph
//! state a constant of type `state`, and `(at ?o ?s)` says where the object is. Each arc
//! the planner searches (the artifact's arcs; verification has moved the infeasible ones
//! to `pruned`) is one action with no other parameter than the item, costing its weight
//! times [`COST_SCALE`], rounded (Fast Downward wants whole-number costs). Every action
//! also sets `(moved ?o)`, which a problem asks for when the object must leave its start
//! and come back. A goal of one state is `(at item S)`; a goal of several states lists
//! them as `(target S)` facts and asks for `(arrived item)`, which the `arrive` action
//! (cost 0) gives at a target state: a disjunctive goal would need axioms, which Fast
//! Downward's optimal heuristics refuse.
//!
//! The text is a function of the artifact and the problems alone (no path, time or
//! hash-map order), so the same cell gives the same bytes.

mod names;
mod problem;

use std::fmt::Write;

use cellc_lang::Diagnostic;
use cellc_schema::{Artifact, NodeId, ObjectId};

pub use names::{problem_ids, Names};
pub use problem::{Problem, ProblemError};

/// Codes of the PDDL export (the registry's `cellc_lang::codes::export`).
pub use cellc_lang::codes::export as codes;

/// Action cost per unit of arc weight: costs are whole thousandths of a weight.
pub const COST_SCALE: f64 = 1000.0;

/// The largest cost a path may add up to: Fast Downward adds costs in 32-bit integers.
pub const MAX_PATH_COST: f64 = i32::MAX as f64;

/// The action cost of an arc of weight `weight`: `weight` x [`COST_SCALE`], rounded
/// (weights are finite and not negative in every validated artifact).
pub fn action_cost(weight: f64) -> u64 {
    (weight * COST_SCALE).round() as u64
}

/// An object's weights would overflow PDDL costs: a path through every state at the
/// largest action cost must stay within [`MAX_PATH_COST`].
#[derive(Clone, Debug, PartialEq)]
pub struct CostsTooLarge {
    /// The object.
    pub object: String,
    /// The largest arc weight of its graph.
    pub weight: f64,
    /// The states of its graph.
    pub n_states: usize,
    /// The largest weight this graph can have.
    pub largest_allowed: f64,
}

impl CostsTooLarge {
    /// The E0508 diagnostic.
    pub fn diagnostic(&self) -> Diagnostic {
        Diagnostic::error(
            codes::COSTS_TOO_LARGE,
            format!(
                "the arc weight {} of `{}` is too large for PDDL's whole-number costs",
                self.weight,
                crate::render::escape(&self.object)
            ),
        )
        .help(format!(
            "lower the cell's `weights` to at most {} for this graph",
            self.largest_allowed
        ))
        .note(format!(
            "an action costs its arc's weight x {COST_SCALE}, rounded, and Fast Downward adds \
             costs in 32-bit integers: a path through all {} states at the largest cost must \
             stay within {MAX_PATH_COST}",
            self.n_states
        ))
    }
}

/// One file of an export.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct File {
    /// Its name in the object's folder: `domain.pddl`, or the problem's id and `.pddl`.
    pub name: String,
    /// Its text.
    pub text: String,
}

/// The PDDL files of one object.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Export {
    /// The folder they go in: the object's PDDL name.
    pub folder: String,
    /// The domain first, then one problem per request given, in order.
    pub files: Vec<File>,
}

/// The domain of `object` and one problem per entry of `problems`.
///
/// # Errors
/// The graph's weights would overflow whole-number costs (E0508).
pub fn export(
    artifact: &Artifact,
    object: ObjectId,
    problems: &[Problem],
) -> Result<Export, CostsTooLarge> {
    check_costs(artifact, object)?;
    let names = Names::of(artifact, object);
    let mut files = vec![File {
        name: "domain.pddl".to_string(),
        text: domain(artifact, object, &names),
    }];
    files.extend(problems.iter().map(|p| File {
        name: format!("{}.pddl", p.id),
        text: problem(artifact, object, &names, p),
    }));
    Ok(Export {
        folder: names.item,
        files,
    })
}

fn check_costs(artifact: &Artifact, object: ObjectId) -> Result<(), CostsTooLarge> {
    let Some(o) = artifact.objects.get(object.index()) else {
        return Ok(());
    };
    let n_states = o.graph.nodes.len().max(1);
    let weight = o.graph.arcs.iter().map(|a| a.weight).fold(0.0, f64::max);
    let largest_allowed = (MAX_PATH_COST / n_states as f64).floor() / COST_SCALE;
    if (weight * COST_SCALE).round() * n_states as f64 > MAX_PATH_COST {
        return Err(CostsTooLarge {
            object: o.name.clone(),
            weight,
            n_states,
            largest_allowed,
        });
    }
    Ok(())
}

/// Text for a `;` comment: one line, no control characters.
fn comment(text: &str) -> String {
    text.chars()
        .map(|c| if c.is_control() { '?' } else { c })
        .collect()
}

/// A state as people write it: `EE.GRASP in WS`.
fn state_words(artifact: &Artifact, object: ObjectId, node: NodeId) -> String {
    let Some(n) = artifact
        .objects
        .get(object.index())
        .and_then(|o| o.graph.nodes.get(node.index()))
    else {
        return "?".to_string();
    };
    comment(&format!(
        "{}.{} in {}",
        artifact.end_effector_name(n.end_effector),
        artifact.grasp_name(object, n.grasp),
        artifact.workspace_name(n.workspace)
    ))
}

/// What the actions are, for the domain's header.
fn provenance(artifact: &Artifact, object: ObjectId) -> String {
    let n_pruned = artifact
        .objects
        .get(object.index())
        .map_or(0, |o| o.graph.pruned.len());
    match &artifact.verification {
        Some(v) => format!(
            "verified with seed {}: every action has a witness; {n_pruned} infeasible arcs left out",
            v.seed
        ),
        None if cellc_driver::has_arms(artifact) => {
            "not verified (the artifact was built with --no-verify)".to_string()
        }
        None => "an abstract cell: no geometry to verify".to_string(),
    }
}

/// The domain: types, the states as constants, the predicates, one action per arc and
/// `arrive`.
pub fn domain(artifact: &Artifact, object: ObjectId, names: &Names) -> String {
    let mut out = String::new();
    let Some(o) = artifact.objects.get(object.index()) else {
        return out;
    };
    let w = &artifact.weights;
    let _ = writeln!(
        out,
        "; cellc PDDL domain: the object-state graph of `{}` in cell `{}`",
        comment(&o.name),
        comment(&artifact.cell)
    );
    let _ = writeln!(
        out,
        "; {} states, {} arc actions, {}",
        o.graph.nodes.len(),
        o.graph.arcs.len(),
        provenance(artifact, object)
    );
    let _ = writeln!(
        out,
        "; action cost: the arc's weight x {COST_SCALE}, rounded (move {} -> {}, transition {} -> {})",
        w.move_weight,
        action_cost(w.move_weight),
        w.transition_weight,
        action_cost(w.transition_weight)
    );
    let _ = writeln!(out, "(define (domain {})", names.domain);
    out.push_str("  (:requirements :strips :typing :action-costs)\n");
    out.push_str("  (:types item state)\n");
    if !names.states.is_empty() {
        out.push_str("  (:constants\n");
        for s in &names.states {
            let _ = writeln!(out, "    {s}");
        }
        out.push_str("    - state)\n");
    }
    out.push_str(concat!(
        "  (:predicates\n",
        "    (at ?o - item ?s - state)\n",
        "    (moved ?o - item)\n",
        "    (target ?s - state)\n",
        "    (arrived ?o - item))\n",
        "  (:functions (total-cost) - number)\n",
    ));
    for (arc, action) in o.graph.arcs.iter().zip(&names.actions) {
        let (Some(from), Some(to)) = (
            names.states.get(arc.from as usize),
            names.states.get(arc.to as usize),
        ) else {
            continue;
        };
        let _ = write!(
            out,
            concat!(
                "  (:action {action}\n",
                "    :parameters (?o - item)\n",
                "    :precondition (at ?o {from})\n",
                "    :effect (and (not (at ?o {from})) (at ?o {to}) (moved ?o)\n",
                "      (increase (total-cost) {cost})))\n",
            ),
            action = action,
            from = from,
            to = to,
            cost = action_cost(arc.weight)
        );
    }
    out.push_str(concat!(
        "  (:action arrive\n",
        "    :parameters (?o - item ?s - state)\n",
        "    :precondition (and (at ?o ?s) (target ?s))\n",
        "    :effect (and (not (at ?o ?s)) (arrived ?o))))\n",
    ));
    out
}

/// One problem: the item, its start, its goal, total cost minimised.
pub fn problem(artifact: &Artifact, object: ObjectId, names: &Names, p: &Problem) -> String {
    let state = |n: NodeId| names.states.get(n.index()).map_or("?", String::as_str);
    let item = &names.item;
    let mut out = String::new();
    let _ = writeln!(
        out,
        "; cellc PDDL problem: {} for `{}` in cell `{}`",
        comment(&p.title),
        comment(artifact.object_name(object)),
        comment(&artifact.cell)
    );
    let _ = writeln!(out, "; start: {}", state_words(artifact, object, p.start));
    let goals: Vec<String> = p
        .goals
        .iter()
        .map(|&g| state_words(artifact, object, g))
        .collect();
    match goals.as_slice() {
        [one] => {
            let _ = writeln!(out, "; goal: {one}");
        }
        many => {
            let _ = writeln!(
                out,
                "; goal: any of {} (the targets; the plan ends with `arrive`)",
                if many.is_empty() {
                    "no state".to_string()
                } else {
                    many.join(", ")
                }
            );
        }
    }
    if p.must_leave {
        out.push_str(
            "; the start is the goal state at another pose: the object must leave it (moved)\n",
        );
    }
    let _ = writeln!(out, "(define (problem {})", p.id);
    let _ = writeln!(out, "  (:domain {})", names.domain);
    let _ = writeln!(out, "  (:objects {item} - item)");
    out.push_str("  (:init\n");
    let _ = writeln!(out, "    (at {item} {})", state(p.start));
    let single = match p.goals.as_slice() {
        [one] => Some(*one),
        _ => None,
    };
    if single.is_none() {
        for &g in &p.goals {
            let _ = writeln!(out, "    (target {})", state(g));
        }
    }
    out.push_str("    (= (total-cost) 0))\n");
    let reached = match single {
        Some(g) => format!("(at {item} {})", state(g)),
        None => format!("(arrived {item})"),
    };
    if p.must_leave {
        let _ = writeln!(out, "  (:goal (and {reached} (moved {item})))");
    } else {
        let _ = writeln!(out, "  (:goal {reached})");
    }
    out.push_str("  (:metric minimize (total-cost)))\n");
    out
}
