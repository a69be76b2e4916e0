//! The node logic, free of any transport: what the commander, the simulator and the monitor do with
//! each message. The DDS executables (`nodes/`) and the in-process pipeline ([`inprocess`]) only move
//! these values; one type per concept crosses every layer ([`fiveaxis_msgs::AxisState`]).

pub mod commander;
pub mod inprocess;
pub mod joint_map;
pub mod joint_stream;
pub mod monitor;
pub mod sim_report;
pub mod simulator;

use crate::kinematics::{Joints, Pose};
use crate::machine::Machine;
use crate::path::Segment;
use fiveaxis_msgs::{AxisState, Header, Point, Time, Vector3};

/// The numbers of one [`AxisState`], without its strings: what the commander and the simulator make
/// per sample and hand on in one process (a copy, no allocation); [`StateBuilder::message`] or
/// [`StateBuilder::fill`] turns it into the message where one is sent or recorded.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StateValues {
    /// Program time, s.
    pub t: f64,
    /// Axis values, velocities and accelerations (m, rad; per s, per s^2), in the machine's axis order.
    pub q: Joints,
    pub qd: Joints,
    pub qdd: Joints,
    /// Tool tip in program coordinates (m) and tool axis (unit vector).
    pub tool_tip: [f64; 3],
    pub tool_axis: [f64; 3],
    /// Programmed and actual tool-tip feed, m/s.
    pub programmed_feed: f64,
    pub path_feed: f64,
    pub program_line: u32,
    pub block_number: i64,
    pub motion: u8,
}

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

    /// One sample's numbers: axis values `q` at time `t` (s), velocities and accelerations `qd`,
    /// `qdd`, in segment `seg` (for the program position and datum), with the actual tool-tip speed
    /// `path_feed`.
    #[allow(clippy::too_many_arguments)]
    pub fn values(&self, machine: &Machine, t: f64, q: &Joints, qd: &Joints, qdd: &Joints, seg: Option<&Segment>, path_feed: f64) -> StateValues {
        self.values_at(&machine.forward(q), t, q, qd, qdd, seg, path_feed)
    }

    /// [`StateBuilder::values`] with the forward kinematics of `q` already computed (`pose`).
    #[allow(clippy::too_many_arguments)]
    pub fn values_at(&self, pose: &Pose, t: f64, q: &Joints, qd: &Joints, qdd: &Joints, seg: Option<&Segment>, path_feed: f64) -> StateValues {
        let tip = pose.tip - seg.map_or(nalgebra::Vector3::zeros(), |s| s.datum);
        StateValues {
            t,
            q: *q,
            qd: *qd,
            qdd: *qdd,
            tool_tip: [tip.x, tip.y, tip.z],
            tool_axis: [pose.axis.x, pose.axis.y, pose.axis.z],
            programmed_feed: seg.map_or(0.0, |s| s.feed),
            path_feed,
            program_line: seg.map_or(0, |s| s.line as u32),
            block_number: seg.and_then(|s| s.number).map_or(-1, |n| n as i64),
            motion: seg.map_or(AxisState::MOTION_UNKNOWN, motion_of),
        }
    }

    /// The message of `v`.
    pub fn message(&self, v: &StateValues) -> AxisState {
        let mut st = AxisState { header: Header { stamp: Time::from_secs(0.0), frame_id: self.frame_id.clone() }, name: self.names.clone(), ..Default::default() };
        self.fill(v, &mut st);
        st
    }

    /// Write `v` into `st`, a message of this builder's ([`StateBuilder::message`]): its names and
    /// frame are kept, its vectors reused, so that nothing is allocated per sample.
    pub fn fill(&self, v: &StateValues, st: &mut AxisState) {
        st.header.stamp = Time::from_secs(v.t);
        st.source = self.source;
        for (to, from) in [(&mut st.position, &v.q), (&mut st.velocity, &v.qd), (&mut st.acceleration, &v.qdd)] {
            to.clear();
            to.extend_from_slice(from);
        }
        let [x, y, z] = v.tool_tip;
        st.tool_tip = Point { x, y, z };
        let [x, y, z] = v.tool_axis;
        st.tool_axis = Vector3 { x, y, z };
        st.programmed_feed = v.programmed_feed;
        st.path_feed = v.path_feed;
        st.program_line = v.program_line;
        st.block_number = v.block_number;
        st.motion = v.motion;
    }

    /// One message ([`StateBuilder::values`], [`StateBuilder::message`]).
    #[allow(clippy::too_many_arguments)]
    pub fn state(&self, machine: &Machine, t: f64, q: &Joints, qd: &Joints, qdd: &Joints, seg: Option<&Segment>, path_feed: f64) -> AxisState {
        self.message(&self.values(machine, t, q, qd, qdd, seg, path_feed))
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
