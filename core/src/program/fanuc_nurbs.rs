//! Fanuc NURBS interpolation, `G06.2`: a curve given by its control points, weights and knots,
//! made as the chords the control's path lies within.
//!
//! Rules, from the FANUC Series 15i/150i-MA Operator's Manual B-63324EN §4.17 "NURBS
//! interpolation": `G06.2 [P] K IP [R] [F]` starts the mode, a modal code of group 01 that a
//! G00-G03 ends; rank `P` 2 to 4 (default 4, a cubic), in the first block only; each control point
//! block has its knot `K` (alarm PS1002 without), and the curve ends after as many blocks of a knot
//! alone as the rank; weight `R` default 1; the first `k` knots equal and the last `k` equal (PS1007),
//! no knot repeated more than `k` times (PS1008); the first control point is where the tool stands
//! (PS1009; under G91 a travel of 0); an axis not in the first block may not come later; nothing
//! but NURBS words in the mode; another mode before the curve's knots end is PS1004/PS1005; G06.2
//! under G41/G42, G93/G95 or G12.1 is PS1006. The curve is `P(t) = Σ N_ik(t) w_i P_i / Σ N_ik(t) w_i`
//! with the de Boor-Cox basis, evaluated here span by span (de Boor's algorithm on the homogeneous
//! points) as soon as its knots are read, so a curve of any length holds `2k` points.
//!
//! "When using a function such as tool length compensation, coordinate rotation, and scaling
//! together with NURBS interpolation, specify the function before setting NURBS interpolation mode":
//! under `G68` the chords are placed as any block is (a rotation turns the curve with its chords).
//!
//! Not read (refused, naming the block): tool-centre point or a tilted working plane `G68.2` in
//! effect (how the control combines them with the curve is not in these pages), a rotary control point on
//! an axis that turns without end (which way the control turns it), the 15i's additional function
//! that leaves out the first control point or knot, an F, M, S or T inside the curve, a knot
//! repeated `k` times inside the curve where the curve breaks, a weight of 0 or less.

use super::fanuc::{code, shot, word};
use super::interp::{Interpreter, OneShot, Word};
use super::lex::Diags;
use super::{Block, Dialect, Motion};

/// The highest rank (`P4`: cubic).
const MAX_RANK: usize = 4;
/// The points and knots a span's evaluation reaches back to from the newest (`2k - 1` points,
/// `2k - 2` knots), kept in rings of this size.
const RING: usize = 8;
/// The largest knot or weight: "a 9-digit absolute value of the minimum data unit" (±999999.999
/// at IS-B millimetre input).
const MAX_WORD: f64 = 999_999.999;
use super::chords::{Chording, CHORD_TOLERANCE_M, CHORD_TOLERANCE_RAD};

const AXES: [char; 6] = ['X', 'Y', 'Z', 'A', 'B', 'C'];

/// The NURBS mode (G06.2 until a G00-G03), and the curve it is reading, if any.
#[derive(Debug, Clone, Default)]
pub(crate) struct Mode {
    curve: Option<Curve>,
}

/// A curve being read: its rank, axes and the newest points and knots.
#[derive(Debug, Clone)]
struct Curve {
    /// `k`: the degree plus one.
    rank: usize,
    /// The axes the first block named: the curve's.
    axes: [bool; 6],
    /// Control points G91 (increments from the one before).
    incremental: bool,
    /// Control points and knots read, and blocks of a knot alone.
    points: usize,
    knots: usize,
    closing: usize,
    /// Control point `i` at `i % RING`: `w x` per axis (program units), then `w`.
    ring: [[f64; 7]; RING],
    /// Knot `i` at `i % RING`, and where it was written (line, column).
    knot: [f64; RING],
    knot_at: [(usize, usize); RING],
    /// The newest control point as written (absolute, program units), for increments and the axes a
    /// block leaves out.
    point: [f64; 6],
    /// How many knots in a row equal the newest.
    run: usize,
    /// The curve is refused: its blocks are read to its end, and make nothing.
    failed: bool,
    /// Where the chords stand (program units): the curve's point at the end of the last span made.
    at: [f64; 6],
    /// The tolerance in program units per axis.
    tolerance: [f64; 6],
}

/// The block's moves if it is a NURBS block (`Some(made)`, false if a defect stopped it), or `None`
/// for a block the mode does not take (a G00-G03 ends the mode, and is read as any other).
pub(crate) fn expand(it: &mut Interpreter, words: &[Word], line: usize, column: usize, number: Option<u64>, diags: &mut Diags, out: &mut Vec<Block>) -> Option<bool> {
    if it.dialect() != Dialect::Fanuc {
        return None;
    }
    let starts = words.iter().find(|w| w.letter == 'G' && w.value == 6.2 && code(w) == "6.2");
    if it.nurbs.is_none() && starts.is_none() {
        return None;
    }
    // Out of the interpreter while the curve's moves are made (each copies the interpreter).
    let mut mode = it.nurbs.take().map_or_else(Mode::default, |m| *m);
    if let Some(g) = words.iter().find(|w| w.letter == 'G' && matches!(code(w).as_str(), "0" | "1" | "2" | "3")) {
        if let Some(c) = mode.curve.as_mut().filter(|c| !c.failed) {
            c.unfinished(&format!("G{}", g.raw), line, g.column, diags);
            c.failed = true;
        }
        // The block ends the mode if it is read; a refused one leaves the mode as it was.
        let done = match super::fanuc::expand_plain(it, words, line, column, number, diags, out) {
            Some(done) => done,
            None => match it.block_one(words, line, column, number, diags) {
                Some(b) => {
                    out.push(b);
                    true
                }
                None => false,
            },
        };
        if !done {
            it.nurbs = Some(Box::new(mode));
        }
        return Some(done);
    }
    let done = match starts {
        Some(g) => {
            if let Some(c) = mode.curve.as_ref().filter(|c| !c.failed) {
                c.unfinished(&format!("G{}", g.raw), line, g.column, diags);
            }
            start(it, &mut mode, g, words, line, column, number, diags, out)
        }
        None => match mode.curve.as_mut() {
            Some(c) => c.block(it, words, line, column, number, diags, out),
            None if words.iter().any(|w| !matches!(w.letter, 'K' | 'R' | 'N') && !AXES.contains(&w.letter)) => {
                let w = words.iter().find(|w| !matches!(w.letter, 'K' | 'R' | 'N') && !AXES.contains(&w.letter));
                w.is_some_and(|w| refuse_word(w, line, diags, "nothing but NURBS curves until a G00-G03 ends the mode (FANUC 15i-MA §4.17: \"commands other than NURBS interpolation cannot be specified\")"))
            }
            None => {
                let what = words.iter().find(|w| w.letter == 'K').map_or("a block without its knot (K)", |_| "a block with a knot but no G06.2");
                diags.error(line, column, format!("{what} in NURBS mode after its curve ended: each curve begins with G06.2 and its first control point and knot, and G00-G03 end the mode (FANUC 15i-MA §4.17, alarm PS1002)"));
                false
            }
        },
    };
    if mode.curve.as_ref().is_some_and(|c| c.closing == c.rank) {
        mode.curve = None;
    }
    it.nurbs = Some(Box::new(mode));
    Some(done)
}

/// At the program's end: a curve whose knots have not all come is never run.
pub(crate) fn finish(it: &mut Interpreter, last_line: usize, diags: &mut Diags) {
    if let Some(c) = it.nurbs.take().and_then(|m| m.curve).filter(|c| !c.failed) {
        c.unfinished("the program's end", last_line, 1, diags);
    }
}

/// What a block's word is to the curve.
fn refuse_word(w: &Word, line: usize, diags: &mut Diags, why: &str) -> bool {
    diags.error(line, w.column, format!("{}{} in a NURBS curve: {why}", w.letter, w.raw));
    false
}

/// `G06.2 [P] K IP [R] [F]`: a curve's first block.
#[allow(clippy::too_many_arguments)]
fn start(it: &mut Interpreter, mode: &mut Mode, g: &Word, words: &[Word], line: usize, column: usize, number: Option<u64>, diags: &mut Diags, out: &mut Vec<Block>) -> bool {
    // A refused first block still opens the curve, so that its blocks are read to its end.
    let rank = match words.iter().find(|w| w.letter == 'P') {
        None => MAX_RANK,
        Some(p) if p.value.fract() == 0.0 && (2.0..=MAX_RANK as f64).contains(&p.value) => p.value as usize,
        Some(p) => {
            diags.error(line, p.column, format!("P{}: the rank of a NURBS curve is 2, 3 or 4 (FANUC 15i-MA §4.17)", p.raw));
            mode.curve = Some(Curve::failed(4));
            return false;
        }
    };
    mode.curve = Some(Curve::failed(rank));
    // The settings the block may carry with the curve: G90/G91 and the feed.
    let mut settings: Vec<Word> = Vec::new();
    for w in words {
        match w.letter {
            'G' if matches!(code(w).as_str(), "6.2") => {}
            'G' if matches!(code(w).as_str(), "90" | "91") => settings.push(w.clone()),
            'F' => settings.push(w.clone()),
            'P' | 'K' | 'R' | 'N' => {}
            l if AXES.contains(&l) => {}
            _ => return refuse_word(w, line, diags, "nothing but the curve's words, G90/G91 and F, with G06.2 (FANUC 15i-MA §4.17: \"commands other than NURBS interpolation cannot be specified\")"),
        }
    }
    // The block's own G90/G91, else the modal one: how its control point is read.
    let absolute = match words.iter().rev().find(|w| w.letter == 'G' && matches!(code(w).as_str(), "90" | "91")) {
        Some(w) => code(w) == "90",
        None => it.absolute(),
    };
    // PS1006, and what these pages leave open.
    let why = if it.inverse_time() || it.per_revolution() {
        Some("under G93 or G95 (FANUC alarm PS1006: a mode incompatible with NURBS interpolation)")
    } else if it.tcp() {
        Some("under tool-centre point control: how the control runs a curve then is not in the pages at hand (cancel it with G49 first)")
    } else if it.feature.is_some() {
        Some("under a tilted working plane (G68.2): the manual names coordinate rotation, tool length compensation and scaling as what a curve runs under, not the three-dimensional conversion (cancel it with G69 first)")
    } else if !absolute && it.rotation2d.is_some_and(|r| r.until_absolute.is_some()) {
        Some("under G91 after G68 before an absolute move: the rotation's centre is then the tool's position at G68 (B-62764EN §15.10), which these moves, made absolute, would leave; write the curve under G90")
    } else {
        None
    };
    if let Some(why) = why {
        diags.error(line, g.column, format!("G{} {why}", g.raw));
        return false;
    }
    if !words.iter().any(|w| w.letter == 'K') {
        diags.error(line, g.column, format!("G{} without its knot (K): each control point block has one (FANUC alarm PS1002; the 15i's additional function that leaves it out of the first block is not read)", g.raw));
        return false;
    }
    let named: Vec<&Word> = words.iter().filter(|w| AXES.contains(&w.letter)).collect();
    if named.is_empty() {
        diags.error(line, g.column, format!("G{} without its first control point: its axis words name the curve's axes (the 15i's additional function that starts from the current position is not read)", g.raw));
        return false;
    }
    let unit = it.unit();
    let mut axes = [false; 6];
    let mut tolerance = [0.0; 6];
    let mut here = [0.0; 6];
    let last = it.position();
    for w in &named {
        let k = AXES.iter().position(|l| *l == w.letter).unwrap_or(0);
        if !it.has_axis(w.letter) {
            diags.error(line, w.column, format!("{}{}: the machine has no {} axis", w.letter, w.raw, w.letter));
            return false;
        }
        if k >= 3 && it.modulo(k - 3) {
            diags.error(line, w.column, format!("{}{}: a control point on a rotary axis that turns without end: which way the control turns it along the curve is not read", w.letter, w.raw));
            return false;
        }
        let per = if k < 3 { unit } else { it.rotary_unit(k - 3) };
        axes[k] = true;
        tolerance[k] = if k < 3 { CHORD_TOLERANCE_M } else { CHORD_TOLERANCE_RAD } / per;
        here[k] = last[k] / per;
        if !it.placed[k] {
            diags.error(line, w.column, format!("{}{}: no move has placed {} before the curve, so its first control point cannot be where the tool stands (FANUC alarm PS1009)", w.letter, w.raw, w.letter));
            return false;
        }
        // PS1009: "If the absolute coordinates differ from the first control point when NURBS
        // interpolation starts"; under G91, "the amount of travel is 0". Half the least input
        // increment apart is the same place.
        let least = if k < 3 { if unit == crate::units::INCH { 1e-4 } else { 1e-3 } } else { 1e-3 };
        let off = if absolute { w.value - here[k] } else { w.value };
        if off.abs() > least / 2.0 {
            let said = if absolute { format!("the tool stands at {}{}", w.letter, fmt(here[k])) } else { "under G91 it must be 0 (no travel)".to_string() };
            diags.error(line, w.column, format!("{}{}: the first control point is where the curve starts, and {said} (FANUC alarm PS1009)", w.letter, w.raw));
            return false;
        }
    }
    let Some(w) = weight(words, line, diags) else {
        return false;
    };
    // Checked: the block's settings take effect. A G06.2 is of group 01: it ends a canned cycle, as
    // G01 does.
    it.cycles.active = None;
    if !super::fanuc::apply(it, &settings, line, column, number, diags, out) {
        return false;
    }
    let mut c = Curve { rank, axes, incremental: !absolute, points: 0, knots: 0, closing: 0, ring: [[0.0; 7]; RING], knot: [0.0; RING], knot_at: [(0, 0); RING], point: here, run: 0, failed: false, at: here, tolerance };
    c.push_point(here, w);
    let ok = c.push_knot(it, words, line, column, number, diags, out);
    mode.curve = Some(c);
    ok
}

/// A block's weight `R` (1 without one): positive, or refused.
fn weight(words: &[Word], line: usize, diags: &mut Diags) -> Option<f64> {
    match words.iter().find(|w| w.letter == 'R') {
        None => Some(1.0),
        Some(r) if r.value > 0.0 && r.value <= MAX_WORD => Some(r.value),
        Some(r) => {
            diags.error(line, r.column, format!("R{}: a control point's weight must be more than 0 (a curve with one of 0 or less is not read)", r.raw));
            None
        }
    }
}

/// A number for a message: as few digits as it needs.
fn fmt(v: f64) -> String {
    let s = format!("{v:.6}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" { "0".to_string() } else { s.to_string() }
}

impl Curve {
    /// A curve refused in its first block: its blocks are read to its end.
    fn failed(rank: usize) -> Curve {
        Curve { rank, axes: [false; 6], incremental: false, points: 0, knots: 0, closing: 0, ring: [[0.0; 7]; RING], knot: [0.0; RING], knot_at: [(0, 0); RING], point: [0.0; 6], run: 0, failed: true, at: [0.0; 6], tolerance: [0.0; 6] }
    }

    /// The curve is cut short by `what` (PS1004, PS1005).
    fn unfinished(&self, what: &str, line: usize, column: usize, diags: &mut Diags) {
        let alarm = if self.closing > 0 { "PS1004: fewer blocks of a knot alone than the rank" } else { "PS1005: NURBS mode ended before the curve's knots" };
        diags.error(line, column, format!("{what} before the NURBS curve's last {} blocks of a knot alone (K), which end it: the curve is not run to its end (FANUC alarm {alarm})", self.rank));
    }

    /// A block after the first: a control point with its knot, or a knot alone.
    #[allow(clippy::too_many_arguments)]
    fn block(&mut self, it: &mut Interpreter, words: &[Word], line: usize, column: usize, number: Option<u64>, diags: &mut Diags, out: &mut Vec<Block>) -> bool {
        let knot_alone = words.iter().all(|w| matches!(w.letter, 'K' | 'N')) && words.iter().any(|w| w.letter == 'K');
        if self.failed {
            // The refused curve's blocks make nothing; a word that is no curve's is said still.
            if let Some(w) = words.iter().find(|w| !matches!(w.letter, 'K' | 'R' | 'N') && !AXES.contains(&w.letter)) {
                return refuse_word(w, line, diags, "nothing but control points, weights and knots in NURBS mode (FANUC 15i-MA §4.17)");
            }
            if knot_alone {
                self.closing += 1;
            }
            return true;
        }
        for w in words {
            match w.letter {
                'K' | 'R' | 'N' => {}
                l if AXES.contains(&l) => {
                    let k = AXES.iter().position(|a| *a == l).unwrap_or(0);
                    if !self.axes[k] {
                        self.failed = true;
                        return refuse_word(w, line, diags, "an axis the curve's first block did not name (FANUC 15i-MA §4.17: \"the axis cannot be specified until the next NURBS curved line starts\")");
                    }
                }
                'F' => {
                    self.failed = true;
                    return refuse_word(w, line, diags, "a feed is given in the curve's first block (FANUC 15i-MA §4.17: \"commands other than NURBS interpolation cannot be specified\")");
                }
                'P' => {
                    self.failed = true;
                    return refuse_word(w, line, diags, "the rank is given in the curve's first block only (FANUC 15i-MA §4.17)");
                }
                _ => {
                    self.failed = true;
                    return refuse_word(w, line, diags, "nothing but control points, weights and knots in NURBS mode (FANUC 15i-MA §4.17: \"commands other than NURBS interpolation cannot be specified\")");
                }
            }
        }
        if !words.iter().any(|w| w.letter == 'K') {
            self.failed = true;
            diags.error(line, column, "a NURBS block without its knot (K): each control point block has one, and the curve ends with blocks of a knot alone (FANUC alarm PS1002)");
            return false;
        }
        if knot_alone {
            self.closing += 1;
        } else {
            if self.closing > 0 {
                self.failed = true;
                diags.error(line, column, format!("a control point after a block of a knot alone: the curve ends with {} blocks of a knot alone and no point between them (FANUC alarm PS1004)", self.rank));
                return false;
            }
            let Some(w) = weight(words, line, diags) else {
                self.failed = true;
                return false;
            };
            let mut p = self.point;
            for v in words.iter().filter(|v| AXES.contains(&v.letter)) {
                let k = AXES.iter().position(|a| *a == v.letter).unwrap_or(0);
                p[k] = if self.incremental { self.point[k] + v.value } else { v.value };
            }
            if p.iter().any(|v| !(v.abs() < 1e12)) {
                self.failed = true;
                diags.error(line, column, "a NURBS control point beyond any machine's travel (1e12 program units): a typo?");
                return false;
            }
            self.push_point(p, w);
        }
        let ok = self.push_knot(it, words, line, column, number, diags, out);
        if ok && self.closing == self.rank {
            return self.end(words, line, diags);
        }
        ok
    }

    /// A control point (absolute, program units) and its weight.
    fn push_point(&mut self, p: [f64; 6], w: f64) {
        let mut h = [0.0; 7];
        for k in 0..6 {
            h[k] = w * p[k];
        }
        h[6] = w;
        self.ring[self.points % RING] = h;
        self.points += 1;
        self.point = p;
    }

    /// The block's knot: checked, kept, and the span it completes made.
    #[allow(clippy::too_many_arguments)]
    fn push_knot(&mut self, it: &mut Interpreter, words: &[Word], line: usize, column: usize, number: Option<u64>, diags: &mut Diags, out: &mut Vec<Block>) -> bool {
        let Some(kw) = words.iter().find(|w| w.letter == 'K') else { return false };
        let x = kw.value;
        let i = self.knots;
        if !(x.abs() <= MAX_WORD) {
            self.failed = true;
            return refuse_word(kw, line, diags, "a knot is at most 9 digits of the least increment (999999.999; FANUC 15i-MA §4.17)");
        }
        if i > 0 {
            let before = self.knot[(i - 1) % RING];
            if x < before {
                self.failed = true;
                return refuse_word(kw, line, diags, &format!("knots never decrease, and the one before is {}", fmt(before)));
            }
            self.run = if x == before { self.run + 1 } else { 1 };
        } else {
            self.run = 1;
        }
        if self.run > self.rank {
            self.failed = true;
            return refuse_word(kw, line, diags, &format!("a knot repeated more than the rank ({}) times (FANUC alarm PS1008)", self.rank));
        }
        self.knot[i % RING] = x;
        self.knot_at[i % RING] = (line, kw.column);
        self.knots += 1;
        // PS1007: the first k knots equal (the curve starts at its first control point).
        if i < self.rank && i > 0 && x != self.knot[0] {
            self.failed = true;
            return refuse_word(kw, line, diags, &format!("the first {} knots must be equal, the curve starting at its first control point (FANUC alarm PS1007)", self.rank));
        }
        // The span j = i - p is complete: its knots reach x_(j+p).
        let p = self.rank - 1;
        if i >= 2 * p && i - p < self.points {
            let j = i - p;
            if self.knot[j % RING] < self.knot[(j + 1) % RING] {
                return self.span(it, j, line, kw.column, column, number, diags, out);
            }
        }
        true
    }

    /// The last block of a knot alone: the last k knots equal (PS1007), and the curve's end.
    fn end(&mut self, words: &[Word], line: usize, diags: &mut Diags) -> bool {
        let kw = words.iter().find(|w| w.letter == 'K');
        if self.run < self.rank {
            self.failed = true;
            if let Some(kw) = kw {
                return refuse_word(kw, line, diags, &format!("the last {} knots must be equal, the curve ending at its last control point (FANUC alarm PS1007)", self.rank));
            }
            return false;
        }
        if self.points < self.rank {
            self.failed = true;
            diags.error(line, kw.map_or(1, |w| w.column), format!("a NURBS curve of rank {} has at least {} control points, this one {} (knots: as many as the control points and the rank)", self.rank, self.rank, self.points));
            return false;
        }
        true
    }

    /// The curve's point at `t` in span `j` (x_j <= t <= x_(j+1)): de Boor's algorithm on the
    /// homogeneous points `w P`, then divided by the weight.
    fn eval(&self, j: usize, t: f64) -> [f64; 6] {
        let p = self.rank - 1;
        let mut d = [[0.0; 7]; MAX_RANK];
        for (r, dr) in d.iter_mut().enumerate().take(p + 1) {
            *dr = self.ring[(j - p + r) % RING];
        }
        for r in 1..=p {
            for i in (r..=p).rev() {
                let lo = self.knot[(j - p + i) % RING];
                let hi = self.knot[(j + 1 + i - r) % RING];
                let a = (t - lo) / (hi - lo);
                for c in 0..7 {
                    d[i][c] = (1.0 - a) * d[i - 1][c] + a * d[i][c];
                }
            }
        }
        let mut out = [0.0; 6];
        for k in 0..6 {
            out[k] = if self.axes[k] { d[p][k] / d[p][6] } else { 0.0 };
        }
        out
    }

    /// Span `j`'s chords, each a one-shot G01 to its end.
    #[allow(clippy::too_many_arguments)]
    fn span(&mut self, it: &mut Interpreter, j: usize, line: usize, at: usize, column: usize, number: Option<u64>, diags: &mut Diags, out: &mut Vec<Block>) -> bool {
        let (x0, x1) = (self.knot[j % RING], self.knot[(j + 1) % RING]);
        // Where the span starts is where the last one ended: a knot repeated k times inside the
        // curve breaks it there.
        let start = self.eval(j, x0);
        if (0..6).any(|k| self.axes[k] && !((start[k] - self.at[k]).abs() <= self.tolerance[k])) {
            self.failed = true;
            // Said at the first of the repeated knots.
            let mut first = j;
            while first > 0 && j - first < self.rank - 1 && self.knot[(first - 1) % RING] == x0 {
                first -= 1;
            }
            let (l, c) = self.knot_at[first % RING];
            diags.error(l, c, format!("the NURBS curve breaks at knot {} (a knot repeated {} times inside it): the path between its two ends is not read", fmt(x0), self.rank));
            return false;
        }
        let mut ends: Vec<[f64; 6]> = Vec::new();
        if self.rank == 2 {
            ends.push(self.eval(j, x1));
        } else if !(Chording { axes: self.axes, tolerance: self.tolerance }).chords(&|t| self.eval(j, t), x0, x1, &mut ends) {
            self.failed = true;
            diags.error(line, at, format!("a span of the NURBS curve {}: a typo?", Chording::too_many()));
            return false;
        }
        // The curve's last span ends at its last control point where the knots after it are all
        // equal (the last, which comes later, does not shape the curve): as written.
        let p = self.rank - 1;
        if self.closing > 0 && j + 1 == self.points && self.knot[(j + 1) % RING] == self.knot[(j + p) % RING] {
            if let Some(e) = ends.last_mut() {
                for k in (0..6).filter(|k| self.axes[*k]) {
                    e[k] = self.point[k];
                }
            }
        }
        for e in ends {
            let words: Vec<Word> = (0..6).filter(|k| self.axes[*k]).map(|k| word(AXES[k], e[k], column)).collect();
            if !shot(it, OneShot { motion: Motion::Linear, absolute: true, axes: None, own: false }, &words, line, column, number, diags, out) {
                self.failed = true;
                return false;
            }
            self.at = e;
        }
        true
    }
}
