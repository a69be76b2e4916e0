//! Logging to stderr with tracing, the DDS stack's own chatter kept out unless asked for.

use crate::RosOptions;

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
}
