//! The look-ahead: the commanded timeline a machine stream is placed on, and the time from there to
//! the next region (the live warning "region ahead in N s").

use super::*;

/// One commanded sample remembered for the look-ahead.
#[derive(Debug, Clone, Copy)]
pub(super) struct Ahead {
    pub(super) t: f64,
    pub(super) line: u32,
    pub(super) tip: Vector3<f64>,
}

/// How much of the commanded timeline the look-ahead keeps (s of commanded time before the newest
/// commanded sample): a stream further behind the commander than this finds no region ahead. It
/// bounds the monitor's memory whatever the program's length.
pub const AHEAD_RETENTION_S: f64 = 120.0;

/// The most commanded samples the look-ahead keeps, whatever their stamps: [`AHEAD_RETENTION_S`] of
/// a commanded stream at up to 4 kHz (the node set's is 1 kHz), so that a publisher stamping its
/// samples microseconds apart cannot make the monitor hold millions (about 19 MB at most).
pub const AHEAD_MAX_ENTRIES: usize = 480_000;

/// The commanded timeline the look-ahead reads: the last [`AHEAD_RETENTION_S`] of commanded samples
/// and which of them lie in a region. Indices are absolute (from the stream's first sample), so the
/// streams' cursors survive the dropping of old entries.
#[derive(Debug, Clone, Default)]
pub(super) struct Timeline {
    /// Absolute index of `entries[0]`, and of `regions[0]` in the list of every in-region entry.
    base: usize,
    entries: VecDeque<Ahead>,
    regions_base: usize,
    regions: VecDeque<usize>,
}

impl Timeline {
    fn end(&self) -> usize {
        self.base + self.entries.len()
    }
    fn get(&self, i: usize) -> &Ahead {
        &self.entries[i - self.base]
    }
    pub(super) fn last(&self) -> Option<&Ahead> {
        self.entries.back()
    }
    /// Entry index of the `k`-th in-region entry, if still held.
    fn region(&self, k: usize) -> Option<usize> {
        k.checked_sub(self.regions_base)
            .and_then(|r| self.regions.get(r))
            .copied()
    }
    pub(super) fn push(&mut self, a: Ahead, in_region: bool) {
        if in_region {
            self.regions.push_back(self.end());
        }
        self.entries.push_back(a);
        while self
            .entries
            .front()
            .is_some_and(|f| f.t < a.t - AHEAD_RETENTION_S || self.entries.len() > AHEAD_MAX_ENTRIES)
        {
            self.entries.pop_front();
            self.base += 1;
        }
        while self.regions.front().is_some_and(|&i| i < self.base) {
            self.regions.pop_front();
            self.regions_base += 1;
        }
    }
}

/// Find a sample's place on the commanded timeline and the time from there to the next region:
/// (new cursor, seconds; -1 if none ahead). The cursor is (place on the timeline, first in-region
/// entry not behind it), both absolute and only moving forward. The place moves from the cursor to
/// the sample's program line, then on while the next entry is as close to the sample's tool tip; the
/// next region is the first in-region entry at or after it.
pub(super) fn lookahead(
    tl: &Timeline,
    cursor: (usize, usize),
    line: u32,
    tip: &Vector3<f64>,
) -> ((usize, usize), f64) {
    if tl.entries.is_empty() {
        return (cursor, -1.0);
    }
    let end = tl.end();
    let mut best = cursor.0.clamp(tl.base, end - 1);
    // A new block: jump to its first entry ahead (the scan happens once per block).
    if line != 0 && tl.get(best).line != line {
        if let Some(k) = (best..end)
            .take(1_000_000)
            .position(|i| tl.get(i).line == line)
        {
            best += k;
        }
    }
    // Then forward while the next entry (of the same block) is at least as close.
    let d = |a: &Ahead| (a.tip - tip).norm();
    while best + 1 < end
        && (line == 0 || tl.get(best + 1).line == line)
        && d(tl.get(best + 1)) <= d(tl.get(best))
    {
        best += 1;
    }
    let mut k = cursor.1.max(tl.regions_base);
    while tl.region(k).is_some_and(|i| i < best) {
        k += 1;
    }
    let next = tl.region(k).map_or(-1.0, |i| tl.get(i).t - tl.get(best).t);
    ((best, k), next)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn samples_a_microsecond_apart_are_held_to_the_entry_bound() {
        // A publisher stamping commanded samples 1 us apart: 120 s of them would be 120 million.
        let mut tl = Timeline::default();
        for k in 0..1_000_000usize {
            let a = Ahead { t: k as f64 * 1e-6, line: (k / 1000) as u32 + 1, tip: Vector3::new(k as f64 * 1e-6, 0.0, 0.0) };
            tl.push(a, k % 1000 == 999);
        }
        assert!(tl.entries.len() <= AHEAD_MAX_ENTRIES + 1, "{}", tl.entries.len());
        assert!(tl.regions.iter().all(|&i| i >= tl.base));
        // The newest entries are the ones kept, and the region ahead of a late sample is found.
        assert_eq!(tl.end(), 1_000_000);
        let at = tl.base + 10;
        let (_, s) = lookahead(&tl, (at, 0), tl.get(at).line, &tl.get(at).tip);
        assert!(s > 0.0, "{s}");
    }
}
