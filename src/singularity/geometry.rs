//! Geometric derivatives of the axes along the tool path, `q_s`, `q_ss`, `q_sss` (seed 002 eq. 2-4).
//!
//! Axes are linear per block, so their second derivative is zero inside a block and infinite at its
//! ends; a control smooths that within its path tolerance. As seed 002 does, we fit a cubic spline
//! (natural, per axis, in tool-tip path length) through the block end points of each run of feed
//! moves, and differentiate it: the same curve the simulator's planner follows. A run ends at a rapid, a rotary-only move, a change of TCPM, or a
//! corner sharper than [`CORNER_DEG`]: there a control stops anyway.

use crate::machine::AXES;
use crate::path::Trajectory;
use crate::machine::Machine;

/// Tool-direction change (degrees) above which a junction is a corner that ends a run (here and in the
/// simulator's planner, which follows the same curve).
pub const CORNER_DEG: f64 = 30.0;

/// A natural cubic spline `y(x)` through knots with increasing `x`.
#[derive(Debug, Clone, PartialEq)]
pub struct CubicSpline {
    x: Vec<f64>,
    y: Vec<f64>,
    m: Vec<f64>,
}

impl CubicSpline {
    /// Fit through `(x, y)`; knots closer than 1e-12 to the previous one are dropped.
    pub fn natural(xs: &[f64], ys: &[f64]) -> CubicSpline {
        let mut x = Vec::with_capacity(xs.len());
        let mut y = Vec::with_capacity(ys.len());
        for (&a, &b) in xs.iter().zip(ys) {
            if x.last().is_none_or(|&l: &f64| a - l > 1e-12) {
                x.push(a);
                y.push(b);
            }
        }
        let n = x.len();
        let mut m = vec![0.0; n];
        if n >= 3 {
            // Tridiagonal system for the interior second derivatives (Thomas algorithm).
            let mut c_prime = vec![0.0; n];
            let mut d_prime = vec![0.0; n];
            for i in 1..n - 1 {
                let h0 = x[i] - x[i - 1];
                let h1 = x[i + 1] - x[i];
                let a = h0 / 6.0;
                let b = (h0 + h1) / 3.0;
                let c = h1 / 6.0;
                let d = (y[i + 1] - y[i]) / h1 - (y[i] - y[i - 1]) / h0;
                let denom = b - a * c_prime[i - 1];
                c_prime[i] = c / denom;
                d_prime[i] = (d - a * d_prime[i - 1]) / denom;
            }
            for i in (1..n - 1).rev() {
                m[i] = d_prime[i] - c_prime[i] * m[i + 1];
            }
        }
        CubicSpline { x, y, m }
    }

    /// Value at `t` (the end values outside the knot range).
    pub fn value(&self, t: f64) -> f64 {
        let n = self.x.len();
        match n {
            0 => return 0.0,
            1 => return self.y[0],
            _ => {}
        }
        let i = self.x.partition_point(|&v| v <= t).saturating_sub(1).min(n - 2);
        let h = self.x[i + 1] - self.x[i];
        let t = t.clamp(self.x[i], self.x[i + 1]);
        let a = (self.x[i + 1] - t) / h;
        let b = (t - self.x[i]) / h;
        a * self.y[i] + b * self.y[i + 1] + ((a * a * a - a) * self.m[i] + (b * b * b - b) * self.m[i + 1]) * h * h / 6.0
    }

    /// First, second and third derivative at `t` (clamped to the knot range).
    pub fn derivatives(&self, t: f64) -> (f64, f64, f64) {
        let n = self.x.len();
        if n < 2 {
            return (0.0, 0.0, 0.0);
        }
        let i = match self.x.partition_point(|&v| v <= t) {
            0 => 0,
            k if k >= n => n - 2,
            k => k - 1,
        };
        let h = self.x[i + 1] - self.x[i];
        let t = t.clamp(self.x[i], self.x[i + 1]);
        let a = (self.x[i + 1] - t) / h;
        let b = (t - self.x[i]) / h;
        let (m0, m1) = (self.m[i], self.m[i + 1]);
        let d1 = (self.y[i + 1] - self.y[i]) / h - (3.0 * a * a - 1.0) / 6.0 * h * m0 + (3.0 * b * b - 1.0) / 6.0 * h * m1;
        let d2 = a * m0 + b * m1;
        let d3 = (m1 - m0) / h;
        (d1, d2, d3)
    }
}

/// Per-axis splines of every run of a trajectory.
#[derive(Debug, Clone)]
pub struct PathGeometry {
    runs: Vec<[CubicSpline; AXES]>,
    /// Run of each segment, if it belongs to one.
    run_of_segment: Vec<Option<usize>>,
}

impl PathGeometry {
    /// Build the runs of `traj`.
    pub fn new(traj: &Trajectory, _machine: &Machine) -> PathGeometry {
        let mut run_of_segment = vec![None; traj.segments.len()];
        let mut runs = Vec::new();
        let mut knots_s: Vec<f64> = Vec::new();
        let mut knots_q: Vec<[f64; AXES]> = Vec::new();
        let mut prev: Option<usize> = None;
        let flush = |s: &mut Vec<f64>, q: &mut Vec<[f64; AXES]>, runs: &mut Vec<[CubicSpline; AXES]>| {
            if !s.is_empty() {
                runs.push(std::array::from_fn(|i| CubicSpline::natural(s, &q.iter().map(|k| k[i]).collect::<Vec<_>>())));
                s.clear();
                q.clear();
            }
        };
        for (k, seg) in traj.segments.iter().enumerate() {
            if !(seg.is_path_move() && seg.length > 1e-9) {
                flush(&mut knots_s, &mut knots_q, &mut runs);
                prev = None;
                continue;
            }
            let joined = prev.is_some_and(|p| {
                let a = &traj.segments[p];
                let (d0, d1) = (a.tip1 - a.tip0, seg.tip1 - seg.tip0);
                a.kind == seg.kind && d0.angle(&d1) <= CORNER_DEG.to_radians()
            });
            if !joined {
                flush(&mut knots_s, &mut knots_q, &mut runs);
                knots_s.push(seg.s0);
                knots_q.push(seg.q0);
            }
            knots_s.push(seg.s0 + seg.length);
            knots_q.push(seg.q1);
            run_of_segment[k] = Some(runs.len());
            prev = Some(k);
        }
        flush(&mut knots_s, &mut knots_q, &mut runs);
        PathGeometry { runs, run_of_segment }
    }

    /// `(q_s, q_ss, q_sss)` at path length `s` of segment `segment`, if it lies in a run.
    pub fn derivatives(&self, segment: usize, s: f64) -> Option<([f64; AXES], [f64; AXES], [f64; AXES])> {
        let run = &self.runs[(*self.run_of_segment.get(segment)?)?];
        let mut out = ([0.0; AXES], [0.0; AXES], [0.0; AXES]);
        for (i, spline) in run.iter().enumerate() {
            let (d1, d2, d3) = spline.derivatives(s);
            out.0[i] = d1;
            out.1[i] = d2;
            out.2[i] = d3;
        }
        Some(out)
    }
}
