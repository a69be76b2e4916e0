//! `fiveaxis-rerun`: the Rerun bridge. `live` subscribes to the node set's axis-state streams over
//! DDS (or a machine bridge's JointState) and streams them to a Rerun viewer; `replay` does the same
//! from an MCAP recording. Both recompute the monitor per sample (the same [`fiveaxis::scene`]), lay
//! an optional roughness profile along the workpiece x, and send the default layout.

use anyhow::Context as _;
use clap::{Args, Parser, Subcommand};
use fiveaxis::live::monitor::MonitorConfig;
use fiveaxis::roughness::RoughnessArgs;
use fiveaxis::scene::{replay_mcap, Scene};
use fiveaxis::units::RPM;
use fiveaxis::live::joint_map::{unmapped_hint, JointMap};
use fiveaxis_bus::{init_tracing, subscribe_states, Bus, CommonArgs, InputArgs, Received, Shutdown, StateReceiver};
use fiveaxis_rerun::{send_layout, Bridge, BridgeOptions, APP_ID};
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::{Duration, Instant};

/// Stream the fiveaxis node set (live over DDS, or from an MCAP recording) to Rerun.
#[derive(Parser)]
#[command(name = "fiveaxis-rerun", version)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Replay a recording (MCAP, rosbag2 layout) into a viewer or an .rrd file.
    Replay(ReplayArgs),
    /// Subscribe to the axis-state streams over DDS and stream them live.
    Live(LiveArgs),
}

/// Where the data goes: a running viewer, an .rrd file, or a viewer spawned here.
#[derive(Args, Clone)]
struct SinkArgs {
    /// Stream to a running viewer at this gRPC URL (default when nothing else is given:
    /// rerun+http://127.0.0.1:9876/proxy, what `rerun` listens on).
    #[arg(long, num_args = 0..=1, default_missing_value = rerun::DEFAULT_CONNECT_URL, value_name = "URL")]
    connect: Option<String>,
    /// Save to this .rrd file instead (open it with `rerun FILE`).
    #[arg(long, value_name = "FILE.rrd")]
    save: Option<PathBuf>,
    /// Spawn a viewer (`rerun` on the PATH, e.g. `pip install rerun-sdk==0.36.3`) and stream to it;
    /// it listens on 127.0.0.1 only.
    #[arg(long, conflicts_with_all = ["connect", "save"])]
    spawn: bool,
    /// Recording name shown in the viewer (default: the file or "live").
    #[arg(long = "recording-name")]
    recording_name: Option<String>,
}

/// How the charts across the part pick their passes.
#[derive(Args, Clone)]
struct ViewArgs {
    /// Passes whose lowest tool-tip z is more than this above the lowest pass are taken for moves at
    /// a clearance height and left out of the charts across the part, mm.
    #[arg(long = "contact-band-mm", default_value_t = fiveaxis::scene::CONTACT_BAND_MM)]
    contact_band_mm: f64,
    /// Workpiece y of the pass the roughness profile was measured on, mm (default: the pass covering
    /// most of the profile's x range).
    #[arg(long = "roughness-y-mm", allow_hyphen_values = true)]
    roughness_y_mm: Option<f64>,
}

impl ViewArgs {
    fn options(&self) -> anyhow::Result<BridgeOptions> {
        if !(self.contact_band_mm.is_finite() && self.contact_band_mm >= 0.0) {
            anyhow::bail!("--contact-band-mm must be a finite length >= 0, not {}", self.contact_band_mm);
        }
        if self.roughness_y_mm.is_some_and(|y| !y.is_finite()) {
            anyhow::bail!("--roughness-y-mm must be finite");
        }
        Ok(BridgeOptions { contact_band_mm: self.contact_band_mm, roughness_y_mm: self.roughness_y_mm })
    }
}

/// What both commands draw and where: the region threshold, the roughness profile, the view, the sink.
#[derive(Args)]
struct OutputArgs {
    /// Region threshold of the singular axis speed, rpm (default: the machine's limit).
    #[arg(long = "max-c-speed-rpm")]
    max_c_speed_rpm: Option<f64>,
    #[command(flatten)]
    roughness: RoughnessArgs,
    #[command(flatten)]
    view: ViewArgs,
    #[command(flatten)]
    sink: SinkArgs,
}

#[derive(Args)]
struct ReplayArgs {
    /// The recording.
    recording: PathBuf,
    #[command(flatten)]
    machine: fiveaxis::args::MachineArgs,
    #[command(flatten)]
    streams: fiveaxis::args::RecordedStreamArgs,
    /// The control's active work offset (G54-style datum) `X,Y,Z` in mm: a recorded machine stream's
    /// tool tip less it is the program's point.
    #[arg(long = "work-offset-mm", value_name = "X,Y,Z", value_parser = fiveaxis::machine::parse_work_offset, allow_hyphen_values = true)]
    work_offset: Option<nalgebra::Vector3<f64>>,
    #[command(flatten)]
    out: OutputArgs,
}

#[derive(Args)]
struct LiveArgs {
    #[command(flatten)]
    common: CommonArgs,
    #[command(flatten)]
    inputs: InputArgs,
    /// Send buffered samples to the viewer at least this often, ms.
    #[arg(long = "flush-ms", default_value_t = 200)]
    flush_ms: u64,
    /// Exit once no sample has arrived for this long after the first, s.
    #[arg(long = "exit-when-idle-s")]
    exit_when_idle_s: Option<f64>,
    #[command(flatten)]
    out: OutputArgs,
}

/// Exit codes: 0 done, 1 the viewer or the file failed, 2 bad input (unreadable recording, bad flags).
const EXIT_FAIL: u8 = 1;
const EXIT_INPUT: u8 = 2;

/// Report bad input (a flag, a file) and give its exit code.
fn bad_input(e: impl std::fmt::Display) -> ExitCode {
    eprintln!("fiveaxis-rerun: {e}");
    ExitCode::from(EXIT_INPUT)
}

/// The machine, the roughness profile and the view both commands take; any of them bad is bad
/// input (exit 2, said).
fn settings(machine: &fiveaxis::args::MachineArgs, roughness: &RoughnessArgs, view: &ViewArgs) -> Result<(fiveaxis::machine::Machine, Option<(fiveaxis::roughness::Profile, f64)>, BridgeOptions), ExitCode> {
    let machine = machine.load().and_then(|m| m.five_axis("the Rerun bridge")).map_err(bad_input)?;
    let roughness = roughness.load().map_err(bad_input)?;
    let options = view.options().map_err(bad_input)?;
    Ok((machine, roughness, options))
}

fn open_stream(sink: &SinkArgs, default_name: &str) -> anyhow::Result<rerun::RecordingStream> {
    let builder = rerun::RecordingStreamBuilder::new(APP_ID)
        .recording_name(sink.recording_name.clone().unwrap_or_else(|| default_name.to_string()));
    let rec = if let Some(path) = &sink.save {
        builder.save(path).with_context(|| format!("creating {}", path.display()))?
    } else if sink.spawn {
        let opts = rerun::SpawnOptions { extra_args: vec!["--bind".into(), "127.0.0.1".into()], ..Default::default() };
        builder.spawn_opts(&opts).context("spawning a Rerun viewer (is `rerun` on the PATH? pip install rerun-sdk==0.36.3)")?
    } else {
        let url = sink.connect.clone().unwrap_or_else(|| rerun::DEFAULT_CONNECT_URL.to_string());
        builder.connect_grpc_opts(url.clone()).with_context(|| format!("connecting to a Rerun viewer at {url}"))?
    };
    send_layout(&rec)?;
    Ok(rec)
}

/// The monitor's settings: the region threshold, and the control's work offset for machine streams.
fn config(max_c_speed_rpm: Option<f64>, work_offset: Option<nalgebra::Vector3<f64>>) -> MonitorConfig {
    MonitorConfig { rate_limit: max_c_speed_rpm.map(|r| r * RPM), work_offset: work_offset.unwrap_or_default(), ..Default::default() }
}

fn replay(a: &ReplayArgs) -> anyhow::Result<ExitCode> {
    let (machine, roughness, options) = match settings(&a.machine, &a.out.roughness, &a.out.view) {
        Ok(s) => s,
        Err(code) => return Ok(code),
    };
    let selection = match a.streams.selection(&machine) {
        Ok(m) => m,
        Err(e) => return Ok(bad_input(e)),
    };
    // Every input is checked before the output is opened (a .rrd is not overwritten for nothing).
    let name = a.recording.file_name().map_or("recording".into(), |n| n.to_string_lossy().into_owned());
    let rec = open_stream(&a.out.sink, &name)?;
    let mut bridge = Bridge::new(rec, &machine, &options)?;
    if let Some((profile, cutoff)) = &roughness {
        bridge.roughness(profile, *cutoff)?;
    }
    let mut scene = Scene::new(&machine, config(a.out.max_c_speed_rpm, a.work_offset));
    let mut failure: Option<anyhow::Error> = None;
    let stats = replay_mcap(&a.recording, &mut scene, &selection, |row, events| {
        if failure.is_some() {
            return;
        }
        let r = row.map_or(Ok(()), |r| bridge.row(r)).and_then(|_| bridge.events(events));
        if let Err(e) = r {
            failure = Some(e);
        }
    });
    let stats = match stats {
        Ok(s) => s,
        Err(e) => {
            // What was read before the damage is already logged: finish the file with it.
            bridge.flush()?;
            bridge.stream().flush_blocking().ok();
            eprintln!("fiveaxis-rerun: {e} (the samples before it were sent)");
            return Ok(ExitCode::from(EXIT_INPUT));
        }
    };
    if let Some(e) = failure {
        return Err(e);
    }
    bridge.flush()?;
    bridge.stream().flush_blocking().context("flushing to the viewer or file")?;
    // A stream asked for and absent, or nothing drawn of any stream read (joints that do not map,
    // nothing the monitor took), is bad input, as `fiveaxis analyze` says of it; a stream not drawn
    // beside others drawn (a gripper's JointState in a machine's bag) is said. The file holds what
    // was drawn.
    let (errors, undrawn) = stats.input_errors(&scene, &selection);
    for e in errors.iter().chain(&undrawn) {
        eprintln!("fiveaxis-rerun: {e}");
    }
    if !errors.is_empty() || stats.rows == 0 {
        return Ok(ExitCode::from(EXIT_INPUT));
    }
    let rejected: u64 = scene.rejected.values().sum();
    eprintln!(
        "fiveaxis-rerun: {} messages read, {} samples drawn{}{}{}",
        stats.read.messages_read,
        stats.rows,
        if stats.read.undecodable() > 0 { format!(", {} undecodable", stats.read.undecodable()) } else { String::new() },
        if rejected > 0 { format!(", {rejected} refused (a joint missing, NaN, out of range, out of order)") } else { String::new() },
        a.out.sink.save.as_ref().map_or(String::new(), |p| format!(" -> {}", p.display()))
    );
    Ok(ExitCode::SUCCESS)
}


fn live(a: LiveArgs, ros: &fiveaxis_bus::RosOptions) -> anyhow::Result<ExitCode> {
    let shutdown = Shutdown::install()?;
    let (machine, roughness, options) = match settings(&a.common.machine, &a.out.roughness, &a.out.view) {
        Ok(s) => s,
        Err(code) => return Ok(code),
    };
    let map = match a.inputs.axis_map(&machine) {
        Ok(m) => m,
        Err(e) => return Ok(bad_input(e)),
    };
    let rec = open_stream(&a.out.sink, "live")?;
    let mut bridge = Bridge::new(rec, &machine, &options)?;
    if let Some((profile, cutoff)) = &roughness {
        bridge.roughness(profile, *cutoff)?;
    }
    let mut scene = Scene::new(&machine, config(a.out.max_c_speed_rpm, a.inputs.work_offset));

    let mut bus = Bus::new("fiveaxis_rerun", &a.common, ros)?;
    let rx = subscribe_states(&mut bus, &a.inputs)?;
    let flush_every = Duration::from_millis(a.flush_ms.max(10));
    let mut last_flush = Instant::now();
    let mut samples = 0u64;
    let mut said = std::collections::BTreeSet::new();
    let receiver = StateReceiver::new(rx, JointMap::new(&machine, &map), &machine, &shutdown, Duration::from_millis(20), a.exit_when_idle_s);
    for received in receiver {
        match received {
            Received::State { topic, state, uncertainty, .. } => {
                let (row, events) = scene.push_merged(&topic, &state, uncertainty.as_ref());
                if let Some(r) = row {
                    bridge.row(&r)?;
                    samples += 1;
                }
                bridge.events(&events)?;
            }
            Received::Refused { topic, why, joints } => {
                // Said once per topic (a machine's JointState comes at 1 kHz); counted in the scene.
                if said.insert(topic.clone()) {
                    let map_hint = joints.map_or(String::new(), |names| format!("; {}", unmapped_hint(&machine, &names, &map)));
                    tracing::warn!(%topic, "{why}{map_hint} (said once)");
                }
                scene.reject(&topic, &why);
            }
            Received::Heard { .. } | Received::Idle => {}
        }
        if last_flush.elapsed() >= flush_every {
            bridge.flush()?;
            last_flush = Instant::now();
        }
    }
    let events = scene.finish();
    bridge.events(&events)?;
    bridge.flush()?;
    bridge.stream().flush_blocking().context("flushing to the viewer or file")?;
    tracing::info!(samples, "done");
    Ok(ExitCode::SUCCESS)
}

fn main() -> ExitCode {
    if std::env::var_os("RUST_LOG").is_none() {
        // Rerun logs its sinks at info: keep those quiet unless asked for.
        std::env::set_var("RUST_LOG", format!("info,re_chunk=error,re_sdk=warn,re_log_encoding=warn,{}", fiveaxis_bus::DDS_LOG_DIRECTIVES));
    }
    let (cli, ros) = fiveaxis_bus::ros_args::parse::<Cli>("fiveaxis_rerun");
    init_tracing(&ros);
    let r = match cli.command {
        Command::Replay(a) => replay(&a),
        Command::Live(a) => live(a, &ros),
    };
    match r {
        Ok(code) => code,
        Err(e) => {
            eprintln!("fiveaxis-rerun: {e:#}");
            ExitCode::from(EXIT_FAIL)
        }
    }
}
