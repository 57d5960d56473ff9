//! The head of an HTTP/1.1 request as the service tests write it by hand: JSON unless a
//! `Content-Type` among `headers` says otherwise, one request per connection.

/// `METHOD PATH HTTP/1.1` and the headers of a body of `length` bytes.
pub fn request_head(method: &str, path: &str, headers: &[&str], length: usize) -> String {
    let typed = headers
        .iter()
        .any(|h| h.to_ascii_lowercase().starts_with("content-type:"));
    let mut extra = String::new();
    if !typed {
        extra.push_str("Content-Type: application/json\r\n");
    }
    for h in headers {
        extra.push_str(h);
        extra.push_str("\r\n");
    }
    format!(
        "{method} {path} HTTP/1.1\r\nHost: test\r\n{extra}Content-Length: {length}\r\nConnection: close\r\n\r\n"
    )
}
