//! The geometric path the planner moves along: runs of segments, each a C2 curve `q(sigma)`.

use crate::kinematics::Joints;
use crate::machine::{Machine, AXES};
use crate::path::{Segment, SegmentKind};
use crate::singularity::CubicSpline;
use nalgebra::Vector3;

pub use crate::singularity::CORNER_DEG;

/// How a run is parametrized and interpolated.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum RunKind {
    /// TCPM feed moves: tool tip (3) and rotaries (2) splined in tool-tip length.
    Tcp,
    /// Feed moves without TCPM: the five machine axes splined in linear-axis length.
    Axes,
    /// One rapid or rotary-only move: all axes linear in its own length (m or rad).
    Linear,
}

/// A stretch of the program the machine runs without stopping.
#[derive(Debug, Clone)]
pub struct Run {
    kind: RunKind,
    /// Segment indices and, for each, its start parameter; the last entry of `sigma` is the end.
    pub segments: Vec<usize>,
    pub sigma: Vec<f64>,
    /// Programmed path speed per segment (m/s, or rad/s for rotary-only; infinite for rapids).
    pub feed: Vec<f64>,
    splines: Vec<CubicSpline>,
    q0: Joints,
    q1: Joints,
    datum: Vector3<f64>,
}

impl Run {
    /// Parameter length of the run.
    pub fn length(&self) -> f64 {
        *self.sigma.last().unwrap_or(&0.0)
    }

    /// True if every axis is linear in the parameter (a rapid or rotary-only move).
    pub fn is_linear(&self) -> bool {
        self.kind == RunKind::Linear
    }

    /// Index into `segments` of the segment holding parameter `s`.
    pub fn segment_at(&self, s: f64) -> usize {
        let k = self.sigma.partition_point(|&v| v <= s);
        k.saturating_sub(1).min(self.segments.len() - 1)
    }

    /// Axis values at parameter `s`.
    pub fn joints(&self, s: f64, machine: &Machine) -> Joints {
        match self.kind {
            RunKind::Linear => {
                let u = if self.length() > 0.0 { (s / self.length()).clamp(0.0, 1.0) } else { 1.0 };
                std::array::from_fn(|i| self.q0[i] + (self.q1[i] - self.q0[i]) * u)
            }
            RunKind::Axes => std::array::from_fn(|i| self.splines[i].value(s)),
            RunKind::Tcp => {
                let tip = Vector3::new(self.splines[0].value(s), self.splines[1].value(s), self.splines[2].value(s));
                let rot = [self.splines[3].value(s), self.splines[4].value(s)];
                let l = machine.chain.linear_for(&(tip + self.datum), &rot);
                [l.x, l.y, l.z, rot[0], rot[1]]
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

/// The length a segment's feed applies to: tool tip (TCPM), linear axes (no TCPM), else rotaries.
fn path_length(seg: &Segment) -> f64 {
    let d = |a: usize, b: usize| (a..b).map(|i| (seg.q1[i] - seg.q0[i]).powi(2)).sum::<f64>().sqrt();
    match seg.kind {
        SegmentKind::Tcp if seg.length > 1e-12 => seg.length,
        SegmentKind::Axes | SegmentKind::Rapid if d(0, 3) > 1e-12 => d(0, 3),
        _ => d(3, 5),
    }
}

fn direction(seg: &Segment) -> Vector3<f64> {
    match seg.kind {
        SegmentKind::Tcp => seg.tip1 - seg.tip0,
        _ => Vector3::new(seg.q1[0] - seg.q0[0], seg.q1[1] - seg.q0[1], seg.q1[2] - seg.q0[2]),
    }
}

/// How a segment is interpolated in a run: TCPM with a moving tip, linear machine axes that move,
/// else a run of its own, linear in its parameter (rapid or rotary-only).
fn run_kind(s: &Segment) -> RunKind {
    match s.kind {
        SegmentKind::Tcp if s.length > 1e-12 => RunKind::Tcp,
        SegmentKind::Axes if (0..3).any(|i| (s.q1[i] - s.q0[i]).abs() > 1e-12) => RunKind::Axes,
        _ => RunKind::Linear,
    }
}

impl PathModel {
    /// Split the segments into runs and fit their curves.
    pub fn new(segments: &[Segment]) -> PathModel {
        let mut runs: Vec<Run> = Vec::new();
        let mut current: Vec<usize> = Vec::new();
        for (k, seg) in segments.iter().enumerate() {
            let kind = run_kind(seg);
            let joins = current.last().is_some_and(|&p| {
                let prev = &segments[p];
                kind != RunKind::Linear
                    && run_kind(prev) == kind
                    && prev.datum == seg.datum
                    && direction(prev).angle(&direction(seg)) <= CORNER_DEG.to_radians()
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
        let last = &segments[*idx.last().unwrap()];
        let kind = run_kind(first);
        let mut sigma = vec![0.0];
        for &k in &idx {
            sigma.push(sigma.last().unwrap() + path_length(&segments[k]));
        }
        let feed = idx.iter().map(|&k| feed_of(&segments[k])).collect();
        let splines = match kind {
            RunKind::Linear => Vec::new(),
            RunKind::Axes => (0..AXES)
                .map(|i| {
                    let ys: Vec<f64> = std::iter::once(first.q0[i]).chain(idx.iter().map(|&k| segments[k].q1[i])).collect();
                    CubicSpline::natural(&sigma, &ys)
                })
                .collect(),
            RunKind::Tcp => (0..AXES)
                .map(|i| {
                    let at = |seg: &Segment, end: bool| match i {
                        0..=2 => (if end { seg.tip1 } else { seg.tip0 })[i],
                        _ => (if end { seg.q1 } else { seg.q0 })[i],
                    };
                    let ys: Vec<f64> = std::iter::once(at(first, false)).chain(idx.iter().map(|&k| at(&segments[k], true))).collect();
                    CubicSpline::natural(&sigma, &ys)
                })
                .collect(),
        };
        Run { kind, segments: idx, sigma, feed, splines, q0: first.q0, q1: last.q1, datum: first.datum }
    }
}
