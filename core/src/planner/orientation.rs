//! Orientation smoothing of the planner's input, as a control with vector orientation interpolation
//! does within a tolerance (Sinumerik's orientation smoothing ORISON/OST, Heidenhain's TA): the tool
//! axis of a chain of great-circle moves (`--orientation great-circle`) follows a C2 spline through
//! programmed directions, not the chain of great circles with a kink at every block end. Near the
//! pole the secondary axis turns at `1/sin A` times the orientation rate (seed 001), so a kink of a
//! hundredth of a degree, or the rounding of a CAM system's tool vectors, becomes a jerk spike in C
//! that the planner can only meet by crawling; the smoothed axis turns C as the surface's own
//! orientation does, whether the CAM system wrote a block every 0.01 mm or every 1 mm.
//!
//! The spline's knots are programmed directions: block ends at most every [`KNOT_SPACING_M`] of the
//! tool-tip path (closer block ends are the CAM system's sampling of one smooth orientation), the
//! ends of a chain, the ends of blocks that turn the tool axis by more than [`KNOT_RAD`] and points
//! on their great circles every [`KNOT_RAD`]. Every other piece end moves onto the spline, if the
//! spline stays within [`ORIENT_TOL_RAD`] of the block's great circle there (else that block keeps
//! its great circle). Each block is fitted through [`SMOOTH_KNOTS`] knots each side: a natural
//! spline's response to a knot decays by about 0.27 per knot, so neighbouring blocks' fits agree to
//! ~1e-9, and memory holds those knots' blocks (at most [`MAX_BUFFERED_PIECES`] pieces).

use crate::kinematics::Joints;
use crate::machine::Machine;
use crate::path::{Segment, SegmentKind};
use crate::singularity::CubicSpline;
use nalgebra::Vector3;
use std::collections::VecDeque;

/// Knots each side of a block that its orientation spline is fitted through.
pub const SMOOTH_KNOTS: usize = 16;

/// Largest angle between the smoothed tool axis and the programmed great circle, rad (0.05 deg, the
/// order of a finishing program's orientation tolerance, e.g. Sinumerik's `OTOL`).
pub const ORIENT_TOL_RAD: f64 = 0.05 * std::f64::consts::PI / 180.0;

/// Largest great-circle angle between two knots inside one block, rad: a block that turns the tool
/// axis further keeps knots on its own great circle every so often, so that the spline follows it.
pub const KNOT_RAD: f64 = 2.0 * std::f64::consts::PI / 180.0;

/// Shortest tool-tip path between knots at block ends, m (0.5 mm, ASSUMED: a finishing program
/// samples the surface every 0.05-0.5 mm): of block ends closer together, one per this length is a
/// knot (the first after each multiple of it).
pub const KNOT_SPACING_M: f64 = 0.5e-3;

/// Most pieces held for the spline's reach ahead and behind: a chain of smaller blocks is fitted
/// with fewer knots ahead (its far end treated as the chain's end).
pub const MAX_BUFFERED_PIECES: usize = 1 << 18;

/// One block of pieces (consecutive segments of one program block).
struct Block {
    pieces: Vec<Segment>,
    /// Global block count (fits are reused between blocks with the same knots), and the chain of
    /// smoothed blocks it belongs to (`None` if it is not smoothed).
    index: u64,
    chain: Option<u64>,
    /// Tool-tip path length and programmed tool axis at the block's start and end; the great-circle
    /// angle of the whole move.
    start: (f64, Vector3<f64>),
    end: (f64, Vector3<f64>),
    angle: f64,
    datum: Vector3<f64>,
    /// Knots at this block's piece starts (`start_knot`: its start is one), and the chain's knots up
    /// to and including these.
    knots: Vec<(f64, Vector3<f64>)>,
    start_knot: bool,
    cum: usize,
    /// The start, moved onto the previous block's spline (it is that block's end).
    moved_start: Option<Joints>,
}

impl Block {
    /// The block's ends and angle, if it is a TCPM feed move whose tool axis turns on a great
    /// circle, every piece with a tool-tip length (the spline's parameter).
    fn new(pieces: Vec<Segment>, index: u64) -> Block {
        let first = &pieces[0];
        let mut b = Block {
            index,
            chain: None,
            start: (first.s0, Vector3::zeros()),
            end: (first.s0, Vector3::zeros()),
            angle: 0.0,
            datum: first.datum,
            knots: Vec::new(),
            start_knot: false,
            cum: 0,
            moved_start: None,
            pieces,
        };
        let smooth = b.pieces.iter().all(|p| p.kind == SegmentKind::Tcp && p.length > 1e-9 && p.orient.is_some());
        if let (true, Some(gc0), Some(last)) = (smooth, b.pieces[0].orient.as_deref(), b.pieces.last()) {
            let gc1 = last.orient.as_deref().expect("checked: every piece has one");
            b.start.1 = gc0.axis(0.0);
            b.end = (last.s0 + last.length, gc1.axis(1.0));
            b.angle = gc0.angle;
            b.chain = Some(0);
        }
        b
    }

    /// True if `next` continues this block's chain: both smoothed, the path length and the tool axis
    /// continuous where they meet, the same datum.
    fn joins(&self, next: &Block) -> bool {
        self.chain.is_some()
            && next.chain.is_some()
            && (next.start.0 - self.end.0).abs() <= 1e-9
            && (next.start.1 - self.end.1).norm() <= 1e-9
            && self.datum == next.datum
    }

    /// Set the block's knots and chain, after `prev` if it joins it.
    fn place(&mut self, prev: Option<&Block>, next_chain: &mut u64) {
        if self.chain.is_none() {
            return;
        }
        let prev = prev.filter(|p| p.joins(self));
        self.chain = Some(match prev {
            Some(p) => p.chain.expect("joined"),
            None => {
                *next_chain += 1;
                *next_chain
            }
        });
        self.start_knot = match prev {
            None => true,
            Some(p) => self.angle > KNOT_RAD || p.angle > KNOT_RAD || (self.start.0 / KNOT_SPACING_M).floor() > (p.start.0 / KNOT_SPACING_M).floor(),
        };
        if self.start_knot {
            self.knots.push(self.start);
        }
        if self.angle > KNOT_RAD {
            // Knots on the great circle every KNOT_RAD: at the start of the piece holding each.
            let m = (self.angle / KNOT_RAD).ceil();
            for p in &self.pieces[1..] {
                let gc = p.orient.as_deref().expect("a smoothed block's pieces are great-circle pieces");
                if (gc.u0 * m).ceil() < gc.u1 * m {
                    self.knots.push((p.s0, gc.axis(0.0)));
                }
            }
        }
        self.cum = prev.map_or(0, |p| p.cum) + self.knots.len();
    }
}

/// The planner's segments with the tool axis of great-circle chains smoothed ([module docs](self)).
/// Segments of other moves pass unchanged.
pub struct OrientationSmoother<'m, I: Iterator<Item = Segment>> {
    source: std::iter::Peekable<I>,
    machine: &'m Machine,
    /// Blocks from the first the next fits reach back to; the block to smooth next is at `next`,
    /// those after it are read ahead. `pieces` counts the pieces held.
    blocks: VecDeque<Block>,
    next: usize,
    pieces: usize,
    read: u64,
    chains: u64,
    ended: bool,
    /// The last fit: the global indices of its first and last block and whether it ends at its
    /// chain's end, with its splines.
    fit: Option<((u64, u64, bool), [CubicSpline; 3])>,
    /// Pieces of the last smoothed block, being handed out.
    out: std::vec::IntoIter<Segment>,
}

impl<'m, I: Iterator<Item = Segment>> OrientationSmoother<'m, I> {
    pub fn new(source: I, machine: &'m Machine) -> Self {
        OrientationSmoother {
            source: source.peekable(),
            machine,
            blocks: VecDeque::new(),
            next: 0,
            pieces: 0,
            read: 0,
            chains: 0,
            ended: false,
            fit: None,
            out: Vec::new().into_iter(),
        }
    }

    /// Read the next block (consecutive segments of one program block); false at the end.
    fn read_block(&mut self) -> bool {
        let Some(first) = self.source.next() else {
            self.ended = true;
            return false;
        };
        let block = first.block;
        let mut pieces = vec![first];
        while let Some(p) = self.source.next_if(|p| p.block == block) {
            pieces.push(p);
        }
        self.pieces += pieces.len();
        let mut b = Block::new(pieces, self.read);
        self.read += 1;
        b.place(self.blocks.back(), &mut self.chains);
        self.blocks.push_back(b);
        true
    }

    /// True if block `k` continues into block `k + 1` (both held).
    fn continues(&self, k: usize) -> bool {
        k + 1 < self.blocks.len() && self.blocks[k].chain.is_some() && self.blocks[k].chain == self.blocks[k + 1].chain
    }

    /// Read until the block at `next` has SMOOTH_KNOTS knots of its chain ahead, or its chain or the
    /// program has ended, or the buffer is full.
    fn read_ahead(&mut self) {
        loop {
            let n = self.blocks.len();
            if n > self.next {
                let (k, last) = (&self.blocks[self.next], &self.blocks[n - 1]);
                let open = k.chain.is_some() && last.chain == k.chain;
                if !open || last.cum - k.cum > SMOOTH_KNOTS || self.pieces >= MAX_BUFFERED_PIECES {
                    return;
                }
            }
            if !self.read_block() {
                return;
            }
        }
    }

    /// Smooth block `k` with the knots of its chain neighbours.
    fn smooth(&mut self, k: usize) -> Vec<Segment> {
        let mut pieces = std::mem::take(&mut self.blocks[k].pieces);
        self.pieces -= pieces.len();
        if let Some(q) = self.blocks[k].moved_start.take() {
            pieces[0].q0 = q;
        }
        let Some(chain) = self.blocks[k].chain else { return pieces };
        // The window: SMOOTH_KNOTS knots before the block's start and after its end, within the chain.
        let before = self.blocks[k].cum - self.blocks[k].knots.len();
        let mut lo = k;
        while lo > 0 && self.blocks[lo - 1].chain == Some(chain) && before - (self.blocks[lo - 1].cum - self.blocks[lo - 1].knots.len()) <= SMOOTH_KNOTS {
            lo -= 1;
        }
        let mut hi = k;
        while self.continues(hi) && self.blocks[hi].cum - self.blocks[k].cum <= SMOOTH_KNOTS {
            hi += 1;
        }
        // The chain's end is a knot; so is the start of the block after k if it is one.
        let chain_end = !self.continues(hi) && (hi + 1 < self.blocks.len() || self.ended);
        let end_knot = if self.continues(k) { self.blocks[k + 1].start_knot } else { true };
        let key = (self.blocks[lo].index, self.blocks[hi].index, chain_end);
        if self.fit.as_ref().is_none_or(|f| f.0 != key) {
            let mut knots: Vec<(f64, Vector3<f64>)> = (lo..=hi).flat_map(|b| self.blocks[b].knots.iter().copied()).collect();
            if chain_end {
                knots.push(self.blocks[hi].end);
            }
            if knots.len() < 2 {
                self.fit = None;
                return pieces;
            }
            let s: Vec<f64> = knots.iter().map(|k| k.0).collect();
            let splines = std::array::from_fn(|i| CubicSpline::natural(&s, &knots.iter().map(|k| k.1[i]).collect::<Vec<_>>()));
            self.fit = Some((key, splines));
        }
        let splines = &self.fit.as_ref().expect("just fitted").1;
        let own = &self.blocks[k].knots;
        // The new piece ends (each piece's start after the first, then the block's end), unless the
        // spline leaves the tolerance: then the block keeps its great circle.
        let machine = self.machine;
        let place = |s: f64, programmed: Vector3<f64>, seed: &Joints, tip: Vector3<f64>| -> Option<Joints> {
            let v = Vector3::from_fn(|i, _| splines[i].value(s));
            let n = v.norm();
            if !(n > 0.5) || (v / n).angle(&programmed) > ORIENT_TOL_RAD {
                return None;
            }
            let rot = machine.rotaries_near(&(v / n), &[seed[3], seed[4]])?;
            let l = machine.chain.linear_for(&tip, &rot);
            Some([l.x, l.y, l.z, rot[0], rot[1]])
        };
        let mut moved = Vec::with_capacity(pieces.len());
        for p in &pieces[1..] {
            if own.iter().any(|kn| kn.0 == p.s0) {
                moved.push(None);
                continue;
            }
            let gc = p.orient.as_deref().expect("a smoothed block's pieces are great-circle pieces");
            match place(p.s0, gc.axis(0.0), &p.q0, p.tip0 + p.datum) {
                Some(q) => moved.push(Some(q)),
                None => return pieces,
            }
        }
        let end = match (end_knot, pieces.last()) {
            (false, Some(p)) => match place(p.s0 + p.length, self.blocks[k].end.1, &p.q1, p.tip1 + p.datum) {
                Some(q) => Some(q),
                None => return pieces,
            },
            _ => None,
        };
        for (j, q) in moved.into_iter().enumerate() {
            if let Some(q) = q {
                pieces[j].q1 = q;
                pieces[j + 1].q0 = q;
            }
        }
        if let (Some(q), Some(p)) = (end, pieces.last_mut()) {
            p.q1 = q;
            self.blocks[k + 1].moved_start = Some(q);
        }
        // Between its (new) ends a piece turns the rotaries linearly: the tool axis no longer follows
        // the programmed great circle.
        for p in &mut pieces {
            p.orient = None;
        }
        pieces
    }
}

impl<I: Iterator<Item = Segment>> Iterator for OrientationSmoother<'_, I> {
    type Item = Segment;

    fn next(&mut self) -> Option<Segment> {
        loop {
            if let Some(p) = self.out.next() {
                return Some(p);
            }
            self.read_ahead();
            if self.next >= self.blocks.len() {
                return None;
            }
            let pieces = self.smooth(self.next);
            self.next += 1;
            // Keep the blocks behind that the next fit reaches back to (their knots; their pieces are
            // handed out): SMOOTH_KNOTS + 1 knots of the chain.
            while self.next > 0 {
                let (front, cur) = (&self.blocks[0], self.blocks.get(self.next));
                let needed = cur.is_some_and(|c| c.chain.is_some() && c.chain == front.chain && (c.cum - c.knots.len()) - (front.cum - front.knots.len()) <= SMOOTH_KNOTS + 1);
                if needed {
                    break;
                }
                self.blocks.pop_front();
                self.next -= 1;
            }
            self.out = pieces.into_iter();
        }
    }
}
