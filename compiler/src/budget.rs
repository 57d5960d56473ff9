//! How large a cell's graphs would be, counted before they are built.
//!
//! Memory grows with the graphs (about 60 bytes for each state, arc and adjacent pair,
//! with the artifact), and a cell of a few megabytes can ask for billions of them: an arm
//! that reaches `n` workspaces with derived adjacency moves between `n (n - 1)` pairs, with
//! every grasp it holds. The counting is the graph rules' own ([`CellRules::count`], on
//! the [`GraphRules`] that [`crate::graph::build`] then builds from), stopping at the
//! first limit crossed, so a cell over a limit is refused (E0320) in time proportional to
//! the limit, not to its graphs. This module sets the limits and says where the count
//! crossed one in the compiler's terms.
//!
//! [`CellRules::count`]: cellc_schema::rules::CellRules::count

use std::cmp::Reverse;

use cellc_schema::rules::{Limit, Limits};

use crate::graph::GraphRules;
use crate::ids::*;
use crate::model::Cell;

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

/// The size of the graphs `rules` make (states, arcs and adjacent pairs), when it is
/// within [`MAX_GRAPH_SIZE`] and the transitions within [`MAX_TRANSITION_VISITS`].
pub fn check(cell: &Cell, rules: &GraphRules) -> Result<u64, TooLarge> {
    let limits = Limits {
        size: MAX_GRAPH_SIZE,
        visits: MAX_TRANSITION_VISITS,
    };
    rules
        .cell
        .count(&rules.objects, limits)
        .map_err(|exceeded| {
            let biggest_reach = cell
                .end_effectors
                .iter()
                .filter(|(_, e)| e.is_movable())
                .map(|(id, e)| (id, e.reaches.len()))
                .max_by_key(|&(id, n)| (n, Reverse(id)));
            TooLarge {
                object: exceeded.object.map(|o| ObjectId(o.0)),
                counted: exceeded.counted,
                limit: match exceeded.limit {
                    Limit::Size => MAX_GRAPH_SIZE,
                    Limit::Visits => MAX_TRANSITION_VISITS,
                },
                biggest_reach,
            }
        })
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
            let rules = crate::graph::rules_of(cell);
            let pairs = rules
                .cell
                .adjacent_pairs(MAX_GRAPH_SIZE)
                .expect("few")
                .len();
            assert_eq!(check(cell, &rules), Ok(built + pairs as u64), "{path}");
            checked += 1;
        }
        assert!(checked >= 3, "{checked} cells");
    }
}
