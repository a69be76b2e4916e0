//! The geometric path the planner moves along: runs of segments the machine runs without stopping,
//! and, per look-ahead window, the C2 curve `q(sigma)` through the window's block end points.

use crate::kinematics::Joints;
use crate::machine::{Machine, AXES};
use crate::path::{Segment, SegmentKind};
use crate::singularity::CubicSpline;
use nalgebra::Vector3;

pub use crate::singularity::CORNER_DEG;

/// Blocks before a window's first committed point that its splines are also fitted through.
pub use crate::singularity::SPLINE_OVERLAP_BLOCKS;

/// How a run is parametrized and interpolated.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum RunKind {
    /// TCPM feed moves: tool tip (3) and rotaries (2) splined in tool-tip length.
    Tcp,
    /// Feed moves without TCPM: the five machine axes splined in linear-axis length.
    Axes,
    /// Feed moves of the rotary axes only (the tool reorients about a fixed tip, or the table turns
    /// under fixed linear axes): the rotaries splined in their own angle length, rad.
    Rotary,
    /// One rapid or a move with nothing to follow: all axes linear in its own length (m or rad).
    Linear,
}

/// A stretch of the program the machine runs without stopping: it ends at rapids, corners sharper
/// than [`CORNER_DEG`], a change of datum and a change between moving the tool tip and only turning
/// the rotary axes.
#[derive(Debug, Clone)]
pub struct Run {
    kind: RunKind,
    /// Segment indices and, for each, its start parameter; the last entry of `sigma` is the end.
    pub segments: Vec<usize>,
    pub sigma: Vec<f64>,
    /// Programmed path speed per segment (m/s, or rad/s for rotary-only; infinite for rapids).
    pub feed: Vec<f64>,
    q0: Joints,
    q1: Joints,
    datum: Vector3<f64>,
    /// For a rotary run under TCPM, the tool tip it turns about (program coordinates).
    tcp_tip: Option<Vector3<f64>>,
}

/// The curve of one look-ahead window of a run.
#[derive(Debug, Clone)]
pub struct Curve<'a> {
    run: &'a Run,
    splines: Vec<CubicSpline>,
}

impl Run {
    /// Parameter length of the run.
    pub fn length(&self) -> f64 {
        *self.sigma.last().unwrap_or(&0.0)
    }

    /// True if every axis is linear in the parameter (a rapid or a single move with nothing to follow).
    pub fn is_linear(&self) -> bool {
        self.kind == RunKind::Linear
    }

    /// True if the parameter is an angle (rad): only the rotary axes move along the path.
    pub fn is_angular(&self, segments: &[Segment]) -> bool {
        match self.kind {
            RunKind::Rotary => true,
            RunKind::Linear => self.segments.iter().all(|&k| {
                let s = &segments[k];
                (0..3).all(|i| (s.q1[i] - s.q0[i]).abs() <= 1e-12) && s.length <= 1e-12
            }),
            _ => false,
        }
    }

    /// Index into `segments` of the segment holding parameter `s`.
    pub fn segment_at(&self, s: f64) -> usize {
        let k = self.sigma.partition_point(|&v| v <= s);
        k.saturating_sub(1).min(self.segments.len() - 1)
    }

    /// The curve through blocks `first..=last` of the run (indices into [`Run::segments`]), fitted
    /// also through [`SPLINE_OVERLAP_BLOCKS`] blocks before `first`.
    pub fn curve<'a>(&'a self, segments: &[Segment], first: usize, last: usize) -> Curve<'a> {
        let lo = first.saturating_sub(SPLINE_OVERLAP_BLOCKS);
        let last = last.min(self.segments.len() - 1);
        let knots = &self.sigma[lo..=last + 1];
        let point = |b: usize, i: usize| -> f64 {
            // Knot b is the start of block b (b <= last) or the end of block last.
            let (seg, end) = if b <= last { (&segments[self.segments[b]], false) } else { (&segments[self.segments[last]], true) };
            match (self.kind, i) {
                (RunKind::Tcp, 0..=2) => (if end { seg.tip1 } else { seg.tip0 })[i],
                _ => (if end { seg.q1 } else { seg.q0 })[i],
            }
        };
        let splines = match self.kind {
            RunKind::Linear => Vec::new(),
            _ => (0..AXES)
                .map(|i| {
                    let ys: Vec<f64> = (lo..=last + 1).map(|b| point(b, i)).collect();
                    CubicSpline::natural(knots, &ys)
                })
                .collect(),
        };
        Curve { run: self, splines }
    }
}

impl Curve<'_> {
    /// Axis values at run parameter `s`.
    pub fn joints(&self, s: f64, machine: &Machine) -> Joints {
        let run = self.run;
        match run.kind {
            RunKind::Linear => {
                let u = if run.length() > 0.0 { (s / run.length()).clamp(0.0, 1.0) } else { 1.0 };
                std::array::from_fn(|i| run.q0[i] + (run.q1[i] - run.q0[i]) * u)
            }
            RunKind::Axes => std::array::from_fn(|i| self.splines[i].value(s)),
            RunKind::Tcp => {
                let tip = Vector3::new(self.splines[0].value(s), self.splines[1].value(s), self.splines[2].value(s));
                let rot = [self.splines[3].value(s), self.splines[4].value(s)];
                let l = machine.chain.linear_for(&(tip + run.datum), &rot);
                [l.x, l.y, l.z, rot[0], rot[1]]
            }
            RunKind::Rotary => {
                let rot = [self.splines[3].value(s), self.splines[4].value(s)];
                match run.tcp_tip {
                    Some(tip) => {
                        let l = machine.chain.linear_for(&(tip + run.datum), &rot);
                        [l.x, l.y, l.z, rot[0], rot[1]]
                    }
                    None => [run.q0[0], run.q0[1], run.q0[2], rot[0], rot[1]],
                }
            }
        }
    }
}

/// All runs of a commanded trajectory, in order.
#[derive(Debug, Clone)]
pub struct PathModel {
    pub runs: Vec<Run>,
}

fn feed_of(seg: &Segment) -> f64 {
    match seg.kind {
        SegmentKind::Rapid => f64::INFINITY,
        _ => {
            let l = path_length(seg);
            if l > 0.0 {
                l / seg.duration
            } else {
                0.0
            }
        }
    }
}

/// The length a segment's feed applies to: tool tip (TCPM), linear axes (no TCPM; along the arc for
/// an arc piece), else rotaries.
fn path_length(seg: &Segment) -> f64 {
    let linear = seg.linear_axes_length();
    match seg.kind {
        SegmentKind::Tcp if seg.length > 1e-12 => seg.length,
        SegmentKind::Axes | SegmentKind::Rapid if linear > 1e-12 => linear,
        _ => ((seg.q1[3] - seg.q0[3]).powi(2) + (seg.q1[4] - seg.q0[4]).powi(2)).sqrt(),
    }
}

/// The direction of a segment in its run's parameter space.
fn direction(seg: &Segment, kind: RunKind) -> Vector3<f64> {
    match kind {
        RunKind::Tcp => seg.tip1 - seg.tip0,
        RunKind::Rotary => Vector3::new(seg.q1[3] - seg.q0[3], seg.q1[4] - seg.q0[4], 0.0),
        _ => Vector3::new(seg.q1[0] - seg.q0[0], seg.q1[1] - seg.q0[1], seg.q1[2] - seg.q0[2]),
    }
}

/// How a segment is interpolated in a run: TCPM with a moving tip, linear machine axes that move,
/// rotary axes only at a feed, else a run of its own, linear in its parameter (a rapid).
fn run_kind(s: &Segment) -> RunKind {
    let rotates = (s.q1[3] - s.q0[3]).abs() > 1e-12 || (s.q1[4] - s.q0[4]).abs() > 1e-12;
    match s.kind {
        SegmentKind::Tcp if s.length > 1e-12 => RunKind::Tcp,
        SegmentKind::Axes if (0..3).any(|i| (s.q1[i] - s.q0[i]).abs() > 1e-12) => RunKind::Axes,
        SegmentKind::Tcp | SegmentKind::Axes if rotates => RunKind::Rotary,
        _ => RunKind::Linear,
    }
}

impl PathModel {
    /// Split the segments into runs.
    pub fn new(segments: &[Segment]) -> PathModel {
        let mut runs: Vec<Run> = Vec::new();
        let mut current: Vec<usize> = Vec::new();
        for (k, seg) in segments.iter().enumerate() {
            let kind = run_kind(seg);
            let joins = current.last().is_some_and(|&p| {
                let prev = &segments[p];
                kind != RunKind::Linear
                    && run_kind(prev) == kind
                    && prev.kind == seg.kind
                    && prev.datum == seg.datum
                    && direction(prev, kind).angle(&direction(seg, kind)) <= CORNER_DEG.to_radians()
            });
            if !joins && !current.is_empty() {
                runs.push(Self::fit(segments, std::mem::take(&mut current)));
            }
            current.push(k);
        }
        if !current.is_empty() {
            runs.push(Self::fit(segments, current));
        }
        PathModel { runs }
    }

    fn fit(segments: &[Segment], idx: Vec<usize>) -> Run {
        let first = &segments[idx[0]];
        let last = &segments[*idx.last().unwrap_or(&idx[0])];
        let kind = run_kind(first);
        let mut sigma = Vec::with_capacity(idx.len() + 1);
        sigma.push(0.0);
        for &k in &idx {
            sigma.push(sigma[sigma.len() - 1] + path_length(&segments[k]));
        }
        let feed = idx.iter().map(|&k| feed_of(&segments[k])).collect();
        let tcp_tip = (kind == RunKind::Rotary && first.kind == SegmentKind::Tcp).then_some(first.tip0);
        Run { kind, segments: idx, sigma, feed, q0: first.q0, q1: last.q1, datum: first.datum, tcp_tip }
    }
}
