//! The limit check: velocity, acceleration and jerk of sampled axis positions by finite differences
//! (5-point stencil at the sample period), as ratios to the machine's limits. One stencil, over a
//! slice ([`limit_ratios`]) or over a stream in constant memory ([`LimitCheck`]).

use crate::kinematics::Joints;
use crate::machine::{AxisLimits, AXES};

/// The stencil's differences at period `t` as ratios to the limits: per axis, the factors that
/// turn a first, second and third difference into |v|/v_max, |a|/a_max and |j|/j_max.
#[derive(Debug, Clone, Copy)]
struct Stencil {
    scale: [[f64; 3]; AXES],
}

impl Stencil {
    fn new(t: f64, limits: &[AxisLimits; AXES]) -> Stencil {
        Stencil {
            scale: std::array::from_fn(|i| {
                let l = &limits[i];
                [1.0 / (2.0 * t * l.velocity), 1.0 / (t * t * l.acceleration), 1.0 / (2.0 * t * t * t * l.jerk)]
            }),
        }
    }

    /// Ratios |v|/v_max, |a|/a_max, |j|/j_max (largest over the axes) at the middle of five
    /// positions `q[k-2..=k+2]`.
    #[inline(always)]
    fn ratio_at(&self, m2: &Joints, m1: &Joints, p0: &Joints, p1: &Joints, p2: &Joints) -> [f64; 3] {
        let mut r = [0.0f64; 3];
        for i in 0..AXES {
            let s = &self.scale[i];
            let v = p1[i] - m1[i];
            let a = p1[i] - 2.0 * p0[i] + m1[i];
            let j = p2[i] - 2.0 * p1[i] + 2.0 * m1[i] - m2[i];
            r[0] = r[0].max(v.abs() * s[0]);
            r[1] = r[1].max(a.abs() * s[1]);
            r[2] = r[2].max(j.abs() * s[2]);
        }
        r
    }
}

/// Largest ratios of finite-difference velocity, acceleration and jerk to the limits, per sample,
/// for a position sequence `q` at period `t` that is at rest before and after.
pub fn limit_ratios(q: &[Joints], t: f64, limits: &[AxisLimits; AXES]) -> Vec<[f64; 3]> {
    let mut out = Vec::with_capacity(q.len());
    limit_ratios_into(q, t, limits, &mut out);
    out
}

/// [`limit_ratios`] into `out` (cleared first), whose allocation a caller reuses.
pub fn limit_ratios_into(q: &[Joints], t: f64, limits: &[AxisLimits; AXES], out: &mut Vec<[f64; 3]>) {
    let n = q.len();
    let stencil = Stencil::new(t, limits);
    let at = |k: isize| &q[k.clamp(0, n as isize - 1) as usize];
    out.clear();
    out.reserve(n);
    // The first and last two positions' stencils reach past the ends (held there); the rest are
    // five neighbours in a row.
    let edge = n.min(2);
    out.extend((0..edge as isize).map(|k| stencil.ratio_at(at(k - 2), at(k - 1), at(k), at(k + 1), at(k + 2))));
    if n > 4 {
        out.extend(q.windows(5).map(|p| stencil.ratio_at(&p[0], &p[1], &p[2], &p[3], &p[4])));
    }
    let tail = n.saturating_sub(2).max(edge);
    out.extend((tail as isize..n as isize).map(|k| stencil.ratio_at(at(k - 2), at(k - 1), at(k), at(k + 1), at(k + 2))));
}

/// [`limit_ratios`] over a stream: positions pushed one at a time, the worst ratios kept; five
/// positions held. The same figures as [`limit_ratios`] on the whole sequence.
#[derive(Debug, Clone)]
pub struct LimitCheck {
    stencil: Stencil,
    /// The last five positions pushed (position k at slot k mod 5) and how many were pushed.
    last: [Joints; 5],
    n: u64,
    worst: [f64; 3],
}

impl LimitCheck {
    pub fn new(t: f64, limits: &[AxisLimits; AXES]) -> LimitCheck {
        LimitCheck {
            stencil: Stencil::new(t, limits),
            last: [[0.0; AXES]; 5],
            n: 0,
            worst: [0.0; 3],
        }
    }

    /// Position `k` (0-based) of the stream, read back from the last five pushed, clamped to the
    /// stream's first and last pushed.
    fn at(&self, k: i64) -> &Joints {
        let n = self.n as i64;
        // Position k is kept at slot k mod 5 (a ring: nothing moves on a push).
        let k = k.clamp((n - 5).max(0), n - 1);
        &self.last[k.rem_euclid(5) as usize]
    }

    fn measure(&mut self, k: i64) {
        let r = self.stencil.ratio_at(self.at(k - 2), self.at(k - 1), self.at(k), self.at(k + 1), self.at(k + 2));
        self.keep_worst(r);
    }

    fn keep_worst(&mut self, r: [f64; 3]) {
        for i in 0..3 {
            self.worst[i] = self.worst[i].max(r[i]);
        }
    }

    /// The next position.
    pub fn push(&mut self, q: &Joints) {
        let slot = (self.n % 5) as usize;
        self.last[slot] = *q;
        self.n += 1;
        if self.n >= 5 {
            // The stencil of sample n - 3 holds the last five pushed, the oldest in the slot after
            // this one's (what `measure` reads back, without its clamping).
            let at = |d: usize| &self.last[(slot + 1 + d) % 5];
            let r = self.stencil.ratio_at(at(0), at(1), at(2), at(3), at(4));
            self.keep_worst(r);
            return;
        }
        // The stencil of sample n - 3 is complete (it reaches two ahead).
        if self.n >= 3 {
            self.measure(self.n as i64 - 3);
        }
    }

    /// The worst ratios over every position pushed (the last two measured with the stream at rest after).
    pub fn finish(mut self) -> [f64; 3] {
        let n = self.n as i64;
        for k in (n - 2).max(0)..n {
            self.measure(k);
        }
        self.worst
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_stream_measures_what_the_slice_does() {
        let limits = crate::machine::Machine::hermle_c600u().limits();
        for n in [0usize, 1, 2, 3, 4, 5, 9, 200] {
            // A wobbly motion with a jump in it: every stencil sees something different.
            let q: Vec<Joints> = (0..n)
                .map(|k| {
                    let x = k as f64 * 1e-3;
                    [
                        1e-3 * (7.0 * x).sin(),
                        x * x,
                        if k > n / 2 { 1e-4 } else { 0.0 },
                        (3.0 * x).cos(),
                        0.2 * x,
                    ]
                })
                .collect();
            let whole = limit_ratios(&q, 1e-3, &limits)
                .iter()
                .fold([0.0f64; 3], |m, r| {
                    [m[0].max(r[0]), m[1].max(r[1]), m[2].max(r[2])]
                });
            let mut c = LimitCheck::new(1e-3, &limits);
            q.iter().for_each(|x| c.push(x));
            assert_eq!(c.finish(), whole, "n = {n}");
        }
    }
}
