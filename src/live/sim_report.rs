//! What the simulated machine did, measured on its stream of states in constant memory: the lowest
//! tool-tip feed outside the planned stops, the stretches below half the programmed feed, and the
//! axis limit check ([`crate::planner::LimitCheck`]).

use super::monitor::LiveRegion;
use super::simulator::{simulate_stream, FeedSample, SimConfig, SimSample, SimStates, SimSummary};
use super::StateValues;
use crate::kinematics::Joints;
use crate::machine::Machine;
use crate::path::{Segment, SegmentKind, Trajectory};
use std::rc::Rc;
use crate::planner::LimitCheck;
use crate::units::mm_per_min;
use serde::Serialize;
use std::collections::VecDeque;

/// How far back (s) the ramp into a planned stop is looked for: a run's samples older than this
/// before its end are taken as outside the ramp. Braking from any programmed feed to a stop takes
/// well under a second on the machines here; the horizon bounds the memory of the figures.
pub const RAMP_HORIZON_S: f64 = 30.0;

/// A stretch where the simulated feed is below half the programmed feed.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SlowRegion {
    pub x_start_mm: f64,
    pub x_end_mm: f64,
    pub t_start_s: f64,
    pub t_end_s: f64,
    pub block_start: i64,
    pub block_end: i64,
    /// Program lines (0: unknown), for programs without block numbers.
    pub line_start: u32,
    pub line_end: u32,
    pub min_feed_mm_per_min: f64,
    /// True where the slow-down is the planned stop at a corner or at the program's ends, not an
    /// axis limit along the path.
    pub at_stop: bool,
}

/// What the simulated machine did.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SimulatedReport {
    pub cycle_time_s: f64,
    pub commanded_cycle_time_s: f64,
    /// Lowest tool-tip feed on feed moves, outside the ramps into and out of planned stops.
    pub min_feed_mm_per_min: f64,
    pub min_feed_x_mm: f64,
    /// The first slow regions (planned stops included) in full, the rest folded, and the planned
    /// stops among all of them.
    pub slow_regions: Vec<SlowRegion>,
    pub unlisted_slow_regions: crate::listing::Unlisted,
    pub planned_stops: usize,
    pub max_axis_velocity_ratio: f64,
    pub max_axis_acceleration_ratio: f64,
    pub max_axis_jerk_ratio: f64,
    pub max_following_error_mm: f64,
    pub max_following_error_deg: f64,
    pub samples: usize,
    pub lost_samples: u64,
    /// Regions the live monitor saw on the simulated stream (the first ones; the rest folded).
    pub monitor_regions: Vec<LiveRegion>,
    pub unlisted_monitor_regions: crate::listing::Unlisted,
    pub monitor_statuses: u64,
}

impl SimulatedReport {
    /// A short table for people.
    pub fn to_table(&self, c: &str) -> String {
        use std::fmt::Write as _;
        let mut o = String::new();
        let _ = writeln!(
            o,
            "simulated  {:.2} s (commanded {:.2} s), {} samples, {} lost",
            self.cycle_time_s, self.commanded_cycle_time_s, self.samples, self.lost_samples
        );
        let _ = writeln!(
            o,
            "lowest feed on the path      {:8.0} mm/min at x {:.3} mm (planned stops excluded)",
            self.min_feed_mm_per_min, self.min_feed_x_mm
        );
        let _ = writeln!(
            o,
            "largest |v|/v_max {:.3}, |a|/a_max {:.3}, |j|/j_max {:.3} over all axes; following error {:.3} mm, {:.4} deg",
            self.max_axis_velocity_ratio, self.max_axis_acceleration_ratio, self.max_axis_jerk_ratio, self.max_following_error_mm, self.max_following_error_deg
        );
        let limit: Vec<_> = self.slow_regions.iter().filter(|r| !r.at_stop).collect();
        if limit.is_empty() && self.unlisted_slow_regions.is_empty() {
            let _ = writeln!(o, "slow regions none below 50 % of the programmed feed (besides {} planned stops)", self.planned_stops);
        } else {
            let _ = writeln!(o, "slow regions below 50 % of the programmed feed (besides {} planned stops):", self.planned_stops);
            let _ = writeln!(o, "     x from     x to   blocks          lowest mm/min");
            for r in limit {
                let _ = writeln!(
                    o,
                    "   {:8.3} {:8.3}   {:<14} {:10.0}",
                    r.x_start_mm,
                    r.x_end_mm,
                    crate::report::block_span(r.block_start, r.block_end, r.line_start, r.line_end),
                    r.min_feed_mm_per_min
                );
            }
            if let Some(more) = self.unlisted_slow_regions.describe() {
                let _ = writeln!(o, "   {more} (planned stops included)");
            }
        }
        for r in &self.monitor_regions {
            let _ = writeln!(
                o,
                "monitor    region {} on the simulated stream: x {:.3} to {:.3} mm, {:.2} s, peak {c} {:.1} rpm, feed down to {:.0} mm/min",
                r.id, r.x_start_mm, r.x_end_mm, r.t_end_s - r.t_start_s, r.peak_c_speed_rpm, r.min_path_feed_mm_per_min
            );
        }
        if let Some(more) = self.unlisted_monitor_regions.describe() {
            let _ = writeln!(o, "monitor    {more}");
        }
        o
    }
}

/// A slow stretch being measured: samples `start..=end`.
#[derive(Debug, Clone)]
struct Stretch {
    start: u64,
    end: u64,
    first: FeedSample,
    last: FeedSample,
    min: f64,
    at_stop: bool,
}

impl crate::listing::Listed for SlowRegion {
    fn figures(&self) -> crate::listing::Figures {
        crate::listing::Figures {
            id: None,
            time_s: self.t_end_s - self.t_start_s,
            min_feed_mm_per_min: Some(self.min_feed_mm_per_min),
            ..Default::default()
        }
    }
}

impl Stretch {
    fn region(&self, period: f64) -> SlowRegion {
        SlowRegion {
            x_start_mm: self.first.x * 1e3,
            x_end_mm: self.last.x * 1e3,
            t_start_s: self.start as f64 * period,
            t_end_s: self.end as f64 * period,
            block_start: self.first.block.into(),
            block_end: self.last.block.into(),
            line_start: self.first.line,
            line_end: self.last.line,
            min_feed_mm_per_min: mm_per_min(self.min),
            at_stop: self.at_stop,
        }
    }
}

/// One sample of the current run, for the ramp into its end.
#[derive(Debug, Clone, Copy)]
struct Held {
    v: f64,
    x: f64,
    programmed: f64,
    /// A feed move with a programmed feed, outside the ramp out of the run's start.
    candidate: bool,
}

/// The ramp out of a planned stop, being followed: the programmed feed at the stop and the highest
/// feed since.
#[derive(Debug, Clone, Copy)]
struct Ramp {
    feed: f64,
    top: f64,
}

/// The feed figures of a simulated stream, pushed one state at a time.
///
/// - Lowest feed: the lowest tool-tip feed on feed moves outside the ramps out of and into each
///   planned stop. A ramp runs from a run boundary (a corner, a rapid, the program's ends) for as long
///   as the feed is below the programmed feed and has not fallen by more than 2 % of it from its
///   highest value since the stop (the servo rounds the corner, so the feed may still dip just after
///   the boundary).
/// - Slow regions: feed moves below half their programmed feed; a stretch within four samples of a
///   run boundary or of the program's ends is a planned stop (a datum change between runs makes the
///   tip jump in program coordinates there).
#[derive(Debug, Clone)]
pub struct FeedFigures {
    period: f64,
    n: u64,
    check: LimitCheck,
    prev_run: Option<usize>,
    /// The latest sample that starts a run (after the first).
    last_change: Option<u64>,
    open: Option<Stretch>,
    /// Stretches that ended less than four samples ago (a run boundary may still follow).
    pending: VecDeque<Stretch>,
    slow: Vec<SlowRegion>,
    unlisted: crate::listing::Unlisted,
    planned_stops: usize,
    max_listed: usize,
    ramp: Option<Ramp>,
    run: VecDeque<Held>,
    horizon: usize,
    lowest: (f64, f64),
}

/// The figures once the stream has ended.
#[derive(Debug, Clone, PartialEq)]
pub struct FeedFiguresReport {
    /// Lowest feed (m/s; infinite if none) and its workpiece x (m).
    pub lowest_feed: f64,
    pub lowest_feed_x: f64,
    pub slow_regions: Vec<SlowRegion>,
    pub unlisted_slow_regions: crate::listing::Unlisted,
    pub planned_stops: usize,
    /// Largest |v|/v_max, |a|/a_max, |j|/j_max over all axes.
    pub worst_ratio: [f64; 3],
    pub samples: u64,
    /// Simulated duration, s (from the first sample to the last).
    pub duration_s: f64,
}

impl FeedFigures {
    /// `max_listed`: slow regions listed in full; the rest are folded.
    pub fn new(machine: &Machine, period: f64, max_listed: usize) -> FeedFigures {
        FeedFigures {
            period,
            n: 0,
            check: LimitCheck::new(period, &machine.limits()),
            prev_run: None,
            last_change: None,
            open: None,
            pending: VecDeque::new(),
            slow: Vec::new(),
            unlisted: Default::default(),
            planned_stops: 0,
            max_listed,
            ramp: None,
            run: VecDeque::new(),
            horizon: (RAMP_HORIZON_S / period).ceil().max(1.0) as usize,
            lowest: (f64::INFINITY, 0.0),
        }
    }

    fn keep(&mut self, r: SlowRegion) {
        self.planned_stops += usize::from(r.at_stop);
        crate::listing::push(&mut self.slow, &mut self.unlisted, self.max_listed, r);
    }

    fn consider(&mut self, h: &Held) {
        if h.candidate && h.v < self.lowest.0 {
            self.lowest = (h.v, h.x);
        }
    }

    /// The current run has ended: the ramp into its end, followed back from its last sample, is
    /// left out; every other candidate counts.
    fn close_run(&mut self) {
        let Some(end) = self.run.back() else { return };
        let f = end.programmed.max(1e-12);
        let (mut j, mut top) = (self.run.len() - 1, 0.0f64);
        while j > 0 {
            let v = self.run[j - 1].v;
            if v >= 0.99 * f || v < top - 0.02 * f {
                break;
            }
            top = top.max(v);
            j -= 1;
        }
        for i in 0..j {
            let h = self.run[i];
            self.consider(&h);
        }
        self.run.clear();
    }

    /// The next simulated state (`s`), at positions `q`, of run `run`; `path_move` if it belongs to a
    /// feed move along the path (not a rapid).
    pub fn push(&mut self, s: &FeedSample, q: &Joints, run: usize, path_move: bool) {
        let k = self.n;
        self.n += 1;
        self.check.push(q);
        let boundary = self.prev_run != Some(run);
        self.prev_run = Some(run);
        if boundary && k > 0 {
            self.last_change = Some(k);
            self.close_run();
            if let Some(o) = self.open.as_mut() {
                o.at_stop = true;
            }
            for p in self.pending.iter_mut().filter(|p| k <= p.end + 4) {
                p.at_stop = true;
            }
        }
        // Slow stretches.
        if path_move && s.programmed_feed > 0.0 && s.path_feed < 0.5 * s.programmed_feed {
            match self.open.as_mut() {
                Some(o) => {
                    o.end = k;
                    o.last = *s;
                    o.min = o.min.min(s.path_feed);
                }
                None => {
                    let at_stop =
                        k == 0 || self.last_change.is_some_and(|c| c > k.saturating_sub(4));
                    self.open = Some(Stretch {
                        start: k,
                        end: k,
                        first: *s,
                        last: *s,
                        min: s.path_feed,
                        at_stop,
                    });
                }
            }
        } else if let Some(o) = self.open.take() {
            self.pending.push_back(o);
        }
        while self.pending.front().is_some_and(|p| p.end + 4 <= k) {
            let p = self.pending.pop_front().expect("front checked");
            self.keep(p.region(self.period));
        }
        // The ramp out of the run's start.
        let in_ramp = if boundary {
            self.ramp = Some(Ramp {
                feed: s.programmed_feed.max(1e-12),
                top: 0.0,
            });
            true
        } else if let Some(r) = self.ramp.as_mut() {
            let v = s.path_feed;
            if v >= 0.99 * r.feed || v < r.top - 0.02 * r.feed {
                self.ramp = None;
                false
            } else {
                r.top = r.top.max(v);
                true
            }
        } else {
            false
        };
        self.run.push_back(Held {
            v: s.path_feed,
            x: s.x,
            programmed: s.programmed_feed,
            candidate: path_move && s.programmed_feed > 0.0 && !in_ramp,
        });
        if self.run.len() > self.horizon {
            let h = self.run.pop_front().expect("longer than the horizon");
            self.consider(&h);
        }
    }

    /// The figures over everything pushed.
    pub fn finish(mut self) -> FeedFiguresReport {
        self.close_run();
        let n = self.n;
        let open = self.open.take();
        let pending: Vec<Stretch> = std::mem::take(&mut self.pending).into_iter().chain(open).collect();
        for mut p in pending {
            p.at_stop |= p.end + 4 >= n;
            self.keep(p.region(self.period));
        }
        FeedFiguresReport {
            lowest_feed: self.lowest.0,
            lowest_feed_x: self.lowest.1,
            slow_regions: self.slow,
            unlisted_slow_regions: self.unlisted,
            planned_stops: self.planned_stops,
            worst_ratio: self.check.finish(),
            samples: n,
            duration_s: n.saturating_sub(1) as f64 * self.period,
        }
    }
}

/// Simulate `traj` on `machine` and measure the feed figures as the states come
/// ([`simulate_measured_stream`] over its segments).
pub fn simulate_measured(
    traj: &Trajectory,
    machine: &Machine,
    config: &SimConfig,
    mut each: impl FnMut(&SimSample, StateValues) -> bool,
) -> (SimSummary, FeedFiguresReport) {
    let segments = || traj.segments.iter().cloned();
    simulate_measured_stream(segments(), segments(), traj.period, machine, config, |s, _, st| each(s, st))
}

/// Simulate a stream of segments sampled every `period` s ([`simulate_stream`], [`SimStates`]) and
/// measure the feed figures as the states come, handing each state and its segment to `each` (false
/// from it stops the simulation). `scout` is the same segments once more.
pub fn simulate_measured_stream(
    segments: impl Iterator<Item = Segment>,
    scout: impl Iterator<Item = Segment>,
    period: f64,
    machine: &Machine,
    config: &SimConfig,
    mut each: impl FnMut(&SimSample, Option<&Segment>, StateValues) -> bool,
) -> (SimSummary, FeedFiguresReport) {
    let mut states = SimStates::new(period, machine);
    let mut figures = FeedFigures::new(machine, period, config.max_listed_regions.unwrap_or(crate::listing::MAX_LISTED));
    let mut open = true;
    // The segment of the state SimStates hands out (it is one sample behind).
    let mut take = |out: Option<(SimSample, StateValues, Option<Rc<Segment>>)>, figures: &mut FeedFigures| -> bool {
        let Some((s, st, seg)) = out else { return open };
        let path_move = seg.as_ref().is_some_and(|g| g.is_path_move() && g.kind != SegmentKind::Rapid);
        figures.push(&(&st).into(), &s.q, s.run, path_move);
        open = open && each(&s, seg.as_deref(), st);
        open
    };
    let summary = simulate_stream(segments, scout, period, machine, config, |s, seg| {
        let out = states.push(s, Some(seg));
        take(out, &mut figures)
    });
    let out = states.finish();
    take(out, &mut figures);
    (summary, figures.finish())
}
