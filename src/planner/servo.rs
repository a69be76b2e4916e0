//! Servo model: each axis follows its set-point through a critically damped position loop (two equal
//! first-order lags, time constant `tau`). Its impulse response is positive, so the actual motion never
//! exceeds a velocity, acceleration or jerk bound its set-point respects; the lag is the following error.

use crate::kinematics::Joints;

/// Servo settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ServoConfig {
    /// Time constant of each of the two lags, s (following error ~ 2 tau v).
    pub tau: f64,
}

impl Default for ServoConfig {
    fn default() -> Self {
        ServoConfig { tau: 0.002 }
    }
}

/// Run the set-points `q` (period `t`, at rest before the first) through the servo; continues after
/// the last set-point until every axis is within 1 nm / 1 nrad of it.
pub fn follow(q: &[Joints], t: f64, config: &ServoConfig) -> Vec<Joints> {
    let Some(first) = q.first() else { return Vec::new() };
    let alpha = 1.0 - (-t / config.tau).exp();
    let (mut y1, mut y2) = (*first, *first);
    let mut out = Vec::with_capacity(q.len() + 64);
    let last = *q.last().unwrap();
    let step = |u: &Joints, y1: &mut Joints, y2: &mut Joints| {
        for i in 0..5 {
            y1[i] += (u[i] - y1[i]) * alpha;
            y2[i] += (y1[i] - y2[i]) * alpha;
        }
    };
    for u in q {
        step(u, &mut y1, &mut y2);
        out.push(y2);
    }
    for _ in 0..100_000 {
        if (0..5).all(|i| (last[i] - y2[i]).abs() < 1e-9) {
            break;
        }
        step(&last, &mut y1, &mut y2);
        out.push(y2);
    }
    out
}
