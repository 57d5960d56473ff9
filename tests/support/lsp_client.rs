//! A client of `cellc lsp` as an editor drives it: the binary spawned, JSON-RPC messages
//! with `Content-Length` framing on its standard input, answers read from its output.
//! Shared by the language server's test binaries (`tests/lsp.rs`, `tests/lsp_names.rs`).

// Each test binary that includes this module uses some of it.
#![allow(dead_code)]

use std::io::{BufRead, BufReader, Write};
use std::process::{Child, ChildStdin, Command, Stdio};
use std::sync::mpsc::{Receiver, RecvTimeoutError};
use std::time::Duration;

use serde_json::{json, Value};

pub const ROOT: &str = env!("CARGO_MANIFEST_DIR");

/// How long any one answer may take (a debug build compiling a cell).
const PATIENCE: Duration = Duration::from_secs(120);

/// A client speaking to one server process.
pub struct Client {
    child: Child,
    pub stdin: ChildStdin,
    messages: Receiver<Value>,
    /// Notifications read while waiting for something else.
    pending: Vec<Value>,
    next_id: i64,
}

impl Client {
    /// Starts `cellc lsp` and initializes it.
    pub fn start() -> Client {
        let mut child = Command::new(env!("CARGO_BIN_EXE_cellc"))
            .arg("lsp")
            .current_dir(ROOT)
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("cellc starts");
        let stdin = child.stdin.take().expect("stdin");
        let stdout = child.stdout.take().expect("stdout");
        let (sender, messages) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            let mut reader = BufReader::new(stdout);
            while let Some(message) = read_message(&mut reader) {
                if sender.send(message).is_err() {
                    break;
                }
            }
        });
        let mut client = Client {
            child,
            stdin,
            messages,
            pending: Vec::new(),
            next_id: 1,
        };
        let init = client.request(
            "initialize",
            json!({ "processId": null, "rootUri": null, "capabilities": {} }),
        );
        assert!(
            init["result"]["capabilities"]["hoverProvider"] == json!(true),
            "{init}"
        );
        assert_eq!(
            init["result"]["capabilities"]["documentRangeFormattingProvider"],
            json!(true),
            "{init}"
        );
        client.notify("initialized", json!({}));
        client
    }

    pub fn write_raw(&mut self, body: &str) {
        let framed = format!("Content-Length: {}\r\n\r\n{body}", body.len());
        self.stdin.write_all(framed.as_bytes()).expect("write");
        self.stdin.flush().expect("flush");
    }

    pub fn next(&mut self) -> Value {
        match self.messages.recv_timeout(PATIENCE) {
            Ok(m) => m,
            Err(RecvTimeoutError::Timeout) => panic!("no answer in {PATIENCE:?}"),
            Err(RecvTimeoutError::Disconnected) => panic!("the server closed its output"),
        }
    }

    pub fn notify(&mut self, method: &str, params: Value) {
        let body = json!({ "jsonrpc": "2.0", "method": method, "params": params });
        self.write_raw(&body.to_string());
    }

    /// Sends a request and waits for its response (keeping notifications for later).
    pub fn request(&mut self, method: &str, params: Value) -> Value {
        let id = self.next_id;
        self.next_id += 1;
        let body = json!({ "jsonrpc": "2.0", "id": id, "method": method, "params": params });
        self.write_raw(&body.to_string());
        self.response(json!(id))
    }

    pub fn response(&mut self, id: Value) -> Value {
        loop {
            let message = self.next();
            if message.get("method").is_some() {
                self.pending.push(message);
            } else if message["id"] == id {
                return message;
            }
        }
    }

    /// The next diagnostics published for `uri`.
    pub fn diagnostics(&mut self, uri: &str) -> Value {
        let is_for = |m: &Value| {
            m["method"] == "textDocument/publishDiagnostics" && m["params"]["uri"] == uri
        };
        if let Some(i) = self.pending.iter().position(is_for) {
            return self.pending.remove(i)["params"]["diagnostics"].clone();
        }
        loop {
            let message = self.next();
            if is_for(&message) {
                return message["params"]["diagnostics"].clone();
            }
            self.pending.push(message);
        }
    }

    pub fn open(&mut self, uri: &str, text: &str) {
        self.notify(
            "textDocument/didOpen",
            json!({ "textDocument": { "uri": uri, "languageId": "cell", "version": 1, "text": text } }),
        );
    }

    pub fn at(&mut self, method: &str, uri: &str, line: u32, character: u32) -> Value {
        let mut params = json!({
            "textDocument": { "uri": uri },
            "position": { "line": line, "character": character },
        });
        if method == "textDocument/references" {
            params["context"] = json!({ "includeDeclaration": true });
        }
        self.request(method, params)
    }

    /// `shutdown` then `exit`: the exit code.
    pub fn stop(mut self) -> Option<i32> {
        let answer = self.request("shutdown", Value::Null);
        assert_eq!(answer["result"], Value::Null, "{answer}");
        self.notify("exit", Value::Null);
        self.child.wait().expect("the server exits").code()
    }
}

/// One framed message, `None` at end of output.
pub fn read_message(reader: &mut impl BufRead) -> Option<Value> {
    let mut length = None;
    loop {
        let mut line = String::new();
        if reader.read_line(&mut line).ok()? == 0 {
            return None;
        }
        let line = line.trim_end();
        if line.is_empty() {
            break;
        }
        if let Some(n) = line.strip_prefix("Content-Length: ") {
            length = n.parse::<usize>().ok();
        }
    }
    let mut body = vec![0; length?];
    reader.read_exact(&mut body).ok()?;
    serde_json::from_slice(&body).ok()
}

pub fn uri(relative: &str) -> String {
    format!("file://{ROOT}/{relative}")
}

pub fn text_of(relative: &str) -> String {
    std::fs::read_to_string(format!("{ROOT}/{relative}")).expect("a shipped file")
}

/// `value` as pretty JSON with the checkout's path as `$ROOT`.
pub fn portable(value: &Value) -> String {
    serde_json::to_string_pretty(value)
        .expect("JSON")
        .replace(ROOT, "$ROOT")
}

/// The line and column (UTF-16, all ASCII here) of the first `needle` in `text`, plus
/// `skip` characters.
pub fn find(text: &str, needle: &str, skip: u32) -> (u32, u32) {
    let at = text.find(needle).expect("the needle is in the text");
    let line = text[..at].matches('\n').count() as u32;
    let column = (at - text[..at].rfind('\n').map_or(0, |i| i + 1)) as u32;
    (line, column + skip)
}

/// The labels of a completion answer.
pub fn labels(answer: &Value) -> Vec<String> {
    answer["result"]
        .as_array()
        .map(|a| {
            a.iter()
                .filter_map(|i| i["label"].as_str().map(str::to_string))
                .collect()
        })
        .unwrap_or_default()
}
