//! Timing a given path (`runtime/src/motion/retime.rs`), on the shipped cells' motions:
//! the planner's certified path timed in parts is the planner's trajectory to the bit; the
//! rest-to-rest baseline is the slowest joint's trapezoid per segment; the smoothed timing
//! is shorter wherever a corner is blended; malformed paths and limits are errors.

use cellc_driver::fs_files::FsFiles;
use cellc_runtime::motion::{
    arm_limits, rest_to_rest, smooth_waypoints, time_smoothed, MotionError, MotionOptions,
    MotionPlanner, MotionProblem, Piece, RrtConnect, SmoothedPath, TimingOptions,
};
use cellc_runtime::plan::{PlanOptions, Trajectory};
use cellc_runtime::robot::RateLimits;
use cellc_runtime::scene::{Scene, SceneScratch};
use cellc_runtime::validity::SceneValidity;
use cellc_runtime::{Cell, Termination};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

/// The requests whose motions are timed here: the Vito handoff and the two Pandas'.
const CASES: [(&str, &str); 2] = [
    ("cells/vito.cell", "handoff_cylinder"),
    ("cells/two_pandas.cell", "handoff"),
];

fn cell(path: &str) -> Cell {
    let built = cellc_driver::build(&FsFiles, path, &Default::default());
    Cell::from_artifact(built.artifact.expect("builds"), &FsFiles).expect("loads")
}

/// Calls `f` with every motion of a plan of `request` in `path` (the scene, the problem
/// in the plan's world, the plan's trajectory); returns how many there were.
fn each_motion(
    path: &str,
    request: &str,
    mut f: impl FnMut(&Scene, &MotionProblem<'_>, &Trajectory),
) -> usize {
    let cell = cell(path);
    let scene = cell.scene().expect("geometric");
    let request = cell
        .named_request(request, PlanOptions::default())
        .expect("declared");
    let plan = cell.plan(&cell.home_world(), &request).expect("plans");
    let mut count = 0;
    for step in &plan.steps {
        let (Some(t), Some(context)) = (&step.motion, &step.motion_context) else {
            continue;
        };
        let (start, goal) = (
            &t.points[0].positions,
            &t.points[t.points.len() - 1].positions,
        );
        if start == goal {
            continue;
        }
        let validity = SceneValidity::new(
            scene,
            &t.arms,
            &context.stationary,
            request.object,
            context.placement,
        )
        .expect("the plan's layout")
        .with_obstacles(&context.obstacles);
        let problem = MotionProblem {
            scene,
            arms: &t.arms,
            start,
            goal,
            validity: &validity,
            timing: TimingOptions::default(),
        };
        f(scene, &problem, t);
        count += 1;
    }
    count
}

fn path_of(problem: &MotionProblem<'_>, seed: u64) -> Vec<f64> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut scratch = SceneScratch::default();
    RrtConnect::default()
        .path(problem, &mut rng, &Termination::never(), &mut scratch)
        .expect("plans")
}

fn smoothed(problem: &MotionProblem<'_>, path: &[f64]) -> SmoothedPath {
    let mut scratch = SceneScratch::default();
    let options = MotionOptions::default();
    smooth_waypoints(
        path,
        problem.start.len(),
        &options,
        problem.validity,
        &mut scratch,
    )
    .expect("smooths")
}

fn duration(t: &Trajectory) -> f64 {
    t.points[t.points.len() - 1].time
}

/// The fastest rest-to-rest time of one joint over `d` under `v` and `a`.
fn alone(d: f64, v: f64, a: f64) -> f64 {
    if d * a <= v * v {
        2.0 * (d / a).sqrt()
    } else {
        d / v + v / a
    }
}

#[test]
fn the_planners_trajectory_is_its_path_timed_in_parts() {
    for (path, request) in CASES {
        let n = each_motion(path, request, |scene, problem, _| {
            for seed in [0, 7] {
                let mut rng = ChaCha8Rng::seed_from_u64(seed);
                let mut scratch = SceneScratch::default();
                let solved = RrtConnect::default()
                    .solve(problem, &mut rng, &Termination::never(), &mut scratch)
                    .expect("plans");
                let waypoints = path_of(problem, seed);
                let dim = problem.start.len();
                assert_eq!(&waypoints[..dim], problem.start);
                assert_eq!(&waypoints[waypoints.len() - dim..], problem.goal);
                let limits = arm_limits(scene, problem.arms).expect("arms");
                let timed = time_smoothed(
                    &smoothed(problem, &waypoints),
                    problem.arms,
                    &limits,
                    &MotionOptions::default(),
                    &TimingOptions::default(),
                )
                .expect("times");
                assert_eq!(timed, solved, "{path} {request}, seed {seed}");
            }
        });
        assert!(n >= 4, "{path} {request}: {n} motions");
    }
}

#[test]
fn rest_to_rest_is_the_slowest_joints_trapezoid_per_segment() {
    // One joint, 1 rad/s and 2 rad/s²: 1 rad cruises (0.5 s each way, 0.5 s at speed),
    // 0.25 rad never reaches the speed.
    let one = RateLimits {
        velocity: vec![1.0],
        acceleration: vec![2.0],
        jerk: vec![None],
    };
    let timing = TimingOptions::default();
    let d = rest_to_rest(&[0.0, 1.0, 0.75, 0.75], 1, &one, &timing).expect("times");
    assert_eq!(d.len(), 3);
    assert!((d[0] - 1.5).abs() < 1e-12, "{d:?}");
    assert!((d[1] - 2.0 * 0.125_f64.sqrt()).abs() < 1e-12, "{d:?}");
    assert_eq!(d[2], 0.0);
    let half = TimingOptions {
        velocity_scaling: 0.5,
        ..timing
    };
    let slow = rest_to_rest(&[0.0, 1.0], 1, &one, &half).expect("times");
    assert!((slow[0] - 2.25).abs() < 1e-12, "{slow:?}");

    // On the shipped motions: no segment faster than its slowest joint alone could go,
    // and none slower than twice that (the speed bound by one joint `p` and the
    // acceleration by another `q`, a segment's trapezoid takes at most `T_p + T_q`).
    for (path, request) in CASES {
        each_motion(path, request, |scene, problem, _| {
            let waypoints = path_of(problem, 0);
            let dim = problem.start.len();
            let limits = arm_limits(scene, problem.arms).expect("arms");
            let d = rest_to_rest(&waypoints, dim, &limits, &timing).expect("times");
            let points: Vec<&[f64]> = waypoints.chunks(dim).collect();
            for (k, pair) in points.windows(2).enumerate() {
                let slowest = (0..dim)
                    .map(|j| {
                        let travel = (pair[1][j] - pair[0][j]).abs();
                        alone(travel, limits.velocity[j], limits.acceleration[j])
                    })
                    .fold(0.0, f64::max);
                assert!(
                    d[k] >= slowest * (1.0 - 1e-12),
                    "{path} {request}: segment {k} in {} s, its slowest joint needs {slowest} s",
                    d[k]
                );
                assert!(d[k] <= 2.0 * slowest, "segment {k}: {} s", d[k]);
            }
        });
    }
}

#[test]
fn blended_corners_are_shorter_than_stops_and_straight_motions_within_the_margins() {
    let mut blended = 0;
    for (path, request) in CASES {
        each_motion(path, request, |scene, problem, _| {
            let waypoints = path_of(problem, 0);
            let dim = problem.start.len();
            let limits = arm_limits(scene, problem.arms).expect("arms");
            let smooth = smoothed(problem, &waypoints);
            let arcs = smooth
                .sections()
                .flatten()
                .filter(|p| matches!(p, Piece::Arc { .. }))
                .count();
            let ours = duration(
                &time_smoothed(
                    &smooth,
                    problem.arms,
                    &limits,
                    &MotionOptions::default(),
                    &TimingOptions::default(),
                )
                .expect("times"),
            );
            let stops: f64 = rest_to_rest(&waypoints, dim, &limits, &TimingOptions::default())
                .expect("times")
                .iter()
                .sum();
            if arcs > 0 {
                blended += 1;
                assert!(ours < 0.95 * stops, "{path}: {ours} s smoothed, {stops} s");
            } else {
                // TOPP-RA keeps 1% of each acceleration limit in hand (timing.rs).
                assert!(ours >= stops * (1.0 - 1e-9), "{path}: {ours} s, {stops} s");
                assert!(ours <= stops * 1.01, "{path}: {ours} s, {stops} s");
            }
        });
    }
    assert!(blended >= 3, "{blended} motions with a blend");
}

#[test]
fn malformed_paths_and_limits_are_errors() {
    let two = RateLimits {
        velocity: vec![1.0, 1.0],
        acceleration: vec![2.0, 2.0],
        jerk: vec![None, None],
    };
    let timing = TimingOptions::default();
    let malformed =
        |r: Result<Vec<f64>, MotionError>| matches!(r, Err(MotionError::MalformedPath(_)));
    assert!(malformed(rest_to_rest(&[0.0, 1.0, 2.0], 2, &two, &timing)));
    assert!(malformed(rest_to_rest(&[], 2, &two, &timing)));
    assert!(malformed(rest_to_rest(&[0.0, 1.0], 0, &two, &timing)));
    assert!(malformed(rest_to_rest(&[0.0, f64::NAN], 2, &two, &timing)));
    assert!(malformed(rest_to_rest(&[0.0, 1.0], 1, &two, &timing)));
    for bad in [0.0, -1.0, f64::INFINITY, f64::NAN] {
        let mut limits = two.clone();
        limits.acceleration[1] = bad;
        assert!(malformed(rest_to_rest(
            &[0.0, 0.0, 1.0, 1.0],
            2,
            &limits,
            &timing
        )));
        let mut limits = two.clone();
        limits.jerk[0] = Some(bad);
        assert!(malformed(rest_to_rest(
            &[0.0, 0.0, 1.0, 1.0],
            2,
            &limits,
            &timing
        )));
    }
    let zero = TimingOptions {
        acceleration_scaling: 0.0,
        ..timing
    };
    assert!(matches!(
        rest_to_rest(&[0.0, 0.0, 1.0, 1.0], 2, &two, &zero),
        Err(MotionError::InvalidOption { .. })
    ));

    // Smoothing and timing a real motion with what does not fit it.
    let (path, request) = CASES[0];
    let mut checked = false;
    each_motion(path, request, |scene, problem, _| {
        if checked {
            return;
        }
        checked = true;
        let waypoints = path_of(problem, 0);
        let dim = problem.start.len();
        let mut scratch = SceneScratch::default();
        let options = MotionOptions::default();
        let mut bad = waypoints.clone();
        bad[dim + 1] = f64::INFINITY;
        let smooth = |p: &[f64], o: &MotionOptions, s: &mut SceneScratch| {
            smooth_waypoints(p, dim, o, problem.validity, s)
        };
        assert!(matches!(
            smooth(&bad, &options, &mut scratch),
            Err(MotionError::MalformedPath(_))
        ));
        assert!(matches!(
            smooth(&waypoints[1..], &options, &mut scratch),
            Err(MotionError::MalformedPath(_))
        ));
        let flat = MotionOptions {
            grid_step: 0.0,
            ..options.clone()
        };
        assert!(matches!(
            smooth(&waypoints, &flat, &mut scratch),
            Err(MotionError::InvalidOption { .. })
        ));
        let smoothed = smooth(&waypoints, &options, &mut scratch).expect("smooths");
        let limits = arm_limits(scene, problem.arms).expect("arms");
        let time = |l: &RateLimits, o: &MotionOptions| {
            time_smoothed(&smoothed, problem.arms, l, o, &TimingOptions::default())
        };
        assert!(matches!(
            time(&two, &options),
            Err(MotionError::MalformedPath(_))
        ));
        let mut slow = limits.clone();
        slow.velocity[0] = -1.0;
        assert!(matches!(
            time(&slow, &options),
            Err(MotionError::MalformedPath(_))
        ));
        assert!(matches!(
            time(&limits, &flat),
            Err(MotionError::InvalidOption { .. })
        ));
        assert!(time(&limits, &options).is_ok());
    });
    assert!(checked);
}
