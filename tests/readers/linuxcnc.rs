//! RS274NGC read as LinuxCNC reads it: end points against its own interpreter's canonical output
//! (`rs274`, fixtures made by make_canon.sh), parameters, expressions and O-word flow, canned cycles,
//! the path tolerance and the bridgemill demo.

use super::*;

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

/// The end points LinuxCNC's own interpreter (`rs274`, Debian 12's linuxcnc-uspace) makes of a program:
/// its canonical STRAIGHT_FEED/STRAIGHT_TRAVERSE(x, y, z, a, b, c) lines (mm, deg; see make_canon.sh).
fn linuxcnc_canon(name: &str) -> Vec<(Motion, [f64; 6])> {
    let path = Path::new(env!("FIVEAXIS_ROOT")).join("recordings/programs/linuxcnc/parameters").join(name);
    std::fs::read_to_string(&path)
        .unwrap()
        .lines()
        .map(|l| {
            let motion = if l.starts_with("STRAIGHT_FEED(") { Motion::Linear } else { Motion::Rapid };
            let inner = &l[l.find('(').unwrap() + 1..l.rfind(')').unwrap()];
            let v: Vec<f64> = inner.split(',').map(|x| x.trim().parse().unwrap()).collect();
            (motion, [v[0], v[1], v[2], v[3], v[4], v[5]])
        })
        .collect()
}

/// LinuxCNC's parameters and expressions (`#<feed>=1500`, `F#<feed>`, `X[2.0 / 3 * 1.5 - 5.5 / 11.0]`,
/// `YSIN[30]`, `X##32`, a setting that takes effect after its line) are read to the motion LinuxCNC's
/// own interpreter makes of them: every operator and function of the manual's §11.4.5-11.4.8 in a
/// fixture, and the demos `xyzac_switchkins_test_1/2.ngc` that set their feed as `#<FRATE>`. So are
/// its work offsets (`offsets.ngc`: G10 L2 and L20, P0 for the active system, G53, G55), and its
/// O-word control flow (`owords.ngc`: a subroutine called twice with arguments, its own `#<n>` and a
/// global `#<_scale>`, `return`, `while` with `continue` and `break`, `do`/`while`, `repeat`, `if`/
/// `elseif`/`else`).
#[test]
fn rs274_evaluates_parameters_and_expressions_as_linuxcnc_does() {
    let dir = Path::new(env!("FIVEAXIS_ROOT")).join("recordings/programs/linuxcnc/parameters");
    let switchkins = ReadOptions { m_codes: vec!["428=tcp-on".parse().unwrap(), "429=tcp-off".parse().unwrap()], ..Default::default() };
    for name in ["expressions", "offsets", "owords", "xyzac_switchkins_test_1", "xyzac_switchkins_test_2"] {
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
    for (dialect, machine) in [(Dialect::Rs274, &linuxcnc), (Dialect::Haas, &haas)] {
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


/// LinuxCNC's canonical moves with their kind (STRAIGHT_TRAVERSE, STRAIGHT_FEED, ARC_FEED in its
/// plane's axis order): end points in mm and deg, an arc's centre in its plane (mm). rs274 prints
/// positions in the program's unit (USE_LENGTH_UNITS), in the current coordinate frame (make_canon.sh's
/// second list).
fn linuxcnc_moves(name: &str) -> Vec<(Motion, [f64; 6], Option<[f64; 2]>)> {
    let path = Path::new(env!("FIVEAXIS_ROOT")).join("recordings/programs/linuxcnc/parameters").join(name);
    let (mut inch, mut plane) = (false, "XY");
    let mut out = Vec::new();
    for l in std::fs::read_to_string(&path).unwrap().lines() {
        let inner = &l[l.find('(').unwrap() + 1..l.rfind(')').unwrap()];
        let v: Vec<f64> = inner.split(',').filter_map(|x| x.trim().parse().ok()).collect();
        let mm = |x: f64| if inch { x * 25.4 } else { x };
        match &l[..l.find('(').unwrap()] {
            "USE_LENGTH_UNITS" => inch = inner.contains("INCHES"),
            "SELECT_PLANE" => plane = if inner.contains("XZ") { "XZ" } else if inner.contains("YZ") { "YZ" } else { "XY" },
            "ARC_FEED" => {
                let turn = v[4];
                let (x, y, z) = match plane { "XY" => (v[0], v[1], v[5]), "XZ" => (v[1], v[5], v[0]), _ => (v[5], v[0], v[1]) };
                let centre = (plane == "XY").then(|| [mm(v[2]), mm(v[3])]);
                out.push((if turn < 0.0 { Motion::ArcCw } else { Motion::ArcCcw }, [mm(x), mm(y), mm(z), v[6], v[7], v[8]], centre));
            }
            kind => out.push((if kind == "STRAIGHT_FEED" { Motion::Linear } else { Motion::Rapid }, [mm(v[0]), mm(v[1]), mm(v[2]), v[3], v[4], v[5]], None)),
        }
    }
    out
}

/// Our moves against `name.canon`: the same kinds, end points and arc centres to rs274's 4 decimals
/// (of an inch, under G20).
fn same_moves_as_linuxcnc(name: &str, p: &Program) {
    assert!(errors(p).is_empty(), "{name}: {:?}", errors(p));
    let ours = end_points(p);
    let centres: Vec<Option<[f64; 2]>> = p.blocks.iter().filter(|b| !b.targets.is_empty()).map(|b| b.arc.as_ref().map(|a| [a.centre[0] / MM, a.centre[1] / MM])).collect();
    let theirs = linuxcnc_moves(&format!("{name}.canon"));
    assert_eq!(ours.len(), theirs.len(), "{name}: moves\nours {ours:?}\ntheirs {theirs:?}");
    let close = |a: f64, b: f64| (a - b).abs() <= 0.5e-4 * 25.4 + 1e-9;
    for (k, (((m, a), c), (n, b, d))) in ours.iter().zip(&centres).zip(&theirs).enumerate() {
        assert_eq!(m, n, "{name}: move {k}: ours {a:?}, LinuxCNC {b:?}");
        assert!((0..6).all(|i| close(a[i], b[i])), "{name}: move {k}: ours {a:?}, LinuxCNC {b:?}");
        if let (Some(c), Some(d)) = (c, d) {
            assert!(close(c[0], d[0]) && close(c[1], d[1]), "{name}: move {k}'s centre: ours {c:?}, LinuxCNC {d:?}");
        }
    }
}

/// LinuxCNC's axis offsets and polar coordinates are read to the moves its own interpreter makes of
/// them (`offsets_g92.ngc`, `polar.ngc`; canonical output by make_canon.sh): G92 makes the current
/// point the block's coordinates in every work offset system, G52 sets the offset itself, G92.2 takes
/// it away keeping its parameters for G92.3, G92.1 zeroes them; G10 L20 counts it, G53 does not.
/// `@` is the distance from the origin and `^` the angle from +X, each kept from the current point
/// when left out under G90, added about the origin under G91 (an arc's end too, and canned cycles'
/// holes on each repeat: `polar_cycles.ngc`, after LinuxCNC's own polar demos). Then LinuxCNC's own
/// refusals of polar coordinates and G92's rotary words that this model does not hold.
#[test]
fn rs274_reads_axis_offsets_and_polar_coordinates_as_linuxcnc_does() {
    let dir = Path::new(env!("FIVEAXIS_ROOT")).join("recordings/programs/linuxcnc/parameters");
    for name in ["offsets_g92", "polar", "polar_cycles"] {
        let text = std::fs::read_to_string(dir.join(format!("{name}.ngc"))).unwrap();
        same_moves_as_linuxcnc(name, &read(&text, Dialect::Rs274, "t.ngc", &ReadOptions::default()));
    }
    refuses_each(
        Dialect::Rs274,
        &ReadOptions::default(),
        &[
            ("G21 G90 G18\nG1 @10 ^30 F100\nM2\n", "2:4:", "except in G17 plane"),
            ("G21 G90\nG1 X1 @10 ^30 F100\nM2\n", "2:7:", "both polar coordinate and X word"),
            ("G21 G90\nG0 X0 Y0\nG1 @10 F100\nM2\n", "3:4:", "Must specify angle in polar coordinate if at the origin"),
            ("G21 G91\nG0 X0 Y0\nG1 ^10 F100\nM2\n", "3:4:", "G91 motion with polar coordinates is indeterminate"),
            ("G21 G90\nG53 G0 @10 ^0\nM2\n", "2:8:", "with G53"),
            ("G21 G90\nG92 @10 ^0\nM2\n", "2:1:", "polar coordinates (@, ^) in a block whose axis words set an offset"),
            ("G21 G90\nG0 A10\nG92 A0\nM2\n", "3:5:", "G92 A0: rotary-axis offsets are not modelled (this one would be 10.000000 deg)"),
            ("G21 G90\nG10 L2 P1 X1 G92 X0\nM2\n", "2:14:", "two G codes of modal group 0"),
        ],
    );
}



/// `v` turned by `deg` about Z (rs274ngc's `rotate`).
fn turned(v: [f64; 2], deg: f64) -> [f64; 2] {
    let (s, c) = deg.to_radians().sin_cos();
    [v[0] * c - v[1] * s, v[0] * s + v[1] * c]
}

/// LinuxCNC's moves placed where its canonical layer puts the axes (emccanon.cc
/// rotate_and_offset_pos: XY = rot(p + G92 offset, R) + G5x offset, Z = p + both offsets), from
/// rs274's positions in the program frame and the offsets and rotation it sets (mm, deg); an XY
/// arc's centre placed alike; a feed move's feed, mm/min (in inverse time too: LinuxCNC's
/// interpreter gives the canonical layer the feed it works out, interp_inverse.cc; in units per
/// revolution, SET_FEED_MODE(spindle, 1), the feed times the spindle speed SET_SPINDLE_SPEED set).
fn linuxcnc_world(path: &Path) -> Vec<Placed> {
    let (mut inch, mut plane, mut g5x, mut g92, mut r) = (false, "XY", [0.0; 3], [0.0; 3], 0.0);
    let (mut feed, mut per_rev, mut speed) = (0.0, false, 0.0);
    let mut out = Vec::new();
    for l in std::fs::read_to_string(path).unwrap().lines() {
        let inner = &l[l.find('(').unwrap() + 1..l.rfind(')').unwrap()];
        let v: Vec<f64> = inner.split(',').filter_map(|x| x.trim().parse().ok()).collect();
        let mm = |x: f64| if inch { x * 25.4 } else { x };
        // A feed move's feed, mm/min.
        let path_feed = feed * if per_rev { speed } else { 1.0 };
        // Offsets in mm as set (the canonical layer keeps them in its own units), positions in
        // the program's unit as it moves.
        let place = |p: [f64; 3]| {
            let xy = turned([mm(p[0]) + g92[0], mm(p[1]) + g92[1]], r);
            [xy[0] + g5x[0], xy[1] + g5x[1], mm(p[2]) + g92[2] + g5x[2]]
        };
        match &l[..l.find('(').unwrap()] {
            "USE_LENGTH_UNITS" => inch = inner.contains("INCHES"),
            "SELECT_PLANE" => plane = if inner.contains("XZ") { "XZ" } else if inner.contains("YZ") { "YZ" } else { "XY" },
            "SET_G5X_OFFSET" => g5x = [mm(v[1]), mm(v[2]), mm(v[3])],
            "SET_G92_OFFSET" => g92 = [mm(v[0]), mm(v[1]), mm(v[2])],
            "SET_XY_ROTATION" => r = v[0],
            // In the program's unit when it is set, as emccanon.cc SET_FEED_RATE converts it
            // (FROM_PROG_LEN), per minute or, in feed per revolution, per turn.
            "SET_FEED_RATE" => feed = mm(v[0]),
            "SET_FEED_MODE" => per_rev = v[1] == 1.0,
            "SET_SPINDLE_SPEED" => speed = v[1],
            "ARC_FEED" => {
                let (x, y, z) = match plane { "XY" => (v[0], v[1], v[5]), "XZ" => (v[1], v[5], v[0]), _ => (v[5], v[0], v[1]) };
                let e = place([x, y, z]);
                let centre = (plane == "XY").then(|| place([v[2], v[3], z])).map(|c| [c[0], c[1]]);
                out.push((if v[4] < 0.0 { Motion::ArcCw } else { Motion::ArcCcw }, [e[0], e[1], e[2], v[6], v[7], v[8]], centre, Some(path_feed)));
            }
            kind @ ("STRAIGHT_FEED" | "STRAIGHT_TRAVERSE") => {
                let e = place([v[0], v[1], v[2]]);
                let f = (kind == "STRAIGHT_FEED").then_some(path_feed);
                out.push((if kind == "STRAIGHT_FEED" { Motion::Linear } else { Motion::Rapid }, [e[0], e[1], e[2], v[3], v[4], v[5]], None, f));
            }
            // The states this comparison does not place (the path control mode).
            _ => {}
        }
    }
    out
}

/// A move placed in the workpiece: its kind, end (mm, deg), an XY arc's centre (mm) and a feed
/// move's feed (mm/min).
type Placed = (Motion, [f64; 6], Option<[f64; 2]>, Option<f64>);

/// Our moves placed in the workpiece (targets plus datum, mm and deg; XY arcs' centres too), against
/// [`linuxcnc_world`] of `canon`: the same kinds and points to rs274's 4 decimals. Rapid moves that
/// go nowhere are left out on both sides (rs274 makes one of G28's intermediate point where the
/// tool stands; this reader none). Ours returned.
fn same_places_as_linuxcnc(p: &Program, canon: &Path) -> Vec<Placed> {
    assert!(errors(p).is_empty(), "{}: {:?}", canon.display(), errors(p));
    let moving = |v: Vec<Placed>| -> Vec<Placed> {
        let mut at = [0.0; 6];
        v.into_iter()
            .filter(|m| {
                // Within rs274's rounding (its 4 decimals, turned): no move.
                let still = m.0 == Motion::Rapid && (0..6).all(|i| (m.1[i] - at[i]).abs() <= 0.75e-4 * 25.4);
                at = m.1;
                !still
            })
            .collect()
    };
    let theirs = moving(linuxcnc_world(canon));
    let mut at = [0.0; 6];
    let ours: Vec<Placed> = p
        .blocks
        .iter()
        .filter(|b| !b.targets.is_empty())
        .map(|b| {
            let t = &b.targets;
            let from = at;
            for (k, v) in [t.x, t.y, t.z, t.a, t.b, t.c].into_iter().enumerate() {
                if let Some(v) = v {
                    at[k] = if k < 3 { (v + b.datum[k]) / MM } else { v / DEG };
                }
            }
            let centre = b.arc.as_ref().filter(|a| a.plane == fiveaxis::program::Plane::Xy).map(|a| [(a.centre[0] + b.datum[0]) / MM, (a.centre[1] + b.datum[1]) / MM]);
            // Inverse time (a straight move): the move's length over its time.
            let length = ((at[0] - from[0]).powi(2) + (at[1] - from[1]).powi(2) + (at[2] - from[2]).powi(2)).sqrt();
            let feed = b.feed.filter(|_| b.motion != Motion::Rapid).map(|f| if f.mode == FeedMode::InverseTime { f.value_per_min * length } else { f.value_per_min });
            (b.motion, at, centre, feed)
        })
        .collect();
    let ours = moving(ours);
    let name = canon.display();
    assert_eq!(ours.len(), theirs.len(), "{name}: moves\nours {ours:?}\ntheirs {theirs:?}");
    // rs274's 4 decimals (of an inch, under G20), turned: a coordinate off by up to 1.5 of them.
    let close = |a: f64, b: f64| (a - b).abs() <= 0.75e-4 * 25.4;
    for (k, ((m, a, c, f), (n, b, d, g))) in ours.iter().zip(&theirs).enumerate() {
        assert_eq!(m, n, "{name}: move {k}: ours {a:?}, LinuxCNC {b:?}");
        assert!(f.zip(*g).is_none_or(|(f, g)| (f - g).abs() <= 1e-4 * 25.4) && f.is_some() == g.is_some(), "{name}: move {k}'s feed: ours {f:?}, LinuxCNC {g:?}");
        assert!((0..6).all(|i| close(a[i], b[i])), "{name}: move {k}: ours {a:?}, LinuxCNC {b:?}");
        if let (Some(c), Some(d)) = (c, d) {
            assert!(close(c[0], d[0]) && close(c[1], d[1]), "{name}: move {k}'s centre: ours {c:?}, LinuxCNC {d:?}");
        }
    }
    ours
}

/// Rotated coordinate systems (`G10 L2 Pn R`) are read to where LinuxCNC places the axes
/// (`rotation.ngc`, rs274's output by make_canon.sh placed as its canonical layer does): moves,
/// arcs in XY and XZ, polar coordinates and a canned cycle's holes in a rotated frame; the rotation
/// of a system not in use, then selected; G92 and G10 L20 in a rotated system; the rotation changed
/// while in use under a G92 offset (which LinuxCNC does not turn in as it re-reads the current
/// point); G53's machine X in it; back to an unrotated system; cutter radius compensation in a
/// rotated system (offset in the program frame, then turned). Each move's end point and each XY
/// arc's centre in the workpiece, to rs274's 4 decimals; then LinuxCNC's refusals.
#[test]
fn rs274_reads_rotated_coordinate_systems_as_linuxcnc_does() {
    let dir = Path::new(env!("FIVEAXIS_ROOT")).join("recordings/programs/linuxcnc/parameters");
    let text = std::fs::read_to_string(dir.join("rotation.ngc")).unwrap();
    let p = read(&text, Dialect::Rs274, "rotation.ngc", &ReadOptions::default());
    let ours = same_places_as_linuxcnc(&p, &dir.join("rotation.canon"));
    let close = |a: f64, b: f64| (a - b).abs() <= 2e-4;
    // The rotation turns the frame: a move along the program's X at R30 goes 30 deg off the machine's.
    let b = &ours[1].1;
    assert!(close(b[0], 10.0 + 20.0 * 30f64.to_radians().cos()) && close(b[1], 5.0 + 20.0 * 30f64.to_radians().sin()), "{b:?}");
    refuses_each(
        Dialect::Rs274,
        &ReadOptions::default(),
        &[
            ("G21 G90\nG10 L20 P1 X0 R10\nM2\n", "2:15:", "R not allowed in G10 L20"),
            ("G21 G90\nG10 L2 P1 R10\nG54 G0 X0 Y0\nG41.1 D0\nG53 G1 X5 F100\nM2\n", "5:1:", "machine coordinates (G53) with cutter radius compensation on in a rotated"),
        ],
    );
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

/// LinuxCNC's moves to a stored position (`home.ngc`, rs274's output by make_canon.sh) on its xyzac-trt
/// sim, whose parameter file starts empty (stored positions 0): `G28 G91 Z0` (the retract CAM posts
/// write), G28 through an absolute intermediate point in a rotated system, under a G92 offset, after
/// `G28.1` stored a position, `G30`, and `G28` alone moving every axis (A and C too); each move's end
/// in the workpiece against rs274's. Then the refusals: a machine file without machine coordinates,
/// G28 with a motion code, axis words with G28.1.
#[test]
fn rs274_moves_to_stored_positions_as_linuxcnc_does() {
    let dir = Path::new(env!("FIVEAXIS_ROOT")).join("recordings/programs/linuxcnc/parameters");
    let machine = fiveaxis::machine::Machine::builtin("linuxcnc-xyzac-trt").unwrap();
    let on = ReadOptions::default().on(&machine);
    let text = std::fs::read_to_string(dir.join("home.ngc")).unwrap();
    let p = read(&text, Dialect::Rs274, "home.ngc", &on);
    let ours = same_places_as_linuxcnc(&p, &dir.join("home.canon"));
    // G28 G91 Z0 takes Z to the machine's 0, X Y staying: from Z10 in G54 (Z offset -5), Z 0.
    assert!(ours.iter().any(|m| m.0 == Motion::Rapid && m.1[2].abs() < 1e-9 && m.1[3] == 10.0), "{ours:?}");
    for (text, machine, at, needle) in [
        ("G21 G90\nG28 G91 Z0\nM2\n", "hermle-c600u", "2:1:", "places no machine coordinates"),
        ("G21 G90\nG28 G0 Z0\nM2\n", "linuxcnc-xyzac-trt", "2:5:", "two G codes that both use axis words"),
        ("G21 G90\nG28.1 X0\nM2\n", "linuxcnc-xyzac-trt", "2:7:", "axis words are not read with them"),
    ] {
        let p = read(text, Dialect::Rs274, "t.ngc", &ReadOptions::default().on(&fiveaxis::machine::Machine::builtin(machine).unwrap()));
        let (l, c) = at.trim_end_matches(':').split_once(':').unwrap();
        has(&p, l.parse().unwrap(), c.parse().unwrap(), needle);
    }
}

/// LinuxCNC's predefined parameters of the interpreter's state and subroutines' return values read
/// as its interpreter reads them (`state_parameters.ngc`, rs274's output by make_canon.sh): each
/// value is seen in the move it makes, so every move's end and feed is checked against rs274's. The
/// values are those before the line runs (LinuxCNC reads a line whole, then runs it: `G91
/// X[#<_incremental>]` reads 0). Then the state this reader does not hold stays refused.
#[test]
fn rs274_reads_the_interpreters_state_parameters_as_linuxcnc_does() {
    let dir = Path::new(env!("FIVEAXIS_ROOT")).join("recordings/programs/linuxcnc/parameters");
    let text = std::fs::read_to_string(dir.join("state_parameters.ngc")).unwrap();
    let p = read(&text, Dialect::Rs274, "state_parameters.ngc", &ReadOptions::default());
    let ours = same_places_as_linuxcnc(&p, &dir.join("state_parameters.canon"));
    // `o<twice> call [5]` returns 10 by `return [#1 * 2]`, in G55 (offset X10 Y5, rotated 30 deg).
    // A parameter number computed (`#[5000 + 420]` is #5420, X where the tool stands) reads the state too.
    let p = read("G21 G90\nG0 X3 Y4\nG1 X[#[5000 + 420] + 1] Y[##<n>] F100\nM2\n".replace("##<n>", "#[5421]").as_str(), Dialect::Rs274, "t.ngc", &ReadOptions::default());
    let ends: Vec<[f64; 2]> = end_points(&p).iter().map(|(_, a)| [a[0], a[1]]).collect();
    assert_eq!(ends, vec![[3.0, 4.0], [4.0, 4.0]], "{:?}", errors(&p));
    let (s, c) = 30f64.to_radians().sin_cos();
    let at = |x: f64, y: f64| [10.0 + x * c - y * s, 5.0 + x * s + y * c];
    assert!(ours.iter().any(|m| { let w = at(10.0, 1.0); (m.1[0] - w[0]).abs() < 1e-9 && (m.1[1] - w[1]).abs() < 1e-9 }), "{ours:?}");
    refuses_each(
        Dialect::Rs274,
        &ReadOptions::default(),
        &[
            ("G21 G90\nG1 X[#<_spindle_on>] F100\nM2\n", "2:6:", "#<_spindle_on> is the interpreter's or the machine's state"),
            ("G21 G90\nG1 X[#5400] F100\nM2\n", "2:6:", "#5400 is a system parameter"),
            ("G21 G90\nG0 X0 Y0\nG41.1 D2\nG1 X[#<_x> + 10] F100\nM2\n", "4:6:", "#<_x> is the interpreter's or the machine's state"),
        ],
    );
}

/// F in a block with G20 or G21 is in the unit before it, and the feed stays what it was across a
/// unit change: LinuxCNC's order of execution sets F (step 4) before the units (step 16), and its
/// task keeps the feed in its own units (emccanon.cc SET_FEED_RATE, GET_EXTERNAL_FEED_RATE), so
/// `#<_feed>` then reads it in the new unit. (Standalone rs274 keeps the number instead, so this is
/// checked against the source, not against it.)
#[test]
fn a_feed_stays_across_a_unit_change_as_linuxcncs_task_keeps_it() {
    let text = "G21 G90 G17\nG0 X0 Y0\nG20 G1 X1 F5\nG1 X2 Y[#<_feed> * 25.4]\nG21 G1 X80\nG1 X[#<_feed>]\nM2\n";
    let p = read(text, Dialect::Rs274, "t.ngc", &ReadOptions::default());
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    let moves: Vec<(usize, f64, f64, f64)> = p
        .blocks
        .iter()
        .filter(|b| b.motion == Motion::Linear && !b.targets.is_empty())
        .map(|b| (b.line, b.targets.x.unwrap_or(f64::NAN) / MM, b.targets.y.unwrap_or(0.0) / MM, b.feed.map_or(0.0, |f| f.value_per_min)))
        .collect();
    let want = [(3, 25.4, 0.0, 5.0), (4, 50.8, 127.0, 5.0), (5, 80.0, 0.0, 5.0), (6, 5.0, 0.0, 5.0)];
    assert_eq!(moves.len(), want.len(), "{moves:?}");
    for (g, w) in moves.iter().zip(want) {
        assert!(g.0 == w.0 && (g.1 - w.1).abs() < 1e-9 && (g.2 - w.2).abs() < 1e-9 && (g.3 - w.3).abs() < 1e-9, "{g:?}, expected {w:?}");
    }
}

/// A subroutine defined after its call, in the program's own file, is found as LinuxCNC skips
/// forward to it (`subs_after.ngc`: the main program, then its subroutines after M2, one calling
/// another defined after it; rs274's output by make_canon.sh): read whole and streamed from its
/// file (which is then read again for the subroutine), the same moves as rs274's. A call of a
/// subroutine defined nowhere is still refused.
#[test]
fn rs274_finds_subroutines_defined_after_their_call_as_linuxcnc_does() {
    let dir = Path::new(env!("FIVEAXIS_ROOT")).join("recordings/programs/linuxcnc/parameters");
    let path = dir.join("subs_after.ngc");
    let text = std::fs::read_to_string(&path).unwrap();
    let whole = read(&text, Dialect::Rs274, "subs_after.ngc", &ReadOptions::default());
    same_places_as_linuxcnc(&whole, &dir.join("subs_after.canon"));
    let mut stream = fiveaxis::program::open(&path, Some(Dialect::Rs274), &ReadOptions::default()).unwrap();
    let streamed: Vec<_> = stream.by_ref().collect();
    assert_eq!(streamed, whole.blocks);
    assert_eq!(stream.diagnostics().errors(), 0, "{:?}", stream.diagnostics().to_vec());
    refuses_each(Dialect::Rs274, &ReadOptions::default(), &[("G21 G90\no<nowhere> call\nM2\no<elsewhere> sub\no<elsewhere> endsub\n", "2:1:", "no subroutine o<nowhere> is defined in this file (before the call or after it)")]);
    // The subroutines after the end are no program cut off; a move after them is, and is said.
    assert!(whole.diagnostics.iter().all(|d| !d.message.contains("are not run")), "{:?}", whole.diagnostics);
    let p = read(&format!("{text}G1 X1 F100\n"), Dialect::Rs274, "t.ngc", &ReadOptions::default());
    let last = text.lines().count() + 1;
    assert!(p.diagnostics.iter().any(|d| d.line == last && d.message.contains("are not run")), "{:?}", p.diagnostics);
}

/// LinuxCNC's Fanuc-style subprograms (LinuxCNC manual, O codes, "Fanuc-Style Numbered Programs"):
/// `M98 P L` runs `O<n>` ... `M99` L times with `#1`-`#30` shared (global) and named parameters its
/// own, `P0200` is `O200`, `P` may be computed, calls nest and come from o-call subroutines, `M99` in
/// a condition returns, `L0` runs nothing (`fanuc_subs.ngc`); an `O<n>` line the main program runs
/// into is its title, and `M99` ends the main program in the standalone interpreter
/// (`fanuc_main_m99.ngc`). Read whole and streamed, the same moves as rs274's (make_canon.sh). Calls
/// and subprograms of the other kind are refused as LinuxCNC refuses them (its tests/interp
/// m98m99/06-error-mixed-sub-styles), and so is what M98 L0's call level, which LinuxCNC 2.9 never
/// leaves, would change.
#[test]
fn rs274_runs_fanuc_style_subprograms_as_linuxcnc_does() {
    let dir = Path::new(env!("FIVEAXIS_ROOT")).join("recordings/programs/linuxcnc/parameters");
    for name in ["fanuc_subs", "fanuc_main_m99"] {
        let path = dir.join(format!("{name}.ngc"));
        let text = std::fs::read_to_string(&path).unwrap();
        let whole = read(&text, Dialect::Rs274, "t.ngc", &ReadOptions::default());
        same_places_as_linuxcnc(&whole, &dir.join(format!("{name}.canon")));
        let mut stream = fiveaxis::program::open(&path, Some(Dialect::Rs274), &ReadOptions::default()).unwrap();
        let streamed: Vec<_> = stream.by_ref().collect();
        assert_eq!(streamed, whole.blocks, "{name}");
        // Nothing after the end is said to be cut off: the subprograms are where calls go.
        assert!(whole.diagnostics.iter().all(|d| !d.message.contains("are not run")), "{name}: {:?}", whole.diagnostics);
    }
    let text = std::fs::read_to_string(dir.join("fanuc_main_m99.ngc")).unwrap();
    let p = read(&text, Dialect::Rs274, "t.ngc", &ReadOptions::default());
    assert_eq!(p.name.as_deref(), Some("O1"));
    assert!(p.diagnostics.iter().any(|d| d.line == 5 && d.message.contains("runs the program again")), "{:?}", p.diagnostics);
    refuses_each(
        Dialect::Rs274,
        &ReadOptions::default(),
        &[
            ("%\nO1 call\nO1\nG0 X1\nM99\n%\n", "2:1:", "must be called with 'M98'"),
            ("%\nM98 P1\nM30\nO1\nG0 X1\nO1 endsub\n%\n", "2:1:", "O1 at line 4 has no M99"),
            ("%\nM98 P1\nM30\nO1 sub\nG0 X1\nO1 endsub\n%\n", "2:1:", "must be called with 'O.... call'"),
            ("%\nO1 call\nM30\nO1 sub\nG0 X1\nM99\n%\n", "2:1:", "has no o1 endsub"),
            ("%\no1 sub\nG0 X1\nM99\no1 endsub\no1 call\nM30\n%\n", "4:1:", "must follow 'O.... sub'"),
            ("%\nM98 P1\nM30\nO1\no1 endsub\nM99\n%\n", "5:1:", "must end with 'M99'"),
            ("M98 L2\nM30\n", "1:1:", "no P-word"),
            ("M98 P1 X5\nM30\nO1\nM99\n", "1:8:", "only P (the program) and L"),
            ("M98 P1.5\nM30\nO1\nM99\n", "1:1:", "a whole number"),
            ("M98 P1 L-2\nM30\nO1\nM99\n", "1:8:", "a whole number 0 or more"),
            ("M98 P7\nM30\n", "1:1:", "no program O7 is defined"),
            ("G0 X1 M98 P1\nM30\nO1\nM99\n", "1:7:", "only as the first word of its line"),
            ("M98 P1\nM30\nO1\nG0 X1 M99\nM99\n", "4:1:", "only as the first word of its line"),
            ("M98 P1 L0\no2 sub\no2 endsub\nM30\nO1\nM99\n", "2:1:", "after M98 L0 (line 1)"),
            ("M98 P1 L0\nG0 X1\nM99\nO1\nM99\n", "3:1:", "after M98 L0 (line 1)"),
        ],
    );
    // The same text without L0's raised level reads.
    let p = read("M98 P1 L0\nG0 X1\nM98 P1 L1\nM30\nO1\nG0 Y1\nM99\n", Dialect::Rs274, "t.ngc", &ReadOptions::default());
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    let ends: Vec<[f64; 2]> = end_points(&p).iter().map(|(_, a)| [a[0], a[1]]).collect();
    assert_eq!(ends, vec![[1.0, 0.0], [1.0, 1.0]]);
}

/// Three small readings of LinuxCNC's, each as its interpreter reads it (rs274 on the same lines, as
/// LinuxCNC 2.9's tests/interp exists and fractional-linenumbers and m19 have them): `EXISTS[#n]`
/// of a numbered parameter is whether the number is one of its parameters (1 to 5601, the number
/// read as a value: `##1` is `#` of #1's value), a block number's fractional part is accepted and
/// ignored, and `M19` takes `R Q P`.
#[test]
fn rs274_reads_exists_of_numbered_parameters_fractional_block_numbers_and_m19_as_linuxcnc_does() {
    let text = "#<a>=999\nG0 X EXISTS[#1] Y EXISTS[#99999] Z EXISTS[#<a>] A EXISTS[#<b>]\n#1=2\n#2=99999\nG0 X EXISTS[##1] Y EXISTS[##2] Z EXISTS[###1]\nN4567.789 S1200\nM19 R45 Q2\nM19 R90 P1\nM2\n";
    let p = read(text, Dialect::Rs274, "t.ngc", &ReadOptions::default());
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    // rs274: STRAIGHT_TRAVERSE(1, 0, 1, 0, 0, 0) and (1, 0, 0, 0, 0, 0).
    let ends: Vec<[f64; 4]> = end_points(&p).iter().map(|(_, a)| [a[0], a[1], a[2], a[3]]).collect();
    assert_eq!(ends, vec![[1.0, 0.0, 1.0, 0.0], [1.0, 0.0, 0.0, 0.0]]);
    assert!(p.blocks.iter().any(|b| b.line == 6 && b.number == Some(4567)), "{:?}", p.blocks.iter().map(|b| (b.line, b.number)).collect::<Vec<_>>());
}

/// A subroutine's arguments the call does not give are 0 in it (interp_read.cc: "zero the remaining
/// params"), and the caller's `#1`-`#30` come back after it: rs274 makes X5 Y0 Z1, then X7, of
/// these lines (a LinuxCNC shop's subroutine library reads arguments its callers leave out).
#[test]
fn rs274_reads_arguments_a_call_leaves_out_as_zero_as_linuxcnc_does() {
    let p = read("o<s> sub\nG1 X[#1] Y[#2] Z[#30 + 1]\no<s> endsub\nG21 G90 F100\n#2 = 7\no<s> call [5]\nG1 X[#2]\nM2\n", Dialect::Rs274, "t.ngc", &ReadOptions::default());
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    let ends: Vec<[f64; 3]> = end_points(&p).iter().map(|(_, a)| [a[0], a[1], a[2]]).collect();
    assert_eq!(ends, vec![[5.0, 0.0, 1.0], [7.0, 0.0, 1.0]]);
    // A comment between arguments is read past (read_o; LinuxCNC's tests/interp flowsnake writes one).
    let p = read("o<s> sub\nG1 X[#1] Y[#2]\no<s> endsub\nG21 G90 F100\no<s> call [5] (a comment) [6]\nM2\n", Dialect::Rs274, "t.ngc", &ReadOptions::default());
    let ends: Vec<[f64; 2]> = end_points(&p).iter().map(|(_, a)| [a[0], a[1]]).collect();
    assert_eq!(ends, vec![[5.0, 6.0]], "{:?}", errors(&p));
}

/// A call's subroutine named by an expression (`o#<sub> call`, `O[#2 / 10] call`: LinuxCNC's tests/interp
/// oword-bug315-p2 and o-expression-call) runs the subroutine of that number: rs274 makes X2 Y2 Z2,
/// then X1 Y1 Z1, of these lines. A number that is not whole is refused.
#[test]
fn rs274_calls_a_subroutine_named_by_an_expression_as_linuxcnc_does() {
    let text = "o1 sub\ng0 x1y1z1\no1 endsub\no2 sub\ng0 x2y2z2\no2 endsub\no<multipass> sub\n#<sub> = 2\no#<sub> call\no<multipass> endsub\no<multipass> call\n#2 = 10\nO[#2 / 10] call\nm2\n";
    let p = read(text, Dialect::Rs274, "t.ngc", &ReadOptions::default());
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    let ends: Vec<[f64; 3]> = end_points(&p).iter().map(|(_, a)| [a[0], a[1], a[2]]).collect();
    assert_eq!(ends, vec![[2.0, 2.0, 2.0], [1.0, 1.0, 1.0]]);
    refuses_each(Dialect::Rs274, &ReadOptions::default(), &[("o1 sub\no1 endsub\nG21\no[1.5] call\nM2\n", "4:2:", "an O word's number is a whole number")]);
}

/// LinuxCNC's saved modal state (`M70`-`M73`) is restored as its interpreter restores it
/// (`modal_state.ngc`, rs274's output by make_canon.sh): after an M73 subroutine's endsub and its
/// `return`, and after M72 in the main program, the moves go in the units, distance mode,
/// coordinate system (a rotated one), plane, feed mode and feed (F to 0.1, as LinuxCNC writes it
/// back) and G92 offsets saved; each move's end, XY centre and feed against rs274's. Then the
/// refusals: M72 with nothing saved (or after M71), two codes of its modal group, F in its block.
#[test]
fn rs274_restores_the_modal_state_as_linuxcnc_does() {
    let dir = Path::new(env!("FIVEAXIS_ROOT")).join("recordings/programs/linuxcnc/parameters");
    let text = std::fs::read_to_string(dir.join("modal_state.ngc")).unwrap();
    let p = read(&text, Dialect::Rs274, "modal_state.ngc", &ReadOptions::default());
    let ours = same_places_as_linuxcnc(&p, &dir.join("modal_state.canon"));
    // The restores are seen: F123.456 comes back as 123.5 mm/min; the inch subroutine's X0.5 is
    // 12.7 mm in G55 (rotated 30 deg), and the next move is in mm again, in G54.
    assert!(ours.iter().any(|m| m.3 == Some(123.5)), "{ours:?}");
    assert!(ours.iter().any(|m| m.0 == Motion::Linear && m.1[0] == 10.0 && m.1[1] == 10.0 && m.3 == Some(500.0)), "{ours:?}");
    refuses_each(
        Dialect::Rs274,
        &ReadOptions::default(),
        &[
            ("G21 G90\nM72\nM2\n", "2:1:", "missing M70/M73"),
            ("G21 G90\nM70\nM71\nM72\nM2\n", "4:1:", "missing M70/M73"),
            ("G21 G90\nM70 M3\nM2\n", "2:5:", "two M codes of modal group 7"),
            ("G21 G90\nM72 F100\nM2\n", "2:5:", "F100 with M72 in one block"),
        ],
    );
    // M73 in the main program saves as M70 does, and says so (LinuxCNC's warning).
    let p = read("G21 G90\nG0 X5\nM73\nG91\nM72\nG1 X1 F100\nM2\n", Dialect::Rs274, "t.ngc", &ReadOptions::default());
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    assert!(p.diagnostics.iter().any(|d| d.line == 3 && d.message.contains("M73 in the main program")), "{:?}", p.diagnostics);
    assert_eq!(p.blocks.iter().filter_map(|b| b.targets.x).map(|x| x / MM).collect::<Vec<_>>(), vec![5.0, 1.0]);
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

/// Subroutines in files of the subroutine path (`--subroutine-path`, LinuxCNC's SUBROUTINE_PATH): `o<name>
/// call` reads `name.ngc` there, from its `sub` to its `endsub`, a subroutine of one file calling
/// another's; `calls_files.ngc` reads to the moves rs274 makes of it with an INI naming `subs/`. A
/// defect inside such a file is said at the call, naming the file and its own line; without the path,
/// or where no file has the subroutine, the call is refused.
#[test]
fn rs274_calls_subroutines_of_other_files_as_linuxcnc_does() {
    let dir = Path::new(env!("FIVEAXIS_ROOT")).join("recordings/programs/linuxcnc/parameters");
    let text = std::fs::read_to_string(dir.join("calls_files.ngc")).unwrap();
    let options = ReadOptions { subroutine_files: Some(std::sync::Arc::new(fiveaxis::program::SubroutineDirs(vec![dir.join("subs")]))), ..ReadOptions::default() };
    same_moves_as_linuxcnc("calls_files", &read(&text, Dialect::Rs274, "t.ngc", &options));
    let p = read(&text, Dialect::Rs274, "t.ngc", &ReadOptions::default());
    has(&p, 4, 1, "give it with --subroutine-path");
    let p = read("G21 G90\no<nowhere> call\nM2\n", Dialect::Rs274, "t.ngc", &options);
    has(&p, 2, 1, "nor in a file of --subroutine-path");
    // A defect inside the file (a peck of 0 loops for ever): at the call, naming the file's line.
    let p = read("G21 G90\nG0 X0 Y0 Z5\no<peck_hole> call [1] [1] [3] [0]\nM2\n", Dialect::Rs274, "t.ngc", &options);
    let e = errors(&p);
    assert!(e.iter().any(|(l, c, m)| (*l, *c) == (3, 1) && m.contains("peck_hole.ngc:")), "{e:#?}");
}

/// Subroutines of other files inside a run: a move before such a call stands at its own line (only
/// the file's moves stand at the call), and what a file's line says is said at the call naming that
/// file, a file's call of another file's subroutine naming both in turn (a review of the streamed
/// runs found the first move moved to the call's line and a's warning named as b's).
#[test]
fn moves_and_warnings_of_other_files_stand_where_linuxcnc_says() {
    let dir = std::env::temp_dir().join(format!("fiveaxis-files-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("a2.ngc"), "o<a2> sub\nG1 X5\no<a2> endsub\n").unwrap();
    std::fs::write(dir.join("a.ngc"), "o<a> sub\nG4 P100\no<b> call\no<a> endsub\n").unwrap();
    std::fs::write(dir.join("b.ngc"), "o<b> sub\nG4 P200\nG1 X2\no<b> endsub\n").unwrap();
    let options = ReadOptions { subroutine_files: Some(std::sync::Arc::new(fiveaxis::program::SubroutineDirs(vec![dir.clone()]))), ..ReadOptions::default() };
    let p = read("G21 G90 F100\no1 if [1]\nG0 X1\no<a2> call\no1 endif\nM2\n", Dialect::Rs274, "t.ngc", &options);
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    let at: Vec<(usize, Option<f64>)> = p.blocks.iter().filter(|b| b.targets.x.is_some()).map(|b| (b.line, b.targets.x.map(|x| x / MM))).collect();
    assert_eq!(at, [(3, Some(1.0)), (4, Some(5.0))]);
    let p = read("G21 G90 F100\no<a> call\nM2\n", Dialect::Rs274, "t.ngc", &options);
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    let said: Vec<&str> = p.diagnostics.iter().filter(|d| d.severity == Severity::Warning && d.line == 2).map(|d| d.message.as_str()).collect();
    assert!(said.iter().any(|m| m.contains("a.ngc:2:") && m.contains("P100") && !m.contains("b.ngc")), "{said:#?}");
    assert!(said.iter().any(|m| m.contains("a.ngc:3:") && m.contains("b.ngc:2:") && m.contains("P200")), "{said:#?}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// `--subroutine-path` through the CLI: the program that calls the files' subroutines reads clean
/// with it, and is refused at its first call without it.
#[test]
fn the_subroutine_path_flag_finds_the_files() {
    let dir = Path::new(env!("FIVEAXIS_ROOT")).join("recordings/programs/linuxcnc/parameters");
    let run = |extra: &[&std::ffi::OsStr]| {
        let mut c = std::process::Command::new(env!("FIVEAXIS_EXE"));
        c.args(["program", "analyze"]).arg(dir.join("calls_files.ngc")).args(["--machine", "linuxcnc-xyzac-trt"]).args(extra);
        let out = c.output().unwrap();
        (out.status.code(), format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr)))
    };
    let subs = dir.join("subs");
    let (code, all) = run(&[std::ffi::OsStr::new("--subroutine-path"), subs.as_os_str()]);
    assert_eq!(code, Some(0), "{all}");
    let (code, all) = run(&[]);
    assert_eq!(code, Some(2), "{all}");
    assert!(all.contains("calls_files.ngc:4:1: error: o<peck_hole> call"), "{all}");
}

/// What one block makes is bounded, and a loop's moves stream: a Fanuc `K9999` or a LinuxCNC
/// `L9999` over a cycle of 9,000 pecks (27 million moves from one 60-byte block, which aborted on
/// memory) is refused at its count, and an O-word loop of 1.2 million passes is read to its last
/// move, handed out a part at a time (its moves had all been held until the loop ended: 600 MB a
/// million; the memory is benches/oword-loop's figure).
#[test]
fn what_one_block_makes_is_bounded_and_a_loop_streams() {
    let fanuc = read("%\nO1000\nG21 G90 G94 G17\nG0 X0 Y0 Z10.\nG91 G99 G83 X0.001 Z-100. R-9. Q0.011 F100. K9999\nG80\nM30\n%\n", Dialect::Fanuc, "t.nc", &ReadOptions::default());
    has(&fanuc, 5, 45, "9999 holes of this cycle make about");
    let lcnc = read("G21 G90 G94 G17\nG0 X0 Y0 Z10\nG91 G99 G83 X0.001 Z-101 R-9 Q0.011 F100 L9999\nG80\nM2\n", Dialect::Rs274, "t.ngc", &ReadOptions::default());
    has(&lcnc, 3, 42, "9999 holes of this cycle make about");
    let passes = 1_200_000u64;
    let text = format!("G21 G90 G94 G17\nG0 X0 Y0 Z10\n#1 = 0\no100 repeat [{passes}]\n#1 = [#1 + 1]\nG1 X[#1 * 0.001] F1000\no100 endrepeat\nG0 Z20\nM2\n");
    let mut stream = fiveaxis::program::BlockStream::from_text(&text, Some(Dialect::Rs274), "t.ngc", &ReadOptions::default());
    let (mut moves, mut last_x, mut after) = (0u64, 0.0, false);
    for b in stream.by_ref() {
        if b.line == 6 {
            assert!(!after, "a move of the loop after the line that follows it");
            moves += 1;
            last_x = b.targets.x.unwrap_or(f64::NAN);
        }
        after |= b.line == 8;
    }
    assert_eq!(stream.diagnostics().errors(), 0, "{:?}", stream.diagnostics().to_vec());
    assert_eq!(moves, passes);
    assert!(after, "the line after the loop");
    assert!((last_x / MM - passes as f64 * 0.001).abs() < 1e-6, "{last_x}");
}

/// LinuxCNC's `#<_rpm>` is the S last set ("Return the current value of S, not the actual spindle
/// speed"), 0 before any: LinuxCNC 2.9.8's rs274 runs this program to X0, then X12 after S1200,
/// and `S[#<_rpm>+300]` sets 1500 (Y15), as here.
#[test]
fn linuxcnc_rpm_is_the_s_last_set() {
    let p = read("G21 G90 G17\nG0 X[#<_rpm>] Y0\nS1200 M3\nG1 X[#<_rpm>/100] F100\nS[#<_rpm>+300]\nG1 Y[#<_rpm>/100]\nM2\n", Dialect::Rs274, "t.ngc", &ReadOptions::default());
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    let ends: Vec<[f64; 2]> = end_points(&p).iter().map(|(_, a)| [a[0], a[1]]).collect();
    let rs274 = [[0.0, 0.0], [12.0, 0.0], [12.0, 15.0]];
    assert_eq!(ends.len(), rs274.len(), "{ends:?}");
    for (e, w) in ends.iter().zip(rs274) {
        assert!((e[0] - w[0]).abs() < 1e-9 && (e[1] - w[1]).abs() < 1e-9, "{ends:?}");
    }
}

/// Feed per revolution as LinuxCNC's interpreter reads it (`feed_per_rev.ngc`, rs274's output by
/// make_canon.sh, each feed move's feed times the spindle speed in force): `G95` with F per turn,
/// S changing the feed, an arc and a move of C alone under it, M70/M72 restoring G95, its F and
/// its S, F per turn in inches, and back to G94. The errors rs274 stops at are ours too.
#[test]
fn rs274_feeds_per_revolution_as_linuxcnc_does() {
    let dir = Path::new(env!("FIVEAXIS_ROOT")).join("recordings/programs/linuxcnc/parameters");
    let text = std::fs::read_to_string(dir.join("feed_per_rev.ngc")).unwrap();
    let p = read(&text, Dialect::Rs274, "feed_per_rev.ngc", &ReadOptions::default());
    let ours = same_places_as_linuxcnc(&p, &dir.join("feed_per_rev.canon"));
    // 0.2 mm/rev at S300; the move of C alone at 0.5 deg/rev at S600; after M72, 0.5 at S250.
    let feeds: Vec<f64> = ours.iter().filter_map(|m| m.3).collect();
    assert!(feeds.contains(&60.0) && feeds.contains(&300.0) && feeds.contains(&125.0), "{feeds:?}");
    // rs274: "Cannot do g1 with zero feed rate" after G94, "Cannot feed with zero spindle speed in
    // feed per rev mode" without S.
    refuses_each(
        Dialect::Rs274,
        &ReadOptions::default(),
        &[
            ("G21 G90\nS300 M3\nG95\nG1 X10 F0.2\nG94\nG1 X30\nM2\n", "6:1:", "without a feed"),
            ("G21 G90\nM3\nG95\nG1 X10 F0.2\nM2\n", "4:1:", "Cannot feed with zero spindle speed in feed per rev mode"),
        ],
    );
}
