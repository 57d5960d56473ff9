//! `Content-Length` framing read within bounds, whatever the stream holds.
//!
//! `lsp-server`'s reader allocates the length a header announces before reading a byte
//! of the body (a header of `1000000000000` aborts the process, one of `2^64 - 1` panics)
//! and reads a header line of any length into memory. An editor's server must outlive a
//! corrupted stream, so this reader keeps the project's bounds: a header line of at most
//! [`MAX_HEADER_LINE`] bytes, at most [`MAX_HEADERS`] lines, a body of at most
//! [`MAX_BODY`] bytes (the size of the largest cell file, 1 MiB, many times over: a
//! `didOpen` carries a whole document, escaped), and memory that grows only with the bytes
//! that actually arrive.
//!
//! A frame it cannot take is reported as [`Frame::Malformed`] and the reader then
//! *resynchronises*: it skips bytes, holding none of them, up to the next
//! `Content-Length:` (in any case), which is where the next message starts whether the
//! bad frame's body was sent or not. A body that arrived whole but is not JSON-RPC leaves
//! the stream at a message boundary; that is for the caller to find.

use std::io::{BufRead, Read};

/// The largest body taken.
pub const MAX_BODY: u64 = 16 << 20;
/// The longest header line taken, line end included.
pub const MAX_HEADER_LINE: usize = 8 << 10;
/// The most header lines of one frame.
pub const MAX_HEADERS: usize = 32;

/// The header that starts every frame, lowercase.
const CONTENT_LENGTH: &[u8] = b"content-length:";

/// What one read gave.
#[derive(Debug, PartialEq, Eq)]
pub enum Frame {
    /// A whole body, of at most [`MAX_BODY`] bytes.
    Body(Vec<u8>),
    /// A frame that was refused, and why (one lowercase sentence).
    Malformed(String),
    /// The end of the stream (a frame cut short by it included).
    End,
}

/// Reads frames from `input`.
pub struct FrameReader<R> {
    input: R,
    /// The last frame was refused where the stream was not at a boundary.
    resync: bool,
}

/// A header line, read within bounds.
enum Line {
    Bytes(Vec<u8>),
    TooLong,
    End,
}

impl<R: BufRead> FrameReader<R> {
    /// A reader at the start of `input`.
    pub fn new(input: R) -> FrameReader<R> {
        FrameReader {
            input,
            resync: false,
        }
    }

    /// Reads the next frame. An I/O error is the end of the stream.
    pub fn next_frame(&mut self) -> Frame {
        match self.read_frame() {
            Ok(frame) => frame,
            Err(_) => Frame::End,
        }
    }

    fn read_frame(&mut self) -> std::io::Result<Frame> {
        let mut length: Option<u64> = None;
        if std::mem::take(&mut self.resync) {
            if !self.skip_to_content_length()? {
                return Ok(Frame::End);
            }
            match self.read_line()? {
                Line::Bytes(value) => match parse_length(&value) {
                    Ok(n) => length = Some(n),
                    Err(why) => return Ok(self.refuse(why)),
                },
                Line::TooLong => return Ok(self.refuse(too_long())),
                Line::End => return Ok(Frame::End),
            }
        }
        let mut lines = 0;
        loop {
            let line = match self.read_line()? {
                Line::Bytes(line) => line,
                Line::TooLong => return Ok(self.refuse(too_long())),
                Line::End => return Ok(Frame::End),
            };
            lines += 1;
            if lines > MAX_HEADERS {
                return Ok(self.refuse(format!("more than {MAX_HEADERS} header lines")));
            }
            let line = trim_line_end(&line);
            if line.is_empty() {
                break;
            }
            let Some(colon) = line.iter().position(|&b| b == b':') else {
                return Ok(self.refuse("a header line without a `:`".into()));
            };
            let name = line[..colon].trim_ascii();
            if name.eq_ignore_ascii_case(&CONTENT_LENGTH[..CONTENT_LENGTH.len() - 1]) {
                match parse_length(&line[colon + 1..]) {
                    Ok(n) => length = Some(n),
                    Err(why) => return Ok(self.refuse(why)),
                }
            }
        }
        let Some(length) = length else {
            return Ok(self.refuse("a frame without `Content-Length`".into()));
        };
        if length > MAX_BODY {
            return Ok(self.refuse(format!(
                "a body of {length} bytes, over the limit of {MAX_BODY} bytes"
            )));
        }
        let mut body = Vec::new();
        (&mut self.input).take(length).read_to_end(&mut body)?;
        if (body.len() as u64) < length {
            return Ok(Frame::End);
        }
        Ok(Frame::Body(body))
    }

    /// Refuses the frame being read; the next read resynchronises.
    fn refuse(&mut self, why: String) -> Frame {
        self.resync = true;
        Frame::Malformed(why)
    }

    /// Reads one line of at most [`MAX_HEADER_LINE`] bytes, its `\n` included; a longer
    /// one is left where it is (resynchronising skips it).
    fn read_line(&mut self) -> std::io::Result<Line> {
        let mut line = Vec::new();
        loop {
            let available = self.input.fill_buf()?;
            if available.is_empty() {
                return Ok(Line::End);
            }
            let room = MAX_HEADER_LINE - line.len();
            let window = &available[..available.len().min(room)];
            if let Some(end) = window.iter().position(|&b| b == b'\n') {
                line.extend_from_slice(&window[..=end]);
                self.input.consume(end + 1);
                return Ok(Line::Bytes(line));
            }
            let taken = window.len();
            line.extend_from_slice(window);
            self.input.consume(taken);
            if line.len() >= MAX_HEADER_LINE {
                return Ok(Line::TooLong);
            }
        }
    }

    /// Skips bytes up to and including the next `Content-Length:`; false at the end of
    /// the stream.
    fn skip_to_content_length(&mut self) -> std::io::Result<bool> {
        // The pattern's first byte occurs nowhere else in it, so after a mismatch the
        // match restarts at that byte or at nothing.
        let mut matched = 0;
        loop {
            let available = self.input.fill_buf()?;
            if available.is_empty() {
                return Ok(false);
            }
            let mut used = 0;
            for &byte in available {
                used += 1;
                let byte = byte.to_ascii_lowercase();
                matched = if byte == CONTENT_LENGTH[matched] {
                    matched + 1
                } else {
                    usize::from(byte == CONTENT_LENGTH[0])
                };
                if matched == CONTENT_LENGTH.len() {
                    self.input.consume(used);
                    return Ok(true);
                }
            }
            self.input.consume(used);
        }
    }
}

fn too_long() -> String {
    format!("a header line longer than {MAX_HEADER_LINE} bytes")
}

fn trim_line_end(line: &[u8]) -> &[u8] {
    let line = line.strip_suffix(b"\n").unwrap_or(line);
    line.strip_suffix(b"\r").unwrap_or(line)
}

/// A `Content-Length` value: decimal digits, at most 20 of them.
fn parse_length(value: &[u8]) -> Result<u64, String> {
    let value = trim_line_end(value).trim_ascii();
    let digits = std::str::from_utf8(value)
        .ok()
        .filter(|v| !v.is_empty() && v.len() <= 20 && v.bytes().all(|b| b.is_ascii_digit()));
    digits
        .and_then(|d| d.parse::<u64>().ok())
        .ok_or_else(|| "a `Content-Length` that is not a length in bytes".to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frames(stream: &[u8]) -> Vec<Frame> {
        let mut reader = FrameReader::new(stream);
        let mut out = Vec::new();
        loop {
            match reader.next_frame() {
                Frame::End => return out,
                frame => out.push(frame),
            }
        }
    }

    fn body(text: &str) -> Frame {
        Frame::Body(text.as_bytes().to_vec())
    }

    const NEXT: &str = "Content-Length: 2\r\n\r\n{}";

    #[test]
    fn frames_are_read_in_turn() {
        let stream = format!("Content-Length: 3\r\nContent-Type: x\r\n\r\n[1]{NEXT}");
        assert_eq!(frames(stream.as_bytes()), vec![body("[1]"), body("{}")]);
    }

    #[test]
    fn an_announced_terabyte_is_refused_and_the_next_message_read() {
        for length in [
            "1000000000000",
            "18446744073709551615",
            "99999999999999999999999",
        ] {
            let stream = format!("Content-Length: {length}\r\n\r\nab{NEXT}");
            let got = frames(stream.as_bytes());
            assert_eq!(got.len(), 2, "{length}: {got:?}");
            assert!(matches!(&got[0], Frame::Malformed(_)), "{got:?}");
            assert_eq!(got[1], body("{}"));
        }
    }

    #[test]
    fn a_header_without_end_is_refused_holding_one_line_at_most() {
        let mut stream = vec![b'x'; 3 * MAX_HEADER_LINE];
        stream.extend_from_slice(NEXT.as_bytes());
        let got = frames(&stream);
        assert_eq!(got, vec![Frame::Malformed(too_long()), body("{}")]);
        let endless = vec![b'x'; 10 * MAX_HEADER_LINE];
        assert_eq!(frames(&endless), vec![Frame::Malformed(too_long())]);
    }

    #[test]
    fn headers_that_are_not_frames_are_refused() {
        let many = "X: y\r\n".repeat(MAX_HEADERS + 1);
        for bad in [
            "no colon\r\n\r\n",
            "Content-Length: -4\r\n\r\n",
            "\r\n",
            many.as_str(),
        ] {
            let stream = format!("{bad}{NEXT}");
            let got = frames(stream.as_bytes());
            assert!(matches!(&got[0], Frame::Malformed(_)), "{bad:?}: {got:?}");
            assert_eq!(got.last(), Some(&body("{}")), "{bad:?}");
        }
    }

    #[test]
    fn a_body_cut_short_ends_the_stream() {
        assert_eq!(frames(b"Content-Length: 10\r\n\r\nabc"), vec![]);
        let limit = format!("Content-Length: {MAX_BODY}\r\n\r\nab");
        assert_eq!(frames(limit.as_bytes()), vec![]);
    }
}
