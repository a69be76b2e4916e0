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

use nalgebra::{Isometry3, Rotation3, Translation3, Unit, UnitQuaternion, Vector3};
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

impl RotaryJoint {
    fn rotation(&self, theta: f64) -> Rotation3<f64> {
        Rotation3::from_axis_angle(&Unit::new_unchecked(self.axis), theta)
    }
    /// The rigid motion of a turn by `theta` about this joint's line, `p' = c + R (p - c)`: what
    /// [`turn_point`](Self::turn_point) does to one point, for a view that moves a whole part.
    pub fn turn(&self, theta: f64) -> Isometry3<f64> {
        let r = UnitQuaternion::from_axis_angle(&Unit::new_unchecked(self.axis), theta);
        Isometry3::from_parts(Translation3::from(self.center - r * self.center), r)
    }
    /// Turn point `p` by `theta` about this joint's line.
    fn turn_point(&self, theta: f64, p: &Vector3<f64>) -> Vector3<f64> {
        self.center + self.rotation(theta) * (p - self.center)
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
