//! Chamfering and corner R on Fanuc and Haas mills: `,C` or `,R` at the end of a G01, G02 or G03
//! block inserts, between that block and the next, a chamfer whose ends lie `,C` from the virtual
//! corner or an arc of radius `,R` tangent to both.
//!
//! Rules, from the Fanuc 16i-M text ("Chamfering and corner R ... can be inserted automatically
//! between linear interpolation and linear interpolation, linear and circular, circular and linear,
//! circular and circular interpolation blocks"; "specified at the end of a block that specifies
//! linear interpolation (G01) or circular interpolation (G02 or G03)"; blocks with it "can be
//! specified consecutively") and the Fanuc-compatible NCT 2000M manual §16.1: `,C` "shows the
//! distance between the start/end point of chamfer and the supposed intersection of the two
//! successive blocks", "the length of the chord drawn from [the] intersection" where a circle is
//! beside it; the two blocks in the selected plane (G17-G19), else error 3081; a value too large
//! for the blocks, error 3084 (Fanuc alarm 0055); `,C` and `,R` in one block, error 3017. Haas
//! (Operator's Manual, "Corner Rounding and Chamfering"): "between two linear interpolation
//! blocks", `,C` the distance from the corner of intersection to where the chamfer begins and to
//! where it ends; "a terminating linear interpolation block must follow", and "a G04 pause may
//! intervene" (it dwells after the inserted element here, said as a warning).
//!
//! Refused, as an error at the word with the blocks kept as written (where the manuals at hand do
//! not say what the control does): a block between the two that moves nothing (M08, G04; on Haas
//! anything but one G04), the next
//! element's feed differing (which one the inserted element takes), G93, a move along the tool axis
//! or a rotary axis in either block, a work coordinate system or `G68` rotation in force or changed
//! between them, the program's end, a line not read, or a branch, loop, call or return (`IF`,
//! `GOTO`, `WHILE`, `END`, `M98`, `M99`, `G65`, `M97`) before the next block. A line that only sets
//! a macro variable (`#1=5.`) moves nothing and is no block between them.

use super::corner_cut::{in_plane, make, Cut, Held};
use super::interp::{Interpreter, Word};
use super::lex::Diags;
use super::rs274::Rs274Reader;
use super::{Block, Dialect, FeedMode, Motion, Plane};

/// A block's chamfer or corner R: which, its value (program unit) and word, and where it stands.
#[derive(Debug, Clone)]
pub(crate) struct Ask {
    round: bool,
    value: f64,
    word: String,
    line: usize,
    col: usize,
    number: Option<u64>,
}

impl Ask {
    /// The corner a line's comma words ask for (values in program units), or why not (where, what).
    fn of(words: &[(Word, bool)], line: usize, number: Option<u64>) -> Result<Option<Ask>, (usize, String)> {
        let mut ask: Option<Ask> = None;
        for (w, _) in words {
            let word = format!(",{}{}", w.letter, w.raw);
            if let Some(a) = &ask {
                return Err((w.column, format!("{word} after {} in one block: one chamfer or corner R ends a block (\",C AND ,R IN ONE BLOCK\", NCT 2000M error 3017)", a.word)));
            }
            if !(w.value > 0.0 && w.value.is_finite()) {
                return Err((w.column, format!("{word}: expected a positive {}", if w.letter == 'R' { "radius" } else { "chamfer length" })));
            }
            ask = Some(Ask { round: w.letter == 'R', value: w.value, word, line, col: w.column, number });
        }
        Ok(ask)
    }
}

/// The element held for the corner at its end, what it asked and the plane it was in.
#[derive(Debug, Clone)]
struct Waiting {
    element: Held,
    ask: Ask,
    plane: Plane,
    /// Haas: the `G04` pause read after it ("a G04 pause may intervene").
    pause: Vec<Block>,
}

/// The corner state beside the reader: the element waiting for the block after it.
#[derive(Debug, Clone, Default)]
pub(crate) struct Corners {
    waiting: Option<Waiting>,
}

/// How a line went, for the corners: it had nothing to run (a comment), it was taken, or not.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Ran {
    Nothing,
    Taken,
    NotUsed,
}

/// Whether a line's blocks are one line or circle at a feed in the plane, moving no tool axis and
/// no rotary axis (from `start` to where the interpreter is now).
fn is_element(blocks: &[Block], start: [f64; 6], interp: &Interpreter) -> bool {
    // A NURBS curve's chords are no G01 of the program's (and its mode takes no other block).
    let [b] = blocks else { return false };
    if interp.nurbs.is_some() {
        return false;
    }
    if !matches!(b.motion, Motion::Linear | Motion::ArcCw | Motion::ArcCcw) || b.targets.is_empty() {
        return false;
    }
    in_plane(start, interp.position(), interp.plane().axes().2)
}

impl Corners {
    /// A corner waits for the block after it.
    pub(crate) fn busy(&self) -> bool {
        self.waiting.is_some()
    }

    /// The blocks a line made (`out[before..]`, from `start`; `ask` its own corner; `ends`: it ends
    /// the program): joined to the element waiting before them by its corner, and held if they end
    /// at a corner; what can go out goes out in order.
    #[allow(clippy::too_many_arguments)]
    fn after_line(&mut self, dialect: Dialect, ask: Option<Ask>, start: [f64; 6], before: usize, interp: &Interpreter, ends: bool, out: &mut Vec<Block>, diags: &mut Diags) {
        let element = is_element(&out[before..], start, interp);
        let still = out[before..].iter().all(|b| b.targets.is_empty());
        // The line's element, as it stands after a corner cut at its start.
        let mut next: Option<Held> = None;
        if let Some(mut w) = self.waiting.take() {
            let mut emit = Vec::new();
            if dialect == Dialect::Haas && w.pause.is_empty() && !ends && ask.is_none() && pause(&out[before..]) {
                // Haas: "a G04 pause may intervene"; where it dwells, before or after the inserted
                // element, is not said: after it, as the pause follows the block that asks.
                diags.warning(
                    w.ask.line,
                    w.ask.col,
                    format!("{}: the G04 between the two blocks dwells after the inserted element here (Haas's manual says a pause may intervene, not on which side of it)", w.ask.word),
                );
                w.pause = out.drain(before..).collect();
                self.waiting = Some(w);
                return;
            }
            if interp.plane() != w.plane {
                refuse(w, "the plane changes (G17, G18, G19) before the block after it (\"DEFINITION ERROR ,C ,R\")", diags, &mut emit);
            } else if !element {
                let why = match (still, ends) {
                    (true, true) => "the program ends before the block after it",
                    (true, false) => "the block after it moves nothing: what the control does with a block between the two (M, G04) is not in the manuals at hand",
                    _ => "the block after it is not a line or circle at a feed (G01, G02, G03) in the plane (\"DEFINITION ERROR ,C ,R\")",
                };
                refuse(w, why, diags, &mut emit);
            } else if let Some(b) = out.pop() {
                let n = Held::made(b, start, interp);
                match join(dialect, &w, &n, interp) {
                    Ok((p2, corner, n2)) => {
                        emit.extend([p2.b, corner.b]);
                        emit.extend(w.pause);
                        next = Some(n2);
                    }
                    Err(why) => {
                        refuse(w, &why, diags, &mut emit);
                        next = Some(n);
                    }
                }
            }
            out.splice(before..before, emit);
        }
        let why = match ask {
            None => None,
            Some(_) if interp.rotation2d.is_some() => Some(ROTATED),
            Some(_) if still => Some("the block it is in moves nothing"),
            Some(_) if !element => Some("the block it is in is not a line or circle at a feed (G01, G02, G03) in the plane"),
            Some(_) if ends => Some("the program ends in its block: no block follows it"),
            Some(_) => None,
        };
        match (ask, why) {
            (Some(ask), None) => {
                // Held until the next block says where the corner is.
                let element = match next {
                    Some(n) => Some(n),
                    None => out.pop().map(|b| Held::made(b, start, interp)),
                };
                if let Some(element) = element {
                    self.waiting = Some(Waiting { element, ask, plane: interp.plane(), pause: Vec::new() });
                }
            }
            (ask, why) => {
                if let (Some(ask), Some(why)) = (ask, why) {
                    diags.error(ask.line, ask.col, format!("{}: {why}", ask.word));
                }
                out.extend(next.map(|n| n.b));
            }
        }
    }

    /// The blocks' sequence is left (a line not read, a macro statement, a call or return): a corner
    /// waiting is refused there, its element returned.
    pub(crate) fn interrupt(&mut self, why: &str, diags: &mut Diags) -> Vec<Block> {
        let mut emit = Vec::new();
        if let Some(w) = self.waiting.take() {
            refuse(w, why, diags, &mut emit);
        }
        emit
    }
}

/// The corner cannot be made: an error at its word, the element as programmed.
fn refuse(w: Waiting, why: &str, diags: &mut Diags, emit: &mut Vec<Block>) {
    diags.error(w.ask.line, w.ask.col, format!("{}: {why}", w.ask.word));
    emit.push(w.element.b);
    emit.extend(w.pause);
}

/// A line's blocks are a pause and nothing else: a `G04` dwell that moves nothing and sets nothing.
fn pause(blocks: &[Block]) -> bool {
    !blocks.is_empty() && blocks.iter().all(|b| b.targets.is_empty() && b.events.is_empty() && b.dwell_s.is_some())
}

/// Why a corner is refused when the line after it was not read.
const NOT_READ: &str = "the block after it is not read";

/// Why a corner under G68 is refused: the reader keeps the program's points unrotated and turns
/// each block's, so the corner would be cut in the wrong frame.
const ROTATED: &str = "under G68 coordinate rotation a chamfer or corner R is not read (cancel it with G69 first)";

/// The element waiting cut back, the corner, the element after cut back; why not.
fn join(dialect: Dialect, w: &Waiting, n: &Held, interp: &Interpreter) -> Result<(Held, Held, Held), String> {
    let p = &w.element;
    let moved = (0..6).any(|k| (n.start[k] - p.end[k]).abs() > 1e-9 * (1.0 + p.end[k].abs()));
    if moved || n.tilt != p.tilt || n.b.datum != p.b.datum {
        return Err("the work coordinate system changes between the two blocks (G54-G59, G92, G52, a tilted plane)".into());
    }
    if interp.rotation2d.is_some() {
        return Err(ROTATED.into());
    }
    if dialect == Dialect::Haas && (p.b.motion != Motion::Linear || n.b.motion != Motion::Linear) {
        return Err("an arc beside the corner: Haas inserts one \"between two linear interpolation blocks\" (G01)".into());
    }
    let mode = interp.feed_state().2;
    if mode == FeedMode::InverseTime {
        return Err("under G93 (inverse time) the corner's feed is not in the manuals at hand".into());
    }
    let same = match (p.b.feed, n.b.feed) {
        (Some(a), Some(b)) => (a.value_per_min - b.value_per_min).abs() <= 1e-9 * a.value_per_min.abs().max(1e-12) && a.mode == b.mode,
        (a, b) => a.is_none() && b.is_none(),
    };
    if !same {
        return Err("the block after it changes the feed: which feed the inserted element takes is not in the manuals at hand (give both blocks the same F)".into());
    }
    let a = &w.ask;
    let cut = Cut { round: a.round, chord: true, size: a.value * p.unit, feed: None, line: a.line, col: a.col, number: a.number };
    let (p2, mut corner, n2) = make(&cut, p, n, interp.plane(), mode)?;
    corner.b.exact = n.b.exact;
    Ok((p2, corner, n2))
}

impl Rs274Reader {
    /// A line's comma words (`,C`, `,R`): their values in program units (without a decimal point,
    /// in least input increments as every length is, said once), the corner they ask for; a word
    /// refused is said at it and asks for nothing (its block runs as written).
    pub(super) fn corner_words(&mut self, commas: &mut [(Word, bool)], words: &[Word], line: usize, number: Option<u64>, diags: &mut Diags) -> Option<Ask> {
        if commas.is_empty() {
            return None;
        }
        let (step, unit) = if self.inch_words(words) { (1e-4, "in") } else { (1e-3, "mm") };
        for (w, computed) in commas.iter_mut() {
            if !*computed && !w.raw.contains('.') && !self.calculator_input {
                w.value *= step;
                if w.value != 0.0 && !std::mem::replace(&mut self.said_no_point, true) {
                    diags.warning(line, w.column, format!(",{}{} has no decimal point: read as {} {unit}, in least input increments, as the control reads it unless its parameter says otherwise (FANUC DPI No. 3401#0, Haas Setting 162: the machine file's decimal_point_input); said once", w.letter, w.raw, w.value));
                }
            }
        }
        Ask::of(commas, line, number).unwrap_or_else(|(col, why)| {
            diags.error(line, col, why);
            None
        })
    }

    /// After a line ran (`ran`; its blocks `out[before..]`, from `start`): the corners take them.
    pub(super) fn corners_after(&mut self, ran: Ran, ask: Option<Ask>, start: [f64; 6], before: usize, out: &mut Vec<Block>, diags: &mut Diags) {
        match ran {
            Ran::Nothing => {}
            Ran::NotUsed => {
                let held = self.corners.interrupt(NOT_READ, diags);
                out.splice(before..before, held);
            }
            Ran::Taken => {
                let ends = super::stream::ends_program(&out[before..], &[2.0, 30.0]);
                self.corners.after_line(self.dialect, ask, start, before, &self.interp, ends, out, diags);
            }
        }
    }

    /// A line was not read (`said`: how many diagnostics there were before it; a blank line or a
    /// comment adds no error).
    pub(super) fn corners_after_damaged(&mut self, said: usize, out: &mut Vec<Block>, diags: &mut Diags) {
        if self.corners.busy() && diags.0.get(said..).is_some_and(|new| new.iter().any(|d| d.severity == super::Severity::Error)) {
            self.corners_not_read(out, diags);
        }
    }

    /// The line after a waiting corner was not read: the corner is refused, its element out.
    pub(super) fn corners_not_read(&mut self, out: &mut Vec<Block>, diags: &mut Diags) {
        out.extend(self.corners.interrupt(NOT_READ, diags));
    }

    /// A macro statement, call or return runs while a corner waits: the corner is refused there.
    pub(super) fn corner_interrupt(&mut self, out: &mut Vec<Block>, diags: &mut Diags) {
        out.extend(self.corners.interrupt("a branch, loop, call or return (IF, GOTO, WHILE, END, M98, M99, G65, M97) stands before the block after it", diags));
    }
}
