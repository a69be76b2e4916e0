//! C-axis smoothing through the singularity (seed 002): where a cut passes close to (or through) the
//! singular direction, the secondary axis swings (a near miss) or jumps by 180 deg (a crossing, seed
//! 002 Table 1). Seed 002 lets the tool axis go *through* the singular point instead, where C is free:
//!
//! 1. detect the passages: steps where C would need more than its speed limit at the programmed feed
//!    (or where A changes sign near zero), around the point closest to the singular direction, s*;
//! 2. after s*, switch to the other solution of seed 002 Table 1, (A, C) -> (-A, C + 180 deg): the same
//!    tool axes, but now the C values before and after s* join up and A passes through 0;
//! 3. fit cubic splines to C (and A) before and after s* (Curve_b, Curve_a) and connect them over a
//!    window [s_b, s_a] by a curve that matches position, slope, curvature and third derivative of both
//!    at the connection (C3, as the paper requires for jerk continuity) and passes the singular point:
//!    A(s*) = 0. We use the lowest-degree polynomials that do this (degree 7 for C, 8 for A) where the
//!    paper uses a cubic B-spline with C3 enforced at the connection points;
//! 4. widen the window one program point at a time on both sides, as the paper's algorithm does, until
//!    seed 002 eq. (2)-(4) hold along the connection at the programmed feed (tangential acceleration and
//!    jerk neglected, as for eq. 5): F |q_s| <= v_max, F^2 |q_ss| <= a_max, F^3 |q_sss| <= j_max;
//! 5. re-discretise: every original point gets the new A/C (linear interpolation between them stays
//!    within the limits because the points are the paper's G1 points), and its tool tip moves so that
//!    the ball centre stays where it was: tip' = tip + R (axis - axis'). Valid for ball-end tools only.

use super::AvoidError;
use crate::machine::Machine;
use crate::path::Trajectory;
use crate::program::{Program, Targets};
use crate::singularity::CubicSpline;
use nalgebra::{DMatrix, DVector, Vector3};
use std::f64::consts::PI;

/// The cutter, as far as smoothing cares: only a ball end keeps its contact when tilted about its centre.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Tool {
    /// Ball-end mill of this radius, m.
    Ball(f64),
    /// Flat-end mill of this radius, m.
    Flat(f64),
    /// Bull-nose (torus) mill: radius and corner radius, m.
    Bull(f64, f64),
}

impl std::str::FromStr for Tool {
    type Err = String;
    /// `ball:R`, `flat:R` or `bull:R:r`, radii in mm.
    fn from_str(s: &str) -> Result<Tool, String> {
        let parts: Vec<&str> = s.split(':').collect();
        let mm = |t: &str| -> Result<f64, String> {
            match t.trim().parse::<f64>() {
                Ok(v) if v.is_finite() && v > 0.0 => Ok(v * 1e-3),
                _ => Err(format!("'{t}' is not a positive radius in mm")),
            }
        };
        match parts.as_slice() {
            ["ball", r] => Ok(Tool::Ball(mm(r)?)),
            ["flat", r] => Ok(Tool::Flat(mm(r)?)),
            ["bull", r, c] => Ok(Tool::Bull(mm(r)?, mm(c)?)),
            _ => Err(format!("expected ball:R_MM, flat:R_MM or bull:R_MM:r_MM, got '{s}'")),
        }
    }
}

/// One smoothed passage.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Passage {
    /// The point closest to the singular direction (where the new path passes through it): x, block.
    pub x_singular_mm: f64,
    pub block_number: Option<u64>,
    /// Original closest approach, degrees.
    pub original_distance_deg: f64,
    /// The connection window along the path and in x, mm.
    pub window_length_mm: f64,
    pub x_start_mm: f64,
    pub x_end_mm: f64,
    /// Program points given new A/C in the window, and after it (the other solution branch).
    pub points_changed: usize,
    /// Largest F|C_s|/v, F^2|C_ss|/a, F^3|C_sss|/j of the connection (<= 1).
    pub c_limit_ratio: [f64; 3],
    /// Largest tool-axis change, degrees.
    pub max_orientation_deviation_deg: f64,
}

/// The outcome of smoothing a program.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Smoothing {
    pub passages: Vec<Passage>,
    pub max_orientation_deviation_deg: f64,
    /// Largest distance between the ball centres of the original and the new program, m.
    pub max_ball_centre_error_m: f64,
}

/// A program point of a five-axis cut: its block, path length, tip (workpiece), A and C (rad), feed.
#[derive(Debug, Clone, Copy)]
struct Point {
    block: usize,
    number: Option<u64>,
    s: f64,
    tip: Vector3<f64>,
    a: f64,
    c: f64,
    feed: f64,
}

/// Smooth every singular passage of `program` for a ball-end `tool`. Refuses other tools, programs
/// without TCPM cuts, and passages it cannot connect within the cut or the machine's A range.
pub fn smooth(program: &Program, machine: &Machine, tool: Tool, options: &crate::job::JobOptions) -> Result<(Program, Smoothing), AvoidError> {
    let radius = match tool {
        Tool::Ball(r) => r,
        Tool::Flat(_) | Tool::Bull(..) => {
            return Err(AvoidError::Refused(
                "smoothing changes the tool axis near the singularity; only a ball-end tool keeps its contact with the surface when it tilts about its centre (seed 002). A flat-end or bull-nose tool would gouge or leave the surface: use reorientation instead".into(),
            ))
        }
    };
    let (pi, si) = (machine.primary_axis(), machine.secondary_axis());
    let (alim, clim) = (machine.axes[pi].limits, machine.axes[si].limits);
    let traj = Trajectory::from_program(program, machine, &options.path);
    if let Some(d) = traj.diagnostics.iter().find(|d| d.severity == crate::program::Severity::Error) {
        return Err(AvoidError::Refused(format!("line {}: {}", d.line, d.message)));
    }
    // The cuts: maximal runs of consecutive TCPM feed segments, as program points.
    let mut cuts: Vec<Vec<Point>> = Vec::new();
    let mut cur: Vec<Point> = Vec::new();
    for seg in &traj.segments {
        let tcp = program.blocks.get(seg.block).is_some_and(|b| b.tcp);
        if !(tcp && seg.is_path_move() && seg.feed > 0.0) {
            if cur.len() > 1 {
                cuts.push(std::mem::take(&mut cur));
            }
            cur.clear();
            continue;
        }
        if cur.is_empty() {
            cur.push(Point { block: usize::MAX, number: None, s: seg.s0, tip: seg.tip0, a: seg.q0[pi], c: seg.q0[si], feed: seg.feed });
        }
        cur.push(Point { block: seg.block, number: seg.number, s: seg.s0 + seg.length, tip: seg.tip1, a: seg.q1[pi], c: seg.q1[si], feed: seg.feed });
    }
    if cur.len() > 1 {
        cuts.push(cur);
    }
    if cuts.is_empty() {
        return Err(AvoidError::Refused("no five-axis cut under TCPM (M128 / G43.4, or CL data): nothing to smooth".into()));
    }

    let mut out = program.clone();
    let mut result = Smoothing { passages: Vec::new(), max_orientation_deviation_deg: 0.0, max_ball_centre_error_m: 0.0 };
    let names = machine.axis_names();
    let (aname, cname) = (names[pi].clone(), names[si].clone());
    let (aletter, cletter) = (aname.chars().next().unwrap_or('A'), cname.chars().next().unwrap_or('C'));
    for cut in &cuts {
        let mut pts = cut.clone();
        let mut k0 = 1; // passages are searched after the previous one's window
        while let Some((ks, near)) = next_passage(&pts, k0, clim.velocity) {
            let new = connect(&pts, ks, &alim, &clim)?;
            // Check the A range on everything that changed.
            for p in &new.points {
                if !machine.axes[si].limits.contains(p.c) {
                    return Err(AvoidError::Refused(format!(
                        "the smoothed passage at x {:.3} mm needs {cname} {:.3} deg, outside the machine's range",
                        pts[ks].tip.x * 1e3,
                        p.c.to_degrees()
                    )));
                }
                if !machine.axes[pi].limits.contains(p.a) {
                    return Err(AvoidError::Refused(format!(
                        "the smoothed passage at x {:.3} mm needs {aname} {:.3} deg, outside the machine's range",
                        pts[ks].tip.x * 1e3,
                        p.a.to_degrees()
                    )));
                }
            }
            let mut dev: f64 = 0.0;
            for (old, p) in pts.iter().zip(&new.points) {
                let (o, n) = (axis(machine, old.a, old.c), axis(machine, p.a, p.c));
                dev = dev.max(o.angle(&n));
            }
            result.passages.push(Passage {
                x_singular_mm: pts[ks].tip.x * 1e3,
                block_number: pts[ks].number,
                original_distance_deg: near.to_degrees(),
                window_length_mm: (pts[new.hi].s - pts[new.lo].s) * 1e3,
                x_start_mm: pts[new.lo].tip.x * 1e3,
                x_end_mm: pts[new.hi].tip.x * 1e3,
                points_changed: pts.iter().zip(&new.points).filter(|(o, n)| (o.a - n.a).abs() > 1e-12 || (o.c - n.c).abs() > 1e-12).count(),
                c_limit_ratio: new.ratio,
                max_orientation_deviation_deg: dev.to_degrees(),
            });
            result.max_orientation_deviation_deg = result.max_orientation_deviation_deg.max(dev.to_degrees());
            k0 = new.hi + 1;
            pts = new.points;
        }
        // Write the points back: new A/C, and the tip moved so that the ball centre stays.
        for (old, p) in cut.iter().zip(&pts) {
            if p.block == usize::MAX || ((old.a - p.a).abs() <= 1e-12 && (old.c - p.c).abs() <= 1e-12) {
                continue;
            }
            let (o, n) = (axis(machine, old.a, old.c), axis(machine, p.a, p.c));
            let centre = old.tip + radius * o;
            let tip = centre - radius * n;
            let b = &mut out.blocks[p.block];
            let mut t = Targets { x: Some(tip.x), y: Some(tip.y), z: Some(tip.z), ..Targets::default() };
            t.set_rotary(aletter, p.a);
            t.set_rotary(cletter, p.c);
            b.targets = t;
        }
        // Blocks after the cut that name rotary positions in the same TCPM stretch keep the branch the
        // cut ended on (same tool axis): otherwise the table would flip at the exit.
        let last = pts.last().copied().expect("cut has points");
        let orig_last = cut.last().copied().expect("cut has points");
        if (last.a - orig_last.a).abs() > 1e-12 || (last.c - orig_last.c).abs() > 1e-12 {
            let shift_c = last.c - (orig_last.c + PI);
            let turns = (shift_c / (2.0 * PI)).round() * 2.0 * PI;
            for b in out.blocks.iter_mut().skip(orig_last.block + 1) {
                if !b.tcp {
                    break;
                }
                if let (Some(a), Some(c)) = (b.targets.rotary(aletter), b.targets.rotary(cletter)) {
                    b.targets.set_rotary(aletter, -a);
                    b.targets.set_rotary(cletter, c + PI + turns);
                }
            }
        }
    }
    out.source = format!("{} (smoothed)", program.source);
    // Ball centres of both programs, point for point.
    let new_traj = Trajectory::from_program(&out, machine, &options.path);
    if new_traj.segments.len() == traj.segments.len() {
        for (a, b) in traj.segments.iter().zip(&new_traj.segments) {
            if !program.blocks.get(a.block).is_some_and(|b| b.tcp) {
                continue;
            }
            let ca = a.tip1 + radius * machine.forward(&a.q1).axis;
            let cb = b.tip1 + radius * machine.forward(&b.q1).axis;
            result.max_ball_centre_error_m = result.max_ball_centre_error_m.max((ca - cb).norm());
        }
    }
    Ok((out, result))
}

fn axis(machine: &Machine, a: f64, c: f64) -> Vector3<f64> {
    let mut q = [0.0; 5];
    q[machine.primary_axis()] = a;
    q[machine.secondary_axis()] = c;
    machine.forward(&q).axis
}

/// The next singular passage at or after point `from`: the index of the point closest to the singular
/// direction (smallest |A|) within a stretch of steps where C needs more than `c_vmax` at the feed, or
/// where A changes sign near zero; with that |A|.
fn next_passage(p: &[Point], from: usize, c_vmax: f64) -> Option<(usize, f64)> {
    let fast = |k: usize| -> bool {
        let flips = p[k].a * p[k - 1].a < 0.0 && p[k].a.abs().min(p[k - 1].a.abs()) < 5f64.to_radians();
        flips || step_fast(p, k, c_vmax * (1.0 + 1e-9))
    };
    let start = (from.max(1)..p.len()).find(|&k| fast(k))?;
    let end = (start..p.len()).take_while(|&k| fast(k)).last().unwrap_or(start);
    let ks = (start - 1..=end).min_by(|&i, &j| p[i].a.abs().total_cmp(&p[j].a.abs()))?;
    Some((ks, p[ks].a.abs()))
}

struct Connected {
    points: Vec<Point>,
    lo: usize,
    hi: usize,
    ratio: [f64; 3],
}

/// Steps 2-4 for the passage at point `ks`.
fn connect(p: &[Point], ks: usize, alim: &crate::machine::AxisLimits, clim: &crate::machine::AxisLimits) -> Result<Connected, AvoidError> {
    let n = p.len();
    // Step 2: the other branch after s*, C unwrapped to join the points before.
    let sign_before = if ks > 0 { p[ks - 1].a.signum() } else { p[ks].a.signum() };
    let mut q: Vec<(f64, f64)> = p.iter().map(|x| (x.a, x.c)).collect();
    for k in ks + 1..n {
        if p[k].a.signum() == sign_before && p[k].a != 0.0 {
            q[k] = (-p[k].a, p[k].c + PI);
        }
    }
    // Unwrap C after s* as one piece: the 2 pi multiple that brings the far side closest to the near
    // side, judged one point outside the fast stretch on each side.
    let far_after = (ks + 1..n).find(|&k| k + 1 >= n || !step_fast(p, k + 1, clim.velocity)).unwrap_or(n - 1);
    let far_before = (1..=ks).rev().find(|&k| !step_fast(p, k, clim.velocity)).map_or(0, |k| k - 1);
    let turns = ((q[far_before].1 - q[far_after].1) / (2.0 * PI)).round() * 2.0 * PI;
    for item in q.iter_mut().skip(ks + 1) {
        item.1 += turns;
    }
    let feed = p[ks].feed;
    let f = [feed, feed * feed, feed * feed * feed];
    let s: Vec<f64> = p.iter().map(|x| x.s).collect();
    let (mut lo, mut hi) = (ks.saturating_sub(1), (ks + 1).min(n - 1));
    loop {
        // Curves before and after (the paper's Curve_b, Curve_a): splines through the points on each side.
        let ok_sides = lo >= 1 && hi + 1 < n;
        if ok_sides {
            let before_s: Vec<f64> = s[..=lo].to_vec();
            let after_s: Vec<f64> = s[hi..].to_vec();
            let side = |idx: std::ops::Range<usize>, pick: fn(&(f64, f64)) -> f64| -> Vec<f64> { q[idx].iter().map(pick).collect() };
            let cb = CubicSpline::natural(&before_s, &side(0..lo + 1, |x| x.1));
            let ca = CubicSpline::natural(&after_s, &side(hi..n, |x| x.1));
            let ab = CubicSpline::natural(&before_s, &side(0..lo + 1, |x| x.0));
            let aa = CubicSpline::natural(&after_s, &side(hi..n, |x| x.0));
            let d = |sp: &CubicSpline, t: f64| {
                let (d1, d2, d3) = sp.derivatives(t);
                [sp.value(t), d1, d2, d3]
            };
            let (s0, s1) = (s[lo], s[hi]);
            let pc = Poly::connect(s0, s1, d(&cb, s0), d(&ca, s1), None);
            let pa = Poly::connect(s0, s1, d(&ab, s0), d(&aa, s1), Some((s[ks], 0.0)));
            if let (Some(pc), Some(pa)) = (pc, pa) {
                let rc = pc.ratio(clim, f);
                let ra = pa.ratio(alim, f);
                if rc.iter().chain(&ra).all(|&r| r <= 1.0) {
                    let mut points = p.to_vec();
                    for k in 0..n {
                        let (a, c) = if k > lo && k < hi { (pa.value(s[k]), pc.value(s[k])) } else { q[k] };
                        points[k].a = a;
                        points[k].c = c;
                    }
                    return Ok(Connected { points, lo, hi, ratio: rc });
                }
            }
        }
        if lo <= 1 && hi + 2 >= n {
            return Err(AvoidError::Refused(format!(
                "the singular passage at x {:.3} mm cannot be smoothed within its cut at F{:.0}: even the whole cut ({:.1} mm) is too short for the C axis' v/a/j limits; lower the feed or reorient",
                p[ks].tip.x * 1e3,
                crate::units::mm_per_min(feed),
                (s[n - 1] - s[0]) * 1e3
            )));
        }
        lo = lo.saturating_sub(1).max(1);
        hi = (hi + 1).min(n - 2);
    }
}

/// True when the step into point `k` needs the secondary axis faster than `c_vmax` at the feed.
fn step_fast(p: &[Point], k: usize, c_vmax: f64) -> bool {
    let ds = p[k].s - p[k - 1].s;
    ds > 0.0 && (p[k].c - p[k - 1].c).abs() / ds * p[k].feed > c_vmax
}

/// A polynomial in u = (s - s0) / (s1 - s0).
struct Poly {
    s0: f64,
    len: f64,
    c: Vec<f64>,
}

impl Poly {
    /// The lowest-degree polynomial with value and first three derivatives `b` at s0 and `a` at s1,
    /// and through `(s, v)` if given (degree 7, or 8).
    fn connect(s0: f64, s1: f64, b: [f64; 4], a: [f64; 4], through: Option<(f64, f64)>) -> Option<Poly> {
        let len = s1 - s0;
        if !(len > 0.0) {
            return None;
        }
        let m = if through.is_some() { 9 } else { 8 };
        let mut mat = DMatrix::<f64>::zeros(m, m);
        let mut rhs = DVector::<f64>::zeros(m);
        // Row for the d-th derivative (in u) at u.
        let row = |u: f64, d: usize| -> Vec<f64> {
            (0..m)
                .map(|j| {
                    if j < d {
                        0.0
                    } else {
                        let falling: f64 = (0..d).map(|i| (j - i) as f64).product();
                        falling * u.powi((j - d) as i32)
                    }
                })
                .collect()
        };
        for d in 0..4 {
            let scale = len.powi(d as i32);
            for (j, v) in row(0.0, d).into_iter().enumerate() {
                mat[(d, j)] = v;
            }
            rhs[d] = b[d] * scale;
            for (j, v) in row(1.0, d).into_iter().enumerate() {
                mat[(4 + d, j)] = v;
            }
            rhs[4 + d] = a[d] * scale;
        }
        if let Some((s, v)) = through {
            let u = (s - s0) / len;
            if !(u > 0.0 && u < 1.0) {
                return None;
            }
            for (j, x) in row(u, 0).into_iter().enumerate() {
                mat[(8, j)] = x;
            }
            rhs[8] = v;
        }
        let c = mat.lu().solve(&rhs)?;
        Some(Poly { s0, len, c: c.iter().copied().collect() })
    }

    /// The d-th derivative with respect to s.
    fn deriv(&self, s: f64, d: usize) -> f64 {
        let u = (s - self.s0) / self.len;
        let mut v = 0.0;
        for (j, &cj) in self.c.iter().enumerate().skip(d) {
            let falling: f64 = (0..d).map(|i| (j - i) as f64).product();
            v += cj * falling * u.powi((j - d) as i32);
        }
        v / self.len.powi(d as i32)
    }

    fn value(&self, s: f64) -> f64 {
        self.deriv(s, 0)
    }

    /// Seed 002 eq. (2)-(4) at feed f = [F, F^2, F^3]: the largest F|q_s|/v, F^2|q_ss|/a, F^3|q_sss|/j
    /// on a fine grid (200 steps per window, at least every 0.05 mm).
    fn ratio(&self, lim: &crate::machine::AxisLimits, f: [f64; 3]) -> [f64; 3] {
        let steps = ((self.len / 5e-5).ceil() as usize).max(200);
        let mut r = [0.0f64; 3];
        for i in 0..=steps {
            let s = self.s0 + self.len * i as f64 / steps as f64;
            r[0] = r[0].max(self.deriv(s, 1).abs() * f[0] / lim.velocity);
            r[1] = r[1].max(self.deriv(s, 2).abs() * f[1] / lim.acceleration);
            r[2] = r[2].max(self.deriv(s, 3).abs() * f[2] / lim.jerk);
        }
        r
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn connection_matches_both_sides_to_the_third_derivative_and_the_singular_point() {
        let b = [1.0, 0.5, -0.2, 0.1];
        let a = [-2.0, 0.3, 0.4, -0.05];
        let p = Poly::connect(1.0, 4.0, b, a, Some((2.5, 0.0))).expect("solvable");
        for d in 0..4 {
            assert!((p.deriv(1.0, d) - b[d]).abs() < 1e-9, "d{d} at s0");
            assert!((p.deriv(4.0, d) - a[d]).abs() < 1e-9, "d{d} at s1");
        }
        assert!(p.value(2.5).abs() < 1e-12);
    }

    #[test]
    fn tool_specs_parse_and_reject_nonsense() {
        assert_eq!("ball:3".parse::<Tool>(), Ok(Tool::Ball(3e-3)));
        assert_eq!("bull:5:1".parse::<Tool>(), Ok(Tool::Bull(5e-3, 1e-3)));
        assert!("ball:-1".parse::<Tool>().is_err());
        assert!("ball".parse::<Tool>().is_err());
    }
}
