//! RS274NGC read as LinuxCNC reads it: end points against its own interpreter's canonical output
//! (`rs274`, fixtures made by make_canon.sh), parameters, expressions and O-word flow, canned cycles,
//! the path tolerance, cutter compensation and the bridgemill demo; the interpreter's state and
//! subroutines in modules of their own, all against LinuxCNC's output as [`canon`] reads it.

use super::*;

mod canon;
mod differential;
mod state;
mod subroutines;

use canon::*;

#[test]
fn rs274_reads_linuxcnc_style_programs() {
    let text = "%\n(five-axis test) ; header\nN10 G21 G90 G94\nG1 X  16.339 Y-2 Z.5 A10 C20 F1500 (cut)\nG91 X1\nG90 G20 X1 ; inches\nG93 G1 X2 F30\nM100\nG0 Z10\nM30\n%\n";
    // M100 is a LinuxCNC user M code: read only when told what it does.
    let refused = read_rs274(text);
    has(&refused, 8, 1, "M100 is not an RS274NGC M code");
    let told = ReadOptions { m_codes: vec!["100=event".parse().unwrap()], ..Default::default() };
    let p = read(text, Dialect::Rs274, "t.ngc", &told);
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    let b: Vec<_> = p.blocks.iter().filter(|b| !b.targets.is_empty()).collect();
    assert_eq!(b[0].targets.x, Some(16.339 * MM));
    assert_eq!(b[0].targets.z, Some(0.5 * MM));
    assert_eq!(b[0].targets.c, Some(20.0 * DEG));
    assert_eq!(b[0].feed.unwrap().value_per_min, 1500.0);
    assert!((b[1].targets.x.unwrap() - 17.339 * MM).abs() < 1e-15, "G91 increment");
    assert!((b[2].targets.x.unwrap() - 25.4 * MM).abs() < 1e-15, "G20 inches");
    assert_eq!(b[3].feed.unwrap().mode, FeedMode::InverseTime);
    assert_eq!(b[3].feed.unwrap().value_per_min, 30.0);
    assert_eq!(b[4].motion, Motion::Rapid);
    let m100 = p.blocks.iter().find(|b| b.events.contains(&"M100".to_string())).expect("unknown M code kept as an event");
    assert_eq!(m100.line, 8);
    // P without a code that takes it is an error, not silently dropped.
    let p = read(&text.replace("M100", "M100 P1"), Dialect::Rs274, "t.ngc", &told);
    has(&p, 8, 6, "word P1 without a G code that takes it");
}

/// LinuxCNC's `G64 P- <Q->`: the naive-CAM tolerance Q (P when Q is not given) is the contour
/// tolerance on the linear axes, in the program's unit; `G64` alone leaves the machine's.
#[test]
fn rs274_reads_the_path_tolerance_of_g64_p_q() {
    let text = "G20 G90 G17 G64 P0.001\nG1 X0 Y0 Z0 F10\nG64 P0.5 Q0.002\nX1\nG21 G64 Q0.02\nX2\nG64 P0 Q0\nX3\nG64\nX4\nM2\n";
    let p = read(text, Dialect::Rs274, "t.ngc", &ReadOptions::default());
    assert!(p.diagnostics.is_empty(), "{:#?}", p.diagnostics);
    let on = |line: usize| p.blocks.iter().find(|b| b.line == line).unwrap_or_else(|| panic!("line {line}")).tolerance;
    let close = |a: Option<f64>, b: f64| a.is_some_and(|a| (a - b).abs() < 1e-15);
    assert!(close(on(2).linear_m, 0.0254e-3) && on(2).rotary_rad.is_none(), "{:?}", on(2));
    assert!(close(on(4).linear_m, 2.0 * 0.0254e-3), "Q before P: {:?}", on(4));
    assert!(close(on(6).linear_m, 0.02e-3), "Q alone, mm: {:?}", on(6));
    assert!(close(on(8).linear_m, 0.0), "Q0: no merging: {:?}", on(8));
    assert!(on(10).is_unset(), "G64 alone: the machine's: {:?}", on(10));
    // Out of range, at the word's column; the block is not used.
    let p = read("G21 G90\nG1 X0 F100\nG64 P-0.1\nG64 P0.01 Q11\nX1\nM2\n", Dialect::Rs274, "t.ngc", &ReadOptions::default());
    has(&p, 3, 5, "G64 P-0.1: the path tolerance must be 0 to 10 mm");
    has(&p, 4, 11, "G64 Q11");
    assert!(p.blocks.iter().all(|b| b.tolerance.is_unset()), "{:#?}", p.blocks);
}

/// LinuxCNC's parameters and expressions (`#<feed>=1500`, `F#<feed>`, `X[2.0 / 3 * 1.5 - 5.5 / 11.0]`,
/// `YSIN[30]`, `X##32`, a setting that takes effect after its line) are read to the motion LinuxCNC's
/// own interpreter makes of them: every operator and function of the manual's §11.4.5-11.4.8 in a
/// fixture, and the demos `xyzac_switchkins_test_1/2.ngc` that set their feed as `#<FRATE>`. So are
/// its work offsets (`offsets.ngc`: G10 L2 and L20, P0 for the active system, G53, G55), and its
/// O-word control flow (`owords.ngc`: a subroutine called twice with arguments, its own `#<n>` and a
/// global `#<_scale>`, `return`, `while` with `continue` and `break`, `do`/`while`, `repeat`, `if`/
/// `elseif`/`else`; `owords_spaces.ngc`: the keywords with blanks in them, `end sub`, `end while`,
/// `else if`, `end if`, `re peat`, `end repeat`, which LinuxCNC reads with its blanks taken out), as
/// are the blanks within words (`blanks.ngc`: `X1 0` is X10, `G4 0` G40, `X - 3` X-3, `G9 1` G91).
#[test]
fn rs274_evaluates_parameters_and_expressions_as_linuxcnc_does() {
    let dir = Path::new(env!("FIVEAXIS_ROOT")).join("recordings/programs/linuxcnc/parameters");
    let switchkins = ReadOptions { m_codes: vec!["428=tcp-on".parse().unwrap(), "429=tcp-off".parse().unwrap()], ..Default::default() };
    for name in ["blanks", "expressions", "offsets", "owords", "owords_spaces", "xyzac_switchkins_test_1", "xyzac_switchkins_test_2"] {
        let text = std::fs::read_to_string(dir.join(format!("{name}.ngc"))).unwrap();
        let p = read(&text, Dialect::Rs274, "t.ngc", &switchkins);
        assert!(errors(&p).is_empty(), "{name}: {:?}", errors(&p));
        let ours = end_points(&p);
        let theirs = linuxcnc_canon(&format!("{name}.canon"));
        assert_eq!(ours.len(), theirs.len(), "{name}: moves");
        for (k, ((m, a), (n, b))) in ours.iter().zip(&theirs).enumerate() {
            assert_eq!(m, n, "{name}: move {k}");
            for i in 0..6 {
                // rs274 prints 4 decimals.
                assert!((a[i] - b[i]).abs() <= 0.5e-4 + 1e-9, "{name}: move {k} axis {i}: ours {a:?}, LinuxCNC {b:?}");
            }
        }
        if name.starts_with("xyzac") {
            let feeds: Vec<f64> = p.blocks.iter().filter_map(|b| b.feed).map(|f| f.value_per_min).collect();
            assert!(!feeds.is_empty() && feeds.iter().all(|&f| f == 1000.0), "{name}: F#<FRATE> is 1000 mm/min: {feeds:?}");
        }
    }
}

/// Canned cycles (G81, G82, G83, G73, G85 three times under G91, G86, G89; G98, G99) make the moves
/// LinuxCNC's own interpreter makes of them (`cycles.ngc`/`.canon`): read as LinuxCNC's (on a machine
/// that sets no peck distance: LinuxCNC 2.9's 0.254 mm), and in the Haas dialect (L repeats, P
/// seconds with a decimal point) on a machine whose peck distances are LinuxCNC's; each dwell where
/// LinuxCNC dwells.
#[test]
fn canned_cycles_move_as_linuxcnc_runs_them() {
    let dir = Path::new(env!("FIVEAXIS_ROOT")).join("recordings/programs/linuxcnc/parameters");
    let text = std::fs::read_to_string(dir.join("cycles.ngc")).unwrap();
    let file = fiveaxis::machine::builtin_file("haas-umc-750").unwrap().replace("g73_retract_mm = 2.54", "g73_retract_mm = 0.254").replace("g83_clearance_mm = 0.76", "g83_clearance_mm = 0.254");
    let haas = fiveaxis::machine::Machine::from_toml_str(&file, "t").unwrap();
    let linuxcnc = fiveaxis::machine::Machine::builtin("linuxcnc-xyzac-trt").unwrap();
    // A generic machine's file gives Fanuc's peck parameters (0.1 mm): not LinuxCNC's settings.
    let generic = fiveaxis::machine::Machine::builtin("generic-ac-table").unwrap();
    assert_eq!(generic.peck_distances, [Some(0.1e-3), Some(0.1e-3)]);
    for (dialect, machine) in [(Dialect::Rs274, &linuxcnc), (Dialect::Rs274, &generic), (Dialect::Haas, &haas)] {
        let p = read(&text, dialect, "cycles.nc", &ReadOptions::default().on(machine));
        assert!(errors(&p).is_empty(), "{dialect:?}: {:?}", errors(&p));
        let ours = end_points(&p);
        let theirs = linuxcnc_canon("cycles.canon");
        assert_eq!(ours.len(), theirs.len(), "{dialect:?}: moves: ours {ours:#?}");
        for (k, ((m, a), (n, b))) in ours.iter().zip(&theirs).enumerate() {
            assert_eq!(m, n, "{dialect:?}: move {k}");
            assert!((0..6).all(|i| (a[i] - b[i]).abs() <= 0.5e-4 + 1e-9), "{dialect:?}: move {k}: ours {a:?}, LinuxCNC {b:?}");
        }
        let dwells: Vec<f64> = p.blocks.iter().filter_map(|b| b.dwell_s).collect();
        assert_eq!(dwells, [0.5, 0.2, 0.25], "{dialect:?}");
    }
}

/// LinuxCNC 2.10's peck clearances (`[RS274NGC]G73_PECK_CLEARANCE`, `G83_PECK_CLEARANCE`), set in
/// the machine file, replace 2.9's 0.254 mm; the moves worked by hand from `convert_cycle_g73` and
/// `convert_cycle_g83` (interp_cycles.cc): G73 feeds a peck and backs off by its clearance, G83
/// feeds a peck, rapids to R and back down to its clearance above the depth reached.
#[test]
fn linuxcnc_peck_clearances_come_from_the_machine_files_linuxcnc_settings() {
    let file = fiveaxis::machine::builtin_file("linuxcnc-xyzac-trt").unwrap().to_owned() + "\n[canned_cycles]\ng73_peck_clearance_mm = 1.0\ng83_peck_clearance_mm = 0.5\n";
    let machine = fiveaxis::machine::Machine::from_toml_str(&file, "t").unwrap();
    let text = "G21 G90 G94 G17 F300 S1000 M3\nG0 X0 Y0 Z20\nG98 G83 X1 Z-12 R1 Q5\nG80\nG98 G73 X2 Z-9 R1 Q4\nG80\nM2\n";
    let p = read(text, Dialect::Rs274, "t.ngc", &ReadOptions::default().on(&machine));
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    let mut moves: Vec<(Motion, f64, f64)> = Vec::new();
    for (m, at) in end_points(&p) {
        if moves.last().is_none_or(|&(_, x, z)| (x, z) != (at[0], at[2])) {
            moves.push((m, at[0], at[2]));
        }
    }
    use Motion::{Linear as F, Rapid as R};
    #[rustfmt::skip]
    let want = [
        (R, 0.0, 20.0), (R, 1.0, 20.0), (R, 1.0, 1.0),
        (F, 1.0, -4.0), (R, 1.0, 1.0), (R, 1.0, -3.5), // G83: 0.5 above the depth reached
        (F, 1.0, -9.0), (R, 1.0, 1.0), (R, 1.0, -8.5),
        (F, 1.0, -12.0), (R, 1.0, 20.0),
        (R, 2.0, 20.0), (R, 2.0, 1.0),
        (F, 2.0, -3.0), (R, 2.0, -2.0), // G73: back off 1 mm
        (F, 2.0, -7.0), (R, 2.0, -6.0),
        (F, 2.0, -9.0), (R, 2.0, 20.0),
    ];
    assert_eq!(moves.len(), want.len(), "{moves:?}");
    for (k, (a, b)) in moves.iter().zip(&want).enumerate() {
        assert!(a.0 == b.0 && (a.1 - b.1).abs() < 1e-9 && (a.2 - b.2).abs() < 1e-9, "move {k}: ours {a:?}, want {b:?}");
    }
    // Out of range, named by its key.
    let bad = fiveaxis::machine::builtin_file("linuxcnc-xyzac-trt").unwrap().to_owned() + "\n[canned_cycles]\ng83_peck_clearance_mm = -1\n";
    let e = fiveaxis::machine::Machine::from_toml_str(&bad, "t").unwrap_err().to_string();
    assert!(e.contains("canned_cycles.g83_peck_clearance_mm"), "{e}");
}

/// Where LinuxCNC's cycles differ from Fanuc's, the moves its interpreter makes (interp_cycles.cc of
/// LinuxCNC 2.9: `convert_cycle_xy`, `CYCLE_MACRO`, `convert_cycle_g89`, `g74_g84`), worked by hand
/// from the source: a tool below R goes straight up to R first and G98 then returns to R; G98 after a
/// G99 hole goes to the return level with the move to the next hole, then down to R; G89 and G84 feed
/// out to the return level itself (Fanuc: to R, then rapid); a block with only Z drills again where
/// the tool stands; P stays from the last cycle (G84 takes G89's 0.5 s).
#[test]
fn linuxcnc_cycles_differ_from_fanucs_as_its_interpreter_says() {
    let text = "G21 G90 G94 G17 F300 S1000 M3\nG0 X0 Y0 Z-1\nG98 G81 X10 Z-5 R2\nG80\nG0 Z20\n\
                G99 G81 X20 Z-5 R2\nG98 X30\nG80\nG0 Z20\nG98 G89 X40 Z-3 R1 P0.5\nZ-4\nG84 X50 Z-2 R1\nG80\nM2\n";
    let p = read(text, Dialect::Rs274, "t.ngc", &ReadOptions::default());
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    let mut moves: Vec<(Motion, f64, f64)> = Vec::new();
    for (m, at) in end_points(&p) {
        if moves.last().is_none_or(|&(_, x, z)| (x, z) != (at[0], at[2])) {
            moves.push((m, at[0], at[2]));
        }
    }
    use Motion::{Linear as F, Rapid as R};
    let want = [
        (R, 0.0, -1.0),
        (R, 0.0, 2.0), // below R: up to it first
        (R, 10.0, 2.0),
        (F, 10.0, -5.0),
        (R, 10.0, 2.0), // G98 returns to R, the tool having started below it
        (R, 10.0, 20.0),
        (R, 20.0, 20.0),
        (R, 20.0, 2.0),
        (F, 20.0, -5.0),
        (R, 20.0, 2.0), // G99
        (R, 30.0, 20.0), // G98 after G99: to the return level with the move
        (R, 30.0, 2.0),
        (F, 30.0, -5.0),
        (R, 30.0, 20.0),
        (R, 40.0, 20.0),
        (R, 40.0, 1.0),
        (F, 40.0, -3.0),
        (F, 40.0, 20.0), // G89 feeds out to the return level
        (R, 40.0, 1.0), // Z-4 alone: the cycle again where the tool stands
        (F, 40.0, -4.0),
        (F, 40.0, 20.0),
        (R, 50.0, 20.0),
        (R, 50.0, 1.0),
        (F, 50.0, -2.0),
        (F, 50.0, 20.0), // G84 feeds out to the return level
    ];
    assert_eq!(moves.len(), want.len(), "{moves:?}");
    for (k, (a, b)) in moves.iter().zip(&want).enumerate() {
        assert!(a.0 == b.0 && (a.1 - b.1).abs() < 1e-9 && (a.2 - b.2).abs() < 1e-9, "move {k}: ours {a:?}, LinuxCNC {b:?}");
    }
    let dwells: Vec<f64> = p.blocks.iter().filter_map(|b| b.dwell_s).collect();
    assert_eq!(dwells, [0.5, 0.5, 0.5]);
    // What LinuxCNC refuses, where it stands.
    let body = |block: &str| format!("G21 G90 G94 G17 F300 S1000 M3\nG0 X0 Y0 Z20\n{block}\nG80\nM2\n");
    for (block, col, what) in [
        ("G81 X1 Z-5", 1, "needs its R plane"),
        ("G82 X1 Z-5 R2", 1, "needs its dwell (P, seconds)"),
        ("G83 X1 Z-5 R2", 1, "needs its peck depth (Q)"),
        ("G81 X1 Z-5 R2 A10", 15, "rotary axis words are not allowed"),
        ("G81 X1 Z5 R2", 1, "R 2 is below Z 5"),
        ("G81 X1 Z-5 R2 L0", 15, "Cannot do zero repeats"),
        ("G83 X1 Z-5 R2 Q-1", 15, "a peck depth must be positive"),
        ("G83 X1 Z-5 R2 Q0.0001", 15, "more than 10000 pecks"),
        ("G87 X1 Z-5 R2", 1, "behaviour is undefined"),
        ("G93 G81 X1 Z-5 R2", 5, "inverse time"),
        ("G81 G0 X1 Z-5 R2", 5, "two G codes of modal group 1"),
        ("G81 X1 Z-5 R2 P1", 15, "G81 takes no P"),
        ("G82 X1 Z-5 R2 P1 Q1", 18, "G82 takes no Q"),
        ("G81 R2", 1, "without X, Y or Z"),
    ] {
        let p = read(&body(block), Dialect::Rs274, "t.ngc", &ReadOptions::default());
        let e = errors(&p);
        assert!(e.iter().any(|(l, c, m)| *l == 3 && *c == col && m.contains(what)), "{block}: {e:?}");
    }
}

/// LinuxCNC's cycles where its interpreter's state says more than the cycle block (LinuxCNC 2.9
/// source, worked by hand): it starts in G99 (interp_setup.cc `retract_mode(R_PLANE)`), so a program
/// that never says G98/G99 returns to R; a work offset selected in the cycle block is in effect
/// before the cycle starts (G55 with Z -10: the tool at Z20 stands at Z30 in it, where G98 returns);
/// G80 belongs to the motion group, so axis words after it need a G0/G1 again; a G10 under an
/// active cycle sets its offset and drills no hole.
#[test]
fn linuxcnc_cycles_follow_the_interpreters_state() {
    let moves = |text: &str| -> Vec<(Motion, f64, f64, f64)> {
        let p = read(text, Dialect::Rs274, "t.ngc", &ReadOptions::default());
        assert!(errors(&p).is_empty(), "{text}: {:?}", errors(&p));
        let mut out: Vec<(Motion, f64, f64, f64)> = Vec::new();
        for (m, at) in end_points(&p) {
            if out.last().is_none_or(|&(_, x, y, z)| (x, y, z) != (at[0], at[1], at[2])) {
                out.push((m, at[0], at[1], at[2]));
            }
        }
        out
    };
    use Motion::{Linear as F, Rapid as R};
    let g99 = moves("G21 G90 G17 G94 F100\nG0 X0 Y0 Z20\nG81 X5 Y5 Z-1 R2\nX10\nG80\nM2\n");
    assert_eq!(g99, [(R, 0.0, 0.0, 20.0), (R, 5.0, 5.0, 20.0), (R, 5.0, 5.0, 2.0), (F, 5.0, 5.0, -1.0), (R, 5.0, 5.0, 2.0), (R, 10.0, 5.0, 2.0), (F, 10.0, 5.0, -1.0), (R, 10.0, 5.0, 2.0)]);
    let g55 = moves("G21 G90 G17 G94 F100\nG10 L2 P2 Z-10\nG0 X0 Y0 Z20\nG98 G55 G81 X5 Y5 Z-1 R2\nG80\nM2\n");
    assert_eq!(g55.last().copied(), Some((R, 5.0, 5.0, 30.0)), "{g55:?}");
    let drilled = moves("G21 G90 G17 G94 F100\nG0 X0 Y0 Z20\nG81 X5 Y5 Z-1 R2\nG10 L2 P1 X0 Y0\nG80\nM2\n");
    assert_eq!(drilled.iter().filter(|m| m.0 == F).count(), 1, "{drilled:?}");
    for (text, line) in [("G21 G90 G17 G94 F100\nG1 X0 Y0 Z10\nG81 X5 Y5 Z-1 R2\nG80 X20\nM2\n", 4), ("G21 G90 G17 G94 F100\nG1 X0 Y0 Z10\nG81 X5 Y5 Z-1 R2\nG80\nX20\nM2\n", 5)] {
        let p = read(text, Dialect::Rs274, "t.ngc", &ReadOptions::default());
        assert!(errors(&p).iter().any(|(l, _, m)| *l == line && m.contains("without a motion mode")), "{text}: {:?}", errors(&p));
    }
}

/// A centre-format arc whose end lies off its start's circle, as LinuxCNC 2.9 checks it (interp_arc.cc
/// `arc_data_ijk`): refused where the radii differ by more than 2 x 0.01 x sqrt 2 = 0.0283 mm (G21;
/// 0.00283 in under G20) and by more than 0.1 % of the radius, or by more than 100 times that; else run
/// as a spiral. The cases, by hand: a 10 mm arc ending 0.02 mm out runs (0.00127 mm, the R-format
/// tolerance, had refused it: 82 arcs of two shop programs), 0.03 mm out is refused; a 50 mm arc
/// 0.04 mm out runs (0.08 %); 1 in ending 0.002 in out runs under G20, the same 0.0508 mm under G21
/// does not.
#[test]
fn linuxcnc_checks_an_arcs_end_as_its_interpreter_does() {
    let cases = [("G21", "10", "20.02", true), ("G21", "10", "20.03", false), ("G21", "50", "100.04", true), ("G20", "1", "2.002", true), ("G21", "25.4", "50.8508", false)];
    for (units, r0, r1, ok) in cases {
        let text = format!("{units} G90 G94 G17 F100\nG0 X0 Y0 Z0\nG2 X{r1} Y0 I{r0} J0\nM2\n");
        let p = read(&text, Dialect::Rs274, "t.ngc", &ReadOptions::default());
        let e = errors(&p);
        if ok {
            assert!(e.is_empty(), "{units} r0 {r0} end X{r1}: {e:?}");
            let arc = p.blocks.iter().find(|b| b.line == 3).expect("the arc");
            assert_eq!(arc.motion, Motion::ArcCw);
        } else {
            assert!(e.iter().any(|(l, c, m)| *l == 3 && *c == 1 && m.contains("differs from the radius to the start")), "{units} r0 {r0} end X{r1}: {e:?}");
        }
    }
}

/// A full circle as LinuxCNC programs it: "No axis words and one or more offsets must be programmed
/// for full circles. The 'P' word defaults to 1" (G-code reference §G2/G3; both offsets under G90.1):
/// `G2 I10` from X0 Y0 is the circle of radius 10 about X10 Y0, 62.83 mm, and with P2 twice round
/// (by hand: 2 pi r per turn). One offset under G90.1 gives no circle: refused, as before.
#[test]
fn linuxcnc_reads_a_full_circle_without_axis_words() {
    use fiveaxis::path::{PathOptions, Trajectory};
    let m = fiveaxis::machine::Machine::builtin("linuxcnc-xyzac-trt").unwrap();
    for (text, turns) in [("G2 I10", 1.0), ("G3 I10 J0 P2", 2.0), ("G90.1 G2 I10 J0", 1.0)] {
        let src = format!("G21 G90 G94 G17 F100\nG0 X0 Y0 Z0\n{text}\nM2\n");
        let p = read(&src, Dialect::Rs274, "t.ngc", &ReadOptions::default().on(&m));
        assert!(errors(&p).is_empty(), "{text}: {:?}", errors(&p));
        let t = Trajectory::from_program(&p, &m, &PathOptions::default());
        let length: f64 = t.segments.iter().filter(|s| s.line == 3).map(|s| s.length).sum();
        let want = turns * std::f64::consts::TAU * 10.0 * MM;
        assert!((length - want).abs() < 1e-6 * want, "{text}: {} mm, by hand {} mm", length / MM, want / MM);
    }
    let p = read("G21 G90 G94 G17 F100\nG0 X0 Y0 Z0\nG90.1 G2 I10\nM2\n", Dialect::Rs274, "t.ngc", &ReadOptions::default());
    assert!(errors(&p).iter().any(|(l, _, m)| *l == 3 && m.contains("without an end point")), "{:?}", errors(&p));
}

/// What the reader cannot know is refused where it stands, and a damaged line sets nothing: a named
/// parameter read before it is set (LinuxCNC's error too), a numbered one (LinuxCNC reads 0, Fanuc
/// vacant), the machine's state this reader does not hold (`#5221`, `#<_spindle_on>`), a division by
/// zero, an unclosed bracket.
#[test]
fn rs274_refuses_parameters_it_cannot_know() {
    let body = |line: &str| format!("G21 G90 G94 F1000\n#<a> = 2\n{line}\nG1 X#<a>\nM2\n");
    for (line, col, what) in [
        ("G1 X#<b>", 5, "named parameter #<b> is not defined"),
        ("G1 X#7", 5, "#7 is read before the program sets it"),
        ("G1 X#5221", 5, "#5221 is a system parameter"),
        ("G1 X#<_Spindle_On>", 5, "#<_spindle_on> is the interpreter's or the machine's state"),
        ("G1 X#<_hal[kins.x-offset]>", 5, "the machine file gives no HAL pin 'kins.x-offset'"),
        ("G1 X[1/[#<a>-2]]", 7, "division by zero"),
        ("G1 X[#<a> + 1", 5, "'[' is not closed"),
        ("G1 XFOO[1]", 5, "unknown function FOO"),
        ("#5221 = 3", 1, "setting it is not modelled"),
        ("#<_x> = 3", 1, "read-only"),
        ("#<a> = [#<a> * 5] G1 X#<nope>", 23, "#<nope> is not defined"),
        ("#<a>", 1, "expected '='"),
    ] {
        let p = read_rs274(&body(line));
        has(&p, 3, col, what);
        assert_eq!(errors(&p).len(), 1, "{line}: {:?}", errors(&p));
        // The damaged line set nothing: #<a> is still 2 on the next line.
        let b = p.blocks.iter().find(|b| b.line == 4).expect("line 4 is read");
        assert_eq!(b.targets.x, Some(2.0 * MM), "{line}");
    }
    // A plain number still reads as before, and a word without a value is refused as before.
    has(&read_rs274("G1 X Y5 F100\n"), 1, 4, "expected a number after 'X'");
    // LinuxCNC's control flow runs (the loop three times, an upper-case O); a call of a subroutine in
    // another file is refused at the O word.
    let p = read_rs274("#<n> = 0\no100 while [#<n> lt 3]\n  G1 X#<n> F100\n  #<n> = [#<n> + 1]\n  O100 endwhile\no<probe> call [1]\nM2\n");
    has(&p, 6, 1, "o<probe> call: no subroutine");
    assert_eq!(errors(&p).len(), 1, "{:?}", errors(&p));
    assert_eq!(p.blocks.iter().filter_map(|b| b.targets.x).map(|x| x / MM).collect::<Vec<_>>(), [0.0, 1.0, 2.0]);
    // A line's first defect from the left is the one said, as LinuxCNC's reader evaluates each
    // value as it reads it: the unset #7 before the unfinished expression after it, and in a loop's
    // test before the text after its brackets.
    let p = read_rs274("G1 X#7 Y[2 +] F100\n");
    has(&p, 1, 5, "#7 is read before");
    assert_eq!(errors(&p).len(), 1, "{:?}", errors(&p));
    let p = read_rs274("o100 while [#7 LT 3] junk\nG1 X1 F100\no100 endwhile\n");
    has(&p, 1, 13, "#7 is read before");
    assert_eq!(errors(&p).len(), 1, "{:?}", errors(&p));
    // A loop's line is read once and evaluated on each pass: the pass whose value fails (a
    // division by zero at #<n> = 3) is a defect at its line and column, the others move.
    let p = read_rs274("#<n> = 0\no1 while [#<n> lt 5]\nG1 X[10 / [3 - #<n>]] Y#<n> F100\n#<n> = [#<n> + 1]\no1 endwhile\nM2\n");
    has(&p, 3, 9, "division by zero");
    assert_eq!(errors(&p).len(), 1, "{:?}", errors(&p));
    let xs: Vec<f64> = p.blocks.iter().filter_map(|b| b.targets.x).map(|x| x / MM).collect();
    let want = [0.0, 1.0, 2.0, 4.0].map(|n: f64| 10.0 / (3.0 - n));
    assert!(xs.len() == 4 && xs.iter().zip(want).all(|(x, w)| (x - w).abs() < 1e-9), "{xs:?}");
    // Fanuc custom macro B's control flow, likewise by name.
    let p = read_rs274("#1 = 0\nWHILE [#1 LT 3] DO1\nG1 X#1 F100\n#1 = [#1 + 1]\nEND1\nIF [#1 EQ 3] GOTO 10\nN10 M30\n");
    has(&p, 2, 1, "Fanuc macro 'WHILE'");
    has(&p, 5, 1, "Fanuc macro 'END'");
    has(&p, 6, 1, "Fanuc macro 'IF'");
    assert_eq!(errors(&p).len(), 3, "{:?}", errors(&p));
}

/// LinuxCNC's O-word blocks fail closed: a block that never ends, an end of another name, a
/// `break` outside its loop, a call of a subroutine defined nowhere, a condition that cannot
/// be read and an endless loop are each refused at their line, and nothing after them is read.
#[test]
fn rs274_o_word_defects_are_refused_where_they_stand() {
    let opts = ReadOptions::default();
    for (text, line, needle) in [
        ("G1 X1 F100\no1 while [1 LT 2]\nG1 X2\n", 2, "the program ends inside o1 while"),
        ("G1 X1 F100\no1 if [1]\nG1 X2\no2 endif\n", 4, "o2 endif ends no block: o1 if is open"),
        ("G1 X1 F100\no1 if [1]\no5 break\no1 endif\n", 3, "not inside a while or do loop of that name"),
        ("G1 X1 F100\no1 repeat [2]\no1 break\no1 endrepeat\n", 3, "not inside a while or do loop of that name"),
        ("G1 X1 F100\no<tool_change> call [3]\n", 2, "no subroutine o<tool_change> is defined in this file"),
        ("G1 X1 F100\no1 while [#<undefined> LT 2]\nG1 X2\no1 endwhile\n", 2, "o1 while"),
        ("G1 X1 F100\n#<i> = 0\no1 while [#<i> LT 1]\nG1 X2\no1 endwhile\nG1 X3\n", 4, "an endless loop"),
        ("G1 X1 F100\no1 endwhile\n", 2, "no block of that name is open"),
        ("G1 X1 F100\no1 repeat [2.5]\nG1 X2\no1 endrepeat\n", 2, "a whole count"),
    ] {
        let p = read(text, Dialect::Rs274, "t.ngc", &opts);
        assert!(errors(&p).iter().any(|(l, _, m)| *l == line && m.contains(needle)), "{text:?}: {:#?}", errors(&p));
    }
    // After an endless loop nothing more is read: X3 never comes.
    let p = read("G1 X1 F100\n#<i> = 0\no1 while [#<i> LT 1]\nG1 X2\no1 endwhile\nG1 X3\n", Dialect::Rs274, "t.ngc", &opts);
    assert!(p.blocks.iter().all(|b| b.targets.x != Some(3.0 * MM)));
    // Fanuc's program number is not an O-word block.
    let p = read("%\nO1001 (PART)\nG1 X1 F100\n%\n", Dialect::Fanuc, "t.nc", &opts);
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
}

/// LinuxCNC's bridgemill demo (`../shared/outside/programs`): a hemisphere of holes drilled in nested
/// O-word loops (`while`, `if`/`else`), named parameters, `cos`, `sin`, `mod`, `G10 L20`, `G53`, read
/// to the same moves as LinuxCNC's own interpreter (`bridgemill_without_w.canon`, made by
/// make_canon.sh), X Y Z B C to its 4 decimals. Standalone rs274 has no W axis, so the W (quill)
/// words are taken out of both copies.
#[test]
fn rs274_runs_linuxcncs_bridgemill_loops_as_linuxcnc_does() {
    let text = std::fs::read_to_string(Path::new(env!("FIVEAXIS_ROOT")).join("../shared/outside/programs/linuxcnc-rs274ngc_bridgemill-5axisgui-oword.ngc")).unwrap();
    // The W words: `w` or `W`, blanks, then a number or a bracketed expression (make_canon.sh's sed).
    let mut without_w = String::new();
    let chars: Vec<char> = text.chars().collect();
    let mut i = 0;
    while i < chars.len() {
        let mut k = i + 1;
        while k < chars.len() && chars[k] == ' ' {
            k += 1;
        }
        if matches!(chars[i], 'w' | 'W') && k < chars.len() && (chars[k] == '[' || chars[k].is_ascii_digit() || "+-.".contains(chars[k])) {
            i = if chars[k] == '[' { k + chars[k..].iter().position(|&c| c == ']').unwrap() + 1 } else { k + 1 + chars[k + 1..].iter().take_while(|c| c.is_ascii_digit() || **c == '.').count() };
            continue;
        }
        without_w.push(chars[i]);
        i += 1;
    }
    let p = read(&without_w, Dialect::Rs274, "bridgemill.ngc", &ReadOptions::default());
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    // rs274 also prints the null moves of a bare `g1` or `g0` (a W move's block without its W): only
    // the moves that go somewhere are compared, on both sides.
    let moving = |v: Vec<(Motion, [f64; 6])>| -> Vec<(Motion, [f64; 6])> {
        let mut out: Vec<(Motion, [f64; 6])> = Vec::new();
        for m in v {
            if out.last().is_none_or(|l| (0..6).any(|i| (l.1[i] - m.1[i]).abs() > 0.5e-4 + 1e-9)) {
                out.push(m);
            }
        }
        out
    };
    let ours = moving(end_points(&p));
    let theirs = moving(linuxcnc_canon("bridgemill_without_w.canon"));
    assert_eq!(ours.len(), theirs.len(), "moves");
    assert!(theirs.len() > 150, "{} moves", theirs.len());
    for (k, ((m, a), (n, b))) in ours.iter().zip(&theirs).enumerate() {
        assert_eq!(m, n, "move {k}");
        for i in 0..6 {
            assert!((a[i] - b[i]).abs() <= 0.5e-4 + 1e-9, "move {k} axis {i}: ours {a:?}, LinuxCNC {b:?}");
        }
    }
}

/// The bridgemill demo's drilling is its W quill: 5axiskins puts the world point at
/// `J + (0, 0, L) + s2r(L + W, C, 180 - B)` with `s2r(r, t, p) = r (sin p cos t, sin p sin t, cos p)`
/// (LinuxCNC src/emc/kinematics/5axiskins.c), the tool drawn L from the pivot, so `g1 w-10` takes the
/// tip to `P - s2r(W, C, 180 - B)`: computed here from the C source's formula at each hole's B and C,
/// and the reader's blocks put the tip there (1e-9 mm), then back on `g0 w0`. The program reads clean
/// on the machine (W its quill, 5axiskins from start).
#[test]
fn rs274_bridgemill_drills_with_its_w_quill_as_5axiskins_moves_the_tip() {
    use fiveaxis::machine::Machine;
    let text = std::fs::read_to_string(Path::new(env!("FIVEAXIS_ROOT")).join("../shared/outside/programs/linuxcnc-rs274ngc_bridgemill-5axisgui-oword.ngc")).unwrap();
    let machine = Machine::builtin("linuxcnc-bridgemill").unwrap();
    let p = read(&text, Dialect::Rs274, "bridgemill.ngc", &ReadOptions::default().on(&machine));
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    let (mut at, mut b, mut c) = ([0.0f64; 3], 0.0f64, 0.0f64);
    let (mut drilled, mut back, mut hole) = (0, 0, [0.0f64; 3]);
    for blk in &p.blocks {
        let t = &blk.targets;
        let to = [t.x.unwrap_or(at[0] * MM) / MM, t.y.unwrap_or(at[1] * MM) / MM, t.z.unwrap_or(at[2] * MM) / MM];
        match blk.line {
            // `g1 w[-10]`: the tip off the hole by -s2r(W, C, 180 - B), W = -10.
            43 => {
                let (w, pr, th) = (-10.0, (180.0 - b).to_radians(), c.to_radians());
                let s2r = [w * pr.sin() * th.cos(), w * pr.sin() * th.sin(), w * pr.cos()];
                for i in 0..3 {
                    assert!((to[i] - (at[i] - s2r[i])).abs() < 1e-9, "line 43 at B {b} C {c}: tip {to:?}, 5axiskins {:?}", [at[0] - s2r[0], at[1] - s2r[1], at[2] - s2r[2]]);
                }
                assert_eq!(blk.motion, Motion::Linear);
                hole = at;
                drilled += 1;
            }
            44 => {
                assert!((0..3).all(|i| (to[i] - hole[i]).abs() < 1e-9) && blk.motion == Motion::Rapid, "line 44: {to:?}, the hole {hole:?}");
                back += 1;
            }
            _ => {}
        }
        if let Some(v) = t.b {
            b = v / DEG;
        }
        if let Some(v) = t.c {
            c = v / DEG;
        }
        at = to;
    }
    assert_eq!((drilled, back), (128, 128), "8 rings of 16 holes");
}

/// Nothing runs after the program's end (RS274/NGC Interpreter v3, NIST IR 6556 §3.3.1: "Lines of a
/// file that occur after the end of a program are not to be executed"; "The useful contents of a
/// file demarcated by percents stop after the second percent line"): not after `M2`, not after `M30`
/// inside a loop (which would otherwise run until its bound), not after the closing `%`. The first
/// line with words after the end is said not to run; the closing `%` and comments are not.
#[test]
fn nothing_runs_after_the_programs_end() {
    let xs = |p: &Program| p.blocks.iter().filter_map(|b| b.targets.x).map(|x| (x / MM).round()).collect::<Vec<_>>();
    for (text, want, said) in [
        ("G21 G90 G94\nG1 X10 F60\nM2\nG1 X100\n", vec![10.0], Some(4)),
        ("G21 G90 G94\nG1 X10 F60\nM30\n%\n(end)\n", vec![10.0], None),
        ("%\nG21 G90 G94\nG1 X10 F60\n%\nG1 X100\n", vec![10.0], Some(5)),
        ("G21 G90 G94\nG1 X10 F60\no100 while [1]\nG1 X20\nM30\nG1 X50\no100 endwhile\nG1 X100\n", vec![10.0, 20.0], Some(8)),
    ] {
        let p = read_rs274(text);
        assert!(errors(&p).is_empty(), "{text:?}: {:?}", errors(&p));
        assert_eq!(xs(&p), want, "{text:?}");
        let warned: Vec<usize> = p.diagnostics.iter().filter(|d| d.message.contains("are not run: the program ended")).map(|d| d.line).collect();
        assert_eq!(warned, said.into_iter().collect::<Vec<_>>(), "{text:?}: {:?}", p.diagnostics);
    }
    // The TNC's DIN/ISO program: M30 stops the run and goes back to block 1; the `N99999 %` end line
    // still closes the program (its name checked against the header's).
    let p = read_heidenhain("%T G71 *\nN10 G90 G01 X+10 Y+0 Z+0 F60 *\nN20 M30 *\nN30 G01 X+100 *\nN99999 %T G71 *\n");
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    assert_eq!(xs(&p), vec![10.0]);
    assert!(p.diagnostics.iter().any(|d| d.line == 4 && d.message.contains("not run")), "{:?}", p.diagnostics);
}

/// A move cutter compensation cannot make is where LinuxCNC stops (rs274 on this program: "Straight
/// feed in concave corner cannot be reached by the tool without gouging" at line 7, and nothing
/// after): one error there, and the lines after it not read, so neither the G40 and M2 that would
/// meet the held move again nor the file's end say anything more.
#[test]
fn a_move_compensation_cannot_make_ends_the_reading_as_linuxcnc_stops() {
    let text = "G21 G90 G17 F500\nG0 X-10 Y-10\nG41.1 D10\nG1 X0 Y0\nG1 X20\nG1 X20.5 Y2\nG1 X40 Y2\nG40 G1 X50 Y-10\nM2\n";
    let p = read(text, Dialect::Rs274, "t.ngc", &ReadOptions::default());
    assert_eq!(p.diagnostics.len(), 1, "{:?}", p.diagnostics);
    has(&p, 7, 1, "cannot be reached by the tool without gouging (LinuxCNC stops here: the rest of the program is not read)");
    // The moves before it were made, as rs274 makes them (the traverse, the entry, the arc round the
    // convex corner, line 5's move cut back at the concave one with line 6: X16.0961 Y5), and the
    // held move of line 6 was not.
    let ends: Vec<[f64; 2]> = end_points(&p).iter().map(|(_, a)| [a[0], a[1]]).collect();
    let rs274 = [[-10.0, -10.0], [-3.5355, 3.5355], [0.0, 5.0], [16.0961, 5.0]];
    assert_eq!(ends.len(), 4, "{ends:?}");
    assert!(ends.iter().zip(rs274).all(|(a, b)| (a[0] - b[0]).abs() < 1e-4 && (a[1] - b[1]).abs() < 1e-4), "{ends:?}");
}

/// LinuxCNC's cutter radius compensation is read to the moves its own interpreter makes
/// (`comp_lines.ngc`, `comp_arcs.ngc`, `comp_table.ngc`, `comp_g10.ngc` whose radii the program sets by
/// `G10 L1 P R`; rs274's canonical output by make_canon.sh):
/// entry moves ending perpendicular to themselves (an entry arc on its end's radius), arcs about
/// convex corners (a rapid straight), moves cut back where the offset paths meet in concave corners
/// (line-line, line-arc, arc-line, arc-arc), a move with no XY motion, a negative diameter on the
/// other side, the exit move, and after `G40` a move without X or Y back over the programmed point
/// (after a tool change, from where the tool stands); `G41.1 D` the diameter, `G41 D` and `G42` (the
/// tool in the spindle, `T2 M6`) the tool table's. Then LinuxCNC's own refusals. (LinuxCNC's own
/// compensation programs, nc_files/comp-g1, comp311, comp311_2, gmoccapy_2_tools…, useful-subroutines
/// and tests/interp cam-nisley and crazy-paths, 1,087 moves, read to the same moves as rs274 makes of
/// them; they are not copied here. Its inverse-time-with-comp is refused: G93 under compensation.)
#[test]
fn rs274_compensates_the_cutter_radius_as_linuxcnc_does() {
    let dir = Path::new(env!("FIVEAXIS_ROOT")).join("recordings/programs/linuxcnc/parameters");
    let table = fiveaxis::program::ToolTable::parse(&std::fs::read_to_string(dir.join("comp.tbl")).unwrap()).unwrap().in_unit(fiveaxis::program::LengthUnit::Inch);
    let options = ReadOptions { tool_table: Some(std::sync::Arc::new(table)), ..ReadOptions::default() };
    for name in ["comp_lines", "comp_arcs", "comp_table", "comp_g10"] {
        let text = std::fs::read_to_string(dir.join(format!("{name}.ngc"))).unwrap();
        same_moves_as_linuxcnc(name, &read(&text, Dialect::Rs274, "t.ngc", &options));
    }
    // G10 L1 needs something to set (LinuxCNC's error), and sets the radius of a tool of the table.
    has(&read("G21 G90\nG10 L1 P1\nM2\n", Dialect::Rs274, "t.ngc", &options), 2, 1, "G10 L1 without offsets has no effect");
    // A file that ends while a compensated move is held: LinuxCNC never sends it (rs274 makes 4 moves
    // of this, the last X20 Y20 not among them), and that is said.
    let p = read("G21 G17 G90 F100\nG0 X-10 Y-10\nG42.1 D6.35\nG1 X0 Y0\nG1 X20 Y0\nG1 X20 Y20\n", Dialect::Rs274, "t.ngc", &options);
    assert_eq!(end_points(&p).len(), 4, "{:#?}", p.blocks);
    assert!(p.diagnostics.iter().any(|d| d.line == 6 && d.message.contains("is never run")), "{:#?}", p.diagnostics);
    for (text, at, needle) in [
        ("G21 G90\nG0 X0 Y0\nG41.1 D10\nG1 X3 F100\nM2\n", "4:1:", "Length of cutter compensation entry move is not greater than the tool radius"),
        ("G21 G90\nG0 X0 Y0\nG41.1 D10\nG1 X30 F100\nG41.1 D4\nM2\n", "5:1:", "Cannot turn cutter radius comp on when on"),
        ("G21 G90\nG0 X0 Y0\nG41.1\nM2\n", "3:1:", "G41.1 with no D word"),
        ("G21 G90\nG0 X0 Y0\nG41 D1\nM2\n", "3:1:", "give it with --tool-table"),
        ("G21 G90\nG10 L1 P9 R2\nM2\n", "2:1:", "Requested tool 9 not found in the tool table"),
        ("G21 G90\nG0 X0 Y0\nG41\nM2\n", "3:1:", "no T ... M6"),
        ("G21 G90\nG0 X0 Y0\nG41.1 D10\nG1 X30 F100\nG92 X0\nM2\n", "5:1:", "Cannot change axis offsets with cutter radius comp"),
        ("G21 G90\nG0 X0 Y0\nG41.1 D10\nG1 X30 F100\nT1 M6\nM2\n", "5:4:", "Cannot change tools with cutter radius compensation on"),
        ("G21 G90\nG0 X0 Y0\nG41.1 D10\nG1 X30 F100\nG40\nG2 X40 Y0 R5\nM2\n", "6:1:", "must be straight, not an arc"),
        // A slot 1 mm wide for a 10 mm tool, a step of 1 mm on the tool's side (rs274 refuses both at that line).
        ("G21 G90\nG0 X0 Y0\nG42.1 D10\nG1 X30 F100\nY30\nX31\nY0\nM2\n", "7:1:", "Straight feed in concave corner cannot be reached by the tool without gouging"),
        ("G21 G90\nG0 X0 Y0\nG42.1 D10\nG1 X30 F100\nY1\nX60\nM2\n", "6:1:", "Straight feed in concave corner cannot be reached by the tool without gouging"),
        ("G21 G90 G18\nG0 X0 Y0\nG41.1 D10\nM2\n", "3:1:", "XY plane (G17) only"),
        // LinuxCNC's order of execution: a plane change and M codes act before G40 in the block,
        // coordinate systems, control modes and tool offsets after G41 (each refused so by rs274).
        ("G21 G90\nG0 X0 Y0\nG41.1 D10\nG1 X30 F100\nG40 G18\nM2\n", "5:5:", "Cannot change planes with cutter radius compensation on"),
        ("G21 G90\nG0 X0 Y0\nG41.1 D10 G54\nG1 X30 F100\nM2\n", "3:11:", "Cannot change coordinate systems with cutter radius compensation on"),
        ("G21 G90\nG0 X0 Y0\nG41.1 D10\nG1 X30 F100\nG64\nM2\n", "5:1:", "Cannot change control mode with cutter radius compensation on"),
        ("G21 G90\nG0 X0 Y0\nG41.1 D10\nG1 X30 F100\nG43\nM2\n", "5:1:", "Cannot change tool offset with cutter radius compensation on"),
        ("G21 G90\nG0 X0 Y0\nG41.1 D10\nG1 X30 F100\nM62 P0\nM2\n", "5:1:", "Cannot set motion output with cutter radius compensation on"),
        ("G21 G90\nG0 X0 Y0\nT1 M6\nG41 D-1\nM2\n", "4:5:", "G41 requires D word to be a whole number"),
        ("G21 G90\nG0 X0 Y0\nG42.1 D5 L3\nM2\n", "3:10:", "G42.1 with L word, but plane is not G18"),
    ] {
        let p = read(text, Dialect::Rs274, "t.ngc", &ReadOptions::default());
        let (l, c) = at.trim_end_matches(':').split_once(':').unwrap();
        has(&p, l.parse().unwrap(), c.parse().unwrap(), needle);
    }
}

/// `--tool-table` through the CLI: a program compensating by the table's tool reads clean, a table
/// with a fault is refused at its line (exit 2), and without a table the G41 block is.
#[test]
fn the_tool_table_flag_reads_a_linuxcnc_table() {
    let dir = crate::common::scratch_root().join("tool_table");
    std::fs::create_dir_all(&dir).unwrap();
    let (prog, good, bad) = (dir.join("slot.ngc"), dir.join("tool.tbl"), dir.join("bad.tbl"));
    std::fs::write(&prog, "G21 G90 G17\nG0 X-20 Y0 Z5\nG1 Z-1 F300\nG41 D4\nG1 X0 Y0\nX50\nG40 G1 X70 Y-20\nG0 Z5\nM2\n").unwrap();
    std::fs::write(&good, "T4 P4 D12 Z0 ;a 12 mm end mill\n").unwrap();
    std::fs::write(&bad, "T4 P4 D12 Z0\nT5 P5 R3\n").unwrap();
    let run = |table: &std::path::Path| {
        std::process::Command::new(env!("FIVEAXIS_EXE")).args(["program", "analyze"]).arg(&prog).arg("--tool-table").arg(table).args(["--machine", "linuxcnc-xyzac-trt", "--json"]).output().unwrap()
    };
    let out = run(&good);
    assert_eq!(out.status.code(), Some(0), "{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    let out = run(&bad);
    let all = format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    assert_eq!(out.status.code(), Some(2), "{all}");
    assert!(all.contains("bad.tbl: line 2: 'R3'"), "{all}");
    // The same program without the table: the radius is unknown, refused where G41 stands.
    let out = std::process::Command::new(env!("FIVEAXIS_EXE")).args(["program", "analyze"]).arg(&prog).args(["--machine", "linuxcnc-xyzac-trt"]).output().unwrap();
    let all = format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    assert_eq!(out.status.code(), Some(2), "{all}");
    assert!(all.contains("slot.ngc:4:1: error: G41: the radius is tool 4's"), "{all}");
}

/// LinuxCNC's canned cycles in the XZ and YZ planes (interp_cycles.cc convert_cycle_zx and _yz: the
/// hole at Z X drilled along Y, at Y Z along X; R and the bottom on the drilling axis) read to the
/// moves rs274 makes of them (`cycles_planes.ngc`: G81, G83, G82, G73, G98/G99, G91 with L repeats).
/// Polar coordinates there are LinuxCNC's error.
#[test]
fn rs274_drills_in_the_xz_and_yz_planes_as_linuxcnc_does() {
    let dir = Path::new(env!("FIVEAXIS_ROOT")).join("recordings/programs/linuxcnc/parameters");
    let text = std::fs::read_to_string(dir.join("cycles_planes.ngc")).unwrap();
    same_moves_as_linuxcnc("cycles_planes", &read(&text, Dialect::Rs274, "t.ngc", &ReadOptions::default()));
    let p = read("G21 G90 G18 F100\nG0 X0 Y20 Z0\nG81 @5 ^30 R15 Y2\nM2\n", Dialect::Rs274, "t.ngc", &ReadOptions::default());
    has(&p, 3, 1, "Cannot use polar coordinate except in G17 plane");
    let p = read("G21 G90 G19 F100\nG0 X20 Y0 Z0\nG81 Y5 Z5 R25\nM2\n", Dialect::Rs274, "t.ngc", &ReadOptions::default());
    has(&p, 3, 1, "X value unspecified in YZ plane canned cycle");
    // LinuxCNC's tapping there moves to axes exchanged (its tests/interp/g84/g18 and g19 programs:
    // the feed of the first hole goes to X-1 Y1 Z1 in, not X1 Y-1 Z1): refused, not copied.
    let p = read("G20 G90 G18 F10 S100 M3\nG0 X1 Y2 Z1\nG84 Z1 X1 R1.5 Y-1\nM2\n", Dialect::Rs274, "t.ngc", &ReadOptions::default());
    has(&p, 3, 1, "G84 in the XZ plane: LinuxCNC 2.9 feeds the tap with its axes exchanged");
}

/// What LinuxCNC 2.9's interpreter refuses is refused here too, never run (each message its own,
/// from its source): an absolute-centre arc (G90.1) missing a centre word ("J word missing in
/// absolute center arc"), G53 with an arc or a cycle ("Must use g0 or g1 with g53", as rs274 prints it), a tap with the
/// spindle the wrong way or stopped (check_g74_g84_spindle), a comment inside a comment ("Nested
/// comment found"), N after other words ("Bad character 'n' used"), and a label opening a second
/// block ("duplicate O-word label").
#[test]
fn what_linuxcnc_refuses_is_refused() {
    let head = "G21 G90 G94 G17 F600 S1000 M3\nG0 X10 Y0 Z0\n";
    refuses_each(
        Dialect::Rs274,
        &ReadOptions::default(),
        &[
            (&format!("{head}G90.1\nG3 X-10 Y0 I0\nM2\n"), "4:1:", "J word missing in an absolute-centre arc"),
            (&format!("{head}G53 G2 X10 Y0 R5\nM2\n"), "3:1:", "Must use g0 or g1 with g53"),
            (&format!("{head}G53 G81 X5 Y0 Z-1 R2\nM2\n"), "3:1:", "Must use g0 or g1 with g53"),
            (&format!("{head}G81 X5 Y0 Z-1 R2\nG53 X20\nM2\n"), "4:1:", "Must use g0 or g1 with g53"),
            (&format!("{head}M4\nG84 X5 Y0 Z-1 R2\nM2\n"), "4:1:", "Spindle turning counterclockwise in G84"),
            (&format!("{head}G74 X5 Y0 Z-1 R2\nM2\n"), "3:1:", "Spindle turning clockwise in G74"),
            (&format!("{head}M5\nG84 X8 Z-1 R2\nM2\n"), "4:1:", "Spindle not turning in G84"),
            (&format!("{head}G1 X10 (a (b) Y5\nM2\n"), "3:11:", "Nested comment found"),
            (&format!("{head}G1 X10 N20 Y5\nM2\n"), "3:8:", "Bad character 'n' used"),
            (&format!("{head}#1=1\no100 if [#1 GT 0]\nG1 X20\no100 endif\no100 if [#1 GT 0]\nG1 Y10\no100 endif\nM2\n"), "7:1:", "duplicate O-word label"),
        ],
    );
    // Their lawful forms read: both centre words under G90.1 (a half circle about X0 Y0), G53 G1, G84
    // under M3 and G74 under M4, N first (after a block delete), labels each opening one block.
    let p = read(&format!("{head}G90.1\nG3 X-10 Y0 I0 J0\nG91.1\nG53 G1 X20\nM4\nG74 X5 Y0 Z-1 R2\nG80\nN30 G1 X1\no1 if [1 GT 0]\nG1 X2\no1 endif\no2 if [1 GT 0]\nG1 X3\no2 endif\nM2\n"), Dialect::Rs274, "t.ngc", &ReadOptions::default());
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    // U, V and W words are axis words to LinuxCNC's G53 rule (its nine axes): `G53 G0 W10` is refused
    // for the W axis no machine here has, not for a G53 without axes.
    for w in ["U10", "V10", "W10"] {
        let p = read(&format!("{head}G53 G0 {w}\nM2\n"), Dialect::Rs274, "t.ngc", &ReadOptions::default());
        let e = errors(&p);
        assert!(e.len() == 1 && (e[0].0, e[0].1) == (3, 8) && e[0].2.contains(w), "{w}: {e:?}");
    }
    // A label is its subroutine's (LinuxCNC keys it "sub#label"): two subroutines may each open o100.
    let subs = "o200 sub\no100 if [1 GT 0]\nG1 X1\no100 endif\no200 endsub\no300 sub\no100 if [1 GT 0]\nG1 X2\no100 endif\no300 endsub\n";
    let p = read(&format!("{subs}{head}o200 call\no300 call\no200 call\nM2\n"), Dialect::Rs274, "t.ngc", &ReadOptions::default());
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
}

