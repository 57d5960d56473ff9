//! One row measured: every pair planned (and, in geometric cells, executed) `trials`
//! times, each request timed alone.

use std::time::Instant;

use cellc_runtime::plan::planner::Planner;
use cellc_runtime::scene::Scene;
use cellc_runtime::{ExecuteOptions, Simulator};

use crate::pairs::{cli, pairs};
use crate::paper::Paper;

/// Times of many requests, seconds: every request, and the successful ones.
#[derive(Default)]
pub(crate) struct Stats {
    samples: Vec<f64>,
    successful: Vec<f64>,
}

impl Stats {
    pub(crate) fn push(&mut self, s: f64, ok: bool) {
        self.samples.push(s);
        if ok {
            self.successful.push(s);
        }
    }
    pub(crate) fn failures(&self) -> usize {
        self.samples.len() - self.successful.len()
    }
    pub(crate) fn avg(&self) -> f64 {
        self.samples.iter().sum::<f64>() / self.samples.len().max(1) as f64
    }
    pub(crate) fn ok_avg(&self) -> f64 {
        self.successful.iter().sum::<f64>() / self.successful.len().max(1) as f64
    }
    pub(crate) fn max(&self) -> f64 {
        self.samples.iter().copied().fold(0.0, f64::max)
    }
    pub(crate) fn min(&self) -> f64 {
        self.samples.iter().copied().fold(f64::INFINITY, f64::min)
    }
    pub(crate) fn median(&self) -> f64 {
        let mut v = self.samples.clone();
        v.sort_by(f64::total_cmp);
        v.get(v.len() / 2).copied().unwrap_or(0.0)
    }
}

/// One measured row.
pub(crate) struct Row {
    /// What the row is ("vito.cell cylinder").
    pub(crate) label: String,
    /// The paper's column it compares with, if any.
    pub(crate) paper: Option<&'static Paper>,
    pub(crate) nodes: usize,
    pub(crate) arcs: usize,
    pub(crate) pairs: usize,
    pub(crate) trials: usize,
    pub(crate) hl: Stats,
    /// `None` for abstract graphs (no geometry, no motions).
    pub(crate) total: Option<Stats>,
    /// Per pair: what, high-level and total times.
    pub(crate) per_pair: Vec<(String, Stats, Option<Stats>)>,
    /// Why the row was not measured.
    pub(crate) skipped: Option<String>,
}

/// Plans and (in geometric cells) executes every pair `trials` times.
pub(crate) fn measure(
    label: &str,
    paper: Option<&'static Paper>,
    planner: &Planner<'_>,
    scene: Option<&Scene>,
    object: &str,
    trials: usize,
) -> Row {
    let a = planner.artifact();
    let index = a
        .objects
        .iter()
        .position(|o| o.name == object)
        .expect("object exists") as u32;
    let graph = &a.objects[index as usize].graph;
    let pairs = pairs(planner, index, scene.is_some());
    for p in &pairs {
        eprintln!(
            "  {label}: {} (cellc plan --object {object} --from '{}' --to '{}')",
            p.what,
            cli(a, index, &p.start),
            cli(a, index, &p.goal)
        );
    }
    let mut row = Row {
        label: label.to_string(),
        paper,
        nodes: graph.nodes.len(),
        arcs: graph.arcs.len(),
        pairs: pairs.len(),
        trials,
        hl: Stats::default(),
        total: scene.map(|_| Stats::default()),
        per_pair: Vec::new(),
        skipped: None,
    };
    if pairs.is_empty() {
        row.skipped = Some("no start/goal pair plans".into());
        return row;
    }
    let mut per_pair: Vec<(Stats, Stats)> = pairs.iter().map(|_| Default::default()).collect();
    for trial in 0..trials {
        let seed = trial as u64;
        for (pair, stats) in pairs.iter().zip(per_pair.iter_mut()) {
            let request = pair.request(index, seed, false);
            let t = Instant::now();
            let plan = planner.plan(&request);
            let seconds = t.elapsed().as_secs_f64();
            let ok = std::hint::black_box(&plan).is_ok();
            row.hl.push(seconds, ok);
            stats.0.push(seconds, ok);
            if let Err(e) = plan {
                eprintln!(
                    "  high level failed: {label}, {}, seed {seed}: {e:?}",
                    pair.what
                );
            }
            let Some(total) = row.total.as_mut() else {
                continue;
            };
            let request = pair.request(index, seed, true);
            let t = Instant::now();
            let outcome = match planner.plan(&request) {
                Ok(plan) => {
                    let mut simulator =
                        Simulator::new(a, scene, plan.object, plan.states[0], plan.start_pose);
                    let options = ExecuteOptions {
                        max_replans: 5,
                        plan: request.options.clone(),
                    };
                    planner
                        .execute(plan, &mut simulator, &options)
                        .map(|_| ())
                        .map_err(|e| format!("execution: {e:?}"))
                }
                Err(e) => Err(format!("plan: {e:?}")),
            };
            let seconds = t.elapsed().as_secs_f64();
            total.push(seconds, outcome.is_ok());
            stats.1.push(seconds, outcome.is_ok());
            if let Err(e) = outcome {
                let mut e = e;
                e.truncate(1500);
                eprintln!("  total failed: {label}, {}, seed {seed}: {e}", pair.what);
            }
        }
    }
    let geometric = row.total.is_some();
    row.per_pair = pairs
        .iter()
        .zip(per_pair)
        .map(|(p, (hl, total))| (p.what.clone(), hl, geometric.then_some(total)))
        .collect();
    row
}

pub(crate) fn skipped(label: &str, paper: Option<&'static Paper>, why: String) -> Row {
    Row {
        label: label.to_string(),
        paper,
        nodes: 0,
        arcs: 0,
        pairs: 0,
        trials: 0,
        hl: Stats::default(),
        total: None,
        per_pair: Vec::new(),
        skipped: Some(why),
    }
}
