//! Commander: the program's commanded axis states, as the NC program asks for them (ideal motion at
//! the programmed feed, axes linear per block under TCPM), one message per sample period.

use super::{derivatives_at, StateBuilder};
use crate::machine::Machine;
use crate::path::Trajectory;
use fiveaxis_msgs::AxisState;

/// The commanded states of a sampled trajectory, in time order, one at a time (nothing is held but
/// the trajectory itself).
pub fn commanded_iter<'a>(traj: &'a Trajectory, machine: &'a Machine) -> impl Iterator<Item = AxisState> + 'a {
    let b = StateBuilder::new(machine, AxisState::SOURCE_COMMANDED);
    let n = traj.samples.len();
    (0..n).map(move |k| {
        let s = &traj.samples[k];
        let (v, a) = derivatives_at(n, k, traj.period, |j| traj.samples[j].q);
        b.state(machine, s.t, &s.q, &v, &a, traj.segments.get(s.segment), s.feed)
    })
}

/// The commanded states of a sampled trajectory, in time order, all in memory.
pub fn commanded_states(traj: &Trajectory, machine: &Machine) -> Vec<AxisState> {
    commanded_iter(traj, machine).collect()
}
