//! Argument groups the commands share: the program and how to read it, and number checks.

use crate::exit::{bad_input, Stop};
use anyhow::Context;
use clap::Args;
use fiveaxis::args::{ListingArgs, MachineArgs};
use fiveaxis::machine::Machine;
use fiveaxis::path::PathOptions;
use fiveaxis::program::{ControlArgs, Dialect, ReadOptions};

/// The program and how to read it (shared by `program analyze` and `run`).
#[derive(Args)]
pub struct ProgramArgs {
    /// A program file (.I/.H Heidenhain, .ngc RS274, .cl/.csv CL data; a pipe such as
    /// `<(zcat P.ngc.gz)`, or `-` for standard input, is held in a temporary file),
    /// builtin:paper-sing, builtin:paper-nonsing, bundled:SING.I or bundled:NON_SING.I.
    pub program: String,
    #[command(flatten)]
    pub machine: MachineArgs,
    /// Tool-tip feed for every feed move (and CL data without a feed column), mm/min.
    #[arg(long = "feed", value_name = "MM_PER_MIN")]
    pub feed_mm_per_min: Option<f64>,
    /// Dialect, instead of guessing from the file name.
    #[arg(long, value_parser = |s: &str| s.parse::<Dialect>())]
    pub dialect: Option<Dialect>,
    /// Longest program accepted, hours: a block that would make it run longer (a feed typo such as
    /// F0.01) is an error (exit 2) naming its line and column.
    #[arg(long = "max-program-hours", value_name = "HOURS", default_value_t = fiveaxis::path::MAX_PROGRAM_DURATION_S / 3600.0)]
    pub max_program_hours: f64,
    #[command(flatten)]
    pub control: ControlArgs,
    #[command(flatten)]
    pub listing: ListingArgs,
}

impl ProgramArgs {
    /// Check the feed and load the machine; an error is bad input (exit 2).
    pub fn machine(&self) -> Result<Machine, Stop> {
        positive("--feed", self.feed_mm_per_min)?;
        positive("--max-program-hours", Some(self.max_program_hours))?;
        self.machine.load().context("loading the machine").map_err(bad_input)
    }

    /// Sampling options at `period` (s).
    pub fn path_options(&self, period: f64) -> PathOptions {
        PathOptions { period, feed_override_mm_per_min: self.feed_mm_per_min, max_duration_s: self.max_program_hours * 3600.0 }
    }

    pub fn read_options(&self) -> ReadOptions {
        ReadOptions {
            cl_feed_mm_per_min: self.feed_mm_per_min.unwrap_or(ReadOptions::default().cl_feed_mm_per_min),
            ..self.control.read_options()
        }
    }
}

/// `flag`'s value, if given, must be a positive finite number (else bad input).
pub fn positive(flag: &str, v: Option<f64>) -> Result<(), Stop> {
    match v {
        Some(x) if !(x.is_finite() && x > 0.0) => Err(bad_input(format!("{flag} must be a positive number, got {x}"))),
        _ => Ok(()),
    }
}
