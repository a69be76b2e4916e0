//! The monitor's settings and what it reports: rejections by reason, where the programmed feed comes
//! from, a region as a stream went through it, a stream's summary, one sample's figures.

use super::*;

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

    pub(super) fn count(&mut self, reason: Reason) {
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
pub(super) enum Reason {
    MissingJoint,
    NonFinite,
    OutOfRange,
    OutOfOrder,
    Malformed,
}

/// The message of a position outside its axis' range (see [`Rejection::is_out_of_range`]).
pub(super) const OUT_OF_RANGE: &str = "outside its range";

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
            FeedSource::Assumed => "ASSUMED: the tool-tip feed the stream held longest (steady within 20 % over 0.1 s, 2 % bins) on feed moves so far (no --program or --feed given: give one for a sound figure)".into(),
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
    /// How far apart the samples around its ends lie along the path, mm (the larger of the two):
    /// each end is known to within that.
    pub x_resolution_mm: f64,
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
    pub(super) fn from_tracked(r: &TrackedRegion) -> LiveRegion {
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
            x_resolution_mm: r.step_in.max(r.step_out) * 1e3,
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
    /// Stretches where the demand passed the limit over less path than the tool tip's uncertainty at
    /// their ends (a sparse per-axis stream's interpolated poses): not regions, counted here.
    pub unconfirmed_regions: u64,
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

