//! Joint motion planning (`cellc_runtime::motion`) on small geometric cells built here as
//! artifact values (the runtime never depends on the compiler, not even in tests): one or
//! two KUKA LWR 4+ arms with SoftHands, boxes as fixed surfaces, one cylinder.
//!
//! This file holds the test cells and what every check of a planned trajectory asks; the
//! modules hold the cases: `paths.rs` the paths found (free, round obstacles, past another
//! arm, with a held object), `trajectories.rs` their timing, determinism and malformed
//! problems, `seams.rs` the termination condition and another motion validator plugged
//! in, `soundness.rs` certified segments and random motions re-checked finer than the
//! planner's resolution.

use std::f64::consts::PI;

use cellc_runtime::motion::{
    check_trajectory, MotionError, MotionOptions, MotionPlanner, MotionProblem, RrtConnect,
    TimingOptions, TrajectoryFault,
};
use cellc_runtime::plan::{MotionContext, Trajectory, TrajectoryPoint};
use cellc_runtime::scene::{ObjectPlacement, Scene, SceneScratch};
use cellc_runtime::validity::{SceneValidity, StateValidity};
use cellc_runtime::Termination;
use cellc_runtime::{EndEffectorId, ObjectId};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

#[path = "../support/motion_fixture.rs"]
mod fixture;
use fixture::*;

mod frozen;
mod paths;
mod seams;
mod soundness;
mod trajectories;

fn scene(arms: &[(&str, [f64; 4])], boxes: &[(&str, [f64; 3], [f64; 3])]) -> Scene {
    Scene::load(&artifact(arms, boxes), &Repo).expect("the test cell loads")
}

/// Joints of an LWR whose base is at `base` (upright) putting its flange at `at` with the
/// hand pointing straight down, elbow up: A1 turns towards the target, A2/A4 solve the
/// planar two-link problem (upper arm 0.4 m, forearm 0.39 m, shoulder 0.31 m up, flange
/// 0.078 m past the wrist), A6 points the hand down.
fn down(base: [f64; 4], at: [f64; 3]) -> Vec<f64> {
    let (dx, dy) = (at[0] - base[0], at[1] - base[1]);
    let r = dx.hypot(dy);
    let z = at[2] + 0.078 - base[2] - 0.31;
    let (l1, l2) = (0.4_f64, 0.39_f64);
    let d = r.hypot(z);
    let gamma = ((l1 * l1 + l2 * l2 - d * d) / (2.0 * l1 * l2)).acos();
    let alpha = ((l1 * l1 + d * d - l2 * l2) / (2.0 * l1 * d)).acos();
    let a = r.atan2(z) - alpha;
    let b = PI - gamma;
    let c = PI - a - b;
    let turn = (dy.atan2(dx) - base[3] + PI).rem_euclid(2.0 * PI) - PI;
    let q = vec![turn, -a, 0.0, b, 0.0, -c, 0.0];
    assert!(q.iter().all(|v| v.is_finite()), "{at:?} is out of reach");
    q
}

/// One upright arm at the origin.
const ARM: (&str, [f64; 4]) = ("left", [0.0, 0.0, 0.0, 0.0]);

/// A pillar in front of the arm, 75 cm tall: sweeping the arm from its right to its left
/// at table height goes through it.
const PILLAR: (&str, [f64; 3], [f64; 3]) = ("pillar", [0.4, -0.1, 0.0], [0.7, 0.1, 0.75]);

/// Fine enough that nothing slips between checks in these cells.
const DENSE: f64 = 0.005;

/// Two arms facing each other across the work area.
const FACING: [(&str, [f64; 4]); 2] = [
    ("left", [0.0, 0.0, 0.0, 0.0]),
    ("right", [1.0, 0.0, 0.0, PI]),
];

/// Both hands at table height on opposite sides of the middle line, swapping sides: moved
/// together along the straight line, the arms meet in the middle.
fn swap(scene: &Scene) -> Case<'_> {
    let (l, r) = (FACING[0].1, FACING[1].1);
    let (a, b) = ([0.5, 0.25, 0.3], [0.5, -0.25, 0.3]);
    let start = [down(l, a), down(r, b)].concat();
    let goal = [down(l, b), down(r, a)].concat();
    problem(scene, vec![0, 1], start, goal)
}

/// A motion in a test cell: the arms, their ends, and the world the default state
/// validity checks them in (the object, when there is one, is the fixture's only one).
#[derive(Clone)]
struct Case<'a> {
    scene: &'a Scene,
    arms: Vec<EndEffectorId>,
    start: Vec<f64>,
    goal: Vec<f64>,
    stationary: Vec<(EndEffectorId, Vec<f64>)>,
    placement: ObjectPlacement,
}

fn problem<'a>(scene: &'a Scene, arms: Vec<u32>, start: Vec<f64>, goal: Vec<f64>) -> Case<'a> {
    Case {
        scene,
        arms: arms.into_iter().map(EndEffectorId).collect(),
        start,
        goal,
        stationary: Vec::new(),
        placement: ObjectPlacement::Absent,
    }
}

impl Case<'_> {
    /// The motion's surroundings, as a plan records them.
    fn context(&self) -> MotionContext {
        MotionContext {
            stationary: self.stationary.clone(),
            placement: self.placement,
            obstacles: Vec::new(),
        }
    }

    /// The default state validity of this motion.
    fn validity(&self) -> Result<SceneValidity<'_>, MotionError> {
        Ok(SceneValidity::new(
            self.scene,
            &self.arms,
            &self.stationary,
            ObjectId(0),
            self.placement,
        )?)
    }

    /// The motion problem with `validity` deciding which states are valid.
    fn with<'v, S>(&'v self, validity: &'v dyn StateValidity<Scratch = S>) -> MotionProblem<'v, S> {
        MotionProblem {
            scene: self.scene,
            arms: &self.arms,
            start: &self.start,
            goal: &self.goal,
            validity,
            timing: Default::default(),
        }
    }

    /// Plans with RRT-Connect and the default state validity, timed as `timing` asks.
    fn solve_timed(
        &self,
        options: &MotionOptions,
        timing: TimingOptions,
        rng: &mut ChaCha8Rng,
    ) -> Result<Trajectory, MotionError> {
        let validity = self.validity()?;
        let problem = MotionProblem {
            timing,
            ..self.with(&validity)
        };
        RrtConnect::new(options.clone()).solve(
            &problem,
            rng,
            &Termination::never(),
            &mut SceneScratch::default(),
        )
    }

    /// Plans with RRT-Connect and the default state validity.
    fn solve(
        &self,
        options: &MotionOptions,
        rng: &mut ChaCha8Rng,
        stop: &Termination,
    ) -> Result<Trajectory, MotionError> {
        let validity = self.validity()?;
        RrtConnect::new(options.clone()).solve(
            &self.with(&validity),
            rng,
            stop,
            &mut SceneScratch::default(),
        )
    }
}

fn plan(case: &Case<'_>, seed: u64) -> Result<Trajectory, MotionError> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    case.solve(&MotionOptions::default(), &mut rng, &Termination::never())
}

/// The dense, independent re-check of a planned trajectory for `case`.
fn recheck(case: &Case<'_>, trajectory: &Trajectory) -> Result<(), TrajectoryFault> {
    check_trajectory(
        case.scene,
        trajectory,
        ObjectId(0),
        &case.context(),
        DENSE,
        &mut SceneScratch::default(),
    )
}

/// The straight line from start to goal as a (roughly timed) trajectory.
fn straight(problem: &Case<'_>) -> Trajectory {
    Trajectory {
        arms: problem.arms.clone(),
        points: vec![
            TrajectoryPoint::at_rest(0.0, &problem.start),
            TrajectoryPoint::at_rest(1.0, &problem.goal),
        ],
    }
}

fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// Whether every point lies on the segment from the first to the last.
fn is_straight(t: &Trajectory) -> bool {
    let (a, b) = (
        &t.points[0].positions,
        &t.points[t.points.len() - 1].positions,
    );
    let d: Vec<f64> = a.iter().zip(b).map(|(x, y)| y - x).collect();
    let len2: f64 = d.iter().map(|v| v * v).sum();
    t.points.iter().map(|p| &p.positions).all(|p| {
        let s = p
            .iter()
            .zip(a)
            .zip(&d)
            .map(|((p, a), d)| (p - a) * d)
            .sum::<f64>()
            / len2;
        let on: Vec<f64> = a.iter().zip(&d).map(|(a, d)| a + d * s).collect();
        (-1e-9..=1.0 + 1e-9).contains(&s) && max_diff(p, &on) < 1e-9
    })
}

/// The fixture's speed limit of every joint (rad/s, `motion_fixture.rs`).
const VELOCITY: f64 = 1.0;

/// What every planned trajectory must satisfy: it starts at time 0 at `start` at rest
/// (accelerating as its first step does), ends
/// exactly at `goal`, times increase, no joint moves more than `step` between points or
/// faster than the speed limit, and the dense re-check finds nothing.
fn assert_valid(problem: &Case<'_>, t: &Trajectory) {
    let options = MotionOptions::default();
    assert_eq!(t.arms, problem.arms);
    let first = &t.points[0];
    assert_eq!(
        (first.time, &first.positions, &first.velocities),
        (0.0, &problem.start, &vec![0.0; problem.start.len()])
    );
    assert_eq!(t.points[t.points.len() - 1].positions, problem.goal);
    for pair in t.points.windows(2) {
        let (t0, a, t1, b) = (
            pair[0].time,
            &pair[0].positions,
            pair[1].time,
            &pair[1].positions,
        );
        assert!(t1 > t0, "times increase: {t0} then {t1}");
        let d = max_diff(a, b);
        assert!(d <= options.step + 1e-12, "a step of {d} rad");
        // The fixture's joints go at most 1 rad/s; a chord of an arc is a hair shorter
        // than the arc, so its mean speed is never above the limit.
        assert!(
            d / (t1 - t0) <= VELOCITY * (1.0 + 1e-9),
            "a joint at {} rad/s",
            d / (t1 - t0)
        );
    }
    if let Err(fault) = recheck(problem, t) {
        panic!("the planned trajectory is not valid: {fault}");
    }
}
