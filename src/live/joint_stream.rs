//! A machine bridge's `JointState` stream made into whole poses: each message's mapped joints are
//! reports of those axes at its stamp (a message may carry some joints only: legal in ROS, what a
//! change-only bridge publishes), merged per axis into poses at common instants by
//! [`fiveaxis_core::sampling::PoseMerger`]. One rule for the live monitor, the Rerun bridge,
//! `analyze` and `replay`.

use super::joint_map::JointMap;
use super::monitor::Rejection;
use crate::machine::{AxisKind, Machine, AXES};
use fiveaxis_core::sampling::{MergeConfig, MergeError, PoseMerger};
use fiveaxis_msgs::{AxisState, Header, JointState, Time};
use crate::kinematics::Joints;
use std::collections::VecDeque;

/// Time an axis may stay unreported at a stream's start before its messages are refused as missing
/// that joint (s, of arrival: a source's snapshot of its last values, such as an MTConnect agent's
/// /current, arrives at once but is stamped over however long ago each axis last changed): the
/// slowest rate machine data come at, with the merge's margin.
pub const FIRST_REPORT_WITHIN_S: f64 = 1.5;

/// One JointState stream's merge.
#[derive(Debug, Clone)]
pub struct JointStream {
    merger: PoseMerger,
    names: Vec<String>,
    /// What the source calls each axis (a JointState's joint, an MTConnect data item), for the
    /// error of one never reported.
    joints: Vec<String>,
    frame_id: String,
    /// Stamps are merged relative to the first one's whole seconds (full f64 resolution).
    base: TimeBase,
    /// Arrival of the first message (of this session).
    first: Option<f64>,
    /// Messages before every axis had been reported, not yet refused.
    waiting: u64,
    /// Poses made, oldest first.
    ready: VecDeque<Merged>,
    /// Arrival time of the last message (any monotonic clock, s).
    last_wall: Option<f64>,
}

impl JointStream {
    /// The merge for `machine` (multi-turn rotary axes unwrapped before interpolating), whose
    /// axes the source calls `joints` (in the machine's axis order).
    pub fn new(machine: &Machine, joints: &[String]) -> JointStream {
        let wrap = std::array::from_fn(|i| machine.axes[i].kind == AxisKind::Rotary && machine.axes[i].limits.is_unlimited());
        let range = std::array::from_fn(|i| (machine.axes[i].limits.min, machine.axes[i].limits.max));
        JointStream {
            merger: PoseMerger::new(MergeConfig { wrap, range, ..MergeConfig::default() }),
            names: machine.axis_names().to_vec(),
            joints: joints.to_vec(),
            frame_id: String::new(),
            base: TimeBase { sec: None },
            first: None,
            waiting: 0,
            ready: VecDeque::new(),
            last_wall: None,
        }
    }

    /// Take one message arriving at `wall` (s, monotonic); `restart_after`: a message stamped no
    /// later than the last after this much silence is a restarted publisher (the merge starts
    /// again) rather than out of order. Poses made go to [`JointStream::pop`].
    pub fn push(&mut self, map: &JointMap, js: &JointState, wall: f64, restart_after: f64) -> Result<(), Rejection> {
        let values = map.reports(js)?;
        self.push_values(js.header.stamp, &js.header.frame_id, &values, wall, restart_after)
    }

    /// [`JointStream::push`] of axis positions already mapped (SI, None where not reported): an
    /// MTConnect adapter's line, an OPC UA notification.
    pub fn push_values(&mut self, stamp: Time, frame_id: &str, values: &[Option<f64>; AXES], wall: f64, restart_after: f64) -> Result<(), Rejection> {
        if stamp.nanosec >= 1_000_000_000 {
            return Err(Rejection::Invalid("header stamp nanosec out of range".into()));
        }
        let base = *self.base.sec.get_or_insert(i64::from(stamp.sec));
        let t = (i64::from(stamp.sec) - base) as f64 + f64::from(stamp.nanosec) * 1e-9;
        let silent = self.last_wall.is_some_and(|w| wall - w > restart_after);
        if silent && self.merger.last_stamp().is_some_and(|last| t <= last) {
            self.restart();
        }
        if self.frame_id != frame_id {
            self.frame_id = frame_id.to_string();
        }
        let (base, names, frame, ready) = (self.base, &self.names, &self.frame_id, &mut self.ready);
        let result = self.merger.push(t, values, |at, q, uncertainty| ready.push_back(Merged { state: base.state(at, &q, names, frame), uncertainty, arrival: wall }));
        match result {
            Err(MergeError::OutOfOrder { stamp, last }) => return Err(Rejection::OutOfOrder { stamp, last }),
            Err(MergeError::NonFinite { axis, value }) => return Err(Rejection::NonFinite(format!("{} position is {value}", self.names[axis]))),
            Err(MergeError::Empty) => return Err(self.missing()),
            Ok(()) => {}
        }
        self.last_wall = Some(wall);
        let first = *self.first.get_or_insert(wall);
        if !self.merger.all_reported() {
            // An axis not reported yet: wait for it a while, then refuse its messages.
            if wall - first <= FIRST_REPORT_WITHIN_S {
                self.waiting += 1;
                return Ok(());
            }
            return Err(self.missing());
        }
        self.waiting = 0;
        Ok(())
    }

    /// The joint of the first axis never reported.
    fn missing(&self) -> Rejection {
        let axis = (0..AXES).find(|&i| !self.merger.reported(i)).unwrap_or(0);
        Rejection::MissingJoint(self.joints[axis].clone())
    }

    /// A new session of the source (its clock starts over): what waits is made, then the merge
    /// starts again.
    pub fn restart(&mut self) {
        self.flush();
        self.merger.reset();
        self.first = None;
        self.waiting = 0;
    }

    /// The next pose made, oldest first.
    pub fn pop(&mut self) -> Option<Merged> {
        self.ready.pop_front()
    }

    /// Make every waiting instant with what is known (the stream ended or fell silent).
    pub fn flush(&mut self) {
        let (base, names, frame, ready, arrival) = (self.base, &self.names, &self.frame_id, &mut self.ready, self.last_wall.unwrap_or(0.0));
        self.merger.flush(|at, q, uncertainty| ready.push_back(Merged { state: base.state(at, &q, names, frame), uncertainty, arrival }));
    }

    /// Messages still waiting at the end for an axis never reported: refused as missing it (the
    /// count, and the rejection), once.
    pub fn unplaced(&mut self) -> Option<(u64, Rejection)> {
        let n = std::mem::take(&mut self.waiting);
        (n > 0 && !self.merger.all_reported()).then(|| (n, self.missing()))
    }

    /// The longest an instant waited for every axis to be known, s (the latency the merge cost).
    pub fn max_latency(&self) -> f64 {
        self.merger.max_latency()
    }

    /// Arrival time of the last message.
    pub fn last_wall(&self) -> Option<f64> {
        self.last_wall
    }

    /// The merge's current wait, s.
    pub fn latency(&self) -> f64 {
        self.merger.latency()
    }

    /// Poses waiting to be made.
    pub fn has_pending(&self) -> bool {
        self.merger.has_pending()
    }
}

/// A pose merged from per-axis reports, and how far each axis' value in it may be off (SI: the
/// merge's interpolation uncertainty, 0 at an axis' own report).
#[derive(Debug, Clone)]
pub struct Merged {
    pub state: AxisState,
    pub uncertainty: Joints,
    /// Arrival of the report that completed it (s, the caller's clock): a pose made because its
    /// stream fell silent carries the last report's, for it says nothing of the source being alive.
    pub arrival: f64,
}

/// A stream's clock base: merge times are seconds after its whole second `sec`.
#[derive(Debug, Clone, Copy)]
struct TimeBase {
    sec: Option<i64>,
}

impl TimeBase {
    fn time(self, t: f64) -> Time {
        let whole = t.floor();
        let mut nanosec = ((t - whole) * 1e9).round() as i64;
        let mut sec = self.sec.unwrap_or(0) + whole as i64;
        if nanosec >= 1_000_000_000 {
            nanosec -= 1_000_000_000;
            sec += 1;
        }
        Time { sec: sec.clamp(i32::MIN.into(), i32::MAX.into()) as i32, nanosec: nanosec as u32 }
    }

    /// A merged pose as a machine stream's AxisState (positions only; m and rad).
    fn state(self, at: f64, q: &[f64; AXES], names: &[String], frame_id: &str) -> AxisState {
        AxisState {
            header: Header { stamp: self.time(at), frame_id: frame_id.to_string() },
            source: AxisState::SOURCE_MACHINE,
            name: names.to_vec(),
            position: q.to_vec(),
            ..Default::default()
        }
    }
}
