//! How large a cell's graphs would be, counted before they are built.
//!
//! Memory grows with the graphs (about 60 bytes for each state, arc and adjacent pair,
//! with the artifact), and a cell of a few megabytes can ask for billions of them: an arm
//! that reaches `n` workspaces with derived adjacency moves between `n (n - 1)` pairs, with
//! every grasp it holds. [`check`] counts exactly what [`crate::graph::build`] would make,
//! cheapest first (adjacent pairs, then states and moves by formula, then transitions by
//! merging sorted state lists, stopping at the limit), so a cell over a limit is refused
//! (E0320) in time proportional to the limit, not to its graphs.

use std::cmp::Reverse;
use std::collections::HashMap;

use crate::ids::*;
use crate::model::{Cell, Holder, Holders, Transition};

/// The most states, arcs and adjacent workspace pairs the graphs of one cell may have in
/// all (pairs counted per movable end-effector's reach before repeats are removed).
pub const MAX_GRAPH_SIZE: u64 = 5_000_000;

/// The most states expanding transitions may visit in all: a transition visits the states
/// of its two grasps to find those that share a workspace, and every pair of holders in a
/// shared workspace, so a cell with many transitions between grasps with many states is
/// refused even when few arcs result.
pub const MAX_TRANSITION_VISITS: u64 = 100_000_000;

/// Why the graphs are not built: they would exceed [`MAX_GRAPH_SIZE`] or
/// [`MAX_TRANSITION_VISITS`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TooLarge {
    /// The object whose graph crossed the limit (`None` when the adjacent pairs alone do).
    pub object: Option<ObjectId>,
    /// What was counted when the limit was crossed (more than the limit).
    pub counted: u64,
    /// The limit crossed.
    pub limit: u64,
    /// The movable end-effector that reaches the most workspaces, with how many (it
    /// makes the most move arcs).
    pub biggest_reach: Option<(EndEffectorId, usize)>,
}

/// Counts toward the two limits; `Err` with the limit crossed.
struct Count {
    size: u64,
    visits: u64,
}

impl Count {
    fn size(&mut self, n: u64) -> Result<(), u64> {
        self.size = self.size.saturating_add(n);
        if self.size > MAX_GRAPH_SIZE {
            return Err(MAX_GRAPH_SIZE);
        }
        Ok(())
    }

    fn visits(&mut self, n: u64) -> Result<(), u64> {
        self.visits = self.visits.saturating_add(n);
        if self.visits > MAX_TRANSITION_VISITS {
            return Err(MAX_TRANSITION_VISITS);
        }
        Ok(())
    }
}

/// The size of the graphs of `cell` (states, arcs and adjacent pairs), when it is within
/// [`MAX_GRAPH_SIZE`] and the transitions within [`MAX_TRANSITION_VISITS`].
pub fn check(cell: &Cell) -> Result<u64, TooLarge> {
    let biggest_reach = cell
        .end_effectors
        .iter()
        .filter(|(_, e)| e.is_movable())
        .map(|(id, e)| (id, e.reaches.len()))
        .max_by_key(|&(id, n)| (n, Reverse(id)));
    let mut count = Count { size: 0, visits: 0 };
    let refuse = |object: Option<ObjectId>, count: &Count, limit: u64| TooLarge {
        object,
        counted: if limit == MAX_GRAPH_SIZE {
            count.size
        } else {
            count.visits
        },
        limit,
        biggest_reach,
    };
    let adjacency = Adjacency::of(cell);
    // The artifact records the adjacent pairs: they count, and must be few enough to list.
    count.size = match adjacency.pairs(cell, MAX_GRAPH_SIZE) {
        Ok(pairs) => pairs.len() as u64,
        Err(listed) => listed,
    };
    if count.size > MAX_GRAPH_SIZE {
        return Err(refuse(None, &count, MAX_GRAPH_SIZE));
    }
    // States and moves by formula: one state per holder of a grasp and workspace it
    // reaches, the moves of a movable holder once per grasp it holds.
    let holders = cell.holders();
    let moves: Vec<u64> = cell
        .end_effectors
        .iter()
        .map(|(_, e)| {
            if e.is_movable() {
                adjacency.n_moves(&e.reaches)
            } else {
                0
            }
        })
        .collect();
    for (object, obj) in cell.objects.iter() {
        for &g in &obj.grasps {
            for &e in holders.of(g) {
                let reached = cell.end_effectors[e].reaches.len() as u64;
                count
                    .size(reached + moves[e.index()])
                    .map_err(|limit| refuse(Some(object), &count, limit))?;
            }
        }
    }
    // Transition arcs, found as the graph finds them, and the visits that takes.
    let transitions = transitions_by_object(cell);
    for (object, obj) in cell.objects.iter() {
        let states: HashMap<GraspId, Vec<(WorkspaceId, EndEffectorId)>> = obj
            .grasps
            .iter()
            .map(|&g| (g, states_by_workspace(cell, &holders, g)))
            .collect();
        let of = |g: GraspId| states.get(&g);
        let mut counted = || -> Result<(), u64> {
            for &t in &transitions[object.index()] {
                let transition = &cell.transitions[t];
                let (Some(givers), Some(takers)) = (of(transition.from), of(transition.to)) else {
                    continue;
                };
                count.visits((givers.len() + takers.len()) as u64)?;
                let explicit = is_explicit(cell, transition);
                for (_, here_from, here_to) in shared_workspaces(givers, takers) {
                    count.visits((here_from.len() * here_to.len()) as u64)?;
                    let arcs = here_from
                        .iter()
                        .flat_map(|&(_, ei)| here_to.iter().map(move |&(_, ej)| (ei, ej)))
                        .filter(|&(ei, ej)| exchanges(cell, ei, ej, explicit))
                        .count();
                    count.size(arcs as u64)?;
                }
            }
            Ok(())
        };
        counted().map_err(|limit| refuse(Some(object), &count, limit))?;
    }
    Ok(count.size)
}

// The rules as the budget reads them: the same arcs `crate::graph::build` makes (through
// `cellc_schema::rules`), counted without being built. `tests::counts_what_the_graphs_hold`
// compares the two on every shipped cell.

/// Which workspaces are adjacent: the declared pairs, or (when the cell declares none)
/// every two workspaces one movable end-effector reaches. Kept as lists of neighbours,
/// never as a matrix: a cell of 10⁵ workspaces has 10¹⁰ pairs, and only the few that are
/// adjacent are stored.
#[derive(Clone, Debug)]
pub enum Adjacency {
    /// Derived from reach: two workspaces are adjacent when a movable end-effector reaches
    /// both. Nothing is stored: an end-effector's moves are all pairs of what it reaches.
    Derived,
    /// Declared: per workspace, its neighbours in id order, each with the first `adjacent`
    /// item (index into [`Cell::adjacencies`]) that declares the pair.
    Declared(Vec<Vec<(WorkspaceId, usize)>>),
}

impl Adjacency {
    /// The adjacency of a cell.
    pub fn of(cell: &Cell) -> Adjacency {
        if cell.adjacencies.is_empty() {
            return Adjacency::Derived;
        }
        let mut neighbours: Vec<Vec<(WorkspaceId, usize)>> =
            vec![Vec::new(); cell.workspaces.len()];
        for (i, adj) in cell.adjacencies.iter().enumerate() {
            neighbours[adj.a.index()].push((adj.b, i));
            neighbours[adj.b.index()].push((adj.a, i));
        }
        for list in &mut neighbours {
            // Sorted by neighbour, then declaration: the first of a repeated pair stays.
            list.sort_unstable();
            list.dedup_by_key(|(w, _)| *w);
        }
        Adjacency::Declared(neighbours)
    }

    /// The move arcs of a movable end-effector that reaches `reaches` (sorted): every
    /// ordered pair of adjacent workspaces in it, in order of the first then the second,
    /// with the declaring `adjacent` (if declared).
    fn moves<'a>(
        &'a self,
        reaches: &'a [WorkspaceId],
    ) -> impl Iterator<Item = (WorkspaceId, WorkspaceId, Option<usize>)> + 'a {
        reaches.iter().flat_map(move |&wi| {
            let pairs: Box<dyn Iterator<Item = (WorkspaceId, WorkspaceId, Option<usize>)>> =
                match self {
                    Adjacency::Derived => Box::new(
                        reaches
                            .iter()
                            .filter(move |&&wj| wj != wi)
                            .map(move |&wj| (wi, wj, None)),
                    ),
                    Adjacency::Declared(neighbours) => Box::new(
                        neighbours[wi.index()]
                            .iter()
                            .filter(|(wj, _)| reaches.binary_search(wj).is_ok())
                            .map(move |&(wj, i)| (wi, wj, Some(i))),
                    ),
                };
            pairs
        })
    }

    /// How many move arcs [`Adjacency::moves`] gives for `reaches`, without listing them.
    pub(crate) fn n_moves(&self, reaches: &[WorkspaceId]) -> u64 {
        match self {
            Adjacency::Derived => {
                let r = reaches.len() as u64;
                r * r.saturating_sub(1)
            }
            Adjacency::Declared(_) => self.moves(reaches).count() as u64,
        }
    }

    /// Every adjacent pair `(a, b)` with `a < b`, each once, in order; when deriving them
    /// would list more than `limit` (before removing repeats), that count instead.
    pub fn pairs(&self, cell: &Cell, limit: u64) -> Result<Vec<(WorkspaceId, WorkspaceId)>, u64> {
        let mut pairs = Vec::new();
        match self {
            Adjacency::Derived => {
                let mut listed = 0u64;
                for (_, e) in cell.end_effectors.iter().filter(|(_, e)| e.is_movable()) {
                    let r = e.reaches.len() as u64;
                    listed = listed.saturating_add(r * r.saturating_sub(1) / 2);
                    if listed > limit {
                        return Err(listed);
                    }
                    for (i, &a) in e.reaches.iter().enumerate() {
                        pairs.extend(e.reaches[i + 1..].iter().map(|&b| (a, b)));
                    }
                }
                pairs.sort_unstable();
                pairs.dedup();
            }
            Adjacency::Declared(neighbours) => {
                for (a, list) in neighbours.iter().enumerate() {
                    let a = WorkspaceId(a as u32);
                    pairs.extend(list.iter().filter(|(b, _)| a < *b).map(|&(b, _)| (a, b)));
                }
            }
        }
        Ok(pairs)
    }
}

/// A grasp's states as `(workspace, holder)`, sorted: the order in which a transition's
/// arcs are found, by merging the lists of its two grasps.
pub(crate) fn states_by_workspace(
    cell: &Cell,
    holders: &Holders,
    g: GraspId,
) -> Vec<(WorkspaceId, EndEffectorId)> {
    let mut states: Vec<(WorkspaceId, EndEffectorId)> = holders
        .of(g)
        .iter()
        .flat_map(|&e| cell.end_effectors[e].reaches.iter().map(move |&w| (w, e)))
        .collect();
    states.sort_unstable();
    states
}

/// A grasp's states in one workspace, as `(workspace, holder)`.
pub(crate) type StatesHere<'a> = &'a [(WorkspaceId, EndEffectorId)];

/// The workspaces two sorted state lists share, each with both lists' states there, in
/// workspace order.
pub(crate) fn shared_workspaces<'a>(
    from: StatesHere<'a>,
    to: StatesHere<'a>,
) -> impl Iterator<Item = (WorkspaceId, StatesHere<'a>, StatesHere<'a>)> + 'a {
    let (mut i, mut j) = (0, 0);
    std::iter::from_fn(move || {
        while i < from.len() && j < to.len() {
            let (wa, wb) = (from[i].0, to[j].0);
            if wa != wb {
                if wa < wb {
                    i += 1;
                } else {
                    j += 1;
                }
                continue;
            }
            let i_end = i + from[i..].partition_point(|s| s.0 == wa);
            let j_end = j + to[j..].partition_point(|s| s.0 == wa);
            let here = (wa, &from[i..i_end], &to[j..j_end]);
            (i, j) = (i_end, j_end);
            return Some(here);
        }
        None
    })
}

/// Whether `giver` passes an object to `taker` by a transition: never two fixed
/// end-effectors, and a hand kind's grasps expand to every hand of that kind but no hand
/// passes an object to itself (explicit same-holder rows, as imported databases have, are
/// kept and warned about).
pub(crate) fn exchanges(
    cell: &Cell,
    giver: EndEffectorId,
    taker: EndEffectorId,
    explicit: bool,
) -> bool {
    (giver != taker || explicit)
        && (cell.end_effectors[giver].is_movable() || cell.end_effectors[taker].is_movable())
}

/// Whether a transition's two grasps are both declared for end-effectors (not kinds).
pub(crate) fn is_explicit(cell: &Cell, transition: &Transition) -> bool {
    let explicit = |g: GraspId| matches!(cell.grasps[g].holder, Some(Holder::EndEffector(_)));
    explicit(transition.from) && explicit(transition.to)
}

/// Each object's transitions (indices into [`Cell::transitions`]), in declaration order.
pub(crate) fn transitions_by_object(cell: &Cell) -> Vec<Vec<usize>> {
    let mut transitions: Vec<Vec<usize>> = vec![Vec::new(); cell.objects.len()];
    for (t, transition) in cell.transitions.iter().enumerate() {
        let object = cell.grasps[transition.from].object;
        if cell.grasps[transition.to].object == object {
            transitions[object.index()].push(t);
        }
    }
    transitions
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::MemoryFiles;

    /// The count is what the graphs hold: states, arcs, and the pairs the artifact lists.
    #[test]
    fn counts_what_the_graphs_hold() {
        let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../cells");
        let mut files: Vec<(String, Vec<u8>)> = Vec::new();
        for folder in ["", "robots/"] {
            for entry in std::fs::read_dir(format!("{root}/{folder}")).expect("cells/") {
                let path = entry.expect("entry").path();
                if path.is_file() {
                    let name = format!("{folder}{}", path.file_name().unwrap().to_string_lossy());
                    files.push((name, std::fs::read(&path).expect("readable")));
                }
            }
        }
        let world = MemoryFiles::new(files.iter().map(|(p, b)| (p.as_str(), b.clone())));
        let mut checked = 0;
        for (path, _) in files
            .iter()
            .filter(|(p, _)| p.ends_with(".cell") && !p.contains('/'))
        {
            let compilation = crate::compile(&world, path);
            // A cell whose robot files lie deeper than `cells/robots/` (a ROS package) does
            // not resolve here, and has no graphs to compare.
            let Some(cell) = compilation
                .cell
                .as_ref()
                .filter(|_| !compilation.has_errors())
            else {
                continue;
            };
            let built: u64 = compilation
                .graphs
                .iter()
                .map(|g| (g.graph.node_count() + g.graph.edge_count()) as u64)
                .sum();
            let pairs = Adjacency::of(cell)
                .pairs(cell, MAX_GRAPH_SIZE)
                .expect("few")
                .len();
            assert_eq!(check(cell), Ok(built + pairs as u64), "{path}");
            checked += 1;
        }
        assert!(checked >= 3, "{checked} cells");
    }
}
