//! The pruned and failed arcs that matter: those that would have joined the sides, or,
//! when the graph connects anyway, those that failed during the request; and the
//! collisions among them that `allow contact` could name.

use cellc_schema::{Artifact, Body, Infeasibility, Node};

use super::context::{Ctx, Lost};
use super::{BodyName, GaveUp, LostArc, MAX_PRUNED};

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

/// The pairs of bodies whose collision removed some lost arcs, when `allow contact` can
/// name both (an end-effector, a part of one (`arm/link`, `arm/hand kind`), an obstacle
/// or an object) and the cell does not allow that contact already; their groups; and each
/// lost arc's pair.
///
/// Verification records one colliding pair per arc, the first it met. A pair where an
/// arm that holds nothing in the arc collides (standing at home, e.g. its base in the
/// torso it is bolted onto) spoils every check that arm stands by in, so any arc it was
/// reported for may well collide in another such pair too: all of those pairs form one
/// group, allowed together. Every other pair is a group of its own.
pub(super) fn contact_pairs(art: &Artifact, nodes: &[Node], lost: &[Lost]) -> ContactPairs {
    let mut pairs: Vec<(BodyName, BodyName)> = Vec::new();
    let mut standing = Vec::new();
    let allowed = |a: &str, b: &str| {
        art.allowed_contacts
            .iter()
            .any(|(x, y)| (x == a && y == b) || (x == b && y == a))
    };
    let arm = |owner: &str| {
        art.end_effectors
            .iter()
            .position(|e| e.name == owner && matches!(e.body, Body::Arm { .. }))
    };
    let of = lost
        .iter()
        .map(|l| {
            let Infeasibility::Collision { a, b } = &l.reason else {
                return None;
            };
            let (x, y) = (BodyName::of(art, a)?, BodyName::of(art, b)?);
            if x == y || allowed(a, b) {
                return None;
            }
            let holders = [l.from, l.to].map(|i| nodes[i as usize].end_effector.index());
            let stands_by = [&x, &y]
                .iter()
                .any(|body| arm(&body.owner).is_some_and(|e| !holders.contains(&e)));
            let pair = if x <= y { (x, y) } else { (y, x) };
            let i = pairs.iter().position(|p| *p == pair).unwrap_or_else(|| {
                pairs.push(pair);
                standing.push(false);
                pairs.len() - 1
            });
            standing[i] |= stands_by;
            Some(i as u32)
        })
        .collect();
    // The standing pairs share the first one's group; the others are their own.
    let first_standing = standing.iter().position(|&s| s);
    let groups = (0..pairs.len())
        .map(|i| match first_standing {
            Some(f) if standing[i] => f as u32,
            _ => i as u32,
        })
        .collect();
    ContactPairs { pairs, groups, of }
}

/// What [`contact_pairs`] finds.
pub(super) struct ContactPairs {
    /// The pairs, each once.
    pub pairs: Vec<(BodyName, BodyName)>,
    /// Per pair, its group.
    pub groups: Vec<u32>,
    /// Per lost arc, its pair.
    pub of: Vec<Option<u32>>,
}
