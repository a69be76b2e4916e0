//! `fiveaxis replay`: a recording into a Rerun viewer or an .rrd file, by the `fiveaxis-rerun`
//! executable (the Rerun SDK is the slowest dependency to build, so the main CLI leaves drawing to it).

use crate::exit::{Outcome, Stop};
use anyhow::Context;
use clap::Args;

#[derive(Args)]
pub struct ReplayArgs {
    /// `fiveaxis-rerun replay`'s arguments.
    #[arg(trailing_var_arg = true, allow_hyphen_values = true, value_name = "ARGS")]
    args: Vec<String>,
}

pub fn main(a: &ReplayArgs) -> Outcome {
    let mut args: Vec<std::ffi::OsString> = vec!["replay".into()];
    args.extend(a.args.iter().map(Into::into));
    rerun_bridge(&args)
}

/// Run the `fiveaxis-rerun` executable (beside this one, else on the PATH) with `args`; its exit code
/// (a missing executable is a failure: exit 1).
pub fn rerun_bridge(args: &[std::ffi::OsString]) -> Result<u8, Stop> {
    let beside = std::env::current_exe().ok().and_then(|p| p.parent().map(|d| d.join("fiveaxis-rerun"))).filter(|p| p.exists());
    let exe = beside.unwrap_or_else(|| "fiveaxis-rerun".into());
    let status = std::process::Command::new(&exe)
        .args(args)
        .status()
        .with_context(|| format!("running {} (build it with `cargo build -p fiveaxis_rerun`)", exe.display()))?;
    Ok(status.code().map_or(crate::exit::VIOLATED, |c| c.clamp(0, 255) as u8))
}
