//! One arm over one region: the grids of columns, rows in parallel, and the tests of one
//! column (the takes from the surface, then the holds up the column).

use cellc_schema::{Artifact, EndEffectorId, ObjectId};
use parry3d_f64::query;
use rand::Rng;
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

use super::{boxes, rng_for, takes, Arm, Grip, ReachOptions, Region, Take};
use crate::kinematics::{solve_ik, IkError, IkOptions, IkTarget};
use crate::math::{Aabb, Iso, Point, Quat, Vec3};
use crate::scene::{Holder, ObjectPlacement, PlacedShape, SceneScratch};
use crate::termination::Termination;
use crate::validity::{SceneValidity, StateValidity};

/// How much farther than a turn of the object could explain an inverse-kinematics miss
/// must be for the other yaws to be skipped, metres.
const FAR_MISS: f64 = 0.05;

/// How close (metres) to the surface a hold's object or hand may come before the hold
/// is not asked for (see `Arm::cuts_into`).
pub const CLEARANCE: f64 = 0.01;

/// How many of its four neighbours must count for a failed column to be tried again.
const REPAIRED_BETWEEN: usize = 2;

/// The effort of a second try: yaws per test, and inverse-kinematics restarts (about
/// four times the first try's).
const PATIENT: (u32, usize) = (8, 8);

/// What one column's tests draw from and count.
struct Trial<'a> {
    rng: &'a mut ChaCha8Rng,
    scratch: &'a mut SceneScratch,
    solves: u64,
    /// The yaws and inverse kinematics of each test.
    effort: &'a ReachOptions,
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
    pub(super) fn region(&self, artifact: &Artifact, region: &Region) -> (Vec<Aabb>, u64, u64) {
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
        let mut fine = self.columns(surface, &takes, (&xs, &ys), &zs, 1, &wanted);
        self.repair(surface, &takes, (&xs, &ys), &zs, &mut fine);
        let tried = (coarse.len() + fine.iter().filter(|c| c.tried).count()) as u64;
        let solves = coarse.iter().chain(&fine).map(|c| c.solves).sum();
        let spans: Vec<Option<(usize, usize)>> = fine
            .iter()
            .map(|c| c.counts.then_some((c.complete, c.top)))
            .collect();
        (boxes::cover(&xs, &ys, &zs, &spans), tried, solves)
    }

    /// Tries again, with [`PATIENT`] effort, each column that failed among neighbours
    /// that count (at least [`REPAIRED_BETWEEN`] of its four): a cheap test's miss there
    /// is more likely than a hole in reach, and one such miss would split the boxes.
    fn repair(
        &self,
        surface: (u32, &Aabb),
        takes: &[Take],
        (xs, ys): (&[f64], &[f64]),
        zs: &[f64],
        columns: &mut [Column],
    ) {
        let nx = xs.len();
        let counts = |columns: &[Column], i: usize, j: usize| columns[i + j * nx].counts;
        let candidates: Vec<usize> = (0..columns.len())
            .filter(|&c| columns[c].tried && !columns[c].counts)
            .filter(|&c| {
                let (i, j) = (c % nx, c / nx);
                let around = [
                    (i > 0).then(|| (i - 1, j)),
                    (i + 1 < nx).then(|| (i + 1, j)),
                    (j > 0).then(|| (i, j - 1)),
                    (j + 1 < ys.len()).then(|| (i, j + 1)),
                ];
                around
                    .iter()
                    .flatten()
                    .filter(|&&(i, j)| counts(columns, i, j))
                    .count()
                    >= REPAIRED_BETWEEN
            })
            .collect();
        let effort = ReachOptions {
            yaws: PATIENT.0,
            ik: IkOptions {
                restarts: PATIENT.1,
                ..self.options.ik
            },
            ..self.options.clone()
        };
        let repaired: Vec<(usize, Column)> = candidates
            .par_iter()
            .map_init(SceneScratch::default, |scratch, &c| {
                let row = (2 << 32) | c as u64;
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
                    effort: &effort,
                };
                let (x, y) = (xs[c % nx], ys[c / nx]);
                let mut column = self.column(surface, takes, (x, y), zs, &mut memory, &mut trial);
                column.solves = trial.solves + columns[c].solves;
                column.tried = true;
                (c, column)
            })
            .collect();
        for (c, column) in repaired {
            columns[c] = column;
        }
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
                    effort: self.options,
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
        let cuts = |shape: &PlacedShape, at: Iso| {
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
        let n = trial.effort.yaws.max(1);
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
                &trial.effort.ik,
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
                    on: EndEffectorId(on),
                    pose: object_pose,
                    by: Some(EndEffectorId(self.e)),
                },
                None => ObjectPlacement::Held {
                    by: EndEffectorId(self.e),
                    grasp: grip.grasp,
                },
            };
            let arm = [EndEffectorId(self.e)];
            let free = SceneValidity::new(self.scene, &arm, &[], ObjectId(grip.object), placement)
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
