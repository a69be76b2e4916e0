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

use super::{Segment, SegmentKind, SegmentWindow};
use crate::kinematics::Joints;
use nalgebra::Vector3;
use std::sync::Arc;

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

/// Opens the program's moves from the start, for an aligner to read as it goes (and again after a
/// restart): the segments as a stream, or why they cannot be read.
pub type OpenSegments = Arc<dyn Fn() -> Result<Box<dyn Iterator<Item = Segment> + Send>, String> + Send + Sync>;

/// The opener of moves already held (each opening reads them from the first).
pub fn open_held(segments: Arc<Vec<Segment>>) -> OpenSegments {
    Arc::new(move || {
        let s = segments.clone();
        Ok(Box::new((0..s.len()).map(move |i| s[i].clone())) as Box<dyn Iterator<Item = Segment> + Send>)
    })
}

/// The most moves held: from the lagging frame's move to [`AHEAD`] past the leading one's. A frame
/// the stream does not follow is moved up to stay within it.
const HELD: usize = 16 * AHEAD;

/// The alignment's state for one stream: a window of the program's moves read as the stream
/// advances (memory does not grow with the program).
pub struct Aligner {
    open: OpenSegments,
    window: Option<SegmentWindow<Box<dyn Iterator<Item = Segment> + Send>>>,
    failed: Option<String>,
    /// Per frame (datum applied, not applied): the current move and the sum of squared distances.
    current: [usize; 2],
    error: [f64; 2],
}

impl std::fmt::Debug for Aligner {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Aligner").field("current", &self.current).field("error", &self.error).field("failed", &self.failed).finish()
    }
}

/// The frame with the datum applied matches better (sums of squared distances: with, without).
fn datum_matches_better(error: &[f64; 2]) -> bool {
    error[0] < error[1]
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
    /// An aligner over the moves `open` reads (opened at the first sample, and again after a reset).
    pub fn new(open: OpenSegments) -> Aligner {
        Aligner { open, window: None, failed: None, current: [0; 2], error: [0.0; 2] }
    }

    /// Why the program's moves could not be read again (no sample is placed then).
    pub fn failure(&self) -> Option<&str> {
        self.failed.as_deref()
    }

    /// Start again from the program's first move (a restarted program).
    pub fn reset(&mut self) {
        self.current = [0; 2];
        self.error = [0.0; 2];
        self.window = None;
        self.failed = None;
    }

    /// True when the program's datum shift is in effect in the stream's coordinates (the better
    /// match so far).
    pub fn datum_applied(&self) -> bool {
        datum_matches_better(&self.error)
    }

    /// The move of a sample with tool tip `tip` (workpiece frame, m) and unwrapped axes `q`.
    pub fn place(&mut self, tip: &Vector3<f64>, q: &Joints) -> Option<Place> {
        if self.window.is_none() && self.failed.is_none() {
            match (self.open)() {
                Ok(segments) => self.window = Some(SegmentWindow::new(segments)),
                Err(e) => self.failed = Some(e),
            }
        }
        let segs = self.window.as_mut()?;
        let lead = self.current[0].max(self.current[1]);
        for c in &mut self.current {
            *c = (*c).max(lead.saturating_sub(HELD - AHEAD));
        }
        let mut found = [((0.0, 0.0), 0); 2];
        for (frame, with_datum) in [(0, true), (1, false)] {
            let cur = self.current[frame];
            let mut best = (dist2(segs.get(cur)?, tip, q, with_datum), cur);
            for k in cur + 1..cur + AHEAD {
                let Some(seg) = segs.get(k) else { break };
                let d = dist2(seg, tip, q, with_datum);
                if d.0 < best.0 .0 {
                    best = (d, k);
                }
            }
            self.current[frame] = best.1;
            self.error[frame] += best.0 .0;
            found[frame] = best;
        }
        segs.release_before(self.current[0].min(self.current[1]));
        let frame = if datum_matches_better(&self.error) { 0 } else { 1 };
        let best = found[frame];
        let seg = segs.loaded(best.1)?;
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::machine::Machine;
    use crate::path::{PathOptions, SegmentStream};
    use crate::program::{BlockStream, Dialect, ReadOptions};
    use std::sync::atomic::{AtomicUsize, Ordering};

    /// A CL raster line of `n` poses 0.02 mm apart along x, the tool tilted and turning slowly
    /// (five-axis moves).
    fn program(n: usize) -> String {
        (0..n)
            .map(|i| {
                let (x, tilt, turn) = (i as f64 * 0.02, 0.3 + 0.1 * (i as f64 * 0.01).sin(), i as f64 * 1e-3);
                format!("{x} 0 0 {} {} {} 1000\n", tilt.sin() * turn.cos(), tilt.sin() * turn.sin(), tilt.cos())
            })
            .collect()
    }

    fn stream(text: &str, machine: &Machine) -> SegmentStream<'static> {
        SegmentStream::owned(
            BlockStream::from_text(text, Some(Dialect::Cl), "raster", &ReadOptions::default()),
            machine.clone(),
            &PathOptions::default(),
        )
    }

    #[test]
    fn a_stream_is_placed_move_by_move_holding_a_window_and_read_again_after_a_reset() {
        let machine = Machine::hermle_c600u();
        let text: Arc<str> = program(5000).into();
        let mut all = stream(&text, &machine);
        let reference: Vec<Segment> = all.by_ref().collect();
        assert_eq!((reference.len(), all.errors()), (4999, 0));
        let opens = Arc::new(AtomicUsize::new(0));
        let open: OpenSegments = {
            let (opens, text, machine) = (opens.clone(), text.clone(), machine.clone());
            Arc::new(move || {
                opens.fetch_add(1, Ordering::SeqCst);
                Ok(Box::new(stream(&text, &machine)) as Box<dyn Iterator<Item = Segment> + Send>)
            })
        };
        let mut aligner = Aligner::new(open);
        let mut most_held = 0;
        for (k, seg) in reference.iter().enumerate() {
            let q = seg.joints_at(0.5, &machine);
            let tip = machine.forward(&q).tip - seg.datum;
            let place = aligner.place(&tip, &q).expect("placed");
            assert_eq!((place.segment, place.line), (k, u32::try_from(seg.line).unwrap()), "move {k}");
            assert!((place.program_time - (seg.t0 + 0.5 * seg.duration)).abs() < 1e-9);
            most_held = most_held.max(aligner.window.as_ref().map_or(0, |w| w.held()));
        }
        // The window: the move being matched and the look-ahead past it, not the program.
        assert!((AHEAD..=HELD).contains(&most_held), "held {most_held} moves");
        assert_eq!(opens.load(Ordering::SeqCst), 1);
        aligner.reset();
        let q = reference[0].joints_at(0.5, &machine);
        assert_eq!(aligner.place(&(machine.forward(&q).tip), &q).map(|p| p.segment), Some(0));
        assert_eq!(opens.load(Ordering::SeqCst), 2, "a restart reads the program again");
    }

    #[test]
    fn a_program_that_cannot_be_read_again_places_nothing_and_says_why() {
        let mut aligner = Aligner::new(Arc::new(|| Err("prog.cl: No such file or directory".to_string())));
        assert_eq!(aligner.place(&Vector3::zeros(), &[0.0; 5]), None);
        assert_eq!(aligner.failure(), Some("prog.cl: No such file or directory"));
        assert_eq!(Aligner::new(open_held(Arc::new(Vec::new()))).place(&Vector3::zeros(), &[0.0; 5]), None);
    }
}
