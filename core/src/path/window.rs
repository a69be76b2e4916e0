//! A trajectory as a stream: segments pulled from their source (a program being read, or a list) as
//! the consumer reaches them and dropped once it is past them, and the samples on the period's grid
//! made from them one at a time. Memory holds the window a consumer asks for (its stencil or
//! look-ahead), not the program.

use super::{PathOptions, Sample, Segment, SegmentPlanner};
use crate::program::{BlockStream, Diagnostic, DiagnosticLog};
use crate::kinematics::SinCos;
use crate::machine::Machine;
use std::borrow::Cow;
use std::collections::VecDeque;

/// The segments `base..base + len` of a stream, loaded on demand.
#[derive(Debug)]
pub struct SegmentWindow<I> {
    source: I,
    buf: VecDeque<Segment>,
    base: usize,
    ended: bool,
}

impl<I: Iterator<Item = Segment>> SegmentWindow<I> {
    pub fn new(source: I) -> Self {
        SegmentWindow { source, buf: VecDeque::new(), base: 0, ended: false }
    }

    /// Segment `i`, reading up to it if needed; `None` past the end or if already dropped.
    pub fn get(&mut self, i: usize) -> Option<&Segment> {
        while !self.ended && self.base + self.buf.len() <= i {
            match self.source.next() {
                Some(s) => self.buf.push_back(s),
                None => self.ended = true,
            }
        }
        i.checked_sub(self.base).and_then(|k| self.buf.get(k))
    }

    /// How many segments are held.
    pub fn held(&self) -> usize {
        self.buf.len()
    }

    /// Segment `i` if it is loaded (no reading).
    pub fn loaded(&self, i: usize) -> Option<&Segment> {
        i.checked_sub(self.base).and_then(|k| self.buf.get(k))
    }

    /// Drop the segments before `i`: no consumer will ask for them again.
    pub fn release_before(&mut self, i: usize) {
        while self.base < i && !self.buf.is_empty() {
            self.buf.pop_front();
            self.base += 1;
        }
    }
}

/// The samples of a segment stream on the global grid `t = k * period`, plus the final end point
/// (as [`super::Trajectory::samples`]), made one at a time from a [`SegmentWindow`].
#[derive(Debug, Clone, Default)]
pub struct GridSampler {
    period: f64,
    i: usize,
    k: u64,
    ended: bool,
    /// The rotaries' sines and cosines, which follow the samples.
    turns: [SinCos; 2],
}

impl GridSampler {
    pub fn new(period: f64) -> Self {
        GridSampler { period, i: 0, k: 0, ended: false, turns: Default::default() }
    }

    /// The next sample, reading segments from `window` as it goes.
    pub fn next<I: Iterator<Item = Segment>>(&mut self, window: &mut SegmentWindow<I>, machine: &Machine) -> Option<Sample> {
        while let Some(seg) = window.get(self.i) {
            let t = self.k as f64 * self.period;
            if t >= seg.t0 + seg.duration {
                self.i += 1;
                continue;
            }
            let u = ((t - seg.t0) / seg.duration).clamp(0.0, 1.0);
            self.k += 1;
            return Some(seg.sample_along(self.i, u, t, machine, &mut self.turns));
        }
        if self.ended {
            return None;
        }
        self.ended = true;
        let last = self.i.checked_sub(1)?;
        window.loaded(last).map(|seg| seg.sample_along(last, 1.0, seg.t0 + seg.duration, machine, &mut self.turns))
    }
}

/// The segments of a program as it is read: blocks from a [`BlockStream`], planned one at a time
/// ([`SegmentPlanner`]). Planning diagnostics are collected as it goes.
#[derive(Debug)]
pub struct SegmentStream<'m> {
    machine: Cow<'m, Machine>,
    blocks: BlockStream,
    planner: SegmentPlanner,
    out: VecDeque<Segment>,
    buf: Vec<Segment>,
    diags: Vec<Diagnostic>,
    log: DiagnosticLog,
    block: usize,
    stopped: bool,
}

impl<'m> SegmentStream<'m> {
    pub fn new(blocks: BlockStream, machine: &'m Machine, options: &PathOptions) -> Self {
        Self::with(blocks, Cow::Borrowed(machine), options)
    }

    fn with(blocks: BlockStream, machine: Cow<'m, Machine>, options: &PathOptions) -> Self {
        let planner = SegmentPlanner::new(&machine, blocks.dialect(), options);
        SegmentStream { machine, blocks, planner, out: VecDeque::new(), buf: Vec::new(), diags: Vec::new(), log: DiagnosticLog::default(), block: 0, stopped: false }
    }

    /// A stream that owns its machine (a copy), for a consumer that outlives the caller's.
    pub fn owned(blocks: BlockStream, machine: Machine, options: &PathOptions) -> SegmentStream<'static> {
        SegmentStream::with(blocks, Cow::Owned(machine), options)
    }

    /// The blocks read so far (and, once ended, the reader's diagnostics).
    pub fn blocks(&self) -> &BlockStream {
        &self.blocks
    }

    /// Read the rest of the program without planning it (after planning stopped at the bound on the
    /// program's duration): its blocks are counted and its defects reported all the same.
    pub fn read_to_end(&mut self) {
        for _ in self.blocks.by_ref() {}
    }

    /// What planning reported so far (unreachable poses, axes the machine lacks, the duration bound).
    pub fn diagnostics(&self) -> &DiagnosticLog {
        &self.log
    }

    /// Errors so far, the reader's and the planning's.
    pub fn errors(&self) -> usize {
        self.blocks.diagnostics().errors() + self.log.errors()
    }
}

impl Iterator for SegmentStream<'_> {
    type Item = Segment;
    fn next(&mut self) -> Option<Segment> {
        while self.out.is_empty() && !self.stopped {
            let Some(b) = self.blocks.next() else { break };
            if !self.planner.push(&self.machine, self.block, &b, &mut self.buf, &mut self.diags) {
                self.stopped = true;
            }
            self.block += 1;
            self.out.extend(self.buf.drain(..));
            for d in self.diags.drain(..) {
                self.log.push(d);
            }
        }
        self.out.pop_front()
    }
}
