//! Shortening a found path: random shortcuts between its waypoints, then dropping every
//! waypoint its neighbours see past.

use rand::Rng;
use rand_chacha::ChaCha8Rng;

use super::{MotionError, MotionValidity};
use crate::scene::SceneScratch;
use crate::termination::Termination;

/// Drops waypoints equal to their predecessor.
pub(super) fn dedup_waypoints(path: &mut Vec<f64>, dim: usize) {
    if dim == 0 {
        return;
    }
    let m = path.len() / dim;
    let mut kept = 1;
    for i in 1..m {
        let same = path[(kept - 1) * dim..kept * dim] == path[i * dim..(i + 1) * dim];
        if !same {
            path.copy_within(i * dim..(i + 1) * dim, kept * dim);
            kept += 1;
        }
    }
    path.truncate(kept * dim);
}

/// Random shortcuts: two random waypoints are joined directly when the edge between them
/// is free, dropping those in between. Then every waypoint whose neighbours see each
/// other is dropped too, since each waypoint costs a stop in the timing. Every segment of
/// the result is an edge `motion` accepted as a whole (with the default validity, a
/// certified one, so the result is as free as the path it shortens). Shortcuts join
/// waypoints only (never points inside segments), which also keeps the cuts of a sampled
/// validity those of [`check_trajectory`](super::check_trajectory); RRT waypoints are at
/// most `step` apart, so little is lost. `stop` is checked before every attempt.
pub(super) fn shortcut(
    motion: &mut dyn MotionValidity,
    path: &mut Vec<f64>,
    dim: usize,
    iterations: usize,
    rng: &mut ChaCha8Rng,
    stop: &Termination,
    scratch: &mut SceneScratch,
) -> Result<(), MotionError> {
    if dim == 0 {
        return Ok(());
    }
    let stopped = || MotionError::Terminated { iterations: 0 };
    for _ in 0..iterations {
        if stop.should_stop() {
            return Err(stopped());
        }
        let m = path.len() / dim;
        if m <= 2 {
            break;
        }
        let (i, j) = (rng.random_range(0..m), rng.random_range(0..m));
        let (i, j) = (i.min(j), i.max(j));
        if j < i + 2 {
            continue;
        }
        let (head, tail) = path.split_at(j * dim);
        if motion.check_motion(&head[i * dim..(i + 1) * dim], &tail[..dim], scratch)? {
            path.drain((i + 1) * dim..j * dim);
        }
    }
    let mut i = 1;
    while (i + 1) * dim < path.len() {
        if stop.should_stop() {
            return Err(stopped());
        }
        let (head, tail) = path.split_at(i * dim);
        let (before, after) = (&head[(i - 1) * dim..], &tail[dim..2 * dim]);
        if motion.check_motion(before, after, scratch)? {
            path.drain(i * dim..(i + 1) * dim);
        } else {
            i += 1;
        }
    }
    Ok(())
}
