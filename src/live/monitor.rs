//! Monitor: per axis-state sample, the distance to the singularity, the predicted secondary-axis speed
//! (seed 001 eq. 5), the feed limit and limiting axis (seed 002 eq. 5), region entry and exit, a
//! look-ahead from the commanded stream, and input health (NaN/Inf, out of range, out of order, stale).
//! The same math as the offline analysis ([`crate::singularity`]), fed one sample at a time.

use crate::kinematics::Joints;
use crate::machine::{Machine, AXES};
use crate::path::align::{Aligner, OpenSegments};
use crate::path::Segment;
use crate::singularity::measured::{MeasuredConfig, MeasuredPath, Motion};
use crate::singularity::tracker::{Cause, RegionRule, RegionTracker, RuleSample, TrackedRegion};
use crate::singularity::{distance, FeedLimiter, LimitKind};
use std::sync::Arc;
use fiveaxis_msgs::{AxisState, DiagnosticArray, DiagnosticStatus, Header, KeyValue, Point, SingularityStatus, Time};
use nalgebra::Vector3;
use std::collections::{BTreeMap, VecDeque};

/// Monitor settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MonitorConfig {
    /// A stream with no sample for this long (s, wall clock) is stale; for one that sends more
    /// slowly, three of its own periods.
    pub stale_timeout: f64,
    /// WARN when the tool axis comes closer than this to the singularity (rad).
    pub warn_distance: f64,
    /// WARN when a region lies less than this ahead (s).
    pub warn_ahead: f64,
    /// Also a region when closer than this (rad), on moving samples.
    pub min_distance: Option<f64>,
    /// Secondary-axis speed limit for regions (rad/s); default the machine's.
    pub rate_limit: Option<f64>,
    /// The control's work offset (G54-style datum, workpiece frame, m): a stream's tool tip less it is
    /// the program's point where no program says which datum is in effect.
    pub work_offset: Vector3<f64>,
    /// Regions listed in full per stream; the rest are folded into its summary's `unlisted_regions`.
    pub max_listed_regions: usize,
}

impl Default for MonitorConfig {
    fn default() -> Self {
        MonitorConfig { stale_timeout: 0.1, warn_distance: 5f64.to_radians(), warn_ahead: 2.0, min_distance: None, rate_limit: None, work_offset: Vector3::zeros(), max_listed_regions: crate::listing::MAX_LISTED }
    }
}

/// Why a sample was not used.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum Rejection {
    #[error("invalid sample: {0}")]
    Invalid(String),
    /// A position that is NaN or infinite (the axis and value).
    #[error("invalid sample: {0}")]
    NonFinite(String),
    #[error("out of order: stamp {stamp:.6} s is not after {last:.6} s")]
    OutOfOrder { stamp: f64, last: f64 },
    /// A machine axis has no joint in a JointState (the joint name looked for).
    #[error("joint '{0}' missing from the JointState")]
    MissingJoint(String),
}

/// Rejections counted by reason (each stream's summary, the status, `/diagnostics`, the JSON).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize)]
pub struct Rejected {
    /// A machine axis had no joint of its mapped name in the message.
    pub missing_joint: u64,
    /// A position or feed was NaN or infinite.
    pub non_finite: u64,
    /// A position outside the axis' range.
    pub out_of_range: u64,
    /// Stamped no later than the previous sample.
    pub out_of_order: u64,
    /// Anything else malformed (array lengths, stamp fields).
    pub malformed: u64,
}

impl Rejected {
    /// Every rejection.
    pub fn total(&self) -> u64 {
        self.missing_joint + self.non_finite + self.out_of_range + self.out_of_order + self.malformed
    }

    /// Rejections other than out of order (the status' `invalid_count`).
    pub fn invalid(&self) -> u64 {
        self.total() - self.out_of_order
    }

    fn count(&mut self, reason: Reason) {
        *match reason {
            Reason::MissingJoint => &mut self.missing_joint,
            Reason::NonFinite => &mut self.non_finite,
            Reason::OutOfRange => &mut self.out_of_range,
            Reason::OutOfOrder => &mut self.out_of_order,
            Reason::Malformed => &mut self.malformed,
        } += 1;
    }
}

/// Which counter a rejection goes to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Reason {
    MissingJoint,
    NonFinite,
    OutOfRange,
    OutOfOrder,
    Malformed,
}

/// The message of a position outside its axis' range (see [`Rejection::is_out_of_range`]).
const OUT_OF_RANGE: &str = "outside its range";

impl Rejection {
    /// True for a position outside its axis' range (a publisher in mm and degrees shows as these).
    pub fn is_out_of_range(&self) -> bool {
        matches!(self, Rejection::Invalid(why) if why.ends_with(OUT_OF_RANGE))
    }
}

/// Where the programmed feed of a machine stream's prediction comes from.
#[derive(Debug, Clone, Default, PartialEq)]
pub enum FeedSource {
    /// Each sample aligned with the program's moves (their feed, block numbers and kinds), and the
    /// program's own regions (for the look-ahead warning).
    Program(Arc<ProgramPlan>),
    /// One feed for every feed move, m/s.
    Fixed(f64),
    /// Neither given: the tool-tip feed the stream has held longest on feed moves so far (in bins of
    /// 2 %; a programmed feed is what a cutting program spends its time at, rapids are short).
    #[default]
    Assumed,
}

/// A program as a machine stream is aligned with it: its moves, read again as a stream by each
/// stream's aligner (not held), and its regions (start and end in program time at the programmed
/// feed, s) from the program analysis.
#[derive(Clone)]
pub struct ProgramPlan {
    pub segments: OpenSegments,
    /// In program order (start times increasing).
    pub regions: Vec<(f64, f64)>,
}

impl ProgramPlan {
    /// Program time from `t` to the start of the first region starting after it, s (-1: none). The
    /// regions are in program order: a binary search, not a scan of a long program's thousands.
    pub fn time_to_next_region(&self, t: f64) -> f64 {
        self.regions.get(self.regions.partition_point(|r| r.0 <= t)).map_or(-1.0, |r| r.0 - t)
    }

    /// A plan over moves already held (built-in paths, tests).
    pub fn held(segments: Vec<Segment>, regions: Vec<(f64, f64)>) -> ProgramPlan {
        ProgramPlan { segments: crate::path::align::open_held(Arc::new(segments)), regions }
    }
}

impl std::fmt::Debug for ProgramPlan {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ProgramPlan").field("regions", &self.regions.len()).finish_non_exhaustive()
    }
}

/// Two plans are the same plan (the same opener).
impl PartialEq for ProgramPlan {
    fn eq(&self, other: &Self) -> bool {
        Arc::ptr_eq(&self.segments, &other.segments) && self.regions == other.regions
    }
}

impl FeedSource {
    /// Say which feed is assumed and why, for people.
    pub fn describe(&self) -> String {
        match self {
            FeedSource::Program(_) => "the program's feed of each move (stream aligned with the program)".into(),
            FeedSource::Fixed(f) => format!("{:.0} mm/min for every feed move (--feed)", f / crate::units::MM_PER_MIN),
            FeedSource::Assumed => "ASSUMED: the tool-tip feed the stream held longest (2 % bins, over 0.1 s) on feed moves so far (no --program or --feed given: give one for a sound figure)".into(),
        }
    }
}

/// A region as one stream went through it.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct LiveRegion {
    pub id: u32,
    pub t_start_s: f64,
    pub t_end_s: f64,
    pub x_start_mm: f64,
    pub x_end_mm: f64,
    pub block_start: i64,
    pub block_end: i64,
    /// Program lines (0: unknown), for programs without block numbers.
    pub line_start: u32,
    pub line_end: u32,
    pub peak_c_speed_rpm: f64,
    pub min_path_feed_mm_per_min: f64,
    pub min_singularity_distance_deg: f64,
    /// Time spent in the region beyond what the programmed feed would have taken, s.
    pub time_lost_s: f64,
    /// Why the region was opened.
    pub cause: Cause,
}

impl crate::listing::Listed for LiveRegion {
    fn figures(&self) -> crate::listing::Figures {
        crate::listing::Figures {
            id: Some(self.id.into()),
            time_s: self.t_end_s - self.t_start_s,
            time_lost_s: Some(self.time_lost_s),
            peak_c_speed_rpm: Some(self.peak_c_speed_rpm),
            min_singularity_distance_deg: Some(self.min_singularity_distance_deg),
            min_feed_mm_per_min: Some(self.min_path_feed_mm_per_min),
        }
    }
}

impl LiveRegion {
    fn from_tracked(r: &TrackedRegion) -> LiveRegion {
        let rpm = crate::units::RPM;
        LiveRegion {
            id: r.id,
            t_start_s: r.t_start,
            t_end_s: r.t_end,
            x_start_mm: r.tip_start.x * 1e3,
            x_end_mm: r.tip_end.x * 1e3,
            block_start: r.block_start,
            block_end: r.block_end,
            line_start: r.line_start,
            line_end: r.line_end,
            peak_c_speed_rpm: r.peak / rpm,
            min_path_feed_mm_per_min: r.min_path_feed / crate::units::MM_PER_MIN,
            min_singularity_distance_deg: r.min_distance.to_degrees(),
            time_lost_s: r.time_lost,
            cause: r.cause,
        }
    }
}

/// What happened on one input stream.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct InputSummary {
    pub topic: String,
    pub source: u8,
    pub samples: u64,
    pub invalid: u64,
    pub out_of_order: u64,
    pub stale: u64,
    pub lost: u64,
    /// Rejections by reason.
    pub rejected: Rejected,
    /// The stream's sample period (mean interval over about the last 1024 stamps, judged losses put back), s.
    pub period_s: Option<f64>,
    /// Samples by motion kind (machine streams: rapid, feed, rotary-only, dwell).
    pub rapid_samples: u64,
    pub feed_samples: u64,
    /// Largest actual tool-tip feed held for 0.1 s on feed moves, mm/min (machine streams).
    pub max_path_feed_mm_per_min: f64,
    /// The programmed feed the machine stream's prediction assumed, for people.
    pub feed_source: Option<String>,
    /// Why the program (`--program`) could not be read again to align this stream with it (its
    /// samples then have no program place): an error.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub program_unreadable: Option<String>,
    /// The first regions in full (with the open one), and the rest folded.
    pub regions: Vec<LiveRegion>,
    pub unlisted_regions: crate::listing::Unlisted,
}

/// The monitor's figures for one sample, without the strings of [`SingularityStatus`]: what the
/// offline analysis needs per message (millions of them), and what a status is built from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Evaluation {
    pub stamp: Time,
    pub source: u8,
    /// Angle between the tool axis and the singular direction, rad.
    pub singularity_distance: f64,
    /// Seed 001 eq. (5) at the programmed feed, rad/s.
    pub predicted_c_speed: f64,
    /// The secondary axis' speed between the last two samples, rad/s.
    pub c_speed: f64,
    /// Seed 002 eq. (5), m/s, with the limiting axis (index) and what limits it.
    pub feed_limit: f64,
    pub limiting_axis: Option<usize>,
    pub limit_kind: LimitKind,
    pub in_region: bool,
    pub region_id: u32,
    /// The tool tip in workpiece coordinates, m.
    pub workpiece_position: Vector3<f64>,
    pub time_to_next_region: f64,
    pub program_line: u32,
    pub block_number: i64,
    /// What the sample is doing, and the region's cause while one is open.
    pub motion: Motion,
    pub cause: Option<Cause>,
    /// The actual tool-tip feed and the programmed feed the prediction assumes, m/s.
    pub path_feed: f64,
    pub programmed_feed: f64,
    /// The tool axis turns (machine streams; true elsewhere): with a feed move, five-axis motion.
    pub turning: bool,
    /// Machine streams: the distance to the singularity of the demand window's middle sample where
    /// that sample lies on simultaneous five-axis motion within a whole window of path (a closest
    /// approach candidate: a blend into a rotary-only move does not count).
    pub five_axis_distance: Option<f64>,
}

/// A stream of the monitor, by index (see [`Monitor::input`]): no topic lookup per sample.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct InputId(usize);

#[derive(Debug, Clone, Copy)]
struct Past {
    t: f64,
    s: f64,
    q: Joints,
    axis: Vector3<f64>,
    tip: Vector3<f64>,
}

/// Tip travel into a block below which the monitor holds the previous prediction (m).
const MIN_DEMAND_PATH: f64 = 1e-6;

/// What the monitor keeps per input stream.
#[derive(Debug, Default)]
struct Input {
    source: u8,
    history: VecDeque<Past>,
    s: f64,
    /// The program line of the current block and the path length where the stream entered it.
    block_start: (u32, f64),
    /// The first closed regions, the rest folded, and the last one closed (its end event).
    regions: Vec<LiveRegion>,
    unlisted: crate::listing::Unlisted,
    last_closed: Option<LiveRegion>,
    stale: u64,
    stale_now: bool,
    last_arrival: Option<f64>,
    last: Option<Evaluation>,
    cursor: (usize, usize),
    samples: u64,
    /// Recent stamps, the period and the spread of the intervals (10th to 90th percentile), samples
    /// missing from gaps in the stamps, a stretch of gaps being judged and the losses judged recently.
    stamps: VecDeque<f64>,
    period: Option<(f64, f64)>,
    /// Gaps are not judged as losses (see [`Monitor::set_change_only`]).
    change_only: bool,
    /// The last interval between stamps (the stale limit before a period is known).
    last_interval: Option<f64>,
    lost: u64,
    episode: Option<LossEpisode>,
    loss_events: VecDeque<LossEvent>,
    rejected: Rejected,
    /// Machine streams: the measured path, the region rule's state, the program alignment and the
    /// lagged sample the rule saw last (t, s).
    measured: Option<MeasuredPath>,
    tracker: RegionTracker,
    aligner: Option<Aligner>,
    lagged: Option<(f64, f64)>,
    max_feed: f64,
    /// (t, s) of the recent samples of the current run of feed motion (the assumed feed is the
    /// highest feed held over [`HELD`] within one run).
    feed_run: VecDeque<(f64, f64)>,
    /// Time spent at each held feed (bins of 2 % from 1 mm/min) and the bin held longest.
    feed_time: Vec<f64>,
    feed_mode: Option<usize>,
    rapid_samples: u64,
    feed_samples: u64,
    /// The worst evaluation since `/diagnostics` last reported (its level and the peak predicted
    /// speed over it), so that a short event between two reports is never missed.
    worst: Option<(u8, Evaluation)>,
}

/// One commanded sample remembered for the look-ahead.
#[derive(Debug, Clone, Copy)]
struct Ahead {
    t: f64,
    line: u32,
    tip: Vector3<f64>,
}

/// How much of the commanded timeline the look-ahead keeps (s of commanded time before the newest
/// commanded sample): a stream further behind the commander than this finds no region ahead. It
/// bounds the monitor's memory whatever the program's length.
pub const AHEAD_RETENTION_S: f64 = 120.0;

/// The commanded timeline the look-ahead reads: the last [`AHEAD_RETENTION_S`] of commanded samples
/// and which of them lie in a region. Indices are absolute (from the stream's first sample), so the
/// streams' cursors survive the dropping of old entries.
#[derive(Debug, Clone, Default)]
struct Timeline {
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
    fn last(&self) -> Option<&Ahead> {
        self.entries.back()
    }
    /// Entry index of the `k`-th in-region entry, if still held.
    fn region(&self, k: usize) -> Option<usize> {
        k.checked_sub(self.regions_base)
            .and_then(|r| self.regions.get(r))
            .copied()
    }
    fn push(&mut self, a: Ahead, in_region: bool) {
        if in_region {
            self.regions.push_back(self.end());
        }
        self.entries.push_back(a);
        while self
            .entries
            .front()
            .is_some_and(|f| f.t < a.t - AHEAD_RETENTION_S)
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

/// The monitor's state.
#[derive(Debug)]
pub struct Monitor {
    machine: Machine,
    config: MonitorConfig,
    singular: Vector3<f64>,
    secondary: usize,
    limit: f64,
    limiter: FeedLimiter,
    /// The streams, and their indices by topic (sorted: summaries list them in topic order).
    inputs: Vec<Input>,
    index: BTreeMap<String, usize>,
    ahead: Timeline,
    prev_commanded_axis: Option<Vector3<f64>>,
    /// Machine streams: where the programmed feed comes from, and the region rule.
    feed_source: FeedSource,
    rule: RegionRule,
    /// Evaluations of program streams carry no feed limit ([`Monitor::set_regions_only`]).
    regions_only: bool,
}

fn vec3(p: &Point) -> Vector3<f64> {
    Vector3::new(p.x, p.y, p.z)
}

impl Monitor {
    pub fn new(machine: &Machine, config: MonitorConfig) -> Monitor {
        let secondary = machine.secondary_axis();
        let limits = machine.limits();
        Monitor {
            machine: machine.clone(),
            config,
            singular: machine.singular_direction(),
            secondary,
            limit: config.rate_limit.unwrap_or(limits[secondary].velocity),
            limiter: FeedLimiter::new(&limits),
            inputs: Vec::new(),
            index: BTreeMap::new(),
            ahead: Timeline::default(),
            prev_commanded_axis: None,
            feed_source: FeedSource::Assumed,
            rule: RegionRule::new(config.rate_limit.unwrap_or(limits[secondary].velocity), config.min_distance),
            regions_only: false,
        }
    }

    /// For a caller that keeps only the regions and counters (an in-process run's report, which
    /// records no status; the offline analysis of a recording): every evaluation then carries the
    /// programmed feed as its feed limit, with no limiting axis, instead of seed 002 eq. (5) on the
    /// divided differences (machine streams: on the measured path), which nothing would read.
    /// Regions, counters and the C speeds are the same.
    pub fn set_regions_only(&mut self, on: bool) {
        self.regions_only = on;
    }

    /// Where machine streams' programmed feed comes from (default [`FeedSource::Assumed`]).
    pub fn set_feed_source(&mut self, source: FeedSource) {
        self.feed_source = source;
    }

    /// Count a sample of stream `id` that could not even be turned into axis positions (a JointState
    /// without a mapped joint): every rejection is counted by reason.
    pub fn reject(&mut self, id: InputId, rejection: &Rejection) {
        self.inputs[id.0].rejected.count(match rejection {
            Rejection::MissingJoint(_) => Reason::MissingJoint,
            Rejection::OutOfOrder { .. } => Reason::OutOfOrder,
            Rejection::Invalid(_) => Reason::Malformed,
            Rejection::NonFinite(_) => Reason::NonFinite,
        });
    }



    /// The sample's tool axis and tool tip (workpiece coordinates): as the message gives them (the
    /// commander and the simulator fill them in), else by forward kinematics of its axis positions
    /// (a machine bridge's JointState carries positions only).
    fn axis_and_tip(machine: &Machine, st: &AxisState, q: &Joints) -> (Vector3<f64>, Vector3<f64>) {
        let given_axis = Vector3::new(st.tool_axis.x, st.tool_axis.y, st.tool_axis.z);
        let axis_given = (given_axis.norm() - 1.0).abs() < 1e-6;
        let tip_given = st.program_line > 0 || st.tool_tip != Point::default();
        if axis_given && tip_given {
            return (given_axis, vec3(&st.tool_tip));
        }
        let pose = machine.forward(q);
        (if axis_given { given_axis } else { pose.axis }, if tip_given { vec3(&st.tool_tip) } else { pose.tip })
    }

    fn validate(&self, st: &AxisState) -> Result<Joints, (Reason, Rejection)> {
        if st.position.len() != AXES {
            return Err((Reason::Malformed, Rejection::Invalid(format!("expected {AXES} positions, got {}", st.position.len()))));
        }
        let q: Joints = std::array::from_fn(|i| st.position[i]);
        for (i, v) in q.iter().enumerate() {
            let a = &self.machine.axes[i];
            if !v.is_finite() {
                return Err((Reason::NonFinite, Rejection::Invalid(format!("{} position is {v}", a.name))));
            }
            // A little slack for servo overshoot and rounding at the end stops.
            let slack = if i < 3 { 1e-3 } else { 1e-3f64.to_radians() };
            if *v < a.limits.min - slack || *v > a.limits.max + slack {
                return Err((Reason::OutOfRange, Rejection::Invalid(format!("{} position {v:.6} {OUT_OF_RANGE}", a.name))));
            }
        }
        let stamp = st.header.stamp;
        if stamp.nanosec >= 1_000_000_000 {
            return Err((Reason::Malformed, Rejection::Invalid("header stamp nanosec out of range".into())));
        }
        for (what, v) in [("programmed_feed", st.programmed_feed), ("path_feed", st.path_feed)] {
            if !v.is_finite() {
                return Err((Reason::NonFinite, Rejection::Invalid(format!("{what} is {v}"))));
            }
            if v < 0.0 {
                return Err((Reason::Malformed, Rejection::Invalid(format!("{what} is {v}"))));
            }
        }
        Ok(q)
    }

    /// Remember a commanded sample for the look-ahead (call for each commanded state, in order).
    pub fn on_commanded_ahead(&mut self, st: &AxisState) {
        let Ok(q) = self.validate(st) else { return };
        let (axis, tip) = Self::axis_and_tip(&self.machine, st, &q);
        let t = st.header.stamp.as_secs();
        if self.ahead.last().is_some_and(|a| t <= a.t) {
            return;
        }
        // In a region if the step from the previous commanded sample demands more than the limit.
        let in_region = match self.ahead.last() {
            Some(prev) => {
                let prev_q = self.prev_commanded_axis.unwrap_or(axis);
                let dt = t - prev.t;
                let rate = if dt > 0.0 { self.machine.chain.secondary_rate(&axis, &((axis - prev_q) / dt), &[q[3], q[4]]) } else { 0.0 };
                rate.abs() > self.limit
            }
            None => false,
        };
        self.prev_commanded_axis = Some(axis);
        self.ahead.push(Ahead { t, line: st.program_line, tip }, in_region);
    }

    /// The stream of `topic`, created on first use.
    pub fn input(&mut self, topic: &str) -> InputId {
        if let Some(&k) = self.index.get(topic) {
            return InputId(k);
        }
        self.inputs.push(Input::default());
        self.index.insert(topic.to_string(), self.inputs.len() - 1);
        InputId(self.inputs.len() - 1)
    }

    fn get(&self, topic: &str) -> Option<&Input> {
        self.index.get(topic).map(|&k| &self.inputs[k])
    }

    /// The streams in topic order.
    fn each(&self) -> impl Iterator<Item = (&String, &Input)> {
        self.index.iter().map(|(t, &k)| (t, &self.inputs[k]))
    }

    /// Evaluate one sample of stream `topic`; `wall` is the arrival time (s, any monotonic clock).
    pub fn on_state(&mut self, topic: &str, st: &AxisState, wall: f64) -> Result<SingularityStatus, Rejection> {
        let id = self.input(topic);
        let e = self.evaluate(id, st, wall)?;
        Ok(self.status_of(id, topic, &e, &st.header.frame_id, false))
    }

    /// The status message of an evaluation of stream `id` (`stale`: published while the input is
    /// silent, repeating the last evaluation).
    fn status_of(&self, id: InputId, topic: &str, e: &Evaluation, frame_id: &str, stale: bool) -> SingularityStatus {
        let input = &self.inputs[id.0];
        SingularityStatus {
            header: Header { stamp: e.stamp, frame_id: frame_id.to_string() },
            source: e.source,
            input_topic: topic.to_string(),
            motion: e.motion.code(),
            singularity_distance: e.singularity_distance,
            secondary_axis: self.machine.axes[self.secondary].name.clone(),
            predicted_c_speed: e.predicted_c_speed,
            c_speed: e.c_speed,
            c_speed_limit: self.limit,
            programmed_feed: e.programmed_feed,
            path_feed: e.path_feed,
            feed_limit: e.feed_limit,
            limiting_axis: e.limiting_axis.map_or(String::new(), |i| self.machine.axes[i].name.clone()),
            limit_kind: limit_kind_code(e.limit_kind),
            in_region: e.in_region,
            region_id: e.region_id,
            region_cause: e.cause.filter(|_| e.in_region).map_or(SingularityStatus::CAUSE_NONE, Cause::code),
            workpiece_position: Point { x: e.workpiece_position.x, y: e.workpiece_position.y, z: e.workpiece_position.z },
            time_to_next_region: e.time_to_next_region,
            program_line: e.program_line,
            block_number: e.block_number,
            stale,
            invalid_count: input.rejected.invalid(),
            missing_joint_count: input.rejected.missing_joint,
            non_finite_count: input.rejected.non_finite,
            out_of_range_count: input.rejected.out_of_range,
            out_of_order_count: input.rejected.out_of_order,
            stale_count: input.stale,
            lost_count: input.lost,
        }
    }

    /// A status for every input that is stale now (the last sample's figures, `stale` set), so that
    /// the status topic says so while the input is silent.
    pub fn stale_statuses(&self) -> Vec<SingularityStatus> {
        self.each()
            .filter(|(_, i)| i.stale_now)
            .filter_map(|(topic, i)| {
                let id = InputId(self.index[topic]);
                let mut e = i.last?;
                e.in_region = false;
                e.region_id = 0;
                Some(self.status_of(id, topic, &e, "", true))
            })
            .collect()
    }

    /// Stream `id` starts a new session where its source says so (an SHDR log whose adapter connected
    /// again: its stamps start over): as for a publisher restarted after going stale.
    pub fn new_session(&mut self, id: InputId) {
        self.inputs[id.0].new_session(self.config.max_listed_regions);
    }

    /// Stream `id`'s source reports values only when they change (an MTConnect adapter): a gap in
    /// its stamps is a machine at rest as likely as a loss, so none is judged lost.
    pub fn set_change_only(&mut self, id: InputId, on: bool) {
        self.inputs[id.0].change_only = on;
    }

    /// A message of `topic` arrived at `wall` without completing a sample yet (one joint of a
    /// bridge that sends each on its own): the source is alive, not stale.
    pub fn heard(&mut self, topic: &str, wall: f64) {
        if let Some(&k) = self.index.get(topic) {
            self.inputs[k].last_arrival = Some(wall);
        }
    }

    /// The stream of `topic`, if seen.
    pub fn input_id(&self, topic: &str) -> Option<InputId> {
        self.index.get(topic).map(|&k| InputId(k))
    }

    /// [`Monitor::on_state`] without building the status message: the figures only.
    pub fn evaluate(&mut self, id: InputId, st: &AxisState, wall: f64) -> Result<Evaluation, Rejection> {
        let q = match self.validate(st) {
            Ok(q) => q,
            Err((reason, e)) => {
                self.inputs[id.0].rejected.count(reason);
                return Err(e);
            }
        };
        let t = st.header.stamp.as_secs();
        let input = &mut self.inputs[id.0];
        input.last_arrival = Some(wall);
        // The stream had gone stale and comes back with its clock restarted (stamped no later than
        // before): a restarted publisher, a new session (a gap still being judged is judged on what
        // came before). A stream that comes back where it left off (a publisher that stalled) goes on.
        if input.stale_now && input.history.back().is_some_and(|h| t <= h.t) {
            input.new_session(self.config.max_listed_regions);
        }
        // The stream went stale and goes on where it left off (a bridge that was down, a publisher
        // that stalled): the gap in its stamps is stale time, already counted as such, not samples
        // lost. The loss judgement starts again after it.
        let outage = std::mem::replace(&mut input.stale_now, false);
        if let Some(last) = input.history.back() {
            if t <= last.t {
                input.rejected.count(Reason::OutOfOrder);
                return Err(Rejection::OutOfOrder { stamp: t, last: last.t });
            }
        }
        input.source = st.source;
        input.samples += 1;
        if let Some(last) = input.history.back().map(|h| h.t) {
            if outage {
                close_loss_episode(input, last);
                input.stamps.clear();
                input.loss_events.clear();
            }
            input.last_interval = Some(t - last);
            count_lost(input, t - last, t);
        }
        if st.source == AxisState::SOURCE_MACHINE {
            return Ok(self.evaluate_measured(id, st, q, t));
        }
        let (axis, tip) = Self::axis_and_tip(&self.machine, st, &q);
        let prev = input.history.back().copied();
        let ds = prev.map_or(0.0, |p| (tip - p.tip).norm());
        input.s += ds;
        let now = Past { t, s: input.s, q, axis, tip };
        input.history.push_back(now);
        while input.history.len() > 4 {
            input.history.pop_front();
        }

        // Seed 001 eq. (5) at the programmed feed: dO/ds times F (dO/dt where the tip does not move).
        // A step that crosses into another block mixes two moves (a rotary-only block's turn over the
        // next block's first micrometres): there the previous sample's prediction holds.
        // So does the block's first micrometre of tip travel: a servo still settling the rotary axes
        // of a reorientation while the tip starts from rest turns the tool over almost no path.
        if input.block_start.0 != st.program_line || prev.is_none() {
            input.block_start = (st.program_line, input.s - ds);
        }
        let settling = input.s - input.block_start.1 < MIN_DEMAND_PATH && ds > 0.0;
        let held = input.last.as_ref().filter(|l| l.program_line != st.program_line || settling).map(|l| l.predicted_c_speed);
        let (predicted, c_speed) = match prev {
            Some(p) => {
                let dt = t - p.t;
                let f = if st.programmed_feed > 0.0 { st.programmed_feed } else { ds / dt };
                let rate = if ds > 1e-12 { (axis - p.axis) / ds * f } else { (axis - p.axis) / dt };
                // The chord is a mid-step quantity: evaluate eq. (5) at the mid-step orientation.
                let mid = (axis + p.axis).try_normalize(1e-12).unwrap_or(axis);
                let predicted = held.unwrap_or_else(|| self.machine.chain.secondary_rate(&mid, &rate, &[q[3], q[4]]));
                (predicted, (q[self.secondary] - p.q[self.secondary]) / dt)
            }
            None => (0.0, 0.0),
        };
        // Seed 002 eq. (5) from divided differences over the last samples along the path.
        let fl = if self.regions_only {
            (st.programmed_feed, None, LimitKind::Programmed)
        } else {
            feed_limit_from_history(&input.history, &self.limiter, st.programmed_feed)
        };
        let dist = distance(&axis, &self.singular);
        let moving = ds > 1e-12;
        // The region rule ([`RegionTracker`], the same as for machine streams): the motion kind from the
        // program where the stream carries it, else from the stream (tip moving: feed; axis turning
        // under a still tip: rotary-only). A rapid never opens a region.
        let motion = match Motion::from_code(st.motion) {
            Motion::Unknown if moving => Motion::Feed,
            Motion::Unknown if prev.is_some_and(|p| (axis - p.axis).norm() > 0.0) => Motion::Rotary,
            Motion::Unknown => Motion::Dwell,
            m => m,
        };
        let rule_sample = RuleSample {
            t,
            s: input.s,
            tip,
            motion,
            predicted: Some(predicted),
            distance: dist,
            path_feed: st.path_feed,
            programmed_feed: st.programmed_feed,
            dt: prev.map_or(0.0, |p| t - p.t),
            ds,
            block: st.block_number,
            line: st.program_line,
        };
        let (verdict, closed) = input.tracker.push(&self.rule, &rule_sample);
        if let Some(r) = closed {
            input.close(&r, self.config.max_listed_regions);
        }
        let in_region = verdict.beyond;

        // Look-ahead on the commanded timeline: where is this sample on it, and what comes next?
        let time_to_next = if in_region {
            0.0
        } else {
            let (cursor, ahead) = lookahead(&self.ahead, input.cursor, st.program_line, &tip);
            input.cursor = cursor;
            ahead
        };
        let evaluation = Evaluation {
            stamp: st.header.stamp,
            source: st.source,
            singularity_distance: dist,
            predicted_c_speed: predicted,
            c_speed,
            feed_limit: fl.0,
            limiting_axis: fl.1,
            limit_kind: fl.2,
            in_region,
            region_id: if in_region { verdict.region_id } else { 0 },
            workpiece_position: tip,
            time_to_next_region: time_to_next,
            program_line: st.program_line,
            block_number: st.block_number,
            motion,
            cause: verdict.cause,
            path_feed: st.path_feed,
            programmed_feed: st.programmed_feed,
            turning: true,
            five_axis_distance: None,
        };
        input.latch(&evaluation, self.config.warn_distance, self.config.warn_ahead);
        input.last = Some(evaluation);
        Ok(evaluation)
    }

    /// A machine stream's sample (a bridge's JointState): the measured path (unwrapped axes, forward
    /// kinematics, actual feed), the path's demand on the secondary axis at the programmed feed (seed
    /// 001 eq. 5 as dC/ds * F over a stretch of path), the feed limit on the same stretch (seed 002
    /// eq. 5, velocity and acceleration terms) and the region rule ([`RegionTracker`]).
    fn evaluate_measured(&mut self, id: InputId, st: &AxisState, q: Joints, t: f64) -> Evaluation {
        let input = &mut self.inputs[id.0];
        let measured = input.measured.get_or_insert_with(|| MeasuredPath::new(&self.machine, MeasuredConfig::default()));
        if input.aligner.is_none() {
            if let FeedSource::Program(plan) = &self.feed_source {
                input.aligner = Some(Aligner::new(plan.segments.clone()));
            }
        }
        // Where in the program (needs the tip: forward kinematics of the unwrapped axes first).
        // A source that knows the motion kind (an AxisState of source MACHINE from a bridge that has the
        // program) says whether this is a rapid; a JointState does not.
        let hint = (st.motion != AxisState::MOTION_UNKNOWN).then_some(st.motion == AxisState::MOTION_RAPID);
        let m = measured.push(&self.machine, t, &q, hint);
        let place = input.aligner.as_mut().and_then(|a| a.place(&m.tip, &m.q));
        let motion = match place {
            Some(p) if p.rapid => Motion::Rapid,
            // The program says a path move; the stream may still be stopped or turning at its ends.
            Some(p) if p.path_move && m.motion == Motion::Rapid => Motion::Feed,
            Some(p) if !p.path_move && m.motion == Motion::Feed => Motion::Rotary,
            _ => m.motion,
        };
        match motion {
            Motion::Rapid => input.rapid_samples += 1,
            Motion::Feed => input.feed_samples += 1,
            _ => {}
        }
        // The feed held over 0.1 s of uninterrupted feed motion (a blend's overshoot or a rapid
        // misjudged for one sample does not count).
        if motion == Motion::Feed {
            input.feed_run.push_back((t, m.s));
            while input.feed_run.len() > 2 && t - input.feed_run[1].0 >= HELD {
                input.feed_run.pop_front();
            }
            while input.feed_run.len() > 4096 {
                input.feed_run.pop_front();
            }
            if let Some(&(t0, s0)) = input.feed_run.front().filter(|f| t - f.0 >= HELD) {
                let held = (m.s - s0) / (t - t0);
                input.max_feed = input.max_feed.max(held);
                let dt = input.feed_run.get(input.feed_run.len().wrapping_sub(2)).map_or(0.0, |p| t - p.0);
                if let Some(k) = feed_bin(held) {
                    if input.feed_time.is_empty() {
                        input.feed_time = vec![0.0; FEED_BINS];
                    }
                    input.feed_time[k] += dt;
                    if input.feed_mode.is_none_or(|b| input.feed_time[k] > input.feed_time[b]) {
                        input.feed_mode = Some(k);
                    }
                }
            }
        } else {
            input.feed_run.clear();
        }
        let f_prog = match (&self.feed_source, place) {
            (FeedSource::Program(_), Some(p)) => p.feed,
            (FeedSource::Program(_), None) => 0.0,
            (FeedSource::Fixed(f), _) => *f,
            (FeedSource::Assumed, _) => input.feed_mode.map_or(0.0, feed_of_bin),
        };
        let f_prog = if motion == Motion::Feed { f_prog } else { 0.0 };
        // Program coordinates: the stream's tip less the datum shift in effect: the aligned program's,
        // else the work offset the control was given.
        let offset = place.map_or(self.config.work_offset, |p| p.offset);
        let dist = distance(&m.axis, &self.singular);
        let predicted = m.demand.map(|d| d.per_metre * f_prog);
        let fl = match m.demand {
            Some(d) if f_prog > 0.0 && !self.regions_only => {
                let f = self.limiter.limit(f_prog, &d.q_s, &d.q_ss, &[0.0; AXES]);
                (f.feed, f.axis, f.kind)
            }
            _ => (f_prog, None, LimitKind::Programmed),
        };
        // The rule runs on the window's middle sample, where the estimate belongs.
        let rule_sample = match m.demand {
            Some(d) => {
                let (dt, ds) = input.lagged.map_or((0.0, 0.0), |(lt, ls)| (d.t - lt, d.s - ls));
                input.lagged = Some((d.t, d.s));
                // The middle sample's motion, except where the program says rapid now.
                let lag_motion = if motion == Motion::Rapid { Motion::Rapid } else { d.motion };
                RuleSample {
                    t: d.t,
                    s: d.s,
                    tip: d.tip - offset,
                    motion: lag_motion,
                    predicted,
                    distance: distance(&d.axis, &self.singular),
                    path_feed: d.path_feed,
                    programmed_feed: f_prog,
                    dt,
                    ds,
                    block: place.map_or(-1, |p| p.block),
                    line: place.map_or(st.program_line, |p| p.line),
                }
            }
            None => {
                input.lagged = None;
                RuleSample { t, s: m.s, tip: m.tip - offset, motion, predicted: None, distance: dist, path_feed: m.path_feed, programmed_feed: f_prog, dt: 0.0, ds: 0.0, block: place.map_or(-1, |p| p.block), line: place.map_or(st.program_line, |p| p.line) }
            }
        };
        let (verdict, closed) = input.tracker.push(&self.rule, &rule_sample);
        // Look-ahead with the program: the next of the program's regions after this sample's place in
        // it, in program time at the programmed feed.
        let time_to_next = match (&self.feed_source, place) {
            _ if verdict.region_id != 0 => 0.0,
            (FeedSource::Program(plan), Some(p)) => plan.time_to_next_region(p.program_time),
            _ => -1.0,
        };
        if let Some(r) = closed {
            input.close(&r, self.config.max_listed_regions);
        }
        let evaluation = Evaluation {
            stamp: st.header.stamp,
            source: st.source,
            singularity_distance: dist,
            predicted_c_speed: predicted.unwrap_or(0.0),
            c_speed: m.c_speed,
            feed_limit: fl.0,
            limiting_axis: fl.1,
            limit_kind: fl.2,
            in_region: verdict.beyond,
            region_id: if verdict.beyond { verdict.region_id } else { 0 },
            workpiece_position: m.tip - offset,
            time_to_next_region: time_to_next,
            program_line: place.map_or(st.program_line, |p| p.line),
            block_number: place.map_or(st.block_number, |p| p.block),
            motion,
            cause: verdict.cause,
            path_feed: m.path_feed,
            programmed_feed: f_prog,
            // Five-axis motion: the tool axis turns, on a move the program makes five-axis (if known).
            turning: m.turning && place.is_none_or(|p| p.five_axis),
            five_axis_distance: m
                .demand
                .filter(|d| d.motion == Motion::Feed && d.turning && place.is_none_or(|p| p.five_axis))
                .map(|d| distance(&d.axis, &self.singular)),
        };
        input.history.push_back(Past { t, s: m.s, q: m.q, axis: m.axis, tip: m.tip });
        while input.history.len() > 1 {
            input.history.pop_front();
        }
        input.latch(&evaluation, self.config.warn_distance, self.config.warn_ahead);
        input.last = Some(evaluation);
        evaluation
    }

    /// Check every input for staleness at wall time `wall`; returns the topics that just went stale.
    pub fn tick(&mut self, wall: f64) -> Vec<String> {
        let mut gone = Vec::new();
        for (topic, &k) in &self.index {
            let input = &mut self.inputs[k];
            if let Some(last) = input.last_arrival {
                if !input.stale_now && wall - last > input.stale_after(self.config.stale_timeout) {
                    input.stale_now = true;
                    input.stale += 1;
                    gone.push(topic.clone());
                }
            }
        }
        gone
    }

    /// Close any open region (end of a stream).
    pub fn finish(&mut self) {
        for input in self.inputs.iter_mut() {
            if let Some(last) = input.history.back().map(|h| h.t) {
                close_loss_episode(input, last);
            }
            if let Some(r) = input.tracker.finish() {
                input.close(&r, self.config.max_listed_regions);
            }
        }
    }

    /// Regions a stream went through, in order: the first ones listed (see
    /// [`MonitorConfig::max_listed_regions`]) and the open one.
    pub fn regions(&self, topic: &str) -> Vec<LiveRegion> {
        self.get(topic).map_or_else(Vec::new, |i| i.all_regions())
    }

    /// The regions of a stream past the listing cap, folded.
    pub fn unlisted_regions(&self, topic: &str) -> crate::listing::Unlisted {
        self.get(topic).map_or_else(Default::default, |i| i.unlisted)
    }

    /// The region `id` of a stream if it is open or the last closed (a region's end event), else a
    /// listed one.
    pub fn region(&self, topic: &str, id: u32) -> Option<LiveRegion> {
        let i = self.get(topic)?;
        match (i.tracker.open(), &i.last_closed) {
            (Some(r), _) if r.id == id => Some(LiveRegion::from_tracked(r)),
            (_, Some(r)) if r.id == id => Some(r.clone()),
            _ => i.regions.iter().find(|r| r.id == id).cloned(),
        }
    }

    /// (samples, invalid, out of order, stale) of a stream.
    pub fn counters(&self, topic: &str) -> (u64, u64, u64, u64) {
        self.get(topic).map_or((0, 0, 0, 0), |i| (i.samples, i.rejected.invalid(), i.rejected.out_of_order, i.stale))
    }

    /// Samples missing from a stream, judged by gaps in its stamps against its period.
    pub fn lost(&self, topic: &str) -> u64 {
        self.get(topic).map_or(0, |i| i.lost)
    }

    /// The topics seen so far.
    pub fn topics(&self) -> Vec<String> {
        self.index.keys().cloned().collect()
    }

    /// The first stream whose program (`--program`) could not be read again to place its samples,
    /// and why: the node fails then (its samples have no program place).
    pub fn program_unreadable(&self) -> Option<(&str, &str)> {
        self.each().find_map(|(topic, i)| i.program_failure().map(|why| (topic.as_str(), why)))
    }

    /// A summary of every stream, for people and CI.
    pub fn summary(&self) -> Vec<InputSummary> {
        self.each()
            .map(|(topic, i)| InputSummary {
                topic: topic.clone(),
                source: i.source,
                samples: i.samples,
                invalid: i.rejected.invalid(),
                out_of_order: i.rejected.out_of_order,
                stale: i.stale,
                lost: i.lost,
                rejected: i.rejected,
                period_s: i.period.map(|p| p.0),
                rapid_samples: i.rapid_samples,
                feed_samples: i.feed_samples,
                max_path_feed_mm_per_min: i.max_feed / crate::units::MM_PER_MIN,
                feed_source: (i.source == AxisState::SOURCE_MACHINE && i.samples > 0).then(|| self.feed_source.describe()),
                program_unreadable: i.program_failure().map(str::to_string),
                regions: i.all_regions(),
                unlisted_regions: i.unlisted,
            })
            .collect()
    }

    /// The diagnostics: one status per input, at the worst level since the last report (ERROR inside
    /// a region, WARN near the singularity or a region ahead, STALE without samples, OK), naming the
    /// region that caused it. Call [`Monitor::reported`] after publishing them.
    pub fn diagnostics(&self, stamp: Time) -> DiagnosticArray {
        let rpm = crate::units::RPM;
        let secondary = &self.machine.axes[self.secondary].name;
        let status = self
            .each()
            .map(|(topic, input)| {
                let event = |level: u8, s: &Evaluation| -> (u8, String) {
                    let when = if input.last.as_ref().is_some_and(|l| l.stamp == s.stamp) { String::new() } else { " since the last report".to_string() };
                    let message = match level {
                        DiagnosticStatus::ERROR => format!(
                            "{secondary} speed {:.1} rpm above its {:.1} rpm limit (region {}, {}){when}",
                            s.predicted_c_speed.abs() / rpm,
                            self.limit / rpm,
                            s.region_id,
                            match s.cause {
                                Some(Cause::Singularity) => "singularity",
                                Some(Cause::RotaryFeed) => "rotary feed",
                                None => "limit",
                            }
                        ),
                        DiagnosticStatus::WARN if s.singularity_distance < self.config.warn_distance => {
                            format!("{:.2} deg from the singularity{when}", s.singularity_distance.to_degrees())
                        }
                        DiagnosticStatus::WARN => format!("region ahead in {:.2} s{when}", s.time_to_next_region),
                        _ => "clear of the singularity".to_string(),
                    };
                    (level, message)
                };
                let current = input.last.as_ref().map(|s| (level_of(s, self.config.warn_distance, self.config.warn_ahead), s));
                let worst = match (current, &input.worst) {
                    (Some(c), Some((l, w))) if *l > c.0 => Some((*l, w)),
                    (c, _) => c,
                };
                let (level, message) = match (input.program_failure(), worst) {
                    (Some(why), _) => {
                        (DiagnosticStatus::ERROR, format!("the program (--program) cannot be read again to place the samples: {why}"))
                    }
                    (None, Some((l, w))) if l == DiagnosticStatus::ERROR => event(l, w),
                    _ if input.stale_now => (DiagnosticStatus::STALE, format!("no sample for {:.0} ms", input.stale_after(self.config.stale_timeout) * 1e3)),
                    (None, None) => (DiagnosticStatus::STALE, "no valid sample yet".to_string()),
                    (None, Some((l, w))) => event(l, w),
                };
                let mut values = vec![
                    KeyValue { key: "invalid_samples".into(), value: input.rejected.invalid().to_string() },
                    KeyValue { key: "missing_joint_samples".into(), value: input.rejected.missing_joint.to_string() },
                    KeyValue { key: "non_finite_samples".into(), value: input.rejected.non_finite.to_string() },
                    KeyValue { key: "out_of_range_samples".into(), value: input.rejected.out_of_range.to_string() },
                    KeyValue { key: "out_of_order_samples".into(), value: input.rejected.out_of_order.to_string() },
                    KeyValue { key: "stale_count".into(), value: input.stale.to_string() },
                    KeyValue { key: "lost_samples".into(), value: input.lost.to_string() },
                ];
                if let Some(s) = &input.last {
                    let machine_stream = s.source == AxisState::SOURCE_MACHINE;
                    values.extend([
                        KeyValue { key: "singularity_distance_deg".into(), value: format!("{:.4}", s.singularity_distance.to_degrees()) },
                        KeyValue { key: "predicted_c_speed_rpm".into(), value: format!("{:.2}", s.predicted_c_speed / rpm) },
                        KeyValue { key: "measured_c_speed_rpm".into(), value: format!("{:.2}", s.c_speed / rpm) },
                        KeyValue { key: "path_feed_mm_per_min".into(), value: format!("{:.1}", s.path_feed / crate::units::MM_PER_MIN) },
                        KeyValue { key: "programmed_feed_mm_per_min".into(), value: format!("{:.1}", s.programmed_feed / crate::units::MM_PER_MIN) },
                        KeyValue { key: "region_id".into(), value: s.region_id.to_string() },
                    ]);
                    // A feed limit only where the sample is on a feed move with a known programmed feed.
                    if s.programmed_feed > 0.0 {
                        values.extend([
                            KeyValue { key: "feed_limit_mm_per_min".into(), value: format!("{:.1}", s.feed_limit / crate::units::MM_PER_MIN) },
                            KeyValue { key: "limiting_axis".into(), value: s.limiting_axis.map_or(String::new(), |i| self.machine.axes[i].name.clone()) },
                        ]);
                    }
                    if machine_stream {
                        values.push(KeyValue { key: "feed_source".into(), value: self.feed_source.describe() });
                    }
                }
                DiagnosticStatus { level, name: format!("fiveaxis monitor: {topic}"), message, hardware_id: self.machine.name.clone(), values }
            })
            .collect();
        DiagnosticArray { header: Header { stamp, frame_id: String::new() }, status }
    }

    /// The diagnostics were published: the worst-since-last-report starts again.
    pub fn reported(&mut self) {
        for input in self.inputs.iter_mut() {
            input.worst = None;
        }
    }
}

/// The `/diagnostics` level of one evaluation: ERROR inside a region, WARN near the singularity or a
/// region ahead, OK otherwise.
fn level_of(e: &Evaluation, warn_distance: f64, warn_ahead: f64) -> u8 {
    if e.in_region {
        DiagnosticStatus::ERROR
    } else if e.singularity_distance < warn_distance || (e.time_to_next_region > 0.0 && e.time_to_next_region < warn_ahead) {
        DiagnosticStatus::WARN
    } else {
        DiagnosticStatus::OK
    }
}

/// A stream is stale after this many of its own sample periods (plus the spread of its intervals)
/// without a sample, or the configured timeout, whichever is longer: a bridge that sends a few times
/// a second is not stale between its samples.
const STALE_PERIODS: f64 = 3.0;

impl Input {
    /// A new session of the stream (a restarted publisher, an adapter that connected again): what
    /// came before is judged and closed, nothing of it is used after.
    fn new_session(&mut self, max_listed: usize) {
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
    fn stale_after(&self, timeout: f64) -> f64 {
        // The period and the spread of its intervals (10th to 90th percentile): a stream whose axes
        // report on their own clocks comes in bursts.
        self.period.map(|p| p.0 + p.1).or(self.last_interval).map_or(timeout, |p| timeout.max(STALE_PERIODS * p))
    }

    /// Why the program (`--program`) could not be read again to place this stream's samples.
    fn program_failure(&self) -> Option<&str> {
        self.aligner.as_ref().and_then(|a| a.failure())
    }

    /// Remember the evaluation if it is the worst since the last report (the peak speed of a region
    /// kept with it).
    fn latch(&mut self, e: &Evaluation, warn_distance: f64, warn_ahead: f64) {
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
    fn close(&mut self, r: &TrackedRegion, cap: usize) {
        let region = LiveRegion::from_tracked(r);
        self.last_closed = Some(region.clone());
        crate::listing::push(&mut self.regions, &mut self.unlisted, cap, region);
    }

    /// Closed regions, then the open one.
    fn all_regions(&self) -> Vec<LiveRegion> {
        // The open one after the listed ones when none was folded yet (it closes listed or folded).
        let tracked = self.tracker.open().filter(|_| self.unlisted.is_empty()).map(LiveRegion::from_tracked);
        self.regions.iter().cloned().chain(tracked).collect()
    }
}

/// Bins of the held-feed histogram: 2 % wide from 1 mm/min (to about 1.5e4 m/min).
const FEED_BINS: usize = 600;
const FEED_BIN_RATIO: f64 = 1.02;

fn feed_bin(feed: f64) -> Option<usize> {
    let mm_min = feed / crate::units::MM_PER_MIN;
    (mm_min >= 1.0 && mm_min.is_finite()).then(|| ((mm_min.ln() / FEED_BIN_RATIO.ln()) as usize).min(FEED_BINS - 1))
}

fn feed_of_bin(k: usize) -> f64 {
    FEED_BIN_RATIO.powf(k as f64 + 0.5) * crate::units::MM_PER_MIN
}

/// How long a feed must be held to count as the stream's programmed feed when none is given, s.
const HELD: f64 = 0.1;

/// Intervals whose spread sets the gap tolerance.
const INTERVALS: usize = 64;

/// A stretch of a stream's stamps with gaps in it, not yet judged: a publisher that stalls and then
/// sends what it owes in a burst, stamping at send time, makes the same gaps as lost samples; the count
/// over the whole stretch decides.
#[derive(Debug, Clone, Copy)]
struct LossEpisode {
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
struct LossEvent {
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
fn count_lost(input: &mut Input, dt: f64, t: f64) {
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
fn close_loss_episode(input: &mut Input, t_end: f64) {
    let Some(e) = input.episode.take() else { return };
    let lost = e.lost(t_end);
    if lost > 0 {
        input.lost += lost;
        input.loss_events.push_back(LossEvent { from: e.t0, to: e.last_gap, lost });
    }
}

fn limit_kind_code(kind: LimitKind) -> u8 {
    match kind {
        LimitKind::Programmed => SingularityStatus::LIMIT_PROGRAMMED,
        LimitKind::Velocity => SingularityStatus::LIMIT_VELOCITY,
        LimitKind::Acceleration => SingularityStatus::LIMIT_ACCELERATION,
        LimitKind::Jerk => SingularityStatus::LIMIT_JERK,
    }
}

/// Seed 002 eq. (5) on divided differences of the last samples with respect to path length.
fn feed_limit_from_history(h: &VecDeque<Past>, limiter: &FeedLimiter, f_prog: f64) -> (f64, Option<usize>, LimitKind) {
    let n = h.len();
    if n < 2 || f_prog <= 0.0 {
        return (f_prog, None, LimitKind::Programmed);
    }
    let p = |k: usize| &h[k];
    let ok = |a: &Past, b: &Past| b.s - a.s > 1e-9;
    let mut qs = [0.0; AXES];
    let mut qss = [0.0; AXES];
    let mut qsss = [0.0; AXES];
    if !ok(p(n - 2), p(n - 1)) {
        return (f_prog, None, LimitKind::Programmed);
    }
    // Divided differences (the reciprocals of the path steps once, not per axis).
    let (p1, p2) = (p(n - 1), p(n - 2));
    let inv = |a: &Past, b: &Past| 1.0 / (b.s - a.s);
    let inv21 = inv(p2, p1);
    let third = (n >= 3 && ok(p(n - 3), p2)).then(|| (p(n - 3), inv(p(n - 3), p2), 2.0 / (p1.s - p(n - 3).s)));
    let fourth = third.filter(|_| n >= 4 && ok(p(n - 4), p(n - 3))).map(|(p3, ..)| {
        let p4 = p(n - 4);
        (p4, inv(p4, p3), 2.0 / (p2.s - p4.s), 3.0 / (p1.s - p4.s))
    });
    for i in 0..AXES {
        let d21 = (p1.q[i] - p2.q[i]) * inv21;
        qs[i] = d21;
        if let Some((p3, inv32, k2)) = third {
            let d32 = (p2.q[i] - p3.q[i]) * inv32;
            let s2 = (d21 - d32) * k2;
            qss[i] = s2;
            if let Some((p4, inv43, k2b, k3)) = fourth {
                let s2b = (d32 - (p3.q[i] - p4.q[i]) * inv43) * k2b;
                qsss[i] = (s2 - s2b) * k3;
            }
        }
    }
    let f = limiter.limit(f_prog, &qs, &qss, &qsss);
    (f.feed, f.axis, f.kind)
}

/// Find a sample's place on the commanded timeline and the time from there to the next region:
/// (new cursor, seconds; -1 if none ahead). The cursor is (place on the timeline, first in-region
/// entry not behind it), both absolute and only moving forward. The place moves from the cursor to
/// the sample's program line, then on while the next entry is as close to the sample's tool tip; the
/// next region is the first in-region entry at or after it.
fn lookahead(
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

    /// The binary search gives what the definition (the first region starting after t) gives.
    #[test]
    fn time_to_next_region_is_the_first_start_after_the_sample() {
        let regions: Vec<(f64, f64)> = (0..500).map(|k| (k as f64 * 2.0 + (k % 3) as f64 * 0.1, k as f64 * 2.0 + 1.0)).collect();
        let plan = ProgramPlan::held(Vec::new(), regions.clone());
        for k in 0..4000 {
            let t = k as f64 * 0.2537 - 3.0;
            let want = regions.iter().find(|r| r.0 > t).map_or(-1.0, |r| r.0 - t);
            assert_eq!(plan.time_to_next_region(t), want, "t {t}");
        }
        assert_eq!(plan.time_to_next_region(0.0), regions[1].0, "a region starting exactly at t is not ahead");
    }
}
