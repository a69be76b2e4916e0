//! A machine's own interface read live, whatever its protocol (an MTConnect agent or adapter, an OPC UA
//! server): the axis positions it reports at each instant, what a reader tells its user as it goes
//! (connected, a report, a refusal, down, a gap), how it waits before connecting again, and how a
//! bridge republishes change-only reports so that a late subscriber learns every axis.

use crate::machine::AXES;
use std::time::{Duration, Instant};

/// An instant in UTC: seconds since the Unix epoch and nanoseconds (a value's own timestamp, as the
/// source gives it).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub struct Stamp {
    pub sec: i64,
    pub nanosec: u32,
}

impl Stamp {
    /// The wall clock now.
    pub fn now() -> Stamp {
        let d = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).unwrap_or_default();
        Stamp { sec: i64::try_from(d.as_secs()).unwrap_or(i64::MAX), nanosec: d.subsec_nanos() }
    }

    /// ISO 8601 in UTC as adapters write it: `2022-08-08T13:51:34.7167146Z` (fraction optional, up
    /// to nine digits; `Z`, `+HH:MM`, `-HH:MM` or nothing, taken as UTC).
    pub fn parse(text: &str) -> Option<Stamp> {
        let b = text.as_bytes();
        let num = |r: std::ops::Range<usize>| -> Option<i64> {
            let s = text.get(r)?;
            (!s.is_empty() && s.bytes().all(|c| c.is_ascii_digit())).then(|| s.parse().ok())?
        };
        if b.len() < 19 || b[4] != b'-' || b[7] != b'-' || !matches!(b[10], b'T' | b' ') || b[13] != b':' || b[16] != b':' {
            return None;
        }
        let (y, mo, d, h, mi, s) = (num(0..4)?, num(5..7)?, num(8..10)?, num(11..13)?, num(14..16)?, num(17..19)?);
        if !(1..=12).contains(&mo) || !(1..=31).contains(&d) || h > 23 || mi > 59 || s > 60 {
            return None;
        }
        let mut k = 19;
        let mut nanosec = 0u32;
        if b.get(k) == Some(&b'.') {
            let start = k + 1;
            k = start;
            while k < b.len() && b[k].is_ascii_digit() {
                k += 1;
            }
            let digits = &text[start..k];
            if digits.is_empty() {
                return None;
            }
            let mut scaled = 0u64;
            for (i, c) in digits.bytes().enumerate() {
                if i < 9 {
                    scaled = scaled * 10 + u64::from(c - b'0');
                }
            }
            for _ in digits.len()..9 {
                scaled *= 10;
            }
            nanosec = scaled as u32;
        }
        let offset = match &text[k..] {
            "" | "Z" => 0,
            tz if tz.len() == 6 && (tz.starts_with('+') || tz.starts_with('-')) && tz.as_bytes()[3] == b':' => {
                let (oh, om) = (num(k + 1..k + 3)?, num(k + 4..k + 6)?);
                let sign = if tz.starts_with('-') { -1 } else { 1 };
                sign * (oh * 3600 + om * 60)
            }
            _ => return None,
        };
        // Days from the civil date (H. Hinnant's days_from_civil).
        let y = if mo <= 2 { y - 1 } else { y };
        let era = y.div_euclid(400);
        let yoe = y - era * 400;
        let mp = (mo + 9) % 12;
        let doy = (153 * mp + 2) / 5 + d - 1;
        let doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
        let days = era * 146_097 + doe - 719_468;
        Some(Stamp { sec: days * 86_400 + h * 3600 + mi * 60 + s - offset, nanosec })
    }

    pub fn as_secs(self) -> f64 {
        self.sec as f64 + f64::from(self.nanosec) * 1e-9
    }
}

/// Axis positions reported at one instant (SI, None where not reported or UNAVAILABLE).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxisReport {
    /// Where it came from: an SHDR line's number (0 for a source without lines).
    pub line: u64,
    pub stamp: Stamp,
    pub values: [Option<f64>; AXES],
}

/// What a source tells its user.
#[derive(Debug, Clone, PartialEq)]
pub enum Event {
    /// Connected (again): what to, and where it starts.
    Connected(String),
    /// Axis positions at one instant.
    Report(AxisReport),
    /// Something read was refused (named by line or sequence); the stream goes on.
    Refused(String),
    /// The connection failed or ended; it is retried.
    Down(String),
    /// Observations the source no longer has: an agent whose buffer moved past the sequence to
    /// continue from, or that restarted (`lost`: how many sequence numbers, when known).
    Gap { why: String, lost: Option<u64> },
}

/// Whether to go on (a reader asks at least every 100 ms).
pub type KeepGoing<'a> = &'a dyn Fn() -> bool;

/// Why a reader gave up on a connection: `Down` (it failed or was lost: try again) or `Refused` (the
/// source is not what was asked for: no such device or axes, no endpoint of the security asked, a
/// refused identity; trying again will not help).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum Failure {
    #[error("{0}")]
    Down(String),
    #[error("{0}")]
    Refused(String),
}

/// Waits between connection attempts: 0.2 s, doubled up to 2 s, back to the first once connected.
#[derive(Debug, Clone, Copy)]
pub struct Retry {
    wait: Duration,
}

impl Retry {
    const FIRST: Duration = Duration::from_millis(200);
    const LAST: Duration = Duration::from_secs(2);

    pub fn new() -> Retry {
        Retry { wait: Self::FIRST }
    }

    /// Connected: the next wait is the first again.
    pub fn reset(&mut self) {
        self.wait = Self::FIRST;
    }

    /// Sleep before the next attempt, waking every 50 ms to ask `keep_going`; false if asked to stop.
    pub fn back_off(&mut self, keep_going: KeepGoing) -> bool {
        let until = Instant::now() + self.wait;
        self.wait = (self.wait * 2).min(Self::LAST);
        while Instant::now() < until {
            if !keep_going() {
                return false;
            }
            std::thread::sleep(Duration::from_millis(50).min(until.saturating_duration_since(Instant::now())));
        }
        keep_going()
    }
}

impl Default for Retry {
    fn default() -> Self {
        Retry::new()
    }
}

/// What a change-only bridge last published per axis: a still axis is restated once it has gone
/// unreported for a while (a subscriber that joins later learns where it stands; its value holds at
/// the message's instant, since the source reports every change), and a report that is not newer
/// than what went out and repeats held values (an agent's `/current` after a reconnection) is
/// dropped.
#[derive(Debug, Clone)]
pub struct Restater {
    /// Per axis: its value and the stamp it was last published at (s).
    axes: [Option<(f64, f64)>; AXES],
    /// The newest stamp published (s).
    last: Option<f64>,
    /// Restate an axis unreported this long (s; 0: never).
    restate_after: f64,
}

impl Restater {
    pub fn new(restate_after: f64) -> Restater {
        Restater { axes: [None; AXES], last: None, restate_after }
    }

    /// The report to publish for `r` (None: it repeats what was published), with the still axes
    /// restated, and how many were.
    pub fn next(&mut self, r: &AxisReport) -> Option<(AxisReport, u64)> {
        let t = r.stamp.as_secs();
        if self.last.is_some_and(|l| t <= l) {
            let same = r.values.iter().enumerate().all(|(i, v)| v.is_none_or(|v| self.axes[i].is_some_and(|(h, _)| h == v)));
            if same {
                return None;
            }
        }
        let mut out = *r;
        let mut restated = 0;
        for (i, held) in self.axes.iter_mut().enumerate() {
            match (r.values[i], held.as_mut()) {
                (Some(v), _) => *held = Some((v, t)),
                (None, Some((v, at))) if self.restate_after > 0.0 && t - *at >= self.restate_after => {
                    out.values[i] = Some(*v);
                    *at = t;
                    restated += 1;
                }
                _ => {}
            }
        }
        self.last = Some(self.last.map_or(t, |l| l.max(t)));
        Some((out, restated))
    }
}

/// Axis values gathered as they arrive, each at its own timestamp (an OPC UA subscription's data
/// changes, several per publish and item by item; an agent's document, component by component), and
/// handed on as axis reports in time order, those of one timestamp together.
#[derive(Debug, Default)]
pub struct ByInstant {
    pending: Vec<(Stamp, usize, f64)>,
}

impl ByInstant {
    /// Take axis `axis`'s value (SI) sampled at `stamp`.
    pub fn push(&mut self, stamp: Stamp, axis: usize, value: f64) {
        if axis < AXES {
            self.pending.push((stamp, axis, value));
        }
    }

    pub fn is_empty(&self) -> bool {
        self.pending.is_empty()
    }

    /// Everything gathered, as reports in time order (an axis reported twice at one instant keeps
    /// its last value).
    pub fn drain(&mut self, mut on: impl FnMut(AxisReport)) {
        self.pending.sort_by_key(|p| p.0);
        let mut report: Option<AxisReport> = None;
        for (stamp, axis, value) in self.pending.drain(..) {
            match report.as_mut() {
                Some(r) if r.stamp == stamp => r.values[axis] = Some(value),
                _ => {
                    if let Some(r) = report.take() {
                        on(r);
                    }
                    let mut values = [None; AXES];
                    values[axis] = Some(value);
                    report = Some(AxisReport { line: 0, stamp, values });
                }
            }
        }
        if let Some(r) = report {
            on(r);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn report(t: f64, values: [Option<f64>; AXES]) -> AxisReport {
        AxisReport { line: 0, stamp: Stamp { sec: t.floor() as i64, nanosec: ((t - t.floor()) * 1e9).round() as u32 }, values }
    }

    #[test]
    fn timestamps() {
        // 2022-08-08T13:51:34Z is 1659966694 s after the epoch (date -u -d ... +%s).
        assert_eq!(Stamp::parse("2022-08-08T13:51:34.7167146Z"), Some(Stamp { sec: 1_659_966_694, nanosec: 716_714_600 }));
        assert_eq!(Stamp::parse("2026-01-01T00:00:00Z"), Some(Stamp { sec: 1_767_225_600, nanosec: 0 }));
        assert_eq!(Stamp::parse("2026-01-01T01:00:00+01:00"), Some(Stamp { sec: 1_767_225_600, nanosec: 0 }));
        assert_eq!(Stamp::parse("2000-02-29T00:00:00.5"), Some(Stamp { sec: 951_782_400, nanosec: 500_000_000 }));
        for bad in ["", "12.5", "2022-13-01T00:00:00Z", "2022-08-08T13:51:34.Z", "2022-08-08T13:51:34Q", "2022-08-08X13:51:34"] {
            assert_eq!(Stamp::parse(bad), None, "{bad}");
        }
    }

    #[test]
    fn still_axes_are_restated_and_repeats_dropped() {
        let mut r = Restater::new(1.0);
        // Every axis once (a /current), then X alone at 3 Hz.
        assert_eq!(r.next(&report(10.0, [Some(1.0), Some(2.0), Some(3.0), Some(4.0), Some(5.0)])).unwrap().1, 0);
        let (out, n) = r.next(&report(10.4, [Some(1.1), None, None, None, None])).unwrap();
        assert_eq!((out.values, n), ([Some(1.1), None, None, None, None], 0));
        r.next(&report(10.7, [Some(1.2), None, None, None, None])).unwrap();
        // 1 s after they were published, the four still axes ride along with X's report.
        let (out, n) = r.next(&report(11.0, [Some(1.3), None, None, None, None])).unwrap();
        assert_eq!((out.values, n), ([Some(1.3), Some(2.0), Some(3.0), Some(4.0), Some(5.0)], 4));
        let (out, _) = r.next(&report(11.3, [Some(1.4), None, None, None, None])).unwrap();
        assert_eq!(out.values, [Some(1.4), None, None, None, None]);
        // A reconnection's /current: older stamps, values held: dropped. A changed value is not.
        assert!(r.next(&report(10.0, [None, Some(2.0), Some(3.0), None, None])).is_none());
        assert!(r.next(&report(11.3, [Some(1.4), None, None, None, None])).is_none());
        assert!(r.next(&report(11.2, [None, Some(2.5), None, None, None])).is_some());
        // Never restated when turned off.
        let mut off = Restater::new(0.0);
        off.next(&report(1.0, [Some(1.0), Some(2.0), None, None, None]));
        assert_eq!(off.next(&report(9.0, [Some(1.5), None, None, None, None])).unwrap().1, 0);
    }

    #[test]
    fn notifications_in_time_order_grouped_by_instant() {
        let s = |ms: i64| Stamp { sec: ms / 1000, nanosec: (ms % 1000) as u32 * 1_000_000 };
        let mut n = ByInstant::default();
        // One publish: each item's queue in turn (X's two samples, then Y's).
        n.push(s(100), 0, 1.0);
        n.push(s(200), 0, 2.0);
        n.push(s(100), 1, 10.0);
        n.push(s(200), 1, 20.0);
        let mut out = Vec::new();
        n.drain(|r| out.push(r));
        assert_eq!(out.len(), 2);
        assert_eq!(out[0].values, [Some(1.0), Some(10.0), None, None, None]);
        assert_eq!(out[1].values, [Some(2.0), Some(20.0), None, None, None]);
        assert!(out[0].stamp < out[1].stamp && n.is_empty());
    }
}
