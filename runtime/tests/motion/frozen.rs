//! The frozen broad phase (`collision::frozen`): a checker that has answered a few
//! queries freezes the standing part of the scene (the other arm, the furniture, an
//! object at rest) and from then on places only the moving bodies. Its answers must be
//! the plain queries' answers, bit for bit: the same validity and the same free radius
//! for every configuration and segment, or plans would depend on how many queries a
//! checker had answered.

use cellc_runtime::math::Iso;
use cellc_runtime::scene::{Holder, ObjectPlacement, SceneScratch};
use cellc_runtime::validity::StateValidity;
use cellc_runtime::EndEffectorId;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::{down, problem, scene, FACING, PILLAR};

/// Random configurations of the left arm, the right arm standing over the table with
/// its hand down, a pillar and a table: a warmed checker (frozen) and a fresh checker
/// per query (plain) agree on validity and on the free radius of random segments, and
/// both answers occur often enough that a disagreement would show.
#[test]
fn frozen_answers_are_the_plain_answers() {
    let table = ("table", [0.25, -0.5, 0.0], [0.75, 0.5, 0.2]);
    let scene = scene(&FACING, &[PILLAR, table]);
    let Holder::Arm { robot, .. } = &scene.holders[0] else {
        panic!("end-effector 0 is an arm");
    };
    let robot = &scene.robots[*robot];
    let placements = [
        ObjectPlacement::Held {
            by: EndEffectorId(0),
            grasp: Iso::translation(0.0, 0.0, 0.2),
        },
        ObjectPlacement::Resting {
            on: EndEffectorId(3),
            pose: Iso::translation(0.5, 0.3, 0.25),
            by: Some(EndEffectorId(0)),
        },
        ObjectPlacement::Held {
            by: EndEffectorId(1),
            grasp: Iso::translation(0.0, 0.0, 0.2),
        },
    ];
    let right = down(FACING[1].1, [0.5, -0.3, 0.55]);
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let (mut valid, mut invalid, mut open, mut shut) = (0, 0, 0, 0);
    for placement in placements {
        let mut case = problem(&scene, vec![0], Vec::new(), Vec::new());
        case.stationary = vec![(EndEffectorId(1), right.clone())];
        case.placement = placement;
        let warmed = case.validity().expect("a valid layout");
        let mut scratch = SceneScratch::default();
        let mut fresh_scratch = SceneScratch::default();
        let mut q = vec![0.0; 7];
        // Past the warm-up, so that the rest is answered frozen.
        for _ in 0..8 {
            robot.sample_configuration(&mut rng, &mut q);
            warmed.is_valid(&q, &mut scratch).expect("well formed");
        }
        for _ in 0..600 {
            robot.sample_configuration(&mut rng, &mut q);
            let fresh = case.validity().expect("a valid layout");
            let frozen = warmed.is_valid(&q, &mut scratch).expect("well formed");
            let plain = fresh.is_valid(&q, &mut fresh_scratch).expect("well formed");
            assert_eq!(frozen, plain, "{placement:?} at {q:?}");
            if !plain {
                invalid += 1;
                continue;
            }
            valid += 1;
            let delta: Vec<f64> = (0..7).map(|_| rng.random_range(-1.5..1.5)).collect();
            let fresh = case.validity().expect("a valid layout");
            let frozen = warmed
                .free_radius(&q, &delta, 1.0, &mut scratch)
                .expect("well formed");
            let plain = fresh
                .free_radius(&q, &delta, 1.0, &mut fresh_scratch)
                .expect("well formed");
            assert_eq!(
                frozen.map(f64::to_bits),
                plain.map(f64::to_bits),
                "{placement:?} at {q:?} along {delta:?}"
            );
            match plain {
                Some(r) if r >= 0.1 => open += 1,
                Some(_) => shut += 1,
                None => {}
            }
        }
    }
    assert!(valid > 300 && invalid > 300, "{valid} valid, {invalid} not");
    assert!(
        open > 50 && shut > 50,
        "{open} radii over a tenth of the segment, {shut} under"
    );
}
