//! `fiveaxis roughness synthesize`: the SYNTHETIC example profile of a program, to CSV or X3P.

use crate::exit::{bad_input, Outcome, OK};
use clap::Subcommand;
use fiveaxis::machine::Machine;

#[derive(Subcommand)]
pub enum RoughnessCmd {
    /// Write the SYNTHETIC example profile for a program: its simulated feed along the cut drives a
    /// documented, seeded model (see core/src/roughness/synthetic.rs). Not a measurement.
    #[command(after_help = crate::exit::HELP)]
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

pub fn main(c: &RoughnessCmd) -> Outcome {
    let RoughnessCmd::Synthesize { program, out, seed } = c;
    let machine = Machine::hermle_c600u();
    let (profile, note) = fiveaxis::roughness::synthesize(program, &machine, *seed).map_err(bad_input)?;
    let written = if out.extension().is_some_and(|e| e.eq_ignore_ascii_case("x3p")) {
        fiveaxis::roughness::write_x3p(&profile, out, &note)
    } else {
        fiveaxis::roughness::write_csv(&profile, out, &note)
    };
    written.map_err(bad_input)?;
    println!("wrote {} ({} points, SYNTHETIC)", out.display(), profile.z.len());
    Ok(OK)
}
