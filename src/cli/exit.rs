//! The exit codes of every `fiveaxis` command, and the one mapping from a command's outcome to them:
//! 0 done, 1 a threshold the user set was violated (or the command itself failed), 2 bad input.

use std::process::ExitCode;

/// Done; no threshold violated.
pub const OK: u8 = 0;
/// A threshold the user set was violated (`analyze --max-c-speed-rpm`, `--min-distance-deg`); also a
/// failure of the command itself (a bug, a `fiveaxis-rerun` that is missing or failed).
pub const VIOLATED: u8 = 1;
/// Bad input: usage, an unreadable or invalid program, machine, recording or profile, a program with
/// defects, an output that cannot be written.
pub const BAD_INPUT: u8 = 2;

/// The exit codes as `--help` states them.
pub const HELP: &str = "Exit codes: 0 done; 1 a threshold set with --max-c-speed-rpm or --min-distance-deg was violated (`fiveaxis analyze` of recordings; `program analyze` reports its regions and exits 0), \
or the command itself failed; 2 bad input: usage, an unreadable or invalid program, machine, recording or profile, \
a program with defects, an output that cannot be written.";

/// Why a command stopped before it was done.
#[derive(Debug)]
pub enum Stop {
    /// The input is bad (exit 2).
    BadInput(anyhow::Error),
    /// The command itself failed (exit 1).
    Failed(anyhow::Error),
}

/// A command's outcome: its exit code when it ran to the end.
pub type Outcome = Result<u8, Stop>;

/// `e` as bad input (exit 2), said with its whole chain of causes.
pub fn bad_input(e: impl std::fmt::Display) -> Stop {
    Stop::BadInput(anyhow::anyhow!("{e:#}"))
}

/// Anything not classified is a failure of the command itself (exit 1).
impl From<anyhow::Error> for Stop {
    fn from(e: anyhow::Error) -> Self {
        Stop::Failed(e)
    }
}

impl From<serde_json::Error> for Stop {
    fn from(e: serde_json::Error) -> Self {
        Stop::Failed(e.into())
    }
}

/// Write `text` to the output `path` the user named; failing to is bad input (exit 2).
pub fn write_output(path: &std::path::Path, text: impl AsRef<[u8]>) -> Result<(), Stop> {
    std::fs::write(path, text).map_err(|e| bad_input(format!("cannot write {}: {e}", path.display())))
}

/// The process exit code of `outcome`, its reason said on stderr.
pub fn code(outcome: Outcome) -> ExitCode {
    match outcome {
        Ok(c) => ExitCode::from(c),
        Err(Stop::BadInput(e)) => {
            eprintln!("fiveaxis: {e:#}");
            ExitCode::from(BAD_INPUT)
        }
        Err(Stop::Failed(e)) => {
            eprintln!("fiveaxis: {e:#}");
            ExitCode::from(VIOLATED)
        }
    }
}
