//! Fanuc's and Haas' coordinate system rotation in the selected plane, `G17 G68 X Y R` (`G18 G68 Z X
//! R`, `G19 G68 Y Z R`) until `G69` (FANUC Series 16/18-C Operator's Manual B-62764EN §15.10 and
//! Series 15i-MA B-63324EN §14 "Coordinate system rotation"; Series 0i-C B-64113EN §11.12: "G17 (G18
//! or G19): Select the plane that contains the figure to be rotated", the centre "two of the X_, Y_
//! and Z_ axes that correspond to the current plane selected"; Haas Mill Operator's Manual, G68
//! Rotation: "Only the values in the plane of rotation are rotated"): a programmed point P of the
//! plane goes to C + rot(P - C, R), C the centre. Its rules:
//! - The plane's two axis words are the centre (absolute, in the work coordinate system); without
//!   them the tool's position when G68 is read. R is the angle, deg, counter-clockwise positive (from
//!   the plane's first axis to its second, as G03 turns: about +Z in G17, +Y in G18, +X in G19).
//!   "Values in the line that contains the G68 command are not rotated" (Haas): the block moves nothing.
//! - Fanuc: "The center of rotation for an incremental command programmed after G68 but before an
//!   absolute command is the tool position when G68 was programmed"; Haas does not say, so there an
//!   incremental move before the first absolute one is refused.
//! - "G17, G18 or G19 must not be designated in the mode of coordinate system rotation"; "The first
//!   move command after G69 must be specified as an absolute command" (B-62764EN).
//! - Refused, their rules depending on the machine's parameters or not at hand: R under G91 (Fanuc
//!   parameter 5400#0, Haas Setting 73), G68 without R (parameter 5410/6411, Haas Setting 72), a work
//!   offset change, G53, G28/G30, tool-centre point or a tilted plane with it.
//!
//! The interpreter keeps the program's point; a block leaves it placed ([`Rotation::place`]).

use super::fanuc::{apply, code};
use super::interp::{rot, Dimension, Interpreter, Word};
use super::lex::Diags;
use super::{Block, Dialect};
use crate::units::DEG;

/// A coordinate system rotation in effect (program coordinates of its plane's two axes, m; rad).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Rotation {
    /// The plane's axes (0 X, 1 Y, 2 Z), the first turned towards the second by a positive angle.
    pub axes: [usize; 2],
    pub centre: [f64; 2],
    pub angle: f64,
    /// Fanuc: the tool's position when G68 was read, the centre of incremental moves until an
    /// absolute one.
    pub until_absolute: Option<[f64; 2]>,
}

impl Rotation {
    /// The centre the next move turns about: Fanuc's tool position at G68 until an absolute move.
    pub(crate) fn centre_in_use(&self) -> [f64; 2] {
        self.until_absolute.unwrap_or(self.centre)
    }

    /// `p` (program X Y, m) where the rotation puts it, about the centre in use.
    pub(crate) fn turn(&self, p: [f64; 2]) -> [f64; 2] {
        let c = self.centre_in_use();
        let t = rot([p[0] - c[0], p[1] - c[1]], self.angle);
        [c[0] + t[0], c[1] + t[1]]
    }

    /// The plane's two coordinates of a point (X Y Z).
    pub(crate) fn of(&self, p: &[f64]) -> [f64; 2] {
        [p[self.axes[0]], p[self.axes[1]]]
    }

    /// A block made in the program's frame, placed: its plane's two targets (one written, the other
    /// where the block before left it, `last`) and an arc's centre turned.
    pub(crate) fn place(&self, b: &mut Block, last: &[f64; 6]) {
        let [u, v] = self.axes;
        if b.targets.axis(u).is_some() || b.targets.axis(v).is_some() {
            let p = [b.targets.axis(u).unwrap_or(last[u]), b.targets.axis(v).unwrap_or(last[v])];
            let t = self.turn(p);
            b.targets.set_axis(u, t[0]);
            b.targets.set_axis(v, t[1]);
        }
        if let Some(a) = b.arc.as_mut() {
            let t = self.turn([a.centre[u], a.centre[v]]);
            (a.centre[u], a.centre[v]) = (t[0], t[1]);
        }
    }

    /// The letters of its plane's two axes.
    pub(crate) fn letters(&self) -> [char; 2] {
        self.axes.map(|k| ['X', 'Y', 'Z'][k])
    }
}

/// G90 or G91 for the block's words: its own code, else the modal one.
fn modal_absolute(it: &Interpreter, words: &[Word]) -> bool {
    let has = |c: &str| words.iter().any(|w| w.letter == 'G' && code(w) == c);
    if has("91") {
        false
    } else {
        has("90") || it.absolute()
    }
}

/// A block with `G68` or `G69`, or any block under a rotation that this reader refuses there:
/// `Some(made)`, or `None` where the block is an ordinary one.
pub(crate) fn expand(it: &mut Interpreter, words: &[Word], line: usize, column: usize, number: Option<u64>, diags: &mut Diags, out: &mut Vec<Block>) -> Option<bool> {
    // Compared by value: most blocks have neither, and their words' text is not looked at.
    let g68 = words.iter().find(|w| w.letter == 'G' && w.value == 68.0);
    let g69 = words.iter().any(|w| w.letter == 'G' && w.value == 69.0);
    let fail = |diags: &mut Diags, col: usize, why: String| {
        diags.error(line, col, why);
        Some(false)
    };
    if g68.is_none() && it.rotation2d.is_none() {
        // "The first move command after G69 must be specified as an absolute command."
        if let Some(plane) = it.after_g69 {
            if let Some(w) = words.iter().find(|w| plane.contains(&w.letter)) {
                if !w.dimension.absolute(modal_absolute(it, words)) {
                    return fail(diags, w.column, format!("{}{}: the first move command after G69 must be specified as an absolute command (FANUC)", w.letter, w.raw));
                }
                it.after_g69 = None;
            }
        }
        // Haas' G69 with no rotation in effect cancels nothing (Fanuc's also ends G68.2, read there).
        if g69 && it.dialect() == Dialect::Haas {
            let rest: Vec<Word> = words.iter().filter(|w| !(w.letter == 'G' && w.value == 69.0)).cloned().collect();
            return Some(apply(it, &rest, line, column, number, diags, out));
        }
        return None;
    }
    if let (Some(r), false) = (it.rotation2d, g69) {
        // What this reader does not read under a rotation.
        for w in words.iter().filter(|w| w.letter == 'G') {
            let why = match code(w).as_str() {
                "17" | "18" | "19" => "G17, G18 or G19 must not be designated in the mode of coordinate system rotation (FANUC)",
                c if matches!(c, "54" | "55" | "56" | "57" | "58" | "59" | "54.1" | "92" | "52" | "10") || crate::program::interp::haas_extra_offset(c) => {
                    "a work offset changed under coordinate system rotation G68: where the centre goes is not read (cancel it with G69 first)"
                }
                "53" | "28" | "30" => "machine coordinates or a reference return under coordinate system rotation G68 are not read (cancel it with G69 first)",
                "43.4" | "43.5" | "68.2" => "tool-centre point or a tilted working plane under coordinate system rotation G68 is not read",
                _ => continue,
            };
            return fail(diags, w.column, format!("G{}: {why}", w.raw));
        }
        // Haas: an incremental move before the first absolute one.
        if r.until_absolute.is_some() && it.dialect() == Dialect::Haas && g68.is_none() {
            if let Some(w) = words.iter().find(|w| r.letters().contains(&w.letter) && !w.dimension.absolute(modal_absolute(it, words))) {
                return fail(diags, w.column, format!("{}{}: an incremental move after G68 before an absolute one: about which centre Haas turns it is not in its manual (write the first move after G68 in G90)", w.letter, w.raw));
            }
        }
        g68?;
    }
    if g69 {
        // The tool stays; its program point is where it stands. The first move must be absolute.
        if let Some(r) = it.rotation2d.take() {
            let p = it.position();
            it.set_position_pair(r.axes, r.turn(r.of(&p)));
            it.after_g69 = Some(r.letters());
        }
        if g68.is_none() {
            let rest: Vec<Word> = words.iter().filter(|w| !(w.letter == 'G' && w.value == 69.0)).cloned().collect();
            return Some(apply(it, &rest, line, column, number, diags, out));
        }
    }
    let g = g68?;
    if it.tilt().is_some() || it.tcp() {
        return fail(diags, g.column, format!("G{}: coordinate system rotation under tool-centre point (G43.4/G43.5) or a tilted working plane (G68.2) is not read", g.raw));
    }
    // Its block: the settings first (a G17 or G90 in it counts), then the rotation.
    let taken = ['X', 'Y', 'Z', 'R', 'I', 'J', 'K'];
    let settings = super::fanuc::settings(words, &taken, &["68"]);
    if let Some(w) = words.iter().find(|w| matches!(w.letter, 'I' | 'J' | 'K')) {
        return fail(diags, w.column, format!("G{} {}{}: only G68 with the plane's two axes and R (a rotation in the selected plane) is read; I J K make Fanuc's three-dimensional conversion", g.raw, w.letter, w.raw));
    }
    if !apply(it, &settings, line, column, number, diags, out) {
        return Some(false);
    }
    // The plane the block's settings leave (a G18 in it counts).
    let (a0, a1, an) = it.plane().axes();
    let letters = [a0, a1].map(|k| ['X', 'Y', 'Z'][k]);
    if let Some(w) = words.iter().find(|w| w.letter == ['X', 'Y', 'Z'][an]) {
        return fail(diags, w.column, format!("G{} {}{}: the centre of rotation is given by the plane's two axes ({} {}); {} is not one of them", g.raw, w.letter, w.raw, letters[0], letters[1], w.letter));
    }
    let Some(r) = words.iter().find(|w| w.letter == 'R') else {
        return fail(diags, g.column, format!("G{} without R: the angle is then the machine's parameter (FANUC No. 5410, Haas Setting 72), not the program's", g.raw));
    };
    // On a calculator-type machine (FANUC DPI No. 3401#0 = 1) it is in degrees.
    if !r.raw.contains('.') && !it.machine().is_some_and(|m| m.calculator_input) {
        return fail(diags, r.column, format!("R{}: an angle without a decimal point counts least increments, 0.001 or 0.00001 deg as the machine's parameter says (FANUC No. 6400#2); write R{}.", r.raw, r.raw));
    }
    if !r.dimension.absolute(it.absolute()) {
        return fail(diags, r.column, format!("R{} under G91: whether the angle adds to the last one is the machine's parameter (FANUC No. 5400#0, Haas Setting 73)", r.raw));
    }
    let p = it.position();
    let unit = it.unit();
    let word = |l: char| words.iter().find(|w| w.letter == l);
    for w in [word(letters[0]), word(letters[1])].into_iter().flatten() {
        if w.dimension == Dimension::Incremental || !it.absolute() && w.dimension != Dimension::Absolute {
            return fail(diags, w.column, format!("{}{}: the centre of rotation is an absolute position (write G68 under G90)", w.letter, w.raw));
        }
    }
    let centre = [word(letters[0]).map_or(p[a0], |w| w.value * unit), word(letters[1]).map_or(p[a1], |w| w.value * unit)];
    // A second G68 before G69 (in the same plane: no plane is selected under a rotation): a new
    // centre and angle (the tool's position read as before it).
    let here = it.rotation2d.map_or([p[a0], p[a1]], |old| old.turn(old.of(&p)));
    if it.rotation2d.is_some() {
        it.set_position_pair([a0, a1], here);
    }
    it.rotation2d = Some(Rotation { axes: [a0, a1], centre, angle: r.value * DEG, until_absolute: Some(here) });
    it.after_g69 = None;
    Some(true)
}
