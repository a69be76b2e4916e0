//! The feed planner of the machine simulator: what a control with axis velocity, acceleration and
//! jerk limits actually does along the commanded path (the stutter near the singularity).
//!
//! 1. Geometry ([`PathModel`]): each run of feed moves becomes a C2 path `q(s)`, natural cubic
//!    splines through the block points in tool-path length, as seed 002 smooths G1 points (the tool
//!    tip under TCPM, the rotary axes, or all machine axes without TCPM). Runs end at rapids,
//!    rotary-only moves and corners sharper than [`CORNER_DEG`], where the machine stops.
//! 2. Velocity-limit curve: seed 002 eq. (5) on `q_s, q_ss, q_sss`, capped by the programmed feed.
//! 3. Forward/backward passes: the largest path speed whose tangential acceleration keeps every axis
//!    within `|q_ss s'^2 + q_s s''| <= a_max` (time-optimal path parametrization).
//! 4. Jerk: a moving average of the path parameter in time (window `a_max/j_max`) makes the path
//!    acceleration continuous with bounded slope; the path stays exactly the same.
//! 5. Check: every axis' velocity, acceleration and jerk is measured on the sampled result; where a
//!    ratio exceeds 1 the limit curve is lowered there and the profile planned again.
//! 6. Servo ([`servo`]): each axis follows its set-point through a critically damped position loop.

mod geometry;
mod profile;
pub mod servo;

pub use geometry::{PathModel, Run, CORNER_DEG};
pub use profile::{limit_ratios, plan, plan_each, PlanConfig, Planned, PlannedSample, LOOKAHEAD_BLOCKS};
