//! `cellc serve` end to end: the real binary on a free port, spoken to over plain TCP
//! (HTTP/1.1 by hand, so the test needs no HTTP client). One server per cell for the
//! whole test, since loading and verifying Vito is the slow part; the requests under
//! `tests/ui/serve/` (one per service code) are sent as they are written.

use std::collections::BTreeSet;
use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::process::{Child, Command, Stdio};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use serde_json::{json, Value};

#[path = "support/http.rs"]
mod http;

/// A running server; killed if the test fails before it is shut down.
struct Server {
    child: Child,
    /// The folder of its state file, removed with the server.
    _state: tempfile::TempDir,
    addr: String,
    log: Arc<Mutex<String>>,
    /// The server's own OpenAPI document, every answer is validated against.
    openapi: Value,
    /// The (method, path, status) of every answer validated.
    validated: Mutex<BTreeSet<(String, String, u16)>>,
}

impl Server {
    fn start(cell: &str) -> Server {
        let state = tempfile::tempdir().expect("a temporary folder");
        let mut child = Command::new(env!("CARGO_BIN_EXE_cellc"))
            .args(["serve", cell, "--addr", "127.0.0.1:0", "--state"])
            .arg(state.path().join("state.sqlite"))
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("cellc starts");
        let mut first = String::new();
        BufReader::new(child.stdout.take().expect("stdout is piped"))
            .read_line(&mut first)
            .expect("a first line");
        let addr = first
            .trim()
            .strip_prefix("listening on http://")
            .unwrap_or_else(|| panic!("not a listening line: {first:?}"))
            .to_string();
        // Drained all along, so the server never blocks on a full pipe.
        let log = Arc::new(Mutex::new(String::new()));
        let mut stderr = child.stderr.take().expect("stderr is piped");
        let sink = log.clone();
        std::thread::spawn(move || {
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
        let mut server = Server {
            child,
            _state: state,
            addr,
            log,
            openapi: Value::Null,
            validated: Mutex::new(BTreeSet::new()),
        };
        let (status, openapi) = server.call("GET", "/v1/openapi.json", b"");
        assert_eq!(status, 200, "{openapi}");
        server.openapi = openapi;
        server.check("GET", "/v1/openapi.json", status, &server.openapi);
        server
    }

    /// Validates an answer against the schema the server's OpenAPI document gives for
    /// its endpoint and status: an undocumented status, or a body that does not fit its
    /// schema, fails the test. A path no endpoint has answers with a report.
    fn check(&self, method: &str, target: &str, status: u16, body: &Value) {
        if self.openapi.is_null() {
            return;
        }
        let path = self.template(target.split('?').next().unwrap_or(target));
        let path = path.as_str();
        let endpoint = &self.openapi["paths"][path];
        let report = json!({"$ref": "#/components/schemas/Report"});
        let name = if endpoint.is_object() {
            let answer = &endpoint[method.to_ascii_lowercase()]["responses"][status.to_string()];
            match &answer["content"]["application/json"]["schema"] {
                Value::Null if status == 405 => report,
                Value::Null => panic!("{method} {path} answered {status}, which the OpenAPI document does not list: {body}"),
                schema => schema.clone(),
            }
        } else {
            // No endpoint has the path (S0003, 404), or not with this method (405).
            assert!(status == 404 || status == 405, "{method} {path}: {status}");
            report
        };
        let problems = self.problems(&name, body);
        assert!(
            problems.is_empty(),
            "{method} {path} {status}: the answer does not fit {name}: {problems:?}\n{body}"
        );
        self.validated
            .lock()
            .unwrap()
            .insert((method.to_string(), path.to_string(), status));
    }

    /// The OpenAPI path `path` is an instance of (`/v1/executions/4` is
    /// `/v1/executions/{id}`), or `path` itself.
    fn template(&self, path: &str) -> String {
        let Some(paths) = self.openapi["paths"].as_object() else {
            return path.to_string();
        };
        if paths.contains_key(path) {
            return path.to_string();
        }
        let segments: Vec<&str> = path.split('/').collect();
        paths
            .keys()
            .find(|t| {
                let ts: Vec<&str> = t.split('/').collect();
                ts.len() == segments.len()
                    && ts.iter().zip(&segments).all(|(t, s)| {
                        (t.starts_with('{') && t.ends_with('}') && !s.is_empty()) || t == s
                    })
            })
            .cloned()
            .unwrap_or_else(|| path.to_string())
    }

    /// What is wrong with `body` as the OpenAPI document's schema `name` describes it.
    fn problems(&self, name: &Value, body: &Value) -> Vec<String> {
        let schema = json!({
            "$schema": "https://json-schema.org/draft/2020-12/schema",
            "allOf": [name],
            "components": self.openapi["components"],
        });
        let validator = jsonschema::validator_for(&schema)
            .unwrap_or_else(|e| panic!("the OpenAPI document's schema {name} is not valid: {e}"));
        validator
            .iter_errors(body)
            .map(|e| format!("{e} at {}", e.instance_path()))
            .collect()
    }

    /// Whether a request's JSON body fits the schema the OpenAPI document gives for the
    /// endpoint's body (`None`: the endpoint takes none, or the body is not JSON).
    fn request_fits(&self, method: &str, target: &str, body: &[u8]) -> Option<bool> {
        let path = target.split('?').next().unwrap_or(target);
        let operation = &self.openapi["paths"][path][method.to_ascii_lowercase()];
        let name = &operation["requestBody"]["content"]["application/json"]["schema"];
        let body: Value = serde_json::from_slice(body).ok()?;
        (!name.is_null()).then(|| self.problems(name, &body).is_empty())
    }

    /// Sends one request and reads the whole answer: (status, JSON body).
    fn call(&self, method: &str, path: &str, body: &[u8]) -> (u16, Value) {
        let (status, _, answer) = self.call_with(method, path, &[], body);
        (status, answer)
    }

    /// [`Server::call`] with headers (`Name: value` each; a `Content-Type` among them
    /// replaces the JSON one), answering the head too.
    fn call_with(
        &self,
        method: &str,
        path: &str,
        headers: &[&str],
        body: &[u8],
    ) -> (u16, String, Value) {
        let mut stream = TcpStream::connect(&self.addr).expect("connects");
        stream
            .set_read_timeout(Some(Duration::from_secs(120)))
            .unwrap();
        let head = http::request_head(method, path, headers, body.len());
        // A body over the limit is refused before it is all read: writing may fail.
        let _ = stream
            .write_all(head.as_bytes())
            .and_then(|()| stream.write_all(body));
        let (status, head, answer) = read_answer_head(&mut stream);
        self.check(method, path, status, &answer);
        // A request the service carried out was one its OpenAPI document describes.
        if status == 200 && !self.openapi.is_null() {
            assert_ne!(
                self.request_fits(method, path, body),
                Some(false),
                "{method} {path} was answered 200, but its body does not fit the document's request schema"
            );
        }
        (status, head, answer)
    }

    fn json(&self, method: &str, path: &str, body: Value) -> (u16, Value) {
        self.call(method, path, body.to_string().as_bytes())
    }

    /// SIGTERM, and the exit status.
    fn terminate(mut self) -> std::process::ExitStatus {
        // SAFETY: the child's id is a live process this test started.
        unsafe {
            libc::kill(self.child.id() as libc::pid_t, libc::SIGTERM);
        }
        self.child.wait().expect("the server exits")
    }
}

impl Server {
    /// Fails unless every endpoint's answers were validated: a success of each, and a
    /// failure of each endpoint that takes a body.
    fn assert_every_endpoint_validated(&self) {
        let validated = self.validated.lock().unwrap();
        for (path, methods) in self.openapi["paths"].as_object().unwrap() {
            for method in methods.as_object().unwrap().keys() {
                let method = method.to_ascii_uppercase();
                let seen = |ok: bool| {
                    validated
                        .iter()
                        .any(|(m, p, s)| *m == method && p == path && (*s == 200) == ok)
                };
                assert!(seen(true), "no success of {method} {path} was validated");
                if method != "GET" {
                    assert!(seen(false), "no failure of {method} {path} was validated");
                }
            }
        }
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn read_answer(stream: &mut TcpStream) -> (u16, Value) {
    let (status, _, body) = read_answer_head(stream);
    (status, body)
}

/// The value of header `name` (lower case) in an answer's head.
fn header<'h>(head: &'h str, name: &str) -> Option<&'h str> {
    head.lines().find_map(|l| {
        let (n, v) = l.split_once(':')?;
        (n.trim().eq_ignore_ascii_case(name)).then(|| v.trim())
    })
}

fn read_answer_head(stream: &mut TcpStream) -> (u16, String, Value) {
    let mut raw = Vec::new();
    let _ = stream.read_to_end(&mut raw);
    let text = String::from_utf8_lossy(&raw);
    let (head, body) = text
        .split_once("\r\n\r\n")
        .unwrap_or_else(|| panic!("no answer: {text:?}"));
    let status: u16 = head
        .split_whitespace()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(|| panic!("no status: {head:?}"));
    assert!(
        head.to_ascii_lowercase()
            .contains("content-type: application/json"),
        "{head}"
    );
    let body = serde_json::from_str(body).unwrap_or_else(|e| panic!("not JSON ({e}): {body}"));
    (status, head.to_string(), body)
}

fn first_code(report: &Value) -> &str {
    report["diagnostics"][0]["code"].as_str().unwrap_or("none")
}

/// Where the world has `object`: its state's end-effector.
fn holder_of(world: &Value, object: &str) -> String {
    world["objects"]
        .as_array()
        .unwrap()
        .iter()
        .find(|o| o["object"] == object)
        .map(|o| o["state"]["end_effector"].to_string())
        .unwrap_or_default()
}

/// The requests of `tests/ui/serve/` (not its `faults/` folder): `METHOD PATH STATUS CODE [repeat=N | stall | prime]`,
/// then `Name: value` header lines, then the body (with `prime`, two bodies split by a
/// `---` line: the first sets the scene, the second is checked).
fn ui_requests(server: &Server) {
    let mut files: Vec<_> = std::fs::read_dir("tests/ui/serve")
        .unwrap()
        .filter_map(Result::ok)
        .map(|e| e.path())
        // `faults/` holds the requests that need a fault set up first
        // (tests/serve_faults.rs sends them).
        .filter(|p| p.is_file())
        .collect();
    files.sort();
    let mut stalled = Vec::new();
    for path in files {
        let text = std::fs::read_to_string(&path).unwrap();
        let (line, rest) = text.split_once('\n').unwrap_or((&text, ""));
        // `Name: value` lines after the request line are headers; the body follows.
        let mut headers: Vec<&str> = Vec::new();
        let mut body = rest;
        while let Some((first, after)) = body.split_once('\n') {
            let is_header = first.split_once(": ").is_some_and(|(n, _)| {
                !n.is_empty() && n.bytes().all(|b| b.is_ascii_alphanumeric() || b == b'-')
            });
            if !is_header {
                break;
            }
            headers.push(first);
            body = after;
        }
        let words: Vec<&str> = line.split_whitespace().collect();
        let (method, target, status, code) = (words[0], words[1], words[2], words[3]);
        let status: u16 = status.parse().unwrap();
        let name = path.display().to_string();
        match words.get(4).copied() {
            Some("stall") => {
                // Headers promising more body than is ever sent.
                let addr = server.addr.clone();
                let (body, target, method) =
                    (body.to_string(), target.to_string(), method.to_string());
                let (code, name) = (code.to_string(), name.clone());
                stalled.push(std::thread::spawn(move || {
                    let mut stream = TcpStream::connect(addr).unwrap();
                    stream
                        .set_read_timeout(Some(Duration::from_secs(60)))
                        .unwrap();
                    let head = format!(
                        "{method} {target} HTTP/1.1\r\nHost: test\r\nContent-Length: 1000\r\n\r\n{body}"
                    );
                    stream.write_all(head.as_bytes()).unwrap();
                    let (got, report) = read_answer(&mut stream);
                    assert_eq!((got, first_code(&report)), (status, code.as_str()), "{name}");
                    (method, target, got, report)
                }));
            }
            Some(claim) if claim.starts_with("declare=") || claim.starts_with("expect=") => {
                // Headers declaring a body over the limit, and none of it sent: the answer
                // must come at once (well before the 10 s body timeout), and a client
                // that asked `Expect: 100-continue` must not be told to go on.
                let (word, length) = claim.split_once('=').unwrap();
                let expect = if word == "expect" {
                    "Expect: 100-continue\r\n"
                } else {
                    ""
                };
                let mut stream = TcpStream::connect(&server.addr).unwrap();
                stream
                    .set_read_timeout(Some(Duration::from_secs(5)))
                    .unwrap();
                let head = format!(
                    "{method} {target} HTTP/1.1\r\nHost: test\r\nContent-Length: {length}\r\n{expect}Connection: close\r\n\r\n"
                );
                stream.write_all(head.as_bytes()).unwrap();
                let (got, report) = read_answer(&mut stream);
                server.check(method, target, got, &report);
                assert_eq!((got, first_code(&report)), (status, code), "{name}");
            }
            Some(repeat) if repeat.starts_with("repeat=") => {
                let n: usize = repeat["repeat=".len()..].parse().unwrap();
                let (got, report) = server.call(method, target, body.repeat(n).as_bytes());
                assert_eq!((got, first_code(&report)), (status, code), "{name}");
            }
            _ if method == "WORKER" => {
                // A worker that panics (no request makes one on purpose).
                let runtime = tokio::runtime::Runtime::new().unwrap();
                let failed = runtime
                    .block_on(async { tokio::task::spawn_blocking(|| panic!("a bug")).await })
                    .expect_err("the task panicked");
                let answer = cellc::commands::serve::worker_failed(&failed);
                let report = serde_json::to_value(&answer.report).unwrap();
                let got = answer.failure.status().as_u16();
                server.check("GET", "/v1/health", got, &report);
                assert_eq!((got, first_code(&report)), (status, code), "{name}");
            }
            Some("prime") => {
                // The first body is sent to set the scene (its answer is not checked); the
                // second is the request under test. Both with the file's headers.
                let (first, second) = body.split_once("\n---\n").expect("two bodies");
                server.call_with(method, target, &headers, first.as_bytes());
                let (got, _, report) =
                    server.call_with(method, target, &headers, second.as_bytes());
                assert_eq!(
                    (got, first_code(&report)),
                    (status, code),
                    "{name}: {report}"
                );
            }
            _ => {
                let (got, _, report) = server.call_with(method, target, &headers, body.as_bytes());
                assert_eq!(
                    (got, first_code(&report)),
                    (status, code),
                    "{name}: {report}"
                );
            }
        }
    }
    // A client that never finishes its headers is disconnected.
    let mut slow = TcpStream::connect(&server.addr).unwrap();
    slow.set_read_timeout(Some(Duration::from_secs(60)))
        .unwrap();
    slow.write_all(b"GET /v1/hea").unwrap();
    let mut rest = Vec::new();
    assert_eq!(
        slow.read_to_end(&mut rest).map(|_| rest.len()).ok(),
        Some(0)
    );
    for t in stalled {
        let (method, target, got, report) = t.join().unwrap();
        server.check(&method, &target, got, &report);
    }
}

#[test]
fn the_service_on_vito() {
    let server = Server::start("cells/vito.cell");

    let (status, health) = server.call("GET", "/v1/health", b"");
    assert_eq!((status, &health["status"]), (200, &json!("ok")));

    let (status, cell) = server.call("GET", "/v1/cell", b"");
    assert_eq!(status, 200);
    let ball = cell["objects"]
        .as_array()
        .unwrap()
        .iter()
        .find(|o| o["name"] == "ball")
        .expect("the ball");
    assert!(!ball["grasps"].as_array().unwrap().is_empty(), "{ball}");
    assert!(
        !ball["resting_poses"].as_array().unwrap().is_empty(),
        "{ball}"
    );
    let arm = &cell["arms"][0];
    assert_eq!(arm["joints"].as_array().unwrap().len(), 7, "{arm}");
    assert!(arm["joints"][0]["upper"].is_number(), "{arm}");
    assert!(cell["workspaces"][0]["boxes"].is_array());
    assert!(cell["end_effectors"][0]["movable"].is_boolean());

    let (status, openapi) = server.call("GET", "/v1/openapi.json", b"");
    assert_eq!((status, &openapi["openapi"]), (200, &json!("3.1.0")));
    for path in [
        "/v1/health",
        "/v1/cell",
        "/v1/world",
        "/v1/plan",
        "/v1/plan/follow_joint_trajectory",
        "/v1/execute",
        "/v1/tasks",
        "/v1/explain",
        "/v1/openapi.json",
    ] {
        assert!(openapi["paths"][path].is_object(), "{path}");
    }

    let (status, world) = server.call("GET", "/v1/world", b"");
    assert_eq!(status, 200);
    assert_eq!(holder_of(&world, "ball"), "\"table\"");

    // A plan leaves the world as it is.
    let trash =
        json!({"object": "ball", "to": "bin in ws_right_bin", "options": {"motions": false}});
    let (status, planned) = server.json("POST", "/v1/plan", trash.clone());
    assert_eq!((status, &planned["ok"]), (200, &json!(true)), "{planned}");
    assert_eq!(planned["kind"], "plan");
    assert_eq!(
        planned["plans"][0]["holders"],
        json!(["table", "right", "bin"])
    );
    // The plan `cellc plan --format json` writes for the same move (nothing is in the
    // ball's way, so the world's other objects change nothing).
    let cli = Command::new(env!("CARGO_BIN_EXE_cellc"))
        .args(["plan", "cells/vito.cell", "--object", "ball", "--from"])
        .args([
            "table at (0.45, -0.25, 0.95)",
            "--to",
            "bin in ws_right_bin",
        ])
        .args(["--no-motions", "--format", "json"])
        .output()
        .expect("cellc plan runs");
    let mut cli: Value = serde_json::from_slice(&cli.stdout).expect("plan JSON");
    let mut served = planned["plans"][0].clone();
    for plan in [&mut cli["plans"][0], &mut served] {
        plan.as_object_mut().unwrap().remove("request");
    }
    assert_eq!(cli["plans"][0], served);
    assert_eq!(
        holder_of(&server.call("GET", "/v1/world", b"").1, "ball"),
        "\"table\""
    );

    // Failures: a did-you-mean, a goal taken, an absent object.
    let (status, report) = server.json(
        "POST",
        "/v1/plan",
        json!({"object": "bal", "to": "bin in ws_right_bin"}),
    );
    assert_eq!((status, first_code(&report)), (422, "R0003"), "{report}");
    assert!(report["diagnostics"][0]["help"]
        .as_str()
        .unwrap()
        .contains("did you mean `ball`"));
    let (status, report) = server.json(
        "POST",
        "/v1/plan",
        json!({"object": "cylinder", "to": "table at (0.4, 0.05, 1.0)", "options": {"motions": false}}),
    );
    assert_eq!((status, first_code(&report)), (409, "R0010"), "{report}");
    assert_eq!(report["ok"], false);
    assert!(report["diagnostics"][0]["help"]
        .as_str()
        .unwrap()
        .contains(r#"`"clear": true`"#));
    let (status, report) = server.json(
        "POST",
        "/v1/plan",
        json!({"object": "ball", "to": "bin in ws_right_bin", "options": {"time_budget_ms": 0}}),
    );
    assert_eq!((status, first_code(&report)), (503, "R0006"), "{report}");
    controller_goals(&server);

    // Plans run side by side, all answered.
    let shared = Arc::new(server);
    let threads: Vec<_> = (0..6)
        .map(|i| {
            let server = shared.clone();
            let trash = trash.clone();
            std::thread::spawn(move || {
                let mut body = trash;
                body["options"]["seed"] = json!(i);
                let (status, planned) = server.json("POST", "/v1/plan", body);
                assert_eq!((status, &planned["ok"]), (200, &json!(true)), "{planned}");
            })
        })
        .collect();
    for t in threads {
        t.join().unwrap();
    }
    let server = Arc::try_unwrap(shared).ok().expect("threads are done");

    // An execution moves the ball into the bin, and the world says so.
    let (status, run) = server.json("POST", "/v1/execute", trash);
    assert_eq!((status, &run["ok"]), (200, &json!(true)), "{run}");
    assert_eq!(run["moves"][0]["done"], true);
    let (_, world) = server.call("GET", "/v1/world", b"");
    assert_eq!(holder_of(&world, "ball"), "\"bin\"");

    // An execution that fails leaves the world as it was: nothing moved.
    let before = server.call("GET", "/v1/world", b"").1;
    let (status, run) = server.json(
        "POST",
        "/v1/execute",
        json!({"object": "cylinder", "to": "table at (0.4, 0.05, 1.0)", "options": {"motions": false}}),
    );
    assert_eq!((status, first_code(&run)), (409, "R0010"), "{run}");
    assert_eq!(run["world"], before);
    assert_eq!(server.call("GET", "/v1/world", b"").1, before);

    // A task: the cylinder to the bin, from where the world has it.
    let (status, run) = server.json(
        "POST",
        "/v1/tasks",
        json!({"moves": [{"object": "cylinder", "to": "bin in ws_right_bin"}], "options": {"motions": false}}),
    );
    assert_eq!((status, &run["ok"]), (200, &json!(true)), "{run}");
    assert_eq!(
        holder_of(&server.call("GET", "/v1/world", b"").1, "cylinder"),
        "\"bin\""
    );

    // A reachable request explained is its plan.
    let (status, explained) = server.json(
        "POST",
        "/v1/explain",
        json!({"object": "pitcher", "to": "table at (0.4, -0.3, 1.01)", "options": {"motions": false}}),
    );
    assert_eq!(
        (status, &explained["reachable"]),
        (200, &json!(true)),
        "{explained}"
    );

    // World documents: a good one replaces the world, bad ones are refused and change
    // nothing.
    let (status, world) = server.json(
        "PUT",
        "/v1/world",
        json!({"objects": {"ball": {"holder": "table", "at": [0.45, -0.25, 0.95]}}}),
    );
    assert_eq!(status, 200, "{world}");
    assert_eq!(holder_of(&world, "ball"), "\"table\"");
    assert_eq!(holder_of(&world, "cylinder"), "null");
    let (status, report) = server.json(
        "PUT",
        "/v1/world",
        json!({"objects": {"ball": {"holder": "table", "pos": [0.45, -0.25, 0.95]}}}),
    );
    assert_eq!((status, first_code(&report)), (400, "R0008"), "{report}");
    // The request schema is the one the service reads with: the misspelt key and a word
    // other than "absent" are outside it, the documents it takes are inside.
    for (document, fits) in [
        (
            r#"{"objects": {"ball": {"holder": "table", "pos": [0, 0, 1]}}}"#,
            false,
        ),
        (r#"{"objects": {"ball": "gone"}}"#, false),
        (
            r#"{"objects": {"ball": "absent"}, "arms": {"left": {"a1": 0.5}}}"#,
            true,
        ),
        (
            r#"{"objects": {"ball": {"holder": "left", "grasp": "top"}}}"#,
            true,
        ),
    ] {
        assert_eq!(
            server.request_fits("PUT", "/v1/world", document.as_bytes()),
            Some(fits),
            "{document}"
        );
    }
    let (status, report) = server.json(
        "PUT",
        "/v1/world",
        json!({"arms": {"left": {"lwr_a9_joint": 0.0}}}),
    );
    assert_eq!((status, first_code(&report)), (422, "R0009"), "{report}");
    assert_eq!(
        holder_of(&server.call("GET", "/v1/world", b"").1, "ball"),
        "\"table\""
    );

    // Revisions: the world carries its store and revision, and its ETag says both.
    let (status, head, world) = server.call_with("GET", "/v1/world", &[], b"");
    assert_eq!(status, 200);
    let etag = header(&head, "etag").expect("an ETag").to_string();
    let revision = world["revision"].as_u64().expect("a revision");
    let instance = world["instance"].as_str().expect("an instance").to_string();
    assert_eq!(etag, format!("\"{instance}-{revision}\""));
    let (_, health) = server.call("GET", "/v1/health", b"");
    assert_eq!(
        (&health["revision"], &health["instance"]),
        (&json!(revision), &json!(instance))
    );
    // A merge patch under If-Match moves the ball and produces the next revision.
    let if_match = format!("If-Match: {etag}");
    let (status, head, patched) = server.call_with(
        "PATCH",
        "/v1/world",
        &[&if_match, "Content-Type: application/merge-patch+json"],
        br#"{"objects": {"ball": {"holder": "table", "at": [0.45, -0.2, 0.95]}}}"#,
    );
    assert_eq!(status, 200, "{patched}");
    assert_eq!(patched["revision"], json!(revision + 1));
    let ball_y = |w: &Value| {
        w["objects"]
            .as_array()
            .unwrap()
            .iter()
            .find(|o| o["object"] == "ball")
            .unwrap()["pose"]["position"][1]
            .clone()
    };
    assert_eq!(ball_y(&patched), json!(-0.2));
    let fresh = header(&head, "etag").expect("an ETag").to_string();
    assert_ne!(fresh, etag);
    // The old ETag is refused, by PUT and by PATCH, and nothing changes.
    let (status, _, report) =
        server.call_with("PUT", "/v1/world", &[&if_match], br#"{"objects": {}}"#);
    assert_eq!((status, first_code(&report)), (412, "S0006"), "{report}");
    let (status, _, report) = server.call_with(
        "PATCH",
        "/v1/world",
        &[&if_match],
        br#"{"objects": {"ball": "absent"}}"#,
    );
    assert_eq!((status, first_code(&report)), (412, "S0006"), "{report}");
    let (_, now) = server.call("GET", "/v1/world", b"");
    assert_eq!(
        (now["revision"].clone(), ball_y(&now)),
        (json!(revision + 1), json!(-0.2))
    );
    // JSON Patch operations, without a precondition: serialised, the answer says which
    // revision they produced.
    let (status, _, patched) = server.call_with(
        "PATCH",
        "/v1/world",
        &["Content-Type: application/json-patch+json"],
        br#"[{"op": "replace", "path": "/objects/ball/at", "value": [0.45, -0.25, 0.95]}]"#,
    );
    assert_eq!(
        (status, &patched["revision"]),
        (200, &json!(revision + 2)),
        "{patched}"
    );
    assert_eq!(ball_y(&patched), json!(-0.25));
    // A patch whose result does not fit the cell is refused like a PUT of it.
    let (status, _, report) = server.call_with(
        "PATCH",
        "/v1/world",
        &["Content-Type: application/json-patch+json"],
        br#"[{"op": "add", "path": "/arms/left", "value": {"lwr_a9_joint": 0.0}}]"#,
    );
    assert_eq!((status, first_code(&report)), (422, "R0009"), "{report}");
    // An execute against an old revision is refused; against the current one it runs and
    // answers with the revision it produced and its journal entry.
    let stale = json!({"object": "ball", "to": "bin in ws_right_bin", "options": {"motions": false}, "revision": revision});
    let (status, report) = server.json("POST", "/v1/execute", stale);
    assert_eq!((status, first_code(&report)), (412, "S0006"), "{report}");
    let key = "Idempotency-Key: 6f1c2a52-ball-to-bin";
    let go = json!({"object": "ball", "to": "bin in ws_right_bin", "options": {"motions": false}, "revision": revision + 2});
    let (status, head, run) =
        server.call_with("POST", "/v1/execute", &[key], go.to_string().as_bytes());
    assert_eq!((status, &run["ok"]), (200, &json!(true)), "{run}");
    let produced = run["world"]["revision"]
        .as_u64()
        .expect("the revision it produced");
    assert!(produced > revision + 2, "{produced}");
    assert_eq!(
        header(&head, "etag"),
        Some(format!("\"{instance}-{produced}\"").as_str())
    );
    let execution = run["execution"].as_u64().expect("a journal entry");
    // The same request under the same key is the first answer again: nothing moves.
    let (status, head, again) =
        server.call_with("POST", "/v1/execute", &[key], go.to_string().as_bytes());
    assert_eq!(status, 200);
    assert_eq!(header(&head, "idempotent-replayed"), Some("true"));
    assert_eq!(again, run);
    assert_eq!(
        server.call("GET", "/v1/world", b"").1["revision"],
        json!(produced)
    );
    // The key with another request is refused.
    let other = json!({"object": "pitcher", "to": "bin in ws_right_bin"});
    let (status, _, report) =
        server.call_with("POST", "/v1/execute", &[key], other.to_string().as_bytes());
    assert_eq!((status, first_code(&report)), (422, "S0008"), "{report}");
    // The journal has it, step by step, each step a revision of the world.
    let (status, listed) = server.call("GET", "/v1/executions?limit=5", b"");
    assert_eq!(status, 200);
    assert_eq!(listed["executions"][0]["id"], json!(execution), "{listed}");
    assert_eq!(listed["executions"][0]["status"], json!("succeeded"));
    let (status, one) = server.call("GET", &format!("/v1/executions/{execution}"), b"");
    assert_eq!(status, 200, "{one}");
    let steps = one["steps"].as_array().unwrap();
    assert_eq!(
        steps.len(),
        run["moves"][0]["plans"][0]["steps"]
            .as_array()
            .unwrap()
            .len()
    );
    let revisions: Vec<u64> = steps
        .iter()
        .map(|s| s["revision"].as_u64().unwrap())
        .collect();
    assert!(
        revisions.windows(2).all(|w| w[1] == w[0] + 1),
        "{revisions:?}"
    );
    assert!(*revisions.last().unwrap() <= produced);
    assert_eq!(steps[0]["report"]["object"], json!("ball"));
    assert_eq!(one["outcome"]["body"], run);
    let (status, report) = server.call("GET", "/v1/executions?limit=0", b"");
    assert_eq!((status, first_code(&report)), (400, "S0001"), "{report}");

    ui_requests(&server);

    let log = server.log.lock().unwrap().clone();
    assert!(
        log.lines().any(|l| l.contains(r#""method":"POST""#)
            && l.contains(r#""path":"/v1/execute""#)
            && l.contains(r#""status":200"#)
            && l.contains(r#""ms":"#)),
        "{log}"
    );
    // A name the cell lacks: a report, before any explanation.
    let unknown = json!({"object": "bal", "to": "bin in ws_right_bin"});
    let (status, report) = server.json("POST", "/v1/explain", unknown);
    assert_eq!((status, first_code(&report)), (422, "R0003"), "{report}");
    // Advice names the request's own option, not the command line's flag.
    let hurried = json!({"object": "ball", "to": "bin in ws_right_bin",
        "options": {"time_budget_ms": 0, "motions": false}});
    let (status, planned) = server.json("POST", "/v1/plan", hurried);
    assert_eq!((status, first_code(&planned)), (503, "R0006"), "{planned}");
    let help = planned["diagnostics"][0]["help"].as_str().unwrap();
    assert!(
        help.contains("`time_budget_ms`") && !help.contains("--"),
        "{help}"
    );
    let (status, report) = server.json(
        "POST",
        "/v1/tasks",
        json!({"moves": [{"object": "bal", "to": "bin in ws_right_bin"}]}),
    );
    assert_eq!((status, first_code(&report)), (422, "R0003"), "{report}");
    server.assert_every_endpoint_validated();
    assert!(server.terminate().success());
}

/// `POST /v1/plan/follow_joint_trajectory` against `POST /v1/plan` of the same body: one
/// goal per arm per step that moves, the arm's joint names, its columns of every point,
/// times to the nanosecond and 4 ms apart at 250 Hz; a rate whose points would be too many
/// is R0012 (400) in the plan document; a name the cell lacks is the report alone.
fn controller_goals(server: &Server) {
    let body = json!({"object": "ball", "to": "bin in ws_right_bin", "options": {"rate": 250}});
    let (status, planned) = server.json("POST", "/v1/plan", body.clone());
    assert_eq!(status, 200, "{planned}");
    let (status, goals) = server.json("POST", "/v1/plan/follow_joint_trajectory", body);
    assert_eq!(status, 200, "{goals}");
    let plan = &planned["plans"][0];
    let goals = goals["plans"][0]["goals"].as_array().expect("goals");
    let mut expected = Vec::new();
    for (i, step) in plan["steps"].as_array().unwrap().iter().enumerate() {
        for arm in step["motion"]["arms"].as_array().into_iter().flatten() {
            expected.push((i, arm["arm"].clone(), arm["joints"].clone()));
        }
    }
    let found: Vec<_> = goals
        .iter()
        .map(|g| {
            let step = g["step"].as_u64().unwrap() as usize;
            (
                step,
                g["arm"].clone(),
                g["goal"]["trajectory"]["joint_names"].clone(),
            )
        })
        .collect();
    assert!(!expected.is_empty());
    assert_eq!(found, expected);
    for goal in goals {
        let motion = &plan["steps"][goal["step"].as_u64().unwrap() as usize]["motion"];
        // Vito's motions move one arm each: its columns are all of them.
        assert_eq!(motion["arms"].as_array().unwrap().len(), 1);
        let points = goal["goal"]["trajectory"]["points"].as_array().unwrap();
        let planned = motion["points"].as_array().unwrap();
        assert_eq!(points.len(), planned.len());
        let mut times = Vec::new();
        for (p, q) in points.iter().zip(planned) {
            for field in ["positions", "velocities", "accelerations"] {
                assert_eq!(p[field], q[field]);
            }
            let (sec, nanosec) = (
                p["time_from_start"]["sec"].as_i64().unwrap(),
                p["time_from_start"]["nanosec"].as_i64().unwrap(),
            );
            assert!((0..1_000_000_000).contains(&nanosec), "{p}");
            let nanos = sec * 1_000_000_000 + nanosec;
            let seconds = q["time_from_start"].as_f64().unwrap();
            assert!(
                (nanos as f64 - seconds * 1e9).abs() <= 1.0,
                "{nanos} {seconds}"
            );
            times.push(nanos);
        }
        let gaps: Vec<i64> = times.windows(2).map(|w| w[1] - w[0]).collect();
        let (last, before) = gaps.split_last().unwrap();
        assert!(before.iter().all(|&g| g == 4_000_000), "{gaps:?}");
        assert!((1..=4_000_000).contains(last), "{gaps:?}");
    }
    let (status, planned) = server.json(
        "POST",
        "/v1/plan",
        json!({"object": "ball", "to": "bin in ws_right_bin",
            "options": {"rate": 1000, "velocity_scaling": 0.001, "acceleration_scaling": 0.001}}),
    );
    assert_eq!((status, first_code(&planned)), (400, "R0012"), "{planned}");
    assert_eq!(planned["ok"], false);
    let help = planned["diagnostics"][0]["message"].as_str().unwrap();
    assert!(help.contains("`rate`") && !help.contains("--"), "{help}");
    let (status, report) = server.json(
        "POST",
        "/v1/plan/follow_joint_trajectory",
        json!({"object": "bal", "to": "bin in ws_right_bin"}),
    );
    assert_eq!((status, first_code(&report)), (422, "R0003"), "{report}");
}

#[test]
fn unreachable_requests_are_explained() {
    let server = Server::start("tests/ui/plan/R0004_no_way_across.cell");
    let across =
        json!({"object": "cylinder", "from": "table.standing in w1", "to": "table.standing in w2"});
    let (status, report) = server.json("POST", "/v1/plan", across.clone());
    assert_eq!((status, first_code(&report)), (422, "R0004"), "{report}");
    let (status, explained) = server.json("POST", "/v1/explain", across);
    assert_eq!(status, 200, "{explained}");
    assert_eq!(explained["reachable"], false);
    let explanation = &explained["explanation"];
    assert_eq!(explanation["object"], "cylinder");
    assert!(
        !explanation["cut"].as_array().unwrap().is_empty(),
        "{explanation}"
    );
    assert_eq!(first_code(&explained["diagnostic"]), "R0004");
    assert!(server.terminate().success());
}
