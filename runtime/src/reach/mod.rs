//! Reach from kinematics: where over each surface an arm can use every one of its grasps,
//! as one box per surface (`reach ARM auto` in a cell).
//!
//! # Method
//!
//! Over a surface's reach space (its top face extruded by its reach height) a grid of
//! columns is laid, [`ReachOptions::spacing`] apart (both edges included), and each
//! column is tried, independently of the others and with its own generator (seeded from
//! the arm, the surface and the column, so the answer does not depend on threads):
//!
//! 1. *Taking and leaving on the surface*: for every resting pose on the surface and
//!    every grasp of the arm that a declared transition joins to it, the object resting
//!    there (centred on the column) is taken with the grasp: inverse kinematics for the
//!    hand's pose, then the state is checked as verification checks a rest (joint limits,
//!    collisions with the other arms at home, the object resting on the surface and held).
//! 2. *Holding above it*: at each height of the column, a spacing apart from the top face
//!    up, for every grasp of the arm, the object upright at that point is held (as
//!    verification's holds are); a height where the object would cut into the surface
//!    counts for no grasp (no such pose exists). The column's height is the last of the
//!    heights, from the bottom, at which every grasp holds.
//!
//! A test passes when some yaw of the object about the vertical works, of
//! [`ReachOptions::yaws`] evenly spaced from a drawn offset (a symmetric object may be
//! taken at any of them; any other is wherever it is placed, so its box promises that
//! some approach works, as a hand-written box does). A column counts when all
//! of its tests of step 1 pass and at least one state was solved; the box is then the
//! largest by volume whose grid columns all count and reach its top (from the top face
//! up: objects rest there). Columns beyond the arm's reach (the sum of its links, its
//! tip offset and its longest grasp, from the base) fail without a solve.
//!
//! # Error
//!
//! Only grid points are tried: a face of the box lies on the last column (or height)
//! that passed, so it is up to one spacing inside where reach really ends, and a hole
//! narrower than a spacing between tried points goes unseen. Each test tries the seeded
//! restarts of [`ReachOptions::ik`]: a point that needs more is counted out (the box
//! errs small). `docs/language.md` gives the measured error on the Vito cell.

mod boxes;

use std::time::{Duration, Instant};

use cellc_schema::{self as schema, Artifact, EndEffectorId};
use parry3d_f64::query;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

use crate::kinematics::{solve_ik, IkError, IkOptions, IkTarget};
use crate::math::{iso_from_schema, Aabb, Iso, Point, Quat, Vec3};
use crate::scene::{Holder, ObjectPlacement, Scene, SceneScratch};
use crate::termination::Termination;
use crate::validity::{SceneValidity, StateValidity};

/// How reach is sampled.
#[derive(Clone, Debug)]
pub struct ReachOptions {
    /// Distance between grid columns and between heights, metres (at most
    /// [`MAX_POINTS_PER_AXIS`] columns along an axis: a larger surface gets a coarser
    /// grid).
    pub spacing: f64,
    /// Yaws tried for an object that is not symmetric about the vertical.
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

/// A box after the first is kept when it holds at least this share of the first's
/// volume; smaller ones would only cut workspaces into slivers.
pub const MIN_SHARE: f64 = 0.2;

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

/// How much farther than a turn of the object could explain an inverse-kinematics miss
/// must be for the other yaws to be skipped, metres.
const FAR_MISS: f64 = 0.05;

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
    hand: &'a [crate::scene::PlacedShape],
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

/// How close (metres) to the surface a hold's object or hand may come before the hold
/// is not asked for (see [`Arm::cuts_into`]).
const CLEARANCE: f64 = 0.01;

/// What one column's tests draw from and count.
struct Trial<'a> {
    rng: &'a mut ChaCha8Rng,
    scratch: &'a mut SceneScratch,
    solves: u64,
}

/// What a test leaves for the same test in the next column of the row: the yaws'
/// offset, drawn once per row, and the yaw and solution that last worked (the next
/// column's first seed: neighbouring poses have neighbouring solutions).
#[derive(Clone, Debug, Default)]
struct Memory {
    offset: Option<f64>,
    worked: Option<(u32, Vec<f64>)>,
}

/// The memories of one row: per take, per grasp and height, and per grasp the height at
/// which it first held in the last column where it did.
struct RowMemory {
    takes: Vec<Memory>,
    holds: Vec<Vec<Memory>>,
    first: Vec<Option<usize>>,
}

/// One column's verdict.
#[derive(Clone, Copy, Debug, Default)]
struct Column {
    /// Every take from the surface worked, and every grasp held somewhere.
    counts: bool,
    /// The height index by which every grasp has held at least once.
    complete: usize,
    /// The highest height index up to which some grasp holds at every height, from the
    /// bottom up.
    top: usize,
    /// Whether it was tried at all (the fine grid skips columns far from reach).
    tried: bool,
    solves: u64,
}

impl Arm<'_> {
    /// The boxes over one region, the columns tried and the solves run: a coarse grid
    /// (twice the spacing) first, then the fine grid where a coarse column that counts
    /// is near, so that most of a large surface out of reach costs a quarter of its
    /// columns.
    fn region(&self, artifact: &Artifact, region: &Region) -> (Vec<Aabb>, u64, u64) {
        let Some(Holder::Surface { slab, .. }) = self.scene.holders.get(region.surface.index())
        else {
            return (Vec::new(), 0, 0);
        };
        let takes = takes(artifact, self, region.surface);
        let space = &region.space;
        let grid = |spacing: f64| {
            (
                boxes::points(space.mins.x, space.maxs.x, spacing),
                boxes::points(space.mins.y, space.maxs.y, spacing),
            )
        };
        // Heights twice the spacing apart: reach changes slowly with height over a
        // surface, and holds are most of the cost.
        let zs = boxes::points(space.mins.z, space.maxs.z, 2.0 * self.options.spacing);
        let surface = (region.surface.0, slab);
        let coarse_spacing = 2.0 * self.options.spacing;
        let (cxs, cys) = grid(coarse_spacing);
        let coarse = self.columns(surface, &takes, (&cxs, &cys), &zs, 0, &|_, _| true);
        let near: Vec<(f64, f64)> = coarse
            .iter()
            .enumerate()
            .filter(|(_, c)| c.counts)
            .map(|(c, _)| (cxs[c % cxs.len()], cys[c / cxs.len()]))
            .collect();
        let reach = coarse_spacing * (1.0 + 1e-9);
        let wanted = |x: f64, y: f64| {
            near.iter()
                .any(|&(cx, cy)| (x - cx).abs() <= reach && (y - cy).abs() <= reach)
        };
        let (xs, ys) = grid(self.options.spacing);
        let fine = self.columns(surface, &takes, (&xs, &ys), &zs, 1, &wanted);
        let tried = (coarse.len() + fine.iter().filter(|c| c.tried).count()) as u64;
        let solves = coarse.iter().chain(&fine).map(|c| c.solves).sum();
        let spans: Vec<Option<(usize, usize)>> = fine
            .iter()
            .map(|c| c.counts.then_some((c.complete, c.top)))
            .collect();
        (boxes::cover(&xs, &ys, &zs, &spans), tried, solves)
    }

    /// Tries the columns of a grid that are `wanted` (the others do not count), rows
    /// (along x) in parallel, each column of a row seeded with what worked in the one
    /// before it. `pass` tells the generators of two grids apart.
    fn columns(
        &self,
        surface: (u32, &Aabb),
        takes: &[Take],
        (xs, ys): (&[f64], &[f64]),
        zs: &[f64],
        pass: u64,
        wanted: &(dyn Fn(f64, f64) -> bool + Sync),
    ) -> Vec<Column> {
        let rows: Vec<Vec<Column>> = ys
            .par_iter()
            .enumerate()
            .map_init(SceneScratch::default, |scratch, (j, &y)| {
                let row = (pass << 32) | j as u64;
                let mut rng = rng_for(self.options.seed, self.e, surface.0, row);
                let mut memory = RowMemory {
                    takes: vec![Memory::default(); takes.len()],
                    holds: vec![vec![Memory::default(); zs.len()]; self.grips.len()],
                    first: vec![None; self.grips.len()],
                };
                let mut trial = Trial {
                    rng: &mut rng,
                    scratch,
                    solves: 0,
                };
                xs.iter()
                    .map(|&x| {
                        if !wanted(x, y) {
                            return Column::default();
                        }
                        let before = trial.solves;
                        let mut column =
                            self.column(surface, takes, (x, y), zs, &mut memory, &mut trial);
                        column.solves = trial.solves - before;
                        column.tried = true;
                        column
                    })
                    .collect()
            })
            .collect();
        rows.into_iter().flatten().collect()
    }

    /// Tries one column at (x, y): the takes from the surface, then the holds at each
    /// height from the bottom up.
    fn column(
        &self,
        (surface, slab): (u32, &Aabb),
        takes: &[Take],
        (x, y): (f64, f64),
        zs: &[f64],
        memory: &mut RowMemory,
        trial: &mut Trial<'_>,
    ) -> Column {
        let mut column = Column::default();
        for (take, memory) in takes.iter().zip(&mut memory.takes) {
            let at = Iso::translation(x, y, slab.maxs.z) * take.rest;
            if !self.test(take.grip, at, Some(surface), memory, trial) {
                return column;
            }
        }
        // Up the column: at each height some grasp must hold (or none be asked for, the
        // object or hand too close to the surface), and each grasp must hold at some
        // height. A grasp that held already is tried again only until another holds at
        // the height.
        let mut first: Vec<Option<usize>> = vec![None; self.grips.len()];
        // Each grasp is tried first where it first held in the column before, so that a
        // grasp that holds only high up (a hand under the object) is not tried at every
        // height on the way.
        for (g, grip) in self.grips.iter().enumerate() {
            let Some(k) = memory.first[g] else { continue };
            let at = Iso::translation(x, y, zs[k]);
            if !self.cuts_into(grip, &at, slab)
                && self.test(*grip, at, None, &mut memory.holds[g][k], trial)
            {
                first[g] = Some(k);
            }
        }
        for (k, &z) in zs.iter().enumerate().skip(1) {
            let at = Iso::translation(x, y, z);
            let (mut asked, mut held) = (false, false);
            for ((grip, memory), first) in self.grips.iter().zip(&mut memory.holds).zip(&mut first)
            {
                if (held && first.is_some()) || self.cuts_into(grip, &at, slab) {
                    continue;
                }
                asked = true;
                if self.test(*grip, at, None, &mut memory[k], trial) {
                    held = true;
                    first.get_or_insert(k);
                }
            }
            if asked && !held {
                break;
            }
            column.top = k;
        }
        for (remembered, found) in memory.first.iter_mut().zip(&first) {
            if found.is_some() {
                *remembered = *found;
            }
        }
        let complete = first.iter().try_fold(0, |most, f| f.map(|k| most.max(k)));
        column.counts = complete.is_some();
        column.complete = complete.unwrap_or(usize::MAX);
        column
    }

    /// Whether the object held with `grip` at `pose`, or the hand holding it, comes
    /// within [`CLEARANCE`] of the slab (at any yaw): such a hold is not asked for, so
    /// the height counts for that grasp neither way. Objects on the surface are taken
    /// from it (step 1); holding them just over it is no task of a cell.
    fn cuts_into(&self, grip: &Grip, pose: &Iso, slab: &Aabb) -> bool {
        let half = (slab.maxs - slab.mins) / 2.0;
        let centre = Iso::translation(
            slab.mins.x + half.x,
            slab.mins.y + half.y,
            slab.mins.z + half.z,
        );
        let cuboid = parry3d_f64::shape::Cuboid::new(half);
        let cuts = |shape: &crate::scene::PlacedShape, at: Iso| {
            query::distance(&(at * shape.local), shape.shape.as_ref(), &centre, &cuboid)
                .map_or(true, |d| d < CLEARANCE)
        };
        // The hand turns with the yaw about the object's centre: its lowest reach is the
        // same at every yaw for the object, and a hand solid's height too.
        let hand = *pose * grip.grasp.inverse();
        self.scene.object_shapes[grip.object as usize]
            .iter()
            .any(|s| cuts(s, *pose))
            || self.hand.iter().any(|s| cuts(s, hand))
    }

    /// Whether the arm holds the object with `grip` at `pose` turned about the vertical
    /// by some yaw tried, the object resting on surface `resting` when given. The yaw and
    /// the solution that work are kept in `memory`, tried first the next time.
    fn test(
        &self,
        grip: Grip,
        pose: Iso,
        resting: Option<u32>,
        memory: &mut Memory,
        trial: &mut Trial<'_>,
    ) -> bool {
        let centre = Point::from(pose.translation.vector);
        if (centre - Point::from(self.base.translation.vector)).norm() > self.radius {
            return false;
        }
        let n = self.options.yaws.max(1);
        let offset = *memory
            .offset
            .get_or_insert_with(|| trial.rng.random::<f64>() * std::f64::consts::TAU);
        let first = memory.worked.as_ref().map_or(0, |(i, _)| *i);
        for step in 0..n {
            let i = (first + step) % n;
            let yaw = offset + std::f64::consts::TAU * f64::from(i) / f64::from(n);
            let turn = Quat::from_axis_angle(&Vec3::z_axis(), yaw);
            // Turned about the vertical through the object's centre.
            let object_pose = Iso::from_parts(pose.translation, turn * pose.rotation);
            let tip = object_pose * grip.grasp.inverse();
            let seed = match &memory.worked {
                Some((j, q)) if *j == i => q.as_slice(),
                _ => self.home,
            };
            trial.solves += 1;
            let q = match solve_ik(
                self.robot,
                &self.base,
                &IkTarget::Pose(tip),
                seed,
                trial.rng,
                &self.options.ik,
                &Termination::never(),
            ) {
                Ok(q) => q,
                // Another yaw moves the hand by at most twice the grasp's reach across
                // the vertical: a miss by more is a miss at every yaw.
                Err(IkError::NotConverged { position_error, .. })
                    if position_error > 2.0 * grip.across + FAR_MISS =>
                {
                    return false;
                }
                Err(_) => continue,
            };
            let placement = match resting {
                Some(on) => ObjectPlacement::Resting {
                    on,
                    pose: object_pose,
                    by: Some(self.e),
                },
                None => ObjectPlacement::Held {
                    by: self.e,
                    grasp: grip.grasp,
                },
            };
            let free = SceneValidity::new(self.scene, &[self.e], &[], grip.object, placement)
                .ok()
                .and_then(|v| v.is_valid(&q, trial.scratch).ok());
            if free == Some(true) {
                memory.worked = Some((i, q));
                return true;
            }
        }
        false
    }
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
