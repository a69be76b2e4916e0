//! fiveaxis-core: the math of watching a five-axis machine tool for kinematic singularities, with no
//! transport, no recording formats, no command line and no progress bars.
//!
//! - [`machine`], [`kinematics`]: machine models (two rotary axes, table or head) and their forward
//!   and inverse kinematics; the singular direction is the secondary rotary axis (seed 001 sec. 2).
//! - [`program`]: NC program readers (RS274NGC, Heidenhain DIN/ISO and Klartext, Sinumerik, CL data),
//!   from text or streamed line by line.
//! - [`path`]: blocks to timed segments and 1 kHz samples of the commanded axes.
//! - [`singularity`]: distance to the singularity, the secondary-axis rate it asks (seed 001 eq. 5),
//!   the seed 002 feed limit and the regions where the rate exceeds the axis.
//! - [`planner`]: a control's look-ahead (seed 002 eq. 5 velocity-limit curve, acceleration passes,
//!   jerk filter) and servo: what a machine with axis limits does.
//! - [`sampling`]: machine data reported per axis at their own rates, merged into poses at common
//!   instants.
//! - [`roughness`]: ISO 16610-21 Gaussian filter and ISO 4287 parameters of a height profile.
//!
//! Units: SI inside (m, rad, s; REP 103). Readers convert from mm, inch and degrees; [`units`] holds
//! the factors reports convert back with.
//!
//! Read the paper's singular program, analyse it, print its peak C speed (seed 001: 175 rpm with the
//! axes linear per block, against the Hermle's 25 rpm):
//!
//! ```
//! use fiveaxis_core::{machine::Machine, path::{PathOptions, Trajectory}, program, singularity, units};
//!
//! let text = program::BUNDLED.iter().find(|(name, _)| *name == "SING.I").unwrap().1;
//! let sing = program::read(text, program::Dialect::Heidenhain, "SING.I", &Default::default());
//! let machine = Machine::hermle_c600u();
//! let path = Trajectory::from_program(&sing, &machine, &PathOptions::default());
//! let found = singularity::analyze(&path, &machine, &Default::default());
//! let rpm = found.summary.peak_rate / units::RPM;
//! println!("peak C speed {rpm:.1} rpm, {} regions above {:.0} rpm", found.regions.len(), found.summary.rate_limit / units::RPM);
//! assert!((rpm - 175.0).abs() < 1.0 && !found.regions.is_empty());
//! ```

// `!(x > 0.0)` is deliberate throughout: it rejects NaN, which `x <= 0.0` would let through.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod kinematics;
pub mod listing;
pub mod machine;
pub mod path;
pub mod planner;
pub mod program;
pub mod roughness;
pub mod sampling;
pub mod singularity;
pub mod units;
pub mod xml;
