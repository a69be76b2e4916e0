//! The whole-trajectory analysis: per-sample status, regions and a summary.

use super::{distance, on_pole, predicted_rate, FeedLimit, FeedLimiter, PathGeometry};
use crate::machine::Machine;
use crate::path::{Sample, Segment, Trajectory};
use nalgebra::Vector3;

/// Options of the analysis.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct AnalysisOptions {
    /// Also open a region where the distance to the singularity falls below this angle (rad), on
    /// simultaneous five-axis moves.
    pub min_distance: Option<f64>,
    /// Secondary-axis speed limit for regions, rad/s (default: the machine's).
    pub rate_limit: Option<f64>,
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
    /// Largest |finite-difference rate|, rad/s.
    pub peak_fd_rate: f64,
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
    pub statuses: Vec<Status>,
    pub regions: Vec<Region>,
    pub summary: Summary,
}

/// Analyze a sampled trajectory on a machine.
pub fn analyze(traj: &Trajectory, machine: &Machine, options: &AnalysisOptions) -> Analysis {
    let sd = machine.singular_direction();
    let sec = machine.secondary_axis();
    let sign = machine.chain.joints()[machine.chain.secondary_slot()].carrier;
    let sign = match sign {
        crate::kinematics::Carrier::Table => -1.0,
        crate::kinematics::Carrier::Head => 1.0,
    };
    let limits = machine.limits();
    let limiter = FeedLimiter::new(&limits);
    let geometry = PathGeometry::new(traj, machine);
    let n = traj.samples.len();
    let samples = &traj.samples;
    let statuses: Vec<Status> = (0..n)
        .map(|k| {
            let sm = &samples[k];
            let seg = &traj.segments[sm.segment];
            let (a, b) = (k.saturating_sub(1), (k + 1).min(n - 1));
            let dt = samples[b].t - samples[a].t;
            let fd_rate = if dt > 0.0 { (samples[b].q[sec] - samples[a].q[sec]) / dt } else { 0.0 };
            let feed_limit = geometry
                .derivatives(sm.segment, sm.s)
                .map(|(d1, d2, d3)| limiter.limit(sm.feed, &d1, &d2, &d3));
            Status {
                distance: distance(&sm.axis, &sd),
                predicted_rate: sign * predicted_rate(&sm.axis, &sm.axis_rate, &sd),
                fd_rate,
                feed_limit,
                five_axis: seg.is_five_axis(),
                on_pole: on_pole(&sm.axis, &sm.axis_rate, &sd),
                rapid: seg.kind == crate::path::SegmentKind::Rapid,
            }
        })
        .collect();
    let rate_limit = options.rate_limit.unwrap_or(limits[sec].velocity);
    let mut regions = find_regions(&traj.segments, samples, &statuses, rate_limit, options.min_distance);
    for r in &mut regions {
        let (a, b) = (&traj.segments[samples[r.first].segment], &traj.segments[samples[r.last].segment]);
        (r.line_start, r.block_start, r.line_end, r.block_end) = (a.line, a.number, b.line, b.number);
    }
    let mut summary = summarize(traj, &statuses, rate_limit);
    // The programmed extremes lie at block ends, which the sample grid may miss by a fraction of a
    // period: take the closest approach over the five-axis moves' end points too.
    for seg in traj.segments.iter().filter(|s| s.is_five_axis()) {
        for (q, tip) in [(&seg.q0, seg.tip0), (&seg.q1, seg.tip1)] {
            let d = distance(&machine.chain.orientation(&[q[3], q[4]]), &sd);
            if summary.min_distance.is_none_or(|m| d < m) {
                summary.min_distance = Some(d);
                summary.min_distance_tip = Some(tip);
            }
            summary.min_distance_all = summary.min_distance_all.min(d);
        }
    }
    Analysis { statuses, regions, summary }
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
/// different segments (the axes are linear per block, so the speed steps there), else at fraction `f`.
fn boundary(segments: &[Segment], a: &Sample, b: &Sample, f: f64) -> (f64, Vector3<f64>) {
    if a.segment != b.segment {
        let seg = &segments[b.segment];
        if seg.t0 >= a.t && seg.t0 <= b.t {
            return (seg.t0, seg.tip0);
        }
    }
    (a.t + (b.t - a.t) * f, a.tip + (b.tip - a.tip) * f)
}

fn find_regions(segments: &[Segment], samples: &[Sample], statuses: &[Status], rate_limit: f64, min_distance: Option<f64>) -> Vec<Region> {
    let mut regions = Vec::new();
    let mut k = 0;
    let n = statuses.len();
    while k < n {
        let Some(mut cause) = in_region(&statuses[k], rate_limit, min_distance) else {
            k += 1;
            continue;
        };
        let first = k;
        while k + 1 < n {
            match in_region(&statuses[k + 1], rate_limit, min_distance) {
                Some(c) => {
                    if c != cause {
                        cause = RegionCause::SpeedAndDistance;
                    }
                    k += 1;
                }
                None => break,
            }
        }
        let last = k;
        let (t_start, tip_start) = if first > 0 {
            boundary(segments, &samples[first - 1], &samples[first], crossing(&statuses[first - 1], &statuses[first], rate_limit))
        } else {
            (samples[first].t, samples[first].tip)
        };
        let (t_end, tip_end) = if last + 1 < n {
            boundary(segments, &samples[last], &samples[last + 1], 1.0 - crossing(&statuses[last + 1], &statuses[last], rate_limit))
        } else {
            (samples[last].t, samples[last].tip)
        };
        let inside = first..=last;
        let peak = inside
            .clone()
            .filter(|&i| statuses[i].predicted_rate.is_finite())
            .max_by(|&a, &b| statuses[a].predicted_rate.abs().total_cmp(&statuses[b].predicted_rate.abs()));
        let min_feed_limit = inside
            .clone()
            .filter_map(|i| statuses[i].feed_limit)
            .min_by(|a, b| a.feed.total_cmp(&b.feed));
        regions.push(Region {
            id: regions.len() + 1,
            cause,
            first,
            last,
            t_start,
            t_end,
            tip_start,
            tip_end,
            line_start: 0,
            line_end: 0,
            block_start: None,
            block_end: None,
            peak_rate: peak.map_or(0.0, |p| statuses[p].predicted_rate.abs()),
            peak_tip: peak.map_or(samples[first].tip, |p| samples[p].tip),
            min_distance: inside.map(|i| statuses[i].distance).fold(f64::INFINITY, f64::min),
            min_feed_limit,
        });
        k += 1;
    }
    regions
}

fn summarize(traj: &Trajectory, statuses: &[Status], rate_limit: f64) -> Summary {
    let samples = &traj.samples;
    let mut peak: Option<usize> = None;
    let mut singular_samples = 0;
    let mut peak_fd: f64 = 0.0;
    let mut min_d: Option<(f64, usize)> = None;
    let mut min_all = f64::INFINITY;
    let mut min_fl: Option<(FeedLimit, usize)> = None;
    for (k, s) in statuses.iter().enumerate() {
        // The peak is the path's: rapids move the axes at their limits by definition.
        if !s.rapid && peak.is_none_or(|p| s.predicted_rate.abs() > statuses[p].predicted_rate.abs()) {
            peak = Some(k);
        }
        if s.on_pole {
            singular_samples += 1;
        }
        peak_fd = peak_fd.max(s.fd_rate.abs());
        min_all = min_all.min(s.distance);
        if s.five_axis && min_d.is_none_or(|(d, _)| s.distance < d) {
            min_d = Some((s.distance, k));
        }
        if let Some(fl) = s.feed_limit {
            if min_fl.is_none_or(|(m, _)| fl.feed < m.feed) {
                min_fl = Some((fl, k));
            }
        }
    }
    let (peak_rate, peak_tip, peak_line, peak_block) = match peak {
        Some(p) => {
            let v = statuses[p].predicted_rate.abs();
            let near = |i: usize| (statuses[i].predicted_rate.abs() - v).abs() <= 1e-3 * v;
            let (mut a, mut b) = (p, p);
            while a > 0 && near(a - 1) {
                a -= 1;
            }
            while b + 1 < statuses.len() && near(b + 1) {
                b += 1;
            }
            let mid = (samples[a].tip + samples[b].tip) / 2.0;
            let seg = &traj.segments[samples[p].segment];
            (v, mid, seg.line, seg.number)
        }
        None => (0.0, Vector3::zeros(), 0, None),
    };
    Summary {
        peak_rate,
        peak_tip,
        peak_line,
        peak_block,
        peak_fd_rate: peak_fd,
        singular_samples,
        min_distance: min_d.map(|(d, _)| d),
        min_distance_tip: min_d.map(|(_, k)| samples[k].tip),
        min_distance_all: if statuses.is_empty() { f64::NAN } else { min_all },
        min_feed_limit: min_fl.map(|(f, _)| f),
        min_feed_limit_tip: min_fl.map(|(_, k)| samples[k].tip),
        rate_limit,
        cycle_time: traj.duration(),
    }
}
