//! The axis-state streams a node watches (the monitor, the Rerun bridge): one subscription per
//! topic onto one channel in arrival order, and the receive loop both nodes run over it, with a
//! machine bridge's JointState mapped onto the machine's axes by one rule
//! ([`fiveaxis::live::joint_map::JointMap`]).

use crate::{forward, Bus, InputArgs, Shutdown};
use fiveaxis::live::joint_map::JointMap;
use fiveaxis::live::monitor::Rejection;
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
    /// A sample of `topic`: our AxisState, or a JointState mapped onto the machine's axes.
    State { topic: String, state: AxisState },
    /// A sample refused before the monitor: a JointState whose joints do not map (with the joint
    /// names it had), or a message that did not decode.
    Refused { topic: String, why: Rejection, joints: Option<Vec<String>> },
    /// No sample within the poll interval (time for the node's periodic work).
    Idle,
}

/// The receive loop over [`subscribe_states`]' channel, as an iterator: it ends on a shutdown
/// signal, when every reader has ended, or once the inputs have been silent for the idle limit after
/// a first sample.
pub struct StateReceiver<'a> {
    rx: Receiver<StateInput>,
    map: JointMap,
    shutdown: &'a Shutdown,
    poll: Duration,
    exit_when_idle_s: Option<f64>,
    start: Instant,
    last_sample: Option<f64>,
}

impl<'a> StateReceiver<'a> {
    /// Receive from `rx`, waiting at most `poll` for each sample; `exit_when_idle_s`: end once no
    /// sample has come for this long after the first.
    pub fn new(rx: Receiver<StateInput>, map: JointMap, shutdown: &'a Shutdown, poll: Duration, exit_when_idle_s: Option<f64>) -> StateReceiver<'a> {
        StateReceiver { rx, map, shutdown, poll, exit_when_idle_s, start: Instant::now(), last_sample: None }
    }

    /// Seconds since the loop started (the node's monotonic arrival clock).
    pub fn now(&self) -> f64 {
        self.start.elapsed().as_secs_f64()
    }
}

impl Iterator for StateReceiver<'_> {
    type Item = Received;

    fn next(&mut self) -> Option<Received> {
        if self.shutdown.requested() {
            return None;
        }
        if let (Some(idle), Some(last)) = (self.exit_when_idle_s, self.last_sample) {
            if self.now() - last > idle {
                tracing::info!("inputs idle for {idle} s: exiting");
                return None;
            }
        }
        let input = match self.rx.recv_timeout(self.poll) {
            Ok(input) => input,
            Err(RecvTimeoutError::Timeout) => return Some(Received::Idle),
            Err(RecvTimeoutError::Disconnected) => return None,
        };
        self.last_sample = Some(self.now());
        Some(match input {
            StateInput::State(topic, state) => Received::State { topic, state },
            StateInput::Joints(topic, js) => match self.map.axis_state(&js) {
                Ok(state) => Received::State { topic, state },
                Err(why) => Received::Refused { topic, why, joints: Some(js.name) },
            },
            // Logged by the reader; a malformed sample of its stream.
            StateInput::Undecodable(topic, reason) => Received::Refused { topic, why: Rejection::Invalid(reason), joints: None },
        })
    }
}
