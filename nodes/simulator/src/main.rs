//! `fiveaxis-simulator`: what a machine with axis velocity, acceleration and jerk limits does with an
//! NC program (look-ahead planner, servo), published as `simulated/axis_state` and
//! `simulated/joint_states`. It reads the program itself, as a control does: its look-ahead needs
//! the path ahead, which a stream of set-points does not carry.

use fiveaxis::topics;
use clap::Parser;
use fiveaxis::live::sim_report::simulate_measured_stream;
use fiveaxis::live::{StateBuilder, StateValues};
use fiveaxis::live::simulator::SimConfig;
use fiveaxis_bus::{init_tracing, open_program, EXIT_INPUT, publish_states, state_qos, Bus, CommonArgs, Shutdown, StreamArgs};
use fiveaxis_msgs::{AxisState, JointState};
use std::time::Duration;

/// Publish the simulated machine's axis states for a program.
#[derive(Parser)]
#[command(name = "fiveaxis-simulator", version)]
struct Args {
    #[command(flatten)]
    stream: StreamArgs,
    #[command(flatten)]
    common: CommonArgs,
    /// Servo time constant (each of two lags), ms.
    #[arg(long = "servo-ms", default_value_t = 2.0)]
    servo_ms: f64,
}

fn main() -> anyhow::Result<()> {
    let (args, ros) = fiveaxis_bus::ros_args::parse::<Args>("fiveaxis_simulator");
    init_tracing(&ros);
    if let Err(e) = args.stream.validate(args.common.use_sim_time) {
        eprintln!("error: {e}");
        std::process::exit(EXIT_INPUT);
    }
    anyhow::ensure!(args.servo_ms > 0.0 && args.servo_ms.is_finite(), "--servo-ms must be positive");
    let shutdown = Shutdown::install()?;
    let machine = args.common.machine_or_exit();
    let (moves, gate) = open_program(&args.stream.program, &args.stream.job_options(), &machine, Duration::from_secs_f64(args.stream.check_before_publish_s));
    let mut config = SimConfig::default();
    config.servo.tau = args.servo_ms * 1e-3;
    tracing::info!(program = %args.stream.program, "simulating as the states are published");

    let mut bus = Bus::new("fiveaxis_simulator", &args.common, &ros)?;
    let state_pub = bus.publisher::<AxisState>(topics::SIMULATED_STATE.name, state_qos())?;
    let joint_pub = bus.publisher::<JointState>(topics::SIMULATED_JOINTS.name, state_qos())?;
    bus.wait_for_stream_subscribers(&state_pub, topics::SIMULATED_STATE.name, &args.stream, &shutdown);
    bus.rosout(ros2_client::ros2::LogLevel::Info, &format!("simulating {}", args.stream.program));
    let pacer = args.stream.pacer(args.common.use_sim_time);
    // The planner and servo run on their own thread, a bounded channel ahead of the publisher: the
    // first state goes out once the first look-ahead window is planned, and memory stays the window's.
    let (tx, rx) = std::sync::mpsc::sync_channel::<StateValues>(4096);
    let builder = StateBuilder::new(&machine, AxisState::SOURCE_SIMULATED);
    let (machine, moves) = (&machine, &moves);
    let (reread, passes) = (std::sync::OnceLock::new(), args.stream.pass_count());
    let reread = &reread;
    let (simulated, sent) = std::thread::scope(|scope| {
        let simulator = scope.spawn(move || {
            // The planner and its scout each read the program again, as a stream (pass after pass).
            let (segments, scout) = (moves.passes(machine, passes, reread)?, moves.passes(machine, passes, reread)?);
            Ok::<_, fiveaxis::job::JobError>(simulate_measured_stream(segments, scout, moves.period(), machine, &config, |_, _, st| tx.send(st).is_ok()))
        });
        let states = rx.into_iter().map(|v| builder.message(&v));
        let (sent, _) = publish_states(gate.guard(states, || shutdown.requested()), &state_pub, &joint_pub, None, &pacer, args.stream.subscriber_wait(), &shutdown);
        (simulator.join().expect("simulator thread"), sent)
    });
    let (summary, figures) = match simulated {
        Ok(s) => s,
        Err(e) => {
            eprintln!("error: reading {} again to simulate it: {e}", args.stream.program);
            std::process::exit(EXIT_INPUT);
        }
    };
    fiveaxis_bus::program::finish_passes(&args.stream.program, reread, sent);
    tracing::info!(
        samples = figures.samples,
        duration_s = figures.duration_s,
        planned_ratios = ?summary.planned_ratio,
        checked_ratios = ?figures.worst_ratio,
        "simulated"
    );
    gate.finish(sent > 0, shutdown.requested());
    Ok(())
}
