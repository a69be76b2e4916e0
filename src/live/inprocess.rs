//! The embedded default: commander, simulator and monitor in one process, each on its own thread,
//! connected by bounded in-process channels instead of DDS, faster than real time. The node logic is
//! the same as the executables'.

use super::commander::commanded_iter;
use super::monitor::{LiveRegion, Monitor, MonitorConfig};
use super::simulator::{simulate, SimConfig, Simulation};
use crate::job::{self, Job, JobError, JobOptions};
use crate::machine::Machine;
use crate::path::{SegmentKind, Trajectory};
use crate::planner::limit_ratios;
use crate::report::AnalysisReport;
use fiveaxis_msgs::{AxisState, SingularityStatus};
use serde::Serialize;
use std::sync::mpsc;

/// Topic names, relative to the namespace (default `/fiveaxis`).
pub const COMMANDED_STATE: &str = "commanded/axis_state";
pub const SIMULATED_STATE: &str = "simulated/axis_state";

/// Options of a run.
#[derive(Debug, Clone, Default)]
pub struct RunOptions {
    pub job: JobOptions,
    pub sim: SimConfig,
    pub monitor: MonitorConfig,
    /// Record every topic of the node set into this MCAP file (rosbag2 layout).
    pub mcap: Option<std::path::PathBuf>,
    /// Keep every status the monitor published in [`RunOutput`] (memory grows with the program).
    pub keep_statuses: bool,
}

/// Topic names of the node set, absolute, with the default namespace.
pub mod topics {
    pub const COMMANDED_STATE: &str = "/fiveaxis/commanded/axis_state";
    pub const COMMANDED_JOINTS: &str = "/fiveaxis/commanded/joint_states";
    pub const SIMULATED_STATE: &str = "/fiveaxis/simulated/axis_state";
    pub const SIMULATED_JOINTS: &str = "/fiveaxis/simulated/joint_states";
    pub const STATUS: &str = "/fiveaxis/monitor/status";
    pub const DIAGNOSTICS: &str = "/diagnostics";
    pub const CLOCK: &str = "/clock";
}

/// Records the node set's topics in program time (the in-process clock, as with use_sim_time).
struct Tape {
    rec: crate::record::Recorder<std::io::BufWriter<std::fs::File>>,
    ids: [u16; 7],
    next_diag: f64,
}

impl Tape {
    fn create(path: &std::path::Path) -> Result<Tape, crate::record::RecordError> {
        use crate::record::{OfferedQos, Recorder};
        use fiveaxis_msgs::{Clock, DiagnosticArray, JointState};
        let mut rec = Recorder::create(path, Default::default())?;
        let ids = [
            rec.add_topic::<AxisState>(topics::COMMANDED_STATE, OfferedQos::STATE)?,
            rec.add_topic::<JointState>(topics::COMMANDED_JOINTS, OfferedQos::STATE)?,
            rec.add_topic::<AxisState>(topics::SIMULATED_STATE, OfferedQos::STATE)?,
            rec.add_topic::<JointState>(topics::SIMULATED_JOINTS, OfferedQos::STATE)?,
            rec.add_topic::<SingularityStatus>(topics::STATUS, OfferedQos::STATE)?,
            rec.add_topic::<DiagnosticArray>(topics::DIAGNOSTICS, OfferedQos::DIAGNOSTICS)?,
            rec.add_topic::<Clock>(topics::CLOCK, OfferedQos::CLOCK)?,
        ];
        Ok(Tape { rec, ids, next_diag: 0.0 })
    }

    fn state(&mut self, st: &AxisState, commanded: bool, monitor: &Monitor) -> Result<(), crate::record::RecordError> {
        let t = st.header.stamp.as_nanos();
        let (s, j) = if commanded { (self.ids[0], self.ids[1]) } else { (self.ids[2], self.ids[3]) };
        self.rec.write(s, st, t, t)?;
        self.rec.write(j, &st.to_joint_state(), t, t)?;
        if commanded {
            self.rec.write(self.ids[6], &fiveaxis_msgs::Clock { clock: st.header.stamp }, t, t)?;
        }
        let secs = st.header.stamp.as_secs();
        if secs >= self.next_diag {
            self.next_diag = secs + 0.5;
            self.rec.write(self.ids[5], &monitor.diagnostics(st.header.stamp), t, t)?;
        }
        Ok(())
    }

    fn status(&mut self, s: &SingularityStatus) -> Result<(), crate::record::RecordError> {
        let t = s.header.stamp.as_nanos();
        self.rec.write(self.ids[4], s, t, t)
    }
}

/// A stretch where the simulated feed is below half the programmed feed.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SlowRegion {
    pub x_start_mm: f64,
    pub x_end_mm: f64,
    pub t_start_s: f64,
    pub t_end_s: f64,
    pub block_start: i64,
    pub block_end: i64,
    /// Program lines (0: unknown), for programs without block numbers.
    pub line_start: u32,
    pub line_end: u32,
    pub min_feed_mm_per_min: f64,
    /// True where the slow-down is the planned stop at a corner or at the program's ends, not an
    /// axis limit along the path.
    pub at_stop: bool,
}

/// What the simulated machine did.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SimulatedReport {
    pub cycle_time_s: f64,
    pub commanded_cycle_time_s: f64,
    /// Lowest tool-tip feed on feed moves, outside the ramps into and out of planned stops.
    pub min_feed_mm_per_min: f64,
    pub min_feed_x_mm: f64,
    pub slow_regions: Vec<SlowRegion>,
    pub max_axis_velocity_ratio: f64,
    pub max_axis_acceleration_ratio: f64,
    pub max_axis_jerk_ratio: f64,
    pub max_following_error_mm: f64,
    pub max_following_error_deg: f64,
    pub samples: usize,
    pub lost_samples: u64,
    /// Regions the live monitor saw on the simulated stream.
    pub monitor_regions: Vec<LiveRegion>,
    pub monitor_statuses: u64,
}

/// `fiveaxis run --json`: the analysis keys plus `simulated`.
#[derive(Debug, Clone, Serialize)]
pub struct RunReport {
    #[serde(flatten)]
    pub analysis: AnalysisReport,
    pub simulated: SimulatedReport,
}

/// Everything a run produced.
pub struct RunOutput {
    pub job: Job,
    pub simulation: Simulation,
    pub simulated_states: usize,
    pub report: RunReport,
    /// The monitor's statuses on the simulated and on the commanded stream, in order (empty unless
    /// [`RunOptions::keep_statuses`]).
    pub statuses: Vec<SingularityStatus>,
    pub commanded_statuses: Vec<SingularityStatus>,
    /// Regions the monitor saw on the commanded stream.
    pub commanded_regions: Vec<LiveRegion>,
    /// Messages written to the MCAP recording, if one was asked for.
    pub recorded_messages: Option<u64>,
}

enum Input {
    Commanded(AxisState),
    Simulated(AxisState),
}

/// Run the node set in one process on `spec`.
pub fn run(spec: &str, machine: &Machine, options: &RunOptions) -> Result<RunOutput, JobError> {
    let options = options.clone();
    let options = &options;
    let job = job::run(spec, machine, &options.job)?;
    let traj = &job.trajectory;
    let (tx, rx) = mpsc::sync_channel::<Input>(4096);
    let tape = match &options.mcap {
        Some(path) => Some(Tape::create(path)?),
        None => None,
    };
    let (simulation, sent, statuses, monitor, tape_result) = std::thread::scope(|scope| {
        let tx_cmd = tx.clone();
        let commander = scope.spawn(move || {
            let mut sent = 0u64;
            for st in commanded_iter(traj, machine) {
                if tx_cmd.send(Input::Commanded(st)).is_err() {
                    break;
                }
                sent += 1;
            }
            sent
        });
        let tx_sim = tx;
        let simulator = scope.spawn(move || {
            let sim = simulate(traj, machine, &options.sim);
            let mut sent = 0u64;
            for st in sim.states_iter(traj, machine) {
                if tx_sim.send(Input::Simulated(st)).is_err() {
                    break;
                }
                sent += 1;
            }
            (sim, sent)
        });
        let mut tape = tape;
        let monitor = scope.spawn(move || {
            let mut m = Monitor::new(machine, options.monitor);
            let mut statuses = Vec::new();
            let mut commanded = Vec::new();
            let mut received = 0u64;
            let mut tape_error = None;
            for input in rx {
                received += 1;
                let (topic, st) = match &input {
                    Input::Commanded(st) => {
                        m.on_commanded_ahead(st);
                        (COMMANDED_STATE, st)
                    }
                    Input::Simulated(st) => (SIMULATED_STATE, st),
                };
                let wall = st.header.stamp.as_secs();
                let status = m.on_state(topic, st, wall);
                if let (Some(t), None) = (tape.as_mut(), &tape_error) {
                    let r = t.state(st, topic == COMMANDED_STATE, &m).and_then(|_| match &status {
                        Ok(s) => t.status(s),
                        Err(_) => Ok(()),
                    });
                    if let Err(e) = r {
                        tape_error = Some(e);
                    }
                }
                if let Some(s) = status.ok().filter(|_| options.keep_statuses) {
                    if topic == SIMULATED_STATE {
                        statuses.push(s);
                    } else {
                        commanded.push(s);
                    }
                }
            }
            m.finish();
            let tape_result = match (tape, tape_error) {
                (_, Some(e)) => Err(e),
                (Some(t), None) => t.rec.finish().map(Some),
                (None, None) => Ok(None),
            };
            (m, (statuses, commanded), received, tape_result)
        });
        let sent_cmd = commander.join().expect("commander thread");
        let (sim, sent_sim) = simulator.join().expect("simulator thread");
        let (m, statuses, received, tape_result) = monitor.join().expect("monitor thread");
        (sim, sent_cmd + sent_sim - received.min(sent_cmd + sent_sim), statuses, m, tape_result)
    });
    let recorded_messages = tape_result?;
    let simulated = simulated_report(traj, machine, &simulation, sent, &monitor);
    let report = RunReport { analysis: job.report.clone(), simulated };
    let (statuses, commanded_statuses) = statuses;
    Ok(RunOutput {
        recorded_messages,
        simulated_states: simulation.q.len(),
        simulation,
        job,
        report,
        statuses,
        commanded_statuses,
        commanded_regions: monitor.regions(COMMANDED_STATE),
    })
}

fn simulated_report(traj: &Trajectory, machine: &Machine, sim: &Simulation, lost: u64, monitor: &Monitor) -> SimulatedReport {
    let states = sim.feed_samples(traj, machine);
    let ratios = limit_ratios(&sim.q, sim.period, &machine.limits());
    let worst = ratios.iter().fold([0.0f64; 3], |m, r| [m[0].max(r[0]), m[1].max(r[1]), m[2].max(r[2])]);
    let path_move = |k: usize| traj.segments.get(sim.segment[k]).is_some_and(|s| s.is_path_move() && s.kind != SegmentKind::Rapid);
    // Slow regions: feed moves below half their programmed feed.
    let mut slow: Vec<SlowRegion> = Vec::new();
    let mut k = 0;
    let n = states.len();
    while k < n {
        let is_slow = |k: usize| path_move(k) && states[k].programmed_feed > 0.0 && states[k].path_feed < 0.5 * states[k].programmed_feed;
        if !is_slow(k) {
            k += 1;
            continue;
        }
        let start = k;
        while k + 1 < n && is_slow(k + 1) {
            k += 1;
        }
        let end = k;
        // A planned stop: the stretch reaches the program's ends or a run boundary (a corner), within a
        // few samples (a datum change between runs makes the tip jump in program coordinates there).
        let at_stop = start == 0 || end + 4 >= n || (start.saturating_sub(4)..=end + 3).any(|j| sim.run[j] != sim.run[j + 1]);
        let min = states[start..=end].iter().map(|s| s.path_feed).fold(f64::INFINITY, f64::min);
        slow.push(SlowRegion {
            x_start_mm: states[start].x * 1e3,
            x_end_mm: states[end].x * 1e3,
            t_start_s: start as f64 * sim.period,
            t_end_s: end as f64 * sim.period,
            block_start: states[start].block.into(),
            block_end: states[end].block.into(),
            line_start: states[start].line,
            line_end: states[end].line,
            min_feed_mm_per_min: min * 60e3,
            at_stop,
        });
        k += 1;
    }
    let (min_feed, min_x) = sim.lowest_path_feed(traj, &states);
    let (samples, ..) = monitor.counters(SIMULATED_STATE);
    SimulatedReport {
        cycle_time_s: sim.duration(),
        commanded_cycle_time_s: traj.duration(),
        min_feed_mm_per_min: if min_feed.is_finite() { min_feed * 60e3 } else { 0.0 },
        min_feed_x_mm: min_x * 1e3,
        slow_regions: slow,
        max_axis_velocity_ratio: worst[0],
        max_axis_acceleration_ratio: worst[1],
        max_axis_jerk_ratio: worst[2],
        max_following_error_mm: sim.following_error_linear * 1e3,
        max_following_error_deg: sim.following_error_rotary.to_degrees(),
        samples: n,
        lost_samples: lost,
        monitor_regions: monitor.regions(SIMULATED_STATE),
        monitor_statuses: samples,
    }
}

impl SimulatedReport {
    /// A short table for people.
    pub fn to_table(&self, c: &str) -> String {
        use std::fmt::Write as _;
        let mut o = String::new();
        let _ = writeln!(o, "simulated  {:.2} s (commanded {:.2} s), {} samples, {} lost", self.cycle_time_s, self.commanded_cycle_time_s, self.samples, self.lost_samples);
        let _ = writeln!(o, "lowest feed on the path      {:8.0} mm/min at x {:.3} mm (planned stops excluded)", self.min_feed_mm_per_min, self.min_feed_x_mm);
        let _ = writeln!(
            o,
            "largest |v|/v_max {:.3}, |a|/a_max {:.3}, |j|/j_max {:.3} over all axes; following error {:.3} mm, {:.4} deg",
            self.max_axis_velocity_ratio, self.max_axis_acceleration_ratio, self.max_axis_jerk_ratio, self.max_following_error_mm, self.max_following_error_deg
        );
        let limit: Vec<_> = self.slow_regions.iter().filter(|r| !r.at_stop).collect();
        if limit.is_empty() {
            let _ = writeln!(o, "slow regions none below 50 % of the programmed feed (besides {} planned stops)", self.slow_regions.len());
        } else {
            let _ = writeln!(o, "slow regions below 50 % of the programmed feed (besides {} planned stops):", self.slow_regions.len() - limit.len());
            let _ = writeln!(o, "     x from     x to   blocks          lowest mm/min");
            for r in limit {
                let _ = writeln!(o, "   {:8.3} {:8.3}   {:<14} {:10.0}", r.x_start_mm, r.x_end_mm, crate::report::block_span(r.block_start, r.block_end, r.line_start, r.line_end), r.min_feed_mm_per_min);
            }
        }
        for r in &self.monitor_regions {
            let _ = writeln!(
                o,
                "monitor    region {} on the simulated stream: x {:.3} to {:.3} mm, {:.2} s, peak {c} {:.1} rpm, feed down to {:.0} mm/min",
                r.id, r.x_start_mm, r.x_end_mm, r.t_end_s - r.t_start_s, r.peak_c_speed_rpm, r.min_path_feed_mm_per_min
            );
        }
        o
    }
}
