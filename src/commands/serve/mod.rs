//! `cellc serve INPUT [--addr 127.0.0.1:7878]`: a long-running planning service.
//!
//! The cell is loaded and verified once; the service then holds it (read-only, shared by
//! every request) and one world (docs/world.md), which plans read and executions update.
//! Plans run in parallel on tokio's blocking pool, each on a copy of the world taken under
//! its lock; an execution holds the lock from planning to the simulator's last step, so
//! executions are serialised and the world is replaced at once with what the simulator
//! reports. HTTP/1.1 only, on loopback unless `--addr` says otherwise; every error is the
//! diagnostics report (docs/service.md).

mod durable;
mod errors;
mod execute;
mod executions;
mod goals;
mod openapi;
mod patch;
mod routes;

use std::net::SocketAddr;
use std::process::ExitCode;
use std::sync::{Arc, Mutex, RwLock};
use std::time::{Duration, Instant};

use axum::body::Body;
use axum::extract::Request;
use axum::http::Method;
use axum::middleware::Next;
use axum::response::{IntoResponse, Response};
use axum::routing::{get, post};
use axum::Router;
pub use durable::StateAt;
use durable::{Durable, Snapshot};
use serde::de::DeserializeOwned;

use super::plan::{load, LoadArgs, Loaded};
pub use errors::{codes, worker_failed};
use errors::{ApiError, Failure};

/// Largest body of a planning request.
const MAX_BODY: usize = 1 << 20;
/// Largest world document (as `--world FILE` allows).
const MAX_WORLD: usize = cellc_schema::world::MAX_WORLD_BYTES;
/// A client that has not sent its headers (or, between requests, its next ones) by then
/// is disconnected.
const HEADER_TIMEOUT: Duration = Duration::from_secs(10);
/// A body not received by then is refused with S0004.
const BODY_TIMEOUT: Duration = Duration::from_secs(10);
/// A request's planning time budget when it gives none.
const DEFAULT_BUDGET: Duration = Duration::from_secs(10);
/// The largest planning time budget a request may ask for.
const MAX_BUDGET: Duration = Duration::from_secs(60);
/// A request still running by then is answered S0004 (the planning budget is smaller,
/// so this catches only what the budget does not bound, e.g. a long task).
const REQUEST_TIMEOUT: Duration = Duration::from_secs(300);
/// The longest a simulated step waits at any `--sim-pace`.
const MAX_STEP_SECONDS: f64 = 30.0;
/// How long shutdown waits for requests in flight.
const SHUTDOWN_GRACE: Duration = Duration::from_secs(10);

/// What `cellc serve` was asked.
pub struct ServeArgs {
    /// Cell or artifact.
    pub input: String,
    /// Where to listen.
    pub addr: SocketAddr,
    /// Seed of verification and of plans that give none.
    pub seed: u64,
    /// Compile options (the package path).
    pub compile: cellc_compiler::CompileOptions,
    /// Colour of the diagnostics printed when the cell does not load.
    pub color: crate::render::Color,
    /// Where the world is kept (`None`: the state file next to the input).
    pub state: Option<StateAt>,
    /// How long the journal keeps ended executions.
    pub retention: cellc_store::Retention,
    /// How many times a robot's time each simulated step takes (0: at once).
    pub pace: f64,
}

/// What every request shares: the cell (read-only) and the durable world.
pub struct Service {
    /// The cell and its sources.
    loaded: Loaded,
    /// The world plans start from and executions update, with its store. Held by every
    /// writer for the whole write (an execution: from planning to its last step).
    state: Mutex<Durable>,
    /// The world as last stored, which readers take without waiting for a writer: an
    /// execution publishes the world after each step it journaled.
    published: RwLock<Arc<Snapshot>>,
    /// A second, read-only connection to the state file, for reading the journal while
    /// an execution holds the writers' lock (WAL lets it read the last commit); `None`
    /// in memory, where the journal is read under the writers' lock.
    reader: Option<Mutex<cellc_store::SqliteStore>>,
    /// `file` or `memory`.
    durability: &'static str,
    /// The state file's path as given, for messages.
    shown: String,
    /// Seed of plans that give none.
    seed: u64,
    /// `--sim-pace`.
    pace: f64,
}

impl Service {
    /// The world as last stored, with its revision.
    fn snapshot(&self) -> Arc<Snapshot> {
        self.published
            .read()
            .unwrap_or_else(|e| e.into_inner())
            .clone()
    }

    /// Makes `now` what readers see; called after every write the store took.
    fn publish(&self, now: Snapshot) {
        *self.published.write().unwrap_or_else(|e| e.into_inner()) = Arc::new(now);
    }

    /// The writers' lock. A request that panicked while holding it left a world that is
    /// still whole (the world is replaced in one assignment, after the store took it),
    /// so poisoning is ignored.
    fn lock_state(&self) -> std::sync::MutexGuard<'_, Durable> {
        self.state.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Runs `read` on the journal without waiting for a writer where the state file
    /// allows it, else under the writers' lock. Errors are worded as store errors while
    /// serving (S0010).
    fn read_journal<T>(
        &self,
        read: impl FnOnce(&mut dyn cellc_store::Store) -> Result<T, cellc_store::StoreError>,
    ) -> Result<T, errors::ApiError> {
        match &self.reader {
            Some(reader) => {
                let mut reader = reader.lock().unwrap_or_else(|e| e.into_inner());
                read(&mut *reader).map_err(|e| durable::serving_error(&e, &self.shown))
            }
            None => {
                let mut state = self.lock_state();
                let result = read(state.store.as_mut());
                result.map_err(|e| state.failed(&e))
            }
        }
    }
}

/// Loads the cell, binds, prints `listening on http://ADDR` on standard output and serves
/// until SIGINT or SIGTERM.
pub fn run(args: &ServeArgs) -> ExitCode {
    let load_args = LoadArgs {
        input: args.input.clone(),
        options: cellc_driver::LoadOptions {
            compile: args.compile.clone(),
            seed: args.seed,
        },
        style: crate::render::Style {
            format: crate::render::Format::Human,
            color: args.color,
        },
    };
    let loaded = match load(&load_args) {
        Ok(l) => l,
        Err(code) => return code,
    };
    let at = args.state.clone().unwrap_or_else(|| {
        StateAt::File(
            durable::default_state(&args.input),
            cellc_store::Durability::Full,
        )
    });
    let initial = || {
        loaded
            .cell
            .initial_world(&cellc_runtime::plan::PlanOptions {
                seed: args.seed,
                ..Default::default()
            })
            .map_err(|e| crate::world_report::world_diagnostic(&e, "the cell's `world`"))
    };
    let state = match Durable::open(&at, args.retention, &loaded.cell, initial) {
        Ok(s) => s,
        Err(d) => {
            loaded.report(&[d]);
            return ExitCode::from(1);
        }
    };
    let recovered: Vec<u64> = state.store.recovered().iter().map(|id| id.0).collect();
    eprintln!(
        "{}",
        serde_json::json!({
            "event": "state",
            "state": state.shown,
            "instance": state.instance().as_str(),
            "revision": state.revision.0,
            "recovered": recovered,
            "uncertain": state.interrupted(),
        })
    );
    let (durability, reader) = match &at {
        StateAt::File(path, _) => match cellc_store::SqliteStore::open_read_only(path) {
            Ok(r) => ("file", Some(Mutex::new(r))),
            Err(e) => {
                loaded.report(&[crate::state::diagnostic(
                    &e,
                    &state.shown,
                    crate::state::When::Opening,
                )]);
                return ExitCode::from(1);
            }
        },
        StateAt::Memory => ("memory", None),
    };
    let shown = state.shown.clone();
    let service = Arc::new(Service {
        loaded,
        published: RwLock::new(Arc::new(state.snapshot())),
        reader,
        shown,
        durability,
        state: Mutex::new(state),
        seed: args.seed,
        pace: args.pace,
    });
    let workers = std::thread::available_parallelism().map_or(2, |n| n.get());
    let runtime = match tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        // Plans are CPU-bound: more planning threads than cores only share the cores,
        // so requests beyond them wait in the pool's queue.
        .max_blocking_threads(workers * 2)
        .build()
    {
        Ok(r) => r,
        Err(e) => {
            eprintln!("error: cannot start the service's threads: {e}");
            return ExitCode::from(1);
        }
    };
    let code = runtime.block_on(serve(service, args.addr));
    runtime.shutdown_timeout(SHUTDOWN_GRACE);
    code
}

/// The router: every endpoint, the fallbacks and the middleware.
fn router(service: Arc<Service>) -> Router {
    Router::new()
        .route("/v1/health", get(routes::health))
        .route("/v1/cell", get(routes::cell))
        .route(
            "/v1/world",
            get(routes::get_world)
                .put(routes::put_world)
                .patch(patch::patch_world),
        )
        .route("/v1/executions", get(executions::list))
        .route("/v1/executions/{id}", get(executions::one))
        .route("/v1/plan", post(routes::plan))
        .route(
            "/v1/plan/follow_joint_trajectory",
            post(goals::follow_joint_trajectory),
        )
        .route("/v1/execute", post(execute::execute))
        .route("/v1/tasks", post(execute::tasks))
        .route("/v1/explain", post(routes::explain))
        .route("/v1/openapi.json", get(routes::openapi))
        .fallback(|method: Method, uri: axum::http::Uri| async move {
            errors::no_endpoint(method.as_str(), uri.path(), false)
        })
        .method_not_allowed_fallback(|method: Method, uri: axum::http::Uri| async move {
            errors::no_endpoint(method.as_str(), uri.path(), true)
        })
        .layer(axum::middleware::from_fn(refuse_oversize))
        .layer(axum::middleware::from_fn(time_and_log))
        .with_state(service)
}

/// Accepts connections until a signal, then lets requests in flight finish.
async fn serve(service: Arc<Service>, addr: SocketAddr) -> ExitCode {
    let listener = match tokio::net::TcpListener::bind(addr).await {
        Ok(l) => l,
        Err(e) => {
            eprintln!("error: cannot listen on {addr}: {e}");
            return ExitCode::from(1);
        }
    };
    let stop = shutdown_signal();
    match listener.local_addr() {
        Ok(bound) => println!("listening on http://{bound}"),
        Err(e) => {
            eprintln!("error: cannot read the bound address: {e}");
            return ExitCode::from(1);
        }
    }
    let app = router(service);
    let graceful = hyper_util::server::graceful::GracefulShutdown::new();
    let mut stop = std::pin::pin!(stop);
    loop {
        tokio::select! {
            accepted = listener.accept() => {
                let stream = match accepted {
                    Ok((stream, _)) => stream,
                    Err(e) => {
                        // Out of file descriptors and the like: wait, then accept again.
                        eprintln!("{}", serde_json::json!({"event": "accept_failed", "error": e.to_string()}));
                        tokio::time::sleep(Duration::from_millis(100)).await;
                        continue;
                    }
                };
                let service = hyper_util::service::TowerToHyperService::new(app.clone());
                let connection = hyper::server::conn::http1::Builder::new()
                    .timer(hyper_util::rt::TokioTimer::new())
                    .header_read_timeout(HEADER_TIMEOUT)
                    .serve_connection(hyper_util::rt::TokioIo::new(stream), service);
                let connection = graceful.watch(connection);
                tokio::spawn(async move {
                    let _ = connection.await;
                });
            }
            () = &mut stop => break,
        }
    }
    drop(listener);
    eprintln!("{}", serde_json::json!({"event": "shutdown"}));
    tokio::select! {
        () = graceful.shutdown() => {}
        () = tokio::time::sleep(SHUTDOWN_GRACE) => {}
    }
    ExitCode::SUCCESS
}

/// SIGINT (Ctrl-C) or SIGTERM. The handlers are installed when this is called, not when
/// the future is first polled: the service calls it before it says it listens, so a stop
/// sent as soon as the listening line is read is a clean shutdown (state file closed,
/// exit 0), not the signal's default death.
fn shutdown_signal() -> impl std::future::Future<Output = ()> {
    #[cfg(unix)]
    {
        use tokio::signal::unix::{signal, Signal, SignalKind};
        let interrupt = signal(SignalKind::interrupt()).ok();
        let terminate = signal(SignalKind::terminate()).ok();
        async fn received(signal: Option<Signal>) {
            match signal {
                Some(mut s) => {
                    s.recv().await;
                }
                None => std::future::pending::<()>().await,
            }
        }
        async move {
            tokio::select! {
                () = received(interrupt) => {}
                () = received(terminate) => {}
            }
        }
    }
    #[cfg(not(unix))]
    async {
        let _ = tokio::signal::ctrl_c().await;
    }
}

/// One JSON line per request on standard error (method, path, status, milliseconds), and
/// the request's overall time limit.
async fn time_and_log(request: Request, next: Next) -> Response {
    let method = request.method().clone();
    let path = request.uri().path().to_string();
    let start = Instant::now();
    let response = match tokio::time::timeout(REQUEST_TIMEOUT, next.run(request)).await {
        Ok(r) => r,
        Err(_) => ApiError::new(
            Failure::TimedOut,
            codes::TIMED_OUT,
            format!(
                "the request took longer than {} s",
                REQUEST_TIMEOUT.as_secs()
            ),
            "send fewer moves at once, or smaller time budgets",
        )
        .into_response(),
    };
    eprintln!(
        "{}",
        serde_json::json!({
            "method": method.as_str(),
            "path": path,
            "status": response.status().as_u16(),
            "ms": (start.elapsed().as_secs_f64() * 1000.0 * 10.0).round() / 10.0,
        })
    );
    response
}

/// The largest body `method path` accepts: world documents are larger than planning
/// requests.
fn body_limit(method: &Method, path: &str) -> usize {
    if (method == Method::PUT || method == Method::PATCH) && path == "/v1/world" {
        MAX_WORLD
    } else {
        MAX_BODY
    }
}

/// Refuses a request whose declared `Content-Length` is over its endpoint's limit before
/// any of the body is read: the client learns at once instead of after uploading (or
/// after the body timeout), and since the body is never polled, hyper sends no
/// `100 Continue` to a client that asked with `Expect: 100-continue`. A body without a
/// declared length (chunked) is still bounded while it is read.
async fn refuse_oversize(request: Request, next: Next) -> Response {
    let limit = body_limit(request.method(), request.uri().path());
    let declared = request
        .headers()
        .get(axum::http::header::CONTENT_LENGTH)
        .and_then(|v| v.to_str().ok())
        .and_then(|v| v.trim().parse::<u128>().ok());
    match declared {
        Some(length) if length > limit as u128 => too_large(limit, Some(length)).into_response(),
        _ => next.run(request).await,
    }
}

/// The report of a body over `limit` bytes (of `declared` bytes, when the client said).
fn too_large(limit: usize, declared: Option<u128>) -> ApiError {
    let size = declared.map_or(String::new(), |d| format!(" ({d} bytes declared)"));
    ApiError::new(
        Failure::TooLarge,
        codes::TOO_LARGE,
        format!("the body is larger than this endpoint's {limit} bytes{size}"),
        "send a smaller body: planning requests take at most 1 MiB, world documents 4 MiB",
    )
}

/// Reads a body of at most `limit` bytes within [`BODY_TIMEOUT`] and parses it as `T`.
async fn read_json<T: DeserializeOwned>(body: Body, limit: usize) -> Result<T, ApiError> {
    let bytes = read_body(body, limit).await?;
    serde_json::from_slice(&bytes).map_err(|e| bad_body(&e.to_string()))
}

/// Reads a body of at most `limit` bytes within [`BODY_TIMEOUT`].
async fn read_body(body: Body, limit: usize) -> Result<axum::body::Bytes, ApiError> {
    match tokio::time::timeout(BODY_TIMEOUT, axum::body::to_bytes(body, limit)).await {
        Err(_) => Err(ApiError::new(
            Failure::TimedOut,
            codes::TIMED_OUT,
            format!(
                "the body did not arrive within {} s",
                BODY_TIMEOUT.as_secs()
            ),
            "send the whole body at once",
        )),
        Ok(Err(e)) if is_length_limit(&e) => Err(too_large(limit, None)),
        Ok(Err(e)) => Err(bad_body(&format!("the body could not be read: {e}"))),
        Ok(Ok(bytes)) => Ok(bytes),
    }
}

fn is_length_limit(e: &axum::Error) -> bool {
    let mut source: Option<&(dyn std::error::Error + 'static)> = Some(e);
    while let Some(s) = source {
        if s.is::<http_body_util::LengthLimitError>() {
            return true;
        }
        source = s.source();
    }
    false
}

/// S0001: the body is not what the endpoint takes.
fn bad_body(detail: &str) -> ApiError {
    let d = cellc_lang::Diagnostic::error(
        codes::BAD_BODY,
        "the request body is not what this endpoint takes",
    )
    .note(crate::render::escape(detail).into_owned())
    .help("send JSON of the endpoint's schema (GET /v1/openapi.json, docs/service.md)");
    ApiError::from_diagnostic(Failure::BadBody, &d, &cellc_lang::SourceMap::new())
}
