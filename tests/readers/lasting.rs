//! A modal code the control runs and the reader refuses (Fanuc's and Haas' cutter compensation,
//! scaling, mirror image, tilted plane, Haas' feed per revolution, LinuxCNC's dynamic tool length)
//! stays in effect on the control until its cancel: the moves under it are refused, naming the
//! refused block (read for the program's state only), and so are the moves after the cancel until
//! the axes the held moves placed are written absolute (the control left them where the held code
//! put them).

use super::*;

/// The lines of a program's errors, in order.
fn error_lines(p: &Program) -> Vec<usize> {
    errors(p).iter().map(|(l, _, _)| *l).collect()
}

/// The X a line's move ends at (mm, workpiece), if the line made one.
fn x_at(p: &Program, line: usize) -> Option<f64> {
    p.blocks.iter().filter(|b| b.line == line).filter_map(|b| b.targets.x.map(|x| (x + b.datum[0]) / MM)).last()
}

/// FANUC B-64484EN "Cutter compensation C": G41/G42 offset every move until G40, and the move with
/// G40 starts from the offset point. Each move from G41 to G40's block is refused naming line 5;
/// the moves before and after are read, at the X they write.
#[test]
fn moves_under_a_refused_cutter_compensation_are_refused_until_g40() {
    for dialect in [Dialect::Fanuc, Dialect::Haas] {
        let text = "%\nO1000\nG21 G90 G17 G94\nG0 X0. Y0. Z10.\nG41 D1 G1 X10. Y10. F500.\nG1 X20.\nG0 Z20.\nG40 X30. Y0.\nG1 X40. F500.\nM30\n%\n";
        let p = read(text, dialect, "t.nc", &ReadOptions::default());
        // Line 6 also lacks the feed line 5 gave (refused, its F took no effect here).
        assert_eq!(error_lines(&p), [5, 6, 6, 7, 8], "{dialect:?}: {:?}", errors(&p));
        for l in [6, 7] {
            has(&p, l, 4, "line 5's G41 (cutter radius compensation) is in effect on the control until G40");
        }
        has(&p, 8, 5, "G40 with a move after line 5's G41");
        assert_eq!(x_at(&p, 4), Some(0.0), "{dialect:?}");
        assert_eq!(x_at(&p, 9), Some(40.0), "{dialect:?}: the move after G40 is read");
        for l in 5..=8 {
            assert_eq!(x_at(&p, l), None, "{dialect:?}: line {l} made no move");
        }
    }
}

/// A G40 without a move ends the hold; a G40 in a refused block too (the control runs it). The
/// first move after it starts where the compensation left the tool in X and Y (G17): refused until
/// both are written absolute; Z is not compensated, so a move of Z alone before it is refused too
/// (it starts at the unknown X Y) and the move that writes X and Y is the last refused.
#[test]
fn a_cancel_ends_the_hold_in_a_block_of_its_own_or_a_refused_one() {
    let p = read("%\nO1000\nG21 G90 G17 G94\nG0 X0. Y0. Z10.\nG42 D1\nG40\nG0 Z20.\nG1 X5. Y0. F100.\nG91 G1 Z1.\nM30\n%\n", Dialect::Fanuc, "t.nc", &ReadOptions::default());
    assert_eq!(error_lines(&p), [5, 7, 8], "{:?}", errors(&p));
    has(&p, 7, 4, "once X and Y are written absolute");
    has(&p, 8, 4, "once X and Y are written absolute");
    let z = p.blocks.iter().filter(|b| b.line == 9).filter_map(|b| b.targets.z.map(|z| (z + b.datum[2]) / MM)).last();
    assert_eq!(z, Some(21.0), "the refused Z move was read for the position: Z20, then 1 more");
    // Line 6 is refused for its G39 (unknown), but its G40 acts on the control.
    let p = read("%\nO1000\nG21 G90 G17 G94\nG0 X0. Y0. Z10.\nG42 D1\nG40 G39\nG1 X5. Y0. F100.\nG1 X6.\nM30\n%\n", Dialect::Fanuc, "t.nc", &ReadOptions::default());
    assert_eq!(error_lines(&p), [5, 6, 7], "{:?}", errors(&p));
    assert_eq!(x_at(&p, 8), Some(6.0));
}

/// FANUC B-64484EN "Scaling" and "Programmable mirror image": G51 scales and G51.1 mirrors every
/// move until G50 and G50.1. Under each, a move is refused naming it; after the cancel the move is
/// read. G50 and G50.1 with nothing in effect change nothing: read without a word.
#[test]
fn scaling_and_mirror_image_hold_until_g50_and_g50_1() {
    for (on, off, what) in [("G51 X0. Y0. P2", "G50", "scaling"), ("G51.1 X0.", "G50.1", "mirror image")] {
        let text = format!("%\nO1000\nG21 G90 G17 G94 F100.\n{off}\nG0 X1. Y0. Z10.\n{on}\nG1 X2.\n{off}\nG1 X3. Y0. Z10.\nG1 X4.\nM30\n%\n");
        let p = read(&text, Dialect::Haas, "t.nc", &ReadOptions::default());
        let e = errors(&p);
        assert!(e.iter().all(|(l, _, _)| [6, 7, 9].contains(l)), "{on}: {e:?}");
        has(&p, 7, 4, &format!("line 6's G{} ({what}) is in effect on the control until {off}", &on[1..on.find(' ').unwrap()]));
        has(&p, 9, 4, "once X, Y and Z are written absolute");
        assert_eq!(x_at(&p, 5), Some(1.0), "{on}");
        assert_eq!(x_at(&p, 10), Some(4.0), "{on}");
    }
}

/// Haas' G95 is refused: under it a feed move is refused (its feed is per revolution on the
/// control), a rapid is read (it does not take the feed), and G94 ends it. G95's own block moved X
/// to where this reader did not go: the rapid that writes X next is refused once, the next read.
#[test]
fn a_refused_feed_per_revolution_holds_feed_moves_only() {
    let text = "%\nO1000\nG21 G90 G17 G94\nG0 X0. Y0. Z10.\nG95 G1 X1. F0.1\nG0 X2.\nG0 X2.5\nG1 X3.\nG94 G1 X4. F200.\nM30\n%\n";
    let p = read(text, Dialect::Haas, "t.nc", &ReadOptions::default());
    // Line 8 also lacks the feed line 5 gave (refused, its F took no effect here).
    assert_eq!(error_lines(&p), [5, 6, 8, 8], "{:?}", errors(&p));
    has(&p, 6, 4, "a move from where the moves under line 5's G95 (feed per revolution) left the tool");
    has(&p, 8, 4, "line 5's G95 (feed per revolution)");
    assert_eq!(x_at(&p, 6), None);
    assert_eq!(x_at(&p, 7), Some(2.5));
    assert_eq!(x_at(&p, 9), Some(4.0));
}

/// A code the reader reads, refused for a defect of its block (a G83 with a peck of 0), leaves
/// nothing held: the control stops at that block's alarm, and the next move is read as written.
/// LinuxCNC's G43.1 (dynamic tool length, not read) holds until G49.
#[test]
fn a_defect_in_a_read_code_holds_nothing_and_g43_1_holds_until_g49() {
    let text = "%\nO1000\nG20 G90 G17 G94\nG0 X0. Y0. Z1.\nG83 X1. Y0. Z-.5 R.1 F10. Q0.\nX2. Y0.\nG80\nM30\n%\n";
    let p = read(text, Dialect::Haas, "t.nc", &ReadOptions::default());
    assert_eq!(error_lines(&p), [5], "{:?}", errors(&p));
    let p = read("G21 G90 G94\nG0 X0 Y0 Z10\nG43.1 Z1\nG0 X5\nG49\nG0 X6 Y0 Z10\nG0 X7\nM2\n", Dialect::Rs274, "t.ngc", &ReadOptions::default());
    assert_eq!(error_lines(&p), [3, 4, 6], "{:?}", errors(&p));
    has(&p, 4, 4, "line 3's G43.1 (dynamic or additional tool length offset) is in effect on the control until G49");
    assert_eq!(x_at(&p, 7), Some(7.0));
}

/// A held move is read for the program's state: its F is the modal feed after it (as on the control).
#[test]
fn a_held_moves_feed_stays_in_effect() {
    let p = read("%\nO1000\nG21 G90 G17 G94\nG0 X0. Y0. Z10.\nG41 D1\nG1 X1. F100.\nG40\nG1 X2. Y0.\nG1 X3.\nM30\n%\n", Dialect::Fanuc, "t.nc", &ReadOptions::default());
    assert_eq!(error_lines(&p), [5, 6, 8], "{:?}", errors(&p));
    let b = p.blocks.iter().find(|b| b.line == 9).expect("line 9 is read");
    assert_eq!(b.feed.map(|f| f.value_per_min), Some(100.0));
}

/// A block refused under a hold keeps its own held code (G41 under G51 holds after G50); a line
/// damaged before its words are read (a vacant `#100`) holds its G41 too; under a hold a full circle
/// by its centre alone is a move, G10's and G04's words are not; a drilling cycle under G95 is a
/// feed move; Fanuc's G68.2 refused in a form not read (P1) holds until G69; normal direction
/// control G41.1 holds until G40.1 (not G40); G43.4 ends G43.1's hold (one group).
#[test]
fn holds_reach_every_way_a_block_is_refused_and_end_at_their_groups_codes() {
    let fanuc = |body: &str| read(&format!("%\nO1000\nG21 G90 G17 G94 F100.\nG0 X0. Y0. Z10.\n{body}M30\n%\n"), Dialect::Fanuc, "t.nc", &ReadOptions::default());
    let p = fanuc("G51 X0. Y0. P2\nG41 D1 G1 X10. Y10.\nG50\nG1 X20.\nG40\nG1 X30. Y0. Z10.\nG1 X31.\n");
    assert_eq!(error_lines(&p), [5, 5, 6, 6, 8, 10], "{:?}", errors(&p));
    has(&p, 8, 4, "line 6's G41");
    assert_eq!(x_at(&p, 11), Some(31.0));
    let p = fanuc("G41 D1 G1 X#100 Y10.\nG1 X20.\nG40\nG1 X30.\n");
    assert_eq!(error_lines(&p), [5, 6, 8], "{:?}", errors(&p));
    has(&p, 6, 4, "line 5's G41");
    let p = fanuc("G41 D1\nG10 L2 P2 X100. Y0. Z0.\nG3 I-10.\nG40\n");
    assert_eq!(error_lines(&p), [5, 7], "{:?}", errors(&p));
    has(&p, 7, 4, "line 5's G41");
    let p = fanuc("G41.1\nG40\nG1 X5.\nG40.1\nG1 X6. Y0. Z10.\nG1 X7.\n");
    assert_eq!(error_lines(&p), [5, 7, 9], "{:?}", errors(&p));
    has(&p, 7, 4, "line 5's G41.1 (normal direction control) is in effect on the control until G40.1");
    assert_eq!(x_at(&p, 10), Some(7.0));
    let p = fanuc("G43.1 H1\nG1 X5.\nG43.4 H1\nG1 X6.\n");
    assert_eq!(error_lines(&p), [5, 6, 8], "{:?}", errors(&p));
    has(&p, 6, 4, "until G49 or G43 or G44 or G43.4 or G43.5");
    let hermle = fiveaxis::machine::Machine::hermle_c600u();
    // After G69 the linear axes and the machine's rotary axes (A, C on the Hermle: G53.1 under the
    // plane turns them) are unknown until written.
    let p = read("%\nO1000\nG21 G90 G17 G94\nG0 X0. Y0. Z10.\nG68.2 P1 X0. Y0. Z0. I0. J30. K0.\nG0 X10.\nG69\nG0 X5. Y0. Z10.\nG0 A0. C0.\nG0 X6.\nM30\n%\n", Dialect::Fanuc, "t.nc", &ReadOptions::default().on(&hermle));
    assert_eq!(error_lines(&p), [5, 6, 8, 9], "{:?}", errors(&p));
    has(&p, 8, 4, "once X, Y, Z, A and C are written absolute");
    has(&p, 9, 4, "once A and C are written absolute");
    assert_eq!(x_at(&p, 10), Some(6.0));
    has(&p, 6, 4, "line 5's G68.2 (tilted working plane)");
    let p = read("%\nO1000\nG21 G90 G17 G94\nG0 X0. Y0. Z10.\nG95\nG0 X10. Y10.\nG81 X20. Y10. Z-5. R1. F0.1\nG80\nG94\nM30\n%\n", Dialect::Haas, "t.nc", &ReadOptions::default());
    assert_eq!(error_lines(&p), [5, 7], "{:?}", errors(&p));
    has(&p, 7, 5, "line 5's G95");
}

/// A canned cycle refused for what is not read (Fanuc's G87 with its shift Q: the direction is a
/// machine parameter; LinuxCNC's G88, "currently unimplemented") is run by the control at every later
/// hole position until G80 or a group-01 code: those positions are refused, naming it; after the
/// cancel the drilling axis stands at the cycle's initial or R level, unknown until Z is written
/// (the move that writes it starts there too, as does the block that cancels it with a move: it
/// starts where the held moves left the tool). A G83 refused for a defect (its Q0) holds nothing.
#[test]
fn a_canned_cycle_refused_for_what_is_not_read_holds_until_g80() {
    let p = read("%\nO1000\nG21 G90 G17 G94\nG0 X0. Y0. Z10.\nG98 G87 X0. Y0. Z-5. R2. Q1. F100.\nX10. Y10.\nG80\nG0 X0. Y0.\nG0 Z20.\nG0 X5.\nM30\n%\n", Dialect::Fanuc, "t.nc", &ReadOptions::default());
    assert_eq!(error_lines(&p), [5, 6, 8, 9], "{:?}", errors(&p));
    has(&p, 6, 1, "line 5's G87 (canned cycle: the control drills at every later position) is in effect on the control until G80, a G00-G03 or another canned cycle");
    has(&p, 8, 4, "once Z is written absolute");
    assert_eq!(x_at(&p, 10), Some(5.0));
    // Another cycle replaces it on the control: its first hole starts where the held cycle left the
    // tool (refused), the next is read.
    let p = read("%\nO1000\nG21 G90 G17 G94\nG0 X0. Y0. Z10.\nG98 G87 X0. Y0. Z-5. R2. Q1. F100.\nG81 X5. Y5. Z-2. R2. F100.\nX6.\nG80\nM30\n%\n", Dialect::Fanuc, "t.nc", &ReadOptions::default());
    assert_eq!(error_lines(&p), [5, 6], "{:?}", errors(&p));
    has(&p, 6, 5, "G80, a G00-G03 or another canned cycle with a move after line 5's G87");
    assert_eq!(x_at(&p, 7), Some(6.0));
    let p = read("G21 G90 G94 G17\nG0 X0 Y0 Z10\nG88 X1 Y1 Z-2 R1 F100\nX2 Y2\nG80\nG0 Z10\nG0 X5\nM2\n", Dialect::Rs274, "t.ngc", &ReadOptions::default());
    assert_eq!(error_lines(&p), [3, 4, 6], "{:?}", errors(&p));
    has(&p, 4, 1, "line 3's G88 (canned cycle");
    assert_eq!(x_at(&p, 7), Some(5.0));
}

/// LinuxCNC's G80 ends a refused spline's mode too (no motion mode after it, as after any G80): a
/// later block refused for its own defect is not blamed on the spline. The 840D: a point refused in
/// a `BSPLINE` mode on a line the reader restores (a `G64` with it) still leaves its axes unknown.
#[test]
fn g80_ends_a_mode_not_read_and_an_840d_point_leaves_its_axes_unknown() {
    let p = read("G21 G90 G94 G17\nG0 X0 Y0 Z10\nG5.2 X1 Y2 P1 L3\nG80\nG0 X0 Y0 Z10\nG80\nZ-5\nG0 X1 Y1\nM2\n", Dialect::Rs274, "t.ngc", &ReadOptions::default());
    assert!(errors(&p).iter().all(|(l, _, m)| *l != 8 && !(*l == 7 && m.contains("G5.2"))), "{:?}", errors(&p));
    assert_eq!(x_at(&p, 8), Some(1.0));
    let p = read("G71 G90 G94\nG0 X0 Y0 Z10\nBSPLINE X10 Y10\nX20 Y20 Z-5 G64\nG0 X0 Y0\nG1 X50 F100\nG1 X1 Y1 Z1\nG1 X2\nM30\n", Dialect::Sinumerik, "t.mpf", &ReadOptions::default());
    has(&p, 5, 4, "once X, Y and Z are written absolute");
    has(&p, 6, 4, "once Z is written absolute");
    assert_eq!(x_at(&p, 8), Some(2.0), "{:?}", errors(&p));
}

/// A `G10 L20 P1` refused (a rotary-axis offset, B10., not modelled); the control sets the offset,
/// so selecting it (`G54.1 P1`) is refused too, and the moves in it are held until G54-G59, after
/// which X, Y and Z are unknown until written. A `G54.1 P2` the program never set is read (zero).
#[test]
fn an_offset_set_by_a_refused_g10_l20_is_not_selected_silently() {
    let text = "%\nO1000\nG21 G90 G17 G94\nG10 L20 P1 X50. Y0. Z0. B10.\nG0 X0. Y0. Z10.\nG54.1 P1\nG0 X10. Y0.\nG54\nG0 X1. Y1. Z1.\nG0 X2.\nG54.1 P2\nG0 X3.\nM30\n%\n";
    let p = read(text, Dialect::Fanuc, "t.nc", &ReadOptions::default());
    assert_eq!(error_lines(&p), [4, 6, 7, 9], "{:?}", errors(&p));
    has(&p, 4, 25, "G10 L20 B10.: rotary-axis work offsets are not modelled");
    has(&p, 6, 7, "G54.1 P1: line 4's G10 L20 P1 set this offset");
    has(&p, 7, 4, "is in effect on the control until G54-G59 or another additional work offset");
    assert_eq!(x_at(&p, 10), Some(2.0));
    assert_eq!(x_at(&p, 12), Some(3.0));
}

/// Haas: `G10 L20 P3` refused sets G112 and G154 P3 on the control (Haas, "Programmable Offsets":
/// P1-P20 are G110-G129 and G154 P1-P20); `G112` is refused, its moves held until another offset is
/// read (`G154 P4`, the operator's, zero: its own move starts where the held moves left the tool),
/// then Y and Z unknown until written. A `G10 L20 P4` refused while G154 P4 is in effect holds the
/// next move at once; `G55` ends it, and X, Y, Z are unknown until written.
#[test]
fn haas_offsets_set_by_a_refused_g10_l20_are_held() {
    let text = "%\nO1000\nG21 G90 G17 G94\nG10 L20 P3 X50. B10.\nG0 X0. Y0. Z10.\nG112\nG0 X10.\nG154 P3\nG154 P4 G0 X1.\nG0 X1. Y1. Z1.\nG10 L20 P4 X5. B1.\nG0 X2.\nG55\nG0 X3. Y3. Z3.\nG0 X4.\nM30\n%\n";
    let p = read(text, Dialect::Haas, "t.nc", &ReadOptions::default());
    assert_eq!(error_lines(&p), [4, 6, 7, 8, 9, 10, 11, 12, 14], "{:?}", errors(&p));
    has(&p, 4, 17, "G10 L20 B10.: rotary-axis work offsets are not modelled");
    has(&p, 6, 1, "G112: line 4's G10 L20 P3 set this offset");
    has(&p, 7, 4, "line 6's G112 (an additional work offset its refused G10 L20 set) is in effect");
    has(&p, 8, 6, "G154 P3: line 4's G10 L20 P3 set this offset");
    has(&p, 9, 12, "with a move after line 8's G154");
    has(&p, 10, 4, "a move from where the moves under line 8's G154");
    has(&p, 12, 4, "line 11's G10 L20 (an additional work offset its refused G10 L20 set) is in effect");
    has(&p, 14, 4, "a move from where the moves under line 11's G10 L20");
    assert_eq!(x_at(&p, 5), Some(0.0));
    for l in [7, 9, 10, 12, 14] {
        assert_eq!(x_at(&p, l), None, "line {l}");
    }
    assert_eq!(x_at(&p, 15), Some(4.0), "{:?}", errors(&p));
    // Haas' G54.1 Pn names the same offsets as G154 Pn.
    let p = read("%\nG21 G90 G17 G94\nG10 L20 P2 X1. B1.\nG0 X0. Y0. Z10.\nG54.1 P2\nG0 X1.\nM30\n%\n", Dialect::Haas, "t.nc", &ReadOptions::default());
    assert_eq!(error_lines(&p), [3, 5, 6], "{:?}", errors(&p));
    has(&p, 6, 4, "line 5's G54.1 (an additional work offset its refused G10 L20 set) is in effect");
}

/// The 840D's frame statements not read (`MIRROR`, `SCALE`, `ROTS` and their additive forms, `CROTS`)
/// change the programmable frame the control runs every later move in, until a `TRANS` or `ROT`
/// replaces it (NC programming 6FC5398-2EP40 12/2019 §2.12: "old instructions for offsetting,
/// rotation, scaling factor, mirroring" cleared): the moves, a drilling cycle and a swivel under it are
/// refused naming it; after `TRANS`, X, Y and Z are unknown until written absolute.
#[test]
fn an_840d_frame_not_read_holds_the_moves_until_trans_or_rot() {
    let text = "G71 G90 G94\nG0 X0 Y0 Z10\nMIRROR X0\nG1 X10 F100\nCYCLE81(10,0,2,-5)\nAMIRROR Y0\nG1 Y5\nTRANS\nG1 X1\nG1 X1 Y1 Z1\nG1 X2\n\
                SCALE X2\nG0 X3\nROT Z0\nG0 X0 Y0 Z5\nG0 X4\nM30\n";
    let p = read(text, Dialect::Sinumerik, "t.mpf", &ReadOptions::default());
    assert_eq!(error_lines(&p), [3, 4, 5, 6, 7, 9, 10, 12, 13, 15], "{:?}", errors(&p));
    has(&p, 4, 4, "a move while line 3's MIRROR (a programmable frame not read: scaling, mirroring or a solid-angle rotation) is in effect on the control until a TRANS or ROT that is read");
    has(&p, 5, 1, "CYCLE81: line 3's MIRROR");
    has(&p, 7, 4, "line 6's AMIRROR");
    has(&p, 9, 4, "a move from where the moves under line 6's AMIRROR");
    has(&p, 10, 4, "once Y and Z are written absolute");
    has(&p, 13, 4, "line 12's SCALE");
    assert_eq!(x_at(&p, 2), Some(0.0));
    assert_eq!(x_at(&p, 11), Some(2.0), "{:?}", errors(&p));
    assert_eq!(x_at(&p, 16), Some(4.0), "{:?}", errors(&p));
    for l in [4, 7, 9, 10, 13, 15] {
        assert_eq!(x_at(&p, l), None, "line {l}");
    }
}

/// The 840D's other lasting statements not read hold until the statement that ends them is read:
/// `TRANSMIT` until `TRAFOOF` (then X, Y, Z unknown until written); `ORICONCW` (G group 51) until
/// `ORIVECT` (the orientation is the programmed one at each block's end: nothing unknown after);
/// `FLIN` until `FNORM` (feed moves only); `CUT3DC` until `CUT2D`, which acts only with G41/G42: a
/// move without compensation is read, a compensated one stops the reading (its path not known).
#[test]
fn the_840ds_lasting_statements_hold_until_their_end() {
    let text = "G71 G90 G94\nG0 X0 Y0 Z10\nTRANSMIT\nG1 X10 F100\nTRAFOOF\nG1 X1 Y1 Z1\nG1 X2\nORICONCW\nG1 X3\nORIVECT\nG1 X4\n\
                FLIN\nG0 X5\nG1 X6\nFNORM\nG1 X7\nCUT3DC\nG1 X8\nCUT2D\nG1 X0 Y0 Z0\nG1 X9\nM30\n";
    let p = read(text, Dialect::Sinumerik, "t.mpf", &ReadOptions::default());
    assert_eq!(error_lines(&p), [3, 4, 6, 8, 9, 12, 14, 17], "{:?}", errors(&p));
    has(&p, 4, 4, "line 3's TRANSMIT (a kinematic transformation not read) is in effect on the control until TRAFOOF");
    has(&p, 6, 4, "a move from where the moves under line 3's TRANSMIT");
    has(&p, 9, 4, "line 8's ORICONCW (an orientation interpolation not read) is in effect on the control until ORIVECT, ORIPLANE or ORIAXES");
    has(&p, 14, 4, "line 12's FLIN (a feed profile over the block not read) is in effect on the control until FNORM");
    for (l, x) in [(7, 2.0), (11, 4.0), (13, 5.0), (16, 7.0), (18, 8.0), (21, 9.0)] {
        assert_eq!(x_at(&p, l), Some(x), "line {l}: {:?}", errors(&p));
    }
    let tools = ReadOptions { tool_table: Some(std::sync::Arc::new(fiveaxis::program::ToolTable::parse("T1 P1 D6\n").unwrap())), ..Default::default() };
    let p = read("G71 G90 G94\nT1 D1\nG0 X-20 Y-20 Z10\nCUT3DC\nG1 G41 X0 Y0 F100\nG1 X10\nM30\n", Dialect::Sinumerik, "t.mpf", &tools);
    assert_eq!(error_lines(&p), [4, 5], "{:?}", errors(&p));
    has(&p, 5, 1, "a compensated move while line 4's CUT3DC (3D tool radius compensation, not read) is in force on the control until CUT2D");
    has(&p, 5, 1, "the rest of the program is not read");
}

/// The orientation relative to the path, `ORIPATH`/`ORIPATHS`, is of G group 51 as the cones are
/// (NC programming 12/2019 §4.3.51): held until `ORIAXES`. `ORIROTR`/`ORIROTT`/`ORIROTC` (G group 54,
/// the rotation vector's interpolation; Fundamentals 10.2004 §12.3) hold until `ORIROTA`, the group's
/// default, which is read (alone: nothing held, nothing refused).
#[test]
fn the_840ds_path_relative_orientation_and_rotation_vector_modes_hold_until_their_group_default() {
    let text = "G71 G90 G94\nG0 X0 Y0 Z10\nORIPATH\nG1 X1 F100\nORIAXES\nG1 X2\nORIROTT\nG1 X3\nORIROTA\nG1 X4\nORIROTA\nORIPATHS\nG0 X5\nORIVECT\nG1 X6\nM30\n";
    let p = read(text, Dialect::Sinumerik, "t.mpf", &ReadOptions::default());
    assert_eq!(error_lines(&p), [3, 4, 7, 8, 12, 13], "{:?}", errors(&p));
    has(&p, 4, 4, "line 3's ORIPATH (an orientation interpolation not read) is in effect on the control until ORIVECT, ORIPLANE or ORIAXES");
    has(&p, 8, 4, "line 7's ORIROTT (an interpolation of the tool's rotation vector not read) is in effect on the control until ORIROTA");
    has(&p, 13, 4, "line 12's ORIPATHS (an orientation interpolation not read)");
    for (l, x) in [(6, 2.0), (10, 4.0), (15, 6.0)] {
        assert_eq!(x_at(&p, l), Some(x), "line {l}: {:?}", errors(&p));
    }
}

/// A refused block whose move the control makes leaves the axes it moves unknown until written
/// absolute: Fanuc's G31 skip (it stops where the signal comes) and G60; G33 thread cutting, a motion
/// of group 01, also makes the later moves without a G00-G03 of their own refused; LinuxCNC's G38.2
/// probe (group 1) and G28 alone (every axis, to the stored position, with no machine coordinates
/// in the machine file); the 840D's G74 reference approach (every axis), G331 tapping (modal) and
/// G147 smooth approach (X, Y, Z).
#[test]
fn a_refused_move_the_control_makes_leaves_its_axes_unknown() {
    let text = "%\nO1000\nG21 G90 G17 G94 F100.\nG0 X0. Y0. Z10.\nG31 X50. F100.\nG1 Y5.\nG1 X1. Y1.\nG60 Z5.\nG1 Z4.\nG1 X3. Z3.\nG33 Z-10. F1.5\nZ-20.\nG0 Z10.\nG0 X2.\nM30\n%\n";
    let p = read(text, Dialect::Fanuc, "t.nc", &ReadOptions::default());
    let mut lines = error_lines(&p);
    lines.dedup();
    assert_eq!(lines, [5, 6, 7, 8, 9, 11, 12, 13], "{:?}", errors(&p));
    has(&p, 6, 4, "a move from where the moves under line 5's G31 (a move this reader does not read)");
    has(&p, 6, 4, "once X is written absolute");
    has(&p, 9, 4, "line 8's G60");
    has(&p, 13, 4, "line 11's G33 (threading or probing)");
    has(&p, 13, 4, "once Z is written absolute");
    for (l, x) in [(4, Some(0.0)), (7, None), (10, Some(3.0)), (14, Some(2.0))] {
        assert_eq!(x_at(&p, l), x, "line {l}: {:?}", errors(&p));
    }

    let text = "G21 G90 G94 G17\nG0 X0 Y0 Z10\nG38.2 Z-5 F50\nG0 Z10\nX5\nG28\nG0 X1 Y1 Z1\nG0 X2\nM2\n";
    let p = read(text, Dialect::Rs274, "t.ngc", &ReadOptions::default());
    assert_eq!(error_lines(&p), [3, 4, 6, 7], "{:?}", errors(&p));
    has(&p, 4, 4, "line 3's G38.2 (threading or probing)");
    has(&p, 7, 4, "a move from where the moves under line 6's G28 (a move to a stored position)");
    assert_eq!(x_at(&p, 5), Some(5.0), "{:?}", errors(&p));
    assert_eq!(x_at(&p, 8), Some(2.0), "{:?}", errors(&p));

    let text = "G71 G90 G94\nG0 X0 Y0 Z10\nG74 X1=0 Z1=0\nG1 X10 F100\nG0 X0 Y0 Z10\nG331 Z-10 K1\nG1 X11\nG1 Z10\nG147 G41 DISR=5 X20 Y20\nG1 X12\nG0 X0 Y0 Z10\nG0 X3\nM30\n";
    let p = read(text, Dialect::Sinumerik, "t.mpf", &ReadOptions::default());
    for l in [4, 5, 7, 8, 10, 11] {
        assert!(error_lines(&p).contains(&l), "line {l}: {:?}", errors(&p));
    }
    has(&p, 4, 4, "line 3's G74 (a reference or fixed point approach)");
    has(&p, 7, 4, "line 6's G331 (threading or tapping)");
    has(&p, 10, 4, "line 9's G147 (smooth approach or retraction)");
    assert_eq!(x_at(&p, 12), Some(3.0), "{:?}", errors(&p));
}

/// Fanuc's coordinate modes refused here change what the axis words mean until their cancel (FANUC
/// B-64484EN "Polar coordinate command (G15, G16)", "Polar coordinate interpolation (G12.1, G13.1)",
/// "Cylindrical interpolation (G07.1)"): G16 until G15, G12.1 until G13.1, G07.1 C10. until G07.1 C0
/// (its C the radius, no move); the moves under them refused, then X, Y, Z unknown until written.
/// G15 and G13.1 with nothing in effect are read.
#[test]
fn fanucs_coordinate_modes_hold_until_their_cancel() {
    for (on, off) in [("G16", "G15"), ("G12.1", "G13.1"), ("G07.1 C10.", "G07.1 C0")] {
        let text = format!("%\nO1000\nG21 G90 G17 G94 F100.\nG0 X0. Y0. Z10.\n{on}\nG1 X10. Y45.\n{off}\nG1 X1. Y1. Z1.\nG1 X2.\nM30\n%\n");
        let p = read(&text, Dialect::Fanuc, "t.nc", &ReadOptions::default());
        let mut lines = error_lines(&p);
        lines.retain(|l| *l != 7); // G07.1 C0 is refused as G07.1 is (not read), G15/G13.1 are read
        assert_eq!(lines, [5, 6, 8], "{on}: {:?}", errors(&p));
        has(&p, 6, 4, &format!("line 5's G{}", on.split(' ').next().unwrap().trim_start_matches("G").trim_start_matches('0')));
        has(&p, 8, 4, "once X, Y and Z are written absolute");
        assert_eq!(x_at(&p, 9), Some(2.0), "{on}: {:?}", errors(&p));
    }
    let p = read("%\nO1000\nG21 G90 G17 G94 F100.\nG15 G13.1\nG0 X3. Y0. Z10.\nM30\n%\n", Dialect::Fanuc, "t.nc", &ReadOptions::default());
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
}

/// The second review's cases: the 840D's `TRAFOOF` in a line that also moves ends its hold all the
/// same (its own move starts at the unknown point: refused once); a bare `MIRROR` resets the
/// programmable frame as `TRANS` does (read, ending a frame's hold); `G58` (an axial programmable
/// offset, refused) holds as a frame; a call not read leaves every axis unknown; Haas' `G28` alone,
/// refused, every axis; Fanuc's `G53`, refused, the axes it names.
#[test]
fn ends_in_moving_lines_bare_mirror_g58_calls_and_reference_moves() {
    let text = "G71 G90 G94\nG0 X0 Y0 Z10\nTRANSMIT\nG1 X10 F100\nTRAFOOF G0 X0 Y0 Z100\nG0 X1 Y1 Z1\nG0 X1\nMIRROR X0\nG0 X2\nMIRROR\nG0 X0 Y0 Z10\nG0 X3\n\
                G58 X5\nG0 X4\nTRANS\nG0 X0 Y0 Z10\nCALL BLOCK A1 TO A2\nG0 X0 Y0 Z10\nG0 X5\nM30\n";
    let p = read(text, Dialect::Sinumerik, "t.mpf", &ReadOptions::default());
    let mut lines = error_lines(&p);
    lines.dedup();
    assert_eq!(lines, [3, 4, 5, 6, 8, 9, 11, 13, 14, 16, 17, 18], "{:?}", errors(&p));
    // TRAFOOF ended the hold though its line was refused: line 6 is refused for the unknown axes
    // only (as a move that writes them), and the line after it is read.
    has(&p, 5, 12, "a move from where the moves under line 3's TRANSMIT");
    has(&p, 6, 4, "a move from where the moves under line 3's TRANSMIT");
    has(&p, 11, 4, "a move from where the moves under line 8's MIRROR");
    has(&p, 14, 4, "line 13's G58 (a programmable frame not read");
    has(&p, 18, 4, "a move from where the moves under line 17's CALL (a call not read, which the control runs)");
    for (l, x) in [(7, Some(1.0)), (12, Some(3.0)), (19, Some(5.0))] {
        assert_eq!(x_at(&p, l), x, "line {l}: {:?}", errors(&p));
    }

    let p = read("%\nO1000\nG20 G90 G17 G94\nG0 X0. Y0. Z1.\nG28\nG0 X1.\nG0 X1. Y1. Z1.\nG0 X2.\nM30\n%\n", Dialect::Haas, "t.nc", &ReadOptions::default());
    let mut lines = error_lines(&p);
    lines.dedup();
    assert_eq!(lines, [5, 6, 7], "{:?}", errors(&p));
    has(&p, 7, 4, "once Y and Z are written absolute");
    let p = read("%\nO1000\nG21 G90 G17 G94\nG0 X0. Y0. Z10.\nG53 G0 Z0.\nG0 X1.\nG0 Z5.\nG0 X2.\nM30\n%\n", Dialect::Fanuc, "t.nc", &ReadOptions::default());
    let mut lines = error_lines(&p);
    lines.dedup();
    assert_eq!(lines, [5, 6, 7], "{:?}", errors(&p));
    has(&p, 6, 4, "line 5's G53 (a move in machine coordinates)");
    assert_eq!(x_at(&p, 8), Some(2.0), "{:?}", errors(&p));
}

/// A refused `CYCLE800` swivels the control all the same: the moves after it are held until a
/// `CYCLE800` is read, whose plane is taken but whose own moves (from where the control's swivel
/// left the tool) are not made, said once; then X, Y, Z and the rotary axes are unknown until
/// written absolute. On the Cincinnati FTV5 (its swivel data set R_DATA).
#[test]
fn a_refused_swivel_holds_until_a_swivel_is_read() {
    let ftv5 = fiveaxis::machine::Machine::builtin("cincinnati-ftv5").unwrap();
    let on = ReadOptions::default().on(&ftv5);
    let text = "G90 G71 G94\nG0 X0 Y0 Z100\nCYCLE800(0,\"WRONG\",0,57,0,0,0,30,0,0,0,0,0,1)\nG1 X10 F100\nCYCLE800(0,\"R_DATA\",0,57,0,0,0,0,0,0,0,0,0,1)\nG0 X1\n\
                G0 X0 Y0 Z100 A0 C0\nG0 X2\nM30\n";
    let p = read(text, Dialect::Sinumerik, "t.mpf", &on);
    let mut lines = error_lines(&p);
    lines.dedup();
    assert_eq!(lines, [3, 4, 5, 6, 7], "{:?}", errors(&p));
    has(&p, 4, 4, "line 3's CYCLE800 (a swivel (CYCLE800) not read) is in effect on the control until a CYCLE800 that is read");
    has(&p, 5, 1, "CYCLE800 after a refused CYCLE800: the plane it sets is read");
    has(&p, 6, 4, "a move from where the moves under line 3's CYCLE800");
    assert!(p.blocks.iter().all(|b| b.line != 5 || b.targets.is_empty()), "line 5 made no move");
    assert_eq!(x_at(&p, 8), Some(2.0), "{:?}", errors(&p));
}
