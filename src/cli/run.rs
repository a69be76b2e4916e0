//! `fiveaxis run`: commander, simulator and monitor in one process (no DDS), faster than real time;
//! optionally recorded (MCAP, rosbag2) and drawn (.rrd).

use crate::args::ProgramArgs;
use crate::exit::{bad_input, Outcome, BAD_INPUT, OK};
use clap::Args;
use fiveaxis::job::{self, JobOptions};
use fiveaxis::path::PathOptions;
use fiveaxis::singularity::AnalysisOptions;

#[derive(Args)]
pub struct RunArgs {
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

pub fn main(a: &RunArgs) -> Outcome {
    // A report-only run streams states between its threads and keeps nothing: freed batches are
    // reused (a recording's writer frees and reallocates its chunks: kept, they would add to its
    // resident memory, 44 MB against 42 MB for the 1 h benchmark program).
    if a.mcap.is_none() && a.rrd.is_none() {
        crate::keep_freed_memory();
    }
    let mut machine = a.src.machine()?;
    // A recording names the five axes of its JointStates.
    if a.mcap.is_some() || a.rrd.is_some() {
        machine = machine.five_axis("a recording (--mcap, --rrd)").map_err(bad_input)?;
    }
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
        // The report shows the simulated stream's monitor regions, not the commanded stream's (the
        // program's analysis is its prediction); a recording holds both streams' statuses.
        report_only: true,
        ..Default::default()
    };
    let out = match fiveaxis::live::inprocess::run(&a.src.program, &machine, &options) {
        Ok(o) => o,
        Err(e @ (job::JobError::Load(_) | job::JobError::Record(_))) => return Err(bad_input(e)),
        Err(e) => return Err(anyhow::Error::from(e).into()),
    };
    if let (Some(path), Some(n)) = (&a.mcap, out.recorded_messages) {
        eprintln!("fiveaxis: recorded {n} messages to {}", path.display());
    }
    if let (Some(rrd), Some(m)) = (&a.rrd, &mcap) {
        let mut args: Vec<std::ffi::OsString> = vec!["replay".into(), m.into(), "--save".into(), rrd.into(), "--machine".into(), a.src.machine.spec.clone().into()];
        args.extend(["--recording-name".into(), out.report.analysis.program.clone().into()]);
        let status = crate::replay::rerun_bridge(&args);
        if let Some(t) = &tmp_mcap {
            let _ = std::fs::remove_file(t);
        }
        match status? {
            0 => {}
            code => return Ok(code),
        }
    }
    if a.json {
        println!("{}", serde_json::to_string_pretty(&out.report)?);
    } else {
        print!("{}", out.report.analysis.to_table());
        print!("{}", out.report.simulated.to_table(&out.report.analysis.secondary_axis));
    }
    if out.has_errors() {
        eprintln!("fiveaxis: {} has {} defect(s); see the diagnostics above", out.report.analysis.program, out.report.analysis.errors);
        return Ok(BAD_INPUT);
    }
    Ok(OK)
}
