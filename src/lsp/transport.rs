//! Messages in and out: `Content-Length` framing on standard input and output.
//!
//! `lsp-server`'s own stdio transport ends its reader at the first message that is not
//! JSON-RPC, which would end the session, and trusts every announced length; here frames
//! are read within bounds ([`super::framing`]), and a frame or message that cannot be
//! taken is reported and the reader goes on with the next, so a client's bad message
//! costs one error response.

use std::io::{BufReader, Write};

use super::framing::{Frame, FrameReader};

use lsp_server::Message;
use std::sync::mpsc::Receiver;

/// What the reader read.
pub enum Incoming {
    /// A message.
    Message(Message),
    /// A framed body that is not a JSON-RPC message, or a header that is not one.
    Malformed(String),
}

/// Reads standard input on a thread of its own until end of input, an `exit`
/// notification or a read error.
pub fn spawn_reader() -> Receiver<Incoming> {
    let (sender, receiver) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let mut frames = FrameReader::new(BufReader::new(std::io::stdin().lock()));
        loop {
            let incoming = match frames.next_frame() {
                Frame::Body(body) => message(&body),
                Frame::Malformed(why) => Incoming::Malformed(why),
                Frame::End => break,
            };
            let exit = matches!(&incoming, Incoming::Message(Message::Notification(n)) if n.method == "exit");
            if sender.send(incoming).is_err() || exit {
                break;
            }
        }
    });
    receiver
}

/// The message a whole body holds, or why it holds none (the stream is still at a
/// message boundary).
pub fn message(body: &[u8]) -> Incoming {
    match serde_json::from_slice::<Message>(body) {
        Ok(message) => Incoming::Message(message),
        Err(e) => Incoming::Malformed(format!(
            "not a JSON-RPC message: {}",
            e.to_string().chars().take(200).collect::<String>()
        )),
    }
}

/// Writes one message (a closed output ends nothing here: the next read will).
pub fn send(message: &Message) {
    let mut stdout = std::io::stdout().lock();
    let _ = message.write(&mut stdout);
    let _ = stdout.flush();
}

/// Answers a message that could not be read: JSON-RPC's parse error, with a null id
/// since no id could be read.
pub fn send_parse_error(why: &str) {
    let body = serde_json::json!({
        "jsonrpc": "2.0",
        "id": null,
        "error": { "code": lsp_server::ErrorCode::ParseError as i32, "message": why },
    })
    .to_string();
    let mut stdout = std::io::stdout().lock();
    let _ = write!(stdout, "Content-Length: {}\r\n\r\n{body}", body.len());
    let _ = stdout.flush();
}
