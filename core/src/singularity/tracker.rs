//! The region rule for a stream, one sample at a time: a region opens where the path's demand on
//! the secondary axis exceeds its limit (seed 001 eq. 5) on a feed or rotary-only move, or the tool
//! axis comes closer to the singular direction than a threshold on a feed move; never on a rapid (its
//! axes run at their limits by definition) or a dwell. One pass through it is one region.
//!
//! Confirmation: a region is a stretch of path, which the samples must locate. Each sample says how
//! far its tool tip may be off ([`RuleSample::uncertainty`]: 0 on exact samples, tenths of a
//! millimetre to millimetres on a sparse per-axis stream's interpolated poses). A region is announced
//! (an id, `beyond` in the verdict) once the path inside it, from its first sample to one beyond,
//! is at least the two samples' uncertainty together, starting where it opened; one that closes
//! shorter is not a region but counted ([`RegionTracker::unconfirmed`]): at a block junction where
//! the table turns with the tip still, the interpolated tip wanders by about its uncertainty and no
//! further, where the path through a pole goes on for millimetres. Exact samples confirm at once.
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
    /// How far the tool tip may be off, m (0: exact).
    pub uncertainty: f64,
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
    /// The path inside reached the uncertainty of its ends (the id is given then), and the path
    /// length and uncertainty at its first sample, m.
    confirmed: bool,
    s_start: f64,
    uncertainty_start: f64,
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
    /// Regions closed shorter than the uncertainty of their ends.
    unconfirmed: u64,
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
            closed = self.take_open();
        }
        if beyond {
            if self.open.is_none() {
                self.open = Some(TrackedRegion {
                    id: 0,
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
                    confirmed: false,
                    s_start: x.s,
                    uncertainty_start: x.uncertainty,
                });
            }
            let r = self.open.as_mut().expect("a region is open");
            if !r.confirmed && x.s - r.s_start >= r.uncertainty_start + x.uncertainty {
                self.next_id += 1;
                (r.id, r.confirmed) = (self.next_id, true);
            }
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
                    closed = self.take_open();
                }
            }
        }
        let open = self.open();
        (Verdict { beyond: beyond && open.is_some(), region_id: open.map_or(0, |r| r.id), cause: open.map(|r| r.cause) }, closed)
    }

    /// Close the open region: itself if confirmed, else nothing (counted).
    fn take_open(&mut self) -> Option<Box<TrackedRegion>> {
        let r = self.open.take()?;
        if r.confirmed {
            Some(Box::new(r))
        } else {
            self.unconfirmed += 1;
            None
        }
    }

    /// Close the open region (end of the stream, a stale input).
    pub fn finish(&mut self) -> Option<TrackedRegion> {
        self.take_open().map(|r| *r)
    }

    /// The open region, if any (once confirmed).
    pub fn open(&self) -> Option<&TrackedRegion> {
        self.open.as_ref().filter(|r| r.confirmed)
    }

    /// Regions closed shorter than the uncertainty of their ends.
    pub fn unconfirmed(&self) -> u64 {
        self.unconfirmed
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A feed sample at path `s` (mm) asking `rpm` of C at 25 rpm's limit, its tip `sigma` mm off.
    fn sample(k: usize, s_mm: f64, rpm: f64, sigma_mm: f64) -> RuleSample {
        RuleSample {
            t: k as f64 * 0.01,
            s: s_mm * 1e-3,
            tip: Vector3::new(s_mm * 1e-3, 0.0, 0.0),
            motion: Motion::Feed,
            predicted: Some(rpm * crate::units::RPM),
            uncertainty: sigma_mm * 1e-3,
            distance: 0.1,
            path_feed: 0.01,
            programmed_feed: 0.033,
            dt: 0.01,
            ds: 0.1e-3,
            block: -1,
            line: 0,
        }
    }

    fn run(samples: &[RuleSample]) -> (Vec<Verdict>, Vec<TrackedRegion>, u64) {
        let rule = RegionRule::new(25.0 * crate::units::RPM, None);
        let mut tracker = RegionTracker::default();
        let (mut verdicts, mut closed) = (Vec::new(), Vec::new());
        for x in samples {
            let (v, c) = tracker.push(&rule, x);
            verdicts.push(v);
            closed.extend(c.map(|r| *r));
        }
        closed.extend(tracker.finish());
        (verdicts, closed, tracker.unconfirmed())
    }

    #[test]
    fn a_stretch_shorter_than_its_uncertainty_is_no_region_and_a_longer_one_is_from_its_start() {
        // 0.3 mm beyond the limit with the tip 0.5 mm uncertain at both ends: the wander of a
        // junction, counted but not a region, and never announced.
        let wander: Vec<_> = (0..20).map(|k| sample(k, k as f64 * 0.1, if (5..8).contains(&k) { 60.0 } else { 10.0 }, 0.5)).collect();
        let (verdicts, closed, unconfirmed) = run(&wander);
        assert!(closed.is_empty() && unconfirmed == 1, "{closed:?}");
        assert!(verdicts.iter().all(|v| !v.beyond && v.region_id == 0));
        // 3 mm beyond it, the same uncertainty: announced once 1 mm of it is behind (0.5 + 0.5 mm),
        // and the region starts where the demand first passed the limit.
        let pole: Vec<_> = (0..60).map(|k| sample(k, k as f64 * 0.1, if (10..40).contains(&k) { 150.0 } else { 10.0 }, 0.5)).collect();
        let (verdicts, closed, unconfirmed) = run(&pole);
        assert_eq!((closed.len(), unconfirmed), (1, 0));
        assert!((closed[0].tip_start.x - 1.0e-3).abs() < 1e-12 && (closed[0].tip_end.x - 3.9e-3).abs() < 1e-12, "{:?}", closed[0]);
        let first = verdicts.iter().position(|v| v.beyond).unwrap();
        assert_eq!((first, verdicts[first].region_id), (20, 1));
        // Exact samples: a one-sample region is a region, announced at once.
        let exact: Vec<_> = (0..20).map(|k| sample(k, k as f64 * 0.1, if k == 5 { 60.0 } else { 10.0 }, 0.0)).collect();
        let (verdicts, closed, unconfirmed) = run(&exact);
        assert_eq!((closed.len(), unconfirmed), (1, 0));
        assert!(verdicts[5].beyond && verdicts[5].region_id == 1);
    }
}
