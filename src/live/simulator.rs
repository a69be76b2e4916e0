//! Simulator: what a machine with axis velocity, acceleration and jerk limits does with the program
//! (the planner, then the servo), as simulated axis states.

use super::{differentiate, StateBuilder};
use crate::kinematics::Joints;
use crate::machine::Machine;
use crate::path::Trajectory;
use crate::planner::{self, servo, PlanConfig};
use fiveaxis_msgs::AxisState;

/// Simulator settings.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct SimConfig {
    pub plan: PlanConfig,
    pub servo: servo::ServoConfig,
}

/// A simulated run.
#[derive(Debug, Clone)]
pub struct Simulation {
    pub period: f64,
    /// Actual axis positions (after the servo), and the segment each belongs to.
    pub q: Vec<Joints>,
    pub segment: Vec<usize>,
    /// Run (stretch between stops) of each sample.
    pub run: Vec<usize>,
    /// Largest following error of the linear (m) and rotary (rad) axes.
    pub following_error_linear: f64,
    pub following_error_rotary: f64,
    /// Limit ratios the planner measured on its set-points.
    pub planned_ratio: [f64; 3],
}

/// Plan and servo a trajectory.
pub fn simulate(traj: &Trajectory, machine: &Machine, config: &SimConfig) -> Simulation {
    let plan_cfg = PlanConfig { period: traj.period, ..config.plan };
    let planned = planner::plan(&traj.segments, machine, &plan_cfg);
    let set: Vec<Joints> = planned.samples.iter().map(|s| s.q).collect();
    let q = servo::follow(&set, traj.period, &config.servo);
    let mut segment: Vec<usize> = planned.samples.iter().map(|s| s.segment).collect();
    let mut run: Vec<usize> = planned.samples.iter().map(|s| s.run).collect();
    segment.resize(q.len(), segment.last().copied().unwrap_or(0));
    run.resize(q.len(), run.last().copied().unwrap_or(0));
    let (mut fl, mut fr) = (0.0f64, 0.0f64);
    for (k, s) in set.iter().enumerate() {
        for i in 0..5 {
            let e = (s[i] - q[k][i]).abs();
            if i < 3 {
                fl = fl.max(e);
            } else {
                fr = fr.max(e);
            }
        }
    }
    Simulation { period: traj.period, q, segment, run, following_error_linear: fl, following_error_rotary: fr, planned_ratio: planned.max_ratio }
}

impl Simulation {
    /// Duration, s.
    pub fn duration(&self) -> f64 {
        self.q.len().saturating_sub(1) as f64 * self.period
    }

    /// The simulated states, in time order.
    pub fn states(&self, traj: &Trajectory, machine: &Machine) -> Vec<AxisState> {
        let (v, a) = differentiate(&self.q, self.period);
        let b = StateBuilder::new(machine, AxisState::SOURCE_SIMULATED);
        let tips: Vec<_> = self
            .q
            .iter()
            .zip(&self.segment)
            .map(|(q, &s)| machine.forward(q).tip - traj.segments.get(s).map_or(nalgebra::Vector3::zeros(), |g| g.datum))
            .collect();
        // Tool-tip speed by central differences, never across a datum change (the tip jumps there in
        // program coordinates while the machine does not move).
        let datum = |k: usize| traj.segments.get(self.segment[k]).map(|g| g.datum);
        let last = tips.len() - 1;
        (0..self.q.len())
            .map(|k| {
                let lo = if k > 0 && datum(k - 1) == datum(k) { k - 1 } else { k };
                let hi = if k < last && datum(k + 1) == datum(k) { k + 1 } else { k };
                let feed = if hi > lo { (tips[hi] - tips[lo]).norm() / ((hi - lo) as f64 * self.period) } else { 0.0 };
                b.state(machine, k as f64 * self.period, &self.q[k], &v[k], &a[k], traj.segments.get(self.segment[k]), feed)
            })
            .collect()
    }
}
