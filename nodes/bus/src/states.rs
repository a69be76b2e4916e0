//! The axis-state streams a node watches (the monitor, the Rerun bridge): one subscription per
//! topic onto one channel in arrival order, and the receive loop both nodes run over it, with a
//! machine bridge's JointState mapped onto the machine's axes by one rule
//! ([`fiveaxis::live::joint_map::JointMap`]).

use crate::{forward, Bus, InputArgs, Shutdown};
use fiveaxis::kinematics::Joints;
use fiveaxis::live::joint_map::JointMap;
use fiveaxis::live::joint_stream::JointStream;
use fiveaxis::live::monitor::{MonitorConfig, Rejection};
use fiveaxis::machine::Machine;
use std::collections::{BTreeMap, VecDeque};
use fiveaxis_msgs::{AxisState, JointState};
use std::sync::mpsc::{Receiver, RecvTimeoutError};
use std::time::{Duration, Instant};

/// One axis-state sample from a watched topic: our AxisState, a machine bridge's JointState, or a
/// message that did not decode (counted as a malformed sample of its stream).
pub enum StateInput {
    State(String, AxisState),
    Joints(String, JointState),
    Undecodable(String, String),
}

/// Subscribe to the AxisState and JointState topics of `inputs` (state QoS; with none given, the node
/// set's commanded and simulated streams), all onto one channel in arrival order; the channel closes
/// when every reader has ended.
pub fn subscribe_states(bus: &mut Bus, inputs: &InputArgs) -> anyhow::Result<Receiver<StateInput>> {
    let default = fiveaxis::topics::MONITORED.map(|t| t.name.to_string());
    let states: &[String] = if inputs.inputs.is_empty() && inputs.joint_inputs.is_empty() { &default } else { &inputs.inputs };
    let joint_inputs = &inputs.joint_inputs;
    let (tx, rx) = std::sync::mpsc::sync_channel::<StateInput>(8192);
    for topic in states {
        let sub = bus.subscription::<AxisState>(topic, inputs.input_qos.profile(false))?;
        tracing::info!(topic = %bus.resolve(topic), "watching AxisState");
        forward(sub, bus.resolve(topic), tx.clone(), StateInput::State, StateInput::Undecodable);
    }
    for topic in joint_inputs {
        let sub = bus.subscription::<JointState>(topic, inputs.input_qos.profile(true))?;
        tracing::info!(topic = %bus.resolve(topic), "watching JointState");
        forward(sub, bus.resolve(topic), tx.clone(), StateInput::Joints, StateInput::Undecodable);
    }
    Ok(rx)
}

/// What the receive loop hands the node, in arrival order.
pub enum Received {
    /// A sample of `topic`: our AxisState, or a JointState mapped onto the machine's axes and merged
    /// per axis into a pose, with how far each axis may be off in it (SI; [`JointStream`]).
    /// `arrival`: when the report that completed it arrived (the loop's clock, [`StateReceiver::now`];
    /// None: now).
    State { topic: String, state: AxisState, uncertainty: Option<Joints>, arrival: Option<f64> },
    /// A sample refused before the monitor: a JointState whose joints do not map (with the joint
    /// names it had), or a message that did not decode.
    Refused { topic: String, why: Rejection, joints: Option<Vec<String>> },
    /// A message of `topic` arrived but completed no pose yet (a joint reported on its own, waiting
    /// for the others): the source is alive.
    Heard { topic: String },
    /// No sample within the poll interval (time for the node's periodic work).
    Idle,
}

/// The receive loop over [`subscribe_states`]' channel, as an iterator: it ends on a shutdown
/// signal, when every reader has ended, or once the inputs have been silent for the idle limit after
/// a first sample. A JointState topic's messages (whole or some joints only) are merged per axis into
/// whole poses ([`JointStream`]): a pose comes once every axis is known at its instant, and a topic
/// that falls silent has its waiting poses made.
pub struct StateReceiver<'a> {
    rx: Receiver<StateInput>,
    map: JointMap,
    /// A topic's merge as it starts (each JointState topic begins with a copy).
    fresh: JointStream,
    joints: BTreeMap<String, JointStream>,
    ready: VecDeque<Received>,
    /// A message stamped no later than its topic's last after this much silence is a restarted
    /// publisher (s).
    restart_after: f64,
    shutdown: &'a Shutdown,
    poll: Duration,
    exit_when_idle_s: Option<f64>,
    start: Instant,
    last_sample: Option<f64>,
}

impl<'a> StateReceiver<'a> {
    /// Receive from `rx`, waiting at most `poll` for each sample; `exit_when_idle_s`: end once no
    /// sample has come for this long after the first.
    pub fn new(rx: Receiver<StateInput>, map: JointMap, machine: &Machine, shutdown: &'a Shutdown, poll: Duration, exit_when_idle_s: Option<f64>) -> StateReceiver<'a> {
        StateReceiver {
            rx,
            fresh: JointStream::new(machine, map.joints()),
            map,
            joints: BTreeMap::new(),
            ready: VecDeque::new(),
            restart_after: MonitorConfig::default().stale_timeout,
            shutdown,
            poll,
            exit_when_idle_s,
            start: Instant::now(),
            last_sample: None,
        }
    }

    /// The silence after which a JointState topic stamped anew is a restarted publisher (s; the
    /// monitor's stale timeout).
    pub fn set_restart_after(&mut self, seconds: f64) {
        self.restart_after = seconds;
    }

    /// Merge one JointState message of `topic`; what it completes (and why it was refused) is queued.
    fn take_joints(&mut self, topic: String, js: JointState, wall: f64) {
        let stream = self.joints.entry(topic.clone()).or_insert_with(|| self.fresh.clone());
        let before = self.ready.len();
        if let Err(why) = stream.push(&self.map, &js, wall, self.restart_after) {
            self.ready.push_back(Received::Refused { topic: topic.clone(), why, joints: Some(js.name) });
        }
        queue_poses(&mut self.ready, &topic, stream);
        if self.ready.len() == before {
            self.ready.push_back(Received::Heard { topic });
        }
    }

    /// Make the waiting poses of topics silent for longer than their merge's wait (`all`: every
    /// topic, at the end).
    fn flush_silent(&mut self, wall: f64, all: bool) {
        for (topic, stream) in self.joints.iter_mut() {
            if stream.has_pending() && (all || stream.last_wall().is_some_and(|w| wall - w > stream.latency())) {
                stream.flush();
                queue_poses(&mut self.ready, topic, stream);
            }
        }
    }

    /// Seconds since the loop started (the node's monotonic arrival clock).
    pub fn now(&self) -> f64 {
        self.start.elapsed().as_secs_f64()
    }
}

/// Queue the poses `stream` of `topic` has made, oldest first.
fn queue_poses(ready: &mut VecDeque<Received>, topic: &str, stream: &mut JointStream) {
    while let Some(merged) = stream.pop() {
        ready.push_back(Received::State { topic: topic.to_string(), state: merged.state, uncertainty: Some(merged.uncertainty), arrival: Some(merged.arrival) });
    }
}

impl Iterator for StateReceiver<'_> {
    type Item = Received;

    fn next(&mut self) -> Option<Received> {
        loop {
            if let Some(r) = self.ready.pop_front() {
                return Some(r);
            }
            if self.shutdown.requested() {
                return None;
            }
            if let (Some(idle), Some(last)) = (self.exit_when_idle_s, self.last_sample) {
                if self.now() - last > idle {
                    self.flush_silent(self.now(), true);
                    if !self.ready.is_empty() {
                        continue;
                    }
                    tracing::info!("inputs idle for {idle} s: exiting");
                    return None;
                }
            }
            let input = match self.rx.recv_timeout(self.poll) {
                Ok(input) => input,
                Err(RecvTimeoutError::Timeout) => {
                    self.flush_silent(self.now(), false);
                    if self.ready.is_empty() {
                        return Some(Received::Idle);
                    }
                    continue;
                }
                Err(RecvTimeoutError::Disconnected) => {
                    self.flush_silent(self.now(), true);
                    if self.ready.is_empty() {
                        return None;
                    }
                    // Drain what the end made; the next call finds the channel closed again.
                    continue;
                }
            };
            let now = self.now();
            self.last_sample = Some(now);
            match input {
                StateInput::State(topic, state) => return Some(Received::State { topic, state, uncertainty: None, arrival: None }),
                StateInput::Joints(topic, js) => self.take_joints(topic, js, now),
                // Logged by the reader; a malformed sample of its stream.
                StateInput::Undecodable(topic, reason) => return Some(Received::Refused { topic, why: Rejection::Invalid(reason), joints: None }),
            }
        }
    }
}
