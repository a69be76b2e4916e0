//! Commander: the program's commanded axis states, as the NC program asks for them (ideal motion at
//! the programmed feed, axes linear per block under TCPM), one message per sample period.

use super::{derivatives_at, StateBuilder};
use crate::machine::Machine;
use crate::kinematics::Joints;
use crate::path::{Sample, Trajectory};
use fiveaxis_msgs::AxisState;

/// The commanded states of a trajectory, in time order, one at a time: the samples are made as they
/// are published (three at a time, for the central differences), never held whole.
pub fn commanded_iter<'a>(traj: &'a Trajectory, machine: &'a Machine) -> impl Iterator<Item = AxisState> + 'a {
    let b = StateBuilder::new(machine, AxisState::SOURCE_COMMANDED);
    let mut samples = traj.samples(machine).peekable();
    let mut prev: Option<Sample> = None;
    std::iter::from_fn(move || {
        let cur = samples.next()?;
        let next = samples.peek().copied();
        // Positions around this sample, the ends one-sided, as in `derivatives_at` over the whole stream.
        let mut window: [Joints; 3] = [cur.q; 3];
        let mut n = 0;
        for q in [prev.map(|s| s.q), Some(cur.q), next.map(|s| s.q)].into_iter().flatten() {
            window[n] = q;
            n += 1;
        }
        let k = usize::from(prev.is_some());
        let (v, a) = derivatives_at(n, k, traj.period, |j| window[j]);
        prev = Some(cur);
        Some(b.state(machine, cur.t, &cur.q, &v, &a, traj.segments.get(cur.segment), cur.feed))
    })
}

/// The commanded states of a sampled trajectory, in time order, all in memory.
pub fn commanded_states(traj: &Trajectory, machine: &Machine) -> Vec<AxisState> {
    commanded_iter(traj, machine).collect()
}
