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

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::process::{Command, Stdio};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

const CLIENTS: usize = 8;

/// The plan requests sent, in turn: objects of the Vito world to places they can go from
/// where the world has them (a pick-and-place, a regrasp via the table, a drop).
const MOVES: [&str; 3] = [
    r#"{"object":"ball","to":"bin in ws_right_bin"#,
    r#"{"object":"cylinder","to":"bin in ws_right_bin"#,
    r#"{"object":"ball","to":"table at (0.3, -0.35, 0.95)"#,
];

struct Connection {
    addr: String,
    stream: Option<BufReader<TcpStream>>,
}

impl Connection {
    fn new(addr: &str) -> Connection {
        Connection {
            addr: addr.to_string(),
            stream: None,
        }
    }

    /// Sends one request and reads its answer: the status. The connection is opened again
    /// when the server closed it (after an error answer, for instance).
    fn send(&mut self, method: &str, path: &str, body: &[u8]) -> std::io::Result<u16> {
        for attempt in 0..2 {
            if self.stream.is_none() {
                self.stream = Some(BufReader::new(TcpStream::connect(&self.addr)?));
            }
            let result = self.exchange(method, path, body);
            match result {
                Ok(status) => return Ok(status),
                Err(_) if attempt == 0 => self.stream = None,
                Err(e) => return Err(e),
            }
        }
        unreachable!("two attempts")
    }

    fn exchange(&mut self, method: &str, path: &str, body: &[u8]) -> std::io::Result<u16> {
        let reader = self.stream.as_mut().expect("connected");
        let head = format!(
            "{method} {path} HTTP/1.1\r\nHost: load\r\nContent-Type: application/json\r\nContent-Length: {}\r\n\r\n",
            body.len()
        );
        let stream = reader.get_mut();
        stream.write_all(head.as_bytes())?;
        stream.write_all(body)?;
        let mut line = String::new();
        reader.read_line(&mut line)?;
        let status: u16 = line
            .split_whitespace()
            .nth(1)
            .and_then(|s| s.parse().ok())
            .ok_or_else(|| std::io::Error::other(format!("no status line: {line:?}")))?;
        let mut length = 0usize;
        let mut close = false;
        loop {
            let mut header = String::new();
            reader.read_line(&mut header)?;
            let h = header.trim_end();
            if h.is_empty() {
                break;
            }
            let lower = h.to_ascii_lowercase();
            if let Some(v) = lower.strip_prefix("content-length:") {
                length = v.trim().parse().unwrap_or(0);
            }
            if lower == "connection: close" {
                close = true;
            }
        }
        let mut sink = vec![0u8; length];
        reader.read_exact(&mut sink)?;
        if close {
            self.stream = None;
        }
        Ok(status)
    }
}

/// Resident and peak resident memory of `pid`, KiB.
fn memory(pid: u32) -> (u64, u64) {
    let status = std::fs::read_to_string(format!("/proc/{pid}/status")).unwrap_or_default();
    let field = |name: &str| {
        status
            .lines()
            .find(|l| l.starts_with(name))
            .and_then(|l| l.split_whitespace().nth(1))
            .and_then(|v| v.parse().ok())
            .unwrap_or(0)
    };
    (field("VmRSS:"), field("VmHWM:"))
}

fn percentile(sorted: &[f64], p: f64) -> f64 {
    if sorted.is_empty() {
        return f64::NAN;
    }
    sorted[((sorted.len() - 1) as f64 * p).round() as usize]
}

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
    let mut server = Command::new(env!("CARGO_BIN_EXE_cellc"))
        .args([
            "serve",
            "cells/vito.cell",
            "--addr",
            "127.0.0.1:0",
            "--ephemeral",
        ])
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("cellc serve starts");
    let pid = server.id();
    let mut first = String::new();
    BufReader::new(server.stdout.take().expect("stdout"))
        .read_line(&mut first)
        .expect("the listening line");
    let addr = first
        .trim()
        .strip_prefix("listening on http://")
        .expect("listening on http://ADDR")
        .to_string();
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
