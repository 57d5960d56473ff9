//! A `cellc serve` process for the fault tests: started on a state file the test owns,
//! spoken to over plain TCP (HTTP/1.1 by hand), and stopped by SIGKILL or SIGTERM. A
//! request whose connection the process dropped (it was killed) is an answer of its own,
//! [`Answer::Dropped`], because what a client never heard back is what the tests reason
//! about.

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::path::Path;
use std::process::{Child, Command, ExitStatus, Stdio};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use serde_json::Value;

/// A running service; killed if the test fails before it is stopped.
pub struct Service {
    child: Child,
    /// `127.0.0.1:PORT`.
    pub addr: String,
    log: Arc<Mutex<String>>,
}

/// What a request got back.
#[derive(Clone, Debug, PartialEq)]
pub enum Answer {
    /// A whole answer: its status, head (lower-cased header names kept as sent) and
    /// JSON body.
    Got {
        /// The HTTP status.
        status: u16,
        /// The status line and headers.
        head: String,
        /// The body.
        body: Value,
    },
    /// The connection closed before a whole answer came (the service was killed).
    Dropped,
}

impl Answer {
    /// The status, or `None` when dropped.
    pub fn status(&self) -> Option<u16> {
        match self {
            Answer::Got { status, .. } => Some(*status),
            Answer::Dropped => None,
        }
    }

    /// The body (`Null` when dropped).
    pub fn body(&self) -> &Value {
        match self {
            Answer::Got { body, .. } => body,
            Answer::Dropped => &Value::Null,
        }
    }

    /// The value of header `name`, compared without case.
    pub fn header(&self, name: &str) -> Option<&str> {
        let Answer::Got { head, .. } = self else {
            return None;
        };
        head.lines().find_map(|l| {
            let (n, v) = l.split_once(':')?;
            n.trim().eq_ignore_ascii_case(name).then(|| v.trim())
        })
    }

    /// The first diagnostic's code, or `none`.
    pub fn code(&self) -> &str {
        self.body()["diagnostics"][0]["code"]
            .as_str()
            .unwrap_or("none")
    }
}

/// How a start ended when the service did not come up.
#[derive(Debug)]
pub struct Refused {
    /// Its exit status.
    pub status: ExitStatus,
    /// Everything it wrote on standard error.
    pub stderr: String,
}

impl Service {
    /// Starts `cellc serve cell --state state ARGS` on a free port; `setup` may change the
    /// command further (limits set in the child before it runs).
    pub fn start(
        cell: &str,
        state: &Path,
        args: &[&str],
        setup: impl FnOnce(&mut Command),
    ) -> Result<Service, Refused> {
        let mut command = Command::new(env!("CARGO_BIN_EXE_cellc"));
        command
            .args(["serve", cell, "--addr", "127.0.0.1:0", "--state"])
            .arg(state)
            .args(args)
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped());
        setup(&mut command);
        let mut child = command.spawn().expect("cellc starts");
        // Drained all along, so the service never blocks on a full pipe.
        let log = Arc::new(Mutex::new(String::new()));
        let mut stderr = child.stderr.take().expect("stderr is piped");
        let sink = log.clone();
        let drain = std::thread::spawn(move || {
            let mut buffer = [0u8; 4096];
            while let Ok(n) = stderr.read(&mut buffer) {
                if n == 0 {
                    break;
                }
                sink.lock()
                    .unwrap()
                    .push_str(&String::from_utf8_lossy(&buffer[..n]));
            }
        });
        let mut first = String::new();
        let _ = BufReader::new(child.stdout.take().expect("stdout is piped")).read_line(&mut first);
        match first.trim().strip_prefix("listening on http://") {
            Some(addr) => Ok(Service {
                child,
                addr: addr.to_string(),
                log,
            }),
            None => {
                let status = child.wait().expect("the service exits");
                let _ = drain.join();
                let stderr = log.lock().unwrap().clone();
                Err(Refused { status, stderr })
            }
        }
    }

    /// [`Service::start`] that must come up.
    pub fn up(cell: &str, state: &Path, args: &[&str]) -> Service {
        Service::start(cell, state, args, |_| {})
            .unwrap_or_else(|r| panic!("the service did not start: {r:?}"))
    }

    /// What it wrote on standard error so far.
    pub fn log(&self) -> String {
        self.log.lock().unwrap().clone()
    }

    /// Sends one request (`Name: value` headers; JSON unless a `Content-Type` is among
    /// them) and reads the whole answer.
    pub fn call(&self, method: &str, path: &str, headers: &[&str], body: &[u8]) -> Answer {
        send(&self.addr, method, path, headers, body)
    }

    /// `GET path`, which must answer 200: its body.
    pub fn get(&self, path: &str) -> Value {
        match self.call("GET", path, &[], b"") {
            Answer::Got {
                status: 200, body, ..
            } => body,
            other => panic!("GET {path}: {other:?}\n{}", self.log()),
        }
    }

    /// SIGKILL: no chance to finish anything.
    pub fn kill(mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }

    /// SIGTERM, and the exit status.
    pub fn terminate(mut self) -> ExitStatus {
        // SAFETY: the child's id is a live process this test started and has not waited.
        unsafe {
            libc::kill(self.child.id() as libc::pid_t, libc::SIGTERM);
        }
        self.child.wait().expect("the service exits")
    }
}

impl Drop for Service {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// One request to `addr`; [`Answer::Dropped`] when no whole answer came back.
pub fn send(addr: &str, method: &str, path: &str, headers: &[&str], body: &[u8]) -> Answer {
    let Ok(mut stream) = TcpStream::connect(addr) else {
        return Answer::Dropped;
    };
    stream
        .set_read_timeout(Some(Duration::from_secs(120)))
        .unwrap();
    let head = crate::http::request_head(method, path, headers, body.len());
    if stream
        .write_all(head.as_bytes())
        .and_then(|()| stream.write_all(body))
        .is_err()
    {
        return Answer::Dropped;
    }
    let mut raw = Vec::new();
    let _ = stream.read_to_end(&mut raw);
    let text = String::from_utf8_lossy(&raw);
    let Some((head, body)) = text.split_once("\r\n\r\n") else {
        return Answer::Dropped;
    };
    let Some(status) = head
        .split_whitespace()
        .nth(1)
        .and_then(|s| s.parse::<u16>().ok())
    else {
        return Answer::Dropped;
    };
    // A length the body does not reach is an answer cut by the kill.
    let length = head.lines().find_map(|l| {
        let (n, v) = l.split_once(':')?;
        n.trim()
            .eq_ignore_ascii_case("content-length")
            .then(|| v.trim().parse::<usize>().ok())
            .flatten()
    });
    if length.is_some_and(|n| n != body.len()) {
        return Answer::Dropped;
    }
    let body = serde_json::from_str(body)
        .unwrap_or_else(|e| panic!("{method} {path}: not JSON ({e}): {body}"));
    Answer::Got {
        status,
        head: head.to_string(),
        body,
    }
}

/// A request of `tests/ui/serve/**.http`: `METHOD PATH STATUS CODE`, then `Name: value`
/// header lines, then the body.
pub struct UiRequest {
    /// The method.
    pub method: String,
    /// The path.
    pub path: String,
    /// The status expected.
    pub status: u16,
    /// The code expected.
    pub code: String,
    /// Its headers, `Name: value` each.
    pub headers: Vec<String>,
    /// Its body.
    pub body: String,
}

impl UiRequest {
    /// Reads the file at `path`.
    pub fn read(path: &str) -> UiRequest {
        let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{path}: {e}"));
        let (line, rest) = text.split_once('\n').unwrap_or((&text, ""));
        let mut headers = Vec::new();
        let mut body = rest;
        while let Some((first, after)) = body.split_once('\n') {
            let is_header = first.split_once(": ").is_some_and(|(n, _)| {
                !n.is_empty() && n.bytes().all(|b| b.is_ascii_alphanumeric() || b == b'-')
            });
            if !is_header {
                break;
            }
            headers.push(first.to_string());
            body = after;
        }
        let words: Vec<&str> = line.split_whitespace().collect();
        assert_eq!(words.len(), 4, "{path}: `METHOD PATH STATUS CODE` first");
        UiRequest {
            method: words[0].to_string(),
            path: words[1].to_string(),
            status: words[2].parse().expect("a status"),
            code: words[3].to_string(),
            headers,
            body: body.to_string(),
        }
    }

    /// Sends it to `service`.
    pub fn send(&self, service: &Service) -> Answer {
        let headers: Vec<&str> = self.headers.iter().map(String::as_str).collect();
        service.call(&self.method, &self.path, &headers, self.body.as_bytes())
    }
}
