//! Fanuc's tilted working plane: `G68.2` sets a feature coordinate system, `G53.1` turns the rotary
//! axes so that the tool lies along its Z, `G69` cancels it (FANUC Series 30i-A Descriptions
//! B-63942EN/02 §5.44 "Tilted working plane command"; User's Manual B-63944EN/02 §21.2).
//!
//! Rules:
//! - `G68.2 X Y Z I J K`: "X, Y, Z: feature coordinate system origin", "I, J, K: Euler's angle",
//!   the system "defined on a workpiece coordinate system" (B-63942EN/02 §5.44). The angles turn
//!   about Z, then the new X, then the new Z ([`super::plane::euler_zxz`]; the order as Autodesk's
//!   Fanuc post computes them, `EULER_ZXZ_R`, the Fanuc page drawing it not being at hand). The
//!   frame is the part's: written as though the rotary axes stood at 0, as CAM posts compute it,
//!   and it turns with the table ("the second feature coordinate system", B-63944EN/02 p.719), so a
//!   later block's X Y Z are in it. All six words are needed; the other forms (P1 roll-pitch-yaw, P2
//!   three points, P3 two vectors, P4 projection angles), `G68.3`, `G68.4` and `G53.6` are refused,
//!   their rules not being at hand; so are a second `G68.2` before `G69`, one under G91, and a work
//!   offset changed under the plane.
//! - `G53.1` alone in its block: the rotary axes to the control's output angles for the plane's Z
//!   ([`super::plane::solve_fanuc`]), at rapid (as Autodesk's post and LinuxCNC's remap of it move
//!   them); the linear axes stay. At the pole the free axis stays where it stands, a finding.
//! - Haas' G68.2 is not read here: Haas' documented 3+2 is G254 (the Haas reader's), its G68.2 page
//!   not being at hand.

use std::borrow::Cow;

use super::interp::{Dimension, Interpreter, Word};
use super::lex::Diags;
use super::{Block, Dialect};

const DEG: f64 = std::f64::consts::PI / 180.0;

/// Read the block's tilted-plane codes, if it has any: `Some(made)` (false if a defect stopped it),
/// `None` for a block without them.
pub(crate) fn expand(it: &mut Interpreter, words: &[Word], line: usize, column: usize, number: Option<u64>, diags: &mut Diags, out: &mut Vec<Block>) -> Option<bool> {
    // Most blocks hold none of these codes: passed on without a look at their words' text.
    let plane_code = |w: &Word| w.letter == 'G' && [68.2, 68.3, 68.4, 69.0, 53.1, 53.6].contains(&w.value);
    if it.dialect() != Dialect::Fanuc || it.feature.is_none() && !words.iter().any(plane_code) {
        return None;
    }
    let g: Vec<(String, &Word)> = words.iter().filter(|w| w.letter == 'G').map(|w| (super::fanuc::code(w), w)).collect();
    let has = |c: &str| g.iter().find(|(k, _)| k == c).map(|(_, w)| *w);
    for code in ["68.3", "68.4", "53.6"] {
        if let Some(w) = has(code) {
            diags.error(line, w.column, format!("G{}: only G68.2 with Euler angles and G53.1 are read (this form's rules are not at hand)", w.raw));
            return Some(false);
        }
    }
    if it.feature.is_some() && has("69").is_none() {
        if let Some((_, w)) = g.iter().find(|(k, _)| matches!(k.as_str(), "54" | "55" | "56" | "57" | "58" | "59" | "54.1" | "10" | "92" | "52")) {
            diags.error(line, w.column, format!("G{} under a tilted working plane (G68.2): cancel the plane with G69 before changing the work offset", w.raw));
            return Some(false);
        }
    }
    if let Some(w) = has("68.2") {
        // G90/G91 in the block itself governs its words.
        let absolute = match (has("90"), has("91")) {
            (_, Some(_)) => false,
            (Some(_), None) => true,
            _ => it.absolute(),
        };
        return Some(set_plane(it, w, absolute, words, line, column, number, diags, out));
    }
    if let Some(w) = has("53.1") {
        return Some(turn_axes(it, w, words, line, column, number, diags, out));
    }
    if let Some(w) = has("69") {
        if let Some(origin) = it.feature.take() {
            let datum = it.datum();
            it.set_frame(std::array::from_fn(|k| datum[k] - origin[k]), None, false);
        }
        let rest: Vec<Word> = words.iter().filter(|x| !std::ptr::eq(*x, w)).cloned().collect();
        return Some(super::fanuc::apply(it, &rest, line, column, number, diags, out));
    }
    None
}

/// `G68.2 X Y Z I J K`: the feature coordinate system from here on (no motion); `absolute`: its
/// words are (G90 in effect or in the block).
#[allow(clippy::too_many_arguments)]
fn set_plane(it: &mut Interpreter, g: &Word, absolute: bool, words: &[Word], line: usize, column: usize, number: Option<u64>, diags: &mut Diags, out: &mut Vec<Block>) -> bool {
    let find = |l: char| words.iter().find(|w| w.letter == l);
    if let Some(p) = find('P').filter(|p| p.value != 0.0) {
        diags.error(line, p.column, format!("G68.2 P{}: only Euler angles (P0) are read; roll-pitch-yaw (P1), three points (P2), two vectors (P3) and projection angles (P4) are not", p.raw));
        return false;
    }
    let missing: Vec<char> = ['X', 'Y', 'Z', 'I', 'J', 'K'].into_iter().filter(|&l| find(l).is_none()).collect();
    if !missing.is_empty() {
        let names: String = missing.iter().collect();
        diags.error(line, g.column, format!("G68.2 without {names}: the feature coordinate system needs its origin X Y Z and Euler angles I J K (the format of B-63942EN/02 §5.44; what an omitted word means is not at hand)"));
        return false;
    }
    if it.feature.is_some() {
        diags.error(line, g.column, "G68.2 while a feature coordinate system is in effect: cancel it with G69 first (how a second one composes is not at hand)");
        return false;
    }
    if !absolute {
        diags.error(line, g.column, "G68.2 under G91: write its origin under G90 (how the control reads an incremental origin is not at hand)");
        return false;
    }
    let Some(machine) = it.machine().cloned() else {
        diags.error(line, g.column, "G68.2: a tilted working plane needs the machine's kinematics (--machine)");
        return false;
    };
    let v = |l: char| find(l).map_or(0.0, |w| w.value);
    let r = super::plane::euler_zxz(v('I') * DEG, v('J') * DEG, v('K') * DEG);
    if machine.chain.orientation_solutions(&r.column(2).into_owned()).is_err() {
        diags.error(line, g.column, format!("G68.2: the machine cannot point its tool along the plane's Z ({:.6}, {:.6}, {:.6})", r[(0, 2)], r[(1, 2)], r[(2, 2)]));
        return false;
    }
    // The block's other words (modal codes, M, S, T, F) first.
    let rest = super::fanuc::settings(words, &['X', 'Y', 'Z', 'I', 'J', 'K', 'P'], &["68.2"]);
    if !super::fanuc::apply(it, &rest, line, column, number, diags, out) {
        return false;
    }
    let unit = it.unit();
    let origin = [v('X') * unit, v('Y') * unit, v('Z') * unit];
    let datum = it.datum();
    it.feature = Some(origin);
    it.set_frame(std::array::from_fn(|k| datum[k] + origin[k]), Some(r), false);
    true
}

/// `G53.1`: the rotary axes turned at rapid to put the tool along the plane's Z.
#[allow(clippy::too_many_arguments)]
fn turn_axes(it: &mut Interpreter, g: &Word, words: &[Word], line: usize, column: usize, number: Option<u64>, diags: &mut Diags, out: &mut Vec<Block>) -> bool {
    let (Some(r), Some(machine)) = (it.tilt().filter(|_| it.feature.is_some()), it.machine().cloned()) else {
        diags.error(line, g.column, "G53.1 without a feature coordinate system (G68.2) in effect: nothing to turn the tool to");
        return false;
    };
    if let Some(w) = words.iter().find(|w| !matches!(w.letter, 'G' | 'N')) {
        diags.error(line, w.column, format!("{}{} in a G53.1 block: give G53.1 a block of its own (what the control does with other words there is not at hand)", w.letter, w.raw));
        return false;
    }
    if let Some(w) = words.iter().find(|w| w.letter == 'G' && !std::ptr::eq(*w, g)) {
        diags.error(line, w.column, format!("G{} in a G53.1 block: give G53.1 a block of its own", w.raw));
        return false;
    }
    let sol = match super::plane::solve_fanuc(&machine, &r, it.rot_now()) {
        Ok(s) => s,
        Err(why) => {
            diags.error(line, g.column, format!("G53.1: {why}"));
            return false;
        }
    };
    if let Some(pole) = sol.pole {
        let name = &machine.axes[pole.free_axis].name;
        diags.warning(
            line,
            g.column,
            format!(
                "G53.1 at the pole: the tool lies along {name}'s axis, which leaves {name} free; the control keeps it where it stands (B-63944EN/02 p.680), {name} {:.3} deg: the program depends on it here",
                pole.coord_rot / DEG
            ),
        );
    }
    let letters = it.rotary_letters();
    // The axes' words alone: the one-shot below makes the move a rapid, the modal motion stays.
    let mut moves: Vec<Word> = Vec::new();
    for (k, l) in letters.iter().enumerate() {
        let Some(l) = l else { continue };
        let deg = sol.rot[k] / DEG;
        moves.push(Word { letter: *l, value: deg, raw: Cow::Owned(format!("{deg:.6}")), column: g.column, dimension: Dimension::Modal });
    }
    // Absolute whatever G90/G91 say; the modal motion stays the program's.
    it.oneshot = Some(super::interp::OneShot { motion: super::Motion::Rapid, absolute: true, axes: None, own: false });
    match it.block_one(&moves, line, column, number, diags) {
        Some(b) => {
            out.push(b);
            true
        }
        None => false,
    }
}

#[cfg(test)]
mod tests {
    use super::super::{read, Dialect, ReadOptions, Severity};
    use crate::machine::Machine;

    const D: f64 = std::f64::consts::PI / 180.0;

    /// `generic-bc-head` (a C head carrying the B head: FANUC's "BC type tool axis Z"), its rotary
    /// ranges a turn each way as the manual's example needs.
    fn bc_head() -> ReadOptions {
        let mut m = Machine::builtin("generic-bc-head").unwrap();
        for k in [3, 4] {
            (m.axes[k].limits.min, m.axes[k].limits.max) = (-360.0 * D, 360.0 * D);
        }
        ReadOptions { machine: Some(std::sync::Arc::new(m)), ..ReadOptions::default() }
    }


    /// FANUC's worked example of G53.1 (B-63944EN/02 p.680, example <4>): the tool along -X, from
    /// B180 C90, gives B270 C0. Here the plane comes from G68.2's Euler angles, I-90 J90 K0 (Z, then
    /// X', then Z'': the feature Z is (sin I sin J, -cos I sin J, cos J) = (-1, 0, 0) and its X is
    /// Rz(-90) e_x = (0, -1, 0)); a move then runs in the feature frame, about its origin.
    #[test]
    fn g68_2_and_g53_1_give_the_manuals_output_angles_and_coordinates() {
        let text = "G90 G21\nG0 B180. C90.\nG68.2 X5. Y0 Z0 I-90. J90. K0\nG1 F1000.\nG53.1\nX10. Y0 Z4.\nG69 G54\nG1 X1. Y2. Z3.\n";
        let p = read(text, Dialect::Fanuc, "t.nc", &bc_head());
        assert!(p.messages(Severity::Error).is_empty(), "{:#?}", p.messages(Severity::Error));
        let turn = p.blocks.iter().find(|b| b.line == 5).expect("G53.1 moves the rotary axes");
        let (b, c) = (turn.targets.b.unwrap() / D, turn.targets.c.unwrap() / D);
        assert!((b - 270.0).abs() < 1e-3 && c.abs() < 1e-3, "manual B270 C0, got B{b} C{c}");
        assert_eq!(turn.motion, super::super::Motion::Rapid);
        assert!(turn.targets.x.is_none() && turn.targets.y.is_none() && turn.targets.z.is_none(), "the linear axes stay");
        // X10 Z4 in the feature frame: 10 (0, -1, 0) + 4 (-1, 0, 0), about the origin X5.
        let mv = p.blocks.iter().find(|b| b.line == 6).unwrap();
        let at: Vec<f64> = [mv.targets.x, mv.targets.y, mv.targets.z].iter().zip(mv.datum).map(|(t, d)| (t.unwrap() + d) * 1e3).collect();
        assert!((at[0] - 1.0).abs() < 1e-9 && (at[1] + 10.0).abs() < 1e-9 && at[2].abs() < 1e-9, "{at:?}");
        assert_eq!(mv.motion, super::super::Motion::Linear, "G53.1's rapid leaves the modal G1");
        // G69 (with a work offset in the same block): the workpiece coordinates again.
        let back = p.blocks.iter().find(|b| b.line == 8).unwrap();
        let at: Vec<f64> = [back.targets.x, back.targets.y, back.targets.z].iter().zip(back.datum).map(|(t, d)| (t.unwrap() + d) * 1e3).collect();
        assert!((at[0] - 1.0).abs() < 1e-9 && (at[1] - 2.0).abs() < 1e-9 && (at[2] - 3.0).abs() < 1e-9, "{at:?}");
    }

    /// G68.2's I J K are angles: without a decimal point, thousandths of a degree under G20 too
    /// (FANUC's least input increment of an angle address, 0.001 deg).
    #[test]
    fn g68_2_angles_without_a_point_are_thousandths_of_a_degree() {
        let turn = |text: &str| {
            let p = read(text, Dialect::Fanuc, "t.nc", &bc_head());
            assert!(p.messages(Severity::Error).is_empty(), "{:#?}", p.messages(Severity::Error));
            let b = p.blocks.iter().find(|b| b.line == 3).unwrap();
            [b.targets.b.unwrap(), b.targets.c.unwrap()]
        };
        let inch = turn("G20\nG68.2 X0 Y0 Z0 I10000 J45000 K0\nG53.1\n");
        let mm = turn("G21\nG68.2 X0 Y0 Z0 I10. J45. K0\nG53.1\n");
        assert!((inch[0] - mm[0]).abs() < 1e-12 && (inch[1] - mm[1]).abs() < 1e-12 && (mm[0] / D).abs() > 40.0, "{inch:?} {mm:?}");
    }

    /// The manual's pole (B-63944EN/02 p.680): from B45 C90, a plane whose Z is the tool's at B0 gives
    /// B0 C90, C not moved; the reader says the program depends on it.
    #[test]
    fn g53_1_at_the_pole_keeps_the_free_axis_and_says_so() {
        let p = read("G0 B45. C90.\nG68.2 X0 Y0 Z0 I30. J0 K0\nG53.1\n", Dialect::Fanuc, "t.nc", &bc_head());
        assert!(p.messages(Severity::Error).is_empty(), "{:#?}", p.messages(Severity::Error));
        let turn = p.blocks.iter().find(|b| b.line == 3).unwrap();
        assert!(turn.targets.b.unwrap().abs() < 1e-9 && (turn.targets.c.unwrap() / D - 90.0).abs() < 1e-9, "{:?}", turn.targets);
        let w = p.messages(Severity::Warning);
        assert!(w.iter().any(|m| m.starts_with("3:1: G53.1 at the pole") && m.contains("C 90.000 deg")), "{w:#?}");
    }

    /// What is not read is refused at its word, the block unused.
    #[test]
    fn what_the_plane_rules_do_not_cover_is_refused() {
        for (text, at, needle) in [
            ("G68.2 X0 Y0 Z0 I0 J45\n", "1:1:", "without K"),
            ("G68.2 P1 Q123 X0 Y0 Z0 I0 J45 K0\n", "1:7:", "P1: only Euler angles"),
            ("G68.3\n", "1:1:", "G68.3: only G68.2"),
            ("G53.1\n", "1:1:", "without a feature coordinate system"),
            ("G68.2 X0 Y0 Z0 I0 J45 K0\nG68.2 X0 Y0 Z0 I0 J45 K0\n", "2:1:", "cancel it with G69 first"),
            ("G68.2 X0 Y0 Z0 I0 J45 K0\nG55\n", "2:1:", "G55 under a tilted working plane"),
            ("G68.2 X0 Y0 Z0 I0 J45 K0\nG53.1 X0\n", "2:7:", "a block of its own"),
            ("G91\nG68.2 X0 Y0 Z0 I0 J45 K0\n", "2:1:", "under G91"),
            ("G91 G68.2 X0 Y0 Z0 I0 J45 K0\n", "1:5:", "under G91"),
        ] {
            let p = read(text, Dialect::Fanuc, "t.nc", &bc_head());
            let e = p.messages(Severity::Error);
            assert!(e.iter().any(|m| m.starts_with(at) && m.contains(needle)), "{text:?}: {e:#?}");
        }
        // Without a machine there are no kinematics to tilt with; on Haas G68.2 is not read.
        let p = read("G68.2 X0 Y0 Z0 I0 J45 K0\n", Dialect::Fanuc, "t.nc", &ReadOptions::default());
        assert!(p.messages(Severity::Error).iter().any(|m| m.contains("--machine")));
        let p = read("G68.2 X0 Y0 Z0 I0 J45 K0\n", Dialect::Haas, "t.nc", &bc_head());
        assert!(p.messages(Severity::Error).iter().any(|m| m.contains("tilted working plane")));
        // G69 with no plane in effect (a post's safe start) is read.
        let p = read("G69\nG1 X1 F100\n", Dialect::Fanuc, "t.nc", &bc_head());
        assert!(p.messages(Severity::Error).is_empty(), "{:#?}", p.messages(Severity::Error));
    }
}
