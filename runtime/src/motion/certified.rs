//! Sound segment checks: [`CertifiedMotion`], the default [`MotionValidity`], accepts a
//! straight segment only when clearance certificates cover all of it, so no
//! configuration on an accepted segment collides, at whatever resolution it is
//! re-checked.

use std::collections::VecDeque;

use super::segment::{interpolate, max_diff, DiscreteMotion};
use super::MotionValidity;
use crate::scene::{QueryError, SceneScratch};
use crate::validity::StateValidity;

/// Clearance queries one segment may take before it is refused as too close to call (a
/// segment that grazes an obstacle for its whole length, micrometres away, would need
/// ever more). A free segment in the shipped cells takes a few to a few dozen.
const MAX_QUERIES: usize = 2000;

/// The default [`MotionValidity`]: a segment from `a` to `b` is valid when `b` is valid
/// and every configuration between them is proven free by
/// [`StateValidity::free_radius`].
///
/// The segment's parameter interval [0, 1] is covered by certificates: the midpoint of
/// an uncovered interval is asked for its free radius `r` (with half the interval as
/// the horizon), which proves `[mid - r, mid + r]` free; what is left on either side is
/// queued, and intervals are taken in order, so the checks run coarse to fine (the
/// midpoint, then about the quarters, ...) and a blocked segment is usually refused after
/// a few. A radius of 0 (contact, or closer than the certificate's tolerance) refuses
/// the segment, and so do 2000 queries without covering it: refusing what cannot be
/// proven is what makes the check sound. Joint limits hold on the whole segment because
/// they hold at its ends (the limits are a box).
///
/// A state validity that measures no clearance (`free_radius` gives `None`, as test
/// doubles and other checkers may) gets the sampled check of [`DiscreteMotion`] instead,
/// at the step and resolution given here.
pub struct CertifiedMotion<'v, S = SceneScratch> {
    validity: &'v dyn StateValidity<Scratch = S>,
    sampled: DiscreteMotion<'v, S>,
    delta: Vec<f64>,
    point: Vec<f64>,
    open: VecDeque<(f64, f64)>,
}

impl<'v, S> CertifiedMotion<'v, S> {
    /// Segments checked through `validity`; `step` and `resolution` are those of the
    /// sampled fallback (see [`DiscreteMotion::new`]).
    pub fn new(validity: &'v dyn StateValidity<Scratch = S>, step: f64, resolution: f64) -> Self {
        CertifiedMotion {
            validity,
            sampled: DiscreteMotion::new(validity, step, resolution),
            delta: Vec::new(),
            point: Vec::new(),
            open: VecDeque::new(),
        }
    }
}

impl<S> MotionValidity for CertifiedMotion<'_, S> {
    type Scratch = S;

    fn check_motion(&mut self, a: &[f64], b: &[f64], scratch: &mut S) -> Result<bool, QueryError> {
        if max_diff(a, b) == 0.0 {
            return Ok(true);
        }
        // The far end first: its limits (which the certificates do not look at), and a
        // cheap refusal of the many tree extensions that end in collision.
        if !self.validity.is_valid(b, scratch)? {
            return Ok(false);
        }
        self.delta.clear();
        self.delta.extend(a.iter().zip(b).map(|(x, y)| y - x));
        self.open.clear();
        self.open.push_back((0.0, 1.0));
        let mut queries = 0;
        while let Some((lo, hi)) = self.open.pop_front() {
            if queries == MAX_QUERIES {
                return Ok(false);
            }
            queries += 1;
            let (mid, half) = (0.5 * (lo + hi), 0.5 * (hi - lo));
            interpolate(a, b, mid, &mut self.point);
            let Some(radius) =
                self.validity
                    .free_radius(&self.point, &self.delta, half, scratch)?
            else {
                return self.sampled.check_motion(a, b, scratch);
            };
            if radius <= 0.0 {
                return Ok(false);
            }
            if radius < half {
                self.open.push_back((lo, mid - radius));
                self.open.push_back((mid + radius, hi));
            }
        }
        Ok(true)
    }
}
