//! The cell at home, placed once: every arm at home and the furniture, in one index of
//! boxes that every query of the scene shares.
//!
//! Most of a cell stands still in any one question: a query moves one or two arms and
//! one object, and a line of fifty arms leaves forty-eight at home. Placing and sorting
//! every body per query made each check pay for the whole cell (a check at 50 arms cost
//! eight times one at 5), and the per-motion standing set that replaced that for motions
//! still placed every body once per motion and built its hierarchy over all of them. A
//! [`Home`] is built once per scene: the pose, box and sphere of every robot body at its
//! robot's home configuration and of every fixed body, their boxes in a bounding-volume
//! index (`boxes.rs`), and the pairs among them that already touch (none, in a
//! cell `cellc build` accepts: E0420 refuses an arm at home in collision). A query then
//! names the robots that are *away* from home (their resting bodies are skipped) and
//! places only the bodies that are not at home: its cost follows them and what is near
//! them, not the size of the cell (`frozen.rs` has the queries).
//!
//! Objects are never at home here: a cell's objects are where a request puts them, so
//! they are placed by each query (or once per motion, for one that stands still).

use std::sync::atomic::{AtomicU64, Ordering};

use super::boxes::BoxIndex;
use super::broad_phase::PlacedBody;
use super::build::Mount;
use super::world::{CollisionScratch, CollisionWorld, Visit};
use super::{CollisionError, Configuration};

/// Tags standing sets (a [`Home`], a motion's [`Frozen`](super::Frozen)) so that a
/// scratch knows which one its buffers hold.
static NEXT_TAG: AtomicU64 = AtomicU64::new(1);

/// A fresh tag (never 0, which a scratch uses for "none").
pub(super) fn next_tag() -> u64 {
    NEXT_TAG.fetch_add(1, Ordering::Relaxed)
}

/// The bodies of a cell at home (see [the module](self) documentation). Built by
/// [`CollisionWorld::at_home`] for one world; a query with another world's states is
/// refused by its shape check.
#[derive(Clone, Debug)]
pub(crate) struct Home {
    pub(super) tag: u64,
    /// Per body: where it is at home; `None` for object bodies.
    pub(super) placed: Vec<Option<PlacedBody>>,
    /// The resting bodies' boxes, numbered as `leaves`.
    pub(super) boxes: BoxIndex,
    /// Body index of each box.
    pub(super) leaves: Vec<u32>,
    /// Pairs of resting bodies that may not touch and intersect at home, in body order.
    pub(super) hits: Vec<(u32, u32)>,
    /// Per robot: its bodies.
    pub(super) robot_bodies: Vec<Vec<u32>>,
    /// Per object: its bodies.
    pub(super) object_bodies: Vec<Vec<u32>>,
}

impl CollisionWorld {
    /// The world at home in `home`: robots at the frames it gives (their home
    /// configurations), objects ignored (they are never at home).
    pub(crate) fn at_home(&self, home: &Configuration<'_>) -> Result<Home, CollisionError> {
        self.check_state(home)?;
        let n = self.bodies.len();
        let mut placed = vec![None; n];
        for (i, slot) in placed.iter_mut().enumerate() {
            if !matches!(self.bodies[i].mount, Mount::Object { .. }) {
                *slot = self.place_body(home, i, 0.0)?;
            }
        }
        let leaves: Vec<u32> = (0..n as u32)
            .filter(|&i| placed[i as usize].is_some())
            .collect();
        let boxes = BoxIndex::new(
            leaves
                .iter()
                .filter_map(|&i| placed[i as usize].map(|p| p.aabb))
                .collect(),
        );
        let robot_bodies = self.owned(self.robots.len(), |m| match m {
            Mount::Frame { robot, .. } => Some(robot),
            _ => None,
        });
        let object_bodies = self.owned(self.objects.len(), |m| match m {
            Mount::Object { object } => Some(object),
            _ => None,
        });
        // The pairs that touch at home, by the plain broad phase over the resting state
        // (objects absent).
        let objects = vec![super::ObjectState::absent(); home.objects.len()];
        let at_home_state = Configuration {
            robots: home.robots,
            objects: &objects,
        };
        let mut scratch = CollisionScratch::default();
        self.place(&at_home_state, &mut scratch, |_| 0.0)?;
        let mut hits = Vec::new();
        self.sweep(&at_home_state, &mut scratch, |i, j, scratch| {
            if self.intersect(i, j, scratch)? {
                hits.push((i as u32, j as u32));
            }
            Ok(Visit::Continue)
        })?;
        hits.sort_unstable();
        Ok(Home {
            tag: next_tag(),
            placed,
            boxes,
            leaves,
            hits,
            robot_bodies,
            object_bodies,
        })
    }

    /// Per owner (`count` of them): the bodies `owner` maps to it, in body order.
    fn owned(&self, count: usize, owner: impl Fn(Mount) -> Option<usize>) -> Vec<Vec<u32>> {
        let mut lists = vec![Vec::new(); count];
        for (i, b) in self.bodies.iter().enumerate() {
            if let Some(list) = owner(b.mount).and_then(|o| lists.get_mut(o)) {
                list.push(i as u32);
            }
        }
        lists
    }

    /// Whether body `i` rides on a robot that `away` marks.
    #[inline]
    pub(super) fn on_away_robot(&self, i: usize, away: &[bool]) -> bool {
        match self.bodies[i].mount {
            Mount::Frame { robot, .. } => away.get(robot).copied().unwrap_or(false),
            _ => false,
        }
    }
}

impl Home {
    /// Whether a pair that touches at home has neither body on a robot `away` marks.
    pub(super) fn touches(&self, world: &CollisionWorld, away: &[bool]) -> bool {
        self.hits.iter().any(|&(i, j)| {
            !world.on_away_robot(i as usize, away) && !world.on_away_robot(j as usize, away)
        })
    }
}
