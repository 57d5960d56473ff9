//! Timing a given geometric path outside the planner: what the planner does to the
//! certified path it found (circular blends through its corners, each certified again,
//! then TOPP-RA under every joint's limits: `blend.rs`, `topp.rs`, `timing.rs`), and the
//! rest-to-rest timing that came before it (a trapezoid per straight segment), on the
//! same waypoints and the same limits.
//!
//! Why a way in of its own: a timing is only comparable with another parameterisation
//! (toppra, Ruckig; `benches/timing.rs`) or with the old one on the same path, and the
//! planner's answer hides its path. [`RrtConnect::path`](super::RrtConnect::path) gives
//! the certified waypoints that [`MotionPlanner::solve`](super::MotionPlanner::solve)
//! times; the functions here time them in the planner's steps, each measurable alone.
//!
//! Blends leave the certified segments (by up to [`MotionOptions::blend_deviation`]), so
//! smoothing still needs the scene: [`smooth_waypoints`] certifies every arc through the
//! validity it is given, exactly as the planner does, and passes a corner no arc clears at
//! rest. What follows needs no scene, since it never leaves the path it is given:
//! [`time_smoothed`] parameterises a [`SmoothedPath`] (which only [`smooth_waypoints`]
//! makes, so a path timed here is certified wherever its waypoints were), and
//! [`rest_to_rest`] times the straight segments themselves.

use cellc_schema::EndEffectorId;

use super::blend::{distance, smooth, Piece, Smoothed};
use super::problem::check_options;
use super::shortcut::dedup_waypoints;
use super::timing::{time_sections, MotionLimits};
use super::{check_timing, MotionError, MotionOptions, TimingOptions};
use crate::plan::Trajectory;
use crate::robot::RateLimits;
use crate::scene::Scene;
use crate::validity::{arm_slices, StateValidity};

/// A path of waypoints smoothed by [`smooth_waypoints`]: sections that each start and end
/// at rest (the path's ends and the corners no blend cleared), each a chain of lines and
/// certified arcs whose direction is continuous.
#[derive(Clone, Debug)]
pub struct SmoothedPath {
    dim: usize,
    start: Vec<f64>,
    goal: Vec<f64>,
    smoothed: Smoothed,
}

impl SmoothedPath {
    /// Joints (values per configuration).
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// The sections, in order, each its pieces parameterised by arc length.
    pub fn sections(&self) -> impl Iterator<Item = &[Piece]> {
        self.smoothed.sections.iter().map(Vec::as_slice)
    }

    /// Arc length in joint space (rad, or m; Euclidean over the joints).
    pub fn length(&self) -> f64 {
        self.sections().flatten().map(Piece::length).sum()
    }
}

/// Checks a path of waypoints: `dim` values each, at least one waypoint, every value
/// finite.
fn check_path(path: &[f64], dim: usize) -> Result<(), MotionError> {
    if dim == 0 || path.is_empty() || !path.len().is_multiple_of(dim) {
        return Err(MotionError::MalformedPath(
            "the waypoints do not have the same number of joints",
        ));
    }
    if !path.iter().all(|v| v.is_finite()) {
        return Err(MotionError::MalformedPath("a joint value is not finite"));
    }
    Ok(())
}

/// Checks per-joint limits against `dim` joints: one positive, finite velocity and
/// acceleration per joint, and a jerk (where one is given) as well.
fn check_limits(limits: &RateLimits, dim: usize) -> Result<(), MotionError> {
    let lengths = [
        limits.velocity.len(),
        limits.acceleration.len(),
        limits.jerk.len(),
    ];
    if lengths.iter().any(|&n| n != dim) {
        return Err(MotionError::MalformedPath(
            "the limits do not have one value per joint",
        ));
    }
    let positive = |v: f64| v.is_finite() && v > 0.0;
    let every = limits
        .velocity
        .iter()
        .chain(&limits.acceleration)
        .chain(limits.jerk.iter().flatten());
    if !every.copied().all(positive) {
        return Err(MotionError::MalformedPath(
            "a joint limit is not a positive, finite number",
        ));
    }
    Ok(())
}

/// The rate limits of `arms`' joints, concatenated in their order (the joints' order in a
/// motion of those arms).
///
/// # Errors
/// [`MotionError::NotAnArm`] or [`MotionError::RepeatedArm`].
pub fn arm_limits(scene: &Scene, arms: &[EndEffectorId]) -> Result<RateLimits, MotionError> {
    let mut limits = RateLimits::default();
    for slice in arm_slices(scene, arms)? {
        let rates = scene.robots[slice.robot].rate_limits();
        limits.velocity.extend_from_slice(&rates.velocity);
        limits.acceleration.extend_from_slice(&rates.acceleration);
        limits.jerk.extend_from_slice(&rates.jerk);
    }
    Ok(limits)
}

/// Smooths the waypoints of `path` (`dim` values each; repeated consecutive ones are
/// dropped) as the planner does: a circular blend of at most `options.blend_deviation`
/// through each corner, certified through `validity` with chords of at most
/// `options.grid_step`, a quarter and a sixteenth of the deviation tried where it fails,
/// and the corner passed at rest where none is certified. Every segment of `path` must
/// already be certified for the result to be: the straight pieces are parts of them.
///
/// # Errors
/// [`MotionError::MalformedPath`] for a path that is not waypoints of `dim` finite
/// values, [`MotionError::InvalidOption`] for unusable options, [`MotionError::Query`]
/// when the scene cannot answer.
pub fn smooth_waypoints<S>(
    path: &[f64],
    dim: usize,
    options: &MotionOptions,
    validity: &dyn StateValidity<Scratch = S>,
    scratch: &mut S,
) -> Result<SmoothedPath, MotionError> {
    check_path(path, dim)?;
    check_options(options)?;
    let mut path = path.to_vec();
    dedup_waypoints(&mut path, dim);
    let smoothed = smooth(
        &path,
        dim,
        options.blend_deviation,
        options.grid_step,
        validity,
        scratch,
    )?;
    Ok(SmoothedPath {
        dim,
        start: path[..dim].to_vec(),
        goal: path[path.len() - dim..].to_vec(),
        smoothed,
    })
}

/// Times a smoothed path as the planner does: each section parameterised time-optimally
/// (TOPP-RA) under `limits` scaled by `timing`, on a grid of at most
/// `options.grid_step`, slowed evenly where a declared jerk limit asks it, and written out
/// at the knots or at `timing.rate`. The trajectory is of `arms` (the joints of `limits`
/// in their order: [`arm_limits`] gives them).
///
/// # Errors
/// [`MotionError::MalformedPath`] for limits that do not fit the path's joints or are not
/// positive, [`MotionError::InvalidOption`] for unusable options, scalings or rate,
/// [`MotionError::Untimed`] for a path that cannot be timed.
pub fn time_smoothed(
    path: &SmoothedPath,
    arms: &[EndEffectorId],
    limits: &RateLimits,
    options: &MotionOptions,
    timing: &TimingOptions,
) -> Result<Trajectory, MotionError> {
    check_limits(limits, path.dim)?;
    check_options(options)?;
    check_timing(timing)?;
    let mut motion = MotionLimits::default();
    motion.push(limits);
    time_sections(
        &path.smoothed,
        &path.start,
        &path.goal,
        arms,
        &motion,
        options,
        timing,
    )
}

/// The rest-to-rest timing of `path` (`dim` values per waypoint) that the planner used
/// before blends and TOPP-RA, now under each joint's own limits: every straight segment
/// from rest to rest along the segment, with the trapezoid of its slowest joint (the
/// fastest profile under which every joint stays within `limits` scaled by `timing`:
/// the path parameter's speed and acceleration are bound by the joint whose share of the
/// segment is largest relative to its limit). Jerk limits are not applied, as they were
/// not then. Each segment's duration, in order (seconds; repeated waypoints take none).
///
/// # Errors
/// [`MotionError::MalformedPath`] for a path or limits that do not fit,
/// [`MotionError::InvalidOption`] for unusable scalings.
pub fn rest_to_rest(
    path: &[f64],
    dim: usize,
    limits: &RateLimits,
    timing: &TimingOptions,
) -> Result<Vec<f64>, MotionError> {
    check_path(path, dim)?;
    check_limits(limits, dim)?;
    check_timing(timing)?;
    let waypoints: Vec<&[f64]> = path.chunks_exact(dim).collect();
    let durations = waypoints
        .windows(2)
        .map(|w| {
            let length = distance(w[0], w[1]);
            if length == 0.0 {
                return 0.0;
            }
            // Joint j moves (b_j - a_j) / length per unit of arc length.
            let (mut speed, mut accel) = (f64::INFINITY, f64::INFINITY);
            let joints = w[0].iter().zip(w[1]).zip(&limits.velocity);
            for (((a, b), v), acc) in joints.zip(&limits.acceleration) {
                let share = (b - a).abs() / length;
                if share > 0.0 {
                    speed = speed.min(v * timing.velocity_scaling / share);
                    accel = accel.min(acc * timing.acceleration_scaling / share);
                }
            }
            if speed * speed / accel >= length {
                // Never reaches the cruise speed: accelerate half-way, then brake.
                2.0 * (length / accel).sqrt()
            } else {
                length / speed + speed / accel
            }
        })
        .collect();
    Ok(durations)
}
