//! Chamfers and roundings at contour corners in an 840D program (SINUMERIK Programming Manual
//! Fundamentals, "Chamfer, rounding (CHF, CHR, RND, RNDM, FRC, FRCM)"; 10.2004 §4.22, 11/2006 §4.22,
//! NC programming 12/2019 §2.9): `CHF=`, `CHR=` or `RND=` "is written in the block with axis
//! movements leading to the corner", and the chamfer or rounding "is inserted after the block in
//! which it is programmed", in the plane of G17-G19:
//! - `RND=` a rounding of that radius, tangent to both elements; `RNDM=` the same at every corner
//!   after it until `RNDM=0`;
//! - `CHR=` a chamfer whose sides along both elements are that long ("width of chamfer in direction
//!   of motion"), `CHF=` one whose own length is that (the manual's figure: CHF = 2 cos(α) CHR, α
//!   the angle between the chamfer and each element);
//! - the feed: `FRC=` for this corner, `FRCM=` for every one until `FRCM=0`, else the path feed F,
//!   "by default the value from the block which leads away from the corner" (MD20201
//!   CHFRND_MODE_MASK bit 0 = 0, taken here);
//! - "No chamfer/rounding is inserted if more than three blocks in the connection are programmed
//!   that do not contain any information for traversing in the plane, or a plane change is carried
//!   out": said as a warning, the elements as programmed.
//!
//! Refused (an error at the word, the elements as programmed): a value the elements are too short
//! for ("automatically reduced", by an amount the manuals do not give), a chamfer beside an arc
//! (where its ends lie on the arc is not said), an element that is not a line or circle at a feed in
//! the plane (G0, a helix, a move along the tool axis), a move between the elements, a frame or
//! tilted plane changed between them, a corner at the block that selects or deselects tool radius
//! compensation. Under G41/G42 the corner is the contour's: compensation offsets the rounded or
//! chamfered contour ([`super::trc`] takes the elements from here).

use super::super::corner_cut::{in_plane, make, meet_tangentially, Cut, Held};
use super::super::lex::Diags;
use super::super::{Block, Feed, FeedMode, Motion};
use crate::program::interp::Interpreter;
use crate::units::MM;

/// The most blocks without a move in the plane between the two elements ("more than three blocks
/// ... no chamfer/rounding is inserted").
const MAX_BETWEEN: usize = 3;

/// Which corner a word asks for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Kind {
    /// `RND=`/`RNDM=`: the rounding's radius.
    Round,
    /// `CHR=`: the chamfer's sides along the elements.
    Sides,
    /// `CHF=`: the chamfer's own length.
    Length,
}

/// A block's corner words: one of `CHF=`/`CHR=`/`RND=` (its value in the program's unit and
/// column), `RNDM=`, `FRC=`, `FRCM=`.
#[derive(Debug, Clone, Default)]
pub(crate) struct Words {
    pub cut: Option<(Kind, &'static str, f64, usize)>,
    pub rndm: Option<(f64, usize)>,
    pub frc: Option<(f64, usize)>,
    pub frcm: Option<(f64, usize)>,
}

impl Words {
    /// `name=value` at `col`; why not, for a second corner word or a value out of range.
    pub(crate) fn set(&mut self, name: &str, value: f64, col: usize) -> Result<(), String> {
        let positive = value > 0.0 && value.is_finite();
        let (kind, word) = match name {
            "RND" => (Kind::Round, "RND"),
            "CHR" => (Kind::Sides, "CHR"),
            "CHF" => (Kind::Length, "CHF"),
            "RNDM" if value >= 0.0 && value.is_finite() => return Ok(self.rndm = Some((value, col))),
            "FRC" if positive => return Ok(self.frc = Some((value, col))),
            "FRCM" if value >= 0.0 && value.is_finite() => return Ok(self.frcm = Some((value, col))),
            "FRC" => return Err(format!("FRC={value}: the corner's feed must be positive (\"FRC > 0\")")),
            _ => return Err(format!("{name}={value}: expected a value of 0 or more (0 switches it off)")),
        };
        if !positive {
            return Err(format!("{word}={value}: expected a positive {}", if kind == Kind::Round { "radius" } else { "length" }));
        }
        if let Some((_, other, _, _)) = self.cut {
            return Err(format!("{word} after {other} in one block: one corner is cut at a block's end (which one the control keeps is not read)"));
        }
        self.cut = Some((kind, word, value, col));
        Ok(())
    }

    /// Whether the block has any corner word.
    pub(crate) fn any(&self) -> bool {
        self.cut.is_some() || self.rndm.is_some() || self.frc.is_some() || self.frcm.is_some()
    }
}

/// The corner a block asks for at its end: its word's name, kind and value (program unit), feed,
/// and where it stands.
#[derive(Debug, Clone)]
struct Ask {
    word: &'static str,
    kind: Kind,
    value: f64,
    feed: Option<f64>,
    /// From `RNDM`: a corner the elements do not make (they meet tangentially) is no fault.
    modal: bool,
    line: usize,
    col: usize,
    number: Option<u64>,
}

/// A contour element held for the corner at its end, and the blocks without a move in the plane
/// read after it (their count in lines, the blocks they made).
#[derive(Debug, Clone)]
struct Waiting {
    element: Held,
    ask: Ask,
    plane: crate::program::Plane,
    lines: usize,
    between: Vec<Held>,
}

/// The corner state beside the reader: modal rounding and feed, the element waiting, this block's
/// words.
#[derive(Debug, Clone, Default)]
pub(crate) struct Corners {
    /// `RNDM=` in effect (program unit) and its column.
    rndm: Option<f64>,
    /// `FRCM=` in effect (program unit per minute).
    frcm: Option<f64>,
    waiting: Option<Waiting>,
    /// The words of the block being read, set by [`Corners::take`].
    words: Words,
    line_col: (usize, usize, Option<u64>),
}

/// What a line's blocks are to a waiting corner.
enum Made {
    /// No block, or blocks that move nothing.
    Still,
    /// One line or circle at a feed.
    Element,
    /// Anything else.
    Other,
}

fn made(blocks: &[&Block]) -> Made {
    if blocks.iter().all(|b| b.targets.is_empty()) {
        Made::Still
    } else if let [b] = blocks {
        if matches!(b.motion, Motion::Linear | Motion::ArcCw | Motion::ArcCcw) {
            Made::Element
        } else {
            Made::Other
        }
    } else {
        Made::Other
    }
}

impl Corners {
    /// A corner waits for the element after it, or modal rounding is on.
    pub(crate) fn busy(&self) -> bool {
        self.waiting.is_some() || self.rndm.is_some_and(|r| r > 0.0)
    }

    /// A block's corner words, before it runs (modal ones take effect with it).
    pub(crate) fn take(&mut self, words: Words, line: usize, col: usize, number: Option<u64>) {
        self.words = words;
        self.line_col = (line, col, number);
    }

    /// A block read whose corner words no path took (one that moves nothing under compensation):
    /// its modal ones set, a corner it asks for refused.
    pub(crate) fn leftover(&mut self, diags: &mut Diags) {
        if let Some(a) = self.ask().filter(|a| !a.modal) {
            diags.error(a.line, a.col, format!("{}: the block it is in moves nothing in the plane: it ends no contour element", a.word));
        }
    }

    /// The block was refused: its words go.
    pub(crate) fn drop_words(&mut self) {
        self.words = Words::default();
    }

    /// This block's corner, if it asks for one (its own word, or `RNDM` in effect), after its modal
    /// words are set.
    fn ask(&mut self) -> Option<Ask> {
        let w = std::mem::take(&mut self.words);
        if let Some((r, _)) = w.rndm {
            self.rndm = (r > 0.0).then_some(r);
        }
        if let Some((f, _)) = w.frcm {
            self.frcm = (f > 0.0).then_some(f);
        }
        let feed = w.frc.map(|f| f.0).or(self.frcm);
        let (line, _, number) = self.line_col;
        match (w.cut, self.rndm) {
            (Some((kind, word, value, col)), _) => Some(Ask { word, kind, value, feed, modal: false, line, col, number }),
            (None, Some(r)) => Some(Ask { word: "RNDM", kind: Kind::Round, value: r, feed, modal: true, line, col: w.rndm.map_or(self.line_col.1, |c| c.1), number }),
            (None, None) => None,
        }
    }

    /// The blocks a line made (`out[before..]`, from `start` to where the interpreter is now), without
    /// tool radius compensation: held if its end is a corner, or joined to the element waiting
    /// before them by its corner; what can go out goes out in order. A program end (M2, M30, M17)
    /// lets everything out.
    pub(crate) fn after_line(&mut self, start: [f64; 6], before: usize, interp: &Interpreter, ends: bool, out: &mut Vec<Block>, diags: &mut Diags) {
        let ask = self.ask();
        if self.waiting.is_none() && ask.is_none() {
            return;
        }
        let new: Vec<Held> = out.drain(before..).map(|b| Held::made(b, start, interp)).collect();
        let mut emit = Vec::new();
        self.step(new, start, ask, interp, ends, &mut emit, diags);
        out.extend(emit.into_iter().map(|h| h.b));
    }

    /// The block `h` made under tool radius compensation (from `start`), before compensation: what
    /// goes on to it, in order.
    pub(crate) fn compensated(&mut self, h: Held, start: [f64; 6], interp: &Interpreter, ends: bool, diags: &mut Diags) -> Vec<Held> {
        let ask = self.ask();
        let mut emit = Vec::new();
        if self.waiting.is_none() && ask.is_none() {
            emit.push(h);
        } else {
            self.step(vec![h], start, ask, interp, ends, &mut emit, diags);
        }
        emit
    }

    /// The words of a block that selects or deselects compensation, or that compensation refuses
    /// corners around: a corner waiting or asked for here is refused (`why`), what is held out.
    pub(crate) fn refuse_here(&mut self, why: &str, diags: &mut Diags) -> Vec<Held> {
        let mut emit = Vec::new();
        if let Some(a) = self.ask().filter(|a| !a.modal) {
            diags.error(a.line, a.col, format!("{}: {why}", a.word));
        }
        if let Some(w) = self.waiting.take() {
            refuse(w, why, diags, &mut emit);
        }
        emit
    }

    /// The step itself: `new` the blocks of one line.
    #[allow(clippy::too_many_arguments)]
    fn step(&mut self, mut new: Vec<Held>, start: [f64; 6], ask: Option<Ask>, interp: &Interpreter, ends: bool, emit: &mut Vec<Held>, diags: &mut Diags) {
        let blocks: Vec<&Block> = new.iter().map(|h| &h.b).collect();
        let mut kind = made(&blocks);
        // A line or circle that also moves along the tool axis or a rotary axis is no element of
        // the plane.
        if matches!(kind, Made::Element) && !in_plane(start, interp.position(), interp.plane().axes().2) {
            kind = Made::Other;
        }
        if let Some(mut w) = self.waiting.take() {
            match kind {
                _ if interp.plane() != w.plane => {
                    diags.warning(
                        w.ask.line,
                        w.ask.col,
                        format!("{}: no corner is inserted: the plane changes before the next element (\"No chamfer/rounding is inserted if ... a plane change is carried out\")", w.ask.word),
                    );
                    release(w, emit);
                }
                Made::Still if w.lines < MAX_BETWEEN && !ends => {
                    if let Some(a) = ask.filter(|a| !a.modal) {
                        diags.error(a.line, a.col, format!("{}: the block it is in moves nothing in the plane: it ends no contour element", a.word));
                    }
                    w.lines += 1;
                    w.between.extend(new);
                    self.waiting = Some(w);
                    return;
                }
                // RNDM's last element has no corner after it.
                Made::Still if ends && w.ask.modal => release(w, emit),
                Made::Still if ends => refuse(w, "its program ends (M30, M2 or M17) before a contour element follows it", diags, emit),
                Made::Still => {
                    diags.warning(w.ask.line, w.ask.col, format!("{}: no corner is inserted: more than {MAX_BETWEEN} blocks without a move in the plane follow it (\"No chamfer/rounding is inserted if more than three blocks in the connection are programmed that do not contain any information for traversing in the plane\")", w.ask.word));
                    release(w, emit);
                }
                Made::Other => refuse(w, "the block after it is not a contour element it joins: one line or circle at a feed (G1, G2, G3) in the plane", diags, emit),
                Made::Element => {
                    let rest = new.split_off(1.min(new.len()));
                    let Some(n) = new.pop() else { return release(w, emit) };
                    let n = self.join(w, n, interp, diags, emit);
                    return self.next(n, ask, rest, interp, ends, emit, diags);
                }
            }
        }
        if matches!(kind, Made::Element) {
            let rest = new.split_off(1.min(new.len()));
            if let Some(n) = new.pop() {
                return self.next(n, ask, rest, interp, ends, emit, diags);
            }
        }
        if let Some(a) = ask.filter(|a| !a.modal) {
            diags.error(a.line, a.col, format!("{}: the block it is in is not a contour element a corner ends: one line or circle at a feed (G1, G2, G3) in the plane", a.word));
        }
        emit.extend(new);
    }

    /// The element `n` out, or held for its own corner.
    #[allow(clippy::too_many_arguments)]
    fn next(&mut self, n: Held, ask: Option<Ask>, rest: Vec<Held>, interp: &Interpreter, ends: bool, emit: &mut Vec<Held>, diags: &mut Diags) {
        match ask {
            Some(a) if !ends => self.waiting = Some(Waiting { element: n, ask: a, plane: interp.plane(), lines: 0, between: rest }),
            Some(a) => {
                if !a.modal {
                    diags.error(a.line, a.col, format!("{}: the program ends in its block: no contour element follows it", a.word));
                }
                emit.push(n);
                emit.extend(rest);
            }
            None => {
                emit.push(n);
                emit.extend(rest);
            }
        }
    }

    /// The element waiting (`w`) and the one after it (`n`): `w`'s element cut back and out with
    /// its corner and the blocks between; `n` cut back, returned.
    fn join(&mut self, w: Waiting, n: Held, interp: &Interpreter, diags: &mut Diags, emit: &mut Vec<Held>) -> Held {
        let a = &w.ask;
        let p = &w.element;
        let moved = (0..6).any(|k| (n.start[k] - p.end[k]).abs() > 1e-9 * (1.0 + p.end[k].abs()));
        if a.modal && !moved && n.tilt == p.tilt && meet_tangentially(p, &n, interp.plane()) {
            // RNDM: elements that meet tangentially have no corner to round.
            release(w, emit);
            return n;
        }
        let why = if moved || n.tilt != p.tilt {
            Err("the next element does not start where the one before it ends in the same frame (a frame or the plane's position changed between them)".to_string())
        } else {
            let size = match a.kind {
                Kind::Round | Kind::Sides => Ok(a.value * p.unit),
                Kind::Length => sides_of(p, &n, interp, a.value * p.unit),
            };
            let mode = interp.feed_state().2;
            size.and_then(|size| {
                if mode == FeedMode::InverseTime {
                    return Err("under G93 (inverse time) the corner's feed is not in the manuals read here".to_string());
                }
                if a.feed.is_some() && interp.per_revolution() {
                    return Err("FRC/FRCM under G95 (feed per revolution): the corner's own feed per revolution is not read".to_string());
                }
                // FRC's feed is set below, in the feed's unit (G70/G71 leave F in the basic system's).
                let cut = Cut { round: a.kind == Kind::Round, chord: false, size, feed: None, line: a.line, col: a.col, number: a.number };
                make(&cut, p, &n, interp.plane(), mode)
            })
        };
        match why {
            Ok((p2, mut corner, n2)) => {
                // FRC/FRCM in the feed's unit per minute; else the technology of the block leading
                // away from the corner (MD20201 bit 0 = 0).
                corner.b.feed = match a.feed {
                    Some(f) => Some(Feed { value_per_min: f * interp.feed_unit() / MM, rotary_per_min: f, mode: FeedMode::PerMinute }),
                    None => n.b.feed,
                };
                corner.b.exact = n.b.exact;
                emit.push(p2);
                emit.push(corner);
                emit.extend(w.between);
                n2
            }
            Err(why) => {
                let why = if a.modal { format!("{why} (modal rounding from RNDM)") } else { why };
                diags.error(a.line, a.col, format!("{}={}: {why}", a.word, a.value));
                release(w, emit);
                n
            }
        }
    }

    /// The block sequence is left (a call, a return, a block not read): a corner waiting is refused
    /// there, what it holds returned in order.
    pub(crate) fn interrupt(&mut self, why: &str, diags: &mut Diags) -> Vec<Held> {
        let mut emit = Vec::new();
        if let Some(w) = self.waiting.take() {
            refuse(w, why, diags, &mut emit);
        }
        emit
    }

    /// The program's input has ended: a corner still waiting has no element after it.
    pub(crate) fn end(&mut self, diags: &mut Diags) -> Vec<Held> {
        self.interrupt("its program ends (M30, M2 or M17) before a contour element follows it", diags)
    }
}

/// The element waiting and the blocks after it out as programmed.
fn release(w: Waiting, emit: &mut Vec<Held>) {
    emit.push(w.element);
    emit.extend(w.between);
}

/// The corner cannot be made: an error at its word, the elements as programmed.
fn refuse(w: Waiting, why: &str, diags: &mut Diags, emit: &mut Vec<Held>) {
    diags.error(w.ask.line, w.ask.col, format!("{}={}: {why}", w.ask.word, w.ask.value));
    release(w, emit);
}


/// `CHF=`'s chamfer length as the length of its sides along two lines: the chamfer joins the points
/// `s` from the corner on each, its length 2 s cos(θ/2), θ the turn between their directions.
fn sides_of(p: &Held, n: &Held, interp: &Interpreter, length: f64) -> Result<f64, String> {
    let (a0, a1, _) = interp.plane().axes();
    let (Motion::Linear, Motion::Linear) = (p.b.motion, n.b.motion) else {
        return Err("a chamfer beside an arc: where its ends lie on the arc is not in the manuals read here (between two lines it is read)".into());
    };
    let d = |h: &Held| {
        let v = [h.end[a0] - h.start[a0], h.end[a1] - h.start[a1]];
        let l = v[0].hypot(v[1]);
        (l > 0.0).then(|| [v[0] / l, v[1] / l])
    };
    let (Some(u), Some(v)) = (d(p), d(n)) else { return Err("an element of no length in the plane beside it".into()) };
    let half = ((1.0 + u[0] * v[0] + u[1] * v[1]) / 2.0).max(0.0).sqrt();
    if half < 1e-9 {
        return Err("the contour turns back on itself here".into());
    }
    Ok(length / (2.0 * half))
}
