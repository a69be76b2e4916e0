//! `fiveaxis-commander`: reads an NC program and publishes its commanded axis states
//! (`commanded/axis_state`, `commanded/joint_states`), stamped in wall time, or with `use_sim_time` in
//! program time, which it then also publishes on `/clock` (the node set's clock source).
//! The program is read as it is published, in flat memory; a defect stops it ([`fiveaxis_bus::Gate`]).

use fiveaxis::topics;
use clap::Parser;
use fiveaxis::live::commander::commanded_passes;
use fiveaxis::live::StateBuilder;
use fiveaxis_bus::{clock_qos, init_tracing, EXIT_INPUT, open_program, publish_states, state_qos, Bus, CommonArgs, Shutdown, StreamArgs};
use fiveaxis_msgs::{AxisState, Clock, JointState};
use std::time::Duration;

/// Publish a program's commanded axis states.
#[derive(Parser)]
#[command(name = "fiveaxis-commander", version)]
struct Args {
    #[command(flatten)]
    stream: StreamArgs,
    #[command(flatten)]
    common: CommonArgs,
}

fn main() -> anyhow::Result<()> {
    let (args, ros) = fiveaxis_bus::ros_args::parse::<Args>("fiveaxis_commander");
    init_tracing(&ros);
    if let Err(e) = args.stream.validate(args.common.use_sim_time) {
        eprintln!("error: {e}");
        std::process::exit(EXIT_INPUT);
    }
    let shutdown = Shutdown::install()?;
    let machine = args.common.machine_or_exit();
    let (moves, gate) = open_program(&args.stream.program, &args.stream.job_options(), &machine, Duration::from_secs_f64(args.stream.check_before_publish_s));

    let mut bus = Bus::new("fiveaxis_commander", &args.common, &ros)?;
    let state_pub = bus.publisher::<AxisState>(topics::COMMANDED_STATE.name, state_qos())?;
    let joint_pub = bus.publisher::<JointState>(topics::COMMANDED_JOINTS.name, state_qos())?;
    // Program time goes on /clock only when it is the stamps' clock.
    let clock_pub = if args.common.use_sim_time { Some(bus.publisher::<Clock>(topics::CLOCK.name, clock_qos())?) } else { None };
    bus.wait_for_stream_subscribers(&state_pub, topics::COMMANDED_STATE.name, &args.stream, &shutdown);
    bus.rosout(ros2_client::ros2::LogLevel::Info, &format!("commanding {}", args.stream.program));
    let pacer = args.stream.pacer(args.common.use_sim_time);
    let builder = StateBuilder::new(&machine, AxisState::SOURCE_COMMANDED);
    let reread = std::sync::OnceLock::new();
    let states = match commanded_passes(&moves, &machine, args.stream.pass_count(), &reread) {
        Ok(s) => s.map(|v| builder.message(&v)),
        Err(e) => {
            eprintln!("error: reading {} again to publish it: {e}", args.stream.program);
            std::process::exit(EXIT_INPUT);
        }
    };
    let (sent, _) = publish_states(gate.guard(states, || shutdown.requested()), &state_pub, &joint_pub, clock_pub.as_ref(), &pacer, args.stream.subscriber_wait(), &shutdown);
    fiveaxis_bus::program::finish_passes(&args.stream.program, &reread, sent);
    gate.finish(sent > 0, shutdown.requested());
    Ok(())
}
