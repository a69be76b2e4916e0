//! Tool-path sampling: a block list becomes a time-parametrized commanded trajectory at the
//! programmed feed, as a control with tool-centre-point management runs it: the tool tip moves on a
//! straight line in workpiece coordinates at F, the rotary axes move linearly within each block
//! (seed 001 §4, the reference notes), and the linear machine axes follow from the kinematics
//! (seed 001 eq. 6). Without TCPM the machine axes interpolate linearly. Sampled at a fixed period.
//!
//! Built-in continuous paths `paper-sing` / `paper-nonsing` are seed 001 eq. (8)-(11).

pub mod align;
mod builtin;
mod geometry;
mod passes;
mod segment;
mod shared;
mod window;

pub use builtin::{builtin_names, paper_orientation, BuiltinPath};
pub use passes::Passes;
pub use shared::{SharedRead, SharedReader};
pub use geometry::{ArcPath, GreatCircle};
pub use segment::{plan, Segment, SegmentKind, SegmentPlanner, EXACT_PATH_RAD, ORIENT_PIECE_RAD};
pub use window::{GridSampler, SegmentStream, SegmentWindow};

use crate::kinematics::Joints;
use crate::machine::Machine;
use crate::program::{Diagnostic, Program};
use nalgebra::Vector3;

/// Sampling options.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathOptions {
    /// Sample period, s (default 1 ms).
    pub period: f64,
    /// Replace the programmed tool-tip feed of every feed move, mm/min.
    pub feed_override_mm_per_min: Option<f64>,
    /// Longest program accepted, s (default [`MAX_PROGRAM_DURATION_S`]): a block that would make the
    /// program longer (a typo such as `F0.01`) is an error naming its line and column, and planning
    /// stops there instead of sampling hours of motion that were never meant.
    pub max_duration_s: f64,
}

/// The default bound on a program's commanded duration: 24 hours, a day of unattended machining.
pub const MAX_PROGRAM_DURATION_S: f64 = 24.0 * 3600.0;

impl Default for PathOptions {
    fn default() -> Self {
        PathOptions { period: 1e-3, feed_override_mm_per_min: None, max_duration_s: MAX_PROGRAM_DURATION_S }
    }
}

/// One commanded sample.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample {
    /// Time from the start, s.
    pub t: f64,
    /// Tool-tip path length travelled in the workpiece, m.
    pub s: f64,
    /// Index of the segment (see [`Trajectory::segments`]).
    pub segment: usize,
    /// Axis values `[X, Y, Z, R, R]`, m and rad.
    pub q: Joints,
    /// Tool tip in program (workpiece, datum-shifted) coordinates, m.
    pub tip: Vector3<f64>,
    /// Unit tool axis in the workpiece frame.
    pub axis: Vector3<f64>,
    /// Time derivative of the tool axis at the programmed feed, 1/s.
    pub axis_rate: Vector3<f64>,
    /// Programmed tool-tip feed, m/s (0 while only rotary axes move).
    pub feed: f64,
}

/// A trajectory: the segments of a program, sampled on demand at the period ([`Trajectory::samples`]).
#[derive(Debug, Clone, Default)]
pub struct Trajectory {
    pub period: f64,
    pub segments: Vec<Segment>,
    /// Samples held in memory: only a built-in continuous path has them (sampled from the path
    /// itself); a program's are made from its segments as they are read, so that no consumer holds
    /// one sample per period of an hours-long program.
    pub stored: Vec<Sample>,
    /// Problems met while planning (unreachable poses, axes the machine lacks), with program lines.
    pub diagnostics: Vec<Diagnostic>,
}

impl Trajectory {
    /// Plan a program on a machine (sampled on demand).
    pub fn from_program(program: &Program, machine: &Machine, options: &PathOptions) -> Trajectory {
        let (segments, diagnostics) = plan(program, machine, options);
        Trajectory { period: options.period, segments, stored: Vec::new(), diagnostics }
    }

    /// Total commanded duration, s.
    pub fn duration(&self) -> f64 {
        self.segments.last().map_or(0.0, |s| s.t0 + s.duration)
    }

    /// The samples in time order, one at a time: on the global grid `t = k * period`, plus the end point.
    pub fn samples<'a>(&'a self, machine: &'a Machine) -> Box<dyn Iterator<Item = Sample> + 'a> {
        if !self.stored.is_empty() {
            return Box::new(self.stored.iter().copied());
        }
        let mut window = SegmentWindow::new(self.segments.iter().cloned());
        let mut sampler = GridSampler::new(self.period);
        Box::new(std::iter::from_fn(move || {
            let sample = sampler.next(&mut window, machine);
            // Keep the segment just behind: the end point is sampled from the last one.
            if let Some(s) = &sample {
                window.release_before(s.segment);
            }
            sample
        }))
    }

    /// How many samples [`Trajectory::samples`] yields, without making them.
    pub fn sample_count(&self) -> usize {
        if !self.stored.is_empty() {
            return self.stored.len();
        }
        let t_end = self.duration();
        if self.segments.is_empty() || !(self.period > 0.0) {
            return 0;
        }
        // Grid points k * period < t_end, plus the end point.
        let mut m = (t_end / self.period).ceil().max(0.0) as u64;
        while m > 0 && (m - 1) as f64 * self.period >= t_end {
            m -= 1;
        }
        while (m as f64) * self.period < t_end {
            m += 1;
        }
        m as usize + 1
    }
}

/// Segment `k` of a made-up stream (a unit TCPM move per index), for the tests of what reads
/// segment streams ([`shared`], [`crate::planner`]'s tee).
#[cfg(test)]
pub(crate) fn stream_test_segment(k: usize) -> Segment {
    Segment {
        kind: SegmentKind::Tcp,
        block: k,
        line: k + 1,
        number: None,
        t0: k as f64,
        duration: 1.0,
        s0: k as f64,
        length: 1.0,
        q0: [k as f64; 5],
        q1: [k as f64 + 1.0; 5],
        tip0: Default::default(),
        tip1: Default::default(),
        datum: Default::default(),
        feed: 1.0,
        arc: None,
        orient: None,
        tolerance: Default::default(),
        path: true,
        exact: crate::program::Exact::Blend,
    }
}
