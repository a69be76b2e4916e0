//! `fiveaxis-recorder`: records the node set's topics (or a chosen list) over DDS into MCAP, in the
//! rosbag2 layout. Log time = receive time, publish time = the message's source stamp. Chunks close
//! every second, so a kill loses at most the last second (`fiveaxis mcap recover` rebuilds the rest);
//! SIGINT/SIGTERM finish the file.

use anyhow::Context as _;
use clap::Parser;
use fiveaxis::record::{OfferedQos, RecordOptions, Recorder};
use fiveaxis_bus::{clock_qos, diagnostics_qos, init_tracing, state_qos, Bus, CommonArgs, Shutdown};
use fiveaxis_msgs::{AxisState, Clock, DiagnosticArray, JointState, RosMessage, SingularityStatus};
use ros2_client::QosProfile;
use serde::{de::DeserializeOwned, Serialize};
use std::path::PathBuf;
use std::sync::mpsc;
use std::time::{Duration, SystemTime, UNIX_EPOCH};

/// Record topics to MCAP.
#[derive(Parser)]
#[command(name = "fiveaxis-recorder", version)]
struct Args {
    #[command(flatten)]
    common: CommonArgs,
    /// The MCAP file to write.
    #[arg(long, short)]
    output: PathBuf,
    /// Topics to record as TOPIC:TYPE (TYPE: AxisState, JointState, SingularityStatus, DiagnosticArray,
    /// Clock); default: every topic of the node set.
    #[arg(long = "topic", value_name = "TOPIC:TYPE")]
    topics: Vec<String>,
    /// Stop after this long, s.
    #[arg(long = "duration-s")]
    duration_s: Option<f64>,
    /// Start a new file (NAME_0.mcap, NAME_1.mcap, ... as rosbag2 names them) once one reaches this
    /// size, MB.
    #[arg(long = "split-size-mb")]
    split_size_mb: Option<f64>,
    /// ... or spans this long, s.
    #[arg(long = "split-duration-s")]
    split_duration_s: Option<f64>,
}

/// The file of split `k` (the output itself when not splitting).
fn split_path(output: &std::path::Path, split: bool, k: usize) -> PathBuf {
    if !split {
        return output.to_path_buf();
    }
    let stem = output.file_stem().map_or("recording".into(), |s| s.to_string_lossy().into_owned());
    output.with_file_name(format!("{stem}_{k}.mcap"))
}

/// A recording file being written, and the channel id of each topic in it.
type Open = (Recorder<std::io::BufWriter<std::fs::File>>, std::collections::HashMap<String, u16>);

/// Open a recording with every topic declared.
fn open(path: &std::path::Path, topics: &[(String, String, OfferedQos)]) -> anyhow::Result<Open> {
    let mut rec = Recorder::create(path, RecordOptions::default())?;
    let mut ids = std::collections::HashMap::new();
    for (name, ty, qos) in topics {
        ids.insert(name.clone(), rec.add_topic_type(name, ty, *qos)?);
    }
    Ok((rec, ids))
}

/// A received message, encoded, with its times.
struct Item {
    topic: String,
    data: Vec<u8>,
    log_ns: u64,
    publish_ns: u64,
}

fn now_ns() -> u64 {
    SystemTime::now().duration_since(UNIX_EPOCH).map_or(0, |d| d.as_nanos() as u64)
}

/// The source stamp of a message, for MCAP's publish time.
trait Stamp {
    fn stamp_ns(&self) -> u64;
}
impl Stamp for AxisState {
    fn stamp_ns(&self) -> u64 {
        self.header.stamp.as_nanos()
    }
}
impl Stamp for JointState {
    fn stamp_ns(&self) -> u64 {
        self.header.stamp.as_nanos()
    }
}
impl Stamp for SingularityStatus {
    fn stamp_ns(&self) -> u64 {
        self.header.stamp.as_nanos()
    }
}
impl Stamp for DiagnosticArray {
    fn stamp_ns(&self) -> u64 {
        self.header.stamp.as_nanos()
    }
}
impl Stamp for Clock {
    fn stamp_ns(&self) -> u64 {
        self.clock.as_nanos()
    }
}

fn subscribe<M>(bus: &mut Bus, topic: &str, qos: QosProfile, tx: mpsc::SyncSender<Item>) -> anyhow::Result<String>
where
    M: RosMessage + Serialize + DeserializeOwned + Stamp + Send + 'static,
{
    let sub = bus.subscription::<M>(topic, qos)?;
    let name = bus.resolve(topic);
    let n = name.clone();
    std::thread::spawn(move || loop {
        match smol::block_on(sub.async_take()) {
            Ok((msg, _)) => {
                let log_ns = now_ns();
                match fiveaxis::record::to_cdr(&msg) {
                    Ok(data) => {
                        if tx.send(Item { topic: n.clone(), data, log_ns, publish_ns: msg.stamp_ns() }).is_err() {
                            break;
                        }
                    }
                    Err(e) => tracing::warn!(topic = %n, "encoding: {e}"),
                }
            }
            Err(e) => tracing::warn!(topic = %n, "read error: {e:?}"),
        }
    });
    Ok(name)
}

fn main() -> anyhow::Result<()> {
    let (args, ros) = fiveaxis_bus::ros_args::parse::<Args>("fiveaxis_recorder");
    init_tracing(&ros);
    let shutdown = Shutdown::install()?;
    let topics: Vec<(String, String)> = if args.topics.is_empty() {
        [
            ("commanded/axis_state", "AxisState"),
            ("commanded/joint_states", "JointState"),
            ("simulated/axis_state", "AxisState"),
            ("simulated/joint_states", "JointState"),
            ("monitor/status", "SingularityStatus"),
            ("/diagnostics", "DiagnosticArray"),
            ("/clock", "Clock"),
        ]
        .into_iter()
        .map(|(a, b)| (a.to_string(), b.to_string()))
        .collect()
    } else {
        args.topics
            .iter()
            .map(|t| t.rsplit_once(':').map(|(a, b)| (a.to_string(), b.to_string())).ok_or_else(|| anyhow::anyhow!("expected TOPIC:TYPE, got '{t}'")))
            .collect::<anyhow::Result<_>>()?
    };
    let mut bus = Bus::new("fiveaxis_recorder", &args.common, &ros)?;
    let (tx, rx) = mpsc::sync_channel::<Item>(65536);
    let mut declared: Vec<(String, String, OfferedQos)> = Vec::new();
    for (topic, ty) in &topics {
        let (name, qos, type_name) = match ty.as_str() {
            "AxisState" => (subscribe::<AxisState>(&mut bus, topic, state_qos(), tx.clone())?, OfferedQos::STATE, AxisState::type_name()),
            "JointState" => (subscribe::<JointState>(&mut bus, topic, state_qos(), tx.clone())?, OfferedQos::STATE, JointState::type_name()),
            "SingularityStatus" => (subscribe::<SingularityStatus>(&mut bus, topic, state_qos(), tx.clone())?, OfferedQos::STATE, SingularityStatus::type_name()),
            "DiagnosticArray" => (subscribe::<DiagnosticArray>(&mut bus, topic, diagnostics_qos(), tx.clone())?, OfferedQos::DIAGNOSTICS, DiagnosticArray::type_name()),
            "Clock" => (subscribe::<Clock>(&mut bus, topic, clock_qos(), tx.clone())?, OfferedQos::CLOCK, Clock::type_name()),
            other => anyhow::bail!("unknown type {other} for {topic}: AxisState, JointState, SingularityStatus, DiagnosticArray or Clock"),
        };
        tracing::info!(topic = %name, %type_name, "recording");
        declared.push((name, type_name, qos));
    }
    drop(tx);
    let split = args.split_size_mb.is_some() || args.split_duration_s.is_some();
    let mut k = 0;
    let mut path = split_path(&args.output, split, k);
    let (mut recorder, mut channels) = open(&path, &declared)?;
    let start = std::time::Instant::now();
    let mut file_start = start;
    let mut last_flush = start;
    let mut total = 0u64;
    while !shutdown.requested() {
        if args.duration_s.is_some_and(|d| start.elapsed().as_secs_f64() > d) {
            break;
        }
        match rx.recv_timeout(Duration::from_millis(50)) {
            Ok(item) => {
                let id = channels[&item.topic];
                recorder.write_raw(id, &item.data, item.log_ns, item.publish_ns).with_context(|| format!("writing {}", path.display()))?;
            }
            Err(mpsc::RecvTimeoutError::Timeout) => {}
            Err(mpsc::RecvTimeoutError::Disconnected) => break,
        }
        // Idle streams still get their chunk closed within a second.
        if last_flush.elapsed() >= Duration::from_secs(1) {
            recorder.flush()?;
            last_flush = std::time::Instant::now();
            let size_mb = std::fs::metadata(&path).map_or(0.0, |m| m.len() as f64 / 1e6);
            let too_big = args.split_size_mb.is_some_and(|l| size_mb >= l);
            let too_long = args.split_duration_s.is_some_and(|l| file_start.elapsed().as_secs_f64() >= l);
            if too_big || too_long {
                let (next, ids) = open(&split_path(&args.output, split, k + 1), &declared)?;
                total += std::mem::replace(&mut recorder, next).finish()?;
                tracing::info!(file = %path.display(), "split finished");
                k += 1;
                path = split_path(&args.output, split, k);
                channels = ids;
                file_start = std::time::Instant::now();
            }
        }
    }
    // Drain what already arrived, then finish the file.
    while let Ok(item) = rx.try_recv() {
        let id = channels[&item.topic];
        recorder.write_raw(id, &item.data, item.log_ns, item.publish_ns)?;
    }
    let n = total + recorder.finish()?;
    tracing::info!(messages = n, files = k + 1, file = %path.display(), "recording finished");
    Ok(())
}
