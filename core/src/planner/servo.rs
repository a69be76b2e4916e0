//! Servo model: each axis follows its set-point through a critically damped position loop (two equal
//! first-order lags, time constant `tau`). Its impulse response is positive, so the actual motion never
//! exceeds a velocity, acceleration or jerk bound its set-point respects; the lag is the following error.
//! At a planned stop the control waits until every axis is in position before the next move starts.

use crate::kinematics::Joints;

/// Servo settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ServoConfig {
    /// Time constant of each of the two lags, s (following error ~ 2 tau v).
    pub tau: f64,
    /// In-position window at a planned stop: linear axes (m) and rotary axes (rad). The next move
    /// starts once every axis is this close to its set-point (exact stop, as G60/G09 on a control).
    pub in_position_m: f64,
    pub in_position_rad: f64,
}

impl Default for ServoConfig {
    fn default() -> Self {
        ServoConfig { tau: 0.002, in_position_m: 1e-6, in_position_rad: 1e-3f64.to_radians() }
    }
}

/// The servo's state: the two lags of each axis.
#[derive(Debug, Clone, Copy)]
pub struct Servo {
    alpha: f64,
    y1: Joints,
    y2: Joints,
}

impl Servo {
    /// At rest at `q`, stepping every `t` seconds.
    pub fn new(q: Joints, t: f64, config: &ServoConfig) -> Servo {
        Servo { alpha: 1.0 - (-t / config.tau).exp(), y1: q, y2: q }
    }

    /// One period towards set-point `u`; the actual position.
    pub fn step(&mut self, u: &Joints) -> Joints {
        for i in 0..5 {
            self.y1[i] += (u[i] - self.y1[i]) * self.alpha;
            self.y2[i] += (self.y1[i] - self.y2[i]) * self.alpha;
        }
        self.y2
    }

    /// True if every axis is within the window of `u` (linear within `m`, rotary within `rad`).
    pub fn in_position(&self, u: &Joints, m: f64, rad: f64) -> bool {
        (0..5).all(|i| (u[i] - self.y2[i]).abs() < if i < 3 { m } else { rad } && (u[i] - self.y1[i]).abs() < if i < 3 { m } else { rad })
    }
}
