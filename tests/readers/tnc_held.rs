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

/// Cycle 10 ROTATION turns the working plane's axes about the datum until `CYCL DEF 10.1 ROT+0`
/// (TNC 320 Cycle Programming, "ROTATION (Cycle 10)": reset with a rotation angle of 0). The moves
/// under it are refused; after the reset, those until X, Y and Z are written absolute (the move that
/// writes the last of them starts at the unknown point too). The move before the cycle, held for a
/// corner when the cycle came, is kept.
#[test]
fn a_rotation_cycle_holds_the_moves_until_rot_0_and_x_y_are_written() {
    let text = "0 BEGIN PGM H MM\n1 L X+0 Y+0 Z+10 R0 FMAX\n2 L X+5 R0 F500\n3 CYCL DEF 10.0 ROTATION\n4 CYCL DEF 10.1 ROT+30\n5 L X+10\n6 L Y+20\n\
                7 CYCL DEF 10.0 ROTATION\n8 CYCL DEF 10.1 ROT+0\n9 L Z+20\n10 L X+0 Y+0\n11 L X+5\n12 END PGM H MM\n";
    let p = read(text, Dialect::Klartext, "h.h", &ReadOptions::default());
    let e = error_lines(&p);
    assert!(e.iter().all(|l| [4, 5, 6, 7, 8, 9, 10, 11].contains(l)), "{:?}", errors(&p));
    has(&p, 6, 3, "line 5's CYCL DEF 10 (rotation) is in effect on the TNC until its reset (CYCL DEF 10 with ROT+0)");
    has(&p, 7, 3, "line 5's CYCL DEF 10 (rotation)");
    has(&p, 10, 3, "once X, Y and Z are written absolute");
    has(&p, 11, 4, "once X and Y are written absolute");
    assert_eq!(moved(&p), [2, 3, 12], "{:?}", errors(&p));
    // Read for the position: Z 20 from the refused line 10; an incremental IZ after it goes on from there.
    let p = read(&text.replace("11 L X+5\n", "11 L X+5 IZ+1\n"), Dialect::Klartext, "h.h", &ReadOptions::default());
    let z = p.blocks.iter().filter(|b| b.line == 12).find_map(|b| b.targets.z);
    assert_eq!(z.map(|z| z / MM), Some(21.0), "{:?}", errors(&p));
}

/// Under radius compensation (RL) the TNC's moves come out a block late: a move held under a
/// rotation still is dropped where it comes out, and the move before the rotation is kept. A block
/// skip `/` before the cycle's number holds all the same (the TNC runs the block); an incremental
/// datum shift (`IX`) or `PLANE RELATIV` does not end a hold (both are relative to what is not known);
/// `ROT+0.000` is a reset; a `PLANE` refused while it runs (its angle from an unset Q parameter) holds.
#[test]
fn holds_survive_radius_compensation_block_skip_and_relative_statements() {
    let tools = fiveaxis::program::ToolTable::parse("BEGIN TOOL.T MM\nT       NAME       L           R\n1       MILL       +0          +2\n[END]\n").unwrap();
    let options = ReadOptions { tool_table: Some(std::sync::Arc::new(tools)), ..ReadOptions::default() };
    let text = "0 BEGIN PGM H MM\n1 TOOL CALL 1 Z S1000\n2 L X-20 Y-20 Z-5 R0 FMAX\n3 L X+0 Y+0 RL F500\n4 L X+50\n5 CYCL DEF 10.0 ROTATION\n\
                6 CYCL DEF 10.1 ROT+30\n7 L Y+5000\n8 L X+0\n9 END PGM H MM\n";
    let p = read(text, Dialect::Klartext, "h.h", &options);
    has(&p, 8, 3, "line 7's CYCL DEF 10 (rotation)");
    assert!(p.blocks.iter().all(|b| b.line != 8 && b.line != 9), "{:?}", p.blocks.iter().map(|b| b.line).collect::<Vec<_>>());
    assert!(p.blocks.iter().any(|b| b.line == 5), "the move before the rotation is kept");
    for (cycle, end, line) in [("/6 CYCL DEF 10.1 ROT+30", "7 L X+1 F500", 8), ("6 CYCL DEF 7.1 #5", "7 CYCL DEF 7.0 DATUM SHIFT\n8 CYCL DEF 7.1 IX+5", 9)] {
        let text = format!("0 BEGIN PGM H MM\n1 L X+0 Y+0 Z+10 R0 F500\n2 CYCL DEF 7.0 DATUM SHIFT\n3 CYCL DEF 7.1 X+0\n4 CYCL DEF 10.0 ROTATION\n5 L X+1\n{cycle}\n{end}\n9 L X+2\n10 END PGM H MM\n");
        let p = read(&text, Dialect::Klartext, "h.h", &ReadOptions::default());
        has(&p, line + 1, 3, "is in effect on the TNC until");
    }
    let hermle = fiveaxis::machine::Machine::hermle_c600u();
    let on = ReadOptions::default().on(&hermle);
    for (plane, ends) in [("PLANE RELATIV SPA+10 STAY", false), ("PLANE RESET STAY", true)] {
        let text = format!("0 BEGIN PGM H MM\n1 L X+0 Y+0 Z+100 A+0 C+0 R0 F500\n2 PLANE PROJECTED PROPR+20 PROMIN+0 ROT+0 TURN FMAX\n3 {plane}\n4 L X+0 Y+0 Z+50 A+0 C+0\n5 L X+5\n6 END PGM H MM\n");
        let p = read(&text, Dialect::Klartext, "h.h", &on);
        assert_eq!(p.blocks.iter().any(|b| b.line == 6), ends, "{plane}: {:?}", errors(&p));
    }
    let p = read("0 BEGIN PGM H MM\n1 L X+0 Y+0 Z+100 A+0 C+0 R0 F500\n2 PLANE SPATIAL SPA+Q5 SPB+0 SPC+0 STAY\n3 L X+5\n4 END PGM H MM\n", Dialect::Klartext, "h.h", &on);
    has(&p, 4, 3, "line 3's PLANE (tilted working plane)");
    let p = read("0 BEGIN PGM H MM\n1 L X+0 Y+0 Z+10 R0 F500\n2 CYCL DEF 10.0 ROTATION\n3 CYCL DEF 10.1 ROT+30\n4 CYCL DEF 10.1 ROT+0.000\n5 L X+1 Y+0 Z+10\n6 L X+2\n7 END PGM H MM\n", Dialect::Klartext, "h.h", &ReadOptions::default());
    assert!(p.blocks.iter().any(|b| b.line == 7), "{:?}", errors(&p));
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
/// `FUNCTION RESET TCPM` or M129, then the same axes (a form such as AXIS SPAT turns the rotary ones).
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
        let text = format!("0 BEGIN PGM H MM\n1 L X+0 Y+0 Z+100 A+0 C+0 R0 FMAX\n2 FUNCTION TCPM F CONT AXIS POS PATHCTRL AXIS\n3 L X+10 A+10 F500\n4 {end}\n5 L X+0 Y+0 Z+100 A+0 C+0 FMAX\n6 L X+5\n7 END PGM H MM\n");
        let p = read(&text, Dialect::Klartext, "h.h", &options);
        has(&p, 4, 3, "line 3's FUNCTION TCPM is in effect on the TNC until FUNCTION RESET TCPM or M129");
        has(&p, 6, 3, "once X, Y, Z, A and C are written absolute");
        assert_eq!(moved(&p), [2, 7], "{end}: {:?}", errors(&p));
    }
}

/// A move the TNC makes and this reader does not read (`APPR`, `DEP`, FK, in the working plane)
/// leaves the tool where it is not known: the moves after it are refused until X and Y are written
/// absolute. `APPR ... RL` also turns radius compensation on: the contour under it is refused until
/// `DEP` (or an R0 block).
#[test]
fn approach_departure_and_fk_leave_the_position_unknown() {
    let tools = fiveaxis::program::ToolTable::parse("BEGIN TOOL.T MM\nT       NAME       L           R\n1       MILL       +0          +2\n[END]\n").unwrap();
    let options = ReadOptions { tool_table: Some(std::sync::Arc::new(tools)), ..ReadOptions::default() };
    let text = "0 BEGIN PGM A MM\n1 TOOL CALL 1 Z S1000\n2 L X-20 Y-20 Z-5 R0 F500\n3 APPR LT X+0 Y+0 LEN5 RL F500\n4 L X+50\n5 L Y+50\n\
                6 DEP LT LEN5 F500\n7 L X+0 Y+0 R0\n8 L Z+10\n9 L X+5\n10 END PGM A MM\n";
    let p = read(text, Dialect::Klartext, "a.h", &options);
    for l in [5, 6] {
        has(&p, l, 3, "line 4's APPR (radius compensation RL/RR) is in effect on the TNC until a DEP or an R0 block");
    }
    has(&p, 8, 3, "from where line 7's DEP (departure from a contour) left the tool");
    assert_eq!(moved(&p), [3, 9, 10], "{:?}", errors(&p));
    let p = read("0 BEGIN PGM A MM\n1 L X+0 Y+0 Z+0 R0 F500\n2 FL X+10 Y+5\n3 L IX+10\n4 L X+1 Y+2 Z+3\n5 L X+4\n6 END PGM A MM\n", Dialect::Klartext, "a.h", &ReadOptions::default());
    has(&p, 4, 3, "from where line 3's FK (a free contour element) left the tool");
    assert_eq!(moved(&p), [2, 6], "{:?}", errors(&p));
}

/// A subprogram whose moves were held under a rotation is read when it is called again after the
/// rotation's reset (and X, Y, Z written): the held lines are forgotten once nothing is pending. An
/// `APPR` that names Z leaves Z unknown too; a program called (`CALL PGM`) leaves every axis unknown.
#[test]
fn held_lines_are_forgotten_and_named_axes_go_stale() {
    let text = "0 BEGIN PGM L MM\n1 L X+0 Y+0 Z+50 R0 F500\n2 CYCL DEF 10.0 ROTATION\n3 CYCL DEF 10.1 ROT+30\n4 CALL LBL 1\n5 CYCL DEF 10.0 ROTATION\n\
                6 CYCL DEF 10.1 ROT+0\n7 L X+0 Y+0 Z+50 R0 FMAX\n8 CALL LBL 1\n9 L Z+100 R0 FMAX M30\n10 LBL 1\n11 L X+10 Y+0 R0 F500\n12 L X+10 Y+10\n13 LBL 0\n14 END PGM L MM\n";
    let p = read(text, Dialect::Klartext, "l.h", &ReadOptions::default());
    // The subprogram's two moves: refused in the first call, read in the second.
    assert_eq!(p.blocks.iter().filter(|b| b.line == 12 || b.line == 13).count(), 2, "{:?}", errors(&p));
    assert_eq!(errors(&p).iter().filter(|(l, _, _)| *l == 12 || *l == 13).count(), 2, "{:?}", errors(&p));
    let p = read("0 BEGIN PGM A MM\n1 L X+0 Y+0 Z+50 R0 F500\n2 APPR CT X+10 Y+20 Z-10 CCA180 R+10 R0 F100\n3 L X+30 Y+20\n4 L Z+5\n5 L X+1\n6 END PGM A MM\n", Dialect::Klartext, "a.h", &ReadOptions::default());
    has(&p, 4, 3, "once X, Y and Z are written absolute");
    assert_eq!(moved(&p), [2, 6], "{:?}", errors(&p));
    let p = read("0 BEGIN PGM A MM\n1 L X+0 Y+0 Z+50 R0 F500\n2 CALL PGM SUB.H\n3 L IX+10\n4 L X+1 Y+2 Z+3\n5 L X+4\n6 END PGM A MM\n", Dialect::Klartext, "a.h", &ReadOptions::default());
    has(&p, 4, 3, "from where line 3's CALL PGM (a program called) left the tool");
    assert_eq!(moved(&p), [2, 6], "{:?}", errors(&p));
}

/// The TNC's lasting M functions this reader refuses hold the moves until their reset (iTNC 530
/// user's manual 60642x-03 §12.5: "You can cancel M144 by programming M145"; §12.4 M136 until M137):
/// M144 the kinematics' offsets (positions: after M145 X, Y and Z are unknown until written
/// absolute, and the M145 block's own move starts there); M136 feed per revolution (feed moves only,
/// but its own block's move went where this reader did not: the FMAX move after it writes X and is
/// refused once; after M137 nothing is unknown). In Klartext and in DIN/ISO alike.
#[test]
fn lasting_m_functions_hold_the_moves_until_their_reset() {
    let text = "0 BEGIN PGM T MM\n1 TOOL CALL 1 Z S1000\n2 L X+0 Y+0 Z+50 R0 FMAX\n3 L X+10 F500 M144\n4 L X+20 F500\n5 L X+30 M145\n6 L X+40\n\
                7 L X+1 Y+1 Z+1\n8 L X+2 M136\n9 L X+3 FMAX\n10 L X+4 F100\n11 M137\n12 L X+5\n13 END PGM T MM\n";
    let p = read(text, Dialect::Klartext, "t.h", &ReadOptions::default());
    assert_eq!(error_lines(&p), [4, 5, 6, 7, 8, 9, 10, 11], "{:?}", errors(&p));
    has(&p, 4, 15, "M144: not modelled");
    has(&p, 5, 3, "a move while line 4's M144 (the kinematics' offsets at the block end) is in effect on the TNC until M145");
    has(&p, 6, 3, "a move from where the moves under line 4's M144 (the kinematics' offsets at the block end) left the tool");
    has(&p, 6, 3, "once X, Y and Z are written absolute");
    has(&p, 7, 3, "once Y and Z are written absolute");
    has(&p, 8, 3, "once Y and Z are written absolute");
    has(&p, 10, 3, "a move from where line 9's M136");
    has(&p, 11, 4, "a move while line 9's M136 (feed per spindle revolution) is in effect on the TNC until M137");
    assert_eq!(moved(&p), [3, 13], "{:?}", errors(&p));

    let din = "%T G71 *\nN10 T1 G17 S1000 *\nN20 G00 G40 G90 X+0 Y+0 Z+50 *\nN30 G01 X+10 F500 M144 *\nN40 X+20 F500 *\nN50 M145 *\nN60 X+30 *\nN70 X+1 Y+1 Z+1 *\nN80 X+2 M136 *\nN90 G00 X+3 *\nN100 G01 X+4 F100 *\nN110 M137 *\nN120 X+5 *\nN99999999 %T G71 *\n";
    let p = read(din, Dialect::Heidenhain, "t.i", &ReadOptions::default());
    assert_eq!(error_lines(&p), [4, 5, 7, 8, 9, 10, 11], "{:?}", errors(&p));
    has(&p, 5, 5, "a move while line 4's M144 (the kinematics' offsets at the block end) is in effect on the control until M145");
    has(&p, 7, 5, "once X, Y and Z are written absolute");
    has(&p, 8, 5, "once Y and Z are written absolute");
    has(&p, 10, 9, "a move from where the moves under line 9's M136 (feed per spindle revolution) left the tool");
    has(&p, 11, 10, "a move while line 9's M136 (feed per spindle revolution) is in effect on the control until M137");
    assert_eq!(moved(&p), [3, 13], "{:?}", errors(&p));
    // With none in effect, the resets change nothing and are read.
    let p = read("%T G71 *\nN10 T1 G17 S1000 *\nN20 G00 X+0 Y+0 Z+50 M145 *\nN30 M115 *\nN40 M135 *\nN99999999 %T G71 *\n", Dialect::Heidenhain, "t.i", &ReadOptions::default());
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
}

/// A statement refused for an M function this reader does not read (M97, the radius compensation's
/// small contour steps; M94, the rotary display reduced) is run by the TNC: the axes it names (M94:
/// the machine's rotary axes) are where this reader does not know, so the moves after it are
/// refused until they are written absolute (an incremental `IX` does not place X). Klartext and
/// DIN/ISO alike, on the Hermle's A and C.
#[test]
fn a_block_refused_for_an_m_function_the_tnc_runs_leaves_its_axes_unknown() {
    let machine = fiveaxis::machine::Machine::builtin("hermle-c600u").unwrap();
    let on = ReadOptions::default().on(&machine);
    let text = "0 BEGIN PGM T MM\n1 TOOL CALL 1 Z S1000\n2 L X+0 Y+0 Z+50 A+0 C+0 R0 F500\n3 L X+10 F500 M97\n4 L IX+5\n5 L X+20\n6 L Y+5\n7 M94\n8 L X+1\n\
                9 L C+10\n10 L A+5\n11 L X+2 A+0 C+0\n12 END PGM T MM\n";
    let p = read(text, Dialect::Klartext, "t.h", &on);
    assert_eq!(error_lines(&p), [4, 5, 6, 8, 9, 10, 11], "{:?}", errors(&p));
    has(&p, 5, 3, "a move from where line 4's M97 (an M function not read, which the TNC runs) left the tool");
    has(&p, 5, 3, "once X is written absolute");
    has(&p, 9, 3, "line 8's M94 (an M function not read, which the TNC runs)");
    has(&p, 9, 3, "once A and C are written absolute");
    has(&p, 11, 4, "once A is written absolute");
    assert_eq!(moved(&p), [3, 7, 12], "{:?}", errors(&p));

    let din = "%T G71 *\nN10 T1 G17 S1000 *\nN20 G01 G90 X+0 Y+0 Z+50 A+0 C+0 F500 *\nN30 G01 X+10 F500 M97 *\nN40 G91 X+5 *\nN50 G90 X+20 *\nN60 Y+5 *\nN70 M94 *\n\
               N80 X+1 *\nN90 C+10 *\nN100 A+5 *\nN110 X+2 A+0 C+0 *\nN99999999 %T G71 *\n";
    let p = read(din, Dialect::Heidenhain, "t.i", &on);
    assert_eq!(error_lines(&p), [4, 5, 6, 8, 9, 10, 11], "{:?}", errors(&p));
    has(&p, 5, 9, "a move from where line 4's M97 (an M function not read, which the control runs) left the tool");
    has(&p, 9, 5, "once A and C are written absolute");
    assert_eq!(moved(&p), [3, 7, 12], "{:?}", errors(&p));
}

/// `TRANS DATUM RESET` (the TNC 640's datum shift function, as posts write it in their safe start)
/// is read where no datum shift is in effect; `TRANS DATUM AXIS` and the other `TRANS` functions are
/// refused and hold the moves (until `TRANS DATUM RESET`, then X, Y, Z unknown until written
/// absolute); with cycle 7's shift in effect, `TRANS DATUM RESET` is refused (whether it resets that
/// too is not at hand) and holds the moves until a cycle 7 that is read sets X, Y and Z.
#[test]
fn trans_datum_reset_is_read_where_nothing_is_shifted_and_trans_functions_hold() {
    let text = "0 BEGIN PGM T MM\n1 TOOL CALL 1 Z S1000\n2 TRANS DATUM RESET\n3 L X+0 Y+0 Z+50 R0 F500\n4 TRANS DATUM AXIS X+10\n5 L X+5\n6 TRANS DATUM RESET\n\
                7 L X+1 Y+1 Z+1\n8 L X+2\n9 CYCL DEF 7.0 DATUM SHIFT\n10 CYCL DEF 7.1 X+5\n11 TRANS DATUM RESET\n12 L X+3\n13 END PGM T MM\n";
    let p = read(text, Dialect::Klartext, "t.h", &ReadOptions::default());
    assert_eq!(error_lines(&p), [5, 6, 8, 12, 13], "{:?}", errors(&p));
    has(&p, 5, 3, "TRANS DATUM: the TNC's transformation functions are not read");
    has(&p, 6, 3, "line 5's TRANS DATUM (a datum shift) is in effect on the TNC until TRANS DATUM RESET");
    has(&p, 8, 3, "a move from where the moves under line 5's TRANS DATUM (a datum shift) left the tool");
    has(&p, 12, 4, "TRANS DATUM RESET with cycle 7's datum shift in effect");
    has(&p, 13, 4, "line 12's TRANS DATUM RESET (with cycle 7's datum shift in effect) is in effect on the TNC until a CYCL DEF 7 that is read sets X, Y and Z");
    assert_eq!(moved(&p), [4, 9], "{:?}", errors(&p));
    let p = read("0 BEGIN PGM T MM\n1 L X+0 Y+0 Z+50 R0 F500\n2 TRANS MIRROR X\n3 L X+5\n4 END PGM T MM\n", Dialect::Klartext, "t.h", &ReadOptions::default());
    assert_eq!(error_lines(&p), [3, 4], "{:?}", errors(&p));
    has(&p, 4, 3, "line 3's TRANS (a mirroring, rotation or scaling) is in effect on the TNC until its reset (not read)");
}

/// DIN/ISO: a datum shift `G54 X Y Z` moves nothing, so a hold does not refuse it (nor does it place
/// the axes the hold left unknown); a lasting M function refused under radius compensation (M144 in
/// a G42 contour) stops the reading at the next block, whose compensated path is not known, once;
/// M89 (the modal cycle call, refused) holds until M99.
#[test]
fn din_iso_holds_under_compensation_and_datum_shifts() {
    let t = super::tnc_comp::table("T3 P3 D6\n");
    let text = "%T G71 *\nN10 T3 G17 S1000 *\nN20 G00 G90 X-20 Y-20 Z+5 *\nN30 G01 Z-2 F200 M144 *\nN40 G54 X+10 Y+0 Z+0 *\nN50 X+1 *\nN60 M145 *\nN70 G54 X+0 Y+0 Z+0 *\n\
                N80 X+2 *\nN90 X+0 Y+0 Z+5 *\nN95 X-20 Y-20 *\nN100 G42 X+0 Y+0 F500 *\nN110 X+60 M144 *\nN120 Y+40 *\nN130 X+0 *\nN140 G40 X-20 Y-20 *\nN99999999 %T G71 *\n";
    let p = read(text, Dialect::Heidenhain, "t.i", &t);
    assert_eq!(error_lines(&p), [4, 6, 9, 10, 13, 14], "{:?}", errors(&p));
    has(&p, 6, 5, "a move while line 4's M144");
    has(&p, 9, 5, "a move from where the moves under line 4's M144");
    has(&p, 10, 5, "once Y and Z are written absolute");
    has(&p, 14, 6, "line 13's M144 (the kinematics' offsets at the block end) is in effect on the control until M145");
    has(&p, 14, 6, "the rest of the program is not read");
    assert!(p.diagnostics.iter().any(|d| d.line == 15 && d.message.contains("are not run")), "{:?}", p.diagnostics);
    let m = moved(&p);
    assert!(m.starts_with(&[3, 11]) && m.iter().all(|l| [3, 11, 12].contains(l)), "{m:?} {:?}", errors(&p));

    let text = "%T G71 *\nN10 T3 G17 S1000 *\nN20 G00 G90 X+0 Y+0 Z+5 *\nN30 G01 X+10 F200 M89 *\nN40 X+20 *\nN50 M99 *\nN60 X+30 *\nN70 X+0 Y+0 Z+5 *\nN80 X+1 *\nN99999999 %T G71 *\n";
    let p = read(text, Dialect::Heidenhain, "t.i", &t);
    assert_eq!(error_lines(&p), [4, 5, 6, 7, 8], "{:?}", errors(&p));
    has(&p, 5, 5, "line 4's M89 (the modal cycle call: the TNC drills at every later position) is in effect on the control until M99 or a cycle call");
    has(&p, 7, 5, "once X, Y and Z are written absolute");
    assert_eq!(moved(&p), [3, 9], "{:?}", errors(&p));
}

/// A Klartext line the parser refuses keeps its lasting M functions (`M112 T0.05 A10`, whose words
/// are not read): the TNC runs them, so the moves after it are held until M113.
#[test]
fn a_refused_line_keeps_its_lasting_m_functions() {
    let text = "0 BEGIN PGM T MM\n1 L X+0 Y+0 Z+50 R0 F500\n2 L X+5 M112 T0.05 A10\n3 L X+6\n4 L M113\n5 L X+0 Y+0 Z+0\n6 L X+1\n7 END PGM T MM\n";
    let p = read(text, Dialect::Klartext, "t.h", &ReadOptions::default());
    assert_eq!(error_lines(&p), [3, 4, 6], "{:?}", errors(&p));
    has(&p, 4, 3, "line 3's M112 (rounding arcs between straight lines) is in effect on the TNC until M113");
    assert_eq!(moved(&p), [2, 7], "{:?}", errors(&p));
}

/// DIN/ISO's coordinate transformations, the cycles 8, 10 and 11 in G codes, refused here, hold the
/// moves until their reset as the cycles' (TNC 320 Cycle Programming, "Coordinate transformation
/// cycles": mirroring no axis, a rotation angle of 0, the factor 1): `G28 X` (damaged: its axis
/// without a value) until `G28`, `G72 F2` until `G72 F1`, `G73 H+10` until `G73 H+0`; then X, Y and
/// Z are unknown until written absolute.
#[test]
fn din_iso_transformations_hold_until_their_reset() {
    let text = "%T G71 *\nN10 T1 G17 S1000 *\nN20 G00 G90 X+0 Y+0 Z+50 *\nN30 G28 X *\nN40 G01 X+10 F500 *\nN50 G28 *\nN60 X+1 Y+1 Z+1 *\nN70 X+2 *\n\
                N80 G72 F2 *\nN90 X+3 *\nN100 G72 F1 *\nN110 X+0 Y+0 Z+0 *\nN120 G73 H+10 *\nN130 X+4 *\nN140 G73 H+0 *\nN150 X+0 Y+0 Z+50 *\nN160 X+5 *\nN99999999 %T G71 *\n";
    let p = read(text, Dialect::Heidenhain, "t.i", &ReadOptions::default());
    let mut lines = error_lines(&p);
    lines.dedup();
    assert_eq!(lines, [4, 5, 6, 7, 9, 10, 11, 12, 13, 14, 15, 16], "{:?}", errors(&p));
    has(&p, 5, 9, "line 4's G28 (mirroring (cycle 8)) is in effect on the control until its reset (G28 with no axis)");
    has(&p, 7, 5, "a move from where the moves under line 4's G28");
    has(&p, 10, 5, "line 9's G72 (scaling (cycle 11)) is in effect on the control until its reset (G72 F1)");
    has(&p, 14, 6, "line 13's G73 (rotation (cycle 10)) is in effect on the control until its reset (G73 H+0)");
    has(&p, 16, 6, "a move from where the moves under line 13's G73");
    assert_eq!(moved(&p), [3, 8, 17], "{:?}", errors(&p));
    // An increment of 0 (G91 in its block) keeps the rotation: no reset.
    let p = read(&text.replace("N140 G73 H+0 *", "N140 G73 G91 H+0 *"), Dialect::Heidenhain, "t.i", &ReadOptions::default());
    has(&p, 16, 6, "line 15's G73 (rotation (cycle 10)) is in effect on the control");
    // Nor does one under a modal G91 (set in a held block, whose state the program keeps); the
    // block's own G90 makes it the reset (TNC 360 ISO: "N100 G73 G90 H+0 * Cancel rotation").
    let modal = text.replace("N130 X+4 *", "N130 G91 X+4 *");
    let p = read(&modal, Dialect::Heidenhain, "t.i", &ReadOptions::default());
    has(&p, 16, 6, "line 15's G73 (rotation (cycle 10)) is in effect on the control");
    let p = read(&modal.replace("N140 G73 H+0 *", "N140 G73 G90 H+0 *"), Dialect::Heidenhain, "t.i", &ReadOptions::default());
    has(&p, 16, 6, "a move from where the moves under line 13's G73");
}

/// A statement run again (a section repeated) is judged by what was in effect when it runs: a PLANE
/// refused on the first pass (its angle from an unset Q parameter) holds until PLANE RESET, and on
/// the second pass, read (Q5 now set), its turn starts where the held moves left the rotary axes,
/// so it is refused, naming the first pass' plane.
#[test]
fn a_statement_run_again_is_judged_by_the_holds_of_its_earlier_run() {
    let hermle = fiveaxis::machine::Machine::hermle_c600u();
    let on = ReadOptions::default().on(&hermle);
    let text = "0 BEGIN PGM H MM\n1 L X+0 Y+0 Z+100 A+0 C+0 R0 F500\n2 LBL 1\n3 PLANE SPATIAL SPA+Q5 SPB+0 SPC+0 TURN FMAX\n4 PLANE RESET STAY\n5 Q5 = 10\n\
                6 CALL LBL 1 REP1\n7 END PGM H MM\n";
    let p = read(text, Dialect::Klartext, "h.h", &on);
    // Line 4 on the first pass: Q5 unset. On the second: the move from the unknown rotary axes.
    assert!(errors(&p).iter().any(|(l, _, m)| *l == 4 && m.contains("Q5")), "{:?}", errors(&p));
    has(&p, 4, 3, "a move from where the moves under line 4's PLANE (tilted working plane) left the tool");
}

/// DIN/ISO's `G80` is the working plane, cycle 19 (iTNC 530 ISO user's manual, "WORKING PLANE (Cycle
/// G80)"), not read: refused, its A B C no move, and held until `G80` with its angles 0 (cycle 19's
/// reset), after which X, Y, Z are unknown until written.
#[test]
fn din_iso_g80_is_the_working_plane_refused_and_held() {
    let text = "%T G71 *\nN10 T1 G17 S1000 *\nN20 G00 G90 X+0 Y+0 Z+50 *\nN30 G80 A+10 B+0 C+0 *\nN40 X+10 *\nN50 G80 A+0 B+0 C+0 *\nN60 X+0 Y+0 Z+50 *\nN70 X+5 *\nN99999999 %T G71 *\n";
    let p = read(text, Dialect::Heidenhain, "t.i", &ReadOptions::default());
    let mut lines = error_lines(&p);
    lines.dedup();
    assert_eq!(lines, [4, 5, 6, 7], "{:?}", errors(&p));
    has(&p, 4, 5, "G80 (the working plane, cycle 19) is not supported");
    has(&p, 5, 5, "line 4's G80 (tilted working plane (cycle 19)) is in effect on the control until its reset (G80 with the angles 0)");
    has(&p, 7, 5, "a move from where the moves under line 4's G80");
    assert_eq!(moved(&p), [3, 8], "{:?}", errors(&p));
}
