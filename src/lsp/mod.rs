//! `cellc lsp`: a Language Server Protocol server over standard input and output.
//!
//! The editor's buffers are compiled as `cellc check` compiles files (open buffers served
//! before the disk, so includes see unsaved text); each open document is compiled as a
//! cell of its own and the diagnostics of all of them are published per file. Requests
//! read the latest compilation ([`analysis::Analysis`]) and the table of names the
//! resolver made in it ([`cellc_compiler::names::Names`]).
//!
//! Messages are read on their own thread and handled in batches: every message already
//! waiting is taken at once, changes only replace texts (and note their paths), and the
//! cells are compiled once per batch (or before the first request that needs them). A
//! burst of keystrokes costs one compilation, of the latest text. Only the compilations
//! that read a changed file are made again (an edit of one cell leaves the other open
//! cells' compilations as they are, an edit of a library redoes the cells that include
//! it), and within one, only the changed files are parsed again
//! ([`analysis::ParseCache`]).
//!
//! Nothing a client sends stops the server but `exit`: a message that is not JSON-RPC is
//! answered with a parse error, a request that fails (bad parameters, a panic in a
//! handler) with an error response, and the loop goes on.

pub mod actions;
pub mod analysis;
pub mod complete;
pub mod diagnostics;
pub mod documents;
pub mod format;
pub(crate) mod framing;
pub mod hover;
pub mod navigate;
pub mod position;
pub mod quantities;
pub mod rename;
pub(crate) mod transport;

use std::collections::{BTreeMap, BTreeSet};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::process::ExitCode;

use lsp_server::{ErrorCode, Message, Notification, Request, Response, ResponseError};
use lsp_types::notification::Notification as _;
use lsp_types::request::Request as _;
use lsp_types::{notification, request};
use serde_json::Value;

use analysis::{Analysis, ParseCache, ReachCache};
use documents::{path_of, uri_of, Documents};
use transport::Incoming;

/// Runs the server until `exit`: 0 after a `shutdown`, 1 otherwise (as the protocol says).
pub fn run(options: cellc_compiler::CompileOptions) -> ExitCode {
    let incoming = transport::spawn_reader();
    let mut server = Server::new(options);
    loop {
        // The client went away without `exit`.
        let Ok(first) = incoming.recv() else {
            return ExitCode::from(1);
        };
        let mut batch = vec![first];
        batch.extend(incoming.try_iter());
        for message in batch {
            if let Some(code) = server.handle(message) {
                return code;
            }
        }
        server.refresh();
    }
}

/// Where the session is.
#[derive(Clone, Copy, PartialEq, Eq)]
enum State {
    /// Before `initialize`.
    Starting,
    /// Answering.
    Running,
    /// After `shutdown`: only `exit` is expected.
    ShutDown,
}

/// The server's state between messages.
struct Server {
    state: State,
    options: cellc_compiler::CompileOptions,
    documents: Documents,
    /// One compilation per open document, by path; missing for a document opened, or
    /// reading a file changed, since the last refresh.
    analyses: BTreeMap<String, Analysis>,
    /// The paths of the documents opened, changed or closed since the last refresh.
    changed: BTreeSet<String>,
    /// A save (the disk may hold new text for files no buffer shows): every
    /// compilation is made again.
    everything: bool,
    /// What was last published, by path, so unchanged lists are not sent again.
    published: BTreeMap<String, Vec<lsp_types::Diagnostic>>,
    reach: ReachCache,
    trees: ParseCache,
}

impl Server {
    fn new(options: cellc_compiler::CompileOptions) -> Server {
        Server {
            state: State::Starting,
            options,
            documents: Documents::default(),
            analyses: BTreeMap::new(),
            changed: BTreeSet::new(),
            everything: false,
            published: BTreeMap::new(),
            reach: ReachCache::default(),
            trees: ParseCache::default(),
        }
    }

    /// Handles one message; `Some(exit code)` on `exit`.
    fn handle(&mut self, message: Incoming) -> Option<ExitCode> {
        match message {
            Incoming::Malformed(why) => {
                transport::send_parse_error(&why);
                None
            }
            Incoming::Message(Message::Request(request)) => {
                let response = self.request(request);
                transport::send(&Message::Response(response));
                None
            }
            Incoming::Message(Message::Notification(n)) if n.method == "exit" => {
                Some(if self.state == State::ShutDown {
                    ExitCode::SUCCESS
                } else {
                    ExitCode::from(1)
                })
            }
            Incoming::Message(Message::Notification(n)) => {
                if self.state == State::Running {
                    let method = n.method.clone();
                    if catch_unwind(AssertUnwindSafe(|| self.notification(n))).is_err() {
                        eprintln!("cellc lsp: the `{method}` notification failed");
                    }
                }
                None
            }
            // The server sends no requests, so a response answers nothing.
            Incoming::Message(Message::Response(_)) => None,
        }
    }

    fn request(&mut self, request: Request) -> Response {
        let id = request.id.clone();
        let method = request.method.clone();
        match (self.state, method.as_str()) {
            (State::Starting, request::Initialize::METHOD) => {
                self.state = State::Running;
                return Response::new_ok(id, initialize_result());
            }
            (State::Starting, _) => {
                return error(id, ErrorCode::ServerNotInitialized, "initialize first")
            }
            (State::ShutDown, _) => {
                return error(id, ErrorCode::InvalidRequest, "the server is shut down")
            }
            (State::Running, request::Shutdown::METHOD) => {
                self.state = State::ShutDown;
                return Response::new_ok(id, Value::Null);
            }
            (State::Running, request::Initialize::METHOD) => {
                return error(id, ErrorCode::InvalidRequest, "already initialized")
            }
            (State::Running, _) => {}
        }
        self.refresh();
        match catch_unwind(AssertUnwindSafe(|| self.answer(&method, request.params))) {
            Ok(Ok(result)) => Response::new_ok(id, result),
            Ok(Err(e)) => Response {
                id,
                response_result: Err(e),
            },
            Err(_) => error(id, ErrorCode::InternalError, &format!("`{method}` failed")),
        }
    }

    /// The result of a request, by method.
    fn answer(&self, method: &str, params: Value) -> Result<Value, ResponseError> {
        let docs = &self.documents;
        let analyses = &self.analyses;
        match method {
            request::HoverRequest::METHOD => reply(hover::hover(analyses, parse(params)?)),
            request::GotoDefinition::METHOD => {
                reply(navigate::definition(analyses, parse(params)?))
            }
            request::References::METHOD => reply(navigate::references(analyses, parse(params)?)),
            request::DocumentSymbolRequest::METHOD => {
                reply(navigate::document_symbols(analyses, parse(params)?))
            }
            request::WorkspaceSymbolRequest::METHOD => {
                reply(navigate::workspace_symbols(analyses, parse(params)?))
            }
            request::Completion::METHOD => {
                reply(complete::complete(analyses, docs, parse(params)?))
            }
            request::Formatting::METHOD => reply(format::format(docs, parse(params)?)),
            request::RangeFormatting::METHOD => reply(format::format_range(docs, parse(params)?)),
            request::CodeActionRequest::METHOD => {
                reply(actions::code_actions(analyses, parse(params)?))
            }
            request::PrepareRenameRequest::METHOD => {
                reply(rename::prepare(analyses, parse(params)?).map_err(refused)?)
            }
            request::Rename::METHOD => {
                reply(rename::rename(analyses, parse(params)?).map_err(refused)?)
            }
            _ => Err(ResponseError {
                code: ErrorCode::MethodNotFound as i32,
                message: format!("`{method}` is not supported"),
                data: None,
            }),
        }
    }

    fn notification(&mut self, n: Notification) {
        match n.method.as_str() {
            notification::DidOpenTextDocument::METHOD => {
                if let Ok(p) =
                    serde_json::from_value::<lsp_types::DidOpenTextDocumentParams>(n.params)
                {
                    let d = p.text_document;
                    self.changed
                        .extend(self.documents.open(d.uri, d.version, d.text));
                }
            }
            notification::DidChangeTextDocument::METHOD => {
                if let Ok(p) =
                    serde_json::from_value::<lsp_types::DidChangeTextDocumentParams>(n.params)
                {
                    // Full synchronisation: the last change holds the whole text.
                    if let Some(change) = p.content_changes.into_iter().last() {
                        let d = p.text_document;
                        let path = self.documents.open(d.uri, d.version, change.text);
                        self.changed.extend(path);
                    }
                }
            }
            notification::DidCloseTextDocument::METHOD => {
                if let Ok(p) =
                    serde_json::from_value::<lsp_types::DidCloseTextDocumentParams>(n.params)
                {
                    self.changed
                        .extend(self.documents.close(&p.text_document.uri));
                }
            }
            // Saving may change files that were read from the disk (a library saved in
            // another editor is caught at the next save here).
            notification::DidSaveTextDocument::METHOD => self.everything = true,
            // `initialized`, `$/cancelRequest` and the rest need nothing.
            _ => {}
        }
    }

    /// Compiles again the open documents whose compilations read a changed file (and
    /// those opened since), and publishes what changed in the diagnostics.
    fn refresh(&mut self) {
        if self.changed.is_empty() && !self.everything {
            return;
        }
        let changed = std::mem::take(&mut self.changed);
        if std::mem::take(&mut self.everything) {
            self.analyses.clear();
        }
        let documents = &self.documents;
        self.analyses
            .retain(|path, a| documents.get(path).is_some() && !a.reads_any(path, &changed));
        let overlay = self.documents.overlay();
        for (path, _) in self.documents.iter() {
            if self.analyses.contains_key(path) {
                continue;
            }
            let compiled = catch_unwind(AssertUnwindSafe(|| {
                Analysis::new(&overlay, (&self.reach, &self.trees), path, &self.options)
            }));
            match compiled {
                Ok(analysis) => {
                    self.analyses.insert(path.to_string(), analysis);
                }
                Err(_) => eprintln!("cellc lsp: compiling `{path}` failed"),
            }
        }
        let mut merged: BTreeMap<String, Vec<lsp_types::Diagnostic>> = BTreeMap::new();
        for (path, analysis) in &self.analyses {
            let c = &analysis.compilation;
            for (file, list) in diagnostics::by_file(&c.diagnostics, &c.sources, path) {
                let entry = merged.entry(file).or_default();
                for d in list {
                    if !entry.contains(&d) {
                        entry.push(d);
                    }
                }
            }
        }
        for (path, old) in &self.published {
            if !merged.contains_key(path) && !old.is_empty() {
                publish(&self.documents, path, Vec::new());
            }
        }
        for (path, list) in &merged {
            if self.published.get(path) != Some(list) {
                publish(&self.documents, path, list.clone());
            }
        }
        self.published = merged;
    }
}

/// Sends one file's diagnostics.
fn publish(documents: &Documents, path: &str, diagnostics: Vec<lsp_types::Diagnostic>) {
    let open = documents.get(path);
    let Some(uri) = open.map(|d| d.uri.clone()).or_else(|| uri_of(path)) else {
        return;
    };
    let params = lsp_types::PublishDiagnosticsParams {
        uri,
        diagnostics,
        version: open.map(|d| d.version),
    };
    transport::send(&Message::Notification(Notification::new(
        notification::PublishDiagnostics::METHOD.to_string(),
        params,
    )));
}

/// What the server can do.
fn initialize_result() -> lsp_types::InitializeResult {
    use lsp_types::*;
    InitializeResult {
        capabilities: ServerCapabilities {
            text_document_sync: Some(TextDocumentSyncCapability::Kind(TextDocumentSyncKind::FULL)),
            hover_provider: Some(HoverProviderCapability::Simple(true)),
            definition_provider: Some(OneOf::Left(true)),
            references_provider: Some(OneOf::Left(true)),
            document_symbol_provider: Some(OneOf::Left(true)),
            workspace_symbol_provider: Some(OneOf::Left(true)),
            document_formatting_provider: Some(OneOf::Left(true)),
            document_range_formatting_provider: Some(OneOf::Left(true)),
            code_action_provider: Some(CodeActionProviderCapability::Simple(true)),
            rename_provider: Some(OneOf::Right(RenameOptions {
                prepare_provider: Some(true),
                work_done_progress_options: WorkDoneProgressOptions::default(),
            })),
            completion_provider: Some(CompletionOptions {
                trigger_characters: Some(vec![".".to_string()]),
                ..CompletionOptions::default()
            }),
            ..ServerCapabilities::default()
        },
        server_info: Some(ServerInfo {
            name: "cellc".to_string(),
            version: Some(env!("CARGO_PKG_VERSION").to_string()),
        }),
    }
}

/// A request's parameters, or the JSON-RPC error for parameters that do not fit.
fn parse<P: serde::de::DeserializeOwned>(params: Value) -> Result<P, ResponseError> {
    serde_json::from_value(params).map_err(|e| ResponseError {
        code: ErrorCode::InvalidParams as i32,
        message: format!("invalid parameters: {e}"),
        data: None,
    })
}

/// A result as JSON (`null` for `None`).
fn reply<R: serde::Serialize>(result: R) -> Result<Value, ResponseError> {
    serde_json::to_value(result).map_err(|e| ResponseError {
        code: ErrorCode::InternalError as i32,
        message: format!("the answer could not be written: {e}"),
        data: None,
    })
}

/// A request the server understood and will not do (a rename that would change the
/// cell's meaning), with the reason for the user.
fn refused(message: String) -> ResponseError {
    ResponseError {
        code: ErrorCode::RequestFailed as i32,
        message,
        data: None,
    }
}

fn error(id: lsp_server::RequestId, code: ErrorCode, message: &str) -> Response {
    Response::new_err(id, code as i32, message.to_string())
}

/// The path of a document's URI and the analysis that answers for it: the document's own
/// compilation when it is open, else one that includes it.
pub fn analysis_for<'a>(
    analyses: &'a BTreeMap<String, Analysis>,
    uri: &lsp_types::Uri,
) -> Option<(&'a Analysis, cellc_lang::FileId)> {
    let path = path_of(uri)?;
    if let Some(a) = analyses.get(&path) {
        return Some((a, a.file(&path)?));
    }
    analyses.values().find_map(|a| Some((a, a.file(&path)?)))
}
