//! `fiveaxis program analyze`: predict a program's singular behaviour (seed 001 eq. 5 C speed,
//! closest approach, seed 002 feed limits, regions), read and analysed as a stream.

use crate::args::{positive, ProgramArgs};
use crate::exit::{bad_input, Outcome, BAD_INPUT, OK};
use clap::{Args, Subcommand};
use fiveaxis::job::{self, JobOptions};
use fiveaxis::singularity::AnalysisOptions;
use fiveaxis::units::{DEG, RPM};

#[derive(Subcommand)]
pub enum ProgramCmd {
    /// Predict the singular behaviour of a program: C speed (eq. 5), closest approach, feed limits, regions.
    #[command(after_help = crate::exit::HELP)]
    Analyze(AnalyzeArgs),
}

#[derive(Args)]
pub struct AnalyzeArgs {
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

pub fn main(c: &ProgramCmd) -> Outcome {
    match c {
        ProgramCmd::Analyze(a) => analyze(a),
    }
}

fn analyze(a: &AnalyzeArgs) -> Outcome {
    positive("--min-distance-deg", a.min_distance_deg)?;
    positive("--max-c-speed-rpm", a.max_c_speed_rpm)?;
    positive("--period-ms", Some(a.period_ms))?;
    let machine = a.src.machine()?;
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
        Err(e @ job::JobError::Load(_)) => return Err(bad_input(e)),
        Err(e) => return Err(anyhow::Error::from(e).into()),
    };
    if a.json {
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        print!("{}", report.to_table());
    }
    if report.errors > 0 {
        eprintln!("fiveaxis: {} has {} defect(s); see the diagnostics above", report.program, report.errors);
        return Ok(BAD_INPUT);
    }
    Ok(OK)
}
