//! Timing a path: a rest-to-rest trapezoidal velocity profile per segment, every joint
//! synchronised, sampled at the planner's output step.

use super::segment::{max_diff, sample, steps};
use super::MotionOptions;
use cellc_schema::EndEffectorId;

use crate::plan::Trajectory;

/// A rest-to-rest trapezoidal profile of the path parameter `s` from 0 to 1: the fastest
/// one that keeps every joint of a straight segment within the speed and acceleration
/// limits, with all joints synchronised (they start, cruise and stop together).
#[derive(Clone, Copy, Debug)]
struct Profile {
    /// Cruise rate of `s` (1/s).
    speed: f64,
    /// Acceleration of `s` (1/s²).
    accel: f64,
    /// `s` at the end of the acceleration phase.
    s_accel: f64,
    /// Duration of the acceleration phase.
    t_accel: f64,
    /// Total duration.
    duration: f64,
}

impl Profile {
    /// For a segment with largest joint displacement `d` (> 0).
    fn new(d: f64, velocity: f64, acceleration: f64) -> Profile {
        // Joint j moves d_j s(t): |d_j| s' <= v and |d_j| s'' <= a for every joint, which
        // the joint with the largest displacement binds.
        let (speed, accel) = (velocity / d, acceleration / d);
        if speed * speed / accel >= 1.0 {
            // Never reaches the cruise speed: accelerate to half-way, then brake.
            let t_accel = (1.0 / accel).sqrt();
            Profile {
                speed: accel * t_accel,
                accel,
                s_accel: 0.5,
                t_accel,
                duration: 2.0 * t_accel,
            }
        } else {
            let t_accel = speed / accel;
            let s_accel = 0.5 * speed * t_accel;
            Profile {
                speed,
                accel,
                s_accel,
                t_accel,
                duration: 2.0 * t_accel + (1.0 - 2.0 * s_accel) / speed,
            }
        }
    }

    /// The time at which the parameter reaches `s` (strictly increasing in `s`).
    fn time_at(&self, s: f64) -> f64 {
        if s <= self.s_accel {
            (2.0 * s / self.accel).sqrt()
        } else if s <= 1.0 - self.s_accel {
            self.t_accel + (s - self.s_accel) / self.speed
        } else {
            self.duration - (2.0 * (1.0 - s).max(0.0) / self.accel).sqrt()
        }
    }
}

/// Times the waypoints with a rest-to-rest trapezoid per segment and samples each segment
/// at [`sample`]`(.., step)`, so consecutive points differ by at most `step` per joint.
pub(super) fn time_path(
    path: &[f64],
    dim: usize,
    arms: &[EndEffectorId],
    options: &MotionOptions,
) -> Trajectory {
    let m = path.len().checked_div(dim).unwrap_or(1);
    let mut points = Vec::new();
    points.push((0.0, path[..dim].to_vec()));
    let mut t0 = 0.0;
    let mut q = Vec::with_capacity(dim);
    for i in 1..m {
        let (a, b) = (&path[(i - 1) * dim..i * dim], &path[i * dim..(i + 1) * dim]);
        let d = max_diff(a, b);
        if d == 0.0 {
            continue;
        }
        let profile = Profile::new(d, options.velocity_limit, options.acceleration_limit);
        let n = steps(a, b, options.step);
        for k in 1..=n {
            sample(a, b, k, n, &mut q);
            points.push((t0 + profile.time_at(k as f64 / n as f64), q.clone()));
        }
        t0 += profile.duration;
    }
    Trajectory {
        arms: arms.to_vec(),
        points,
    }
}
