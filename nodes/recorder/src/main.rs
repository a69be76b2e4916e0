//! `fiveaxis-recorder`: records topics over DDS into a rosbag2 bag, as `ros2 bag record` does: a
//! directory with `metadata.yaml` and `NAME_0.mcap`, ... (or one `.mcap` file when the output is
//! named so). Messages are stored as the bytes received, of any type (`--all`, or `TOPIC:pkg/msg/T`);
//! log time = receive time (with `use_sim_time` the node's clock, /clock's time, as `ros2 bag record
//! --use-sim-time`), publish time = the writer's send time (DDS source timestamp). Chunks
//! close every second, so a kill loses at most the last second (`fiveaxis mcap recover` rebuilds the
//! rest); SIGINT/SIGTERM finish the bag.

use clap::Parser;
use fiveaxis::record::bag::{Bag, BagTopic};
use fiveaxis::record::{OfferedQos, RecordOptions};
use fiveaxis_bus::raw::{dds_type_name, ros_type_name, RawSubscription};
use fiveaxis_bus::{clock_qos, diagnostics_qos, init_tracing, state_qos, Bus, CommonArgs, Shutdown};
use fiveaxis_msgs::{AxisState, Clock, DiagnosticArray, JointState, RosMessage, SingularityStatus};
use ros2_client::qos::{Durability, History};
use ros2_client::QosProfile;
use std::collections::BTreeMap;
use std::path::PathBuf;
use std::sync::mpsc;
use std::time::{Duration, Instant};

/// Record topics to a rosbag2 bag.
#[derive(Parser)]
#[command(name = "fiveaxis-recorder", version)]
struct Args {
    #[command(flatten)]
    common: CommonArgs,
    /// The bag to write: a rosbag2 directory (created; metadata.yaml and NAME_0.mcap, ...), or one
    /// MCAP file when the name ends in .mcap.
    #[arg(long, short)]
    output: PathBuf,
    /// Topics to record as TOPIC:TYPE, TYPE one of the node set's (AxisState, JointState,
    /// SingularityStatus, DiagnosticArray, Clock) or any ROS type pkg/msg/Type (recorded as
    /// received; its definition stored where fiveaxis knows it). Default: every topic of the node set.
    #[arg(long = "topic", value_name = "TOPIC:TYPE", conflicts_with = "all")]
    topics: Vec<String>,
    /// Record every topic on the domain, of any type, as its publishers appear (as `ros2 bag record
    /// --all`): reliable where every announcement is, transient-local where every one is.
    #[arg(long)]
    all: bool,
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

/// A received message with its times; `topic` indexes the bag's topics.
struct Item {
    topic: usize,
    data: Vec<u8>,
    log_ns: u64,
    publish_ns: u64,
}

/// Bad input (a `--topic` that does not parse, a bag that cannot be created or written: a full
/// disk, say): the reason, exit 2, as `fiveaxis run --mcap` on the same failure.
fn bad_input(e: &anyhow::Error) -> ! {
    eprintln!("fiveaxis-recorder: {e:#}");
    std::process::exit(2)
}

/// A bag write that failed: the file was closed at its last whole chunk (the error says so); exit 2.
fn written<T>(r: Result<T, fiveaxis::record::RecordError>) -> T {
    r.unwrap_or_else(|e| bad_input(&e.into()))
}

/// A topic to record: its name, type `pkg/msg/Type`, the reader's QoS and the QoS noted in the bag.
type Plan = (String, String, QosProfile, OfferedQos);

/// The node set's message types by short name: the full type name, and the QoS their topics use.
fn our_type(short: &str) -> Option<(String, QosProfile, OfferedQos)> {
    Some(match short {
        "AxisState" => (AxisState::type_name(), state_qos(), OfferedQos::STATE),
        "JointState" => (JointState::type_name(), state_qos(), OfferedQos::STATE),
        "SingularityStatus" => (SingularityStatus::type_name(), state_qos(), OfferedQos::STATE),
        "DiagnosticArray" => (DiagnosticArray::type_name(), diagnostics_qos(), OfferedQos::DIAGNOSTICS),
        "Clock" => (Clock::type_name(), clock_qos(), OfferedQos::CLOCK),
        _ => return None,
    })
}

/// The short names [`our_type`] knows.
const OUR_TYPES: [&str; 5] = ["AxisState", "JointState", "SingularityStatus", "DiagnosticArray", "Clock"];

/// A `--topic TOPIC:TYPE`: one of the node set's types (short or full name) with its QoS; any other
/// ROS type name is recorded reliable (keep-last 1000, volatile).
fn parse_topic(spec: &str) -> anyhow::Result<Plan> {
    let (topic, ty) = spec.rsplit_once(':').filter(|(t, y)| !t.is_empty() && !y.is_empty()).ok_or_else(|| anyhow::anyhow!("--topic '{spec}': expected TOPIC:TYPE"))?;
    if let Some((full, q, o)) = OUR_TYPES.iter().filter_map(|short| our_type(short)).find(|(full, ..)| full == ty).or_else(|| our_type(ty)) {
        return Ok((topic.to_string(), full, q, o));
    }
    let parts: Vec<&str> = ty.split('/').collect();
    if parts.len() != 3 || parts.iter().any(|p| p.is_empty()) || parts[1] != "msg" {
        anyhow::bail!("--topic '{spec}': unknown type '{ty}': {} or a ROS type pkg/msg/Type", OUR_TYPES.join(", "));
    }
    Ok((topic.to_string(), ty.to_string(), state_qos(), OfferedQos::STATE))
}

/// Read `sub` on its own thread onto the recorder's channel, as topic `index`.
fn forward(sub: RawSubscription, index: usize, name: String, tx: mpsc::SyncSender<Item>) {
    std::thread::spawn(move || loop {
        match smol::block_on(sub.take()) {
            Ok(m) => {
                let log_ns = fiveaxis::record::wall_clock_ns();
                let item = Item { topic: index, data: m.data, log_ns, publish_ns: m.sent_ns.unwrap_or(log_ns) };
                if tx.send(item).is_err() {
                    break;
                }
            }
            Err(e) => {
                tracing::warn!(topic = %name, "{e:#}");
                std::thread::sleep(Duration::from_millis(100));
            }
        }
    });
}

/// Subscribe to `topic` raw and declare it in the bag.
fn record(bus: &mut Bus, bag: &mut Bag, tx: &mpsc::SyncSender<Item>, topic: &str, type_name: &str, qos: &QosProfile, offered: OfferedQos) -> anyhow::Result<()> {
    let name = bus.resolve(topic);
    let sub = bus.raw_subscription(topic, &dds_type_name(type_name), qos)?;
    let index = bag.add_topic(BagTopic::named(&name, type_name, offered))?;
    tracing::info!(topic = %name, %type_name, "recording");
    forward(sub, index, name, tx.clone());
    Ok(())
}

/// The topics discovered on the domain (ROS topics, `rt/...`), with the QoS every announcement
/// allows: reliable only if all are, transient-local only if all are.
fn discovered(bus: &Bus) -> BTreeMap<String, (String, bool, bool)> {
    use ros2_client::dds::rustdds::policy::{Durability as D, Reliability as R};
    let mut out: BTreeMap<String, (String, bool, bool)> = BTreeMap::new();
    for t in bus.context().discovered_topics_raw() {
        let data = &t.topic_data;
        let Some(name) = data.name.strip_prefix("rt") else { continue };
        let reliable = !matches!(data.reliability, Some(R::BestEffort));
        let transient = matches!(data.durability, Some(D::TransientLocal | D::Transient | D::Persistent));
        let e = out.entry(name.to_string()).or_insert((data.type_name.clone(), true, true));
        e.1 &= reliable;
        e.2 &= transient;
    }
    out
}

fn main() -> anyhow::Result<()> {
    let (args, ros) = fiveaxis_bus::ros_args::parse::<Args>("fiveaxis_recorder");
    init_tracing(&ros);
    let shutdown = Shutdown::install()?;
    let topics = if args.all {
        Vec::new()
    } else if args.topics.is_empty() {
        fiveaxis::topics::NODE_SET.iter().map(|t| parse_topic(&format!("{}:{}", t.name, t.ty))).collect::<anyhow::Result<_>>()?
    } else {
        args.topics.iter().map(|t| parse_topic(t)).collect::<anyhow::Result<_>>().unwrap_or_else(|e| bad_input(&e))
    };
    let split = args.split_size_mb.is_some() || args.split_duration_s.is_some();
    // Checked before the node joins the graph: a bag that cannot be written is bad input (exit 2).
    let mut bag = Bag::create(&args.output, split, RecordOptions::default()).unwrap_or_else(|e| bad_input(&anyhow::anyhow!("creating the bag: {e}")));
    let mut bus = Bus::new("fiveaxis_recorder", &args.common, &ros)?;
    let (tx, rx) = mpsc::sync_channel::<Item>(65536);
    for (topic, ty, qos, offered) in &topics {
        record(&mut bus, &mut bag, &tx, topic, ty, qos, *offered)?;
    }
    // Receive time on the node's clock: wall time as received, or /clock's time (use_sim_time).
    let sim = args.common.use_sim_time;
    let log_ns = |bus: &Bus, item: &Item| if sim { bus.now().as_nanos() } else { item.log_ns };
    let mut seen: std::collections::BTreeSet<String> = std::collections::BTreeSet::new();
    let start = Instant::now();
    let mut file_start = start;
    let mut last_flush = start;
    let mut next_discovery = start;
    while !shutdown.requested() {
        if args.duration_s.is_some_and(|d| start.elapsed().as_secs_f64() > d) {
            break;
        }
        // --all: subscribe to each new topic as discovery announces it.
        if args.all && Instant::now() >= next_discovery {
            next_discovery = Instant::now() + Duration::from_millis(200);
            for (name, (dds_type, reliable, transient)) in discovered(&bus) {
                if seen.contains(&name) {
                    continue;
                }
                seen.insert(name.clone());
                let ros_type = ros_type_name(&dds_type).unwrap_or_else(|| dds_type.clone());
                let mut qos = if reliable { state_qos() } else { state_qos().reliability_best_effort() };
                qos = qos.durability(if transient { Durability::TransientLocal } else { Durability::Volatile }).history(History::KeepLast { depth: fiveaxis_bus::STATE_DEPTH });
                let offered = OfferedQos { reliable, transient_local: transient, depth: Some(fiveaxis_bus::STATE_DEPTH as u32) };
                if let Err(e) = record(&mut bus, &mut bag, &tx, &name, &ros_type, &qos, offered) {
                    tracing::warn!(topic = %name, "not recorded: {e:#}");
                }
            }
        }
        // (The sender kept here for --all keeps the channel open: no disconnection to wait for.)
        if let Ok(item) = rx.recv_timeout(Duration::from_millis(50)) {
            // A write error (a full disk, say) names the file.
            written(bag.write_raw(item.topic, &item.data, log_ns(&bus, &item), item.publish_ns));
        }
        // Idle streams still get their chunk closed within a second.
        if last_flush.elapsed() >= Duration::from_secs(1) {
            written(bag.flush());
            last_flush = Instant::now();
            let size_mb = std::fs::metadata(bag.current_path()).map_or(0.0, |m| m.len() as f64 / 1e6);
            let too_big = args.split_size_mb.is_some_and(|l| size_mb >= l);
            let too_long = args.split_duration_s.is_some_and(|l| file_start.elapsed().as_secs_f64() >= l);
            if too_big || too_long {
                let done = bag.current_path().to_path_buf();
                written(bag.split());
                tracing::info!(file = %done.display(), "split finished");
                file_start = Instant::now();
            }
        }
    }
    drop(tx);
    // Drain what already arrived, then finish the bag.
    while let Ok(item) = rx.try_recv() {
        written(bag.write_raw(item.topic, &item.data, log_ns(&bus, &item), item.publish_ns));
    }
    let n = written(bag.finish());
    tracing::info!(messages = n, bag = %args.output.display(), "recording finished");
    fiveaxis_bus::exit_if_teardown_hangs(0, Duration::from_secs(10));
    Ok(())
}
