//! `fiveaxis-fleet gateway`: one machine's monitor, from its cell's DDS domain to the fleet's Zenoh
//! network under `/site/cell/machine`, as rmw_zenoh names and encodes topics. One way only: nothing
//! from the fleet network enters the cell. What crosses is the allow list: the monitor's status at
//! most `--state-rate-hz` a second (the latest of each stream), its `/diagnostics`, each region
//! whole, and the machine's axis states (the node set's and a real machine's `JointState` topics)
//! at most `--joint-states-rate-hz` a second. Publications drop rather than wait when the link is slow or down (the cell never waits
//! for the head office); the shift's regions stay here and are answered on request, so a view
//! catches up when the link returns.

use crate::zenoh_args::ZenohArgs;
use fiveaxis::topics;
use fiveaxis_bus::{diagnostics_qos, state_qos, Bus, CommonArgs, InputQos, RosOptions, Shutdown};
use fiveaxis_fleet::{cap::RateCap, keys, keys::MachinePath, regions::RegionTracker};
use fiveaxis_msgs::{DiagnosticArray, JointState, Region, RosMessage, SingularityStatus};
use ros2_client::zenoh::{Context, ContextOptions, Node, Publisher};
use ros2_client::{MessageTypeName, Name, NodeName, NodeOptions, QosProfile};
use std::collections::VecDeque;
use std::sync::{mpsc, Arc, Mutex};
use std::time::{Duration, Instant};
use zenoh::Wait;

#[derive(Debug, clap::Args)]
pub struct Args {
    /// Namespace of the cell's node set (its monitor's topics are read from it).
    #[arg(long, default_value = fiveaxis::topics::NAMESPACE)]
    namespace: String,
    /// Rename a cell topic: `--remap monitor/status:=/cnc/monitor/status` (repeatable).
    #[arg(long = "remap", value_name = "FROM:=TO", value_parser = fiveaxis_bus::parse_remap)]
    remaps: Vec<(String, String)>,
    /// The gateway's node name on the cell's domain.
    #[arg(long, default_value = "fiveaxis_fleet_gateway")]
    node_name: String,
    /// Take time from the cell's /clock, as its nodes do with `use_sim_time`.
    #[arg(long = "use-sim-time")]
    use_sim_time: bool,
    /// This machine's place on the fleet network: `/SITE/CELL/MACHINE`, each a ROS name token.
    #[arg(long = "fleet-namespace", value_name = "/SITE/CELL/MACHINE")]
    fleet_namespace: String,
    /// Status messages a second this machine sends to the fleet, all streams together (the monitor
    /// publishes one per sample, 1 kHz on a live machine).
    #[arg(long = "state-rate-hz", default_value_t = 10.0)]
    state_rate_hz: f64,
    /// JointState messages a second this machine sends to the fleet, all of its axis-state topics
    /// together (commanded, simulated and the real machine's `machine/joint_states`, the latest of
    /// each in turn); 0 sends none.
    #[arg(long = "joint-states-rate-hz", default_value_t = 5.0)]
    joint_states_rate_hz: f64,
    /// Regions kept for a view's catch-up (this shift's); beyond, the oldest are dropped.
    #[arg(long = "max-regions", default_value_t = fiveaxis_fleet::fleet::MAX_REGIONS)]
    max_regions: usize,
    #[command(flatten)]
    zenoh: ZenohArgs,
    /// Stop after this long, s (default: until SIGINT or SIGTERM).
    #[arg(long = "duration-s")]
    duration_s: Option<f64>,
}

/// What the cell side hands the loop.
enum In {
    Status(Box<SingularityStatus>),
    Diagnostics(DiagnosticArray),
    /// A JointState of the cell's joint-state topic `topics::JOINT_STATES[i]`.
    Joints(usize, JointState),
    Undecodable(String),
}

/// A publisher on the fleet network for `topic` of type `M` under the machine's namespace.
/// Its key and liveliness token carry the type's REP 2016 hash, computed from the `.msg` files, as
/// rmw_zenoh subscribers expect.
fn publisher<M: RosMessage + serde::Serialize>(node: &Node, path: &MachinePath, topic: &topics::Topic, qos: &QosProfile) -> anyhow::Result<Publisher<M>> {
    let hash = fiveaxis_msgs::type_hash::rihs01(&M::type_name()).ok_or_else(|| anyhow::anyhow!("no definition of {}", M::type_name()))?;
    ros2_client::zenoh::register_type_hash(&keys::dds_type(M::PACKAGE, M::NAME), &hash);
    let full = path.topic(topic);
    let name = Name::parse(&full).map_err(|e| anyhow::anyhow!("topic {full}: {e:?}"))?;
    let t = node.create_topic(&name, MessageTypeName::new(M::PACKAGE, M::NAME), qos);
    node.create_publisher(&t, None).map_err(|e| anyhow::anyhow!("publisher {full}: {e:?}"))
}

pub fn run(args: Args, ros: &RosOptions) -> anyhow::Result<()> {
    let path = MachinePath::parse(&args.fleet_namespace)?;
    if !(args.state_rate_hz.is_finite() && args.state_rate_hz > 0.0) {
        anyhow::bail!("--state-rate-hz {}: a positive rate", args.state_rate_hz);
    }
    if !(args.joint_states_rate_hz.is_finite() && args.joint_states_rate_hz >= 0.0) {
        anyhow::bail!("--joint-states-rate-hz {}: a rate of 0 (none sent) or more", args.joint_states_rate_hz);
    }
    let config = args.zenoh.config("client")?;
    let shutdown = Shutdown::install()?;

    // The cell side: the monitor's topics on the cell's DDS domain.
    let common = CommonArgs { namespace: args.namespace.clone(), machine: Default::default(), remaps: args.remaps.clone(), node_name: Some(args.node_name.clone()), use_sim_time: args.use_sim_time };
    let mut bus = Bus::new("fiveaxis_fleet_gateway", &common, ros)?;
    let (tx, rx) = mpsc::sync_channel::<In>(4096);
    let status = bus.subscription::<SingularityStatus>(topics::STATUS.name, state_qos())?;
    fiveaxis_bus::forward(status, bus.resolve(topics::STATUS.name), tx.clone(), |_, s| In::Status(Box::new(s)), |t, e| In::Undecodable(format!("{t}: {e}")));
    let diagnostics = bus.subscription::<DiagnosticArray>(topics::DIAGNOSTICS.name, diagnostics_qos())?;
    fiveaxis_bus::forward(diagnostics, bus.resolve(topics::DIAGNOSTICS.name), tx.clone(), |_, d| In::Diagnostics(d), |t, e| In::Undecodable(format!("{t}: {e}")));
    // Axis states as the monitor hears them: a best-effort request, which DDS matches with the node
    // set's reliable publishers and a machine bridge's SensorData ones alike.
    let cell_joint_topics: Vec<String> = topics::JOINT_STATES.iter().map(|t| bus.resolve(t.name)).collect();
    if args.joint_states_rate_hz > 0.0 {
        for (i, t) in topics::JOINT_STATES.iter().enumerate() {
            let sub = bus.subscription::<JointState>(t.name, InputQos::Auto.profile(true))?;
            fiveaxis_bus::forward(sub, bus.resolve(t.name), tx.clone(), move |_, j| In::Joints(i, j), |t, e| In::Undecodable(format!("{t}: {e}")));
        }
    }
    drop(tx);

    // The fleet side: a ROS 2 node on Zenoh in the machine's namespace.
    let domain = args.zenoh.domain;
    let context = Context::with_options(ContextOptions::new().domain_id(domain).zenoh_config(config)).map_err(|e| anyhow::anyhow!("opening the fleet session: {e:?}"))?;
    let node_name = NodeName::new(&path.namespace(), "fiveaxis_fleet_gateway").map_err(|e| anyhow::anyhow!("node name: {e:?}"))?;
    let node = context.new_node(node_name, NodeOptions::new().enable_rosout(false)).map_err(|e| anyhow::anyhow!("fleet node: {e:?}"))?;
    let qos = QosProfile::publisher_default();
    let status_pub = publisher::<SingularityStatus>(&node, &path, &topics::STATUS, &qos)?;
    let diagnostics_pub = publisher::<DiagnosticArray>(&node, &path, &topics::DIAGNOSTICS, &qos)?;
    let regions_pub = publisher::<Region>(&node, &path, &topics::REGIONS, &qos)?;
    let joint_pubs = if args.joint_states_rate_hz > 0.0 { topics::JOINT_STATES.iter().map(|t| publisher::<JointState>(&node, &path, t, &qos)).collect::<anyhow::Result<Vec<_>>>()? } else { Vec::new() };

    // The shift's regions, answered to a view's catch-up query (one reply per region, CDR).
    let store: Arc<Mutex<VecDeque<Region>>> = Arc::new(Mutex::new(VecDeque::new()));
    let answer = store.clone();
    let regions_key = keys::regions_query(domain, &path);
    let reply_key = regions_key.clone();
    let _queryable = context
        .session()
        .declare_queryable(regions_key.clone())
        .callback(move |query| {
            let regions: Vec<Region> = answer.lock().map(|s| s.iter().cloned().collect()).unwrap_or_default();
            for r in regions {
                if let Ok(bytes) = fiveaxis::record::to_cdr(&r) {
                    let _ = query.reply(reply_key.clone(), bytes).wait();
                }
            }
        })
        .wait()
        .map_err(|e| anyhow::anyhow!("regions queryable {regions_key}: {e}"))?;
    tracing::info!(machine = %path, zid = %context.session().zid(), rate_hz = args.state_rate_hz, "fleet gateway up");

    let mut tracker = RegionTracker::new();
    // Statuses of streams beyond [`fiveaxis_fleet::MAX_STREAMS`], not sent.
    let mut beyond = 0u64;
    let mut cap: RateCap<SingularityStatus> = RateCap::new(args.state_rate_hz);
    // The axis states' own cap; none at a rate of 0 (nor their subscriptions above).
    let mut joint_cap: Option<RateCap<(usize, JointState)>> = (args.joint_states_rate_hz > 0.0).then(|| RateCap::new(args.joint_states_rate_hz));
    let mut undecodable = 0u64;
    let (mut sent, mut joints_sent, mut regions, mut dropped) = (0u64, 0u64, 0u64, 0u64);
    let start = Instant::now();
    let send_region = |r: Region, dropped: &mut u64| {
        if let Ok(mut s) = store.lock() {
            if s.len() >= args.max_regions {
                s.pop_front();
                *dropped += 1;
            }
            s.push_back(r.clone());
        }
        tracing::info!(stream = %r.input_topic, region = r.region_id, x_mm = r.start_position.x / fiveaxis::units::MM, "region closed");
        if let Err(e) = regions_pub.publish(r) {
            tracing::debug!("region not sent now (a view catches up): {e:?}");
        }
    };
    while !shutdown.requested() && !args.duration_s.is_some_and(|d| start.elapsed().as_secs_f64() >= d) {
        let now = Instant::now();
        let next = [cap.next_release(), joint_cap.as_ref().and_then(|c| c.next_release())].into_iter().flatten().min();
        let wait = next.map_or(Duration::from_millis(50), |n| n.saturating_duration_since(now).min(Duration::from_millis(50)));
        match rx.recv_timeout(wait) {
            Ok(In::Status(s)) => {
                if let Some(r) = tracker.on_status(&s) {
                    regions += 1;
                    send_region(r, &mut dropped);
                }
                let stream = s.input_topic.clone();
                if !cap.offer(&stream, *s) {
                    if beyond == 0 {
                        tracing::warn!(%stream, max = fiveaxis_fleet::MAX_STREAMS, "a status of a stream beyond the streams followed: not sent");
                    }
                    beyond += 1;
                }
            }
            Ok(In::Joints(i, j)) => {
                if let Some(c) = joint_cap.as_mut() {
                    c.offer(&cell_joint_topics[i], (i, j));
                }
            }
            Ok(In::Diagnostics(d)) => {
                let _ = diagnostics_pub.publish(d);
            }
            Ok(In::Undecodable(why)) => {
                undecodable += 1;
                if undecodable == 1 {
                    tracing::warn!("a message from the cell did not decode: {why} (counted)");
                }
            }
            Err(mpsc::RecvTimeoutError::Timeout) => {}
            Err(mpsc::RecvTimeoutError::Disconnected) => break,
        }
        // Each cap's next release counts from when the message has left (its send stamp is
        // written while it is sent).
        if let Some(s) = cap.poll(Instant::now()) {
            if status_pub.publish(s).is_ok() {
                sent += 1;
            }
            cap.sent(Instant::now());
        }
        if let Some(c) = joint_cap.as_mut() {
            if let Some((i, j)) = c.poll(Instant::now()) {
                if joint_pubs[i].publish(j).is_ok() {
                    joints_sent += 1;
                }
                c.sent(Instant::now());
            }
        }
    }
    for r in tracker.finish() {
        regions += 1;
        send_region(r, &mut dropped);
    }
    tracing::info!(machine = %path, statuses_sent = sent, superseded = cap.superseded(), joint_states_sent = joints_sent, joint_states_superseded = joint_cap.as_ref().map_or(0, |c| c.superseded()), regions, regions_dropped_from_store = dropped, statuses_beyond_streams = beyond, undecodable, "fleet gateway done");
    drop(node);
    let _ = context.session().close().wait();
    Ok(())
}
