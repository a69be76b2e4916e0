//! Commander: the program's commanded axis states, as the NC program asks for them (ideal motion at
//! the programmed feed, axes linear per block under TCPM), one message per sample period.

use super::{derivatives_at, StateBuilder, StateValues};
use crate::kinematics::Joints;
use crate::machine::Machine;
use crate::path::{GridSampler, Sample, Segment, SegmentWindow, Trajectory};
use fiveaxis_msgs::AxisState;

/// The state of sample `cur` between its neighbours (none at the stream's ends): central differences,
/// one-sided at the ends, as [`derivatives_at`] over the whole stream.
fn values_between(b: &StateBuilder, machine: &Machine, period: f64, prev: Option<&Sample>, cur: &Sample, next: Option<&Sample>, seg: Option<&Segment>) -> StateValues {
    let mut window: [Joints; 3] = [cur.q; 3];
    let mut n = 0;
    for s in [prev, Some(cur), next].into_iter().flatten() {
        window[n] = s.q;
        n += 1;
    }
    let (v, a) = derivatives_at(n, usize::from(prev.is_some()), period, |j| window[j]);
    b.values(machine, cur.t, &cur.q, &v, &a, seg, cur.feed)
}

/// The commanded states of a trajectory, in time order, one at a time: the samples are made as they
/// are published (three at a time, for the central differences), never held whole.
pub fn commanded_iter<'a>(traj: &'a Trajectory, machine: &'a Machine) -> Box<dyn Iterator<Item = AxisState> + 'a> {
    let b = StateBuilder::new(machine, AxisState::SOURCE_COMMANDED);
    Box::new(commanded_values_iter(traj, machine).map(move |v| b.message(&v)))
}

/// The numbers of the commanded states of a trajectory ([`commanded_iter`]).
pub fn commanded_values_iter<'a>(traj: &'a Trajectory, machine: &'a Machine) -> Box<dyn Iterator<Item = StateValues> + 'a> {
    if traj.stored.is_empty() {
        return Box::new(commanded_stream(traj.segments.iter().cloned(), traj.period, machine));
    }
    // A built-in path's own samples, with the segments they name.
    let mut values = CommandedValues::new(machine, traj.period);
    let mut samples = traj.stored.iter().peekable();
    Box::new(std::iter::from_fn(move || {
        let cur = samples.next()?;
        Some(values.next(cur, samples.peek().copied(), traj.segments.get(cur.segment)))
    }))
}

/// The commanded states (their numbers) of a stream of segments sampled every `period` s, in time
/// order: segments are read as the samples reach them and dropped behind, so memory holds two or three
/// of them whatever the program's length.
pub fn commanded_stream<'a, I: Iterator<Item = Segment> + 'a>(segments: I, period: f64, machine: &'a Machine) -> impl Iterator<Item = StateValues> + 'a {
    let mut values = CommandedValues::new(machine, period);
    let mut window = SegmentWindow::new(segments);
    let mut sampler = GridSampler::new(period);
    let mut next = sampler.next(&mut window, machine);
    std::iter::from_fn(move || {
        let cur = next.take()?;
        next = sampler.next(&mut window, machine);
        let st = values.next(&cur, next.as_ref(), window.loaded(cur.segment));
        // The end point is sampled from the last segment: keep the one the current sample is on.
        window.release_before(cur.segment);
        Some(st)
    })
}

/// The commanded states of a stream of samples handed over one at a time, each with the next sample
/// and its segment (as [`crate::singularity::analyze_segments_along`] hands them): what
/// [`commanded_stream`] makes of the same samples.
#[derive(Debug, Clone)]
pub struct CommandedValues<'a> {
    b: StateBuilder,
    machine: &'a Machine,
    period: f64,
    prev: Option<Sample>,
}

impl<'a> CommandedValues<'a> {
    pub fn new(machine: &'a Machine, period: f64) -> CommandedValues<'a> {
        CommandedValues { b: StateBuilder::new(machine, AxisState::SOURCE_COMMANDED), machine, period, prev: None }
    }

    /// The state of `cur`, the sample after the last one given.
    pub fn next(&mut self, cur: &Sample, next: Option<&Sample>, seg: Option<&Segment>) -> StateValues {
        let st = values_between(&self.b, self.machine, self.period, self.prev.as_ref(), cur, next, seg);
        self.prev = Some(*cur);
        st
    }
}

/// The commanded states of a sampled trajectory, in time order, all in memory.
pub fn commanded_states(traj: &Trajectory, machine: &Machine) -> Vec<AxisState> {
    commanded_iter(traj, machine).collect()
}

/// The commanded states (their numbers: [`StateBuilder::message`] makes the messages) of a job's
/// moves: a program's as it is read again, a built-in path's from its held samples.
pub fn commanded_moves<'a>(moves: &'a crate::job::Moves, machine: &'a Machine) -> Result<Box<dyn Iterator<Item = StateValues> + 'a>, crate::job::JobError> {
    Ok(match moves.held() {
        Some(traj) => commanded_values_iter(traj, machine),
        None => Box::new(commanded_stream(moves.segments(machine)?, moves.period(), machine)),
    })
}

/// The commanded states of `passes` runs of a job's moves (`None`: endless; [`crate::job::Moves::passes`]):
/// one pass is [`commanded_moves`]; more are streamed from the program's segments, joined by rapids.
pub fn commanded_passes<'a>(
    moves: &'a crate::job::Moves,
    machine: &'a Machine,
    passes: Option<u64>,
    failed: &'a std::sync::OnceLock<crate::job::JobError>,
) -> Result<Box<dyn Iterator<Item = StateValues> + 'a>, crate::job::JobError> {
    if passes == Some(1) {
        return commanded_moves(moves, machine);
    }
    Ok(Box::new(commanded_stream(moves.passes(machine, passes, failed)?, moves.period(), machine)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::job::{JobOptions, Moves};

    /// The in-process run's commander publishes the analysis's samples ([`CommandedValues`] over
    /// [`crate::singularity::analyze_segments_along`]): the same states, bit for bit, as the
    /// commander node's own sampling of the program ([`commanded_stream`]).
    #[test]
    fn states_made_along_the_analysis_are_the_commanded_stream() {
        let m = Machine::hermle_c600u();
        let options = JobOptions::default();
        for spec in ["bundled:SING.I", "bundled:NON_SING.I"] {
            let moves = Moves::open(spec, &m, &options).unwrap();
            let period = moves.period();
            let own: Vec<StateValues> = commanded_stream(moves.segments(&m).unwrap(), period, &m).collect();
            let mut values = CommandedValues::new(&m, period);
            let mut along = Vec::new();
            let (_, counts) = crate::singularity::analyze_segments_along(moves.segments(&m).unwrap(), period, &m, &options.analysis, |cur, next, seg| {
                along.push(values.next(cur, next, seg));
            });
            assert!(own.len() > 1000, "{spec}: {} states", own.len());
            assert_eq!(along.len(), counts.samples, "{spec}");
            assert!(along == own, "{spec}: {} states along the analysis, {} of the commander's own", along.len(), own.len());
        }
    }
}
