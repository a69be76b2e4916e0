//! fiveaxis: watch a five-axis machine tool for kinematic singularities.
//!
//! The math of Cripps et al. 2017 (seed 001) and of the C-axis smoothing paper (seed 002), as plain
//! functions: machine models and kinematics, NC program readers, tool-path sampling and the
//! singularity analysis. No I/O in the math; the nodes move its values across a bus.
//!
//! Units: SI inside (m, rad, s; REP 103). Readers convert from mm/inch/degrees; reports convert back.

// `!(x > 0.0)` is deliberate throughout: it rejects NaN, which `x <= 0.0` would let through.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod analysis;
pub mod avoid;
pub mod job;
pub mod kinematics;
pub mod listing;
pub mod live;
pub mod machine;
pub mod path;
pub mod planner;
pub mod program;
pub mod record;
pub mod report;
pub mod roughness;
pub mod scene;
pub mod singularity;
pub mod units;
mod xml;
