//! The TNC's drilling cycles as the Klartext reader runs them (cycles 1, 9, 200, 201, 203, 207, 209, 241 and
//! M89/M99 calls), each against the manual's process worked by hand, and the cycles not read named
//! where they are called.

use super::*;

/// `M89`, the modal cycle call, calls the cycle at the end of its own block and then after every
/// positioning block until `M99` (which calls it once more) or `CYCL CALL` (TNC 306/406 Technical
/// Manual §7.4: MP7440 bit 1 "Modal cycle-call M89 at end of block"; "for every following
/// positioning block there will be a call of the last-programmed machining-cycle. M89 is canceled
/// by M99 or a CYCL CALL-block"): cycle 200 at X10 (M89), X20, X30 (M99), none at X40. Each hole
/// feeds to its depth Z-10 in two plunges of 5 mm.
#[test]
fn klartext_m89_drills_at_its_own_block_and_each_after_it() {
    let text = "BEGIN PGM T MM\nTOOL CALL 1 Z S1000\nL Z+50 R0 FMAX\nCYCL DEF 200 DRILLING ~\n Q200=+2 ~\n Q201=-10 ~\n Q206=+150 ~\n Q202=+5 ~\n Q210=+0 ~\n Q203=+0 ~\n Q204=+50 ~\n Q211=+0\n\
                L X+10 Y+10 R0 FMAX M89\nL X+20 R0 FMAX\nL X+30 R0 FMAX M99\nL X+40 R0 FMAX\nEND PGM T MM\n";
    let p = read(text, Dialect::Klartext, "t.h", &ReadOptions::default());
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    let bottoms = |line: usize| p.blocks.iter().filter(|b| b.line == line && b.motion != Motion::Rapid && b.targets.z.is_some_and(|z| (z / MM + 10.0).abs() < 1e-9)).count();
    assert_eq!([bottoms(13), bottoms(14), bottoms(15), bottoms(16)], [1, 1, 1, 0], "{:#?}", p.blocks);
}

/// The moves a cycle call made (its line's blocks): rapid or not, Z (mm), feed (mm/min; 0 for a rapid).
fn cycle_moves(p: &Program, line: usize) -> Vec<(bool, f64, f64)> {
    p.blocks
        .iter()
        .filter(|b| b.line == line && b.targets.z.is_some())
        .map(|b| (b.motion == Motion::Rapid, b.targets.z.unwrap() / MM, if b.motion == Motion::Rapid { 0.0 } else { b.feed.unwrap().value_per_min }))
        .collect()
}

fn same_moves(got: &[(bool, f64, f64)], want: &[(bool, f64, f64)]) -> bool {
    got.len() == want.len() && got.iter().zip(want).all(|(g, w)| g.0 == w.0 && (g.1 - w.1).abs() < 1e-9 && (g.2 - w.2).abs() < 1e-9)
}

/// Cycle 203 UNIVERSAL DRILLING with a shop's hyperMILL parameters (W5246NS01007B16.h: surface
/// 0.1, set-up clearance 1, depth -0.6 in plunges of 0.1, one chip break of 0.2 before each
/// retraction, out at Q208=25000), its moves worked by hand from the parameters' rules (iTNC 530
/// User's Manual, cycle 203): infeeds to 0, -0.1, ... -0.5 at Q206; after the first of each pair
/// the tool backs off 0.2, after the second it goes out to the set-up clearance (1.1) and back at
/// FMAX to 1 above the depth reached; at the bottom out at Q208, then the 2nd set-up clearance.
/// `Q208= MAX` retracts at rapid traverse; `Q208=0` at Q206. A maker's cycle between the definition
/// and its call does not change the drilling cycle's parameters.
#[test]
fn klartext_cycle_203_drills_with_chip_breaks_and_retractions() {
    let params = |q208: &str| {
        format!(
            "0 BEGIN PGM T MM\n1 TOOL CALL 1 Z S3000\n2 L X+0 Y+0 Z+50 R0 FMAX\n3 FN 0: Q3=100\n4 CYCL DEF 203 UNIVERSAL DRILLING~\n  Q200=1 ;SET-UP CLEARANCE~\n  Q201=-0.6 ;DEPTH~\n  Q206=Q3 ;FEED RATE FOR PLUNGING~\n  Q202=0.1 ;PLUNGING DEPTH~\n  Q210=0 ;DWELL TIME AT TOP~\n  Q203=0.1 ;SURFACE COORDINATE~\n  Q204=1 ;2ND SET-UP CLEARANCE~\n  Q212=0 ;DECREMENT~\n  Q213=1 ;BREAKS~\n  Q205=0.1 ;MIN. PLUNGING DEPTH~\n  Q211=0 ;DWELL TIME AT BOTTOM~\n  Q208={q208} ;RETRACTION FEED RATE~\n  Q256=0.2 ;DIST FOR CHIP BRKNG\n5 L X+10 Y+5 R0 FMAX M99\n6 END PGM T MM\n"
        )
    };
    // (rapid, Z mm, feed mm/min): P the plunging feed, R the retraction's.
    let want = |r: f64| {
        let out = |z: f64| if r == 0.0 { (true, z, 0.0) } else { (false, z, r) };
        vec![
            (true, 1.1, 0.0),
            (false, 0.0, 100.0),
            out(0.2),
            (false, -0.1, 100.0),
            out(1.1),
            (true, 0.9, 0.0),
            (false, -0.2, 100.0),
            out(0.0),
            (false, -0.3, 100.0),
            out(1.1),
            (true, 0.7, 0.0),
            (false, -0.4, 100.0),
            out(-0.2),
            (false, -0.5, 100.0),
            out(1.1),
            (true, 1.1, 0.0),
        ]
    };
    for (q208, r) in [("25000", 25000.0), (" MAX", 0.0), ("0", 100.0)] {
        let p = read(&params(q208), Dialect::Klartext, "t.h", &ReadOptions::default());
        assert!(errors(&p).is_empty(), "Q208={q208}: {:?}", errors(&p));
        let got = cycle_moves(&p, 19);
        assert!(same_moves(&got, &want(r)), "Q208={q208}: {got:?}");
    }
    // The Trimill's cycle 332 TUNING between the definition and its call sets Q395=+3, which is
    // cycle 203's depth reference: the drilling cycle keeps the parameters its definition wrote.
    let trimill = fiveaxis::machine::Machine::builtin("trimill-vu3019").unwrap();
    let tuned = params("25000").replace("5 L X+10", "5 CYCL DEF 332 TUNING ~\n  Q395=+3 ;TUNING MODE\n6 L X+10");
    let p = read(&tuned, Dialect::Klartext, "t.h", &ReadOptions::default().on(&trimill));
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    assert!(same_moves(&cycle_moves(&p, 21), &want(25000.0)), "{:?}", cycle_moves(&p, 21));
    // A fractional number of breaks, and MAX where a length is expected, are refused at the call.
    for (from, to, message) in [("Q213=1 ", "Q213=1.5 ", "Q213=1.5"), ("Q201=-0.6 ", "Q201= MAX ", "Q201=MAX")] {
        let p = read(&params("0").replace(from, to), Dialect::Klartext, "t.h", &ReadOptions::default());
        let e = errors(&p);
        assert!(e.len() == 1 && e[0].0 == 19 && e[0].2.contains(message), "{to}: {e:?}");
    }
}

/// Cycle 207 RIGID TAPPING as a DMU shop's hyperMILL program writes it (W5270NS01061A7.h: no
/// Q206, the cycle has no feed of its own: "the feed rate is the thread pitch times the spindle
/// speed"): at S500 and Q239=+1 it feeds at 500 mm/min from the set-up clearance (27.1493 + 3) to
/// the depth (27.1493 - 12.5296) and back, then FMAX to the 2nd set-up clearance (27.1493 + 76.8507).
#[test]
fn klartext_cycle_207_taps_at_the_pitch_times_the_speed() {
    let text = "0 BEGIN PGM T MM\n1 TOOL CALL 1 Z S500\n2 L X+0 Y+0 Z+150 R0 FMAX M3\n3 CYCL DEF 207 RIGID TAPPING NEW~\n   Q200=3 ;SET-UP CLEARANCE~\n   Q201=-12.5296 ;DEPTH~\n   Q239=+1 ;THREAD PITCH~\n   Q203=27.1493 ;SURFACE COORDINATE~\n   Q204=76.8507 ;2ND SET-UP CLEARANCE\n4 L X-71.1452 Y0 R0 F MAX M99\n5 END PGM T MM\n";
    let p = read(text, Dialect::Klartext, "t.h", &ReadOptions::default());
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    let got = cycle_moves(&p, 10);
    let want = [(true, 30.1493, 0.0), (false, 14.6197, 500.0), (false, 30.1493, 500.0), (true, 104.0, 0.0)];
    assert!(same_moves(&got, &want), "{got:?}");
}

/// Cycle 201 REAMING as a Trimill shop's hyperMILL program writes it (W5269NS01006B20.h: Q200=5,
/// Q201=-15, Q206=Q2, Q211=0, Q208=50, Q203=1, Q204=29), its moves worked by hand from the
/// parameters' definitions (iTNC 530 User's Manual, cycle 201: Q206 the feed "during reaming", Q208
/// "when retracting from the hole ... If Q208 = 0 is entered, the reaming feed rate applies"): FMAX
/// to the set-up clearance (1 + 5), ream at Q2 = 75 to 1 - 15, out at 50 to 6, FMAX to 1 + 29.
#[test]
fn klartext_cycle_201_reams_in_and_comes_out_at_its_retraction_feed() {
    let text = |q208: &str| {
        format!("0 BEGIN PGM T MM\n1 TOOL CALL 1 Z S800\n2 FN 0: Q2=75\n3 L X+0 Y+0 Z+50 R0 FMAX M3\n4 CYCL DEF 201 REAMING~\n Q200=5 ;SET-UP CLEARANCE~\n Q201=-15 ;DEPTH~\n Q206=Q2 ;FEED RATE FOR PLUNGING~\n Q211=0 ;DWELL TIME AT BOTTOM~\n Q208={q208} ;RETRACTION FEED TIME~\n Q203=1 ;SURFACE COORDINATE~\n Q204=29 ;2ND SET-UP CLEARANCE\n5 L X305 Y280 R0 F MAX M99\n6 END PGM T MM\n")
    };
    for (q208, out) in [("50", 50.0), ("0", 75.0)] {
        let p = read(&text(q208), Dialect::Klartext, "t.h", &ReadOptions::default());
        assert!(errors(&p).is_empty(), "Q208={q208}: {:?}", errors(&p));
        let got = cycle_moves(&p, 13);
        assert!(same_moves(&got, &[(true, 6.0, 0.0), (false, -14.0, 75.0), (false, 6.0, out), (true, 30.0, 0.0)]), "Q208={q208}: {got:?}");
    }
}

/// Cycle 209 TAPPING WITH CHIP BREAKING as a DMU shop's hyperMILL program writes it
/// (W5269NS01007C19.h: Q200=3, Q201=-48, Q239=+2, Q203=0, Q204=50, Q257=25, Q256=1, Q336=0, Q403),
/// its moves worked by hand from the parameters' definitions (TNC 320 User's Manual for cycle
/// programming 9/2016 §4.4): at S800 the tap feeds at 2 x 800 = 1600 mm/min to 25 deep, backs off
/// Q256 x Q239 = 2 at Q403 = 1.5 times that (2400), taps on to 48 deep, comes out at 2400, then FMAX
/// to the 2nd set-up clearance. Q256=0 backs out to the set-up clearance; a definition without
/// Q403 (older software's) comes out at the tapping feed; Q257=0 taps in one go.
#[test]
fn klartext_cycle_209_taps_with_chip_breaks_by_its_parameters() {
    let text = |q257: &str, q256: &str, q403: &str| {
        format!("0 BEGIN PGM T MM\n1 TOOL CALL 1 Z S800\n2 L X+0 Y+0 Z+80 R0 FMAX M3\n3 CYCL DEF 209 TAPPING W/ CHIP BRKG~\n Q200=  3  ;SET-UP CLEARANCE~\n Q201= -48  ;DEPTH~\n Q239= +2  ;THREAD PITCH~\n Q203=0 ;SURFACE COORDINATE~\n Q204=50 ;2ND SET-UP CLEARANCE~\n Q257={q257}  ;DEPTH FOR CHIP BRKNG~\n Q256={q256}  ;DIST FOR CHIP BRKNG~\n Q336=0  ;ANGLE OF SPINDLE{q403}\n4 L X298 Y164 R0 F MAX M99\n5 END PGM T MM\n")
    };
    let factor = "~\n Q403=1.5  ;RPM FACTOR";
    let cases: [(&str, &str, &str, usize, &[(bool, f64, f64)]); 4] = [
        ("25", "1", factor, 14, &[(true, 3.0, 0.0), (false, -25.0, 1600.0), (false, -23.0, 2400.0), (false, -48.0, 1600.0), (false, 3.0, 2400.0), (true, 50.0, 0.0)]),
        ("25", "0", factor, 14, &[(true, 3.0, 0.0), (false, -25.0, 1600.0), (false, 3.0, 2400.0), (false, -48.0, 1600.0), (false, 3.0, 2400.0), (true, 50.0, 0.0)]),
        ("25", "1", "", 13, &[(true, 3.0, 0.0), (false, -25.0, 1600.0), (false, -23.0, 1600.0), (false, -48.0, 1600.0), (false, 3.0, 1600.0), (true, 50.0, 0.0)]),
        ("0", "1", factor, 14, &[(true, 3.0, 0.0), (false, -48.0, 1600.0), (false, 3.0, 2400.0), (true, 50.0, 0.0)]),
    ];
    for (q257, q256, q403, line, want) in cases {
        let p = read(&text(q257, q256, q403), Dialect::Klartext, "t.h", &ReadOptions::default());
        assert!(errors(&p).is_empty(), "Q257={q257} Q256={q256}: {:?}", errors(&p));
        let got = cycle_moves(&p, line);
        assert!(same_moves(&got, want), "Q257={q257} Q256={q256} {q403:?}: {got:?}");
    }
    // An inch program on a machine that reads its F in tenths (tnc_inch_feed): the pitch 0.1 in at
    // S800 taps at 80 in/min (2032 mm/min) and comes out at 1.5 times that, the levels in inches.
    let mut tenths = fiveaxis::machine::Machine::builtin("trimill-vu3019").unwrap();
    tenths.tnc_inch_feed_tenths = Some(true);
    let inch = "0 BEGIN PGM T INCH\n1 TOOL CALL 1 Z S800\n2 L X+0 Y+0 Z+3 R0 FMAX M3\n3 CYCL DEF 209 TAPPING W/ CHIP BRKG~\n Q200=0.1 ;SET-UP CLEARANCE~\n Q201=-1 ;DEPTH~\n Q239=+0.1 ;THREAD PITCH~\n Q203=0 ;SURFACE COORDINATE~\n Q204=2 ;2ND SET-UP CLEARANCE~\n Q257=0 ;DEPTH FOR CHIP BRKNG~\n Q256=0 ;DIST FOR CHIP BRKNG~\n Q336=0 ;ANGLE OF SPINDLE~\n Q403=1.5 ;RPM FACTOR\n4 L X1 Y1 R0 FMAX M99\n5 END PGM T INCH\n";
    let p = read(inch, Dialect::Klartext, "t.h", &ReadOptions::default().on(&tenths));
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    let got = cycle_moves(&p, 14);
    assert!(same_moves(&got, &[(true, 2.54, 0.0), (false, -25.4, 2032.0), (false, 2.54, 3048.0), (true, 50.8, 0.0)]), "{got:?}");
    // An RPM factor beyond the input range (0.0001 to 10) is refused at the call.
    let p = read(&text("25", "1", "~\n Q403=12  ;RPM FACTOR"), Dialect::Klartext, "t.h", &ReadOptions::default());
    assert!(errors(&p).iter().any(|e| e.0 == 14 && e.2.contains("Q403=12")), "{:?}", errors(&p));
}

/// Cycle 9's dwell as the TNC writes it in its dialog language: `DWELL 2.5`, German `V.ZEIT 2.5`,
/// and a Hungarian shop's hyperMILL output, `V.IDO2.5` or `V.IDŐ2.5` (label and time joined, as
/// cycle 1's parts may be): each the same 2.5 s; a label without a time, or a second number, is
/// refused.
#[test]
fn klartext_cycle_9_reads_its_time_after_a_label_in_any_language() {
    for label in ["DWELL 2.5", "V.ZEIT 2.5", "V.IDO2.5", "V.IDŐ2.5", "DWELL +Q5"] {
        let text = format!("0 BEGIN PGM T MM\n1 Q5 = 2.5\n2 L X+0 Y+0 Z+10 R0 F500\n3 CYCL DEF 9.0 DWELL TIME\n4 CYCL DEF 9.1 {label}\n5 END PGM T MM\n");
        let p = read(&text, Dialect::Klartext, "t.h", &ReadOptions::default());
        assert!(errors(&p).is_empty(), "{label}: {:?}", errors(&p));
        let dwells: Vec<f64> = p.blocks.iter().filter_map(|b| b.dwell_s).collect();
        assert_eq!(dwells, [2.5], "{label}");
    }
    // A label without a time, a second number, or words with digits before the time: refused.
    for bad in ["V.IDO", "DWELL 2.5 3.5", "X+5 DWELL 2.5"] {
        let p = read(&format!("0 BEGIN PGM T MM\n1 CYCL DEF 9.1 {bad}\n2 END PGM T MM\n"), Dialect::Klartext, "t.h", &ReadOptions::default());
        assert!(errors(&p).iter().any(|e| e.0 == 2 && e.2.contains("CYCL DEF 9.1")), "{bad}: {:?}", errors(&p));
    }
}

/// A cycle's parameters are the Q assignments right after its CYCL DEF, written with `~` or as
/// blocks of their own, a comment line among them: cycle 200's `Q395=+1` (a depth to the tool's full
/// diameter, not read) is refused in each layout. A parameter changed between the definition and
/// the call (cycle parameters are Q parameters like any) is refused naming both values: which one
/// the cycle takes is not in the pages at hand. `MAX` outside a cycle's lines is refused.
#[test]
fn klartext_cycle_parameters_follow_their_definition_in_any_layout() {
    let params = ["Q200=2", "Q201=-10", "Q206=150", "Q202=5", "Q210=0", "Q203=0", "Q204=50", "Q211=0", "Q395=+1"];
    let run = |def: String, between: &str| {
        let text = format!("0 BEGIN PGM T MM\n1 TOOL CALL 1 Z S1000\n2 L X+0 Y+0 Z+50 R0 FMAX\n{def}{between}9 L X+10 R0 FMAX M99\n10 END PGM T MM\n");
        errors(&read(&text, Dialect::Klartext, "t.h", &ReadOptions::default()))
    };
    let tilde = format!("3 CYCL DEF 200 DRILLING ~\n{}\n", params.iter().map(|q| format!("  {q} ;P")).collect::<Vec<_>>().join(" ~\n"));
    let blocks = format!("3 CYCL DEF 200 DRILLING\n{}", params.iter().enumerate().map(|(k, q)| format!("{} {q}\n", 4 + k)).collect::<String>());
    let comment = tilde.replace("  Q211=0 ;P ~\n", "  Q211=0 ;P ~\n; a comment\n");
    for def in [tilde.clone(), blocks, comment] {
        let e = run(def.clone(), "");
        assert!(e.len() == 1 && e[0].2.contains("Q395=1"), "{def}: {e:?}");
    }
    let ok = tilde.replace("Q395=+1", "Q395=+0");
    assert!(run(ok.clone(), "").is_empty());
    let e = run(ok.clone(), "8 FN 0: Q5 = 1\n8 Q201 = -40\n");
    assert!(e.len() == 1 && e[0].2.contains("Q201 was -10 in the cycle's definition and is -40 at its call"), "{e:?}");
    let e = run(ok, "8 Q208 = MAX\n");
    assert!(e.iter().any(|e| e.2.contains("MAX (rapid traverse) is written among a cycle's parameters")), "{e:?}");
}

/// Cycle 241 SINGLE-LIP DEEP-HOLE DRILLING as a DMU shop's program has it (W5270NS01061A4.h: set-up
/// clearance 3, depth -272.441, a pilot hole to Q379=16 entered at Q253=50, drilled at Q206=25, out
/// at Q208=300, 2nd set-up clearance 30): FMAX to 3, at 50 to 3 above the pilot hole's bottom (-13),
/// at 25 to the depth, at 300 to 3, FMAX to 30. The spindle's speeds and coolant (Q426-Q430) move no
/// axis. A maker's cycle between the definition and its call (the Trimill's 332 TUNING, as the
/// shop's Trimill programs write it, sets Q395=+3, which to cycles 200 and 203 is a depth reference)
/// leaves the drilling cycle's parameters as they were. A dwell depth (Q435) is refused.
#[test]
fn klartext_cycle_241_enters_the_pilot_hole_then_drills() {
    let text = |q435: &str| {
        format!(
            "0 BEGIN PGM T MM\n1 TOOL CALL 1 Z S1790\n2 L X+0 Y+0 Z+50 R0 FMAX\n3 FN 0: Q1901=4\n4 CYCL DEF 241 SINGLE-LIP DEEP-HOLE DRILLING~\n  Q200=3 ;SET-UP CLEARANCE~\n  Q201=-272.441 ;DEPTH~\n  Q206=25 ;FEED RATE FOR PLUNGING~\n  Q211=0 ;DWELL TIME AT BOTTOM~\n  Q203=0 ;SURFACE COORDINATE~\n  Q204=30 ;2ND SET-UP CLEARANCE~\n  Q379=16 ;STARTING POINT~\n  Q253=50 ;F PRE-POSITIONING~\n  Q208=300 ;RETRACTION FEED TIME~\n  Q426=Q1901 ;DIR. OF SPINDLE ROT.~\n  Q427=50 ;ROT. SPEED INFEED/OUT~\n  Q428=1790 ;DRILLING SPEED~\n  Q429=7 ;COOLANT ON~\n  Q430=7 ;COOLANT OFF~\n  Q435={q435} ;DWELL DEPTH\n5 CYCL DEF 332 TUNING ~\n  Q395=+3 ;TUNING MODE\n6 L X-23 Y-4 R0 F MAX M99\n7 END PGM T MM\n"
        )
    };
    let trimill = fiveaxis::machine::Machine::builtin("trimill-vu3019").unwrap();
    assert!(trimill.state_cycles.contains(&332), "the Trimill's file names its maker's cycle 332");
    let options = ReadOptions::default().on(&trimill);
    let p = read(&text("0"), Dialect::Klartext, "t.h", &options);
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    let got = cycle_moves(&p, 23);
    let want = [(true, 3.0, 0.0), (false, -13.0, 50.0), (false, -272.441, 25.0), (false, 3.0, 300.0), (true, 30.0, 0.0)];
    assert!(same_moves(&got, &want), "{got:?}");
    let e = errors(&read(&text("-200"), Dialect::Klartext, "t.h", &options));
    assert!(e.len() == 1 && e[0].0 == 23 && e[0].2.contains("Q435=-200"), "{e:?}");
}

/// A cycle not read says what it is, and a call of it names it: the older numbered form (`CYCL DEF
/// 2.0 TAPPING`, NX's TNC posts' tapping) is named as such, not "expected a cycle number", and
/// `M99` after a refused `CYCL DEF 205` names the cycle it would run (had been "a cycle call with no
/// cycle defined before it").
#[test]
fn cycles_not_read_are_named_where_they_are_called() {
    let old = "BEGIN PGM T MM\nTOOL CALL 1 Z S1000\nL Z+100 R0 FMAX\nCYCL DEF 2.0 TAPPING\nCYCL DEF 2.1 SET UP 2\nL X+10 Y+10 R0 FMAX M99\nEND PGM T MM\n";
    let p = read(old, Dialect::Klartext, "t.h", &ReadOptions::default());
    let e = errors(&p);
    assert!(e.iter().any(|(l, c, m)| (*l, *c) == (4, 1) && m.contains("cycle 2 in the older numbered form")), "{e:?}");
    assert!(e.iter().any(|(l, _, m)| *l == 5 && m.contains("cycle 2 in the older numbered form")), "{e:?}");
    let called = "BEGIN PGM T MM\nTOOL CALL 1 Z S1000\nL Z+100 R0 FMAX\nCYCL DEF 205 UNIVERSAL PECKING ~\n Q200=+2 ;SET-UP CLEARANCE\nL X+10 Y+10 R0 FMAX M99\nEND PGM T MM\n";
    let p = read(called, Dialect::Klartext, "t.h", &ReadOptions::default());
    let e = errors(&p);
    assert!(e.iter().any(|(l, c, m)| (*l, *c) == (6, 1) && m.contains("a call of CYCL DEF 205 (line 4), which is not read")), "{e:?}");
}

/// The older cycle 1 PECKING (`CYCL DEF 1.0` to `1.5`, as NX's TNC posts and older shop programs
/// write it) runs as the TNC 426/425/415 B/407 manual's PECKING process says (ISO Programming 280
/// 580, §8.2, the same cycle): from where the tool stands, feed to the first pecking depth below
/// the surface (the set-up clearance below the start), back to the start at rapid, down at rapid to
/// the advanced stop distance t above the depth reached (0.6 mm up to a 30 mm hole, else depth/50,
/// at most 7 mm), the next infeed at feed, ... to the total depth, the dwell, back to the start at
/// rapid. The expected moves are computed here from those rules. German labels (`ABST`, `TIEFE`,
/// `ZUSTLG`, `V.ZEIT`, joined to their values) and mixed signs read the same; a decimal comma, a
/// part without its value, a call before `1.5` and pecks too small to be meant are refused where
/// they stand.
#[test]
fn klartext_cycle_1_pecking_runs_as_the_manuals_process() {
    // The manual's rules, for a start z0, set-up a, depth d, peck c (mm): (motion, z) per move.
    let rules = |z0: f64, a: f64, d: f64, c: f64, dwell: bool| -> Vec<(&'static str, f64)> {
        let t = if d <= 30.0 { 0.6 } else { (d / 50.0).min(7.0) };
        let (surface, bottom) = (z0 - a, z0 - a - d);
        let mut moves = Vec::new();
        let mut k = 1.0;
        while surface - k * c > bottom + 1e-9 {
            moves.extend([("feed", surface - k * c), ("rapid", z0), ("rapid", surface - k * c + t)]);
            k += 1.0;
        }
        moves.push(("feed", bottom));
        if dwell {
            moves.push(("dwell", bottom));
        }
        moves.push(("rapid", z0));
        moves
    };
    let head = "BEGIN PGM T MM\nTOOL CALL 1 Z S1000\nL Z+100 R0 FMAX\nL X+10 Y+10 Z+2 R0 FMAX\n";
    let moves = |p: &Program| -> Vec<(&'static str, f64)> {
        p.blocks
            .iter()
            .filter(|b| b.line == 11 && (b.dwell_s.is_some() || b.targets.z.is_some()))
            .map(|b| match (b.dwell_s, b.targets.z, b.motion) {
                (Some(_), _, _) => ("dwell", f64::NAN),
                (None, Some(z), Motion::Rapid) => ("rapid", z / MM),
                (None, Some(z), _) => ("feed", z / MM),
                _ => ("other", f64::NAN),
            })
            .collect()
    };
    let same = |got: &[(&str, f64)], want: &[(&str, f64)]| {
        got.len() == want.len() && got.iter().zip(want).all(|(g, w)| g.0 == w.0 && (g.0 == "dwell" || (g.1 - w.1).abs() < 1e-9))
    };
    let cases = [
        // English labels, a 40 mm hole (t = 0.8 mm), pecks of 15 and a dwell.
        ("CYCL DEF 1.0 PECKING\nCYCL DEF 1.1 SET UP -2\nCYCL DEF 1.2 DEPTH -40\nCYCL DEF 1.3 PECKG -15\nCYCL DEF 1.4 DWELL 0.5\nCYCL DEF 1.5 F100\n", rules(2.0, 2.0, 40.0, 15.0, true)),
        // German labels joined to their values, signs mixed as lk_BewegBlv.h writes them (t = 0.6 mm).
        ("CYCL DEF 1.0 TIEFBOHREN\nCYCL DEF 1.1 ABST+1\nCYCL DEF 1.2 TIEFE-21\nCYCL DEF 1.3 ZUSTLG+3\nCYCL DEF 1.4 V.ZEIT0\nCYCL DEF 1.5 F150\n", rules(2.0, 1.0, 21.0, 3.0, false)),
        // A peck deeper than the hole: one pass.
        ("CYCL DEF 1.0 PECKING\nCYCL DEF 1.1 DIST2.000\nCYCL DEF 1.2 DEPTH-10.000\nCYCL DEF 1.3 PLNGNG12.0\nCYCL DEF 1.4 DWELL0\nCYCL DEF 1.5 F229\n", rules(2.0, 2.0, 10.0, 12.0, false)),
    ];
    for (cycle, want) in &cases {
        let text = format!("{head}{cycle}L X+20 R0 FMAX M99\nEND PGM T MM\n");
        let p = read(&text, Dialect::Klartext, "t.h", &ReadOptions::default());
        assert!(errors(&p).is_empty(), "{cycle}: {:?}", errors(&p));
        let got = moves(&p);
        assert!(same(&got, want), "{cycle}\n got {got:?}\nwant {want:?}");
        // The cycle's feed drills; the program's modal feed (FMAX here) is back after it.
        let feed = p.blocks.iter().filter(|b| b.line == 11 && b.targets.z.is_some() && b.motion != Motion::Rapid && b.dwell_s.is_none()).map(|b| b.feed.map(|f| f.value_per_min)).next().flatten();
        assert!(feed.is_some_and(|f| f > 0.0), "{feed:?}");
    }
    // Refused where they stand: a decimal comma, a part without its value, a call before 1.5.
    let refused = [
        ("CYCL DEF 1.0 TIEFBOHREN\nCYCL DEF 1.1 ABST+1\nCYCL DEF 1.2 TIEFE-11,5\n", 7, 14, "CYCL DEF 1.2: expected the DEPTH"),
        ("CYCL DEF 1.0 PECKING\nCYCL DEF 1.1 SET UP 2\nCYCL DEF 1.2 DEPTH -10\nCYCL DEF 1.3 PECKG 5\nCYCL DEF 1.4 DWELL\n", 9, 14, "CYCL DEF 1.4: expected the DWELL"),
        ("CYCL DEF 1.0 PECKING\nCYCL DEF 1.1 SET UP 2\n", 7, 1, "a call of cycle 1 PECKING (line 5), whose definition is not complete"),
        // Pecks a thousand times too small are a typo, not ten million blocks (cycle 200's Q202
        // took memory without bound before).
        ("CYCL DEF 1.0 PECKING\nCYCL DEF 1.1 SET UP 2\nCYCL DEF 1.2 DEPTH -100\nCYCL DEF 1.3 PECKG 0.00001\nCYCL DEF 1.4 DWELL 0\nCYCL DEF 1.5 F100\n", 11, 1, "makes more than 10000 pecks"),
        ("CYCL DEF 200 DRILLING ~\n Q200=2 ~\n Q201=-100 ~\n Q206=150 ~\n Q202=+0.00001 ~\n Q210=0 ~\n Q203=+0 ~\n Q204=50 ~\n Q211=0\n", 14, 1, "makes more than 10000 plunges"),
    ];
    for (cycle, line, col, message) in refused {
        let text = format!("{head}{cycle}L X+20 R0 FMAX M99\nEND PGM T MM\n");
        let p = read(&text, Dialect::Klartext, "t.h", &ReadOptions::default());
        let e = errors(&p);
        assert!(e.iter().any(|(l, c, m)| (*l, *c) == (line, col) && m.contains(message)), "{cycle}: {e:?}");
    }
}
