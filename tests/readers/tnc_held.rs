//! A TNC statement this reader refuses whose effect lasts on the control (a rotation, scaling or
//! mirroring cycle, `PLANE PROJECTED`, a `FUNCTION TCPM` of a form not read, a datum shift from a
//! table): every move until the statement that ends it is refused, naming it, and so are the moves
//! after that until the axes it displaced are written absolute.

use super::*;

/// The lines of a program's errors, in order.
fn error_lines(p: &Program) -> Vec<usize> {
    errors(p).iter().map(|(l, _, _)| *l).collect()
}

/// The lines that made blocks with targets.
fn moved(p: &Program) -> Vec<usize> {
    let mut l: Vec<usize> = p.blocks.iter().filter(|b| !b.targets.is_empty()).map(|b| b.line).collect();
    l.dedup();
    l
}

/// Cycle 10 ROTATION turns the working plane's X and Y about the datum until `CYCL DEF 10.1 ROT+0`
/// (TNC 320 Cycle Programming, "ROTATION (Cycle 10)": reset with a rotation angle of 0). The moves
/// under it are refused; after the reset, those until X and Y are written (Z is not turned: Z alone
/// is refused as it starts at the unknown X Y, then X Y read, then all). The move before the cycle,
/// held for a corner when the cycle came, is kept.
#[test]
fn a_rotation_cycle_holds_the_moves_until_rot_0_and_x_y_are_written() {
    let text = "0 BEGIN PGM H MM\n1 L X+0 Y+0 Z+10 R0 FMAX\n2 L X+5 R0 F500\n3 CYCL DEF 10.0 ROTATION\n4 CYCL DEF 10.1 ROT+30\n5 L X+10\n6 L Y+20\n\
                7 CYCL DEF 10.0 ROTATION\n8 CYCL DEF 10.1 ROT+0\n9 L Z+20\n10 L X+0 Y+0\n11 L X+5\n12 END PGM H MM\n";
    let p = read(text, Dialect::Klartext, "h.h", &ReadOptions::default());
    let e = error_lines(&p);
    assert!(e.iter().all(|l| [4, 5, 6, 7, 8, 9, 10, 11].contains(l)), "{:?}", errors(&p));
    has(&p, 6, 3, "line 5's CYCL DEF 10 (rotation) is in effect on the TNC until its reset (CYCL DEF 10 with ROT+0)");
    has(&p, 7, 3, "line 5's CYCL DEF 10 (rotation)");
    has(&p, 10, 3, "once X and Y are written absolute");
    has(&p, 11, 4, "once X and Y are written absolute");
    assert_eq!(moved(&p), [2, 3, 12], "{:?}", errors(&p));
    // Read for the position: Z 20 from the refused line 10, so the last move stays at Z 20.
    let z = p.blocks.iter().filter(|b| b.line == 12).find_map(|b| b.targets.z);
    assert!(z.is_none_or(|z| (z - 20.0 * MM).abs() < 1e-12), "{z:?}");
}

/// Scaling (cycle 11) ends at SCL 1, written joined or apart; a factor from a Q parameter is not
/// known, so the hold stays. Every axis is scaled: after the reset X, Y and Z must be written.
#[test]
fn a_scaling_cycle_ends_at_scl_1_and_not_at_a_q_parameter() {
    for (reset, ends) in [("SCL1", true), ("SCL 1", true), ("SCL+Q5", false)] {
        let text = format!("0 BEGIN PGM H MM\n1 L X+0 Y+0 Z+10 R0 F500\n2 CYCL DEF 11.0 SCALING\n3 CYCL DEF 11.1 SCL0.5\n4 L X+10\n5 CYCL DEF 11.0 SCALING\n6 CYCL DEF 11.1 {reset}\n7 L X+1 Y+2 Z+3\n8 L X+5\n9 END PGM H MM\n");
        let p = read(&text, Dialect::Klartext, "h.h", &ReadOptions::default());
        has(&p, 5, 3, "line 4's CYCL DEF 11 (scaling)");
        if ends {
            has(&p, 8, 3, "once X, Y and Z are written absolute");
            assert_eq!(moved(&p), [2, 9], "{reset}: {:?}", errors(&p));
        } else {
            has(&p, 8, 3, "line 7's CYCL DEF 11 (scaling)");
            has(&p, 9, 3, "line 7's CYCL DEF 11 (scaling)");
            assert_eq!(moved(&p), [2], "{reset}: {:?}", errors(&p));
        }
    }
}

/// `PLANE PROJECTED` (refused: the sign of its angles is not at hand) tilts the plane on the TNC:
/// the moves are refused until a PLANE that is read (`PLANE RESET STAY`), then until X, Y, Z and the
/// machine's rotary axes (A, C on the Hermle) are written. A refused `FUNCTION TCPM` form holds until
/// `FUNCTION RESET TCPM` or M129, then X, Y and Z.
#[test]
fn plane_projected_and_a_tcpm_form_not_read_hold_until_what_ends_them() {
    let hermle = fiveaxis::machine::Machine::hermle_c600u();
    let options = ReadOptions::default().on(&hermle);
    let text = "0 BEGIN PGM H MM\n1 L X+0 Y+0 Z+100 A+0 C+0 R0 FMAX\n2 PLANE PROJECTED PROPR+20 PROMIN+0 ROT+0 TURN FMAX\n3 L X+10 Y+0 Z+50 F500\n\
                4 PLANE RESET STAY\n5 L X+0 Y+0 Z+100 R0 FMAX\n6 L A+0 C+0 FMAX\n7 L X+5\n8 END PGM H MM\n";
    let p = read(text, Dialect::Klartext, "h.h", &options);
    has(&p, 4, 3, "line 3's PLANE (tilted working plane) is in effect on the TNC until a PLANE that is read");
    has(&p, 6, 3, "once X, Y, Z, A and C are written absolute");
    has(&p, 7, 3, "once A and C are written absolute");
    assert_eq!(moved(&p), [2, 8], "{:?}", errors(&p));
    for end in ["FUNCTION RESET TCPM", "L M129"] {
        let text = format!("0 BEGIN PGM H MM\n1 L X+0 Y+0 Z+100 A+0 C+0 R0 FMAX\n2 FUNCTION TCPM F CONT AXIS POS PATHCTRL AXIS\n3 L X+10 A+10 F500\n4 {end}\n5 L X+0 Y+0 Z+100 FMAX\n6 L X+5\n7 END PGM H MM\n");
        let p = read(&text, Dialect::Klartext, "h.h", &options);
        has(&p, 4, 3, "line 3's FUNCTION TCPM is in effect on the TNC until FUNCTION RESET TCPM or M129");
        has(&p, 6, 3, "once X, Y and Z are written absolute");
        assert_eq!(moved(&p), [2, 7], "{end}: {:?}", errors(&p));
    }
}
