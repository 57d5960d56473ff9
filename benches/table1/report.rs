//! The tables, in markdown: what was measured, per pair, and beside the paper's figures.

use crate::measure::Row;

/// Prints the three tables of `rows`.
pub(crate) fn print(rows: &[Row]) {
    measured(rows);
    per_pair(rows);
    beside_the_paper(rows);
}

/// Every row: sizes, high-level and total times, failures.
fn measured(rows: &[Row]) {
    println!();
    println!("| graph | nodes | arcs | pairs x trials | high-level avg / max / min (ms) | high-level median (ms) | total avg (ms) | total median (ms) | failed requests (high level / total) | successful only: high-level avg / total avg (ms) |");
    println!("|---|---|---|---|---|---|---|---|---|---|");
    for r in rows {
        if let Some(why) = &r.skipped {
            println!("| {} | — | — | — | skipped: {why} | | | | | |", r.label);
            continue;
        }
        let (total, total_median, total_failed, total_ok) = match &r.total {
            Some(t) => (
                ms(t.avg()),
                ms(t.median()),
                t.failures().to_string(),
                ms(t.ok_avg()),
            ),
            None => (
                "n/a (no geometry)".into(),
                "n/a".into(),
                "n/a".into(),
                "n/a".into(),
            ),
        };
        println!(
            "| {} | {} | {} | {} x {} | {} / {} / {} | {} | {} | {} | {} / {} | {} / {} |",
            r.label,
            r.nodes,
            r.arcs,
            r.pairs,
            r.trials,
            ms(r.hl.avg()),
            ms(r.hl.max()),
            ms(r.hl.min()),
            ms(r.hl.median()),
            total,
            total_median,
            r.hl.failures(),
            total_failed,
            ms(r.hl.ok_avg()),
            total_ok
        );
    }
}

/// Every pair of every row.
fn per_pair(rows: &[Row]) {
    println!();
    println!("Per pair (over the trials):\n");
    println!("| graph | pair | high-level avg (ms) | failed | total avg (ms) | failed |");
    println!("|---|---|---|---|---|---|");
    for r in rows {
        for (what, hl, total) in &r.per_pair {
            let (t, f) = match total {
                Some(t) => (ms(t.avg()), t.failures().to_string()),
                None => ("n/a".into(), "n/a".into()),
            };
            println!(
                "| {} | {what} | {} | {} | {t} | {f} |",
                r.label,
                ms(hl.avg()),
                hl.failures()
            );
        }
    }
}

/// The rows that have a column in the paper, with the ratios paper / ours.
fn beside_the_paper(rows: &[Row]) {
    println!();
    println!("# Beside the paper's Table I (i7-4770K, single thread)\n");
    println!("Ratios are paper / ours on the average over every request (failed ones included); in brackets, on the successful requests only. \"Per arc\" divides both times by their graph's arcs (pessimistic for our smaller graphs: it assumes the time grows with the graph).\n");
    println!("| graph | paper nodes / arcs | ours nodes / arcs | paper high-level avg / max / min (s) | ours (ms) | high-level ratio | per arc | paper total avg (s) | ours (ms) | total ratio | per arc |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|");
    for r in rows {
        let Some(p) = r.paper else { continue };
        if r.skipped.is_some() {
            println!(
                "| {} | {} / {} | — | {} / {} / {} | — | — | — | {} | — | — | — |",
                r.label, p.nodes, p.arcs, p.hl_avg, p.hl_max, p.hl_min, p.total_avg
            );
            continue;
        }
        let per_arc = r.arcs as f64 / p.arcs as f64;
        let both = |x: f64, y: f64| {
            if (x - y).abs() <= 1e-9 * x.abs() {
                ratio(x)
            } else {
                format!("{} ({})", ratio(x), ratio(y))
            }
        };
        let hl = (p.hl_avg / r.hl.avg(), p.hl_avg / r.hl.ok_avg());
        let (total_ours, total_ratio, total_per_arc) = match &r.total {
            Some(t) => {
                let x = (p.total_avg / t.avg(), p.total_avg / t.ok_avg());
                (
                    ms(t.avg()),
                    both(x.0, x.1),
                    both(x.0 * per_arc, x.1 * per_arc),
                )
            }
            None => ("n/a".into(), "n/a".into(), "n/a".into()),
        };
        println!(
            "| {} | {} / {} | {} / {} | {} / {} / {} | {} / {} / {} | {} | {} | {} | {} | {} | {} |",
            r.label,
            p.nodes,
            p.arcs,
            r.nodes,
            r.arcs,
            p.hl_avg,
            p.hl_max,
            p.hl_min,
            ms(r.hl.avg()),
            ms(r.hl.max()),
            ms(r.hl.min()),
            both(hl.0, hl.1),
            both(hl.0 * per_arc, hl.1 * per_arc),
            p.total_avg,
            total_ours,
            total_ratio,
            total_per_arc
        );
    }
    println!();
    println!("high level = Planner::plan with motions off (geometric rows: locate, search, path -> Cartesian conversion with IK and collision checks; abstract rows: search and simplification only). total = Planner::plan with motions on (adds RRT-Connect motions, shortcuts, timing) + execution in the kinematic simulator. Goals: high-level ratio >= 1000x, total ratio >= 200x.");
}

/// Milliseconds with four significant digits.
pub(crate) fn ms(seconds: f64) -> String {
    let m = seconds * 1e3;
    if m >= 100.0 {
        format!("{m:.1}")
    } else if m >= 10.0 {
        format!("{m:.2}")
    } else if m >= 1.0 {
        format!("{m:.3}")
    } else if m >= 0.1 {
        format!("{m:.4}")
    } else {
        format!("{m:.5}")
    }
}

fn ratio(x: f64) -> String {
    if x >= 100.0 {
        format!("{:.0}x", x)
    } else {
        format!("{:.1}x", x)
    }
}
