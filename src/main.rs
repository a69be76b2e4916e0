//! `fiveaxis`: the command-line front of the library.

use anyhow::Context;
use clap::{Args, Parser, Subcommand};
use fiveaxis::job::{self, JobOptions};
use fiveaxis::machine::{Machine, BUILTIN_NAMES};
use fiveaxis::path::PathOptions;
use fiveaxis::program::{Dialect, ReadOptions};
use fiveaxis::singularity::AnalysisOptions;
use fiveaxis::units::{DEG, RPM};
use std::process::ExitCode;

/// Watch a five-axis machine tool for kinematic singularities (Cripps et al. 2017).
#[derive(Parser)]
#[command(name = "fiveaxis", version)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// NC programs: analyze one.
    #[command(subcommand)]
    Program(ProgramCmd),
    /// Machines: list or show the built-in ones.
    #[command(subcommand)]
    Machine(MachineCmd),
    /// Run commander, simulator and monitor in one process (no DDS), faster than real time.
    Run(RunArgs),
    /// Analyse recordings (MCAP files, rosbag2 bags) offline: the monitor recomputed, regions, threshold
    /// checks for CI. Several recordings are analysed in parallel, one report each and a summary; the
    /// exit code is the worst of theirs.
    Analyze(OfflineArgs),
    /// MCAP recordings: recover a damaged one.
    #[command(subcommand)]
    Mcap(McapCmd),
    /// Roughness profiles: make the synthetic example.
    #[command(subcommand)]
    Roughness(RoughnessCmd),
    /// Remedies for a singular program.
    #[command(subcommand)]
    Avoid(AvoidCmd),
    /// Replay a recording (MCAP) into a Rerun viewer or an .rrd file: runs `fiveaxis-rerun replay`
    /// with these arguments (see `fiveaxis-rerun replay --help`).
    Replay {
        #[arg(trailing_var_arg = true, allow_hyphen_values = true, value_name = "ARGS")]
        args: Vec<String>,
    },
    /// The embedded default: the node set in one process on the paper's two programs and two continuous
    /// paths, on the Hermle.
    Demo {
        /// Print one JSON object per program (one per line).
        #[arg(long)]
        json: bool,
    },
}

#[derive(Subcommand)]
enum ProgramCmd {
    /// Predict the singular behaviour of a program: C speed (eq. 5), closest approach, feed limits, regions.
    Analyze(AnalyzeArgs),
}

/// The program and how to read it (shared by `program analyze` and `run`).
#[derive(Args)]
struct ProgramArgs {
    /// A program file (.I/.H Heidenhain, .ngc RS274, .cl/.csv CL data), builtin:paper-sing,
    /// builtin:paper-nonsing, bundled:SING.I or bundled:NON_SING.I.
    program: String,
    /// Built-in machine name, or a TOML or URDF (.urdf) machine file.
    #[arg(long, default_value = "hermle-c600u")]
    machine: String,
    /// Tool-tip feed for every feed move (and CL data without a feed column), mm/min.
    #[arg(long = "feed", value_name = "MM_PER_MIN")]
    feed_mm_per_min: Option<f64>,
    /// Dialect, instead of guessing from the file name.
    #[arg(long, value_parser = parse_dialect)]
    dialect: Option<Dialect>,
    /// Longest program accepted, hours: a block that would make it run longer (a feed typo such as
    /// F0.01) is an error (exit 2) naming its line and column.
    #[arg(long = "max-program-hours", value_name = "HOURS", default_value_t = fiveaxis::path::MAX_PROGRAM_DURATION_S / 3600.0)]
    max_program_hours: f64,
    #[command(flatten)]
    control: fiveaxis::program::ControlArgs,
    #[command(flatten)]
    listing: ListingArgs,
}

/// How many regions a report lists (shared by `program analyze`, `run` and `analyze`).
#[derive(Args, Clone, Copy)]
struct ListingArgs {
    /// Regions listed in full per list; the rest are counted and folded into one line (JSON:
    /// `unlisted_regions`: count, time inside, worst figures), so an hours-long run's report stays small.
    #[arg(long = "max-listed-regions", value_name = "N", default_value_t = fiveaxis::listing::MAX_LISTED)]
    max_listed_regions: usize,
}

impl ProgramArgs {
    /// Check the feed and load the machine; an error is bad input (exit 2).
    fn machine(&self) -> anyhow::Result<Machine> {
        positive("--feed", self.feed_mm_per_min)?;
        positive("--max-program-hours", Some(self.max_program_hours))?;
        Machine::from_name_or_file(&self.machine).context("loading the machine")
    }

    /// Sampling options at `period` (s).
    fn path_options(&self, period: f64) -> PathOptions {
        PathOptions { period, feed_override_mm_per_min: self.feed_mm_per_min, max_duration_s: self.max_program_hours * 3600.0 }
    }

    fn read_options(&self) -> ReadOptions {
        ReadOptions {
            cl_feed_mm_per_min: self.feed_mm_per_min.unwrap_or(ReadOptions::default().cl_feed_mm_per_min),
            ..self.control.read_options()
        }
    }
}

#[derive(Args)]
struct AnalyzeArgs {
    #[command(flatten)]
    src: ProgramArgs,
    /// Also report regions where the tool axis comes closer than this to the singularity, degrees.
    #[arg(long = "min-distance-deg", value_name = "DEG")]
    min_distance_deg: Option<f64>,
    /// Region threshold for the singular axis speed, rpm (default: the machine's limit).
    #[arg(long = "max-c-speed-rpm", value_name = "RPM")]
    max_c_speed_rpm: Option<f64>,
    /// Sample period, ms.
    #[arg(long = "period-ms", default_value_t = 1.0)]
    period_ms: f64,
    /// Print one JSON object instead of the table.
    #[arg(long)]
    json: bool,
}

#[derive(Args)]
struct RunArgs {
    #[command(flatten)]
    src: ProgramArgs,
    /// Print one JSON object (the keys of `program analyze --json` plus `simulated`).
    #[arg(long)]
    json: bool,
    /// Record every topic of the node set to this rosbag2 bag: a directory (metadata.yaml and
    /// NAME_0.mcap, as `ros2 bag record` writes), or one MCAP file when the name ends in .mcap.
    #[arg(long, visible_alias = "bag", value_name = "BAG")]
    mcap: Option<std::path::PathBuf>,
    /// Also write the run as a Rerun recording (.rrd, the default layout): the MCAP replayed by
    /// `fiveaxis-rerun`, which must sit beside this executable (`cargo build -p fiveaxis_rerun`).
    #[arg(long)]
    rrd: Option<std::path::PathBuf>,
}

#[derive(Args)]
struct OfflineArgs {
    /// The recordings: MCAP files or rosbag2 bag directories (a directory of split files is one bag).
    #[arg(required_unless_present = "all_in")]
    recordings: Vec<std::path::PathBuf>,
    /// Also every recording directly in this directory, each on its own: its `.mcap` files and its
    /// bag directories, in name order.
    #[arg(long = "all-in", value_name = "DIR")]
    all_in: Option<std::path::PathBuf>,
    /// Recordings analysed at once (default: one per core).
    #[arg(long, value_name = "N")]
    jobs: Option<usize>,
    /// Built-in machine name, or a TOML or URDF (.urdf) machine file.
    #[arg(long, default_value = "hermle-c600u")]
    machine: String,
    /// Fail (exit 1) when the predicted C speed exceeds this, rpm.
    #[arg(long = "max-c-speed-rpm")]
    max_c_speed_rpm: Option<f64>,
    /// Fail (exit 1) when a moving tool axis comes closer than this to the singularity, degrees.
    #[arg(long = "min-distance-deg")]
    min_distance_deg: Option<f64>,
    /// sensor_msgs/JointState topics to analyse (default: all, if the recording has no AxisState).
    #[arg(long = "joint-state-topic")]
    joint_state_topics: Vec<String>,
    /// Joint name for a machine axis in those JointStates: `--axis-map A=joint_a` (repeatable; axis
    /// names case-insensitive; an axis the machine lacks is refused).
    #[arg(long = "axis-map", value_name = "AXIS=JOINT", value_parser = fiveaxis::machine::parse_axis_map)]
    axis_map: Vec<(String, String)>,
    /// The program the machine ran (a file, bundled:NAME): machine streams are aligned with its moves
    /// for the programmed feed, block numbers and rapids.
    #[arg(long, conflicts_with = "feed_mm_per_min")]
    program: Option<String>,
    /// The control's active work offset (G54-style datum) `X,Y,Z` in mm: a machine stream's tool tip
    /// less it is the program's point (without --program; with one, its datum is used).
    #[arg(long = "work-offset-mm", value_name = "X,Y,Z", value_parser = fiveaxis::machine::parse_work_offset, allow_hyphen_values = true, conflicts_with = "program")]
    work_offset: Option<nalgebra::Vector3<f64>>,
    /// The programmed feed of every feed move of a machine stream, mm/min (without --program).
    #[arg(long = "feed", value_name = "MM_PER_MIN")]
    feed_mm_per_min: Option<f64>,
    #[command(flatten)]
    control: fiveaxis::program::ControlArgs,
    /// Refuse a stream (exit 2) with more than this share of its samples rejected, percent.
    #[arg(long = "max-rejected-percent", default_value_t = 100.0 * fiveaxis::analysis::MAX_REJECTED_SHARE)]
    max_rejected_percent: f64,
    /// Write the report as JSON here.
    #[arg(long)]
    json: Option<std::path::PathBuf>,
    /// Write a JUnit XML report here.
    #[arg(long)]
    junit: Option<std::path::PathBuf>,
    #[command(flatten)]
    roughness: fiveaxis::roughness::RoughnessArgs,
    #[command(flatten)]
    listing: ListingArgs,
}

#[derive(Subcommand)]
enum AvoidCmd {
    /// Reorient the workpiece on a jig (seed 001 §3, eq. 7): search the jig angles that minimise the peak
    /// predicted C speed within the tilt bound; the tool path relative to the workpiece is unchanged.
    Reorient {
        /// A program, or builtin:NAME (taken as CL data every 0.1 mm).
        program: String,
        /// Built-in machine name, or a TOML or URDF (.urdf) machine file.
        #[arg(long, default_value = "hermle-c600u")]
        machine: String,
        /// Largest jig tilt allowed, degrees.
        #[arg(long = "max-tilt-deg", default_value_t = 10.0)]
        max_tilt_deg: f64,
        /// Write the reoriented program here (RS274NGC stays RS274NGC; every other input, builtins too, is written as Heidenhain DIN/ISO).
        #[arg(long)]
        out: Option<std::path::PathBuf>,
        /// Print one JSON object with `before`, `after`, `theta_x_deg`, `theta_z_deg`.
        #[arg(long)]
        json: bool,
    },
    /// Smooth the C axis through the singularity (seed 002): the tool axis passes the singular point,
    /// C and A follow C3 connecting curves within the machine's v/a/j limits at the programmed feed.
    /// Ball-end tools only (the ball centre stays on the path).
    Smooth {
        /// A program, or builtin:NAME (taken as CL data every 0.1 mm).
        program: String,
        /// Built-in machine name, or a TOML or URDF (.urdf) machine file.
        #[arg(long, default_value = "hermle-c600u")]
        machine: String,
        /// The cutter: ball:R_MM (required: flat:R_MM and bull:R_MM:r_MM are refused).
        #[arg(long)]
        tool: fiveaxis::avoid::smooth::Tool,
        /// Write the smoothed program here (RS274NGC stays RS274NGC; every other input, builtins too, is written as Heidenhain DIN/ISO).
        #[arg(long)]
        out: Option<std::path::PathBuf>,
        /// Print one JSON object with `before`, `after` and `passages`.
        #[arg(long)]
        json: bool,
    },
    /// Refine CL data near the singularity (seed 003 §5): densify where the tool-axis angle, the step
    /// or a rotary-axis change between neighbours exceeds a threshold, on the IK branch that avoids
    /// 180 deg C flips; reports the overcut the original discretisation causes.
    Refine {
        /// CL data (or a TCPM program read as CL), builtin:NAME or builtin:semi-cylinder.
        program: String,
        /// Built-in machine name, or a TOML or URDF (.urdf) machine file.
        #[arg(long, default_value = "hermle-c600u")]
        machine: String,
        /// Largest tool-axis angle between neighbours, degrees.
        #[arg(long = "max-angle-deg", default_value_t = 1.0)]
        max_angle_deg: f64,
        /// Largest tool-tip step, mm.
        #[arg(long = "max-step-mm", default_value_t = 1.0)]
        max_step_mm: f64,
        /// Largest rotary-axis change between neighbours, degrees.
        #[arg(long = "max-axis-step-deg", default_value_t = 2.0)]
        max_axis_step_deg: f64,
        /// Write the refined program here (RS274NGC stays RS274NGC; every other input is written as Heidenhain DIN/ISO).
        #[arg(long)]
        out: Option<std::path::PathBuf>,
        /// Print one JSON object with `before`, `after` and the chord errors.
        #[arg(long)]
        json: bool,
    },
}

#[derive(Subcommand)]
enum RoughnessCmd {
    /// Write the SYNTHETIC example profile for a program: its simulated feed along the cut drives a
    /// documented, seeded model (see src/roughness/synthetic.rs). Not a measurement.
    Synthesize {
        /// The program whose simulated cut drives the model.
        #[arg(long, default_value = "bundled:SING.I")]
        program: String,
        /// Output file: .csv (x_mm,height_um) or .x3p.
        #[arg(long)]
        out: std::path::PathBuf,
        /// Seed of the model's noise.
        #[arg(long, default_value_t = 2017)]
        seed: u64,
    },
}

#[derive(Subcommand)]
enum McapCmd {
    /// Rebuild a valid MCAP from a damaged or truncated one, keeping every complete chunk; a rosbag2
    /// directory (with or without its metadata.yaml) is recovered file by file into the directory OUTPUT.
    Recover { input: std::path::PathBuf, output: std::path::PathBuf },
}

#[derive(Subcommand)]
enum MachineCmd {
    /// List the built-in machines.
    List,
    /// Print a built-in machine's TOML description (a template for your own), or check a machine
    /// file and print it (a URDF as the TOML it amounts to); an unknown name or an invalid file exits 2
    /// naming the field.
    Show { name: String },
    /// Write a machine (built-in name, TOML or URDF file) as URDF, for `robot_description`: joints named
    /// after the axes as our JointStates name them, link `workpiece` (program frame) and `tool`.
    Urdf {
        name: String,
        /// Write here instead of to standard output.
        #[arg(long, short)]
        out: Option<std::path::PathBuf>,
    },
}

fn parse_dialect(s: &str) -> Result<Dialect, String> {
    match s.to_ascii_lowercase().as_str() {
        "heidenhain" | "din" | "iso" => Ok(Dialect::Heidenhain),
        "rs274" | "ngc" | "gcode" | "linuxcnc" => Ok(Dialect::Rs274),
        "cl" => Ok(Dialect::Cl),
        "sinumerik" | "840d" | "siemens" => Ok(Dialect::Sinumerik),
        "klartext" | "conversational" => Ok(Dialect::Klartext),
        _ => Err(format!("unknown dialect '{s}': expected heidenhain, rs274, cl, sinumerik or klartext")),
    }
}

/// Exit codes: 0 success, 1 failure of the tool itself, 2 bad input (usage, an unreadable file or
/// machine, or a program with defects).
const EXIT_INPUT: u8 = 2;
/// Exit code when a tool the command needs failed.
const EXIT_FAILURE: u8 = 1;

fn positive(name: &str, v: Option<f64>) -> anyhow::Result<()> {
    match v {
        Some(x) if !(x.is_finite() && x > 0.0) => anyhow::bail!("{name} must be a positive number, got {x}"),
        _ => Ok(()),
    }
}

fn analyze(a: &AnalyzeArgs) -> anyhow::Result<ExitCode> {
    let checked = positive("--min-distance-deg", a.min_distance_deg)
        .and(positive("--max-c-speed-rpm", a.max_c_speed_rpm))
        .and(positive("--period-ms", Some(a.period_ms)))
        .and_then(|_| a.src.machine());
    let machine = match checked {
        Ok(m) => m,
        Err(e) => {
            eprintln!("fiveaxis: {e:#}");
            return Ok(ExitCode::from(EXIT_INPUT));
        }
    };
    let options = JobOptions {
        dialect: a.src.dialect,
        path: a.src.path_options(a.period_ms * 1e-3),
        analysis: AnalysisOptions {
            min_distance: a.min_distance_deg.map(|d| d * DEG),
            rate_limit: a.max_c_speed_rpm.map(|r| r * RPM),
            max_listed_regions: Some(a.src.listing.max_listed_regions),
        },
        read: a.src.read_options(),
    };
    // Read, planned and analysed as a stream: an hours-long program in flat memory.
    let report = match job::analyze_streaming(&a.src.program, &machine, &options) {
        Ok(r) => r,
        Err(e @ job::JobError::Load(_)) => {
            eprintln!("fiveaxis: {e}");
            return Ok(ExitCode::from(EXIT_INPUT));
        }
        Err(e) => return Err(e.into()),
    };
    if a.json {
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        print!("{}", report.to_table());
    }
    if report.errors > 0 {
        eprintln!("fiveaxis: {} has {} defect(s); see the diagnostics above", a.src.program, report.errors);
        return Ok(ExitCode::from(EXIT_INPUT));
    }
    Ok(ExitCode::SUCCESS)
}

fn run(a: &RunArgs) -> anyhow::Result<ExitCode> {
    let machine = match a.src.machine() {
        Ok(m) => m,
        Err(e) => {
            eprintln!("fiveaxis: {e:#}");
            return Ok(ExitCode::from(EXIT_INPUT));
        }
    };
    // An .rrd is made from the recording: record to a temporary MCAP when none was asked for.
    let tmp_mcap = (a.rrd.is_some() && a.mcap.is_none()).then(|| std::env::temp_dir().join(format!("fiveaxis-run-{}.mcap", std::process::id())));
    let mcap = a.mcap.clone().or_else(|| tmp_mcap.clone());
    let listed = a.src.listing.max_listed_regions;
    let options = fiveaxis::live::inprocess::RunOptions {
        mcap: mcap.clone(),
        job: JobOptions {
            dialect: a.src.dialect,
            path: a.src.path_options(PathOptions::default().period),
            read: a.src.read_options(),
            analysis: AnalysisOptions { max_listed_regions: Some(listed), ..Default::default() },
        },
        sim: fiveaxis::live::simulator::SimConfig { max_listed_regions: Some(listed), ..Default::default() },
        monitor: fiveaxis::live::monitor::MonitorConfig { max_listed_regions: listed, ..Default::default() },
        ..Default::default()
    };
    let out = match fiveaxis::live::inprocess::run(&a.src.program, &machine, &options) {
        Ok(o) => o,
        Err(e @ (job::JobError::Load(_) | job::JobError::Record(_))) => {
            eprintln!("fiveaxis: {e}");
            return Ok(ExitCode::from(EXIT_INPUT));
        }
        Err(e) => return Err(e.into()),
    };
    if let (Some(path), Some(n)) = (&a.mcap, out.recorded_messages) {
        eprintln!("fiveaxis: recorded {n} messages to {}", path.display());
    }
    if let (Some(rrd), Some(m)) = (&a.rrd, &mcap) {
        let mut args: Vec<std::ffi::OsString> = vec!["replay".into(), m.into(), "--save".into(), rrd.into(), "--machine".into(), a.src.machine.clone().into()];
        args.extend(["--recording-name".into(), a.src.program.clone().into()]);
        let status = rerun_bridge(&args);
        if let Some(t) = &tmp_mcap {
            let _ = std::fs::remove_file(t);
        }
        match status {
            Ok(0) => {}
            Ok(code) => return Ok(ExitCode::from(code)),
            Err(e) => {
                eprintln!("fiveaxis: {e:#}");
                return Ok(ExitCode::from(EXIT_FAILURE));
            }
        }
    }
    if a.json {
        println!("{}", serde_json::to_string_pretty(&out.report)?);
    } else {
        print!("{}", out.report.analysis.to_table());
        print!("{}", out.report.simulated.to_table(&out.report.analysis.secondary_axis));
    }
    if out.has_errors() {
        eprintln!("fiveaxis: {} has {} defect(s); see the diagnostics above", a.src.program, out.report.analysis.errors);
        return Ok(ExitCode::from(EXIT_INPUT));
    }
    Ok(ExitCode::SUCCESS)
}

fn offline(a: &OfflineArgs) -> anyhow::Result<ExitCode> {
    let machine = match Machine::from_name_or_file(&a.machine) {
        Ok(m) => m,
        Err(e) => {
            eprintln!("fiveaxis: {e}");
            return Ok(ExitCode::from(EXIT_INPUT));
        }
    };
    let axis_map = match machine.resolve_axis_map(&a.axis_map) {
        Ok(m) => m,
        Err(e) => {
            eprintln!("fiveaxis: {e}");
            return Ok(ExitCode::from(EXIT_INPUT));
        }
    };
    let feed_source = match job::feed_source(a.program.as_deref(), a.feed_mm_per_min, &machine, &a.control.read_options()) {
        Ok(f) => f,
        Err(e) => {
            eprintln!("fiveaxis: {e}");
            return Ok(ExitCode::from(EXIT_INPUT));
        }
    };
    if !(a.max_rejected_percent >= 0.0 && a.max_rejected_percent <= 100.0) {
        eprintln!("fiveaxis: --max-rejected-percent {} is not a percentage", a.max_rejected_percent);
        return Ok(ExitCode::from(EXIT_INPUT));
    }
    let roughness = match a.roughness.load() {
        Ok(r) => r,
        Err(e) => {
            eprintln!("fiveaxis: {e}");
            return Ok(ExitCode::from(EXIT_INPUT));
        }
    };
    let options = fiveaxis::analysis::OfflineOptions {
        roughness,
        max_c_speed_rpm: a.max_c_speed_rpm,
        min_distance_deg: a.min_distance_deg,
        joint_state_topics: a.joint_state_topics.clone(),
        axis_map,
        feed_source,
        max_rejected_share: a.max_rejected_percent / 100.0,
        monitor: fiveaxis::live::monitor::MonitorConfig { work_offset: a.work_offset.unwrap_or_default(), max_listed_regions: a.listing.max_listed_regions, ..Default::default() },
        ..Default::default()
    };
    let recordings = match recordings_of(a) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("fiveaxis: {e}");
            return Ok(ExitCode::from(EXIT_INPUT));
        }
    };
    if let [one] = recordings.as_slice() {
        return offline_one(a, one, &machine, &options);
    }
    offline_many(a, &recordings, &machine, &options)
}

/// The recordings an `analyze` names: those given, then those in `--all-in` (MCAP files and bag
/// directories, by name); none is an error.
fn recordings_of(a: &OfflineArgs) -> Result<Vec<std::path::PathBuf>, String> {
    let mut all = a.recordings.clone();
    if let Some(dir) = &a.all_in {
        let entries = std::fs::read_dir(dir).map_err(|e| format!("--all-in {}: {e}", dir.display()))?;
        let mut found: Vec<std::path::PathBuf> = entries
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| if p.is_dir() { fiveaxis::record::read::recording_files(p).is_ok() } else { p.extension().is_some_and(|e| e.eq_ignore_ascii_case("mcap")) })
            .collect();
        if found.is_empty() {
            return Err(format!("--all-in {}: no .mcap file or bag directory in it", dir.display()));
        }
        found.sort();
        all.extend(found);
    }
    Ok(all)
}

/// Exit code of one recording's report: 2 if its input cannot be trusted or is damaged, 1 if a
/// threshold is violated, else 0.
fn offline_code(report: &fiveaxis::analysis::OfflineReport) -> u8 {
    if !report.input_errors.is_empty() || report.damage.is_some() {
        EXIT_INPUT
    } else if !report.violations.is_empty() {
        1
    } else {
        0
    }
}

/// `fiveaxis analyze` on one recording: a progress bar on long files, the table, JSON and JUnit.
fn offline_one(a: &OfflineArgs, recording: &std::path::Path, machine: &Machine, options: &fiveaxis::analysis::OfflineOptions) -> anyhow::Result<ExitCode> {
    // A progress bar on long files, on stderr; indicatif hides it when stderr is not a terminal.
    let bar = indicatif::ProgressBar::with_draw_target(None, indicatif::ProgressDrawTarget::stderr());
    bar.set_style(
        indicatif::ProgressStyle::with_template("{msg} [{bar:40}] {bytes}/{total_bytes} ({eta})")
            .expect("a valid template")
            .progress_chars("=> "),
    );
    bar.set_message("analysing");
    let mut progress = |done: u64, total: u64| {
        if total >= 32 << 20 {
            bar.set_length(total);
            bar.set_position(done);
        }
    };
    let result = fiveaxis::analysis::analyze_mcap_with_progress(recording, machine, options, &mut progress);
    bar.finish_and_clear();
    let report = match result {
        Ok(r) => r,
        Err(e) => {
            eprintln!("fiveaxis: cannot analyse {}: {e}", recording.display());
            return Ok(ExitCode::from(EXIT_INPUT));
        }
    };
    print!("{}", report.to_table());
    if let Some(p) = &a.json {
        std::fs::write(p, serde_json::to_string_pretty(&report)?).with_context(|| format!("writing {}", p.display()))?;
    }
    if let Some(p) = &a.junit {
        std::fs::write(p, report.to_junit().context("writing JUnit XML")?).with_context(|| format!("writing {}", p.display()))?;
    }
    report_problems(recording, &report);
    Ok(ExitCode::from(offline_code(&report)))
}

/// Say on stderr why a recording's report is not clean (input errors, damage).
fn report_problems(recording: &std::path::Path, report: &fiveaxis::analysis::OfflineReport) {
    for e in &report.input_errors {
        eprintln!("fiveaxis: {}: {e}", recording.display());
    }
    if let Some(d) = &report.damage {
        // The report covers what was readable; the input itself is damaged: exit 2.
        eprintln!(
            "fiveaxis: {} is damaged ({d}); the report covers the {} messages before it (`fiveaxis mcap recover` rebuilds a sound file)",
            recording.display(),
            report.messages_read
        );
    }
}

/// One recording's line in the summary of a multi-recording `analyze`.
#[derive(serde::Serialize)]
struct RecordingSummary {
    file: String,
    exit_code: u8,
    messages_read: u64,
    regions: usize,
    violations: usize,
    /// Why it could not be analysed at all, if so.
    error: Option<String>,
}

/// `fiveaxis analyze` on several recordings, `--jobs` at a time (each on its own core): the reports in
/// the order given, a summary, JSON `{"recordings": [...], "summary": [...]}`, JUnit `<testsuites>`.
fn offline_many(a: &OfflineArgs, recordings: &[std::path::PathBuf], machine: &Machine, options: &fiveaxis::analysis::OfflineOptions) -> anyhow::Result<ExitCode> {
    use std::sync::atomic::{AtomicUsize, Ordering};
    let jobs = a.jobs.unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get())).clamp(1, recordings.len());
    let next = AtomicUsize::new(0);
    let results: Vec<std::sync::Mutex<Option<Result<fiveaxis::analysis::OfflineReport, String>>>> = recordings.iter().map(|_| std::sync::Mutex::new(None)).collect();
    std::thread::scope(|scope| {
        for _ in 0..jobs {
            scope.spawn(|| loop {
                let k = next.fetch_add(1, Ordering::Relaxed);
                let Some(path) = recordings.get(k) else { break };
                let r = fiveaxis::analysis::analyze_mcap(path, machine, options).map_err(|e| e.to_string());
                *results[k].lock().unwrap_or_else(|p| p.into_inner()) = Some(r);
            });
        }
    });
    let mut summary = Vec::new();
    let mut reports = Vec::new();
    let mut worst = 0u8;
    for (path, slot) in recordings.iter().zip(results) {
        let r = slot.into_inner().unwrap_or_else(|p| p.into_inner()).unwrap_or_else(|| Err("not analysed".into()));
        let file = path.display().to_string();
        let line = match r {
            Ok(report) => {
                print!("{}", report.to_table());
                println!();
                report_problems(path, &report);
                let code = offline_code(&report);
                let line = RecordingSummary { file, exit_code: code, messages_read: report.messages_read, regions: report.regions.len() + report.unlisted_regions.count, violations: report.violations.len(), error: None };
                reports.push(report);
                line
            }
            Err(e) => {
                eprintln!("fiveaxis: cannot analyse {file}: {e}");
                RecordingSummary { file, exit_code: EXIT_INPUT, messages_read: 0, regions: 0, violations: 0, error: Some(e) }
            }
        };
        worst = worst.max(line.exit_code);
        summary.push(line);
    }
    println!("summary of {} recordings ({jobs} at a time)", summary.len());
    println!("  exit  messages  regions  violations  recording");
    for s in &summary {
        println!("  {:>4}  {:>8}  {:>7}  {:>10}  {}{}", s.exit_code, s.messages_read, s.regions, s.violations, s.file, s.error.as_ref().map_or(String::new(), |e| format!(" (cannot analyse: {e})")));
    }
    if let Some(p) = &a.json {
        let all = serde_json::json!({ "recordings": reports, "summary": summary });
        std::fs::write(p, serde_json::to_string_pretty(&all)?).with_context(|| format!("writing {}", p.display()))?;
    }
    if let Some(p) = &a.junit {
        let unreadable: Vec<(&str, &str)> = summary.iter().filter_map(|s| s.error.as_deref().map(|e| (s.file.as_str(), e))).collect();
        std::fs::write(p, fiveaxis::analysis::junit_testsuites(&reports, &unreadable).context("writing JUnit XML")?).with_context(|| format!("writing {}", p.display()))?;
    }
    Ok(ExitCode::from(worst))
}

fn synthesize(program: &str, out: &std::path::Path, seed: u64) -> anyhow::Result<ExitCode> {
    let machine = Machine::hermle_c600u();
    let options = fiveaxis::live::inprocess::RunOptions { keep_simulation: true, ..Default::default() };
    let run = fiveaxis::live::inprocess::run(program, &machine, &options)?;
    let simulation = run.simulation.as_ref().context("the run kept its simulation")?;
    let traj = &run.job.as_ref().context("the run kept its job")?.trajectory;
    let states = simulation.states(traj, &machine);
    // The simulated feed along the simultaneous five-axis cut.
    let mut cut: Vec<(f64, f64, f64)> = states
        .iter()
        .zip(&simulation.segment)
        .filter(|(_, &seg)| traj.segments[seg].is_five_axis())
        .map(|(s, _)| (s.tool_tip.x, s.path_feed, s.programmed_feed))
        .collect();
    anyhow::ensure!(cut.len() > 10, "{program} has no simultaneous five-axis cut to model");
    cut.sort_by(|a, b| a.0.total_cmp(&b.0));
    let feed = |x: f64| {
        let k = cut.partition_point(|c| c.0 < x).min(cut.len() - 1);
        (cut[k].1, cut[k].2)
    };
    let model = fiveaxis::roughness::synthetic::SyntheticModel { seed, ..Default::default() };
    let profile = fiveaxis::roughness::synthetic::profile(cut[0].0, cut[cut.len() - 1].0, &feed, &model);
    let note = format!(
        "SYNTHETIC roughness profile, not a measurement: fiveaxis model (src/roughness/synthetic.rs), seed {seed},\n\
         driven by the simulated feed of {program} on the {}; x is the workpiece x.",
        machine.name
    );
    let r = if out.extension().is_some_and(|e| e.eq_ignore_ascii_case("x3p")) {
        fiveaxis::roughness::write_x3p(&profile, out, &note)
    } else {
        fiveaxis::roughness::write_csv(&profile, out, &note)
    };
    r.map_err(anyhow::Error::from)?;
    println!("wrote {} ({} points, SYNTHETIC)", out.display(), profile.z.len());
    Ok(ExitCode::SUCCESS)
}

/// The machine and program of an `avoid` command (files, bundled:, builtin: paths as CL every 0.1 mm,
/// builtin:semi-cylinder); refuses programs with defects. Errors are printed; the exit code returned.
fn avoid_input(program: &str, machine: &str, what: &str, options: &JobOptions) -> Result<(Machine, fiveaxis::program::Program), ExitCode> {
    let machine = Machine::from_name_or_file(machine).map_err(|e| {
        eprintln!("fiveaxis: {e}");
        ExitCode::from(EXIT_INPUT)
    })?;
    let prog = if program == "builtin:semi-cylinder" {
        fiveaxis::avoid::refine::semi_cylinder()
    } else if let Some(name) = program.strip_prefix("builtin:") {
        match fiveaxis::path::BuiltinPath::by_name(name) {
            Some(p) => p.cl_program(0.1),
            None => {
                eprintln!("fiveaxis: unknown built-in path '{name}' (also builtin:semi-cylinder)");
                return Err(ExitCode::from(EXIT_INPUT));
            }
        }
    } else {
        job::read_spec(program, options).map_err(|e| {
            eprintln!("fiveaxis: {e}");
            ExitCode::from(EXIT_INPUT)
        })?
    };
    if prog.has_errors() {
        for d in prog.report() {
            eprintln!("{d}");
        }
        eprintln!("fiveaxis: {program} has defects: refusing to {what} it");
        return Err(ExitCode::from(EXIT_INPUT));
    }
    Ok((machine, prog))
}

/// The before/after table every remedy prints.
fn remedy_table(before: &fiveaxis::avoid::Figures, after: &fiveaxis::avoid::Figures) {
    println!("{:<34} {:>12} {:>12}", "", "before", "after");
    println!("{:<34} {:>12.1} {:>12.1}", "peak C speed (eq. 5), rpm", before.peak_c_speed_rpm, after.peak_c_speed_rpm);
    println!("{:<34} {:>12.3} {:>12.3}", "closest approach, deg", before.min_singularity_distance_deg, after.min_singularity_distance_deg);
    println!("{:<34} {:>12.2} {:>12.2}", "simulated cycle time, s", before.cycle_time_s, after.cycle_time_s);
    println!("{:<34} {:>12.2} {:>12.2}", "time lost against F, s", before.time_lost_s, after.time_lost_s);
    println!("{:<34} {:>12.0} {:>12.0}", "lowest feed in the cuts, mm/min", before.min_cut_feed_mm_min, after.min_cut_feed_mm_min);
    println!("{:<34} {:>12.3} {:>12.3}", "max orientation change, deg", before.max_orientation_deviation_deg, after.max_orientation_deviation_deg);
}

fn write_out(prog: &fiveaxis::program::Program, new: &fiveaxis::program::Program, machine: &Machine, out: Option<&std::path::Path>, options: &JobOptions) -> anyhow::Result<()> {
    if let Some(path) = out {
        let dialect = if prog.dialect == Dialect::Rs274 { Dialect::Rs274 } else { Dialect::Heidenhain };
        std::fs::write(path, fiveaxis::avoid::write_program(new, machine, dialect, options)).with_context(|| format!("writing {}", path.display()))?;
    }
    Ok(())
}

fn smooth(program: &str, machine: &str, tool: fiveaxis::avoid::smooth::Tool, out: Option<&std::path::Path>, json: bool) -> anyhow::Result<ExitCode> {
    let options = JobOptions::default();
    let (machine, prog) = match avoid_input(program, machine, "smooth", &options) {
        Ok(x) => x,
        Err(code) => return Ok(code),
    };
    let (new, s) = match fiveaxis::avoid::smooth::smooth(&prog, &machine, tool, &options) {
        Ok(x) => x,
        Err(e) => {
            eprintln!("fiveaxis: cannot smooth {program}: {e}");
            return Ok(ExitCode::from(EXIT_INPUT));
        }
    };
    let (before, mut after) = match (fiveaxis::avoid::figures(&prog, &machine, &options), fiveaxis::avoid::figures(&new, &machine, &options)) {
        (Ok(b), Ok(a)) => (b, a),
        (Err(e), _) | (_, Err(e)) => {
            eprintln!("fiveaxis: cannot smooth {program}: {e}");
            return Ok(ExitCode::from(EXIT_INPUT));
        }
    };
    after.max_orientation_deviation_deg = s.max_orientation_deviation_deg;
    write_out(&prog, &new, &machine, out, &options)?;
    if json {
        println!("{}", serde_json::to_string_pretty(&serde_json::json!({ "before": before, "after": after, "passages": s.passages, "max_ball_centre_error_mm": s.max_ball_centre_error_m * 1e3, "valid_for": "ball-end tools only" }))?);
        return Ok(ExitCode::SUCCESS);
    }
    println!("C-axis smoothing of {program} on {} (seed 002)", machine.name);
    println!("valid for ball-end tools only: the ball centre stays on the path, the tool axis changes");
    if s.passages.is_empty() {
        println!("no singular passage: nothing changed");
    }
    for p in &s.passages {
        println!(
            "passage        x {:.3} mm (closest {:.3} deg): window x {:.3} to {:.3} mm ({:.1} mm of path), {} points changed; C at {:.2}/{:.2}/{:.2} of its v/a/j limits; tool axis changed by up to {:.3} deg",
            p.x_singular_mm, p.original_distance_deg, p.x_start_mm, p.x_end_mm, p.window_length_mm, p.points_changed, p.c_limit_ratio[0], p.c_limit_ratio[1], p.c_limit_ratio[2], p.max_orientation_deviation_deg
        );
    }
    println!("ball centre    within {:.4} um of the original", s.max_ball_centre_error_m * 1e6);
    remedy_table(&before, &after);
    if let Some(path) = out {
        println!("wrote {}", path.display());
    }
    Ok(ExitCode::SUCCESS)
}

fn refine(program: &str, machine: &str, opts: &fiveaxis::avoid::refine::RefineOptions, out: Option<&std::path::Path>, json: bool) -> anyhow::Result<ExitCode> {
    let options = JobOptions::default();
    let (machine, prog) = match avoid_input(program, machine, "refine", &options) {
        Ok(x) => x,
        Err(code) => return Ok(code),
    };
    let refined = fiveaxis::avoid::refine::refine(&prog, &machine, opts, &options)
        .and_then(|(new, r)| fiveaxis::avoid::refine::conventional(&prog, &machine, &options).map(|c| (new, r, c)));
    let (new, r, conventional) = match refined {
        Ok(x) => x,
        Err(e) => {
            eprintln!("fiveaxis: cannot refine {program}: {e}");
            return Ok(ExitCode::from(EXIT_INPUT));
        }
    };
    let (before, after) = match (fiveaxis::avoid::figures(&conventional, &machine, &options), fiveaxis::avoid::figures(&new, &machine, &options)) {
        (Ok(b), Ok(a)) => (b, a),
        (Err(e), _) | (_, Err(e)) => {
            eprintln!("fiveaxis: cannot refine {program}: {e}");
            return Ok(ExitCode::from(EXIT_INPUT));
        }
    };
    write_out(&prog, &new, &machine, out, &options)?;
    if json {
        println!("{}", serde_json::to_string_pretty(&serde_json::json!({ "before": before, "after": after, "refinement": r }))?);
        return Ok(ExitCode::SUCCESS);
    }
    println!("CL refinement of {program} on {} (seed 003 §5); before = the conventional post (A >= 0 branch)", machine.name);
    println!("points         {} -> {} (tool tips within {:.4} um of the original CL polyline)", r.points_before, r.points_after, r.max_tip_error_m * 1e6);
    println!("{:<34} {:>12} {:>12}", "", "before", "after");
    println!("{:<34} {:>12.1} {:>12.1}", "largest C step, deg", r.before.max_c_step_deg, r.after.max_c_step_deg);
    println!("{:<34} {:>12} {:>12}", "180 deg C flips", r.before.c_flips, r.after.c_flips);
    println!("{:<34} {:>12.4} {:>12.4}", "overcut without TCPM, mm", r.before.overcut_mm, r.after.overcut_mm);
    println!("{:<34} {:>12.4} {:>12.4}", "undercut without TCPM, mm", r.before.undercut_mm, r.after.undercut_mm);
    println!("{:<34} {:>12.4} {:>12.4}", "tip off the chord without TCPM, mm", r.before.max_deviation_mm, r.after.max_deviation_mm);
    remedy_table(&before, &after);
    if let Some(path) = out {
        println!("wrote {}", path.display());
    }
    Ok(ExitCode::SUCCESS)
}

fn reorient(program: &str, machine: &str, max_tilt_deg: f64, out: Option<&std::path::Path>, json: bool) -> anyhow::Result<ExitCode> {
    if !(max_tilt_deg.is_finite() && max_tilt_deg > 0.0 && max_tilt_deg <= 90.0) {
        eprintln!("fiveaxis: --max-tilt-deg must be in (0, 90], got {max_tilt_deg}");
        return Ok(ExitCode::from(EXIT_INPUT));
    }
    let options = JobOptions::default();
    let (machine, prog) = match avoid_input(program, machine, "reorient", &options) {
        Ok(x) => x,
        Err(code) => return Ok(code),
    };
    let (r, new) = match fiveaxis::avoid::search(&prog, &machine, max_tilt_deg * DEG, &options) {
        Ok(x) => x,
        Err(e) => {
            eprintln!("fiveaxis: cannot reorient {program}: {e}");
            return Ok(ExitCode::from(EXIT_INPUT));
        }
    };
    write_out(&prog, &new, &machine, out, &options)?;
    if json {
        println!("{}", serde_json::to_string_pretty(&r)?);
    } else {
        println!("reorientation of {program} on {} (jig tilt within {max_tilt_deg} deg)", machine.name);
        println!("jig angles     theta_x {:.2} deg, theta_z {:.2} deg (seed 001 eq. 7)", r.theta_x_deg, r.theta_z_deg);
        remedy_table(&r.before, &r.after);
        if let Some(path) = out {
            println!("wrote {}", path.display());
        }
    }
    Ok(ExitCode::SUCCESS)
}

/// Run the `fiveaxis-rerun` executable (beside this one, else on the PATH) with `args`; its exit code.
/// The Rerun SDK is the slowest dependency to build, so the main CLI leaves drawing to that crate.
fn rerun_bridge(args: &[std::ffi::OsString]) -> anyhow::Result<u8> {
    let beside = std::env::current_exe().ok().and_then(|p| p.parent().map(|d| d.join("fiveaxis-rerun"))).filter(|p| p.exists());
    let exe = beside.unwrap_or_else(|| "fiveaxis-rerun".into());
    let status = std::process::Command::new(&exe)
        .args(args)
        .status()
        .with_context(|| format!("running {} (build it with `cargo build -p fiveaxis_rerun`)", exe.display()))?;
    Ok(status.code().map_or(EXIT_FAILURE, |c| c.clamp(0, 255) as u8))
}

fn recover(input: &std::path::Path, output: &std::path::Path) -> anyhow::Result<ExitCode> {
    match fiveaxis::record::recover_recording(input, output) {
        Ok(files) => {
            for (out, r) in &files {
                println!("recovered {} messages on {} channels ({} bytes read) into {}", r.messages, r.channels, r.bytes_total, out.display());
                if let Some(why) = &r.stopped {
                    println!("stopped at the damage: {why}");
                }
            }
            Ok(ExitCode::SUCCESS)
        }
        Err(e) => {
            eprintln!("fiveaxis: {e}");
            Ok(ExitCode::from(EXIT_INPUT))
        }
    }
}

fn demo(json: bool) -> anyhow::Result<ExitCode> {
    let machine = Machine::hermle_c600u();
    if !json {
        println!("fiveaxis demo: the paper's paths on the {} (C limit 25 rpm), F2000 mm/min", machine.name);
        println!("commander + simulator + monitor in one process, no DDS\n");
        println!("predicted (seed 001 eq. 5, axes linear per block as programmed):");
        println!("{:<24} {:>12} {:>10} {:>14} {:>16}", "program", "peak C rpm", "at x mm", "closest deg", "C > 25 rpm, x mm");
    }
    let specs = ["builtin:paper-sing", "bundled:SING.I", "builtin:paper-nonsing", "bundled:NON_SING.I"];
    let mut runs = Vec::new();
    for spec in specs {
        let out = fiveaxis::live::inprocess::run(spec, &machine, &Default::default())?;
        if json {
            println!("{}", serde_json::to_string(&out.report)?);
            continue;
        }
        let r = &out.report.analysis;
        let regions = if r.regions.is_empty() {
            "none".to_string()
        } else {
            r.regions.iter().map(|g| format!("{:.2}-{:.2}", g.x_start_mm, g.x_end_mm)).collect::<Vec<_>>().join(", ")
        };
        println!(
            "{:<24} {:>12.1} {:>10.2} {:>14.3} {:>16}",
            spec,
            r.peak_c_speed_rpm,
            r.peak_c_speed_x_mm,
            r.min_singularity_distance_deg.unwrap_or(f64::NAN),
            regions
        );
        runs.push((spec, out));
    }
    if !json {
        println!("\nsimulated machine (A/C 150 deg/s, 600 deg/s^2; look-ahead planner, servo):");
        println!("{:<24} {:>10} {:>16} {:>22} {:>12}", "program", "cycle s", "lowest mm/min", "feed < 50 %, x mm", "max a/a_max");
        for (spec, out) in &runs {
            let s = &out.report.simulated;
            let slow: Vec<String> = s.slow_regions.iter().filter(|r| !r.at_stop).map(|r| format!("{:.1}-{:.1}", r.x_start_mm, r.x_end_mm)).collect();
            println!(
                "{:<24} {:>10.2} {:>16.0} {:>22} {:>12.3}",
                spec,
                s.cycle_time_s,
                s.min_feed_mm_per_min,
                if slow.is_empty() { "none".to_string() } else { slow.join(", ") },
                s.max_axis_acceleration_ratio
            );
        }
        println!("\nDetails: fiveaxis run bundled:SING.I   fiveaxis program analyze FILE   (--json for CI)");
    }
    Ok(ExitCode::SUCCESS)
}

/// `machine urdf`: the machine written as URDF, to a file or standard output.
fn machine_urdf(spec: &str, out: Option<&std::path::Path>) -> anyhow::Result<ExitCode> {
    let machine = match Machine::from_name_or_file(spec) {
        Ok(m) => m,
        Err(e) => {
            eprintln!("fiveaxis: {e}");
            return Ok(ExitCode::from(EXIT_INPUT));
        }
    };
    let text = fiveaxis::machine::urdf::write(&machine);
    match out {
        Some(path) => std::fs::write(path, text).with_context(|| format!("writing {}", path.display()))?,
        None => print!("{text}"),
    }
    Ok(ExitCode::SUCCESS)
}

/// `machine show`: a built-in machine's file, or a machine file checked whole.
fn machine_show(spec: &str) -> anyhow::Result<ExitCode> {
    let checked = if fiveaxis::machine::urdf::is_urdf_path(spec) {
        // The TOML the URDF amounts to, once the machine it describes is valid.
        fiveaxis::machine::read_machine_file(spec).and_then(|text| {
            let (_, file) = fiveaxis::machine::urdf::read_with_file(&text, spec)?;
            let toml = toml::to_string(&file).map_err(|e| fiveaxis::machine::MachineError::Parse { path: spec.to_string(), message: e.to_string() })?;
            Ok(format!("# {spec} as a fiveaxis machine file (mm, deg)\n{toml}").into())
        })
    } else {
        fiveaxis::machine::description_text(spec).and_then(|text| Machine::from_toml_str(&text, spec).map(|_| text))
    };
    match checked {
        Ok(text) => {
            print!("{text}");
            Ok(ExitCode::SUCCESS)
        }
        Err(e) => {
            eprintln!("fiveaxis: {e}");
            Ok(ExitCode::from(EXIT_INPUT))
        }
    }
}

fn main() -> ExitCode {
    // A closed stdout (`fiveaxis ... | head`) ends the process as it ends other Unix tools, by
    // SIGPIPE, instead of a panic in println! (Rust ignores SIGPIPE by default).
    #[cfg(unix)]
    // SAFETY: called first in main, before any thread exists; SIG_DFL is a valid action for SIGPIPE.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
    let cli = Cli::parse();
    let result = match &cli.command {
        Command::Program(ProgramCmd::Analyze(a)) => analyze(a),
        Command::Machine(MachineCmd::List) => {
            let w = BUILTIN_NAMES.iter().map(|n| n.len()).max().unwrap_or(0);
            for n in BUILTIN_NAMES {
                match Machine::builtin(n) {
                    Ok(m) => println!("{n:<w$}  {}", m.description),
                    Err(e) => println!("{n:<w$}  ({e})"),
                }
            }
            Ok(ExitCode::SUCCESS)
        }
        Command::Machine(MachineCmd::Show { name }) => machine_show(name),
        Command::Machine(MachineCmd::Urdf { name, out }) => machine_urdf(name, out.as_deref()),
        Command::Run(a) => run(a),
        Command::Analyze(a) => offline(a),
        Command::Mcap(McapCmd::Recover { input, output }) => recover(input, output),
        Command::Roughness(RoughnessCmd::Synthesize { program, out, seed }) => synthesize(program, out, *seed),
        Command::Avoid(AvoidCmd::Reorient { program, machine, max_tilt_deg, out, json }) => reorient(program, machine, *max_tilt_deg, out.as_deref(), *json),
        Command::Avoid(AvoidCmd::Smooth { program, machine, tool, out, json }) => smooth(program, machine, *tool, out.as_deref(), *json),
        Command::Avoid(AvoidCmd::Refine { program, machine, max_angle_deg, max_step_mm, max_axis_step_deg, out, json }) => {
            let opts = fiveaxis::avoid::refine::RefineOptions { max_step: max_step_mm * 1e-3, max_angle: max_angle_deg * DEG, max_axis_step: max_axis_step_deg * DEG };
            refine(program, machine, &opts, out.as_deref(), *json)
        }
        Command::Replay { args } => {
            let mut a: Vec<std::ffi::OsString> = vec!["replay".into()];
            a.extend(args.iter().map(Into::into));
            match rerun_bridge(&a) {
                Ok(code) => Ok(ExitCode::from(code)),
                Err(e) => {
                    eprintln!("fiveaxis: {e:#}");
                    Ok(ExitCode::from(EXIT_FAILURE))
                }
            }
        }
        Command::Demo { json } => demo(*json),
    };
    match result {
        Ok(code) => code,
        Err(e) => {
            eprintln!("fiveaxis: {e:#}");
            ExitCode::FAILURE
        }
    }
}
