//! The one transport seam of the fiveaxis nodes: ROS 2 over DDS with `ros2-client`.
//!
//! - The participant honours `ROS_DOMAIN_ID`, `ROS_AUTOMATIC_DISCOVERY_RANGE` (`LOCALHOST`, `SUBNET`,
//!   `OFF`) and the older `ROS_LOCALHOST_ONLY=1`, which ros2-client itself does not read.
//! - QoS: state streams are reliable, keep-last [`STATE_DEPTH`] (1 s at 1 kHz), volatile, on both
//!   sides (ros2-client's subscription default is best effort, depth 1, which would drop samples).
//! - Topic names are relative to `--namespace` (default `/fiveaxis`) unless absolute, then remapped
//!   with `--remap FROM:=TO`.
//! - DDS Security (SROS2 keystores) when `ROS_SECURITY_ENABLE=true`, from `ROS_SECURITY_KEYSTORE` and
//!   the node's `--enclave` ([`security`]).
//! - SIGINT/SIGTERM set a flag the node loops poll, so they finish cleanly.

pub mod program;
pub mod raw;
pub mod ros_args;
pub mod security;
pub mod states;
pub use ros_args::RosOptions;
pub use program::{open_program, Gate};
pub use states::{subscribe_states, Received, StateInput, StateReceiver};

use anyhow::{bail, Context as _};
use fiveaxis_msgs::RosMessage;
// The DDS backend by its module path: the fleet crate enables ros2-client's Zenoh backend too, and with
// both backends the crate root re-exports neither's `Context`/`Node`/... (ros2-client's ADR-0010).
use ros2_client::{
    dds::{rustdds, Context, Node, Publisher, Subscription},
    qos::{Durability, History, WhenFull},
    MessageTypeName, Name, NodeName, NodeOptions, QosProfile,
};
use serde::{de::DeserializeOwned, Serialize};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// Keep-last depth of the axis-state and status streams.
pub const STATE_DEPTH: usize = 1000;

/// How long `Bus::new` waits for the spinner to create its readers (milliseconds when all is well).
const SPINNER_START: Duration = Duration::from_secs(30);

/// QoS of the axis-state and status streams: reliable, keep-last 1000, volatile.
pub fn state_qos() -> QosProfile {
    QosProfile::publisher_default()
        .reliability_reliable(WhenFull::Wait(Duration::from_millis(100)))
        .durability(Durability::Volatile)
        .history(History::KeepLast { depth: STATE_DEPTH })
}

/// The reliability a node asks of its input publishers.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum InputQos {
    /// Reliable: hears only reliable publishers (a best-effort one, e.g. ROS SensorData QoS, is
    /// incompatible and never heard).
    Reliable,
    /// Best effort: hears best-effort and reliable publishers alike (DDS matches a best-effort reader
    /// with both), without retransmission.
    BestEffort,
    /// Hear whatever the publisher offers: JointState inputs (machine bridges, often ROS 2's
    /// SensorData QoS) with a best-effort request, which DDS matches with reliable and best-effort
    /// publishers alike; AxisState inputs (the node set's own reliable streams) reliable, so that a
    /// commander publishing as fast as it can loses nothing.
    Auto,
}

impl InputQos {
    /// The reader QoS of a state input (keep-last 1000 either way); `joint_state` for a bridge's
    /// JointState topic.
    pub fn profile(self, joint_state: bool) -> QosProfile {
        match (self, joint_state) {
            (InputQos::Reliable, _) | (InputQos::Auto, false) => state_qos(),
            (InputQos::BestEffort, _) | (InputQos::Auto, true) => state_qos().reliability_best_effort(),
        }
    }
}

/// QoS of /diagnostics (as diagnostic_updater: reliable, keep-last 10).
pub fn diagnostics_qos() -> QosProfile {
    state_qos().history(History::KeepLast { depth: 10 })
}

/// QoS of /clock (as ROS 2's clock publisher: best effort, keep-last 1).
pub fn clock_qos() -> QosProfile {
    QosProfile::publisher_default().reliability_best_effort().history(History::KeepLast { depth: 1 })
}

/// Options every node takes.
#[derive(Debug, Clone, clap::Args)]
pub struct CommonArgs {
    /// Namespace of the node and of relative topic names.
    #[arg(long, default_value = "/fiveaxis")]
    pub namespace: String,
    #[command(flatten)]
    pub machine: fiveaxis::args::MachineArgs,
    /// Rename a topic: `--remap commanded/axis_state:=/cnc/axis_state` (repeatable).
    #[arg(long = "remap", value_name = "FROM:=TO", value_parser = parse_remap)]
    pub remaps: Vec<(String, String)>,
    /// Node name (default: the executable's).
    #[arg(long)]
    pub node_name: Option<String>,
    /// Stamp in program time, as ROS 2's `use_sim_time`: the commander publishes it on /clock and
    /// the other nodes take their time from /clock. Without it every message carries wall time (the
    /// commander and simulator then run in real time: no --fast, --speed 1).
    #[arg(long = "use-sim-time")]
    pub use_sim_time: bool,
}

/// Options of the nodes that publish a program's axis states (commander, simulator).
#[derive(Debug, Clone, clap::Args)]
pub struct StreamArgs {
    /// Program file (`-`: standard input), builtin:NAME or bundled:NAME (as for `fiveaxis program analyze`).
    pub program: String,
    /// Samples per second.
    #[arg(long, default_value_t = 1000.0)]
    pub rate: f64,
    /// Publish in real time (the default).
    #[arg(long, conflicts_with = "fast")]
    pub realtime: bool,
    /// Publish as fast as possible (follow /clock for time).
    #[arg(long)]
    pub fast: bool,
    /// Real-time factor: 2 runs twice as fast as the machine would.
    #[arg(long, default_value_t = 1.0)]
    pub speed: f64,
    /// Tool-tip feed for every feed move, mm/min.
    #[arg(long = "feed", value_name = "MM_PER_MIN")]
    pub feed_mm_per_min: Option<f64>,
    /// Longest program accepted, hours: a block that would make it run longer (a feed typo such as
    /// F0.01) is an error naming its line and column.
    #[arg(long = "max-program-hours", value_name = "HOURS", default_value_t = fiveaxis::path::MAX_PROGRAM_DURATION_S / 3600.0)]
    pub max_program_hours: f64,
    #[command(flatten)]
    pub control: fiveaxis::program::ControlArgs,
    /// Wait this long for subscribers before publishing (0: do not wait), s.
    #[arg(long = "wait-for-subscriber-s", default_value_t = 10.0)]
    pub wait_s: f64,
    /// How many subscribers of the state stream to wait for (e.g. monitor and recorder: 2).
    #[arg(long = "min-subscribers", default_value_t = 1)]
    pub min_subscribers: usize,
    /// Wait this long for the whole program's check before publishing, s: a program checked in that
    /// time is refused whole if it has defects; a longer one is published while the check goes on
    /// and stops at its first defect (0: publish at once; a large value: check it all first).
    #[arg(long = "check-before-publish-s", value_name = "S", default_value_t = program::SETTLE.as_secs_f64())]
    pub check_before_publish_s: f64,
    /// Run the program this many times, one pass after the other as a machine makes part after
    /// part: each pass joined to the last by a rapid back to the program's first pose.
    #[arg(long, value_name = "N", default_value_t = 1, conflicts_with = "endless")]
    pub passes: u64,
    /// Run the program again and again until stopped (SIGINT/SIGTERM), as `--passes` (soak tests,
    /// a demonstration left running).
    #[arg(long = "loop", id = "endless")]
    pub endless: bool,
}

impl StreamArgs {
    /// Check the numbers, and that a run off real time (`--fast`, `--speed` other than 1) stamps in
    /// program time (`use_sim_time`): wall-clock stamps would compress or stretch every velocity.
    pub fn validate(&self, use_sim_time: bool) -> anyhow::Result<()> {
        anyhow::ensure!(self.rate > 0.0 && self.rate.is_finite(), "--rate must be positive");
        anyhow::ensure!(self.speed > 0.0 && self.speed.is_finite(), "--speed must be positive");
        anyhow::ensure!(
            use_sim_time || (!self.fast && self.speed == 1.0),
            "{} runs off the wall clock, so stamps in wall time would not be the program's: add --ros-args -p use_sim_time:=true (or --use-sim-time) to stamp in program time and publish /clock",
            if self.fast { "--fast".to_string() } else { format!("--speed {}", self.speed) }
        );
        anyhow::ensure!(self.wait_s >= 0.0 && self.wait_s <= 1e6, "--wait-for-subscriber-s must be between 0 and 1e6 s");
        anyhow::ensure!(self.max_program_hours > 0.0 && self.max_program_hours.is_finite(), "--max-program-hours must be positive");
        anyhow::ensure!(self.check_before_publish_s >= 0.0 && self.check_before_publish_s <= 1e6, "--check-before-publish-s must be between 0 and 1e6 s");
        if let Some(f) = self.feed_mm_per_min {
            anyhow::ensure!(f > 0.0 && f.is_finite(), "--feed must be a positive number of mm/min");
        }
        anyhow::ensure!(self.passes >= 1, "--passes must be at least 1");
        Ok(())
    }

    /// `--wait-for-subscriber-s` as a duration (none when 0): how long the node waits for its
    /// subscribers before publishing, and then for their acknowledgement of the first sample.
    pub fn subscriber_wait(&self) -> Duration {
        if self.wait_s > 0.0 { Duration::from_secs_f64(self.wait_s.min(1e6)) } else { Duration::ZERO }
    }

    /// How many times the program runs (`None`: until stopped).
    pub fn pass_count(&self) -> Option<u64> {
        (!self.endless).then_some(self.passes)
    }

    /// How the program is read and sampled: the control's options, at the rate, with the feed
    /// override and the duration bound.
    pub fn job_options(&self) -> fiveaxis::job::JobOptions {
        fiveaxis::job::JobOptions { path: self.path_options(), read: self.control.read_options(), ..Default::default() }
    }

    /// How the program is sampled: at the rate, with the feed override and the duration bound.
    pub fn path_options(&self) -> fiveaxis::path::PathOptions {
        fiveaxis::path::PathOptions { period: 1.0 / self.rate, feed_override_mm_per_min: self.feed_mm_per_min, max_duration_s: self.max_program_hours * 3600.0 }
    }

    /// The pacing these options ask for, stamping in program time (`use_sim_time`) or wall time.
    pub fn pacer(&self, use_sim_time: bool) -> Pacer {
        let pacer = Pacer::new(if self.fast { None } else { Some(self.speed) });
        if use_sim_time { pacer } else { pacer.stamping_wall_time() }
    }
}

/// `FROM:=TO`, as `--remap` and ROS 2's `-r` take it.
pub fn parse_remap(s: &str) -> Result<(String, String), String> {
    match s.split_once(":=") {
        Some((a, b)) if !a.is_empty() && !b.is_empty() => Ok((a.to_string(), b.to_string())),
        _ => Err(format!("expected FROM:=TO, got '{s}'")),
    }
}

/// Exit code of bad input (a program with defects, a file that cannot be read), as `fiveaxis`'s.
pub const EXIT_INPUT: i32 = 2;

impl CommonArgs {
    /// The machine `--machine` names; an unknown name or an invalid file is bad input: the reason
    /// (naming the field) on stderr, exit 2, before the node joins the graph.
    pub fn machine_or_exit(&self) -> fiveaxis::machine::Machine {
        self.machine.load().unwrap_or_else(|e| {
            eprintln!("error: loading the machine: {e}");
            std::process::exit(EXIT_INPUT)
        })
    }
}

/// Tracing directives that keep the DDS stack's own logs to warnings (and ros2-client's distribution
/// notice quiet) whatever level the node logs at. RustDDS 0.15 warns on every datagram over 1500 bytes
/// (`udp_sender`: "Message size = N"), that is on every batch of samples: 238 k lines from a commander
/// feeding a monitor for an hour of program, so that target is kept to errors.
pub const DDS_LOG_DIRECTIVES: &str = "rustdds=warn,rustdds::network::udp_sender=error,ros2_client=warn,ros2_client::distributions=error";

/// A filter the user wrote (`RUST_LOG`, `--ros-args --log-level`) with [`DDS_LOG_DIRECTIVES`] added for each
/// target it does not name: `RUST_LOG=debug` does not open the DDS stack's per-datagram chatter, and
/// `RUST_LOG=debug,rustdds=trace` still gets RustDDS's traces.
pub fn user_log_filter(user: &str) -> String {
    const LEVELS: [&str; 6] = ["off", "error", "warn", "info", "debug", "trace"];
    // A directive is `target=level`, a bare `level`, or a bare `target` (every level of it).
    let named: Vec<&str> = user
        .split(',')
        .map(|d| d.split_once('=').map_or(d, |(t, _)| t).trim())
        .filter(|t| !t.is_empty() && !LEVELS.contains(&t.to_ascii_lowercase().as_str()))
        .collect();
    let mut f = user.trim().trim_end_matches(',').to_string();
    for d in DDS_LOG_DIRECTIVES.split(',') {
        let target = d.split_once('=').map_or(d, |(t, _)| t);
        // A target the user named, or one inside it (rustdds::network::udp_sender inside rustdds), is theirs.
        if named.iter().any(|n| target == *n || target.starts_with(&format!("{n}::"))) {
            continue;
        }
        if !f.is_empty() {
            f.push(',');
        }
        f.push_str(d);
    }
    f
}

/// Log with tracing to stderr: `--ros-args --log-level` first, else `RUST_LOG`, else info with DDS
/// internals at warn; nothing with `--disable-stdout-logs`. Then log what the ROS arguments skipped.
pub fn init_tracing(ros: &RosOptions) {
    let default = user_log_filter("info");
    let default = default.as_str();
    let filter = match (&ros.log_filter, ros.stdout_logs) {
        (_, false) => tracing_subscriber::EnvFilter::new("off"),
        (Some(f), _) => tracing_subscriber::EnvFilter::try_new(f).unwrap_or_else(|_| default.into()),
        (None, _) => match std::env::var(tracing_subscriber::EnvFilter::DEFAULT_ENV) {
            Ok(user) if !user.trim().is_empty() => tracing_subscriber::EnvFilter::try_new(user_log_filter(&user)).unwrap_or_else(|_| default.into()),
            _ => default.into(),
        },
    };
    let _ = tracing_subscriber::fmt().with_env_filter(filter).with_writer(std::io::stderr).try_init();
    for w in &ros.warnings {
        tracing::warn!("{w}");
    }
}

/// Which peers discovery may reach, from the ROS 2 environment.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DiscoveryRange {
    /// Only this host (loopback).
    Localhost,
    /// The local networks (the DDS default).
    Subnet,
    /// No discovery beyond this process.
    Off,
}

/// The participant settings the ROS 2 environment asks for: `(domain id, range)`.
pub fn ros_environment(get: impl Fn(&str) -> Option<String>) -> anyhow::Result<(u16, DiscoveryRange)> {
    let domain = match get("ROS_DOMAIN_ID").map(|s| s.trim().to_string()).filter(|s| !s.is_empty()) {
        None => 0,
        Some(s) => match s.parse::<u16>() {
            Ok(d) if d <= 232 => d,
            _ => bail!("ROS_DOMAIN_ID must be a number from 0 to 232, got '{s}'"),
        },
    };
    let range = match get("ROS_AUTOMATIC_DISCOVERY_RANGE").map(|s| s.trim().to_ascii_uppercase()).filter(|s| !s.is_empty()) {
        Some(r) => match r.as_str() {
            "LOCALHOST" => DiscoveryRange::Localhost,
            "SUBNET" | "SYSTEM_DEFAULT" => DiscoveryRange::Subnet,
            "OFF" => DiscoveryRange::Off,
            _ => bail!("ROS_AUTOMATIC_DISCOVERY_RANGE must be OFF, LOCALHOST, SUBNET or SYSTEM_DEFAULT, got '{r}'"),
        },
        None if get("ROS_LOCALHOST_ONLY").is_some_and(|v| v.trim() == "1") => DiscoveryRange::Localhost,
        None => DiscoveryRange::Subnet,
    };
    Ok((domain, range))
}

/// What the ROS 2 environment asks of the participant: domain, discovery range, DDS Security.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ParticipantSettings {
    pub domain: u16,
    pub range: DiscoveryRange,
    pub security: security::Security,
}

/// Read the participant's settings from the environment, the DDS Security enclave being `enclave`
/// (`--enclave`) when `ROS_SECURITY_ENABLE=true` ([`security`]). An error is bad input (exit 2).
pub fn participant_settings(enclave: Option<&str>) -> anyhow::Result<ParticipantSettings> {
    let (domain, range) = ros_environment(|k| std::env::var(k).ok())?;
    let security = security::from_env(|k| std::env::var(k).ok(), enclave).context("DDS Security")?;
    Ok(ParticipantSettings { domain, range, security })
}

/// A ROS 2 context with these settings.
pub fn context_with(settings: &ParticipantSettings) -> anyhow::Result<Context> {
    let ParticipantSettings { domain, range, security } = settings;
    let mut builder = rustdds::DomainParticipantBuilder::new(*domain);
    match security {
        security::Security::Off => {}
        security::Security::Permissive(why) => tracing::warn!("DDS Security asked for but not used (ROS_SECURITY_STRATEGY is not Enforce): {why}"),
        security::Security::Enclave(dir) => {
            tracing::info!(enclave = %dir.display(), "DDS Security: authenticating with the enclave");
            builder = builder.builtin_security(rustdds::DomainParticipantSecurityConfigFiles::with_ros_default_names(dir, String::new()));
        }
    }
    let builder = match range {
        DiscoveryRange::Localhost => builder.with_only_networks([std::net::IpAddr::from([127, 0, 0, 1])]),
        // OFF: no interface is advertised or joined; only same-host loopback peers remain reachable.
        DiscoveryRange::Off => builder.with_only_networks(Vec::<std::net::IpAddr>::new()),
        DiscoveryRange::Subnet => builder,
    };
    let participant = builder.build().context("creating the DDS participant")?;
    tracing::info!(domain, ?range, secured = matches!(security, security::Security::Enclave(_)), "DDS participant");
    Context::from_domain_participant(participant).context("creating the ROS 2 context")
}

/// Exit with `code` if the process is still running `grace` after this call: a node calls it once
/// its results are written, before it returns and drops its DDS participant, whose teardown (RustDDS
/// joins its threads) must not keep a finished node alive. (A CI run of the 100-kill test waited
/// 300 s on a monitor or recorder told to stop; where it hung is not known.)
pub fn exit_if_teardown_hangs(code: i32, grace: Duration) {
    std::thread::spawn(move || {
        std::thread::sleep(grace);
        tracing::warn!("the DDS teardown did not end within {} s of the node's last work: exiting", grace.as_secs_f64());
        std::process::exit(code);
    });
}

/// Set when SIGINT or SIGTERM arrives.
#[derive(Debug, Clone)]
pub struct Shutdown(Arc<AtomicBool>);

impl Shutdown {
    pub fn install() -> anyhow::Result<Shutdown> {
        let flag = Arc::new(AtomicBool::new(false));
        for sig in [signal_hook::consts::SIGINT, signal_hook::consts::SIGTERM] {
            signal_hook::flag::register(sig, flag.clone()).context("installing the signal handler")?;
        }
        Ok(Shutdown(flag))
    }
    pub fn requested(&self) -> bool {
        self.0.load(Ordering::Relaxed)
    }
}

/// A node on the bus, its spinner running on a background thread.
pub struct Bus {
    pub node: Node,
    namespace: String,
    remaps: Vec<(String, String)>,
    context: Context,
}

impl Bus {
    /// Create the context and the node `name` (or `--node-name`, `-r __node:=`) in `--namespace`
    /// (`-r __ns:=`), its settings declared as read-only parameters (served by ros2-client's
    /// parameter services: `ros2 param list/get`).
    pub fn new(default_name: &str, args: &CommonArgs, ros: &RosOptions) -> anyhow::Result<Bus> {
        let settings = participant_settings(ros.enclave.as_deref()).unwrap_or_else(|e| {
            eprintln!("error: {e:#}");
            std::process::exit(EXIT_INPUT)
        });
        let context = context_with(&settings)?;
        let name = args.node_name.clone().unwrap_or_else(|| default_name.to_string());
        let mut options = NodeOptions::new().enable_rosout(ros.rosout);
        for p in &ros.parameters {
            options = options.declare_parameter(&p.name, p.value.clone());
        }
        // Read-only: only the value the node runs with (which declaring it sets) is accepted.
        let declared = ros.parameters.clone();
        let options = options.parameter_validator(Box::new(move |name, value| match declared.iter().find(|p| p.name == name) {
            Some(p) if p.value == *value => Ok(()),
            _ => Err(format!("{name} is read-only: the node reads its settings at start; restart it with --ros-args -p {name}:=VALUE")),
        }));
        let mut node = context
            .new_node(NodeName::new(&args.namespace, &name).map_err(|e| anyhow::anyhow!("node name: {e:?}"))?, options)
            .map_err(|e| anyhow::anyhow!("creating node {name}: {e:?}"))?;
        let spinner = node.spinner().map_err(|e| anyhow::anyhow!("spinner: {e:?}"))?;
        // Under DDS Security, RustDDS 0.15 deadlocks when one thread creates a topic (participant
        // lock, then the security plugins' lock) while another creates a reader (the plugins' lock,
        // then the participant's): a keyed recorder hung so at start. The spinner creates its
        // readers before its first await, so the node's own entities wait for its first poll.
        let (started, first_poll) = std::sync::mpsc::sync_channel::<()>(1);
        std::thread::Builder::new()
            .name("ros2-spinner".into())
            .spawn(move || {
                let mut spin = Box::pin(spinner.spin());
                let mut started = Some(started);
                let spun = smol::block_on(std::future::poll_fn(move |cx| {
                    let poll = std::future::Future::poll(spin.as_mut(), cx);
                    if let Some(started) = started.take() {
                        let _ = started.send(());
                    }
                    poll
                }));
                if let Err(e) = spun {
                    tracing::warn!("spinner stopped: {e:?}");
                }
            })
            .context("starting the spinner")?;
        // Disconnected (the spinner ended or panicked at its first poll): nothing more will race.
        if let Err(std::sync::mpsc::RecvTimeoutError::Timeout) = first_poll.recv_timeout(SPINNER_START) {
            bail!("the ROS 2 spinner did not create its readers within {} s", SPINNER_START.as_secs());
        }
        Ok(Bus { node, namespace: args.namespace.clone(), remaps: args.remaps.clone(), context })
    }

    /// The node's clock now, as ROS 2 nodes keep it: the last `/clock` received with `use_sim_time`
    /// (zero before the first), else the wall clock.
    pub fn now(&self) -> fiveaxis_msgs::Time {
        fiveaxis_msgs::Time::from_nanos(self.node.time_now().to_nanos().max(0) as u64)
    }

    /// Log `msg` on /rosout (and stderr) stamped by the node's clock, as every other message
    /// ([`Bus::now`]; ros2-client's `rosout!` stamps wall time whatever `use_sim_time` says).
    #[track_caller]
    pub fn rosout(&self, level: ros2_client::ros2::LogLevel, msg: &str) {
        use ros2_client::dds::RosoutRaw;
        let at = std::panic::Location::caller();
        self.node.rosout_raw(self.node.time_now().into(), level, self.node.base_name(), msg, at.file(), "<unknown_func>", at.line());
    }

    /// The node's ROS 2 context (its DDS participant, discovery).
    pub fn context(&self) -> &Context {
        &self.context
    }

    /// The full topic name for `topic` (relative to the namespace unless absolute), after remapping.
    pub fn resolve(&self, topic: &str) -> String {
        resolve(&self.namespace, &self.remaps, topic)
    }

    fn topic<M: RosMessage>(&mut self, topic: &str, qos: &QosProfile) -> anyhow::Result<rustdds::Topic> {
        let full = self.resolve(topic);
        let name = Name::parse(&full).map_err(|e| anyhow::anyhow!("topic name {full}: {e:?}"))?;
        self.node
            .create_topic(&name, MessageTypeName::new(M::PACKAGE, M::NAME), qos)
            .map_err(|e| anyhow::anyhow!("topic {full}: {e:?}"))
    }

    pub fn publisher<M: RosMessage + Serialize>(&mut self, topic: &str, qos: QosProfile) -> anyhow::Result<Publisher<M>> {
        let t = self.topic::<M>(topic, &qos)?;
        self.node.create_publisher(&t, Some(qos)).map_err(|e| anyhow::anyhow!("publisher {topic}: {e:?}"))
    }

    pub fn subscription<M: RosMessage + DeserializeOwned + 'static>(&mut self, topic: &str, qos: QosProfile) -> anyhow::Result<Subscription<M>> {
        let t = self.topic::<M>(topic, &qos)?;
        self.node.create_subscription(&t, Some(qos)).map_err(|e| anyhow::anyhow!("subscription {topic}: {e:?}"))
    }

    /// Wait up to `timeout` until `publisher` has at least `n` matched subscriptions; false on timeout
    /// or shutdown.
    pub fn wait_for_subscribers<M: Serialize>(&self, publisher: &Publisher<M>, n: usize, timeout: Duration, shutdown: &Shutdown) -> bool {
        let end = Instant::now() + timeout;
        if !self.wait_for_subscriber(publisher, timeout, shutdown) {
            return false;
        }
        let enough = |pause: Duration| {
            let n_now = publisher.get_subscription_count(&self.node);
            if n_now < n {
                std::thread::sleep(pause);
            }
            n_now >= n
        };
        retry_until(end, shutdown, Duration::from_millis(10), enough).unwrap_or(false)
    }

    /// Wait as `--wait-for-subscriber-s` and `--min-subscribers` ask until `publisher` (on `topic`)
    /// has enough matched subscriptions; on timeout warn and go on (the stream publishes anyway).
    pub fn wait_for_stream_subscribers<M: Serialize>(&self, publisher: &Publisher<M>, topic: &str, stream: &StreamArgs, shutdown: &Shutdown) {
        if stream.wait_s > 0.0 && !self.wait_for_subscribers(publisher, stream.min_subscribers.max(1), stream.subscriber_wait(), shutdown) {
            tracing::warn!("no subscriber on {} after {} s: publishing anyway", self.resolve(topic), stream.wait_s);
        }
    }

    /// Wait up to `timeout` until `publisher` has a matched subscription; false on timeout or shutdown.
    pub fn wait_for_subscriber<M: Serialize>(&self, publisher: &Publisher<M>, timeout: Duration, shutdown: &Shutdown) -> bool {
        let mut matched = Box::pin(publisher.wait_for_subscription(&self.node));
        let matched_within = |slice: Duration| {
            smol::block_on(smol::future::or(
                async {
                    (&mut matched).await;
                    true
                },
                async {
                    smol::Timer::after(slice).await;
                    false
                },
            ))
        };
        retry_until(Instant::now() + timeout, shutdown, Duration::from_millis(100), matched_within).unwrap_or(false)
    }
}

/// Resolve a topic name against a namespace and remaps (exact match on the name as given or resolved).
pub fn resolve(namespace: &str, remaps: &[(String, String)], topic: &str) -> String {
    let ns = namespace.trim_end_matches('/');
    let full = if topic.starts_with('/') { topic.to_string() } else { format!("{ns}/{topic}") };
    for (from, to) in remaps {
        let from_full = if from.starts_with('/') { from.clone() } else { format!("{ns}/{from}") };
        if *from == topic || from_full == full {
            return if to.starts_with('/') { to.clone() } else { format!("{ns}/{to}") };
        }
    }
    full
}

/// Publish axis states in time (each also as JointState; and as /clock when given: the commander
/// gives it only with `use_sim_time`), paced and stamped by `pacer`, until done or shutdown. A publish that times out on a subscriber that cannot keep up drops that
/// sample (counted, warned at most once a second; the monitor sees the gap): the stream never stops for
/// one slow reader. Returns (sent, dropped).
///
/// The first sample waits up to `first_ack_wait` until every matched subscriber has acknowledged
/// it (the pacing then starts over from there, or in wall time catches up on a short wait): a subscriber is matched before it can read, and
/// under DDS Security before the key exchange that lets it decrypt has completed, so without the
/// wait it lost the stream's first samples (a secure recorder kept 575-1025 of 1501 in half the runs
/// at speed 4).
pub fn publish_states(
    states: impl IntoIterator<Item = fiveaxis_msgs::AxisState>,
    state_pub: &Publisher<fiveaxis_msgs::AxisState>,
    joint_pub: &Publisher<fiveaxis_msgs::JointState>,
    clock_pub: Option<&Publisher<fiveaxis_msgs::Clock>>,
    pacer: &Pacer,
    first_ack_wait: Duration,
    shutdown: &Shutdown,
) -> (usize, usize) {
    let (mut sent, mut dropped) = (0usize, 0usize);
    let mut last_warn: Option<Instant> = None;
    let mut pacer = *pacer;
    let mut first = true;
    for mut st in states {
        if shutdown.requested() {
            tracing::info!("stopping on signal after {sent} samples");
            break;
        }
        let t = st.header.stamp.as_secs();
        pacer.wait_until(t);
        st.header.stamp = pacer.stamp(t);
        let joints = st.to_joint_state();
        if let Some(c) = clock_pub {
            // The clock first, so that a node stamping by /clock is not behind the sample.
            let _ = c.publish(fiveaxis_msgs::Clock { clock: st.header.stamp });
        }
        let ok = state_pub.publish(st).is_ok() & joint_pub.publish(joints).is_ok();
        if std::mem::take(&mut first) && !first_ack_wait.is_zero() {
            let began = Instant::now();
            if !first_sample_acknowledged(state_pub, joint_pub, clock_pub, first_ack_wait, shutdown) {
                tracing::warn!(
                    "a matched subscriber did not acknowledge the first sample within {} s (under DDS Security: its key exchange did not complete): publishing on",
                    first_ack_wait.as_secs_f64()
                );
            }
            // Program-time stamps do not move with the pacing, so it starts over after the wait.
            // Wall-time stamps are due times: a short wait is caught up (a burst of at most half a
            // second of samples, within the writers' history), so the stamps stay regular (the soak
            // counts a gap of 1.5 ms); only a longer one moves the pacing, leaving a gap there.
            let waited = began.elapsed();
            if !pacer.stamps_wall_time() || waited > CATCH_UP_MAX {
                pacer = pacer.delayed(waited);
            }
        }
        if ok {
            sent += 1;
        } else {
            dropped += 1;
            if last_warn.is_none_or(|t| t.elapsed() >= Duration::from_secs(1)) {
                tracing::warn!(dropped, "a subscriber is not keeping up: samples dropped");
                last_warn = Some(Instant::now());
            }
        }
    }
    if dropped > 0 {
        tracing::warn!(sent, dropped, "done, with samples dropped by slow subscribers");
    } else {
        tracing::info!(sent, "done");
    }
    // Let reliable delivery finish before the participant goes away.
    std::thread::sleep(Duration::from_millis(500));
    (sent, dropped)
}

/// The longest wait for the first sample's acknowledgement that wall-time pacing catches up on.
const CATCH_UP_MAX: Duration = Duration::from_millis(500);

/// Wait up to `max_wait` until every matched subscriber of the three publishers has acknowledged
/// what they published; false on timeout (shutdown ends the wait early, as acknowledged).
fn first_sample_acknowledged(
    state_pub: &Publisher<fiveaxis_msgs::AxisState>,
    joint_pub: &Publisher<fiveaxis_msgs::JointState>,
    clock_pub: Option<&Publisher<fiveaxis_msgs::Clock>>,
    max_wait: Duration,
    shutdown: &Shutdown,
) -> bool {
    let end = Instant::now() + max_wait;
    let slice = Duration::from_millis(100);
    fn acked<M: Serialize>(p: &Publisher<M>, end: Instant, slice: Duration, shutdown: &Shutdown) -> bool {
        retry_until(end, shutdown, slice, |d| p.wait_for_acknowledgments(d).unwrap_or(false)).unwrap_or(true)
    }
    acked(state_pub, end, slice, shutdown) && acked(joint_pub, end, slice, shutdown) && clock_pub.is_none_or(|c| acked(c, end, slice, shutdown))
}

/// Call `attempt` with how long it may block (`slice`, less near `end`) until it succeeds:
/// Some(true); or `end` passes: Some(false); or shutdown is asked: None.
fn retry_until(end: Instant, shutdown: &Shutdown, slice: Duration, mut attempt: impl FnMut(Duration) -> bool) -> Option<bool> {
    loop {
        if shutdown.requested() {
            return None;
        }
        let left = end.saturating_duration_since(Instant::now());
        if attempt(slice.min(left)) {
            return Some(true);
        }
        if left <= slice {
            return Some(false);
        }
    }
}

/// Paces a loop against the wall clock: sample time `t` (s) is due at `start + t / speed`; and
/// stamps it: program time `t` (ROS 2's sim time), or the wall time it is due at.
#[derive(Debug, Clone, Copy)]
pub struct Pacer {
    start: Instant,
    speed: Option<f64>,
    /// The wall clock at `start`, ns since the Unix epoch, when stamping wall time.
    wall: Option<u128>,
}

impl Pacer {
    /// `speed` None: as fast as possible. Stamps program time.
    pub fn new(speed: Option<f64>) -> Pacer {
        Pacer { start: Instant::now(), speed, wall: None }
    }

    /// Whether it stamps wall time (else program time).
    pub fn stamps_wall_time(&self) -> bool {
        self.wall.is_some()
    }

    /// The same pacing started `d` later: every sample is due, and stamped in wall time, `d` later.
    pub fn delayed(self, d: Duration) -> Pacer {
        Pacer { start: self.start + d, wall: self.wall.map(|w| w + d.as_nanos()), ..self }
    }

    /// Stamp the wall time each sample is due at, from the wall clock now (the pacer's start).
    pub fn stamping_wall_time(self) -> Pacer {
        let wall = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map_or(0, |d| d.as_nanos());
        Pacer { wall: Some(wall.saturating_sub(self.start.elapsed().as_nanos())), ..self }
    }

    /// The stamp of sample time `t` (s): `t` itself in program time, else the wall time it is due
    /// at (start + t / speed), to the nanosecond.
    pub fn stamp(&self, t: f64) -> fiveaxis_msgs::Time {
        match self.wall {
            None => fiveaxis_msgs::Time::from_secs(t),
            Some(w) => {
                let dt = (t / self.speed.unwrap_or(1.0)).max(0.0);
                fiveaxis_msgs::Time::from_nanos((w + (dt * 1e9).round() as u128).min(u64::MAX as u128) as u64)
            }
        }
    }
    pub fn wait_until(&self, t: f64) {
        if let Some(speed) = self.speed {
            let due = self.start + Duration::from_secs_f64((t / speed).max(0.0));
            let now = Instant::now();
            if due > now {
                std::thread::sleep(due - now);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Whether a filter lets through a warning from RustDDS's sender, and a debug event of RustDDS and
    /// of the node (asked of tracing-subscriber's own EnvFilter).
    fn lets_through(filter: &str) -> (bool, bool, bool) {
        use tracing_subscriber::layer::SubscriberExt as _;
        let f = tracing_subscriber::EnvFilter::try_new(filter).unwrap_or_else(|e| panic!("{filter}: {e}"));
        tracing::subscriber::with_default(tracing_subscriber::registry().with(f), || {
            (
                tracing::event_enabled!(target: "rustdds::network::udp_sender", tracing::Level::WARN),
                tracing::event_enabled!(target: "rustdds::rtps::writer", tracing::Level::DEBUG),
                tracing::event_enabled!(target: "fiveaxis_monitor", tracing::Level::DEBUG),
            )
        })
    }

    #[test]
    fn the_dds_stacks_per_datagram_warnings_stay_out_of_the_logs_unless_asked_for() {
        // Whatever level the user asks (RUST_LOG or --log-level), RustDDS's "Message size" warning on
        // every datagram over 1500 bytes is not logged, nor RustDDS's debug events.
        for user in ["warn", "debug", "info,fiveaxis_monitor=debug", "DEBUG,"] {
            let (sender, dds_debug, _) = lets_through(&user_log_filter(user));
            assert!(!sender && !dds_debug, "{user}: {}", user_log_filter(user));
        }
        assert!(lets_through(&user_log_filter("debug")).2, "the node's own debug events stay");
        // A user who names RustDDS gets what they named.
        assert_eq!(lets_through(&user_log_filter("info,rustdds=debug")), (true, true, false));
        assert!(lets_through(&user_log_filter("rustdds::network=warn")).0);
        assert!(lets_through(&user_log_filter("warn,rustdds")).0, "a bare target is every level of it");
        // The default filter.
        assert!(!lets_through(&format!("info,{DDS_LOG_DIRECTIVES}")).0);
    }

    #[test]
    fn environment() {
        let env = |pairs: &'static [(&'static str, &'static str)]| move |k: &str| pairs.iter().find(|(a, _)| *a == k).map(|(_, v)| v.to_string());
        assert_eq!(ros_environment(env(&[])).unwrap(), (0, DiscoveryRange::Subnet));
        assert_eq!(ros_environment(env(&[("ROS_DOMAIN_ID", "42")])).unwrap().0, 42);
        assert!(ros_environment(env(&[("ROS_DOMAIN_ID", "300")])).is_err());
        assert!(ros_environment(env(&[("ROS_DOMAIN_ID", "x")])).is_err());
        assert_eq!(ros_environment(env(&[("ROS_LOCALHOST_ONLY", "1")])).unwrap().1, DiscoveryRange::Localhost);
        // The newer variable wins over the older one.
        assert_eq!(
            ros_environment(env(&[("ROS_LOCALHOST_ONLY", "1"), ("ROS_AUTOMATIC_DISCOVERY_RANGE", "SUBNET")])).unwrap().1,
            DiscoveryRange::Subnet
        );
        assert_eq!(ros_environment(env(&[("ROS_AUTOMATIC_DISCOVERY_RANGE", "localhost")])).unwrap().1, DiscoveryRange::Localhost);
        assert!(ros_environment(env(&[("ROS_AUTOMATIC_DISCOVERY_RANGE", "MOON")])).is_err());
    }

    #[test]
    fn topic_names() {
        let r = vec![("commanded/axis_state".to_string(), "/cnc/state".to_string())];
        assert_eq!(resolve("/fiveaxis", &[], "monitor/status"), "/fiveaxis/monitor/status");
        assert_eq!(resolve("/fiveaxis/", &[], "/diagnostics"), "/diagnostics");
        assert_eq!(resolve("/fiveaxis", &r, "commanded/axis_state"), "/cnc/state");
        assert_eq!(resolve("/fiveaxis", &r, "/fiveaxis/commanded/axis_state"), "/cnc/state");
        assert!(parse_remap("a:=b").is_ok() && parse_remap("a=b").is_err());
    }

    #[test]
    fn a_delayed_pacer_is_due_and_stamps_wall_time_that_much_later() {
        // 4x: sample time 2 s is due 0.5 s after the start.
        let p = Pacer::new(Some(4.0)).stamping_wall_time();
        let d = Pacer::delayed(p, Duration::from_millis(1500));
        assert_eq!(d.start - p.start, Duration::from_millis(1500));
        let ns = |t: fiveaxis_msgs::Time| t.sec as i128 * 1_000_000_000 + t.nanosec as i128;
        assert_eq!(ns(d.stamp(2.0)) - ns(p.stamp(2.0)), 1_500_000_000);
        assert_eq!(ns(p.stamp(2.0)) - ns(p.stamp(0.0)), 500_000_000);
        // Program time stamps do not move.
        let sim = Pacer::new(Some(4.0));
        assert_eq!(ns(Pacer::delayed(sim, Duration::from_secs(3)).stamp(2.0)), 2_000_000_000);
    }
}

/// Read `sub` on its own thread and hand each message to a node's main loop as `wrap(topic, msg)`;
/// the thread ends when the receiver is gone. A message that does not decode (malformed, or beyond
/// the bounds of `fiveaxis_msgs::bounds`) is logged (the first of each topic, then every 1000th)
/// and handed on as `failed(topic, reason)` for the node to count.
pub fn forward<M: DeserializeOwned + Send + 'static, T: Send + 'static>(
    sub: Subscription<M>,
    topic: String,
    tx: std::sync::mpsc::SyncSender<T>,
    wrap: impl Fn(String, M) -> T + Send + 'static,
    failed: impl Fn(String, String) -> T + Send + 'static,
) {
    std::thread::spawn(move || {
        let mut errors = 0u64;
        loop {
            let out = match smol::block_on(sub.async_take()) {
                Ok((msg, _)) => wrap(topic.clone(), msg),
                Err(e) => {
                    errors += 1;
                    if errors % 1000 == 1 {
                        tracing::warn!(%topic, errors, "a message did not decode: {e:?}");
                    }
                    failed(topic.clone(), format!("{e:?}"))
                }
            };
            if tx.send(out).is_err() {
                break;
            }
        }
    });
}

/// The axis-state streams a node watches (the monitor, the Rerun bridge).
#[derive(Debug, Clone, clap::Args)]
pub struct InputArgs {
    /// AxisState topics to watch (repeatable; default commanded/axis_state and simulated/axis_state).
    #[arg(long = "input", value_name = "TOPIC")]
    pub inputs: Vec<String>,
    /// sensor_msgs/JointState topics to watch, e.g. a machine bridge's /joint_states (repeatable).
    #[arg(long = "joint-state-input", value_name = "TOPIC")]
    pub joint_inputs: Vec<String>,
    #[command(flatten)]
    pub axis_map: fiveaxis::args::AxisMapArgs,
    /// Reliability asked of the input publishers: reliable, best-effort, or auto (hear both).
    #[arg(long = "input-qos", value_enum, default_value = "auto")]
    pub input_qos: InputQos,
    /// The control's active work offset (G54-style datum) `X,Y,Z` in mm: a machine stream's tool tip
    /// less it is the program's point (without --program; with one, its datum is used).
    #[arg(long = "work-offset-mm", value_name = "X,Y,Z", value_parser = fiveaxis::machine::parse_work_offset, allow_hyphen_values = true)]
    pub work_offset: Option<nalgebra::Vector3<f64>>,
}

impl InputArgs {
    /// Machine axis -> joint name, resolved against `machine` (axis names case-insensitive; an axis
    /// the machine lacks is an error naming its axes).
    pub fn axis_map(&self, machine: &fiveaxis::machine::Machine) -> Result<std::collections::BTreeMap<String, String>, String> {
        self.axis_map.resolve(machine)
    }
}

