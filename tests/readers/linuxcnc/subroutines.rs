//! RS274NGC subroutines as LinuxCNC runs them: defined after their call, Fanuc-style `M98`, their
//! arguments, named by an expression, in other files (`--subroutine-path`), and bounded in what one
//! block makes; each against LinuxCNC's own output.

use super::*;

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
