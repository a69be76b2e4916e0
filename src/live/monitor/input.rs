//! What the monitor keeps per input stream: its recent samples, stamps and losses, regions and
//! staleness, and the worst evaluation since the last report.

use super::*;

/// A recent sample of a stream: its time (s), path length (m), axes, tool axis and tip.
#[derive(Debug, Clone, Copy)]
pub(super) struct Past {
    pub(super) t: f64,
    pub(super) s: f64,
    pub(super) q: Joints,
    pub(super) axis: Vector3<f64>,
    pub(super) tip: Vector3<f64>,
}

/// What the monitor keeps per input stream.
#[derive(Debug, Default)]
pub(super) struct Input {
    pub(super) source: u8,
    pub(super) history: VecDeque<Past>,
    pub(super) s: f64,
    /// The program line of the current block and the path length where the stream entered it.
    pub(super) block_start: (u32, f64),
    /// The first closed regions, the rest folded, and the last one closed (its end event).
    pub(super) regions: Vec<LiveRegion>,
    pub(super) unlisted: crate::listing::Unlisted,
    pub(super) last_closed: Option<LiveRegion>,
    pub(super) stale: u64,
    pub(super) stale_now: bool,
    pub(super) last_arrival: Option<f64>,
    pub(super) last: Option<Evaluation>,
    pub(super) cursor: (usize, usize),
    pub(super) samples: u64,
    /// Recent stamps, the period and the spread of the intervals (10th to 90th percentile), samples
    /// missing from gaps in the stamps, a stretch of gaps being judged and the losses judged recently.
    pub(super) stamps: VecDeque<f64>,
    pub(super) period: Option<(f64, f64)>,
    /// Gaps are not judged as losses (see [`Monitor::set_change_only`]).
    pub(super) change_only: bool,
    /// The last interval between stamps (the stale limit before a period is known).
    pub(super) last_interval: Option<f64>,
    pub(super) lost: u64,
    pub(super) episode: Option<LossEpisode>,
    pub(super) loss_events: VecDeque<LossEvent>,
    pub(super) rejected: Rejected,
    /// Machine streams: the measured path, the region rule's state, the program alignment and the
    /// lagged sample the rule saw last (t, s).
    pub(super) measured: Option<MeasuredPath>,
    pub(super) tracker: RegionTracker,
    pub(super) aligner: Option<Aligner>,
    pub(super) lagged: Option<(f64, f64)>,
    pub(super) max_feed: f64,
    /// (t, s) of the recent samples of the current run of feed motion (the assumed feed is the
    /// highest feed held over [`HELD`] within one run).
    pub(super) feed_run: VecDeque<(f64, f64)>,
    /// Time spent at each held feed (bins of 2 % from 1 mm/min) and the bin held longest.
    pub(super) feed_time: Vec<f64>,
    pub(super) feed_mode: Option<usize>,
    pub(super) rapid_samples: u64,
    pub(super) feed_samples: u64,
    /// The worst evaluation since `/diagnostics` last reported (its level and the peak predicted
    /// speed over it), so that a short event between two reports is never missed.
    pub(super) worst: Option<(u8, Evaluation)>,
}

/// A stream is stale after this many of its own sample periods (plus the spread of its intervals)
/// without a sample, or the configured timeout, whichever is longer: a bridge that sends a few times
/// a second is not stale between its samples.
const STALE_PERIODS: f64 = 3.0;

impl Input {
    /// A new session of the stream (a restarted publisher, an adapter that connected again): what
    /// came before is judged and closed, nothing of it is used after.
    pub(super) fn new_session(&mut self, max_listed: usize) {
        if let Some(last) = self.history.back().map(|h| h.t) {
            close_loss_episode(self, last);
        }
        self.history.clear();
        // The new session's stamps start again: the old ones must not enter its period (mixed,
        // they make the period tiny and every interval a gap, judging the stream mostly lost).
        self.stamps.clear();
        self.period = None;
        self.last_interval = None;
        self.loss_events.clear();
        if let Some(r) = self.tracker.finish() {
            self.close(&r, max_listed);
        }
        if let Some(m) = self.measured.as_mut() {
            m.reset();
        }
        if let Some(a) = self.aligner.as_mut() {
            a.reset();
        }
        self.lagged = None;
        self.last = None;
    }

    /// How long this stream may be silent before it is stale, s.
    pub(super) fn stale_after(&self, timeout: f64) -> f64 {
        // The period and the spread of its intervals (10th to 90th percentile): a stream whose axes
        // report on their own clocks comes in bursts.
        self.period.map(|p| p.0 + p.1).or(self.last_interval).map_or(timeout, |p| timeout.max(STALE_PERIODS * p))
    }

    /// Why the program (`--program`) could not be read again to place this stream's samples.
    pub(super) fn program_failure(&self) -> Option<&str> {
        self.aligner.as_ref().and_then(|a| a.failure())
    }

    /// Remember the evaluation if it is the worst since the last report (the peak speed of a region
    /// kept with it).
    pub(super) fn latch(&mut self, e: &Evaluation, warn_distance: f64, warn_ahead: f64) {
        let level = level_of(e, warn_distance, warn_ahead);
        match &mut self.worst {
            Some((l, w)) if *l == level && level == DiagnosticStatus::ERROR && w.region_id == e.region_id => {
                if e.predicted_c_speed.abs() > w.predicted_c_speed.abs() {
                    w.predicted_c_speed = e.predicted_c_speed;
                }
            }
            Some((l, _)) if *l >= level => {}
            _ => self.worst = Some((level, *e)),
        }
    }

    /// Keeps a closed region: listed while there is room, else folded.
    pub(super) fn close(&mut self, r: &TrackedRegion, cap: usize) {
        let region = LiveRegion::from_tracked(r);
        self.last_closed = Some(region.clone());
        crate::listing::push(&mut self.regions, &mut self.unlisted, cap, region);
    }

    /// Closed regions, then the open one.
    pub(super) fn all_regions(&self) -> Vec<LiveRegion> {
        // The open one after the listed ones when none was folded yet (it closes listed or folded).
        let tracked = self.tracker.open().filter(|_| self.unlisted.is_empty()).map(LiveRegion::from_tracked);
        self.regions.iter().cloned().chain(tracked).collect()
    }
}
