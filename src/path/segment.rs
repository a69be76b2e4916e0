//! Blocks -> segments: resolve each move's start and end axis values, length and duration.

use super::{PathOptions, Sample};
use crate::kinematics::{Joints, Pose};
use crate::machine::Machine;
use crate::program::{Block, Diagnostic, FeedMode, Motion, Program, Severity};
use crate::units::{DEG_PER_MIN, MM_PER_MIN};
use nalgebra::Vector3;

/// How a segment moves.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SegmentKind {
    /// G00: every axis linear, the slowest at its maximum velocity.
    Rapid,
    /// Feed move with tool-centre-point management: tip on a line in the workpiece, rotaries linear.
    Tcp,
    /// Feed move without TCPM: machine axes linear.
    Axes,
}

/// One move of the program.
#[derive(Debug, Clone, PartialEq)]
pub struct Segment {
    pub kind: SegmentKind,
    /// Index of the block in [`Program::blocks`], its line and number.
    pub block: usize,
    pub line: usize,
    pub number: Option<u64>,
    /// Start time and duration, s.
    pub t0: f64,
    pub duration: f64,
    /// Tool-tip path length at the start and length of this move (workpiece frame), m.
    pub s0: f64,
    pub length: f64,
    pub q0: Joints,
    pub q1: Joints,
    /// Tool tip at start and end, program coordinates, m.
    pub tip0: Vector3<f64>,
    pub tip1: Vector3<f64>,
    /// Datum shift in effect, m.
    pub datum: Vector3<f64>,
    /// Programmed tool-tip feed, m/s (0 for rapid and rotary-only moves).
    pub feed: f64,
}

impl Segment {
    /// True for a simultaneous five-axis feed move: the programmed linear motion (the tool tip under
    /// TCPM, the linear machine axes without it) and the rotary axes both move. A rotary-only move
    /// without TCPM (the table turning under a retracted tool) is positioning, not five-axis.
    pub fn is_five_axis(&self) -> bool {
        let rotates = (self.q1[3] - self.q0[3]).abs() > 1e-12 || (self.q1[4] - self.q0[4]).abs() > 1e-12;
        rotates && self.is_path_move()
    }

    /// True for a feed move along a programmed path: the tool tip (TCPM) or the linear machine axes
    /// (no TCPM) move. Rapids and rotary-only moves are not path moves.
    pub fn is_path_move(&self) -> bool {
        match self.kind {
            SegmentKind::Rapid => false,
            SegmentKind::Tcp => self.length > 1e-9,
            SegmentKind::Axes => (0..3).any(|i| (self.q1[i] - self.q0[i]).abs() > 1e-12),
        }
    }

    /// Axis values at fraction `u` of the move.
    pub fn joints_at(&self, u: f64, machine: &Machine) -> Joints {
        let lerp = |a: f64, b: f64| a + (b - a) * u;
        let rot = [lerp(self.q0[3], self.q1[3]), lerp(self.q0[4], self.q1[4])];
        match self.kind {
            SegmentKind::Tcp => {
                let tip = self.tip0 + (self.tip1 - self.tip0) * u + self.datum;
                let l = machine.chain.linear_for(&tip, &rot);
                [l.x, l.y, l.z, rot[0], rot[1]]
            }
            _ => std::array::from_fn(|i| lerp(self.q0[i], self.q1[i])),
        }
    }

    /// The commanded sample at fraction `u` (time `t`); `index` is this segment's index.
    pub fn sample(&self, index: usize, u: f64, t: f64, machine: &Machine) -> Sample {
        let q = self.joints_at(u, machine);
        let rot = [q[3], q[4]];
        let rate = [(self.q1[3] - self.q0[3]) / self.duration, (self.q1[4] - self.q0[4]) / self.duration];
        let tip = match self.kind {
            SegmentKind::Tcp => self.tip0 + (self.tip1 - self.tip0) * u,
            _ => machine.forward(&q).tip - self.datum,
        };
        Sample {
            t,
            s: self.s0 + self.length * u,
            segment: index,
            q,
            tip,
            axis: machine.chain.orientation(&rot),
            axis_rate: machine.chain.orientation_rate(&rot, &rate),
            feed: self.feed,
        }
    }
}

/// Tool-tip moves shorter than this (m) are program rounding when the rotaries turn.
const MIN_PATH: f64 = 1e-6;

fn diag(b: &Block, message: String) -> Diagnostic {
    Diagnostic { line: b.line, column: b.column, severity: Severity::Error, message }
}

/// Plan every motion block of `program` on `machine`, starting from all axes at zero.
/// Blocks that cannot be run (an axis the machine lacks, an unreachable pose) are reported and skipped.
pub fn plan(program: &Program, machine: &Machine, options: &PathOptions) -> (Vec<Segment>, Vec<Diagnostic>) {
    let mut segments = Vec::new();
    let mut diags = Vec::new();
    let mut q: Joints = [0.0; 5];
    let mut t = 0.0;
    let mut s = 0.0;
    let letters: [char; 2] = [3, 4].map(|i| machine.axes[i].name.chars().next().unwrap_or('?').to_ascii_uppercase());
    let mut first_orientation = true;

    for (bi, b) in program.blocks.iter().enumerate() {
        if b.targets.is_empty() {
            continue;
        }
        if let Some(l) = ['A', 'B', 'C'].into_iter().find(|l| b.targets.rotary(*l).is_some() && !letters.contains(l)) {
            diags.push(diag(b, format!("axis {l} does not exist on machine {}: block skipped", machine.name)));
            continue;
        }
        let datum = Vector3::from(b.datum);
        let tcp = b.tcp;
        let tip0 = machine.forward(&q).tip - datum;
        let mut rot1 = [q[3], q[4]];
        for slot in 0..2 {
            if let Some(v) = b.targets.rotary(letters[slot]) {
                rot1[slot] = v;
            }
        }
        let q1: Joints;
        let tip1: Vector3<f64>;
        if tcp {
            let tip = Vector3::new(b.targets.x.unwrap_or(tip0.x), b.targets.y.unwrap_or(tip0.y), b.targets.z.unwrap_or(tip0.z));
            if let Some(axis) = b.targets.tool_axis {
                let pose = Pose { tip: tip + datum, axis: Vector3::from(axis) };
                let mut previous = q;
                if first_orientation {
                    // First pose: the + sign of seed 001 Table 1 (non-negative primary angle).
                    if let Ok(all) = machine.inverse_all(&pose) {
                        let p = machine.primary_axis();
                        let pick = if all[0][p] >= 0.0 { all[0] } else { all[1] };
                        previous[3] = pick[3];
                        previous[4] = pick[4];
                    }
                }
                match machine.inverse(&pose, &previous) {
                    Ok(sol) => rot1 = [sol[3], sol[4]],
                    Err(e) => {
                        diags.push(diag(b, format!("tool pose cannot be reached: {e}; block skipped")));
                        continue;
                    }
                }
                first_orientation = false;
            }
            let l = machine.chain.linear_for(&(tip + datum), &rot1);
            q1 = [l.x, l.y, l.z, rot1[0], rot1[1]];
            tip1 = tip;
        } else {
            let lin = |k: usize, w: Option<f64>| w.map_or(q[k], |v| v + datum[k]);
            q1 = [lin(0, b.targets.x), lin(1, b.targets.y), lin(2, b.targets.z), rot1[0], rot1[1]];
            tip1 = machine.forward(&q1).tip - datum;
        }
        if let Some((i, _)) = q1.iter().enumerate().find(|(i, v)| !machine.axes[*i].limits.contains(**v)) {
            let a = &machine.axes[i];
            let (v, unit, f) = if i < 3 { (q1[i], "mm", 1e3) } else { (q1[i], "deg", 1f64.to_degrees()) };
            diags.push(diag(
                b,
                format!(
                    "axis {} would move to {:.3} {unit}, outside its range {:.3}..{:.3} {unit}: block skipped",
                    a.name,
                    v * f,
                    a.limits.min * f,
                    a.limits.max * f
                ),
            ));
            continue;
        }
        // Tool-tip length in the workpiece: a TCP move is a line; otherwise integrate along the move.
        let kind = match (b.motion, tcp) {
            (Motion::Rapid, _) => SegmentKind::Rapid,
            (Motion::Linear, true) => SegmentKind::Tcp,
            (Motion::Linear, false) => SegmentKind::Axes,
        };
        let mut seg = Segment {
            kind,
            block: bi,
            line: b.line,
            number: b.number,
            t0: t,
            duration: 0.0,
            s0: s,
            length: 0.0,
            q0: q,
            q1,
            tip0,
            tip1,
            datum,
            feed: 0.0,
        };
        seg.length = tip_length(&seg, machine);
        let lin_len = ((q1[0] - q[0]).powi(2) + (q1[1] - q[1]).powi(2) + (q1[2] - q[2]).powi(2)).sqrt();
        let rot_len = ((q1[3] - q[3]).powi(2) + (q1[4] - q[4]).powi(2)).sqrt();
        let duration = match kind {
            SegmentKind::Rapid => (0..5)
                .map(|i| (q1[i] - q[i]).abs() / machine.axes[i].limits.velocity)
                .fold(0.0, f64::max),
            _ => {
                let Some(feed) = b.feed else {
                    diags.push(diag(b, "feed move without a feed: block skipped".into()));
                    continue;
                };
                match feed.mode {
                    FeedMode::InverseTime => 60.0 / feed.value_per_min,
                    FeedMode::PerMinute => {
                        let path_len = if kind == SegmentKind::Tcp { seg.length } else { lin_len };
                        // A tip move under 1 um that turns the rotaries is rounding in the program's
                        // coordinates, not a path: it is a rotary move (F in deg/min).
                        let rounding = path_len < MIN_PATH && rot_len > 1e-9;
                        if path_len > 1e-9 && !rounding {
                            let f = options.feed_override_mm_per_min.unwrap_or(feed.value_per_min) * MM_PER_MIN;
                            seg.feed = seg.length / (path_len / f);
                            path_len / f
                        } else {
                            // Rotary axes only: F is read in degrees per minute.
                            rot_len / (feed.value_per_min * DEG_PER_MIN)
                        }
                    }
                }
            }
        };
        if !(duration > 1e-12) {
            continue; // nothing moves
        }
        if t + duration > options.max_duration_s {
            let what = match (kind, b.feed) {
                (SegmentKind::Rapid, _) => "this rapid move".to_string(),
                (_, Some(f)) if f.mode == FeedMode::InverseTime => format!("this move (inverse-time F{})", f.value_per_min),
                (_, Some(f)) => format!("this move (F{} over {:.3} mm)", options.feed_override_mm_per_min.unwrap_or(f.value_per_min), seg.length * 1e3),
                (_, None) => "this move".to_string(),
            };
            diags.push(diag(
                b,
                format!(
                    "{what} takes {:.1} h and would make the program run {:.1} h, beyond the bound of {:.1} h: \
                     a feed typo? planning stops here (raise the bound with --max-program-hours if the program is meant to run this long)",
                    duration / 3600.0,
                    (t + duration) / 3600.0,
                    options.max_duration_s / 3600.0
                ),
            ));
            break;
        }
        if seg.feed == 0.0 {
            // Rapid, inverse-time and rotary-only moves: the tool-tip speed they result in.
            seg.feed = seg.length / duration;
        }
        seg.duration = duration;
        t += duration;
        s += seg.length;
        q = q1;
        segments.push(seg);
    }
    (segments, diags)
}

/// Tool-tip path length of a segment in the workpiece frame (exact for TCP moves, else integrated).
fn tip_length(seg: &Segment, machine: &Machine) -> f64 {
    if seg.kind == SegmentKind::Tcp {
        return (seg.tip1 - seg.tip0).norm();
    }
    const N: usize = 64;
    let mut len = 0.0;
    let mut prev = machine.forward(&seg.q0).tip;
    for k in 1..=N {
        let u = k as f64 / N as f64;
        let q: Joints = std::array::from_fn(|i| seg.q0[i] + (seg.q1[i] - seg.q0[i]) * u);
        let p = machine.forward(&q).tip;
        len += (p - prev).norm();
        prev = p;
    }
    len
}
