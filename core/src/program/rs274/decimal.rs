//! Fanuc's and Haas' decimal-point rule: a length, angle or feed written without its point counts
//! least input increments.

use super::Rs274Reader;
use crate::program::interp::Word;
use crate::program::Dialect;

impl Rs274Reader {
    /// Fanuc and Haas read a number without a decimal point in a length or angle address as a count
    /// of least input increments: `X1` is 0.001 mm, 0.0001 in or 0.001 deg (FANUC B-64484EN,
    /// "Decimal point programming", parameter DPI No. 3401#0 = 0; Haas Setting 162 "Default to
    /// float" off: "X5 means X0.0005"). A value computed from parameters has its point. A machine
    /// whose file says `decimal_point_input = "calculator"` (DPI = 1) is not asked: the caller skips this.
    /// The first word read so whose value is not 0, if any (for the warning said once).
    pub(super) fn decimal_points(&self, words: &mut [Word], computed: &[usize]) -> Option<usize> {
        // Most CAM blocks write every such value with its point: then the block's codes need no look.
        let bare = |i: usize, w: &Word| computed.binary_search(&i).is_err() && !w.raw.contains('.');
        if !words.iter().enumerate().any(|(i, w)| Increment::of(w.letter).is_some() && bare(i, w)) {
            return None;
        }
        let g = |v: f64| words.iter().any(|w| w.letter == 'G' && w.value == v);
        let inch = self.inch_words(words);
        let mut first = None;
        // Q is a depth in a cycle but a mode in G05.1; K a repeat count in a cycle.
        // G06.2 (NURBS) ends a cycle: its K is a knot.
        let cycle = !g(6.2) && self.interp.cycles.active.is_some() || words.iter().any(|w| w.letter == 'G' && [73.0, 74.0, 76.0, 81.0, 82.0, 83.0, 84.0, 85.0, 86.0, 87.0, 88.0, 89.0].contains(&w.value));
        let mode_q = g(5.1);
        // G68.2's I J K are angles (Euler's), in degrees' increments whatever the length unit.
        let angles_ijk = g(68.2);
        // An inverse-time F (G93) counts thousandths: "F1 -> 0.001" (FANUC Series 16/18-C MC
        // Operator's Manual, Feed functions, inverse time feed: F code specification value FRN).
        let inverse_time = self.block_feed_mode(words).0;
        for (i, w) in words.iter_mut().enumerate() {
            let Some(kind) = Increment::of(w.letter).filter(|_| bare(i, w)) else {
                continue;
            };
            let step = match (w.letter, kind) {
                // G05.1's Q (a mode) and R (a machining condition, 1-10) are numbers, not lengths.
                ('Q' | 'R', _) if mode_q => continue,
                // (Haas counts holes with L; its G83's K is the least peck, a length.)
                ('K', _) if cycle && self.dialect != Dialect::Haas => continue,
                ('I' | 'J' | 'K', _) if angles_ijk => 1e-3,
                (_, Increment::Length) => if inch { 1e-4 } else { 1e-3 },
                (_, Increment::Angle) => 1e-3,
                (_, Increment::Feed) if inverse_time && self.dialect == Dialect::Fanuc => 1e-3,
                (_, Increment::Feed) => continue,
            };
            w.value *= step;
            if first.is_none() && w.value != 0.0 && kind != Increment::Feed {
                first = Some(i);
            }
        }
        first
    }

    /// The feed mode a block's F is read in, (inverse time G93, per revolution G95): its own G93,
    /// G94 or G95, else the modal one.
    pub(super) fn block_feed_mode(&self, words: &[Word]) -> (bool, bool) {
        let g = |v: f64| words.iter().any(|w| w.letter == 'G' && w.value == v);
        let (g93, g94, g95) = (g(93.0), g(94.0), g(95.0));
        (g93 || !g94 && !g95 && self.interp.inverse_time(), g95 || !g94 && !g93 && self.interp.per_revolution())
    }

    /// Whether a block's lengths are in inches: its own G20/G21, else the modal unit.
    pub(crate) fn inch_words(&self, words: &[Word]) -> bool {
        let g = |v: f64| words.iter().any(|w| w.letter == 'G' && w.value == v);
        if g(20.0) {
            true
        } else if g(21.0) {
            false
        } else {
            self.interp.unit() == crate::units::INCH
        }
    }
}

/// What a Fanuc or Haas address written without its decimal point counts in least input
/// increments ([`Rs274Reader::decimal_points`]): the one list of the addresses it steps.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Increment {
    Length,
    Angle,
    Feed,
}

impl Increment {
    fn of(letter: char) -> Option<Increment> {
        match letter {
            'X' | 'Y' | 'Z' | 'I' | 'J' | 'K' | 'R' | 'Q' | 'U' | 'V' | 'W' => Some(Increment::Length),
            'A' | 'B' | 'C' => Some(Increment::Angle),
            'F' => Some(Increment::Feed),
            _ => None,
        }
    }
}
