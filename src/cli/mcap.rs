//! `fiveaxis mcap recover`: a valid MCAP rebuilt from a damaged or truncated one.

use crate::exit::{bad_input, Outcome, OK};
use clap::Subcommand;

#[derive(Subcommand)]
pub enum McapCmd {
    /// Rebuild a valid MCAP from a damaged or truncated one, keeping every complete chunk; a rosbag2
    /// directory (with or without its metadata.yaml) is recovered file by file into the directory OUTPUT.
    #[command(after_help = crate::exit::HELP)]
    Recover { input: std::path::PathBuf, output: std::path::PathBuf },
}

pub fn main(c: &McapCmd) -> Outcome {
    let McapCmd::Recover { input, output } = c;
    let files = fiveaxis::record::recover_recording(input, output).map_err(bad_input)?;
    for (out, r) in &files {
        println!("recovered {} messages on {} channels ({} bytes read) into {}", r.messages, r.channels, r.bytes_total, out.display());
        if let Some(why) = &r.stopped {
            println!("stopped at the damage: {why}");
        }
    }
    Ok(OK)
}
