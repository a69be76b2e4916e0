//! A Heidenhain TNC's tool radius compensation in its DIN/ISO programs: `G41` (left), `G42`
//! (right) until `G40`, the ISO names of Klartext's `RL`/`RR`/`R0`, with the same rules
//! ([`super::cutter_comp::TncComp`], from the TNC 620 ISO user's manual 340 56x-02 pp. 146, 154):
//! compensation starts in a straight-line block (`G00`/`G01`), the tool ending it perpendicular to
//! the contour's first element; a change of side needs a `G40` block between; `G40` in a straight
//! line leaves the last element perpendicular at its end. The radius is the called tool's (`T5
//! G17`), R + DR in the tool table (`--tool-table`).
//!
//! While it is on, what would move the contour's frame, tool or machine is refused, as the Klartext
//! reader refuses it: a tool call, the plane (`G17`-`G19`), a datum shift (`G54`), machine
//! coordinates (`M91`/`M92`), M128, cycle calls (`G79`, `M99`, `M89`); a contour the tool cannot
//! follow stops the program there ("Tool radius too large").

use super::cutter_comp::{tnc_diameter, tnc_radius, tnc_said, Fail, Side, TncComp};
use super::heidenhain::DinReader;
use super::interp::Word;
use super::lex::Diags;
use super::{Block, Motion};

/// Compensation beside the DIN/ISO reader: the path held, the tool called, a stop.
#[derive(Debug, Clone, Default)]
pub(crate) struct DinComp {
    engine: TncComp,
    /// The tool of the last tool call (`T5 G17`), whose radius `G41`/`G42` take.
    tool: Option<u32>,
    /// Compensation stopped the program at this line: nothing after it runs (said once: `said`).
    pub(crate) stopped: Option<usize>,
    pub(crate) said: bool,
}

/// `G40` (`None`), `G41`, `G42` taken out of a block's words, and the column; two of them in one
/// block are refused (which one the TNC takes is not read).
pub(crate) fn take_codes(words: &mut Vec<Word<'_>>) -> Result<Option<(Option<Side>, usize)>, usize> {
    let mut code = None;
    let mut second = None;
    words.retain(|w| {
        let side = match (w.letter, w.value) {
            ('G', g) if g == 40.0 => None,
            ('G', g) if g == 41.0 => Some(Side::Left),
            ('G', g) if g == 42.0 => Some(Side::Right),
            _ => return true,
        };
        if code.is_some() {
            second = second.or(Some(w.column));
        }
        code = Some((side, w.column));
        false
    });
    match second {
        Some(col) => Err(col),
        None => Ok(code),
    }
}

impl DinComp {
    /// Compensation on, or blocks held.
    pub(crate) fn busy(&self) -> bool {
        self.engine.busy()
    }

    /// A block's tool call: `T` without `G99` (which defines a tool).
    pub(crate) fn track(&mut self, words: &[Word<'_>]) {
        let defines = words.iter().any(|w| w.letter == 'G' && w.value == 99.0);
        if let Some(t) = words.iter().find(|w| w.letter == 'T').filter(|_| !defines) {
            self.tool = (t.value >= 0.0 && t.value.fract() == 0.0 && t.value <= u32::MAX as f64).then_some(t.value as u32);
        }
    }
}

/// What a block may not hold while compensation is on (or in the block that starts it): its column
/// and what it is.
fn refused_under_comp(words: &[Word<'_>]) -> Option<(usize, &'static str)> {
    words.iter().find_map(|w| {
        let what = match (w.letter, w.value) {
            ('T', _) => "a tool call",
            ('G', g) if g == 17.0 || g == 18.0 || g == 19.0 => "a working plane (G17-G19)",
            ('G', g) if g == 54.0 => "a datum shift (G54)",
            ('G', g) if g == 79.0 => "a cycle call (G79)",
            ('M', m) if m == 91.0 || m == 92.0 => "M91/M92 machine coordinates",
            ('M', m) if m == 99.0 || m == 89.0 => "a cycle call (M99/M89)",
            ('M', m) if m == 128.0 => "M128",
            _ => return None,
        };
        Some((w.column, what))
    })
}

impl DinReader {
    /// A block while compensation is on, or the one that starts it (`code`: its `G40`/`G41`/`G42`
    /// taken out): checked, run, its move through compensation. False if it is refused.
    pub(crate) fn compensated(&mut self, words: &[Word<'_>], code: Option<(Option<Side>, usize)>, line: usize, col: usize, number: Option<u64>, out: &mut Vec<Block>, diags: &mut Diags) -> bool {
        let refuse = |diags: &mut Diags, c: usize, why: String| {
            diags.error(line, c, why);
            false
        };
        if let Some((c, what)) = refused_under_comp(words) {
            // M91/M92's machine coordinates were set up for this block, which does not run.
            self.interp.oneshot = None;
            return refuse(diags, c, format!("{what} with radius compensation G41/G42 on is not read: end the compensation with a G40 block before it"));
        }
        if self.out_of_order {
            return refuse(diags, col, "radius compensation in a program whose block numbers are out of order is not read (the blocks' order decides the corners)".into());
        }
        let motion =
            words.iter().rev().find(|w| w.letter == 'G' && matches!(w.value as i64, 0..=3 | 5 | 6 | 10..=16) && w.value.fract() == 0.0).map_or(self.interp.feed_state().0, |w| match w.value as i64 {
                0 | 10 => Some(Motion::Rapid),
                1 | 11 => Some(Motion::Linear),
                _ => Some(Motion::ArcCw),
            });
        let straight = matches!(motion, Some(Motion::Rapid | Motion::Linear));
        let unit = self.interp.unit();
        let tilt = self.interp.tilt();
        let on = self.comp.engine.side();
        match (on, code) {
            (None, Some((Some(side), c))) => {
                if self.interp.tcp() {
                    return refuse(diags, c, "radius compensation G41/G42 under M128 is not read: reset it first (M129)".into());
                }
                if !straight {
                    return refuse(diags, c, "G41/G42 in a circle block: \"You cannot activate radius compensation in a circle block. Activate it beforehand in a straight-line block\" (TNC 620 ISO user's manual, p. 154)".into());
                }
                if words.iter().any(|w| w.letter == 'M' && (w.value == 2.0 || w.value == 30.0)) {
                    return refuse(diags, c, "G41/G42 in the block that ends the program (M02/M30): no contour follows".into());
                }
                let r = match self.comp_radius() {
                    Ok(r) => r,
                    Err(why) => return refuse(diags, c, format!("G4{}: {why}", if side == Side::Left { 1 } else { 2 })),
                };
                let start = self.interp.position();
                let Some(b) = self.interp.block_one(words, line, col, number, diags) else { return false };
                let end = self.interp.position();
                self.comp.engine.start(side, r, [start[0], start[1], start[2]]);
                let fed = self.comp.engine.feed(b, start, end, unit, tilt, self.interp.arc_feed(), out);
                self.comp_result(fed, line, col, diags)
            }
            (Some(now), Some((Some(side), c))) if side != now => refuse(
                diags,
                c,
                "G41 and G42 without a block between them: \"Between two program blocks with different radius compensations you must program at least one traversing block in the working plane without radius compensation\" (TNC 620 ISO user's manual, p. 146), a G40 block".into(),
            ),
            (Some(_), Some((None, c))) => {
                if !straight {
                    return refuse(diags, c, "G40 in a circle block: compensation ends in a straight-line block (G00/G01) only (an arc from the compensated point to the programmed one is no circle)".into());
                }
                let Some(b) = self.interp.block_one(words, line, col, number, diags) else { return false };
                let end = self.interp.position();
                let left = self.comp.engine.leave(b, end, unit, tilt, out);
                self.comp_result(left, line, col, diags)
            }
            _ => {
                let start = self.interp.position();
                let Some(b) = self.interp.block_one(words, line, col, number, diags) else { return false };
                let end = self.interp.position();
                let ends = words.iter().any(|w| w.letter == 'M' && (w.value == 2.0 || w.value == 30.0));
                let fed = self.comp.engine.feed(b, start, end, unit, tilt, self.interp.arc_feed(), out);
                if !self.comp_result(fed, line, col, diags) {
                    return true;
                }
                if ends {
                    // The program's end: the last element left perpendicular at its end point.
                    let stopped = self.comp.engine.stop(unit, tilt, out);
                    self.comp_result(stopped, line, col, diags);
                }
                true
            }
        }
    }

    /// The called tool's radius, R + DR in the tool table (m).
    fn comp_radius(&self) -> Result<f64, String> {
        let tool = self.comp.tool.ok_or("the radius is the called tool's, and no tool call (T.. G17) comes before this block")?;
        tnc_radius(&format!("tool {tool}"), tnc_diameter(self.interp.tool_table(), tool)?)
    }

    /// Compensation's outcome: a failure stops the program there (true: it went on).
    fn comp_result(&mut self, r: Result<(), Fail>, line: usize, col: usize, diags: &mut Diags) -> bool {
        match r {
            Ok(()) => true,
            Err(why) => {
                diags.error(line, col, format!("radius compensation: {}", tnc_said(&why)));
                self.comp.engine = TncComp::default();
                self.comp.stopped = Some(line);
                false
            }
        }
    }

    /// The input has ended with compensation on: the last element left perpendicular at its end
    /// point, what is held out.
    pub(crate) fn comp_end(&mut self, out: &mut Vec<Block>, diags: &mut Diags) {
        // (Where the reading stopped, nothing after it runs: the end's compensation neither.)
        if self.comp.busy() && self.comp.stopped.is_none() {
            let stopped = self.comp.engine.stop(self.interp.unit(), self.interp.tilt(), out);
            self.comp_result(stopped, self.last_line.max(1), 1, diags);
        }
    }
}
