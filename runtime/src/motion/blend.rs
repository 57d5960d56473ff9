//! Smoothing a certified path: circular blends through its corners, each certified again.
//!
//! A path of straight segments has a corner at every interior waypoint, where the joints'
//! direction jumps; a controller can only pass a corner at rest. As in Kunz and Stilman's
//! time-optimal trajectory generation (RSS 2012), each corner is replaced by the circular
//! arc (in joint space) tangent to both of its segments whose distance from the corner is
//! at most the stated deviation, no longer than 45% of either segment so that
//! neighbouring blends never meet. The path is then continuous in its direction, and the
//! time parameterisation (`timing.rs`) need not stop at it.
//!
//! The straight pieces left are parts of segments the planner certified, so they are free.
//! The arcs are not: an arc leaves the certified segments, by up to the deviation, so each
//! one is certified again before it is taken, with the same clearance certificates as a
//! segment (`certified.rs`). A piece of an arc within angle `h` of its middle `m` lies in
//! the box `|q_j - m_j| <= r h sqrt(u_j² + v_j²)` (the arc's speed in joint `j` is at most
//! `r sqrt(u_j² + v_j²)` for its plane's unit vectors `u`, `v`), widened by the sagitta
//! of the chords a trajectory's points cut the arc into; a certificate that proves the box
//! free ([`StateValidity::certifies_boxes`]) proves the piece and its chords free. An arc
//! that cannot be proven free is tried at a quarter of the deviation, then at a sixteenth;
//! a corner none of them clears stays a corner, passed at rest. Corners that turn back on
//! themselves (more than about 179°) are not blended either.

use super::segment::interpolate;
use crate::scene::QueryError;
use crate::validity::StateValidity;
use std::collections::VecDeque;

/// Share of a segment a blend may take at either end (Kunz and Stilman take half; less
/// keeps a straight piece between two blends, so each junction is one grid point).
const MAX_SHARE: f64 = 0.45;
/// Corners turning by less than this (rad) are straight for timing: no arc is needed.
const STRAIGHT: f64 = 1e-9;
/// Corners turning by more than this (rad) are passed at rest: an arc would be tiny and
/// its curvature would force a near stop anyway.
const REVERSAL: f64 = std::f64::consts::PI - 1e-2;
/// Clearance queries one arc may take before it is refused (as `certified.rs`).
const MAX_QUERIES: usize = 2000;
/// Each retry of a refused arc takes this share of the previous deviation.
const RETRY_SHARE: f64 = 0.25;
/// Deviations tried per corner: the stated one, a quarter, a sixteenth.
const TRIES: usize = 3;

/// One piece of a smoothed path, parameterised by arc length in joint space. Public
/// (through [`SmoothedPath::sections`](super::SmoothedPath::sections)) so that another
/// parameterisation can be run on exactly the path cellc times.
#[derive(Clone, Debug, PartialEq)]
pub enum Piece {
    /// The straight piece from `a` to `b`, part of a certified segment.
    Line {
        /// Where it starts.
        a: Vec<f64>,
        /// Where it ends.
        b: Vec<f64>,
        /// Its length, `|b - a|`.
        length: f64,
    },
    /// A blend: `centre + radius (u cos θ + v sin θ)` for `θ` in `[0, angle]`, tangent to
    /// the pieces on either side, certified on its own.
    Arc {
        /// The circle's centre.
        centre: Vec<f64>,
        /// Unit vector from the centre to the arc's start.
        u: Vec<f64>,
        /// Unit vector orthogonal to `u` in the arc's plane: the direction at the start.
        v: Vec<f64>,
        /// The circle's radius.
        radius: f64,
        /// The angle it turns (rad).
        angle: f64,
    },
}

impl Piece {
    /// Its arc length.
    pub fn length(&self) -> f64 {
        match self {
            Piece::Line { length, .. } => *length,
            Piece::Arc { radius, angle, .. } => radius * angle,
        }
    }

    /// Position, first and second derivative with respect to arc length at `s` (clamped
    /// to the piece); the end of a line is its `b` exactly.
    pub(super) fn eval(&self, s: f64, q: &mut [f64], dq: &mut [f64], ddq: &mut [f64]) {
        match self {
            Piece::Line { a, b, length } => {
                let t = (s / length).clamp(0.0, 1.0);
                for j in 0..a.len() {
                    q[j] = if t >= 1.0 {
                        b[j]
                    } else {
                        a[j] + (b[j] - a[j]) * t
                    };
                    dq[j] = (b[j] - a[j]) / length;
                    ddq[j] = 0.0;
                }
            }
            Piece::Arc {
                centre,
                u,
                v,
                radius,
                angle,
            } => {
                let theta = (s / radius).clamp(0.0, *angle);
                let (sin, cos) = theta.sin_cos();
                for j in 0..centre.len() {
                    let radial = u[j] * cos + v[j] * sin;
                    q[j] = centre[j] + radius * radial;
                    dq[j] = -u[j] * sin + v[j] * cos;
                    ddq[j] = -radial / radius;
                }
            }
        }
    }
}

/// A smoothed path: sections that each start and end at rest (the motion's ends and the
/// corners that could not be blended), each a chain of pieces whose direction is
/// continuous.
#[derive(Clone, Debug, Default)]
pub(super) struct Smoothed {
    pub(super) sections: Vec<Vec<Piece>>,
}

/// What a corner becomes.
struct Corner {
    /// The arc, and how far it cuts into the segments before and after it.
    arc: Option<(Piece, f64)>,
}

/// Smooths the waypoints of `path` (`dim` values each, consecutive ones distinct, every
/// segment certified) with blends of at most `deviation` (rad, in joint space), each
/// certified through `validity`, chords of at most `chord` (the timing's grid step)
/// included. `deviation <= 0` or a validity that certifies no boxes blends nothing.
pub(super) fn smooth<S>(
    path: &[f64],
    dim: usize,
    deviation: f64,
    chord: f64,
    validity: &dyn StateValidity<Scratch = S>,
    scratch: &mut S,
) -> Result<Smoothed, QueryError> {
    let m = path.len().checked_div(dim).unwrap_or(0);
    let point = |i: usize| &path[i * dim..(i + 1) * dim];
    let mut smoothed = Smoothed::default();
    if m < 2 {
        return Ok(smoothed);
    }
    let blend = deviation > 0.0 && validity.certifies_boxes();
    let mut corners = Vec::with_capacity(m.saturating_sub(2));
    for i in 1..m - 1 {
        let corner = if blend {
            corner(
                point(i - 1),
                point(i),
                point(i + 1),
                deviation,
                chord,
                validity,
                scratch,
            )?
        } else {
            None
        };
        corners.push(corner);
    }
    // How far each waypoint's blend cuts into its segments (0 at the ends, at stops and
    // at straight corners).
    let cut = |i: usize| match corners.get(i.wrapping_sub(1)) {
        Some(Some(Corner {
            arc: Some((_, cut)),
        })) if i + 1 < m => *cut,
        _ => 0.0,
    };
    let mut section = Vec::new();
    for k in 0..m - 1 {
        let (p, q) = (point(k), point(k + 1));
        let length = distance(p, q);
        let (mut a, mut b) = (Vec::with_capacity(dim), Vec::with_capacity(dim));
        interpolate(p, q, cut(k) / length, &mut a);
        if cut(k + 1) > 0.0 {
            interpolate(q, p, cut(k + 1) / length, &mut b);
        } else {
            b.extend_from_slice(q);
        }
        let piece = distance(&a, &b);
        if piece > 0.0 {
            section.push(Piece::Line {
                a,
                b,
                length: piece,
            });
        }
        match corners.get(k) {
            // The corner at waypoint k + 1.
            Some(Some(Corner {
                arc: Some((arc, _)),
            })) => section.push(arc.clone()),
            Some(Some(Corner { arc: None })) => {}
            Some(None) | None => {
                if !section.is_empty() {
                    smoothed.sections.push(std::mem::take(&mut section));
                }
            }
        }
    }
    Ok(smoothed)
}

/// The corner at `p` between segments from `a` and to `b`: `None` when it must be passed
/// at rest, a corner without an arc when the segments are collinear.
fn corner<S>(
    a: &[f64],
    p: &[f64],
    b: &[f64],
    deviation: f64,
    chord: f64,
    validity: &dyn StateValidity<Scratch = S>,
    scratch: &mut S,
) -> Result<Option<Corner>, QueryError> {
    let (l1, l2) = (distance(a, p), distance(p, b));
    if l1 == 0.0 || l2 == 0.0 {
        return Ok(None);
    }
    let y1: Vec<f64> = a.iter().zip(p).map(|(x, y)| (y - x) / l1).collect();
    let y2: Vec<f64> = p.iter().zip(b).map(|(x, y)| (y - x) / l2).collect();
    let cos = dot(&y1, &y2).clamp(-1.0, 1.0);
    let alpha = cos.acos();
    if alpha < STRAIGHT {
        return Ok(Some(Corner { arc: None }));
    }
    if alpha > REVERSAL {
        return Ok(None);
    }
    let half = 0.5 * alpha;
    let mut deviation = deviation;
    for _ in 0..TRIES {
        // Kunz and Stilman's blend: the cut `l` along each segment for which the arc
        // passes `deviation` from the corner, capped by the segments' shares.
        let cut = (MAX_SHARE * l1)
            .min(MAX_SHARE * l2)
            .min(deviation * half.sin() / (1.0 - half.cos()));
        let radius = cut / half.tan();
        let bisector: Vec<f64> = y2.iter().zip(&y1).map(|(x, y)| x - y).collect();
        let norm = dot(&bisector, &bisector).sqrt();
        if !(radius.is_finite() && radius > 0.0 && norm > 0.0) {
            return Ok(None);
        }
        let to_centre = radius / half.cos() / norm;
        let centre: Vec<f64> = p
            .iter()
            .zip(&bisector)
            .map(|(x, d)| x + d * to_centre)
            .collect();
        let start: Vec<f64> = p.iter().zip(&y1).map(|(x, d)| x - d * cut).collect();
        let u: Vec<f64> = start
            .iter()
            .zip(&centre)
            .map(|(s, c)| (s - c) / radius)
            .collect();
        let arc = Piece::Arc {
            centre,
            u,
            v: y1.clone(),
            radius,
            angle: alpha,
        };
        if certify_arc(&arc, chord, validity, scratch)? {
            return Ok(Some(Corner {
                arc: Some((arc, cut)),
            }));
        }
        deviation *= RETRY_SHARE;
    }
    Ok(None)
}

/// Whether every configuration of `arc`, and of every chord of at most `chord` arc
/// length between two of its points, is proven free by box certificates.
pub(super) fn certify_arc<S>(
    arc: &Piece,
    chord: f64,
    validity: &dyn StateValidity<Scratch = S>,
    scratch: &mut S,
) -> Result<bool, QueryError> {
    let Piece::Arc {
        u,
        v,
        radius,
        angle,
        ..
    } = arc
    else {
        return Ok(true);
    };
    let dim = u.len();
    // Joint j's share of the arc's plane: its speed along the arc is at most this.
    let plane: Vec<f64> = u
        .iter()
        .zip(v)
        .map(|(a, b)| (a * a + b * b).sqrt())
        .collect();
    // A chord of arc length c between two points of the arc is within its sagitta,
    // r (1 - cos(c / 2r)), of the arc, in the arc's plane.
    let sagitta = radius * (1.0 - (0.5 * chord.min(radius * angle) / radius).cos());
    let (mut q, mut dq, mut ddq) = (vec![0.0; dim], vec![0.0; dim], vec![0.0; dim]);
    let mut widths = vec![0.0; dim];
    let mut open = VecDeque::from([(0.0, *angle)]);
    let mut queries = 0;
    while let Some((lo, hi)) = open.pop_front() {
        if queries == MAX_QUERIES {
            return Ok(false);
        }
        queries += 1;
        let (mid, half) = (0.5 * (lo + hi), 0.5 * (hi - lo));
        arc.eval(mid * radius, &mut q, &mut dq, &mut ddq);
        let reach = radius * half + sagitta;
        for (w, p) in widths.iter_mut().zip(&plane) {
            *w = reach * p;
        }
        let Some(t) = validity.free_radius(&q, &widths, 1.0, scratch)? else {
            return Ok(false);
        };
        if t <= 0.0 {
            return Ok(false);
        }
        if t >= 1.0 {
            continue;
        }
        // The box proven is `t` times the one asked: it covers the angles within `h` of
        // the middle where r h + sagitta <= t (r half + sagitta).
        let proven = (t * reach - sagitta) / radius;
        if proven <= 0.0 {
            open.push_back((lo, mid));
            open.push_back((mid, hi));
        } else {
            open.push_back((lo, mid - proven));
            open.push_back((mid + proven, hi));
        }
    }
    Ok(true)
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// Euclidean distance in joint space.
pub(super) fn distance(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y) * (x - y))
        .sum::<f64>()
        .sqrt()
}
