//! The geometric path the planner moves along: runs of segments the machine runs without stopping,
//! and, per look-ahead window, the C2 curve `q(sigma)` through the window's block end points.

use crate::kinematics::{Joints, SinCos};
use crate::machine::{Machine, AXES};
use crate::path::{Segment, SegmentKind};
use crate::singularity::{Knots, SplineSet};
use nalgebra::Vector3;

pub use crate::singularity::CORNER_DEG;

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

/// What a run is, measured over all its segments before it is planned (the planner needs its
/// length for its grid): a stretch of the program the machine runs without stopping. Runs end at
/// rapids, corners sharper than [`CORNER_DEG`], a change of datum and a change between moving the
/// tool tip and only turning the rotary axes.
#[derive(Debug, Clone, PartialEq)]
pub struct RunHead {
    kind: RunKind,
    /// Segments in the run, and its parameter length (the sum of their path lengths, in order).
    pub count: usize,
    pub length: f64,
    q0: Joints,
    q1: Joints,
    datum: Vector3<f64>,
    /// For a rotary run under TCPM, the tool tip it turns about (program coordinates).
    tcp_tip: Option<Vector3<f64>>,
    /// The parameter is an angle (rad): only the rotary axes move along the run.
    angular: bool,
    /// A dwell's time, s (a dwell is a run of its own, of length 0): the axes stand at `q0`.
    dwell: f64,
}

/// A run being planned: its head, and the window of its segments the look-ahead has read (each with
/// its start and end parameter and programmed path speed), read from the segment stream as the
/// planner reaches them and dropped behind it. Memory is the look-ahead, not the run.
#[derive(Debug, Clone)]
pub struct Run {
    head: RunHead,
    /// Global index of the run's first segment.
    pub first: usize,
    /// Local index of `window[0]`, and how many segments have been read.
    base: usize,
    read: usize,
    window: std::collections::VecDeque<(Segment, f64, f64, f64)>,
    next_sigma: f64,
    /// The curve's knots among the block starts read (local block index), on what the control
    /// interpolates ([`Segment::interpolated`]).
    knots: Knots,
}

/// The curve of one look-ahead window of a run.
#[derive(Debug, Clone)]
pub struct Curve<'a> {
    run: &'a Run,
    /// One spline per axis (or tool tip and rotary axes), all through the same knots (none for a
    /// linear run).
    splines: SplineSet<AXES>,
    /// The knot interval of the last evaluation: the planner evaluates along increasing `s`.
    hint: std::cell::Cell<usize>,
    /// The rotary angles' sines and cosines, which follow the evaluations.
    turns: std::cell::Cell<[SinCos; 2]>,
}

impl Run {
    /// The run `head`, whose first segment is `first` in the stream.
    pub fn new(head: RunHead, first: usize) -> Run {
        Run { head, first, base: 0, read: 0, window: Default::default(), next_sigma: 0.0, knots: Knots::default() }
    }

    /// Parameter length of the run.
    pub fn length(&self) -> f64 {
        self.head.length
    }

    /// A dwell's time, s (0 for a run that moves).
    pub fn dwell(&self) -> f64 {
        self.head.dwell
    }

    /// Segments in the run.
    pub fn count(&self) -> usize {
        self.head.count
    }

    /// True if every axis is linear in the parameter (a rapid or a single move with nothing to follow).
    pub fn is_linear(&self) -> bool {
        self.head.kind == RunKind::Linear
    }

    /// True if the parameter is an angle (rad): only the rotary axes move along the path.
    pub fn is_angular(&self) -> bool {
        self.head.angular
    }

    /// Read the run's segments from `source` through local index `b` (at most the run's last).
    pub fn read_through(&mut self, b: usize, source: &mut dyn Iterator<Item = Segment>) {
        while self.read <= b.min(self.head.count - 1) {
            let Some(seg) = source.next() else { break };
            let (start, feed) = (self.next_sigma, feed_of(&seg));
            self.next_sigma = start + path_length(&seg);
            if self.head.kind != RunKind::Linear {
                self.knots.offer(self.read, (start, self.next_sigma), &seg, seg.interpolated(false));
            }
            self.window.push_back((seg, start, self.next_sigma, feed));
            self.read += 1;
        }
    }

    /// Read past every segment of the run not read yet (a run that is not planned).
    pub fn skip_rest(&mut self, source: &mut dyn Iterator<Item = Segment>) {
        while self.read < self.head.count && source.next().is_some() {
            self.read += 1;
        }
    }

    /// Drop the segments before local index `b`, and the knots no curve from `b` on reaches
    /// ([`Knots::release_before`]): the planner will not reach back to them.
    pub fn release_before(&mut self, b: usize) {
        while self.base < b && self.window.len() > 1 {
            self.window.pop_front();
            self.base += 1;
        }
        self.knots.release_before(b);
    }

    fn entry(&self, b: usize) -> &(Segment, f64, f64, f64) {
        &self.window[b - self.base]
    }

    /// Segment `b` of the run (local index; it must have been read and not dropped).
    pub fn segment(&self, b: usize) -> &Segment {
        &self.entry(b).0
    }

    /// Start parameter of segment `b`; `b = count` is the run's end.
    pub fn sigma(&self, b: usize) -> f64 {
        if b == self.head.count {
            self.head.length
        } else {
            self.entry(b).1
        }
    }

    /// Programmed path speed of segment `b` (m/s, or rad/s for rotary-only; infinite for rapids).
    pub fn feed(&self, b: usize) -> f64 {
        self.entry(b).3
    }

    /// Local index of the segment holding parameter `s`, among those read.
    pub fn segment_at(&self, s: f64) -> usize {
        let k = self.window.partition_point(|e| e.1 <= s);
        (self.base + k).saturating_sub(1).min(self.head.count - 1)
    }

    /// [`Run::segment_at`] for an `s` at or after that of segment `b` (read and not dropped): a walk
    /// forward from `b`, for evaluations along increasing `s`.
    pub fn segment_at_from(&self, b: usize, s: f64) -> usize {
        if b < self.base || b >= self.base + self.window.len() || self.entry(b).1 > s {
            return self.segment_at(s);
        }
        let mut b = b;
        while b + 1 < self.base + self.window.len() && self.entry(b + 1).1 <= s {
            b += 1;
        }
        b.min(self.head.count - 1)
    }

    /// Read segments from `source` until the one holding parameter `s` is read; its local index.
    pub fn segment_at_reading(&mut self, s: f64, source: &mut dyn Iterator<Item = Segment>) -> usize {
        while self.read < self.head.count && self.window.back().is_none_or(|e| e.2 <= s) {
            self.read_through(self.read, source);
        }
        self.segment_at(s)
    }

    /// The curve through blocks `first..=last` of the run (local indices): through their knots and
    /// the end of `last`, fitted also through [`crate::singularity::SPLINE_OVERLAP_BLOCKS`] knots
    /// before `first`'s ([`Knots::for_fit`]).
    pub fn curve(&self, first: usize, last: usize) -> Curve<'_> {
        let last = last.min(self.head.count - 1);
        let end = self.entry(last);
        let splines = match self.head.kind {
            RunKind::Linear => SplineSet::default(),
            _ => {
                let (xs, ys): (Vec<f64>, Vec<Joints>) = self.knots.for_fit(first, last).map(|k| (k.1, k.2)).chain(std::iter::once((end.2, end.0.interpolated(true)))).unzip();
                SplineSet::natural(&xs, &ys)
            }
        };
        Curve { run: self, splines, hint: std::cell::Cell::new(0), turns: Default::default() }
    }
}

impl Curve<'_> {
    /// The splines' values at `s`: one knot search for all of them (they share their knots).
    /// Inlined: returned through memory, the values stalled their caller's loads.
    #[inline(always)]
    fn values(&self, s: f64) -> Joints {
        let i = self.splines.interval(s, self.hint.get());
        self.hint.set(i);
        self.splines.values_at(&self.splines.basis(i, s))
    }

    /// The linear axes that put the tool tip at `tip` with the rotaries at `rot`.
    fn linear_for(&self, tip: &Vector3<f64>, rot: &[f64; 2], machine: &Machine) -> Vector3<f64> {
        let mut turns = self.turns.get();
        let l = machine.chain.linear_for_along(tip, rot, &mut turns);
        self.turns.set(turns);
        l
    }

    /// Axis values at run parameter `s`.
    pub fn joints(&self, s: f64, machine: &Machine) -> Joints {
        let run = &self.run.head;
        match run.kind {
            RunKind::Linear => {
                let u = if run.length > 0.0 { (s / run.length).clamp(0.0, 1.0) } else { 1.0 };
                std::array::from_fn(|i| run.q0[i] + (run.q1[i] - run.q0[i]) * u)
            }
            RunKind::Axes => self.values(s),
            RunKind::Tcp => {
                let v = self.values(s);
                let tip = Vector3::new(v[0], v[1], v[2]);
                let rot = [v[3], v[4]];
                let l = self.linear_for(&(tip + run.datum), &rot, machine);
                [l.x, l.y, l.z, rot[0], rot[1]]
            }
            RunKind::Rotary => {
                let v = self.values(s);
                let rot = [v[3], v[4]];
                match run.tcp_tip {
                    Some(tip) => {
                        let l = self.linear_for(&(tip + run.datum), &rot, machine);
                        [l.x, l.y, l.z, rot[0], rot[1]]
                    }
                    None => [run.q0[0], run.q0[1], run.q0[2], rot[0], rot[1]],
                }
            }
        }
    }
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

/// Splits a segment stream into runs, one [`RunHead`] at a time: it reads one segment past the end of
/// each run (to see that it ends there) and holds nothing else.
#[derive(Debug)]
pub struct RunScout<I> {
    source: I,
    pending: Option<Segment>,
}

impl<I: Iterator<Item = Segment>> RunScout<I> {
    pub fn new(source: I) -> Self {
        RunScout { source, pending: None }
    }
}

impl<I: Iterator<Item = Segment>> Iterator for RunScout<I> {
    type Item = RunHead;
    fn next(&mut self) -> Option<RunHead> {
        let first = self.pending.take().or_else(|| self.source.next())?;
        let kind = run_kind(&first);
        let mut head = RunHead {
            kind,
            count: 1,
            length: 0.0 + path_length(&first),
            q0: first.q0,
            q1: first.q1,
            datum: first.datum,
            tcp_tip: (kind == RunKind::Rotary && first.kind == SegmentKind::Tcp).then_some(first.tip0),
            angular: match kind {
                RunKind::Rotary => true,
                RunKind::Linear => (0..3).all(|i| (first.q1[i] - first.q0[i]).abs() <= 1e-12) && first.length <= 1e-12,
                _ => false,
            },
            dwell: if first.kind == SegmentKind::Dwell { first.duration } else { 0.0 },
        };
        let mut prev = first;
        for seg in self.source.by_ref() {
            let angle = direction(&prev, kind).angle(&direction(&seg, kind));
            // Where a block ends in an exact stop the run ends (under exact path, where the next
            // block turns away).
            let stops = prev.stops_before(&seg, angle);
            let joins = kind != RunKind::Linear
                && run_kind(&seg) == kind
                && prev.kind == seg.kind
                && prev.datum == seg.datum
                && angle <= CORNER_DEG.to_radians()
                && !stops;
            if !joins {
                self.pending = Some(seg);
                break;
            }
            head.count += 1;
            head.length += path_length(&seg);
            head.q1 = seg.q1;
            prev = seg;
        }
        Some(head)
    }
}
