//! Timing a certified path: smoothed through its corners (`blend.rs`), then parameterised
//! time-optimally under every joint's speed and acceleration limits (`topp.rs`), each
//! section from rest to rest, and written out as points with positions, velocities and
//! accelerations: at the parameterisation's knots, or at a control rate.
//!
//! The knots are the grid points of the parameterisation, at most
//! [`MotionOptions::grid_step`] of arc length apart (so never more than that per joint),
//! with every junction of a line and an arc among them. On a step between two knots the
//! path parameter's acceleration `s̈` is constant (TOPP-RA's profile): a point's
//! acceleration is the one of the step that starts there (the last point's, of the step
//! that ends there). A jerk limit, where the cell declares one, is met on the knots by
//! slowing the whole motion evenly (jerk falls with the cube of the slow-down); the
//! profile itself stays TOPP-RA's, not a jerk-limited one.

use super::blend::{smooth, Piece, Smoothed};
use super::topp::{parameterise, Limits, PathGrid, Timing, ToppError};
use super::{MotionError, MotionOptions, TimingOptions};
use crate::plan::{Trajectory, TrajectoryPoint};
use crate::robot::RateLimits;
use crate::validity::StateValidity;
use cellc_schema::EndEffectorId;

/// Largest turn (rad) of an arc between two grid points: a chord of a turn `θ` moves a
/// joint at most `(θ/2)²/2` (5e-5 here) faster than the arc's ends do, which
/// [`VELOCITY_MARGIN`] covers.
const MAX_TURN: f64 = 0.02;
/// Share of each speed limit the parameterisation keeps in hand, so that speeds between
/// grid points (where the limits are not imposed) stay within the limits too.
const VELOCITY_MARGIN: f64 = 1e-3;
/// Share of each acceleration limit kept in hand, for the same reason (TOPP-RA imposes
/// the limits at both ends of every step; on an arc the acceleration turns in between).
const ACCELERATION_MARGIN: f64 = 1e-2;

/// The limits of the joints of a motion, concatenated in the motion's order.
#[derive(Clone, Debug, Default)]
pub(super) struct MotionLimits {
    pub(super) velocity: Vec<f64>,
    pub(super) acceleration: Vec<f64>,
    pub(super) jerk: Vec<Option<f64>>,
}

impl MotionLimits {
    /// Appends one arm's limits.
    pub(super) fn push(&mut self, rates: &RateLimits) {
        self.velocity.extend_from_slice(&rates.velocity);
        self.acceleration.extend_from_slice(&rates.acceleration);
        self.jerk.extend_from_slice(&rates.jerk);
    }

    /// The limits a request's scalings leave (jerk scales as acceleration does).
    fn scaled(&self, timing: &TimingOptions) -> MotionLimits {
        MotionLimits {
            velocity: self
                .velocity
                .iter()
                .map(|v| v * timing.velocity_scaling)
                .collect(),
            acceleration: self
                .acceleration
                .iter()
                .map(|a| a * timing.acceleration_scaling)
                .collect(),
            jerk: self
                .jerk
                .iter()
                .map(|j| j.map(|j| j * timing.acceleration_scaling))
                .collect(),
        }
    }
}

/// One rest-to-rest section, parameterised: its pieces, where each starts in the
/// section's arc length, the grid and its timing.
struct Timed<'p> {
    pieces: &'p [Piece],
    starts: Vec<f64>,
    grid: PathGrid,
    timing: Timing,
}

impl Timed<'_> {
    /// Position, velocity and acceleration at grid point `i`.
    fn knot(&self, i: usize, start: f64, out: &mut TrajectoryPoint) {
        let s = self.grid.s[i];
        let sdot = self.timing.sdot[i];
        let sddot = self.timing.sddot[i.min(self.timing.sddot.len() - 1)];
        self.at(s, sdot, sddot, start + self.timing.time[i], out);
    }

    /// The point at arc length `s` moving at `sdot` and accelerating at `sddot`.
    fn at(&self, s: f64, sdot: f64, sddot: f64, time: f64, out: &mut TrajectoryPoint) {
        let k = self.starts.partition_point(|&a| a <= s).saturating_sub(1);
        let k = k.min(self.pieces.len() - 1);
        let dim = out.positions.len();
        let (mut dq, mut ddq) = (vec![0.0; dim], vec![0.0; dim]);
        self.pieces[k].eval(s - self.starts[k], &mut out.positions, &mut dq, &mut ddq);
        for j in 0..dim {
            out.velocities[j] = dq[j] * sdot;
            out.accelerations[j] = dq[j] * sddot + ddq[j] * sdot * sdot;
        }
        out.time = time;
    }

    /// The state at `t` seconds into the section (within it).
    fn sample(&self, t: f64, start: f64, out: &mut TrajectoryPoint) {
        let time = &self.timing.time;
        let i = time.partition_point(|&a| a <= t).saturating_sub(1);
        let i = i.min(time.len() - 2);
        let tau = (t - time[i]).max(0.0);
        let (s0, s1) = (self.grid.s[i], self.grid.s[i + 1]);
        let (v, a) = (self.timing.sdot[i], self.timing.sddot[i]);
        let s = (s0 + v * tau + 0.5 * a * tau * tau).clamp(s0, s1);
        let sdot = (v + a * tau).max(0.0);
        self.at(s, sdot, a, start + t, out);
    }
}

/// The grid of a section: every piece cut into equal steps of at most `step`, a junction
/// taking an arc's derivatives (the curvature the speed there must respect).
fn grid(pieces: &[Piece], dim: usize, step: f64) -> (PathGrid, Vec<f64>) {
    let mut g = PathGrid {
        s: Vec::new(),
        dq: Vec::new(),
        ddq: Vec::new(),
        dim,
    };
    let mut starts = Vec::with_capacity(pieces.len());
    let (mut q, mut dq, mut ddq) = (vec![0.0; dim], vec![0.0; dim], vec![0.0; dim]);
    let mut offset = 0.0;
    for (k, piece) in pieces.iter().enumerate() {
        starts.push(offset);
        let length = piece.length();
        let turns = match piece {
            Piece::Arc { angle, .. } => (angle / MAX_TURN).ceil(),
            Piece::Line { .. } => 1.0,
        };
        let n = (length / step).ceil().max(turns).max(1.0) as usize;
        let first = if k == 0 { 0 } else { 1 };
        if k > 0 && matches!(piece, Piece::Arc { .. }) {
            // The junction is the previous piece's last point: an arc's start wins.
            piece.eval(0.0, &mut q, &mut dq, &mut ddq);
            let at = g.dq.len() - dim;
            g.dq[at..].copy_from_slice(&dq);
            g.ddq[at..].copy_from_slice(&ddq);
        }
        for i in first..=n {
            // The last point exactly at the piece's length, so that it and the next
            // piece's start (`offset + length` too) are the same number: the point where
            // one piece ends is evaluated on the piece that starts there, whose step it
            // begins, not on the one before by a rounding of `length * n / n`.
            let s = if i == n {
                length
            } else {
                length * i as f64 / n as f64
            };
            piece.eval(s, &mut q, &mut dq, &mut ddq);
            g.s.push(offset + s);
            g.dq.extend_from_slice(&dq);
            g.ddq.extend_from_slice(&ddq);
        }
        offset += length;
    }
    (g, starts)
}

/// Times the waypoints of `path` (`dim` values each, consecutive ones distinct, every
/// segment certified through `validity`): smoothed, parameterised under `limits` as
/// `timing` scales them, and sampled at the knots or at `timing.rate`.
#[allow(clippy::too_many_arguments)]
pub(super) fn time_path<S>(
    path: &[f64],
    dim: usize,
    arms: &[EndEffectorId],
    limits: &MotionLimits,
    options: &MotionOptions,
    timing: &TimingOptions,
    validity: &dyn StateValidity<Scratch = S>,
    scratch: &mut S,
) -> Result<Trajectory, MotionError> {
    let smoothed = smooth(
        path,
        dim,
        options.blend_deviation,
        options.grid_step,
        validity,
        scratch,
    )
    .map_err(MotionError::Query)?;
    let goal = &path[path.len() - dim..];
    time_sections(&smoothed, &path[..dim], goal, arms, limits, options, timing)
}

/// Times a smoothed path from `start` to `goal` (its first and last configurations):
/// each section parameterised under `limits` as `timing` scales them, and sampled at the
/// knots or at `timing.rate`.
pub(super) fn time_sections(
    smoothed: &Smoothed,
    start: &[f64],
    goal: &[f64],
    arms: &[EndEffectorId],
    limits: &MotionLimits,
    options: &MotionOptions,
    timing: &TimingOptions,
) -> Result<Trajectory, MotionError> {
    let dim = start.len();
    let first = TrajectoryPoint::at_rest(0.0, start);
    let limits = limits.scaled(timing);
    let topp = Limits {
        velocity: limits
            .velocity
            .iter()
            .map(|v| v * (1.0 - VELOCITY_MARGIN))
            .collect(),
        acceleration: limits
            .acceleration
            .iter()
            .map(|a| a * (1.0 - ACCELERATION_MARGIN))
            .collect(),
    };
    let mut sections = Vec::with_capacity(smoothed.sections.len());
    for pieces in &smoothed.sections {
        let (grid, starts) = grid(pieces, dim, options.grid_step);
        let timing = parameterise(&grid, &topp).map_err(untimed)?;
        sections.push(Timed {
            pieces,
            starts,
            grid,
            timing,
        });
    }
    let slow = slow_down(&sections, &limits, dim);
    if slow > 1.0 {
        for t in &mut sections {
            stretch(&mut t.timing, slow);
        }
    }
    // A point's acceleration is the one of the step that starts there: the first point's
    // that of the first step, and where one rest-to-rest section ends and the next
    // begins (at rest, at the same time), the next section's first step's.
    let mut first = first;
    if let Some(t) = sections.first() {
        t.knot(0, 0.0, &mut first);
        first.positions.copy_from_slice(start);
        first.velocities.fill(0.0);
    }
    let mut point = first.clone();
    let mut points = vec![first];
    let mut start = 0.0;
    match timing.rate {
        None => {
            for (k, t) in sections.iter().enumerate() {
                if k > 0 {
                    t.knot(0, start, &mut point);
                    if let Some(junction) = points.last_mut() {
                        junction.accelerations.copy_from_slice(&point.accelerations);
                    }
                }
                for i in 1..t.grid.s.len() {
                    t.knot(i, start, &mut point);
                    points.push(point.clone());
                }
                start += t.timing.duration();
            }
        }
        Some(rate) => {
            let total: f64 = sections.iter().map(|t| t.timing.duration()).sum();
            let count = (total * rate).ceil();
            if count > TimingOptions::MAX_POINTS as f64 {
                return Err(MotionError::InvalidOption {
                    name: "rate",
                    value: rate,
                });
            }
            let mut k = 1usize;
            for t in &sections {
                let end = start + t.timing.duration();
                while (k as f64) / rate < end {
                    t.sample(k as f64 / rate - start, start, &mut point);
                    points.push(point.clone());
                    k += 1;
                }
                start = end;
            }
            if let Some(t) = sections.last() {
                t.knot(t.grid.s.len() - 1, start - t.timing.duration(), &mut point);
                points.push(point.clone());
            }
        }
    }
    // The last point is the goal itself, at rest.
    if let Some(last) = points.last_mut() {
        last.positions.copy_from_slice(goal);
        last.velocities.fill(0.0);
    }
    Ok(Trajectory {
        arms: arms.to_vec(),
        points,
    })
}

/// A parameterisation that failed. Kinematic limits leave standing still admissible
/// everywhere, so only a degenerate grid or rounding gets here.
fn untimed(e: ToppError) -> MotionError {
    let index = match e {
        ToppError::Infeasible { index } => index,
        ToppError::Malformed(_) => 0,
    };
    MotionError::Untimed { index }
}

/// The factor every time must grow by for the knots' jerk (the change of acceleration
/// between consecutive knots over their time apart) to stay within the declared limits.
fn slow_down(sections: &[Timed<'_>], limits: &MotionLimits, dim: usize) -> f64 {
    if limits.jerk.iter().all(Option::is_none) {
        return 1.0;
    }
    let mut worst: f64 = 1.0;
    let mut a = TrajectoryPoint::at_rest(0.0, &vec![0.0; dim]);
    let mut b = a.clone();
    for t in sections {
        for i in 0..t.grid.s.len() - 1 {
            t.knot(i, 0.0, &mut a);
            t.knot(i + 1, 0.0, &mut b);
            let dt = b.time - a.time;
            for (j, jerk) in limits.jerk.iter().enumerate() {
                if let Some(jerk) = jerk {
                    let fd = (b.accelerations[j] - a.accelerations[j]).abs() / dt;
                    worst = worst.max(fd / jerk);
                }
            }
        }
    }
    worst.cbrt()
}

/// Slows a timing down evenly by `k`: speeds divided by `k`, accelerations by `k²`.
fn stretch(timing: &mut Timing, k: f64) {
    timing.sdot.iter_mut().for_each(|v| *v /= k);
    timing.sddot.iter_mut().for_each(|a| *a /= k * k);
    timing.time.iter_mut().for_each(|t| *t *= k);
}
