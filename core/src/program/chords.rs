//! A parametric curve of the machine's axes made as the chords a control's path lies within: a
//! Fanuc NURBS curve (`G06.2`), a TNC spline (`SPL`). The chords' ends lie on the curve, and every
//! point of the curve within the tolerance of a point of a chord (along which the axes move together).

/// How far a chord may stray from the curve: 1 µm on the linear axes.
pub const CHORD_TOLERANCE_M: f64 = 1e-6;
/// How far a chord may stray from the curve on a rotary axis: 0.001 deg.
pub const CHORD_TOLERANCE_RAD: f64 = 0.001 * std::f64::consts::PI / 180.0;
/// A curve is first cut in this many pieces (an S within it has its chords then), each halved until
/// its chord lies within the tolerance, at most [`MAX_HALVINGS`] times.
const FIRST_PIECES: usize = 4;
const MAX_HALVINGS: u32 = 10;

/// The axes a curve moves (X Y Z A B C) and how far a chord may stray on each (its units).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Chording {
    pub axes: [bool; 6],
    pub tolerance: [f64; 6],
}

impl Chording {
    /// What a curve that [`Chording::chords`] refuses needs (for its message).
    pub fn too_many() -> String {
        format!("needs chords shorter than 1/{} of it to stay within 1 µm (0.001 deg on a rotary axis), or its points are not numbers", FIRST_PIECES << MAX_HALVINGS)
    }

    /// The chords of `f` from `t0` to `t1` (either way): their ends pushed in order (not `f(t0)`);
    /// false past 4096 chords, or where `f` is not a number.
    pub fn chords(&self, f: &dyn Fn(f64) -> [f64; 6], t0: f64, t1: f64, ends: &mut Vec<[f64; 6]>) -> bool {
        let mut a = f(t0);
        for n in 0..FIRST_PIECES {
            let s0 = t0 + (t1 - t0) * n as f64 / FIRST_PIECES as f64;
            let s1 = if n + 1 == FIRST_PIECES { t1 } else { t0 + (t1 - t0) * (n + 1) as f64 / FIRST_PIECES as f64 };
            let b = f(s1);
            if !b.iter().all(|v| v.is_finite()) || !self.halve(f, s0, &a, s1, &b, 0, ends) {
                return false;
            }
            a = b;
        }
        true
    }

    /// The chords from `a` (at `t0`) to `b` (at `t1`), halved until each lies within the tolerance.
    #[allow(clippy::too_many_arguments)]
    fn halve(&self, f: &dyn Fn(f64) -> [f64; 6], t0: f64, a: &[f64; 6], t1: f64, b: &[f64; 6], depth: u32, ends: &mut Vec<[f64; 6]>) -> bool {
        let tm = 0.5 * (t0 + t1);
        let m = f(tm);
        let quarters = [f(t0 + 0.25 * (t1 - t0)), f(t0 + 0.75 * (t1 - t0))];
        if !m.iter().chain(quarters.iter().flatten()).all(|v| v.is_finite()) {
            return false;
        }
        // The midpoint and the quarter points: an inflection at the middle leaves the midpoint on
        // the chord while the curve strays on either side of it.
        if self.within(a, &m, b) && quarters.iter().all(|q| self.within(a, q, b)) {
            ends.push(*b);
            return true;
        }
        if depth == MAX_HALVINGS {
            return false;
        }
        self.halve(f, t0, a, tm, &m, depth + 1, ends) && self.halve(f, tm, &m, t1, b, depth + 1, ends)
    }

    /// Whether the curve's point `m` lies within the tolerance of the chord from `a` to `b`: some
    /// point of the chord within 1 µm of it on the linear axes and within 0.001 deg on each rotary
    /// axis. Each axis, scaled by its tolerance, allows an interval of the chord's parameter; the
    /// point exists where they meet.
    pub fn within(&self, a: &[f64; 6], m: &[f64; 6], b: &[f64; 6]) -> bool {
        // f64::max and min pass a NaN by: none may reach them.
        if !a.iter().chain(m).chain(b).all(|v| v.is_finite()) {
            return false;
        }
        let (mut ab, mut am) = ([0.0; 6], [0.0; 6]);
        for k in (0..6).filter(|k| self.axes[*k]) {
            ab[k] = (b[k] - a[k]) / self.tolerance[k];
            am[k] = (m[k] - a[k]) / self.tolerance[k];
        }
        let (mut lo, mut hi) = (0.0f64, 1.0f64);
        // The linear axes: |am - s ab|^2 <= 1, a quadratic in s.
        let ab2: f64 = ab[..3].iter().map(|v| v * v).sum();
        let am2: f64 = am[..3].iter().map(|v| v * v).sum();
        let dot: f64 = (0..3).map(|k| am[k] * ab[k]).sum();
        if ab2 > 0.0 {
            let d = dot * dot - ab2 * (am2 - 1.0);
            if !(d >= 0.0) {
                return false;
            }
            lo = lo.max((dot - d.sqrt()) / ab2);
            hi = hi.min((dot + d.sqrt()) / ab2);
        } else if !(am2 <= 1.0) {
            return false;
        }
        // Each rotary axis: |am - s ab| <= 1.
        for k in 3..6 {
            if ab[k] != 0.0 {
                let (s0, s1) = ((am[k] - 1.0) / ab[k], (am[k] + 1.0) / ab[k]);
                lo = lo.max(s0.min(s1));
                hi = hi.min(s0.max(s1));
            } else if !(am[k].abs() <= 1.0) {
                return false;
            }
        }
        lo <= hi
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A straight line is one chord a piece; a circle's chords keep their sagitta within 1 µm.
    #[test]
    fn chords_of_a_line_and_a_circle() {
        let c = Chording { axes: [true, true, false, false, false, false], tolerance: [1e-3; 6] };
        let mut ends = Vec::new();
        assert!(c.chords(&|t| [t, 2.0 * t, 0.0, 0.0, 0.0, 0.0], 0.0, 10.0, &mut ends));
        assert_eq!(ends.len(), FIRST_PIECES);
        let mut ends = Vec::new();
        let r = 50.0;
        assert!(c.chords(&|t: f64| [r * t.cos(), r * t.sin(), 0.0, 0.0, 0.0, 0.0], 0.0, 1.0, &mut ends));
        let mut a = [r, 0.0];
        for e in &ends {
            let chord = ((e[0] - a[0]).powi(2) + (e[1] - a[1]).powi(2)).sqrt();
            assert!(r - (r * r - chord * chord / 4.0).sqrt() <= 1e-3 + 1e-12);
            a = [e[0], e[1]];
        }
        assert!(!c.chords(&|_| [f64::NAN; 6], 0.0, 1.0, &mut Vec::new()));
    }
}
