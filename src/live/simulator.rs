//! Simulator: what a machine with axis velocity, acceleration and jerk limits does with the program
//! (the planner, then the servo), as simulated axis states.

use super::{derivatives_at, StateBuilder, StateValues};
use crate::kinematics::Joints;
use crate::machine::Machine;
use crate::path::{Segment, Trajectory};
use crate::planner::{self, servo, PlanConfig};
use fiveaxis_msgs::AxisState;
use std::rc::Rc;

/// Simulator settings.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct SimConfig {
    pub plan: PlanConfig,
    pub servo: servo::ServoConfig,
    /// Slow regions listed in full (default [`crate::listing::MAX_LISTED`]); the rest are folded.
    pub max_listed_regions: Option<usize>,
}

/// One simulated sample: the actual axis positions (after the servo), the segment and the run
/// (stretch between planned stops) it belongs to.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SimSample {
    pub q: Joints,
    pub segment: usize,
    pub run: usize,
}

/// What a simulation measured besides its samples.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct SimSummary {
    pub samples: u64,
    /// Largest following error of the linear (m) and rotary (rad) axes.
    pub following_error_linear: f64,
    pub following_error_rotary: f64,
    /// Limit ratios the planner measured on its set-points.
    pub planned_ratio: [f64; 3],
}

/// A simulated run, every sample in memory ([`simulate_each`] streams them instead).
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

/// Plan and servo a trajectory, calling `emit` for each actual sample in time order (false from
/// `emit` stops the simulation): [`simulate_stream`] over its segments.
pub fn simulate_each(
    traj: &Trajectory,
    machine: &Machine,
    config: &SimConfig,
    mut emit: impl FnMut(SimSample) -> bool,
) -> SimSummary {
    let segments = || traj.segments.iter().cloned();
    simulate_stream(segments(), segments(), traj.period, machine, config, |s, _| emit(s))
}

/// Plan and servo a stream of segments sampled every `period` s, calling `emit` for each actual
/// sample in time order with the segment it belongs to (false from `emit` stops the simulation).
/// `scout` is the same segments once more ([`planner::plan_stream`]). At each planned stop between
/// runs (a corner, a rapid, a rotary-only move) the next run starts once the servo is in position.
/// Memory is the planner's look-ahead window, whatever the program's length.
pub fn simulate_stream(
    segments: impl Iterator<Item = Segment>,
    scout: impl Iterator<Item = Segment>,
    period: f64,
    machine: &Machine,
    config: &SimConfig,
    mut emit: impl FnMut(SimSample, &Rc<Segment>) -> bool,
) -> SimSummary {
    let plan_cfg = PlanConfig { period, ..config.plan };
    let cfg = &config.servo;
    let mut servo: Option<servo::Servo> = None;
    let (mut fl, mut fr) = (0.0f64, 0.0f64);
    let mut samples = 0u64;
    let mut open = true;
    // The segment of the latest set-point, shared by its samples (one copy per segment), and that
    // set-point with its run.
    let mut current: Option<(usize, Rc<Segment>)> = None;
    let mut last: Option<(Joints, usize)> = None;
    let mut push = |s: &mut servo::Servo, u: &Joints, segment: usize, run: usize, seg: &Rc<Segment>| -> bool {
        let q = s.step(u);
        for i in 0..5 {
            let e = (u[i] - q[i]).abs();
            if i < 3 {
                fl = fl.max(e);
            } else {
                fr = fr.max(e);
            }
        }
        samples += 1;
        open = open && emit(SimSample { q, segment, run }, seg);
        open
    };
    let planned = planner::plan_stream(segments, scout, machine, &plan_cfg, |p, segment| {
        let s = servo.get_or_insert_with(|| servo::Servo::new(p.q, period, cfg));
        if let (Some((u, r)), Some((seg, held))) = (last.filter(|l| l.1 != p.run), current.as_ref()) {
            // Exact stop: hold the last set-point until in position (bounded: 10 s).
            for _ in 0..(10.0 / period) as usize {
                if s.in_position(&u, cfg.in_position_m, cfg.in_position_rad) {
                    break;
                }
                if !push(s, &u, *seg, r, held) {
                    return false;
                }
            }
        }
        if current.as_ref().is_none_or(|c| c.0 != p.segment) {
            current = Some((p.segment, Rc::new(segment.clone())));
        }
        last = Some((p.q, p.run));
        push(s, &p.q, p.segment, p.run, &current.as_ref().expect("just set").1)
    });
    if let (Some(s), Some((u, r)), Some((seg, held))) = (servo.as_mut(), last, current.as_ref()) {
        for _ in 0..100_000 {
            if s.in_position(&u, 1e-9, 1e-9) || !push(s, &u, *seg, r, held) {
                break;
            }
        }
    }
    SimSummary {
        samples,
        following_error_linear: fl,
        following_error_rotary: fr,
        planned_ratio: planned.max_ratio,
    }
}

/// Plan and servo a trajectory, keeping every sample ([`simulate_each`]).
pub fn simulate(traj: &Trajectory, machine: &Machine, config: &SimConfig) -> Simulation {
    let mut sim = Simulation::empty(traj.period);
    let summary = simulate_each(traj, machine, config, |s| {
        sim.push(&s);
        true
    });
    sim.measured(&summary);
    sim
}

/// Simulated samples to [`AxisState`] messages as they come, one sample behind (the central
/// differences and the tool-tip speed need the next sample): the one formula of every simulated stream.
pub struct SimStates<'a> {
    machine: &'a Machine,
    period: f64,
    builder: StateBuilder,
    /// The samples before, at and after the one to be emitted next, with their tool tips (program
    /// coordinates) and segments, in a ring (`cur` is `ring[at]`; a new sample takes the oldest
    /// slot, so none is moved); `k` is the index of `cur`.
    ring: [Option<Held>; 3],
    at: usize,
    k: u64,
    /// The rotaries' sines and cosines, which follow the samples.
    turns: [crate::kinematics::SinCos; 2],
}

#[derive(Clone)]
struct Held {
    s: SimSample,
    /// The sample's forward kinematics, and its tool tip in program coordinates.
    pose: crate::kinematics::Pose,
    tip: nalgebra::Vector3<f64>,
    seg: Option<Rc<Segment>>,
}

impl Held {
    fn datum(&self) -> nalgebra::Vector3<f64> {
        self.seg.as_ref().map_or(nalgebra::Vector3::zeros(), |g| g.datum)
    }
}

impl<'a> SimStates<'a> {
    /// States of samples every `period` s on `machine`.
    pub fn new(period: f64, machine: &'a Machine) -> SimStates<'a> {
        SimStates {
            machine,
            period,
            builder: StateBuilder::new(machine, AxisState::SOURCE_SIMULATED),
            ring: [None, None, None],
            at: 0,
            k: 0,
            turns: Default::default(),
        }
    }

    fn held(&mut self, s: SimSample, seg: Option<Rc<Segment>>) -> Held {
        let datum = seg.as_ref().map_or(nalgebra::Vector3::zeros(), |g| g.datum);
        let turns = [self.turns[0].at(s.q[3]), self.turns[1].at(s.q[4])];
        let pose = self.machine.chain.forward_turns(&s.q, &turns);
        Held { s, tip: pose.tip - datum, pose, seg }
    }

    /// The state of `cur` with its neighbours (none at the stream's ends).
    fn state(&self, prev: Option<&Held>, cur: &Held, next: Option<&Held>) -> StateValues {
        let period = self.period;
        // Tool-tip speed by central differences, never across a datum change (the tip jumps there
        // in program coordinates while the machine does not move).
        let lo = prev.filter(|p| p.datum() == cur.datum());
        let hi = next.filter(|n| n.datum() == cur.datum());
        let feed = match (lo, hi) {
            (Some(a), Some(b)) => (b.tip - a.tip).norm() / (2.0 * period),
            (Some(a), None) => (cur.tip - a.tip).norm() / period,
            (None, Some(b)) => (b.tip - cur.tip).norm() / period,
            (None, None) => 0.0,
        };
        let mut window = [cur.s.q; 3];
        let mut n = 0;
        for h in [prev, Some(cur), next].into_iter().flatten() {
            window[n] = h.s.q;
            n += 1;
        }
        let (v, a) = derivatives_at(n, usize::from(prev.is_some()), period, |j| window[j]);
        self.builder.values_at(&cur.pose, self.k as f64 * period, &cur.s.q, &v, &a, cur.seg.as_deref(), feed)
    }

    /// The next sample and its segment; the state of the one before it (its numbers:
    /// [`SimStates::message`] makes the message), if any, with its sample and segment.
    pub fn push(&mut self, s: SimSample, seg: Option<&Rc<Segment>>) -> Option<(SimSample, StateValues, Option<Rc<Segment>>)> {
        let (prev, cur, next) = ((self.at + 2) % 3, self.at, (self.at + 1) % 3);
        self.ring[next] = Some(self.held(s, seg.cloned()));
        let out = self.ring[cur].as_ref().map(|c| {
            let st = self.state(self.ring[prev].as_ref(), c, self.ring[next].as_ref());
            (c.s, st, c.seg.clone())
        });
        self.k += u64::from(out.is_some());
        self.ring[prev] = None;
        self.at = next;
        out
    }

    /// The message of a state's numbers.
    pub fn message(&self, v: &StateValues) -> AxisState {
        self.builder.message(v)
    }

    /// The state of the last sample (the stream's end).
    pub fn finish(&mut self) -> Option<(SimSample, StateValues, Option<Rc<Segment>>)> {
        let prev = (self.at + 2) % 3;
        let cur = self.ring[self.at].take()?;
        let st = self.state(self.ring[prev].as_ref(), &cur, None);
        self.ring[prev] = None;
        self.k += 1;
        Some((cur.s, st, cur.seg))
    }
}

impl Simulation {
    /// No sample yet, at period `period` (s).
    pub fn empty(period: f64) -> Simulation {
        Simulation {
            period,
            q: Vec::new(),
            segment: Vec::new(),
            run: Vec::new(),
            following_error_linear: 0.0,
            following_error_rotary: 0.0,
            planned_ratio: [0.0; 3],
        }
    }

    /// Keep the next sample.
    pub fn push(&mut self, s: &SimSample) {
        self.q.push(s.q);
        self.segment.push(s.segment);
        self.run.push(s.run);
    }

    /// Take what the simulation measured besides its samples.
    pub fn measured(&mut self, summary: &SimSummary) {
        self.following_error_linear = summary.following_error_linear;
        self.following_error_rotary = summary.following_error_rotary;
        self.planned_ratio = summary.planned_ratio;
    }

    /// Duration, s.
    pub fn duration(&self) -> f64 {
        self.q.len().saturating_sub(1) as f64 * self.period
    }

    /// The samples, in time order.
    pub fn samples(&self) -> impl Iterator<Item = SimSample> + '_ {
        (0..self.q.len()).map(|k| SimSample {
            q: self.q[k],
            segment: self.segment[k],
            run: self.run[k],
        })
    }

    /// The simulated states, in time order, one at a time (nothing is held but the simulation).
    pub fn states_iter<'a>(
        &'a self,
        traj: &'a Trajectory,
        machine: &'a Machine,
    ) -> impl Iterator<Item = AxisState> + 'a {
        let mut states = SimStates::new(traj.period, machine);
        let mut samples = self.samples();
        // One shared copy of each segment, as the simulation hands them out.
        let mut current: Option<(usize, Rc<Segment>)> = None;
        std::iter::from_fn(move || loop {
            match samples.next() {
                Some(s) => {
                    if current.as_ref().is_none_or(|c| c.0 != s.segment) {
                        current = traj.segments.get(s.segment).map(|g| (s.segment, Rc::new(g.clone())));
                    }
                    if let Some((_, st, _)) = states.push(s, current.as_ref().map(|c| &c.1)) {
                        return Some(states.message(&st));
                    }
                }
                None => return states.finish().map(|(_, st, _)| states.message(&st)),
            }
        })
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

impl From<&StateValues> for FeedSample {
    fn from(s: &StateValues) -> FeedSample {
        FeedSample { path_feed: s.path_feed, programmed_feed: s.programmed_feed, x: s.tool_tip[0], block: s.block_number.clamp(-1, i64::from(i32::MAX)) as i32, line: s.program_line }
    }
}
