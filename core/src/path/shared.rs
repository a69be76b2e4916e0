//! One read of a segment stream for two threads: `fiveaxis run`'s commander and its simulator each
//! need every segment of the program, at their own pace. The reader ahead reads (parses and plans)
//! the next segments from the one stream and keeps them until the other has taken them too, so the
//! program is parsed and segmented once instead of twice.
//!
//! Memory stays bounded whatever the distance between the two: past [`KEPT_SEGMENTS`] kept, the reader
//! behind is detached and reads a second copy of the stream of its own, skipped to where it is (what
//! both did before). Neither reader ever waits for the other, so no pacing between the two threads
//! can deadlock on it.
//!
//! ```
//! use fiveaxis_core::machine::Machine;
//! use fiveaxis_core::path::{PathOptions, SegmentStream, SharedRead};
//! use fiveaxis_core::program::{BlockStream, Dialect, ReadOptions};
//! let machine = Machine::hermle_c600u();
//! let text: String = (0..500).map(|i| format!("{} 0 0 0.1 0 0.995 1000\n", i as f64 * 0.1)).collect();
//! let open = || SegmentStream::new(BlockStream::from_text(&text, Some(Dialect::Cl), "raster", &ReadOptions::default()), &machine, &PathOptions::default());
//! let shared = SharedRead::new(open());
//! // Each side can open the program again, should it fall too far behind the other.
//! let (mut a, mut b) = (shared.reader(0, || Some(open())), shared.reader(1, || Some(open())));
//! let first = a.next().expect("a segment");
//! assert_eq!(b.by_ref().count(), 499);
//! assert_eq!(a.count(), 498);
//! assert_eq!(first.line, 2);
//! ```

use super::Segment;
use std::collections::VecDeque;
use std::sync::{Mutex, MutexGuard};

/// Segments kept for the reader behind at most (about 300 bytes each: 10 MB). The commander of
/// `run` leads the simulator by at most a minute of program time: 20,000 segments of a program with
/// a block every 0.1 mm at F2000.
pub const KEPT_SEGMENTS: usize = 32_768;

/// Segments a reader takes from the shared stream per lock.
const BATCH: usize = 64;

#[derive(Debug)]
struct State<I> {
    source: I,
    /// Segments read from `source` that a reader attached to it has not taken; `kept[0]` is segment
    /// `base` of the stream.
    kept: VecDeque<Segment>,
    base: u64,
    /// Segments each reader has taken, and whether it reads a copy of its own.
    taken: [u64; 2],
    detached: [bool; 2],
    /// `source` has ended.
    ended: bool,
    /// A reader was detached and could not read its copy to where it was (it ended there).
    failed: bool,
}

/// What taking a batch from the shared stream found.
enum Batch {
    Took,
    Ended,
    Detached,
}

impl<I> State<I> {
    /// Drop what every attached reader has taken; detach the reader behind when too much is kept.
    fn trim(&mut self) {
        if self.kept.len() > KEPT_SEGMENTS {
            let behind = if self.taken[0] <= self.taken[1] { 0 } else { 1 };
            if !self.detached[1 - behind] {
                self.detached[behind] = true;
            }
        }
        let low = (0..2).filter(|&i| !self.detached[i]).map(|i| self.taken[i]).min().unwrap_or(u64::MAX);
        while self.base < low && self.kept.pop_front().is_some() {
            self.base += 1;
        }
    }
}

/// A segment stream read once for two readers ([`SharedRead::reader`], sides 0 and 1).
#[derive(Debug)]
pub struct SharedRead<I> {
    state: Mutex<State<I>>,
}

impl<I: Iterator<Item = Segment>> SharedRead<I> {
    pub fn new(source: I) -> Self {
        SharedRead { state: Mutex::new(State { source, kept: VecDeque::new(), base: 0, taken: [0; 2], detached: [false; 2], ended: false, failed: false }) }
    }

    fn lock(&self) -> MutexGuard<'_, State<I>> {
        // A reader that panicked holding the lock left the state whole (no step of it can panic
        // half-way but the source's own `next`): read on.
        self.state.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// True if a reader fell behind and could not read a copy of its own to where it was: it ended
    /// early, so what it read is not the whole stream.
    pub fn failed(&self) -> bool {
        self.lock().failed
    }

    /// The reader of side `side` (0 or 1). `reopen` opens the stream again from its start, for
    /// a reader that falls too far behind (`None`: it could not, and that reader ends there).
    pub fn reader<F: FnMut() -> Option<I>>(&self, side: usize, reopen: F) -> SharedReader<'_, I, F> {
        assert!(side < 2, "a shared read has two sides");
        SharedReader { shared: self, side, local: VecDeque::new(), next: 0, own: None, reopen, failed: false }
    }
}

/// One side's reading of a [`SharedRead`]: the segments in order, from the shared stream or, once
/// detached, from its own copy.
#[derive(Debug)]
pub struct SharedReader<'s, I, F> {
    shared: &'s SharedRead<I>,
    side: usize,
    /// Segments taken and not yet handed out, and the index of the next to take.
    local: VecDeque<Segment>,
    next: u64,
    own: Option<I>,
    reopen: F,
    failed: bool,
}

impl<I: Iterator<Item = Segment>, F: FnMut() -> Option<I>> SharedReader<'_, I, F> {
    /// True if this reader was detached and could not open its own copy (it ended there).
    pub fn failed(&self) -> bool {
        self.failed
    }

    /// `f` on the shared stream (the reader's own copy once detached), e.g. to read what the stream
    /// found once the reader has ended.
    pub fn with_source<R>(&mut self, f: impl FnOnce(&mut I) -> R) -> R {
        match self.own.as_mut() {
            Some(own) => f(own),
            None => f(&mut self.shared.lock().source),
        }
    }

    /// Take the next batch from the shared stream, reading it further if this reader is ahead.
    fn take_batch(&mut self) -> Batch {
        let mut st = self.shared.lock();
        if st.detached[self.side] {
            return Batch::Detached;
        }
        let want = self.next + BATCH as u64;
        while !st.ended && st.base + (st.kept.len() as u64) < want {
            match st.source.next() {
                Some(s) => st.kept.push_back(s),
                None => st.ended = true,
            }
        }
        let from = (self.next - st.base) as usize;
        let n = st.kept.len().saturating_sub(from).min(BATCH);
        self.local.extend(st.kept.range(from..from + n).cloned());
        self.next += n as u64;
        let side = self.side;
        st.taken[side] = self.next;
        st.trim();
        if n > 0 {
            Batch::Took
        } else {
            Batch::Ended
        }
    }

    /// This reader ends early: it was detached and has no copy to read on from where it was.
    fn fail(&mut self) -> Option<Segment> {
        self.failed = true;
        self.shared.lock().failed = true;
        None
    }
}

impl<I: Iterator<Item = Segment>, F: FnMut() -> Option<I>> Iterator for SharedReader<'_, I, F> {
    type Item = Segment;

    fn next(&mut self) -> Option<Segment> {
        if let Some(own) = self.own.as_mut() {
            return own.next();
        }
        if let Some(s) = self.local.pop_front() {
            return Some(s);
        }
        if self.failed {
            return None;
        }
        match self.take_batch() {
            Batch::Took => return self.local.pop_front(),
            Batch::Ended => return None,
            Batch::Detached => {}
        }
        // Detached: a copy of its own, skipped to where this reader is.
        let Some(mut own) = (self.reopen)() else {
            return self.fail();
        };
        if self.next > 0 && own.nth((self.next - 1) as usize).is_none() {
            return self.fail();
        }
        let s = own.next();
        self.own = Some(own);
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::{AtomicUsize, Ordering};

    type Boxed<'a> = Box<dyn Iterator<Item = Segment> + Send + 'a>;

    fn boxed<'a>(i: impl Iterator<Item = Segment> + Send + 'a) -> Boxed<'a> {
        Box::new(i)
    }

    use crate::path::stream_test_segment as seg;

    /// Both readers see the whole stream in order whatever their distance; the stream is read once
    /// while the distance stays within the bound, and a copy only past it.
    #[test]
    fn both_readers_see_the_stream_whole_and_the_copy_only_past_the_bound() {
        for (n, ahead) in [(0usize, 0usize), (10, 3), (100_000, 1000), (100_000, KEPT_SEGMENTS - BATCH), (100_000, KEPT_SEGMENTS + BATCH), (100_000, 60_000)] {
            let (first, copies) = (AtomicUsize::new(0), AtomicUsize::new(0));
            let shared = SharedRead::new(boxed((0..n).map(|k| {
                first.fetch_add(1, Ordering::Relaxed);
                seg(k)
            })));
            let reopen = || {
                Some(boxed((0..n).map(|k| {
                    copies.fetch_add(1, Ordering::Relaxed);
                    seg(k)
                })))
            };
            let (mut lead, mut follow) = (shared.reader(0, reopen), shared.reader(1, reopen));
            let (mut a, mut b) = (Vec::new(), Vec::new());
            loop {
                // The lead runs `ahead` segments in front, then the follower takes one.
                while a.len() < b.len() + ahead {
                    match lead.next() {
                        Some(s) => a.push(s.block),
                        None => break,
                    }
                }
                match follow.next() {
                    Some(s) => b.push(s.block),
                    None => break,
                }
            }
            a.extend(lead.map(|s| s.block));
            let all: Vec<usize> = (0..n).collect();
            assert_eq!(a, all, "lead, n {n}, ahead {ahead}");
            assert_eq!(b, all, "follower, n {n}, ahead {ahead}");
            assert_eq!(first.load(Ordering::Relaxed), n);
            if ahead + BATCH <= KEPT_SEGMENTS {
                assert_eq!(copies.load(Ordering::Relaxed), 0, "n {n}, ahead {ahead}: a copy was read");
            } else {
                assert!(copies.load(Ordering::Relaxed) > 0, "n {n}, ahead {ahead}: no copy was read");
            }
        }
    }

    /// On two threads reading at their own pace, each sees the stream whole and in order.
    #[test]
    fn two_threads_each_see_the_stream_whole() {
        let n = 200_000;
        let shared = SharedRead::new(boxed((0..n).map(seg)));
        let reopen = || Some(boxed((0..n).map(seg)));
        let (a, b) = (shared.reader(0, reopen), shared.reader(1, reopen));
        let (a, b) = std::thread::scope(|scope| {
            let a = scope.spawn(move || a.map(|s| s.block).collect::<Vec<_>>());
            let b = scope.spawn(move || b.map(|s| s.block).collect::<Vec<_>>());
            (a.join().unwrap(), b.join().unwrap())
        });
        let all: Vec<usize> = (0..n).collect();
        assert_eq!(a, all);
        assert_eq!(b, all);
    }

    /// A reader detached with no copy to read ends, and says so; the other reads on.
    #[test]
    fn a_detached_reader_without_a_copy_fails_and_the_other_reads_on() {
        let n = KEPT_SEGMENTS * 2;
        let shared = SharedRead::new(boxed((0..n).map(seg)));
        let mut lead = shared.reader(0, || None);
        let mut behind = shared.reader(1, || None);
        assert_eq!(behind.next().map(|s| s.block), Some(0));
        assert_eq!(lead.by_ref().count(), n);
        let rest = behind.by_ref().count();
        assert!(rest < n - 1, "the reader behind read {rest} after being detached");
        assert!(behind.failed());
        assert!(!lead.failed());
        assert!(shared.failed());
    }
}
