//! Path-speed profile of each run and the sampled set-points.

use super::geometry::{PathModel, Run};
use crate::kinematics::Joints;
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
    /// How often the profile may be replanned where a limit was exceeded.
    pub max_iterations: usize,
}

impl Default for PlanConfig {
    fn default() -> Self {
        PlanConfig { period: 1e-3, grid_m: 2e-5, grid_rad: 1e-4, jerk_window: None, max_iterations: 30 }
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

/// The planned set-points with what the check measured.
#[derive(Debug, Clone, PartialEq)]
pub struct Planned {
    pub samples: Vec<PlannedSample>,
    /// Largest |v|/v_max, |a|/a_max and |j|/j_max over all axes and samples (finite differences at
    /// the sample period), after the last iteration.
    pub max_ratio: [f64; 3],
    /// Replanning rounds the worst run needed.
    pub iterations: usize,
}

/// Largest ratios of finite-difference velocity, acceleration and jerk to the limits, per sample,
/// for a position sequence `q` at period `t` that is at rest before and after.
pub fn limit_ratios(q: &[Joints], t: f64, limits: &[AxisLimits; AXES]) -> Vec<[f64; 3]> {
    let n = q.len();
    let at = |k: isize| q[k.clamp(0, n as isize - 1) as usize];
    (0..n as isize)
        .map(|k| {
            let (m2, m1, p0, p1, p2) = (at(k - 2), at(k - 1), at(k), at(k + 1), at(k + 2));
            let mut r = [0.0f64; 3];
            for i in 0..AXES {
                let v = (p1[i] - m1[i]) / (2.0 * t);
                let a = (p1[i] - 2.0 * p0[i] + m1[i]) / (t * t);
                let j = (p2[i] - 2.0 * p1[i] + 2.0 * m1[i] - m2[i]) / (2.0 * t * t * t);
                r[0] = r[0].max(v.abs() / limits[i].velocity);
                r[1] = r[1].max(a.abs() / limits[i].acceleration);
                r[2] = r[2].max(j.abs() / limits[i].jerk);
            }
            r
        })
        .collect()
}

struct Grid {
    h: f64,
    q: Vec<Joints>,
    qs: Vec<Joints>,
    qss: Vec<Joints>,
    limit: Vec<f64>,
}

fn build_grid(run: &Run, machine: &Machine, limiter: &FeedLimiter, step: f64) -> Grid {
    let len = run.length();
    // A run linear in its parameter (rapid, rotary-only) has q_ss = q_sss = 0: a coarse grid is exact.
    let cap = if run.is_linear() { 2000 } else { 4_000_000 };
    let n = ((len / step).ceil() as usize).clamp(4, cap) + 1;
    let h = len / (n - 1) as f64;
    let q: Vec<Joints> = (0..n).map(|k| run.joints(k as f64 * h, machine)).collect();
    let at = |k: isize| q[k.clamp(0, n as isize - 1) as usize];
    let mut qs = vec![[0.0; AXES]; n];
    let mut qss = vec![[0.0; AXES]; n];
    let mut qsss = vec![[0.0; AXES]; n];
    for k in 0..n as isize {
        let (m2, m1, p0, p1, p2) = (at(k - 2), at(k - 1), at(k), at(k + 1), at(k + 2));
        let span = if k == 0 || k == n as isize - 1 { h } else { 2.0 * h };
        for i in 0..AXES {
            qs[k as usize][i] = (p1[i] - m1[i]) / span;
            qss[k as usize][i] = if k == 0 || k == n as isize - 1 { 0.0 } else { (p1[i] - 2.0 * p0[i] + m1[i]) / (h * h) };
            qsss[k as usize][i] = if k < 2 || k > n as isize - 3 { 0.0 } else { (p2[i] - 2.0 * p1[i] + 2.0 * m1[i] - m2[i]) / (2.0 * h * h * h) };
        }
    }
    let feed: Vec<f64> = (0..n).map(|k| run.feed[run.segment_at(k as f64 * h)]).collect();
    let mut limit: Vec<f64> = (0..n).map(|k| limiter.limit(feed[k], &qs[k], &qss[k], &qsss[k]).feed).collect();
    limit[0] = 0.0;
    limit[n - 1] = 0.0;
    Grid { h, q, qs, qss, limit }
}

/// Tangential acceleration bounds (min, max) at a grid point moving at path speed `v`.
fn accel_bounds(qs: &Joints, qss: &Joints, v: f64, limits: &[AxisLimits; AXES]) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::NEG_INFINITY, f64::INFINITY);
    for i in 0..AXES {
        if qs[i].abs() < 1e-12 {
            continue;
        }
        let c = qss[i] * v * v;
        let a = limits[i].acceleration;
        let (b1, b2) = ((a - c) / qs[i], (-a - c) / qs[i]);
        hi = hi.min(b1.max(b2));
        lo = lo.max(b1.min(b2));
    }
    (lo, hi)
}

/// Path speed over the grid: forward and backward acceleration passes under `cap`.
fn speed_profile(g: &Grid, cap: &[f64], limits: &[AxisLimits; AXES]) -> Vec<f64> {
    let n = g.q.len();
    let mut v = vec![0.0; n];
    for k in 0..n - 1 {
        let (_, hi) = accel_bounds(&g.qs[k], &g.qss[k], v[k], limits);
        let hi = if hi.is_finite() { hi } else { 1e12 };
        let v2 = v[k] * v[k] + 2.0 * hi * g.h;
        v[k + 1] = v2.max(0.0).sqrt().min(cap[k + 1]);
    }
    v[n - 1] = 0.0;
    for k in (0..n - 1).rev() {
        let (lo, _) = accel_bounds(&g.qs[k + 1], &g.qss[k + 1], v[k + 1], limits);
        let lo = if lo.is_finite() { lo } else { -1e12 };
        let v2 = v[k + 1] * v[k + 1] - 2.0 * lo * g.h;
        v[k] = v[k].min(v2.max(0.0).sqrt());
    }
    v
}

/// Sample a run: path parameter in time at `period`, then the jerk filter (moving average of `w`
/// samples, at rest before and after). Returns the filtered parameter per sample.
fn sample_parameter(g: &Grid, v: &[f64], period: f64, w: usize) -> Vec<f64> {
    let n = v.len();
    let mut t = vec![0.0; n];
    let v_floor = 1e-9;
    for k in 0..n - 1 {
        t[k + 1] = t[k] + 2.0 * g.h / (v[k] + v[k + 1]).max(v_floor);
    }
    let total = t[n - 1];
    let m = (total / period).ceil() as usize + 1;
    let mut s = Vec::with_capacity(m);
    let mut k = 0;
    for j in 0..m {
        let tj = (j as f64 * period).min(total);
        while k + 1 < n - 1 && t[k + 1] < tj {
            k += 1;
        }
        // Exact within the step under the profile's model: constant path acceleration.
        let tau = (tj - t[k]).clamp(0.0, t[k + 1] - t[k]);
        let acc = (v[k + 1] * v[k + 1] - v[k] * v[k]) / (2.0 * g.h);
        let ds = (v[k] * tau + 0.5 * acc * tau * tau).clamp(0.0, g.h);
        s.push(k as f64 * g.h + ds);
    }
    let end = (n - 1) as f64 * g.h;
    if w <= 1 {
        return s;
    }
    // Causal moving average over `w` samples, the run at rest (0) before and (end) after.
    let len = s.len() + w - 1;
    let get = |i: isize| if i < 0 { 0.0 } else if (i as usize) < s.len() { s[i as usize] } else { end };
    let mut out = Vec::with_capacity(len);
    let mut acc: f64 = (0..w as isize).map(|i| get(i - w as isize + 1)).sum();
    for j in 0..len as isize {
        out.push(acc / w as f64);
        acc += get(j + 1) - get(j + 1 - w as isize);
    }
    // Remove accumulated rounding at the very end: the run ends exactly at its end point.
    if let Some(last) = out.last_mut() {
        *last = end;
    }
    out
}

/// Plan the whole trajectory on `machine`.
pub fn plan(segments: &[Segment], machine: &Machine, config: &PlanConfig) -> Planned {
    let model = PathModel::new(segments);
    let limits = machine.limits();
    let limiter = FeedLimiter::new(&limits);
    // A moving average of width T turns a path acceleration bounded by +-b into a jerk bounded by
    // 2b/T: T = 2 a/j keeps the tangential term of every axis' jerk (q_s times s''') within its limit.
    let window = config
        .jerk_window
        .unwrap_or_else(|| limits.iter().map(|l| 2.0 * l.acceleration / l.jerk).fold(0.0, f64::max));
    let w = ((window / config.period).round() as usize).max(1);
    let mut samples = Vec::new();
    let mut max_ratio = [0.0f64; 3];
    let mut iterations = 0;
    let mut t0 = 0.0;
    for (ri, run) in model.runs.iter().enumerate() {
        if run.length() <= 0.0 {
            continue;
        }
        let rotary_only = run.feed.iter().all(|f| f.is_finite()) && is_rotary_param(run, segments);
        let step = if rotary_only { config.grid_rad } else { config.grid_m };
        let g = build_grid(run, machine, &limiter, step);
        let mut cap = g.limit.clone();
        let mut best: Option<(Vec<f64>, Vec<Joints>, [f64; 3])> = None;
        for it in 0..=config.max_iterations {
            let v = speed_profile(&g, &cap, &limits);
            let s = sample_parameter(&g, &v, config.period, w);
            let q: Vec<Joints> = s.iter().map(|&x| run.joints(x, machine)).collect();
            let ratios = limit_ratios(&q, config.period, &limits);
            let worst = ratios.iter().fold([0.0f64; 3], |m, r| [m[0].max(r[0]), m[1].max(r[1]), m[2].max(r[2])]);
            let ok = worst.iter().all(|&r| r <= 1.0);
            best = Some((s.clone(), q, worst));
            iterations = iterations.max(it);
            if ok || it == config.max_iterations {
                break;
            }
            // Lower the limit curve around every violation, over the stretch the filter mixes.
            for (j, r) in ratios.iter().enumerate() {
                let factor = [1.0 / r[0], 1.0 / r[1].sqrt(), 1.0 / r[2].cbrt()].into_iter().fold(1.0f64, f64::min);
                if factor >= 1.0 {
                    continue;
                }
                let lo = s[j.saturating_sub(w)];
                let hi = s[(j + w).min(s.len() - 1)];
                let (ka, kb) = ((lo / g.h).floor() as usize, ((hi / g.h).ceil() as usize).min(cap.len() - 1));
                for k in ka..=kb {
                    let cur = if cap[k] > 0.0 { cap[k] } else { 0.0 };
                    let current_speed = v[k].max(1e-12);
                    cap[k] = cur.min(current_speed * factor * 0.97);
                }
            }
        }
        let (s, q, worst) = best.expect("at least one iteration");
        for k in 0..3 {
            max_ratio[k] = max_ratio[k].max(worst[k]);
        }
        for (j, (&x, qj)) in s.iter().zip(q).enumerate() {
            samples.push(PlannedSample {
                t: t0 + j as f64 * config.period,
                segment: run.segments[run.segment_at(x)],
                run: ri,
                q: qj,
            });
        }
        t0 += s.len() as f64 * config.period;
    }
    Planned { samples, max_ratio, iterations }
}

fn is_rotary_param(run: &Run, segments: &[Segment]) -> bool {
    run.segments.iter().all(|&k| {
        let s = &segments[k];
        (0..3).all(|i| (s.q1[i] - s.q0[i]).abs() <= 1e-12) && s.length <= 1e-12
    })
}
