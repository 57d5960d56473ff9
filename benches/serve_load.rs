//! Load test of `cellc serve` (issue 11): the real server on the Vito cell, 8 concurrent
//! clients on loopback, each on its own keep-alive connection, sending plan requests
//! (high level, then with motions) with malformed and oversized requests mixed in, and one
//! more client that keeps opening connections and stalling mid-request. Every answer's
//! status is checked against what that request must get; the server's resident memory is
//! read from `/proc` after every 1,000 requests. Prints throughput, median and p99
//! latency per kind, and the memory series; exits non-zero on any unexpected answer.
//!
//! `cargo bench --bench serve_load` (`CELLC_LOAD_REQUESTS` sets the number of high-level
//! plans, 10,000 by default; a tenth as many are planned with motions).

use std::io::{Read, Write};
use std::net::TcpStream;
use std::process::Command;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

#[path = "support/load.rs"]
mod load;
use load::{memory, percentile, Connection};

const CLIENTS: usize = 8;

/// The plan requests sent, in turn: objects of the Vito world to places they can go from
/// where the world has them (a pick-and-place, a regrasp via the table, a drop).
const MOVES: [&str; 3] = [
    r#"{"object":"ball","to":"bin in ws_right_bin"#,
    r#"{"object":"cylinder","to":"bin in ws_right_bin"#,
    r#"{"object":"ball","to":"table at (0.3, -0.35, 0.95)"#,
];

/// Sends `total` requests from `CLIENTS` threads; latencies (ms) of the plans, and the
/// number of unexpected answers.
fn phase(
    addr: &str,
    total: usize,
    motions: bool,
    pid: u32,
    memory_log: &Mutex<Vec<(usize, u64)>>,
) -> (Vec<f64>, usize, Duration) {
    let next = Arc::new(AtomicUsize::new(0));
    let unexpected = Arc::new(AtomicUsize::new(0));
    let latencies = Arc::new(Mutex::new(Vec::with_capacity(total)));
    let start = Instant::now();
    std::thread::scope(|scope| {
        for _ in 0..CLIENTS {
            let (next, unexpected, latencies) =
                (next.clone(), unexpected.clone(), latencies.clone());
            scope.spawn(move || {
                let mut connection = Connection::new(addr);
                loop {
                    let i = next.fetch_add(1, Ordering::Relaxed);
                    if i >= total {
                        break;
                    }
                    // Mixed in: malformed JSON (400) and oversized bodies (413).
                    let (body, expected): (Vec<u8>, u16) = if i % 50 == 7 {
                        (b"{\"object\": \"ball\", \"to\": ".to_vec(), 400)
                    } else if i % 250 == 11 {
                        (vec![b' '; (1 << 20) + 16], 413)
                    } else {
                        let text = format!(
                            "{}\",\"options\":{{\"motions\":{motions}}}}}",
                            MOVES[i % MOVES.len()]
                        );
                        (text.into_bytes(), 200)
                    };
                    let t = Instant::now();
                    let status = connection.send("POST", "/v1/plan", &body);
                    let ms = t.elapsed().as_secs_f64() * 1000.0;
                    match status {
                        Ok(s) if s == expected => {
                            if expected == 200 {
                                latencies.lock().expect("not poisoned").push(ms);
                            }
                        }
                        other => {
                            unexpected.fetch_add(1, Ordering::Relaxed);
                            eprintln!("request {i}: expected {expected}, got {other:?}");
                        }
                    }
                    if (i + 1) % 1000 == 0 {
                        memory_log
                            .lock()
                            .expect("not poisoned")
                            .push((i + 1, memory(pid).0));
                    }
                }
            });
        }
    });
    let elapsed = start.elapsed();
    let mut l = Arc::try_unwrap(latencies)
        .map(|m| m.into_inner().expect("not poisoned"))
        .unwrap_or_default();
    l.sort_by(f64::total_cmp);
    (l, unexpected.load(Ordering::Relaxed), elapsed)
}

fn main() {
    let total: usize = std::env::var("CELLC_LOAD_REQUESTS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(10_000);
    let (mut server, addr) = load::start(&["--ephemeral"]);
    let pid = server.id();
    let (rss_loaded, _) = memory(pid);
    // A client that keeps stalling: half a request, then silence until the server cuts it.
    let stop = Arc::new(AtomicBool::new(false));
    let stalled = Arc::new(AtomicUsize::new(0));
    let staller = {
        let (stop, stalled, addr) = (stop.clone(), stalled.clone(), addr.clone());
        std::thread::spawn(move || {
            while !stop.load(Ordering::Relaxed) {
                let Ok(mut s) = TcpStream::connect(&addr) else {
                    break;
                };
                let _ = s.write_all(b"POST /v1/plan HTTP/1.1\r\nHost: slow\r\n");
                let _ = s.set_read_timeout(Some(Duration::from_secs(15)));
                let mut buf = [0u8; 512];
                let _ = s.read(&mut buf);
                stalled.fetch_add(1, Ordering::Relaxed);
            }
        })
    };
    let memory_log = Mutex::new(Vec::new());
    let (high, bad_high, t_high) = phase(&addr, total, false, pid, &memory_log);
    let with = (total / 10).max(1);
    let (motion, bad_motion, t_motion) = phase(&addr, with, true, pid, &memory_log);
    stop.store(true, Ordering::Relaxed);
    let (rss_end, hwm) = memory(pid);
    let _ = Command::new("kill")
        .args(["-TERM", &pid.to_string()])
        .status();
    let exit = server.wait().expect("the server ends");
    let _ = staller.join();
    let report = |name: &str, l: &[f64], n: usize, t: Duration| {
        println!(
            "{name}: {n} requests in {:.2} s = {:.0} requests/s; plans: median {:.2} ms, p99 {:.2} ms, max {:.2} ms",
            t.as_secs_f64(),
            n as f64 / t.as_secs_f64(),
            percentile(l, 0.5),
            percentile(l, 0.99),
            l.last().copied().unwrap_or(f64::NAN)
        );
    };
    report("high level", &high, total, t_high);
    report("with motions", &motion, with, t_motion);
    println!(
        "stalled connections cut by the server: {}",
        stalled.load(Ordering::Relaxed)
    );
    let log = memory_log.into_inner().expect("not poisoned");
    let series: Vec<String> = log
        .iter()
        .map(|(n, kib)| format!("{n}: {} MiB", kib / 1024))
        .collect();
    println!(
        "server resident memory: {} MiB loaded; after requests {}; at the end {} MiB; peak {} MiB",
        rss_loaded / 1024,
        series.join(", "),
        rss_end / 1024,
        hwm / 1024
    );
    println!("server exit: {exit}");
    let bad = bad_high + bad_motion;
    println!("unexpected answers: {bad}");
    if bad > 0 || !exit.success() {
        std::process::exit(1);
    }
}
