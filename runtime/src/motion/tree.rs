//! RRT-Connect's two trees, grown lazily: a node joins a tree when it is valid, and the
//! edges of a path are checked only once the trees have met and the path has been
//! shortened (`rrt.rs` drives the rounds, `shortcut.rs` checks what survives).
//!
//! Checking every edge as the trees grow is what RRT-Connect does in its paper and in
//! OMPL, and with sound edge checks it is most of the cost: an edge takes a dozen or more
//! clearance certificates where a node takes one intersection test, and most edges never
//! lie on the path. In the cage of `cells/panda_cage.cell` the trees grow about 340 edges
//! for a path of 25 waypoints, and shortcutting leaves 5 of those; checking edges eagerly
//! spent 1,600 certificates on the trees alone. Lazily, a found path that crosses an
//! obstacle between two valid nodes is caught when its edges are checked: the refused
//! edge's lower node and everything below it are cut off (they were reached through it)
//! and the trees grow on, their other nodes and already accepted edges kept (a node's
//! edge midpoint is checked with it, which keeps most such paths from forming). This is the
//! lazy evaluation of Bohlin and Kavraki's Lazy PRM (2000), applied to the two trees.

use rand::Rng;
use rand_chacha::ChaCha8Rng;

use super::segment::{interpolate, max_diff};
use super::{MotionError, MotionOptions};
use crate::scene::QueryError;
use crate::termination::Termination;
use crate::validity::{all_valid, Screened, StateValidity};

/// A tree of configurations, stored flat (`dim` values per node) so growing it allocates
/// rarely and the nearest-neighbour scan runs over contiguous memory.
struct Tree {
    dim: usize,
    nodes: Vec<f64>,
    parents: Vec<u32>,
    /// Whether the edge from a node to its parent has been accepted (the root's: true).
    checked: Vec<bool>,
    /// Nodes cut off: an edge between them and the root was refused.
    dead: Vec<bool>,
}

impl Tree {
    fn new(root: &[f64]) -> Tree {
        let mut nodes = Vec::with_capacity(root.len() * 256);
        nodes.extend_from_slice(root);
        Tree {
            dim: root.len(),
            nodes,
            parents: vec![0],
            checked: vec![true],
            dead: vec![false],
        }
    }

    fn len(&self) -> usize {
        self.parents.len()
    }

    fn node(&self, i: usize) -> &[f64] {
        &self.nodes[i * self.dim..(i + 1) * self.dim]
    }

    fn push(&mut self, q: &[f64], parent: usize) -> usize {
        self.nodes.extend_from_slice(q);
        // Trees never approach 2^32 nodes (iterations are bounded far below).
        self.parents.push(parent as u32);
        self.checked.push(false);
        self.dead.push(false);
        self.len() - 1
    }

    /// The live node closest to `q` (Euclidean in joint space). A linear scan: trees have
    /// tens to a few thousand nodes, where it beats building a spatial index. The root
    /// never dies, so there always is one.
    fn nearest(&self, q: &[f64]) -> usize {
        let mut best = (0, f64::INFINITY);
        let nodes = self.nodes.chunks_exact(self.dim.max(1)).zip(&self.dead);
        for (i, (node, &dead)) in nodes.enumerate() {
            if dead {
                continue;
            }
            let d: f64 = node.iter().zip(q).map(|(x, y)| (x - y) * (x - y)).sum();
            if d < best.1 {
                best = (i, d);
            }
        }
        best.0
    }

    /// Cuts node `i` and its descendants off. Children are pushed after their parents,
    /// so one pass over the later nodes finds every descendant.
    fn cut(&mut self, i: usize) {
        self.dead[i] = true;
        for k in i + 1..self.len() {
            if self.dead[self.parents[k] as usize] {
                self.dead[k] = true;
            }
        }
    }

    /// Node `i` and its ancestors up to the root, in that order.
    fn chain(&self, mut i: usize) -> Vec<usize> {
        let mut nodes = vec![i];
        while i != 0 {
            i = self.parents[i] as usize;
            nodes.push(i);
        }
        nodes
    }
}

/// An edge of a found path as the trees hold it: node `node` of tree `tree` (0 is rooted
/// at the start, 1 at the goal) and its parent.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct TreeEdge {
    tree: usize,
    node: usize,
}

/// The result of extending a tree towards a configuration.
enum Extension {
    /// Reached it (node index).
    Reached(usize),
    /// Moved one step towards it (node index).
    Advanced(usize),
    /// Blocked.
    Trapped,
}

/// The search between rounds: both trees, whose turn it is, and the iterations spent.
pub(super) struct Search<'v, S> {
    validity: &'v dyn StateValidity<Scratch = S>,
    step: f64,
    trees: [Tree; 2],
    /// Which tree grows towards the next sample; the other connects to it.
    active: usize,
    iteration: usize,
    sample: Vec<f64>,
    reached: Vec<f64>,
    new: Vec<f64>,
    mid: Vec<f64>,
    /// The new node and its edge's midpoint, concatenated, for the batched screen.
    pair: Vec<f64>,
}

impl<'v, S> Search<'v, S> {
    /// Trees rooted at `start` and `goal` (both valid), nodes checked by `validity`, at
    /// most `step` apart per joint.
    pub(super) fn new(
        validity: &'v dyn StateValidity<Scratch = S>,
        step: f64,
        start: &[f64],
        goal: &[f64],
    ) -> Search<'v, S> {
        let dim = start.len();
        Search {
            validity,
            step,
            trees: [Tree::new(start), Tree::new(goal)],
            active: 0,
            iteration: 0,
            sample: vec![0.0; dim],
            reached: vec![0.0; dim],
            new: Vec::with_capacity(dim),
            mid: Vec::with_capacity(dim),
            pair: Vec::with_capacity(2 * dim),
        }
    }

    /// Grows the trees until they meet, RRT-Connect's way (the active tree one step
    /// towards a goal-biased uniform sample in `ranges`, the other greedily towards the
    /// new node): the path through them (waypoints flat, start first, no two equal in a
    /// row) and, per pair of consecutive waypoints, the tree edge it runs along. `None`
    /// once `options.max_iterations` iterations have been spent, over all rounds. `stop`
    /// is checked at the start of every iteration.
    #[allow(clippy::type_complexity)]
    pub(super) fn next_path(
        &mut self,
        ranges: &[(f64, f64)],
        options: &MotionOptions,
        rng: &mut ChaCha8Rng,
        stop: &Termination,
        scratch: &mut S,
    ) -> Result<Option<(Vec<f64>, Vec<TreeEdge>)>, MotionError> {
        while self.iteration < options.max_iterations {
            if stop.should_stop() {
                return Err(MotionError::Terminated {
                    iterations: self.iteration,
                });
            }
            self.iteration += 1;
            let grow = self.active;
            self.active = 1 - self.active;
            let other = 1 - grow;
            if rng.random::<f64>() < options.goal_bias {
                let root = self.trees[other].node(0);
                self.sample.copy_from_slice(root);
            } else {
                for (v, &(lo, hi)) in self.sample.iter_mut().zip(ranges) {
                    *v = lo + (hi - lo) * rng.random::<f64>();
                }
            }
            let target = std::mem::take(&mut self.sample);
            let new = self.extend(grow, &target, scratch);
            self.sample = target;
            let i = match new? {
                Extension::Trapped => continue,
                Extension::Reached(i) | Extension::Advanced(i) => i,
            };
            self.reached.clear();
            self.reached.extend_from_slice(self.trees[grow].node(i));
            let target = std::mem::take(&mut self.reached);
            let met = self.connect(other, &target, scratch);
            self.reached = target;
            if let Some(j) = met? {
                let (i_s, i_g) = if grow == 0 { (i, j) } else { (j, i) };
                return Ok(Some(self.path(i_s, i_g)));
            }
        }
        Ok(None)
    }

    /// The path from the start tree's root to its node `i_s`, then on from the goal
    /// tree's node `i_g` (the same configuration, bit for bit) to its root.
    fn path(&self, i_s: usize, i_g: usize) -> (Vec<f64>, Vec<TreeEdge>) {
        let [from_start, from_goal] = &self.trees;
        let mut path = Vec::new();
        let mut edges = Vec::new();
        let down = from_start.chain(i_s);
        for (k, &n) in down.iter().rev().enumerate() {
            path.extend_from_slice(from_start.node(n));
            if k > 0 {
                edges.push(TreeEdge { tree: 0, node: n });
            }
        }
        let up = from_goal.chain(i_g);
        for pair in up.windows(2) {
            path.extend_from_slice(from_goal.node(pair[1]));
            edges.push(TreeEdge {
                tree: 1,
                node: pair[0],
            });
        }
        (path, edges)
    }

    /// Iterations spent so far, over all rounds.
    pub(super) fn iterations(&self) -> usize {
        self.iteration
    }

    /// Whether `edge` has been accepted.
    pub(super) fn checked(&self, edge: TreeEdge) -> bool {
        self.trees[edge.tree].checked[edge.node]
    }

    /// Records that `edge` was accepted.
    pub(super) fn accept(&mut self, edge: TreeEdge) {
        self.trees[edge.tree].checked[edge.node] = true;
    }

    /// Records that `edge` was refused: its lower node and what hangs below are cut off.
    pub(super) fn refuse(&mut self, edge: TreeEdge) {
        self.trees[edge.tree].cut(edge.node);
    }

    /// One step of at most `step` (per joint) from the live node of tree `t` nearest
    /// `target` towards it; the new node joins when it and its edge's midpoint are
    /// valid.
    fn extend(
        &mut self,
        t: usize,
        target: &[f64],
        scratch: &mut S,
    ) -> Result<Extension, QueryError> {
        let tree = &mut self.trees[t];
        let near = tree.nearest(target);
        let from = tree.node(near);
        let d = max_diff(from, target);
        if d == 0.0 {
            return Ok(Extension::Reached(near));
        }
        let reached = d <= self.step;
        if reached {
            // Exactly the target, so trees that meet share the configuration bit for bit.
            self.new.clear();
            self.new.extend_from_slice(target);
        } else {
            interpolate(from, target, self.step / d, &mut self.new);
        }
        // And its edge's midpoint: a step can jump a thin obstacle (a hand through a
        // table top, past a cube's corner), and a path through such an edge would be
        // refused only after its round's shortcutting. With the midpoint the Vito
        // requests plan in about a third of the time, the cage's VAMP motion in 3.6 ms
        // (4.7 ms without it), and the carry round the cage for 31 of 32 seeds (26); the
        // quarters too measured slower again.
        interpolate(from, &self.new, 0.5, &mut self.mid);
        self.pair.clear();
        self.pair.extend_from_slice(&self.new);
        self.pair.extend_from_slice(&self.mid);
        let mut screened = [Screened::Unknown; 2];
        if !all_valid(self.validity, &self.pair, &mut screened, scratch)? {
            return Ok(Extension::Trapped);
        }
        let i = tree.push(&self.new, near);
        Ok(if reached {
            Extension::Reached(i)
        } else {
            Extension::Advanced(i)
        })
    }

    /// Extends tree `t` towards `target` until it gets there or is blocked.
    fn connect(
        &mut self,
        t: usize,
        target: &[f64],
        scratch: &mut S,
    ) -> Result<Option<usize>, QueryError> {
        loop {
            match self.extend(t, target, scratch)? {
                Extension::Reached(i) => return Ok(Some(i)),
                Extension::Advanced(_) => {}
                Extension::Trapped => return Ok(None),
            }
        }
    }
}
