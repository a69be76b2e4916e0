//! MTConnect sources read live, over TCP: an adapter's SHDR stream (the agent's side of cppagent's
//! Adapter Agent Protocol: `* PING`, the adapter's `* PONG <ms>`, a connection silent for twice that
//! is dead) and an agent's REST service (MTConnect Part 1 §8: `/probe`, `/current`, then a streamed
//! `/sample?from=&interval=&heartbeat=`, continued `from` the next sequence after a reconnect, and
//! from `/current` again when the agent restarted or its buffer moved past it). Both reconnect on
//! their own and hand what they read to a callback as [`Event`]s.

use super::devices::{self, Device};
use super::http::{self, HttpError};
use super::shdr::ShdrReader;
use super::streams::{self, StreamsError};
use super::{axis_items, pick, AxisItems, UnitsOf, MAX_LINE};
use crate::source::{ByInstant, Event, Failure, KeepGoing, Retry, Stamp};
use crate::machine::Machine;
use std::collections::BTreeMap;
use std::io::{BufRead, BufReader, ErrorKind, Read, Write};
use std::net::{TcpStream, ToSocketAddrs};
use std::time::{Duration, Instant};

/// How often a blocked read wakes to check whether to stop.
const POLL: Duration = Duration::from_millis(100);
/// How long a connection attempt may take.
const CONNECT: Duration = Duration::from_secs(2);
/// A silent adapter that never answered a PING is dead after this long (cppagent's legacy timeout).
const LEGACY_TIMEOUT: Duration = Duration::from_secs(600);

fn connect(address: &str) -> std::io::Result<TcpStream> {
    let mut last = std::io::Error::new(ErrorKind::NotFound, format!("'{address}' resolves to no address"));
    for a in address.to_socket_addrs()? {
        match TcpStream::connect_timeout(&a, CONNECT) {
            Ok(s) => {
                s.set_nodelay(true)?;
                return Ok(s);
            }
            Err(e) => last = e,
        }
    }
    Err(last)
}

fn timed_out(e: &std::io::Error) -> bool {
    matches!(e.kind(), ErrorKind::WouldBlock | ErrorKind::TimedOut)
}

/// An adapter's SHDR stream over TCP, against the device description `devices`.
pub struct Adapter {
    pub address: String,
    pub devices: Vec<Device>,
    pub device: usize,
    pub items: AxisItems,
}

impl Adapter {
    /// An adapter at `address` (host:port) whose lines name `device` of `devices` (the only one if
    /// None); its axes found as [`axis_items`] finds them.
    pub fn new(address: &str, devices: Vec<Device>, device: Option<&str>, machine: &Machine, axis_map: &BTreeMap<String, String>) -> Result<Adapter, String> {
        let d = pick(&devices, device)?;
        let items = axis_items(d, machine, axis_map, UnitsOf::Adapter)?;
        let index = devices.iter().position(|x| std::ptr::eq(x, d)).unwrap_or(0);
        Ok(Adapter { address: address.to_string(), devices, device: index, items })
    }

    /// Read until `keep_going` says stop, reconnecting whenever the connection fails or ends.
    pub fn run(&self, keep_going: KeepGoing, on: &mut dyn FnMut(Event)) {
        let mut retry = Retry::new();
        let mut line = 0u64;
        while keep_going() {
            match connect(&self.address) {
                Ok(stream) => {
                    on(Event::Connected(format!("adapter {}", self.address)));
                    retry.reset();
                    let why = self.session(stream, &mut line, keep_going, on);
                    on(Event::Down(why));
                }
                Err(e) => on(Event::Down(format!("adapter {}: {e}", self.address))),
            }
            if !retry.back_off(keep_going) {
                return;
            }
        }
    }

    /// One connection: PING, lines to reports, until it ends; why it ended.
    fn session(&self, stream: TcpStream, line: &mut u64, keep_going: KeepGoing, on: &mut dyn FnMut(Event)) -> String {
        let device = &self.devices[self.device];
        let mut writer = match stream.try_clone() {
            Ok(w) => w,
            Err(e) => return format!("adapter {}: {e}", self.address),
        };
        if let Err(e) = stream.set_read_timeout(Some(POLL)) {
            return format!("adapter {}: {e}", self.address);
        }
        let mut reader = BufReader::new(stream);
        let mut state = ShdrReader::default();
        let mut buf = Vec::new();
        // The adapter's heartbeat, once it answered a PING.
        let mut heartbeat: Option<Duration> = None;
        let mut last_ping = Instant::now();
        let mut last_heard = Instant::now();
        if let Err(e) = writer.write_all(b"* PING\n") {
            return format!("adapter {}: {e}", self.address);
        }
        while keep_going() {
            let now = Instant::now();
            let limit = heartbeat.map_or(LEGACY_TIMEOUT, |h| h * 2);
            if now - last_heard > limit {
                return format!("adapter {}: silent for {:.1} s (heartbeat {:?})", self.address, (now - last_heard).as_secs_f64(), heartbeat);
            }
            if heartbeat.is_some_and(|h| now - last_ping >= h) {
                last_ping = now;
                if let Err(e) = writer.write_all(b"* PING\n") {
                    return format!("adapter {}: {e}", self.address);
                }
            }
            match (&mut reader).take(MAX_LINE as u64 + 1 - buf.len() as u64).read_until(b'\n', &mut buf) {
                Ok(0) if buf.is_empty() => return format!("adapter {}: closed the connection", self.address),
                Ok(_) if buf.last() != Some(&b'\n') && buf.len() <= MAX_LINE => {
                    // The connection ended within a line.
                    return format!("adapter {}: closed the connection within a line", self.address);
                }
                Ok(_) => {}
                Err(e) if timed_out(&e) => continue,
                Err(e) => return format!("adapter {}: {e}", self.address),
            }
            last_heard = Instant::now();
            *line += 1;
            if buf.len() > MAX_LINE {
                on(Event::Refused(format!("line {line}: longer than {MAX_LINE} bytes", line = *line)));
                return format!("adapter {}: a line longer than {MAX_LINE} bytes", self.address);
            }
            let text = String::from_utf8_lossy(&buf).trim_end_matches(['\n', '\r']).to_string();
            buf.clear();
            if let Some(ms) = text.strip_prefix("* PONG") {
                // A heartbeat past the legacy timeout would only wait longer for a dead adapter.
                heartbeat = ms.trim().parse::<u64>().ok().filter(|&ms| ms > 0).map(|ms| Duration::from_millis(ms).min(LEGACY_TIMEOUT));
                continue;
            }
            match super::shdr_report(&mut state, &text, *line, &self.devices, device, &self.items, Some(Stamp::now())) {
                Ok(Some(r)) => on(Event::Report(r)),
                Ok(None) => {}
                Err(e) => on(Event::Refused(e)),
            }
        }
        format!("adapter {}: stopped", self.address)
    }
}

/// An agent's base URL: `http://host[:port][/prefix]`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct AgentUrl {
    /// host:port to connect to.
    pub address: String,
    /// The Host header.
    pub host: String,
    /// The path before `/probe` (no trailing slash).
    pub prefix: String,
}

impl AgentUrl {
    pub fn parse(url: &str) -> Result<AgentUrl, String> {
        let rest = url.strip_prefix("http://").ok_or_else(|| {
            if url.starts_with("https://") {
                format!("'{url}': https is not read (put the agent behind plain http on the cell's network)")
            } else {
                format!("'{url}': an agent's URL starts http://")
            }
        })?;
        let (host, path) = rest.split_once('/').map_or((rest, ""), |(h, p)| (h, p));
        if host.is_empty() {
            return Err(format!("'{url}': no host"));
        }
        let address = if host.rsplit_once(':').is_some_and(|(_, p)| p.parse::<u16>().is_ok()) && !host.ends_with(']') { host.to_string() } else { format!("{host}:80") };
        let prefix = path.trim_end_matches('/');
        Ok(AgentUrl { address, host: host.to_string(), prefix: if prefix.is_empty() { String::new() } else { format!("/{prefix}") } })
    }
}

/// A request's outcome: the agent's answer, or why there is none.
#[derive(Debug, thiserror::Error)]
enum AgentError {
    #[error(transparent)]
    Http(#[from] HttpError),
    #[error(transparent)]
    Streams(#[from] StreamsError),
    #[error("{0}")]
    Other(String),
}

/// An agent's REST service, streamed.
pub struct Agent {
    pub url: AgentUrl,
    /// The device's name, its description and axis items (from `/probe`).
    pub device: String,
    pub items: AxisItems,
    /// `interval` and `heartbeat` asked of the stream, ms.
    pub interval_ms: u64,
    pub heartbeat_ms: u64,
}

impl Agent {
    /// Probe the agent at `url` (blocking): down (unreachable: worth retrying), or refused (the URL,
    /// the description, the device or its axes are wrong: retrying will not help).
    pub fn probe(url: &str, device: Option<&str>, machine: &Machine, axis_map: &BTreeMap<String, String>) -> Result<Agent, Failure> {
        let url = AgentUrl::parse(url).map_err(Failure::Refused)?;
        let at = format!("{}{}/probe", url.host, url.prefix);
        let body = match get(&url, &format!("{}/probe", url.prefix), None) {
            Ok(b) => b,
            Err(AgentError::Http(HttpError::Io(e))) => return Err(Failure::Down(format!("{at}: {e}"))),
            Err(AgentError::Http(HttpError::Closed(w))) => return Err(Failure::Down(format!("{at}: the connection closed {w}"))),
            Err(e) => return Err(Failure::Refused(format!("{at}: {e}"))),
        };
        let all = devices::parse(&String::from_utf8_lossy(&body)).map_err(|e| Failure::Refused(format!("{at}: {e}")))?;
        let d = pick(&all, device).map_err(Failure::Refused)?;
        let items = axis_items(d, machine, axis_map, UnitsOf::Agent).map_err(Failure::Refused)?;
        Ok(Agent { url, device: d.name.clone(), items, interval_ms: 0, heartbeat_ms: 10_000 })
    }

    fn path(&self, what: &str) -> String {
        format!("{}/{}/{what}", self.url.prefix, percent(&self.device))
    }

    /// Stream until `keep_going` says stop: `/current`, then `/sample` from its next sequence;
    /// reconnect from where the stream left off.
    pub fn run(&self, keep_going: KeepGoing, on: &mut dyn FnMut(Event)) {
        let mut retry = Retry::new();
        // Where to continue: (instance, next sequence).
        let mut at: Option<(u64, u64)> = None;
        while keep_going() {
            let why = match self.session(&mut at, keep_going, on, &mut retry) {
                Ok(()) => return,
                Err(e) => e,
            };
            on(Event::Down(format!("agent {}: {why}", self.url.host)));
            if !retry.back_off(keep_going) {
                return;
            }
        }
    }

    /// `/current` when there is nowhere to continue from; returns (instance, next sequence).
    fn current(&self, on: &mut dyn FnMut(Event)) -> Result<(u64, u64), AgentError> {
        let body = get(&self.url, &self.path("current"), None)?;
        let doc = streams::parse(&String::from_utf8_lossy(&body))?;
        self.emit(&doc.observations, on);
        Ok((doc.header.instance_id, doc.header.next_sequence))
    }

    fn session(&self, at: &mut Option<(u64, u64)>, keep_going: KeepGoing, on: &mut dyn FnMut(Event), retry: &mut Retry) -> Result<(), String> {
        let (instance, from) = match *at {
            Some(a) => a,
            None => {
                let a = self.current(on).map_err(|e| format!("{}: {e}", self.path("current")))?;
                *at = Some(a);
                a
            }
        };
        let path = format!("{}?from={from}&interval={}&heartbeat={}&count=1000", self.path("sample"), self.interval_ms, self.heartbeat_ms);
        let stream = connect(&self.url.address).map_err(|e| e.to_string())?;
        let timeout = Duration::from_millis(self.heartbeat_ms.saturating_mul(2)).max(Duration::from_secs(1));
        stream.set_read_timeout(Some(POLL)).map_err(|e| e.to_string())?;
        request(&stream, &self.url, &path).map_err(|e| e.to_string())?;
        let mut reader = BufReader::new(Watchdog { inner: stream, timeout, last: Instant::now(), keep_going });
        let head = http::read_head(&mut reader).map_err(|e| format!("{path}: {e}"))?;
        if head.code != 200 {
            let body = http::read_body(&head, &mut reader).unwrap_or_default();
            // An error document (OUT_OF_RANGE: the buffer moved past `from`): start again at /current.
            if let Err(e) = streams::parse(&String::from_utf8_lossy(&body)) {
                if !e.agent_codes().is_empty() {
                    on(Event::Gap { why: format!("{path}: {e}"), lost: None });
                    *at = None;
                    return Err(format!("{path}: {e}"));
                }
            }
            return Err(format!("{path}: HTTP {} {}", head.code, head.reason));
        }
        let Some(boundary) = head.boundary() else {
            return Err(format!("{path}: the answer is not a stream (Content-Type {:?})", head.header("content-type")));
        };
        on(Event::Connected(format!("agent {}{}: device {}, instance {instance}, from sequence {from}", self.url.host, self.url.prefix, self.device)));
        retry.reset();
        let body: Box<dyn Read + '_> = if head.chunked() { Box::new(http::Chunked::new(reader)) } else { Box::new(reader) };
        let mut parts = http::Parts::new(BufReader::new(body), &boundary);
        loop {
            let part = match parts.next_part() {
                Ok(Some(p)) => p,
                Ok(None) if !keep_going() => return Ok(()),
                Ok(None) => return Err(format!("{path}: the stream ended")),
                Err(_) if !keep_going() => return Ok(()),
                Err(e) => return Err(format!("{path}: {e}")),
            };
            let doc = match streams::parse(&String::from_utf8_lossy(&part)) {
                Ok(d) => d,
                Err(e) if !e.agent_codes().is_empty() => {
                    on(Event::Gap { why: format!("{path}: {e}"), lost: None });
                    *at = None;
                    return Err(format!("{path}: {e}"));
                }
                Err(e) => {
                    on(Event::Refused(format!("{path}: a part: {e}")));
                    continue;
                }
            };
            let (inst, next) = at.unwrap_or((instance, from));
            if doc.header.instance_id != inst {
                on(Event::Gap { why: format!("the agent restarted (instance {inst} -> {})", doc.header.instance_id), lost: None });
                *at = None;
                return Err("the agent restarted".into());
            }
            if let Some(first) = doc.observations.iter().map(|o| o.sequence).min() {
                if first > next {
                    on(Event::Gap { why: format!("sequences {next}-{} are no longer in the agent's buffer", first - 1), lost: Some(first - next) });
                }
            }
            self.emit(&doc.observations, on);
            *at = Some((inst, doc.header.next_sequence.max(next)));
        }
    }

    /// The axes' observations as reports: in time order, those of one timestamp together.
    fn emit(&self, observations: &[streams::Observation], on: &mut dyn FnMut(Event)) {
        let mut gathered = ByInstant::default();
        for o in observations {
            let Some(i) = self.items.axis_of(&o.data_item_id) else { continue };
            match self.items.value(i, &o.value) {
                Ok(Some(v)) => gathered.push(o.stamp, i, v),
                Ok(None) => {}
                Err(e) => on(Event::Refused(format!("sequence {}: {e}", o.sequence))),
            }
        }
        gathered.drain(|r| on(Event::Report(r)));
    }
}

/// Percent-encode a path segment (a device name may hold spaces).
fn percent(s: &str) -> String {
    s.bytes().map(|b| if b.is_ascii_alphanumeric() || b"-._~".contains(&b) { (b as char).to_string() } else { format!("%{b:02X}") }).collect()
}

fn request(mut stream: &TcpStream, url: &AgentUrl, path: &str) -> std::io::Result<()> {
    stream.write_all(format!("GET {path} HTTP/1.1\r\nHost: {}\r\nAccept: application/xml\r\nUser-Agent: fiveaxis\r\nConnection: close\r\n\r\n", url.host).as_bytes())
}

/// A whole answer's body (a `/probe` or `/current`), within `timeout` (default 10 s).
fn get(url: &AgentUrl, path: &str, timeout: Option<Duration>) -> Result<Vec<u8>, AgentError> {
    let stream = connect(&url.address).map_err(HttpError::from)?;
    stream.set_read_timeout(Some(timeout.unwrap_or(Duration::from_secs(10)))).map_err(HttpError::from)?;
    request(&stream, url, path).map_err(HttpError::from)?;
    let mut reader = BufReader::new(stream);
    let head = http::read_head(&mut reader)?;
    let body = http::read_body(&head, &mut reader)?;
    if head.code != 200 {
        // An MTConnectError document says why.
        return match streams::parse(&String::from_utf8_lossy(&body)) {
            Err(e @ StreamsError::Agent(_)) => Err(e.into()),
            _ => Err(AgentError::Other(format!("HTTP {} {}", head.code, head.reason))),
        };
    }
    Ok(body)
}

/// A socket read with a short timeout retried until the stream has been silent for `timeout` (then
/// an error), or the caller asks to stop (then the end of the stream).
struct Watchdog<'a> {
    inner: TcpStream,
    timeout: Duration,
    last: Instant,
    keep_going: KeepGoing<'a>,
}

impl Read for Watchdog<'_> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        loop {
            if !(self.keep_going)() {
                return Ok(0);
            }
            match self.inner.read(buf) {
                Ok(n) => {
                    self.last = Instant::now();
                    return Ok(n);
                }
                Err(e) if timed_out(&e) => {
                    if self.last.elapsed() > self.timeout {
                        return Err(std::io::Error::new(ErrorKind::TimedOut, format!("silent for {:.1} s (heartbeat not kept)", self.last.elapsed().as_secs_f64())));
                    }
                }
                Err(e) if e.kind() == ErrorKind::Interrupted => {}
                Err(e) => return Err(e),
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn agent_urls() {
        assert_eq!(AgentUrl::parse("http://agent:5000").unwrap(), AgentUrl { address: "agent:5000".into(), host: "agent:5000".into(), prefix: String::new() });
        assert_eq!(AgentUrl::parse("http://10.0.0.5/mtc/").unwrap(), AgentUrl { address: "10.0.0.5:80".into(), host: "10.0.0.5".into(), prefix: "/mtc".into() });
        assert!(AgentUrl::parse("https://a").unwrap_err().contains("https"));
        assert!(AgentUrl::parse("agent:5000").is_err());
        assert_eq!(percent("C600 U/1"), "C600%20U%2F1");
    }
}
