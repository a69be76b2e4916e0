//! The feed a machine stream is judged at: the held-feed histogram that gives the assumed programmed
//! feed, and seed 002 eq. (5) on the divided differences of a program stream.

use super::*;

/// Bins of the held-feed histogram: 2 % wide from 1 mm/min (to about 1.5e4 m/min).
pub(super) const FEED_BINS: usize = 600;
const FEED_BIN_RATIO: f64 = 1.02;

pub(super) fn feed_bin(feed: f64) -> Option<usize> {
    let mm_min = feed / crate::units::MM_PER_MIN;
    (mm_min >= 1.0 && mm_min.is_finite()).then(|| ((mm_min.ln() / FEED_BIN_RATIO.ln()) as usize).min(FEED_BINS - 1))
}

pub(super) fn feed_of_bin(k: usize) -> f64 {
    FEED_BIN_RATIO.powf(k as f64 + 0.5) * crate::units::MM_PER_MIN
}

/// How long a feed must be held to count as the stream's programmed feed when none is given, s.
pub(super) const HELD: f64 = 0.1;

pub(super) fn limit_kind_code(kind: LimitKind) -> u8 {
    match kind {
        LimitKind::Programmed => SingularityStatus::LIMIT_PROGRAMMED,
        LimitKind::Velocity => SingularityStatus::LIMIT_VELOCITY,
        LimitKind::Acceleration => SingularityStatus::LIMIT_ACCELERATION,
        LimitKind::Jerk => SingularityStatus::LIMIT_JERK,
    }
}

/// Seed 002 eq. (5) on divided differences of the last samples with respect to path length.
pub(super) fn feed_limit_from_history(h: &VecDeque<Past>, limiter: &FeedLimiter, f_prog: f64) -> (f64, Option<usize>, LimitKind) {
    let n = h.len();
    if n < 2 || f_prog <= 0.0 {
        return (f_prog, None, LimitKind::Programmed);
    }
    let p = |k: usize| &h[k];
    let ok = |a: &Past, b: &Past| b.s - a.s > 1e-9;
    let mut qs = [0.0; AXES];
    let mut qss = [0.0; AXES];
    let mut qsss = [0.0; AXES];
    if !ok(p(n - 2), p(n - 1)) {
        return (f_prog, None, LimitKind::Programmed);
    }
    // Divided differences (the reciprocals of the path steps once, not per axis).
    let (p1, p2) = (p(n - 1), p(n - 2));
    let inv = |a: &Past, b: &Past| 1.0 / (b.s - a.s);
    let inv21 = inv(p2, p1);
    let third = (n >= 3 && ok(p(n - 3), p2)).then(|| (p(n - 3), inv(p(n - 3), p2), 2.0 / (p1.s - p(n - 3).s)));
    let fourth = third.filter(|_| n >= 4 && ok(p(n - 4), p(n - 3))).map(|(p3, ..)| {
        let p4 = p(n - 4);
        (p4, inv(p4, p3), 2.0 / (p2.s - p4.s), 3.0 / (p1.s - p4.s))
    });
    for i in 0..AXES {
        let d21 = (p1.q[i] - p2.q[i]) * inv21;
        qs[i] = d21;
        if let Some((p3, inv32, k2)) = third {
            let d32 = (p2.q[i] - p3.q[i]) * inv32;
            let s2 = (d21 - d32) * k2;
            qss[i] = s2;
            if let Some((p4, inv43, k2b, k3)) = fourth {
                let s2b = (d32 - (p3.q[i] - p4.q[i]) * inv43) * k2b;
                qsss[i] = (s2 - s2b) * k3;
            }
        }
    }
    let f = limiter.limit(f_prog, &qs, &qss, &qsss);
    (f.feed, f.axis, f.kind)
}
