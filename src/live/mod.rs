//! The node logic, free of any transport: what the commander, the simulator and the monitor do with
//! each message. The DDS executables (`nodes/`) and the in-process pipeline ([`inprocess`]) only move
//! these values; one type per concept crosses every layer ([`fiveaxis_msgs::AxisState`]).

pub mod commander;
pub mod inprocess;
pub mod monitor;
pub mod sim_report;
pub mod simulator;

use crate::kinematics::Joints;
use crate::machine::Machine;
use crate::path::Segment;
use fiveaxis_msgs::{AxisState, Header, Point, Time, Vector3};

/// Builds [`AxisState`] messages for one machine and source.
#[derive(Debug, Clone)]
pub struct StateBuilder {
    names: Vec<String>,
    source: u8,
    frame_id: String,
}

impl StateBuilder {
    pub fn new(machine: &Machine, source: u8) -> StateBuilder {
        StateBuilder { names: machine.axis_names().to_vec(), source, frame_id: "workpiece".into() }
    }

    /// One message: axis values `q` at time `t` (s), velocities and accelerations `qd`, `qdd`, in
    /// segment `seg` (for the program position and datum), with the actual tool-tip speed `path_feed`.
    #[allow(clippy::too_many_arguments)]
    pub fn state(&self, machine: &Machine, t: f64, q: &Joints, qd: &Joints, qdd: &Joints, seg: Option<&Segment>, path_feed: f64) -> AxisState {
        let pose = machine.forward(q);
        let tip = pose.tip - seg.map_or(nalgebra::Vector3::zeros(), |s| s.datum);
        AxisState {
            header: Header { stamp: Time::from_secs(t), frame_id: self.frame_id.clone() },
            source: self.source,
            name: self.names.clone(),
            position: q.to_vec(),
            velocity: qd.to_vec(),
            acceleration: qdd.to_vec(),
            tool_tip: Point { x: tip.x, y: tip.y, z: tip.z },
            tool_axis: Vector3 { x: pose.axis.x, y: pose.axis.y, z: pose.axis.z },
            programmed_feed: seg.map_or(0.0, |s| s.feed),
            path_feed,
            program_line: seg.map_or(0, |s| s.line as u32),
            block_number: seg.and_then(|s| s.number).map_or(-1, |n| n as i64),
            motion: seg.map_or(AxisState::MOTION_UNKNOWN, motion_of),
        }
    }
}

/// The `motion` code of a program move: rapid, feed along a path, rotary-only, or a dwell (nothing
/// moves).
pub fn motion_of(seg: &Segment) -> u8 {
    if seg.kind == crate::path::SegmentKind::Rapid {
        AxisState::MOTION_RAPID
    } else if seg.is_path_move() {
        AxisState::MOTION_FEED
    } else if (0..crate::machine::AXES).any(|i| (seg.q1[i] - seg.q0[i]).abs() > 1e-12) {
        AxisState::MOTION_ROTARY
    } else {
        AxisState::MOTION_DWELL
    }
}

/// Velocity and acceleration of sample `k` of `n` positions `q(j)` sampled at period `t`: central
/// finite differences, one-sided (velocity) and zero (acceleration) at the ends. The one formula of
/// the commanded and simulated streams, computed per sample so that no stream is held whole.
pub fn derivatives_at(n: usize, k: usize, t: f64, q: impl Fn(usize) -> Joints) -> (Joints, Joints) {
    let end = k == 0 || k + 1 >= n;
    let (m, p0, p) = (q(k.saturating_sub(1)), q(k), q((k + 1).min(n.saturating_sub(1))));
    let span = if end { t } else { 2.0 * t };
    (
        std::array::from_fn(|i| (p[i] - m[i]) / span),
        std::array::from_fn(|i| if end { 0.0 } else { (p[i] - 2.0 * p0[i] + m[i]) / (t * t) }),
    )
}

/// Central finite differences (one-sided at the ends) of positions sampled at period `t`:
/// velocities and accelerations ([`derivatives_at`] for every sample).
pub fn differentiate(q: &[Joints], t: f64) -> (Vec<Joints>, Vec<Joints>) {
    (0..q.len()).map(|k| derivatives_at(q.len(), k, t, |j| q[j])).unzip()
}
