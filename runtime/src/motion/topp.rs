//! Time-optimal parameterisation of a path under joint velocity and acceleration limits:
//! TOPP-RA's reachability analysis (Pham & Pham, "A new approach to time-optimal path
//! parameterization based on reachability analysis", T-RO 2018), written for the case of
//! kinematic limits, where each step's two-variable program has a closed form.
//!
//! The path `q(s)`, `s` in `[s_0, s_N]`, is given at grid points by its first and second
//! derivatives. With `x = ṡ²` and `u = s̈`, joint `j` moves at `q'_j ṡ` and accelerates at
//! `q'_j u + q''_j x`, so at grid point `i`:
//! - velocity: `q'_j² x ≤ v_j²`;
//! - acceleration: `-a_j ≤ q'_j u + q''_j x ≤ a_j`;
//! - and between grid points `x_{i+1} = x_i + 2 Δ_i u_i` (constant `s̈` on a step).
//!
//! For a fixed `x`, every constraint bounds `u` from one side by a function linear in
//! `x`, so `x` is admissible together with some `u` exactly when every lower bound is at
//! most every upper bound: a set of linear inequalities in `x` alone, an interval. The
//! backward pass computes each grid point's *controllable* interval (the `x` from which
//! the end can be reached at rest) from the next one, in `O(d²)` per point; the forward
//! pass then takes, at each point, the largest `u` that stays controllable (the paper's
//! greedy choice). Each step's `u` is held to the acceleration limits at both of its ends
//! (the paper's first-order interpolation scheme, toppra's default), which keeps the
//! greedy profile from zig-zagging where a joint reverses; `tests.rs` compares it with a
//! brute-force search over speeds on random paths.
//!
//! Nothing here knows of collisions: the path is the one the planner certified, and this
//! only chooses how fast to go along it.

/// Why a path cannot be timed.
#[derive(Clone, Debug, PartialEq)]
pub enum ToppError {
    /// The grid, derivatives or limits do not fit together (lengths, order, signs).
    Malformed(&'static str),
    /// No admissible speed at grid point `index` lets the path end at rest: the limits
    /// cannot hold the path's curvature there even at standstill.
    Infeasible {
        /// The grid point.
        index: usize,
    },
}

/// A path sampled on a grid: `s` increasing, and at each point the path's first and
/// second derivatives with respect to `s`, `dim` values each.
#[derive(Clone, Debug)]
pub struct PathGrid {
    /// The path parameter at each grid point, strictly increasing.
    pub s: Vec<f64>,
    /// `dq/ds` at each point, row-major (`s.len()` rows of `dim`).
    pub dq: Vec<f64>,
    /// `d²q/ds²` at each point.
    pub ddq: Vec<f64>,
    /// Joints.
    pub dim: usize,
}

/// Per-joint limits, both positive.
#[derive(Clone, Debug)]
pub struct Limits {
    /// Largest speed of each joint (rad/s or m/s).
    pub velocity: Vec<f64>,
    /// Largest acceleration of each joint (rad/s² or m/s²).
    pub acceleration: Vec<f64>,
}

/// The parameterisation: at each grid point, `ṡ`, `s̈` (constant until the next point)
/// and the time it is reached.
#[derive(Clone, Debug, PartialEq)]
pub struct Timing {
    /// `ṡ` at each grid point (0 at both ends).
    pub sdot: Vec<f64>,
    /// `s̈` on each step (one fewer than the grid points).
    pub sddot: Vec<f64>,
    /// Time from the start at each grid point.
    pub time: Vec<f64>,
}

impl Timing {
    /// The motion's duration.
    pub fn duration(&self) -> f64 {
        self.time.last().copied().unwrap_or(0.0)
    }
}

/// Relative slack allowed when an interval is found empty by rounding alone.
const SLACK: f64 = 1e-9;

/// The bounds one constraint puts on `u` as a function of `x`: `u ≥ p x + r` (lower) or
/// `u ≤ p x + r` (upper).
#[derive(Clone, Copy, Debug)]
struct Line {
    p: f64,
    r: f64,
}

impl Line {
    fn at(self, x: f64) -> f64 {
        self.p * x + self.r
    }
}

/// Every bound on `u` at grid point `i`, and the largest `x` its velocities allow.
fn bounds(
    path: &PathGrid,
    limits: &Limits,
    i: usize,
    lower: &mut Vec<Line>,
    upper: &mut Vec<Line>,
) -> f64 {
    lower.clear();
    upper.clear();
    let d = path.dim;
    let mut x_max = f64::INFINITY;
    for j in 0..d {
        let (dq, ddq) = (path.dq[i * d + j], path.ddq[i * d + j]);
        let (v, a) = (limits.velocity[j], limits.acceleration[j]);
        if dq.abs() > 1e-12 {
            x_max = x_max.min((v / dq).powi(2));
            // -a ≤ dq u + ddq x ≤ a  ⇔  (-a - ddq x)/dq ≤ u ≤ (a - ddq x)/dq for dq > 0.
            let (lo, hi) = (
                Line {
                    p: -ddq / dq,
                    r: -a / dq,
                },
                Line {
                    p: -ddq / dq,
                    r: a / dq,
                },
            );
            if dq > 0.0 {
                lower.push(lo);
                upper.push(hi);
            } else {
                lower.push(hi);
                upper.push(lo);
            }
        } else if ddq.abs() > 1e-12 {
            // Only the curvature term: |ddq| x ≤ a.
            x_max = x_max.min(a / ddq.abs());
        }
    }
    x_max
}

/// The acceleration limits of grid point `i + 1` as bounds on the step's `u` in terms of
/// `x_i` (TOPP-RA's first-order interpolation scheme): with `x_{i+1} = x_i + 2Δu`, joint
/// `j` accelerates at `(q'_j + 2Δ q''_j) u + q''_j x_i` there. Holding the step's `u` to
/// both ends of the step is what keeps the profile from zig-zagging where a joint
/// reverses (collocation at the start alone lets the fastest speed at one point force a
/// needlessly slow one at the next).
fn step_end_bounds(
    path: &PathGrid,
    limits: &Limits,
    i: usize,
    delta: f64,
    lower: &mut Vec<Line>,
    upper: &mut Vec<Line>,
) {
    let d = path.dim;
    for j in 0..d {
        let (dq, ddq) = (path.dq[(i + 1) * d + j], path.ddq[(i + 1) * d + j]);
        let a = limits.acceleration[j];
        let k = dq + 2.0 * delta * ddq;
        if k.abs() <= 1e-12 {
            continue;
        }
        let (lo, hi) = (
            Line {
                p: -ddq / k,
                r: -a / k,
            },
            Line {
                p: -ddq / k,
                r: a / k,
            },
        );
        if k > 0.0 {
            lower.push(lo);
            upper.push(hi);
        } else {
            lower.push(hi);
            upper.push(lo);
        }
    }
}

/// The interval of `x ≥ 0`, `x ≤ x_max`, for which some `u` satisfies every line of
/// `lower` ≤ u ≤ every line of `upper`. `None` when empty.
fn admissible(lower: &[Line], upper: &[Line], x_max: f64) -> Option<(f64, f64)> {
    let (mut lo, mut hi) = (0.0_f64, x_max);
    for l in lower {
        for u in upper {
            // l.p x + l.r ≤ u.p x + u.r  ⇔  (l.p - u.p) x ≤ u.r - l.r
            let (k, c) = (l.p - u.p, u.r - l.r);
            if k.abs() < 1e-15 {
                if c < -SLACK * (1.0 + u.r.abs() + l.r.abs()) {
                    return None;
                }
            } else if k > 0.0 {
                hi = hi.min(c / k);
            } else {
                lo = lo.max(c / k);
            }
        }
    }
    (lo <= hi * (1.0 + SLACK) + SLACK).then_some((lo, hi.max(lo)))
}

/// Times `path` from rest to rest as fast as `limits` allow.
///
/// # Errors
/// [`ToppError::Malformed`] for a grid that does not fit its derivatives or limits,
/// [`ToppError::Infeasible`] where no speed is admissible.
pub fn parameterise(path: &PathGrid, limits: &Limits) -> Result<Timing, ToppError> {
    let n = path.s.len();
    let d = path.dim;
    if n < 2 {
        return Err(ToppError::Malformed("a path needs two grid points"));
    }
    if path.dq.len() != n * d || path.ddq.len() != n * d {
        return Err(ToppError::Malformed("derivatives do not match the grid"));
    }
    if limits.velocity.len() != d || limits.acceleration.len() != d {
        return Err(ToppError::Malformed("limits do not match the joints"));
    }
    let positive = |v: &f64| v.is_finite() && *v > 0.0;
    if !limits.velocity.iter().all(positive) || !limits.acceleration.iter().all(positive) {
        return Err(ToppError::Malformed("limits must be positive and finite"));
    }
    if !path.s.windows(2).all(|w| w[1] > w[0])
        || !path.dq.iter().chain(&path.ddq).all(|v| v.is_finite())
    {
        return Err(ToppError::Malformed("the grid must increase and be finite"));
    }
    let mut lower = Vec::with_capacity(d + 2);
    let mut upper = Vec::with_capacity(d + 2);
    // Backward pass: controllable intervals, the last one {0} (at rest).
    let mut controllable = vec![(0.0, 0.0); n];
    let x_max_end = bounds(path, limits, n - 1, &mut lower, &mut upper);
    if admissible(&lower, &upper, x_max_end).is_none() {
        return Err(ToppError::Infeasible { index: n - 1 });
    }
    let mut x_max = vec![0.0; n];
    x_max[n - 1] = x_max_end;
    for i in (0..n - 1).rev() {
        let delta = path.s[i + 1] - path.s[i];
        x_max[i] = bounds(path, limits, i, &mut lower, &mut upper);
        step_end_bounds(path, limits, i, delta, &mut lower, &mut upper);
        let (k_lo, k_hi) = controllable[i + 1];
        // k_lo ≤ x + 2Δu ≤ k_hi  ⇔  (k_lo - x)/2Δ ≤ u ≤ (k_hi - x)/2Δ.
        lower.push(Line {
            p: -1.0 / (2.0 * delta),
            r: k_lo / (2.0 * delta),
        });
        upper.push(Line {
            p: -1.0 / (2.0 * delta),
            r: k_hi / (2.0 * delta),
        });
        controllable[i] =
            admissible(&lower, &upper, x_max[i]).ok_or(ToppError::Infeasible { index: i })?;
    }
    if controllable[0].0 > SLACK {
        // Even the slowest admissible start is not at rest.
        return Err(ToppError::Infeasible { index: 0 });
    }
    // Forward pass: from rest, the largest u that stays controllable.
    let mut x = vec![0.0; n];
    let mut sddot = Vec::with_capacity(n - 1);
    for i in 0..n - 1 {
        let delta = path.s[i + 1] - path.s[i];
        bounds(path, limits, i, &mut lower, &mut upper);
        step_end_bounds(path, limits, i, delta, &mut lower, &mut upper);
        let u_hi = upper
            .iter()
            .map(|l| l.at(x[i]))
            .fold((controllable[i + 1].1 - x[i]) / (2.0 * delta), f64::min);
        let u_lo = lower
            .iter()
            .map(|l| l.at(x[i]))
            .fold((controllable[i + 1].0 - x[i]) / (2.0 * delta), f64::max);
        // Rounding may leave u_hi a hair under u_lo where the interval is a point.
        let u = u_hi.max(u_lo);
        let next = (x[i] + 2.0 * delta * u).clamp(controllable[i + 1].0, controllable[i + 1].1);
        x[i + 1] = next.max(0.0);
        sddot.push((x[i + 1] - x[i]) / (2.0 * delta));
    }
    x[n - 1] = 0.0;
    let sdot: Vec<f64> = x.iter().map(|v| v.max(0.0).sqrt()).collect();
    let mut time = Vec::with_capacity(n);
    time.push(0.0);
    for i in 0..n - 1 {
        let delta = path.s[i + 1] - path.s[i];
        let mean = sdot[i] + sdot[i + 1];
        if mean <= 0.0 {
            // At rest at both ends of a step that moves: only a path that cannot move.
            return Err(ToppError::Infeasible { index: i });
        }
        time.push(time[i] + 2.0 * delta / mean);
    }
    Ok(Timing { sdot, sddot, time })
}

#[cfg(test)]
mod tests;
