//! What Fanuc-style controls (Fanuc 30i, Haas NGC) make of a block beyond one move: a reference
//! return through an intermediate point (G28, G30), a move in machine coordinates (G53), a canned
//! drilling cycle (G73-G89 with G98/G99, R, Q, P, K or L). Each becomes the plain moves it is,
//! made by the interpreter as one-shot blocks ([`OneShot`]); the modal state is the control's.
//!
//! Rules, from FANUC Series 15i-MB Operator's Manual B-63784EN §6 (G28/G30: "positioning to the
//! intermediate or reference positions are performed at the rapid traverse rate of each axis";
//! only the axes named move), the 30i User's Manual B-63944EN §5.1 (canned cycles: initial level,
//! R point, G98/G99; under G91 R is from the initial level and Z from the R point; K repeats) and
//! the Haas Mill Operator's Manual (G28 with no axis returns every axis; G53 non-modal machine
//! coordinates; canned cycles repeat with L, dwell P in seconds).

use std::borrow::Cow;

use super::cycles::{self, Active, Kind, Step};
use super::interp::{Dimension, Interpreter, OneShot, Word};
use super::lex::Diags;
use super::{Block, Dialect, Motion};

/// A G word's code without leading zeros (`G01` is `1`, `G05.1` is `5.1`).
pub(crate) fn code(w: &Word) -> String {
    let c = w.raw.trim_start_matches('+').trim_start_matches('0');
    if c.is_empty() || c.starts_with('.') {
        format!("0{c}")
    } else {
        c.to_string()
    }
}

/// A word made here, its value in program units.
pub(crate) fn word(letter: char, value: f64, column: usize) -> Word<'static> {
    Word { letter, value, raw: Cow::Owned(format!("{value}")), column, dimension: Dimension::Modal }
}

/// Make the block's special moves, if it has any: `Some(made)` (false if a defect stopped it), or
/// `None` for an ordinary block (a cycle cancelled by it is cancelled here).
pub(crate) fn expand(it: &mut Interpreter, words: &[Word], line: usize, column: usize, number: Option<u64>, diags: &mut Diags, out: &mut Vec<Block>) -> Option<bool> {
    if let Some(done) = super::fanuc_nurbs::expand(it, words, line, column, number, diags, out) {
        return Some(done);
    }
    expand_plain(it, words, line, column, number, diags, out)
}

/// [`expand`] outside NURBS mode.
pub(crate) fn expand_plain(it: &mut Interpreter, words: &[Word], line: usize, column: usize, number: Option<u64>, diags: &mut Diags, out: &mut Vec<Block>) -> Option<bool> {
    if let Some(done) = super::fanuc_rotation::expand(it, words, line, column, number, diags, out) {
        return Some(done);
    }
    if let Some(done) = super::feature::expand(it, words, line, column, number, diags, out) {
        return Some(done);
    }
    // Most blocks run under no cycle and hold none of the codes below that act without one: passed
    // on without a look at their words' text (each such code is one of these values; G00-G03 and
    // G80 only end a cycle).
    let special = |w: &Word| w.letter == 'G' && matches!(w.value, 28.0 | 30.0 | 53.0 | 73.0 | 74.0 | 76.0 | 81.0..=89.0);
    if it.cycles.active.is_none() && !words.iter().any(special) {
        return None;
    }
    let g: Vec<(String, &Word)> = words.iter().filter(|w| w.letter == 'G').map(|w| (code(w), w)).collect();
    let has = |c: &str| g.iter().find(|(k, _)| k == c).map(|(_, w)| *w);
    // G80, or a motion code (group 01), ends the cycle, in a block of G28, G30 or G53 too
    // (`G80 G91 G28 Z0.`: group 09 and group 00 codes in one block each act).
    let ends_cycle = g.iter().any(|(k, _)| matches!(k.as_str(), "80" | "0" | "1" | "2" | "3"));
    if ends_cycle {
        it.cycles.active = None;
    }
    if let Some(w) = has("28").or(has("30")) {
        return Some(reference_return(it, w, words, line, column, number, diags, out));
    }
    // G92 and G52 take the block's X and Y for the coordinate system: no hole there, and what the
    // control makes of them under a cycle is not read.
    if let Some(w) = has("92").or(has("52")).filter(|_| it.cycles.active.is_some()) {
        diags.error(line, w.column, format!("G{} under a canned cycle: not read (cancel the cycle with G80 first)", w.raw));
        return Some(false);
    }
    if let Some(w) = has("53") {
        return Some(machine_move(it, w, words, line, column, number, diags, out));
    }
    if let Some((kind, w)) = g.iter().find_map(|(k, w)| Kind::from_code(k).map(|kind| (kind, *w))) {
        return Some(drill(it, Some((kind, w)), words, line, column, number, diags, out));
    }
    if ends_cycle {
        return None;
    }
    let positions = words.iter().any(|w| matches!(w.letter, 'X' | 'Y'));
    if it.cycles.active.is_some() && positions {
        return Some(drill(it, None, words, line, column, number, diags, out));
    }
    // The cycle stays the modal motion until G80 or G00-G03: a block that moves an axis other than
    // X or Y under it is no G01 move. Whether the control drills there or only stores the value is
    // not at hand: refused.
    if it.cycles.active.is_some() {
        if let Some(w) = words.iter().find(|w| matches!(w.letter, 'Z' | 'A' | 'B' | 'C')) {
            diags.error(line, w.column, format!("{}{} without X or Y under a canned cycle: whether the control drills at the new value or only stores it is not read (cancel the cycle with G80 first, or give the hole's X Y)", w.letter, w.raw));
            return Some(false);
        }
    }
    None
}

/// The words a special block's own codes take (its axis words, R, Q, P, K, L), kept out of the
/// block of settings (modal codes, M, S, T, F) the interpreter reads first.
pub(crate) fn settings<'a>(words: &'a [Word<'a>], taken: &[char], special: &[&str]) -> Vec<Word<'a>> {
    words.iter().filter(|w| !taken.contains(&w.letter) && !(w.letter == 'G' && special.contains(&code(w).as_str()))).cloned().collect()
}

/// The block of settings (if it has words), read before the special moves; false if a defect.
pub(crate) fn apply(it: &mut Interpreter, words: &[Word], line: usize, column: usize, number: Option<u64>, diags: &mut Diags, out: &mut Vec<Block>) -> bool {
    if words.is_empty() {
        return true;
    }
    match it.block_one(words, line, column, number, diags) {
        Some(b) => {
            out.push(b);
            true
        }
        None => false,
    }
}

/// One one-shot move.
pub(crate) fn shot(it: &mut Interpreter, shot: OneShot, words: &[Word], line: usize, column: usize, number: Option<u64>, diags: &mut Diags, out: &mut Vec<Block>) -> bool {
    if words.iter().all(|w| !"XYZABC".contains(w.letter)) {
        return true;
    }
    it.oneshot = Some(shot);
    match it.block_one(words, line, column, number, diags) {
        Some(b) => {
            out.push(b);
            true
        }
        None => false,
    }
}

const AXES: [char; 6] = ['X', 'Y', 'Z', 'A', 'B', 'C'];

/// `G28 IP` / `G30 [Pn] IP`: to the intermediate point (rapid, the block's own G90/G91), then to
/// the reference point in machine coordinates, for the axes named (Haas' G28 with none: every axis).
#[allow(clippy::too_many_arguments)]
fn reference_return(it: &mut Interpreter, g: &Word, words: &[Word], line: usize, column: usize, number: Option<u64>, diags: &mut Diags, out: &mut Vec<Block>) -> bool {
    let g30 = code(g) == "30";
    // A reference return clears the local system on some controls ("cleared by ... reference (zero)
    // position return", Mitsubishi M700V §14.11) and by a parameter's choice on others: not read.
    if it.local_offset != [0.0; 3] {
        diags.error(line, g.column, format!("G{} with a local coordinate system (G52) set: whether the reference return cancels it depends on the control and its parameters, so the moves after it are not read (cancel it with G52 X0 Y0 Z0 first)", g.raw));
        return false;
    }
    let n = match words.iter().find(|w| w.letter == 'P') {
        None => if g30 { 2 } else { 1 },
        Some(p) if g30 && p.value.fract() == 0.0 && (2.0..=4.0).contains(&p.value) => p.value as usize,
        Some(p) => {
            diags.error(line, p.column, format!("G{} P{}: expected G30 P2, P3 or P4 (the reference point)", g.raw, p.raw));
            return false;
        }
    };
    if !apply(it, &settings(words, &['X', 'Y', 'Z', 'A', 'B', 'C', 'P'], &["28", "30"]), line, column, number, diags, out) {
        return false;
    }
    let mut axes: Vec<Word> = words.iter().filter(|w| AXES.contains(&w.letter)).cloned().collect();
    if axes.is_empty() {
        if it.dialect() != Dialect::Haas || g30 {
            // Fanuc: only the axes named move; none named, none moves.
            return true;
        }
        // Haas: "G28 returns all axes simultaneously to the machine zero position when no axis is specified".
        axes = ['X', 'Y', 'Z', 'A', 'B', 'C'].into_iter().filter(|l| it.has_axis(*l)).map(|l| Word { dimension: Dimension::Incremental, ..word(l, 0.0, g.column) }).collect();
    }
    let origin = OneShot::machine_origin(it);
    let Some(reference) = it.machine_coords().map(|m| m.references.get(n - 1).copied()) else {
        diags.error(line, g.column, format!("G{}: the machine file places no machine coordinates ([machine_coordinates]), so the reference point is unknown", g.raw));
        return false;
    };
    let Some(reference) = reference else {
        diags.error(line, g.column, format!("G{}: the machine file gives no reference point {n} (machine_coordinates.reference_points_mm)", g.raw));
        return false;
    };
    // The intermediate point: nothing to do where it is where the tool stands (`G91 G28 Z0`).
    let still = !it.absolute() && axes.iter().all(|w| w.value == 0.0) || axes.iter().all(|w| w.dimension == Dimension::Incremental && w.value == 0.0);
    if !still && !shot(it, OneShot { motion: Motion::Rapid, absolute: false, axes: None, own: false }, &axes, line, column, number, diags, out) {
        return false;
    }
    let unit = it.unit();
    let to: Vec<Word> = axes
        .iter()
        .map(|w| {
            let k = AXES.iter().position(|l| *l == w.letter).unwrap_or(0);
            // Rotary axes' reference point: their zero.
            word(w.letter, if k < 3 { reference[k] / unit } else { 0.0 }, w.column)
        })
        .collect();
    shot(it, OneShot { motion: Motion::Rapid, absolute: true, axes: origin, own: false }, &to, line, column, number, diags, out)
}

/// `G53 IP`: a rapid move to a point in machine coordinates, this block only (absolute values).
#[allow(clippy::too_many_arguments)]
fn machine_move(it: &mut Interpreter, g: &Word, words: &[Word], line: usize, column: usize, number: Option<u64>, diags: &mut Diags, out: &mut Vec<Block>) -> bool {
    let axes: Vec<Word> = words.iter().filter(|w| AXES.contains(&w.letter)).cloned().collect();
    if !apply(it, &settings(words, &AXES, &["53"]), line, column, number, diags, out) {
        return false;
    }
    if axes.iter().any(|w| w.dimension == Dimension::Incremental) {
        diags.error(line, g.column, format!("G{}: machine coordinates are absolute", g.raw));
        return false;
    }
    let Some(origin) = OneShot::machine_origin(it) else {
        if axes.iter().any(|w| "XYZ".contains(w.letter)) {
            diags.error(line, g.column, format!("G{}: the machine file places no machine coordinates ([machine_coordinates] zero_mm)", g.raw));
            return false;
        }
        return shot(it, OneShot { motion: Motion::Rapid, absolute: true, axes: None, own: false }, &axes, line, column, number, diags, out);
    };
    shot(it, OneShot { motion: Motion::Rapid, absolute: true, axes: Some(origin), own: false }, &axes, line, column, number, diags, out)
}

/// A canned cycle's block (`kind` where it names the cycle, `None` for a new position under the
/// active one): its settings, then for each repeat the positioning, the rapid to the R point and
/// the hole's moves.
#[allow(clippy::too_many_arguments)]
fn drill(it: &mut Interpreter, named: Option<(Kind, &Word)>, words: &[Word], line: usize, column: usize, number: Option<u64>, diags: &mut Diags, out: &mut Vec<Block>) -> bool {
    let haas = it.dialect() == Dialect::Haas;
    let repeat_letter = if haas { 'L' } else { 'K' };
    let find = |l: char| words.iter().find(|w| w.letter == l);
    let before = it.cycles.active;
    // Haas' G83 takes I J K, a peck that shrinks (its L counts the holes).
    let shrinking = haas && named.map(|(k, _)| k).or(before.map(|a| a.kind)) == Some(Kind::G83);
    let taken: &[char] = if shrinking { &['X', 'Y', 'Z', 'A', 'B', 'C', 'R', 'Q', 'P', 'L', 'I', 'J', 'K'] } else { &['X', 'Y', 'Z', 'A', 'B', 'C', 'R', 'Q', 'P', repeat_letter] };
    let Some(start) = cycle_settings(it, words, taken, false, line, column, number, diags, out) else {
        return false;
    };
    let unit = it.unit();
    let (kind, at) = match (named, before) {
        (Some((k, w)), _) => (k, w.column),
        (None, Some(a)) => (a.kind, column),
        (None, None) => return true,
    };
    // The initial level: where the tool stood when the cycle began (a cycle that follows another
    // without G80 keeps it).
    let initial = before.map_or(start[2], |a| a.initial);
    let r = match (find('R'), before) {
        (Some(w), _) if it.absolute() => w.value * unit,
        (Some(w), _) => initial + w.value * unit,
        (None, Some(a)) => a.r,
        // Fanuc's format has R in a cycle's first block; Haas marks it optional ("*R - Position of the
        // R plane", its G81-G89 pages) without saying where the plane then lies.
        (None, None) if it.dialect() == crate::program::Dialect::Haas => {
            diags.error(line, at, format!("G{} without R: Haas marks the R plane optional, but where it lies without one is not in its pages (write R)", kind.code()));
            return false;
        }
        (None, None) => {
            diags.error(line, at, format!("G{}: a new cycle needs its R point (R)", kind.code()));
            return false;
        }
    };
    let bottom = match (find('Z'), before) {
        (Some(w), _) if it.absolute() => w.value * unit,
        (Some(w), _) => r + w.value * unit,
        (None, Some(a)) => a.bottom,
        (None, None) => {
            diags.error(line, at, format!("G{}: a new cycle needs the hole's bottom (Z)", kind.code()));
            return false;
        }
    };
    // Q is modal cycle data, read by the peck cycles alone: "Q (shift at the bottom of a hole) is
    // modal information in a canned cycle, and is also used to specify a depth of cut with G73 and
    // G83" (Series 15i-MA Operator's Manual, G76); a G81-G89 keeps it without using it, so it is
    // checked where a G73 or G83 takes it. FANUC's alarm PS0045 ADDRESS Q NOT FOUND (G73/G83):
    // "the amount of each-time cutting is not specified by address Q, or Q0 is specified" (its
    // alarm list); Haas' pages say no more than Q's meaning, so the same rule is said there without
    // the alarm.
    let fanuc = it.dialect() == crate::program::Dialect::Fanuc;
    let ps0045 = if fanuc { " (FANUC alarm PS0045: Q missing or Q0 in G73/G83)" } else { "" };
    let q_word = find('Q');
    // Haas G83 I J K: "If I, J, and K are specified, a different operating mode is selected. The
    // first pass will cut in by I, each succeeding cut will be reduced by amount J, and the minimum
    // cutting depth is K" (Mill Operator's Manual 96-8000, G83); kept for later holes as Q is.
    let ijk = if shrinking { [find('I'), find('J'), find('K')] } else { [None; 3] };
    let (peck, reduce) = match (ijk, q_word, before) {
        ([None, None, None], Some(w), _) => (Some(w.value * unit), None),
        ([None, None, None], None, Some(a)) => (a.peck, a.reduce),
        ([None, None, None], None, None) => (None, None),
        ([Some(i), Some(j), Some(k)], None, _) => {
            if !(i.value > 0.0) || !(j.value >= 0.0) || !(k.value > 0.0) {
                diags.error(line, i.column, format!("G83 I{} J{} K{}: the first peck I and the least one K must be positive, the reduction J not negative", i.raw, j.raw, k.raw));
                return false;
            }
            (Some(i.value * unit), Some((j.value * unit, k.value * unit)))
        }
        ([Some(_), Some(_), Some(_)], Some(w), _) => {
            diags.error(line, w.column, "G83 with Q and with I J K: either a fixed peck Q or a shrinking one I J K (Haas' two modes)");
            return false;
        }
        (w, _, _) => {
            let at = w.iter().flatten().map(|w| w.column).min().unwrap_or(at);
            diags.error(line, at, "G83: I, J and K go together (the first peck, its reduction each pass, the least peck: Haas' G83)");
            return false;
        }
    };
    let q_at = q_word.map_or(at, |w| w.column);
    // G84/G74 with a Q, written or kept: under rigid tapping the peck tapping cycle ("Peck rigid
    // tapping cycle (G84 or G88)": Q the depth of each cut, back off by parameter No. 5213 or to R
    // by No. 5200#5 PCP; FANUC 0i operator's manual), which is not read.
    if matches!(kind, cycles::Kind::G84 | cycles::Kind::G74) && peck.is_some_and(|q| q != 0.0) {
        let q = q_word.map_or_else(|| format!("the Q{} kept from an earlier cycle block", peck.unwrap_or(0.0) / unit), |w| format!("Q{}", w.raw));
        diags.error(line, q_at, format!("G{} with {q}: under rigid tapping, peck tapping (its back-off is parameter No. 5213 or 5200#5's), which is not read; cancel the cycle with G80 before the tap", kind.code()));
        return false;
    }
    // A Q the block does not write, as its messages name it.
    let kept = || format!("the Q{} kept from an earlier cycle block", peck.unwrap_or(0.0) / unit);
    if kind.pecks() {
        let q_said = || q_word.map_or_else(|| format!("G{}: {}", kind.code(), kept()), |w| format!("Q{}", w.raw));
        match peck {
            None => {
                diags.error(line, at, format!("G{}: a peck cycle needs its depth (Q){ps0045}", kind.code()));
                return false;
            }
            Some(0.0) => {
                diags.error(line, q_at, format!("{}: a peck depth must be positive{ps0045}", q_said()));
                return false;
            }
            // "Be sure to specify a positive value in Q. Negative values are ignored." (Series
            // 30i-MA User's Manual B-63944EN §5.1.6): whether the sign or the value is ignored is
            // not said, so it is not guessed.
            Some(q) if q < 0.0 => {
                let manual = if fanuc { " (FANUC: \"Be sure to specify a positive value in Q. Negative values are ignored\"; what the control then drills is not said)" } else { "" };
                diags.error(line, q_at, format!("{}: a peck depth must be positive{manual}", q_said()));
                return false;
            }
            Some(_) => {}
        }
    }
    // With a shrinking peck, at most as many as the least one makes.
    let least = reduce.map_or(peck, |(_, k)| Some(k));
    if let Some(q) = least.filter(|q| kind.pecks() && cycles::too_many_pecks(r - bottom, *q)) {
        let (letter, at) = match reduce {
            Some(_) => ('K', find('K').map_or(at, |w| w.column)),
            None => ('Q', q_at),
        };
        diags.error(line, at, format!("G{}: {letter}{} makes more than {} pecks of a {} deep hole: a typo?", kind.code(), q / unit, cycles::MAX_PECKS, (r - bottom).abs() / unit));
        return false;
    }
    if kind == Kind::G87 && it.cycles.to_r {
        diags.warning(line, at, "G87 under G99: back boring returns to the initial level whatever G99 says (its R point is below the part)");
    }
    // G76's and G87's shift at the bottom is Q, written in the block or kept from an earlier cycle
    // block ("Q (shift at the bottom of a hole) is modal information in a canned cycle", 15i-MA).
    if matches!(kind, Kind::G76 | Kind::G87) && (q_word.is_some() || peck.is_some_and(|q| q != 0.0)) {
        let q = if q_word.is_some() { "Q".to_string() } else { kept() };
        diags.error(line, at, format!("G{} with {q}: the shift at the bottom goes the way the machine's parameter says (Fanuc No. 5101 RD1/RD2): not modelled", kind.code()));
        it.hold_cycle(line, kind.code());
        return false;
    }
    let dwell_s = match (find('P'), before) {
        (Some(w), _) => match dwell(it.dialect(), w) {
            Ok(t) => Some(t),
            Err(why) => {
                diags.error(line, w.column, why);
                return false;
            }
        },
        (None, Some(a)) => a.dwell_s,
        (None, None) => None,
    };
    let repeats = match find(repeat_letter) {
        None => 1,
        Some(w) if w.value.fract() == 0.0 && (0.0..=9999.0).contains(&w.value) => w.value as usize,
        Some(w) => {
            diags.error(line, w.column, format!("{repeat_letter}{}: expected a repeat count 0 to 9999", w.raw));
            return false;
        }
    };
    if let Err(moves) = cycles::check_cycle_moves(repeats, r - bottom, least.filter(|_| kind.pecks())) {
        let at = find(repeat_letter).map_or(at, |w| w.column);
        diags.error(line, at, format!("G{}: {repeats} holes of this cycle make about {moves} moves, more than the {} read from one block: a typo?", kind.code(), cycles::MAX_CYCLE_MOVES));
        return false;
    }
    let active = Active { kind, bottom, r, peck, reduce, dwell_s, initial };
    it.cycles.active = Some(active);
    let clearance = if kind.pecks() {
        match it.peck_clearance(kind) {
            Ok(d) => d,
            Err(why) => {
                diags.error(line, at, format!("G{}: {why}", kind.code()));
                return false;
            }
        }
    } else {
        0.0
    };
    // The position: X Y (and rotary axes) as written, under the modal G90/G91, repeated K times.
    let position: Vec<Word> = words.iter().filter(|w| matches!(w.letter, 'X' | 'Y' | 'A' | 'B' | 'C')).cloned().collect();
    for k in 0..repeats {
        if (k == 0 || !it.absolute()) && !shot(it, OneShot { motion: Motion::Rapid, absolute: false, axes: None, own: false }, &position, line, column, number, diags, out) {
            return false;
        }
        let z = |v: f64| [word('Z', v / unit, column)];
        if it.position()[2] != r && !shot(it, OneShot { motion: Motion::Rapid, absolute: true, axes: None, own: false }, &z(r), line, column, number, diags, out) {
            return false;
        }
        if !hole_moves(it, cycles::hole(&active, it.cycles.to_r, clearance), 'Z', line, column, number, diags, out) {
            return false;
        }
    }
    true
}

/// A cycle block's settings (its modal codes, F, S, M: every word but the cycle's G code and the
/// `taken` ones), read first; then where the tool stands, with them in effect (a work offset), if
/// the plane is G17 (`any_plane`: in any plane, the cycle drilling along its normal, as LinuxCNC's
/// G18 and G19 cycles do). `None` on a defect.
#[allow(clippy::too_many_arguments)]
pub(crate) fn cycle_settings(it: &mut Interpreter, words: &[Word], taken: &[char], any_plane: bool, line: usize, column: usize, number: Option<u64>, diags: &mut Diags, out: &mut Vec<Block>) -> Option<[f64; 6]> {
    if !apply(it, &settings(words, taken, &cycles::CODES), line, column, number, diags, out) {
        return None;
    }
    if !any_plane && it.plane() != super::Plane::Xy {
        diags.error(line, column, "a canned cycle outside the G17 plane (drilling along X or Y) is not modelled");
        return None;
    }
    Some(it.position())
}

/// A hole's steps as blocks: each move along the drilling axis (`depth`: Z, or Y and X in LinuxCNC's
/// G18 and G19 planes) a one-shot rapid or feed to that level (absolute, program units), each dwell a
/// block of its own; false if a defect stopped it.
#[allow(clippy::too_many_arguments)]
pub(crate) fn hole_moves(it: &mut Interpreter, steps: Vec<Step>, depth: char, line: usize, column: usize, number: Option<u64>, diags: &mut Diags, out: &mut Vec<Block>) -> bool {
    let unit = it.unit();
    let z = |v: f64| [word(depth, v / unit, column)];
    for step in steps {
        let ok = match step {
            Step::Rapid(v) => shot(it, OneShot { motion: Motion::Rapid, absolute: true, axes: None, own: false }, &z(v), line, column, number, diags, out),
            Step::Feed(v) => shot(it, OneShot { motion: Motion::Linear, absolute: true, axes: None, own: false }, &z(v), line, column, number, diags, out),
            Step::Dwell(t) => {
                out.push(Block { dwell_s: Some(t), ..it.still_block(line, column, number) });
                true
            }
        };
        if !ok {
            return false;
        }
    }
    true
}

/// A dwell's P, s: Fanuc's is in milliseconds and takes no decimal point (B-63944EN §5.1: "P: dwell
/// time"; the least input increment of P is 1 ms); Haas reads a P with a decimal point as seconds
/// (its G82 example `P.05`), one without as milliseconds.
pub(crate) fn dwell(dialect: Dialect, p: &Word) -> Result<f64, String> {
    if !(p.value >= 0.0 && p.value.is_finite()) {
        return Err(format!("P{}: a dwell must be 0 or more", p.raw));
    }
    match (dialect, p.raw.contains('.')) {
        (_, false) => Ok(p.value / 1000.0),
        (Dialect::Haas, true) => Ok(p.value),
        (_, true) => Err(format!("P{}: Fanuc reads a dwell's P in milliseconds, without a decimal point", p.raw)),
    }
}
