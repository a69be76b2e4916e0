//! NC program readers: the paper's programs, their OCR-damaged copies, RS274NGC, Sinumerik,
//! Heidenhain conversational and CL data.

use std::path::Path;
use fiveaxis::program::{read, read_cl, read_heidenhain, read_rs274, Dialect, FeedMode, Motion, Orientation, Program, ReadOptions, Severity};
use fiveaxis::units::{DEG, MM};
use proptest::prelude::*;

const SING: &str = include_str!("../recordings/programs/SING.I");
const NON_SING: &str = include_str!("../recordings/programs/NON_SING.I");
const SING_OCR: &str = include_str!("../recordings/programs/damaged/SING_ocr.I");
const NON_SING_OCR: &str = include_str!("../recordings/programs/damaged/NON_SING_ocr.I");

fn errors(p: &Program) -> Vec<(usize, usize, String)> {
    p.diagnostics.iter().filter(|d| d.severity == Severity::Error).map(|d| (d.line, d.column, d.message.clone())).collect()
}

fn has(p: &Program, line: usize, column: usize, needle: &str) {
    assert!(
        errors(p).iter().any(|(l, c, m)| *l == line && *c == column && m.contains(needle)),
        "no error at {line}:{column} containing {needle:?}; errors: {:#?}",
        errors(p)
    );
}

#[test]
fn sing_program_reads_clean() {
    let p = read_heidenhain(SING);
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    assert_eq!(p.name.as_deref(), Some("SING"));
    let b = p.blocks.iter().find(|b| b.number == Some(360)).unwrap();
    assert_eq!(b.line, 41);
    assert_eq!(b.targets.x, Some(25.0 * MM));
    assert_eq!(b.targets.a, Some(1.0 * DEG));
    assert_eq!(b.targets.c, Some(180.0 * DEG));
    assert!(b.tcp, "M128 is on");
    assert_eq!(b.motion, Motion::Linear);
    assert_eq!(b.feed.unwrap().value_per_min, 2000.0);
    assert_eq!(b.feed.unwrap().mode, FeedMode::PerMinute);
    for (k, want) in [-30.489, -7.1, 38.054].into_iter().enumerate() {
        assert!((b.datum[k] - want * MM).abs() < 1e-15);
    }
    // M129 switches TCPM off; `N680 M05 M09*` (no space) is read with its events.
    assert!(!p.blocks.iter().find(|b| b.number == Some(650)).unwrap().tcp);
    assert_eq!(p.blocks.iter().find(|b| b.number == Some(680)).unwrap().events, vec!["M05", "M09"]);
    assert_eq!(p.blocks.iter().find(|b| b.number == Some(50)).unwrap().events, vec!["S12000", "M13"]);
    // The datum block shifts; it does not move.
    let g54 = p.blocks.iter().find(|b| b.number == Some(60)).unwrap();
    assert!(g54.targets.is_empty());
    // The end datum reset.
    assert_eq!(p.blocks.iter().find(|b| b.number == Some(700)).unwrap().datum, [0.0; 3]);
}

/// Every defect of the damaged SING copy, with line and column; the good blocks recover the program.
#[test]
fn damaged_sing_reports_each_defect_and_keeps_the_good_blocks() {
    let p = read_heidenhain(SING_OCR);
    has(&p, 52, 27, "expected a number after 'C', found '.L..'");
    has(&p, 52, 33, "two blocks run together");
    has(&p, 53, 1, "N470 repeats");
    has(&p, 53, 1, "N470 is out of order");
    assert_eq!(errors(&p).len(), 4, "{:#?}", errors(&p));
    // Never a damaged value read as a number: the damaged N470 is not used; N480 from the same
    // line is good and kept; order is recovered from the block numbers.
    let clean = read_heidenhain(SING);
    let targets = |p: &Program| p.blocks.iter().map(|b| (b.number, b.targets)).collect::<Vec<_>>();
    assert_eq!(targets(&p), targets(&clean));
}

#[test]
fn damaged_nonsing_reports_each_defect_and_keeps_the_good_blocks() {
    let p = read_heidenhain(NON_SING_OCR);
    has(&p, 1, 5, "program name 'NON SING' contains a space");
    has(&p, 48, 39, "block N440 begins before block N430 ended");
    has(&p, 65, 24, "number '162' without an address letter after A+23");
    has(&p, 65, 34, "number '198' without an address letter after C+386");
    has(&p, 66, 1, "N610 repeats the block on line 65");
    has(&p, 77, 13, "contains a space");
    assert_eq!(errors(&p).len(), 6, "{:#?}", errors(&p));
    assert!(!p.blocks.iter().any(|b| b.targets.a == Some(23.0 * DEG)), "A+23 of a split number was read");
    let clean = read_heidenhain(NON_SING);
    let targets = |p: &Program| p.blocks.iter().map(|b| (b.number, b.targets)).collect::<Vec<_>>();
    assert_eq!(targets(&p), targets(&clean));
}

#[test]
fn heidenhain_unsupported_words_and_arcs_are_reported() {
    // A word the reader does not model may change the motion (a Q parameter): an error, its block unused.
    let p = read_heidenhain("%T G71 *\nN10 G01 X+1 F100 *\nN15 X+2 Q5 *\nN20 G02 X+2 Y+3 *\nN30 X+3 *\n");
    has(&p, 3, 9, "Q5");
    // An arc with no centre before it (I J) and no R: refused where it stands.
    has(&p, 4, 1, "arc without a circle centre");
    assert_eq!(p.blocks.iter().map(|b| b.number).collect::<Vec<_>>(), vec![Some(10), Some(30)]);
    // The TNC's tool call `T1 G18` calls the tool along Y (G19: X): the tool axis is not the one
    // modelled, so it is refused at the plane code; `T1 G17` and a G18 of its own (the arc plane) read.
    let p = read_heidenhain("%T G71 *\nN10 T1 G18 S1000 *\nN20 T2 G19 *\nN30 T1 G17 S1000 *\nN40 G18 *\nN50 G01 X+1 F100 *\n");
    has(&p, 2, 8, "T with G18: a tool call along tool axis Y");
    has(&p, 3, 8, "T with G19: a tool call along tool axis X");
    assert_eq!(errors(&p).len(), 2, "{:?}", errors(&p));
}

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

/// Fanuc's program number (`O1234`, with its name as a comment, the first block of a program as
/// every Fanuc program opens) names the program and moves nothing; it is the same program without
/// it. An O word anywhere else (a second program number, LinuxCNC's `o100 sub` or `o100 call`) is
/// still refused where it stands.
#[test]
fn rs274_reads_fanucs_program_number() {
    let body = "G21 G90 G94\nG1 X0 Y0 Z10 F2000\nG1 X10 A5 C20\nM30\n";
    let plain = read_rs274(body);
    let numbered = read_rs274(&format!("%\nO1234 (SING TEST)\n{body}%\n"));
    assert!(errors(&numbered).is_empty() && numbered.diagnostics.is_empty(), "{:?}", numbered.diagnostics);
    assert_eq!(numbered.name.as_deref(), Some("O1234"));
    let targets = |p: &Program| p.blocks.iter().map(|b| (b.motion, b.targets.x, b.targets.a, b.targets.c, b.feed.map(|f| f.value_per_min))).collect::<Vec<_>>();
    assert_eq!(targets(&numbered), targets(&plain));
    assert_eq!(numbered.blocks.len(), 4);
    has(&read_rs274(&format!("O1234\n{body}O1235\n")), 6, 1, "unsupported word O1235");
    has(&read_rs274(&format!("{body}O1234\n")), 5, 1, "unsupported word O1234");
    has(&read_rs274(&format!("O1234 G1 X5\n{body}")), 1, 1, "unsupported word O1234");
    assert!(!errors(&read_rs274(&format!("o100 sub\n{body}"))).is_empty());
}

#[test]
fn rs274_defects_name_line_and_column() {
    let p = read_rs274("G1 X1 F100\nG1 X1.2.3 Y2\nG1 X2 (open comment\nG93 G1 X3\nG1 X$4\n");
    has(&p, 2, 4, "expected a number after 'X', found '1.2.3'");
    has(&p, 3, 7, "not closed");
    has(&p, 4, 1, "inverse-time");
    has(&p, 5, 4, "found '$4'");
    assert_eq!(p.blocks.len(), 1);
}

#[test]
fn cl_data_with_header_commas_and_feed() {
    let p = read_cl("x,y,z,i,j,k\n1, 2, 3, 0, 0, 1\n4 5 6 0 0.6 0.8 1500\n7 8 9 0 0 0\n1 2 3 0 0 x\n", 1000.0);
    assert_eq!(p.blocks.len(), 2);
    assert_eq!(p.blocks[0].feed.unwrap().value_per_min, 1000.0);
    assert_eq!(p.blocks[1].feed.unwrap().value_per_min, 1500.0);
    assert_eq!(p.blocks[1].targets.tool_axis, Some([0.0, 0.6, 0.8]));
    assert!(p.blocks.iter().all(|b| b.tcp));
    has(&p, 4, 7, "zero length");
    has(&p, 5, 11, "expected a number, found 'x'");
}

#[test]
fn dialect_detection() {
    let path = |p: &'static str| Some(std::path::Path::new(p));
    assert_eq!(Dialect::detect(None, SING), Dialect::Heidenhain);
    assert_eq!(Dialect::detect(None, "G1 X1 Y2\n"), Dialect::Rs274);
    assert_eq!(Dialect::detect(None, "1 2 3 0 0 1\n"), Dialect::Cl);
    // A comment header says nothing of the dialect (LinuxCNC's programs open with `;` and `(` lines
    // of prose; read from a pipe, there is no extension to go by).
    assert_eq!(Dialect::detect(None, "; made from SING.I by a script, for LinuxCNC\n(six words or more here)\nG21 G90 G94 G17 G40 G49\n"), Dialect::Rs274);
    assert_eq!(Dialect::detect(None, "# x y z i j k feed, every 0.1 mm\n1 2 3 0 0 1 2000\n"), Dialect::Cl);
    assert_eq!(Dialect::detect(None, "; Heidenhain DIN/ISO with a header comment\n%SING G71 *\nN10 G90 *\n"), Dialect::Heidenhain);
    assert_eq!(Dialect::detect(path("a.ngc"), ""), Dialect::Rs274);
    // Sinumerik by extension and by its own words, whatever the extension (.nc is everyone's).
    assert_eq!(Dialect::detect(path("a.MPF"), ""), Dialect::Sinumerik);
    assert_eq!(Dialect::detect(path("a.nc"), "N10 G1 X1 F100\nN20 TRAORI ; on\n"), Dialect::Sinumerik);
    assert_eq!(Dialect::detect(None, "G1 X1 A3=0 B3=0 C3=1 F100\n"), Dialect::Sinumerik);
    assert_eq!(Dialect::detect(path("a.nc"), "G1 X1 F100 ; TRAORI in a comment\n"), Dialect::Rs274);
    // Heidenhain conversational: recognised (also as .h, which DIN/ISO shares) and read as such.
    let klartext = "0 BEGIN PGM TEST MM\n1 BLK FORM 0.1 Z X+0 Y+0 Z-40\n2 L X+10 Y+5 R0 FMAX\n3 END PGM TEST MM\n";
    assert_eq!(Dialect::detect(path("test.h"), klartext), Dialect::Klartext);
    let p = read(klartext, Dialect::Klartext, "test.h", &ReadOptions::default());
    assert!(p.diagnostics.is_empty(), "{:#?}", p.diagnostics);
    assert_eq!(p.blocks.len(), 1);
    assert_eq!((p.blocks[0].motion, p.blocks[0].targets.x, p.blocks[0].number), (Motion::Rapid, Some(10.0 * MM), Some(2)));
}

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
    let p = read(text, Dialect::Klartext, "t.h", &ReadOptions::default());
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

#[test]
fn klartext_refuses_what_changes_the_motion_at_line_and_column() {
    let text = "0 BEGIN PGM BAD MM\n1 L X+0 Y+0 Z+0 R0 F100\n2 L X+5 RL\n3 APPR LT X+1 Y+1 LEN5 RL\n4 CYCL DEF 19.0 WORKING PLANE\n\
                5 PLANE SPATIAL SPA+0 SPB+45 SPC+0 TURN FMAX\n6 Q1 = Q2 + 3\n7 TOOL CALL 2 Z DL+0.5\n\
                8 FUNCTION TCPM F TCP AXIS SPAT PATHCTRL AXIS\n9 L X+1 M91\n10 L X+Q5\n11 CT X+9 Y+9\n12 LN X+1 Y+1 NX+0 NY+0 NZ+1\n\
                13 L X+7\n14 END PGM BAD MM\n";
    let p = read(text, Dialect::Klartext, "bad.h", &ReadOptions::default());
    has(&p, 3, 9, "RL: tool radius compensation");
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
    // Every good block is kept; none of the refused ones is.
    let numbers: Vec<u64> = p.blocks.iter().filter_map(|b| b.number).collect();
    assert_eq!(numbers, vec![1, 13]);
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

#[test]
fn sinumerik_reads_traori_vectors_frames_and_arcs() {
    let text = "; a Sinumerik 840D test program\nN10 G71 G90 G94 G17\nN20 T=\"MILL_10\" D1 S12000 M3\nN30 TRANS X10 Y-5 Z2\n\
                N40 TRAORI\nN50 G1 X=1 Y2 Z=-3 A3=0 B3=1 C3=1 F2000 ; 45 deg in Y Z\nN60 C3=1\nN70 ORIAXES\nN80 X5 A=10 C=20\n\
                N90 TRAFOOF\nN100 ATRANS X1\nN105 G1 X0 Y0\nN110 G2 X10 Y0 I5 J0\nN120 G3 X0 Y0 CR=5 TURN=1\nN130 M30\n";
    let p = read(text, Dialect::Sinumerik, "t.mpf", &ReadOptions::default());
    assert!(errors(&p).is_empty(), "{:#?}", errors(&p));
    let by = |n: u64| p.blocks.iter().find(|b| b.number == Some(n)).unwrap_or_else(|| panic!("block N{n}"));
    assert!(by(20).events.iter().any(|e| e.contains("MILL_10")));
    let b = by(50);
    assert!(b.tcp && b.orientation == Orientation::GreatCircle, "TRAORI on, ORIWKS/ORIVECT at reset");
    assert_eq!((b.targets.x, b.targets.z), (Some(1.0 * MM), Some(-3.0 * MM)));
    let h = 0.5f64.sqrt();
    let v = b.targets.tool_axis.unwrap();
    assert!((v[0]).abs() < 1e-15 && (v[1] - h).abs() < 1e-15 && (v[2] - h).abs() < 1e-15, "{v:?}");
    for (got, want) in b.datum.iter().zip([10.0, -5.0, 2.0]) {
        assert!((got - want * MM).abs() < 1e-15, "TRANS: {:?}", b.datum);
    }
    // A vector component not written is 0, not the previous one (840D: not modal).
    assert_eq!(by(60).targets.tool_axis, Some([0.0, 0.0, 1.0]));
    let b = by(80);
    assert_eq!(b.orientation, Orientation::AxisLinear, "ORIAXES switches");
    assert_eq!(b.targets.a, Some(10.0 * DEG));
    assert!(!by(105).tcp, "TRAFOOF");
    assert!((by(105).datum[0] - 11.0 * MM).abs() < 1e-15, "ATRANS adds to the frame: {:?}", by(105).datum);
    let arc = by(110).arc.expect("G2 with I J from the start");
    assert_eq!(by(110).motion, Motion::ArcCw);
    assert!((arc.centre[0] - 5.0 * MM).abs() < 1e-15 && arc.centre[1].abs() < 1e-15, "{:?}", arc.centre);
    let arc = by(120).arc.expect("G3 with CR=");
    assert_eq!(arc.extra_turns, 1, "TURN=1: one full turn more");
    // --orientation sets the control's start state.
    let told = ReadOptions { orientation: Some(Orientation::AxisLinear), ..Default::default() };
    assert_eq!(read(text, Dialect::Sinumerik, "t.mpf", &told).blocks.iter().find(|b| b.number == Some(50)).unwrap().orientation, Orientation::AxisLinear);
}

#[test]
fn sinumerik_refuses_what_changes_the_motion_and_is_not_modelled() {
    let text = "N10 G1 X1 F100\nN20 ROT Z45\nN30 CYCLE800(1,\"TC1\",0,57,0,0,0,0,0,0,0,0,0,1)\nN40 X=R1+5\nN50 G60 X2\n\
                N60 A3=0 B3=0 C3=1\nN70 RET\nN80 X=IC(5)\nN90 TRAORI\nN100 A3=0 B3=0 C3=0\nN110 X3 A3=0 B3=0 C3=1 C=5\nN120 ORICONCW\n";
    let p = read(text, Dialect::Sinumerik, "t.mpf", &ReadOptions::default());
    has(&p, 2, 5, "ROT");
    has(&p, 3, 5, "CYCLE800");
    has(&p, 4, 7, "R1 is read before this program sets it");
    has(&p, 5, 5, "exact stop");
    has(&p, 6, 1, "without TRAORI");
    has(&p, 7, 5, "subprogram calls");
    has(&p, 8, 7, "IC()");
    has(&p, 10, 6, "zero length");
    has(&p, 11, 1, "both a tool vector");
    has(&p, 12, 6, "cone");
    let used: Vec<_> = p.blocks.iter().filter(|b| !b.targets.is_empty()).map(|b| b.number).collect();
    assert_eq!(used, vec![Some(10)], "no refused block is used");
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]
    /// Arbitrary bytes never panic any reader, nor the sampler and analysis behind them.
    #[test]
    fn readers_never_panic_on_arbitrary_bytes(bytes in proptest::collection::vec(any::<u8>(), 0..400)) {
        let text = String::from_utf8_lossy(&bytes);
        let m = fiveaxis::machine::Machine::hermle_c600u();
        for d in [Dialect::Heidenhain, Dialect::Rs274, Dialect::Cl, Dialect::Sinumerik, Dialect::Klartext, Dialect::Fanuc, Dialect::Haas] {
            // A loop the noise makes ends within 20,000 lines run, not 4 million.
            let great = ReadOptions { orientation: Some(Orientation::GreatCircle), max_run_lines: 20_000, ..Default::default() };
            let p = read(&text, d, "fuzz", &great);
            let opts = fiveaxis::path::PathOptions { period: 0.05, ..Default::default() };
            let t = fiveaxis::path::Trajectory::from_program(&p, &m, &opts);
            let _ = fiveaxis::singularity::analyze(&t, &m, &Default::default());
        }
    }

    /// Expression-shaped noise: LinuxCNC's expressions with brackets, parameters, operators and function
    /// names cut in or out never panic the reader, and a refused line names a column on it.
    #[test]
    fn mutated_expressions_never_panic(cuts in proptest::collection::vec((0usize..3000, proptest::sample::select(EXPRESSION_NOISE.chars().collect::<Vec<_>>())), 0..16)) {
        let text = mutate(include_str!("../recordings/programs/linuxcnc/parameters/expressions.ngc"), cuts);
        let p = read_rs274(&text);
        for d in p.diagnostics.iter() {
            let line = text.lines().nth(d.line - 1).unwrap_or("");
            prop_assert!(d.column >= 1 && d.column <= line.chars().count() + 1, "{d:?} on {line:?}");
        }
    }

    /// Flow-shaped noise: Fanuc's macro statements and subprograms and the 840D's jumps and control
    /// structures, characters cut in, never panic their readers, and a defect names a column on its line.
    #[test]
    fn mutated_program_flow_never_panics(cuts in proptest::collection::vec((0usize..3000, proptest::sample::select(FLOW_NOISE.chars().collect::<Vec<_>>())), 0..12)) {
        for (original, d) in [(FANUC_FLOW, Dialect::Fanuc), (FANUC_FLOW, Dialect::Haas), (SINUMERIK_FLOW, Dialect::Sinumerik)] {
            let text = mutate(original, cuts.clone());
            let p = read(&text, d, "t", &ReadOptions { max_run_lines: 20_000, ..Default::default() });
            for e in p.diagnostics.iter() {
                let line = text.lines().nth(e.line - 1).unwrap_or("");
                prop_assert!(e.column >= 1 && e.column <= line.chars().count() + 1, "{d:?} {e:?} on {line:?}");
            }
        }
    }
}

/// A Fanuc program of every flow statement the reader runs, for the mutation test.
const FANUC_FLOW: &str = "%\nO0001\n#1=0\nWHILE [#1 LT 3] DO1\nG1 X[#1*10] F100.\n#1=#1+1\nEND1\nN10 #2=#1*2\nIF [#2 GT 100] GOTO 20\n#2=#2+50\nGOTO10\nN20 M98 P1000 L2\nG65 P1000 X1. Y2.\nIF [#1 EQ 3] THEN #3=1\nM97 P30\nM30\nN30 G1 Y1.\nM99\nO1000\nG91 G1 X1.\nM99 P40\nN40 G90\nM99\n%\n";
/// An 840D program of every jump and control structure the reader runs, for the mutation test.
const SINUMERIK_FLOW: &str = "DEF INT COUNT\nR1=0\nWHILE R1<3\nG1 X=R1*10 F100\nR1=R1+1\nENDWHILE\nFOR COUNT=1 TO 2\nIF COUNT==1\nG1 Y1\nELSE\nG1 Y2\nENDIF\nENDFOR\nMARK1: R2=R1\nREPEAT\nR2=R2-1\nUNTIL R2<=0\nIF R1<2 GOTOB MARK1\nGOTOF DONE\nLOOP\nENDLOOP\nDONE: M30\n";
/// Characters of program flow, for the mutation test.
const FLOW_NOISE: &str = "#[]=<>+-*/ .0123456789GOTIFWHLEDNMPXYRU:\n";

/// Characters of LinuxCNC's expressions, for the mutation test.
const EXPRESSION_NOISE: &str = "#[]<>=+-*/ .0123456789XYZACFGMOSINTAQRDE_";

/// `original` with the characters at `cuts` (positions taken modulo its length) replaced.
fn mutate(original: &str, cuts: Vec<(usize, char)>) -> String {
    let mut s: Vec<char> = original.chars().collect();
    for (at, c) in cuts {
        let at = at % s.len();
        s[at] = c;
    }
    s.into_iter().collect()
}

/// Plan a program on the Hermle, sample it (about 3000 samples, at least 1 ms apart) and analyze
/// it: its segment and sample counts.
fn plan_sample_analyze(p: &Program) -> (usize, usize) {
    let m = fiveaxis::machine::Machine::hermle_c600u();
    let (segments, _) = fiveaxis::path::plan(p, &m, &Default::default());
    let duration = segments.last().map_or(0.0, |s| s.t0 + s.duration);
    let opts = fiveaxis::path::PathOptions { period: (duration / 3000.0).max(1e-3), ..Default::default() };
    let t = fiveaxis::path::Trajectory::from_program(p, &m, &opts);
    let _ = fiveaxis::singularity::analyze(&t, &m, &Default::default());
    (segments.len(), t.sample_count())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]
    /// Program-shaped noise: mutations of the real program never panic and never invent blocks.
    /// (64 cases: each one plans and analyzes a whole program in a debug build.)
    #[test]
    fn mutated_programs_never_panic(cuts in proptest::collection::vec((0usize..2500, any::<char>()), 0..12)) {
        let p = read_heidenhain(&mutate(SING, cuts));
        prop_assert!(p.blocks.len() <= 75);
        // A mutated feed (F2 for F2000) stretches the program: keep the sample count bounded.
        let (_, samples) = plan_sample_analyze(&p);
        prop_assert!(samples <= 3100);
    }

    /// The same for the Sinumerik twin, whose tool vectors run on great circles (pieces refined near
    /// the pole): a mutated vector or axis word never panics and never makes unbounded pieces.
    #[test]
    fn mutated_sinumerik_programs_never_panic(cuts in proptest::collection::vec((0usize..5000, any::<char>()), 0..12)) {
        let text = mutate(include_str!("../recordings/programs/twins/SING_840d.mpf"), cuts);
        let p = read(&text, Dialect::Sinumerik, "fuzz.mpf", &ReadOptions::default());
        prop_assert!(p.blocks.len() <= 72);
        let (segments, _) = plan_sample_analyze(&p);
        prop_assert!(segments <= 72 * (1 << 16));
    }

    /// The same for the Klartext programs: the LN twin on great circles, and the contour with its
    /// arcs, repeats and subprogram (a mutated REP count or label never runs away).
    #[test]
    fn mutated_klartext_programs_never_panic(cuts in proptest::collection::vec((0usize..5000, any::<char>()), 0..12), contour in any::<bool>()) {
        let original = if contour {
            include_str!("../recordings/programs/twins/CONTOUR_tnc.h")
        } else {
            include_str!("../recordings/programs/twins/SING_tnc_ln.h")
        };
        let text = mutate(original, cuts);
        let great = ReadOptions { orientation: Some(Orientation::GreatCircle), ..Default::default() };
        let p = read(&text, Dialect::Klartext, "fuzz.h", &great);
        // Repeats at most REP 9 (one mutated digit) of the 8-block section, and at most 2 levels.
        prop_assert!(p.blocks.len() <= 75 + 8 * 9 * 10, "{} blocks", p.blocks.len());
        let _ = plan_sample_analyze(&p);
    }
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

/// Our reader's end points of every motion block in the block's program coordinates, as rs274 prints
/// them: an axis a block does not write stays where the machine is (mm, deg), so after a change of
/// work offset it reads anew.
fn end_points(p: &Program) -> Vec<(Motion, [f64; 6])> {
    let mut machine = [0.0; 6];
    let mut out = Vec::new();
    for b in p.blocks.iter().filter(|b| !b.targets.is_empty()) {
        let t = &b.targets;
        let datum = [b.datum[0], b.datum[1], b.datum[2], 0.0, 0.0, 0.0];
        for (k, v) in [t.x, t.y, t.z, t.a, t.b, t.c].into_iter().enumerate() {
            if let Some(v) = v {
                machine[k] = v + datum[k];
            }
        }
        let at: [f64; 6] = std::array::from_fn(|k| (machine[k] - datum[k]) / if k < 3 { MM } else { DEG });
        out.push((b.motion, at));
    }
    out
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

/// Canned cycles (G81, G82, G83, G73, G85 three times under G91, G86, G89; G98, G99) read in the
/// Haas dialect (L repeats, P seconds with a decimal point) make the moves LinuxCNC's own
/// interpreter makes of them (`cycles.ngc`/`.canon`), on a machine whose peck distances are
/// LinuxCNC's 0.254 mm; each dwell where LinuxCNC dwells.
#[test]
fn canned_cycles_move_as_linuxcnc_runs_them() {
    let dir = Path::new(env!("FIVEAXIS_ROOT")).join("recordings/programs/linuxcnc/parameters");
    let text = std::fs::read_to_string(dir.join("cycles.ngc")).unwrap();
    let file = fiveaxis::machine::builtin_file("haas-umc-750").unwrap().replace("g73_retract_mm = 2.54", "g73_retract_mm = 0.254").replace("g83_clearance_mm = 0.76", "g83_clearance_mm = 0.254");
    let machine = fiveaxis::machine::Machine::from_toml_str(&file, "t").unwrap();
    let p = read(&text, Dialect::Haas, "cycles.nc", &ReadOptions::default().on(&machine));
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    let ours = end_points(&p);
    let theirs = linuxcnc_canon("cycles.canon");
    assert_eq!(ours.len(), theirs.len(), "moves: ours {ours:#?}");
    for (k, ((m, a), (n, b))) in ours.iter().zip(&theirs).enumerate() {
        assert_eq!(m, n, "move {k}");
        assert!((0..6).all(|i| (a[i] - b[i]).abs() <= 0.5e-4 + 1e-9), "move {k}: ours {a:?}, LinuxCNC {b:?}");
    }
    let dwells: Vec<f64> = p.blocks.iter().filter_map(|b| b.dwell_s).collect();
    assert_eq!(dwells, [0.5, 0.2, 0.25]);
}

/// Fanuc's reference returns and machine coordinates on a machine whose file places them: `G91 G28
/// Z0` goes straight up to the reference point, `G28 X10 Y0` (G90) through the intermediate point,
/// `G53 G0 Z-5` to 5 mm below the machine zero; a number without a decimal point is in thousandths
/// of a mm (`X1500` is 1.5 mm); the leader before `%` is skipped; Fanuc's G04 P is milliseconds.
#[test]
fn fanuc_reference_returns_and_decimal_points() {
    let machine = fiveaxis::machine::Machine::builtin("mori-seiki-nmv5000").unwrap();
    let text = "NX listing header\nDate : today\n%\nO0001\nG21 G90 G17 G40\nG91 G28 Z0.\nG90 G0 X1500 Y2. Z3.\nG28 X10. Y0.\nG53 G0 Z-5.\nG04 P250\nM30\n%\ntrailer text\n";
    let p = read(text, Dialect::Fanuc, "t.nc", &ReadOptions::default().on(&machine));
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    let zero = machine.machine_coordinates.as_ref().unwrap().zero;
    let pts = end_points(&p);
    let mm = |v: f64| v * 1e3;
    // Z to the machine zero (program = machine point + zero, G54 taken as zero).
    assert_eq!(pts[0].0, Motion::Rapid);
    assert!((pts[0].1[2] - mm(zero.z)).abs() < 1e-9, "{pts:?}");
    assert!((pts[1].1[0] - 1.5).abs() < 1e-12 && (pts[1].1[1] - 2.0).abs() < 1e-12);
    // G28 X10 Y0: the intermediate point, then X and Y to the reference (Z stays).
    assert_eq!(&pts[2].1[..3], &[10.0, 0.0, 3.0]);
    assert!((pts[3].1[0] - mm(zero.x)).abs() < 1e-9 && (pts[3].1[1] - mm(zero.y)).abs() < 1e-9 && (pts[3].1[2] - 3.0).abs() < 1e-9, "{pts:?}");
    assert!((pts[4].1[2] - (mm(zero.z) - 5.0)).abs() < 1e-9);
    assert_eq!(p.blocks.iter().filter_map(|b| b.dwell_s).collect::<Vec<_>>(), [0.25]);
    assert!(p.diagnostics.iter().any(|d| d.line == 1 && d.message.contains("leader")));
    // Fanuc's P takes no decimal point; a peck cycle needs the machine's d.
    let p = read("%\nG21 G90\nG04 P1.5\n", Dialect::Fanuc, "t.nc", &ReadOptions::default().on(&machine));
    assert!(errors(&p).iter().any(|(l, _, m)| *l == 3 && m.contains("milliseconds")), "{:?}", errors(&p));
    let bare = fiveaxis::machine::builtin_file("mori-seiki-nmv5000").unwrap().replace("g83_clearance_mm = 0.1\n", "");
    let bare = fiveaxis::machine::Machine::from_toml_str(&bare, "t").unwrap();
    let p = read("%\nG21 G90 F100\nG0 Z10.\nG83 X0 Y0 Z-5. R1. Q2.\n", Dialect::Fanuc, "t.nc", &ReadOptions::default().on(&bare));
    assert!(errors(&p).iter().any(|(l, _, m)| *l == 4 && m.contains("No. 5115")), "{:?}", errors(&p));
    // Without machine coordinates, G28 cannot be placed.
    let p = read("%\nG21 G91 G28 Z0.\n", Dialect::Fanuc, "t.nc", &ReadOptions::default());
    assert!(errors(&p).iter().any(|(l, _, m)| *l == 2 && m.contains("machine_coordinates")), "{:?}", errors(&p));
}

/// What the reader cannot know is refused where it stands, and a damaged line sets nothing: a named
/// parameter read before it is set (LinuxCNC's error too), a numbered one (LinuxCNC reads 0, Fanuc
/// vacant), the machine's state (`#5221`, `#<_x>`), a division by zero, an unclosed bracket.
#[test]
fn rs274_refuses_parameters_it_cannot_know() {
    let body = |line: &str| format!("G21 G90 G94 F1000\n#<a> = 2\n{line}\nG1 X#<a>\nM2\n");
    for (line, col, what) in [
        ("G1 X#<b>", 5, "named parameter #<b> is not defined"),
        ("G1 X#7", 5, "#7 is read before the program sets it"),
        ("G1 X#5221", 5, "#5221 is a system parameter"),
        ("G1 X#<_X>", 5, "#<_x> is the interpreter's or the machine's state"),
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

/// Scratch: print the blocks of a program (development aid).
#[test]
#[ignore]
fn scratch_print_blocks() {
    let path = std::env::var("SCRATCH_PROGRAM").unwrap();
    let machine = fiveaxis::machine::load(&std::env::var("SCRATCH_MACHINE").unwrap()).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    let p = read(&text, Dialect::detect(Some(Path::new(&path)), &text), "s", &ReadOptions::default().on(&machine));
    for b in &p.blocks {
        let t = &b.targets;
        let f = |v: Option<f64>, u: f64| v.map_or("-".to_string(), |v| format!("{:.3}", v / u));
        eprintln!("{:>4} tcp={} x={} y={} z={} a={} b={} c={}", b.line, b.tcp, f(t.x, MM), f(t.y, MM), f(t.z, MM), f(t.a, DEG), f(t.b, DEG), f(t.c, DEG));
    }
    for d in &p.diagnostics {
        eprintln!("{d}");
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

/// LinuxCNC's O-word blocks fail closed: a block that never ends, an end of another name, a
/// `break` outside its loop, a call of a subroutine not defined before it, a condition that cannot
/// be read and an endless loop are each refused at their line, and nothing after them is read.
#[test]
fn rs274_o_word_defects_are_refused_where_they_stand() {
    let opts = ReadOptions::default();
    for (text, line, needle) in [
        ("G1 X1 F100\no1 while [1 LT 2]\nG1 X2\n", 2, "the program ends inside o1 while"),
        ("G1 X1 F100\no1 if [1]\nG1 X2\no2 endif\n", 4, "o2 endif ends no block: o1 if is open"),
        ("G1 X1 F100\no1 if [1]\no5 break\no1 endif\n", 3, "not inside a while or do loop of that name"),
        ("G1 X1 F100\no1 repeat [2]\no1 break\no1 endrepeat\n", 3, "not inside a while or do loop of that name"),
        ("G1 X1 F100\no<tool_change> call [3]\n", 2, "no subroutine o<tool_change> is defined before it"),
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
    has(&bad, 6, 3, "LP: expected the polar radius PR");
    let no_pole = read("0 BEGIN PGM P MM\n1 L X+10 Y+0 R0 F600\n2 LP PR+5 PA+0\n3 END PGM P MM\n", Dialect::Klartext, "p.h", &ReadOptions::default());
    has(&no_pole, 3, 3, "no pole CC");
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 192, ..ProptestConfig::default() })]
    /// O-word noise (block names, keywords, brackets) cut into `owords.ngc` never panics the flow, nor
    /// runs past its budget, and every diagnostic names a column on its line. The budget is the
    /// reader's option at 20,000 lines (the default's 4,000,000 runs the same code 200 times longer
    /// for each mutation that makes an endless loop).
    #[test]
    fn mutated_o_word_programs_never_panic(cuts in proptest::collection::vec((0usize..1800, proptest::sample::select("o0123456789<>[] \nwhiledorepatsubcl#".chars().collect::<Vec<_>>())), 0..14)) {
        let text = mutate(include_str!("../recordings/programs/linuxcnc/parameters/owords.ngc"), cuts);
        let budget = ReadOptions { max_run_lines: 20_000, ..ReadOptions::default() };
        let p = read(&text, Dialect::Rs274, "owords.ngc", &budget);
        prop_assert!(p.blocks.len() <= 20_000 + text.lines().count());
        for d in p.diagnostics.iter() {
            let line = text.lines().nth(d.line - 1).unwrap_or("");
            prop_assert!(d.column >= 1 && d.column <= line.chars().count() + 1, "{d:?} on {line:?}");
        }
    }

    /// Klartext's polar contours and M140 with their words cut and shuffled never panic.
    #[test]
    fn mutated_polar_klartext_never_panics(cuts in proptest::collection::vec((0usize..400, proptest::sample::select("LPCRAIMB+-.0123456789 \nDX".chars().collect::<Vec<_>>())), 0..12)) {
        let original = "0 BEGIN PGM P MM\n1 CC X+0 Y+0\n2 L X+10 Y+0 Z+0 R0 F600\n3 LP PR+20 PA+90\n4 CP PA+180 DR+\n5 CP IPA+720 Z-4 DR+\n6 LP IPR+5 IPA-90\n7 M140 MB MAX F500\n8 M140 MB+5\n9 END PGM P MM\n";
        let text = mutate(original, cuts);
        let m = fiveaxis::machine::Machine::hermle_c600u();
        let p = read(&text, Dialect::Klartext, "p.h", &ReadOptions::default().on(&m));
        let opts = fiveaxis::path::PathOptions { period: 0.05, ..Default::default() };
        let _ = fiveaxis::path::Trajectory::from_program(&p, &m, &opts);
    }
}
