//! Geometric derivatives of the axes along the tool path, `q_s`, `q_ss`, `q_sss` (seed 002 eq. 2-4).
//!
//! Axes are linear per block, so their second derivative is zero inside a block and infinite at its
//! ends; a control smooths that within its path tolerance. As seed 002 does, we fit a cubic spline
//! (natural, per axis, in tool-tip path length) through the block end points of each run of feed
//! moves, and differentiate it: the same curve the simulator's planner follows. A run ends at a rapid, a rotary-only move, a change of TCPM, or a
//! corner sharper than [`CORNER_DEG`]: there a control stops anyway.

use crate::machine::AXES;
use crate::path::{Segment, SegmentWindow};

/// Tool-direction change (degrees) above which a junction is a corner that ends a run (here and in the
/// simulator's planner, which follows the same curve).
pub const CORNER_DEG: f64 = 30.0;

/// A natural cubic spline `y(x)` through knots with increasing `x`: a [`SplineSet`] of one.
#[derive(Debug, Clone, PartialEq)]
pub struct CubicSpline(SplineSet<1>);

/// The second derivatives at the knots of the natural cubic spline through `(x, y)` (`x`
/// increasing): the tridiagonal system of the interior ones by the Thomas algorithm, zero at the ends.
fn second_derivatives(x: &[f64], y: &[f64]) -> Vec<f64> {
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
    m
}

/// A point on a knot interval of a [`SplineSet`]: the interval and the weights of its knots'
/// values and second derivatives.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SplineBasis {
    i: usize,
    a: f64,
    b: f64,
    a3: f64,
    b3: f64,
    h: f64,
}

impl CubicSpline {
    /// Fit through `(x, y)`; knots closer than 1e-12 to the previous one are dropped.
    pub fn natural(xs: &[f64], ys: &[f64]) -> CubicSpline {
        let ys: Vec<[f64; 1]> = ys.iter().map(|&y| [y]).collect();
        CubicSpline(SplineSet::natural(xs, &ys))
    }

    /// Value at `t` (the end values outside the knot range).
    pub fn value(&self, t: f64) -> f64 {
        self.value_on(self.interval(t, 0), t)
    }

    /// The knots `x`, increasing.
    pub fn knots(&self) -> &[f64] {
        &self.0.x
    }

    /// The knot interval [`CubicSpline::value`] evaluates `t` on ([`SplineSet::interval`]).
    pub fn interval(&self, t: f64, hint: usize) -> usize {
        self.0.interval(t, hint)
    }

    /// Value at `t` on knot interval `i` ([`CubicSpline::interval`]).
    pub fn value_on(&self, i: usize, t: f64) -> f64 {
        self.value_at(&self.basis(i, t))
    }

    /// The weights of the knot values at `t` on knot interval `i` ([`SplineSet::basis`]).
    pub fn basis(&self, i: usize, t: f64) -> SplineBasis {
        self.0.basis(i, t)
    }

    /// Value at the point `w` was made for ([`CubicSpline::basis`] of this spline or of one through
    /// the same knots).
    pub fn value_at(&self, w: &SplineBasis) -> f64 {
        self.0.values_at(w)[0]
    }

    /// First, second and third derivative at `t` (clamped to the knot range).
    pub fn derivatives(&self, t: f64) -> (f64, f64, f64) {
        self.derivatives_on(self.interval(t, 0), t)
    }

    /// [`CubicSpline::derivatives`] on knot interval `i` ([`CubicSpline::interval`]).
    pub fn derivatives_on(&self, i: usize, t: f64) -> (f64, f64, f64) {
        let (d1, d2, d3) = self.0.derivatives_on(i, t);
        (d1[0], d2[0], d3[0])
    }
}

/// `N` natural cubic splines through the same knots, as the planner's curve and the analysis fit
/// the axes of one stretch of path: one knot search and one basis serve them all, and each knot's
/// values and second derivatives lie together. Component `c` is the [`CubicSpline`] through the
/// `c`-th values, to the bit.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SplineSet<const N: usize> {
    /// The knots, increasing.
    x: Vec<f64>,
    /// Per knot, each component's value and second derivative.
    ym: Vec<[[f64; 2]; N]>,
}

impl<const N: usize> SplineSet<N> {
    /// Fit component `c` through `(xs[k], ys[k][c])`; knots closer than 1e-12 to the previous one
    /// are dropped (from every component).
    pub fn natural(xs: &[f64], ys: &[[f64; N]]) -> SplineSet<N> {
        let mut x = Vec::with_capacity(xs.len());
        let mut kept: Vec<[f64; N]> = Vec::with_capacity(ys.len());
        for (&a, b) in xs.iter().zip(ys) {
            if x.last().is_none_or(|&l: &f64| a - l > 1e-12) {
                x.push(a);
                kept.push(*b);
            }
        }
        let mut ym = vec![[[0.0; 2]; N]; x.len()];
        let mut y = Vec::with_capacity(x.len());
        for c in 0..N {
            y.clear();
            y.extend(kept.iter().map(|v| v[c]));
            let m = second_derivatives(&x, &y);
            for (k, e) in ym.iter_mut().enumerate() {
                e[c] = [y[k], m[k]];
            }
        }
        SplineSet { x, ym }
    }

    /// The knot interval of `t` (0 with fewer than two knots). `hint` is a guess (the interval of
    /// the previous, nearby `t`): checked first, then the next one, then by bisection, so that
    /// evaluating along increasing `t` costs O(1) per value.
    #[inline]
    pub fn interval(&self, t: f64, hint: usize) -> usize {
        let n = self.x.len();
        if n < 2 {
            return 0;
        }
        // Interval i holds t when partition_point(x <= t) - 1, clamped to 0..=n-2, is i.
        let holds = |i: usize| (i == 0 || self.x[i] <= t) && (i == n - 2 || t < self.x[i + 1]);
        if hint <= n - 2 && holds(hint) {
            return hint;
        }
        if hint < n - 2 && holds(hint + 1) {
            return hint + 1;
        }
        self.x.partition_point(|&v| v <= t).saturating_sub(1).min(n - 2)
    }

    /// The weights of the knot values at `t` on knot interval `i`: they depend on the knots only, so
    /// every component (and splines through the same knots) share them.
    #[inline]
    pub fn basis(&self, i: usize, t: f64) -> SplineBasis {
        if self.x.len() < 2 {
            return SplineBasis { i: 0, a: 0.0, b: 0.0, a3: 0.0, b3: 0.0, h: 0.0 };
        }
        let h = self.x[i + 1] - self.x[i];
        let t = t.clamp(self.x[i], self.x[i + 1]);
        let a = (self.x[i + 1] - t) / h;
        let b = (t - self.x[i]) / h;
        SplineBasis { i, a, b, a3: a * a * a - a, b3: b * b * b - b, h }
    }

    /// Every component's value at the point `w` was made for ([`SplineSet::basis`]; the end values
    /// outside the knot range).
    #[inline(always)]
    pub fn values_at(&self, w: &SplineBasis) -> [f64; N] {
        let mut out = [0.0; N];
        match self.ym.len() {
            0 => return out,
            1 => {
                for (o, e) in out.iter_mut().zip(&self.ym[0]) {
                    *o = e[0];
                }
                return out;
            }
            _ => {}
        }
        let (i, h) = (w.i, w.h);
        let (k0, k1) = (&self.ym[i], &self.ym[i + 1]);
        for c in 0..N {
            out[c] = w.a * k0[c][0] + w.b * k1[c][0] + (w.a3 * k0[c][1] + w.b3 * k1[c][1]) * h * h / 6.0;
        }
        out
    }

    /// Every component's first, second and third derivative at `t` on interval `i` (clamped to
    /// the knot range; zero with fewer than two knots).
    pub fn derivatives_on(&self, i: usize, t: f64) -> ([f64; N], [f64; N], [f64; N]) {
        let mut out = ([0.0; N], [0.0; N], [0.0; N]);
        if self.ym.len() < 2 {
            return out;
        }
        let SplineBasis { a, b, h, .. } = self.basis(i, t);
        let (k0, k1) = (&self.ym[i], &self.ym[i + 1]);
        for c in 0..N {
            let (m0, m1) = (k0[c][1], k1[c][1]);
            out.0[c] = (k1[c][0] - k0[c][0]) / h - (3.0 * a * a - 1.0) / 6.0 * h * m0 + (3.0 * b * b - 1.0) / 6.0 * h * m1;
            out.1[c] = a * m0 + b * m1;
            out.2[c] = (m1 - m0) / h;
        }
        out
    }
}

/// Blocks before a window's first evaluated segment that its splines are also fitted through (here
/// and in the planner's look-ahead windows). A natural spline's response to a knot decays by about
/// 2 - sqrt(3) = 0.27 per knot, so over 32 blocks two windows' curves agree to ~1e-18 of the path's
/// curvature where they meet: the windowed fit is the whole run's, and memory holds the window.
pub const SPLINE_OVERLAP_BLOCKS: usize = 32;

/// Most block end points in a row that are not knots: a chord is checked against all of them.
pub const MAX_SKIPPED_POINTS: usize = 64;

/// Chooses a run's spline knots among its block start points, in path order, as a control's
/// compressor joins short blocks within its tolerance (the TNC smooths contour points whose chord
/// error is within cycle 32's `T`: TNC 620 Cycle Programming, 340 56x-03, §12.5). On the points of what the control
/// interpolates ([`crate::path::Segment::interpolated`]), a point is skipped if it, and every point
/// skipped since the last knot, lies within the segment's contour tolerance
/// ([`crate::machine::ContourTolerance`]: tool tip or linear axes, and rotaries; the program's cycle 32,
/// else the machine's) of the chord from that knot to the next point, linear in the path
/// parameter. A block a CAM system cut into pieces along one axis-linear line then has the knots of
/// the block: an interpolating spline through every piece end would bend each corner between blocks
/// within one piece, and ask the axes for an acceleration the piece length divides (seed 002 eq. 5).
/// Each decision needs the points since the last knot only, so every window of a run sees the same
/// knots. The knots are kept from [`SPLINE_OVERLAP_BLOCKS`] before the first block a fit serves: the
/// planner's windows and [`PathGeometry`] both fit through [`Knots::for_fit`].
#[derive(Debug, Clone, Default)]
pub struct Knots {
    /// The last knot and the points skipped since, on what the control interpolates.
    anchor: Option<(f64, [f64; AXES])>,
    skipped: Vec<(f64, [f64; AXES])>,
    /// The knots decided: segment index, path parameter and the value splined there.
    knots: std::collections::VecDeque<(usize, f64, [f64; AXES])>,
}

impl Knots {
    /// Offer the start of segment `j` of a run, in path order: parameter `x0` (its end `x1`), and
    /// `value`, the splined axes there. It is a knot if it is the run's first or its point
    /// ([`Segment::interpolated`]) is not skipped.
    pub fn offer(&mut self, j: usize, (x0, x1): (f64, f64), seg: &Segment, value: [f64; AXES]) {
        if self.is_knot(x0, seg.interpolated(false), (x1, seg.interpolated(true)), seg.tolerance) {
            self.knots.push_back((j, x0, value));
        }
    }

    /// The knots a fit through segments `first..=last` uses: [`SPLINE_OVERLAP_BLOCKS`] before the knot
    /// at or before `first`'s start, through the last at or before `last`'s (the fit adds `last`'s end).
    pub fn for_fit(&self, first: usize, last: usize) -> impl Iterator<Item = &(usize, f64, [f64; AXES])> {
        let from = self.knots.partition_point(|k| k.0 <= first).saturating_sub(SPLINE_OVERLAP_BLOCKS + 1);
        self.knots.range(from..self.knots.partition_point(|k| k.0 <= last))
    }

    /// Drop the knots no fit from segment `first` on reaches ([`Knots::for_fit`]).
    pub fn release_before(&mut self, first: usize) {
        while self.knots.len() > SPLINE_OVERLAP_BLOCKS + 1 && self.knots[SPLINE_OVERLAP_BLOCKS + 1].0 <= first {
            self.knots.pop_front();
        }
    }

    /// Knots decided after segment `k`'s start.
    pub fn after(&self, k: usize) -> usize {
        self.knots.len() - self.knots.partition_point(|x| x.0 <= k)
    }

    /// The segment of the knot [`SPLINE_OVERLAP_BLOCKS`] before the last at or before segment
    /// `last`'s start (0 if there are fewer).
    pub fn overlap_start(&self, last: usize) -> usize {
        self.knots.partition_point(|k| k.0 <= last).checked_sub(SPLINE_OVERLAP_BLOCKS + 1).map_or(0, |i| self.knots[i].0)
    }

    /// Whether the point `(x, y)`, followed on the path by `next`, is a knot (the first point of a
    /// run is one).
    fn is_knot(&mut self, x: f64, y: [f64; AXES], next: (f64, [f64; AXES]), tolerance: crate::machine::ContourTolerance) -> bool {
        let Some(anchor) = self.anchor else {
            self.anchor = Some((x, y));
            return true;
        };
        let on_chord = |p: &(f64, [f64; AXES])| -> bool {
            let span = next.0 - anchor.0;
            if span <= 1e-12 {
                return false;
            }
            let u = (p.0 - anchor.0) / span;
            (0..AXES).all(|i| {
                let tol = if i < 3 { tolerance.linear_m } else { tolerance.rotary_rad };
                (anchor.1[i] + (next.1[i] - anchor.1[i]) * u - p.1[i]).abs() <= tol
            })
        };
        if self.skipped.len() < MAX_SKIPPED_POINTS && on_chord(&(x, y)) && self.skipped.iter().all(on_chord) {
            self.skipped.push((x, y));
            false
        } else {
            self.anchor = Some((x, y));
            self.skipped.clear();
            true
        }
    }
}

/// Knots a geometry window reaches ahead of the segment it is fitted for.
const AHEAD_KNOTS: usize = 256;

/// True if a segment belongs to a run of the spline geometry: a path move that moves.
fn in_run(seg: &Segment) -> bool {
    seg.is_path_move() && seg.length > 1e-9
}

/// True if segment `b` continues the run of segment `a` just before it: the same kind of move, its
/// direction turned by at most [`CORNER_DEG`], and no exact stop between them.
fn joined(a: &Segment, b: &Segment) -> bool {
    let turn = (a.tip1 - a.tip0).angle(&(b.tip1 - b.tip0));
    in_run(a) && in_run(b) && a.kind == b.kind && turn <= CORNER_DEG.to_radians() && !a.stops_before(b, turn)
}

/// The per-axis spline geometry of the runs of a segment stream, fitted window by window as the
/// samples reach them: each window is fitted through the knots ([`Knots`], as the planner's)
/// [`SPLINE_OVERLAP_BLOCKS`] behind and up to 256 ahead, cut at the run's ends, and used up to the
/// overlap before its far end.
#[derive(Debug, Clone, Default)]
pub struct PathGeometry {
    /// Segments the current fit serves, and its splines (which share their knots).
    fit: Option<(std::ops::Range<usize>, SplineSet<AXES>)>,
    /// The knot interval of the last evaluation: samples come in path order.
    hint: usize,
    /// The next segment whose start point is to be decided a knot or not, and the current run's
    /// knots (splined on the machine axes, in tool-tip length).
    decided: usize,
    knots: Knots,
}

impl PathGeometry {
    pub fn new() -> PathGeometry {
        PathGeometry::default()
    }

    /// `(q_s, q_ss, q_sss)` at path length `s` of segment `segment`, if it lies in a run. The window
    /// must hold the segments from [`SPLINE_OVERLAP_BLOCKS`] before `segment` on.
    pub fn derivatives<I: Iterator<Item = Segment>>(&mut self, segment: usize, s: f64, window: &mut SegmentWindow<I>) -> Option<([f64; AXES], [f64; AXES], [f64; AXES])> {
        if !in_run(window.get(segment)?) {
            return None;
        }
        if !self.fit.as_ref().is_some_and(|(r, _)| r.contains(&segment)) {
            self.fit = Some(self.fit(segment, window));
            self.hint = 0;
        }
        let (_, splines) = self.fit.as_ref()?;
        let k = splines.interval(s, self.hint);
        self.hint = k;
        Some(splines.derivatives_on(k, s))
    }

    /// Decide whether segment `j`'s start is a knot (thinned on what the control interpolates, the
    /// knot on the machine axes): the first of a run (or of the held segments, if the decisions do
    /// not reach it) is.
    fn decide<I: Iterator<Item = Segment>>(&mut self, j: usize, window: &SegmentWindow<I>) {
        let seg = window.loaded(j).expect("the window holds the segment decided");
        let continues = j > 0 && self.decided == j && window.loaded(j - 1).is_some_and(|a| joined(a, seg));
        if !continues {
            self.knots = Knots::default();
        }
        self.knots.offer(j, (seg.s0, seg.s0 + seg.length), seg, seg.q0);
        self.decided = j + 1;
    }

    /// Fit the window for segment `k` (which is in a run).
    fn fit<I: Iterator<Item = Segment>>(&mut self, k: usize, window: &mut SegmentWindow<I>) -> (std::ops::Range<usize>, SplineSet<AXES>) {
        let mut lo = k;
        while lo + SPLINE_OVERLAP_BLOCKS > k && lo > 0 && matches!((window.loaded(lo - 1), window.loaded(lo)), (Some(a), Some(b)) if joined(a, b)) {
            lo -= 1;
        }
        // The decisions go on from the last one if it is in k's run and held, else from `lo`.
        let start = if self.decided > k { k + 1 } else { self.decided.max(lo) };
        for j in start..=k {
            self.decide(j, window);
        }
        let mut hi = k;
        let mut run_end = true;
        while window.get(hi + 1).is_some() && matches!((window.loaded(hi), window.loaded(hi + 1)), (Some(a), Some(b)) if joined(a, b)) {
            if self.knots.after(k) >= AHEAD_KNOTS {
                run_end = false;
                break;
            }
            hi += 1;
            if hi >= self.decided {
                self.decide(hi, window);
            }
        }
        let valid_end = if run_end { hi + 1 } else { self.knots.overlap_start(hi).max(k + 1) };
        self.knots.release_before(k);
        let last = window.loaded(hi).expect("the window holds the fit's segments");
        let (mut xs, mut qs): (Vec<f64>, Vec<[f64; AXES]>) = self.knots.for_fit(k, hi).map(|&(_, x, q)| (x, q)).unzip();
        xs.push(last.s0 + last.length);
        qs.push(last.q1);
        (k..valid_end, SplineSet::natural(&xs, &qs))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each component of a [`SplineSet`] is the [`CubicSpline`] (a set of one) through its values,
    /// to the bit: the interleaved components do not mix. Values and derivatives, with knots closer
    /// than 1e-12 dropped, and with 0, 1 and 2 knots.
    #[test]
    fn a_set_is_its_splines_to_the_bit() {
        for n in [0usize, 1, 2, 3, 7, 60] {
            let mut xs: Vec<f64> = (0..n).map(|k| k as f64 * 1e-3 + (k as f64 * 0.7).sin() * 2e-4).collect();
            if n > 4 {
                xs[3] = xs[2] + 1e-13; // dropped
            }
            let ys: Vec<[f64; 3]> = (0..n).map(|k| [(k as f64).cos(), 1e-3 * k as f64 * k as f64, -(k as f64 * 0.3).exp()]).collect();
            let set = SplineSet::natural(&xs, &ys);
            let one: Vec<CubicSpline> = (0..3).map(|c| CubicSpline::natural(&xs, &ys.iter().map(|y| y[c]).collect::<Vec<_>>())).collect();
            let end = xs.last().copied().unwrap_or(0.0);
            let mut hint = 0;
            for j in 0..=200 {
                let t = -1e-4 + (end + 2e-4) * j as f64 / 200.0;
                let i = set.interval(t, hint);
                hint = i;
                assert_eq!(i, one[0].interval(t, 0));
                let v = set.values_at(&set.basis(i, t));
                let (d1, d2, d3) = set.derivatives_on(i, t);
                for c in 0..3 {
                    assert_eq!(v[c].to_bits(), one[c].value(t).to_bits(), "n {n} t {t} c {c}");
                    let d = if n < 2 { (0.0, 0.0, 0.0) } else { one[c].derivatives_on(i, t) };
                    assert_eq!([d1[c], d2[c], d3[c]].map(f64::to_bits), [d.0, d.1, d.2].map(f64::to_bits), "n {n} t {t} c {c}");
                }
            }
        }
    }
}
