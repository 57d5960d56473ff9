//! Shortening a found path: random shortcuts between its waypoints, then dropping every
//! waypoint its neighbours see past.

use rand::Rng;
use rand_chacha::ChaCha8Rng;
use rustc_hash::FxHashSet;

use super::{MotionError, MotionValidity};
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
/// other is dropped too, since each waypoint costs a stop in the timing. Shortcuts join
/// waypoints only (never points inside segments), which also keeps the cuts of a sampled
/// validity those of [`check_trajectory`](super::check_trajectory); RRT waypoints are at
/// most `step` apart, so little is lost. `stop` is checked before every attempt.
///
/// Nothing is checked by `motion` (the sound check) until the end. The shortcuts are
/// taken on `screen`'s word (a sampled check, many times cheaper than certifying an edge,
/// and right about most), and most of them are later cut short by a longer one: in the
/// cage of `cells/panda_cage.cell` about 4 of 11 taken shortcuts survive, and certifying
/// one there takes 30 or more clearance certificates. Then every edge of the result goes
/// to `motion`, unless it is an edge of `path` that `accepted` (one flag per edge of
/// `path`, edge `e` joining waypoints `e` and `e + 1`) marks as accepted already. A
/// refused shortcut is replaced by the waypoints of `path` it had cut out, whose edges
/// are checked in turn. A refused edge of `path` ends the call with its index: `path` is
/// then left part shortened, and the caller must find another (the lazy trees of
/// `tree.rs` cut that edge off). Otherwise (`None`) every segment of the result is one
/// `motion` accepted as a whole: with the default validity, certified. Edges of `path`
/// accepted on the way are marked in `accepted`.
///
/// Checks are reused: an edge between two waypoints that was refused once is never
/// checked again (random draws repeat pairs often on a short path, and the final pass
/// asks again about neighbours the random phase already tried). Edge checks are
/// deterministic in their ends, so skipping a known refusal changes no result, and the
/// random draws are the same as without the memory.
#[allow(clippy::too_many_arguments)]
pub(super) fn shortcut<S>(
    motion: &mut dyn MotionValidity<Scratch = S>,
    screen: &mut dyn MotionValidity<Scratch = S>,
    path: &mut Vec<f64>,
    dim: usize,
    accepted: &mut [bool],
    iterations: usize,
    rng: &mut ChaCha8Rng,
    stop: &Termination,
    scratch: &mut S,
) -> Result<Option<usize>, MotionError> {
    if dim == 0 {
        return Ok(None);
    }
    let stopped = || MotionError::Terminated { iterations: 0 };
    let original = path.clone();
    // Waypoints keep their original index as identity while others are dropped.
    let mut ids: Vec<u32> = (0..(path.len() / dim) as u32).collect();
    let mut refused: FxHashSet<(u32, u32)> = FxHashSet::default();
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
        if j < i + 2 || refused.contains(&(ids[i], ids[j])) {
            continue;
        }
        let (head, tail) = path.split_at(j * dim);
        if screen.check_motion(&head[i * dim..(i + 1) * dim], &tail[..dim], scratch)? {
            path.drain((i + 1) * dim..j * dim);
            ids.drain(i + 1..j);
        } else {
            refused.insert((ids[i], ids[j]));
        }
    }
    let mut i = 1;
    while (i + 1) * dim < path.len() {
        if stop.should_stop() {
            return Err(stopped());
        }
        if refused.contains(&(ids[i - 1], ids[i + 1])) {
            i += 1;
            continue;
        }
        let (head, tail) = path.split_at(i * dim);
        let (before, after) = (&head[(i - 1) * dim..], &tail[dim..2 * dim]);
        if screen.check_motion(before, after, scratch)? {
            path.drain(i * dim..(i + 1) * dim);
            ids.remove(i);
        } else {
            i += 1;
        }
    }
    // What survives, to `motion`: an edge of `path` it refuses ends the round; a refused
    // shortcut gets the waypoints it cut out back, their edges checked in turn.
    let mut k = 1;
    while k < ids.len() {
        if stop.should_stop() {
            return Err(stopped());
        }
        let (from, to) = (ids[k - 1] as usize, ids[k] as usize);
        if to == from + 1 && accepted[from] {
            k += 1;
            continue;
        }
        let (head, tail) = path.split_at(k * dim);
        if motion.check_motion(&head[(k - 1) * dim..], &tail[..dim], scratch)? {
            if to == from + 1 {
                accepted[from] = true;
            }
            k += 1;
        } else if to == from + 1 {
            return Ok(Some(from));
        } else {
            let at = k * dim;
            path.splice(at..at, original[(from + 1) * dim..to * dim].iter().copied());
            ids.splice(k..k, (from + 1) as u32..to as u32);
        }
    }
    Ok(None)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::QueryError;
    use rand::SeedableRng;
    use std::collections::HashMap;

    /// A plane with a wall on x = 0 for y < 1: an edge is free when it does not cross the
    /// wall below its top. Counts how often each edge is asked about.
    #[derive(Default)]
    struct Wall {
        asked: HashMap<(u64, u64, u64, u64), usize>,
    }

    impl MotionValidity for Wall {
        type Scratch = ();

        fn check_motion(&mut self, a: &[f64], b: &[f64], _: &mut ()) -> Result<bool, QueryError> {
            let key = (
                a[0].to_bits(),
                a[1].to_bits(),
                b[0].to_bits(),
                b[1].to_bits(),
            );
            *self.asked.entry(key).or_default() += 1;
            if (a[0] < 0.0) == (b[0] < 0.0) {
                return Ok(true);
            }
            let t = a[0] / (a[0] - b[0]);
            Ok(a[1] + t * (b[1] - a[1]) >= 1.0)
        }
    }

    /// A path that goes round the wall in many small steps.
    fn detour() -> Vec<f64> {
        let mut path = Vec::new();
        for k in 0..=20 {
            path.extend([-1.0, f64::from(k) * 0.1]);
        }
        for k in 1..=20 {
            path.extend([-1.0 + f64::from(k) * 0.1, 2.0]);
        }
        for k in 1..=20 {
            path.extend([1.0, 2.0 - f64::from(k) * 0.1]);
        }
        path
    }

    /// Accepts every edge: a screen that is always wrong about the wall.
    struct Blind;

    impl MotionValidity for Blind {
        type Scratch = ();

        fn check_motion(&mut self, _: &[f64], _: &[f64], _: &mut ()) -> Result<bool, QueryError> {
            Ok(true)
        }
    }

    /// [`shortcut`] on a plane path with `iterations` random attempts drawn with `seed`.
    fn run(
        motion: &mut dyn MotionValidity<Scratch = ()>,
        screen: &mut dyn MotionValidity<Scratch = ()>,
        path: &mut Vec<f64>,
        accepted: &mut [bool],
        iterations: usize,
        seed: u64,
    ) -> Option<usize> {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let (stop, mut scratch) = (Termination::never(), ());
        shortcut(
            motion,
            screen,
            path,
            2,
            accepted,
            iterations,
            &mut rng,
            &stop,
            &mut scratch,
        )
        .unwrap()
    }

    /// Every segment of `path` is free by the wall's own check.
    fn assert_free(path: &[f64], scratch: &mut ()) {
        let mut check = Wall::default();
        for w in path.chunks(2).collect::<Vec<_>>().windows(2) {
            assert!(check.check_motion(w[0], w[1], scratch).unwrap(), "{w:?}");
        }
    }

    #[test]
    fn no_edge_is_checked_twice_and_every_kept_edge_is_free() {
        for seed in 0..8 {
            let (mut screen, mut wall) = (Wall::default(), Wall::default());
            let mut path = detour();
            let mut accepted = vec![true; path.len() / 2 - 1];
            let mut scratch = ();
            let refused = run(&mut wall, &mut screen, &mut path, &mut accepted, 200, seed);
            assert_eq!(refused, None);
            let repeated = screen.asked.values().filter(|&&n| n > 1).count();
            assert_eq!(repeated, 0, "seed {seed}: an edge was screened again");
            // The sound check saw the surviving shortcuts only, each once.
            assert!(!wall.asked.is_empty() && wall.asked.len() < screen.asked.len());
            assert!(wall.asked.values().all(|&n| n == 1));
            assert!(
                path.len() < detour().len(),
                "seed {seed}: nothing was shortened"
            );
            assert_eq!(&path[..2], &[-1.0, 0.0]);
            assert_eq!(&path[path.len() - 2..], &[1.0, 0.0]);
            assert_free(&path, &mut scratch);
        }
    }

    /// A screen that lets shortcuts through the wall: the sound check refuses them and
    /// the waypoints they cut out come back, so the result is still free.
    #[test]
    fn refused_shortcuts_get_their_waypoints_back() {
        for seed in 0..8 {
            let mut wall = Wall::default();
            let mut path = detour();
            let mut accepted = vec![true; path.len() / 2 - 1];
            let mut scratch = ();
            let refused = run(&mut wall, &mut Blind, &mut path, &mut accepted, 200, seed);
            assert_eq!(refused, None);
            // Blind took shortcuts through the wall, which the sound check was asked.
            assert!(!wall.asked.is_empty());
            assert_eq!(&path[..2], &[-1.0, 0.0]);
            assert_eq!(&path[path.len() - 2..], &[1.0, 0.0]);
            assert_free(&path, &mut scratch);
        }
    }

    /// An edge of the given path that the sound check refuses is reported by its index,
    /// after the edges before it were accepted and marked.
    #[test]
    fn a_refused_edge_of_the_path_is_reported() {
        // The edge from the second waypoint to the third crosses the wall.
        let mut path = vec![-1.0, 0.0, -0.5, 0.0, 0.5, 0.0, 1.0, 0.0];
        let mut accepted = vec![false; 3];
        let (mut wall, mut screen) = (Wall::default(), Wall::default());
        let refused = run(&mut wall, &mut screen, &mut path, &mut accepted, 20, 0);
        assert_eq!(refused, Some(1));
        assert_eq!(accepted, [true, false, false]);
    }
}
