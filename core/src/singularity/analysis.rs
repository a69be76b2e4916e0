//! The whole-trajectory analysis: per-sample status (seed 001 eq. 5, seed 002 eq. 5), regions and a
//! summary, in one streaming pass over the samples.

use super::geometry::SPLINE_OVERLAP_BLOCKS;
use super::{distance, on_pole, FeedLimit, FeedLimiter, PathGeometry};
use crate::machine::Machine;
use crate::path::{GridSampler, Sample, Segment, SegmentWindow, Trajectory};
use nalgebra::Vector3;

/// Options of the analysis.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct AnalysisOptions {
    /// Also open a region where the distance to the singularity falls below this angle (rad), on
    /// simultaneous five-axis moves.
    pub min_distance: Option<f64>,
    /// Secondary-axis speed limit for regions, rad/s (default: the machine's).
    pub rate_limit: Option<f64>,
    /// Regions listed in full (default [`crate::listing::MAX_LISTED`]); the rest are folded into
    /// [`Analysis::unlisted`].
    pub max_listed_regions: Option<usize>,
}

/// What one sample says about the singularity.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Status {
    /// Angle between tool axis and singular direction, rad.
    pub distance: f64,
    /// Seed 001 eq. (5): secondary-axis speed the programmed feed demands, rad/s (machine sign).
    pub predicted_rate: f64,
    /// Plain finite difference of the commanded secondary axis, rad/s.
    pub fd_rate: f64,
    /// Seed 002 eq. (5) at this point of a feed move (None on rapids and rotary-only moves).
    pub feed_limit: Option<FeedLimit>,
    /// True on a simultaneous five-axis move (tool tip and tool axis both moving).
    pub five_axis: bool,
    /// True exactly on the singular direction while the tool axis moves (eq. 5 undefined, 0 reported).
    pub on_pole: bool,
    /// True on a rapid (G00) move: the axes run at their limits by definition, not along a path.
    pub rapid: bool,
    /// The rapid the finite difference spans (this sample's, else the one before's or after's): its
    /// line and block number.
    pub fd_rapid: Option<(usize, Option<u64>)>,
}

/// Why a region was opened.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum RegionCause {
    Speed,
    Distance,
    SpeedAndDistance,
}

/// A contiguous stretch of samples near the singularity.
#[derive(Debug, Clone, PartialEq)]
pub struct Region {
    pub id: usize,
    pub cause: RegionCause,
    /// First and last sample inside (inclusive).
    pub first: usize,
    pub last: usize,
    /// Entry and exit time (s) and tool tip (program coordinates, m), interpolated at the threshold.
    pub t_start: f64,
    pub t_end: f64,
    pub tip_start: Vector3<f64>,
    pub tip_end: Vector3<f64>,
    /// Program lines and block numbers at entry and exit.
    pub line_start: usize,
    pub line_end: usize,
    pub block_start: Option<u64>,
    pub block_end: Option<u64>,
    /// Largest |predicted rate| inside (rad/s, finite), and where.
    pub peak_rate: f64,
    pub peak_tip: Vector3<f64>,
    pub min_distance: f64,
    /// Lowest feed limit inside.
    pub min_feed_limit: Option<FeedLimit>,
    /// Segments of the first and last sample inside.
    pub first_segment: usize,
    pub last_segment: usize,
}

/// The headline figures.
#[derive(Debug, Clone, PartialEq)]
pub struct Summary {
    /// Largest |predicted rate| on feed moves (rad/s) and the tip where it occurs (centre of the stretch
    /// within 0.1 % of the peak around its first sample).
    pub peak_rate: f64,
    pub peak_tip: Vector3<f64>,
    pub peak_line: usize,
    pub peak_block: Option<u64>,
    /// Largest |finite-difference rate|, rad/s: over every sample, over the feed moves alone, and over
    /// the rapids (where the axes run at their own speeds, not along a path) with its line and block.
    pub peak_fd_rate: f64,
    pub peak_fd_feed_rate: f64,
    pub peak_fd_rapid: Option<(f64, usize, Option<u64>)>,
    /// Samples exactly on the singular direction with the tool axis moving (eq. 5 undefined there).
    pub singular_samples: usize,
    /// Closest approach on simultaneous five-axis moves (rad; None if there are none) and overall.
    pub min_distance: Option<f64>,
    pub min_distance_tip: Option<Vector3<f64>>,
    pub min_distance_all: f64,
    /// Lowest seed 002 feed limit over feed moves.
    pub min_feed_limit: Option<FeedLimit>,
    pub min_feed_limit_tip: Option<Vector3<f64>>,
    /// Secondary-axis speed limit used for the regions, rad/s.
    pub rate_limit: f64,
    /// Commanded duration at the programmed feed, s.
    pub cycle_time: f64,
}

/// Everything the analysis found.
#[derive(Debug, Clone)]
pub struct Analysis {
    /// The first regions, in order; the rest are counted and folded into `unlisted`.
    pub regions: Vec<Region>,
    pub unlisted: crate::listing::Unlisted,
    pub summary: Summary,
}

/// What a sample's status needs of its segment (the segment itself may be gone by the time a
/// region closes: only a window of the segments is held).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SegmentInfo {
    /// Block index, program line and block number.
    pub block: usize,
    pub line: usize,
    pub number: Option<u64>,
    /// Start time (s) and tool tip (program coordinates, m).
    pub t0: f64,
    pub tip0: Vector3<f64>,
}

/// What sample `sm` of segment `seg` says on `machine` (singular direction `sd`): the singularity's
/// figures at it, with its finite difference and feed limit as the caller has them.
fn status(machine: &Machine, sd: &Vector3<f64>, sm: &Sample, seg: &Segment, fd: (f64, Option<(usize, Option<u64>)>), feed_limit: Option<FeedLimit>) -> Status {
    let (fd_rate, fd_rapid) = fd;
    Status {
        distance: distance(&sm.axis, sd),
        predicted_rate: machine.chain.secondary_rate(&sm.axis, &sm.axis_rate, &[sm.q[3], sm.q[4]]),
        fd_rate,
        feed_limit,
        five_axis: seg.is_five_axis(),
        on_pole: on_pole(&sm.axis, &sm.axis_rate, sd),
        rapid: seg.kind == crate::path::SegmentKind::Rapid,
        fd_rapid: if seg.kind == crate::path::SegmentKind::Rapid { Some((seg.line, seg.number)) } else { fd_rapid },
    }
}

impl SegmentInfo {
    fn of(seg: &Segment) -> SegmentInfo {
        SegmentInfo { block: seg.block, line: seg.line, number: seg.number, t0: seg.t0, tip0: seg.tip0 }
    }
}

/// Where the samples come from: the period's grid over the segments, or samples held already (a
/// built-in continuous path, sampled from the path itself).
enum SampleSource<'a> {
    Grid(GridSampler),
    Stored(std::slice::Iter<'a, Sample>),
}

/// Each sample of a segment stream with what it says about the singularity, in time order, one at
/// a time: memory holds the window of segments the spline geometry needs, not the trajectory.
pub struct Statuses<'a, I: Iterator<Item = Segment>> {
    machine: &'a Machine,
    window: SegmentWindow<I>,
    source: SampleSource<'a>,
    geometry: PathGeometry,
    limiter: FeedLimiter,
    sd: Vector3<f64>,
    sec: usize,
    prev: Option<Sample>,
    next: Option<Sample>,
    started: bool,
    /// The segments between the last two samples that no sample fell in (shorter than the period),
    /// each evaluated once at its middle, and the closest approach between them (see
    /// [`Statuses::skipped`]), in time order.
    skipped: Vec<(Sample, Status, SegmentInfo)>,
}

impl<'a, I: Iterator<Item = Segment>> Statuses<'a, I> {
    /// The statuses of `segments` sampled every `period` s (or of `stored` samples of them).
    pub fn new(segments: I, stored: Option<&'a [Sample]>, period: f64, machine: &'a Machine) -> Self {
        Statuses {
            machine,
            window: SegmentWindow::new(segments),
            source: match stored {
                Some(s) if !s.is_empty() => SampleSource::Stored(s.iter()),
                _ => SampleSource::Grid(GridSampler::new(period)),
            },
            geometry: PathGeometry::new(),
            limiter: FeedLimiter::new(&machine.limits()),
            sd: machine.singular_direction(),
            sec: machine.secondary_axis(),
            prev: None,
            next: None,
            started: false,
            skipped: Vec::new(),
        }
    }

    /// The segments the sample just handed out passed over since the one before: no sample fell in
    /// them (each shorter than the period), so each is evaluated once, at its middle, so that no
    /// block's demand on the secondary axis goes unseen (a C flip in a 0.15 ms block had been).
    /// Not samples: what publishes samples never sees them.
    pub fn skipped(&mut self) -> std::vec::Drain<'_, (Sample, Status, SegmentInfo)> {
        self.skipped.drain(..)
    }

    /// Segment `j` evaluated at its middle, if it lasts.
    fn midway(&mut self, j: usize) -> Option<(Sample, Status, SegmentInfo)> {
        let seg = self.window.get(j)?;
        if !(seg.duration > 0.0) {
            return None;
        }
        let sm = seg.sample(j, 0.5, seg.t0 + 0.5 * seg.duration, self.machine);
        let info = SegmentInfo::of(seg);
        let status = status(self.machine, &self.sd, &sm, seg, (0.0, None), None);
        Some((sm, status, info))
    }



    /// The closest approach to the singular direction between samples `a` and `b`, where the
    /// distance was falling at `a` and rising at `b` (its rate's sign: that of `(o . s)(o' . s)`,
    /// o the tool axis, s the singular direction): found by golden section over the time between
    /// them and evaluated there, so that a block whose tilt crosses the pole between two samples
    /// reports its true closest approach (a 1 ms grid had left up to half a sample's tilt step:
    /// 0.37 deg for a block through the pole). `None` elsewhere.
    fn closest_between(&mut self, a: &Sample, b: &Sample) -> Option<(Sample, Status, SegmentInfo)> {
        let approach = |s: &Sample| s.axis.dot(&self.sd).signum() * s.axis_rate.dot(&self.sd);
        if !(approach(a) > 0.0 && approach(b) < 0.0) {
            return None;
        }
        let (window, machine, sd) = (&mut self.window, self.machine, self.sd);
        let mut at = |t: f64| -> Option<(Sample, usize)> {
            let j = (a.segment..=b.segment).find(|&j| window.get(j).is_some_and(|seg| t <= seg.t0 + seg.duration))?;
            let seg = window.get(j)?;
            let u = if seg.duration > 0.0 { ((t - seg.t0) / seg.duration).clamp(0.0, 1.0) } else { 0.0 };
            Some((seg.sample(j, u, t, machine), j))
        };
        let d = |s: &Sample| distance(&s.axis, &sd);
        // Golden section: 60 steps narrow the bracket by 0.618^60 (below 1e-12 of it), one new
        // evaluation each (the other interior point is the last step's).
        let g = 0.5 * (5f64.sqrt() - 1.0);
        let (mut lo, mut hi) = (a.t, b.t);
        let (mut t1, mut t2) = (hi - g * (hi - lo), lo + g * (hi - lo));
        let (mut d1, mut d2) = (d(&at(t1)?.0), d(&at(t2)?.0));
        for _ in 0..60 {
            if d1 < d2 {
                (hi, t2, d2) = (t2, t1, d1);
                t1 = hi - g * (hi - lo);
                d1 = d(&at(t1)?.0);
            } else {
                (lo, t1, d1) = (t1, t2, d2);
                t2 = lo + g * (hi - lo);
                d2 = d(&at(t2)?.0);
            }
        }
        let (sm, j) = at(0.5 * (lo + hi))?;
        if !(d(&sm) < d(a).min(d(b))) {
            return None;
        }
        let seg = window.get(j)?;
        let info = SegmentInfo::of(seg);
        Some((sm, status(machine, &sd, &sm, seg, (0.0, None), None), info))
    }

    fn pull(&mut self) -> Option<Sample> {
        match &mut self.source {
            SampleSource::Grid(g) => g.next(&mut self.window, self.machine),
            SampleSource::Stored(it) => it.next().copied(),
        }
    }
}

impl<I: Iterator<Item = Segment>> Iterator for Statuses<'_, I> {
    type Item = (Sample, Status, SegmentInfo);
    fn next(&mut self) -> Option<Self::Item> {
        if !self.started {
            self.started = true;
            self.next = self.pull();
        }
        let sm = self.next.take()?;
        self.next = self.pull();
        // The segments passed over since the last sample, while the window still holds them.
        self.skipped.clear();
        if let (Some(p), SampleSource::Grid(_)) = (self.prev, &self.source) {
            for j in p.segment + 1..sm.segment {
                if let Some(x) = self.midway(j) {
                    self.skipped.push(x);
                }
            }
            if let Some(x) = self.closest_between(&p, &sm) {
                let k = self.skipped.partition_point(|(s, _, _)| s.t <= x.0.t);
                self.skipped.insert(k, x);
            }
        }
        // Central difference of the commanded secondary axis (one-sided at the ends).
        let (a, b) = (self.prev.unwrap_or(sm), self.next.unwrap_or(sm));
        let dt = b.t - a.t;
        let fd_rate = if dt > 0.0 { (b.q[self.sec] - a.q[self.sec]) / dt } else { 0.0 };
        let mut rapid = |x: &Sample| self.window.get(x.segment).filter(|g| g.kind == crate::path::SegmentKind::Rapid).map(|g| (g.line, g.number));
        let fd_rapid = rapid(&a).or_else(|| rapid(&b));
        let feed_limit = self.geometry.derivatives(sm.segment, sm.s, &mut self.window).map(|(d1, d2, d3)| self.limiter.limit(sm.feed, &d1, &d2, &d3));
        let seg = self.window.get(sm.segment).expect("a sample's segment is in the window");
        let (info, status) = (SegmentInfo::of(seg), status(self.machine, &self.sd, &sm, seg, (fd_rate, fd_rapid), feed_limit));
        // Keep what the geometry's overlap reaches back to.
        self.window.release_before(sm.segment.saturating_sub(SPLINE_OVERLAP_BLOCKS + 1));
        self.prev = Some(sm);
        Some((sm, status, info))
    }
}

/// Each sample of a trajectory with what it says about the singularity, in time order, one at a
/// time (the samples are made from the segments as they are read).
pub fn statuses<'a>(traj: &'a Trajectory, machine: &'a Machine) -> impl Iterator<Item = (Sample, Status)> + 'a {
    Statuses::new(traj.segments.iter().cloned(), Some(&traj.stored), traj.period, machine).map(|(sm, st, _)| (sm, st))
}

/// Analyze a trajectory on a machine in one pass over its samples (see [`analyze_segments`]).
pub fn analyze(traj: &Trajectory, machine: &Machine, options: &AnalysisOptions) -> Analysis {
    analyze_stream(traj.segments.iter().cloned(), Some(&traj.stored), traj.period, machine, options, |_| {}, |_, _, _| {}).0
}

/// What a streamed analysis counted besides its findings.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct StreamCounts {
    pub samples: usize,
    pub segments: usize,
}

/// Analyze a stream of segments sampled every `period` s, in one pass: memory holds a window of the
/// segments and the regions, never the samples or the program.
pub fn analyze_segments(segments: impl Iterator<Item = Segment>, period: f64, machine: &Machine, options: &AnalysisOptions) -> (Analysis, StreamCounts) {
    analyze_stream(segments, None, period, machine, options, |_| {}, |_, _, _| {})
}

/// [`analyze_segments`], handing each sample to `on_sample` as the analysis makes it, with the next
/// sample (None at the end) and the sample's segment: a consumer that needs the same samples (the
/// in-process run's commander, which publishes them) takes them instead of sampling the program again.
pub fn analyze_segments_along(
    segments: impl Iterator<Item = Segment>,
    period: f64,
    machine: &Machine,
    options: &AnalysisOptions,
    on_sample: impl FnMut(&Sample, Option<&Sample>, Option<&Segment>),
) -> (Analysis, StreamCounts) {
    analyze_stream(segments, None, period, machine, options, |_| {}, on_sample)
}

/// [`analyze_segments`], handing every region to `each` as it closes (listed or folded): what a
/// consumer keeps of all of them (their times, say) without holding them whole.
pub fn analyze_segments_each(
    segments: impl Iterator<Item = Segment>,
    period: f64,
    machine: &Machine,
    options: &AnalysisOptions,
    each: impl FnMut(&Region),
) -> (Analysis, StreamCounts) {
    analyze_stream(segments, None, period, machine, options, each, |_, _, _| {})
}

/// The programmed extremes lie at block ends, which the sample grid may miss by a fraction of a
/// period: the closest approach over the five-axis moves' end points (the first of equal ones), and
/// the end of the last segment.
#[derive(Debug, Clone, Copy)]
struct SegmentEnds {
    sd: Vector3<f64>,
    /// Over five-axis moves (distance, tool tip), and over all their end points.
    five_axis: Option<(f64, Vector3<f64>)>,
    all: f64,
    end_time: f64,
    count: usize,
    /// The last end point's rotary angles and distance: a segment starts where the last ended.
    last: Option<([u64; 2], f64)>,
}

impl SegmentEnds {
    fn push(&mut self, seg: &Segment, machine: &Machine) {
        self.count += 1;
        self.end_time = seg.t0 + seg.duration;
        if !seg.is_five_axis() {
            return;
        }
        for (q, tip) in [(&seg.q0, seg.tip0), (&seg.q1, seg.tip1)] {
            let key = [q[3].to_bits(), q[4].to_bits()];
            let d = match self.last {
                Some((k, d)) if k == key => d,
                _ => distance(&machine.chain.orientation(&[q[3], q[4]]), &self.sd),
            };
            self.last = Some((key, d));
            if self.five_axis.is_none_or(|(m, _)| d < m) {
                self.five_axis = Some((d, tip));
            }
            self.all = self.all.min(d);
        }
    }
}

fn analyze_stream(
    segments: impl Iterator<Item = Segment>,
    stored: Option<&[Sample]>,
    period: f64,
    machine: &Machine,
    options: &AnalysisOptions,
    mut each: impl FnMut(&Region),
    mut on_sample: impl FnMut(&Sample, Option<&Sample>, Option<&Segment>),
) -> (Analysis, StreamCounts) {
    let sd = machine.singular_direction();
    let limits = machine.limits();
    let rate_limit = options.rate_limit.unwrap_or(limits[machine.secondary_axis()].velocity);
    let mut regions: Vec<Region> = Vec::new();
    let mut unlisted = crate::listing::Unlisted::default();
    let cap = options.max_listed_regions.unwrap_or(crate::listing::MAX_LISTED);
    let mut opened = 0usize;
    let mut open: Option<Region> = None;
    let mut peak = PeakTracker::default();
    let mut singular_samples = 0;
    let mut peak_fd: f64 = 0.0;
    let mut peak_fd_feed: f64 = 0.0;
    let mut peak_fd_rapid: Option<(f64, usize, Option<u64>)> = None;
    let mut min_d: Option<(f64, Vector3<f64>)> = None;
    let mut min_all = f64::INFINITY;
    let mut min_fl: Option<(FeedLimit, Vector3<f64>)> = None;
    let mut last: Option<(Sample, Status, SegmentInfo)> = None;
    let mut n = 0usize;
    let mut ends = SegmentEnds { sd, five_axis: None, all: f64::INFINITY, end_time: 0.0, count: 0, last: None };
    let segments = segments.inspect(|seg| ends.push(seg, machine));
    let mut statuses = Statuses::new(segments, stored, period, machine);
    // One evaluation (a sample, or a segment no sample fell in: `real` false) into the regions and
    // the summary, as the `k`th sample.
    macro_rules! evaluate {
        ($k:expr, $sm:expr, $st:expr, $info:expr, $real:expr) => {{
            let (k, sm, st, info, real): (usize, Sample, Status, SegmentInfo, bool) = ($k, $sm, $st, $info, $real);
            // Regions: contiguous samples beyond the limits, entered and left at the interpolated crossing.
            // On the pole eq. (5) is undefined (0 is reported): a region goes on through it.
            let cause = match (in_region(&st, rate_limit, options.min_distance), &open) {
                (None, Some(r)) if st.on_pole && !st.rapid => Some(r.cause),
                (c, _) => c,
            };
            match (cause, open.as_mut()) {
                (Some(cause), Some(r)) => {
                    if cause != r.cause {
                        r.cause = RegionCause::SpeedAndDistance;
                    }
                    r.grow(k, &sm, &st, &info);
                }
                (Some(cause), None) => {
                    let (t_start, tip_start) = match &last {
                        Some((ps, pst, pinfo)) => boundary((ps, pinfo), (&sm, &info), crossing(pst, &st, rate_limit)),
                        None => (sm.t, sm.tip),
                    };
                    opened += 1;
                    let mut r = Region::start(opened, cause, k, t_start, tip_start, &sm, &info);
                    r.grow(k, &sm, &st, &info);
                    open = Some(r);
                }
                (None, Some(_)) => {
                    let (ls, lst, linfo) = last.as_ref().expect("a region holds a sample");
                    let mut r = open.take().expect("open");
                    (r.t_end, r.tip_end) = boundary((ls, linfo), (&sm, &info), 1.0 - crossing(&st, lst, rate_limit));
                    each(&r);
                    crate::listing::push(&mut regions, &mut unlisted, cap, r);
                }
                (None, None) => {}
            }
            // Summary.
            peak.push(k, &sm, &st, &info);
            if real && st.on_pole {
                singular_samples += 1;
            }
            peak_fd = peak_fd.max(st.fd_rate.abs());
            match st.fd_rapid {
                None => peak_fd_feed = peak_fd_feed.max(st.fd_rate.abs()),
                Some((line, number)) if st.fd_rate.abs() > peak_fd_rapid.map_or(0.0, |p| p.0) => peak_fd_rapid = Some((st.fd_rate.abs(), line, number)),
                Some(_) => {}
            }
            min_all = min_all.min(st.distance);
            if st.five_axis && min_d.is_none_or(|(d, _)| st.distance < d) {
                min_d = Some((st.distance, sm.tip));
            }
            if let Some(fl) = st.feed_limit {
                if min_fl.is_none_or(|(m, _)| fl.feed < m.feed) {
                    min_fl = Some((fl, sm.tip));
                }
            }
            last = Some((sm, st, info));
        }};
    }
    while let Some((sm, st, info)) = statuses.next() {
        on_sample(&sm, statuses.next.as_ref(), statuses.window.loaded(sm.segment));
        let passed: Vec<_> = statuses.skipped().collect();
        for (xs, xst, xinfo) in passed {
            evaluate!(n, xs, xst, xinfo, false);
        }
        let k = n;
        n += 1;
        evaluate!(k, sm, st, info, true);
    }
    if let (Some(mut r), Some((ls, _, _))) = (open.take(), &last) {
        (r.t_end, r.tip_end) = (ls.t, ls.tip);
        each(&r);
        crate::listing::push(&mut regions, &mut unlisted, cap, r);
    }
    let (peak_rate, peak_tip, peak_line, peak_block) = match peak.best {
        Some((v, _, _, line, number)) => (v, (peak.a_tip + peak.b_tip) / 2.0, line, number),
        None => (0.0, Vector3::zeros(), 0, None),
    };
    let mut summary = Summary {
        peak_rate,
        peak_tip,
        peak_line,
        peak_block,
        peak_fd_rate: peak_fd,
        peak_fd_feed_rate: peak_fd_feed,
        peak_fd_rapid,
        singular_samples,
        min_distance: min_d.map(|(d, _)| d),
        min_distance_tip: min_d.map(|(_, t)| t),
        min_distance_all: if n == 0 { f64::NAN } else { min_all },
        min_feed_limit: min_fl.map(|(f, _)| f),
        min_feed_limit_tip: min_fl.map(|(_, t)| t),
        rate_limit,
        cycle_time: ends.end_time,
    };
    // The block ends' closest approach, where it is closer than the samples'.
    if let Some((d, tip)) = ends.five_axis {
        if summary.min_distance.is_none_or(|m| d < m) {
            summary.min_distance = Some(d);
            summary.min_distance_tip = Some(tip);
        }
    }
    summary.min_distance_all = summary.min_distance_all.min(ends.all);
    (Analysis { regions, unlisted, summary }, StreamCounts { samples: n, segments: ends.count })
}

impl crate::listing::Listed for Region {
    fn figures(&self) -> crate::listing::Figures {
        crate::listing::Figures {
            id: Some(self.id as u64),
            time_s: self.t_end - self.t_start,
            time_lost_s: None,
            peak_c_speed_rpm: Some(self.peak_rate / crate::units::RPM),
            min_singularity_distance_deg: Some(self.min_distance.to_degrees()),
            min_feed_mm_per_min: self.min_feed_limit.map(|f| f.feed / crate::units::MM_PER_MIN),
        }
    }
}

impl Region {
    fn start(id: usize, cause: RegionCause, k: usize, t_start: f64, tip_start: Vector3<f64>, sm: &Sample, info: &SegmentInfo) -> Region {
        Region {
            id,
            cause,
            first: k,
            last: k,
            t_start,
            t_end: sm.t,
            tip_start,
            tip_end: sm.tip,
            line_start: info.line,
            line_end: info.line,
            block_start: info.number,
            block_end: info.number,
            peak_rate: 0.0,
            peak_tip: sm.tip,
            min_distance: f64::INFINITY,
            min_feed_limit: None,
            first_segment: sm.segment,
            last_segment: sm.segment,
        }
    }

    /// Take sample `k` into the region: its peak (the last of equal peaks), closest approach and lowest
    /// feed limit (the first of equal ones).
    fn grow(&mut self, k: usize, sm: &Sample, st: &Status, info: &SegmentInfo) {
        self.last = k;
        self.last_segment = sm.segment;
        (self.line_end, self.block_end) = (info.line, info.number);
        if st.predicted_rate.is_finite() && st.predicted_rate.abs() >= self.peak_rate {
            self.peak_rate = st.predicted_rate.abs();
            self.peak_tip = sm.tip;
        }
        self.min_distance = self.min_distance.min(st.distance);
        if let Some(fl) = st.feed_limit {
            if self.min_feed_limit.is_none_or(|m| fl.feed < m.feed) {
                self.min_feed_limit = Some(fl);
            }
        }
    }
}

/// The peak predicted rate over the path (rapids excluded) and the stretch around it within 0.1 % of
/// it (its centre is where the peak is reported): streaming, keeping only the samples of the current
/// run near the running maximum.
#[derive(Debug, Default)]
struct PeakTracker {
    /// (|rate|, sample index, segment, its line and block number) of the first largest.
    best: Option<(f64, usize, usize, usize, Option<u64>)>,
    a_tip: Vector3<f64>,
    b_tip: Vector3<f64>,
    /// Still extending the stretch forward from the peak.
    b_open: bool,
    /// The trailing run of samples (|rate|, tip) that could belong to a later peak's stretch: within
    /// 0.1 % below the running maximum or above it.
    chain: std::collections::VecDeque<(f64, Vector3<f64>)>,
}

impl PeakTracker {
    const NEAR: f64 = 1e-3;
    const MAX_CHAIN: usize = 1 << 20;

    fn push(&mut self, k: usize, sm: &Sample, st: &Status, info: &SegmentInfo) {
        let r = st.predicted_rate.abs();
        let v = self.best.map_or(0.0, |b| b.0);
        let near = |x: f64, v: f64| (x - v).abs() <= Self::NEAR * v;
        if !st.rapid && (self.best.is_none() || r > v) {
            // A new peak: its stretch reaches back over the trailing samples near it.
            let mut a_tip = sm.tip;
            for &(x, tip) in self.chain.iter().rev() {
                if !near(x, r) {
                    break;
                }
                a_tip = tip;
            }
            self.best = Some((r, k, sm.segment, info.line, info.number));
            (self.a_tip, self.b_tip, self.b_open) = (a_tip, sm.tip, true);
        } else if self.b_open && near(r, v) {
            self.b_tip = sm.tip;
        } else {
            self.b_open = false;
        }
        // Keep the trailing run that a later, higher peak could extend back over.
        let v = self.best.map_or(0.0, |b| b.0);
        if r >= (1.0 - Self::NEAR) * v {
            if self.chain.len() == Self::MAX_CHAIN {
                self.chain.pop_front();
            }
            self.chain.push_back((r, sm.tip));
        } else {
            self.chain.clear();
        }
    }
}

fn in_region(s: &Status, rate_limit: f64, min_distance: Option<f64>) -> Option<RegionCause> {
    // A rapid runs its axes at their limits by definition: it is not a tool path that demands more.
    if s.rapid {
        return None;
    }
    let speed = s.predicted_rate.abs() > rate_limit;
    let dist = s.five_axis && min_distance.is_some_and(|d| s.distance < d);
    match (speed, dist) {
        (true, true) => Some(RegionCause::SpeedAndDistance),
        (true, false) => Some(RegionCause::Speed),
        (false, true) => Some(RegionCause::Distance),
        (false, false) => None,
    }
}

/// Fraction between an outside sample `o` and an inside sample `i` where the speed crosses the limit.
fn crossing(o: &Status, i: &Status, rate_limit: f64) -> f64 {
    let (a, b) = (o.predicted_rate.abs() - rate_limit, i.predicted_rate.abs() - rate_limit);
    if a.is_finite() && b.is_finite() && a <= 0.0 && b > 0.0 {
        a / (a - b)
    } else {
        0.5
    }
}

/// Where a region boundary between samples `a` and `b` lies: at the block junction if they belong to
/// different blocks (the speed steps there: the axes, or the tool axis' great circle, change rate from
/// block to block), else at fraction `f` (within a block the speed is continuous, across the pieces of
/// an arc or of a great circle too).
fn boundary(a: (&Sample, &SegmentInfo), b: (&Sample, &SegmentInfo), f: f64) -> (f64, Vector3<f64>) {
    let ((a, ai), (b, bi)) = (a, b);
    if ai.block != bi.block && bi.t0 >= a.t && bi.t0 <= b.t {
        return (bi.t0, bi.tip0);
    }
    (a.t + (b.t - a.t) * f, a.tip + (b.tip - a.tip) * f)
}
