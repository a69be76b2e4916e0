//! The command-line options the nodes share: the common ones, a program stream's and the inputs'.

use crate::{program, InputQos, Pacer};
use std::time::Duration;

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
        self.machine.load().and_then(|m| m.five_axis("the node set")).unwrap_or_else(|e| {
            eprintln!("error: loading the machine: {e}");
            std::process::exit(EXIT_INPUT)
        })
    }
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
