//! `fiveaxis-bridge`: a machine's axis positions read from its MTConnect agent (`/probe`, `/current`,
//! a streamed `/sample`), straight from its adapter (SHDR over TCP), or from its OPC UA server (the
//! OPC 40502 CNC model, by subscription), published as
//! `sensor_msgs/JointState` (REP 103: m, rad) on `machine/joint_states`: one message per instant
//! the source reported, carrying only the axes reported then (legal in ROS; the monitor, the Rerun
//! bridge and `analyze` merge them per axis), stamped with the source's own timestamp. It
//! reconnects on its own; an agent stream continues from the sequence it left off at.

mod opcua;

use clap::Parser;
use fiveaxis::machine::Machine;
use fiveaxis::mtconnect::devices;
use fiveaxis::mtconnect::live::{Adapter, Agent};
use fiveaxis::source::{AxisReport, Event, Failure, Restater, Retry};
use fiveaxis::topics;
use fiveaxis_bus::{init_tracing, state_qos, Bus, CommonArgs, Shutdown};
use fiveaxis_msgs::{Header, JointState, Time};
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// Exit status for input the bridge cannot use (a description, a device, axes not found).
const EXIT_INPUT: i32 = 2;

/// Publish a machine's axes from MTConnect as JointState.
#[derive(Parser)]
#[command(name = "fiveaxis-bridge", version)]
struct Args {
    #[command(flatten)]
    common: CommonArgs,
    /// An MTConnect agent's base URL (`http://host:5000`): its /probe names the axes; /sample is
    /// streamed.
    #[arg(long = "mtconnect-agent", value_name = "URL", required_unless_present_any = ["shdr_adapter", "opcua_server"], conflicts_with_all = ["shdr_adapter", "opcua_server"])]
    mtconnect_agent: Option<String>,
    /// An OPC UA server of the control (`opc.tcp://cnc:4840`): its OPC 40502 CNC model
    /// (Objects/CncInterface/CncAxisList) is browsed for the axes, whose ActPos are subscribed to.
    #[arg(long = "opcua-server", value_name = "URL", conflicts_with = "shdr_adapter")]
    opcua_server: Option<String>,
    /// Which position of each CncAxis to read: its indirect (motor encoder) or direct (scale)
    /// measuring system.
    #[arg(long = "opcua-measuring", value_enum, default_value = "indirect")]
    opcua_measuring: fiveaxis::opcua::Measuring,
    /// The sampling and publishing interval asked of the OPC UA server, ms (a Sinumerik offers 100
    /// at best).
    #[arg(long = "sampling-ms", default_value_t = 100)]
    sampling_ms: u64,
    /// Read OPC UA positions without EngineeringUnits as mm and degrees (else refused).
    #[arg(long = "assume-mm-deg")]
    assume_mm_deg: bool,
    /// The OPC UA channel's security: none, or Basic256Sha256 signed (`sign`) or signed and
    /// encrypted (`sign-and-encrypt`, what a Sinumerik offers by default). The server's certificate
    /// is trusted on first use and kept (the bridge's PKI directory).
    #[arg(long = "opcua-security", value_enum, default_value = "none")]
    opcua_security: fiveaxis::opcua::Security,
    /// Log in as this user (the password from the environment variable FIVEAXIS_OPCUA_PASSWORD,
    /// never on the command line); anonymous without it.
    #[arg(long = "opcua-user", value_name = "NAME")]
    opcua_user: Option<String>,
    /// The OPC UA node of a machine axis' position, for a control's own address space instead of
    /// the CNC model: `--opcua-node X=ns=2;s=/Channel/MachineAxis/actToolBasePos[u1,1]` (one per
    /// axis).
    #[arg(long = "opcua-node", value_name = "AXIS=NODEID", requires = "opcua_server")]
    opcua_node: Vec<String>,
    /// An MTConnect adapter's SHDR stream (`host:7878`), read without an agent; needs the device's
    /// description (--mtconnect-devices).
    #[arg(long = "shdr-adapter", value_name = "HOST:PORT", requires = "mtconnect_devices")]
    shdr_adapter: Option<String>,
    /// The device description the adapter's keys name (an agent's Devices.xml or /probe answer).
    #[arg(long = "mtconnect-devices", value_name = "DEVICES.XML")]
    mtconnect_devices: Option<PathBuf>,
    /// The device (name or uuid) when the description has several.
    #[arg(long = "mtconnect-device", value_name = "NAME")]
    mtconnect_device: Option<String>,
    #[command(flatten)]
    axis_map: fiveaxis::args::AxisMapArgs,
    /// The agent's `interval` between streamed documents, ms (0: as soon as there is data).
    #[arg(long = "interval-ms", default_value_t = 0)]
    interval_ms: u64,
    /// The agent's `heartbeat` (an empty document when nothing changed), ms; a stream silent for
    /// twice this is reconnected.
    #[arg(long = "heartbeat-ms", default_value_t = 10_000)]
    heartbeat_ms: u64,
    /// Topic of the JointState published.
    #[arg(long, default_value = topics::MACHINE_JOINTS.name)]
    topic: String,
    /// Restate an axis unreported this long in the next message, s (0: never): a change-only source
    /// says nothing of a still axis, so a subscriber that joins later would never learn where it
    /// stands. Its value still holds at the message's instant (nothing changed, or the source would
    /// have said so).
    #[arg(long = "restate-still-s", default_value_t = 1.0)]
    restate_still_s: f64,
    /// Wait this long for a subscriber before reading the source, s (then read anyway).
    #[arg(long = "wait-for-subscriber-s", default_value_t = 0.0)]
    wait_for_subscriber_s: f64,
    /// Exit once the source has been unreachable this long, s (exit 2 if it never answered).
    #[arg(long = "exit-when-down-s")]
    exit_when_down_s: Option<f64>,
    /// Write a JSON summary (messages, axis reports per axis, refusals, reconnections, gaps) here on
    /// exit.
    #[arg(long = "summary-json")]
    summary_json: Option<PathBuf>,
}

/// What the bridge did, for its summary.
#[derive(Default, serde::Serialize)]
struct Summary {
    source: String,
    messages: u64,
    /// Reports per machine axis, in the machine's order (`axes`).
    axes: Vec<String>,
    reports_per_axis: Vec<u64>,
    refused: u64,
    /// Values restated for still axes.
    restated: u64,
    /// Reports not newer than what was published, repeating held values (an agent's /current after a
    /// reconnection).
    repeated: u64,
    connections: u64,
    downs: u64,
    gaps: u64,
    /// Sequence numbers the agent no longer had, where it said how many.
    lost: u64,
}

fn joint_state(machine: &Machine, r: &AxisReport) -> JointState {
    let names = machine.axis_names();
    let (mut name, mut position) = (Vec::new(), Vec::new());
    for (i, v) in r.values.iter().enumerate() {
        if let Some(v) = v {
            name.push(names[i].clone());
            position.push(*v);
        }
    }
    let sec = i32::try_from(r.stamp.sec).unwrap_or(if r.stamp.sec < 0 { 0 } else { i32::MAX });
    JointState { header: Header { stamp: Time { sec, nanosec: r.stamp.nanosec }, frame_id: String::new() }, name, position, velocity: Vec::new(), effort: Vec::new() }
}

enum Source {
    Agent(Agent),
    Adapter(Adapter),
    OpcUa(opcua::OpcUa),
}

fn main() -> anyhow::Result<()> {
    let (args, ros) = fiveaxis_bus::ros_args::parse::<Args>("fiveaxis_bridge");
    init_tracing(&ros);
    let shutdown = Shutdown::install()?;
    let machine = args.common.machine_or_exit();
    let refuse = |why: String| -> ! {
        eprintln!("fiveaxis-bridge: {why}");
        std::process::exit(EXIT_INPUT);
    };
    let axis_map = args.axis_map.resolve(&machine).unwrap_or_else(|e| refuse(e));
    let source = if let Some(url) = &args.opcua_server {
        if args.sampling_ms == 0 {
            refuse("--sampling-ms must be positive".into());
        }
        let nodes = args.opcua_node.iter().map(|n| opcua::parse_node(n)).collect::<Result<Vec<_>, _>>().unwrap_or_else(|e| refuse(e));
        let mut server = opcua::OpcUa::new(url, &machine, axis_map.clone(), args.opcua_measuring, Duration::from_millis(args.sampling_ms), args.assume_mm_deg, nodes).unwrap_or_else(|e| refuse(e));
        server.security = args.opcua_security;
        if let Some(user) = &args.opcua_user {
            let password = std::env::var("FIVEAXIS_OPCUA_PASSWORD").unwrap_or_else(|_| refuse(format!("--opcua-user {user}: set its password in the environment variable FIVEAXIS_OPCUA_PASSWORD")));
            server.identity = Some((user.clone(), password));
        }
        Source::OpcUa(server)
    } else if let Some(url) = &args.mtconnect_agent {
        // The agent may come up after the bridge: an unreachable one is retried, a wrong one refused.
        let mut retry = Retry::new();
        let start = Instant::now();
        loop {
            match Agent::probe(url, args.mtconnect_device.as_deref(), &machine, &axis_map) {
                Ok(mut agent) => {
                    agent.interval_ms = args.interval_ms;
                    agent.heartbeat_ms = args.heartbeat_ms.max(1);
                    break Source::Agent(agent);
                }
                Err(Failure::Refused(why)) => refuse(why),
                Err(Failure::Down(why)) => {
                    if args.exit_when_down_s.is_some_and(|s| start.elapsed().as_secs_f64() > s) {
                        refuse(format!("{why}: no answer for {:.1} s", start.elapsed().as_secs_f64()));
                    }
                    tracing::warn!("{why}: retrying");
                    if !retry.back_off(&|| !shutdown.requested()) {
                        return Ok(());
                    }
                }
            }
        }
    } else {
        let (address, path) = (args.shdr_adapter.as_deref().unwrap_or_default(), args.mtconnect_devices.as_ref().expect("clap requires it"));
        let text = std::fs::read_to_string(path).unwrap_or_else(|e| refuse(format!("{}: {e}", path.display())));
        let all = devices::parse(&text).unwrap_or_else(|e| refuse(format!("{}: {e}", path.display())));
        Source::Adapter(Adapter::new(address, all, args.mtconnect_device.as_deref(), &machine, &axis_map).unwrap_or_else(|e| refuse(format!("{}: {e}", path.display()))))
    };
    let items = match &source {
        Source::Agent(a) => Some(&a.items),
        Source::Adapter(a) => Some(&a.items),
        Source::OpcUa(_) => None,
    };
    for (axis, id) in machine.axis_names().iter().zip(items.map(|i| i.ids.as_slice()).unwrap_or_default()) {
        tracing::info!(axis = %axis, data_item = %id, "axis read from");
    }

    let mut bus = Bus::new("fiveaxis_bridge", &args.common, &ros)?;
    let publisher = bus.publisher::<JointState>(&args.topic, state_qos())?;
    tracing::info!(topic = %bus.resolve(&args.topic), "publishing JointState");
    if args.wait_for_subscriber_s > 0.0 && !bus.wait_for_subscriber(&publisher, Duration::from_secs_f64(args.wait_for_subscriber_s), &shutdown) {
        tracing::warn!("no subscriber on {} after {} s: reading the source anyway", bus.resolve(&args.topic), args.wait_for_subscriber_s);
    }
    let mut held = Restater::new(args.restate_still_s);
    let mut summary = Summary {
        source: args.mtconnect_agent.clone().or(args.shdr_adapter.clone()).or(args.opcua_server.clone()).unwrap_or_default(),
        axes: machine.axis_names().to_vec(),
        reports_per_axis: vec![0; machine.axis_names().len()],
        ..Default::default()
    };
    let stop = AtomicBool::new(false);
    let keep_going = || !shutdown.requested() && !stop.load(Ordering::Relaxed);
    let (tx, rx) = std::sync::mpsc::sync_channel::<Event>(4096);
    let refused = std::thread::scope(|scope| {
        let source = &source;
        let keep_going = &keep_going;
        let reader = scope.spawn(move || {
            let mut send = |e: Event| {
                let _ = tx.send(e);
            };
            match source {
                Source::Agent(a) => a.run(keep_going, &mut send),
                Source::Adapter(a) => a.run(keep_going, &mut send),
                Source::OpcUa(o) => return o.run(keep_going, &mut send),
            }
            Ok(())
        });
        // Since when the source has been down (from the start until it delivers).
        let mut down_since: Option<Instant> = Some(Instant::now());
        let mut delivered = false;
        loop {
            if !keep_going() {
                break;
            }
            if let (Some(limit), Some(since)) = (args.exit_when_down_s, down_since) {
                if since.elapsed().as_secs_f64() > limit {
                    if !delivered {
                        tracing::error!("the source gave nothing for {limit} s: exiting");
                        std::process::exit(EXIT_INPUT);
                    }
                    tracing::info!("the source has been down for {limit} s: exiting");
                    break;
                }
            }
            let event = match rx.recv_timeout(Duration::from_millis(100)) {
                Ok(e) => e,
                Err(std::sync::mpsc::RecvTimeoutError::Timeout) => continue,
                Err(std::sync::mpsc::RecvTimeoutError::Disconnected) => break,
            };
            match event {
                Event::Report(r) => {
                    tracing::debug!(stamp_s = r.stamp.as_secs(), at = r.line, values = ?r.values, "axis report");
                    delivered = true;
                    down_since = None;
                    for (i, v) in r.values.iter().enumerate() {
                        summary.reports_per_axis[i] += u64::from(v.is_some());
                    }
                    let Some((out, restated)) = held.next(&r) else {
                        summary.repeated += 1;
                        continue;
                    };
                    summary.restated += restated;
                    summary.messages += 1;
                    if let Err(e) = publisher.publish(joint_state(&machine, &out)) {
                        tracing::warn!("publishing: {e:?}");
                    }
                }
                Event::Connected(what) => {
                    summary.connections += 1;
                    down_since = None;
                    tracing::info!("connected: {what}");
                }
                Event::Down(why) => {
                    summary.downs += 1;
                    down_since.get_or_insert_with(Instant::now);
                    tracing::warn!("{why}: reconnecting");
                }
                Event::Refused(why) => {
                    summary.refused += 1;
                    tracing::warn!("refused: {why}");
                }
                Event::Gap { why, lost } => {
                    summary.gaps += 1;
                    summary.lost = summary.lost.saturating_add(lost.unwrap_or(0));
                    tracing::warn!("gap: {why}");
                }
            }
        }
        stop.store(true, Ordering::Relaxed);
        reader.join().unwrap_or_else(|_| Err("the source's reader panicked".into())).err()
    });
    if let Some(why) = refused {
        refuse(why);
    }
    tracing::info!(messages = summary.messages, refused = summary.refused, connections = summary.connections, gaps = summary.gaps, "bridge summary");
    if let Some(path) = &args.summary_json {
        std::fs::write(path, serde_json::to_string_pretty(&summary)?)?;
    }
    Ok(())
}
