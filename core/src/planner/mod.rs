//! The feed planner of the machine simulator: what a control with axis velocity, acceleration and
//! jerk limits actually does along the commanded path (the stutter near the singularity).
//!
//! 1. Geometry ([`RunScout`], [`Run`]): the moves split into runs the machine runs without stopping; they end
//!    at rapids, corners sharper than [`CORNER_DEG`], a datum change and a change between moving the
//!    tool tip and only turning the rotary axes. Consecutive rotary-only moves form one run. Each run
//!    is a C2 path `q(s)`: natural cubic splines through the block points in path length, as seed 002
//!    smooths G1 points (the tool tip under TCPM, the rotary axes, or all machine axes without TCPM).
//!    Under vector orientation interpolation the tool axis is first smoothed through the programmed
//!    directions within a tolerance ([`orientation`]), as a control smooths a CAM system's vectors.
//! 2. Look-ahead: a run is planned window by window, [`PlanConfig::lookahead_blocks`] blocks ahead
//!    (default [`LOOKAHEAD_BLOCKS`]); each window is planned to stop at its end, as a control must be
//!    able to, and only what that stop has not shaped is committed (at most three quarters); the
//!    next window continues from the committed speed. Memory is bounded by the window, not the program.
//! 3. Velocity-limit curve: seed 002 eq. (5) on `q_s, q_ss, q_sss`, capped by the programmed feed.
//! 4. Forward/backward passes: the largest path speed whose tangential acceleration keeps every axis
//!    within `|q_ss s'^2 + q_s s''| <= a_max` (time-optimal path parametrization).
//! 5. Jerk: a moving average of the path parameter in time (window `2 a_max/j_max`) makes the path
//!    acceleration continuous with bounded slope; the path stays exactly the same.
//! 6. Check: every axis' velocity, acceleration and jerk is measured on the sampled result; where a
//!    ratio exceeds 1 the limit curve is lowered there and the window planned again.
//! 7. Servo ([`servo`]): each axis follows its set-point through a critically damped position loop;
//!    at a stop between runs the next starts once every axis is in position.

mod check;
mod geometry;
pub mod orientation;
mod profile;
pub mod servo;
mod tee;

pub use geometry::{Run, RunHead, RunScout, CORNER_DEG};
pub use check::{limit_ratios, limit_ratios_into, LimitCheck};
pub use profile::{plan_each, plan_stream, PlanConfig, Planned, PlannedSample, LOOKAHEAD_BLOCKS};
