//! The batched screen of sampled motion checks (`runtime/src/collision/batch.rs`, used by
//! `DiscreteMotion` through `StateValidity::screen`) on the shipped cells: for many
//! segments of real motions (the Vito arms with and without the object in hand, the
//! Panda in its cage), the batched check gives the one-by-one check's verdict, the
//! configurations it judges are the one-by-one check's in the same order, and every
//! configuration the screen judges gets the full check's answer.

use std::cell::RefCell;

#[path = "support/verified.rs"]
mod verified;
use verified::verified_cell;

use cellc_runtime::motion::{DiscreteMotion, MotionValidity};
use cellc_runtime::plan::PlanOptions;
use cellc_runtime::scene::{Holder, ObjectPlacement, QueryError, Scene, SceneScratch};
use cellc_runtime::validity::{SceneValidity, Screened, StateFault, StateValidity};
use cellc_runtime::{Cell, EndEffectorId, ObjectId};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// The shortcut screen's resolution (`motion/rrt.rs`).
const SCREEN: f64 = 0.1;

/// Forwards the full checks of a validity and hides its screen (the default screen
/// proves nothing): the one-by-one check. Records every configuration it judges.
struct OneByOne<'a> {
    inner: &'a dyn StateValidity<Scratch = SceneScratch>,
    judged: RefCell<Vec<Vec<f64>>>,
}

impl StateValidity for OneByOne<'_> {
    type Scratch = SceneScratch;

    fn check(
        &self,
        q: &[f64],
        scratch: &mut SceneScratch,
    ) -> Result<Option<StateFault>, QueryError> {
        self.inner.check(q, scratch)
    }

    fn is_valid(&self, q: &[f64], scratch: &mut SceneScratch) -> Result<bool, QueryError> {
        self.judged.borrow_mut().push(q.to_vec());
        self.inner.is_valid(q, scratch)
    }
}

/// Forwards everything, screen included, and records the configurations screened, the
/// verdicts of the screen and the configurations the full check was asked about.
struct Batched<'a> {
    inner: &'a dyn StateValidity<Scratch = SceneScratch>,
    screened: RefCell<Vec<(Vec<f64>, Screened)>>,
    asked: RefCell<Vec<Vec<f64>>>,
}

impl StateValidity for Batched<'_> {
    type Scratch = SceneScratch;

    fn check(
        &self,
        q: &[f64],
        scratch: &mut SceneScratch,
    ) -> Result<Option<StateFault>, QueryError> {
        self.inner.check(q, scratch)
    }

    fn is_valid(&self, q: &[f64], scratch: &mut SceneScratch) -> Result<bool, QueryError> {
        self.asked.borrow_mut().push(q.to_vec());
        self.inner.is_valid(q, scratch)
    }

    fn screen(&self, qs: &[f64], out: &mut [Screened], scratch: &mut SceneScratch) {
        self.inner.screen(qs, out, scratch);
        let dim = qs.len() / out.len().max(1);
        for (q, &verdict) in qs.chunks_exact(dim.max(1)).zip(out.iter()) {
            self.screened.borrow_mut().push((q.to_vec(), verdict));
        }
    }
}

/// What the segments of one cell gave.
#[derive(Default, Debug)]
struct Tally {
    free: usize,
    blocked: usize,
    /// Configurations the screen proved valid, proved invalid, and left to the full
    /// check.
    valid: usize,
    invalid: usize,
    left: usize,
}

/// Random segments of the arms `arms` in the layout of `validity`: each from a valid
/// configuration, `0.05` rad to `longest` long per joint at most, checked one by one and
/// batched; panics on any difference.
fn compare(
    scene: &Scene,
    arms: &[EndEffectorId],
    validity: &SceneValidity<'_>,
    (segments, longest): (usize, f64),
    seed: u64,
    tally: &mut Tally,
) {
    let robots: Vec<usize> = arms
        .iter()
        .map(|e| match &scene.holders[e.index()] {
            Holder::Arm { robot, .. } => *robot,
            _ => panic!("an arm"),
        })
        .collect();
    let dim: usize = robots.iter().map(|&r| scene.robots[r].n_joints()).sum();
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut scratch = SceneScratch::default();
    let mut a = vec![0.0; dim];
    let mut b = vec![0.0; dim];
    let sample = |rng: &mut ChaCha8Rng, q: &mut [f64]| {
        let mut at = 0;
        for &r in &robots {
            let n = scene.robots[r].n_joints();
            scene.robots[r].sample_configuration(rng, &mut q[at..at + n]);
            at += n;
        }
    };
    let mut done = 0;
    let mut tries = 0;
    while done < segments {
        tries += 1;
        assert!(tries < 100 * segments, "too few valid configurations");
        sample(&mut rng, &mut a);
        if !validity.is_valid(&a, &mut scratch).expect("well formed") {
            continue;
        }
        // Every other segment towards another random configuration, cut to a length
        // the trees and the shortcuts would try; the others end in an invalid one
        // (random ones are mostly free in an open cell).
        if done % 2 == 0 {
            sample(&mut rng, &mut b);
            let length = rng.random_range(0.05..longest);
            let far = a
                .iter()
                .zip(&b)
                .map(|(x, y)| (y - x).abs())
                .fold(0.0, f64::max);
            if far > length {
                for (y, x) in b.iter_mut().zip(&a) {
                    *y = x + (*y - x) * (length / far);
                }
            }
        } else {
            loop {
                sample(&mut rng, &mut b);
                if !validity.is_valid(&b, &mut scratch).expect("well formed") {
                    break;
                }
            }
        }
        let one = OneByOne {
            inner: validity,
            judged: RefCell::default(),
        };
        let batched = Batched {
            inner: validity,
            screened: RefCell::default(),
            asked: RefCell::default(),
        };
        let expected = DiscreteMotion::new(&one, f64::INFINITY, SCREEN)
            .check_motion(&a, &b, &mut scratch)
            .expect("well formed");
        let got = DiscreteMotion::new(&batched, f64::INFINITY, SCREEN)
            .check_motion(&a, &b, &mut scratch)
            .expect("well formed");
        assert_eq!(got, expected, "segment {a:?} -> {b:?}");
        let judged = one.judged.into_inner();
        let (screened, asked) = (batched.screened.into_inner(), batched.asked.into_inner());
        // The same configurations, bit for bit, in the same order: the one-by-one
        // check's are where the batches begin (a batch may run past the first invalid
        // one), and the full check is asked about those the screen left unknown.
        assert!(screened.len() >= judged.len());
        for (q, (s, _)) in judged.iter().zip(&screened) {
            assert_eq!(q, s);
        }
        let unknown: Vec<&Vec<f64>> = screened[..judged.len()]
            .iter()
            .filter(|(_, v)| *v == Screened::Unknown)
            .map(|(q, _)| q)
            .collect();
        assert_eq!(asked.iter().collect::<Vec<_>>(), unknown);
        // Every verdict of the screen is the full check's.
        for (q, verdict) in &screened {
            let valid = validity.is_valid(q, &mut scratch).expect("well formed");
            match verdict {
                Screened::Valid => assert!(valid, "the screen passed an invalid {q:?}"),
                Screened::Invalid => assert!(!valid, "the screen refused a valid {q:?}"),
                Screened::Unknown => {}
            }
            let count = |v: Screened| usize::from(*verdict == v);
            tally.valid += count(Screened::Valid);
            tally.invalid += count(Screened::Invalid);
        }
        tally.left += asked.len();
        if expected {
            tally.free += 1;
        } else {
            tally.blocked += 1;
        }
        done += 1;
    }
}

/// Every motion of the request's plan with `seed`: its arms and layout (the object held,
/// the other arm where it stands), `segments` random segments each (how many, longest).
fn compare_plan(cell: &Cell, request: &str, seed: u64, segments: (usize, f64), tally: &mut Tally) {
    let scene = cell.scene().expect("geometric");
    let options = PlanOptions {
        seed,
        ..PlanOptions::default()
    };
    let request = cell.named_request(request, options).expect("declared");
    let plan = cell.plan(&cell.home_world(), &request).expect("plans");
    let mut motions = 0;
    for (k, step) in plan.steps.iter().enumerate() {
        let (Some(t), Some(context)) = (&step.motion, &step.motion_context) else {
            continue;
        };
        let validity = SceneValidity::new(
            scene,
            &t.arms,
            &context.stationary,
            plan.object,
            context.placement,
        )
        .expect("the plan's layout")
        .with_obstacles(&context.obstacles);
        compare(scene, &t.arms, &validity, segments, seed + k as u64, tally);
        motions += 1;
    }
    assert!(motions > 0, "no motions");
}

/// Each arm alone with nothing held, `segments` segments (how many, longest).
fn compare_arms(cell: &Cell, arms: &[&str], segments: (usize, f64), tally: &mut Tally) {
    let scene = cell.scene().expect("geometric");
    for (k, name) in arms.iter().enumerate() {
        let arm = cell.end_effector(name).expect("an arm");
        let validity = SceneValidity::new(scene, &[arm], &[], ObjectId(0), ObjectPlacement::Absent)
            .expect("a layout");
        compare(scene, &[arm], &validity, segments, 100 + k as u64, tally);
    }
}

#[test]
fn the_batched_screen_answers_as_one_by_one_on_vito() {
    let cell = verified_cell("cells/vito.cell");
    let mut tally = Tally::default();
    compare_arms(&cell, &["left", "right"], (200, 3.0), &mut tally);
    compare_plan(&cell, "handoff_cylinder", 0, (40, 3.0), &mut tally);
    compare_plan(&cell, "trash", 0, (40, 3.0), &mut tally);
    // Both verdicts, and both kinds of configuration, many times: not vacuous.
    println!("{tally:?}");
    assert!(tally.free >= 100 && tally.blocked >= 100, "{tally:?}");
    assert!(tally.valid >= 1000 && tally.invalid >= 100, "{tally:?}");
}

#[test]
fn the_batched_screen_answers_as_one_by_one_in_the_cage() {
    let cell = verified_cell("cells/panda_cage.cell");
    let mut tally = Tally::default();
    compare_arms(&cell, &["franka"], (500, 1.2), &mut tally);
    compare_plan(&cell, "through_cage", 0, (60, 1.2), &mut tally);
    println!("{tally:?}");
    assert!(tally.free >= 100 && tally.blocked >= 100, "{tally:?}");
    assert!(tally.valid >= 500 && tally.invalid >= 100, "{tally:?}");
}
