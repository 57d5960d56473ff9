//! The queries that stand on the cell at home (`collision::home`, `collision::frozen`)
//! against the plain broad phase, which places and sorts every body of the cell: the
//! same validity and, bit for bit, the same free radius, for one-off questions and for a
//! motion's frozen queries, with arms at home, arms standing by away from home, the
//! object held, resting, handed over or put down, and another object in the way. Plans
//! would otherwise depend on which path a checker took.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

#[path = "../../tests/support/motion_fixture.rs"]
mod fixture;

use super::{Holder, ObjectPlacement, Obstacle, Placed, Scene, SceneScratch};
use crate::collision::SweepBounds;
use crate::math::Iso;
use crate::swept::SweptBodies;
use crate::validity::arm_slices;
use cellc_schema::{self as schema, EndEffectorId, ObjectId};

/// Four arms in a row, 0.75 m apart (neighbours reach each other), a table in front of
/// them, a pillar between the middle two; the can and a second object, a box.
fn line() -> Scene {
    let arms = [
        ("a", [0.0, 0.0, 0.0, 0.0]),
        ("b", [0.75, 0.0, 0.0, 0.0]),
        ("c", [1.5, 0.0, 0.0, 0.0]),
        ("d", [2.25, 0.0, 0.0, 0.0]),
    ];
    let boxes = [
        ("table", [-0.3, 0.35, 0.0], [2.6, 0.9, 0.4]),
        ("pillar", [1.05, -0.45, 0.0], [1.2, -0.3, 0.9]),
    ];
    let mut artifact = fixture::artifact(&arms, &boxes);
    let mut other = artifact.objects[0].clone();
    other.name = "crate".into();
    other.shape = Some(schema::Shape::Box {
        size: [0.2, 0.2, 0.2],
    });
    artifact.objects.push(other);
    Scene::load(&artifact, &fixture::Repo).expect("the test cell loads")
}

/// The plain answers: every body placed and swept.
fn plain_free(
    scene: &Scene,
    arms: &[(EndEffectorId, &[f64])],
    at: Placed<'_>,
    scratch: &mut SceneScratch,
) -> bool {
    scene
        .with_configuration(arms, at, scratch, |state, s, _| {
            scene.world.is_free(state, s)
        })
        .expect("well formed")
}

fn plain_radius(
    scene: &Scene,
    arms: &[(EndEffectorId, &[f64])],
    at: Placed<'_>,
    bounds: &SweepBounds,
    scratch: &mut SceneScratch,
) -> f64 {
    scene
        .with_configuration(arms, at, scratch, |state, s, _| {
            scene.world.free_radius(state, bounds, 1.0, s)
        })
        .expect("well formed")
}

const B: EndEffectorId = EndEffectorId(1);
const C: EndEffectorId = EndEffectorId(2);
const D: EndEffectorId = EndEffectorId(3);
const TABLE: EndEffectorId = EndEffectorId(4);
const HOME: [f64; 7] = [0.0; 7];

#[test]
fn standing_answers_are_the_plain_answers() {
    let scene = line();
    let Holder::Arm { robot, .. } = &scene.holders[1] else {
        panic!("end-effector 1 is an arm");
    };
    let robot = &scene.robots[*robot];
    let grasp = Iso::translation(0.0, 0.0, 0.2);
    let on_table = Iso::translation(0.75, 0.6, 0.55);
    // Arm b moves; arm c stands by at a random configuration in some cases.
    let placements = [
        ObjectPlacement::Held { by: B, grasp },
        ObjectPlacement::Resting {
            on: TABLE,
            pose: on_table,
            by: Some(B),
        },
        ObjectPlacement::Handoff {
            a: C,
            grasp_a: grasp,
            b: B,
        },
        ObjectPlacement::Placing {
            by: B,
            grasp,
            on: TABLE,
            also: None,
            from: None,
        },
        ObjectPlacement::Absent,
    ];
    let crate_on_table = [Obstacle {
        object: ObjectId(1),
        placement: ObjectPlacement::Resting {
            on: TABLE,
            pose: Iso::translation(1.1, 0.55, 0.5),
            by: None,
        },
    }];
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let mut scratch = SceneScratch::default();
    let mut frozen_scratch = SceneScratch::default();
    let mut plain_scratch = SceneScratch::default();
    let (mut free, mut hit, mut wide, mut narrow) = (0, 0, 0, 0);
    let mut q = vec![0.0; 7];
    let mut qc = vec![0.0; 7];
    for (k, placement) in placements.into_iter().enumerate() {
        for with_crate in [false, true] {
            for stand_by in [false, true] {
                if matches!(placement, ObjectPlacement::Handoff { .. }) && !stand_by {
                    continue;
                }
                robot.sample_configuration(&mut rng, &mut qc);
                let obstacles: &[Obstacle] = if with_crate { &crate_on_table } else { &[] };
                let at = Placed {
                    object: ObjectId(0),
                    placement,
                    obstacles,
                };
                let slices = arm_slices(&scene, &[B]).expect("an arm");
                let swept = SweptBodies::new(&scene, &slices, ObjectId(0), &placement);
                let mut frozen = None;
                for _ in 0..120 {
                    robot.sample_configuration(&mut rng, &mut q);
                    // Arm d is listed at its home joints, as the planner lists every arm.
                    let mut arms: Vec<(EndEffectorId, &[f64])> = vec![(B, &q), (D, &HOME)];
                    if stand_by {
                        arms.push((C, &qc));
                    }
                    let frozen = frozen.get_or_insert_with(|| {
                        scene
                            .freeze(&arms, &[B], at, false, &mut frozen_scratch)
                            .expect("freezes")
                    });
                    let plain = plain_free(&scene, &arms, at, &mut plain_scratch);
                    let standing = scene
                        .is_free(&arms, ObjectId(0), placement, obstacles, &mut scratch)
                        .expect("well formed");
                    let moving = &arms[..1];
                    let motion = scene
                        .is_free_frozen(frozen, moving, &mut frozen_scratch)
                        .expect("well formed");
                    let case =
                        format!("{k} {placement:?} crate {with_crate} c {stand_by:?} at {q:?}");
                    assert_eq!(standing, plain, "one-off: {case}");
                    assert_eq!(motion, plain, "frozen: {case}");
                    if !plain {
                        hit += 1;
                        continue;
                    }
                    free += 1;
                    let delta: Vec<f64> = (0..7).map(|_| rng.random_range(-1.5..1.5)).collect();
                    let mut bounds = SweepBounds::default();
                    swept
                        .fill(&delta, &mut bounds, scene.world.body_count())
                        .expect("finite bounds");
                    let plain = plain_radius(&scene, &arms, at, &bounds, &mut plain_scratch);
                    let standing = scene
                        .free_radius(&arms, at, &bounds, 1.0, &mut scratch)
                        .expect("well formed");
                    let motion = scene
                        .free_radius_frozen(frozen, moving, &bounds, 1.0, &mut frozen_scratch)
                        .expect("well formed");
                    assert_eq!(standing.to_bits(), plain.to_bits(), "one-off: {case}");
                    assert_eq!(motion.to_bits(), plain.to_bits(), "frozen: {case}");
                    if plain >= 0.1 {
                        wide += 1;
                    } else {
                        narrow += 1;
                    }
                }
            }
        }
    }
    assert!(free > 400 && hit > 400, "{free} free, {hit} colliding");
    assert!(
        wide > 100 && narrow > 100,
        "{wide} radii over 0.1, {narrow} under"
    );
}

/// An arm standing on another's hand: at home the lower one's hand is inside the upper
/// one's base, so every state that leaves the lower arm at home collides (the pair is
/// found once, when the home is built), and moving it away can free the state, as the
/// plain broad phase agrees.
#[test]
fn arms_touching_at_home_collide_until_one_moves() {
    let arms = [
        ("a", [0.0, 0.0, 0.0, 0.0]),
        ("b", [0.0, 0.0, 1.15, 0.0]),
        ("c", [2.0, 0.0, 0.0, 0.0]),
    ];
    let scene = Scene::load(&fixture::artifact(&arms, &[]), &fixture::Repo).expect("loads");
    let Holder::Arm { robot, .. } = &scene.holders[0] else {
        panic!("end-effector 0 is an arm");
    };
    let robot = &scene.robots[*robot];
    let at = Placed {
        object: ObjectId(0),
        placement: ObjectPlacement::Absent,
        obstacles: &[],
    };
    let mut scratch = SceneScratch::default();
    let mut plain_scratch = SceneScratch::default();
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let mut q = vec![0.0; 7];
    let (mut free, mut hit) = (0, 0);
    for arm in [EndEffectorId(0), EndEffectorId(1), EndEffectorId(2)] {
        for _ in 0..100 {
            robot.sample_configuration(&mut rng, &mut q);
            let arms = [(arm, q.as_slice())];
            let plain = plain_free(&scene, &arms, at, &mut plain_scratch);
            let standing = scene
                .is_free(
                    &arms,
                    ObjectId(0),
                    ObjectPlacement::Absent,
                    &[],
                    &mut scratch,
                )
                .expect("well formed");
            assert_eq!(standing, plain, "{arm:?} at {q:?}");
            if arm != EndEffectorId(0) {
                assert!(!standing, "a and b touch while a is at home");
            }
            if standing {
                free += 1;
            } else {
                hit += 1;
            }
        }
    }
    assert!(free > 20 && hit > 120, "{free} free, {hit} colliding");
}
