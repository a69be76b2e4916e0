//! A program run again and again, as a machine makes part after part: each pass's segments shifted
//! to start where the previous pass ended (in time and in tool-tip path), joined by a rapid from the
//! last pass's end pose back to the program's first pose (every axis linear, the slowest at its
//! rapid speed, as G00 moves). The segments come one at a time: memory is one pass's stream's, not
//! the number of passes'.

use super::segment::{rapid_duration, tip_length};
use super::{Segment, SegmentKind};
use crate::kinematics::Joints;
use crate::machine::Machine;

/// The segments of `passes` runs of a program (`None`: endless), each pass's stream opened by
/// `open` when the last one ends. A pass that cannot be opened (`open` gives `None`) ends the stream.
pub struct Passes<'m, F, I> {
    open: F,
    current: Option<I>,
    /// Passes opened so far, and how many to run.
    opened: u64,
    passes: Option<u64>,
    /// The current pass's shift in time (s) and path (m).
    shift: (f64, f64),
    /// Where the last segment handed out ends: time (s), path (m) and axes (the next pass's joining
    /// rapid starts there).
    end: Option<(f64, f64, Joints)>,
    /// The next pass's first segment, after its joining rapid.
    pending: Option<Segment>,
    machine: &'m Machine,
}

impl<'m, F: FnMut() -> Option<I>, I: Iterator<Item = Segment>> Passes<'m, F, I> {
    /// Run the segments `open` gives `passes` times (`None`: until the consumer stops).
    pub fn new(open: F, passes: Option<u64>, machine: &'m Machine) -> Self {
        Passes { open, current: None, opened: 0, passes, shift: (0.0, 0.0), end: None, pending: None, machine }
    }

    fn shifted(&self, mut seg: Segment) -> Segment {
        seg.t0 += self.shift.0;
        seg.s0 += self.shift.1;
        seg
    }

    fn hand_out(&mut self, seg: Segment) -> Option<Segment> {
        self.end = Some((seg.t0 + seg.duration, seg.s0 + seg.length, seg.q1));
        Some(seg)
    }
}

impl<F: FnMut() -> Option<I>, I: Iterator<Item = Segment>> Iterator for Passes<'_, F, I> {
    type Item = Segment;

    fn next(&mut self) -> Option<Segment> {
        if let Some(seg) = self.pending.take() {
            return self.hand_out(seg);
        }
        if let Some(cur) = self.current.as_mut() {
            if let Some(seg) = cur.next() {
                let seg = self.shifted(seg);
                return self.hand_out(seg);
            }
            self.current = None;
        }
        if self.passes.is_some_and(|n| self.opened >= n) {
            return None;
        }
        let mut next = (self.open)()?;
        self.opened += 1;
        let first = next.next()?;
        self.current = Some(next);
        let Some((t_end, s_end, q_end)) = self.end else {
            // The first pass runs as programmed.
            return self.hand_out(first);
        };
        let join = joining_rapid(q_end, &first, t_end, s_end, self.machine);
        let (t_start, s_start) = join.as_ref().map_or((t_end, s_end), |j| (j.t0 + j.duration, j.s0 + j.length));
        self.shift = (t_start - first.t0, s_start - first.s0);
        let first = self.shifted(first);
        match join {
            Some(j) => {
                self.pending = Some(first);
                self.hand_out(j)
            }
            None => self.hand_out(first),
        }
    }
}

/// The rapid from axes `q0` to where `first` starts, from time `t0` and path `s0`; `None` where
/// they are the same pose.
fn joining_rapid(q0: Joints, first: &Segment, t0: f64, s0: f64, machine: &Machine) -> Option<Segment> {
    let q1 = first.q0;
    let duration = rapid_duration(&q0, &q1, machine);
    if !(duration > 1e-12) {
        return None;
    }
    let datum = first.datum;
    let mut seg = Segment {
        kind: SegmentKind::Rapid,
        block: first.block,
        line: first.line,
        number: first.number,
        t0,
        duration,
        s0,
        length: 0.0,
        q0,
        q1,
        tip0: machine.forward(&q0).tip - datum,
        tip1: machine.forward(&q1).tip - datum,
        datum,
        feed: 0.0,
        arc: None,
        orient: None,
        tolerance: first.tolerance,
        path: false,
        exact: crate::program::Exact::Blend,
    };
    seg.length = tip_length(&seg, machine);
    seg.feed = seg.length / duration;
    Some(seg)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::path::{PathOptions, Trajectory};
    use crate::program::{self, Dialect};

    /// SING.I's segments, with the stream's interface (`segments` opens them again each call).
    struct Moves(Trajectory);

    impl Moves {
        fn segments<'a>(&'a self, _: &Machine) -> Result<impl Iterator<Item = Segment> + 'a, ()> {
            Ok(self.0.segments.iter().cloned())
        }
    }

    fn sing() -> (Machine, Moves) {
        let m = Machine::hermle_c600u();
        let text = program::BUNDLED.iter().find(|(n, _)| *n == "SING.I").expect("SING.I").1;
        let p = program::read(text, Dialect::Heidenhain, "SING.I", &Default::default());
        let traj = Trajectory::from_program(&p, &m, &PathOptions::default());
        assert!(traj.diagnostics.is_empty() && !traj.segments.is_empty());
        (m, Moves(traj))
    }

    #[test]
    fn passes_follow_each_other_joined_by_a_rapid() {
        let (m, moves) = sing();
        let once: Vec<Segment> = moves.segments(&m).unwrap().collect();
        let three: Vec<Segment> = Passes::new(|| moves.segments(&m).ok(), Some(3), &m).collect();
        let (first, last) = (once.first().unwrap(), once.last().unwrap());
        // A program that ends away from where it starts gets a joining rapid between passes.
        assert!((0..5).any(|i| (first.q0[i] - last.q1[i]).abs() > 1e-6));
        assert_eq!(three.len(), 3 * once.len() + 2);
        // Continuous in time, path and axes, segment to segment.
        for w in three.windows(2) {
            assert!((w[0].t0 + w[0].duration - w[1].t0).abs() < 1e-9, "time gap at t = {}", w[1].t0);
            assert!((w[0].s0 + w[0].length - w[1].s0).abs() < 1e-9);
            assert!((0..5).all(|i| (w[0].q1[i] - w[1].q0[i]).abs() < 1e-12));
        }
        // Each pass is the program again, shifted.
        let pass2 = &three[once.len() + 1..2 * once.len() + 1];
        let shift = pass2[0].t0 - first.t0;
        for (a, b) in once.iter().zip(pass2) {
            assert_eq!((a.q0, a.q1, a.line, a.kind), (b.q0, b.q1, b.line, b.kind));
            assert!((b.t0 - a.t0 - shift).abs() < 1e-9 && (b.duration - a.duration).abs() < 1e-15);
        }
        // The joining rapid takes as long as its slowest axis at rapid speed.
        let j = &three[once.len()];
        assert_eq!(j.kind, SegmentKind::Rapid);
        let slowest = (0..5).map(|i| (j.q1[i] - j.q0[i]).abs() / m.axes[i].limits.velocity).fold(0.0, f64::max);
        assert!((j.duration - slowest).abs() < 1e-12 && j.duration > 0.0);
    }

    #[test]
    fn endless_passes_run_until_the_consumer_stops_and_a_failed_open_ends_them() {
        let (m, moves) = sing();
        let n = moves.segments(&m).unwrap().count();
        assert_eq!(Passes::new(|| moves.segments(&m).ok(), None, &m).take(10 * n).count(), 10 * n);
        let mut opens = 0;
        let two = Passes::new(
            || {
                opens += 1;
                (opens <= 2).then(|| moves.segments(&m).unwrap())
            },
            None,
            &m,
        )
        .count();
        assert_eq!(two, 2 * n + 1);
    }
}
