//! Commander: the program's commanded axis states, as the NC program asks for them (ideal motion at
//! the programmed feed, axes linear per block under TCPM), one message per sample period.

use super::{differentiate, StateBuilder};
use crate::machine::Machine;
use crate::path::Trajectory;
use fiveaxis_msgs::AxisState;

/// The commanded states of a sampled trajectory, in time order.
pub fn commanded_states(traj: &Trajectory, machine: &Machine) -> Vec<AxisState> {
    let q: Vec<_> = traj.samples.iter().map(|s| s.q).collect();
    let (v, a) = differentiate(&q, traj.period);
    let b = StateBuilder::new(machine, AxisState::SOURCE_COMMANDED);
    traj.samples
        .iter()
        .enumerate()
        .map(|(k, s)| b.state(machine, s.t, &s.q, &v[k], &a[k], traj.segments.get(s.segment), s.feed))
        .collect()
}
