//! `fiveaxis-monitor`: subscribes to axis-state streams (our AxisState, or any JointState from a
//! machine's bridge) and publishes, per sample, the singularity status (`monitor/status`) and, at
//! 2 Hz, `/diagnostics`: OK, WARN near the singularity or with a region ahead, ERROR above the C
//! limit, STALE without samples.

use anyhow::Context as _;
use clap::Parser;
use fiveaxis::live::joint_map::{unmapped_hint, JointMap};
use fiveaxis::live::monitor::{Monitor, MonitorConfig, Rejection};
use fiveaxis::topics;
use fiveaxis::units::{MM, MM_PER_MIN, RPM};
use fiveaxis_bus::{diagnostics_qos, init_tracing, state_qos, subscribe_states, Bus, CommonArgs, InputArgs, Received, Shutdown, StateReceiver};
use fiveaxis_msgs::{DiagnosticArray, SingularityStatus};
use std::collections::BTreeMap;
use std::path::PathBuf;
use std::time::Duration;

/// Columns of `--samples-csv`: mm, mm/min, rpm, degrees.
const SAMPLES_CSV_HEADER: [&str; 15] = [
    "topic",
    "t_s",
    "x_mm",
    "y_mm",
    "z_mm",
    "path_feed_mm_per_min",
    "programmed_feed_mm_per_min",
    "predicted_c_speed_rpm",
    "c_speed_rpm",
    "singularity_distance_deg",
    "feed_limit_mm_per_min",
    "limiting_axis",
    "in_region",
    "region_id",
    "block",
];

/// Watch axis-state streams for the singularity.
#[derive(Parser)]
#[command(name = "fiveaxis-monitor", version)]
struct Args {
    #[command(flatten)]
    common: CommonArgs,
    #[command(flatten)]
    inputs: InputArgs,
    /// The commanded stream used for the look-ahead ("" for none).
    #[arg(long, default_value = "commanded/axis_state")]
    lookahead: String,
    /// An input with no sample for this long is stale, ms.
    #[arg(long = "stale-ms", default_value_t = 100.0)]
    stale_ms: f64,
    /// Also a region when the tool axis comes closer than this to the singularity, degrees.
    #[arg(long = "min-distance-deg")]
    min_distance_deg: Option<f64>,
    /// Region threshold of the singular axis speed, rpm (default: the machine's limit).
    #[arg(long = "max-c-speed-rpm")]
    max_c_speed_rpm: Option<f64>,
    /// Write a JSON summary (per input: counters, regions) here on exit.
    #[arg(long = "summary-json")]
    summary_json: Option<PathBuf>,
    /// Write every evaluated sample as a CSV row here (topic, time, tool tip, feeds, C speeds,
    /// distance, feed limit, region), in mm, mm/min, rpm and degrees.
    #[arg(long = "samples-csv")]
    samples_csv: Option<PathBuf>,
    /// The program the machine runs (a file, `-` for standard input, bundled:NAME): machine streams (JointState inputs) are
    /// aligned with its moves for the programmed feed, block numbers and rapids.
    #[arg(long, conflicts_with = "feed_mm_per_min")]
    program: Option<String>,
    /// The programmed feed of every feed move of a machine stream, mm/min (without --program).
    #[arg(long = "feed", value_name = "MM_PER_MIN")]
    feed_mm_per_min: Option<f64>,
    #[command(flatten)]
    control: fiveaxis::program::ControlArgs,
    /// Exit once every input has been stale this long after having delivered samples, s.
    #[arg(long = "exit-when-idle-s")]
    exit_when_idle_s: Option<f64>,
}

fn main() -> anyhow::Result<()> {
    let (args, ros) = fiveaxis_bus::ros_args::parse::<Args>("fiveaxis_monitor");
    init_tracing(&ros);
    let shutdown = Shutdown::install()?;
    let machine = args.common.machine_or_exit();
    let config = MonitorConfig {
        stale_timeout: args.stale_ms * 1e-3,
        min_distance: args.min_distance_deg.map(f64::to_radians),
        rate_limit: args.max_c_speed_rpm.map(|r| r * RPM),
        work_offset: args.inputs.work_offset.unwrap_or_default(),
        ..Default::default()
    };
    let mut monitor = Monitor::new(&machine, config);
    let (rename, feed_source) = match args.inputs.axis_map(&machine).and_then(|m| {
        fiveaxis::job::feed_source(args.program.as_deref(), args.feed_mm_per_min, &machine, &args.control.read_options()).map(|f| (m, f))
    }) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("fiveaxis-monitor: {e}");
            std::process::exit(2);
        }
    };
    if !args.inputs.joint_inputs.is_empty() {
        tracing::info!("machine streams: programmed feed {}", feed_source.describe());
    }
    monitor.set_feed_source(feed_source);
    // Each kind of rejection is said once per topic (the counters go on in the status and /diagnostics).
    let mut said: std::collections::BTreeSet<(String, &'static str)> = Default::default();

    let mut bus = Bus::new("fiveaxis_monitor", &args.common, &ros)?;
    let status_pub = bus.publisher::<SingularityStatus>(topics::STATUS.name, state_qos())?;
    let diag_pub = bus.publisher::<DiagnosticArray>(topics::DIAGNOSTICS.name, diagnostics_qos())?;
    let lookahead = (!args.lookahead.is_empty()).then(|| bus.resolve(&args.lookahead));
    let rx = subscribe_states(&mut bus, &args.inputs)?;

    let mut csv = match &args.samples_csv {
        Some(p) => {
            let mut w = csv::Writer::from_writer(std::fs::File::create(p).with_context(|| format!("creating {}", p.display()))?);
            w.write_record(SAMPLES_CSV_HEADER)?;
            Some(w)
        }
        None => None,
    };
    let mut receiver = StateReceiver::new(rx, JointMap::new(&machine, &rename), &machine, &shutdown, Duration::from_millis(10), args.exit_when_idle_s);
    receiver.set_restart_after(args.stale_ms * 1e-3);
    let mut last_diag = 0.0;
    let mut last_stale_status = 0.0;
    let mut in_region: BTreeMap<String, u32> = BTreeMap::new();
    let mut said_unreadable = false;
    while let Some(received) = receiver.next() {
        let now = receiver.now();
        match received {
            Received::State { topic, state, uncertainty, arrival } => {
                if lookahead.as_deref() == Some(topic.as_str()) {
                    monitor.on_commanded_ahead(&state);
                }
                match monitor.on_merged_state(&topic, &state, uncertainty.as_ref(), arrival.unwrap_or(now)) {
                    Ok(status) => {
                        let was = in_region.get(&topic).copied().unwrap_or(0);
                        if status.in_region && was != status.region_id {
                            tracing::warn!(%topic, region = status.region_id, x_mm = status.workpiece_position.x * 1e3, "entering a region: C speed above its limit");
                            bus.rosout(
                                ros2_client::ros2::LogLevel::Warn,
                                &format!("{topic}: region {} at x {:.3} mm", status.region_id, status.workpiece_position.x * 1e3),
                            );
                        } else if !status.in_region && was != 0 {
                            tracing::info!(%topic, region = was, x_mm = status.workpiece_position.x * 1e3, "leaving the region");
                        }
                        in_region.insert(topic.clone(), if status.in_region { status.region_id } else { 0 });
                        if let Some(w) = csv.as_mut() {
                            let p = &status.workpiece_position;
                            w.write_record([
                                topic.clone(),
                                format!("{:.6}", status.header.stamp.as_secs()),
                                format!("{:.5}", p.x / MM),
                                format!("{:.5}", p.y / MM),
                                format!("{:.5}", p.z / MM),
                                format!("{:.3}", status.path_feed / MM_PER_MIN),
                                format!("{:.3}", status.programmed_feed / MM_PER_MIN),
                                format!("{:.3}", status.predicted_c_speed / RPM),
                                format!("{:.3}", status.c_speed / RPM),
                                format!("{:.5}", status.singularity_distance.to_degrees()),
                                format!("{:.3}", status.feed_limit / MM_PER_MIN),
                                status.limiting_axis.clone(),
                                u8::from(status.in_region).to_string(),
                                status.region_id.to_string(),
                                status.block_number.to_string(),
                            ])?;
                        }
                        if let Err(e) = status_pub.publish(status) {
                            tracing::warn!("publishing the status: {e:?}");
                        }
                    }
                    Err(e) => {
                        let kind = match &e {
                            Rejection::OutOfOrder { .. } => "out of order",
                            e if e.is_out_of_range() => "out of range",
                            _ => "invalid",
                        };
                        if said.insert((topic.clone(), kind)) {
                            let hint = if kind == "out of range" { " (positions must be in m and rad, REP 103)" } else { "" };
                            tracing::warn!(%topic, "{e}{hint} (said once; counted in the status and /diagnostics)");
                        }
                    }
                }
            }
            Received::Refused { topic, why, joints } => {
                let id = monitor.input(&topic);
                monitor.reject(id, &why);
                // A JointState whose joints do not map: said once, with the joints it has.
                if let (Rejection::MissingJoint(_), Some(names)) = (&why, joints) {
                    if said.insert((topic.clone(), "missing joint")) {
                        tracing::error!(
                            %topic,
                            "{why}: {} (said once; counted in the status and /diagnostics)",
                            unmapped_hint(&machine, &names, &rename)
                        );
                    }
                }
            }
            Received::Heard { topic } => monitor.heard(&topic, now),
            Received::Idle => {}
        }
        let gone = monitor.tick(now);
        for topic in &gone {
            tracing::warn!(%topic, "stale: no sample for {} ms", args.stale_ms);
        }
        // While an input is stale the status topic says so (at once, then every 50 ms).
        if !gone.is_empty() || now - last_stale_status >= 0.05 {
            let stale = monitor.stale_statuses();
            if !stale.is_empty() {
                last_stale_status = now;
                for s in stale {
                    if let Err(e) = status_pub.publish(s) {
                        tracing::warn!("publishing the status: {e:?}");
                    }
                }
            }
        }
        if now - last_diag >= 0.5 {
            last_diag = now;
            if let (Some((topic, why)), false) = (monitor.program_unreadable(), said_unreadable) {
                said_unreadable = true;
                tracing::error!(%topic, "the program cannot be read again to place this stream's samples: {why} (the node will exit 2)");
            }
            // The node's clock: /clock's program time with use_sim_time, else wall time.
            if let Err(e) = diag_pub.publish(monitor.diagnostics(bus.now())) {
                tracing::warn!("publishing diagnostics: {e:?}");
            }
            monitor.reported();
        }
    }
    monitor.finish();
    if let Some(mut w) = csv.take() {
        w.flush()?;
    }
    let summary = monitor.summary();
    for s in &summary {
        tracing::info!(topic = %s.topic, samples = s.samples, invalid = s.invalid, out_of_order = s.out_of_order, stale = s.stale, lost = s.lost, regions = s.regions.len(), "input summary");
    }
    if let Some(path) = &args.summary_json {
        std::fs::write(path, serde_json::to_string_pretty(&summary)?).with_context(|| format!("writing {}", path.display()))?;
    }
    // Fail closed: a stream that could not be placed in the program was not monitored as asked.
    if let Some((topic, why)) = monitor.program_unreadable() {
        tracing::error!(%topic, "the program could not be read again to place this stream's samples: {why}");
        std::process::exit(2);
    }
    fiveaxis_bus::exit_if_teardown_hangs(0, Duration::from_secs(10));
    Ok(())
}
