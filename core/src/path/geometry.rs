//! The shapes a move takes between its ends: the tool axis turning on a great circle (vector
//! orientation interpolation) and the tool tip on a circular, helical or spiral arc, each as a
//! function of the fraction of the move, cut into pieces by the segment planner.

use crate::program::ArcSpec;
use nalgebra::Vector3;

/// The tool axis turning on the great circle from `o0` to `o1` at a constant angular rate (slerp),
/// as a control with vector orientation interpolation moves it: `o(w) = (sin((1-w) g) o0 + sin(w g) o1)
/// / sin g` with `g` the angle between them, `w` the fraction of the whole move. A piece of the move
/// covers `w` in `u0..u1`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GreatCircle {
    pub o0: Vector3<f64>,
    pub o1: Vector3<f64>,
    /// Angle between `o0` and `o1`, rad, in (0, pi).
    pub angle: f64,
    pub u0: f64,
    pub u1: f64,
}

impl GreatCircle {
    /// The great circle from `o0` to `o1` (unit), or `None` if they are parallel (no turn) or
    /// opposite (no single great circle).
    pub fn new(o0: Vector3<f64>, o1: Vector3<f64>) -> Option<GreatCircle> {
        let angle = o0.cross(&o1).norm().atan2(o0.dot(&o1));
        (angle > 1e-12 && angle < std::f64::consts::PI - 1e-9).then_some(GreatCircle { o0, o1, angle, u0: 0.0, u1: 1.0 })
    }

    fn whole(&self, w: f64) -> Vector3<f64> {
        let g = self.angle;
        (self.o0 * ((1.0 - w) * g).sin() + self.o1 * (w * g).sin()) / g.sin()
    }

    /// Tool axis at fraction `u` of this piece.
    pub fn axis(&self, u: f64) -> Vector3<f64> {
        self.whole(self.u0 + (self.u1 - self.u0) * u)
    }

    /// Derivative of the tool axis with respect to `u`, the fraction of this piece.
    pub fn axis_rate(&self, u: f64) -> Vector3<f64> {
        let (g, w) = (self.angle, self.u0 + (self.u1 - self.u0) * u);
        (self.o1 * (w * g).cos() - self.o0 * ((1.0 - w) * g).cos()) * (g / g.sin() * (self.u1 - self.u0))
    }

    /// The part between fractions `ua` and `ub` of this piece.
    pub fn piece(&self, ua: f64, ub: f64) -> GreatCircle {
        let at = |u: f64| self.u0 + (self.u1 - self.u0) * u;
        GreatCircle { u0: at(ua), u1: at(ub), ..*self }
    }
}

/// A circular or helical arc: `p(u) = c + r(u) (cos th(u) e1 + sin th(u) e2) + h(u) n` for
/// `u` in 0..1, with the angle `th`, the radius `r` and the height `h` along the normal linear in
/// `u` (a spiral when the program's start and end radii differ within the reader's tolerance, as
/// LinuxCNC runs it).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ArcPath {
    /// Centre, with no component along `n`; `e1`, `e2`, `n` the plane's axes (`e1 x e2 = n`).
    pub centre: Vector3<f64>,
    pub e1: Vector3<f64>,
    pub e2: Vector3<f64>,
    pub n: Vector3<f64>,
    /// Start angle from `e1` towards `e2` and signed sweep (positive: counter-clockwise, G03), rad.
    pub theta0: f64,
    pub sweep: f64,
    pub r0: f64,
    pub r1: f64,
    pub h0: f64,
    pub h1: f64,
}

/// Largest angle of one piece of an arc. The planners fit splines through piece ends: a natural
/// cubic through points 5 deg apart on a circle of radius R departs from it by about R 1e-7.
pub const ARC_PIECE_RAD: f64 = 5.0 * std::f64::consts::PI / 180.0;

impl ArcPath {
    /// The arc of `spec` from `start` to `end` (program coordinates, m), counter-clockwise if `ccw`.
    pub fn new(spec: &ArcSpec, ccw: bool, start: Vector3<f64>, end: Vector3<f64>) -> ArcPath {
        let (a0, a1, an) = spec.plane.axes();
        // In a tilted working plane the arc's axes are the plane's.
        let turn = spec.frame.map_or(nalgebra::Matrix3::identity(), |f| nalgebra::Matrix3::from_columns(&f.map(Vector3::from)));
        let (e1, e2, n) = (turn * Vector3::ith(a0, 1.0), turn * Vector3::ith(a1, 1.0), turn * Vector3::ith(an, 1.0));
        let c = Vector3::from(spec.centre);
        let centre = c - n * c.dot(&n);
        let (ds, de) = (start - centre, end - centre);
        let theta0 = ds.dot(&e2).atan2(ds.dot(&e1));
        let theta1 = de.dot(&e2).atan2(de.dot(&e1));
        let tau = std::f64::consts::TAU;
        // Sweep in (0, 2 pi] counter-clockwise or [-2 pi, 0) clockwise: an end within 1e-9 rad of
        // the start is a full circle.
        let d = (theta1 - theta0).rem_euclid(tau);
        let mut sweep = match ccw {
            true if d < 1e-9 => tau,
            true => d,
            false if d > tau - 1e-9 => -tau,
            false => d - tau,
        };
        sweep += if ccw { 1.0 } else { -1.0 } * tau * f64::from(spec.extra_turns);
        let radial = |d: Vector3<f64>| d.dot(&e1).hypot(d.dot(&e2));
        ArcPath { centre, e1, e2, n, theta0, sweep, r0: radial(ds), r1: radial(de), h0: start.dot(&n), h1: end.dot(&n) }
    }

    /// The point at fraction `u`.
    pub fn point(&self, u: f64) -> Vector3<f64> {
        let th = self.theta0 + self.sweep * u;
        let r = self.r0 + (self.r1 - self.r0) * u;
        self.centre + (self.e1 * th.cos() + self.e2 * th.sin()) * r + self.n * (self.h0 + (self.h1 - self.h0) * u)
    }

    /// Arc length (exact for a circle or helix; a spiral's by Simpson's rule).
    pub fn length(&self) -> f64 {
        let dh = self.h1 - self.h0;
        if self.r0 == self.r1 {
            return (self.r0 * self.sweep).hypot(dh);
        }
        let speed = |u: f64| {
            let r = self.r0 + (self.r1 - self.r0) * u;
            ((r * self.sweep).powi(2) + (self.r1 - self.r0).powi(2) + dh * dh).sqrt()
        };
        const N: usize = 64;
        let h = 1.0 / N as f64;
        (0..=N).map(|k| speed(k as f64 * h) * if k == 0 || k == N { 1.0 } else if k % 2 == 1 { 4.0 } else { 2.0 }).sum::<f64>() * h / 3.0
    }

    /// The part of the arc between fractions `ua` and `ub`.
    pub fn piece(&self, ua: f64, ub: f64) -> ArcPath {
        let lerp = |a: f64, b: f64, u: f64| a + (b - a) * u;
        ArcPath {
            theta0: self.theta0 + self.sweep * ua,
            sweep: self.sweep * (ub - ua),
            r0: lerp(self.r0, self.r1, ua),
            r1: lerp(self.r0, self.r1, ub),
            h0: lerp(self.h0, self.h1, ua),
            h1: lerp(self.h0, self.h1, ub),
            ..*self
        }
    }

    /// How many pieces of at most [`ARC_PIECE_RAD`] the arc is cut into.
    pub fn pieces(&self) -> usize {
        ((self.sweep.abs() / ARC_PIECE_RAD).ceil() as usize).max(1)
    }
}
