//! What an MTConnect agent's HTTP answers need, over any byte stream (no sockets here): an HTTP/1.1
//! response head, a chunked body (RFC 9112 §7.1), and the parts of a streamed `/sample`, a
//! multipart body whose parts each carry one document (cppagent 2: `multipart/mixed;boundary=...`
//! inside chunks; agents of 1.x: `multipart/x-mixed-replace` without; each part `--boundary`,
//! `Content-type`, `Content-length`, a blank line, the document). Every read is bounded.

use std::io::{self, BufRead, Read};

/// Longest head or header line read (bytes).
pub const MAX_HEAD: usize = 64 * 1024;
/// Largest document (a body or a part) taken (bytes): a `/probe` of a large shop's agent is a few MB.
pub const MAX_DOCUMENT: usize = 64 * 1024 * 1024;

/// Why an answer was refused.
#[derive(Debug, thiserror::Error)]
pub enum HttpError {
    #[error(transparent)]
    Io(#[from] io::Error),
    #[error("the connection closed {0}")]
    Closed(&'static str),
    #[error("{what} longer than {limit} bytes")]
    TooLong { what: &'static str, limit: usize },
    #[error("not an HTTP/1.x status line: '{0}'")]
    Status(String),
    #[error("HTTP {code} {reason}")]
    NotOk { code: u16, reason: String, body: String },
    #[error("bad chunk size line '{0}'")]
    Chunk(String),
    #[error("multipart: {0}")]
    Multipart(String),
}

/// A response's status and headers.
#[derive(Debug, Clone, PartialEq)]
pub struct Head {
    pub code: u16,
    pub reason: String,
    headers: Vec<(String, String)>,
}

impl Head {
    /// A header's value (names compare without case).
    pub fn header(&self, name: &str) -> Option<&str> {
        self.headers.iter().find(|(n, _)| n.eq_ignore_ascii_case(name)).map(|(_, v)| v.as_str())
    }

    /// The body is chunked (`Transfer-Encoding: chunked`).
    pub fn chunked(&self) -> bool {
        self.header("transfer-encoding").is_some_and(|v| v.split(',').any(|t| t.trim().eq_ignore_ascii_case("chunked")))
    }

    /// The `boundary` of a multipart `Content-Type`, if it is one.
    pub fn boundary(&self) -> Option<String> {
        let ct = self.header("content-type")?;
        if !ct.trim_start().to_ascii_lowercase().starts_with("multipart/") {
            return None;
        }
        ct.split(';').skip(1).find_map(|p| {
            let (k, v) = p.split_once('=')?;
            k.trim().eq_ignore_ascii_case("boundary").then(|| v.trim().trim_matches('"').to_string())
        })
    }
}

/// Read one line (CRLF or LF) of at most [`MAX_HEAD`] bytes, without its end; None at end of stream.
fn line<R: BufRead>(r: &mut R, what: &'static str) -> Result<Option<String>, HttpError> {
    let mut buf = Vec::new();
    let n = r.take(MAX_HEAD as u64 + 1).read_until(b'\n', &mut buf)?;
    if n == 0 {
        return Ok(None);
    }
    if buf.last() != Some(&b'\n') {
        return if buf.len() > MAX_HEAD { Err(HttpError::TooLong { what, limit: MAX_HEAD }) } else { Err(HttpError::Closed("within a line")) };
    }
    buf.pop();
    if buf.last() == Some(&b'\r') {
        buf.pop();
    }
    Ok(Some(String::from_utf8_lossy(&buf).into_owned()))
}

/// Header lines up to the blank line.
fn headers<R: BufRead>(r: &mut R) -> Result<Vec<(String, String)>, HttpError> {
    let mut out = Vec::new();
    let mut total = 0;
    loop {
        let l = line(r, "a header")?.ok_or(HttpError::Closed("within the headers"))?;
        if l.is_empty() {
            return Ok(out);
        }
        total += l.len();
        if total > MAX_HEAD {
            return Err(HttpError::TooLong { what: "the headers", limit: MAX_HEAD });
        }
        if let Some((k, v)) = l.split_once(':') {
            out.push((k.trim().to_string(), v.trim().to_string()));
        }
    }
}

/// Read a response head (skipping `100 Continue` heads).
pub fn read_head<R: BufRead>(r: &mut R) -> Result<Head, HttpError> {
    loop {
        let status = line(r, "the status line")?.ok_or(HttpError::Closed("before the status line"))?;
        let mut parts = status.splitn(3, ' ');
        let (version, code) = (parts.next().unwrap_or(""), parts.next().unwrap_or(""));
        let code: u16 = match (version.starts_with("HTTP/1."), code.parse()) {
            (true, Ok(c)) => c,
            _ => return Err(HttpError::Status(status.chars().take(80).collect())),
        };
        let reason = parts.next().unwrap_or("").to_string();
        let headers = headers(r)?;
        if code != 100 {
            return Ok(Head { code, reason, headers });
        }
    }
}

/// A chunked body as a plain byte stream: it ends at the last chunk.
pub struct Chunked<R> {
    inner: R,
    /// Bytes left in the current chunk; None before a chunk's size line.
    left: Option<u64>,
    done: bool,
}

impl<R: BufRead> Chunked<R> {
    pub fn new(inner: R) -> Self {
        Chunked { inner, left: None, done: false }
    }
}

impl<R: BufRead> Read for Chunked<R> {
    fn read(&mut self, out: &mut [u8]) -> io::Result<usize> {
        let to_io = |e: HttpError| match e {
            HttpError::Io(e) => e,
            e => io::Error::new(io::ErrorKind::InvalidData, e.to_string()),
        };
        loop {
            if self.done || out.is_empty() {
                return Ok(0);
            }
            match self.left {
                None => {
                    let l = line(&mut self.inner, "a chunk size line").map_err(to_io)?.ok_or_else(|| to_io(HttpError::Closed("before a chunk")))?;
                    let size = l.split(';').next().unwrap_or("").trim();
                    let n = u64::from_str_radix(size, 16).map_err(|_| to_io(HttpError::Chunk(l.chars().take(40).collect())))?;
                    if n == 0 {
                        // The trailer, to its blank line.
                        headers(&mut self.inner).map_err(to_io)?;
                        self.done = true;
                        return Ok(0);
                    }
                    self.left = Some(n);
                }
                Some(0) => {
                    let l = line(&mut self.inner, "a chunk's end").map_err(to_io)?;
                    if l.as_deref() != Some("") {
                        return Err(to_io(HttpError::Chunk("no CRLF after a chunk's data".into())));
                    }
                    self.left = None;
                }
                Some(left) => {
                    let want = out.len().min(usize::try_from(left).unwrap_or(usize::MAX));
                    let n = self.inner.read(&mut out[..want])?;
                    if n == 0 {
                        return Err(to_io(HttpError::Closed("within a chunk")));
                    }
                    self.left = Some(left - n as u64);
                    return Ok(n);
                }
            }
        }
    }
}

/// Read a whole body of at most [`MAX_DOCUMENT`] bytes (chunked, of `Content-Length`, or to the
/// connection's end).
pub fn read_body<R: BufRead>(head: &Head, r: &mut R) -> Result<Vec<u8>, HttpError> {
    let mut body = Vec::new();
    let limit = MAX_DOCUMENT as u64 + 1;
    if head.chunked() {
        Chunked::new(r).take(limit).read_to_end(&mut body)?;
    } else if let Some(len) = head.header("content-length") {
        let len: u64 = len.trim().parse().map_err(|_| HttpError::Status(format!("Content-Length '{len}'")))?;
        if len > MAX_DOCUMENT as u64 {
            return Err(HttpError::TooLong { what: "the body", limit: MAX_DOCUMENT });
        }
        r.take(len).read_to_end(&mut body)?;
        if (body.len() as u64) < len {
            return Err(HttpError::Closed("within the body"));
        }
    } else {
        r.take(limit).read_to_end(&mut body)?;
    }
    if body.len() > MAX_DOCUMENT {
        return Err(HttpError::TooLong { what: "the body", limit: MAX_DOCUMENT });
    }
    Ok(body)
}

/// The parts of a multipart body, one document at a time.
pub struct Parts<R> {
    inner: R,
    delimiter: String,
    /// A part without a length ended at a delimiter already read: Some(true) a next part's, Some(false)
    /// the closing one.
    read_delimiter: Option<bool>,
}

impl<R: BufRead> Parts<R> {
    pub fn new(inner: R, boundary: &str) -> Self {
        Parts { inner, delimiter: format!("--{boundary}"), read_delimiter: None }
    }

    /// Which delimiter a line is: Some(true) a part's, Some(false) the closing one.
    fn delimiter_of(&self, line: &str) -> Option<bool> {
        let l = line.trim_end();
        let rest = l.strip_prefix(self.delimiter.as_str())?;
        match rest {
            "" => Some(true),
            "--" => Some(false),
            _ => None,
        }
    }

    /// The next part's body; None when the body ends (the closing delimiter or the stream's end).
    pub fn next_part(&mut self) -> Result<Option<Vec<u8>>, HttpError> {
        // Up to the delimiter line (a preamble, or the CRLF after the previous part).
        match self.read_delimiter.take() {
            Some(false) => return Ok(None),
            Some(true) => {}
            None => loop {
                let Some(l) = line(&mut self.inner, "a line between parts")? else { return Ok(None) };
                match self.delimiter_of(&l) {
                    Some(true) => break,
                    Some(false) => return Ok(None),
                    None => {}
                }
            },
        }
        let headers = headers(&mut self.inner)?;
        let length = headers.iter().find(|(n, _)| n.eq_ignore_ascii_case("content-length")).map(|(_, v)| v.trim().to_string());
        let mut body = Vec::new();
        match length {
            Some(len) => {
                let len: u64 = len.parse().map_err(|_| HttpError::Multipart(format!("Content-length '{len}'")))?;
                if len > MAX_DOCUMENT as u64 {
                    return Err(HttpError::TooLong { what: "a part", limit: MAX_DOCUMENT });
                }
                (&mut self.inner).take(len).read_to_end(&mut body)?;
                if (body.len() as u64) < len {
                    return Err(HttpError::Closed("within a part"));
                }
            }
            // No length: the part runs to the next delimiter line.
            None => loop {
                let mut l = Vec::new();
                let n = (&mut self.inner).take(MAX_HEAD as u64).read_until(b'\n', &mut l)?;
                if n == 0 {
                    return Err(HttpError::Closed("within a part"));
                }
                if let Some(more) = self.delimiter_of(&String::from_utf8_lossy(&l)) {
                    self.read_delimiter = Some(more);
                    // The CRLF before a delimiter belongs to it.
                    if body.last() == Some(&b'\n') {
                        body.pop();
                        if body.last() == Some(&b'\r') {
                            body.pop();
                        }
                    }
                    break;
                }
                body.extend_from_slice(&l);
                if body.len() > MAX_DOCUMENT {
                    return Err(HttpError::TooLong { what: "a part", limit: MAX_DOCUMENT });
                }
            },
        }
        Ok(Some(body))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::{BufReader, Cursor};

    /// A streamed /sample as cppagent 2 writes it (session_impl.cpp: beginStreaming, writeChunk):
    /// chunked, each chunk one part with its length.
    #[test]
    fn a_cppagent_stream() {
        let part = |doc: &str| format!("--B1\r\nContent-type: text/xml\r\nContent-length: {}\r\n\r\n{doc}\r\n", doc.len());
        let chunk = |s: &str| format!("{:x}\r\n{s}\r\n", s.len());
        let text = format!(
            "HTTP/1.1 200 OK\r\nServer: MTConnectAgent\r\nConnection: close\r\nContent-Type: multipart/mixed;boundary=B1\r\nTransfer-Encoding: chunked\r\n\r\n{}{}0\r\n\r\n",
            chunk(&part("<a>1</a>")),
            chunk(&part("<b>\r\n2</b>"))
        );
        let mut r = BufReader::new(Cursor::new(text.into_bytes()));
        let head = read_head(&mut r).unwrap();
        assert_eq!((head.code, head.chunked(), head.boundary().as_deref()), (200, true, Some("B1")));
        let mut parts = Parts::new(BufReader::new(Chunked::new(r)), "B1");
        assert_eq!(parts.next_part().unwrap().unwrap(), b"<a>1</a>");
        assert_eq!(parts.next_part().unwrap().unwrap(), b"<b>\r\n2</b>");
        assert_eq!(parts.next_part().unwrap(), None);
    }

    /// An agent of 1.x: x-mixed-replace, not chunked; a part without a length runs to the next
    /// delimiter.
    #[test]
    fn parts_without_lengths_and_a_closing_delimiter() {
        let text = "preamble\r\n--xyz\r\nContent-type: text/xml\r\n\r\n<a/>\r\n--xyz\r\n\r\n<b/>\r\n--xyz--\r\n";
        let mut parts = Parts::new(BufReader::new(Cursor::new(text)), "xyz");
        assert_eq!(parts.next_part().unwrap().unwrap(), b"<a/>");
        assert_eq!(parts.next_part().unwrap().unwrap(), b"<b/>");
        assert_eq!(parts.next_part().unwrap(), None);
        let head = Head { code: 200, reason: "OK".into(), headers: vec![("content-type".into(), "multipart/x-mixed-replace; boundary=\"xyz\"".into())] };
        assert_eq!(head.boundary().as_deref(), Some("xyz"));
    }

    #[test]
    fn refusals() {
        let mut r = BufReader::new(Cursor::new("SSH-2.0-OpenSSH\r\n"));
        assert!(matches!(read_head(&mut r), Err(HttpError::Status(_))));
        let mut c = Chunked::new(BufReader::new(Cursor::new("zz\r\n")));
        let e = c.read(&mut [0; 8]).unwrap_err();
        assert!(e.to_string().contains("bad chunk size line 'zz'"), "{e}");
        // A part longer than the stream: closed, not a short document.
        let mut parts = Parts::new(BufReader::new(Cursor::new("--b\r\nContent-length: 99\r\n\r\n<a/>")), "b");
        assert!(matches!(parts.next_part(), Err(HttpError::Closed(_))));
        let long = format!("HTTP/1.1 200 OK\r\nX: {}\r\n\r\n", "a".repeat(MAX_HEAD + 10));
        assert!(matches!(read_head(&mut BufReader::new(Cursor::new(long))), Err(HttpError::TooLong { .. })));
    }
}
