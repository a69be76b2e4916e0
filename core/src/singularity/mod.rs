//! Singularity analysis, per sample (seed 001 §2, seed 002 eq. 5):
//! - distance to the singularity: the angle between the tool axis and the singular direction
//!   (|A| on the Hermle, seed 001 §2.4);
//! - predicted secondary-axis speed, seed 001 eq. (5): `dC/dt = (dTheta_h/dt) / sin(A)`, made exact for
//!   any two-rotary chain in [`TwoRotaryChain::secondary_rate`](crate::kinematics::TwoRotaryChain::secondary_rate);
//! - feed limit and the limiting axis from per-axis velocity/acceleration/jerk limits, seed 002 eq. (5);
//! - regions: contiguous stretches where the predicted speed exceeds the axis limit (or the distance
//!   falls below a threshold).

mod analysis;
mod feed;
mod geometry;
pub mod measured;
pub mod tracker;

pub use analysis::{analyze, analyze_segments, analyze_segments_along, analyze_segments_each, statuses, Analysis, AnalysisOptions, Region, RegionCause, SegmentInfo, Status, Statuses, StreamCounts, Summary};
pub use feed::{feed_limit, FeedLimit, FeedLimiter, LimitKind};
pub use geometry::{CubicSpline, Knots, PathGeometry, SplineBasis, SplineSet, CORNER_DEG, SPLINE_OVERLAP_BLOCKS};

use nalgebra::Vector3;

/// Angle (rad) between the tool axis and the singular direction, folded so that both `s` and `-s`
/// count as singular: in [0, pi/2].
#[inline]
pub fn distance(axis: &Vector3<f64>, singular: &Vector3<f64>) -> f64 {
    axis.cross(singular).norm().atan2(axis.dot(singular).abs())
}

pub use crate::kinematics::POLE;

/// True when the tool axis lies on the singular direction while moving: eq. (5) is undefined there.
#[inline]
pub fn on_pole(axis: &Vector3<f64>, axis_rate: &Vector3<f64>, singular: &Vector3<f64>) -> bool {
    singular.cross(axis).norm() <= POLE && axis_rate.norm() > 0.0
}
