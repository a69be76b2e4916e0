//! The SYNTHETIC example profile of a program: its simulated feed along the simultaneous five-axis
//! cut drives the seeded model of [`fiveaxis_core::roughness::synthetic`]. Not a measurement.

use super::synthetic::{profile, SyntheticModel};
use super::Profile;
use crate::job::JobError;
use crate::machine::Machine;

/// Why no profile could be made.
#[derive(Debug, thiserror::Error)]
pub enum SynthesizeError {
    #[error(transparent)]
    Run(#[from] JobError),
    #[error("{0} has no simultaneous five-axis cut to model")]
    NoCut(String),
}

/// The synthetic profile of `program` run on `machine` (seeded by `seed`), with the note that says
/// what it is wherever it is written.
pub fn synthesize(program: &str, machine: &Machine, seed: u64) -> Result<(Profile, String), SynthesizeError> {
    let options = crate::live::inprocess::RunOptions { keep_simulation: true, ..Default::default() };
    let run = crate::live::inprocess::run(program, machine, &options)?;
    let (Some(simulation), Some(job)) = (run.simulation.as_ref(), run.job.as_ref()) else {
        return Err(SynthesizeError::NoCut(program.into()));
    };
    let traj = &job.trajectory;
    let states = simulation.states(traj, machine);
    // The simulated feed along the simultaneous five-axis cut.
    let mut cut: Vec<(f64, f64, f64)> = states
        .iter()
        .zip(&simulation.segment)
        .filter(|(_, &seg)| traj.segments[seg].is_five_axis())
        .map(|(s, _)| (s.tool_tip.x, s.path_feed, s.programmed_feed))
        .collect();
    if cut.len() <= 10 {
        return Err(SynthesizeError::NoCut(program.into()));
    }
    cut.sort_by(|a, b| a.0.total_cmp(&b.0));
    let feed = |x: f64| {
        let k = cut.partition_point(|c| c.0 < x).min(cut.len() - 1);
        (cut[k].1, cut[k].2)
    };
    let model = SyntheticModel { seed, ..Default::default() };
    let p = profile(cut[0].0, cut[cut.len() - 1].0, &feed, &model);
    let note = format!(
        "SYNTHETIC roughness profile, not a measurement: fiveaxis model (core/src/roughness/synthetic.rs), seed {seed},\n\
         driven by the simulated feed of {program} on the {}; x is the workpiece x.",
        machine.name
    );
    Ok((p, note))
}
