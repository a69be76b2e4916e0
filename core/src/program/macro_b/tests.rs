//! The macro runner as a control runs Fanuc and Haas programs: loops, branches, calls, the tape.

use super::super::{read, Dialect, Program, ReadOptions, Severity};

fn run(text: &str, dialect: Dialect, options: &ReadOptions) -> Program {
    read(text, dialect, "t.nc", options)
}


/// The X Y of each block that moves, mm.
fn points(p: &Program) -> Vec<(usize, f64, f64)> {
    p.blocks.iter().filter(|b| b.targets.x.is_some() || b.targets.y.is_some()).map(|b| (b.line, b.targets.x.unwrap_or(f64::NAN) * 1e3, b.targets.y.unwrap_or(f64::NAN) * 1e3)).collect()
}

fn near(a: f64, b: f64) -> bool {
    (a - b).abs() < 1e-9
}

/// A bolt circle by `WHILE [..] DO1` ... `END1`: six holes 60 deg apart on a 50 mm radius, the
/// positions computed here from the circle's definition.
#[test]
fn a_while_loop_runs_as_its_condition_says() {
    let text = "%\nO0001\n#1=0\nWHILE [#1 LT 6] DO1\nG1 X[50*COS[#1*60]] Y[50*SIN[#1*60]] F500.\n#1=#1+1\nEND1\nG0 X0. Y0.\nM30\n%\n";
    let p = run(text, Dialect::Fanuc, &ReadOptions::default());
    assert!(p.messages(Severity::Error).is_empty(), "{:#?}", p.messages(Severity::Error));
    let pts = points(&p);
    assert_eq!(pts.len(), 7, "{pts:?}");
    for (k, (line, x, y)) in pts[..6].iter().enumerate() {
        let a = (60.0 * k as f64).to_radians();
        assert!(*line == 5 && (x - 50.0 * a.cos()).abs() < 1e-9 && (y - 50.0 * a.sin()).abs() < 1e-9, "hole {k}: {pts:?}");
    }
    assert_eq!(pts[6].0, 8);
}

/// Fanuc's FIX and FUP round toward and away from zero (the custom macro manual's example: #2 =
/// -1.2, FUP[#2] = -2.0, FIX[#2] = -1.0), and AND, OR, XOR act on bits (Haas: `1 OR 2` is 3),
/// in macro statements and in words; LinuxCNC's FIX and FUP are floor and ceiling, its AND and
/// OR logical. A bit operation on a fraction is refused where it stands.
#[test]
fn fanucs_fix_fup_and_bit_operations() {
    let text = "#1=FIX[-1.6]\n#2=FUP[-1.2]\n#3=1 OR 2\n#4=7 AND 3\n#5=5 XOR 3\nG1 X#1 Y#2 Z#3 F100.\nG1 X#4 Y#5 Z[FIX[1.6]+FUP[1.2]]\nM30\n";
    for dialect in [Dialect::Fanuc, Dialect::Haas] {
        let p = run(text, dialect, &ReadOptions::default());
        assert!(p.messages(Severity::Error).is_empty(), "{:#?}", p.messages(Severity::Error));
        let xyz: Vec<[f64; 3]> = p.blocks.iter().filter(|b| b.targets.x.is_some()).map(|b| [b.targets.x, b.targets.y, b.targets.z].map(|v| v.unwrap() * 1e3)).collect();
        assert_eq!(xyz, vec![[-1.0, -2.0, 3.0], [3.0, 6.0, 3.0]], "{dialect:?}");
    }
    let linuxcnc = crate::program::read("G21 G1 X[FIX[-1.6]] Y[FUP[-1.2]] Z[1 OR 2] F100\nM2\n", Dialect::Rs274, "t.ngc", &ReadOptions::default());
    let b = linuxcnc.blocks.iter().find(|b| b.targets.x.is_some()).unwrap();
    assert_eq!([b.targets.x, b.targets.y, b.targets.z].map(|v| v.unwrap() * 1e3), [-2.0, -1.0, 1.0]);
    let p = run("#1=1.5 OR 2\nM30\n", Dialect::Fanuc, &ReadOptions::default());
    assert!(p.messages(Severity::Error).iter().any(|m| m.starts_with("1:") && m.contains("bits of whole numbers")), "{:#?}", p.messages(Severity::Error));
}

/// The macro alarm `#3000 = n` stops the control where it runs: refused there, as a setting of any
/// system variable (#1000 and up) is; a branch that skips it runs on.
#[test]
fn the_macro_alarm_stops_the_program_where_it_runs() {
    let p = run("#1=5.\nIF [#1 LT 3.] GOTO 10\n#3000=1 (TOO FEW)\nN10 G1 X#1 F100.\nM30\n", Dialect::Fanuc, &ReadOptions::default());
    assert!(p.messages(Severity::Error).iter().any(|m| m.starts_with("3:1:") && m.contains("macro alarm")), "{:#?}", p.messages(Severity::Error));
    assert!(points(&p).is_empty(), "nothing runs after the alarm: {:?}", points(&p));
    let p = run("#1=1.\nIF [#1 LT 3.] GOTO 10\n#3000=1 (TOO FEW)\nN10 G1 X#1 F100.\nM30\n", Dialect::Fanuc, &ReadOptions::default());
    assert!(p.messages(Severity::Error).is_empty(), "{:#?}", p.messages(Severity::Error));
    let p = run("#2=2001.\n#[#2]=0.5\nM30\n", Dialect::Haas, &ReadOptions::default());
    assert!(p.messages(Severity::Error).iter().any(|m| m.starts_with("2:1:") && m.contains("#2001 is a system variable")), "{:#?}", p.messages(Severity::Error));
}

/// A line a loop runs again is read once and evaluated on each pass: its values follow the
/// counter, and a value that fails on one pass only (a division by zero at #100 = 3) is that
/// pass's defect, at its line and column, while the passes before and after it move.
#[test]
fn a_line_run_again_is_evaluated_on_each_pass() {
    let text = "%\nO1000\nG21 G90 G94\nG1 F100.\n#100 = 0\nWHILE [#100 LT 5] DO1\nG1 X[10 / [3 - #100]] Y#100\n#100 = #100 + 1\nEND1\nM30\n%\n";
    let p = run(text, Dialect::Fanuc, &ReadOptions::default());
    let errors = p.messages(Severity::Error);
    assert_eq!(errors.len(), 1, "{errors:#?}");
    assert!(errors[0].starts_with("7:9:") && errors[0].contains("division by zero"), "{errors:#?}");
    let pts = points(&p);
    let want: Vec<(usize, f64, f64)> = [0.0, 1.0, 2.0, 4.0].iter().map(|k| (7, 10.0 / (3.0 - k), *k)).collect();
    assert_eq!(pts.len(), want.len(), "{pts:?}");
    for ((l, x, y), (wl, wx, wy)) in pts.iter().zip(&want) {
        assert!(l == wl && near(*x, *wx) && near(*y, *wy), "{pts:?}");
    }
}

/// `IF [..] GOTO n` back to a numbered block, `IF [..] THEN`, and a `GOTO` forward past blocks
/// that then never run.
#[test]
fn branches_go_to_their_numbered_blocks() {
    let text = "#1=1.\nN10 G1 X#1 F100.\n#1=#1+1.\nIF [#1 LE 3.] GOTO10\nIF [#1 EQ 4.] THEN #2=7.\nGOTO 30\nG1 X99.\nN30 G1 Y#2\nM30\n";
    let p = run(text, Dialect::Fanuc, &ReadOptions::default());
    assert!(p.messages(Severity::Error).is_empty(), "{:#?}", p.messages(Severity::Error));
    let pts = points(&p);
    let xs: Vec<f64> = pts.iter().filter(|p| p.0 == 2).map(|p| p.1).collect();
    assert_eq!(xs.len(), 3);
    assert!(near(xs[0], 1.0) && near(xs[1], 2.0) && near(xs[2], 3.0), "{xs:?}");
    assert!(!pts.iter().any(|p| p.0 == 7), "GOTO 30 skips line 7: {pts:?}");
    assert!(pts.iter().any(|p| p.0 == 8 && near(p.2, 7.0)), "{pts:?}");
}

/// `M98 P L` runs the file's subprogram after M30 L times (under G91: 10, 20, 30 mm), and the
/// subprogram's blocks never run as the main program's.
#[test]
fn a_subprogram_runs_where_it_is_called() {
    let text = "%\nO0001\nG90 G0 X0. Y0.\nM98 P1000 L3\nG90 G0 X0.\nM30\nO1000 (STEP)\nG91 G1 X10. F100.\nM99\n%\n";
    let p = run(text, Dialect::Fanuc, &ReadOptions::default());
    assert!(p.messages(Severity::Error).is_empty(), "{:#?}", p.messages(Severity::Error));
    let pts = points(&p);
    let lines: Vec<usize> = pts.iter().map(|p| p.0).collect();
    assert_eq!(lines, [3, 8, 8, 8, 5], "{pts:?}");
    assert!(near(pts[1].1, 10.0) && near(pts[2].1, 20.0) && near(pts[3].1, 30.0) && near(pts[4].1, 0.0), "{pts:?}");
}

/// `G65 P` with arguments: `X` is `#24`, `Y` `#25` (argument specification I), the macro's own,
/// gone after its return.
#[test]
fn a_macro_call_passes_its_arguments_as_locals() {
    let text = "G65 P9000 X5. Y7.\nG1 X#24\nM30\nO9000\nG1 X#24 Y#25 F100.\nM99\n";
    let p = run(text, Dialect::Fanuc, &ReadOptions::default());
    let pts = points(&p);
    assert!(pts.iter().any(|p| p.0 == 5 && near(p.1, 5.0) && near(p.2, 7.0)), "{pts:?}");
    let e = p.messages(Severity::Error);
    assert!(e.len() == 1 && e[0].starts_with("2:") && e[0].contains("#24"), "the caller has no #24: {e:#?}");
}

/// Haas' `M97 P n L`: the program's own blocks from `N n` (after M30), twice.
#[test]
fn haas_m97_runs_the_programs_own_blocks() {
    let text = "%\nO01234\nG90 G0 X0.\nM97 P100 L2\nM30\nN100 G91 G1 X1. F100.\nM99\n%\n";
    let p = run(text, Dialect::Haas, &ReadOptions::default());
    assert!(p.messages(Severity::Error).is_empty(), "{:#?}", p.messages(Severity::Error));
    let xs: Vec<f64> = points(&p).iter().map(|p| p.1).collect();
    assert_eq!(xs.len(), 3);
    assert!(near(xs[1], 1.0) && near(xs[2], 2.0), "{xs:?}");
    let p = run(text, Dialect::Fanuc, &ReadOptions::default());
    assert!(p.messages(Severity::Error).iter().any(|e| e.contains("M97 is Haas'")), "{:#?}", p.messages(Severity::Error));
}

/// What the flow cannot follow is refused at its place, and nothing after it is read.
#[test]
fn flow_defects_are_refused_where_they_stand() {
    for (text, at, needle) in [
        ("GOTO 20\nG1 X1.\nM30\n", "1:6:", "no block N20"),
        ("GOTO 20\nN20 G1 X1.\nN20 G1 X2.\nM30\n", "1:6:", "more than one block"),
        ("M98 P2000\nM30\n", "1:5:", "O2000 is not in this file"),
        ("G1 X1. M98 P2000\nM30\nO2000\nM99\n", "1:1:", "a block of its own"),
        ("END1\n", "1:1:", "END1 with no DO1"),
        ("WHILE [1 EQ 1] DO1\nWHILE [1 EQ 1] DO1\nEND1\nEND1\n", "2:1:", "nested loops take different numbers"),
        ("N1 G1 X1. F100.\nGOTO 1\n", "", "an endless loop"),
        ("M98 P12341000\nM30\n", "1:5:", "packed in P"),
        ("G66 P9000\n", "1:1:", "modal macro call"),
        ("WHILE [1 EQ 0] DO1\nG1 X1.\n", "1:1:", "whose END1 never comes"),
        ("WHILE [1 EQ 1] DO1\nG1 X1. F100.\n", "1:1:", "ends inside the loop DO1"),
        ("M 98 P2000\nM30\n", "1:6:", "O2000 is not in this file"),
    ] {
        let options = ReadOptions { max_run_lines: 1000, ..ReadOptions::default() };
        let p = run(text, Dialect::Fanuc, &options);
        let e = p.messages(Severity::Error);
        assert!(e.iter().any(|m| m.starts_with(at) && m.contains(needle)), "{text:?}: {e:#?}");
    }
    // M99 in the main program: read once, said.
    let p = run("G1 X1. F100.\nM99\n", Dialect::Fanuc, &ReadOptions::default());
    assert!(p.messages(Severity::Error).is_empty() && p.diagnostics.iter().any(|d| d.message.contains("read once")));
}

/// A branch taken again goes where it went without searching again: 5,000 turns of a loop before
/// 2,000 lines run within a bound (14,000 lines beyond the program's own) that a search per turn
/// (2,000 lines each) would pass many times over.
#[test]
fn a_branch_taken_again_does_not_search_again() {
    let mut text = String::from("#1=0\nN10 #1=#1+1\nIF [#1 LT 5000] GOTO10\n");
    text.push_str(&"G1 X1. F100.\n".repeat(2000));
    text.push_str("M30\n");
    let p = run(&text, Dialect::Fanuc, &ReadOptions { max_run_lines: 14_000, ..ReadOptions::default() });
    assert!(p.messages(Severity::Error).is_empty(), "{:#?}", p.messages(Severity::Error));
    assert_eq!(points(&p).len(), 2000);
}

/// A program whose only `%` ends it, after more lines than a tape's leader holds: every line is
/// run as the flow says, the first ones too (its M97 calls its blocks after M30, which run once).
#[test]
fn a_long_program_without_a_leading_percent_runs_its_flow() {
    let mut text = String::from("O01234\nM97 P100\n");
    text.push_str(&"G1 X1. F100.\n".repeat(80));
    text.push_str("M30\nN100 G1 Y5. F100.\nM99\n%\n");
    let p = run(&text, Dialect::Haas, &ReadOptions::default());
    assert!(p.messages(Severity::Error).is_empty(), "{:#?}", p.messages(Severity::Error));
    let pts = points(&p);
    assert_eq!(pts.len(), 81);
    assert!(pts[0].0 == 84 && near(pts[0].2, 5.0), "{:?}", pts[0]);
}

/// A short program whose only `%` is the file's last line: the `%` ends the tape, and the lines
/// before it are the program, not a leader (a leader is skipped only when a program follows).
#[test]
fn a_lone_percent_at_the_end_is_the_tape_end_not_a_leaders() {
    for dialect in [Dialect::Fanuc, Dialect::Haas] {
        let p = run("O1001\n(FACE)\nG0 X10. Y5.\nG1 X20. F200.\nM30\n%\n\n", dialect, &ReadOptions::default());
        assert!(p.messages(Severity::Error).is_empty(), "{:#?}", p.messages(Severity::Error));
        assert!(p.diagnostics.iter().all(|d| !d.message.contains("leader")), "{:#?}", p.diagnostics);
        let pts = points(&p);
        assert_eq!(pts.len(), 2, "{pts:?}");
        assert!(pts[0].0 == 3 && near(pts[1].1, 20.0), "{pts:?}");
        // With a program after it, the same `%` opens the tape: what came before is skipped.
        let p = run("NX LISTING\nG1 X99.\n%\nO1001\nG1 X20. F200.\nM30\n%\n", dialect, &ReadOptions::default());
        let pts = points(&p);
        assert!(pts.len() == 1 && near(pts[0].1, 20.0), "{pts:?}");
        assert!(p.diagnostics.iter().any(|d| d.message.contains("tape's leader")), "{:#?}", p.diagnostics);
    }
}

/// The program ends at M30: what follows it runs only when called.
#[test]
fn nothing_after_m30_runs_uncalled() {
    let p = run("G1 X1. F100.\nM30\nG1 X2.\n", Dialect::Fanuc, &ReadOptions::default());
    assert_eq!(points(&p).len(), 1, "{:?}", points(&p));
}
