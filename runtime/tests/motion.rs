//! Joint motion planning (`cellc_runtime::motion`) on small geometric cells built here as
//! artifact values (the runtime never depends on the compiler, not even in tests): one or
//! two KUKA LWR 4+ arms with SoftHands, boxes as fixed surfaces, one cylinder.

use std::f64::consts::PI;

use std::cell::Cell;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Instant;

use cellc_runtime::math::Iso;
use cellc_runtime::motion::{
    check_trajectory, CertifiedMotion, Joints, MotionError, MotionOptions, MotionPlanner,
    MotionProblem, MotionValidity, RrtConnect, TrajectoryFault,
};
use cellc_runtime::plan::{MotionContext, Trajectory};
use cellc_runtime::scene::{Holder, ObjectPlacement, QueryError, Scene, SceneScratch};
use cellc_runtime::termination::Termination;
use cellc_runtime::validity::{SceneValidity, StateFault, StateValidity};
use cellc_runtime::{EndEffectorId, ObjectId};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

#[path = "support/motion_fixture.rs"]
mod fixture;
use fixture::*;

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
    fn with<'v>(&'v self, validity: &'v dyn StateValidity) -> MotionProblem<'v> {
        MotionProblem {
            scene: self.scene,
            arms: &self.arms,
            start: &self.start,
            goal: &self.goal,
            validity,
        }
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
        points: vec![(0.0, problem.start.clone()), (1.0, problem.goal.clone())],
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
    let (a, b) = (&t.points[0].1, &t.points[t.points.len() - 1].1);
    let d: Vec<f64> = a.iter().zip(b).map(|(x, y)| y - x).collect();
    let len2: f64 = d.iter().map(|v| v * v).sum();
    t.points.iter().all(|(_, p)| {
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

/// What every planned trajectory must satisfy: it starts at time 0 at `start`, ends
/// exactly at `goal`, times increase, no joint moves more than `step` between points or
/// faster than the speed limit, and the dense re-check finds nothing.
fn assert_valid(problem: &Case<'_>, t: &Trajectory) {
    let options = MotionOptions::default();
    assert_eq!(t.arms, problem.arms);
    assert_eq!(t.points[0], (0.0, problem.start.clone()));
    assert_eq!(t.points[t.points.len() - 1].1, problem.goal);
    for pair in t.points.windows(2) {
        let ((t0, a), (t1, b)) = (&pair[0], &pair[1]);
        assert!(t1 > t0, "times increase: {t0} then {t1}");
        let d = max_diff(a, b);
        assert!(d <= options.step + 1e-12, "a step of {d} rad");
        assert!(
            d / (t1 - t0) <= options.velocity_limit * (1.0 + 1e-9),
            "a joint at {} rad/s",
            d / (t1 - t0)
        );
    }
    if let Err(fault) = recheck(problem, t) {
        panic!("the planned trajectory is not valid: {fault}");
    }
}

/// The fixture's closed-form inverse kinematics is right (everything below relies on it).
#[test]
fn down_puts_the_hand_where_asked() {
    let scene = scene(&FACING, &[]);
    for (e, target) in [
        (0, [0.5, -0.35, 0.35]),
        (0, [0.5, 0.4, 0.6]),
        (1, [0.5, 0.25, 0.3]),
    ] {
        let Holder::Arm { robot, base, .. } = &scene.holders[e] else {
            panic!("end-effector {e} is an arm");
        };
        let q = down(FACING[e].1, target);
        let tip = scene.robots[*robot].tip_pose(base, &q);
        let error = (tip.translation.vector - nalgebra::Vector3::from(target)).norm();
        assert!(error < 1e-9, "{target:?}: {error} m off");
        let z = tip.rotation * nalgebra::Vector3::z();
        assert!((z.z + 1.0).abs() < 1e-9, "{target:?}: hand axis {z:?}");
    }
}

#[test]
fn straight_line_when_free() {
    let scene = scene(&[ARM], &[]);
    let p = problem(
        &scene,
        vec![0],
        down(ARM.1, [0.5, -0.35, 0.35]),
        down(ARM.1, [0.5, 0.35, 0.35]),
    );
    let t = plan(&p, 1).expect("a free straight line");
    assert_valid(&p, &t);
    assert!(is_straight(&t), "the planner keeps the straight line");
    // About 1 rad of A1 at 0.25 rad per point.
    assert!(t.points.len() >= 5, "{} points", t.points.len());
}

#[test]
fn path_around_an_obstacle() {
    let scene = scene(&[ARM], &[PILLAR]);
    let p = problem(
        &scene,
        vec![0],
        down(ARM.1, [0.5, -0.35, 0.35]),
        down(ARM.1, [0.5, 0.35, 0.35]),
    );
    match recheck(&p, &straight(&p)) {
        Err(TrajectoryFault::Collision { a, b, .. }) => {
            assert!(a == "pillar" || b == "pillar", "{a} / {b}")
        }
        other => panic!("the straight line hits the pillar: {other:?}"),
    }
    let t = plan(&p, 1).expect("a way around the pillar");
    assert_valid(&p, &t);
    assert!(!is_straight(&t));
}

#[test]
fn start_or_goal_in_collision() {
    let scene = scene(&[ARM], &[PILLAR]);
    let free = down(ARM.1, [0.5, -0.35, 0.35]);
    let inside = down(ARM.1, [0.55, 0.0, 0.35]);
    match plan(&problem(&scene, vec![0], inside.clone(), free.clone()), 1) {
        Err(MotionError::StartInCollision { a, b }) => {
            assert!(a == "pillar" || b == "pillar", "{a} / {b}");
            assert!(
                a.starts_with("left/") || b.starts_with("left/"),
                "{a} / {b}"
            );
        }
        other => panic!("expected StartInCollision, got {other:?}"),
    }
    match plan(&problem(&scene, vec![0], free, inside), 1) {
        Err(MotionError::GoalInCollision { a, b }) => {
            assert!(a == "pillar" || b == "pillar", "{a} / {b}")
        }
        other => panic!("expected GoalInCollision, got {other:?}"),
    }
}

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

#[test]
fn two_arms_avoid_each_other() {
    let scene = scene(&FACING, &[]);
    let p = swap(&scene);
    match recheck(&p, &straight(&p)) {
        Err(TrajectoryFault::Collision { a, b, .. }) => assert!(
            a.starts_with("left/") && b.starts_with("right/")
                || a.starts_with("right/") && b.starts_with("left/"),
            "{a} / {b}"
        ),
        other => panic!("the straight line makes the arms meet: {other:?}"),
    }
    let t = plan(&p, 2).expect("the arms can pass each other");
    assert_eq!(t.points[0].1.len(), 14);
    assert_valid(&p, &t);
}

#[test]
fn stationary_arms_are_obstacles() {
    let scene = scene(&FACING, &[]);
    let l = FACING[0].1;
    let mut p = problem(
        &scene,
        vec![0],
        down(l, [0.5, 0.25, 0.3]),
        down(l, [0.5, -0.25, 0.3]),
    );
    // The right arm at home (upright) is out of the way.
    let t = plan(&p, 3).expect("a free straight line");
    assert!(is_straight(&t));
    // Parked in the middle, it is in the way.
    p.stationary = vec![(EndEffectorId(1), down(FACING[1].1, [0.55, 0.0, 0.3]))];
    assert!(matches!(
        recheck(&p, &straight(&p)),
        Err(TrajectoryFault::Collision { .. })
    ));
    let t = plan(&p, 3).expect("a way around the parked arm");
    assert_valid(&p, &t);
    assert!(!is_straight(&t));
}

#[test]
fn held_object_follows_the_hand() {
    // A block under the hand's path: the hand passes over it, the can hanging from the
    // hand (grasped 25 cm out along the hand axis, 30 cm long) does not.
    let table = ("table", [0.35, -0.2, 0.0], [0.8, 0.2, 0.3]);
    let scene = scene(&[ARM], &[table]);
    let mut p = problem(
        &scene,
        vec![0],
        down(ARM.1, [0.5, -0.4, 0.6]),
        down(ARM.1, [0.5, 0.4, 0.6]),
    );
    let empty = plan(&p, 4).expect("empty-handed, the straight line is free");
    assert!(is_straight(&empty));
    p.placement = ObjectPlacement::Held {
        by: EndEffectorId(0),
        grasp: Iso::translation(0.0, 0.0, 0.25),
    };
    match recheck(&p, &straight(&p)) {
        Err(TrajectoryFault::Collision { a, b, .. }) => {
            let mut pair = [a, b];
            pair.sort();
            assert_eq!(pair, ["can".to_string(), "table".to_string()]);
        }
        other => panic!("the held can hits the table: {other:?}"),
    }
    let t = plan(&p, 4).expect("a way over the table with the can");
    assert_valid(&p, &t);
    assert!(!is_straight(&t));
}

#[test]
fn timing_is_monotonic_and_within_limits() {
    let scene = scene(&[ARM], &[PILLAR]);
    let p = problem(
        &scene,
        vec![0],
        down(ARM.1, [0.5, -0.35, 0.35]),
        down(ARM.1, [0.5, 0.35, 0.35]),
    );
    let slow = MotionOptions {
        velocity_limit: 0.3,
        acceleration_limit: 0.5,
        ..MotionOptions::default()
    };
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let t = p
        .solve(&slow, &mut rng, &Termination::never())
        .expect("a path");
    let mut peak: f64 = 0.0;
    for pair in t.points.windows(2) {
        let ((t0, a), (t1, b)) = (&pair[0], &pair[1]);
        assert!(t1 > t0);
        peak = peak.max(max_diff(a, b) / (t1 - t0));
    }
    assert!(peak <= 0.3 * (1.0 + 1e-9), "peak speed {peak}");
    // A rest-to-rest trapezoid takes at least d / v + v / a per segment when it cruises,
    // 2 sqrt(d / a) when it does not; the whole motion at least the sum.
    let total = t.points[t.points.len() - 1].0;
    let travelled: f64 = t
        .points
        .windows(2)
        .map(|w| max_diff(&w[0].1, &w[1].1))
        .sum();
    assert!(total >= travelled / 0.3, "{total} s for {travelled} rad");
    // The same motion with the defaults is faster.
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let fast = p
        .solve(&MotionOptions::default(), &mut rng, &Termination::never())
        .expect("a path");
    assert!(fast.points[fast.points.len() - 1].0 < total);
}

#[test]
fn same_seed_same_trajectory() {
    let scene = scene(&FACING, &[]);
    let p = swap(&scene);
    let a = plan(&p, 11).expect("a path");
    let b = plan(&p, 11).expect("a path");
    assert_eq!(a, b);
}

#[test]
fn equal_start_and_goal_is_one_point() {
    let scene = scene(&[ARM], &[]);
    let q = down(ARM.1, [0.5, 0.0, 0.4]);
    let t = plan(&problem(&scene, vec![0], q.clone(), q.clone()), 0).expect("no motion");
    assert_eq!(t.points, vec![(0.0, q)]);
}

#[test]
fn malformed_problems_are_errors() {
    let scene = scene(&[ARM], &[PILLAR]);
    let q = down(ARM.1, [0.5, -0.35, 0.35]);
    let short = q[..6].to_vec();
    assert!(matches!(
        plan(&problem(&scene, vec![0], short, q.clone()), 0),
        Err(MotionError::WrongLength {
            joints: Joints::Start,
            expected: 7,
            found: 6
        })
    ));
    let mut far = q.clone();
    far[1] = 3.0;
    assert!(matches!(
        plan(&problem(&scene, vec![0], q.clone(), far), 0),
        Err(MotionError::OutOfLimits {
            joints: Joints::Goal,
            end_effector: EndEffectorId(0),
            joint: 1,
            ..
        })
    ));
    // End-effector 1 is the pillar.
    assert_eq!(
        plan(&problem(&scene, vec![1], Vec::new(), Vec::new()), 0),
        Err(MotionError::NotAnArm {
            end_effector: EndEffectorId(1)
        })
    );
    assert_eq!(
        plan(
            &problem(
                &scene,
                vec![0, 0],
                [q.clone(), q.clone()].concat(),
                [q.clone(), q.clone()].concat()
            ),
            0
        ),
        Err(MotionError::RepeatedArm {
            end_effector: EndEffectorId(0)
        })
    );
    let mut rng = ChaCha8Rng::seed_from_u64(0);
    let bad = MotionOptions {
        collision_resolution: 0.0,
        ..MotionOptions::default()
    };
    assert!(matches!(
        problem(&scene, vec![0], q.clone(), q.clone()).solve(&bad, &mut rng, &Termination::never()),
        Err(MotionError::InvalidOption {
            name: "collision_resolution",
            ..
        })
    ));
    // A held object's holder must be an arm.
    let mut p = problem(&scene, vec![0], q.clone(), q);
    p.placement = ObjectPlacement::Held {
        by: EndEffectorId(1),
        grasp: Iso::identity(),
    };
    assert!(matches!(plan(&p, 0), Err(MotionError::Query(_))));
}

/// A state validity that delegates to the default one, counts the states it is asked
/// about, and raises a cancel flag once it has answered `limit` of them: a deterministic
/// stand-in for a deadline that passes mid-search.
struct Tripwire<'a> {
    inner: SceneValidity<'a>,
    calls: Cell<usize>,
    limit: usize,
    flag: Arc<AtomicBool>,
}

impl StateValidity for Tripwire<'_> {
    fn check(
        &self,
        q: &[f64],
        scratch: &mut SceneScratch,
    ) -> Result<Option<StateFault>, QueryError> {
        self.calls.set(self.calls.get() + 1);
        if self.calls.get() >= self.limit {
            self.flag.store(true, Ordering::Relaxed);
        }
        self.inner.check(q, scratch)
    }
}

/// The arm swinging round the pillar: the straight line is blocked, so RRT-Connect runs.
fn around_the_pillar(scene: &Scene) -> Case<'_> {
    problem(
        scene,
        vec![0],
        down(ARM.1, [0.5, -0.35, 0.35]),
        down(ARM.1, [0.5, 0.35, 0.35]),
    )
}

/// Solves `case` through a [`Tripwire`] that trips after `limit` states, stopped by its
/// flag (and by `stop`'s deadline, if any); also gives how many states were checked.
fn tripped(
    case: &Case<'_>,
    limit: usize,
    stop: Termination,
) -> (Result<Trajectory, MotionError>, usize) {
    let flag = Arc::new(AtomicBool::new(false));
    let tripwire = Tripwire {
        inner: case.validity().expect("a valid layout"),
        calls: Cell::new(0),
        limit,
        flag: flag.clone(),
    };
    let mut rng = ChaCha8Rng::seed_from_u64(9);
    let result = RrtConnect::default().solve(
        &case.with(&tripwire),
        &mut rng,
        &stop.with_cancel(flag),
        &mut SceneScratch::default(),
    );
    (result, tripwire.calls.get())
}

#[test]
fn a_deadline_already_past_stops_before_the_first_iteration() {
    let scene = scene(&[ARM], &[PILLAR]);
    let case = around_the_pillar(&scene);
    let stop = Termination::at(Instant::now());
    let (result, _) = tripped(&case, usize::MAX, stop);
    assert_eq!(result, Err(MotionError::Terminated { iterations: 0 }));
}

#[test]
fn a_cancelled_search_stops_mid_way_with_its_own_error() {
    let scene = scene(&[ARM], &[PILLAR]);
    let case = around_the_pillar(&scene);
    // Unhurried, the search finds a path after many checks.
    let (full, all_checks) = tripped(&case, usize::MAX, Termination::never());
    assert_valid(&case, &full.expect("a way round the pillar"));
    // The checks before the first iteration: start, goal, the straight line.
    let (early, before_search) = tripped(&case, usize::MAX, Termination::at(Instant::now()));
    assert!(matches!(
        early,
        Err(MotionError::Terminated { iterations: 0 })
    ));
    let limit = before_search + 40;
    assert!(all_checks > limit, "{all_checks} checks in all");
    // Raised 40 checks into the search: it stops in the iteration that raised it.
    let (stopped, checks) = tripped(&case, limit, Termination::never());
    let Err(MotionError::Terminated { iterations }) = stopped else {
        panic!("the raised flag stops the search: {stopped:?}");
    };
    assert!(iterations >= 1, "stopped mid-search, not before it");
    assert!(iterations < MotionOptions::default().max_iterations);
    assert!(checks < all_checks, "{checks} of {all_checks} checks");
    // Deterministic: the same limit stops at the same iteration.
    let (again, _) = tripped(&case, limit, Termination::never());
    assert_eq!(again, Err(MotionError::Terminated { iterations }));
}

/// Counts the segments it is asked about and lets [`CertifiedMotion`], the default,
/// answer.
struct CountingSegments<'v> {
    inner: CertifiedMotion<'v>,
    segments: usize,
}

impl MotionValidity for CountingSegments<'_> {
    fn check_motion(
        &mut self,
        a: &[f64],
        b: &[f64],
        scratch: &mut SceneScratch,
    ) -> Result<bool, QueryError> {
        self.segments += 1;
        self.inner.check_motion(a, b, scratch)
    }
}

#[test]
fn another_motion_validator_plugs_into_rrt_connect() {
    let scene = scene(&[ARM], &[PILLAR]);
    let case = around_the_pillar(&scene);
    let validity = case.validity().expect("a valid layout");
    let options = MotionOptions::default();
    let mut counting = CountingSegments {
        inner: CertifiedMotion::new(&validity, options.step, options.collision_resolution),
        segments: 0,
    };
    let planner = RrtConnect::new(options);
    let mut rng = ChaCha8Rng::seed_from_u64(4);
    let through_it = planner
        .solve_with(
            &case.with(&validity),
            &mut counting,
            &mut rng,
            &Termination::never(),
            &mut SceneScratch::default(),
        )
        .expect("a path");
    assert!(
        counting.segments > 1,
        "the straight line and the tree's edges"
    );
    assert_eq!(Ok(through_it), plan(&case, 4));
}

/// Straight segments between random configurations around the pillar and over a table,
/// with a can in the hand: every segment the certified check accepts is free when
/// re-checked fifty times finer than the planner's resolution (the sampled check at that
/// resolution is not: a contact shallower than one step can lie between its samples).
#[test]
fn certified_segments_are_free_at_any_resolution() {
    let table = ("table", [0.35, -0.3, 0.0], [0.8, 0.3, 0.3]);
    let scene = scene(&[ARM], &[PILLAR, table]);
    let Holder::Arm { robot, .. } = &scene.holders[0] else {
        panic!("end-effector 0 is an arm");
    };
    let robot = &scene.robots[*robot];
    let mut case = problem(&scene, vec![0], Vec::new(), Vec::new());
    case.placement = ObjectPlacement::Held {
        by: EndEffectorId(0),
        grasp: Iso::translation(0.0, 0.0, 0.25),
    };
    let validity = case.validity().expect("a valid layout");
    let options = MotionOptions::default();
    let mut certified = CertifiedMotion::new(&validity, options.step, options.collision_resolution);
    let mut rng = ChaCha8Rng::seed_from_u64(12);
    let mut scratch = SceneScratch::default();
    let (mut accepted, mut refused) = (0, 0);
    let mut a = vec![0.0; 7];
    for _ in 0..300 {
        // A free start, and a goal up to a radian away per joint.
        loop {
            robot.sample_configuration(&mut rng, &mut a);
            if validity.is_valid(&a, &mut scratch).expect("well formed") {
                break;
            }
        }
        let mut b: Vec<f64> = a.iter().map(|v| v + rng.random_range(-1.0..1.0)).collect();
        robot.clamp_to_limits(&mut b);
        if !certified
            .check_motion(&a, &b, &mut scratch)
            .expect("well formed")
        {
            refused += 1;
            continue;
        }
        accepted += 1;
        let t = Trajectory {
            arms: vec![EndEffectorId(0)],
            points: vec![(0.0, a.clone()), (1.0, b)],
        };
        let fine = options.collision_resolution / 50.0;
        let checked =
            check_trajectory(&scene, &t, ObjectId(0), &case.context(), fine, &mut scratch);
        assert_eq!(checked, Ok(()), "{:?}", t.points);
    }
    // Both answers are exercised.
    assert!(
        accepted > 100 && refused > 30,
        "{accepted} accepted, {refused} refused"
    );
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig { cases: 8, ..Default::default() })]

    /// Random collision-free start and goal around the pillar: every trajectory point is
    /// within limits and collision-free, and so is every configuration between them at
    /// the planner's resolution. Random pairs can be hard (an arm folded around the
    /// pillar): not finding a path in time is allowed, a wrong path is not.
    #[test]
    fn random_motions_are_valid(seed in 0u64..1_000_000) {
        let scene = scene(&[ARM], &[PILLAR]);
        let Holder::Arm { robot, .. } = &scene.holders[0] else {
            panic!("end-effector 0 is an arm");
        };
        let robot = &scene.robots[*robot];
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut scratch = SceneScratch::default();
        let free = |q: &[f64], scratch: &mut SceneScratch| {
            scene
                .collision(&[(EndEffectorId(0), q)], ObjectId(0), ObjectPlacement::Absent, &[], scratch)
                .expect("the query is well formed")
                .is_none()
        };
        let mut random_free = || loop {
            let mut q = vec![0.0; 7];
            robot.sample_configuration(&mut rng, &mut q);
            if free(&q, &mut scratch) {
                break q;
            }
        };
        let (start, goal) = (random_free(), random_free());
        let p = problem(&scene, vec![0], start, goal);
        let options = MotionOptions::default();
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let t = match p.solve(&options, &mut rng, &Termination::never()) {
            Ok(t) => t,
            Err(MotionError::NoPath { .. }) => return Ok(()),
            Err(e) => panic!("{e}"),
        };
        for (time, q) in &t.points {
            proptest::prop_assert!(robot.within_limits(q), "at {time} s: {q:?}");
            proptest::prop_assert!(free(q, &mut scratch), "at {time} s: {q:?}");
        }
        let checked = check_trajectory(
            &scene,
            &t,
            ObjectId(0),
            &MotionContext {
                stationary: Vec::new(),
                placement: ObjectPlacement::Absent,
                obstacles: Vec::new(),
            },
            options.collision_resolution,
            &mut scratch,
        );
        proptest::prop_assert_eq!(checked, Ok(()));
    }
}
