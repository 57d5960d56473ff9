//! The paper's Table I (Marino et al., RA-L 2016, Sec. V), the figures our rows compare
//! with.

/// One column of the paper's Table I (times in seconds).
pub(crate) struct Paper {
    graph: &'static str,
    pub(crate) nodes: usize,
    pub(crate) arcs: usize,
    pub(crate) hl_avg: f64,
    pub(crate) hl_max: f64,
    pub(crate) hl_min: f64,
    pub(crate) total_avg: f64,
}

const PAPER: [Paper; 5] = [
    Paper {
        graph: "pitcher",
        nodes: 108,
        arcs: 1609,
        hl_avg: 3.2,
        hl_max: 4.6,
        hl_min: 1.8,
        total_avg: 24.2,
    },
    Paper {
        graph: "colander",
        nodes: 144,
        arcs: 3426,
        hl_avg: 5.4,
        hl_max: 9.4,
        hl_min: 2.5,
        total_avg: 28.5,
    },
    Paper {
        graph: "ball",
        nodes: 80,
        arcs: 1056,
        hl_avg: 1.9,
        hl_max: 2.4,
        hl_min: 1.1,
        total_avg: 17.6,
    },
    Paper {
        graph: "cylinder",
        nodes: 224,
        arcs: 5248,
        hl_avg: 2.6,
        hl_max: 3.2,
        hl_min: 2.1,
        total_avg: 21.5,
    },
    Paper {
        graph: "assembly line",
        nodes: 736,
        arcs: 14016,
        hl_avg: 8.5,
        hl_max: 21.3,
        hl_min: 3.1,
        total_avg: 53.0,
    },
];

pub(crate) fn paper(graph: &str) -> Option<&'static Paper> {
    PAPER.iter().find(|p| p.graph == graph)
}
