//! fiveaxis: watch a five-axis machine tool for kinematic singularities.
//!
//! The math of Cripps et al. 2017 (seed 001) and of the C-axis smoothing paper (seed 002) lives in
//! the sans-I/O crate [`fiveaxis_core`] (machines, kinematics, program readers, paths, singularity,
//! planner, roughness math), re-exported here at the same paths. This crate adds what touches files
//! and formats: recordings (MCAP, rosbag2: [`record`]), the offline [`analysis`] of them, reports,
//! roughness files, the in-process node set ([`live`]) and the jobs the command line runs ([`job`]).
//!
//! Units: SI inside (m, rad, s; REP 103). Readers convert from mm/inch/degrees; reports convert back.

// `!(x > 0.0)` is deliberate throughout: it rejects NaN, which `x <= 0.0` would let through.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod analysis;
pub mod avoid;
pub mod args;
pub mod job;
pub mod live;
pub mod mtconnect;
pub mod opcua;
pub mod source;
pub mod record;
pub mod recorded;
pub mod report;
pub mod scene;
pub mod topics;

// The math, from the sans-I/O core crate, at the paths it has always had.
pub use fiveaxis_core::{kinematics, listing, path, planner, singularity, units};
use fiveaxis_core::xml;

/// Machines ([`fiveaxis_core::machine`]) and their files.
pub mod machine {
    mod files;
    pub use files::{description_text, load, read_machine_file, MAX_MACHINE_FILE_BYTES};
    pub use fiveaxis_core::machine::*;
}

/// NC program readers ([`fiveaxis_core::program`]), their files and the control's set-up flags.
pub mod program {
    mod files;
    pub use crate::args::ControlArgs;
    pub use files::{load, open, ProgramFile, SubroutineDirs, MAX_SPOOL_BYTES, STDIN};
    pub use fiveaxis_core::program::*;
}

/// Surface roughness ([`fiveaxis_core::roughness`]) and its files (X3P, CSV) and flags.
pub mod roughness {
    mod args;
    mod io;
    mod synthesize;
    pub use args::RoughnessArgs;
    pub use synthesize::{synthesize, SynthesizeError};
    pub use fiveaxis_core::roughness::*;
    pub use io::{read_csv, read_profile, read_x3p, write_csv, write_x3p, CsvUnits};
}
