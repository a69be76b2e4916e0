//! `fiveaxis-fleet view`: the head office's view of every machine on the fleet network. It
//! subscribes to every machine's status, `/diagnostics`, regions and axis states by wildcard (machines join and
//! leave without a restart), shows each one's state (OK/WARN/ERROR/STALE), distance, C demand and
//! regions this shift, asks each gateway for the shift's regions when a machine joins or comes back
//! from stale (the catch-up after an outage), writes its events as JSON lines, records what
//! reaches it to MCAP (a topic per machine) and streams it to a Rerun viewer (a machine per entity
//! tree).

use crate::rerun_out::{FleetRerun, RerunArgs};
use crate::zenoh_args::ZenohArgs;
use fiveaxis::record::{from_cdr, wall_clock_ns, OfferedQos, RecordOptions, Recorder};
use fiveaxis::topics::{self, Topic};
use fiveaxis_fleet::fleet::{Event, Fleet, Row};
use fiveaxis_fleet::keys::{self, MachinePath};
use fiveaxis_msgs::{DiagnosticArray, JointState, Region, RosMessage, SingularityStatus};
use std::collections::BTreeMap;
use std::io::Write;
use std::path::PathBuf;
use std::sync::mpsc;
use std::time::{Duration, Instant};
use zenoh::Wait;

#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(flatten)]
    zenoh: ZenohArgs,
    /// A machine not heard for this long is STALE, ms.
    #[arg(long = "stale-ms", default_value_t = 3000)]
    stale_ms: u64,
    /// Write the view's events (joined, region, stale, recovered) and, every `--table-every-s`,
    /// each machine's line, as JSON lines to this file (`-`: standard output).
    #[arg(long = "json-lines", value_name = "FILE")]
    json_lines: Option<PathBuf>,
    /// Print the fleet's table to standard error this often, s (0: never).
    #[arg(long = "table-every-s", default_value_t = 2.0)]
    table_every_s: f64,
    /// Record every message that reaches the office to this MCAP file (a topic per machine).
    #[arg(long = "record", value_name = "FILE.mcap")]
    record: Option<PathBuf>,
    #[command(flatten)]
    rerun: RerunArgs,
    /// Stop after this long, s (default: until SIGINT or SIGTERM).
    #[arg(long = "duration-s")]
    duration_s: Option<f64>,
    /// Regions remembered per machine, the newest (each is reported once; memory stays flat however
    /// long the view runs): at least the gateways' `--max-regions`, whose store a catch-up answers from.
    #[arg(long = "max-regions", default_value_t = fiveaxis_fleet::fleet::MAX_REGIONS)]
    max_regions: usize,
}

/// How often each machine's line goes to Rerun.
const RERUN_EVERY: Duration = Duration::from_millis(200);

/// The streams the view takes from each machine.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
enum Stream {
    Status,
    Diagnostics,
    Regions,
    /// One of [`topics::JOINT_STATES`] (recorded, not shown).
    Joints(usize),
}

impl Stream {
    /// Every stream the view subscribes to: one per joint-state topic, however many there are.
    fn all() -> impl Iterator<Item = Stream> {
        [Stream::Status, Stream::Diagnostics, Stream::Regions].into_iter().chain((0..topics::JOINT_STATES.len()).map(Stream::Joints))
    }

    fn topic(self) -> Topic {
        match self {
            Stream::Status => topics::STATUS,
            Stream::Diagnostics => topics::DIAGNOSTICS,
            Stream::Regions => topics::REGIONS,
            Stream::Joints(i) => topics::JOINT_STATES[i],
        }
    }

    /// Its message type's package and name.
    fn message(self) -> (&'static str, &'static str) {
        match self {
            Stream::Status => (SingularityStatus::PACKAGE, SingularityStatus::NAME),
            Stream::Diagnostics => (DiagnosticArray::PACKAGE, DiagnosticArray::NAME),
            Stream::Regions => (Region::PACKAGE, Region::NAME),
            Stream::Joints(_) => (JointState::PACKAGE, JointState::NAME),
        }
    }
}

/// What the network hands the loop.
enum In {
    /// A sample of a stream from a machine: its payload and rmw_zenoh attachment (seq, send stamp).
    Sample { path: MachinePath, stream: Stream, payload: Vec<u8>, sent: Option<keys::Sent>, received_ns: u64 },
    /// A region from a gateway's store.
    CaughtUp { path: MachinePath, payload: Vec<u8> },
}

/// The machines' lines as a table: what a process engineer reads.
fn table(rows: &[Row]) -> String {
    let mut out = format!("{:<32} {:<6} {:>13} {:>13} {:>8} {:>9} {:>7}\n", "machine", "state", "distance deg", "C demand rpm", "regions", "heard s", "rate/s");
    for r in rows {
        let f = |v: Option<f64>, p: usize| v.map_or("-".to_string(), |v| format!("{v:.p$}"));
        out += &format!("{:<32} {:<6} {:>13} {:>13} {:>8} {:>9.1} {:>7}\n", r.machine, r.state.name(), f(r.distance_deg, 3), f(r.c_demand_rpm, 1), r.regions, r.last_heard_s, r.status_rate_hz);
    }
    out
}

/// When a machine's catch-up is asked again after the first, from it (see where it is used).
const CATCH_UP_AGAIN: [Duration; 2] = [Duration::from_secs(2), Duration::from_secs(3)];

/// Run `f` on a thread of its own, or say why not (the system refused a thread: many machines
/// joining at once), rather than panic as `std::thread::spawn` does.
fn spawn_or_warn(what: &str, f: impl FnOnce() + Send + 'static) {
    if let Err(e) = std::thread::Builder::new().name(what.to_string()).spawn(f) {
        tracing::warn!("{what}: no thread: {e}");
    }
}

/// Ask the gateways matching `key` for their regions; the replies come back on `tx`.
fn catch_up(session: &zenoh::Session, key: String, domain: u16, tx: mpsc::SyncSender<In>) {
    // Every reply: they share the key, and Zenoh's default consolidation would keep only the latest.
    match session.get(&key).consolidation(zenoh::query::ConsolidationMode::None).timeout(Duration::from_secs(10)).wait() {
        Ok(replies) => {
            spawn_or_warn("catch-up replies", move || {
                while let Ok(reply) = replies.recv() {
                    if let Ok(sample) = reply.result() {
                        if let Some(path) = keys::machine_of_regions(sample.key_expr().as_str(), domain) {
                            let _ = tx.send(In::CaughtUp { path, payload: sample.payload().to_bytes().into_owned() });
                        }
                    }
                }
            });
        }
        Err(e) => tracing::warn!(%key, "catch-up query not sent: {e}"),
    }
}

/// The MCAP channels of the machines heard so far.
struct Recording {
    recorder: Recorder,
    channels: BTreeMap<(MachinePath, Stream), u16>,
}

impl Recording {
    fn write(&mut self, path: &MachinePath, stream: Stream, payload: &[u8], publish_ns: u64) -> anyhow::Result<()> {
        let key = (path.clone(), stream);
        let channel = match self.channels.get(&key) {
            Some(c) => *c,
            None => {
                let qos = if stream == Stream::Diagnostics { OfferedQos::DIAGNOSTICS } else { OfferedQos::STATE };
                let (package, name) = stream.message();
                let c = self.recorder.add_topic_type(&path.topic(&stream.topic()), &format!("{package}/msg/{name}"), qos)?;
                self.channels.insert(key, c);
                c
            }
        };
        self.recorder.write_raw(channel, payload, wall_clock_ns(), publish_ns)?;
        Ok(())
    }
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let shutdown = fiveaxis_bus::Shutdown::install()?;
    let domain = args.zenoh.domain;
    let config = args.zenoh.config("client")?;
    let mut json: Option<Box<dyn Write>> = match &args.json_lines {
        None => None,
        Some(p) if p.as_os_str() == "-" => Some(Box::new(std::io::stdout())),
        Some(p) => Some(Box::new(std::io::BufWriter::new(std::fs::File::create(p).map_err(|e| anyhow::anyhow!("{}: {e}", p.display()))?))),
    };
    let mut recording = match &args.record {
        None => None,
        Some(p) => Some(Recording { recorder: Recorder::create(p, RecordOptions::default()).map_err(|e| anyhow::anyhow!("{}: {e}", p.display()))?, channels: BTreeMap::new() }),
    };
    let mut rerun = FleetRerun::open(&args.rerun)?;
    let session = zenoh::open(config).wait().map_err(|e| anyhow::anyhow!("opening the fleet session: {e}"))?;
    let (tx, rx) = mpsc::sync_channel::<In>(65536);
    let mut subscribers = Vec::new();
    for stream in Stream::all() {
        let (topic, (package, name)) = (stream.topic(), stream.message());
        let key = keys::every_machine(domain, &topic, package, name);
        let tx = tx.clone();
        let sub = session
            .declare_subscriber(&key)
            .callback(move |sample| {
                let Some(path) = keys::machine_of(sample.key_expr().as_str(), domain, &topic) else { return };
                let sent = sample.attachment().and_then(|a| keys::attachment(&a.to_bytes()));
                let _ = tx.try_send(In::Sample { path, stream, payload: sample.payload().to_bytes().into_owned(), sent, received_ns: wall_clock_ns() });
            })
            .wait()
            .map_err(|e| anyhow::anyhow!("subscribing to {key}: {e}"))?;
        subscribers.push(sub);
    }
    tracing::info!(zid = %session.zid(), connect = ?args.zenoh.connect, "fleet view up");
    catch_up(&session, keys::every_regions_query(domain), domain, tx.clone());

    let mut fleet = Fleet::new(Duration::from_millis(args.stale_ms)).with_max_regions(args.max_regions);
    let start = Instant::now();
    let mut next_table = start;
    let mut next_rerun = start;
    let mut last_flush = start;
    let mut undecodable = 0u64;
    while !shutdown.requested() && !args.duration_s.is_some_and(|d| start.elapsed().as_secs_f64() >= d) {
        let mut events = Vec::new();
        match rx.recv_timeout(Duration::from_millis(50)) {
            Ok(In::Sample { path, stream, payload, sent, received_ns }) => {
                let now = Instant::now();
                let decoded = match stream {
                    Stream::Status => from_cdr::<SingularityStatus>(&payload).map(|s| events.extend(fleet.on_status(&path, s, sent, received_ns as i64, now))),
                    Stream::Regions => from_cdr::<Region>(&payload).map(|r| events.extend(fleet.on_region(&path, r, false, now))),
                    Stream::Diagnostics => from_cdr::<DiagnosticArray>(&payload).map(|d| events.extend(fleet.on_diagnostics(&path, &d, now))),
                    Stream::Joints(_) => from_cdr::<JointState>(&payload).map(|_| ()),
                };
                match decoded {
                    Ok(()) => {
                        if let Some(rec) = recording.as_mut() {
                            let publish_ns = sent.map_or_else(wall_clock_ns, |s| s.stamp_ns.max(0) as u64);
                            rec.write(&path, stream, &payload, publish_ns)?;
                        }
                    }
                    Err(e) => {
                        undecodable += 1;
                        if undecodable == 1 {
                            tracing::warn!(machine = %path, topic = stream.topic().absolute, "a message did not decode: {e} (counted)");
                        }
                    }
                }
            }
            Ok(In::CaughtUp { path, payload }) => match from_cdr::<Region>(&payload) {
                Ok(r) => {
                    let new = fleet.on_region(&path, r, true, Instant::now());
                    // A region first heard by a catch-up is recorded too (its own stamps say when it was).
                    if let (Some(rec), true) = (recording.as_mut(), new.iter().any(|e| matches!(e, Event::Region { .. }))) {
                        rec.write(&path, Stream::Regions, &payload, wall_clock_ns())?;
                    }
                    events.extend(new);
                }
                Err(_) => undecodable += 1,
            },
            Err(_) => {}
        }
        events.extend(fleet.tick(Instant::now()));
        if let Some(rr) = rerun.as_mut() {
            rr.events(start.elapsed().as_secs_f64(), &events)?;
            if Instant::now() >= next_rerun {
                next_rerun = Instant::now() + RERUN_EVERY;
                rr.rows(start.elapsed().as_secs_f64(), &fleet.rows(Instant::now()))?;
            }
        }
        for e in &events {
            match e {
                Event::Joined { machine } | Event::Recovered { machine, .. } => {
                    tracing::info!(%machine, "{}", if matches!(e, Event::Joined { .. }) { "machine joined" } else { "machine heard again" });
                    if let Ok(path) = MachinePath::parse(machine) {
                        let key = keys::regions_query(domain, &path);
                        catch_up(&session, key.clone(), domain, tx.clone());
                        // Again a little later: after an outage the machine's statuses can come
                        // before the routers have learnt its gateway's queryable again, and a query
                        // then reaches no one. A region is reported once however often it comes.
                        let (again, tx) = (session.clone(), tx.clone());
                        spawn_or_warn("catch-up again", move || {
                            for wait in CATCH_UP_AGAIN {
                                std::thread::sleep(wait);
                                catch_up(&again, key.clone(), domain, tx.clone());
                            }
                        });
                    }
                }
                Event::Stale { machine, silent_s } => tracing::warn!(%machine, silent_s, "machine stale"),
                Event::Region { machine, region_id, start_x_mm, peak_c_demand_rpm, caught_up, .. } => {
                    tracing::info!(%machine, region = region_id, x_mm = start_x_mm, peak_c_demand_rpm, caught_up, "region")
                }
            }
            if let Some(out) = json.as_mut() {
                writeln!(out, "{}", serde_json::to_string(e)?)?;
            }
        }
        let now = Instant::now();
        if now >= next_table && args.table_every_s > 0.0 {
            next_table = now + Duration::from_secs_f64(args.table_every_s);
            let rows = fleet.rows(now);
            if !rows.is_empty() {
                eprint!("{}", table(&rows));
            }
            if let Some(out) = json.as_mut() {
                for r in &rows {
                    writeln!(out, "{}", serde_json::json!({ "event": "line", "line": r }))?;
                }
            }
        }
        if now.duration_since(last_flush) >= Duration::from_secs(1) {
            last_flush = now;
            if let Some(out) = json.as_mut() {
                out.flush()?;
            }
            if let Some(rec) = recording.as_mut() {
                rec.recorder.flush()?;
            }
        }
    }
    let rows = fleet.rows(Instant::now());
    if let Some(out) = json.as_mut() {
        for r in &rows {
            writeln!(out, "{}", serde_json::json!({ "event": "final", "line": r }))?;
        }
        out.flush()?;
    }
    if let Some(mut rec) = recording {
        rec.recorder.finish()?;
    }
    if let Some(mut rr) = rerun {
        rr.rows(start.elapsed().as_secs_f64(), &rows)?;
        rr.flush();
    }
    tracing::info!(machines = rows.len(), undecodable, "fleet view done");
    drop(subscribers);
    let _ = session.close().wait();
    Ok(())
}
