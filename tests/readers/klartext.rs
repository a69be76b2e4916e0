//! Heidenhain Klartext read as the TNC reads it: feeds, datums, labels and repeats, cycle 32, PLANE
//! POINTS, Q formulas and jumps, M140 and polar contours, and what it refuses.

use super::*;

#[test]
fn klartext_reads_feeds_datums_labels_and_tcpm() {
    let text = "0 BEGIN PGM T MM\n1 TOOL CALL 5 Z S12000 F750\n2 Q7 = +1.5\n3 FN 0: Q8 = -2\n4 L X+1 Y+Q7 Z-Q8 R0 F1000 M3\n\
                5 L IX+2 FMAX\n6 L X+0 FAUTO\n7 CYCL DEF 7.0 DATUM SHIFT\n8 CYCL DEF 7.1 X+10\n9 CYCL DEF 7.2 IY+5\n\
                10 FUNCTION TCPM F TCP AXIS POS PATHCTRL VECTOR\n11 L A+10 C+20\n12 FUNCTION RESET TCPM\n13 L Z+50 FMAX M30\n\
                14 L X+99 F100\n15 END PGM T MM\n";
    let p = read(text, Dialect::Klartext, "t.h", &ReadOptions::default());
    assert!(p.diagnostics.is_empty(), "{:#?}", p.diagnostics);
    let by = |n: u64| p.blocks.iter().find(|b| b.number == Some(n)).unwrap_or_else(|| panic!("block {n}"));
    assert_eq!(by(1).events, vec!["T5".to_string(), "S12000".to_string()]);
    // Q parameters set to numbers, with the word's sign: Y = Q7, Z = -Q8.
    assert_eq!((by(4).targets.y, by(4).targets.z), (Some(1.5 * MM), Some(2.0 * MM)));
    assert_eq!(by(4).feed.unwrap().value_per_min, 1000.0);
    // FMAX: a rapid for its block only; the feed of the blocks after it stays; FAUTO is TOOL CALL's F.
    assert_eq!((by(5).motion, by(5).targets.x), (Motion::Rapid, Some(3.0 * MM)));
    assert_eq!((by(6).motion, by(6).feed.unwrap().value_per_min), (Motion::Linear, 750.0));
    // Cycle 7: absolute X, incremental Y from the last shift.
    assert_eq!(by(11).datum, [10.0 * MM, 5.0 * MM, 0.0]);
    assert!(by(11).tcp && by(11).orientation == Orientation::GreatCircle);
    assert!(!by(13).tcp);
    // M30 ends the program: block 14 is not run.
    assert!(p.blocks.iter().all(|b| b.number != Some(14)));
}

#[test]
fn klartext_refuses_a_decimal_comma_naming_the_number_it_would_be() {
    // A post written for a German-language system can write `X35,524` (NC-PB/gEdit's owner-public
    // 5X_MILLING.H); the TNC's numbers take a decimal point. Refused at each word's column, the
    // number named as it would be written; an expression's comma is no decimal comma.
    let text = "0 BEGIN PGM T MM\n1 L X35,524 Y-19,868 Z+5 R0 FMAX\n2 L X1,2,3\n3 END PGM T MM\n";
    let p = read(text, Dialect::Klartext, "t.h", &ReadOptions::default());
    let at = |l: usize, c: usize| p.diagnostics.iter().find(|d| (d.line, d.column) == (l, c)).map(|d| d.message.as_str()).unwrap_or_else(|| panic!("{l}:{c}: {:#?}", p.diagnostics));
    assert!(at(2, 5).contains("a decimal comma: numbers take a decimal point, X35.524"), "{}", at(2, 5));
    assert!(at(2, 13).contains("Y-19.868"), "{}", at(2, 13));
    assert!(!at(3, 5).contains("decimal comma"), "{}", at(3, 5));
    assert!(p.blocks.iter().all(|b| b.line != 2 && b.line != 3), "the blocks are refused");
}

#[test]
fn klartext_reads_f_max_and_f_auto_written_with_a_space() {
    // hyperMILL's and other posts' Klartext writes the rapid as `F MAX` (a public DMG DMU program:
    // `L X173.5 Y20 R0 F MAX M3`); the TNC reads it as FMAX.
    let text = "0 BEGIN PGM T MM\n1 TOOL CALL 5 Z S12000 F750\n2 L X+1 Y+2 Z+3 R0 F1000 M3\n3 L X+5 R0 F MAX M8\n\
                4 L Y+6 f max\n5 L X+7 F AUTO\n6 L Z+9\n7 END PGM T MM\n";
    let p = read(text, Dialect::Klartext, "t.h", &ReadOptions::default());
    assert!(p.diagnostics.is_empty(), "{:#?}", p.diagnostics);
    let by = |n: u64| p.blocks.iter().find(|b| b.number == Some(n)).unwrap_or_else(|| panic!("block {n}"));
    assert_eq!((by(3).motion, by(3).targets.x), (Motion::Rapid, Some(5.0 * MM)));
    assert!(by(3).events.iter().any(|e| e == "M8"), "{:?}", by(3).events);
    assert_eq!(by(4).motion, Motion::Rapid);
    // F AUTO is the TOOL CALL's feed; a rapid is for its block only, so block 6 cuts at F750 too.
    assert_eq!((by(5).motion, by(5).feed.unwrap().value_per_min), (Motion::Linear, 750.0));
    assert_eq!((by(6).motion, by(6).feed.unwrap().value_per_min), (Motion::Linear, 750.0));
    // `F` then something else is still a feed without its number, at F's column; on a circle F MAX
    // is refused as FMAX is.
    let bad = "0 BEGIN PGM T MM\n1 L X+1 R0 F MAXI\n2 CC X+0 Y+0\n3 C X+1 Y+0 DR+ F MAX\n4 END PGM T MM\n";
    let p = read(bad, Dialect::Klartext, "t.h", &ReadOptions::default());
    let found: Vec<(usize, usize)> = p.diagnostics.iter().map(|d| (d.line, d.column)).collect();
    assert!(found.contains(&(2, 12)) && found.contains(&(2, 14)) && found.contains(&(4, 17)), "{:#?}", p.diagnostics);
    assert!(p.diagnostics.iter().any(|d| d.message.contains("FMAX on a circle")), "{:#?}", p.diagnostics);
}

#[test]
fn klartext_runs_section_repeats_and_subprograms_as_the_tnc_does() {
    // LBL 1 ... CALL LBL 1 REP 2 runs the section three times; CALL LBL 2 runs the subprogram after
    // M2 up to LBL 0 and comes back, nested once more inside it.
    let text = "0 BEGIN PGM R MM\n1 L X+0 Y+0 Z+0 R0 F100\n2 LBL 1\n3 L IX+1\n4 CALL LBL 1 REP2\n5 CALL LBL 2\n\
                6 L X+50\n7 L Z+10 M2\n8 LBL 2\n9 L Y+7\n10 CALL LBL \"DEEP\"\n11 LBL 0\n12 LBL \"DEEP\"\n13 L Z-1\n14 LBL 0\n\
                15 END PGM R MM\n";
    let p = read(text, Dialect::Klartext, "r.h", &ReadOptions::default());
    assert!(p.diagnostics.is_empty(), "{:#?}", p.diagnostics);
    let run: Vec<(u64, Option<f64>)> = p.blocks.iter().map(|b| (b.number.unwrap(), b.targets.x.or(b.targets.y).or(b.targets.z))).collect();
    let mm = |v: f64| Some(v * MM);
    assert_eq!(run, vec![(1, mm(0.0)), (3, mm(1.0)), (3, mm(2.0)), (3, mm(3.0)), (9, mm(7.0)), (13, mm(-1.0)), (6, mm(50.0)), (7, mm(10.0))]);
    // Keywords in mixed case read the same (the labels found before the run too).
    let lower = read(&text.replace("LBL", "Lbl").replace("CALL", "Call"), Dialect::Klartext, "r.h", &ReadOptions::default());
    assert!(lower.diagnostics.is_empty(), "{:#?}", lower.diagnostics);
    assert_eq!(lower.blocks.len(), run.len());

    // A call that never returns, a label that is not there, a repeat beyond the TNC's count.
    let p = read("0 BEGIN PGM R MM\n1 LBL 1\n2 CALL LBL 1\n3 CALL LBL 9\n4 END PGM R MM\n", Dialect::Klartext, "r.h", &ReadOptions::default());
    has(&p, 3, 3, "subprograms nested deeper than 19 levels");
    let p = read("0 BEGIN PGM R MM\n1 CALL LBL 9\n2 LBL 1\n3 CALL LBL 1 REP 70000\n4 END PGM R MM\n", Dialect::Klartext, "r.h", &ReadOptions::default());
    has(&p, 2, 3, "no LBL 9");
    has(&p, 4, 14, "REP 70000");
    // Repeats nested to billions of blocks stop at a stated bound, not at the memory's end.
    let mut t = String::from("0 BEGIN PGM R MM\n1 L X+0 F100\n");
    for k in 0..4 {
        t.push_str(&format!("{} LBL {}\n", 2 + 3 * k, k + 1));
    }
    t.push_str("20 L IX+1\n");
    for k in (0..4).rev() {
        t.push_str(&format!("{} CALL LBL {} REP 1000\n", 30 - k, k + 1));
    }
    t.push_str("40 END PGM R MM\n");
    let p = read(&t, Dialect::Klartext, "r.h", &ReadOptions::default());
    assert!(errors(&p).iter().any(|(_, _, m)| m.contains("blocks beyond the program's own")), "{:#?}", errors(&p));
    assert!(p.blocks.len() <= fiveaxis::program::MAX_RUN_LINES + 20);
    // The bound is the reader's option: a smaller one stops the same program sooner, and says so.
    let small = ReadOptions { max_run_lines: 5000, ..ReadOptions::default() };
    let p = read(&t, Dialect::Klartext, "r.h", &small);
    assert!(errors(&p).iter().any(|(_, _, m)| m.contains("more than 5000 blocks beyond the program's own")), "{:#?}", errors(&p));
    // (It counts statements run, labels and calls too: fewer blocks than that, and far fewer than the default's.)
    assert!((1000..=5000 + 20).contains(&p.blocks.len()), "{}", p.blocks.len());
}

/// Cycle 32 (TNC 620 Cycle Programming §12.5): `T` in the program's unit, `TA` in degrees, for the
/// blocks after it; `32.1` alone returns both to the machine's; the roughing filter and values out of
/// the cycle's range are refused where they are written.
#[test]
fn klartext_reads_the_contour_tolerance_of_cycle_32() {
    let text = "0 BEGIN PGM T INCH\n1 L X+0 Y+0 Z+0 R0 F100\n2 CYCL DEF 32.0 TOLERANCE\n3 CYCL DEF 32.1 T0.001\n\
                4 L X+1\n5 CYCL DEF 32.2 HSC-MODE:0 TA0.5\n6 L X+2\n7 CYCL DEF 32.0 TOLERANZ\n8 CYCL DEF 32.1\n9 L X+3\n\
                10 END PGM T INCH\n";
    let tenths = fiveaxis::machine::Machine::from_toml_str(&format!("tnc_inch_feed = \"tenths\"\n{}", fiveaxis::machine::builtin_file("generic-bc-table").unwrap()), "t").unwrap();
    let p = read(text, Dialect::Klartext, "t.h", &ReadOptions::default().on(&tenths));
    assert!(p.diagnostics.is_empty(), "{:#?}", p.diagnostics);
    let by = |n: u64| p.blocks.iter().find(|b| b.number == Some(n)).unwrap_or_else(|| panic!("block {n}")).tolerance;
    let close = |a: Option<f64>, b: f64| a.is_some_and(|a| (a - b).abs() < 1e-15);
    assert!(by(1).is_unset());
    assert!(close(by(4).linear_m, 0.0254e-3) && by(4).rotary_rad.is_none(), "{:?}", by(4));
    assert!(close(by(6).linear_m, 0.0254e-3) && close(by(6).rotary_rad, 0.5 * DEG), "{:?}", by(6));
    assert!(by(9).is_unset(), "{:?}", by(9));

    // Lines are the file's (block n on line n + 1).
    let text = "0 BEGIN PGM T MM\n1 L X+0 Y+0 Z+0 R0 F100\n2 CYCL DEF 32.2 HSC-MODE:1 TA1\n3 CYCL DEF 32.1 T12\n\
                4 CYCL DEF 32.2 HSC-MODE:0 TA-1\n5 CYCL DEF 32.1 T0.01 TA1\n6 L X+1\n7 END PGM T MM\n";
    let p = read(text, Dialect::Klartext, "t.h", &ReadOptions::default());
    // HSC-MODE:1 (the roughing filter) keeps the tolerance as the bound: read as HSC-MODE:0.
    assert!(errors(&p).iter().all(|(l, _, _)| *l != 3), "{:?}", errors(&p));
    has(&p, 4, 17, "12 mm is outside 0 to 10 mm");
    has(&p, 5, 28, "-1 deg is outside 0 to 10 deg");
    has(&p, 6, 3, "CYCL DEF 32");
    let six = p.blocks.iter().find(|b| b.number == Some(6)).unwrap().tolerance;
    assert!(six.linear_m.is_none() && six.rotary_rad.is_some_and(|r| (r - DEG).abs() < 1e-15), "{six:?}");
}

#[test]
fn klartext_refuses_what_changes_the_motion_at_line_and_column() {
    let text = "0 BEGIN PGM BAD MM\n1 L X+0 Y+0 Z+0 R0 F100\n2 L X+5 RL\n3 APPR LT X+1 Y+1 LEN5 RL\n4 CYCL DEF 19.0 WORKING PLANE\n\
                5 PLANE SPATIAL SPA+0 SPB+45 SPC+0 TURN FMAX\n6 Q1 = Q2 + 3\n7 TOOL CALL 2 Z DL+0.5\n\
                8 FUNCTION TCPM F TCP AXIS SPAT PATHCTRL AXIS\n9 L X+1 M91\n10 L X+Q5\n11 CT X+9 Y+9\n12 LN X+1 Y+1 NX+0 NY+0 NZ+1\n\
                13 L X+7\n14 END PGM BAD MM\n";
    let p = read(text, Dialect::Klartext, "bad.h", &ReadOptions::default());
    has(&p, 3, 9, "RL: the radius is the called tool's, and no TOOL CALL");
    has(&p, 4, 3, "APPR");
    // Without a machine, a tilted plane cannot be solved (the machine's kinematics pick the axes).
    has(&p, 6, 3, "PLANE: a tilted working plane needs the machine's kinematics");
    has(&p, 7, 3, "Q2 is read before it is set");
    has(&p, 8, 17, "DL+0.5");
    has(&p, 9, 3, "AXIS SPAT");
    has(&p, 10, 9, "M91: the machine file places no machine coordinates");
    has(&p, 11, 6, "Q5 is used before it is set");
    has(&p, 12, 4, "CT: no contour element before it");
    has(&p, 13, 4, "LN: expected X Y Z and NX NY NZ");
    // Every good block is kept; none of the refused ones is. Block 13 is refused too: the radius
    // compensation of block 3's APPR, the plane of block 5 (refused: no machine) and the FUNCTION
    // TCPM of block 8 are in effect on the TNC.
    has(&p, 14, 4, "line 4's APPR (radius compensation RL/RR) is in effect on the TNC");
    let numbers: Vec<u64> = p.blocks.iter().filter_map(|b| b.number).collect();
    assert_eq!(numbers, vec![1]);
    // A file without BEGIN PGM says so.
    let p = read("1 L X+0 F100\n", Dialect::Klartext, "x.h", &ReadOptions::default());
    has(&p, 1, 3, "expected BEGIN PGM");
}

/// `PLANE POINTS` (iTNC 530 ISO 340 49x-03 §9.6: point 1 to point 2 is the tilted X, point 3 on the
/// tilted Y's side) of the plane of the manual's worked example `PLANE SPATIAL SPA+0 SPB+45 SPC+0` on
/// a table with a rotary C and a tilting A (User's Manual DIN/ISO 6/2010 §12.2): from A0 C0 the
/// control turns to A+45 C+90, to 0.001 deg, as for the spatial angles; STAY leaves the angles in
/// Q120-Q122 for the program's own positioning. Points on one line are refused at the block.
#[test]
fn klartext_plane_points_gives_the_manuals_axes() {
    let hermle = fiveaxis::machine::Machine::hermle_c600u();
    let options = ReadOptions::default().on(&hermle);
    let axes = |plane: &str| {
        let text = format!("0 BEGIN PGM P MM\n1 L X+0 Y+0 Z+100 A+0 C+0 R0 FMAX\n2 {plane}\n3 END PGM P MM\n");
        let p = read(&text, Dialect::Klartext, "p.h", &options);
        assert!(errors(&p).is_empty(), "{plane}: {:?}", errors(&p));
        let b = p.blocks.iter().rev().find(|b| b.line == 3 && b.targets.a.is_some()).unwrap_or_else(|| panic!("{plane}: {:#?}", p.blocks));
        [b.targets.a.unwrap().to_degrees(), b.targets.c.unwrap().to_degrees()]
    };
    let spatial = axes("PLANE SPATIAL SPA+0 SPB+45 SPC+0 TURN FMAX");
    let points = axes("PLANE POINTS P1X+0 P1Y+0 P1Z+0 P2X+10 P2Y+0 P2Z-10 P3X+0 P3Y+10 P3Z+0 TURN FMAX");
    for (got, name) in [(spatial, "SPATIAL"), (points, "POINTS")] {
        assert!((got[0] - 45.0).abs() < 1e-3 && (got[1] - 90.0).abs() < 1e-3, "PLANE {name}: A{} C{}, the manual's A+45 C+90", got[0], got[1]);
    }
    // STAY: the same angles in Q120 (A) and Q122 (C), positioned by the program.
    let text = "0 BEGIN PGM P MM\n1 L X+0 Y+0 Z+100 A+0 C+0 R0 FMAX\n\
                2 PLANE POINTS P1X+5 P1Y+5 P1Z+5 P2X+15 P2Y+5 P2Z-5 P3X+5 P3Y+15 P3Z+5 STAY\n3 L A+Q120 C+Q122 FMAX\n4 END PGM P MM\n";
    let p = read(text, Dialect::Klartext, "p.h", &options);
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    let b = p.blocks.iter().find(|b| b.line == 4).unwrap();
    assert!((b.targets.a.unwrap().to_degrees() - 45.0).abs() < 1e-3 && (b.targets.c.unwrap().to_degrees() - 90.0).abs() < 1e-3, "{:?}", b.targets);
    let text = "0 BEGIN PGM P MM\n1 PLANE POINTS P1X+0 P1Y+0 P1Z+0 P2X+10 P2Y+0 P2Z+0 P3X+30 P3Y+0 P3Z+0 TURN FMAX\n2 END PGM P MM\n";
    has(&read(text, Dialect::Klartext, "p.h", &options), 2, 3, "PLANE POINTS: the three points lie on one line");
}

/// Klartext Q parameter formulas, FN 0-8 and the jumps FN 9-12 run as the TNC runs them: a loop
/// by FN 12 back to a label three times, a named label jumped to, a block skip before a block
/// number; a parameter read before it is set, a formula's defect and an unknown label are refused
/// where they stand.
#[test]
fn klartext_q_formulas_and_jumps_run_as_the_tnc_runs_them() {
    let text = "0 BEGIN PGM Q MM\n1 Q1 = 10\n2 Q2 = (Q1 + 2) * 2 ^ 2 - 400 % 360 ; 8\n3 FN 1: Q3 = +Q1 + +Q2\n4 FN 0: Q4 = +0\n\
                5 LBL 1\n6 FN 1: Q4 = +Q4 + +1\n7 L X+Q4 Y+Q3 Z-Q2 R0 F500\n8 FN 12: IF +Q4 LT +3 GOTO LBL 1\n\
                9 FN 9: IF +Q4 EQU +3 GOTO LBL \"DONE\"\n10 L X+99 R0 F500\n11 LBL \"DONE\"\n12 Q5 = SQRT (Q1 ^ 2 - 36)\n13 L X+Q5 R0 F500\n/14 M30\n15 END PGM Q MM\n";
    let p = read(text, Dialect::Klartext, "q.h", &ReadOptions::default());
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    let xs: Vec<f64> = p.blocks.iter().filter_map(|b| b.targets.x).map(|x| x / MM).collect();
    assert_eq!(xs, [1.0, 2.0, 3.0, 8.0], "the loop three times, X+99 jumped over, then SQRT(100 - 36)");
    let b = p.blocks.iter().find(|b| b.targets.y.is_some()).unwrap();
    assert_eq!((b.targets.y.unwrap() / MM, b.targets.z.unwrap() / MM), (18.0, -8.0));
    let bad = |line: &str| read(&format!("0 BEGIN PGM Q MM\n1 Q1 = 1\n{line}\n3 END PGM Q MM\n"), Dialect::Klartext, "q.h", &ReadOptions::default());
    for (line, needle) in [
        ("2 L X+Q7 R0 F100", "Q7 is used before it is set"),
        ("2 Q2 = Q1 / (Q1 - 1)", "division by zero"),
        ("2 Q2 = (Q1 + 1", "not closed"),
        ("2 FN 9: IF +Q1 EQU +1 GOTO LBL 5", "no LBL 5"),
        ("2 FN 14: ERROR = 1000", "FN 14: not read"),
    ] {
        let p = bad(line);
        assert!(errors(&p).iter().any(|(l, _, m)| *l == 3 && m.contains(needle)), "{line}: {:?}", errors(&p));
    }
}

/// `M140 MB` (iTNC 530 user's manual, "Retraction from the contour in the tool-axis direction:
/// M140"): the tool backs off along its own axis, by MB or, with MB MAX, to the end of the
/// traverse range. On the Hermle (a table machine, the spindle along Z) MAX takes Z to the top of
/// its range; on the generic B/C fork head at B 90 the tool lies along +X, so
/// MB 25 moves X by 25 mm (the head's pivot 300 mm up does not change the direction) and MAX
/// takes X to +5 m.
#[test]
fn klartext_m140_backs_off_along_the_tool_axis() {
    use fiveaxis::machine::Machine;
    let hermle = Machine::builtin("hermle-c600u").unwrap();
    let p = read("0 BEGIN PGM R MM\n1 L X+10 Y+20 Z+30 FMAX\n2 M140 MB MAX F1000\n3 L Z+40 FMAX\n4 M140 MB+12 F500\n5 END PGM R MM\n", Dialect::Klartext, "r.h", &ReadOptions::default().on(&hermle));
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    let zmax = hermle.axes[2].limits.max;
    let b2 = p.blocks.iter().find(|b| b.line == 3).unwrap();
    assert!((b2.targets.z.unwrap() + b2.datum[2] - zmax).abs() < 1e-9 && b2.motion == fiveaxis::program::Motion::Linear, "{b2:?}");
    let b4 = p.blocks.iter().find(|b| b.line == 5).unwrap();
    assert!((b4.targets.z.unwrap() + b4.datum[2] - 0.052).abs() < 1e-9, "Z 40 + 12 mm: {b4:?}");
    assert!((b4.feed.unwrap().value_per_min - 500.0).abs() < 1e-9);

    let head = Machine::builtin("generic-bc-head").unwrap();
    let p = read("0 BEGIN PGM R MM\n1 L X+10 Y+20 Z+30 B+90 C+0 FMAX\n2 M140 MB+25 F800\n3 M140 MB MAX\n4 END PGM R MM\n", Dialect::Klartext, "r.h", &ReadOptions::default().on(&head));
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    let at = |line: usize| {
        let b = p.blocks.iter().find(|b| b.line == line).unwrap();
        [b.targets.x.unwrap() + b.datum[0], b.targets.y.unwrap() + b.datum[1], b.targets.z.unwrap() + b.datum[2]]
    };
    let (a, b, c) = (at(2), at(3), at(4));
    assert!((b[0] - a[0] - 0.025).abs() < 1e-9 && (b[1] - a[1]).abs() < 1e-9 && (b[2] - a[2]).abs() < 1e-9, "{a:?} -> {b:?}");
    assert!((c[0] - 5.0).abs() < 1e-9 && (c[2] - a[2]).abs() < 1e-9, "{c:?}");
    // Without F, at rapid traverse.
    assert_eq!(p.blocks.iter().find(|b| b.line == 4).unwrap().motion, fiveaxis::program::Motion::Rapid);
    // Without a machine there is no tool axis or travel to go by: refused, naming why.
    let p = read("0 BEGIN PGM R MM\n1 M140 MB MAX\n2 END PGM R MM\n", Dialect::Klartext, "r.h", &ReadOptions::default());
    has(&p, 2, 3, "M140: ");
}

/// `CR` with a radius written without a sign (a shop editor's demo: `CR Y-59.224 R9.45
/// DR-`) is R+, as a number without a sign is everywhere on the TNC: the arc under 180 deg, the same
/// circle as `R+9.45`; `R-9.45` is the other one (its centre mirrored across the chord). From
/// X-80 Y-50 to Y-59.224: the chord is 13.531 long, so the centre lies sqrt(9.45^2 -
/// 6.7655^2) = 6.598 from its middle.
#[test]
fn klartext_cr_reads_an_unsigned_radius_as_positive() {
    let circle = |r: &str| {
        let text = format!("0 BEGIN PGM T MM\n1 TOOL CALL 1 Z S1000\n2 L X-80 Y-50 Z+0 R0 F500\n3 CR X-89.9 Y-59.224 R{r} DR-\n4 END PGM T MM\n");
        let p = read(&text, Dialect::Klartext, "t.h", &ReadOptions::default());
        assert!(errors(&p).is_empty(), "R{r}: {:?}", errors(&p));
        let b = p.blocks.iter().find(|b| b.line == 4).unwrap();
        (b.motion, b.arc.as_deref().unwrap().centre)
    };
    let (plus, unsigned, minus) = (circle("+9.45"), circle("9.45"), circle("-9.45"));
    assert_eq!(plus, unsigned);
    assert_eq!(unsigned.0, Motion::ArcCw);
    let (mx, my) = (-84.95 * MM, -54.612 * MM);
    let off = |c: [f64; 3]| ((c[0] - mx).hypot(c[1] - my) / MM, c);
    let h = (9.45f64.powi(2) - (13.531_f64 / 2.0).powi(2)).sqrt();
    assert!((off(unsigned.1).0 - h).abs() < 2e-3 && (off(minus.1).0 - h).abs() < 2e-3, "{:?} {:?}", off(unsigned.1), off(minus.1));
    assert!((unsigned.1[0] - minus.1[0]).abs() > 1e-3, "R- is the other circle");
}

/// A TNC inch program's F is in 1/10 inch/min (TNC7 user's manual "Cutting data"; a TNC7
/// programming station reads `F100` in an inch program at 254 mm/min; Autodesk's Klartext post writes
/// inch feeds tenfold), where NX's sample posts write whole inch/min: the machine file's
/// `tnc_inch_feed` settles it. With "tenths", 1 inch at F100 (10 in/min) is 254 mm/min and cycle
/// 200's Q206=+50 plunges at 5 in/min (127 mm/min); with "whole", F100 is 2540 mm/min; without it,
/// tenths and one error at the header. A rotary axis' F stays degrees per minute.
#[test]
fn klartext_inch_feeds_are_in_tenths_of_an_inch_per_minute() {
    let file = fiveaxis::machine::builtin_file("generic-bc-table").unwrap();
    let on = |setting: &str| ReadOptions::default().on(&fiveaxis::machine::Machine::from_toml_str(&format!("{setting}\n{file}"), "t").unwrap());
    let text = "0 BEGIN PGM T INCH\n1 TOOL CALL 1 Z S1000\n2 L X+0 Y+0 Z+1 C+0 R0 FMAX\n3 L X+1 F100\n4 CYCL DEF 200 DRILLING ~\n Q200=+0.1 ~\n Q201=-0.5 ~\n Q206=+50 ~\n Q202=+0.5 ~\n Q210=+0 ~\n Q203=+0 ~\n Q204=+1 ~\n Q211=+0\n13 L X+2 Y+0 R0 FMAX M99\n14 L C+90 F100\n15 END PGM T INCH\n";
    let p = read(text, Dialect::Klartext, "t.h", &on("tnc_inch_feed = \"tenths\""));
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    let feed = |line: usize| p.blocks.iter().filter(|b| b.line == line && b.motion == Motion::Linear).map(|b| b.feed.unwrap()).collect::<Vec<_>>();
    let mm_per_min = |f: fiveaxis::program::Feed| f.value_per_min;
    assert!((mm_per_min(feed(4)[0]) - 254.0).abs() < 1e-9, "{:?}", feed(4));
    let plunge = feed(14);
    assert!(!plunge.is_empty() && plunge.iter().all(|f| (mm_per_min(*f) - 127.0).abs() < 1e-9), "{plunge:?}");
    assert!((feed(15)[0].rotary_per_min - 100.0).abs() < 1e-9, "{:?}", feed(15));
    let whole = read(text, Dialect::Klartext, "t.h", &on("tnc_inch_feed = \"whole\""));
    assert!(errors(&whole).is_empty(), "{:?}", errors(&whole));
    let f = whole.blocks.iter().find(|b| b.line == 4).and_then(|b| b.feed).unwrap();
    assert!((f.value_per_min - 2540.0).abs() < 1e-9, "{f:?}");
    let unset = read(text, Dialect::Klartext, "t.h", &ReadOptions::default().on(&fiveaxis::machine::Machine::builtin("generic-bc-table").unwrap()));
    let e = errors(&unset);
    assert!(e.len() == 1 && e[0].0 == 1 && e[0].2.contains("tnc_inch_feed"), "{e:?}");
    let f = unset.blocks.iter().find(|b| b.line == 4).and_then(|b| b.feed).unwrap();
    assert!((f.value_per_min - 254.0).abs() < 1e-9, "{f:?}");
}

/// `PLANE ... TURN MB n|MAX` (TNC 620 User's Manual 10/2017, "The PLANE function", positioning: the
/// retraction MB "is effective incrementally from the current tool position in the active tool axis
/// direction that the control approaches before tilting. MB MAX positions the tool just before the
/// software limit switch"). On the Hermle, untilted, the tool axis is Z: from Z+30, MB+20 at F2000
/// retracts to Z 50 at that feed, MB MAX at rapid to the top of Z's range; then the rotary axes turn
/// to the manual's A+45 C+90 with X, Y and Z where the retract left them. MB with STAY (nothing
/// moves) and MB without a distance are refused at the word.
#[test]
fn klartext_plane_mb_retracts_along_the_tool_axis_before_tilting() {
    use fiveaxis::program::Motion;
    let hermle = fiveaxis::machine::Machine::hermle_c600u();
    let options = ReadOptions::default().on(&hermle);
    let zmax = hermle.axes[2].limits.max;
    for (mb, z, motion) in [("MB+20 F2000", 0.050, Motion::Linear), ("MB MAX FMAX", zmax, Motion::Rapid)] {
        let text = format!("0 BEGIN PGM P MM\n1 L X+10 Y+20 Z+30 A+0 C+0 R0 FMAX\n2 PLANE SPATIAL SPA+0 SPB+45 SPC+0 TURN {mb}\n3 END PGM P MM\n");
        let p = read(&text, Dialect::Klartext, "p.h", &options);
        assert!(errors(&p).is_empty(), "{mb}: {:?}", errors(&p));
        let moves: Vec<_> = p.blocks.iter().filter(|b| b.line == 3 && !b.targets.is_empty()).collect();
        assert!(moves.len() >= 2, "{mb}: a retract, then the rotary axes: {moves:#?}");
        let (r, t) = (moves[0], moves.last().unwrap());
        let at = |b: &fiveaxis::program::Block, k: usize| [b.targets.x, b.targets.y, b.targets.z][k].unwrap() + b.datum[k];
        assert!((at(r, 2) - z).abs() < 1e-9 && (at(r, 0) - 0.010).abs() < 1e-9 && (at(r, 1) - 0.020).abs() < 1e-9, "{mb}: {r:?}");
        assert!(r.targets.a.is_none_or(|a| a.abs() < 1e-12) && r.motion == motion, "{mb}: the retract moves no rotary axis: {r:?}");
        if motion == Motion::Linear {
            assert!((r.feed.unwrap().value_per_min - 2000.0).abs() < 1e-9, "{r:?}");
        }
        assert!((t.targets.a.unwrap().to_degrees() - 45.0).abs() < 1e-3 && (t.targets.c.unwrap().to_degrees() - 90.0).abs() < 1e-3, "{mb}: {t:?}");
    }
    let refused = |plane: &str, col: usize, needle: &str| {
        let text = format!("0 BEGIN PGM P MM\n1 L X+10 Y+20 Z+30 A+0 C+0 R0 FMAX\n2 {plane}\n3 END PGM P MM\n");
        has(&read(&text, Dialect::Klartext, "p.h", &options), 3, col, needle);
    };
    refused("PLANE SPATIAL SPA+0 SPB+45 SPC+0 STAY MB MAX", 41, "STAY MB");
    refused("PLANE SPATIAL SPA+0 SPB+45 SPC+0 TURN MB FMAX", 41, "MB: expected a retract distance or MAX");
}

/// Klartext polar contours (iTNC 530 user's manual §6.5): LP to a radius and angle about the pole,
/// CP about it to an angle (its radius the start's), IPA beyond 360 deg as turns of a helix with the
/// tool axis' coordinate, IPR and IPA from the start's polar coordinates. By hand, pole (0, 0) from
/// (10, 0): LP PR+20 PA+90 to (0, 20); CP PA+180 DR+ to (-20, 0), a quarter circle (10 pi mm); CP
/// IPA+720 Z-4 DR+ two turns down 4 mm (a helix of sqrt((80 pi)^2 + 4^2) mm) back to (-20, 0);
/// LP IPR+5 IPA-90 to (0, 25). CP IPA+90 with DR- is refused (the TNC wants one sign for both).
#[test]
fn klartext_polar_lines_circles_and_helices_are_where_the_tnc_puts_them() {
    let text = "0 BEGIN PGM P MM\n1 CC X+0 Y+0\n2 L X+10 Y+0 Z+0 R0 F600\n3 LP PR+20 PA+90\n4 CP PA+180 DR+\n5 CP IPA+720 Z-4 DR+\n6 LP IPR+5 IPA-90\n7 END PGM P MM\n";
    let p = read(text, Dialect::Klartext, "p.h", &ReadOptions::default());
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    let end = |line: usize| {
        let b = p.blocks.iter().find(|b| b.line == line).unwrap();
        [b.targets.x.unwrap() / MM, b.targets.y.unwrap() / MM]
    };
    let close = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).abs() < 1e-9 && (a[1] - b[1]).abs() < 1e-9;
    assert!(close(end(4), [0.0, 20.0]), "{:?}", end(4));
    assert!(close(end(5), [-20.0, 0.0]), "{:?}", end(5));
    assert!(close(end(6), [-20.0, 0.0]), "{:?}", end(6));
    assert!(close(end(7), [0.0, 25.0]), "{:?}", end(7));
    // The path's lengths, sampled by the planner.
    let dir = std::env::temp_dir().join(format!("fiveaxis-polar-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("p.h");
    std::fs::write(&path, text).unwrap();
    let machine = fiveaxis::machine::Machine::hermle_c600u();
    let job = fiveaxis::job::run(&path.display().to_string(), &machine, &fiveaxis::job::JobOptions::default()).unwrap();
    let length = |line: usize| job.trajectory.segments.iter().filter(|g| g.line == line).map(|g| g.length).sum::<f64>() / MM;
    let pi = std::f64::consts::PI;
    // The planner's arcs are cubic pieces 5 deg long, within R 1e-7 of the circle.
    assert!((length(5) - 10.0 * pi).abs() < 1e-4, "quarter circle: {}", length(5));
    assert!((length(6) - (80.0 * pi).hypot(4.0)).abs() < 1e-4, "helix: {}", length(6));
    let worst = job.trajectory.samples(&machine).filter(|s| job.trajectory.segments[s.segment].line == 6).map(|s| (s.tip.x.hypot(s.tip.y) / MM - 20.0).abs()).fold(0.0, f64::max);
    assert!(worst < 1e-4, "the helix leaves its cylinder by {worst} mm");
    let _ = std::fs::remove_dir_all(&dir);
    let bad = read("0 BEGIN PGM P MM\n1 CC X+0 Y+0\n2 L X+10 Y+0 R0 F600\n3 CP IPA+90 DR-\n4 LP PR+5 PA+0 X+3\n5 LP PA+10\n6 END PGM P MM\n", Dialect::Klartext, "p.h", &ReadOptions::default());
    has(&bad, 4, 3, "the same sign");
    has(&bad, 5, 16, "the end point in the working plane is the polar one");
    // `LP PA+10` alone keeps the start's radius (tests/readers/shop_words.rs): no defect.
    assert!(errors(&bad).iter().all(|(l, _, _)| *l != 6), "{:?}", errors(&bad));
    let no_pole = read("0 BEGIN PGM P MM\n1 L X+10 Y+0 R0 F600\n2 LP PR+5 PA+0\n3 END PGM P MM\n", Dialect::Klartext, "p.h", &ReadOptions::default());
    has(&no_pole, 3, 3, "no pole CC");
    // A helix's angle beyond the TNC's input range, 5400 deg (TNC 640 DIN/ISO manual §19.3), is said
    // at its IPA (ten million turns were blamed on a P word the program does not have); 5400 reads.
    let typo = read("0 BEGIN PGM P MM\n1 CC X+0 Y+0\n2 L X+10 Y+0 Z+0 R0 F600\n3 CP IPA+3600000000 IZ-1 DR+\n4 CP IPA-5400.001 IZ-1 DR-\n5 CP IPA+5400 IZ-1 DR+\n6 END PGM P MM\n", Dialect::Klartext, "p.h", &ReadOptions::default());
    has(&typo, 4, 6, "IPA+3600000000: beyond the TNC's input range of a helix's angle, -5400 to +5400 deg");
    has(&typo, 5, 6, "IPA-5400.001: beyond the TNC's input range");
    assert!(errors(&typo).iter().all(|(l, _, _)| *l != 6), "{:?}", errors(&typo));
}

/// A circle `C` with no pole before it is refused once, naming the TNC's `CC` (not DIN/ISO's I and J).
#[test]
fn klartext_a_circle_without_its_pole_names_cc() {
    let p = read("BEGIN PGM T MM\nL X+10 Y+0 Z+0 R0 F100\nC X+0 Y+10 DR+\nEND PGM T MM\n", Dialect::Klartext, "t.h", &ReadOptions::default());
    let said: Vec<_> = errors(&p).into_iter().filter(|(l, _, _)| *l == 3).collect();
    assert_eq!(said.len(), 1, "{said:?}");
    assert!(said[0].2.contains("a circle centre CC before this block"), "{said:?}");
}

/// A comment the TNC broke over lines with `~` (a block longer than a line goes on in the next, as
/// its cycles' parameters do): the lines after it are its text, however they begin, up to the line
/// that ends without `~`. The block after the comment is read; a stray line after a comment that
/// does not go on is still refused.
#[test]
fn klartext_reads_a_comment_going_on_over_lines() {
    let text = "0 BEGIN PGM C MM\n1 ;This program is free software: you can redistribute it~\n under the terms of the GNU License~\n version 3.\n\
                2 L X+1 Y+2 Z+3 R0 F100\n3 ;one line ~ in the middle\n4 L X+4\n5 END PGM C MM\n";
    let p = read(text, Dialect::Klartext, "c.h", &ReadOptions::default());
    assert!(p.diagnostics.is_empty(), "{:#?}", p.diagnostics);
    assert_eq!(p.blocks.iter().filter_map(|b| b.targets.x).collect::<Vec<_>>(), vec![1.0 * MM, 4.0 * MM]);
    let stray = "0 BEGIN PGM C MM\n1 ;a comment that ends here\n under the terms\n2 L X+1 Y+2 Z+3 R0 F100\n3 END PGM C MM\n";
    let p = read(stray, Dialect::Klartext, "c.h", &ReadOptions::default());
    assert!(p.diagnostics.iter().any(|d| d.line == 3 && d.message.contains("unknown block 'under'")), "{:#?}", p.diagnostics);
    // A continuation begins with a blank: a numbered block after a comment of tildes is read, with a
    // warning; a continuation that reads `LBL 5` is no label (the call finds none).
    let tildes = "0 BEGIN PGM C MM\n1 ;~~~~~~~~\n2 L Z+100 R0 FMAX\n3 L X+0 Y+0 FMAX\n4 ;see~\n LBL 5\n5 CALL LBL 5\n6 END PGM C MM\n";
    let p = read(tildes, Dialect::Klartext, "c.h", &ReadOptions::default());
    assert!(p.blocks.iter().any(|b| b.line == 3 && b.targets.z == Some(100.0 * MM)), "{:#?}", p.blocks);
    assert!(p.diagnostics.iter().any(|d| d.line == 3 && d.severity == Severity::Warning && d.message.contains("does not begin with a blank")), "{:#?}", p.diagnostics);
    assert!(p.diagnostics.iter().any(|d| d.line == 7 && d.severity == Severity::Error), "{:#?}", p.diagnostics);
}

/// `PLANE ... MOVE DIST.. F..` (TNC 620 User's Manual 10/2017, "The PLANE function": "The control
/// tilts the tool (or table) relative to the tool tip"; DIST "shifts the center of rotation of the
/// movement relative to the current position of the tool tip"; a tool at that distance from the
/// workpiece before is at the same relative position after). On the Hermle from the tip at (10, 20,
/// 30) with the tool along Z, SPB+45 MOVE DIST+30: the centre is (10, 20, 0); every chord end lies
/// 30 mm from it, every chord's middle within 1 µm of that sphere, and the last is 30 mm along the
/// plane's Z, (sin 45°, 0, cos 45°) (the manual's SPB, by hand): (31.2132, 20, 21.2132), with the
/// axes at the plane's A+45 C+90. DIST+0 keeps the tip where it stands; FMAX makes rapids.
#[test]
fn klartext_plane_move_turns_about_the_point_dist_below_the_tip() {
    use fiveaxis::program::Motion;
    let hermle = fiveaxis::machine::Machine::hermle_c600u();
    let options = ReadOptions::default().on(&hermle);
    let s = std::f64::consts::FRAC_1_SQRT_2;
    for (dist, feed, motion) in [(30.0, "F1000", Motion::Linear), (0.0, "FMAX", Motion::Rapid)] {
        let text = format!("0 BEGIN PGM P MM\n1 L X+10 Y+20 Z+30 A+0 C+0 R0 FMAX\n2 PLANE SPATIAL SPA+0 SPB+45 SPC+0 MOVE DIST+{dist} {feed}\n3 L Z+50 R0 FMAX\n4 END PGM P MM\n");
        let p = read(&text, Dialect::Klartext, "p.h", &options);
        assert!(errors(&p).is_empty(), "DIST {dist}: {:?}", errors(&p));
        let moves: Vec<_> = p.blocks.iter().filter(|b| b.line == 3 && !b.targets.is_empty()).collect();
        assert!(moves.len() >= if dist > 0.0 { 16 } else { 1 } && moves.iter().all(|b| b.tcp && b.motion == motion), "DIST {dist}: {} chords", moves.len());
        let tip = |b: &fiveaxis::program::Block| [0, 1, 2].map(|k| ([b.targets.x, b.targets.y, b.targets.z][k].unwrap() + b.datum[k]) / MM);
        let centre = [10.0, 20.0, 30.0 - dist];
        let from = |t: [f64; 3]| ((t[0] - centre[0]).powi(2) + (t[1] - centre[1]).powi(2) + (t[2] - centre[2]).powi(2)).sqrt();
        let mut last = [10.0, 20.0, 30.0];
        for b in &moves {
            let t = tip(b);
            assert!((from(t) - dist).abs() < 1e-9, "DIST {dist}: a chord end {t:?} is {} mm from the centre", from(t));
            let mid = [0, 1, 2].map(|k| 0.5 * (t[k] + last[k]));
            assert!(from(mid) > dist - 1e-3, "DIST {dist}: a chord's middle {mid:?} is {} mm from the centre", from(mid));
            last = t;
        }
        let want = [centre[0] + dist * s, 20.0, centre[2] + dist * s];
        assert!((0..3).all(|k| (last[k] - want[k]).abs() < 1e-9), "DIST {dist}: ends at {last:?}, by hand {want:?}");
        let end = moves.last().unwrap();
        assert!((end.targets.a.unwrap().to_degrees() - 45.0).abs() < 1e-9 && (end.targets.c.unwrap().to_degrees() - 90.0).abs() < 1e-9, "{end:?}");
        if motion == Motion::Linear {
            assert!((moves[0].feed.unwrap().value_per_min - 1000.0).abs() < 1e-9, "{:?}", moves[0]);
        }
        // In the plane, Z+50 goes along its Z from where the MOVE left the tip: (x, y) stay.
        let after = p.blocks.iter().find(|b| b.line == 4).unwrap();
        let t = tip(after);
        let z_plane = 50.0 - (want[0] * s + want[2] * s); // how far along the plane's Z the tip goes
        assert!((0..3).all(|k| (t[k] - (want[k] + z_plane * [s, 0.0, s][k])).abs() < 1e-9), "DIST {dist}: {t:?}");
    }
    let refused = |plane: &str, col: usize, needle: &str| {
        let text = format!("0 BEGIN PGM P MM\n1 L X+10 Y+20 Z+30 A+0 C+0 R0 FMAX\n2 {plane}\n3 END PGM P MM\n");
        has(&read(&text, Dialect::Klartext, "p.h", &options), 3, col, needle);
    };
    refused("PLANE SPATIAL SPA+0 SPB+45 SPC+0 MOVE F1000", 3, "MOVE without DIST");
    refused("PLANE SPATIAL SPA+0 SPB+45 SPC+0 TURN DIST+5 FMAX", 41, "DIST goes with MOVE");
    refused("PLANE SPATIAL SPA+0 SPB+45 SPC+0 MOVE DIST FMAX", 41, "DIST: expected the distance");
}

/// MOVE turns a modulo axis as TURN does: under M126 the shorter way, under M127 as written. From
/// C+350 to the plane's C+90 on the Hermle (A+30 to A+45): the last chord's C is 450 (100° on)
/// under M126, 90 (260° back) under M127, both by hand.
#[test]
fn klartext_plane_move_turns_a_modulo_axis_the_way_turn_does() {
    let hermle = fiveaxis::machine::Machine::hermle_c600u();
    let options = ReadOptions::default().on(&hermle);
    for (m, c) in [("M126", 450.0), ("M127", 90.0)] {
        let text = format!("0 BEGIN PGM P MM\n1 L X+10 Y+20 Z+30 A+30 C+350 R0 FMAX\n2 L {m}\n3 PLANE SPATIAL SPA+0 SPB+45 SPC+0 MOVE DIST+0 F1000\n4 END PGM P MM\n");
        let p = read(&text, Dialect::Klartext, "p.h", &options);
        assert!(errors(&p).is_empty(), "{m}: {:?}", errors(&p));
        let last = p.blocks.iter().filter(|b| b.line == 4).last().unwrap();
        assert!((last.targets.c.unwrap().to_degrees() - c).abs() < 1e-9, "{m}: {last:?}");
    }
    has(&read("0 BEGIN PGM P MM\n1 L X+10 Y+20 Z+30 A+0 C+0 R0 FMAX\n2 PLANE RESET MOVE DIST+0 FMAX\n3 END PGM P MM\n", Dialect::Klartext, "p.h", &options), 3, 3, "PLANE RESET ... MOVE");
    // A plane refused (a DIST whose chords would exceed 4096) leaves no MB retract before it: the TNC
    // refuses the block before it moves.
    let p = read("0 BEGIN PGM P MM\n1 L X+10 Y+20 Z+30 A+0 C+0 R0 FMAX\n2 PLANE SPATIAL SPA+0 SPB+45 SPC+0 MOVE DIST+99999 MB+20 F1000\n3 END PGM P MM\n", Dialect::Klartext, "p.h", &options);
    has(&p, 3, 3, "PLANE ... MOVE: the compensating move needs chords");
    assert!(p.blocks.iter().all(|b| b.line != 3), "{:?}", p.blocks);
}

/// What the TNC does and this reader does not read is refused at its block, never read as
/// something else: `PLANE RESET TURN` (the rotary axes turn back to their basic position, MOVE or
/// TURN; STAY leaves them), a datum shift programmed in a tilted plane (it acts in the tilted system,
/// TNC 320 user's manual 9/2016 p.108), an arc with no end point, and an LN block whose tool has
/// radius deltas in the tool table (the TNC moves it along the normal by them). The forms whose
/// rule is at hand read: STAY, a shift before the plane or to 0 in it, C with its start's X.
#[test]
fn klartext_refuses_what_moves_the_tool_unread() {
    let hermle = fiveaxis::machine::Machine::hermle_c600u();
    let options = ReadOptions::default().on(&hermle);
    let pgm = |body: &str| format!("0 BEGIN PGM P MM\n1 TOOL CALL 3 Z S5000\n2 L X+0 Y+0 Z+100 A+0 C+0 R0 FMAX\n{body}99 END PGM P MM\n");
    let tilt = "3 PLANE SPATIAL SPA+30 SPB+0 SPC+40 TURN MB MAX FMAX\n";
    for reset in ["PLANE RESET TURN MB MAX FMAX", "PLANE RESET TURN FMAX"] {
        has(&read(&pgm(&format!("{tilt}4 {reset}\n5 L X+10 F1000\n")), Dialect::Klartext, "p.h", &options), 5, 3, "PLANE RESET ... TURN");
    }
    let stay = read(&pgm(&format!("{tilt}4 PLANE RESET STAY\n5 L X+10 F1000\n")), Dialect::Klartext, "p.h", &options);
    assert!(errors(&stay).is_empty(), "{:?}", errors(&stay));
    // Cycle 7 after the plane: refused at its word; before it, or a shift to 0 after it, read.
    let shift = |at: &str| format!("{at}.0 CYCL DEF 7.0 DATUM SHIFT\n{at}.1 CYCL DEF 7.2 Y+50\n");
    let text = pgm(&format!("{tilt}{}6 L X+0 Y+0 Z+0 F1000\n", shift("4").replace("4.0", "4").replace("4.1", "5")));
    has(&read(&text, Dialect::Klartext, "p.h", &options), 6, 16, "acts in the tilted system");
    let before = pgm(&format!("3 CYCL DEF 7.0 DATUM SHIFT\n4 CYCL DEF 7.2 Y+50\n{}6 L X+0 Y+0 Z+0 F1000\n", tilt.replace("3 ", "5 ")));
    assert!(errors(&read(&before, Dialect::Klartext, "p.h", &options)).is_empty());
    let zero = pgm(&format!("{tilt}4 CYCL DEF 7.0 DATUM SHIFT\n5 CYCL DEF 7.1 X+0\n6 CYCL DEF 7.2 Y+0\n7 L X+0 Y+0 Z+0 F1000\n"));
    assert!(errors(&read(&zero, Dialect::Klartext, "p.h", &options)).is_empty());
    // hyperMILL's reset in the plane of a shift made before it: X, Y and Z to 0 together, read; X
    // alone to 0 while Y's shift stands: which system's X it zeroes is not read.
    let before_tilt = "3 CYCL DEF 7.0 DATUM SHIFT\n4 CYCL DEF 7.1 X+10\n5 CYCL DEF 7.2 Y+5\n";
    let reset = pgm(&format!("{before_tilt}{}7 CYCL DEF 7.0 DATUM SHIFT\n8 CYCL DEF 7.1 X+0\n9 CYCL DEF 7.2 Y+0\n10 CYCL DEF 7.3 Z+0\n11 PLANE RESET STAY\n", tilt.replace("3 ", "6 ")));
    assert!(errors(&read(&reset, Dialect::Klartext, "p.h", &options)).is_empty(), "{:?}", errors(&read(&reset, Dialect::Klartext, "p.h", &options)));
    let partial = pgm(&format!("{before_tilt}{}7 CYCL DEF 7.0 DATUM SHIFT\n8 CYCL DEF 7.1 X+0\n9 L Z+50 F1000\n", tilt.replace("3 ", "6 ")));
    has(&read(&partial, Dialect::Klartext, "p.h", &options), 9, 16, "CYCL DEF 7 of 0 in a tilted working plane leaving a shift");
    // Arcs without an end point; C with its start's X is the full circle about CC.
    for (arc, needle) in [("C DR+", "C: expected the arc's end point"), ("CR R+10 DR+", "CR: expected the arc's end point"), ("C DR+ F1000", "C: expected")] {
        has(&read(&pgm(&format!("3 L X+10 Y+0 F1000\n4 CC X+0 Y+0\n5 {arc}\n")), Dialect::Klartext, "p.h", &options), 6, 3, needle);
    }
    let full = read(&pgm("3 L X+10 Y+0 F1000\n4 CC X+0 Y+0\n5 C X+10 DR+\n"), Dialect::Klartext, "p.h", &options);
    assert!(errors(&full).is_empty(), "{:?}", errors(&full));
    // LN with tool 3's DR -0.5 in the table: refused; with DR 0, read at the point written.
    let table = |dr: &str| {
        let text = format!("BEGIN TOOL.T MM\nT    NAME                 L           R           DR          DR2\n3    MILL                 +55         +3          {dr:<12}+0\n[END]\n");
        std::sync::Arc::new(fiveaxis::program::ToolTable::parse(&text).unwrap())
    };
    let ln = pgm("3 LN X+10 Y+0 Z+100 NX+0 NY+0 NZ+1 F1000\n");
    let with = ReadOptions { tool_table: Some(table("-0.5")), ..options.clone() };
    has(&read(&ln, Dialect::Klartext, "p.h", &with), 4, 3, "LN with tool 3's deltas DR -0.5000");
    let without = ReadOptions { tool_table: Some(table("+0")), ..options.clone() };
    let p = read(&ln, Dialect::Klartext, "p.h", &without);
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    assert_eq!(ends(&p).last().copied(), Some([10.0, 0.0, 100.0]));
}

/// Cycle 19 with a feed positions the rotary axes itself on a machine so set up (MP7500 bit 2), which
/// is not read: refused at F. On a machine whose cycle 19 takes spatial angles, the control stores
/// Q120-Q122 by its own choice (the shorter path from zero, TNC 320 Cycle Programming §11.9), not
/// read here: a program reading them after it stops there, not at the angles of an earlier PLANE.
#[test]
fn cycle_19_positioning_and_its_q_parameters_fail_closed() {
    let a_c = fiveaxis::machine::Machine::builtin("dmg-dmu-85-monoblock").unwrap();
    let options = ReadOptions::default().on(&a_c);
    let text = "0 BEGIN PGM P MM\n1 L X+0 Y+0 Z+150 A+0 C+0 R0 FMAX\n2 CYCL DEF 19.0 WORKING PLANE\n3 CYCL DEF 19.1 A+30 C+90 F5000\n4 END PGM P MM\n";
    has(&read(text, Dialect::Klartext, "p.h", &options), 4, 27, "CYCL DEF 19.1 with F5000");
    let file = fiveaxis::machine::builtin_file("dmg-dmu-85-monoblock").unwrap().replace("tool_axis = [0.0, 0.0, 1.0]", "tool_axis = [0.0, 0.0, 1.0]\ncycle19_spatial = true");
    let spatial = fiveaxis::machine::Machine::from_toml_str(&file, "t").unwrap();
    let options = ReadOptions::default().on(&spatial);
    let text = "0 BEGIN PGM P MM\n1 L X+0 Y+0 Z+150 A+0 C+0 R0 FMAX\n2 PLANE SPATIAL SPA+20 SPB+0 SPC+0 STAY\n3 PLANE RESET STAY\n\
                4 CYCL DEF 19.0 WORKING PLANE\n5 CYCL DEF 19.1 A+30 B+0 C+0\n6 L A+Q120 C+Q122 R0 FMAX\n7 END PGM P MM\n";
    let p = read(text, Dialect::Klartext, "p.h", &options);
    assert!(errors(&p).iter().any(|(l, _, m)| *l == 7 && m.contains("Q120")), "{:?}", errors(&p));
}
