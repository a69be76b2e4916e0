//! Seed 002 eq. (5): the feed a path allows under per-axis limits, neglecting tangential acceleration
//! and jerk (valid where the feed falls and recovers):
//! `s' <= min_i (F, v_max_i/|q_s_i|, sqrt(a_max_i/|q_ss_i|), cbrt(j_max_i/|q_sss_i|))`.

use crate::machine::{AxisLimits, AXES};

/// Which bound is the lowest.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum LimitKind {
    /// The programmed feed: no axis limit binds.
    Programmed,
    Velocity,
    Acceleration,
    Jerk,
}

/// The feed limit at one point of the path.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct FeedLimit {
    /// Tool-tip feed, m/s.
    pub feed: f64,
    /// Index of the limiting axis (None when the programmed feed is the bound).
    pub axis: Option<usize>,
    pub kind: LimitKind,
}

/// Seed 002 eq. (5) for geometric derivatives `q_s`, `q_ss`, `q_sss` of each axis with respect to the
/// tool-tip path length (m/m or rad/m, per m, per m^2), programmed feed `f_prog` (m/s).
#[inline]
pub fn feed_limit(
    f_prog: f64,
    q_s: &[f64; AXES],
    q_ss: &[f64; AXES],
    q_sss: &[f64; AXES],
    limits: &[AxisLimits; AXES],
) -> FeedLimit {
    let mut best = FeedLimit { feed: f_prog, axis: None, kind: LimitKind::Programmed };
    for i in 0..AXES {
        let l = &limits[i];
        let bounds = [
            (l.velocity / q_s[i].abs(), LimitKind::Velocity),
            ((l.acceleration / q_ss[i].abs()).sqrt(), LimitKind::Acceleration),
            ((l.jerk / q_sss[i].abs()).cbrt(), LimitKind::Jerk),
        ];
        for (v, kind) in bounds {
            // NaN (0/0) never binds; +inf (x/0) never binds.
            if v < best.feed {
                best = FeedLimit { feed: v, axis: Some(i), kind };
            }
        }
    }
    best
}
