//! The seams of a search: a termination condition that stops RRT-Connect inside its loop
//! (a deadline already past, a cancel flag raised mid-search), and another motion
//! validator plugged into it.

use std::cell::Cell;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Instant;

use cellc_runtime::motion::{
    CertifiedMotion, MotionError, MotionOptions, MotionPlanner, MotionValidity, RrtConnect,
};
use cellc_runtime::plan::Trajectory;
use cellc_runtime::scene::{QueryError, Scene, SceneScratch};
use cellc_runtime::validity::{SceneValidity, StateFault, StateValidity};
use cellc_runtime::Termination;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use super::{assert_valid, down, plan, problem, scene, Case, ARM, PILLAR};

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
    type Scratch = SceneScratch;

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
    type Scratch = SceneScratch;

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

/// A state checker with buffers of its own instead of the scene's: it counts the states
/// it judges in its scratch (what a cache or a perception query would keep there) and
/// calls every state within the joint limits valid, as an empty cell would.
struct OwnScratch<'a> {
    limits: (&'a [f64], &'a [f64]),
}

impl StateValidity for OwnScratch<'_> {
    type Scratch = usize;

    fn check(&self, q: &[f64], judged: &mut usize) -> Result<Option<StateFault>, QueryError> {
        *judged += 1;
        let (lower, upper) = self.limits;
        let inside = q
            .iter()
            .zip(lower.iter().zip(upper))
            .all(|(v, (lo, hi))| lo <= v && v <= hi);
        Ok((!inside).then(|| StateFault::OutOfLimits {
            end_effector: cellc_runtime::EndEffectorId(0),
            joint: 0,
            value: q[0],
        }))
    }
}

#[test]
fn a_checker_with_its_own_scratch_plugs_into_rrt_connect() {
    // The pillar is there, but this checker does not look at the scene: the straight
    // line is free for it, so the motion is the straight segment, checked through the
    // caller's scratch.
    let scene = scene(&[ARM], &[PILLAR]);
    let case = around_the_pillar(&scene);
    let robot = &scene.robots[0];
    let checker = OwnScratch {
        limits: robot.limits(),
    };
    let mut judged = 0usize;
    let mut rng = ChaCha8Rng::seed_from_u64(4);
    let trajectory = RrtConnect::default()
        .solve(
            &case.with(&checker),
            &mut rng,
            &Termination::never(),
            &mut judged,
        )
        .expect("a path where the checker sees no obstacle");
    assert!(judged > 2, "the checker judged {judged} states");
    let (first, last) = (
        trajectory.points.first().expect("points"),
        trajectory.points.last().expect("points"),
    );
    assert_eq!(first.positions, case.start);
    assert_eq!(last.positions, case.goal);
    // The scene's checker refuses that straight line: the two answers differ only by
    // the checker plugged in.
    let scene_checker = case.validity().expect("a valid layout");
    let through_pillar = (0..=200).any(|k| {
        let t = f64::from(k) / 200.0;
        let q: Vec<f64> = case
            .start
            .iter()
            .zip(&case.goal)
            .map(|(a, b)| a + t * (b - a))
            .collect();
        !scene_checker
            .is_valid(&q, &mut SceneScratch::default())
            .expect("a state of the arm")
    });
    assert!(through_pillar, "the pillar blocks the straight line");
}
