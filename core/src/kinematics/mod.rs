//! Forward and inverse kinematics of any machine with three linear and two rotary axes.
//!
//! The orientation part follows seed 001 §2.4: the tool axis in the workpiece frame is
//! `O_W = R_r2(phi2) R_r1(phi1) O_M`, a product of two rotations about fixed axes (the product of
//! exponentials of the home configuration). `r2` is the rotary axis whose direction stays fixed in
//! the workpiece frame (the inner table axis, or the outer head axis); the machine is singular when
//! the tool axis is parallel to it (`C` on the Hermle, eq. 2 and Table 1). A table axis turns the
//! workpiece, so it enters with `phi = -theta`; a head axis turns the tool, `phi = +theta`.
//!
//! The inverse is solved in closed form (two intersecting rotations: Paden-Kahan subproblems 1 and 2),
//! which yields both solutions of seed 001 Table 1, `(A, C)` and `(-A, C + pi)` on the Hermle.

mod chain;

pub use chain::{OrientationSolutions, Pose, TwoRotaryChain, POLE};

use nalgebra::{Isometry3, Translation3, Unit, UnitQuaternion, Vector3};
use serde::Deserialize;

/// Axis values `[X, Y, Z, R1st, R2nd]` in SI (m, rad), in the machine's axis order.
pub type Joints = [f64; 5];

/// What a rotary axis turns.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Carrier {
    /// Turns the workpiece (a rotary or tilting table).
    Table,
    /// Turns the spindle (a swivel head).
    Head,
}

/// A rotary joint: direction (unit, right-handed sense of a positive move) and a point on its line.
#[derive(Debug, Clone, PartialEq)]
pub struct RotaryJoint {
    pub name: String,
    pub carrier: Carrier,
    pub axis: Vector3<f64>,
    pub center: Vector3<f64>,
}

/// The sine and cosine of a turn, `(sin, cos)`: each joint's computed once per transform and
/// shared by every point and vector it turns.
pub type Turn = (f64, f64);

impl RotaryJoint {
    /// The rigid motion of a turn by `theta` about this joint's line, `p' = c + R (p - c)`: what
    /// [`turn_point`](Self::turn_point) does to one point, for a view that moves a whole part.
    pub fn turn(&self, theta: f64) -> Isometry3<f64> {
        let r = UnitQuaternion::from_axis_angle(&Unit::new_unchecked(self.axis), theta);
        Isometry3::from_parts(Translation3::from(self.center - r * self.center), r)
    }
    /// Turn vector `v` about this joint's direction by the turn whose sine and cosine are given
    /// (Rodrigues' formula: `v cos + (k x v) sin + k (k . v)(1 - cos)`).
    fn turn_vector(&self, (sin, cos): Turn, v: &Vector3<f64>) -> Vector3<f64> {
        let k = &self.axis;
        v * cos + k.cross(v) * sin + k * (k.dot(v) * (1.0 - cos))
    }
    /// Turn point `p` about this joint's line by the turn whose sine and cosine are given.
    fn turn_point(&self, turn: Turn, p: &Vector3<f64>) -> Vector3<f64> {
        self.center + self.turn_vector(turn, &(p - self.center))
    }
}

/// The sine and cosine of angles met in sequence, as a planner evaluates nearby set-points: from an
/// exact anchor `sin_cos` by the angle-addition formula when the angle is within [`SinCos::REACH`]
/// of it (the small difference's Taylor series is exact to rounding there), else a new anchor.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SinCos {
    anchor: f64,
    sin: f64,
    cos: f64,
}

impl Default for SinCos {
    fn default() -> Self {
        SinCos { anchor: 0.0, sin: 0.0, cos: 1.0 }
    }
}

impl SinCos {
    /// Largest distance from the anchor, rad: the series' first omitted terms, `d^11/11!` and
    /// `d^12/12!`, are below 1e-22 there (the C axis of a table near the singularity turns up to
    /// 0.003 rad per millisecond: an anchor serves a dozen samples or more).
    pub const REACH: f64 = 0.05;

    /// `(sin theta, cos theta)`.
    pub fn at(&mut self, theta: f64) -> (f64, f64) {
        let d = theta - self.anchor;
        if !(d.abs() <= Self::REACH) {
            (self.sin, self.cos) = theta.sin_cos();
            self.anchor = theta;
            return (self.sin, self.cos);
        }
        let d2 = d * d;
        // Multiplications by the reciprocal factorial ratios, which are cheaper than divisions.
        let sd = d * (1.0 - d2 * (1.0 / 6.0) * (1.0 - d2 * (1.0 / 20.0) * (1.0 - d2 * (1.0 / 42.0) * (1.0 - d2 * (1.0 / 72.0)))));
        // 1 - cos d, kept apart from the 1 so that no digits of the small term are lost.
        let vd = d2 * 0.5 * (1.0 - d2 * (1.0 / 12.0) * (1.0 - d2 * (1.0 / 30.0) * (1.0 - d2 * (1.0 / 56.0) * (1.0 - d2 * (1.0 / 90.0)))));
        (self.sin - (self.sin * vd - self.cos * sd), self.cos - (self.cos * vd + self.sin * sd))
    }
}

/// Errors of the kinematic transforms. Angles in messages are in degrees, lengths in mm.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum KinematicsError {
    #[error("input is not finite (NaN or infinite)")]
    NotFinite,
    #[error("tool axis has zero length")]
    ZeroToolAxis,
    #[error("tool orientation cannot be reached by this machine's rotary axes")]
    Unreachable,
    /// Values in people's units: mm for linear axes, degrees for rotary axes (named by `unit`).
    #[error("no solution within the limits: {axis} would be {value:.3} {unit}, range {min:.3}..{max:.3} {unit}")]
    OutOfRange { axis: String, value: f64, min: f64, max: f64, unit: &'static str },
    #[error("the rotary axes are parallel: not a five-axis machine")]
    ParallelAxes,
    #[error("the tool lies along the only rotary axis: turning it does not tilt the tool")]
    ToolAlongRotary,
}

/// Rotate `p` about unit `axis` onto the direction of `q` (Paden-Kahan subproblem 1): the angle, or
/// `None` when either point lies on the axis (the angle is then undefined: a singularity).
pub fn subproblem1(axis: &Vector3<f64>, p: &Vector3<f64>, q: &Vector3<f64>) -> Option<f64> {
    let pp = p - axis * axis.dot(p);
    let qp = q - axis * axis.dot(q);
    const EPS: f64 = 1e-12;
    if pp.norm_squared() < EPS * EPS || qp.norm_squared() < EPS * EPS {
        return None;
    }
    Some(axis.dot(&pp.cross(&qp)).atan2(pp.dot(&qp)))
}

/// Wrap an angle to (-pi, pi].
pub fn wrap_pi(a: f64) -> f64 {
    let two_pi = std::f64::consts::TAU;
    let mut r = a.rem_euclid(two_pi);
    if r > std::f64::consts::PI {
        r -= two_pi;
    }
    r
}

/// The representative `a + 2 pi k` nearest to `reference`.
pub fn unwrap_near(a: f64, reference: f64) -> f64 {
    reference + wrap_pi(a - reference)
}

#[cfg(test)]
mod tests {
    use super::SinCos;
    use crate::machine::Machine;
    use nalgebra::Vector3;

    /// `SinCos` along a sequence (small steps, steps past its reach, a jump back) agrees with
    /// `f64::sin_cos` to rounding.
    #[test]
    fn sin_cos_along_a_sequence_is_libm_to_rounding() {
        let mut sc = SinCos::default();
        let mut theta = -3.0f64;
        let mut worst = 0.0f64;
        for k in 0..200_000 {
            theta += match k % 1000 {
                0 => 0.5,
                500 => -1.7,
                _ => 1e-4 * (1.0 + (k as f64 * 0.37).sin()),
            };
            let (s, c) = sc.at(theta);
            let (s0, c0) = theta.sin_cos();
            worst = worst.max((s - s0).abs()).max((c - c0).abs());
        }
        assert!(worst < 1e-15, "largest difference {worst:e}");
        assert!(sc.at(f64::NAN).0.is_nan());
    }

    /// The linear axes along a sequence of angles are those of the exact transform, on a table-table,
    /// a head-table and a head-head machine.
    #[test]
    fn linear_axes_along_a_sequence_match_the_exact_transform() {
        for name in ["hermle-c600u", "dmu-style-b45", "linuxcnc-max5"] {
            let m = Machine::builtin(name).unwrap();
            let mut turns = Default::default();
            let mut worst = 0.0f64;
            for k in 0..20_000 {
                let x = k as f64 * 1e-4;
                let rot = [0.8 * (0.7 * x).sin(), 3.0 * x - 2.0];
                let tip = Vector3::new(0.05 * x.cos(), -0.02 + 0.01 * x, 0.03);
                let a = m.chain.linear_for(&tip, &rot);
                let b = m.chain.linear_for_along(&tip, &rot, &mut turns);
                worst = worst.max((a - b).amax());
            }
            assert!(worst < 1e-15, "{name}: largest difference {worst:e} m");
        }
    }
}
