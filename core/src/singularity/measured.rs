//! A measured axis stream (a machine bridge's JointState, a control's joint trace) turned into path
//! quantities, one sample at a time: modulo rotary axes unwrapped, the tool tip and tool axis by
//! forward kinematics, the actual tool-tip feed, the measured secondary-axis speed, the kind of motion,
//! and the path's demand on the secondary axis per metre of tool-tip path (seed 001 eq. 5 written as
//! `dC/dt = dC/ds * F`): what the path asks of C at the programmed feed `F`, not what the machine did.
//!
//! Every estimate spans a stretch, never one stamp interval, so that timestamp jitter and send-time
//! stamping do not make spikes: the demand spans [`MeasuredConfig::demand_window`] of tool-tip path
//! (and is attributed to the middle of that stretch), speeds span [`MeasuredConfig::speed_window`] of
//! time. Memory is bounded ([`MeasuredConfig::max_samples`]) whatever the stream's length or feed.

use crate::kinematics::Joints;
use crate::machine::{AxisKind, Machine, AXES};
use nalgebra::Vector3;
use std::collections::VecDeque;
use std::f64::consts::{PI, TAU};

/// What a sample of a stream is doing.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Motion {
    /// Not known (the first samples, before any speed can be measured).
    Unknown,
    /// A rapid (G00) move: the axes run at their limits by definition, not along a cutting path.
    Rapid,
    /// A feed move along a path (the tool tip moves).
    Feed,
    /// The rotary axes turn under a still tool tip (positioning).
    Rotary,
    /// Nothing moves (a dwell, a stop).
    Dwell,
}

impl Motion {
    /// The `motion` code of `fiveaxis_msgs/AxisState` and `SingularityStatus` (MOTION_*).
    pub fn code(self) -> u8 {
        match self {
            Motion::Unknown => 0,
            Motion::Rapid => 1,
            Motion::Feed => 2,
            Motion::Rotary => 3,
            Motion::Dwell => 4,
        }
    }

    /// The inverse of [`Motion::code`] (unknown codes are `Unknown`).
    pub fn from_code(code: u8) -> Motion {
        match code {
            1 => Motion::Rapid,
            2 => Motion::Feed,
            3 => Motion::Rotary,
            4 => Motion::Dwell,
            _ => Motion::Unknown,
        }
    }
}

/// The stated rules of the estimator.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeasuredConfig {
    /// Tool-tip path length over which the secondary axis' change per metre is measured, m
    /// (0.5 mm: half the shortest block of the paper's programs, long enough that a block junction
    /// or a stamp's jitter cannot dominate it).
    pub demand_window: f64,
    /// Time over which speeds (feed, axis speeds) are measured, s (10 ms: ten samples at 1 kHz).
    pub speed_window: f64,
    /// Below this tool-tip speed the tip is still, m/s (1 mm/min).
    pub still_feed: f64,
    /// Also still: a tip moving at less than this share of its *swing* (the sum of the tip speeds
    /// each axis alone would make) while the axes move: the axes compensate each other, as on a
    /// rotary-only move under TCP, and what is left is servo error or the sampling's interpolation
    /// (1 %: on the paper's cut at the pole the tip keeps 7 % of its swing, LinuxCNC's slowed run 5 %).
    pub still_share: f64,
    /// Above this tool-axis turning rate the rotary axes are moving, rad/s (0.1 deg/s).
    pub turning: f64,
    /// Without a program: the tool tip (workpiece frame) above this share of the linear axes' rapid
    /// traverse (the smallest linear velocity limit) is a rapid (cutting feeds lie far below rapid
    /// traverse; the machine axes are not judged, since near the singularity the path itself swings
    /// the linear axes with the turning part and drives the rotary axes to their limit).
    pub rapid_share: f64,
    /// Most samples kept (bounds memory at very low feeds).
    pub max_samples: usize,
}

impl Default for MeasuredConfig {
    fn default() -> Self {
        MeasuredConfig { demand_window: 0.5e-3, speed_window: 0.010, still_feed: crate::units::MM_PER_MIN, still_share: 0.01, turning: 0.1f64.to_radians(), rapid_share: 0.5, max_samples: 8192 }
    }
}

/// Kept samples searched back for the start of a demand window.
const SEARCH: usize = 256;

/// One sample of the measured path.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeasuredSample {
    /// Axis positions with modulo rotary axes unwrapped (continuous), SI.
    pub q: Joints,
    /// Tool tip (workpiece frame, m) and unit tool axis, by forward kinematics.
    pub tip: Vector3<f64>,
    pub axis: Vector3<f64>,
    /// Tool-tip path length since the start of the stream, m.
    pub s: f64,
    /// Actual tool-tip speed over the speed window, m/s.
    pub path_feed: f64,
    /// Measured secondary-axis speed over the speed window, rad/s.
    pub c_speed: f64,
    /// What the sample is doing, by the stream's own motion (see [`MeasuredConfig`]).
    pub motion: Motion,
    /// The tool axis turns (faster than [`MeasuredConfig::turning`]): with the tip moving, a
    /// simultaneous five-axis move.
    pub turning: bool,
    /// The secondary axis' change per metre of tool-tip path over the demand window (rad/m), and the
    /// tool tip and tool axis in the middle of that stretch (where the estimate belongs). None until a
    /// whole window of path has been travelled since the start or the last rotary-only move.
    pub demand: Option<Demand>,
}

/// The path's demand on the secondary axis, measured over a stretch of path and attributed to the
/// sample in its middle: everything here is that sample's (a lag of half the window of path), so that
/// a region's x range, feeds and times all belong to the same samples.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Demand {
    /// dC/ds, rad/m (machine sign).
    pub per_metre: f64,
    /// How far the middle sample's tool tip may be off, m (0 on exact samples; a per-axis merge's
    /// interpolation uncertainty carried through the kinematics, [`crate::sampling`]).
    pub tip_uncertainty: f64,
    /// Every axis' first and second derivative with respect to path length over the window (the
    /// second from the two halves' first derivatives): the geometry seed 002 eq. (5) needs.
    pub q_s: Joints,
    pub q_ss: Joints,
    pub t: f64,
    pub s: f64,
    pub tip: Vector3<f64>,
    pub axis: Vector3<f64>,
    pub path_feed: f64,
    pub motion: Motion,
    pub turning: bool,
}

#[derive(Debug, Clone, Copy)]
struct Kept {
    t: f64,
    s: f64,
    /// How far the tool tip may be off, m.
    tip_sigma: f64,
    q: Joints,
    tip: Vector3<f64>,
    axis: Vector3<f64>,
    path_feed: f64,
    motion: Motion,
    turning: bool,
}

/// The estimator's state for one stream.
#[derive(Debug, Clone)]
pub struct MeasuredPath {
    config: MeasuredConfig,
    secondary: usize,
    unlimited: [bool; AXES],
    /// The linear axes' rapid traverse (their smallest velocity limit), m/s.
    rapid_traverse: f64,
    /// Raw previous positions and the unwrap offsets (multiples of 2 pi) of each axis.
    raw: Option<Joints>,
    offset: Joints,
    s: f64,
    /// Samples since the last rotary-only move, back to at least one demand window and one speed window.
    kept: VecDeque<Kept>,
    /// The rotary axes' indices, for the swing.
    rotary: Vec<usize>,
    /// The previous sample was a rotary-only move: the step from it mixes the turn with the path.
    after_stop: bool,
}

impl MeasuredPath {
    pub fn new(machine: &Machine, config: MeasuredConfig) -> MeasuredPath {
        MeasuredPath {
            config,
            secondary: machine.secondary_axis(),
            unlimited: std::array::from_fn(|i| machine.axes[i].kind == AxisKind::Rotary && machine.axes[i].limits.is_unlimited()),
            rapid_traverse: (0..3).map(|i| machine.axes[i].limits.velocity).fold(f64::INFINITY, f64::min),
            raw: None,
            offset: [0.0; AXES],
            s: 0.0,
            kept: VecDeque::new(),
            rotary: (0..AXES).filter(|&i| machine.axes[i].kind == AxisKind::Rotary).collect(),
            after_stop: false,
        }
    }

    /// Start again (a restarted publisher, a new session): nothing of the past is used.
    pub fn reset(&mut self) {
        self.raw = None;
        self.offset = [0.0; AXES];
        self.s = 0.0;
        self.kept.clear();
        self.after_stop = false;
    }

    /// The unwrapped value of a raw position of axis `i`: a multi-turn rotary axis that a control
    /// reports modulo 360 deg jumps by about a turn between two samples; no axis can turn half a turn
    /// in one sample period, so a step beyond 180 deg is taken as a wrap.
    fn unwrap(&mut self, q: &Joints) -> Joints {
        if let Some(prev) = self.raw {
            for i in 0..AXES {
                if self.unlimited[i] {
                    let step = q[i] - prev[i];
                    if step > PI {
                        self.offset[i] -= TAU * ((step + PI) / TAU).floor();
                    } else if step < -PI {
                        self.offset[i] += TAU * ((-step + PI) / TAU).floor();
                    }
                }
            }
        }
        self.raw = Some(*q);
        std::array::from_fn(|i| q[i] + self.offset[i])
    }

    /// Take one sample: stamp `t` (s, increasing), raw axis positions (SI) and how far each may be
    /// off (SI; zeros for exact samples, a per-axis merge's interpolation uncertainty otherwise).
    /// `rapid` says, where a program is known, that the sample belongs to a rapid move (None: judge
    /// by the stream).
    pub fn push(&mut self, machine: &Machine, t: f64, raw: &Joints, sigma: &Joints, rapid: Option<bool>) -> MeasuredSample {
        let q = self.unwrap(raw);
        let pose = machine.forward(&q);
        let (tip, axis) = (pose.tip, pose.axis);
        // The tip's uncertainty: each linear axis' own, each rotary axis' swung by the tip's distance
        // from it (forward kinematics of that axis' uncertainty alone).
        let tip_sigma = if sigma.iter().any(|s| *s > 0.0) {
            (0..AXES)
                .filter(|&i| sigma[i] > 0.0)
                .map(|i| {
                    if self.rotary.contains(&i) {
                        let mut off = q;
                        off[i] += sigma[i];
                        (machine.forward(&off).tip - tip).norm()
                    } else {
                        sigma[i]
                    }
                })
                .sum()
        } else {
            0.0
        };
        if let Some(last) = self.kept.back() {
            self.s += (tip - last.tip).norm();
        }
        let now = Kept { t, s: self.s, tip_sigma, q, tip, axis, path_feed: 0.0, motion: Motion::Unknown, turning: false };
        self.kept.push_back(now);
        let c = &self.config;
        // Drop what neither window needs any more (the front is the newest sample outside both).
        // Two windows of path are kept: the demand's window is one of displacement, which a path
        // that curves within it takes more path to fill.
        // The demand's window ends one sample back (see below): its path counts from there.
        while self.kept.len() > 3 && (self.kept[self.kept.len() - 2].s - self.kept[1].s >= 2.0 * c.demand_window && t - self.kept[1].t >= c.speed_window || self.kept.len() > c.max_samples) {
            self.kept.pop_front();
        }
        // Speeds over the speed window: from the newest kept sample at least that old.
        let back = self.kept.iter().rev().skip(1).find(|k| t - k.t >= c.speed_window).or_else(|| self.kept.front().filter(|k| k.t < t));
        let (path_feed, c_speed, turn, linear_share, swing) = match back {
            Some(b) => {
                let dt = t - b.t;
                let feed = (self.s - b.s) / dt;
                // A rapid is fast tool-tip motion in the workpiece frame, never fast linear axes
                // swinging with a part that turns under the tool.
                let share = feed / self.rapid_traverse;
                // The swing: linear axes move the tip by their own step, a rotary axis by its step
                // times the tip's distance from it (forward kinematics of that axis' step alone).
                let swing = if feed >= c.still_feed {
                    let linear: f64 = (0..AXES).filter(|i| !self.rotary.contains(i)).map(|i| (q[i] - b.q[i]).abs()).sum();
                    // (An axis that did not move adds nothing: no kinematics for it.)
                    let rotary: f64 = self
                        .rotary
                        .iter()
                        .filter(|&&i| q[i] != b.q[i])
                        .map(|&i| {
                            let mut alone = b.q;
                            alone[i] = q[i];
                            (machine.forward(&alone).tip - b.tip).norm()
                        })
                        .sum();
                    (linear + rotary) / dt
                } else {
                    0.0
                };
                (feed, (q[self.secondary] - b.q[self.secondary]) / dt, (axis - b.axis).norm() / dt, share, swing)
            }
            None => (0.0, 0.0, 0.0, 0.0, 0.0),
        };
        let motion = match back {
            None => Motion::Unknown,
            Some(_) if rapid == Some(true) => Motion::Rapid,
            Some(_) if path_feed < c.still_feed || path_feed < c.still_share * swing => {
                if turn > c.turning {
                    Motion::Rotary
                } else {
                    Motion::Dwell
                }
            }
            Some(_) if rapid.is_none() && linear_share > c.rapid_share => Motion::Rapid,
            Some(_) => Motion::Feed,
        };
        if let Some(k) = self.kept.back_mut() {
            (k.path_feed, k.motion, k.turning) = (path_feed, motion, turn > c.turning);
        }
        // A rotary-only move changes C without path: a stretch that contains one measures no path's
        // demand. Start the demand window again after it, at the first sample of the move that
        // follows (the step into it mixes the turn's end with the path's start).
        if motion == Motion::Rotary || (motion == Motion::Feed && self.after_stop) {
            let keep = self.kept.len().saturating_sub(1);
            self.kept.drain(..keep);
        }
        self.after_stop = motion == Motion::Rotary;
        // The newest step is judged by the next sample: the step into a rotary-only move mixes the
        // path's end with the turn's start, so the demand ends one sample back and a turn starting
        // next withholds it.
        let demand = if motion == Motion::Rotary { None } else { self.demand(self.kept.len() - 1) };
        MeasuredSample { q, tip, axis, s: self.s, path_feed, c_speed, motion, turning: turn > c.turning, demand }
    }

    /// dC/ds over the last demand window ending at kept sample `end - 1`, attributed to the window's
    /// middle. The window must reach one window of tool-tip *displacement* (dC is then taken per
    /// metre of the path within it): noise about a still point (servo error, a sparse stream's
    /// interpolation) fills no window however long it goes on, where the path summed over it would.
    fn demand(&self, end: usize) -> Option<Demand> {
        let c = &self.config;
        let last = self.kept.get(end.checked_sub(1)?)?;
        // The newest kept sample at least one window of displacement back: at least a window of path
        // back too (a chord is no longer than its path); the search is bounded, a tip that has
        // wandered about for longer than that has no window.
        let within = self.kept.partition_point(|k| last.s - k.s >= c.demand_window).min(end - 1);
        let first = self.kept.range(..within).rev().take(SEARCH).find(|k| (last.tip - k.tip).norm() >= c.demand_window)?;
        let ds = last.s - first.s;
        let m = self.kept.partition_point(|k| k.s < last.s - ds / 2.0).min(end - 1);
        let mid = &self.kept[m];
        let (h1, h2) = (mid.s - first.s, last.s - mid.s);
        let q_s: Joints = std::array::from_fn(|i| (last.q[i] - first.q[i]) / ds);
        let q_ss: Joints = std::array::from_fn(|i| {
            if h1 > 0.0 && h2 > 0.0 {
                ((last.q[i] - mid.q[i]) / h2 - (mid.q[i] - first.q[i]) / h1) / (ds / 2.0)
            } else {
                0.0
            }
        });
        Some(Demand {
            per_metre: q_s[self.secondary],
            tip_uncertainty: mid.tip_sigma,
            q_s,
            q_ss,
            t: mid.t,
            s: mid.s,
            tip: mid.tip,
            axis: mid.axis,
            path_feed: mid.path_feed,
            motion: mid.motion,
            turning: mid.turning,
        })
    }
}
