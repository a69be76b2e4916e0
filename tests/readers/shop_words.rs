//! What shops' and CAM posts' programs write (found by reading public programs the corpus does not
//! hold), read by each control's rule: Fanuc's and Haas' full circle by its centre alone, high-precision
//! contour control, an H word alone, a program number 0 and numbers without a decimal point; the TNC's
//! `CYCL CALL M13` and `L M140 MB MAX`; the 840D's `DEF` variables without a value, `SETMS`, `EXTERN`;
//! and what a generic machine model now assumes so that a program's machine moves read.

use super::*;
use fiveaxis::machine::Machine;
use fiveaxis::path::{PathOptions, Trajectory};

/// Fanuc and Haas: "When X_, Y_, and Z_ are all omitted (the end point is the same as the start point)
/// and the center is specified with I_, J_, and K_, a 360° arc (circle) is specified" (FANUC
/// B-64484EN, "Circular interpolation"; Haas the same, with I J K only): `G3 I10. J0` from X0 Y0 is the
/// circle of radius 10 mm about X10 Y0, 2 pi 10 mm long (by hand). An R with no end point is no
/// circle: still refused.
#[test]
fn fanuc_and_haas_read_a_full_circle_by_its_centre_alone() {
    for (dialect, machine) in [(Dialect::Fanuc, "mori-seiki-nmv5000"), (Dialect::Haas, "haas-umc-750")] {
        let m = Machine::builtin(machine).unwrap();
        let p = read("%\nO1000\nG21 G90 G94 G17\nG0 X0. Y0. Z10.\nG3 I10. J0 F100.\nM30\n%\n", dialect, "t.nc", &ReadOptions::default().on(&m));
        assert!(errors(&p).is_empty(), "{dialect:?}: {:?}", errors(&p));
        let t = Trajectory::from_program(&p, &m, &PathOptions::default());
        let length: f64 = t.segments.iter().filter(|s| s.line == 5).map(|s| s.length).sum();
        let want = std::f64::consts::TAU * 10.0 * MM;
        assert!((length - want).abs() < 1e-6 * want, "{dialect:?}: {} mm, by hand {} mm", length / MM, want / MM);
        let p = read("%\nO1000\nG21 G90 G94 G17\nG0 X0. Y0. Z10.\nG3 R10. F100.\nM30\n%\n", dialect, "t.nc", &ReadOptions::default().on(&m));
        assert!(errors(&p).iter().any(|(l, _, m)| *l == 5 && m.contains("without an end point")), "{dialect:?}: {:?}", errors(&p));
    }
}

/// Fanuc's high-precision contour control `G05 P10000` / `G05 P0` (Series 16i/18i-MB) is look-ahead
/// feed control, as AI contour `G05.1 Q1` is: the moves are those without it. G05 with another P
/// (high-speed cycle machining, binary data) stays refused, and Haas has no G05.
#[test]
fn fanuc_reads_high_precision_contour_control_and_refuses_other_g05() {
    let body = "G1 X10. Y5. F500.\nG1 X20.\n";
    let plain = read(&format!("%\nO1000\nG21 G90 G94\n{body}M30\n%\n"), Dialect::Fanuc, "t.nc", &ReadOptions::default());
    let hpcc = read(&format!("%\nO1000\nG21 G90 G94\nG05 P10000\n{body}G05 P0\nM30\n%\n"), Dialect::Fanuc, "t.nc", &ReadOptions::default());
    assert!(errors(&hpcc).is_empty(), "{:?}", errors(&hpcc));
    assert_eq!(end_points(&hpcc), end_points(&plain));
    refuses_each(Dialect::Fanuc, &ReadOptions::default(), &[("%\nO1000\nG05 P3\nM30\n%\n", "3:1:", "high-speed cycle machining")]);
    refuses_each(Dialect::Haas, &ReadOptions::default(), &[("%\nO1000\nG05 P10000\nM30\n%\n", "3:1:", "G05")]);
    // FANUC's G08 (as NX's posts write `G08 P1`) is no lathe diameter mode, LinuxCNC's G8: refused
    // as a code not read, not named as that.
    refuses_each(Dialect::Fanuc, &ReadOptions::default(), &[("%\nO1000\nG08 P1\nM30\n%\n", "3:1:", "unknown G code G08")]);
    refuses_each(Dialect::Rs274, &ReadOptions::default(), &[("G7\nM2\n", "1:1:", "lathe diameter or radius mode")]);
}

/// AI contour control `G05.1 Q1` with its machining condition `R1`-`R10` (feed control: the moves are
/// those without it, R a level, not a length in increments) and `G05.1 Q0`; smooth interpolation
/// `G05.1 Q2 X0 Y0 Z0` and nano smoothing `Q3` make a curve through the points and are refused (their
/// block's axis words name axes, they are not a move), as are R0, R11 and a G05.1 without Q.
#[test]
fn fanuc_g05_1_reads_ai_contour_and_refuses_smoothing() {
    let body = "G1 X10. Y5. F500.\nG1 X20.\n";
    let plain = read(&format!("%\nO1000\nG21 G90 G94\n{body}M30\n%\n"), Dialect::Fanuc, "t.nc", &ReadOptions::default());
    let ai = read(&format!("%\nO1000\nG21 G90 G94\nG05.1 Q1 R5\n{body}G05.1 Q0\nM30\n%\n"), Dialect::Fanuc, "t.nc", &ReadOptions::default());
    assert!(errors(&ai).is_empty(), "{:?}", errors(&ai));
    assert_eq!(end_points(&ai), end_points(&plain));
    refuses_each(
        Dialect::Fanuc,
        &ReadOptions::default(),
        &[
            ("%\nO1000\nG21 G90\nG05.1 Q2 X0 Y0 Z0\nM30\n%\n", "4:1:", "smooth or nano smoothing interpolation"),
            ("%\nO1000\nG21 G90\nG05.1 Q3 X0 Y0 Z0\nM30\n%\n", "4:1:", "smooth or nano smoothing interpolation"),
            ("%\nO1000\nG21 G90\nG05.1 Q1 R11\nM30\n%\n", "4:10:", "machining condition R1 to R10"),
            ("%\nO1000\nG21 G90\nG05.1 Q1 R0\nM30\n%\n", "4:10:", "machining condition R1 to R10"),
            ("%\nO1000\nG21 G90\nG05.1\nM30\n%\n", "4:1:", "expected Q1"),
        ],
    );
}

/// An H word alone (NX's Fanuc posts write `N0250 H00` after a tool change) selects a tool length
/// offset, a length this model takes from the machine file as it takes G43's: read, and said.
/// `O0000` opening a program (Mastercam's placeholder) is no program number: read as its title, said.
#[test]
fn fanuc_reads_an_h_word_alone_and_program_number_zero() {
    let p = read("%\nO0000 (MY PART)\nG21 G90 G94\nN0250 H00\nG1 X10. F500.\nM30\n%\n", Dialect::Fanuc, "t.nc", &ReadOptions::default());
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    assert!(p.diagnostics.iter().any(|d| d.line == 4 && d.message.contains("tool length offset number")), "{:?}", p.diagnostics);
    assert!(p.diagnostics.iter().any(|d| d.line == 2 && d.message.contains("is program number 0: read as the program's title")), "{:?}", p.diagnostics);
    assert_eq!(end_points(&p).len(), 1);
}

/// Fanuc and Haas read a length without a decimal point in least input increments (`X160` is 0.160
/// mm): as before, and now said once, naming the word and what it is read as (a program meant in
/// mm otherwise fails far from its cause, on an arc's radius).
#[test]
fn fanuc_says_once_where_a_length_has_no_decimal_point() {
    let p = read("%\nO1000\nG21 G90 G94\nG1 X160 Y0 F500.\nG1 X200 Y50\nM30\n%\n", Dialect::Fanuc, "t.nc", &ReadOptions::default());
    let said: Vec<_> = p.diagnostics.iter().filter(|d| d.message.contains("has no decimal point")).collect();
    assert_eq!(said.len(), 1, "{:?}", p.diagnostics);
    assert!(said[0].line == 4 && said[0].column == 4 && said[0].message.contains("X160 has no decimal point: read as 0.16 mm"), "{said:?}");
    assert!((end_points(&p)[0].1[0] - 0.16).abs() < 1e-12, "{:?}", end_points(&p));
    // Written with points: nothing said.
    let p = read("%\nO1000\nG21 G90 G94\nG1 X160. Y0 F500.\nM30\n%\n", Dialect::Fanuc, "t.nc", &ReadOptions::default());
    assert!(p.diagnostics.iter().all(|d| !d.message.contains("decimal point")), "{:?}", p.diagnostics);
}

/// The TNC's `CYCL CALL M13` ("Calling cycles": CYCL CALL takes a miscellaneous function) is the M
/// function, then the cycle: the same moves as `L M13` and `CYCL CALL`; an M function acting at the
/// block's end is refused there. `L M140 MB MAX` (hyperMILL's posts) is `M140 MB MAX`.
#[test]
fn klartext_reads_a_cycle_call_with_m_functions_and_m140_in_an_l_block() {
    let hermle = Machine::builtin("hermle-c600u").unwrap();
    let head = "BEGIN PGM T MM\nTOOL CALL 1 Z S1000\nL Z+50 R0 FMAX\nCYCL DEF 200 DRILLING ~\n Q200=+2 ~\n Q201=-10 ~\n Q206=+150 ~\n Q202=+5 ~\n Q210=+0 ~\n Q203=+0 ~\n Q204=+50 ~\n Q211=+0\nL X+10 Y+10 R0 FMAX\n";
    let read_k = |text: String| read(&text, Dialect::Klartext, "t.h", &ReadOptions::default().on(&hermle));
    let with_m = read_k(format!("{head}CYCL CALL M13\nEND PGM T MM\n"));
    let apart = read_k(format!("{head}L M13\nCYCL CALL\nEND PGM T MM\n"));
    assert!(errors(&with_m).is_empty(), "{:?}", errors(&with_m));
    assert!(end_points(&with_m).len() > 2);
    assert_eq!(end_points(&with_m), end_points(&apart));
    assert!(with_m.blocks.iter().any(|b| b.events.iter().any(|e| e == "M13")), "{:?}", with_m.blocks);
    let p = read_k(format!("{head}CYCL CALL M9\nEND PGM T MM\n"));
    assert!(errors(&p).iter().any(|(l, _, m)| *l == 14 && m.contains("CYCL CALL M9: only M functions acting at the block's start")), "{:?}", errors(&p));
    let l_block = read_k("0 BEGIN PGM R MM\n1 L X+10 Y+20 Z+30 FMAX\n2 L M140 MB MAX\n3 END PGM R MM\n".into());
    let plain = read_k("0 BEGIN PGM R MM\n1 L X+10 Y+20 Z+30 FMAX\n2 M140 MB MAX\n3 END PGM R MM\n".into());
    assert!(errors(&l_block).is_empty(), "{:?}", errors(&l_block));
    assert_eq!(end_points(&l_block), end_points(&plain));
}

/// The 840D's user variables without a value are 0 (checked in tests/sinumerik.rs); `SETMS(1)` and
/// `EXTERN NAME(REAL, REAL)` move nothing: read, the declared program's call still refused. A frame's
/// offset of a rotary axis (`TRANS B=5`) is refused naming that, with its `=`.
#[test]
fn sinumerik_reads_setms_and_extern_and_names_a_rotary_frame_offset() {
    let p = read("EXTERN WARMUP(REAL, REAL)\nSETMS(1)\nG90 G71 G94\nG1 X10 Y5 F500\nWARMUP(1, 2)\nM30\n", Dialect::Sinumerik, "t.mpf", &ReadOptions::default());
    let e = errors(&p);
    assert_eq!(e.len(), 1, "{e:?}");
    assert!(e[0].0 == 5 && e[0].2.contains("WARMUP"), "{e:?}");
    refuses_each(Dialect::Sinumerik, &ReadOptions::default(), &[("G90 G71\nTRANS X=10 B=5\nM30\n", "2:12:", "B=5 in a TRANS block: a frame's offset of a rotary axis is not read")]);
}

/// A G02/G03 without a feed is said as what it is (it used to be called a G01 move).
#[test]
fn an_arc_without_a_feed_is_named_as_an_arc() {
    refuses_each(Dialect::Rs274, &ReadOptions::default(), &[("G21 G90 G94\nG0 X0 Y0\nG2 X10 Y0 R5\nM2\n", "3:1:", "G02 move without a feed")]);
}

/// A generic machine model assumes machine coordinates (its file: the machine zero 500 mm above the
/// part zero, the reference points there), so that `G53 Z0`, `G28 G91 Z0` and Heidenhain's `M91`
/// read on it: each retract ends 500 mm above the part zero. An axis the offset left out of range
/// (warned once) is not blamed again by a machine move of another axis.
#[test]
fn generic_machines_read_machine_coordinate_moves() {
    let m = Machine::builtin("generic-bc-table").unwrap();
    for (dialect, text) in [
        (Dialect::Fanuc, "%\nO1000\nG21 G90 G94 G54\nG0 X10. Y5. Z20.\nG53 Z0.\nM30\n%\n"),
        (Dialect::Fanuc, "%\nO1000\nG21 G90 G94 G54\nG0 X10. Y5. Z20.\nG28 G91 Z0.\nM30\n%\n"),
        (Dialect::Klartext, "0 BEGIN PGM R MM\n1 L X+10 Y+5 Z+20 R0 FMAX\n2 L Z+0 R0 FMAX M91\n3 END PGM R MM\n"),
        (Dialect::Heidenhain, "%R G71 *\nN10 G00 G90 X+10 Y+5 Z+20 *\nN20 G00 Z+0 M91 *\nN99999999 %R G71 *\n"),
    ] {
        let p = read(text, dialect, "t", &ReadOptions::default().on(&m));
        assert!(errors(&p).is_empty(), "{dialect:?}: {:?}", errors(&p));
        let t = Trajectory::from_program(&p, &m, &PathOptions::default());
        assert!(t.diagnostics.iter().all(|d| d.severity != Severity::Error), "{dialect:?}: {:?}", t.diagnostics);
        // The machine's Z (its file's frame, the part zero at its origin, B and C at 0).
        let last = t.segments.last().unwrap();
        assert!((last.q1[2] / MM - 500.0).abs() < 1e-6, "{dialect:?}: Z {} mm", last.q1[2] / MM);
    }
    // Heidenhain DIN/ISO's M91 as Klartext's: an absolute straight line only.
    refuses_each(
        Dialect::Heidenhain,
        &ReadOptions::default().on(&m),
        &[
            ("%R G71 *\nN10 G00 G90 X+10 Y+5 Z+20 *\nN20 G91 G00 Z+0 M91 *\nN99999999 %R G71 *\n", "3:17:", "absolute positions of a straight-line block"),
            ("%R G71 *\nN10 G01 G90 X+10 Y+5 Z+20 F100 *\nN20 I+0 J+0 G02 X+10 Y+5 M91 *\nN99999999 %R G71 *\n", "3:26:", "straight-line block"),
            ("%R G71 *\nN10 G00 G90 X+10 Y+5 Z+20 M128 *\nN20 G00 Z+0 M91 *\nN99999999 %R G71 *\n", "3:13:", "under M128"),
        ],
    );
    // X far outside a small machine's travel with the work offset unknown (warned), then G28 Z: read.
    let nmv = Machine::builtin("mori-seiki-nmv5000").unwrap();
    let p = read("%\nO1000\nG20 G90 G94 G54\nG0 X-39.6 Y0. Z0.6\nG28 G91 Z0.\nG90\nM30\n%\n", Dialect::Fanuc, "t.nc", &ReadOptions::default().on(&nmv));
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    let t = Trajectory::from_program(&p, &nmv, &PathOptions::default());
    assert!(t.diagnostics.iter().any(|d| d.severity == Severity::Warning && d.message.contains("axis X would move")), "{:?}", t.diagnostics);
    assert!(t.diagnostics.iter().all(|d| d.severity != Severity::Error), "{:?}", t.diagnostics);
}

/// The TNC's `LP` with its radius or angle left out keeps the start's: the TNC 410 User's Manual's
/// example ("Straight line LP": `CC X+45 Y+25`, `LP PR+30 PA+0`, `LP PA+60`, `LP IPA+60`, `LP PA+180`;
/// its RR left out) ends at the pole plus 30 mm at 0, 60, 120 and 180 deg, computed here.
#[test]
fn klartext_lp_keeps_the_polar_radius_left_out() {
    let p = read("0 BEGIN PGM P MM\n1 TOOL CALL 1 Z S1000\n2 CC X+45 Y+25\n3 LP PR+30 PA+0 R0 F300 M3\n4 LP PA+60\n5 LP IPA+60\n6 LP PA+180\n7 LP PR+10\n8 END PGM P MM\n", Dialect::Klartext, "p.h", &ReadOptions::default());
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    let ends: Vec<[f64; 2]> = end_points(&p).iter().map(|(_, a)| [a[0], a[1]]).collect();
    let want: Vec<[f64; 2]> = [(30.0, 0.0), (30.0, 60.0), (30.0, 120.0), (30.0, 180.0), (10.0, 180.0)].iter().map(|(r, deg): &(f64, f64)| [45.0 + r * deg.to_radians().cos(), 25.0 + r * deg.to_radians().sin()]).collect();
    assert_eq!(ends.len(), want.len(), "{ends:?}");
    for (e, w) in ends.iter().zip(&want) {
        assert!((e[0] - w[0]).abs() < 1e-9 && (e[1] - w[1]).abs() < 1e-9, "{ends:?}, computed {want:?}");
    }
    refuses_each(Dialect::Klartext, &ReadOptions::default(), &[("0 BEGIN PGM P MM\n1 CC X+45 Y+25\n2 LP R0 F300\n3 END PGM P MM\n", "3:3:", "LP: expected the polar radius PR (or IPR) or angle PA")]);
}

/// Fanuc's modal information (custom macro B, system variables #4001-#4030 the G code groups,
/// #4109 F, #4120 T) as the blocks before left it, so that a macro saving and restoring a mode reads:
/// `#10 = #4003` under G90 is 90 (`G#10` then restores absolute: X5 is X5, not 10 + 5), `#11 = #4006`
/// under G21 is 21, `#12 = #4001` after a G01 is 1, `#13 = #4109` the feed 100, `#4119` the S last
/// set (1200). A system variable this reader does not hold (`#4111`, the H code), or `#4119` before
/// any S (the control's from before the program), is refused as the control's.
#[test]
fn fanuc_macros_read_the_modal_information() {
    let p = read("%\nO1000\nG21 G90 G94 G17\nG0 X0. Y0. Z10.\n#10 = #4003\n#11 = #4006\nG91 G1 X10. F100.\nG#10 G1 X5. Y#11\n#12 = #4001\n#13 = #4109\nG1 Z#12 X#13\nM30\n%\n", Dialect::Fanuc, "t.nc", &ReadOptions::default());
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    let ends: Vec<[f64; 3]> = end_points(&p).iter().map(|(_, a)| [a[0], a[1], a[2]]).collect();
    assert_eq!(ends, vec![[0.0, 0.0, 10.0], [10.0, 0.0, 10.0], [5.0, 21.0, 10.0], [100.0, 21.0, 1.0]]);
    let p = read("%\nO1000\nG21 G90 G94\nS1200 M3\n#13 = #4119\nG1 X[#13/100] F100.\nM30\n%\n", Dialect::Fanuc, "t.nc", &ReadOptions::default());
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    let x = end_points(&p).last().map_or(f64::NAN, |(_, a)| a[0]);
    assert!((x - 12.0).abs() < 1e-9, "X{x}: #4119 after S1200 is 1200");
    for (text, var) in [("%\nO1000\nG21 G90 G94\n#13 = #4119\nG1 X#13 F100.\nM30\n%\n", "#4119"), ("%\nO1000\nG21 G90 G94\n#13 = #4111\nG1 X#13 F100.\nM30\n%\n", "#4111")] {
        let p = read(text, Dialect::Fanuc, "t.nc", &ReadOptions::default());
        assert!(errors(&p).iter().any(|(_, _, m)| m.contains(&format!("{var} is a system variable"))), "{text}: {:?}", errors(&p));
    }
}

/// A refused block changes none of the state (fail closed): its incremental mode, inch unit, feed,
/// work offset and plane do not reach the next block. LinuxCNC's G10 L2 P2 X100. sets G55's offset
/// to X 100 mm; a refused `G91 G20 G55 G18 G1 X1. F50. Q5.` (Q without a cycle) leaves G90, G21,
/// F100, G54 and G17, so `G1 X20.` ends at X 20 mm at 100 mm/min and `G2 X40. I10.` (I: an XY-plane
/// centre) is an arc (by hand; a state left from the refused block would end it at 30 inch, at
/// 50 in/min, 100 mm further, or in the XZ plane, where I J is refused).
#[test]
fn a_refused_block_leaves_every_part_of_the_state() {
    let text = "G21 G90 G17 G94 F100.\nG10 L2 P2 X100.\nG0 X10. Y0. Z0.\nG91 G20 G55 G18 G1 X1. F50. Q5.\nG1 X20.\nG2 X40. I10. J0.\nM2\n";
    let p = read(text, Dialect::Rs274, "t.ngc", &ReadOptions::default());
    let e = errors(&p);
    assert_eq!(e.len(), 1, "only the Q5 block is refused: {e:?}");
    assert_eq!(e[0].0, 4, "{e:?}");
    let b: Vec<_> = p.blocks.iter().filter(|b| b.line >= 5 && !b.targets.is_empty()).collect();
    assert_eq!(b.len(), 2, "{b:?}");
    let x = b[0].targets.x.unwrap() + b[0].datum[0];
    assert!((x - 20.0 * MM).abs() < 1e-12, "X {x} m: G90, G21 and G54 stay");
    assert_eq!(b[0].feed.map(|f| f.value_per_min), Some(100.0), "F100 mm/min stays");
    assert_eq!(b[1].motion, Motion::ArcCw);
    let x = b[1].targets.x.unwrap() + b[1].datum[0];
    assert!((x - 40.0 * MM).abs() < 1e-12, "X {x} m");
}

/// A refused block sets none of its codes (fail closed), so a later block may be refused for a
/// code the refused one would have set: that defect names the refused line, so the first cause is
/// found (a real program's `G18 G2 ... Q5` refused for its Q, then `G2 ... K0.` read in the XY plane).
#[test]
fn a_defect_after_a_refused_block_names_it() {
    let p = read("%\nO1000\nG21 G90 G17 G94 F100.\nG0 X10. Y0. Z0.\nG18 G2 X12. Z0. I1. K0. Q5.\nG2 X14. Z0. I1. K0.\nM30\n%\n", Dialect::Fanuc, "t.nc", &ReadOptions::default());
    let e = errors(&p);
    assert!(e.iter().any(|(l, _, m)| *l == 5 && m.contains("Q5.")), "{e:?}");
    assert!(e.iter().any(|(l, _, m)| *l == 6 && m.contains("not an arc-centre word") && m.contains("line 5 was refused before it")), "{e:?}");
    // A block with a defect of its own (an unknown G code) is not told of the earlier one.
    let p = read("%\nO1000\nG21 G90 G17 G94 F100.\nG0 X10. Y0. Z0.\nG18 G2 X12. Z0. I1. K0. Q5.\nG2 G39 X14. Z0. I1. K0.\nM30\n%\n", Dialect::Fanuc, "t.nc", &ReadOptions::default());
    let e = errors(&p);
    assert!(e.iter().any(|(l, _, m)| *l == 6 && m.contains("G39")), "{e:?}");
    assert!(e.iter().any(|(l, _, m)| *l == 6 && m.contains("not an arc-centre word") && !m.contains("was refused before it")), "{e:?}");
    // A chain names its first block (the one whose G code did not take effect), and a block refused
    // for a code of its own names no other.
    let p = read("G21 G90 G94
G0 X0 Y0
G2 X10 Y0 R5
X20 R5
X30 R5
G33 Z-1 K1
G33 Z-2 K1
M2
", Dialect::Rs274, "t.ngc", &ReadOptions::default());
    let e = errors(&p);
    for l in [4, 5] {
        assert!(e.iter().any(|(k, _, m)| *k == l && m.contains("R5 without a G code") && m.contains("line 3 was refused before it")), "{e:?}");
    }
    assert!(e.iter().any(|(l, _, m)| *l == 7 && m.contains("K1 without a G code") && !m.contains("was refused before it")), "{e:?}");
}

/// A machine maker's M function (the TNC's, the 840D's, Fanuc's and LinuxCNC's alike: outside the
/// control's own list its effect is the machine's) is refused where it stands, the message naming both ways to say
/// what it does: its machine file's `[[m_function]]` and `--m-code`. Said either way as an event, the
/// program reads clean (exit 0). The shop archive's DMGs and Trimill write such M functions (M25,
/// M54, M55, M58) beside the coolant.
#[test]
fn a_makers_m_function_is_refused_until_the_machine_file_or_a_flag_says_what_it_does() {
    let dir = crate::common::scratch_dir("maker_m");
    let hermle = fiveaxis::machine::builtin_file("hermle-c600u").unwrap();
    let declared = dir.join("hermle-m55.toml");
    std::fs::write(&declared, format!("{hermle}\n[[m_function]]\ncode = 55\naction = \"event\"\nwhat = \"the maker's, moving nothing (this test's)\"\n")).unwrap();
    let programs = [
        ("t.h", "BEGIN PGM T MM\nL X+0 Y+0 Z+10 R0 FMAX\nL X+10 F600 M55\nEND PGM T MM\n", "3:13"),
        ("t.mpf", "G90 G71\nG0 X0 Y0 Z10\nG1 X10 F600 M55\nM30\n", "3:13"),
        ("t.nc", "%\nO1000\nG21 G90 G94\nG0 X0. Y0. Z10.\nG1 X10. F600. M55\nM30\n%\n", "5:15"),
        ("t.ngc", "G21 G90\nG0 X0 Y0 Z10\nG1 X10 F600 M55\nM2\n", "3:13"),
    ];
    for (name, text, at) in programs {
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        let run = |extra: &[&str]| {
            let dialect: &[&str] = if name.ends_with(".nc") { &["--dialect", "fanuc"] } else { &[] };
            let out = std::process::Command::new(env!("FIVEAXIS_EXE")).args(["program", "analyze"]).arg(&path).args(dialect).args(extra).output().unwrap();
            (out.status.code(), format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr)))
        };
        let (code, said) = run(&["--machine", "hermle-c600u"]);
        assert_eq!(code, Some(2), "{name}: {said}");
        let line = said.lines().find(|l| l.contains("error: M55")).unwrap_or_else(|| panic!("{name}: no M55 error: {said}"));
        assert!(line.contains(&format!("{name}:{at}: error: M55")), "{name}: {line}");
        assert!(line.contains("[[m_function]]") && line.contains("--m-code 55=tcp-on|tcp-off|event"), "{name}: {line}");
        let (code, said) = run(&["--machine", "hermle-c600u", "--m-code", "55=event"]);
        assert_eq!(code, Some(0), "{name} with --m-code: {said}");
        let (code, said) = run(&["--machine", declared.to_str().unwrap()]);
        assert_eq!(code, Some(0), "{name} on a machine file that names M55: {said}");
    }
}

/// The TNC's own M functions are not a machine maker's: M107/M108 (a replacement tool's radius
/// check, TNC7 basic user's manual 81762x-18) move nothing and read clean; M97/M98 (radius
/// compensation at contour steps and open corners, TNC 620 user's manual §10.4) and M112/M124
/// (rounding between lines, TNC 426/430) change the tool path and are refused under their own name,
/// not as the maker's.
#[test]
fn the_tncs_own_m_functions_are_named_as_the_tncs() {
    use fiveaxis::program::{read, Dialect, ReadOptions, Severity};
    let program = |m: &str| format!("0 BEGIN PGM T MM\n1 TOOL CALL 1 Z S5000\n2 L X+0 Y+0 Z+10 R0 FMAX\n3 L X+10 F600 {m}\n4 END PGM T MM\n");
    let errors = |m: &str| -> Vec<(usize, usize, String)> {
        let p = read(&program(m), Dialect::Klartext, "t.h", &ReadOptions::default());
        p.diagnostics.iter().filter(|d| d.severity == Severity::Error).map(|d| (d.line, d.column, d.message.clone())).collect()
    };
    for m in ["M107", "M108", "M101 M108", "M137", "M113"] {
        assert!(errors(m).is_empty(), "{m}: {:?}", errors(m));
    }
    for (m, what) in [("M97", "contour steps"), ("M98", "open contour corners"), ("M112", "rounding"), ("M124", "rounding")] {
        let e = errors(m);
        assert!(e.len() == 1 && e[0].0 == 4 && e[0].1 == 15 && e[0].2.starts_with(&format!("{m}: the TNC's")) && e[0].2.contains(what) && !e[0].2.contains("maker"), "{m}: {e:?}");
    }
}

/// A Klartext circle's defect names the circle as the program writes it (`C ... DR+`), not as the
/// ISO G code the reader makes of it: the radius to the end (12 mm) is not the radius to the start
/// (10 mm) about CC X0 Y0.
#[test]
fn a_klartext_circles_defect_names_its_direction_as_written() {
    use fiveaxis::program::{read, Dialect, ReadOptions, Severity};
    for (dr, want) in [("DR+", "the circle DR+: the radius to the end (12.0000 mm) differs from the radius to the start (10.0000 mm)"), ("DR-", "the circle DR-: the radius to the end")] {
        let text = format!("0 BEGIN PGM ARC MM\n1 L X+10 Y+0 Z+0 R0 F500\n2 CC X+0 Y+0\n3 C X+0 Y+12 {dr}\n4 END PGM ARC MM\n");
        let p = read(&text, Dialect::Klartext, "t.h", &ReadOptions::default());
        let e: Vec<_> = p.diagnostics.iter().filter(|d| d.severity == Severity::Error).collect();
        assert!(e.len() == 1 && e[0].line == 4 && e[0].message.starts_with(want) && !e[0].message.contains("G0"), "{dr}: {e:?}");
    }
}

/// A TNC string parameter set to a text (`QS330="T1"`, as hyperMILL writes it in a touch probe
/// cycle's list; iTNC 530 user's manual, "String parameters") moves nothing: read without a defect
/// of its own, where it had been refused as a malformed Q parameter. A string formula is refused.
#[test]
fn a_tnc_string_parameter_set_to_a_text_moves_nothing() {
    use fiveaxis::program::{read, Dialect, ReadOptions, Severity};
    let errors = |body: &str| -> Vec<(usize, usize, String)> {
        let text = format!("0 BEGIN PGM QS MM\n1 TOOL CALL 1 Z S5000\n{body}\n3 L X+0 Y+0 Z+50 R0 FMAX\n4 END PGM QS MM\n");
        let p = read(&text, Dialect::Klartext, "t.h", &ReadOptions::default());
        p.diagnostics.iter().filter(|d| d.severity == Severity::Error).map(|d| (d.line, d.column, d.message.clone())).collect()
    };
    assert!(errors("2 QS1 = \"T1\"").is_empty(), "{:?}", errors("2 QS1 = \"T1\""));
    let e = errors("2 TCH PROBE 421 MEASURE HOLE~\n Q273=0 ;CENTER IN 1ST AXIS~\n QS330=\"T1\" ;TOOL~\n Q423=4 ;NO. OF MEAS. POINTS");
    // The probe moves the tool: the move after it starts where it is not known (refused too).
    assert!(e.len() == 2 && e[0].2.contains("touch probe cycle") && e[1].2.contains("from where line 3's TCH PROBE"), "{e:?}");
    let e = errors("2 QS2 = QS1 || \"X\"");
    assert!(e.len() == 1 && e[0].0 == 3 && e[0].2.contains("a string formula is not read"), "{e:?}");
}

/// LinuxCNC's own M codes M48-M53, M60-M68 (overrides, pallet, tool number, I/O) are LinuxCNC's:
/// on a Fanuc or Haas control the same numbers are the machine maker's, refused as such (they had
/// been read as LinuxCNC's, a P or Q word taken with them).
#[test]
fn linuxcncs_own_m_codes_are_linuxcncs_only() {
    use fiveaxis::program::{read, Dialect, ReadOptions, Severity};
    for (code, more) in [("M50", ""), ("M62", " P1"), ("M66", " P0 L0"), ("M48", "")] {
        let rs = read(&format!("G21 G90\nG0 X0 Y0 Z10\n{code}{more}\nG1 X10 F600\nM2\n"), Dialect::Rs274, "t.ngc", &ReadOptions::default());
        assert!(rs.diagnostics.iter().all(|d| d.severity != Severity::Error), "{code} RS274: {:?}", rs.diagnostics);
        for dialect in [Dialect::Fanuc, Dialect::Haas] {
            let p = read(&format!("%\nO1000\nG21 G90\nG0 X0. Y0. Z10.\n{code}{more}\nG1 X10. F600.\nM30\n%\n"), dialect, "t.nc", &ReadOptions::default());
            let e: Vec<_> = p.diagnostics.iter().filter(|d| d.severity == Severity::Error).collect();
            assert!(e.iter().any(|d| d.line == 5 && d.message.starts_with(&format!("{code}: the machine maker's M function"))), "{code} {dialect:?}: {e:?}");
        }
    }
}

/// The Haas control's own M codes that move no axis (chip auger M31/M33, coolant spigot M34/M35, gear
/// override M41/M42, display M76/M77, air jet M83/M84, through-spindle coolant M88/M89: the Haas
/// mill M-code list) are named in the built-in Haas machines' files: a program writing them reads
/// without a defect there. On a machine whose file does not name them they stay the maker's,
/// refused; and a Haas code that moves something (M50, a pallet change) stays refused on the Haas.
#[test]
fn the_haas_machines_name_their_controls_own_m_codes() {
    let text = |codes: &str| format!("%\nO1000\nG20 G90 G17\nG0 X0. Y0. Z1.\n{codes}\nG1 X1. F10.\nM30\n%\n");
    let listed = "M31\nM88\nM34\nM35\nM83\nM84\nM41\nM42\nM76\nM77\nM89\nM33";
    for machine in ["haas-umc-750", "haas-vf2-tr"] {
        let m = Machine::builtin(machine).unwrap();
        let p = read(&text(listed), Dialect::Haas, "t.nc", &ReadOptions::default().on(&m));
        assert!(errors(&p).is_empty(), "{machine}: {:?}", errors(&p));
        let p = read(&text("M50"), Dialect::Haas, "t.nc", &ReadOptions::default().on(&m));
        assert!(errors(&p).iter().any(|(l, _, msg)| *l == 5 && msg.starts_with("M50: the machine maker's M function")), "{machine}: {:?}", errors(&p));
    }
    let generic = Machine::builtin("generic-bc-table").unwrap();
    let p = read(&text("M31"), Dialect::Haas, "t.nc", &ReadOptions::default().on(&generic));
    assert!(errors(&p).iter().any(|(l, _, msg)| *l == 5 && msg.starts_with("M31: the machine maker's M function")), "{:?}", errors(&p));
}

/// A move without a feed after a refused block that carried the F word names that block (a
/// Sinumerik 828D warm-up program's `G1 SUPA Z-4 F300`, refused, then every G1 after it refused for
/// want of a feed, 90 of its 133 errors, none saying why).
#[test]
fn a_move_without_a_feed_names_the_refused_block_that_had_it() {
    for (dialect, text, refused, moved) in [
        (Dialect::Sinumerik, "G90 G71\nG0 X0 Y0 Z10\nG1 SUPA Z-4 F300\nG1 X10\nM30\n", 3, 4),
        (Dialect::Fanuc, "%\nO1000\nG21 G90\nG0 X0. Y0. Z10.\nG1 G39 Z-4. F300.\nG1 X10.\nM30\n%\n", 5, 6),
    ] {
        let m = Machine::builtin("generic-ac-table").unwrap();
        let p = read(text, dialect, "t", &ReadOptions::default().on(&m));
        let e = errors(&p);
        assert!(e.iter().any(|(l, _, _)| *l == refused), "{dialect:?}: {e:?}");
        let note = format!("line {refused}, refused before it, gave one");
        assert!(e.iter().any(|(l, _, m)| *l == moved && m.starts_with("G01 move without a feed") && m.contains(&note)), "{dialect:?}: {e:?}");
    }
    // Not named: a refused block without F; one followed by a block that set a feed (the later
    // change of feed mode is the cause, said as such).
    let fanuc = |body: &str| errors(&read(&format!("%\nO1000\nG21 G90 G17 G94\nG0 X0 Y0 Z5.\n{body}M30\n%\n"), Dialect::Fanuc, "t.nc", &ReadOptions::default()));
    let e = fanuc("G1 X10. Q5\nG1 X20.\n");
    assert!(e.iter().any(|(l, _, m)| *l == 6 && m.starts_with("G01 move without a feed") && !m.contains("refused")), "{e:?}");
    let e = fanuc("G1 X1. F100. Q5\nG93 G1 X2. F10.\nG94 G1 X3.\n");
    assert!(e.iter().any(|(l, _, m)| *l == 7 && m.contains("the change of feed mode left none") && !m.contains("line 5")), "{e:?}");
    let e = fanuc("G1 X1. F100. Q5\nG1 X2. F10.\nG94\nG93\nG94\nG1 X3.\n");
    assert!(e.iter().all(|(_, _, m)| !m.contains("line 5, refused")), "{e:?}");
    // The motion-mode note still names the refused G00, not a later refused F block.
    let e = errors(&read("%\nO1000\nG21 G90\nG00 W0.0\nF100. Q5.\nX10. Y10.\nM30\n%\n", Dialect::Fanuc, "t.nc", &ReadOptions::default()));
    assert!(e.iter().any(|(l, _, m)| *l == 6 && m.contains("(line 4 was refused before it")), "{e:?}");
}

/// An 840D arc's radius is named as the program wrote it, `CR=` (it had been shown as `R5`, and
/// `CR=BR` of a variable as `RBR`); Fanuc's stays `R`.
#[test]
fn an_840d_radius_is_named_cr_in_its_defects() {
    let sin = read("DEF REAL BR=5\nG90 G71 F100\nG0 X0 Y0 Z0\nG2 X0 Y0 CR=BR\nM30\n", Dialect::Sinumerik, "t.mpf", &ReadOptions::default());
    assert!(errors(&sin).iter().any(|(l, _, m)| *l == 4 && m.starts_with("G02 CR=BR: the end point is the start point")), "{:?}", errors(&sin));
    let sin = read("G90 G71 F100\nG0 X0 Y0 Z0\nG1 X30 CR=5\nG2 X10 Y0\nM30\n", Dialect::Sinumerik, "t.mpf", &ReadOptions::default());
    assert!(errors(&sin).iter().any(|(l, _, m)| *l == 3 && m.starts_with("word CR=5 without a G code")), "{:?}", errors(&sin));
    assert!(errors(&sin).iter().any(|(l, _, m)| *l == 4 && m.ends_with("or a radius (CR=)")), "{:?}", errors(&sin));
    let fanuc = read("%\nO1000\nG21 G90 F100.\nG0 X0. Y0. Z0.\nG2 X0. Y0. R5.\nM30\n%\n", Dialect::Fanuc, "t.nc", &ReadOptions::default());
    assert!(errors(&fanuc).iter().any(|(l, _, m)| *l == 5 && m.starts_with("G02 R5.: the end point is the start point")), "{:?}", errors(&fanuc));
}

/// An arc without a centre after a refused block that held the motion code the program meant
/// (`G01 X10. R10` refused, so the modal G03 stays) names that block, as the other follow-on
/// defects do.
#[test]
fn an_arc_without_a_centre_names_a_refused_block_before_it() {
    let p = read("%\nO1000\nG21 G90 G17 F100.\nG0 X0. Y0. Z0.\nG3 X5. Y5. R5.\nG01 X10. R10\nX20. Y5.\nM30\n%\n", Dialect::Fanuc, "t.nc", &ReadOptions::default());
    let e = errors(&p);
    assert!(e.iter().any(|(l, _, m)| *l == 7 && m.starts_with("G03 without a centre") && m.contains("(line 6 was refused before it")), "{e:?}");
}

/// A FANUC post's start (NC-PB/gEdit's owner-public 5X_MILLING.NC, a hyperMILL toolpath: `N30 G69`
/// before `G43.4`) in a `.nc` file on a machine without a control is guessed to be LinuxCNC's, which
/// has no G69: the refusal says so and names the dialect that reads it; read as FANUC's, clean.
#[test]
fn a_fanuc_program_read_as_linuxcncs_names_the_dialect_that_reads_it() {
    let text = "%\nO0001 (5X_MILLING)\nN10 G0 G40\nN20 G80 G90 G94 G98\nN30 G69\nN40 G54\nN50 T1 M6\nN70 S5093 M3\n\
                N80 G0 G17 A-43.657 C-8.247\nN90 X35.524 Y19.868\nN100 G43 Z189. H1\nN110 G49\nN120 G43.4\n\
                N130 X25.443 Y100.88 Z165.439\nN160 G1 X31.404 Y59.749 Z121.883 F5093\nN170 X32.493 Y59.706 Z121.891 A-43.789 C-6.933\nN180 G49\nN190 M30\n%\n";
    assert_eq!(Dialect::detect(Some(std::path::Path::new("5X_MILLING.NC")), text), Dialect::Rs274);
    let p = read(text, Dialect::Rs274, "5X_MILLING.NC", &ReadOptions::default());
    let e = p.diagnostics.iter().find(|d| d.line == 5 && d.message.contains("G69")).unwrap_or_else(|| panic!("{:#?}", p.diagnostics));
    assert!(e.message.contains("G69: no LinuxCNC code") && e.message.contains("--dialect fanuc"), "{}", e.message);
    let p = read(text, Dialect::Fanuc, "5X_MILLING.NC", &ReadOptions::default());
    assert!(!p.has_errors(), "{:?}", p.report());
}
