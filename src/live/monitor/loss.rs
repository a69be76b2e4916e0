//! Samples lost from a stream, judged from gaps in its stamps against its own period: a stretch of
//! gaps is judged as a whole, so that a publisher that stalls and then sends what it owes loses nothing.

use super::*;

/// Intervals whose spread sets the gap tolerance.
const INTERVALS: usize = 64;

/// A stretch of a stream's stamps with gaps in it, not yet judged: a publisher that stalls and then
/// sends what it owes in a burst, stamping at send time, makes the same gaps as lost samples; the count
/// over the whole stretch decides.
#[derive(Debug, Clone, Copy)]
pub(super) struct LossEpisode {
    /// Stamp before the first gap, samples received since, stamp at the end of the latest gap, how
    /// long to wait after it before judging, and the period in force when it began.
    t0: f64,
    received: u64,
    last_gap: f64,
    window: f64,
    period: f64,
    /// Where the sample before the first gap lies on the stream's grid: its stamp less its lateness,
    /// the least lateness of the stamps before it (send-time stamps are never early).
    grid0: f64,
    /// Groups of gaps: the first gap's stamp, and the fewest samples missing from the grid at any
    /// sample since it. Both rise from group to group; a sample that brings groups level merges them.
    groups: [(f64, f64); GAP_GROUPS],
    len: usize,
    /// The stamps were on a grid before the gap (intervals within a tenth of a period): a late
    /// publisher cannot hide in them, so every gap is judged at once.
    on_grid: bool,
}

/// Groups of gaps an episode keeps apart (beyond, the oldest two merge: the later one's loss is then
/// judged on the earlier one's fewest, which can only count less).
const GAP_GROUPS: usize = 32;

impl LossEpisode {
    /// Samples missing from the grid at stamp `t`: the periods since `grid0` less those received.
    fn missing_at(&self, t: f64) -> f64 {
        (t - self.grid0) / self.period - self.received as f64
    }

    /// A sample at stamp `t` (counted in `received`), which ends a gap when `gap`.
    fn sample(&mut self, t: f64, gap: bool) {
        let m = self.missing_at(t);
        let mut from = gap.then_some(t);
        while self.len > 0 && self.groups[self.len - 1].1 >= m {
            self.len -= 1;
            from = Some(self.groups[self.len].0);
        }
        if let Some(from) = from {
            if self.len == GAP_GROUPS {
                self.groups.copy_within(2.., 1);
                self.len -= 1;
            }
            self.groups[self.len] = (from, m);
            self.len += 1;
        }
    }

    /// Samples lost, judged at stamp `t_end`: the fewest missing since the latest gap at least a
    /// window before it. Later gaps of jittered stamps are not judged yet (a stalled publisher may
    /// still be paying them back), and a stream that ends in the window leaves them unjudged.
    fn lost(&self, t_end: f64) -> u64 {
        let cutoff = if self.on_grid { f64::INFINITY } else { t_end - self.window };
        let least = self.groups[..self.len].iter().rev().find(|g| g.0 <= cutoff).map_or(0.0, |g| g.1);
        (least + LATE_TOLERATED).floor().max(0.0) as u64
    }
}

/// Stamps before a gap that place the stream's grid (the least late of them).
const GRID_STAMPS: usize = 64;

/// A loss is counted once the least late sample after it is 3/4 of a period behind the grid: a
/// publisher under load can stay that late for a whole judging window, or the stream ends in one.
const LATE_TOLERATED: f64 = 0.25;

/// The grid time of the last stamp kept: the least of `s_k + k p` over the last [`GRID_STAMPS`]
/// stamps from `since` on (a judged loss shifts the grid: stamps before it are left out).
fn grid_of_last(stamps: &VecDeque<f64>, p: f64, since: f64) -> Option<f64> {
    stamps.iter().rev().take(GRID_STAMPS).take_while(|s| **s >= since).enumerate().map(|(k, s)| s + k as f64 * p).reduce(f64::min)
}

/// The grid time of `stamps[i0]`: the least of `s_k - k p` over the [`GRID_STAMPS`] stamps from it
/// up to `until` (where a loss begins).
fn grid_of(stamps: &VecDeque<f64>, i0: usize, p: f64, until: f64) -> Option<f64> {
    stamps.range(i0..).take(GRID_STAMPS).take_while(|s| **s <= until).enumerate().map(|(k, s)| s - k as f64 * p).reduce(f64::min)
}

/// Samples judged lost and the span of the episode's gaps they were missing from (stamps).
#[derive(Debug, Clone, Copy)]
pub(super) struct LossEvent {
    from: f64,
    to: f64,
    lost: u64,
}

/// Stamps kept for the period estimate (about 1 s at 1 kHz), and how many before gaps are judged.
const STAMPS: usize = 1025;
const STAMPS_BEFORE_JUDGING: usize = 256;

/// Count samples missing from a stream, one interval `dt` (ending at stamp `t`) at a time.
///
/// The period is the mean interval over the last 1024 stamps with the samples already judged lost
/// put back, from after any loss that began before them (exact under jitter, whose intervals add up;
/// not the smallest interval, which one catch-up makes tiny). An interval longer than the period plus the larger of half a period and twice the
/// spread of the recent intervals (10th to 90th percentile) is a gap; a gap opens an episode that lasts
/// until `max(0.2 s, 2 gaps)` pass without another. Then the samples missing from the stream's grid
/// are lost, counted at the least late sample since the last gap against the least late of the 64
/// before the first (send-time stamps are late, never early; judged on the last sample alone, a
/// publisher still behind there counted its lateness as loss): a stalled publisher that catches up
/// loses nothing, a real outage loses exactly its samples, on a grid or jittered.
/// Stated tolerance: with jittered stamps, a loss shorter than the jitter's spread makes no gap and is
/// not seen; the first 256 samples of a stream are not judged.
pub(super) fn count_lost(input: &mut Input, dt: f64, t: f64) {
    if let Some(e) = input.episode.as_mut() {
        e.received += 1;
    }
    let gap = match input.period {
        Some((p, spread)) if input.stamps.len() >= STAMPS_BEFORE_JUDGING && !input.change_only => dt > p + (0.5 * p).max(2.0 * spread),
        _ => false,
    };
    if gap {
        match input.episode.as_mut() {
            None => {
                let period = input.period.map_or(dt, |p| p.0);
                let on_grid = input.period.is_some_and(|(p, spread)| spread < 0.1 * p);
                let since = input.loss_events.back().map_or(f64::NEG_INFINITY, |e| e.to);
                let grid0 = grid_of_last(&input.stamps, period, since).unwrap_or(t - dt);
                let mut e = LossEpisode { t0: t - dt, received: 1, last_gap: t, window: (2.0 * dt).max(0.2), period, grid0, groups: [(0.0, 0.0); GAP_GROUPS], len: 0, on_grid };
                e.sample(t, true);
                input.episode = Some(e);
            }
            Some(e) => {
                e.last_gap = t;
                e.window = e.window.max(2.0 * dt);
                e.sample(t, true);
            }
        }
    } else if let Some(e) = input.episode.as_mut() {
        e.sample(t, false);
        if t - e.last_gap >= e.window {
            close_loss_episode(input, t);
        }
    }
    if input.stamps.len() == STAMPS {
        input.stamps.pop_front();
    }
    input.stamps.push_back(t);
    while input.loss_events.front().is_some_and(|e| input.stamps.front().is_some_and(|s| e.to <= *s)) {
        input.loss_events.pop_front();
    }
    // Re-estimate every 64 samples (and at the start), outside episodes (a gap being judged must not
    // move the period): a mean and two O(n) selections, no allocation.
    let n = input.stamps.len();
    if input.episode.is_none() && n >= 25 && (input.period.is_none() || input.samples.is_multiple_of(64)) {
        // Stamps from after the last gap of a loss that began before the oldest stamp: every loss
        // put back then lies within the stamps. (Putting back a whole loss of which the window held
        // only part shortened the period, which made more gaps: a runaway, 106 k lost of 8 k missing.)
        let cut = input.loss_events.iter().filter(|e| e.from < input.stamps[0]).map(|e| e.to).reduce(f64::max);
        let i0 = cut.map_or(0, |c| input.stamps.partition_point(|s| *s < c)).min(n - 1);
        let (first, last) = (input.stamps[i0], input.stamps[n - 1]);
        if n - i0 < 25 {
            return; // too few stamps since such a loss: the period stays as it was
        }
        let lost_within: u64 = input.loss_events.iter().filter(|e| e.to > first).map(|e| e.lost).sum();
        // Both ends on the stream's grid, once there is a period: send-time stamps are late by varying
        // amounts, and one late end skews the mean (a first stamp 4 ms late made the period 1.6 %
        // short: a stalling bridge was judged to lose 11 samples a second).
        // The anchors use the period, so they are found again on the new one (three rounds settle it
        // to well under a part per thousand even from the first, plain mean).
        let intervals = (n - 1 - i0) as f64 + lost_within as f64;
        let mut mean = (last - first) / intervals;
        if input.period.is_some() {
            let until = input.loss_events.iter().filter(|e| e.to > first).map(|e| e.from).reduce(f64::min).unwrap_or(f64::INFINITY);
            let since = input.loss_events.back().map_or(f64::NEG_INFINITY, |e| e.to);
            for _ in 0..3 {
                let (g0, g1) = (grid_of(&input.stamps, i0, mean, until).unwrap_or(first), grid_of_last(&input.stamps, mean, since).unwrap_or(last));
                mean = (g1 - g0) / intervals;
            }
        }
        let m = INTERVALS.min(n - 1);
        let mut v = [0.0; INTERVALS];
        for (k, slot) in v.iter_mut().take(m).enumerate() {
            *slot = input.stamps[n - m + k] - input.stamps[n - m + k - 1];
        }
        let v = &mut v[..m];
        let hi = *v.select_nth_unstable_by(m * 9 / 10, f64::total_cmp).1;
        let lo = *v.select_nth_unstable_by(m / 10, f64::total_cmp).1;
        if mean > 0.0 {
            input.period = Some((mean, hi - lo));
        }
    }
}

/// Judge an open loss episode at stamp `t_end`, its last sample (see [`count_lost`]).
pub(super) fn close_loss_episode(input: &mut Input, t_end: f64) {
    let Some(e) = input.episode.take() else { return };
    let lost = e.lost(t_end);
    if lost > 0 {
        input.lost = input.lost.saturating_add(lost);
        input.loss_events.push_back(LossEvent { from: e.t0, to: e.last_gap, lost });
    }
}
