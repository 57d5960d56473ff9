//! Straight segments in joint space: how they are cut into the configurations that are
//! checked ([`DiscreteMotion`], the sampled [`MotionValidity`]) and into the points of a
//! timed trajectory, which are the same cuts, so that a trajectory planned with it
//! re-checks exactly as it was planned.

use super::MotionValidity;
use crate::scene::{QueryError, SceneScratch};
use crate::validity::StateValidity;

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
/// a few checks. No allocation once the buffers have grown to the dimension.
///
/// Sampling is not sound: a contact shallower than what one step sweeps can lie between
/// two checked configurations, and a finer re-check finds it. The planner uses
/// [`CertifiedMotion`](super::CertifiedMotion), which falls back to this only for state
/// validities that measure no clearance.
pub struct DiscreteMotion<'v> {
    validity: &'v dyn StateValidity,
    step: f64,
    resolution: f64,
    from: Vec<f64>,
    to: Vec<f64>,
    point: Vec<f64>,
}

impl<'v> DiscreteMotion<'v> {
    /// Segments checked through `validity`, cut by the output `step` and the checking
    /// `resolution` (both positive; an infinite `step` checks every segment as one
    /// piece).
    pub fn new(validity: &'v dyn StateValidity, step: f64, resolution: f64) -> Self {
        DiscreteMotion {
            validity,
            step,
            resolution,
            from: Vec::new(),
            to: Vec::new(),
            point: Vec::new(),
        }
    }
}

impl MotionValidity for DiscreteMotion<'_> {
    fn check_motion(
        &mut self,
        a: &[f64],
        b: &[f64],
        scratch: &mut SceneScratch,
    ) -> Result<bool, QueryError> {
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
            ..
        } = self;
        // The samples themselves (the pieces' ends) first, then inside each piece.
        let ends = bisection(pieces, |i| {
            sample(a, b, i, pieces, to);
            validity.is_valid(to, scratch)
        })?;
        if !ends {
            return Ok(false);
        }
        for i in 1..=pieces {
            sample(a, b, i - 1, pieces, from);
            sample(a, b, i, pieces, to);
            let n = steps(from, to, *resolution);
            let inside = bisection(n.saturating_sub(1), |k| {
                sample(from, to, k, n, point);
                validity.is_valid(point, scratch)
            })?;
            if !inside {
                return Ok(false);
            }
        }
        Ok(true)
    }
}

/// Calls `visit` on `n`, then on every `k` in `1..n` coarse to fine (the midpoint, the
/// quarters, ...), until it returns `false` or an error; `Ok(true)` when every call did.
fn bisection<E>(n: usize, mut visit: impl FnMut(usize) -> Result<bool, E>) -> Result<bool, E> {
    if n == 0 {
        return Ok(true);
    }
    if !visit(n)? {
        return Ok(false);
    }
    // Every k in 1..n is an odd multiple of exactly one power of two, so visiting odd
    // multiples of s for s = 2^m, ..., 2, 1 visits each once.
    let mut s = 1usize << (usize::BITS - 1 - n.leading_zeros());
    while s >= 1 {
        let mut k = s;
        while k < n {
            if !visit(k)? {
                return Ok(false);
            }
            k += 2 * s;
        }
        s /= 2;
    }
    Ok(true)
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
