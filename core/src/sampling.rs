//! Machine data as shop-floor interfaces deliver it: each axis reported on its own clock, a few
//! times a second, often only when it changed (an MTConnect adapter's SHDR, a change-only bridge's
//! partial `JointState`), or every axis at once (an OPC UA subscription, a control's servo trace).
//! [`PoseMerger`] keeps each axis' own reports and makes whole poses at common instants by
//! interpolating every axis to them: never a stale value held beside a fresh one.
//!
//! The rule, per axis: a report whose value differs from the axis' last one is a *change point*.
//! Between two change points the axis follows a cubic through its neighbouring change points
//! (an axis swinging on an arc while the part turns under the tool is not a chord), unless they lie
//! more than [`MergeConfig::hold_factor`] of the axis' own reporting period apart: then it stood still
//! until one period before the second (moving, it would have been reported sooner). A pose is made at
//! every report's instant once every axis' value there is known: two change points of that axis at
//! or after it, or no change of it while the stream went on for `hold_factor` of its periods (it
//! stood still). That wait is the latency the merge costs ([`PoseMerger::latency`]): a few samples at
//! 1 kHz, up to a second for an axis reported at 3 Hz.
//!
//! Every pose comes with each axis' uncertainty: how far its interpolated value may be off (0 at its
//! own reports, and between them as much as its speed departs there from a smooth course). The path
//! estimates downstream carry it through the kinematics, and a region must be longer than it to be
//! one ([`crate::singularity::tracker`]).

use crate::kinematics::Joints;
use crate::machine::AXES;
use std::collections::VecDeque;
use std::f64::consts::{PI, TAU};

/// The merge's stated rules.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MergeConfig {
    /// Change points further apart than this many of the axis' reporting periods enclose a stop.
    pub hold_factor: f64,
    /// Most instants waiting for an axis; beyond it the oldest is made with what is known (bounds
    /// memory when an axis falls silent while the others go on).
    pub max_pending: usize,
    /// Axes reported modulo a turn (multi-turn rotary axes): unwrapped before interpolation, a step
    /// beyond half a turn between two reports taken as a wrap.
    pub wrap: [bool; AXES],
    /// Each axis' travel (SI): the cubic between two reports within it stays within it (an axis
    /// that runs up to its end stop does not overshoot it between reports).
    pub range: [(f64, f64); AXES],
}

impl Default for MergeConfig {
    fn default() -> Self {
        MergeConfig { hold_factor: 1.5, max_pending: 65_536, wrap: [false; AXES], range: [(f64::NEG_INFINITY, f64::INFINITY); AXES] }
    }
}

/// An axis' period before it has shown one (s): 1 Hz, the slowest rate machine data come at.
pub const DEFAULT_PERIOD: f64 = 1.0;
/// Change intervals an axis' own period is the median of.
const OWN_INTERVALS: usize = 15;
/// Change intervals of every axis pooled, for an axis that has shown too few of its own.
const POOLED_INTERVALS: usize = 64;
/// Own intervals needed before the axis' own median is trusted.
const OWN_NEEDED: usize = 4;

/// Why a report was refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MergeError {
    #[error("out of order: stamp {stamp:.6} s is not after {last:.6} s")]
    OutOfOrder { stamp: f64, last: f64 },
    #[error("axis {axis} position is {value}")]
    NonFinite { axis: usize, value: f64 },
    #[error("a report with no axis in it")]
    Empty,
}

#[derive(Debug, Clone, Default)]
struct AxisTrack {
    /// Change points (t, unwrapped value), oldest first, from the last one at or before the oldest
    /// waiting instant.
    points: VecDeque<(f64, f64)>,
    /// The last raw value and the unwrap offset (multiples of a turn).
    raw: Option<f64>,
    offset: f64,
    intervals: VecDeque<f64>,
    /// Median of `intervals` once there are enough of them.
    own_period: Option<f64>,
}

/// Median of at most [`POOLED_INTERVALS`] values, without allocating (it runs on every change of
/// every axis: five times a sample at 1 kHz).
fn median(v: &VecDeque<f64>) -> Option<f64> {
    let mut buf = [0.0; POOLED_INTERVALS];
    let n = v.len().min(POOLED_INTERVALS);
    if n == 0 {
        return None;
    }
    for (slot, x) in buf.iter_mut().zip(v.iter()) {
        *slot = *x;
    }
    Some(*buf[..n].select_nth_unstable_by(n / 2, f64::total_cmp).1)
}

/// The merge's state for one stream.
#[derive(Debug, Clone)]
pub struct PoseMerger {
    config: MergeConfig,
    axes: [AxisTrack; AXES],
    pooled: VecDeque<f64>,
    pooled_period: Option<f64>,
    /// Instants waiting for an axis, oldest first, and the newest report's stamp.
    pending: VecDeque<f64>,
    last: Option<f64>,
    /// The longest wait an instant has had, s.
    max_latency: f64,
}

impl PoseMerger {
    pub fn new(config: MergeConfig) -> PoseMerger {
        PoseMerger {
            config,
            axes: Default::default(),
            pooled: VecDeque::new(),
            pooled_period: None,
            pending: VecDeque::new(),
            last: None,
            max_latency: 0.0,
        }
    }

    /// Start again (a restarted publisher): nothing of the past is used; nothing waiting is made.
    pub fn reset(&mut self) {
        *self = PoseMerger::new(self.config);
    }

    /// The reporting period of axis `i` as the merge judges it now (s).
    pub fn period(&self, i: usize) -> f64 {
        self.axes[i].own_period.or(self.pooled_period).unwrap_or(DEFAULT_PERIOD)
    }

    /// How long an instant waits now, at most, before every axis' value there is known (s).
    pub fn latency(&self) -> f64 {
        (0..AXES).map(|i| self.config.hold_factor * self.period(i)).fold(0.0, f64::max)
    }

    /// The longest an instant has waited so far (s).
    pub fn max_latency(&self) -> f64 {
        self.max_latency
    }

    /// Axis `i` has been reported.
    pub fn reported(&self, i: usize) -> bool {
        self.axes[i].raw.is_some()
    }

    /// Every axis has been reported: instants are made from here on (before, they are dropped).
    pub fn all_reported(&self) -> bool {
        (0..AXES).all(|i| self.reported(i))
    }

    /// Instants wait for an axis.
    pub fn has_pending(&self) -> bool {
        !self.pending.is_empty()
    }

    /// The newest report's stamp.
    pub fn last_stamp(&self) -> Option<f64> {
        self.last
    }

    /// Take one report: stamp `t` (s, increasing) and the axes it carries (SI); every pose that
    /// became known goes to `out` in time order. A refused report changes nothing.
    pub fn push(&mut self, t: f64, values: &[Option<f64>; AXES], mut out: impl FnMut(f64, Joints, Joints)) -> Result<(), MergeError> {
        if let Some(last) = self.last {
            if !(t > last) {
                return Err(MergeError::OutOfOrder { stamp: t, last });
            }
        }
        if values.iter().all(Option::is_none) {
            return Err(MergeError::Empty);
        }
        if let Some((axis, value)) = values.iter().enumerate().find_map(|(i, v)| v.filter(|v| !v.is_finite()).map(|v| (i, v))) {
            return Err(MergeError::NonFinite { axis, value });
        }
        self.last = Some(t);
        for (i, v) in values.iter().enumerate() {
            let Some(raw) = *v else { continue };
            let track = &mut self.axes[i];
            if self.config.wrap[i] {
                if let Some(prev) = track.raw {
                    let step = raw - prev;
                    if step > PI {
                        track.offset -= TAU * ((step + PI) / TAU).floor();
                    } else if step < -PI {
                        track.offset += TAU * ((-step + PI) / TAU).floor();
                    }
                }
            }
            track.raw = Some(raw);
            let value = raw + track.offset;
            if track.points.back().is_some_and(|p| p.1 == value) {
                continue;
            }
            if let Some(&(t0, _)) = track.points.back() {
                let dt = t - t0;
                track.intervals.push_back(dt);
                if track.intervals.len() > OWN_INTERVALS {
                    track.intervals.pop_front();
                }
                if track.intervals.len() >= OWN_NEEDED {
                    track.own_period = median(&track.intervals);
                }
                self.pooled.push_back(dt);
                if self.pooled.len() > POOLED_INTERVALS {
                    self.pooled.pop_front();
                }
                self.pooled_period = median(&self.pooled);
            }
            track.points.push_back((t, value));
        }
        if self.all_reported() {
            self.pending.push_back(t);
        } else {
            // No instant is made before every axis has reported (an axis not yet mapped, or one its
            // source leaves unavailable): each axis keeps what the first instant will need, its last
            // three change points as `emit` keeps them, not every change while another stays silent.
            for a in self.axes.iter_mut() {
                while a.points.len() > 3 {
                    a.points.pop_front();
                }
            }
        }
        self.emit(false, &mut out);
        Ok(())
    }

    /// Make every waiting instant with what is known (the end of a stream, a stream gone silent):
    /// an axis with no change after an instant is taken as still there.
    pub fn flush(&mut self, mut out: impl FnMut(f64, Joints, Joints)) {
        self.emit(true, &mut out);
    }

    /// Axis `i`'s value at `at` is known: a change point at the instant itself, two of its change
    /// points after it (the cubic needs the one beyond the bracket), or one and no change since for
    /// `hold_factor` periods, or none for that long (it stood still).
    fn known(&self, i: usize, at: f64) -> bool {
        let a = &self.axes[i];
        let k = a.points.partition_point(|p| p.0 < at);
        let after = a.points.len() - k;
        let still = |since: f64| self.last.is_some_and(|last| last - since >= self.config.hold_factor * self.period(i));
        // Reported at the instant itself: its value there is exact.
        let exact = a.points.get(k).is_some_and(|p| p.0 == at);
        exact || after >= 2 || (after == 1 && still(a.points.back().map_or(at, |p| p.0))) || (after == 0 && still(at))
    }

    /// Axis `i` at instant `at` by the rule of the module's doc, and how far that value may be off
    /// (its uncertainty, SI). Between two change points of a move, a cubic Hermite curve whose slopes
    /// are the three-point derivatives at its ends (exact for a quadratic: the arc an axis sweeps
    /// while the part turns under the tool is followed to the fourth order in the step, a straight
    /// chord only to the second); linear where a neighbour lies across a stop; held, then one
    /// period's ramp, across a stop.
    ///
    /// The uncertainty is 0 at the axis' own reports and where it stood still. Between reports of a
    /// move it is `u (1 - u) h r`: how far the axis could stray from the curve at the fraction `u` of
    /// the interval `h` had its speed departed by `r` from the course the curve assumes, `r` being
    /// [`PoseMerger::unsmooth`]. Across a stop, once the axis may have started (within `hold_factor`
    /// periods of the change), half the change: it started somewhere in that time.
    fn value(&self, i: usize, at: f64) -> (f64, f64) {
        let points = &self.axes[i].points;
        let k = points.partition_point(|p| p.0 <= at);
        let Some(&(t0, v0)) = k.checked_sub(1).and_then(|j| points.get(j)) else {
            return (points.front().map_or(0.0, |p| p.1), 0.0);
        };
        let Some(&(t1, v1)) = points.get(k) else { return (v0, 0.0) };
        let p = self.period(i);
        let stop = |a: f64, b: f64| b - a > self.config.hold_factor * p;
        if stop(t0, t1) {
            let start = t1 - p;
            let v = if at <= start { v0 } else { v0 + (v1 - v0) * (at - start) / p };
            let sigma = if at <= t1 - self.config.hold_factor * p { 0.0 } else { 0.5 * (v1 - v0).abs() };
            return (v, sigma);
        }
        let h = t1 - t0;
        let secant = (v1 - v0) / h;
        // The derivative at a point from its two neighbours (second order on uneven steps).
        let slope = |(ta, va): (f64, f64), (tb, vb): (f64, f64), (tc, vc): (f64, f64)| {
            let (h1, h2) = (tb - ta, tc - tb);
            ((vb - va) / h1 * h2 + (vc - vb) / h2 * h1) / (h1 + h2)
        };
        let before = k.checked_sub(2).and_then(|j| points.get(j)).copied().filter(|b| !stop(b.0, t0));
        let beyond = points.get(k + 1).copied().filter(|b| !stop(t1, b.0));
        let m0 = before.map_or(secant, |b| slope(b, (t0, v0), (t1, v1)));
        let m1 = beyond.map_or(secant, |b| slope((t0, v0), (t1, v1), b));
        let u = (at - t0) / h;
        let (u2, u3) = (u * u, u * u * u);
        let v = (2.0 * u3 - 3.0 * u2 + 1.0) * v0 + (u3 - 2.0 * u2 + u) * h * m0 + (-2.0 * u3 + 3.0 * u2) * v1 + (u3 - u2) * h * m1;
        let (lo, hi) = self.config.range[i];
        // At the axis' own report (every pose of a stream that reports all axes together) the value
        // is exact: no need to look at its neighbours.
        let sigma = if at == t0 { 0.0 } else { u * (1.0 - u) * h * self.unsmooth(i, k) };
        (v.clamp(lo.min(v0).min(v1), hi.max(v0).max(v1)), sigma)
    }

    /// How far axis `i`'s speed departs from a smooth course about its interval from change point
    /// `k - 1` to `k` (SI per second): the largest residual of the quadratic in time (a constant jerk,
    /// which the cubic follows closely) through the speeds of the four intervals from `k - 3` to
    /// `k + 1`, taken at their middles. The table turning at the pole swings the linear axes on arcs
    /// that such a quadratic follows to a few hundredths of a millimetre at 3 Hz; a block junction
    /// where an axis stops, starts or turns back within an interval leaves residuals of tens of mm/s.
    /// With fewer than four intervals of motion about it (beside a stop, at a stream's ends): the
    /// spread of the speeds there, and at least the interval's own speed beside a stop or an end
    /// (the axis may have started or stopped anywhere in it).
    fn unsmooth(&self, i: usize, k: usize) -> f64 {
        let points = &self.axes[i].points;
        let hold = self.config.hold_factor * self.period(i);
        // (mid-time, speed) of the interval from change point `a` to `a + 1`, if a move.
        let interval = |a: usize| -> Option<(f64, f64)> {
            let (&(ta, va), &(tb, vb)) = (points.get(a)?, points.get(a + 1)?);
            (tb - ta <= hold).then(|| (0.5 * (ta + tb), (vb - va) / (tb - ta)))
        };
        let around: [Option<(f64, f64)>; 4] = std::array::from_fn(|j| (k + j).checked_sub(3).and_then(interval));
        let own = around[2].map_or(0.0, |x| x.1);
        if let [Some(a), Some(b), Some(c), Some(d)] = around {
            // The residual of the least-squares quadratic through four points is along the weights
            // of their third divided difference, w_j = 1 / prod(t_j - t_m), which every quadratic
            // sums to zero against.
            let x = [a, b, c, d];
            let w: [f64; 4] = std::array::from_fn(|j| 1.0 / (0..4).filter(|&m| m != j).map(|m| x[j].0 - x[m].0).product::<f64>());
            let dot: f64 = (0..4).map(|j| w[j] * x[j].1).sum();
            let norm: f64 = w.iter().map(|w| w * w).sum();
            return (dot / norm).abs() * w.iter().map(|w| w.abs()).sum::<f64>();
        }
        let speeds = around.iter().flatten().map(|x| x.1);
        let spread = speeds.clone().fold(f64::NEG_INFINITY, f64::max) - speeds.fold(f64::INFINITY, f64::min);
        let beside_stop = around[1].is_none() || around[3].is_none();
        spread.max(0.0).max(if beside_stop { own.abs() } else { 0.0 })
    }

    fn emit(&mut self, all: bool, out: &mut impl FnMut(f64, Joints, Joints)) {
        while let Some(&at) = self.pending.front() {
            let ready = (0..AXES).all(|i| self.known(i, at));
            let forced = !ready && self.pending.len() > self.config.max_pending;
            if !(ready || all || forced) {
                break;
            }
            let both: [(f64, f64); AXES] = std::array::from_fn(|i| self.value(i, at));
            let (q, sigma): (Joints, Joints) = (both.map(|b| b.0), both.map(|b| b.1));
            self.pending.pop_front();
            if let Some(last) = self.last {
                self.max_latency = self.max_latency.max(last - at);
            }
            // Keep each axis' change points from the second before the last at or before the next
            // instant (the cubic's left neighbour, and the one before it for the uncertainty).
            let next = self.pending.front().copied().unwrap_or(at);
            for a in self.axes.iter_mut() {
                while a.points.len() > 3 && a.points[3].0 <= next {
                    a.points.pop_front();
                }
            }
            out(at, q, sigma);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(m: &mut PoseMerger, reports: &[(f64, [Option<f64>; AXES])]) -> Vec<(f64, Joints)> {
        let mut got = Vec::new();
        for (t, v) in reports {
            m.push(*t, v, |t, q, _| got.push((t, q))).unwrap();
        }
        m.flush(|t, q, _| got.push((t, q)));
        got
    }

    #[test]
    fn together_stream_passes_through() {
        let mut m = PoseMerger::new(MergeConfig::default());
        let reports: Vec<_> = (0..50).map(|k| (k as f64 * 1e-3, [Some(k as f64), Some(0.0), Some(-(k as f64)), Some(0.5), Some(2.0 * k as f64)])).collect();
        let got = run(&mut m, &reports);
        assert_eq!(got.len(), 50);
        for (k, (t, q)) in got.iter().enumerate() {
            assert_eq!(*t, k as f64 * 1e-3);
            assert_eq!(*q, [k as f64, 0.0, -(k as f64), 0.5, 2.0 * k as f64]);
        }
        // The still axes are known two samples later: 1.5 ms of wait at 1 kHz.
        assert!(m.max_latency() <= 2.0e-3 + 1e-12, "{}", m.max_latency());
    }

    #[test]
    fn per_axis_reports_interpolate_to_common_instants() {
        // X moves at 1 unit/s, reported every 0.3 s; C at 10 units/s, reported every 0.25 s with
        // another phase; Y, Z, A report once and stay still.
        let mut m = PoseMerger::new(MergeConfig::default());
        let mut reports: Vec<(f64, [Option<f64>; AXES])> = vec![(0.01, [None, Some(0.0), Some(0.0), Some(0.0), None])];
        for k in 0..20 {
            let t = 0.02 + 0.3 * k as f64;
            reports.push((t, [Some(t), None, None, None, None]));
            let t = 0.03 + 0.25 * k as f64;
            reports.push((t, [None, None, None, None, Some(10.0 * t)]));
        }
        reports.sort_by(|a, b| a.0.total_cmp(&b.0));
        let got = run(&mut m, &reports);
        for (t, q) in got.iter().filter(|(t, _)| *t > 0.1 && *t < 4.7) {
            assert!((q[0] - t).abs() < 1e-9, "X at {t}: {}", q[0]);
            assert!((q[4] - 10.0 * t).abs() < 1e-9, "C at {t}: {}", q[4]);
            assert_eq!(&q[1..4], &[0.0; 3]);
        }
        assert!(got.windows(2).all(|w| w[0].0 < w[1].0));
    }

    #[test]
    fn an_arc_swept_between_sparse_reports_is_followed_closely() {
        // X = R cos(wt), Y = R sin(wt) (the linear axes while the part turns under the tool): R = 25
        // mm, 96 deg/s, each reported every 0.33 s on its own phase. A chord between reports misses
        // the arc by R (1 - cos 16 deg) = 0.97 mm; the cubic must stay within a tenth of that.
        let (r, w) = (25e-3, 96f64.to_radians());
        let mut m = PoseMerger::new(MergeConfig::default());
        let mut reports = Vec::new();
        for k in 0..30 {
            let t = 0.05 + 0.33 * k as f64;
            reports.push((t, [Some(r * (w * t).cos()), None, Some(0.0), Some(0.0), Some(0.0)]));
            let t = 0.21 + 0.33 * k as f64;
            reports.push((t, [None, Some(r * (w * t).sin()), None, None, None]));
        }
        reports.sort_by(|a, b| a.0.total_cmp(&b.0));
        let got = run(&mut m, &reports);
        let worst = got
            .iter()
            .filter(|(t, _)| *t > 0.6 && *t < 9.0)
            .map(|(t, q)| ((q[0] - r * (w * t).cos()).powi(2) + (q[1] - r * (w * t).sin()).powi(2)).sqrt())
            .fold(0.0, f64::max);
        assert!(worst < 0.097e-3, "worst error {:.4} mm", worst * 1e3);
    }

    #[test]
    fn the_cubic_does_not_overshoot_an_end_stop() {
        // An axis decelerating into its end stop at 1.0, then reported a little later at 1.0
        // again after a small dip (a servo's settling): the cubic through the neighbours would
        // overshoot past 1.0 between the reports.
        let reports = [(0.0, 0.0), (0.3, 0.6), (0.6, 0.99), (0.9, 1.0), (1.2, 0.7), (1.5, 0.2)];
        let run_with = |range: (f64, f64)| {
            let mut config = MergeConfig::default();
            config.range[0] = range;
            let mut m = PoseMerger::new(config);
            let mut got = Vec::new();
            for (t, x) in reports {
                m.push(t, &[Some(x), Some(0.0), Some(0.0), Some(0.0), Some(0.0)], |_, q, _| got.push(q[0])).unwrap();
                // Instants between the reports, from the other axes.
                m.push(t + 0.15, &[None, Some(t), None, None, None], |_, q, _| got.push(q[0])).unwrap();
            }
            m.flush(|_, q, _| got.push(q[0]));
            got.into_iter().fold(f64::NEG_INFINITY, f64::max)
        };
        assert!(run_with((f64::NEG_INFINITY, f64::INFINITY)) > 1.0, "the unbounded cubic overshoots here");
        assert!(run_with((-1.0, 1.0)) <= 1.0);
    }

    #[test]
    fn a_still_axis_that_starts_moving_ramps_over_one_period() {
        // X reported every 0.3 s; still at 0 until t = 3, then at 1 unit/s.
        let mut m = PoseMerger::new(MergeConfig::default());
        let reports: Vec<_> = (0..20)
            .map(|k| {
                let t = 0.3 * k as f64;
                let x = (t - 3.0).max(0.0);
                (t, [Some(x), Some(0.0), Some(0.0), Some(0.0), Some(0.0)])
            })
            .collect();
        let got = run(&mut m, &reports);
        let at = |t: f64| got.iter().find(|g| (g.0 - t).abs() < 1e-9).unwrap().1[0];
        // Held, not ramped from t = 0: the report at 3.3 (0.3) is X's first change.
        assert_eq!(at(2.7), 0.0);
        assert!((at(3.3) - 0.3).abs() < 1e-9);
        assert!((at(3.6) - 0.6).abs() < 1e-9);
    }

    /// (t, value, uncertainty) of axis `i` for every pose made.
    fn run_sigma(m: &mut PoseMerger, reports: &[(f64, [Option<f64>; AXES])], i: usize) -> Vec<(f64, f64, f64)> {
        let mut got = Vec::new();
        for (t, v) in reports {
            m.push(*t, v, |t, q, s| got.push((t, q[i], s[i]))).unwrap();
        }
        m.flush(|t, q, s| got.push((t, q[i], s[i])));
        got
    }

    #[test]
    fn the_uncertainty_covers_a_stop_between_reports_and_stays_small_on_an_arc() {
        // Z at 2000 mm/min (33.3 mm/s) until it arrives at 100 mm at t = 3.02 s, then creeping at
        // -0.1 mm/s (a TCP's compensation), reported every 0.33 s; Y reported between. The cubic
        // rounds the stop off (0.9 mm short of 100 at 3.05 s): the uncertainty must say so.
        let z = |t: f64| if t <= 3.02 { 100.0 - 33.3 * (3.02 - t) } else { 100.0 - 0.1 * (t - 3.02) };
        let mut reports = Vec::new();
        for k in 0..14 {
            let t = 0.33 * k as f64;
            reports.push((t, [Some(0.0), Some(0.0), Some(z(t)), Some(0.0), Some(0.0)]));
            for f in [0.08, 0.16, 0.24] {
                reports.push((t + f, [None, Some(t + f), None, None, None]));
            }
        }
        let got = run_sigma(&mut PoseMerger::new(MergeConfig::default()), &reports, 2);
        let about: Vec<_> = got.iter().filter(|g| (2.4..3.6).contains(&g.0)).collect();
        let worst = about.iter().map(|g| (g.1 - z(g.0)).abs()).fold(0.0, f64::max);
        assert!(worst > 0.5, "the cubic is off by {worst:.3} mm about the stop");
        for (t, v, sigma) in &about {
            assert!((v - z(*t)).abs() <= *sigma + 1e-9, "at {t:.2} s off by {:.3} mm, uncertainty {sigma:.3} mm", (v - z(*t)).abs());
        }
        // Before the stop, a steady move (once Z has shown its own period): no uncertainty.
        for g in got.iter().filter(|g| (1.7..2.3).contains(&g.0)) {
            assert!(g.2 < 1e-6, "{g:?}");
        }

        // X = R cos(wt) (a linear axis while the part turns under the tool, R = 25 mm, 96 deg/s),
        // reported every 0.33 s, Y between: the cubic is within 0.1 mm (0.05 here) and says it may be off
        // by at most 0.25 mm (0.22 here: four times too careful on an arc, against a junction's 0.6 mm).
        let (r, w) = (25.0, 96f64.to_radians());
        let mut reports = Vec::new();
        for k in 0..30 {
            let t = 0.05 + 0.33 * k as f64;
            reports.push((t, [Some(r * (w * t).cos()), Some(0.0), Some(0.0), Some(0.0), Some(0.0)]));
            reports.push((t + 0.16, [None, Some(t), None, None, None]));
        }
        let got = run_sigma(&mut PoseMerger::new(MergeConfig::default()), &reports, 0);
        let inner: Vec<_> = got.iter().filter(|g| (1.5..8.5).contains(&g.0)).collect();
        let largest = inner.iter().map(|g| g.2).fold(0.0, f64::max);
        let worst = inner.iter().map(|g| (g.1 - r * (w * g.0).cos()).abs()).fold(0.0, f64::max);
        assert!(worst < 0.1, "{worst}");
        assert!(largest > 0.0 && largest < 0.25, "uncertainty on the arc up to {largest:.3} mm");
    }

    #[test]
    fn modulo_axis_is_unwrapped_before_interpolating() {
        let mut config = MergeConfig::default();
        config.wrap[4] = true;
        let mut m = PoseMerger::new(config);
        let c = |deg: f64| Some(deg.to_radians().rem_euclid(TAU));
        let reports: Vec<_> = (0..10).map(|k| (0.1 * k as f64, [Some(0.0), Some(0.0), Some(0.0), Some(0.0), c(340.0 + 10.0 * k as f64)])).collect();
        let got = run(&mut m, &reports);
        for (k, (_, q)) in got.iter().enumerate() {
            assert!((q[4] - (340.0 + 10.0 * k as f64).to_radians()).abs() < 1e-9);
        }
    }

    #[test]
    fn refused_reports_change_nothing() {
        let mut m = PoseMerger::new(MergeConfig::default());
        m.push(1.0, &[Some(0.0); AXES], |_, _, _| {}).unwrap();
        assert!(matches!(m.push(1.0, &[Some(1.0); AXES], |_, _, _| {}), Err(MergeError::OutOfOrder { .. })));
        assert!(matches!(m.push(2.0, &[None; AXES], |_, _, _| {}), Err(MergeError::Empty)));
        assert!(matches!(m.push(2.0, &[Some(f64::NAN), None, None, None, None], |_, _, _| {}), Err(MergeError::NonFinite { axis: 0, .. })));
        assert_eq!(m.last_stamp(), Some(1.0));
    }

    #[test]
    fn memory_is_bounded_when_an_axis_falls_silent() {
        let mut m = PoseMerger::new(MergeConfig { max_pending: 100, ..MergeConfig::default() });
        // C reported once, then X alone for a long time at 1 kHz while C's period says 1 s.
        m.push(0.0, &[Some(0.0); AXES], |_, _, _| {}).unwrap();
        let mut made = 0;
        for k in 1..10_000 {
            m.push(k as f64 * 1e-3, &[Some(k as f64), None, None, None, None], |_, _, _| made += 1).unwrap();
        }
        assert!(m.pending.len() <= 101);
        assert!(made > 9_000);
    }

    #[test]
    fn an_axis_never_reported_holds_no_more_than_the_first_instant_needs() {
        // X Y Z A at 1 kHz for 100 s, C silent (a joint not mapped, or unavailable at its source):
        // nothing can be made, and each axis keeps its last three change points, not 100,000.
        let mut m = PoseMerger::new(MergeConfig::default());
        let mut made = 0;
        for k in 0..100_000 {
            let t = k as f64 * 1e-3;
            m.push(t, &[Some(t), Some(2.0 * t), Some(-t), Some(0.5 * t), None], |_, _, _| made += 1).unwrap();
        }
        assert_eq!(made, 0);
        assert!(m.axes.iter().all(|a| a.points.len() <= 3), "{:?}", m.axes.iter().map(|a| a.points.len()).collect::<Vec<_>>());
        // C reports: the first instant is made with every axis where it was reported then.
        let t = 100.0;
        let mut got = Vec::new();
        m.push(t, &[Some(t), Some(2.0 * t), Some(-t), Some(0.5 * t), Some(1.0)], |at, q, _| got.push((at, q))).unwrap();
        m.flush(|at, q, _| got.push((at, q)));
        assert_eq!(got, vec![(t, [t, 2.0 * t, -t, 0.5 * t, 1.0])]);
    }
}
