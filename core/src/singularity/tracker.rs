//! The region rule for a stream, one sample at a time: a region opens where the path's demand on
//! the secondary axis exceeds its limit (seed 001 eq. 5) on a feed or rotary-only move, or the tool
//! axis comes closer to the singular direction than a threshold on a feed move; never on a rapid (its
//! axes run at their limits by definition) or a dwell. One pass through it is one region.
//!
//! Hysteresis: a region stays open until the demand has stayed within the limit (and the distance
//! above its threshold) for [`RegionRule::min_gap`] of tool-tip path, or the motion changes kind (a
//! rapid, a feed move after a rotary-only one or the reverse); it then ends at its last sample inside. Each region says its cause:
//! `singularity` when its closest approach lies within [`RegionRule::singular_within`] of the singular
//! direction (where the `1/sin` of eq. 5 dominates), `rotary_feed` otherwise (a programmed rotary
//! motion faster than the axis far from the pole, e.g. indexing moves).

use super::measured::Motion;
use nalgebra::Vector3;

/// The stated parameters of the rule.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RegionRule {
    /// Secondary-axis speed limit, rad/s.
    pub rate_limit: f64,
    /// Also in a region when closer than this to the singular direction (rad), on feed moves.
    pub min_distance: Option<f64>,
    /// Path length within the limits that closes a region, m (0.5 mm).
    pub min_gap: f64,
    /// Closest approach within which a region's cause is the singularity, rad (15 deg: there
    /// `1/sin` amplifies the orientation speed at least 3.9 times).
    pub singular_within: f64,
}

/// The closest approach within which a region's cause is the singularity, deg (15 deg: there `1/sin`
/// amplifies the orientation speed at least 3.9 times): the rule's default, for live streams,
/// recordings and programs alike.
pub const SINGULAR_WITHIN_DEG: f64 = 15.0;

impl RegionRule {
    pub fn new(rate_limit: f64, min_distance: Option<f64>) -> RegionRule {
        RegionRule { rate_limit, min_distance, min_gap: 0.5e-3, singular_within: SINGULAR_WITHIN_DEG.to_radians() }
    }
}

/// Why a region was opened.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Cause {
    Singularity,
    RotaryFeed,
}

impl Cause {
    /// A region's cause from its closest approach to the singular direction (rad): the singularity
    /// within `singular_within` of it, a rotary feed beyond.
    pub fn of(min_distance: f64, singular_within: f64) -> Cause {
        if min_distance <= singular_within {
            Cause::Singularity
        } else {
            Cause::RotaryFeed
        }
    }

    /// The cause's name, as the JSON reports spell it.
    pub fn name(self) -> &'static str {
        match self {
            Cause::Singularity => "singularity",
            Cause::RotaryFeed => "rotary_feed",
        }
    }

    /// The `region_cause` code of `fiveaxis_msgs/SingularityStatus` (CAUSE_*).
    pub fn code(self) -> u8 {
        match self {
            Cause::Singularity => 1,
            Cause::RotaryFeed => 2,
        }
    }
}

/// One sample as the rule sees it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RuleSample {
    pub t: f64,
    /// Tool-tip path length, m.
    pub s: f64,
    /// Where the estimate belongs (the tool tip, workpiece frame, m).
    pub tip: Vector3<f64>,
    pub motion: Motion,
    /// Predicted secondary-axis speed at the programmed feed, rad/s (None: not known here).
    pub predicted: Option<f64>,
    /// Angle to the singular direction, rad.
    pub distance: f64,
    /// Actual tool-tip feed and programmed feed, m/s (0: none).
    pub path_feed: f64,
    pub programmed_feed: f64,
    /// Time since the previous sample and path since it, s and m.
    pub dt: f64,
    pub ds: f64,
    /// Block number (-1 without) and program line (0 unknown).
    pub block: i64,
    pub line: u32,
}

/// A region as the rule found it.
#[derive(Debug, Clone, PartialEq)]
pub struct TrackedRegion {
    pub id: u32,
    pub cause: Cause,
    pub t_start: f64,
    pub t_end: f64,
    pub tip_start: Vector3<f64>,
    pub tip_end: Vector3<f64>,
    pub block_start: i64,
    pub block_end: i64,
    pub line_start: u32,
    pub line_end: u32,
    /// Largest |predicted| inside, rad/s; closest approach, rad; lowest actual feed, m/s.
    pub peak: f64,
    pub min_distance: f64,
    pub min_path_feed: f64,
    /// Time spent beyond what the programmed feed would have taken, s.
    pub time_lost: f64,
    /// The tool-tip path from the sample before the region to its first, and from its last to the
    /// sample after (0 until seen), m: where between those samples each end lies is not known (the
    /// ends' resolution; sparse machine data make it millimetres).
    pub step_in: f64,
    pub step_out: f64,
    /// Path length since the last sample inside (for the hysteresis), m, and what the gap would add
    /// to the lowest feed and the time lost if the region goes on after it.
    gap: f64,
    gap_min_feed: f64,
    gap_lost: f64,
    /// The motion kind it opened on (feed or rotary-only).
    kind: Motion,
}

/// What the rule says about one sample.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Verdict {
    /// The sample itself is beyond a limit.
    pub beyond: bool,
    /// A region is open (the sample is inside it, or in its hysteresis gap after it): its id, else 0.
    pub region_id: u32,
    pub cause: Option<Cause>,
}

/// The rule's state for one stream.
#[derive(Debug, Clone, Default)]
pub struct RegionTracker {
    next_id: u32,
    open: Option<TrackedRegion>,
}

impl RegionTracker {
    /// Take one sample; returns the verdict and a region that just closed (boxed: the return per
    /// sample stays small, the rare closed region takes the allocation).
    pub fn push(&mut self, rule: &RegionRule, x: &RuleSample) -> (Verdict, Option<Box<TrackedRegion>>) {
        let moving = matches!(x.motion, Motion::Feed | Motion::Rotary);
        let speed = moving && x.predicted.is_some_and(|p| p.abs() > rule.rate_limit);
        let close = x.motion == Motion::Feed && rule.min_distance.is_some_and(|d| x.distance < d);
        let beyond = speed || close;
        let mut closed = None;
        if self.open.as_ref().is_some_and(|r| x.motion == Motion::Rapid || (moving && x.motion != r.kind)) {
            closed = self.open.take().map(Box::new);
        }
        if beyond {
            if self.open.is_none() {
                self.next_id += 1;
                self.open = Some(TrackedRegion {
                    id: self.next_id,
                    cause: Cause::RotaryFeed,
                    t_start: x.t,
                    t_end: x.t,
                    tip_start: x.tip,
                    tip_end: x.tip,
                    block_start: x.block,
                    block_end: x.block,
                    line_start: x.line,
                    line_end: x.line,
                    peak: 0.0,
                    min_distance: f64::INFINITY,
                    min_path_feed: f64::INFINITY,
                    time_lost: 0.0,
                    step_in: x.ds,
                    step_out: 0.0,
                    gap: 0.0,
                    gap_min_feed: f64::INFINITY,
                    gap_lost: 0.0,
                    kind: x.motion,
                });
            }
            let r = self.open.as_mut().expect("a region is open");
            r.t_end = x.t;
            r.tip_end = x.tip;
            r.block_end = x.block;
            r.line_end = x.line;
            // Back inside after a gap shorter than the hysteresis: the gap belongs to the region.
            r.time_lost += r.gap_lost;
            r.min_path_feed = r.min_path_feed.min(r.gap_min_feed);
            r.step_out = 0.0;
            (r.gap, r.gap_lost, r.gap_min_feed) = (0.0, 0.0, f64::INFINITY);
            r.peak = r.peak.max(x.predicted.map_or(0.0, f64::abs));
            r.min_distance = r.min_distance.min(x.distance);
            r.cause = Cause::of(r.min_distance, rule.singular_within);
        }
        if let Some(r) = self.open.as_mut() {
            // The machine's lowest feed and the time lost against the programmed feed, over the
            // samples inside (a gap counts once the region goes on after it).
            let lost = if x.programmed_feed > 0.0 && r.t_start < x.t { x.dt - x.ds / x.programmed_feed } else { 0.0 };
            if beyond {
                r.min_path_feed = r.min_path_feed.min(x.path_feed);
                r.time_lost += lost;
            } else {
                if r.gap == 0.0 {
                    r.step_out = x.ds;
                }
                r.gap += x.ds;
                r.gap_lost += lost;
                r.gap_min_feed = r.gap_min_feed.min(x.path_feed);
                if r.gap >= rule.min_gap {
                    closed = self.open.take().map(Box::new);
                }
            }
        }
        let open = self.open.as_ref();
        (Verdict { beyond, region_id: open.map_or(0, |r| r.id), cause: open.map(|r| r.cause) }, closed)
    }

    /// Close the open region (end of the stream, a stale input).
    pub fn finish(&mut self) -> Option<TrackedRegion> {
        self.open.take()
    }

    /// The open region, if any.
    pub fn open(&self) -> Option<&TrackedRegion> {
        self.open.as_ref()
    }
}
