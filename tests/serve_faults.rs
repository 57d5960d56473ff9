//! `cellc serve` under faults (issue 33, point 6): killed with SIGKILL at random points of
//! a task, raced by concurrent writers, restarted on a torn write-ahead log, and given a
//! state file that cannot be written at start-up or at write time. Every check is exact:
//! after each fault the world is the last acknowledged one, or the one the journal says
//! the interrupted execution's last stored step left, and nothing else.
//!
//! The tests take a lock so they run one at a time: the kill delays are measured against
//! the task's duration, which would stretch if the tests shared the cores.
//!
//! `cargo test --release --test serve_faults` (about 3 minutes on 2 cores).

#[path = "support/http.rs"]
mod http;
#[path = "support/service.rs"]
mod service;

use std::collections::BTreeMap;
use std::sync::Mutex;
use std::time::{Duration, Instant};

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde_json::{json, Value};
use service::{Answer, Service, UiRequest};

const CELL: &str = "cells/vito.cell";

/// The tests run one at a time.
static SERIAL: Mutex<()> = Mutex::new(());

fn serial() -> std::sync::MutexGuard<'static, ()> {
    SERIAL.lock().unwrap_or_else(|e| e.into_inner())
}

/// The world as a document `PUT /v1/world` takes, from the world `GET /v1/world` gives:
/// what a client that senses the cell would send back to confirm it. Objects in a hand
/// are given by their grasp (the arm's joints place them).
fn document_of(world: &Value) -> Value {
    let arms: Vec<&str> = world["arms"]
        .as_array()
        .unwrap()
        .iter()
        .map(|a| a["arm"].as_str().unwrap())
        .collect();
    let mut objects = serde_json::Map::new();
    for o in world["objects"].as_array().unwrap() {
        let name = o["object"].as_str().unwrap().to_string();
        let state = &o["state"];
        if state.is_null() {
            objects.insert(name, json!("absent"));
            continue;
        }
        let holder = state["end_effector"].as_str().unwrap();
        let mut placement =
            json!({"holder": holder, "grasp": state["grasp"], "workspace": state["workspace"]});
        if !arms.contains(&holder) {
            let r = &o["pose"]["rotation"];
            placement["at"] = o["pose"]["position"].clone();
            placement["quat"] = json!([r[3], r[0], r[1], r[2]]);
        }
        objects.insert(name, placement);
    }
    let mut joints = serde_json::Map::new();
    for a in world["arms"].as_array().unwrap() {
        let named: serde_json::Map<String, Value> = a["joints"]
            .as_array()
            .unwrap()
            .iter()
            .zip(a["positions"].as_array().unwrap())
            .map(|(j, p)| (j.as_str().unwrap().to_string(), p.clone()))
            .collect();
        joints.insert(a["arm"].as_str().unwrap().to_string(), Value::Object(named));
    }
    json!({"objects": objects, "arms": joints})
}

/// Where everything is: a world answer's objects and arms, without its revision.
fn place(world: &Value) -> Value {
    json!({"objects": world["objects"], "arms": world["arms"]})
}

/// What a world answer says is uncertain (the field is left out when nothing is).
fn uncertain(world: &Value) -> Value {
    match &world["uncertain"] {
        Value::Null => json!([]),
        u => u.clone(),
    }
}

fn revision(world: &Value) -> u64 {
    world["revision"]
        .as_u64()
        .unwrap_or_else(|| panic!("no revision: {world}"))
}

fn etag_header(world: &Value) -> String {
    format!(
        "If-Match: \"{}-{}\"",
        world["instance"].as_str().unwrap(),
        revision(world)
    )
}

/// PUTs `document` under `If-Match` of `current`: it must be taken, as the next revision.
fn confirm(service: &Service, current: &Value, document: &Value) -> Value {
    let answer = service.call(
        "PUT",
        "/v1/world",
        &[&etag_header(current)],
        document.to_string().as_bytes(),
    );
    assert_eq!(answer.status(), Some(200), "{answer:?}\n{}", service.log());
    let world = answer.body().clone();
    assert_eq!(revision(&world), revision(current) + 1, "{world}");
    assert_eq!(uncertain(&world), json!([]), "a PUT confirms everything");
    world
}

/// The world where vito starts: ball and cylinder on the table.
fn on_the_table() -> Value {
    json!({"objects": {
        "ball": {"holder": "table", "at": [0.45, -0.25, 0.95]},
        "cylinder": {"holder": "table", "at": [0.45, 0.45, 1.0]},
        "pitcher": {"holder": "table", "at": [0.4, 0.05, 1.01]},
        "colander": "absent"
    }})
}

/// The two tasks the kill test alternates: each moves both objects, the second back.
fn task(to_bin: bool) -> Value {
    if to_bin {
        json!({"moves": [{"object": "ball", "to": "bin in ws_right_bin"},
                         {"object": "cylinder", "to": "bin in ws_right_bin"}]})
    } else {
        json!({"moves": [{"object": "ball", "to": "table at (0.45, -0.25, 0.95)"},
                         {"object": "cylinder", "to": "table at (0.45, 0.45, 1.0)"}]})
    }
}

/// A task run without faults, watched step by step: the world after every step, by the
/// number of steps done (0: the world it started from), the journal's step reports, and
/// what it took.
struct Trace {
    start_doc: Value,
    worlds: Vec<Value>,
    finished: Value,
    reports: Vec<Value>,
    seconds: f64,
}

/// Runs `task` from `start_doc` on `service` (at `--sim-pace pace`), reading the world
/// as fast as it can meanwhile so that every step's world is seen. `None` when a step
/// went by unseen (the machine was too busy): the caller slows the pace.
fn trace(service: &Service, start_doc: &Value, task: &Value) -> Option<Trace> {
    let current = service.get("/v1/world");
    let start = confirm(service, &current, start_doc);
    let base = revision(&start);
    let addr = service.addr.clone();
    let body = task.to_string();
    let began = Instant::now();
    let run =
        std::thread::spawn(move || service::send(&addr, "POST", "/v1/tasks", &[], body.as_bytes()));
    let mut seen: BTreeMap<u64, Value> = BTreeMap::new();
    seen.insert(base, place(&start));
    while !run.is_finished() {
        let w = service.get("/v1/world");
        seen.entry(revision(&w)).or_insert_with(|| place(&w));
    }
    let seconds = began.elapsed().as_secs_f64();
    let answer = run.join().unwrap();
    assert_eq!(
        answer.status(),
        Some(200),
        "the task without faults: {answer:?}"
    );
    let finished = answer.body()["world"].clone();
    let id = answer.body()["execution"]
        .as_u64()
        .expect("an execution id");
    let record = service.get(&format!("/v1/executions/{id}"));
    let steps = record["steps"].as_array().unwrap();
    let mut worlds = vec![place(&start)];
    for (i, s) in steps.iter().enumerate() {
        assert_eq!(s["revision"].as_u64(), Some(base + i as u64 + 1), "{s}");
        worlds.push(seen.get(&(base + i as u64 + 1))?.clone());
    }
    assert!(steps.len() > 4, "a task of two moves has steps: {record}");
    Some(Trace {
        start_doc: start_doc.clone(),
        worlds,
        finished,
        reports: steps.iter().map(|s| s["report"].clone()).collect(),
        seconds,
    })
}

/// The reference traces of both tasks, on a service of their own.
fn traces() -> [Trace; 2] {
    let mut pace: f64 = 0.2;
    loop {
        let dir = tempfile::tempdir().unwrap();
        let reference = Service::up(
            CELL,
            &dir.path().join("reference.sqlite"),
            &["--sim-pace", &pace.to_string()],
        );
        if let Some(to_bin) = trace(&reference, &on_the_table(), &task(true)) {
            let back_doc = document_of(&to_bin.finished);
            if let Some(back) = trace(&reference, &back_doc, &task(false)) {
                return [to_bin, back].map(|mut t| {
                    t.seconds /= pace;
                    t
                });
            }
        }
        pace *= 2.0;
        assert!(
            pace < 2.0,
            "the world after every step could not be read even at a slow pace"
        );
    }
}

/// One round of the kill test, as seen by the client.
struct Round {
    delay_ms: u64,
    outcome: String,
}

impl std::fmt::Debug for Round {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} ms: {}", self.delay_ms, self.outcome)
    }
}

#[test]
fn sigkill_at_random_points_of_a_task_loses_nothing_acknowledged() {
    let _serial = serial();
    const ROUNDS: usize = 50;
    const PACE: f64 = 0.05;
    // Another seed to try: `CELLC_FAULT_SEED=N`.
    let seed: u64 = std::env::var("CELLC_FAULT_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(0x5eed_0033);
    let traces = traces();
    let dir = tempfile::tempdir().unwrap();
    let state = dir.path().join("state.sqlite");
    let pace = PACE.to_string();
    let args = ["--sim-pace", pace.as_str()];
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut rounds: Vec<Round> = Vec::new();
    let mut instance: Option<String> = None;
    let mut last_revision = 0;
    let report = |rounds: &Vec<Round>| {
        format!("seed {seed:#x}, rounds so far (kill delay, outcome): {rounds:?}")
    };
    for i in 0..ROUNDS {
        let to_bin = i % 2 == 0;
        let reference = &traces[usize::from(!to_bin)];
        let service = Service::up(CELL, &state, &args);
        let now = service.get("/v1/world");
        let id = now["instance"].as_str().unwrap().to_string();
        assert_eq!(
            instance.get_or_insert(id.clone()),
            &id,
            "the instance changed: {}",
            report(&rounds)
        );
        assert!(
            revision(&now) >= last_revision,
            "the revision went back: {}",
            report(&rounds)
        );
        // Confirms the world (and makes it the task's start): the sensing client found
        // the objects where the task starts from.
        let start = confirm(&service, &now, &reference.start_doc);
        assert_eq!(
            place(&start),
            reference.worlds[0],
            "round {i}: the start world differs from the reference's: {}",
            report(&rounds)
        );
        let base = revision(&start);
        let key = format!("Idempotency-Key: faults-round-{i}");
        let expected = reference.seconds * PACE;
        // Mostly during the task, some after it ended, a few before it can have begun.
        let delay_ms = if rng.random_bool(0.1) {
            rng.random_range(0..20)
        } else {
            rng.random_range(0..=((expected * 1400.0) as u64).max(1))
        };
        let addr = service.addr.clone();
        let body = task(to_bin).to_string();
        let sent_key = key.clone();
        let run = std::thread::spawn(move || {
            service::send(&addr, "POST", "/v1/tasks", &[&sent_key], body.as_bytes())
        });
        std::thread::sleep(Duration::from_millis(delay_ms));
        service.kill();
        let answer = run.join().unwrap();

        let service = Service::up(CELL, &state, &args);
        let health = service.get("/v1/health");
        let world = service.get("/v1/world");
        let context = || {
            format!(
                "round {i} ({}): {}\nworld {world}\nhealth {health}\n{}",
                if to_bin { "to the bin" } else { "back" },
                report(&rounds),
                service.log()
            )
        };
        assert_eq!(
            health["instance"].as_str(),
            Some(id.as_str()),
            "{}",
            context()
        );
        assert_eq!(health["revision"], world["revision"], "{}", context());
        let listed = service.get("/v1/executions?limit=3");
        let ours = listed["executions"]
            .as_array()
            .unwrap()
            .iter()
            .find(|e| e["key"] == format!("faults-round-{i}"))
            .cloned();
        let outcome = match (&answer, ours) {
            (
                Answer::Got {
                    status: 200, body, ..
                },
                Some(execution),
            ) => {
                // Acknowledged: the world is the answer's, and a retry replays it.
                assert_eq!(execution["status"], "succeeded", "{}", context());
                assert_eq!(place(&world), place(&body["world"]), "{}", context());
                assert_eq!(place(&world), place(&reference.finished), "{}", context());
                assert_eq!(revision(&world), revision(&body["world"]), "{}", context());
                assert_eq!(health["interrupted"], json!([]), "{}", context());
                let again = service.call(
                    "POST",
                    "/v1/tasks",
                    &[&key],
                    task(to_bin).to_string().as_bytes(),
                );
                assert_eq!(
                    (again.status(), again.header("idempotent-replayed")),
                    (Some(200), Some("true")),
                    "{}",
                    context()
                );
                assert_eq!(again.body(), body, "{}", context());
                "answered".to_string()
            }
            (Answer::Got { .. }, _) => {
                panic!("an answer that is not a success: {answer:?}\n{}", context())
            }
            (Answer::Dropped, None) => {
                // Killed before the execution was journaled: nothing happened.
                assert_eq!(place(&world), reference.worlds[0], "{}", context());
                assert_eq!(revision(&world), base, "{}", context());
                assert_eq!(health["interrupted"], json!([]), "{}", context());
                "before it began".to_string()
            }
            (Answer::Dropped, Some(execution)) if execution["status"] == "succeeded" => {
                // Stored, but killed before the answer went out: the world is the stored
                // outcome's, and the key gives that outcome.
                let record = service.get(&format!("/v1/executions/{}", execution["id"]));
                let stored = &record["outcome"]["body"];
                assert_eq!(place(&world), place(&stored["world"]), "{}", context());
                assert_eq!(place(&world), place(&reference.finished), "{}", context());
                assert_eq!(
                    revision(&world),
                    execution["result"].as_u64().unwrap(),
                    "{}",
                    context()
                );
                assert_eq!(health["interrupted"], json!([]), "{}", context());
                let again = service.call(
                    "POST",
                    "/v1/tasks",
                    &[&key],
                    task(to_bin).to_string().as_bytes(),
                );
                assert_eq!(
                    (again.status(), again.header("idempotent-replayed")),
                    (Some(200), Some("true")),
                    "{}",
                    context()
                );
                assert_eq!(again.body(), stored, "{}", context());
                "done, unanswered".to_string()
            }
            (Answer::Dropped, Some(execution)) => {
                // In flight: exactly this execution is interrupted, for exactly its
                // objects and the cell's arms, and the world is the one its last stored
                // step left.
                assert_eq!(execution["status"], "interrupted", "{}", context());
                let number = execution["id"].as_u64().unwrap();
                let k = execution["steps_done"].as_u64().unwrap();
                assert!((k as usize) < reference.worlds.len(), "{}", context());
                let interrupted = json!([{"execution": number, "steps_done": k,
                    "objects": ["ball", "cylinder"], "arms": ["left", "right"]}]);
                assert_eq!(health["interrupted"], interrupted, "{}", context());
                assert_eq!(uncertain(&world), interrupted, "{}", context());
                assert_eq!(execution["base"].as_u64(), Some(base), "{}", context());
                assert_eq!(
                    execution["result"].as_u64(),
                    Some(base + k),
                    "{}",
                    context()
                );
                // Recovery writes the uncertainty as one more revision.
                assert_eq!(revision(&world), base + k + 1, "{}", context());
                assert_eq!(place(&world), reference.worlds[k as usize], "{}", context());
                let record = service.get(&format!("/v1/executions/{number}"));
                let steps = record["steps"].as_array().unwrap();
                assert_eq!(steps.len() as u64, k, "{}", context());
                for (j, s) in steps.iter().enumerate() {
                    assert_eq!(
                        s["revision"].as_u64(),
                        Some(base + j as u64 + 1),
                        "{}",
                        context()
                    );
                    assert_eq!(
                        s["report"],
                        reference.reports[j],
                        "step {} differs from the reference's: {}",
                        j + 1,
                        context()
                    );
                }
                // Nothing is planned from it, and its key is not carried out again.
                let refused = service.call(
                    "POST",
                    "/v1/plan",
                    &[],
                    json!({"object": "pitcher", "to": "bin in ws_right_bin"})
                        .to_string()
                        .as_bytes(),
                );
                assert_eq!(
                    (refused.status(), refused.code()),
                    (Some(409), "S0007"),
                    "{refused:?}\n{}",
                    context()
                );
                let again = service.call(
                    "POST",
                    "/v1/tasks",
                    &[&key],
                    task(to_bin).to_string().as_bytes(),
                );
                assert_eq!(
                    (again.status(), again.code()),
                    (Some(409), "S0012"),
                    "{again:?}\n{}",
                    context()
                );
                format!("interrupted after {k} steps")
            }
        };
        last_revision = revision(&service.get("/v1/world"));
        rounds.push(Round { delay_ms, outcome });
        service.kill();
    }
    let interrupted = rounds
        .iter()
        .filter(|r| r.outcome.starts_with("interrupted"))
        .count();
    eprintln!("seed {seed:#x}: {rounds:?}");
    assert!(
        interrupted >= ROUNDS / 4,
        "too few kills landed during a task ({interrupted}): {}",
        report(&rounds)
    );
}

/// What one writer of the race test got: its request and answer, in its own order.
#[derive(Debug)]
struct Written {
    what: String,
    /// The revision `If-Match` named, for a conditional PUT.
    expected: Option<u64>,
    answer: Answer,
}

/// Whether an execution's answer planned no step at all (every object was already there).
fn moved_nothing(answer: &Answer) -> bool {
    let body = answer.body();
    body["kind"] == "run"
        && body["moves"].as_array().unwrap().iter().all(|m| {
            m["plans"]
                .as_array()
                .unwrap()
                .iter()
                .all(|p| p["steps"] == json!([]))
        })
}

/// The revision a 200 answer produced: a PUT's world, an execution's world.
fn produced(answer: &Answer) -> Option<(u64, Value)> {
    if answer.status() != Some(200) {
        return None;
    }
    let body = answer.body();
    let world = if body["kind"] == "run" {
        &body["world"]
    } else {
        body
    };
    Some((revision(world), place(world)))
}

#[test]
fn concurrent_executes_and_puts_lose_no_acknowledged_write() {
    let _serial = serial();
    let dir = tempfile::tempdir().unwrap();
    let service = Service::up(CELL, &dir.path().join("state.sqlite"), &[]);
    let addr = service.addr.clone();
    let start = service.get("/v1/world");
    let instance = start["instance"].as_str().unwrap().to_string();
    let mut writers = Vec::new();
    // Executes, each thread moving its own object there and back, some under a key.
    for (object, home) in [
        ("ball", "table at (0.45, -0.25, 0.95)"),
        ("cylinder", "table at (0.45, 0.45, 1.0)"),
    ] {
        let addr = addr.clone();
        writers.push(std::thread::spawn(move || {
            let mut written = Vec::new();
            for n in 0..6 {
                let to = if n % 2 == 0 {
                    "bin in ws_right_bin"
                } else {
                    home
                };
                let body = json!({"object": object, "to": to, "options": {"motions": false}});
                let key = format!("Idempotency-Key: race-{object}-{n}");
                let headers: Vec<&str> = if n % 3 == 0 {
                    vec![]
                } else {
                    vec![key.as_str()]
                };
                let answer = service::send(
                    &addr,
                    "POST",
                    "/v1/execute",
                    &headers,
                    body.to_string().as_bytes(),
                );
                written.push(Written {
                    what: format!("execute {body} {headers:?}"),
                    expected: None,
                    answer,
                });
            }
            written
        }));
    }
    // PUTs of the world just read, half of them conditional on it.
    for conditional in [true, false] {
        let addr = addr.clone();
        writers.push(std::thread::spawn(move || {
            let mut written = Vec::new();
            for n in 0..12 {
                let Answer::Got { body: read, .. } =
                    service::send(&addr, "GET", "/v1/world", &[], b"")
                else {
                    panic!("GET /v1/world was dropped");
                };
                std::thread::sleep(Duration::from_millis(5 * (n % 3)));
                let tag = etag_header(&read);
                let headers: Vec<&str> = if conditional {
                    vec![tag.as_str()]
                } else {
                    vec![]
                };
                let answer = service::send(
                    &addr,
                    "PUT",
                    "/v1/world",
                    &headers,
                    document_of(&read).to_string().as_bytes(),
                );
                written.push(Written {
                    what: format!("PUT {headers:?}"),
                    expected: conditional.then(|| revision(&read)),
                    answer,
                });
            }
            written
        }));
    }
    // The same keyed request twice at once: carried out once, answered twice alike.
    let twice: Vec<_> = (0..2)
        .map(|_| {
            let addr = addr.clone();
            std::thread::spawn(move || {
                let body = json!({"object": "pitcher", "to": "table at (0.4, 0.1, 1.01)", "options": {"motions": false}});
                service::send(&addr, "POST", "/v1/execute", &["Idempotency-Key: race-twice"], body.to_string().as_bytes())
            })
        })
        .collect();
    let by_writer: Vec<Vec<Written>> = writers.into_iter().map(|w| w.join().unwrap()).collect();
    let twice: Vec<Answer> = twice.into_iter().map(|t| t.join().unwrap()).collect();
    let log = service.log();

    let mut acknowledged: BTreeMap<u64, Value> = BTreeMap::new();
    let mut noops = Vec::new();
    let mut count = 0;
    for written in &by_writer {
        let mut last = 0;
        for w in written {
            let status = w
                .answer
                .status()
                .unwrap_or_else(|| panic!("{}: dropped\n{log}", w.what));
            assert!(status < 500, "{}: {:?}\n{log}", w.what, w.answer);
            if let Some((r, world)) = produced(&w.answer) {
                if moved_nothing(&w.answer) {
                    // An object already where it was asked to go: nothing is written,
                    // the answer names the world's revision as it was.
                    assert!(r >= last, "{}: revision {r} after {last}", w.what);
                    noops.push((r, world));
                    continue;
                }
                // Each writer's own writes come out in the order it sent them.
                assert!(r > last, "{}: revision {r} after {last}", w.what);
                last = r;
                count += 1;
                if let Some(before) = acknowledged.insert(r, world.clone()) {
                    panic!(
                        "two answers produced revision {r}: {} ({:?}) and before {before}",
                        w.what, w.answer
                    );
                }
                if let Some(expected) = w.expected {
                    assert_eq!(
                        r,
                        expected + 1,
                        "{}: a conditional PUT writes the revision after the one it names",
                        w.what
                    );
                }
            }
            if status == 412 {
                // Only a stale precondition is refused, and it says the world moved on.
                let expected = w
                    .expected
                    .unwrap_or_else(|| panic!("{}: 412 without a precondition", w.what));
                let message = w.answer.body()["diagnostics"][0]["message"]
                    .as_str()
                    .unwrap();
                let at: u64 = message
                    .strip_prefix("the world is at revision ")
                    .and_then(|m| m.split(',').next())
                    .and_then(|m| m.split_whitespace().next())
                    .and_then(|m| m.parse().ok())
                    .unwrap_or_else(|| panic!("{message}"));
                assert!(
                    at > expected,
                    "{}: refused at {at}, expecting {expected}",
                    w.what
                );
                assert_eq!(w.answer.code(), "S0006");
            }
        }
    }
    assert!(count >= 12, "too few writes got through: {by_writer:?}");
    for (r, world) in &noops {
        if let Some(acked) = acknowledged.get(r) {
            assert_eq!(
                acked, world,
                "an execution that moved nothing answered another world at {r}"
            );
        }
    }
    let conditional_refused = by_writer[2]
        .iter()
        .filter(|w| w.answer.status() == Some(412))
        .count();
    eprintln!("{count} writes acknowledged, {conditional_refused} conditional PUTs refused");
    // No acknowledged write is lost: the world is the latest acknowledged one.
    let end = service.get("/v1/world");
    let (&latest, latest_world) = acknowledged.iter().next_back().unwrap();
    assert_eq!(
        (revision(&end), place(&end)),
        (latest, latest_world.clone()),
        "{acknowledged:?}"
    );
    assert_eq!(end["instance"].as_str(), Some(instance.as_str()));
    // The doubled request: one execution, the same answer twice.
    assert_eq!(twice[0].status(), twice[1].status(), "{twice:?}");
    assert_eq!(twice[0].body(), twice[1].body());
    let replayed: Vec<_> = twice
        .iter()
        .filter_map(|a| a.header("idempotent-replayed"))
        .collect();
    assert_eq!(replayed, ["true"], "{twice:?}");
    // A key sent again gives its first answer, whatever the world is now.
    for written in &by_writer[..2] {
        for w in written.iter().filter(|w| w.what.contains("race-")) {
            let (body, key) = w
                .what
                .strip_prefix("execute ")
                .unwrap()
                .split_once(" [\"")
                .unwrap();
            let key = key.trim_end_matches("\"]");
            let again = service.call("POST", "/v1/execute", &[key], body.as_bytes());
            assert_eq!(again.status(), w.answer.status(), "{}", w.what);
            assert_eq!(
                again.header("idempotent-replayed"),
                Some("true"),
                "{}",
                w.what
            );
            assert_eq!(again.body(), w.answer.body(), "{}", w.what);
        }
    }
    // And a restart finds the same.
    assert!(service.terminate().success());
    let service = Service::up(CELL, &dir.path().join("state.sqlite"), &[]);
    let after = service.get("/v1/world");
    assert_eq!(
        (revision(&after), place(&after)),
        (latest, latest_world.clone())
    );
}

/// A start that must be a coded refusal: exit 1, S0011 on standard error, no panic.
fn assert_refused(refused: &service::Refused, words: &str) {
    assert_eq!(refused.status.code(), Some(1), "{refused:?}");
    assert!(refused.stderr.contains("S0011"), "{}", refused.stderr);
    assert!(refused.stderr.contains(words), "{}", refused.stderr);
    assert!(!refused.stderr.contains("panicked"), "{}", refused.stderr);
}

#[test]
fn a_torn_write_ahead_log_opens_to_an_acknowledged_world_or_is_refused() {
    let _serial = serial();
    let dir = tempfile::tempdir().unwrap();
    let state = dir.path().join("state.sqlite");
    let service = Service::up(CELL, &state, &[]);
    let mut acknowledged: BTreeMap<u64, Value> = BTreeMap::new();
    let first = service.get("/v1/world");
    acknowledged.insert(revision(&first), place(&first));
    for (n, x) in [0.45, 0.44, 0.43, 0.42, 0.41, 0.40].iter().enumerate() {
        let mut document = on_the_table();
        document["objects"]["ball"]["at"] = json!([x, -0.25 + 0.01 * n as f64, 0.95]);
        let answer = service.call("PUT", "/v1/world", &[], document.to_string().as_bytes());
        assert_eq!(answer.status(), Some(200), "{answer:?}");
        acknowledged.insert(revision(answer.body()), place(answer.body()));
    }
    // A PATCH too: a smaller write of its own.
    let answer = service.call(
        "PATCH",
        "/v1/world",
        &["Content-Type: application/merge-patch+json"],
        json!({"objects": {"pitcher": {"holder": "table", "at": [0.4, 0.1, 1.01]}}})
            .to_string()
            .as_bytes(),
    );
    assert_eq!(answer.status(), Some(200), "{answer:?}");
    acknowledged.insert(revision(answer.body()), place(answer.body()));
    // Killed, so nothing is checkpointed: the writes are in the write-ahead log.
    service.kill();
    let wal = std::fs::read(dir.path().join("state.sqlite-wal")).expect("a write-ahead log");
    let database = std::fs::read(&state).unwrap();
    assert!(wal.len() > 32, "the log holds frames: {} bytes", wal.len());
    let page = u32::from_be_bytes(wal[8..12].try_into().unwrap()) as usize;
    let frame = 24 + page;
    let frames = (wal.len() - 32) / frame;
    assert!(frames >= 7, "{frames} frames");
    let mut offsets = vec![0, 7, 31, 32, 32 + 10, 32 + frame / 2];
    for f in 1..=frames {
        offsets.push(32 + f * frame);
        offsets.push(32 + f * frame - page / 3);
    }
    offsets.push(wal.len() - 1);
    offsets.sort_unstable();
    offsets.dedup();
    let mut seen = BTreeMap::new();
    for offset in offsets {
        let torn = tempfile::tempdir().unwrap();
        let path = torn.path().join("state.sqlite");
        std::fs::write(&path, &database).unwrap();
        std::fs::write(torn.path().join("state.sqlite-wal"), &wal[..offset]).unwrap();
        match Service::start(CELL, &path, &[], |_| {}) {
            Err(refused) => {
                assert_refused(&refused, "state.sqlite");
                seen.insert(offset, "refused".to_string());
            }
            Ok(service) => {
                let health = service.get("/v1/health");
                assert_eq!(health["status"], "ok");
                let world = service.get("/v1/world");
                let r = revision(&world);
                assert_eq!(health["revision"].as_u64(), Some(r));
                assert_eq!(
                    acknowledged.get(&r),
                    Some(&place(&world)),
                    "the log cut at {offset} opened to an unacknowledged world at {r}"
                );
                assert_eq!(health["interrupted"], json!([]));
                // And it takes a write again.
                let answer = service.call(
                    "PUT",
                    "/v1/world",
                    &[&etag_header(&world)],
                    on_the_table().to_string().as_bytes(),
                );
                assert_eq!(answer.status(), Some(200), "cut at {offset}: {answer:?}");
                assert!(!service.log().contains("panicked"));
                seen.insert(offset, format!("revision {r}"));
            }
        }
    }
    eprintln!("the log cut at (offset: outcome): {seen:?}");
    // The whole log is the latest world; a cut log reaches back no further than its cut.
    let whole = seen.values().last().unwrap();
    let latest = *acknowledged.keys().next_back().unwrap();
    assert_eq!(whole, &format!("revision {latest}"), "{seen:?}");
}

#[test]
fn an_unwritable_state_file_is_refused_at_start_up() {
    let _serial = serial();
    let dir = tempfile::tempdir().unwrap();
    // A folder this process may not write: as root, permissions are not enforced, and
    // sysfs refuses a new file even to root.
    let root = unsafe { libc::geteuid() } == 0;
    let read_only = if root {
        std::path::PathBuf::from("/sys/cellc-faults.sqlite")
    } else {
        let folder = dir.path().join("read-only");
        std::fs::create_dir(&folder).unwrap();
        std::fs::set_permissions(&folder, std::os::unix::fs::PermissionsExt::from_mode(0o555))
            .unwrap();
        folder.join("state.sqlite")
    };
    let refused = Service::start(CELL, &read_only, &[], |_| {})
        .err()
        .expect("refused");
    assert_refused(
        &refused,
        "cannot be written (a read-only file, folder or disk)",
    );
    // A folder that is a file.
    std::fs::write(dir.path().join("file"), "").unwrap();
    let refused = Service::start(CELL, &dir.path().join("file/state.sqlite"), &[], |_| {})
        .err()
        .expect("refused");
    assert_refused(&refused, "not a directory");
    // No room at all for the new file: the first write is refused.
    let refused = Service::start(CELL, &dir.path().join("state.sqlite"), &[], |c| {
        limit_file_size(c, 0)
    })
    .err()
    .expect("refused");
    assert_refused(&refused, "could not write");
}

/// Limits the files the child writes to `bytes` (a disk that is full past them), with
/// SIGXFSZ ignored so that a write past the limit fails instead of killing the process.
fn limit_file_size(command: &mut std::process::Command, bytes: u64) {
    use std::os::unix::process::CommandExt;
    // SAFETY: only async-signal-safe calls between fork and exec.
    unsafe {
        command.pre_exec(move || {
            libc::signal(libc::SIGXFSZ, libc::SIG_IGN);
            let limit = libc::rlimit {
                rlim_cur: bytes as libc::rlim_t,
                rlim_max: bytes as libc::rlim_t,
            };
            if libc::setrlimit(libc::RLIMIT_FSIZE, &limit) != 0 {
                return Err(std::io::Error::last_os_error());
            }
            Ok(())
        });
    }
}

#[test]
fn a_write_the_disk_cannot_take_answers_507_and_keeps_the_last_acknowledged_world() {
    let _serial = serial();
    let dir = tempfile::tempdir().unwrap();
    let state = dir.path().join("state.sqlite");
    // A state file with a world, closed cleanly (the log checkpointed into the file).
    let service = Service::up(CELL, &state, &[]);
    assert!(service.terminate().success());
    let size = std::fs::metadata(&state).unwrap().len();
    // Room for the file as it is, the shared-memory index (32 KiB) and a few frames of
    // the log: a few writes are taken, then one is not.
    let limit = size.max(32 * 1024) + 3 * 4120;
    let service = Service::start(CELL, &state, &[], |c| limit_file_size(c, limit))
        .unwrap_or_else(|r| panic!("starts under the limit: {r:?}"));
    let mut last = service.get("/v1/world");
    let mut taken = 0;
    let refusal = loop {
        let mut document = on_the_table();
        document["objects"]["ball"]["at"] = json!([0.45 - 0.005 * taken as f64, -0.25, 0.95]);
        let answer = service.call("PUT", "/v1/world", &[], document.to_string().as_bytes());
        match answer.status() {
            Some(200) => {
                assert_eq!(revision(answer.body()), revision(&last) + 1);
                last = answer.body().clone();
                taken += 1;
                assert!(
                    taken < 40,
                    "the limit of {limit} bytes never stopped a write"
                );
            }
            _ => break answer,
        }
    };
    assert!(
        taken >= 1,
        "no write was taken under the limit: {refusal:?}"
    );
    assert_eq!(
        (refusal.status(), refusal.code()),
        (Some(507), "S0010"),
        "{refusal:?}\n{}",
        service.log()
    );
    eprintln!(
        "after {taken} writes: {}",
        refusal.body()["diagnostics"][0]["message"]
    );
    // Nothing of it was acknowledged.
    let now = service.get("/v1/world");
    assert_eq!(
        (revision(&now), place(&now)),
        (revision(&last), place(&last))
    );
    // An execution is refused the same way, and moves nothing.
    let ui = UiRequest::read("tests/ui/serve/faults/S0010_disk_full.http");
    let answer = ui.send(&service);
    assert_eq!(
        (answer.status(), answer.code()),
        (Some(ui.status), ui.code.as_str()),
        "{answer:?}"
    );
    let now = service.get("/v1/world");
    assert_eq!(place(&now), place(&last));
    assert!(!service.log().contains("panicked"), "{}", service.log());
    service.kill();
    // Restarted with room again: the last acknowledged world.
    let service = Service::up(CELL, &state, &[]);
    let now = service.get("/v1/world");
    assert_eq!(
        (revision(&now), place(&now)),
        (revision(&last), place(&last)),
        "{}",
        service.log()
    );
}

#[test]
fn a_key_whose_execution_was_interrupted_answers_s0012() {
    let _serial = serial();
    let dir = tempfile::tempdir().unwrap();
    let state = dir.path().join("state.sqlite");
    let ui = UiRequest::read("tests/ui/serve/faults/S0012_interrupted_key.http");
    let service = Service::up(CELL, &state, &["--sim-pace", "1"]);
    let base = revision(&service.get("/v1/world"));
    let addr = service.addr.clone();
    let (method, path, headers, body) = (
        ui.method.clone(),
        ui.path.clone(),
        ui.headers.clone(),
        ui.body.clone(),
    );
    let run = std::thread::spawn(move || {
        let headers: Vec<&str> = headers.iter().map(String::as_str).collect();
        service::send(&addr, &method, &path, &headers, body.as_bytes())
    });
    // Killed once its first step is stored.
    let began = Instant::now();
    while revision(&service.get("/v1/world")) == base {
        assert!(
            began.elapsed() < Duration::from_secs(60),
            "no step was stored"
        );
        std::thread::sleep(Duration::from_millis(10));
    }
    service.kill();
    assert_eq!(run.join().unwrap(), Answer::Dropped);
    let service = Service::up(CELL, &state, &[]);
    let world = service.get("/v1/world");
    assert_eq!(
        uncertain(&world).as_array().map(Vec::len),
        Some(1),
        "{world}"
    );
    // Confirmed as read, the world is certain again; the key still is not carried out.
    confirm(&service, &world, &document_of(&world));
    let answer = ui.send(&service);
    assert_eq!(
        (answer.status(), answer.code()),
        (Some(ui.status), ui.code.as_str()),
        "{answer:?}"
    );
    assert_eq!(
        revision(&service.get("/v1/world")),
        revision(&world) + 1,
        "nothing moved"
    );
}
