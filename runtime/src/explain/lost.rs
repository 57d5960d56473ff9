//! The pruned and failed arcs that matter: those that would have joined the sides, or,
//! when the graph connects anyway, those that failed during the request.

use super::context::Ctx;
use super::{GaveUp, LostArc, MAX_PRUNED};

impl Ctx<'_> {
    /// Pruned and failed arcs on some start-to-goal path once they are all restored, those
    /// leaving R into G first, then those leaving R, then those entering G; and how many
    /// were left out.
    pub fn pruned_arcs(&self) -> (Vec<LostArc>, usize) {
        let n = self.nodes.len();
        let (r_all, g_all) = self.distances(true);
        let mut picked: Vec<(u8, usize)> = self
            .lost
            .iter()
            .enumerate()
            .filter(|(_, l)| {
                let (f, t) = (l.from as usize, l.to as usize);
                f < n && t < n && r_all[f].is_finite() && g_all[t].is_finite()
            })
            .map(|(i, l)| {
                let (f, t) = (l.from as usize, l.to as usize);
                let rank = match (self.in_r[f], self.in_g[t]) {
                    (true, true) => 0,
                    (true, false) => 1,
                    (false, true) => 2,
                    (false, false) => 3,
                };
                (rank, i)
            })
            .collect();
        picked.sort_unstable();
        let omitted = picked.len().saturating_sub(MAX_PRUNED);
        let arcs = picked
            .into_iter()
            .take(MAX_PRUNED)
            .map(|(_, i)| self.lost_arc(i))
            .collect();
        (arcs, omitted)
    }

    /// Why the planner gave up on a graph that connects: the arcs that failed during the
    /// request, in the order they failed.
    pub fn gave_up(&self) -> GaveUp {
        let failed: Vec<usize> = (0..self.lost.len())
            .filter(|&i| self.lost[i].failed)
            .collect();
        if failed.is_empty() {
            return GaveUp::NothingFailed;
        }
        GaveUp::Backtracks {
            omitted: failed.len().saturating_sub(MAX_PRUNED),
            failed: failed
                .into_iter()
                .take(MAX_PRUNED)
                .map(|i| self.lost_arc(i))
                .collect(),
        }
    }
}
