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

mod args;
mod logging;
mod participant;
pub mod program;
mod publish;
pub mod raw;
pub mod ros_args;
pub mod security;
pub mod states;
pub use args::{parse_remap, CommonArgs, InputArgs, StreamArgs, EXIT_INPUT};
pub use logging::{init_tracing, user_log_filter, DDS_LOG_DIRECTIVES};
pub use participant::{context_with, participant_settings, ros_environment, DiscoveryRange, ParticipantSettings};
use publish::retry_until;
pub use publish::{publish_states, Pacer};
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn topic_names() {
        let r = vec![("commanded/axis_state".to_string(), "/cnc/state".to_string())];
        assert_eq!(resolve("/fiveaxis", &[], "monitor/status"), "/fiveaxis/monitor/status");
        assert_eq!(resolve("/fiveaxis/", &[], "/diagnostics"), "/diagnostics");
        assert_eq!(resolve("/fiveaxis", &r, "commanded/axis_state"), "/cnc/state");
        assert_eq!(resolve("/fiveaxis", &r, "/fiveaxis/commanded/axis_state"), "/cnc/state");
        assert!(parse_remap("a:=b").is_ok() && parse_remap("a=b").is_err());
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
