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
    init_tracing();
    let args = Args::parse();
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
    let mut recorder = Recorder::create(&args.output, RecordOptions::default())?;
    let mut bus = Bus::new("fiveaxis_recorder", &args.common)?;
    let (tx, rx) = mpsc::sync_channel::<Item>(65536);
    let mut channels = std::collections::HashMap::new();
    for (topic, ty) in &topics {
        let (name, qos, type_name) = match ty.as_str() {
            "AxisState" => (subscribe::<AxisState>(&mut bus, topic, state_qos(), tx.clone())?, OfferedQos::STATE, AxisState::type_name()),
            "JointState" => (subscribe::<JointState>(&mut bus, topic, state_qos(), tx.clone())?, OfferedQos::STATE, JointState::type_name()),
            "SingularityStatus" => (subscribe::<SingularityStatus>(&mut bus, topic, state_qos(), tx.clone())?, OfferedQos::STATE, SingularityStatus::type_name()),
            "DiagnosticArray" => (subscribe::<DiagnosticArray>(&mut bus, topic, diagnostics_qos(), tx.clone())?, OfferedQos::DIAGNOSTICS, DiagnosticArray::type_name()),
            "Clock" => (subscribe::<Clock>(&mut bus, topic, clock_qos(), tx.clone())?, OfferedQos::CLOCK, Clock::type_name()),
            other => anyhow::bail!("unknown type {other} for {topic}: AxisState, JointState, SingularityStatus, DiagnosticArray or Clock"),
        };
        let id = recorder.add_topic_type(&name, &type_name, qos)?;
        tracing::info!(topic = %name, %type_name, "recording");
        channels.insert(name, id);
    }
    drop(tx);
    let start = std::time::Instant::now();
    let mut last_flush = start;
    while !shutdown.requested() {
        if args.duration_s.is_some_and(|d| start.elapsed().as_secs_f64() > d) {
            break;
        }
        match rx.recv_timeout(Duration::from_millis(50)) {
            Ok(item) => {
                let id = channels[&item.topic];
                recorder.write_raw(id, &item.data, item.log_ns, item.publish_ns).with_context(|| format!("writing {}", args.output.display()))?;
            }
            Err(mpsc::RecvTimeoutError::Timeout) => {}
            Err(mpsc::RecvTimeoutError::Disconnected) => break,
        }
        // Idle streams still get their chunk closed within a second.
        if last_flush.elapsed() >= Duration::from_secs(1) {
            recorder.flush()?;
            last_flush = std::time::Instant::now();
        }
    }
    // Drain what already arrived, then finish the file.
    while let Ok(item) = rx.try_recv() {
        let id = channels[&item.topic];
        recorder.write_raw(id, &item.data, item.log_ns, item.publish_ns)?;
    }
    let n = recorder.finish()?;
    tracing::info!(messages = n, file = %args.output.display(), "recording finished");
    Ok(())
}
