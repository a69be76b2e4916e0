//! Path-speed profile of each run and the sampled set-points.

use super::geometry::{Curve, Run, RunScout};
use std::collections::VecDeque;
use crate::kinematics::Joints;
use super::check::limit_ratios_into;
use crate::machine::{AxisLimits, Machine, AXES};
use crate::path::Segment;
use crate::singularity::FeedLimiter;

/// Planner settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlanConfig {
    /// Output sample period, s.
    pub period: f64,
    /// Path grid step for runs measured in length, m (rotary-only runs use `grid_rad`).
    pub grid_m: f64,
    pub grid_rad: f64,
    /// Jerk filter window, s (default: the largest `2 a_max / j_max` of the axes).
    pub jerk_window: Option<f64>,
    /// How often the profile of a look-ahead window may be replanned where a limit was exceeded.
    pub max_iterations: usize,
    /// Look-ahead, blocks: how far ahead the planner reads; it plans to be able to stop at the end
    /// of what it has read and commits the first three quarters. Default [`LOOKAHEAD_BLOCKS`].
    pub lookahead_blocks: usize,
}

/// The default look-ahead, 5000 blocks: Heidenhain's figure ("look-ahead cyclically calculates the
/// maximum possible contouring speed up to 5000 blocks in advance", MANUALplus 620 Technical Manual
/// §6.16.4; the paper's Hermle runs a Heidenhain TNC). Others read less: LinuxCNC's trajectory planner
/// 50 segments (`ARC_BLEND_OPTIMIZATION_DEPTH`, docs/src/config/ini-config.adoc), Fanuc's AI contour
/// control "maximum 40 blocks ahead" (A-63512EN §2.3). The window must cover the braking distance
/// and the jerk filter's lag (its width times the feed) for the limits to hold where the path
/// demands braking; a shorter one makes the planner report ratios above 1 there.
pub const LOOKAHEAD_BLOCKS: usize = 5000;

/// Largest look-ahead window in path grid points (a single long block is read in pieces).
const MAX_WINDOW_POINTS: usize = 200_000;

impl Default for PlanConfig {
    fn default() -> Self {
        PlanConfig { period: 1e-3, grid_m: 2e-5, grid_rad: 1e-4, jerk_window: None, max_iterations: 30, lookahead_blocks: LOOKAHEAD_BLOCKS }
    }
}

/// One planned set-point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlannedSample {
    pub t: f64,
    /// Global segment index (into the trajectory's segments) and run index.
    pub segment: usize,
    pub run: usize,
    /// Axis set-points, m and rad.
    pub q: Joints,
}

/// What the check measured on the planned set-points.
#[derive(Debug, Clone, PartialEq)]
pub struct Planned {
    /// Largest |v|/v_max, |a|/a_max and |j|/j_max over all axes and samples (finite differences at
    /// the sample period), after the last iteration.
    pub max_ratio: [f64; 3],
    /// Replanning rounds the worst run needed.
    pub iterations: usize,
}

/// The smaller of `a` and `b` by a plain comparison: the planner's passes and estimate compare
/// values that are never NaN, where `f64::min`'s NaN handling costs more than the arithmetic (and
/// lengthens chains of dependent steps).
#[inline(always)]
fn lesser(a: f64, b: f64) -> f64 {
    if b < a { b } else { a }
}

/// The larger of `a` and `b` by a plain comparison (see [`lesser`]).
#[inline(always)]
fn greater(a: f64, b: f64) -> f64 {
    if b > a { b } else { a }
}

/// The tangential acceleration bounds of one grid point: axis `i` at path speed `v` and path
/// acceleration `s''` moves at `q_s s'' + q_ss v^2`, within `+-a_max` when
/// `-r_i - p_i v^2 <= s'' <= r_i - p_i v^2` with `p_i = q_ss / q_s` and `r_i = a_max / |q_s|`
/// (axes that do not move along the path, `|q_s| < 1e-12`, bound nothing).
#[derive(Debug, Clone, Copy)]
struct AccelBounds {
    p: [f64; AXES],
    r: [f64; AXES],
}

impl AccelBounds {
    fn new(qs: &Joints, qss: &Joints, limits: &[AxisLimits; AXES]) -> AccelBounds {
        let mut b = AccelBounds { p: [0.0; AXES], r: [f64::INFINITY; AXES] };
        for i in 0..AXES {
            if qs[i].abs() >= 1e-12 {
                let per_qs = 1.0 / qs[i];
                b.p[i] = qss[i] * per_qs;
                b.r[i] = limits[i].acceleration * per_qs.abs();
            }
        }
        b
    }

    /// Tangential acceleration bounds (min, max) moving at path speed `sqrt(v2)`: the bounds depend
    /// on the speed's square only, so the profile passes run on squared speeds without a root.
    /// The passes are chains of dependent steps, each waiting on this: the axes' bounds are
    /// combined pairwise (a minimum is exact in any order) with plain comparisons (nothing here is
    /// NaN: `p` is finite, `r` finite or infinite).
    #[inline(always)]
    fn at_sq(&self, v2: f64) -> (f64, f64) {
        const _: () = assert!(AXES == 5, "the pairwise combination below is written for five axes");
        let c: [f64; AXES] = std::array::from_fn(|i| self.p[i] * v2);
        let hi: [f64; AXES] = std::array::from_fn(|i| self.r[i] - c[i]);
        let lo: [f64; AXES] = std::array::from_fn(|i| -self.r[i] - c[i]);
        (
            greater(greater(greater(lo[0], lo[1]), greater(lo[2], lo[3])), lo[4]),
            lesser(lesser(lesser(hi[0], hi[1]), lesser(hi[2], hi[3])), hi[4]),
        )
    }
}

/// The path grid of one look-ahead window: points `ka..=kb` of the run's uniform grid of step `h`.
struct Window {
    ka: usize,
    h: f64,
    bounds: Vec<AccelBounds>,
    limit: Vec<f64>,
    /// The curve's derivatives at each grid point, `[q_s, q_ss, q_sss]` (for [`Window::estimate`]).
    deriv: Vec<[Joints; 3]>,
}

impl Window {
    /// Geometric derivatives by finite differences on the run's grid (one-sided at the run's ends)
    /// and the seed 002 eq. (5) velocity-limit curve, zero at the run's ends and at the window's end.
    #[allow(clippy::too_many_arguments)]
    fn new(run: &Run, curve: &Curve, machine: &Machine, limiter: &FeedLimiter, h: f64, k_max: usize, ka: usize, kb: usize) -> Window {
        let at = |k: isize| curve.joints(k.clamp(0, k_max as isize) as f64 * h, machine);
        let lo = ka as isize - 2;
        let q: Vec<Joints> = (lo..=kb as isize + 2).map(at).collect();
        let n = kb - ka + 1;
        let limits = machine.limits();
        let mut b = run.segment_at(ka as f64 * h);
        let mut bounds = Vec::with_capacity(n);
        let mut limit = vec![0.0; n];
        let mut deriv = Vec::with_capacity(n);
        // The differences' divisors as factors (a division costs several products; 25 a grid point
        // were a tenth of the window's making).
        let (per_h, per_2h, per_h2, per_2h3) = (1.0 / h, 1.0 / (2.0 * h), 1.0 / (h * h), 1.0 / (2.0 * h * h * h));
        for r in 0..n {
            let k = ka + r;
            let (m2, m1, p0, p1, p2) = (q[r], q[r + 1], q[r + 2], q[r + 3], q[r + 4]);
            let end = k == 0 || k == k_max;
            let per_span = if end { per_h } else { per_2h };
            let (mut qs, mut qss, mut qsss) = ([0.0; AXES], [0.0; AXES], [0.0; AXES]);
            for i in 0..AXES {
                qs[i] = (p1[i] - m1[i]) * per_span;
                qss[i] = if end { 0.0 } else { (p1[i] - 2.0 * p0[i] + m1[i]) * per_h2 };
                qsss[i] = if k < 2 || k + 2 > k_max { 0.0 } else { (p2[i] - 2.0 * p1[i] + 2.0 * m1[i] - m2[i]) * per_2h3 };
            }
            bounds.push(AccelBounds::new(&qs, &qss, &limits));
            deriv.push([qs, qss, qsss]);
            b = run.segment_at_from(b, k as f64 * h);
            let feed = run.feed(b);
            limit[r] = if end || k == kb { 0.0 } else { limiter.limit(feed, &qs, &qss, &qsss).feed };
        }
        Window { ka, h, bounds, limit, deriv }
    }

    /// Estimated limit ratios of the set-points at filtered parameters `f`, as [`limit_ratios_into`]
    /// measures them but without the kinematics of each set-point: the chain rule,
    /// `q' = q_s s'`, `q'' = q_ss s'^2 + q_s s''`, `q''' = q_sss s'^3 + 3 q_ss s' s'' + q_s s'''`, with
    /// the grid's derivatives carried to the parameter and the parameter's own differences at the
    /// check's stencil (held at the ends); `limiter` holds the limits' reciprocals.
    fn estimate(&self, f: &[f64], period: f64, limiter: &FeedLimiter, out: &mut Vec<[f64; 3]>) {
        out.clear();
        let n = f.len();
        out.reserve(n);
        let (d1, d2, d3) = (1.0 / (2.0 * period), 1.0 / (period * period), 1.0 / (2.0 * period * period * period));
        // A window has two grid points or more.
        let last = self.deriv.len() - 1;
        debug_assert!(last >= 1);
        let (origin, per_step) = (self.ka as f64 * self.h, 1.0 / self.h);
        let [iv, ia, ij] = limiter.reciprocals();
        let ratio = |m2: f64, m1: f64, p0: f64, p1: f64, p2: f64| -> [f64; 3] {
            let sd = (p1 - m1) * d1;
            let sdd = (p1 - 2.0 * p0 + m1) * d2;
            let sddd = (p2 - 2.0 * p1 + 2.0 * m1 - m2) * d3;
            let (sd2, mixed) = (sd * sd, 3.0 * sd * sdd);
            let sd3 = sd2 * sd;
            // The grid point before the parameter (a parameter before the window's start reads its
            // first): its first two derivatives carried to the parameter by the next one, the third
            // interpolated to it from the next point's.
            let x = ((p0 - origin) * per_step).max(0.0);
            let k = (x as usize).min(last - 1);
            let u = x - k as f64;
            let dx = u * self.h;
            let [qs, qss, qsss] = &self.deriv[k];
            let qsss_next = &self.deriv[k + 1][2];
            let mut r = [0.0f64; 3];
            for i in 0..AXES {
                let (qs, qss) = (qs[i] + qss[i] * dx, qss[i] + qsss[i] * dx);
                let qsss = qsss[i] + (qsss_next[i] - qsss[i]) * u;
                r[0] = greater(r[0], (qs * sd).abs() * iv[i]);
                r[1] = greater(r[1], (qss * sd2 + qs * sdd).abs() * ia[i]);
                r[2] = greater(r[2], (qsss * sd3 + qss * mixed + qs * sddd).abs() * ij[i]);
            }
            r
        };
        // The check's stencil, held at the ends ([`limit_ratios_into`]'s three parts, spelled out
        // again: one walker shared by both, closure-driven, cost the check and the estimate 1.8 %
        // more instructions). Inside, every other sample, its ratios standing for the next one's
        // too: a limit is exceeded over stretches of many samples (the filter's reach), and the check
        // judges every sample.
        let at = |k: isize| f[k.clamp(0, n as isize - 1) as usize];
        let edge = n.min(2);
        out.extend((0..edge as isize).map(|k| ratio(at(k - 2), at(k - 1), at(k), at(k + 1), at(k + 2))));
        if n > 4 {
            let mut x = [0.0; 3];
            out.extend(f.windows(5).enumerate().map(|(i, p)| {
                if i % 2 == 0 {
                    x = ratio(p[0], p[1], p[2], p[3], p[4]);
                }
                x
            }));
        }
        let tail = n.saturating_sub(2).max(edge);
        out.extend((tail as isize..n as isize).map(|k| ratio(at(k - 2), at(k - 1), at(k), at(k + 1), at(k + 2))));
    }

    /// Path speed over the window from `v0` at its start: forward and backward acceleration passes
    /// under `cap`, at rest at its end (the control must be able to stop where its look-ahead ends).
    fn speed_profile(&self, cap: &[f64], v0: f64) -> Vec<f64> {
        self.speed_profile_to(cap, v0, true)
    }

    /// As [`Window::speed_profile`], at rest at the end only if `stop`. Both passes step the squared
    /// speed, `u' = u + 2 s'' h` (constant path acceleration over a step): the bounds need only `u`,
    /// so no root lies on the passes' chain of dependent steps.
    fn speed_profile_to(&self, cap: &[f64], v0: f64, stop: bool) -> Vec<f64> {
        let n = cap.len();
        let mut u = vec![0.0; n];
        u[0] = v0 * v0;
        // Each step waits on the one before: plain comparisons (nothing here is NaN) and `2 h` once
        // (`2 hi h` and `hi (2 h)` round alike: doubling is exact).
        let two_h = 2.0 * self.h;
        for k in 0..n - 1 {
            let (_, hi) = self.bounds[k].at_sq(u[k]);
            let hi = if hi.is_finite() { hi } else { 1e12 };
            u[k + 1] = lesser(greater(u[k] + hi * two_h, 0.0), cap[k + 1] * cap[k + 1]);
        }
        if stop {
            u[n - 1] = 0.0;
        }
        for k in (1..n - 1).rev() {
            let (lo, _) = self.bounds[k + 1].at_sq(u[k + 1]);
            let lo = if lo.is_finite() { lo } else { -1e12 };
            u[k] = lesser(u[k], greater(u[k + 1] - lo * two_h, 0.0));
        }
        let mut v: Vec<f64> = u.into_iter().map(f64::sqrt).collect();
        v[0] = v0;
        v
    }

    /// The hardest braking from `v0` at the window's start: the speeds below which no lowering of the
    /// limit curve may go (the committed speed cannot drop faster than the axes can brake).
    fn braking(&self, v0: f64) -> Vec<f64> {
        let n = self.bounds.len();
        let mut u = vec![0.0; n];
        u[0] = v0 * v0;
        for k in 0..n - 1 {
            let (lo, _) = self.bounds[k].at_sq(u[k]);
            let lo = if lo.is_finite() { lo.min(0.0) } else { -1e12 };
            u[k + 1] = (u[k] + 2.0 * lo * self.h).max(0.0);
        }
        let mut v: Vec<f64> = u.into_iter().map(f64::sqrt).collect();
        v[0] = v0;
        v
    }

    /// The path parameter at the sample times `j * period` (j from `j0`) that fall in the window,
    /// the window starting at time `tau0`: exact within each step under the profile's model
    /// (constant path acceleration). Returns the parameters, each grid point's time, and how many
    /// samples fall before grid point `kc` (the committed part).
    fn sample(&self, v: &[f64], tau0: f64, j0: u64, period: f64, kc: usize, last: bool) -> (Vec<f64>, Vec<f64>, usize) {
        let n = v.len();
        let mut t = vec![tau0; n];
        for k in 0..n - 1 {
            t[k + 1] = t[k] + 2.0 * self.h / (v[k] + v[k + 1]).max(1e-9);
        }
        let sigma = |k: usize| (self.ka + k) as f64 * self.h;
        let mut s = Vec::new();
        let mut committed = None;
        let mut k = 0;
        let mut j = j0;
        loop {
            let tj = j as f64 * period;
            if tj >= t[n - 1] {
                break;
            }
            while k + 1 < n - 1 && t[k + 1] <= tj {
                k += 1;
            }
            if committed.is_none() && self.ka + k >= kc {
                committed = Some(s.len());
            }
            let tau = (tj - t[k]).clamp(0.0, t[k + 1] - t[k]);
            let acc = (v[k + 1] * v[k + 1] - v[k] * v[k]) / (2.0 * self.h);
            let ds = (v[k] * tau + 0.5 * acc * tau * tau).clamp(0.0, self.h);
            s.push(sigma(k) + ds);
            j += 1;
        }
        if last {
            s.push(sigma(n - 1));
        }
        let c = if last { s.len() } else { committed.unwrap_or(s.len()) };
        (s, t, c)
    }
}

/// One planning iteration of a window: raw and filtered parameters, set-points (with the two of
/// history first), grid times and speeds, committed sample count, committed worst ratios, caps.
type Plan = (Vec<f64>, Vec<f64>, Vec<Joints>, Vec<f64>, Vec<f64>, usize, [f64; 3], Vec<f64>);

/// The largest of all ratios.
fn worst_all(ratios: &[[f64; 3]]) -> f64 {
    ratios.iter().flat_map(|r| r.iter().copied()).fold(0.0, f64::max)
}

/// No ratio above 1 (rounding on a ratio exactly at its limit, the filter's own jerk bound, is not a
/// violation).
fn within_limits(ratios: &[[f64; 3]]) -> bool {
    ratios.iter().all(|r| r.iter().all(|&x| x <= 1.0 + 1e-9))
}

/// What planning a run measured.
#[derive(Debug, Clone, Copy, Default)]
struct RunStats {
    worst: [f64; 3],
    iterations: usize,
    samples: u64,
    /// The consumer asked to stop.
    stopped: bool,
}

/// Plan one run look-ahead window by window, reading its segments from `source` as the look-ahead
/// reaches them, calling `emit(set-point, segment index, segment)` for each sample in order (false
/// from `emit` stops planning). Each window is planned to stop at its end, checked, and its first
/// three quarters committed.
#[allow(clippy::too_many_arguments)]
fn plan_run(run: &mut Run, source: &mut dyn Iterator<Item = Segment>, machine: &Machine, limiter: &FeedLimiter, config: &PlanConfig, w: usize, emit: &mut dyn FnMut(Joints, usize, &Segment) -> bool) -> RunStats {
    let limits = machine.limits();
    let len = run.length();
    let step = if run.is_angular() { config.grid_rad } else { config.grid_m };
    // A run linear in its parameter (rapid) has q_ss = q_sss = 0: a coarse grid is exact.
    let cap_points = if run.is_linear() { 2000.0 } else { 1e15 };
    let k_max = (len / step).ceil().clamp(4.0, cap_points) as usize;
    let h = len / k_max as f64;
    let nb = run.count();
    let lookahead = config.lookahead_blocks.max(2);
    let mut stats = RunStats::default();
    // Committed state: grid point, its speed and time; next sample index; the filter's last w - 1
    // inputs (at rest at 0 before the run) and the last two set-points (for the check's stencil).
    let (mut ka, mut v0, mut tau0, mut j0) = (0usize, 0.0f64, 0.0f64, 0u64);
    let mut raw_hist: VecDeque<f64> = std::iter::repeat_n(0.0, w - 1).collect();
    let mut q_hist: Vec<Joints> = Vec::new();
    let mut carry: Vec<f64> = Vec::new();
    // Scratch of every plan: the filter's prefix sums and the check's ratios.
    let (mut prefix, mut all): (Vec<f64>, Vec<[f64; 3]>) = (Vec::new(), Vec::new());
    loop {
        // The jerk filter's outputs lag its inputs: the curve must reach back to the oldest input
        // the filter still holds, where this window's first set-points lie; nothing before it (and
        // the splines' overlap) is needed again.
        let oldest = raw_hist.front().map_or(ka as f64 * h, |&x| x.min(ka as f64 * h));
        let b_oldest = run.segment_at(oldest);
        run.release_before(b_oldest);
        let b_first = run.segment_at_reading(ka as f64 * h, source);
        let b_last = (b_first + lookahead - 1).min(nb - 1);
        run.read_through(b_last + 1, source);
        let kb_blocks = if b_last == nb - 1 { k_max } else { ((run.sigma(b_last + 1) / h).floor() as usize).min(k_max) };
        let kb = kb_blocks.min(ka + MAX_WINDOW_POINTS).max(ka + 1);
        let last = kb == k_max;
        let kc = if last { k_max } else { ka + ((kb - ka) * 3 / 4).max(1) };
        let curve = run.curve(b_oldest, run.segment_at(kb as f64 * h));
        let win = Window::new(run, &curve, machine, limiter, h, k_max, ka, kb);
        let end = kb as f64 * h;
        // The limit curve, lowered where the previous window's check found a violation (the part of
        // it this window plans again), never below the hardest braking from the committed speed.
        let mut cap = win.limit.clone();
        for (r, &x) in carry.iter().enumerate().take(cap.len().saturating_sub(1)) {
            cap[r] = cap[r].min(x);
        }
        let floor = win.braking(v0);
        // Lower the limit curve around every violation, over the stretch the filter mixes (the
        // committed part before the window cannot change), never below the braking floor.
        let ka_f = ka as f64 * h;
        let lower = |cap: &mut Vec<f64>, raw: &[f64], v: &[f64], ratios: &[[f64; 3]], protected: usize| {
            // The spans to lower and their factors, in order of the outputs: both ends of the spans
            // move forward with the output (the raw parameters grow).
            let mut spans: Vec<(usize, usize, f64)> = Vec::new();
            let mut last: Option<([f64; 3], f64)> = None;
            for (i, r) in ratios.iter().enumerate().skip(protected) {
                if r.iter().all(|&x| x <= 1.0) {
                    continue;
                }
                // The estimate repeats its ratios for the sample after each it computes.
                let factor = match last {
                    Some((lr, f)) if lr == *r => f,
                    _ => [1.0 / r[0], 1.0 / r[1].sqrt(), 1.0 / r[2].cbrt()].into_iter().fold(1.0f64, f64::min),
                };
                last = Some((*r, factor));
                if factor >= 1.0 {
                    continue;
                }
                // Output i averages inputs i + 1 - w ..= i: lower them, with half a window each side.
                let lo = raw[i.saturating_sub(w + w / 2).max(protected).min(raw.len() - 1)];
                let hi = raw[(i + w / 2).min(raw.len() - 1)];
                // floor and ceil of the grid positions (`as` truncates, and 0 is where both clamp).
                let (x_lo, x_hi) = ((lo - ka_f) / h, (hi - ka_f) / h);
                let (below, above) = (x_lo as usize, (x_hi as usize) + usize::from((x_hi as usize as f64) < x_hi));
                let a = below.max(1).min(cap.len() - 1);
                let b = above.max(1).min(cap.len() - 1);
                spans.push((a, b, factor));
            }
            // Each grid point is lowered to the smallest factor of the spans over it: a sliding
            // minimum, the spans entering in order of their starts and leaving in order of their ends.
            let mut open: std::collections::VecDeque<usize> = std::collections::VecDeque::new();
            let mut next = 0;
            let mut k = spans.first().map_or(usize::MAX, |s| s.0);
            while k < cap.len() && (next < spans.len() || !open.is_empty()) {
                while next < spans.len() && spans[next].0 <= k {
                    while open.back().is_some_and(|&j| spans[j].2 >= spans[next].2) {
                        open.pop_back();
                    }
                    open.push_back(next);
                    next += 1;
                }
                while open.front().is_some_and(|&j| spans[j].1 < k) {
                    open.pop_front();
                }
                match open.front() {
                    Some(&j) => {
                        cap[k] = cap[k].max(0.0).min(v[k].max(1e-12) * spans[j].2 * 0.97).max(floor[k]);
                        k += 1;
                    }
                    // A gap between spans: on to the next one's start.
                    None => k = spans.get(next).map_or(usize::MAX, |s| s.0),
                }
            }
        };
        let mut it = 0;
        let mut best: Option<(f64, Plan)> = None;
        // The previous iteration's filtered parameters and set-points: lowering the limit curve
        // leaves the plan before the first lowered speed as it was, and its set-points are not
        // evaluated again. They are the best plan's when that iteration made the best so far, else
        // kept here.
        let mut prev: Option<(Vec<f64>, Vec<Joints>)> = None;
        let mut first_len: Option<usize> = None;
        let mut estimating = true;
        let (raw, filtered, q, t, v, c, worst, cap) = loop {
            let v = win.speed_profile(&cap, v0);
            let (raw, t, c) = win.sample(&v, tau0, j0, config.period, kc, last);
            // Jerk filter: causal moving average over w samples, at rest at the window's end after it.
            prefix.clear();
            prefix.push(0.0);
            let mut sum = 0.0;
            for x in raw_hist.iter().chain(&raw).chain(std::iter::repeat_n(&end, w - 1)) {
                sum += x;
                prefix.push(sum);
            }
            let outputs = raw.len() + w - 1;
            let mut filtered: Vec<f64> = (0..outputs).map(|i| (prefix[i + w] - prefix[i]) / w as f64).collect();
            if last {
                if let Some(x) = filtered.last_mut() {
                    *x = end; // the run ends exactly at its end point
                }
            }
            // Set-points past what this window commits and checks (and the check's stencil reaches)
            // are the next window's: not evaluated.
            let needed = if last { outputs } else { outputs.min(c + w + 2) };
            let (prev_filtered, prev_q): (&[f64], &[Joints]) = match (&prev, &best) {
                (Some((f, q)), _) => (f, q),
                (None, Some((_, plan))) => (&plan.1, &plan.2),
                (None, None) => (&[], &[]),
            };
            let first_len = *first_len.get_or_insert(raw.len());
            let collapsing = raw.len() > 4 * first_len + 16;
            // The first w outputs of a window that continues committed motion average committed inputs:
            // lowering this window's limit curve cannot change them (and braking there would put a
            // step into the path acceleration where the windows meet).
            let protected = if ka > 0 { w.min(raw.len()) } else { 0 };
            // Outputs after the commit point (and past the filter's reach into the committed inputs)
            // are the next window's to plan, with more look-ahead: only what this window commits is checked.
            let checked = if last { outputs } else { (c + w).min(outputs) };
            // The first plans of a window are judged on the estimate, and lowered where it exceeds a
            // limit, until it exceeds none: their set-points are not evaluated. From then on each plan
            // is evaluated and checked.
            if estimating && !collapsing && it < config.max_iterations && !raw.is_empty() {
                win.estimate(&filtered[..needed], config.period, limiter, &mut all);
                if !within_limits(&all[protected.min(checked)..checked]) {
                    lower(&mut cap, &raw, &v, &all[..checked], protected);
                    it += 1;
                    continue;
                }
                estimating = false;
            }
            let same = filtered[..needed].iter().zip(prev_filtered).take_while(|(a, b)| a.to_bits() == b.to_bits()).count();
            let reused = same.min(prev_q.len().saturating_sub(q_hist.len()));
            let mut q: Vec<Joints> = Vec::with_capacity(q_hist.len() + needed);
            q.extend_from_slice(&q_hist);
            q.extend(prev_q.iter().skip(q_hist.len()).take(reused).copied());
            q.extend(filtered[reused..needed].iter().map(|&x| curve.joints(x, machine)));
            limit_ratios_into(&q, config.period, &limits, &mut all);
            let ratios = &all[q_hist.len()..];
            let keep = if last { outputs } else { c };
            let worst = ratios[..keep].iter().fold([0.0f64; 3], |m, r| [m[0].max(r[0]), m[1].max(r[1]), m[2].max(r[2])]);
            let ok = within_limits(&ratios[protected.min(checked)..checked]);
            // Keep the best plan so far. A violation the committed past causes cannot be lowered
            // away: once lowering has more than quadrupled the window's time, stop with the best.
            let score = worst_all(&ratios[protected.min(checked)..checked]);
            let done = ok || collapsing || it == config.max_iterations || raw.is_empty();
            // The limit curve this plan was made under, before it is lowered for the next.
            let used = best.as_ref().is_none_or(|b| score < b.0).then(|| cap.clone());
            if !done {
                lower(&mut cap, &raw, &v, &ratios[..checked], protected);
            }
            match used {
                Some(used) => {
                    best = Some((score, (raw, filtered, q, t, v, c, worst, used)));
                    prev = None;
                }
                None => prev = Some((filtered, q)),
            }
            if done {
                let (_, plan) = best.take().expect("a plan: the first iteration always sets one");
                break plan;
            }
            it += 1;
        };
        stats.iterations = stats.iterations.max(it);
        for k in 0..3 {
            stats.worst[k] = stats.worst[k].max(worst[k]);
        }
        // Commit only what the stop at the window's end has not yet shaped: the next window, reading
        // further, plans the same speeds up to there, so nothing changes where the two meet (at least an
        // eighth of the window, so that a look-ahead shorter than the braking distance still advances).
        let (kc, c, shaped) = if last {
            (kc, c, cap.len())
        } else {
            let mut free_cap = cap.clone();
            let n = free_cap.len();
            free_cap[n - 1] = free_cap[n - 2];
            let free = win.speed_profile_to(&free_cap, v0, false);
            let top = free.iter().fold(0.0f64, |m, &x| m.max(x));
            let bound = (1..n).find(|&r| v[r] < free[r] - 1e-9 * top).unwrap_or(n - 1);
            let kc = ka + (kc - ka).min(bound.saturating_sub(1).max((kb - ka) / 8).max(1));
            let t_end = t[kc - ka];
            (kc, raw.iter().enumerate().take_while(|(i, _)| (j0 + *i as u64) as f64 * config.period < t_end).count(), bound)
        };
        let new_q = &q[q_hist.len()..];
        let keep = if last { new_q.len() } else { c };
        let mut b = filtered.first().map_or(0, |&x| run.segment_at(x));
        for i in 0..keep {
            b = run.segment_at_from(b, filtered[i]);
            if !emit(new_q[i], run.first + b, run.segment(b)) {
                stats.stopped = true;
                return stats;
            }
            stats.samples += 1;
        }
        if last {
            break;
        }
        for &x in &raw[..c] {
            raw_hist.push_back(x);
            raw_hist.pop_front();
        }
        let tail: Vec<Joints> = q_hist.iter().chain(&new_q[..keep]).copied().collect();
        q_hist = tail[tail.len().saturating_sub(2)..].to_vec();
        let r = kc - ka;
        (v0, tau0, j0) = (v[r], t[r], j0 + c as u64);
        // Carry the lowered limit curve up to where the stop at this window's end began to shape the
        // speed (lowering after that answered the stop's own ramp, which the next window does not have).
        carry = cap[r..shaped.max(r)].to_vec();
        ka = kc;
    }
    stats
}

/// Plan the whole trajectory on `machine`, calling `emit` for each set-point in time order (planning
/// stops early if it returns false); returns what the check measured. Memory is bounded by the
/// look-ahead window.
pub fn plan_each(segments: &[Segment], machine: &Machine, config: &PlanConfig, mut emit: impl FnMut(PlannedSample) -> bool) -> Planned {
    plan_stream(segments.iter().cloned(), segments.iter().cloned(), machine, config, |p, _| emit(p))
}

/// Plan a stream of segments on `machine`, calling `emit` for each set-point in time order, with
/// the segment it lies on (planning stops early if it returns false). `scout` is the same segments
/// once more: it runs ahead to measure each run before it is planned (its length sets the run's
/// path grid), keeping what it reads for the planner up to a bound; `segments` is read only past
/// it (see `tee`). Memory is the look-ahead window and that bound, whatever the program's length.
pub fn plan_stream(
    segments: impl Iterator<Item = Segment>,
    scout: impl Iterator<Item = Segment>,
    machine: &Machine,
    config: &PlanConfig,
    mut emit: impl FnMut(PlannedSample, &Segment) -> bool,
) -> Planned {
    // The control smooths the tool axis of great-circle moves within a tolerance: the planner and its
    // scout see the same smoothed segments.
    // The program is read once for both while the scout's lead fits what it keeps (`tee`).
    let (scout, mut source) = super::tee::tee(
        super::orientation::OrientationSmoother::new(scout, machine),
        super::orientation::OrientationSmoother::new(segments, machine),
    );
    let limits = machine.limits();
    let limiter = FeedLimiter::new(&limits);
    // A moving average of width T turns a path acceleration bounded by +-b into a jerk bounded by
    // 2b/T: T = 2 a/j keeps the tangential term of every axis' jerk (q_s times s''') within its limit.
    let window = config
        .jerk_window
        .unwrap_or_else(|| limits.iter().map(|l| 2.0 * l.acceleration / l.jerk).fold(0.0, f64::max));
    let w = ((window / config.period).round() as usize).max(1);
    let mut max_ratio = [0.0f64; 3];
    let mut iterations = 0;
    let mut t0 = 0.0;
    let mut first = 0;
    for (ri, head) in RunScout::new(scout).enumerate() {
        let mut run = Run::new(head, first);
        first += run.count();
        if run.length() <= 0.0 {
            // A dwell: the axes stand where the last run stopped, for its time in whole periods.
            let n = (run.dwell() / config.period).round() as u64;
            if n > 0 {
                run.read_through(0, &mut source);
                let seg = run.segment(0).clone();
                let mut stopped = false;
                for j in 0..n {
                    if !emit(PlannedSample { t: t0 + j as f64 * config.period, segment: run.first, run: ri, q: seg.q0 }, &seg) {
                        stopped = true;
                        break;
                    }
                }
                t0 += n as f64 * config.period;
                if stopped {
                    break;
                }
            }
            run.skip_rest(&mut source);
            continue;
        }
        let mut j = 0u64;
        let stats = plan_run(&mut run, &mut source, machine, &limiter, config, w, &mut |q, segment, seg| {
            j += 1;
            emit(PlannedSample { t: t0 + (j - 1) as f64 * config.period, segment, run: ri, q }, seg)
        });
        for k in 0..3 {
            max_ratio[k] = max_ratio[k].max(stats.worst[k]);
        }
        iterations = iterations.max(stats.iterations);
        t0 += stats.samples as f64 * config.period;
        if stats.stopped {
            break;
        }
        run.skip_rest(&mut source);
    }
    Planned { max_ratio, iterations }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::planner::check::limit_ratios;

    /// A curve with its derivatives in closed form: per axis `a sin(s / l) + b s^2`, m or rad.
    const CURVE: [(f64, f64, f64); AXES] = [(0.02, 0.004, 0.5), (0.01, 0.0025, -0.3), (0.005, 0.006, 0.0), (0.3, 0.003, 0.0), (0.8, 0.002, 2.0)];

    fn curve(s: f64, d: usize) -> Joints {
        std::array::from_fn(|i| {
            let (a, l, b) = CURVE[i];
            let x = s / l;
            match d {
                0 => a * x.sin() + b * s * s,
                1 => a / l * x.cos() + 2.0 * b * s,
                2 => -a / (l * l) * x.sin() + 2.0 * b,
                _ => -a / (l * l * l) * x.cos(),
            }
        })
    }

    /// The estimate of the first plans measures what the check measures on the set-points' own
    /// kinematics: on a motion along a curve whose derivatives are known, with a path speed that
    /// swings, every ratio the estimate computes is within 1 % of the finite-difference check's (or
    /// within 0.001 of it where both are small). The curve turns hard (the C axis 0.8 rad over 2 mm),
    /// so that a derivative read at the nearest grid point alone would miss by several per cent.
    #[test]
    fn the_estimate_measures_what_the_check_measures() {
        let limits = crate::machine::Machine::hermle_c600u().limits();
        let (h, period) = (2e-5, 1e-3);
        let n_grid = 60_000;
        let deriv: Vec<[Joints; 3]> = (0..n_grid).map(|k| [curve(k as f64 * h, 1), curve(k as f64 * h, 2), curve(k as f64 * h, 3)]).collect();
        let win = Window { ka: 0, h, bounds: Vec::new(), limit: Vec::new(), deriv };
        // A path speed of 10-40 mm/s swinging at 2 Hz: the tangential terms matter as much as the
        // curve's.
        let s_at = |t: f64| 0.025 * t - 0.015 / (2.0 * std::f64::consts::PI * 2.0) * (2.0 * std::f64::consts::PI * 2.0 * t).sin();
        let f: Vec<f64> = (0..2000).map(|j| s_at(j as f64 * period)).collect();
        let q: Vec<Joints> = f.iter().map(|&s| curve(s, 0)).collect();
        let exact = limit_ratios(&q, period, &limits);
        let mut estimate = Vec::new();
        win.estimate(&f, period, &FeedLimiter::new(&limits), &mut estimate);
        assert_eq!(estimate.len(), exact.len());
        let mut largest = [0.0f64; 3];
        // Interior samples the estimate computes (every other one from the third).
        for i in (2..f.len() - 2).step_by(2) {
            for k in 0..3 {
                let (e, x) = (estimate[i][k], exact[i][k]);
                largest[k] = largest[k].max(x);
                assert!((e - x).abs() <= 0.01 * x.max(0.1), "sample {i}, ratio {k}: estimate {e}, check {x}");
            }
        }
        // The motion asks enough of the axes for the comparison to mean something.
        assert!(largest.iter().all(|&x| x > 0.3), "{largest:?}");
    }
}
