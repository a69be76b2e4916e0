//! A machine's state rate cap on the fleet link: at most `rate` messages a second in all, each the
//! latest of its stream (older ones are superseded, never queued), the streams served in turn, so
//! that a 1 kHz cell costs the WAN what the setting says and the head office always sees the newest.

use std::time::{Duration, Instant};

/// The latest message of each stream, released no closer together than `1 / rate`.
#[derive(Debug)]
pub struct RateCap<T> {
    period: Duration,
    next: Option<Instant>,
    /// Per stream: its name, its pending (latest) message, when it was last released.
    streams: Vec<(String, Option<T>, Option<Instant>)>,
    superseded: u64,
}

impl<T> RateCap<T> {
    /// A cap of `rate_hz` (> 0) messages a second.
    pub fn new(rate_hz: f64) -> RateCap<T> {
        RateCap { period: Duration::from_secs_f64(1.0 / rate_hz), next: None, streams: Vec::new(), superseded: 0 }
    }

    /// Offer the latest message of `stream` (it replaces one not yet released); false, and the
    /// message not taken, for a new stream beyond [`crate::MAX_STREAMS`].
    pub fn offer(&mut self, stream: &str, msg: T) -> bool {
        let full = self.streams.len() >= crate::MAX_STREAMS;
        match self.streams.iter_mut().find(|(s, ..)| s == stream) {
            Some((_, pending, _)) => {
                if pending.replace(msg).is_some() {
                    self.superseded += 1;
                }
            }
            None if full => return false,
            None => self.streams.push((stream.to_string(), Some(msg), None)),
        }
        true
    }

    /// The message to send now, if the cap allows one and one is pending: the stream served least
    /// recently first.
    pub fn poll(&mut self, now: Instant) -> Option<T> {
        if matches!(self.next, Some(n) if now < n) {
            return None;
        }
        let (_, pending, last) = self.streams.iter_mut().filter(|(_, p, _)| p.is_some()).min_by_key(|(_, _, last)| *last)?;
        *last = Some(now);
        self.next = Some(now + self.period);
        pending.take()
    }

    /// The message [`poll`](Self::poll) released has left, at `at`: the next leaves a period after
    /// that. The receiver counts the rate on the send stamp the publisher writes as it sends, after
    /// the poll; a send delayed by a loaded machine would otherwise bring the next one closer than a
    /// period (11 statuses in one second at a 10 Hz cap, seen once in the fleet test).
    pub fn sent(&mut self, at: Instant) {
        let after = at + self.period;
        self.next = Some(self.next.map_or(after, |n| n.max(after)));
    }

    /// When [`poll`](Self::poll) may next release a message: `None` while nothing is pending (a
    /// loop waiting on it then waits for input, not for a release time long past).
    pub fn next_release(&self) -> Option<Instant> {
        if self.streams.iter().any(|(_, p, _)| p.is_some()) {
            Some(self.next.unwrap_or_else(Instant::now))
        } else {
            None
        }
    }

    /// Messages replaced by a newer one of their stream before release.
    pub fn superseded(&self) -> u64 {
        self.superseded
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two 1 kHz streams for 2 s through a 10 Hz cap: never two releases closer than 100 ms, no
    /// more than 10 in any second, the streams served in turn, and each release the newest sample.
    #[test]
    fn two_1_khz_streams_through_a_10_hz_cap() {
        let t0 = Instant::now();
        let mut cap = RateCap::new(10.0);
        let mut out: Vec<(Duration, &str, u32)> = Vec::new();
        for ms in 0..2000u32 {
            let now = t0 + Duration::from_millis(ms as u64);
            cap.offer("commanded", ("commanded", ms));
            cap.offer("simulated", ("simulated", ms));
            if let Some((s, at)) = cap.poll(now) {
                out.push((now - t0, s, at));
            }
        }
        assert_eq!(out.len(), 20);
        for w in out.windows(2) {
            assert!(w[1].0 - w[0].0 >= Duration::from_millis(100));
            assert_ne!(w[0].1, w[1].1, "served in turn");
        }
        for (at, _, ms) in &out {
            assert_eq!(at.as_millis() as u32, *ms, "the newest sample");
        }
        // Every sample is released, superseded, or still pending (one per stream) at the end.
        assert_eq!(cap.superseded(), 2 * 2000 - 20 - 2);
    }

    /// A send that ends late holds the next release a period after it: the stamps a publisher
    /// writes while sending stay a period apart however long the send took.
    #[test]
    fn a_late_send_holds_the_next_release() {
        let t = Instant::now();
        let mut cap = RateCap::new(10.0);
        cap.offer("a", 1);
        assert_eq!(cap.poll(t), Some(1));
        // The send ended 30 ms after the poll (its stamp written somewhere in between).
        cap.sent(t + Duration::from_millis(30));
        cap.offer("a", 2);
        assert_eq!(cap.poll(t + Duration::from_millis(100)), None);
        assert_eq!(cap.poll(t + Duration::from_millis(129)), None);
        assert_eq!(cap.poll(t + Duration::from_millis(130)), Some(2));
        // A send within its period changes nothing.
        cap.sent(t + Duration::from_millis(130));
        cap.offer("a", 3);
        assert_eq!(cap.next_release(), Some(t + Duration::from_millis(230)));
    }

    #[test]
    fn nothing_pending_releases_nothing() {
        let mut cap: RateCap<u8> = RateCap::new(5.0);
        assert_eq!(cap.poll(Instant::now()), None);
        assert_eq!(cap.next_release(), None);
        cap.offer("a", 1);
        assert!(cap.next_release().is_some());
        let t = Instant::now();
        assert_eq!(cap.poll(t), Some(1));
        assert_eq!(cap.poll(t + Duration::from_secs(1)), None);
        // Nothing pending: no release time to wait for, however long ago the last one was.
        assert_eq!(cap.next_release(), None);
        cap.offer("a", 2);
        assert_eq!(cap.next_release(), Some(t + Duration::from_millis(200)));
    }

    #[test]
    fn streams_beyond_the_ones_followed_are_not_taken() {
        let mut cap = RateCap::new(10.0);
        for k in 0..crate::MAX_STREAMS {
            assert!(cap.offer(&format!("/s{k}"), k));
        }
        assert!(!cap.offer("/one_more", 99));
        assert!(cap.offer("/s0", 100), "a stream followed still is");
        assert_eq!(cap.streams.len(), crate::MAX_STREAMS);
    }
}
