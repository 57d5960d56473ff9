//! Reach from kinematics: where over each surface an arm can take its objects and hold
//! them with every one of its grasps, as a few boxes per surface (`reach ARM auto` in a
//! cell).
//!
//! # Method
//!
//! Over a surface's reach space (its top face extruded by its reach height) a grid of
//! *columns* is laid, [`ReachOptions::spacing`] apart along x and y (both edges
//! included), with *heights* twice that apart from the top face up. A column counts when
//!
//! 1. every *take* works there: for every resting pose on the surface and every grasp of
//!    the arm that a declared transition joins to it, the object resting centred on the
//!    column is taken with the grasp (inverse kinematics for the hand's pose, then the
//!    state as verification checks a rest: joint limits, collisions with the other arms
//!    at home, the object resting on the surface and held); and
//! 2. the object is *held* up the column: at each height, from the bottom up, some grasp
//!    holds the object upright there (as verification's holds do), and every grasp holds
//!    it at some height. A hold whose object or hand would come within [`CLEARANCE`] of
//!    the surface is not asked for: objects there rest, they are taken rather than held.
//!    The column counts for boxes whose top lies between the height by which every
//!    grasp has held and the last height held.
//!
//! A test passes when some yaw of the object about the vertical works, of
//! [`ReachOptions::yaws`] evenly spaced from an offset drawn once per row (a symmetric
//! object may be taken at any of them; any other stands wherever it is placed, so the
//! box promises that some approach works, as a hand-written box does). Columns beyond
//! the arm's reach (the sum of its links, its tip offset and its longest grasp, from the
//! base) fail without a solve.
//!
//! The grid is tried at twice the spacing first, then at the spacing only near columns
//! that counted. Rows run in parallel; along a row, each test is seeded with what worked
//! in the column before (neighbouring poses have neighbouring solutions), and each row
//! draws from its own generator, seeded from the seed, the arm, the surface and the row,
//! so the answer does not depend on threads. The boxes are the largest by volume from
//! the top face up whose grid cells have counting corners, then the largest of what is
//! left, while it is worth a workspace ([`MAX_BOXES_PER_REGION`], [`MIN_STEPS`]). A column
//! that failed between columns that count is tried again with more effort first: one
//! cheap miss would split the boxes.
//!
//! # Error
//!
//! Only grid points are tried: a face of a box lies on the last column (or height) that
//! passed, so up to one spacing inside where reach really ends, and a hole narrower than
//! a spacing between tried points goes unseen. Each test tries the seeded restarts of
//! [`ReachOptions::ik`]: a point that needs more is counted out (the box errs small), and
//! the largest boxes leave out reach that is not box-shaped. `docs/language.md` gives the
//! error measured on the Vito cell.

mod boxes;
mod column;

pub use column::CLEARANCE;

use std::time::{Duration, Instant};

use cellc_schema::{self as schema, Artifact, EndEffectorId};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use crate::kinematics::IkOptions;
use crate::math::{iso_from_schema, Aabb, Iso};
use crate::scene::{Holder, PlacedShape, Scene};

/// How reach is sampled.
#[derive(Clone, Debug)]
pub struct ReachOptions {
    /// Distance between grid columns and between heights, metres (at most
    /// [`MAX_POINTS_PER_AXIS`] columns along an axis: a larger surface gets a coarser
    /// grid).
    pub spacing: f64,
    /// Yaws of the object about the vertical tried per test.
    pub yaws: u32,
    /// Inverse kinematics of each test.
    pub ik: IkOptions,
    /// Seed of every generator.
    pub seed: u64,
}

/// Columns (or heights) along one axis of a region, at most.
pub const MAX_POINTS_PER_AXIS: usize = 41;

/// Boxes over one region, at most: the largest, then the largest of what it leaves
/// (reach over a table beside a torso is an L more often than a rectangle).
pub const MAX_BOXES_PER_REGION: usize = 3;

/// A box after the first is kept when it is at least this many grid steps wide along x
/// and y; narrower ones would only cut workspaces into slivers.
pub const MIN_STEPS: usize = 2;

impl Default for ReachOptions {
    fn default() -> ReachOptions {
        ReachOptions {
            spacing: 0.05,
            yaws: 4,
            // Most tests that fail are far out of reach; a try that has not converged in
            // 50 iterations rarely does (neighbouring columns seed each other, so the
            // tries that matter start near a solution).
            ik: IkOptions {
                restarts: 4,
                max_iterations: 50,
                ..IkOptions::default()
            },
            seed: 0,
        }
    }
}

/// A region to find an arm's reach in: a surface's reach space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Region {
    /// The surface.
    pub surface: EndEffectorId,
    /// Its reach space.
    pub space: Aabb,
}

/// What was found for one arm.
#[derive(Clone, Debug, PartialEq)]
pub struct ArmReach {
    /// Per region, in order, its boxes (none where nothing counts; see
    /// [`MAX_BOXES_PER_REGION`]).
    pub boxes: Vec<Vec<Aabb>>,
    /// Grid columns tried.
    pub tried: u64,
    /// Inverse-kinematics solves run.
    pub solves: u64,
    /// How long it took.
    pub elapsed: Duration,
}

/// Why an arm's reach cannot be computed.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum ReachError {
    /// The end-effector is not an arm.
    NotAnArm,
    /// A robot with fewer than six joints cannot take the hand poses tried.
    TooFewJoints {
        /// Its joints.
        joints: usize,
    },
}

/// One grasp of the arm: its object, its pose, and how far the hand frame is from the
/// vertical through the object's centre (what a turn about that vertical moves it by).
#[derive(Clone, Copy, Debug)]
struct Grip {
    object: u32,
    grasp: Iso,
    across: f64,
}

impl Grip {
    fn new(object: u32, grasp: Iso) -> Grip {
        // The hand frame's origin in the object frame: where it is across the vertical
        // for an upright object (and no farther from the centre for a tilted one).
        let hand = grasp.inverse().translation.vector;
        Grip {
            object,
            grasp,
            across: hand.norm(),
        }
    }
}

/// A resting pose on the surface taken with one of the arm's grasps.
#[derive(Clone, Copy, Debug)]
struct Take {
    grip: Grip,
    /// The resting pose, in the surface's frame at its top face.
    rest: Iso,
}

/// Everything one arm's tests share.
struct Arm<'a> {
    scene: &'a Scene,
    e: u32,
    robot: &'a crate::robot::Robot,
    base: Iso,
    home: &'a [f64],
    grips: Vec<Grip>,
    /// The solids of its hand, in the hand frame.
    hand: &'a [PlacedShape],
    /// How far from the base origin any object it holds can be.
    radius: f64,
    options: &'a ReachOptions,
}

/// The reach of arm `arm` over each of `regions`.
pub fn arm_reach(
    artifact: &Artifact,
    scene: &Scene,
    arm: EndEffectorId,
    regions: &[Region],
    options: &ReachOptions,
) -> Result<ArmReach, ReachError> {
    let start = Instant::now();
    let Some(Holder::Arm { robot, base, home }) = scene.holders.get(arm.index()) else {
        return Err(ReachError::NotAnArm);
    };
    let robot = &scene.robots[*robot];
    if robot.n_joints() < 6 {
        return Err(ReachError::TooFewJoints {
            joints: robot.n_joints(),
        });
    }
    let grips = grips(artifact, arm);
    let links: f64 = robot
        .origins()
        .iter()
        .map(|o| o.translation.vector.norm())
        .sum();
    let longest = grips
        .iter()
        .map(|g| g.grasp.translation.vector.norm())
        .fold(0.0, f64::max);
    let context = Arm {
        scene,
        e: arm.0,
        robot,
        base: *base,
        home,
        grips,
        hand: artifact.end_effectors[arm.index()]
            .kind
            .and_then(|k| scene.kind_solids.get(k as usize))
            .map_or(&[], Vec::as_slice),
        radius: links + robot.tip_offset().translation.vector.norm() + longest,
        options,
    };
    let mut found = ArmReach {
        boxes: Vec::with_capacity(regions.len()),
        tried: 0,
        solves: 0,
        elapsed: Duration::ZERO,
    };
    for region in regions {
        let (b, tried, solves) = context.region(artifact, region);
        found.boxes.push(b);
        found.tried += tried;
        found.solves += solves;
    }
    found.elapsed = start.elapsed();
    Ok(found)
}

/// The grasps arm `e` can hold (not resting poses), in object and grasp order.
fn grips(artifact: &Artifact, e: EndEffectorId) -> Vec<Grip> {
    let kind = artifact.end_effectors[e.index()].kind;
    let mut out = Vec::new();
    for (o, object) in artifact.objects.iter().enumerate() {
        for grasp in &object.grasps {
            let ours = match grasp.holder {
                schema::Holder::EndEffector(h) => h == e.0,
                schema::Holder::Kind(k) => kind == Some(k),
            };
            if ours && !grasp.rest {
                out.push(Grip::new(
                    o as u32,
                    grasp
                        .pose
                        .as_ref()
                        .map_or_else(Iso::identity, iso_from_schema),
                ));
            }
        }
    }
    out
}

/// The takes of arm `arm` from `surface`: every resting pose on it joined by a declared
/// transition (either way) to a grasp of the arm.
fn takes(artifact: &Artifact, arm: &Arm<'_>, surface: EndEffectorId) -> Vec<Take> {
    let kind_of = |e: u32| artifact.end_effectors.get(e as usize).and_then(|x| x.kind);
    let held_by = |holder: schema::Holder, e: u32| match holder {
        schema::Holder::EndEffector(h) => h == e,
        schema::Holder::Kind(k) => kind_of(e) == Some(k),
    };
    let mut out = Vec::new();
    for (o, object) in artifact.objects.iter().enumerate() {
        for t in &object.transitions {
            for (r, g) in [(t.from, t.to), (t.to, t.from)] {
                let (Some(rest), Some(grasp)) =
                    (object.grasps.get(r as usize), object.grasps.get(g as usize))
                else {
                    continue;
                };
                if !(rest.rest && held_by(rest.holder, surface.0))
                    || grasp.rest
                    || !held_by(grasp.holder, arm.e)
                {
                    continue;
                }
                let rest = rest
                    .pose
                    .as_ref()
                    .map_or_else(Iso::identity, iso_from_schema);
                let grasp = grasp
                    .pose
                    .as_ref()
                    .map_or_else(Iso::identity, iso_from_schema);
                let take = Take {
                    grip: Grip::new(o as u32, grasp),
                    rest,
                };
                // `a <-> b` declares both directions: one take each.
                let same = |x: &Take| {
                    x.grip.object == take.grip.object
                        && x.rest == take.rest
                        && x.grip.grasp == take.grip.grasp
                };
                if !out.iter().any(same) {
                    out.push(take);
                }
            }
        }
    }
    out
}

/// The generator of one row of columns: the same for a given seed, arm, surface and row,
/// whatever thread tries it.
fn rng_for(seed: u64, arm: u32, surface: u32, row: u64) -> ChaCha8Rng {
    let mut h = seed ^ 0xA5A5_5A5A_0F0F_F0F0;
    for word in [u64::from(arm), u64::from(surface), row] {
        // SplitMix64 steps, as verification seeds its checks.
        h = h.wrapping_add(word).wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = h;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        h = z ^ (z >> 31);
    }
    ChaCha8Rng::seed_from_u64(h)
}
