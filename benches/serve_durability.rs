//! The cost of durability (issue 33): `cellc serve cells/vito.cell` with its world in
//! memory (`--ephemeral`), in a state file with `--durability normal` (SQLite's
//! `synchronous=NORMAL`: a crash of the process loses nothing) and with
//! `--durability full` (the default: every commit waits for the disk). Each
//! configuration runs the same three phases, and the configurations are interleaved in
//! rounds so that the machine's load changes them alike:
//!
//! - **execute**: one client executing moves one after another, the ball into the bin
//!   and back onto the table (`"motions": false`): each execute is journaled before it
//!   starts, after each of its four steps and when it ends (six commits);
//! - **put**: one client replacing the world with a world document (one commit each);
//! - **mixed**: three clients planning (`POST /v1/plan`, no write) while a fourth
//!   executes, as a task planner and an executive share a cell. A plan sees the world as
//!   the execute's last journaled step left it, so some are answered 422 (the hand that
//!   would carry the cylinder holds the ball); those count as answered plans too.
//!
//! Prints, per configuration, the median over rounds of each phase's throughput, median
//! and p99 latency. The state file is in the system's temporary folder (`TMPDIR`): put it
//! on the disk a cell would use. `CELLC_DURABILITY_ROUNDS` (default 3) and
//! `CELLC_DURABILITY_EXECUTES` (default 100 per phase) size the run.
//!
//! `cargo bench --bench serve_durability`

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Mutex;
use std::time::Instant;

#[path = "support/load.rs"]
mod load;
use load::{percentile, Connection};

/// The two executes a client alternates: there and back again, so every one moves.
const THERE_AND_BACK: [&str; 2] = [
    r#"{"object":"ball","to":"bin in ws_right_bin","options":{"motions":false}}"#,
    r#"{"object":"ball","to":"table at (0.45, -0.25, 0.95)","options":{"motions":false}}"#,
];

/// What the put phase sends: the cell's world as a document.
const WORLD: &str = r#"{"objects": {"ball": {"holder": "table", "at": [0.45, -0.25, 0.95]}, "cylinder": {"holder": "table", "at": [0.45, 0.45, 1.0]}, "pitcher": {"holder": "table", "at": [0.4, 0.05, 1.01]}}}"#;

/// A plan that writes nothing.
const PLAN: &str =
    r#"{"object":"cylinder","to":"bin in ws_right_bin","options":{"motions":false}}"#;

/// One phase's result.
#[derive(Clone, Copy, Debug)]
struct Measured {
    per_second: f64,
    median_ms: f64,
    p99_ms: f64,
}

fn measured(mut latencies: Vec<f64>, seconds: f64) -> Measured {
    latencies.sort_by(f64::total_cmp);
    Measured {
        per_second: latencies.len() as f64 / seconds,
        median_ms: percentile(&latencies, 0.5),
        p99_ms: percentile(&latencies, 0.99),
    }
}

/// Sends `n` requests one after another; their latencies (ms). Every answer must be 200.
fn sequential(addr: &str, path: &str, method: &str, bodies: &[&str], n: usize) -> Vec<f64> {
    let mut connection = Connection::new(addr);
    (0..n)
        .map(|i| {
            let body = bodies[i % bodies.len()].as_bytes();
            let t = Instant::now();
            let status = connection.send(method, path, body).expect("answered");
            assert_eq!(status, 200, "{method} {path} {}", bodies[i % bodies.len()]);
            t.elapsed().as_secs_f64() * 1000.0
        })
        .collect()
}

/// One configuration, once: (execute, put, mixed plans, mixed executes).
fn run(extra: &[&str], executes: usize) -> [Measured; 4] {
    let (mut server, addr) = load::start(extra);
    let t = Instant::now();
    let exec = sequential(&addr, "/v1/execute", "POST", &THERE_AND_BACK, executes);
    let exec = measured(exec, t.elapsed().as_secs_f64());
    let t = Instant::now();
    let put = sequential(&addr, "/v1/world", "PUT", &[WORLD], executes * 3);
    let put = measured(put, t.elapsed().as_secs_f64());
    let stop = AtomicBool::new(false);
    let plans = Mutex::new(Vec::new());
    let t = Instant::now();
    let mixed_exec = std::thread::scope(|scope| {
        for _ in 0..3 {
            scope.spawn(|| {
                let mut connection = Connection::new(&addr);
                let mut mine = Vec::new();
                while !stop.load(Ordering::Relaxed) {
                    let t = Instant::now();
                    let status = connection
                        .send("POST", "/v1/plan", PLAN.as_bytes())
                        .expect("answered");
                    // 422 while the execute's right hand holds the ball: plans see the
                    // world as its last journaled step left it.
                    assert!(status == 200 || status == 422, "plan: {status}");
                    mine.push(t.elapsed().as_secs_f64() * 1000.0);
                }
                plans.lock().expect("not poisoned").extend(mine);
            });
        }
        let done = sequential(&addr, "/v1/execute", "POST", &THERE_AND_BACK, executes);
        stop.store(true, Ordering::Relaxed);
        done
    });
    let seconds = t.elapsed().as_secs_f64();
    let mixed_plans = measured(plans.into_inner().expect("not poisoned"), seconds);
    let mixed_exec = measured(mixed_exec, seconds);
    let (_, peak) = load::memory(server.id());
    eprintln!("server peak resident memory: {} MiB", peak / 1024);
    let _ = std::process::Command::new("kill")
        .args(["-TERM", &server.id().to_string()])
        .status();
    let exit = server.wait().expect("the server ends");
    assert!(exit.success(), "the server exits 0 on SIGTERM: {exit}");
    [exec, put, mixed_plans, mixed_exec]
}

fn median(values: &mut [f64]) -> f64 {
    values.sort_by(f64::total_cmp);
    values[values.len() / 2]
}

fn main() {
    let rounds: usize = std::env::var("CELLC_DURABILITY_ROUNDS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(3);
    let executes: usize = std::env::var("CELLC_DURABILITY_EXECUTES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(100);
    let folder = tempfile::tempdir().expect("a temporary folder");
    let normal = folder.path().join("normal.state.sqlite");
    let full = folder.path().join("full.state.sqlite");
    let (normal, full) = (normal.to_string_lossy(), full.to_string_lossy());
    let configurations: [(&str, Vec<&str>); 3] = [
        ("memory (--ephemeral)", vec!["--ephemeral"]),
        (
            "file, --durability normal",
            vec!["--state", &normal, "--durability", "normal"],
        ),
        (
            "file, --durability full",
            vec!["--state", &full, "--durability", "full"],
        ),
    ];
    let mut results: Vec<Vec<[Measured; 4]>> = vec![Vec::new(); configurations.len()];
    for round in 0..rounds {
        for (i, (name, extra)) in configurations.iter().enumerate() {
            let r = run(extra, executes);
            eprintln!("round {}: {name}: {r:?}", round + 1);
            results[i].push(r);
        }
    }
    println!("medians over {rounds} rounds ({executes} executes per phase):");
    let phases = [
        "execute (1 client)",
        "put (1 client)",
        "mixed: plans (3 clients)",
        "mixed: executes (1 client)",
    ];
    for (i, (name, _)) in configurations.iter().enumerate() {
        println!("{name}:");
        for (p, phase) in phases.iter().enumerate() {
            let pick = |f: fn(&Measured) -> f64| {
                let mut v: Vec<f64> = results[i].iter().map(|r| f(&r[p])).collect();
                median(&mut v)
            };
            println!(
                "  {phase}: {:.0} requests/s, median {:.2} ms, p99 {:.2} ms",
                pick(|m| m.per_second),
                pick(|m| m.median_ms),
                pick(|m| m.p99_ms)
            );
        }
    }
}
