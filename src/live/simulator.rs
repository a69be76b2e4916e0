//! Simulator: what a machine with axis velocity, acceleration and jerk limits does with the program
//! (the planner, then the servo), as simulated axis states.

use super::{derivatives_at, StateBuilder};
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

/// Plan and servo a trajectory. At each planned stop between runs (a corner, a rapid, a rotary-only
/// move) the next run starts once the servo is in position.
pub fn simulate(traj: &Trajectory, machine: &Machine, config: &SimConfig) -> Simulation {
    let plan_cfg = PlanConfig { period: traj.period, ..config.plan };
    let cfg = &config.servo;
    let mut servo: Option<servo::Servo> = None;
    let (mut q, mut segment, mut run) = (Vec::new(), Vec::new(), Vec::new());
    let (mut fl, mut fr) = (0.0f64, 0.0f64);
    let mut last: Option<(Joints, usize, usize)> = None;
    let mut push = |s: &mut servo::Servo, u: &Joints, seg: usize, r: usize| {
        let y = s.step(u);
        for i in 0..5 {
            let e = (u[i] - y[i]).abs();
            if i < 3 {
                fl = fl.max(e);
            } else {
                fr = fr.max(e);
            }
        }
        q.push(y);
        segment.push(seg);
        run.push(r);
    };
    let planned = planner::plan_each(&traj.segments, machine, &plan_cfg, |p| {
        let s = servo.get_or_insert_with(|| servo::Servo::new(p.q, traj.period, cfg));
        if let Some((u, seg, r)) = last.filter(|l| l.2 != p.run) {
            // Exact stop: hold the last set-point until in position (bounded: 10 s).
            for _ in 0..(10.0 / traj.period) as usize {
                if s.in_position(&u, cfg.in_position_m, cfg.in_position_rad) {
                    break;
                }
                push(s, &u, seg, r);
            }
        }
        push(s, &p.q, p.segment, p.run);
        last = Some((p.q, p.segment, p.run));
    });
    if let (Some(s), Some((u, seg, r))) = (servo.as_mut(), last) {
        for _ in 0..100_000 {
            if s.in_position(&u, 1e-9, 1e-9) {
                break;
            }
            push(s, &u, seg, r);
        }
    }
    Simulation { period: traj.period, q, segment, run, following_error_linear: fl, following_error_rotary: fr, planned_ratio: planned.max_ratio }
}

impl Simulation {
    /// Duration, s.
    pub fn duration(&self) -> f64 {
        self.q.len().saturating_sub(1) as f64 * self.period
    }

    /// The lowest tool-tip feed on the feed moves (m/s) and its x (m), planned stops excluded: the
    /// ramps out of and into each run boundary (a corner or the program's ends) do not count.
    pub fn lowest_path_feed(&self, traj: &Trajectory, states: &[FeedSample]) -> (f64, f64) {
        let sim = self;
        let n = states.len();
        let path_move = |k: usize| traj.segments.get(sim.segment[k]).is_some_and(|s| s.is_path_move() && s.kind != crate::path::SegmentKind::Rapid);
        // The ramps out of and into each planned stop: from a run boundary for as long as the feed is
        // below the programmed feed and has not fallen by more than 2 % of it from its highest value since
        // the stop (the servo rounds the corner, so the feed may still dip just after the boundary).
        let mut ramp = vec![false; n];
        let boundary = |k: usize| k == 0 || sim.run[k - 1] != sim.run[k];
        let mark = |k: usize, forward: bool, ramp: &mut Vec<bool>| {
            let f = states[k].programmed_feed.max(1e-12);
            let (mut j, mut top) = (k, 0.0f64);
            ramp[j] = true;
            loop {
                let next = if forward { j + 1 } else { j.wrapping_sub(1) };
                if next >= n || (forward && boundary(next)) || (!forward && boundary(j)) {
                    break;
                }
                let v = states[next].path_feed;
                if v >= 0.99 * f || v < top - 0.02 * f {
                    break;
                }
                top = top.max(v);
                j = next;
                ramp[j] = true;
            }
        };
        for k in 0..n {
            if boundary(k) {
                mark(k, true, &mut ramp);
            }
            if k + 1 == n || boundary(k + 1) {
                mark(k, false, &mut ramp);
            }
        }
        (0..n)
            .filter(|&k| path_move(k) && states[k].programmed_feed > 0.0 && !ramp[k])
            .map(|k| (states[k].path_feed, states[k].x))
            .fold((f64::INFINITY, 0.0), |a, b| if b.0 < a.0 { b } else { a })
    }

    /// The simulated states, in time order, one at a time (nothing is held but the simulation).
    pub fn states_iter<'a>(&'a self, traj: &'a Trajectory, machine: &'a Machine) -> impl Iterator<Item = AxisState> + 'a {
        let b = StateBuilder::new(machine, AxisState::SOURCE_SIMULATED);
        let n = self.q.len();
        let datum = move |k: usize| traj.segments.get(self.segment[k]).map_or(nalgebra::Vector3::zeros(), |g| g.datum);
        let tip = move |k: usize| machine.forward(&self.q[k]).tip - datum(k);
        // Tool tips of the samples before, at and after k (rolling, one forward kinematics per sample).
        let mut tips: Option<[nalgebra::Vector3<f64>; 3]> = None;
        (0..n).map(move |k| {
            let t3 = match tips {
                None => [tip(0), tip(0), tip(1.min(n - 1))],
                Some([_, cur, next]) => [cur, next, tip((k + 1).min(n - 1))],
            };
            tips = Some(t3);
            // Tool-tip speed by central differences, never across a datum change (the tip jumps there
            // in program coordinates while the machine does not move).
            let lo = if k > 0 && datum(k - 1) == datum(k) { 0 } else { 1 };
            let hi = if k + 1 < n && datum(k + 1) == datum(k) { 2 } else { 1 };
            let feed = if hi > lo { (t3[hi] - t3[lo]).norm() / ((hi - lo) as f64 * self.period) } else { 0.0 };
            let (v, a) = derivatives_at(n, k, self.period, |j| self.q[j]);
            b.state(machine, k as f64 * self.period, &self.q[k], &v, &a, traj.segments.get(self.segment[k]), feed)
        })
    }

    /// What the feed figures need of every simulated state ([`Simulation::lowest_path_feed`], slow regions).
    pub fn feed_samples(&self, traj: &Trajectory, machine: &Machine) -> Vec<FeedSample> {
        self.states_iter(traj, machine).map(|s| (&s).into()).collect()
    }

    /// The simulated states, in time order, all in memory.
    pub fn states(&self, traj: &Trajectory, machine: &Machine) -> Vec<AxisState> {
        self.states_iter(traj, machine).collect()
    }
}

/// What the feed figures need of a simulated state (32 bytes instead of a message).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FeedSample {
    /// Actual and programmed tool-tip feed, m/s; workpiece x, m; block number (-1 without).
    pub path_feed: f64,
    pub programmed_feed: f64,
    pub x: f64,
    /// Block number (-1 without; numbers beyond i32 are clamped) and program line (0: unknown).
    pub block: i32,
    pub line: u32,
}

impl From<&AxisState> for FeedSample {
    fn from(s: &AxisState) -> FeedSample {
        FeedSample { path_feed: s.path_feed, programmed_feed: s.programmed_feed, x: s.tool_tip.x, block: s.block_number.clamp(-1, i64::from(i32::MAX)) as i32, line: s.program_line }
    }
}
