//! Closed-chain solves shared between the handoff checks of two arms.
//!
//! A handoff's closed chain (`crate::kinematics::closed_chain`) depends on the two grasps only through
//! where each puts the object's origin in its tip frame and through the rotation between
//! them, `R(ga) R(gb)⁻¹`: the residual's position rows compare the two estimates of the
//! origin, its rotation rows are `log(R(tip_a) R(ga) R(gb)⁻¹ R(tip_b)⁻¹)`, and the
//! Jacobian's points are the origin's estimates. Grasp sets are written as families
//! (`every 15 deg about z`, or one grasp per yaw as the generated lines of
//! `benches/line.rs` have them), and two families exchanged give the same relative
//! rotation over and over: in the 70-grasp line, the 4,900 grasp pairs of two neighbouring
//! arms are about 120 distinct chains. Verification solved each pair on its own, 16
//! placements each; the 50-arm line with 10^6 arcs spent 95% of 520 s there.
//!
//! So the chain is solved once per [`ChainKey`]: the two arms, the grasps' origins (exact
//! bits), their relative rotation rounded to 2⁻³² (about 2·10⁻¹⁰ rad), and the target
//! point and box (exact bits; a check draws its targets from a stream of its chain, not
//! of the check, so the checks that are one chain ask about the same points), and where
//! the solve starts ([`Start`]). The solve is of the key's own problem (the rounded
//! rotation, grasps made of it) with a generator seeded from the key, so its answer is a
//! function of the key alone: whichever check asks first, and on whatever thread, the
//! answer is the same, and the artifact's bytes do not depend on scheduling. Each check
//! then takes the joints only if they close its own chain to the solver's tolerances
//! (`closed_chain::closes_at`, on the tips the table keeps), with its own grasps; when rounding put a solution just over a tolerance, the check solves its own
//! problem (from the same generator), so no witness rests on another problem's closure.
//! What the object collides with is never shared: every check runs its own state check.
//!
//! The table holds one entry per distinct chain asked, which is at most the placements of
//! every handoff check (it is dropped with the verification).

use std::hash::BuildHasher;
use std::sync::{Arc, Mutex, OnceLock};

use cellc_schema::{EndEffectorId, WorkspaceId};
use nalgebra as na;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rustc_hash::{FxBuildHasher, FxHashMap};

use crate::kinematics::closed_chain::{
    closes_at, solve_handoff, HandoffOptions, HandoffProblem, HandoffSolution,
};
use crate::kinematics::IkError;
use crate::math::{Iso, Quat};
use crate::termination::Termination;

/// The scale of the relative rotation's rounding: quaternion components are kept to
/// multiples of 2⁻³². Far finer than the loop-closure rotation tolerance (10⁻³ rad by
/// default), far coarser than the rounding of the quaternion products that make two equal
/// relative rotations differ (10⁻¹⁶).
const ROTATION_GRID: f64 = 4_294_967_296.0;

/// A handoff's closed chain without its target: the two arms, where each grasp puts the
/// object's origin in its tip frame, and the grasps' relative rotation.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(super) struct Chain {
    a: EndEffectorId,
    b: EndEffectorId,
    /// The object's origin in A's and B's tip frames, as bits.
    origin_a: [u64; 3],
    origin_b: [u64; 3],
    /// `R(ga) R(gb)⁻¹` on the grid, the sign fixed so that q and -q are one chain.
    relative: [i64; 4],
}

impl Chain {
    /// The chain of `a` holding the object with `grasp_a` and `b` with `grasp_b`.
    pub(super) fn of(a: EndEffectorId, b: EndEffectorId, grasp_a: &Iso, grasp_b: &Iso) -> Chain {
        let q = (grasp_a.rotation * grasp_b.rotation.inverse()).into_inner();
        let mut relative = [q.w, q.i, q.j, q.k].map(|c| (c * ROTATION_GRID).round() as i64);
        // On the grid, not before: a half turn has w = ±1e-17, whose sign is noise.
        if relative.iter().find(|&&c| c != 0).is_some_and(|&c| c < 0) {
            relative = relative.map(|c| -c);
        }
        Chain {
            a,
            b,
            origin_a: bits(&grasp_a.translation.vector),
            origin_b: bits(&grasp_b.translation.vector),
            relative,
        }
    }

    fn words(&self) -> impl Iterator<Item = u64> + '_ {
        [u64::from(self.a.0), u64::from(self.b.0)]
            .into_iter()
            .chain(self.origin_a)
            .chain(self.origin_b)
            .chain(self.relative.map(|c| c as u64))
    }

    /// The generator of the object positions a handoff check of this chain tries (its
    /// first turn's chain): every grasp pair that is this chain tries the same positions
    /// and so asks the table the same questions, while other chains of the same arms try
    /// others, so that the witnesses of one workspace are not all at one point.
    pub(super) fn targets(&self, seed: u64, w: WorkspaceId) -> ChaCha8Rng {
        let words = [5, u64::from(w.0)].into_iter().chain(self.words());
        ChaCha8Rng::seed_from_u64(super::mix(seed, words))
    }
}

fn bits(v: &na::Vector3<f64>) -> [u64; 3] {
    [v.x.to_bits(), v.y.to_bits(), v.z.to_bits()]
}

/// Everything a handoff's closed chain depends on: the chain and where the object should
/// be.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
struct ChainKey {
    chain: Chain,
    target: [u64; 3],
    bounds: Option<[u64; 6]>,
    start: Start,
}

/// Where a solve starts.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(super) enum Start {
    /// From the arms' homes, where most handoffs close (and close the same way every
    /// time).
    Homes,
    /// From configurations drawn from the key's generator: in the second half of a
    /// check's placements, once a chain of the first half closed into a collision, since
    /// a solve from the homes tends to close the next chain in the same basin, the same
    /// collision (in `cells/two_pandas.cell`, a forearm in the other arm's wrist placement
    /// after placement). Not sooner: a drawn start closes the chain in whatever posture
    /// it lands, and an arm left in an odd one makes long motions (drawn from the first
    /// collision on, the assembly line's arm 3 took a 30 s retreat from its handoff
    /// instead of 6 s, and its request planned in 0.8 s instead of 0.06 s).
    Drawn,
}

impl ChainKey {
    fn new(
        a: EndEffectorId,
        b: EndEffectorId,
        problem: &HandoffProblem<'_>,
        start: Start,
    ) -> ChainKey {
        ChainKey {
            start,
            chain: Chain::of(a, b, &problem.grasp_a, &problem.grasp_b),
            target: bits(&problem.target.coords),
            bounds: problem.bounds.map(|(min, max)| {
                let (l, u) = (bits(&min.coords), bits(&max.coords));
                [l[0], l[1], l[2], u[0], u[1], u[2]]
            }),
        }
    }

    /// The key's own problem: A's grasp without rotation, B's turned by the rounded
    /// relative rotation's inverse, so that `R(ga') R(gb')⁻¹` is that rotation.
    fn problem<'r>(&self, of: &HandoffProblem<'r>) -> HandoffProblem<'r> {
        let [w, i, j, k] = self.chain.relative.map(|c| c as f64 / ROTATION_GRID);
        let relative = Quat::from_quaternion(na::Quaternion::new(w, i, j, k));
        HandoffProblem {
            grasp_a: Iso::from_parts(of.grasp_a.translation, Quat::identity()),
            grasp_b: Iso::from_parts(of.grasp_b.translation, relative.inverse()),
            ..*of
        }
    }

    /// The generator of the key's solve: a function of the seed and the key.
    fn rng(&self, seed: u64) -> ChaCha8Rng {
        let words = [6, self.start as u64]
            .into_iter()
            .chain(self.chain.words())
            .chain(self.target)
            .chain(self.bounds.into_iter().flatten());
        ChaCha8Rng::seed_from_u64(super::mix(seed, words))
    }
}

/// A chain's solution as the table keeps it.
pub(super) struct Joints {
    /// A's joints, then B's.
    q: Box<[f64]>,
    /// The two tips' world poses at `q`, so that a check tests its own closure without
    /// forward kinematics.
    tips: (Iso, Iso),
    /// Whether the two arms alone, without the object, collide at `q`: a fact of the
    /// joints, so it is decided once, by the first check that asks, for every check that
    /// takes them (an object only adds bodies, so arms that collide without it collide
    /// with it). In the 50-arm line most handoffs end so, the two forearms in each other.
    arms_collide: OnceLock<bool>,
}

impl Joints {
    /// Whether the arms alone collide, `decide` asked only the first time.
    pub(super) fn arms_collide(&self, decide: impl FnOnce() -> bool) -> bool {
        *self.arms_collide.get_or_init(decide)
    }
}

/// A solve's answer: the joints, or the solver's error.
type Solved = Result<Arc<Joints>, IkError>;

/// The answers of the closed chains asked so far, shared by every check of a verification.
pub(super) struct ChainTable {
    shards: Vec<Mutex<FxHashMap<ChainKey, Solved>>>,
    hasher: FxBuildHasher,
}

/// Shards of the table: a solve takes a tenth of a millisecond and a look-up a few tens of
/// nanoseconds, so contention is rare; shards keep it so on machines with many cores.
const SHARDS: usize = 64;

impl ChainTable {
    pub(super) fn new() -> ChainTable {
        ChainTable {
            shards: (0..SHARDS)
                .map(|_| Mutex::new(FxHashMap::default()))
                .collect(),
            hasher: FxBuildHasher,
        }
    }

    /// How many chains were solved.
    pub(super) fn len(&self) -> usize {
        self.shards
            .iter()
            .map(|s| {
                s.lock()
                    .unwrap_or_else(std::sync::PoisonError::into_inner)
                    .len()
            })
            .sum()
    }

    /// Joints for `a` and `b` holding the object as `problem` asks, found from the arms'
    /// homes (`seeds`) or, with [`Start::Drawn`], from configurations drawn for the key,
    /// or why there are none; the same for a given seed, problem and start. With the
    /// solution, the table's entry when the joints are the chain's (its verdict
    /// on the arms alone is shared), `None` when this problem was solved on its own.
    pub(super) fn solve(
        &self,
        seed: u64,
        (a, b): (EndEffectorId, EndEffectorId),
        problem: &HandoffProblem<'_>,
        (seeds, start): ((&[f64], &[f64]), Start),
        options: &HandoffOptions,
    ) -> Result<(HandoffSolution, Option<Arc<Joints>>), IkError> {
        let key = ChainKey::new(a, b, problem, start);
        let shard = &self.shards[(self.hasher.hash_one(key) as usize) % SHARDS];
        let known = shard
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .get(&key)
            .cloned();
        let (robot_a, base_a) = problem.a;
        let (robot_b, base_b) = problem.b;
        // The generator and the start configurations of a solve of `key`'s.
        let begin = || {
            let mut rng = key.rng(seed);
            let (mut qa, mut qb) = (seeds.0.to_vec(), seeds.1.to_vec());
            if start == Start::Drawn {
                robot_a.sample_configuration(&mut rng, &mut qa);
                robot_b.sample_configuration(&mut rng, &mut qb);
            }
            (rng, qa, qb)
        };
        let solved = match known {
            Some(solved) => solved,
            None => {
                let (mut rng, qa, qb) = begin();
                let solved = solve_handoff(
                    &key.problem(problem),
                    &qa,
                    &qb,
                    &mut rng,
                    options,
                    &Termination::never(),
                )
                .map(|s| {
                    Arc::new(Joints {
                        tips: (
                            robot_a.tip_pose(&base_a, &s.qa),
                            robot_b.tip_pose(&base_b, &s.qb),
                        ),
                        q: [s.qa, s.qb].concat().into(),
                        arms_collide: OnceLock::new(),
                    })
                });
                // Another thread may have solved the same key meanwhile: the same answer.
                shard
                    .lock()
                    .unwrap_or_else(std::sync::PoisonError::into_inner)
                    .insert(key, solved.clone());
                solved
            }
        };
        let n_a = robot_a.n_joints();
        match solved {
            Ok(joints)
                if joints.q.len() == n_a + robot_b.n_joints()
                    && closes_at(problem, &joints.tips.0, &joints.tips.1, options) =>
            {
                let solution = HandoffSolution {
                    qa: joints.q[..n_a].to_vec(),
                    qb: joints.q[n_a..].to_vec(),
                    object: joints.tips.0 * problem.grasp_a,
                };
                Ok((solution, Some(joints)))
            }
            // Closed for the rounded rotation, not to the tolerances for this one: solve
            // this problem itself.
            Ok(_) => {
                let (mut rng, qa, qb) = begin();
                solve_handoff(problem, &qa, &qb, &mut rng, options, &Termination::never())
                    .map(|s| (s, None))
            }
            Err(error) => Err(error),
        }
    }
}

#[cfg(test)]
mod tests {
    //! The table shares what is one chain, and only that; its answers close each asker's
    //! own chain and do not depend on the order of the asking.

    use std::f64::consts::{FRAC_PI_2, PI};

    use super::*;
    use crate::kinematics::closed_chain::closes;
    use crate::math::{Point, Vec3};
    use crate::robot::Robot;
    use crate::MemoryFiles;

    const A: EndEffectorId = EndEffectorId(0);
    const B: EndEffectorId = EndEffectorId(2);

    fn lwr() -> Robot {
        let urdf = include_str!("../../../cells/robots/kuka_lwr4.urdf");
        Robot::from_urdf(
            urdf,
            "robot.urdf",
            "lwr_base_link",
            "lwr_flange",
            &MemoryFiles::default(),
        )
        .expect("the URDF loads")
    }

    /// Two LWRs facing each other across a metre, as the handoff tests of the kinematics
    /// place them.
    fn bases() -> (Iso, Iso) {
        (
            Iso::translation(0.0, -0.5, 0.0) * Iso::rotation(Vec3::z() * FRAC_PI_2),
            Iso::translation(0.0, 0.5, 0.0) * Iso::rotation(Vec3::z() * -FRAC_PI_2),
        )
    }

    /// A family member: the object 0.1 m out of the flange, turned by `yaw` about its own
    /// axis; B's members flipped, so that the two hands hold it from opposite ends.
    fn grasp(yaw_deg: f64, flipped: bool) -> Iso {
        let flip = if flipped { PI } else { 0.0 };
        Iso::translation(0.0, 0.0, 0.1)
            * Iso::rotation(Vec3::x() * flip)
            * Iso::rotation(Vec3::z() * yaw_deg.to_radians())
    }

    fn problem<'r>(robot: &'r Robot, grasp_a: Iso, grasp_b: Iso) -> HandoffProblem<'r> {
        let (base_a, base_b) = bases();
        HandoffProblem {
            a: (robot, base_a),
            b: (robot, base_b),
            grasp_a,
            grasp_b,
            target: Point::new(0.3, 0.0, 0.6),
            bounds: Some((Point::new(0.15, -0.15, 0.45), Point::new(0.45, 0.15, 0.75))),
        }
    }

    /// Relative rotation `R(ga) R(gb)⁻¹` of two yaws.
    fn relative(a: &Iso, b: &Iso) -> [f64; 4] {
        let q = (a.rotation * b.rotation.inverse()).into_inner();
        [q.w, q.i, q.j, q.k]
    }

    #[test]
    fn grasp_pairs_of_one_relative_rotation_share_one_solve_and_each_closes_its_own_chain() {
        let robot = lwr();
        let home = vec![0.0; robot.n_joints()];
        let options = HandoffOptions::default();
        let table = ChainTable::new();
        // R(ga) R(gb)⁻¹ = Rz(ya - yb) Rx(π)⁻¹: these four pairs are one chain, computed by
        // four different products.
        let pairs = [(0.0, 30.0), (10.0, 40.0), (21.0, 51.0), (30.0, 60.0)]
            .map(|(ya, yb)| (grasp(ya, false), grasp(yb, true)));
        let rotations: Vec<[f64; 4]> = pairs.iter().map(|(a, b)| relative(a, b)).collect();
        assert!(
            rotations.windows(2).any(|w| w[0] != w[1]),
            "the rounding must be what makes them one: {rotations:?}"
        );
        let mut joints = Vec::new();
        for (ga, gb) in pairs {
            let p = problem(&robot, ga, gb);
            let (s, shared) = table
                .solve(7, (A, B), &p, ((&home, &home), Start::Homes), &options)
                .expect("the facing arms hand over");
            assert!(shared.is_some(), "the chain's own joints");
            assert!(closes(&p, &s.qa, &s.qb, &options));
            // The object is A's own estimate, with A's own grasp.
            let object = robot.tip_pose(&p.a.1, &s.qa) * ga;
            assert_eq!(s.object, object);
            joints.push([s.qa, s.qb].concat());
        }
        assert_eq!(table.len(), 1);
        assert!(joints.windows(2).all(|w| w[0] == w[1]));
        // Another sum is another chain.
        let p = problem(&robot, grasp(0.0, false), grasp(45.0, true));
        table
            .solve(7, (A, B), &p, ((&home, &home), Start::Homes), &options)
            .expect("hands over");
        assert_eq!(table.len(), 2);
    }

    #[test]
    fn answers_do_not_depend_on_the_order_of_asking() {
        let robot = lwr();
        let home = vec![0.0; robot.n_joints()];
        let options = HandoffOptions::default();
        let problems: Vec<HandoffProblem<'_>> = [(0.0, 30.0), (10.0, 40.0), (0.0, 90.0)]
            .iter()
            .map(|&(ya, yb)| problem(&robot, grasp(ya, false), grasp(yb, true)))
            .collect();
        let answers = |order: &[usize]| {
            let table = ChainTable::new();
            let mut out = vec![None; problems.len()];
            for &i in order {
                let s = table.solve(
                    3,
                    (A, B),
                    &problems[i],
                    ((&home, &home), Start::Homes),
                    &options,
                );
                out[i] = Some(s.map(|(s, _)| [s.qa, s.qb].concat()));
            }
            out
        };
        let forward = answers(&[0, 1, 2]);
        assert_eq!(forward, answers(&[2, 1, 0]));
        assert_eq!(forward, answers(&[1, 2, 0]));
        // Asked alone, the second is what it is when the first was asked before it: the
        // table answered it from the first's solve, which is its own chain's.
        assert_eq!(forward[1], answers(&[1])[1]);
    }

    #[test]
    fn a_drawn_start_is_another_solve_of_the_same_chain() {
        let robot = lwr();
        let home = vec![0.0; robot.n_joints()];
        let options = HandoffOptions::default();
        let table = ChainTable::new();
        let p = problem(&robot, grasp(0.0, false), grasp(30.0, true));
        let solve = |start| {
            let (s, shared) = table
                .solve(5, (A, B), &p, ((&home, &home), start), &options)
                .expect("hands over");
            assert!(shared.is_some());
            assert!(closes(&p, &s.qa, &s.qb, &options));
            [s.qa, s.qb].concat()
        };
        let from_homes = solve(Start::Homes);
        let drawn = solve(Start::Drawn);
        assert_eq!(table.len(), 2);
        assert_ne!(from_homes, drawn, "the drawn start found the homes' answer");
        // Asked again, each start is answered from the table.
        assert_eq!(solve(Start::Drawn), drawn);
        assert_eq!(table.len(), 2);
    }

    #[test]
    fn a_half_turn_is_one_key_whatever_the_sign_of_its_rounding() {
        let half_turn = |w: f64| {
            let q = Quat::from_quaternion(na::Quaternion::new(w, 1.0, 0.0, 0.0));
            Iso::from_parts(Vec3::new(0.0, 0.0, 0.1).into(), q)
        };
        let key = |gb: Iso| Chain::of(A, B, &Iso::identity(), &gb);
        assert_eq!(key(half_turn(1e-17)), key(half_turn(-1e-17)));
        assert_ne!(key(half_turn(1e-17)), key(half_turn(0.3)));
    }

    #[test]
    fn a_solve_the_rounding_puts_over_a_tolerance_is_solved_again_for_the_asker() {
        let robot = lwr();
        let home = vec![0.0; robot.n_joints()];
        // A rotation tolerance finer than the grid: the rounded chain's solution misses
        // the asker's by up to the rounding, 10⁻¹⁰ rad.
        let mut options = HandoffOptions::default();
        options.ik.rotation_tolerance = 1e-11;
        options.ik.position_tolerance = 1e-9;
        options.ik.max_iterations = 200;
        let off_grid = Iso::rotation(Vec3::y() * 3e-10);
        let p = problem(&robot, grasp(0.0, false), grasp(30.0, true) * off_grid);
        let table = ChainTable::new();
        let (s, shared) = table
            .solve(1, (A, B), &p, ((&home, &home), Start::Homes), &options)
            .expect("hands over");
        assert!(shared.is_none(), "solved on its own");
        assert!(closes(&p, &s.qa, &s.qb, &options));
        // The table's own answer is the rounded chain's, and it does not close this one:
        // the answer above was solved again.
        let key = ChainKey::new(A, B, &p, Start::Homes);
        let shard = &table.shards[(table.hasher.hash_one(key) as usize) % SHARDS];
        let stored = shard.lock().unwrap()[&key]
            .clone()
            .expect("solved")
            .q
            .clone();
        let n = robot.n_joints();
        assert!(closes(
            &key.problem(&p),
            &stored[..n],
            &stored[n..],
            &options
        ));
        assert!(!closes(&p, &stored[..n], &stored[n..], &options));
    }
}
