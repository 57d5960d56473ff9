//! Build-time verification: every arc of every object graph is checked kinematically
//! once, and either gets a witness (an object pose and joint configurations that realise
//! it, collision-free and within limits) or is pruned with a reason.
//!
//! Handoff and resting-pose feasibility depend only on (end-effectors, grasps, workspace),
//! never on a request, so checking them here, in parallel, means the runtime planner
//! rarely backtracks. Results are deterministic for a seed: each check draws from its own
//! generator, seeded from the seed and the check's identity, so thread scheduling cannot
//! change them.
//!
//! What each arc needs:
//! - move S(e, g, wi) -> S(e, g, wj): e holds the object with g somewhere in wj;
//! - transition between two arms in w (a handoff): one object pose in w where both hold
//!   it at once, found with the closed-chain solver;
//! - transition between an arm and a fixed surface in w: a resting pose on the surface
//!   inside w that the arm reaches with its grasp (`rest.rs`);
//! - transition between two grasps of one arm (kept by the compiler, with a warning, when
//!   a cell or an imported database lists one): refused, since nothing would hold the
//!   object while the hand lets go and takes it again; the pruned arc says so.
//!
//! A move into a state is realised by the same holding pose whatever workspace it comes
//! from, and a handoff A -> B by the same configurations as B -> A, so checks are keyed
//! by what they depend on and shared between arcs.
//!
//! Here: the questions and their sharing; `attempt.rs`: one arm reaching one object pose,
//! and what a failed check reports; `witness.rs`: how each question is answered. Every
//! state is judged by [`crate::validity::SceneValidity`].

mod attempt;
mod chains;
mod hands;
pub mod preflight;
mod witness;

use std::collections::BTreeMap;

use cellc_schema::{
    self as schema, ArcKind, Artifact, EndEffectorId, GraspId, Infeasibility, ObjectId, Witness,
    WorkspaceId,
};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

use crate::kinematics::closed_chain::HandoffOptions;
use crate::kinematics::IkOptions;
use crate::scene::{Holder, Scene, SceneScratch};

/// Verification settings.
#[derive(Clone, Debug)]
pub struct VerifyOptions {
    /// Seed of every randomized solver.
    pub seed: u64,
    /// Object poses tried per check before giving up.
    pub placements: u32,
    /// Inverse-kinematics settings.
    pub ik: IkOptions,
    /// Closed-chain (handoff) settings.
    pub handoff: HandoffOptions,
}

impl Default for VerifyOptions {
    fn default() -> VerifyOptions {
        VerifyOptions {
            seed: 0,
            // Failing checks dominate the time: a few placements, each with a modest number
            // of restarts, find the feasible arcs of real cells (measured on the shipped
            // cells) while keeping infeasible ones cheap.
            placements: 16,
            // A hold or rest whose pose an arm reaches converges from its home or within a
            // few restarts; measured on `vito_full.cell` (25,100 arcs), 6 restarts keep
            // the same arcs as 12 (to within the few that any change of random stream
            // moves) with half the IK work.
            ik: IkOptions {
                restarts: 6,
                ..IkOptions::default()
            },
            // A closed-chain try that has not closed in 60 iterations almost never closes
            // later (on `vito_full.cell`, 60 and 200 iterations keep the same arcs to
            // within a few), and failing tries are most of the cost.
            handoff: HandoffOptions {
                ik: IkOptions {
                    restarts: 20,
                    max_iterations: 60,
                    ..HandoffOptions::default().ik
                },
                ..HandoffOptions::default()
            },
        }
    }
}

/// What verification found, for reporting.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct VerifyReport {
    /// Arcs checked.
    pub n_checked: u64,
    /// Arcs pruned.
    pub n_pruned: u64,
    /// Distinct feasibility checks run (arcs share checks).
    pub n_checks: u64,
    /// Closed-chain problems solved for the handoff checks' placements (checks share
    /// them: `chains.rs`).
    pub n_chains: u64,
}

/// One feasibility question, keyed by everything its answer depends on.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
enum Check {
    /// Arm `e` holds the object with grasp `g` somewhere in workspace `w`.
    Hold {
        object: ObjectId,
        e: EndEffectorId,
        g: GraspId,
        w: WorkspaceId,
    },
    /// Arms (or an arm and a conveyor) `a` with `ga` and `b` with `gb` hold it at once in
    /// `w`; stored with (a, ga) <= (b, gb) so both directions share it.
    Handoff {
        object: ObjectId,
        a: EndEffectorId,
        ga: GraspId,
        b: EndEffectorId,
        gb: GraspId,
        w: WorkspaceId,
    },
    /// Arm `arm` with `g` and surface `surface` with resting pose `r` in `w`.
    Rest {
        object: ObjectId,
        arm: EndEffectorId,
        g: GraspId,
        surface: EndEffectorId,
        r: GraspId,
        w: WorkspaceId,
    },
    /// Arm `e` changing its own grasp from `from` to `to` in `w`.
    Regrasp {
        object: ObjectId,
        e: EndEffectorId,
        from: GraspId,
        to: GraspId,
        w: WorkspaceId,
    },
}

/// What [`check_and_verify`] found: the scene as a whole, and the arcs unless the scene
/// blocked them.
#[derive(Clone, Debug)]
pub struct Checked {
    /// The scene as a whole (homes, permanent contacts, grasps away from their hands).
    pub preflight: preflight::Preflight,
    /// The arcs' verification; `None` when the preflight [blocks
    /// verification](preflight::Preflight::blocks_verification) and the artifact is left
    /// as it was.
    pub report: Option<VerifyReport>,
}

/// The scene as a whole, then, unless it is wrong whatever the arc, every arc: the one
/// sequence `cellc build` and [`crate::Cell::verify`] both run, so that an embedder gets
/// the build's answer. A scene with a permanent contact or a colliding home is not
/// verified arc by arc, since every arc would be pruned for the same reason and the
/// artifact would read as a cell with no way anywhere.
pub fn check_and_verify(
    artifact: &mut Artifact,
    scene: &Scene,
    options: &VerifyOptions,
    progress: &(dyn Fn(u64, u64) + Sync),
) -> Checked {
    let preflight = preflight::preflight(artifact, scene);
    let report =
        (!preflight.blocks_verification()).then(|| verify(artifact, scene, options, progress));
    Checked { preflight, report }
}

/// Verifies every arc of `artifact` in place: feasible arcs get witnesses, infeasible ones
/// move to `pruned`. `progress` is called with (done, total) as checks finish.
pub fn verify(
    artifact: &mut Artifact,
    scene: &Scene,
    options: &VerifyOptions,
    progress: &(dyn Fn(u64, u64) + Sync),
) -> VerifyReport {
    // Which check each arc needs (None: nothing geometric to check, e.g. abstract holders).
    let mut arc_checks: Vec<Vec<Option<Check>>> = Vec::new();
    let mut checks: BTreeMap<Check, ()> = BTreeMap::new();
    for (o, object) in artifact.objects.iter().enumerate() {
        let mut per_arc = Vec::with_capacity(object.graph.arcs.len());
        for arc in &object.graph.arcs {
            let check = check_of(scene, ObjectId(o as u32), object, arc);
            if let Some(c) = check {
                checks.insert(c, ());
            }
            per_arc.push(check);
        }
        arc_checks.push(per_arc);
    }
    let checks: Vec<Check> = checks.into_keys().collect();
    let turns = hands::TurnTable::new(artifact, scene, &checks);
    let chains = chains::ChainTable::new();
    let total = checks.len() as u64;
    let done = std::sync::atomic::AtomicU64::new(0);
    let results: Vec<(Check, Result<Witness, Infeasibility>)> = checks
        .par_iter()
        .map_init(SceneScratch::default, |scratch, &check| {
            let result =
                witness::run_check(artifact, scene, scratch, options, (&turns, &chains), check);
            let n = done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
            progress(n, total);
            (check, result)
        })
        .collect();
    let results: BTreeMap<Check, Result<Witness, Infeasibility>> = results.into_iter().collect();

    let mut report = VerifyReport {
        n_checks: total,
        n_chains: chains.len() as u64,
        ..VerifyReport::default()
    };
    for (object, per_arc) in artifact.objects.iter_mut().zip(arc_checks) {
        let graph = &mut object.graph;
        let mut witness_of: BTreeMap<Check, u32> = BTreeMap::new();
        let mut kept = Vec::with_capacity(graph.arcs.len());
        for (mut arc, check) in graph.arcs.drain(..).zip(per_arc) {
            let Some(check) = check else {
                kept.push(arc);
                continue;
            };
            report.n_checked += 1;
            match &results[&check] {
                Ok(witness) => {
                    let index = *witness_of.entry(check).or_insert_with(|| {
                        graph.witnesses.push(witness.clone());
                        graph.witnesses.len() as u32 - 1
                    });
                    arc.witness = Some(index);
                    kept.push(arc);
                }
                Err(reason) => {
                    report.n_pruned += 1;
                    graph.pruned.push(schema::PrunedArc {
                        arc,
                        reason: reason.clone(),
                    });
                }
            }
        }
        graph.arcs = kept;
    }
    artifact.verification = Some(schema::Verification {
        seed: options.seed,
        n_checked: report.n_checked,
        n_pruned: report.n_pruned,
    });
    report
}

/// The question an arc asks, or `None` when it has nothing geometric to check (abstract
/// holders).
fn check_of(
    scene: &Scene,
    object: ObjectId,
    obj: &schema::Object,
    arc: &schema::Arc,
) -> Option<Check> {
    let from = obj.graph.nodes[arc.from as usize];
    let to = obj.graph.nodes[arc.to as usize];
    let holder = |e: EndEffectorId| &scene.holders[e.index()];
    match arc.kind {
        ArcKind::Move => match holder(to.end_effector) {
            Holder::Arm { .. } => Some(Check::Hold {
                object,
                e: to.end_effector,
                g: to.grasp,
                w: to.workspace,
            }),
            _ => None,
        },
        ArcKind::Transition => {
            let w = to.workspace;
            let (a, ga, b, gb) = (from.end_effector, from.grasp, to.end_effector, to.grasp);
            match (holder(a), holder(b)) {
                (Holder::Arm { .. }, Holder::Arm { .. }) if a == b => Some(Check::Regrasp {
                    object,
                    e: a,
                    from: ga,
                    to: gb,
                    w,
                }),
                (Holder::Arm { .. }, Holder::Arm { .. }) => {
                    let ((a, ga), (b, gb)) = if (a, ga) <= (b, gb) {
                        ((a, ga), (b, gb))
                    } else {
                        ((b, gb), (a, ga))
                    };
                    Some(Check::Handoff {
                        object,
                        a,
                        ga,
                        b,
                        gb,
                        w,
                    })
                }
                (Holder::Arm { .. }, Holder::Surface { .. }) => Some(Check::Rest {
                    object,
                    arm: a,
                    g: ga,
                    surface: b,
                    r: gb,
                    w,
                }),
                (Holder::Surface { .. }, Holder::Arm { .. }) => Some(Check::Rest {
                    object,
                    arm: b,
                    g: gb,
                    surface: a,
                    r: ga,
                    w,
                }),
                _ => None,
            }
        }
    }
}

/// The generator of one check: the same for a given seed and check, whatever thread runs
/// it and in whatever order.
fn rng_for(seed: u64, check: &Check) -> ChaCha8Rng {
    let words: Vec<u32> = match *check {
        Check::Hold { object, e, g, w } => vec![1, object.0, e.0, g.0, w.0],
        Check::Handoff {
            object,
            a,
            ga,
            b,
            gb,
            w,
        } => vec![2, object.0, a.0, ga.0, b.0, gb.0, w.0],
        Check::Rest {
            object,
            arm,
            g,
            surface,
            r,
            w,
        } => vec![3, object.0, arm.0, g.0, surface.0, r.0, w.0],
        Check::Regrasp {
            object,
            e,
            from,
            to,
            w,
        } => vec![4, object.0, e.0, from.0, to.0, w.0],
    };
    ChaCha8Rng::seed_from_u64(mix(seed, words.into_iter().map(u64::from)))
}

/// A cheap, well-mixed hash of `words` (SplitMix64 steps) under `seed`.
fn mix(seed: u64, words: impl IntoIterator<Item = u64>) -> u64 {
    let mut h: u64 = seed ^ 0x9E37_79B9_7F4A_7C15;
    for word in words {
        h = h.wrapping_add(word).wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = h;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        h = z ^ (z >> 31);
    }
    h
}
