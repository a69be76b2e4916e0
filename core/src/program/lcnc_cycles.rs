//! LinuxCNC's canned cycles (G73, G74, G81-G86, G89 with G98/G99, R, Q, P, L) as the motion
//! LinuxCNC 2.9's interpreter makes of them, in the XY plane: `interp_cycles.cc` (`convert_cycle`,
//! `convert_cycle_xy`, `CYCLE_MACRO`, `convert_cycle_g73` ... `g89`) and the G-code reference
//! §"G80-G89 Canned Cycles". Where they differ from Fanuc's ([`super::fanuc`]): R and Z are sticky
//! only while the same cycle goes on, a tool below R goes up to it first and G98's return level is
//! then R, G74/G84/G89 feed out to the return level itself, a block with only Z drills, the pecks'
//! clearance is LinuxCNC's 0.254 mm, and rotary words, inverse time, a zero L and R below Z are
//! errors, as LinuxCNC makes them.

use super::cycles::{Active, Kind};
use super::fanuc::{code, cycle_settings, hole_moves, shot, word};
use super::interp::{lcnc_group, polar_step, x10, Interpreter, OneShot, Word};
use super::lex::Diags;
use super::{Block, Motion};
use crate::units::MM;

/// The peck clearance of LinuxCNC 2.9 (`G83_RAPID_DELTA`, 0.010 in, times 25.4 in mm programs:
/// the same length either way), m: G73 backs off by it, G83 comes back down to it above the last
/// depth. A machine file's `canned_cycles.g73_peck_clearance_mm` and `g83_peck_clearance_mm`
/// replace it (LinuxCNC 2.10's INI settings); its Fanuc parameters (`g73_retract_mm`...) do not.
const RAPID_DELTA: f64 = 0.254 * MM;

/// What stays from one cycle block to the next (`settings->cycle_*`): the words as written (program
/// units), which each block reads again under its own G90/G91.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(crate) struct Sticky {
    pub r: f64,
    pub z: f64,
    pub p: f64,
    pub q: f64,
}

/// Make the block's cycle moves: `Some(made)`, or `None` for a block that is no cycle's (a motion
/// code or G80 ends the cycle here).
pub(crate) fn expand(it: &mut Interpreter, words: &[Word], line: usize, column: usize, number: Option<u64>, diags: &mut Diags, out: &mut Vec<Block>) -> Option<bool> {
    // Most blocks: no cycle active and no cycle's G code (G73-G89) in them.
    if it.cycles.active.is_none() && !words.iter().any(|w| w.letter == 'G' && (73.0..90.0).contains(&w.value)) {
        return None;
    }
    let g: Vec<(String, &Word)> = words.iter().filter(|w| w.letter == 'G').map(|w| (code(w), w)).collect();
    // A cycle's motion with G53 (named here or modal): "Must use g0 or g1 with g53" (interp_check.cc).
    if let Some((_, w)) = g.iter().find(|(k, _)| k == "53") {
        if !g.iter().any(|(_, w)| lcnc_group(x10(w)) == Some(1) && !(73.0..90.0).contains(&w.value)) {
            diags.error(line, w.column, "G53 with a canned cycle's motion: LinuxCNC refuses it (\"Must use g0 or g1 with g53\")");
            return Some(false);
        }
    }
    // G76 is LinuxCNC's threading cycle, not a drilling one: the interpreter refuses it elsewhere.
    if let Some((kind, w)) = g.iter().find_map(|(k, w)| Kind::from_code(k).filter(|k| *k != Kind::G76).map(|kind| (kind, *w))) {
        if !words.iter().any(|w| matches!(w.letter, 'X' | 'Y' | 'Z' | '@' | '^')) {
            diags.error(line, w.column, format!("G{}: a canned cycle block without X, Y or Z (LinuxCNC: \"All axes missing with motion code\")", code(w)));
            return Some(false);
        }
        return Some(drill(it, Some((kind, w)), words, line, column, number, diags, out));
    }
    // Another code of the motion group ends the cycle (and is read, or refused, as itself).
    // (A block has one code of the group: Interpreter::block refuses two.)
    if g.iter().any(|(_, w)| lcnc_group(x10(w)) == Some(1)) {
        it.cycles.active = None;
        return None;
    }
    // A code that takes the block's axis words for itself (G10, G28, G30, G52, G92, G53): no hole
    // (interp_convert.cc: `mode_zero_covets_axes`).
    if g.iter().any(|(k, _)| matches!(k.as_str(), "10" | "28" | "30" | "52" | "53" | "92")) {
        return None;
    }
    // "The canned cycle will attempt to repeat itself using the next block of code that contains an
    // X, Y, or Z word" (G80 section).
    if it.cycles.active.is_some() && words.iter().any(|w| matches!(w.letter, 'X' | 'Y' | 'Z' | 'A' | 'B' | 'C' | '@' | '^')) {
        return Some(drill(it, None, words, line, column, number, diags, out));
    }
    None
}

/// A cycle block: its settings, the checks `convert_cycle` makes, then `convert_cycle_xy`'s moves.
#[allow(clippy::too_many_arguments)]
fn drill(it: &mut Interpreter, named: Option<(Kind, &Word)>, words: &[Word], line: usize, column: usize, number: Option<u64>, diags: &mut Diags, out: &mut Vec<Block>) -> bool {
    let find = |l: char| words.iter().find(|w| w.letter == l);
    let taken = ['X', 'Y', 'Z', 'A', 'B', 'C', 'R', 'Q', 'P', 'L', '@', '^'];
    let before = it.cycles.active;
    let (kind, at) = match (named, before) {
        (Some((k, w)), _) => (k, w.column),
        (None, Some(a)) => (a.kind, column),
        (None, None) => return true,
    };
    let name = format!("G{}", kind.code());
    if matches!(kind, Kind::G87 | Kind::G88) {
        diags.error(line, at, format!("{name}: LinuxCNC accepts it but its behaviour is undefined (G-code reference, \"currently unimplemented\"): not read"));
        it.hold_cycle(line, kind.code());
        return false;
    }
    if let Some(w) = words.iter().find(|w| matches!(w.letter, 'A' | 'B' | 'C')) {
        diags.error(line, w.column, format!("{}{}: rotary axis words are not allowed in a canned cycle (LinuxCNC: \"Cannot put an {} in canned cycle\")", w.letter, w.raw, w.letter));
        return false;
    }
    let Some(start) = cycle_settings(it, words, &taken, true, line, column, number, diags, out) else {
        return false;
    };
    // The hole's position axes and its drilling axis (interp_cycles.cc: convert_cycle_xy with X Y and
    // Z, convert_cycle_zx with Z X and Y, convert_cycle_yz with Y Z and X).
    let [ia, ib, id] = match it.plane() {
        super::Plane::Xy => [0, 1, 2],
        super::Plane::Zx => [2, 0, 1],
        super::Plane::Yz => [1, 2, 0],
    };
    let letter = |k: usize| ['X', 'Y', 'Z'][k];
    let (depth, plane_name) = (letter(id), ["YZ", "XZ", "XY"][id]);
    if id != 2 && matches!(kind, Kind::G74 | Kind::G84) {
        diags.error(line, at, format!("{name} in the {plane_name} plane: LinuxCNC 2.9 feeds the tap with its axes exchanged (interp_cycles.cc convert_cycle_g74_g84 hands cycle_feed the axes already in the plane's order), not read"));
        it.hold_cycle(line, kind.code());
        return false;
    }
    // The tap's spindle: turning, clockwise for G84, counter-clockwise for G74 (interp_cycles.cc
    // check_g74_g84_spindle; a program starts with it stopped).
    if matches!(kind, Kind::G74 | Kind::G84) {
        let why = match (it.spindle_turning, it.spindle_ccw, kind) {
            (Some(true), true, Kind::G84) => Some("Spindle turning counterclockwise in G84"),
            (Some(true), false, Kind::G74) => Some("Spindle turning clockwise in G74"),
            (Some(true), _, _) => None,
            _ => Some(if kind == Kind::G84 { "Spindle not turning in G84" } else { "Spindle not turning in G74" }),
        };
        if let Some(why) = why {
            diags.error(line, at, format!("{name}: LinuxCNC refuses the tap: \"{why}\" (G84 taps with M3, G74 with M4)"));
            return false;
        }
    }
    // G86 stops the spindle at the bottom and starts it again: it wants it turning
    // (convert_cycle_g86: "Spindle not turning in g86").
    if kind == Kind::G86 && it.spindle_turning != Some(true) {
        diags.error(line, at, format!("{name}: LinuxCNC refuses it with the spindle stopped: \"Spindle not turning in g86\" (M3 or M4 first; a tool change M6 stops it)"));
        return false;
    }
    if it.inverse_time() {
        diags.error(line, at, format!("{name}: LinuxCNC cannot use inverse time feed with canned cycles"));
        return false;
    }
    if it.feed_now().is_none_or(|f| !(f.value_per_min > 0.0)) {
        diags.error(line, at, format!("{name}: LinuxCNC cannot feed with zero feed rate (no F yet)"));
        return false;
    }
    // R and Z as written: sticky while the same cycle goes on (`settings->motion_mode == motion`).
    let same = before.is_some_and(|a| a.kind == kind);
    let sticky = it.cycles.linuxcnc;
    let Some(r_word) = find('R').map(|w| w.value).or(same.then_some(sticky.r)) else {
        diags.error(line, at, format!("{name}: a cycle after another motion needs its R plane (R)"));
        return false;
    };
    let Some(z_word) = find(depth).map(|w| w.value).or(same.then_some(sticky.z)) else {
        diags.error(line, at, format!("{name}: a cycle after another motion needs its {depth} (the hole's bottom; LinuxCNC: \"{depth} value unspecified in {plane_name} plane canned cycle\")"));
        return false;
    };
    let repeats = match find('L') {
        None => 1,
        Some(w) if w.value.fract() == 0.0 && (1.0..=9999.0).contains(&w.value) => w.value as usize,
        Some(w) => {
            diags.error(line, w.column, format!("L{}: expected a repeat count 1 to 9999 (LinuxCNC: \"Cannot do zero repeats of cycle\")", w.raw));
            return false;
        }
    };
    // A P or Q the cycle does not take, and no other code of the block does, is LinuxCNC's error
    // (interp_check.cc `check_other_codes`: "P word with no G2 G3 G4 G10 G64 ... to use it").
    let other_takes = |w: &Word| words.iter().any(|g| g.letter == 'G' && matches!(code(g).as_str(), "4" | "10" | "64")) || (w.letter == 'Q' && words.iter().any(|m| m.letter == 'M' && matches!(m.value, 66.0 | 67.0 | 68.0)));
    for (letter, takes) in [('P', matches!(kind, Kind::G74 | Kind::G82 | Kind::G84 | Kind::G86 | Kind::G89)), ('Q', kind.pecks())] {
        if let Some(w) = find(letter).filter(|w| !takes && !other_takes(w)) {
            diags.error(line, w.column, format!("{letter}{}: {name} takes no {letter} (LinuxCNC: \"{letter} word with no G code that uses it\")", w.raw));
            return false;
        }
    }
    // P (s) and Q: required where the cycle starts, sticky after (G82, G86, G89; G73, G83); G74/G84
    // take the last P any cycle had.
    let p = match find('P') {
        Some(w) if w.value < 0.0 => {
            diags.error(line, w.column, format!("P{}: a dwell must be 0 or more", w.raw));
            return false;
        }
        Some(w) => w.value,
        None if matches!(kind, Kind::G82 | Kind::G86 | Kind::G89) && !same => {
            diags.error(line, at, format!("{name}: a cycle after another motion needs its dwell (P, seconds)"));
            return false;
        }
        None => sticky.p,
    };
    let q = match find('Q') {
        Some(w) => w.value,
        None if kind.pecks() && !same => {
            diags.error(line, at, format!("{name}: a cycle after another motion needs its peck depth (Q)"));
            return false;
        }
        None => sticky.q,
    };
    if kind.pecks() && !(q > 0.0) {
        diags.error(line, find('Q').map_or(at, |w| w.column), format!("{name}: Q{q}: a peck depth must be positive (LinuxCNC: \"negative or zero Q value used\")"));
        return false;
    }
    let unit = it.unit();
    // The level the series began at (`cycle_il`), reset where another motion ran.
    let initial = before.map_or(start[id], |a| a.initial);
    let (r, bottom) = if it.absolute() { (r_word * unit, z_word * unit) } else { (r_word * unit + initial, r_word * unit + initial + z_word * unit) };
    if r < bottom {
        diags.error(line, at, format!("{name}: R {} is below {depth} {}: LinuxCNC refuses it (\"R less than {depth} in cycle in {plane_name} plane\")", r / unit, bottom / unit));
        return false;
    }
    if kind.pecks() && super::cycles::too_many_pecks(r - bottom, q * unit) {
        diags.error(line, find('Q').map_or(at, |w| w.column), format!("{name}: Q{q} makes more than {} pecks of a {} deep hole: a typo?", super::cycles::MAX_PECKS, (r - bottom) / unit));
        return false;
    }
    if let Err(moves) = super::cycles::check_cycle_moves(repeats, r - bottom, kind.pecks().then_some(q * unit)) {
        diags.error(line, find('L').map_or(at, |w| w.column), format!("{name}: {repeats} holes of this cycle make about {moves} moves, more than the {} read from one block: a typo?", super::cycles::MAX_CYCLE_MOVES));
        return false;
    }
    let clearance = match kind {
        Kind::G73 | Kind::G83 => it.lcnc_peck_clearance(kind).unwrap_or(RAPID_DELTA),
        _ => 0.0,
    };
    it.cycles.linuxcnc = Sticky { r: r_word, z: z_word, p, q };
    it.cycles.active = Some(Active { kind, bottom, r, peck: kind.pecks().then_some(q * unit), reduce: None, dwell_s: Some(p), initial });
    let rapid = |absolute| OneShot { motion: Motion::Rapid, absolute, axes: None, own: false };
    let z = |v: f64| [word(depth, v / unit, column)];
    // Below the R plane: straight up to it first, once, and the return level is then R.
    let mut here = start;
    let mut old = initial;
    if old < r {
        if !shot(it, rapid(true), &z(r), line, column, number, diags, out) {
            return false;
        }
        old = r;
        here[id] = r;
    }
    let clear = if it.cycles.to_r { r } else { old };
    let (x_word, y_word) = (find(letter(ia)).map(|w| w.value * unit), find(letter(ib)).map(|w| w.value * unit));
    // Polar hole positions (interp_cycles.cc convert_cycle_xy and CYCLE_MACRO): under G90 the point
    // of `@` and `^` (each kept from the current point when left out), under G91 added about the
    // origin on each repeat, the distance first.
    let (radius, theta) = (find('@').map(|w| w.value * unit), find('^').map(|w| w.value.to_radians()));
    let polar = radius.is_some() || theta.is_some();
    if let (true, false) = (polar, id == 2) {
        diags.error(line, column, format!("{name}: polar coordinates outside the G17 plane (LinuxCNC: \"Cannot use polar coordinate except in G17 plane\")"));
        return false;
    }
    if let (true, Some(w)) = (polar, find('X').or(find('Y'))) {
        diags.error(line, w.column, format!("{}{}: polar coordinates and X or Y in one block (LinuxCNC: \"Cannot specify both polar coordinate and X word\")", w.letter, w.raw));
        return false;
    }
    let (mut x, mut y) = (here[ia], here[ib]);
    for k in 0..repeats {
        if it.absolute() && polar {
            let r = radius.unwrap_or(x.hypot(y));
            let t = theta.unwrap_or(y.atan2(x));
            [x, y] = [r * t.cos(), r * t.sin()];
        } else if it.absolute() {
            (x, y) = (x_word.unwrap_or(x), y_word.unwrap_or(y));
        } else {
            (x, y) = (x + x_word.unwrap_or(0.0), y + y_word.unwrap_or(0.0));
            // CYCLE_MACRO: the distance, then the angle, each refused at the origin.
            for (dr, dt) in [(radius, None), (None, theta)].into_iter().filter(|(dr, dt)| dr.is_some() || dt.is_some()) {
                let Some(p) = polar_step([x, y], dr.unwrap_or(0.0), dt.unwrap_or(0.0)) else {
                    diags.error(line, column, format!("{name}: polar increments at the origin (LinuxCNC: \"Incremental motion with polar coordinates is indeterminate when at the origin\")"));
                    return false;
                };
                [x, y] = p;
            }
        }
        let xy = [word(letter(ia), x / unit, column), word(letter(ib), y / unit, column)];
        let ok = if k == 0 && here[id] > r {
            shot(it, rapid(true), &xy, line, column, number, diags, out) && shot(it, rapid(true), &z(r), line, column, number, diags, out)
        } else {
            let to_clear = [xy[0].clone(), xy[1].clone(), z(clear)[0].clone()];
            shot(it, rapid(true), &to_clear, line, column, number, diags, out) && (clear <= r || shot(it, rapid(true), &z(r), line, column, number, diags, out))
        };
        if !ok {
            return false;
        }
        if !hole_moves(it, super::cycles::lcnc_hole(kind, r, bottom, clear, q * unit, p, clearance), depth, line, column, number, diags, out) {
            return false;
        }
    }
    true
}
