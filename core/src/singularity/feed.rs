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
    FeedLimiter::new(limits).limit(f_prog, q_s, q_ss, q_sss)
}

/// Seed 002 eq. (5) with the machine's limits prepared once (reciprocals), for the per-sample loop.
///
/// `min_i v_i/|q_s_i|` is `1 / max_i |q_s_i| (1/v_i)`, and likewise `min_i sqrt(a_i/|q_ss_i|)` is
/// `sqrt(1 / max_i |q_ss_i| (1/a_i))`: three max-reductions of products, and a root only where that
/// kind of limit binds (checked as `k f^2 > 1`, `k f^3 > 1`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FeedLimiter {
    inv_v: [f64; AXES],
    inv_a: [f64; AXES],
    inv_j: [f64; AXES],
}

#[inline]
fn max_product(d: &[f64; AXES], inv: &[f64; AXES]) -> (f64, usize) {
    let mut best = (0.0, 0);
    for i in 0..AXES {
        let k = d[i].abs() * inv[i];
        if k > best.0 {
            best = (k, i);
        }
    }
    best
}

impl FeedLimiter {
    pub fn new(limits: &[AxisLimits; AXES]) -> FeedLimiter {
        FeedLimiter {
            inv_v: limits.map(|l| 1.0 / l.velocity),
            inv_a: limits.map(|l| 1.0 / l.acceleration),
            inv_j: limits.map(|l| 1.0 / l.jerk),
        }
    }

    /// The limits' reciprocals per axis, `[1/v_max, 1/a_max, 1/j_max]` (the planner's estimate of its
    /// check reads them too).
    pub fn reciprocals(&self) -> [&[f64; AXES]; 3] {
        [&self.inv_v, &self.inv_a, &self.inv_j]
    }

    /// The feed limit and the limiting axis (see [`feed_limit`]).
    #[inline]
    pub fn limit(&self, f_prog: f64, q_s: &[f64; AXES], q_ss: &[f64; AXES], q_sss: &[f64; AXES]) -> FeedLimit {
        let mut best = FeedLimit { feed: f_prog, axis: None, kind: LimitKind::Programmed };
        let (kv, iv) = max_product(q_s, &self.inv_v);
        if kv * best.feed > 1.0 {
            best = FeedLimit { feed: 1.0 / kv, axis: Some(iv), kind: LimitKind::Velocity };
        }
        let (ka, ia) = max_product(q_ss, &self.inv_a);
        if ka * best.feed * best.feed > 1.0 {
            best = FeedLimit { feed: (1.0 / ka).sqrt(), axis: Some(ia), kind: LimitKind::Acceleration };
        }
        let (kj, ij) = max_product(q_sss, &self.inv_j);
        if kj * best.feed * best.feed * best.feed > 1.0 {
            best = FeedLimit { feed: (1.0 / kj).cbrt(), axis: Some(ij), kind: LimitKind::Jerk };
        }
        best
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::machine::Machine;

    /// The root-free comparison picks the same bound as evaluating seed 002 eq. (5) literally.
    #[test]
    fn matches_the_literal_minimum() {
        let limits = Machine::hermle_c600u().limits();
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut rnd = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        for _ in 0..20_000 {
            let mut d = [[0.0; AXES]; 3];
            for row in d.iter_mut() {
                for v in row.iter_mut() {
                    *v = if rnd() < 0.2 { 0.0 } else { (rnd() - 0.5) * 10f64.powf(rnd() * 8.0 - 3.0) };
                }
            }
            let f = rnd() * 0.1;
            let got = feed_limit(f, &d[0], &d[1], &d[2], &limits);
            let mut want = (f, None);
            for i in 0..AXES {
                for (b, _) in [
                    (limits[i].velocity / d[0][i].abs(), 0),
                    ((limits[i].acceleration / d[1][i].abs()).sqrt(), 1),
                    ((limits[i].jerk / d[2][i].abs()).cbrt(), 2),
                ] {
                    if b < want.0 {
                        want = (b, Some(i));
                    }
                }
            }
            assert!((got.feed - want.0).abs() <= 1e-12 * want.0.max(1e-12), "{got:?} vs {want:?}");
            assert_eq!(got.axis, want.1);
        }
    }
}
