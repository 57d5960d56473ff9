//! Straight segments in joint space: how they are cut into the configurations that are
//! checked ([`DiscreteMotion`], the sampled [`MotionValidity`]) and into the points of a
//! timed trajectory, which are the same cuts, so that a trajectory planned with it
//! re-checks exactly as it was planned.

use super::MotionValidity;
use crate::scene::{QueryError, SceneScratch};
use crate::validity::{all_valid, Screened, StateValidity};

/// The sampled [`MotionValidity`]: a segment is valid when the state validity accepts
/// every configuration at which [`super::check_trajectory`] at `resolution` will look
/// once the segment is part of a trajectory timed with output step `step`.
///
/// The segment is cut into the output samples (the trajectory's points at `step`), each
/// piece into the fewest equal steps that move no joint more than `resolution`,
/// and every step's end is checked: so a planned trajectory always passes
/// `check_trajectory` at the planner's resolution, bit for bit, whatever the rounding.
/// The order is coarse to fine (the pieces' ends in bisection order, then the points
/// inside each piece in bisection order), so a blocked segment is usually rejected after
/// a few checks. The configurations go to the state validity in batches in that order:
/// [`StateValidity::screen`] first (the scene's checker judges all of a batch at once,
/// most pairs settled by their capsules, `collision/batch.rs`), then
/// [`StateValidity::is_valid`] for what it left unknown, until one is invalid; a batch
/// may cost the forward kinematics of a few configurations past the first invalid one,
/// never another answer. No allocation once the buffers have grown to the segment.
///
/// Sampling is not sound: a contact shallower than what one step sweeps can lie between
/// two checked configurations, and a finer re-check finds it. The planner uses
/// [`CertifiedMotion`](super::CertifiedMotion), which falls back to this only for state
/// validities that measure no clearance.
pub struct DiscreteMotion<'v, S = SceneScratch> {
    validity: &'v dyn StateValidity<Scratch = S>,
    step: f64,
    resolution: f64,
    from: Vec<f64>,
    to: Vec<f64>,
    point: Vec<f64>,
    /// Every configuration of the segment in the order checked, concatenated.
    samples: Vec<f64>,
    /// What the screen proved of each configuration of a batch.
    screened: Vec<Screened>,
}

/// Configurations handed to [`StateValidity::screen`] at once. The first batch
/// holds the far end and the coarse bisection points, where a blocked segment is
/// usually caught; batches after it are twice as large each time.
const FIRST_BATCH: usize = 4;

impl<'v, S> DiscreteMotion<'v, S> {
    /// Segments checked through `validity`, cut by the output `step` and the checking
    /// `resolution` (both positive; an infinite `step` checks every segment as one
    /// piece).
    pub fn new(validity: &'v dyn StateValidity<Scratch = S>, step: f64, resolution: f64) -> Self {
        DiscreteMotion {
            validity,
            step,
            resolution,
            from: Vec::new(),
            to: Vec::new(),
            point: Vec::new(),
            samples: Vec::new(),
            screened: Vec::new(),
        }
    }
}

impl<S> MotionValidity for DiscreteMotion<'_, S> {
    type Scratch = S;

    fn check_motion(&mut self, a: &[f64], b: &[f64], scratch: &mut S) -> Result<bool, QueryError> {
        let pieces = steps(a, b, self.step);
        if pieces == 0 {
            return Ok(true);
        }
        let DiscreteMotion {
            validity,
            resolution,
            from,
            to,
            point,
            samples,
            screened,
            ..
        } = self;
        // Every configuration in the order checked: the samples themselves (the pieces'
        // ends) first, then inside each piece.
        samples.clear();
        bisection(pieces, |i| {
            sample(a, b, i, pieces, to);
            samples.extend_from_slice(to);
        });
        for i in 1..=pieces {
            sample(a, b, i - 1, pieces, from);
            sample(a, b, i, pieces, to);
            let n = steps(from, to, *resolution);
            bisection(n.saturating_sub(1), |k| {
                sample(from, to, k, n, point);
                samples.extend_from_slice(point);
            });
        }
        // In batches, in that order: the screen judges what it can, the full check the
        // rest, and the first invalid configuration ends the check, so the answer is
        // the one-by-one answer.
        let dim = a.len().max(1);
        let mut batch = FIRST_BATCH;
        let mut done = 0;
        while done < samples.len() {
            let end = (done + batch * dim).min(samples.len());
            let chunk = &samples[done..end];
            let count = chunk.len() / dim;
            screened.clear();
            screened.resize(count, Screened::Unknown);
            if !all_valid(*validity, chunk, screened, scratch)? {
                return Ok(false);
            }
            done = end;
            batch *= 2;
        }
        Ok(true)
    }
}

/// Calls `visit` on `n`, then on every `k` in `1..n` coarse to fine (the midpoint, the
/// quarters, ...); nothing for `n == 0`.
fn bisection(n: usize, mut visit: impl FnMut(usize)) {
    if n == 0 {
        return;
    }
    visit(n);
    // Every k in 1..n is an odd multiple of exactly one power of two, so visiting odd
    // multiples of s for s = 2^m, ..., 2, 1 visits each once.
    let mut s = 1usize << (usize::BITS - 1 - n.leading_zeros());
    while s >= 1 {
        let mut k = s;
        while k < n {
            visit(k);
            k += 2 * s;
        }
        s /= 2;
    }
}

/// Sample `i` of `n` of the segment from `a` to `b`: `b` itself for `i == n` (so waypoints
/// are reproduced exactly), otherwise `a + (b - a) i / n`. The timed trajectory's points
/// and the planner's edge checks both come from here.
pub(super) fn sample(a: &[f64], b: &[f64], i: usize, n: usize, out: &mut Vec<f64>) {
    if i >= n {
        out.clear();
        out.extend_from_slice(b);
    } else {
        interpolate(a, b, i as f64 / n as f64, out);
    }
}

/// Largest absolute joint difference.
pub(super) fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// Steps so that no joint moves more than `resolution` per step (0 for equal points).
pub(super) fn steps(a: &[f64], b: &[f64], resolution: f64) -> usize {
    let d = max_diff(a, b);
    if d == 0.0 {
        0
    } else {
        // Finite and positive by validation; the cast saturates anyway.
        (d / resolution).ceil().max(1.0) as usize
    }
}

/// `out = a + (b - a) s`.
pub(super) fn interpolate(a: &[f64], b: &[f64], s: f64, out: &mut Vec<f64>) {
    out.clear();
    out.extend(a.iter().zip(b).map(|(x, y)| x + (y - x) * s));
}
