//! One read of the segment stream for the planner and its scout. The scout ([`super::RunScout`])
//! reads a whole run before the planner plans it (the run's length sets its path grid); it keeps
//! what it reads for the planner, up to [`KEPT_SEGMENTS`], so the program is parsed, segmented and
//! smoothed once. Past that bound (a run longer than it), the planner reads its own second copy of
//! the stream from where it is, as both did before: memory stays bounded whatever the run's length.

use crate::path::Segment;
use std::cell::RefCell;
use std::collections::VecDeque;
use std::rc::Rc;

/// Segments the scout keeps for the planner at most (a few hundred bytes each, about 5 MB).
pub const KEPT_SEGMENTS: usize = 16_384;

#[derive(Debug, Default)]
struct Kept {
    segments: VecDeque<Segment>,
    /// The scout keeps no more: the planner reads its second copy once it has taken what is kept.
    stopped: bool,
    /// The scout has read the whole stream.
    ended: bool,
}

/// The scout's side: the stream, each segment also kept for the planner while there is room.
#[derive(Debug)]
pub struct Lead<I> {
    source: I,
    kept: Rc<RefCell<Kept>>,
}

/// The planner's side: what the scout kept, then (past the bound) the second copy, skipped to here.
#[derive(Debug)]
pub struct Follow<J> {
    again: J,
    kept: Rc<RefCell<Kept>>,
    /// Segments taken so far, and whether the second copy is being read.
    taken: usize,
    reading: bool,
}

/// Split `source` for a scout that reads ahead and a planner that follows; `again` is the same
/// stream once more, read only if the scout's lead outgrows [`KEPT_SEGMENTS`].
pub fn tee<I, J>(source: I, again: J) -> (Lead<I>, Follow<J>)
where
    I: Iterator<Item = Segment>,
    J: Iterator<Item = Segment>,
{
    let kept = Rc::new(RefCell::new(Kept::default()));
    (Lead { source, kept: kept.clone() }, Follow { again, kept, taken: 0, reading: false })
}

impl<I: Iterator<Item = Segment>> Iterator for Lead<I> {
    type Item = Segment;
    fn next(&mut self) -> Option<Segment> {
        let Some(s) = self.source.next() else {
            self.kept.borrow_mut().ended = true;
            return None;
        };
        let mut kept = self.kept.borrow_mut();
        if !kept.stopped {
            if kept.segments.len() < KEPT_SEGMENTS {
                kept.segments.push_back(s.clone());
            } else {
                kept.stopped = true;
            }
        }
        Some(s)
    }
}

impl<J: Iterator<Item = Segment>> Iterator for Follow<J> {
    type Item = Segment;
    fn next(&mut self) -> Option<Segment> {
        if !self.reading {
            let mut kept = self.kept.borrow_mut();
            if let Some(s) = kept.segments.pop_front() {
                self.taken += 1;
                return Some(s);
            }
            if kept.ended && !kept.stopped {
                return None;
            }
            // Past what was kept: the scout stopped keeping, or (not the planner's way) the follower
            // caught up with it. Either way the second copy takes over, and the scout keeps no more.
            kept.stopped = true;
            drop(kept);
            self.reading = true;
            if self.taken > 0 {
                self.again.nth(self.taken - 1)?;
            }
        }
        self.again.next()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::path::stream_test_segment as seg;

    /// A stream that counts how many segments were read from it.
    fn counted(n: usize, reads: Rc<RefCell<usize>>) -> impl Iterator<Item = Segment> {
        (0..n).map(move |k| {
            *reads.borrow_mut() += 1;
            seg(k)
        })
    }

    /// The follower sees the stream in order, whatever the lead's distance ahead; the second copy is
    /// not read while the lead stays within the bound, and is read from where the follower is past it.
    #[test]
    fn the_follower_sees_the_stream_whole_and_the_copy_only_past_the_bound() {
        for (n, ahead) in [(0usize, 0usize), (10, 1), (50_000, 1000), (50_000, KEPT_SEGMENTS), (50_000, KEPT_SEGMENTS + 1), (50_000, 40_000)] {
            let (first, second) = (Rc::new(RefCell::new(0)), Rc::new(RefCell::new(0)));
            let (mut lead, mut follow) = tee(counted(n, first.clone()), counted(n, second.clone()));
            let mut seen = Vec::new();
            let mut led = 0;
            loop {
                // The lead runs `ahead` segments in front (a run), then the follower takes them.
                while led < seen.len() + ahead && lead.next().is_some() {
                    led += 1;
                }
                match follow.next() {
                    Some(s) => seen.push(s.block),
                    None => break,
                }
            }
            assert_eq!(seen, (0..n).collect::<Vec<_>>(), "n {n}, ahead {ahead}");
            assert_eq!(*first.borrow(), n);
            if ahead <= KEPT_SEGMENTS && ahead > 0 {
                assert_eq!(*second.borrow(), 0, "n {n}, ahead {ahead}: the copy was read");
            } else if n > 0 {
                assert!(*second.borrow() > 0, "n {n}, ahead {ahead}: the copy was not read");
            }
        }
    }
}
