//! `fiveaxis`: the command-line front of the library, one module per command. Each command owns its
//! arguments and handler; they share the flag groups of [`args`] and one outcome-to-exit-code mapping
//! ([`exit`]: 0 done, 1 threshold violated, 2 bad input).

mod analyze;
mod args;
mod avoid;
mod demo;
mod exit;
mod machine;
mod mcap;
mod program;
mod replay;
mod roughness;
mod run;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// Watch a five-axis machine tool for kinematic singularities (Cripps et al. 2017).
#[derive(Parser)]
#[command(name = "fiveaxis", version, after_help = exit::HELP)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// NC programs: analyze one.
    #[command(subcommand)]
    Program(program::ProgramCmd),
    /// Machines: list or show the built-in ones.
    #[command(subcommand)]
    Machine(machine::MachineCmd),
    /// Run commander, simulator and monitor in one process (no DDS), faster than real time.
    #[command(after_help = exit::HELP)]
    Run(run::RunArgs),
    /// Analyse recordings (MCAP files, rosbag2 bags) offline: the monitor recomputed, regions, threshold
    /// checks for CI. Several recordings are analysed in parallel, one report each and a summary; the
    /// exit code is the worst of theirs.
    #[command(after_help = exit::HELP)]
    Analyze(analyze::OfflineArgs),
    /// MCAP recordings: recover a damaged one.
    #[command(subcommand)]
    Mcap(mcap::McapCmd),
    /// Roughness profiles: make the synthetic example.
    #[command(subcommand)]
    Roughness(roughness::RoughnessCmd),
    /// Remedies for a singular program.
    #[command(subcommand)]
    Avoid(avoid::AvoidCmd),
    /// Replay a recording (MCAP) into a Rerun viewer or an .rrd file: runs `fiveaxis-rerun replay`
    /// with these arguments (see `fiveaxis-rerun replay --help`); its exit code is this one's.
    Replay(replay::ReplayArgs),
    /// The embedded default: the node set in one process on the paper's two programs and two continuous
    /// paths, on the Hermle.
    Demo(demo::DemoArgs),
}

/// Keep freed memory for reuse instead of handing it back to the kernel and faulting it in again.
/// `run` streams its states between threads in batches of about 850 KB, and glibc's per-thread
/// arenas gave each freed one back at once: 24 k page faults on the 1 h benchmark program, 5.5 k
/// with this, about 2 % of `run`'s time on one core; its peak resident memory 28 MB against 24 MB.
/// Call before the threads start.
fn keep_freed_memory() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: mallopt only sets the allocator's parameters, under its own lock.
    unsafe {
        libc::mallopt(libc::M_TRIM_THRESHOLD, 256 << 20);
        libc::mallopt(libc::M_MMAP_THRESHOLD, 32 << 20);
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
    // Usage errors exit 2 (clap's own code, the same as bad input).
    let cli = Cli::parse();
    exit::code(match &cli.command {
        Command::Program(c) => program::main(c),
        Command::Machine(c) => machine::main(c),
        Command::Run(a) => run::main(a),
        Command::Analyze(a) => analyze::main(a),
        Command::Mcap(c) => mcap::main(c),
        Command::Roughness(c) => roughness::main(c),
        Command::Avoid(c) => avoid::main(c),
        Command::Replay(a) => replay::main(a),
        Command::Demo(a) => demo::main(a),
    })
}
