//! `fiveaxis-commander`: reads an NC program and publishes its commanded axis states
//! (`commanded/axis_state`, `commanded/joint_states`) and `/clock` (program time, use_sim_time).

use anyhow::Context as _;
use clap::Parser;
use fiveaxis::job::{self, JobOptions};
use fiveaxis::live::commander::commanded_states;
use fiveaxis::machine::Machine;
use fiveaxis::path::PathOptions;
use fiveaxis_bus::{clock_qos, init_tracing, publish_states, state_qos, Bus, CommonArgs, Pacer, Shutdown};
use fiveaxis_msgs::{AxisState, Clock, JointState};
use std::time::Duration;

/// Publish a program's commanded axis states.
#[derive(Parser)]
#[command(name = "fiveaxis-commander", version)]
struct Args {
    /// Program file, builtin:NAME or bundled:NAME (as for `fiveaxis program analyze`).
    program: String,
    #[command(flatten)]
    common: CommonArgs,
    /// Samples per second.
    #[arg(long, default_value_t = 1000.0)]
    rate: f64,
    /// Publish in real time (the default).
    #[arg(long, conflicts_with = "fast")]
    realtime: bool,
    /// Publish as fast as possible (follow /clock for time).
    #[arg(long)]
    fast: bool,
    /// Real-time factor: 2 runs twice as fast as the machine would.
    #[arg(long, default_value_t = 1.0)]
    speed: f64,
    /// Tool-tip feed for every feed move, mm/min.
    #[arg(long = "feed", value_name = "MM_PER_MIN")]
    feed_mm_per_min: Option<f64>,
    /// Wait this long for subscribers before publishing (0: do not wait), s.
    #[arg(long = "wait-for-subscriber-s", default_value_t = 10.0)]
    wait_s: f64,
    /// How many subscribers of the state stream to wait for (e.g. monitor and recorder: 2).
    #[arg(long = "min-subscribers", default_value_t = 1)]
    min_subscribers: usize,
}

fn main() -> anyhow::Result<()> {
    init_tracing();
    let args = Args::parse();
    anyhow::ensure!(args.rate > 0.0 && args.rate.is_finite(), "--rate must be positive");
    anyhow::ensure!(args.speed > 0.0 && args.speed.is_finite(), "--speed must be positive");
    let shutdown = Shutdown::install()?;
    let machine = Machine::from_name_or_file(&args.common.machine).context("loading the machine")?;
    let options = JobOptions {
        path: PathOptions { period: 1.0 / args.rate, feed_override_mm_per_min: args.feed_mm_per_min },
        ..Default::default()
    };
    let job = job::run(&args.program, &machine, &options).with_context(|| format!("reading {}", args.program))?;
    for d in job.program.report() {
        tracing::warn!("{d}");
    }
    let states = commanded_states(&job.trajectory, &machine);
    tracing::info!(program = %args.program, samples = states.len(), duration_s = job.trajectory.duration(), "commanded trajectory");

    let mut bus = Bus::new("fiveaxis_commander", &args.common)?;
    let state_pub = bus.publisher::<AxisState>("commanded/axis_state", state_qos())?;
    let joint_pub = bus.publisher::<JointState>("commanded/joint_states", state_qos())?;
    let clock_pub = bus.publisher::<Clock>("/clock", clock_qos())?;
    if args.wait_s > 0.0 && !bus.wait_for_subscribers(&state_pub, args.min_subscribers.max(1), Duration::from_secs_f64(args.wait_s), &shutdown) {
        tracing::warn!("no subscriber on {} after {} s: publishing anyway", bus.resolve("commanded/axis_state"), args.wait_s);
    }
    ros2_client::rosout!(bus.node, ros2_client::ros2::LogLevel::Info, "commanding {} ({} samples)", args.program, states.len());
    let pacer = Pacer::new(if args.fast { None } else { Some(args.speed) });
    publish_states(&states, &state_pub, &joint_pub, Some(&clock_pub), &pacer, &shutdown);
    Ok(())
}
