//! The embedded default: commander, simulator and monitor in one process, each on its own thread,
//! connected by bounded in-process channels instead of DDS, faster than real time. The node logic is
//! the same as the executables'.

use super::commander::{commanded_moves, CommandedValues};
use super::monitor::{LiveRegion, Monitor, MonitorConfig};
pub use super::sim_report::{SimulatedReport, SlowRegion};
use super::sim_report::{simulate_measured_stream, FeedFiguresReport};
use super::simulator::{SimConfig, SimSummary, Simulation};
use super::{StateBuilder, StateValues};
use crate::job::{self, Job, JobError, JobOptions, Moves};
use crate::path::{Segment, SharedRead};
use crate::machine::Machine;
use crate::report::AnalysisReport;
use fiveaxis_msgs::{AxisState, SingularityStatus};
use serde::Serialize;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::mpsc;
use crate::topics;

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
    /// Keep every simulated sample in [`RunOutput::simulation`] (memory grows with the program).
    pub keep_simulation: bool,
    /// Make only what the report shows or the recording holds: without a recording or kept statuses
    /// the commander's states are not made (the program's analysis is, along the same reading), so
    /// the monitor has no commanded stream: no look-ahead (which feeds only the statuses and
    /// diagnostics nothing keeps then) and [`RunOutput::commanded_regions`] stays empty (`fiveaxis
    /// run` prints neither).
    pub report_only: bool,
}

/// How far (s of commanded time) the in-process commander runs ahead of the simulated machine's place
/// in the program: at least [`COMMANDER_LEAD_MIN_S`] (the simulator waits for it), at most
/// [`COMMANDER_LEAD_MAX_S`] (the commander waits). The monitor's look-ahead sees the regions within
/// that lead, and what it holds stays bounded whatever the program's length.
pub const COMMANDER_LEAD_MIN_S: f64 = 10.0;
pub const COMMANDER_LEAD_MAX_S: f64 = 60.0;

/// A side that has had to wait waits on until the other has moved this far (s of commanded time)
/// past the point where it had to: it then works in bursts instead of waking for every batch the
/// other makes (on one core, each wake-up was a context switch: about a third of a run's). The
/// leads stay within [`COMMANDER_LEAD_MIN_S`] and [`COMMANDER_LEAD_MAX_S`], and the two sides still
/// never wait on each other at once (60 - 5 > 10 + 5).
const PACE_HYSTERESIS_S: f64 = 5.0;

/// Where the commander and the simulator are, in commanded time (f64 bits; infinite once done).
struct Pace {
    commanded: AtomicU64,
    simulated: AtomicU64,
}

impl Pace {
    fn get(a: &AtomicU64) -> f64 {
        f64::from_bits(a.load(Ordering::Acquire))
    }
    fn set(a: &AtomicU64, t: f64) {
        a.store(t.to_bits(), Ordering::Release);
    }
    /// If `ahead(0)` says to wait, wait while `ahead(PACE_HYSTERESIS_S)` does, polling at 0.2 ms
    /// doubling to 3.2 ms (the two never wait on each other at once: see the leads).
    fn wait(ahead: impl Fn(f64) -> bool) {
        if !ahead(0.0) {
            return;
        }
        let mut pause = std::time::Duration::from_micros(200);
        while ahead(PACE_HYSTERESIS_S) {
            std::thread::sleep(pause);
            pause = (pause * 2).min(std::time::Duration::from_micros(3200));
        }
    }

    /// The commander at commanded time `t` waits while it is more than [`COMMANDER_LEAD_MAX_S`]
    /// ahead of the simulator.
    fn commander_at(&self, t: f64) {
        Pace::wait(|slack| t > Pace::get(&self.simulated) + COMMANDER_LEAD_MAX_S - slack);
    }
}

/// Records the node set's topics in program time (the in-process clock, as with use_sim_time) to a
/// rosbag2 bag (a directory, or one `.mcap` file when so named).
struct Tape {
    rec: crate::record::bag::Bag,
    ids: [usize; 7],
    next_diag: f64,
}

impl Tape {
    fn create(path: &std::path::Path) -> Result<Tape, crate::record::RecordError> {
        use crate::record::{bag::Bag, OfferedQos};
        use fiveaxis_msgs::{Clock, DiagnosticArray, JointState};
        let mut rec = Bag::create(path, false, Default::default())?;
        let ids = [
            rec.add::<AxisState>(topics::COMMANDED_STATE.absolute, OfferedQos::STATE)?,
            rec.add::<JointState>(topics::COMMANDED_JOINTS.absolute, OfferedQos::STATE)?,
            rec.add::<AxisState>(topics::SIMULATED_STATE.absolute, OfferedQos::STATE)?,
            rec.add::<JointState>(topics::SIMULATED_JOINTS.absolute, OfferedQos::STATE)?,
            rec.add::<SingularityStatus>(topics::STATUS.absolute, OfferedQos::STATE)?,
            rec.add::<DiagnosticArray>(topics::DIAGNOSTICS.absolute, OfferedQos::DIAGNOSTICS)?,
            rec.add::<Clock>(topics::CLOCK.absolute, OfferedQos::CLOCK)?,
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

/// `fiveaxis run --json`: the analysis keys plus `simulated`.
#[derive(Debug, Clone, Serialize)]
pub struct RunReport {
    #[serde(flatten)]
    pub analysis: AnalysisReport,
    pub simulated: SimulatedReport,
}

/// Everything a run produced.
pub struct RunOutput {
    /// The job read whole (trajectory, analysis), if [`RunOptions::keep_simulation`] (to look the
    /// simulation's segments up); the run itself streams the program.
    pub job: Option<Job>,
    /// Every simulated sample, if [`RunOptions::keep_simulation`].
    pub simulation: Option<Simulation>,
    pub simulated_states: usize,
    pub report: RunReport,
    /// The monitor's statuses on the simulated and on the commanded stream, in order (empty unless
    /// [`RunOptions::keep_statuses`]).
    pub statuses: Vec<SingularityStatus>,
    pub commanded_statuses: Vec<SingularityStatus>,
    /// Regions the monitor saw on the commanded stream (none with [`RunOptions::report_only`]).
    pub commanded_regions: Vec<LiveRegion>,
    /// Messages written to the MCAP recording, if one was asked for.
    pub recorded_messages: Option<u64>,
}

impl RunOutput {
    /// True if the program or its planning had defects.
    pub fn has_errors(&self) -> bool {
        self.report.analysis.errors > 0
    }
}

/// States cross to the monitor in batches of this many: one channel operation (and at most one
/// wake-up) per batch instead of per state. About 4 s of program at 1 kHz, inside the commander's
/// lead ([`COMMANDER_LEAD_MIN_S`]); on one core each batch costs two context switches (the monitor
/// wakes, takes it, sleeps): 4096 rather than 1024 takes a 1 h run from 33 k to 14 k switches
/// (about 850 kB a batch).
const BATCH: usize = 4096;

/// A batch of states of one stream, in time order.
enum Input {
    Commanded(Vec<StateValues>),
    Simulated(Vec<StateValues>),
}

/// Collects states into batches ([`BATCH`]) and sends each full one.
struct Batcher {
    batch: Vec<StateValues>,
    wrap: fn(Vec<StateValues>) -> Input,
}

impl Batcher {
    fn new(wrap: fn(Vec<StateValues>) -> Input) -> Batcher {
        Batcher { batch: Vec::with_capacity(BATCH), wrap }
    }

    /// Add `v`; send the batch once full. The number of states sent (0 until a batch goes), or None
    /// once the monitor has gone.
    fn push(&mut self, tx: &mpsc::SyncSender<Input>, v: StateValues) -> Option<u64> {
        self.batch.push(v);
        if self.batch.len() < BATCH {
            return Some(0);
        }
        self.flush(tx)
    }

    /// Send what is collected.
    fn flush(&mut self, tx: &mpsc::SyncSender<Input>) -> Option<u64> {
        if self.batch.is_empty() {
            return Some(0);
        }
        let n = self.batch.len() as u64;
        let batch = std::mem::replace(&mut self.batch, Vec::with_capacity(BATCH));
        tx.send((self.wrap)(batch)).ok().map(|_| n)
    }
}

/// Run the node set in one process on `spec`. The program is read as a stream ([`Moves`]): once for
/// the commander (which makes the program's analysis along its reading) and the simulator's scout,
/// and again by the simulator's planner only past what its scout keeps for it. The
/// commander's and the simulator's states stream through bounded channels into the monitor (and
/// the recording) as they are made; nothing is held per sample or per block unless asked
/// ([`RunOptions::keep_simulation`], [`RunOptions::keep_statuses`]), so memory does not grow with the
/// program's length.
pub fn run(spec: &str, machine: &Machine, options: &RunOptions) -> Result<RunOutput, JobError> {
    let options = options.clone();
    let options = &options;
    let moves = Moves::open(spec, machine, &options.job)?;
    let job = if options.keep_simulation { Some(moves.whole(machine)?) } else { None };
    let period = moves.period();
    let (tx, rx) = mpsc::sync_channel::<Input>(1);
    let tape = match &options.mcap {
        Some(path) => Some(Tape::create(path)?),
        None => None,
    };
    let pace = Pace {
        commanded: AtomicU64::new(0f64.to_bits()),
        simulated: AtomicU64::new(0f64.to_bits()),
    };
    let moves = &moves;
    // A program is read and segmented once for the commander, the analysis and the simulator's
    // scout: the commander makes the analysis along its reading (a built-in path's report is made
    // from its held samples), and shares the reading with the simulator (`SharedRead`: whichever is
    // ahead reads on; one that falls too far behind reads a copy of its own, opened again here).
    let shared = moves.segment_stream(machine)?.map(SharedRead::new);
    let shared = shared.as_ref();
    let reopen_failed = std::sync::Mutex::new(None);
    let reopen_failed = &reopen_failed;
    let reopen = move || {
        let stream = moves.segment_stream(machine);
        if let Ok(Some(stream)) = stream {
            return Some(stream);
        }
        let e = stream.err().unwrap_or(JobError::FeedCut);
        reopen_failed.lock().unwrap_or_else(|e| e.into_inner()).get_or_insert(e);
        None
    };
    // A report-only run that records and keeps nothing makes only what its report shows: no
    // commanded states (they feed the monitor's look-ahead and commanded statuses, which nothing
    // keeps then) and no feed limits in the monitor's evaluations (the report lists regions).
    let lean = options.report_only && options.mcap.is_none() && !options.keep_statuses;
    let (analysis, sim_out, sent, statuses, monitor, tape_result) = std::thread::scope(|scope| {
        // A built-in path's report is made from its held samples, beside the commander.
        let analysis = moves.held().is_some().then(|| scope.spawn(move || moves.report(machine)));
        let tx_cmd = tx.clone();
        let pace = &pace;
        let commander = scope.spawn(move || -> Result<(u64, Option<AnalysisReport>), JobError> {
            let mut sent = 0u64;
            let mut batch = Batcher::new(Input::Commanded);
            // Without states, the commander still keeps its lead on the simulator (the two share
            // their reading of the program) and says how far it is, as often as a batch would.
            let mut sampled = 0usize;
            let mut keep_pace = |t: f64| {
                pace.commander_at(t);
                sampled += 1;
                if sampled.is_multiple_of(BATCH) {
                    Pace::set(&pace.commanded, t);
                }
            };
            // Publish one state; false once the monitor has gone.
            let mut publish = |st: StateValues| {
                let t = st.t;
                pace.commander_at(t);
                match batch.push(&tx_cmd, st) {
                    None => false,
                    Some(0) => true,
                    // The monitor has every state up to t.
                    Some(n) => {
                        Pace::set(&pace.commanded, t);
                        sent += n;
                        true
                    }
                }
            };
            let published = match shared {
                Some(shared) => {
                    // The program's analysis samples it as the commander must: the commander publishes
                    // the analysis's samples (one sampling of the program for both), and the analysis
                    // goes on to the program's end if the commander stops publishing early.
                    let mut reader = shared.reader(0, reopen);
                    let mut values = CommandedValues::new(machine, period);
                    let mut publishing = true;
                    let (analysis, counts) = crate::singularity::analyze_segments_along(reader.by_ref(), period, machine, &options.job.analysis, |cur, next, seg| {
                        match (publishing, lean) {
                            (false, _) => {}
                            (true, false) => publishing = publish(values.next(cur, next, seg)),
                            (true, true) => keep_pace(cur.t),
                        }
                    });
                    match reader.failed() {
                        // The reading's end is not known (the reopening's error is the run's).
                        true => Err(JobError::FeedCut),
                        false => reader.with_source(|stream| job::report_of_reading(stream, &analysis, counts, machine, &options.job)).map(Some),
                    }
                }
                None => commanded_moves(moves, machine).map(|states| {
                    for st in states {
                        if !publish(st) {
                            break;
                        }
                    }
                    None
                }),
            };
            sent += batch.flush(&tx_cmd).unwrap_or(0);
            Pace::set(&pace.commanded, f64::INFINITY);
            published.map(|report| (sent, report))
        });
        let tx_sim = tx;
        let simulator = scope.spawn(move || -> Result<_, JobError> {
            // The scout shares the commander's reading; the planner's second copy is read only past
            // what the scout keeps for it (a run longer than its bound).
            let scout = match shared {
                Some(shared) => Ok(Box::new(shared.reader(1, reopen)) as Box<dyn Iterator<Item = Segment> + '_>),
                None => moves.segments(machine),
            };
            let opened = moves.segments(machine).and_then(|s| Ok((s, scout?)));
            let (segments, scout) = match opened {
                Ok(o) => o,
                Err(e) => {
                    Pace::set(&pace.simulated, f64::INFINITY);
                    return Err(e);
                }
            };
            let mut kept = options.keep_simulation.then(|| Simulation::empty(period));
            let mut sent = 0u64;
            let mut batch = Batcher::new(Input::Simulated);
            let mut last_segment = usize::MAX;
            let (summary, figures) = simulate_measured_stream(segments, scout, period, machine, &options.sim, |s, seg, st| {
                if s.segment != last_segment {
                    last_segment = s.segment;
                    let t0 = seg.map_or(f64::INFINITY, |g| g.t0);
                    Pace::set(&pace.simulated, t0);
                    Pace::wait(|slack| t0 + COMMANDER_LEAD_MIN_S + slack > Pace::get(&pace.commanded));
                }
                if let Some(k) = kept.as_mut() {
                    k.push(s);
                }
                let n = batch.push(&tx_sim, st);
                sent += n.unwrap_or(0);
                n.is_some()
            });
            sent += batch.flush(&tx_sim).unwrap_or(0);
            // The commander may run to the end.
            Pace::set(&pace.simulated, f64::INFINITY);
            if let Some(k) = kept.as_mut() {
                k.measured(&summary);
            }
            Ok((summary, figures, kept, sent))
        });
        let mut tape = tape;
        let monitor = scope.spawn(move || {
            let mut m = Monitor::new(machine, options.monitor);
            let mut statuses = Vec::new();
            let mut commanded = Vec::new();
            let mut received = 0u64;
            let mut tape_error = None;
            // One message per stream, refilled for each state (nothing allocated per state).
            let builders = [AxisState::SOURCE_COMMANDED, AxisState::SOURCE_SIMULATED].map(|s| StateBuilder::new(machine, s));
            let mut messages: [Option<AxisState>; 2] = [None, None];
            let want_status = tape.is_some() || options.keep_statuses;
            m.set_regions_only(lean);
            let mut ids: [Option<crate::live::monitor::InputId>; 2] = [None, None];
            let inputs = rx.into_iter().map(|input| match input {
                Input::Commanded(b) => (0, b),
                Input::Simulated(b) => (1, b),
            });
            // Each state is read where its batch holds it, not moved out (about 200 bytes each).
            for (k, batch) in inputs {
                for v in &batch {
                    received += 1;
                    let st: &AxisState = match &mut messages[k] {
                        Some(st) => {
                            builders[k].fill(v, st);
                            st
                        }
                        slot => slot.insert(builders[k].message(v)),
                    };
                    let topic = if k == 0 {
                        m.on_commanded_ahead(st);
                        topics::COMMANDED_STATE.name
                    } else {
                        topics::SIMULATED_STATE.name
                    };
                    let wall = st.header.stamp.as_secs();
                    if !want_status {
                        // Nothing records or keeps the status message: evaluate only (no per-state allocation).
                        let id = *ids[k].get_or_insert_with(|| m.input(topic));
                        let _ = m.evaluate(id, st, wall);
                        continue;
                    }
                    let status = m.on_state(topic, st, wall);
                    if let (Some(t), None) = (tape.as_mut(), &tape_error) {
                        let r = t
                            .state(st, topic == topics::COMMANDED_STATE.name, &m)
                            .and_then(|_| match &status {
                                Ok(s) => t.status(s),
                                Err(_) => Ok(()),
                            });
                        if let Err(e) = r {
                            tape_error = Some(e);
                        }
                    }
                    if let Some(s) = status.ok().filter(|_| options.keep_statuses) {
                        if topic == topics::SIMULATED_STATE.name {
                            statuses.push(s);
                        } else {
                            commanded.push(s);
                        }
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
        let (commanded, along) = match commander.join().expect("commander thread") {
            Ok((sent, report)) => (Ok(sent), report),
            Err(e) => (Err(e), None),
        };
        // The report: the built-in path's own, else the one made along the commander's reading.
        let analysis = match (analysis, along) {
            (Some(a), _) => a.join().expect("analysis thread"),
            (None, Some(report)) => Ok(report),
            (None, None) => Err(JobError::FeedCut),
        };
        let simulated = simulator.join().expect("simulator thread");
        let (m, statuses, received, tape_result) = monitor.join().expect("monitor thread");
        let sim_out = commanded.and_then(|sent_cmd| simulated.map(|s| (s, sent_cmd)));
        let lost = sim_out.as_ref().map_or(0, |((.., sent_sim), sent_cmd)| (sent_cmd + sent_sim).saturating_sub(received));
        (analysis, sim_out, lost, statuses, m, tape_result)
    });
    // A reader that fell behind and could not read the program again: what it read is not the
    // program (fail closed).
    if let Some(e) = reopen_failed.lock().unwrap_or_else(|e| e.into_inner()).take() {
        return Err(e);
    }
    // One that opened a copy but could not read it to where it was (the file changed under it).
    if shared.is_some_and(|s| s.failed()) {
        return Err(JobError::FeedCut);
    }
    // A feed cut short by the commander's failure: the commander's error says why.
    let analysis = match (analysis, &sim_out) {
        (Err(JobError::FeedCut), Err(_)) => None,
        (a, _) => Some(a?),
    };
    let ((summary, figures, simulation, _), _) = sim_out?;
    let analysis = analysis.ok_or(JobError::FeedCut)?;
    let recorded_messages = tape_result?;
    let simulated = simulated_report(analysis.cycle_time_s, &summary, figures, sent, &monitor);
    let report = RunReport { analysis, simulated };
    let (statuses, commanded_statuses) = statuses;
    Ok(RunOutput {
        recorded_messages,
        simulated_states: summary.samples as usize,
        simulation,
        job,
        report,
        statuses,
        commanded_statuses,
        commanded_regions: monitor.regions(topics::COMMANDED_STATE.name),
    })
}

/// `commanded_s`: the commanded cycle time, s.
fn simulated_report(
    commanded_s: f64,
    summary: &SimSummary,
    f: FeedFiguresReport,
    lost: u64,
    monitor: &Monitor,
) -> SimulatedReport {
    let (samples, ..) = monitor.counters(topics::SIMULATED_STATE.name);
    SimulatedReport {
        cycle_time_s: f.duration_s,
        commanded_cycle_time_s: commanded_s,
        min_feed_mm_per_min: if f.lowest_feed.is_finite() {
            crate::units::mm_per_min(f.lowest_feed)
        } else {
            0.0
        },
        min_feed_x_mm: f.lowest_feed_x * 1e3,
        slow_regions: f.slow_regions,
        unlisted_slow_regions: f.unlisted_slow_regions,
        planned_stops: f.planned_stops,
        max_axis_velocity_ratio: f.worst_ratio[0],
        max_axis_acceleration_ratio: f.worst_ratio[1],
        max_axis_jerk_ratio: f.worst_ratio[2],
        max_following_error_mm: summary.following_error_linear * 1e3,
        max_following_error_deg: summary.following_error_rotary.to_degrees(),
        samples: f.samples as usize,
        lost_samples: lost,
        monitor_regions: monitor.regions(topics::SIMULATED_STATE.name),
        unlisted_monitor_regions: monitor.unlisted_regions(topics::SIMULATED_STATE.name),
        monitor_statuses: samples,
    }
}
