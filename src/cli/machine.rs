//! `fiveaxis machine`: the built-in machines listed, a machine file checked and shown, a machine as URDF.

use crate::exit::{bad_input, write_output, Outcome, OK};
use clap::Subcommand;
use fiveaxis::machine::{Machine, MachineError, BUILTIN_NAMES};

#[derive(Subcommand)]
pub enum MachineCmd {
    /// List the built-in machines.
    List,
    /// Print a built-in machine's TOML description (a template for your own), or check a machine
    /// file and print it (a URDF as the TOML it amounts to); an unknown name or an invalid file exits 2
    /// naming the field.
    #[command(after_help = crate::exit::HELP)]
    Show { name: String },
    /// Write a machine (built-in name, TOML or URDF file) as URDF, for `robot_description`: joints named
    /// after the axes as our JointStates name them, link `workpiece` (program frame) and `tool`.
    #[command(after_help = crate::exit::HELP)]
    Urdf {
        name: String,
        /// Write here instead of to standard output.
        #[arg(long, short)]
        out: Option<std::path::PathBuf>,
    },
}

pub fn main(c: &MachineCmd) -> Outcome {
    match c {
        MachineCmd::List => list(),
        MachineCmd::Show { name } => show(name),
        MachineCmd::Urdf { name, out } => urdf(name, out.as_deref()),
    }
}

/// `machine list`: each built-in machine's name (what `--machine` takes), maker and model as
/// program headers write them, control, and description.
fn list() -> Outcome {
    let machines: Vec<(&str, Result<Machine, MachineError>)> = BUILTIN_NAMES.iter().map(|n| (*n, Machine::builtin(n))).collect();
    let w = BUILTIN_NAMES.iter().map(|n| n.len()).max().unwrap_or(0);
    let label = |m: &Machine| match &m.control {
        Some(c) => format!("{} ({c})", m.label()),
        None => m.label(),
    };
    let wl = machines.iter().filter_map(|(_, m)| m.as_ref().ok()).map(|m| label(m).chars().count()).max().unwrap_or(0);
    for (n, m) in machines {
        match m {
            Ok(m) => println!("{n:<w$}  {:<wl$}  {}", label(&m), m.description),
            Err(e) => println!("{n:<w$}  ({e})"),
        }
    }
    Ok(OK)
}

/// `machine urdf`: the machine written as URDF, to a file or standard output.
fn urdf(spec: &str, out: Option<&std::path::Path>) -> Outcome {
    let machine = fiveaxis::machine::load(spec).map_err(bad_input)?;
    let text = fiveaxis::machine::urdf::write(&machine);
    match out {
        Some(path) => write_output(path, text)?,
        None => print!("{text}"),
    }
    Ok(OK)
}

/// `machine show`: a built-in machine's file, or a machine file checked whole.
fn show(spec: &str) -> Outcome {
    let text = if fiveaxis::machine::urdf::is_urdf_path(spec) {
        // The TOML the URDF amounts to, once the machine it describes is valid.
        fiveaxis::machine::read_machine_file(spec).and_then(|text| {
            let (_, file) = fiveaxis::machine::urdf::read_with_file(&text, spec)?;
            let toml = toml::to_string(&file).map_err(|e| MachineError::Parse { path: spec.to_string(), message: e.to_string() })?;
            Ok(format!("# {spec} as a fiveaxis machine file (mm, deg)\n{toml}"))
        })
    } else {
        fiveaxis::machine::description_text(spec).and_then(|text| Machine::from_toml_str(&text, spec).map(|_| text.to_string()))
    }
    .map_err(bad_input)?;
    print!("{text}");
    Ok(OK)
}
