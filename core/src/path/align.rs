//! Align a measured stream (a machine's joint positions) with the program it runs, as it progresses:
//! which move of the program each sample belongs to, so that the machine stream gets the programmed
//! feed, the block numbers and the kind of move (rapid, feed, rotary-only) the program gives.
//!
//! Each move is a line in (tool tip, rotary axes) space (exact for moves with tool-centre-point
//! management, close for the others); a sample belongs to the nearest move within a window ahead of
//! the current one, and the current move only moves forward (a path that passes the same place twice is
//! matched to the earlier pass until it leaves it).
//!
//! A program's datum shift (Heidenhain's `G54 X.. Y.. Z..` datum input, `CYCL DEF 7`) may or may not
//! be in effect on the machine: the operator may have set the work offset in the control's table
//! instead, or not at all. Both frames are followed, and the one the stream has matched better so
//! far (mean squared distance) is the answer; [`Place::offset`] says which (the datum, or zero).

use super::{Segment, SegmentKind};
use crate::kinematics::Joints;
use nalgebra::Vector3;

/// Metres of tool-tip distance per radian of rotary-axis distance in the match (1 deg ~ 0.87 mm).
const ROTARY_WEIGHT: f64 = 0.05;
/// Moves looked at ahead of the current one.
const AHEAD: usize = 64;

/// Where a sample is in the program.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Place {
    /// Index of the move.
    pub segment: usize,
    /// Program line (1-based) and block number (-1 if none).
    pub line: u32,
    pub block: i64,
    /// Programmed tool-tip feed, m/s (0 for rapids and rotary-only moves).
    pub feed: f64,
    pub rapid: bool,
    /// True on a move along a path (not a rapid, not rotary-only), and on a simultaneous five-axis
    /// move (the path and the rotary axes both move).
    pub path_move: bool,
    pub five_axis: bool,
    /// The program time at the sample's place on the move, at the programmed feed, s.
    pub program_time: f64,
    /// The datum shift in effect in the frame that matches (zero where the stream's coordinates are
    /// the program's): subtract it from the stream's tool tip to get program coordinates, m.
    pub offset: Vector3<f64>,
}

/// The alignment's state for one stream.
#[derive(Debug, Clone)]
pub struct Aligner {
    segments: std::sync::Arc<Vec<Segment>>,
    /// Per frame (datum applied, not applied): the current move and the sum of squared distances.
    current: [usize; 2],
    error: [f64; 2],
}

/// Squared distance of a sample from a move, and the fraction along the move of the nearest point.
fn dist2(seg: &Segment, tip: &Vector3<f64>, q: &Joints, with_datum: bool) -> (f64, f64) {
    let d = if with_datum { seg.datum } else { Vector3::zeros() };
    let (t0, t1) = (seg.tip0 + d, seg.tip1 + d);
    let a = [t0.x, t0.y, t0.z, seg.q0[3] * ROTARY_WEIGHT, seg.q0[4] * ROTARY_WEIGHT];
    let b = [t1.x, t1.y, t1.z, seg.q1[3] * ROTARY_WEIGHT, seg.q1[4] * ROTARY_WEIGHT];
    let p = [tip.x, tip.y, tip.z, q[3] * ROTARY_WEIGHT, q[4] * ROTARY_WEIGHT];
    let (mut ab2, mut apab) = (0.0, 0.0);
    for i in 0..5 {
        ab2 += (b[i] - a[i]) * (b[i] - a[i]);
        apab += (p[i] - a[i]) * (b[i] - a[i]);
    }
    let u = if ab2 > 0.0 { (apab / ab2).clamp(0.0, 1.0) } else { 0.0 };
    ((0..5).map(|i| (p[i] - (a[i] + (b[i] - a[i]) * u)).powi(2)).sum(), u)
}

impl Aligner {
    /// An aligner over the program's moves (empty: every sample is unplaced).
    pub fn new(segments: std::sync::Arc<Vec<Segment>>) -> Aligner {
        Aligner { segments, current: [0; 2], error: [0.0; 2] }
    }

    /// Start again from the program's first move (a restarted program).
    pub fn reset(&mut self) {
        self.current = [0; 2];
        self.error = [0.0; 2];
    }

    /// True when the program's datum shift is in effect in the stream's coordinates (the better
    /// match so far).
    pub fn datum_applied(&self) -> bool {
        self.error[0] < self.error[1]
    }

    /// The move of a sample with tool tip `tip` (workpiece frame, m) and unwrapped axes `q`.
    pub fn place(&mut self, tip: &Vector3<f64>, q: &Joints) -> Option<Place> {
        let segs = &self.segments;
        if segs.is_empty() {
            return None;
        }
        let mut found = [((0.0, 0.0), 0); 2];
        for (frame, with_datum) in [(0, true), (1, false)] {
            let cur = self.current[frame];
            let end = (cur + AHEAD).min(segs.len());
            let mut best = (dist2(&segs[cur], tip, q, with_datum), cur);
            for k in cur + 1..end {
                let d = dist2(&segs[k], tip, q, with_datum);
                if d.0 < best.0 .0 {
                    best = (d, k);
                }
            }
            self.current[frame] = best.1;
            self.error[frame] += best.0 .0;
            found[frame] = best;
        }
        let frame = if self.datum_applied() { 0 } else { 1 };
        let best = found[frame];
        let seg = &segs[best.1];
        Some(Place {
            segment: best.1,
            line: u32::try_from(seg.line).unwrap_or(u32::MAX),
            block: seg.number.map_or(-1, |n| i64::try_from(n).unwrap_or(i64::MAX)),
            feed: seg.feed,
            rapid: seg.kind == SegmentKind::Rapid,
            path_move: seg.is_path_move(),
            five_axis: seg.is_five_axis(),
            program_time: seg.t0 + best.0 .1 * seg.duration,
            offset: if frame == 0 { seg.datum } else { Vector3::zeros() },
        })
    }
}
