//! NC program readers: the paper's programs, their OCR-damaged copies, RS274NGC, Sinumerik,
//! Heidenhain conversational and CL data.

use std::path::Path;
use fiveaxis::program::{read, read_cl, read_heidenhain, read_rs274, Dialect, FeedMode, Motion, Orientation, Program, ReadOptions, Severity};
use fiveaxis::units::{DEG, MM};
use proptest::prelude::*;

mod fanuc;
mod fanuc_corners;
mod fanuc_cycles;
mod fanuc_macro;
mod fanuc_nurbs;
mod fanuc_offsets;
mod feed_per_rev;
mod feed_units;
mod klartext;
mod lasting;
mod linuxcnc;
mod linuxcnc_words;
mod shop_words;
mod sinumerik_corners;
mod sinumerik_trc;
mod tnc_comp;
mod tnc_corners;
mod tnc_cycles;
mod tnc_held;
mod tnc_spline;
mod tnc_words;

const SING: &str = include_str!("../recordings/programs/SING.I");
const NON_SING: &str = include_str!("../recordings/programs/NON_SING.I");
const SING_OCR: &str = include_str!("../recordings/programs/damaged/SING_ocr.I");
const NON_SING_OCR: &str = include_str!("../recordings/programs/damaged/NON_SING_ocr.I");

/// Where each move ends in the frame without work offsets (mm, X Y Z): the block's target plus its
/// datum, an axis not written staying where it was.
fn ends(p: &Program) -> Vec<[f64; 3]> {
    let mut at = [0.0; 3];
    p.blocks
        .iter()
        .filter(|b| !b.targets.is_empty())
        .map(|b| {
            for (k, v) in [b.targets.x, b.targets.y, b.targets.z].into_iter().enumerate() {
                if let Some(v) = v {
                    at[k] = (v + b.datum[k]) / MM;
                }
            }
            at
        })
        .collect()
}

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

/// Each program of `cases` read in `dialect` with `options` has an error at its `line:col:`
/// containing its text.
fn refuses_each(dialect: Dialect, options: &ReadOptions, cases: &[(&str, &str, &str)]) {
    for (text, at, needle) in cases {
        let p = read(text, dialect, "t", options);
        let (l, c) = at.trim_end_matches(':').split_once(':').unwrap();
        has(&p, l.parse().unwrap(), c.parse().unwrap(), needle);
    }
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
    let p = read_heidenhain("%T G71 *\nN10 T1 G18 S1000 *\nN20 T2 G19 *\nN30 T1 G17 S1000 *\nN40 G18 *\nN50 G01 X+1 F100 *\nN99999999 %T G71 *\n");
    has(&p, 2, 8, "T with G18: a tool call along tool axis Y");
    has(&p, 3, 8, "T with G19: a tool call along tool axis X");
    assert_eq!(errors(&p).len(), 2, "{:?}", errors(&p));
}

/// Fanuc's program number (`O1234`, with its name as a comment, the first block of a program as
/// every Fanuc program opens) names the program and moves nothing; it is the same program without
/// it. An O number alone later is LinuxCNC's Fanuc-style program start, run through; an O word with
/// a block's words after it, or an `o100 sub` that never ends, is still refused.
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
    // An O number alone later (LinuxCNC's Fanuc-style program start) is a title the program runs
    // on through: rs274 makes the same two moves of these (its own tests/interp m98m99 12 and 13).
    for text in [format!("O1234\nG21\nO1235\n{body}"), format!("G21\nO1234\n{body}"), format!("O<named>\n{body}")] {
        let p = read_rs274(&text);
        assert!(errors(&p).is_empty(), "{:?}", errors(&p));
        assert_eq!(end_points(&p), end_points(&plain));
    }
    has(&read_rs274(&format!("O1234 G1 X5\n{body}")), 1, 1, "unsupported word O1234");
    assert!(!errors(&read_rs274(&format!("o100 sub\n{body}"))).is_empty());
}

#[test]
fn rs274_defects_name_line_and_column() {
    let p = read_rs274("G1 X1 F100\nG1 X1.2.3 Y2\nG1 X2 (open comment\nG93 G1 X3\nG1 X$4\n/2 G1 X5\n");
    has(&p, 2, 4, "expected a number after 'X', found '1.2.3'");
    has(&p, 3, 7, "not closed");
    has(&p, 4, 1, "inverse-time");
    has(&p, 5, 4, "found '$4'");
    // A numbered block delete (Fanuc's optional block skip 2-9) is not read: refused, not run.
    has(&p, 6, 1, "block delete level '/2' is not read");
    assert_eq!(p.blocks.len(), 1);
    // A word written twice (LinuxCNC: "Multiple X words on one line"): refused in every G-code
    // dialect, where the last one had silently counted.
    for (dialect, name) in [(Dialect::Rs274, "t.ngc"), (Dialect::Fanuc, "t.nc"), (Dialect::Haas, "t.nc"), (Dialect::Sinumerik, "t.mpf")] {
        let p = read("G90 G1 X10. F60.\nX20. Y5. X30.\nM30\n", dialect, name, &ReadOptions::default());
        has(&p, 2, 10, "X written twice in one block");
    }
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
    // The 840D's transfer header and its variable definitions, in a shop's `.nc` file (EdytorNC's
    // example: `%_N_SINUMERIK840D_MPF`, `DEF REAL WYSPAD`).
    assert_eq!(Dialect::detect(path("a.nc"), "%_N_SINUMERIK840D_MPF\n;$PATH=/_N_MPF_DIR\nN10 G0 X0\n"), Dialect::Sinumerik);
    assert_eq!(Dialect::detect(path("a.nc"), "N10 DEF REAL WYSPAD=20\nN20 G0 X0\n"), Dialect::Sinumerik);
    assert_eq!(Dialect::detect(path("a.nc"), "def int cnt\nG0 X0\n"), Dialect::Sinumerik);
    // Not a definition: LinuxCNC's named parameter and a comment.
    assert_eq!(Dialect::detect(path("a.nc"), "#<def> = 1\n(DEF REAL in a comment)\nG0 X0\n"), Dialect::Rs274);
    assert_eq!(Dialect::detect(path("a.nc"), "N10 DEFINE X\nG0 X0\n"), Dialect::Rs274);
    // Heidenhain conversational: recognised (also as .h, which DIN/ISO shares) and read as such.
    let klartext = "0 BEGIN PGM TEST MM\n1 BLK FORM 0.1 Z X+0 Y+0 Z-40\n2 L X+10 Y+5 R0 FMAX\n3 END PGM TEST MM\n";
    assert_eq!(Dialect::detect(path("test.h"), klartext), Dialect::Klartext);
    let p = read(klartext, Dialect::Klartext, "test.h", &ReadOptions::default());
    assert!(p.diagnostics.is_empty(), "{:#?}", p.diagnostics);
    assert_eq!(p.blocks.len(), 1);
    assert_eq!((p.blocks[0].motion, p.blocks[0].targets.x, p.blocks[0].number), (Motion::Rapid, Some(10.0 * MM), Some(2)));
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
    let arc = by(110).arc.as_deref().copied().expect("G2 with I J from the start");
    assert_eq!(by(110).motion, Motion::ArcCw);
    assert!((arc.centre[0] - 5.0 * MM).abs() < 1e-15 && arc.centre[1].abs() < 1e-15, "{:?}", arc.centre);
    let arc = by(120).arc.as_deref().copied().expect("G3 with CR=");
    assert_eq!(arc.extra_turns, 1, "TURN=1: one full turn more");
    // --orientation sets the control's start state.
    let told = ReadOptions { orientation: Some(Orientation::AxisLinear), ..Default::default() };
    assert_eq!(read(text, Dialect::Sinumerik, "t.mpf", &told).blocks.iter().find(|b| b.number == Some(50)).unwrap().orientation, Orientation::AxisLinear);
}

#[test]
fn sinumerik_refuses_what_changes_the_motion_and_is_not_modelled() {
    // (A refused CYCLE800 holds every later move: it comes last.)
    let text = "N10 G1 X1 F100\nN20 ROT C45\nN30 G1 Y=R9\nN40 X=R1+5\nN50 G42 X2\n\
                N60 A3=0 B3=0 C3=1\nN70 EXTCALL(\"SUB\")\nN80 X=DC(5)\nN90 TRAORI\nN100 A3=0 B3=0 C3=0\nN110 X3 A3=0 B3=0 C3=1 C=5\nN120 ORICONCW\n/1 N130 X4\n\
                N140 CYCLE800(1,\"TC1\",0,57,0,0,0,0,0,0,0,0,0,1)\n";
    let p = read(text, Dialect::Sinumerik, "t.mpf", &ReadOptions::default());
    has(&p, 2, 9, "ROT block");
    has(&p, 3, 10, "R9 is read before this program sets it");
    has(&p, 14, 6, "CYCLE800");
    has(&p, 4, 7, "R1 is read before this program sets it");
    has(&p, 5, 5, "no tool was loaded");
    has(&p, 6, 1, "without TRAORI");
    has(&p, 7, 5, "this call of another program is not read");
    has(&p, 8, 7, "DC");
    has(&p, 10, 6, "zero length");
    has(&p, 11, 1, "both a tool vector");
    has(&p, 12, 6, "cone");
    has(&p, 13, 1, "block skip level '/1' is not read");
    let used: Vec<_> = p.blocks.iter().filter(|b| !b.targets.is_empty()).map(|b| b.number).collect();
    assert_eq!(used, vec![Some(10)], "no refused block is used");
}

/// The 840D's spline and polynomial modes (`BSPLINE`, `ASPLINE`, `CSPLINE`, `POLY`) are modal motions
/// of G group 1 (Job Planning, "Spline interpolation"): each is refused naming what it is (not as a
/// call of a program named BSPLINE), and the moves after it that give no G0-G3 of their own are
/// refused, naming it, instead of being read as straight lines. A `CIP` (read) from where a spline
/// left the tool is refused as any move from there, and the moves after it are refused naming it;
/// a `CT` (read) after refused lines has no tangent to leave along, and governs the moves after it
/// as well.
#[test]
fn sinumerik_splines_and_cip_are_refused_with_the_moves_they_govern() {
    let text = "G71 G90 G94\nG0 X0 Y0 Z100\nBSPLINE\nX10 Y5 F1000\nG1 X20 Y0\nCIP X30 Y15 I1=25 J1=10\nX40\nG1 X0\nCT X40 Y0\nX50\nG0 X60 Y0\nG0 X70\nM30\n";
    let p = read(text, Dialect::Sinumerik, "t.mpf", &ReadOptions::default());
    has(&p, 3, 1, "BSPLINE: spline or polynomial interpolation is not read");
    has(&p, 4, 1, "without a motion mode");
    has(&p, 4, 1, "line 3 was refused");
    has(&p, 6, 5, "under line 3's BSPLINE");
    has(&p, 7, 1, "line 6 was refused");
    has(&p, 9, 1, "CT: no contour element in the working plane before it");
    has(&p, 8, 4, "under line 6's CIP");
    has(&p, 10, 1, "line 9 was refused");
    assert!(!p.diagnostics.iter().any(|d| d.message.contains("subprogram")), "{:?}", p.diagnostics);
    // Only the blocks with their own G0 or G1 (and a feed) move, once X and Y (which the control's
    // spline and circles moved) are written absolute again: X0 Y0 Z100; G1 X20 Y0 (F1000 came from a
    // refused line), G1 X0 and G0 X60 Y0 start where the curves left the tool, refused; G0 X70.
    let xs: Vec<f64> = p.blocks.iter().filter_map(|b| b.targets.x).map(|x| x / MM).collect();
    assert_eq!(xs, [0.0, 70.0], "{:?}", errors(&p));
    has(&p, 11, 4, "from where the moves under line 9's CT");
    has(&p, 5, 1, "without a feed");
}

/// LinuxCNC's splines `G5`, `G5.1`, `G5.2` (and Fanuc's 3D circle `G02.4`) are motions of modal group
/// 1: refused, they leave the motion mode unknown, so the move after one that gives no G code of
/// its own is refused naming it, not read as a line of the mode before (`G1`). The control made the
/// spline: the moves after it are refused until the axes it names (X Y) are written absolute.
#[test]
fn refused_spline_modes_govern_the_moves_after_them() {
    let text = "G21 G90 G17\nG0 X0 Y0 Z10\nG1 F500 X1\nG5 X10 Y10 I5 J0 P5 Q0\nX20 Y0\nG1 X2\nG1 X2 Y0\nX3\nM2\n";
    let p = read(text, Dialect::Rs274, "t.ngc", &ReadOptions::default());
    has(&p, 4, 1, "G5 (spline or NURBS motion) is not supported");
    has(&p, 5, 1, "without a motion mode");
    has(&p, 5, 1, "line 4 was refused");
    has(&p, 6, 4, "once X and Y are written absolute");
    has(&p, 7, 4, "once Y is written absolute");
    let xs: Vec<f64> = p.blocks.iter().filter_map(|b| b.targets.x).map(|x| x / MM).collect();
    assert_eq!(xs, [0.0, 1.0, 3.0], "X20 is not a line; G1 X2 sets the mode again, from where the spline left the tool");
    let text = "%\nG21 G90 G17 G0 X0. Y0. Z10.\nG1 F500. X1.\nG02.4 X10. Y10. Z0.\nX5. Y2. Z1.\nM30\n%\n";
    let p = read(text, Dialect::Fanuc, "t.nc", &ReadOptions::default());
    has(&p, 5, 1, "line 4 was refused");
    assert!(!errors(&p).iter().any(|(_, _, m)| m.contains("power-on")), "{:?}", errors(&p));
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

/// Fanuc chamfers and corner R between lines and arcs, for the mutation test.
const FANUC_CORNERS: &str = "%\nO0001\nG90 G17 G21 G94\nG00 X10. Y10.\nG01 X50. F100. ,C5.\nY25. ,R8.\nG03 X80. Y55. R30. ,R8.\nG01 X50. ,R8.\nY70. ,C5.\nX10. ,C5.\nG04 P1.\nY10. ,R2.\nG02 X0. Y0. R10. ,C1.\nG01 Y-10.\nM30\n%\n";
/// Characters of chamfers and corner R, for the mutation test.
const CORNER_NOISE: &str = ",CRAXYGF.-0123456789 #[]\n";

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

    /// Chamfer- and corner-shaped noise in a Fanuc and a Haas contour: never a panic, a column on
    /// the defect's line, and the plan and samples bounded.
    #[test]
    fn mutated_fanuc_corners_never_panic(cuts in proptest::collection::vec((0usize..3000, proptest::sample::select(CORNER_NOISE.chars().collect::<Vec<_>>())), 0..12)) {
        let text = mutate(FANUC_CORNERS, cuts);
        for d in [Dialect::Fanuc, Dialect::Haas] {
            let p = read(&text, d, "t", &ReadOptions { max_run_lines: 20_000, ..Default::default() });
            for e in p.diagnostics.iter() {
                let line = text.lines().nth(e.line - 1).unwrap_or("");
                prop_assert!(e.column >= 1 && e.column <= line.chars().count() + 1, "{d:?} {e:?} on {line:?}");
            }
            prop_assert!(p.blocks.len() <= 40);
            let _ = plan_sample_analyze(&p);
        }
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
        eprintln!("{:>4} tcp={} x={} y={} z={} a={} b={} c={} datum={:?}", b.line, b.tcp, f(t.x, MM), f(t.y, MM), f(t.z, MM), f(t.a, DEG), f(t.b, DEG), f(t.c, DEG), b.datum.map(|d| d / MM)); eprintln!("      feed={:?} arc={:?}", b.feed, b.arc);
    }
    for d in &p.diagnostics {
        eprintln!("{d}");
    }
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

/// What `program analyze --json` reports of a program, on a machine.
fn analyze_json(text: &str, ext: &str, machine: &str) -> serde_json::Value {
    let path = std::env::temp_dir().join(format!("fiveaxis-feed-{}-{}-{}.{ext}", std::process::id(), text.len(), text.bytes().map(u64::from).sum::<u64>()));
    std::fs::write(&path, text).unwrap();
    let out = std::process::Command::new(env!("FIVEAXIS_EXE")).args(["program", "analyze", path.to_str().unwrap(), "--machine", machine, "--json"]).output().unwrap();
    std::fs::remove_file(&path).ok();
    assert!(out.status.success(), "{text:?}: {}", String::from_utf8_lossy(&out.stderr));
    serde_json::from_slice::<serde_json::Value>(&out.stdout).unwrap()
}

/// The cycle time `program analyze` gives a program (s), on a machine.
fn cycle_time_s(text: &str, ext: &str, machine: &str) -> f64 {
    analyze_json(text, ext, machine)["cycle_time_s"].as_f64().unwrap()
}

/// A UTF-8 byte-order mark before the first line (some editors write one) is the file's encoding:
/// each dialect's program reads with it as without it, its dialect guessed the same (a Klartext `.h`
/// with one was taken for DIN/ISO), and a Fanuc tape's `%` behind it still opens the tape.
#[test]
fn a_byte_order_mark_is_the_files_encoding_in_every_dialect() {
    for (dialect, ext, machine, text) in [
        (Dialect::Klartext, "h", "dmg-dmu-50", "0 BEGIN PGM T MM\n1 TOOL CALL 1 Z S5000\n2 L X+0 Y+0 Z+10 R0 FMAX\n3 L X+10 F600\n4 END PGM T MM\n"),
        (Dialect::Sinumerik, "mpf", "spinner-u5-620", "G90 G71\nG0 X0 Y0 Z10\nG1 X10 F600\nM30\n"),
        (Dialect::Fanuc, "nc", "mori-seiki-nmv5000", "%\nO1000\nG21 G90 G17\nG0 X0. Y0. Z10.\nG1 X10. F600.\nM30\n%\n"),
        (Dialect::Rs274, "ngc", "linuxcnc-xyzac-trt", "G21 G90\nG0 X0 Y0 Z10\nG1 X10 F600\nM2\n"),
    ] {
        let marked = format!("\u{feff}{text}");
        let control = fiveaxis::machine::Machine::builtin(machine).unwrap().dialect;
        let name = format!("t.{ext}");
        assert_eq!(Dialect::detect_for(Some(Path::new(&name)), &marked, control), dialect, "{ext}");
        let p = read(&marked, dialect, &name, &ReadOptions::default());
        assert!(errors(&p).is_empty() && p.diagnostics.iter().all(|d| !d.message.contains("leader")), "{ext}: {:#?}", p.diagnostics);
        assert_eq!(end_points(&p), end_points(&read(text, dialect, &name, &ReadOptions::default())), "{ext}");
        // Through the command, which streams the file: the 10 mm at F600 take 1 s of it.
        let (with, without) = (cycle_time_s(&marked, ext, machine), cycle_time_s(text, ext, machine));
        assert!(with == without && with >= 1.0, "{ext}: {with} s with the mark, {without} s without");
    }
    // A jump back to the first line finds its N number behind the mark: X10, then (G91) X20, 10 mm
    // each at F600, 2 s (the G91 tells the second pass from the first: #4003, group 03).
    let text = "N1 G1 X10. F600.\nIF [#4003 EQ 91] GOTO 9\nG91\nGOTO 1\nN9 M30\n";
    let (with, without) = (cycle_time_s(&format!("\u{feff}{text}"), "nc", "mori-seiki-nmv5000"), cycle_time_s(text, "nc", "mori-seiki-nmv5000"));
    assert!((with - 2.0).abs() < 1e-9 && with == without, "{with} s with the mark, {without} s without");
}

/// A block shorter than the 1 ms sample period is seen: C turns 170 deg in a block of 0.005 mm at
/// F2000 near A = 0 (0.15 ms), which asks 170/360 rev in 0.005/2000 min = 188,889 rpm of C, by hand;
/// it had fallen between two samples (peak 2.8 rpm elsewhere, no region), or not, as the program's
/// start shifted the sample grid. Each such block is now evaluated once at its middle.
#[test]
fn a_block_between_two_samples_is_still_seen() {
    let want = 170.0 / 360.0 / (0.005 / 2000.0);
    for dz in ["50", "50.3", "50.6"] {
        let text = format!("G21 G90 G94\nG0 X0 Y0 Z{dz} A3 C0\nG1 X10 A1 C0 F2000\nG1 X19.5 A0.3 C0\nG1 X19.505 A0.3 C170\nG1 X30 A2 C175\nG1 X40 A10 C180\nM2\n");
        let r = analyze_json(&text, "ngc", "hermle-c600u");
        let peak = r["peak_c_speed_rpm"].as_f64().unwrap();
        assert!((peak - want).abs() < 1e-3 * want, "Z{dz}: peak {peak} rpm, want {want}");
        assert_eq!(r["peak_c_speed_line"], 5, "Z{dz}");
        let lines: Vec<(u64, u64)> = r["regions"].as_array().unwrap().iter().map(|g| (g["line_start"].as_u64().unwrap(), g["line_end"].as_u64().unwrap())).collect();
        assert!(lines.iter().any(|&(a, b)| a <= 5 && 5 <= b), "Z{dz}: regions {lines:?}");
    }
}

/// What a Fanuc control reads and this reader does not is refused with the control's own name for
/// it: a dwell written `G04 X` (seconds on Fanuc, where P is milliseconds), the vacant variable
/// `#0`, a G65 argument given twice (argument specification II).
#[test]
fn fanuc_forms_not_read_are_named_as_the_control_names_them() {
    let fanuc = |text: &str| read(text, Dialect::Fanuc, "t.nc", &ReadOptions::default());
    has(&fanuc("G21 G90\nG04 X1\nM30\n"), 2, 5, "a dwell written with X is read on FANUC only in seconds with a decimal point");
    has(&fanuc("#4=#0+1\nM30\n"), 1, 4, "Fanuc's #0 is its vacant variable");
    has(&fanuc("G65 P2 I1. J2. K3. I4.\nM30\nO0002\nM99\n"), 1, 20, "I given twice in a G65 call (argument specification II)");
    // A variable number past LinuxCNC's 5602 is a Fanuc control's (its addresses take eight
    // digits): refused as the control's variable, set or read, not as a number out of range.
    has(&fanuc("#901200=1.\nM30\n"), 1, 1, "#901200 is a system variable of the control");
    has(&fanuc("#1=900000\nG1 X#[#1+1200] F100.\nM30\n"), 2, 5, "#901200 is a system variable of the control");
    has(&fanuc("#1=100000000\nG1 X#[#1] F100.\nM30\n"), 2, 5, "a variable number must be a whole number 1 to 99999999");
    has(&read_rs274("G21\n#6000=1\nM2\n"), 2, 1, "a parameter number must be a whole number 1 to 5602");
    // Axis words before any G00/G01: the power-on mode is the machine's parameter; after a refused
    // G00, its G00 did not take effect, and the message says so.
    has(&fanuc("G21 G90\nX10. Y10.\nM30\n"), 2, 1, "by its parameter 3402 bit 0, is the machine's setting: its machine file's power_on_motion");
    // Said by the machine file, the power-on mode moves them: a rapid under G00, a feed under G01.
    let nmv = fiveaxis::machine::builtin_file("mori-seiki-nmv5000").unwrap();
    for (mode, motion) in [("G00", Motion::Rapid), ("G01", Motion::Linear)] {
        let m = fiveaxis::machine::Machine::from_toml_str(&format!("power_on_motion = \"{mode}\"\n{nmv}"), "t").unwrap();
        for dialect in [Dialect::Fanuc, Dialect::Haas] {
            let p = read("G21 G90\nX10. Y10. F100.\nM30\n", dialect, "t.nc", &ReadOptions::default().on(&m));
            assert!(errors(&p).is_empty(), "{mode} {dialect:?}: {:?}", errors(&p));
            let pts = end_points(&p);
            assert!(pts.len() == 1 && pts[0].0 == motion && pts[0].1[0] == 10.0 && pts[0].1[1] == 10.0, "{mode} {dialect:?}: {pts:?}");
        }
    }
    let bad = fiveaxis::machine::Machine::from_toml_str(&format!("power_on_motion = \"G02\"\n{nmv}"), "t").unwrap_err().to_string();
    assert!(bad.contains("power_on_motion") && bad.contains("expected \"G00\" or \"G01\""), "{bad}");
    has(&fanuc("G21 G90\nG00 W0.0\nX10. Y10.\nM30\n"), 3, 1, "(line 2 was refused before it, and none of its codes took effect)");
}

/// Fanuc and Haas read a number without a decimal point in least input increments (`X5` is 0.005
/// mm, FANUC B-64484EN "Decimal point programming", parameter DPI No. 3401#0 = 0); a machine whose
/// file says `decimal_point_input = "calculator"` (DPI = 1, Haas Setting 162 "Default to float" on)
/// reads it in the program's unit: `X5` is 5 mm, `B30` 30 deg, a corner `,R2` 2 mm, and an F under
/// G95 (refused in increments, where its meaning is not read) is mm per revolution.
#[test]
fn a_calculator_type_machine_reads_numbers_without_a_point_in_units() {
    let nmv = fiveaxis::machine::builtin_file("mori-seiki-nmv5000").unwrap();
    let text = "%\nO1000\nG21 G90 G17\nG0 X5 Y10 Z20 B30\nG1 X20 F100\nM30\n%\n";
    let increments = fiveaxis::machine::Machine::builtin("mori-seiki-nmv5000").unwrap();
    let calculator = fiveaxis::machine::Machine::from_toml_str(&format!("decimal_point_input = \"calculator\"\n{nmv}"), "t").unwrap();
    for dialect in [Dialect::Fanuc, Dialect::Haas] {
        let p = read(text, dialect, "t.nc", &ReadOptions::default().on(&increments));
        let pts = end_points(&p);
        assert!((pts[0].1[0] - 0.005).abs() < 1e-12 && (pts[0].1[1] - 0.010).abs() < 1e-12, "{dialect:?} increments: {pts:?}");
        let p = read(text, dialect, "t.nc", &ReadOptions::default().on(&calculator));
        assert!(errors(&p).is_empty(), "{dialect:?}: {:?}", errors(&p));
        assert!(p.diagnostics.iter().all(|d| !d.message.contains("has no decimal point")), "{dialect:?}: {:?}", p.diagnostics);
        let pts = end_points(&p);
        assert!(pts[0].1[0] == 5.0 && pts[0].1[1] == 10.0 && pts[0].1[2] == 20.0 && pts[1].1[0] == 20.0, "{dialect:?} calculator: {pts:?}");
        let b = p.blocks.iter().find_map(|b| b.targets.b).unwrap();
        assert!((b.to_degrees() - 30.0).abs() < 1e-9, "{dialect:?}: B {}", b.to_degrees());
    }
    // A G65 argument without a point is in units too (#24 = 50 mm, #2 = 30 deg), and G68's R30 is 30 deg.
    let g65 = "%\nO1000\nG21 G90 G17\nG0 X0 Y0 Z20 B0\nG65 P9010 X50 B30\nM30\nO9010\nG1 X#24 F1000\nG0 B#2\nM99\n%\n";
    for dialect in [Dialect::Fanuc, Dialect::Haas] {
        let p = read(g65, dialect, "t.nc", &ReadOptions::default().on(&calculator));
        assert!(errors(&p).is_empty(), "{dialect:?}: {:?}", errors(&p));
        let pts = end_points(&p);
        assert!(pts.iter().any(|(_, at)| at[0] == 50.0) && pts.iter().any(|(_, at)| (at[4] - 30.0).abs() < 1e-9), "{dialect:?} G65: {pts:?}");
    }
    let g68 = "%\nO1000\nG21 G90 G17\nG0 X0 Y0 Z20\nG68 X0 Y0 R90\nG1 X10 F100\nG69\nM30\n%\n";
    assert!(errors(&read(g68, Dialect::Fanuc, "t.nc", &ReadOptions::default().on(&increments))).iter().any(|(l, _, m)| *l == 5 && m.starts_with("R90: an angle without a decimal point")));
    let p = read(g68, Dialect::Fanuc, "t.nc", &ReadOptions::default().on(&calculator));
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    let last = *end_points(&p).last().unwrap();
    assert!(last.1[0].abs() < 1e-9 && (last.1[1] - 10.0).abs() < 1e-9, "G68 R90: X10 turned to Y10: {last:?}");
    // G95 F without a point: refused in increments, mm/rev in calculator mode.
    let g95 = "%\nO1000\nG21 G90 G17\nG0 X0 Y0 Z0\nS1000 M3\nG95 G1 X10 F1\nM30\n%\n";
    assert!(errors(&read(g95, Dialect::Fanuc, "t.nc", &ReadOptions::default().on(&increments))).iter().any(|(l, _, m)| *l == 6 && m.contains("F1 without a decimal point under G95")));
    assert!(errors(&read(g95, Dialect::Fanuc, "t.nc", &ReadOptions::default().on(&calculator))).is_empty());
    let bad = fiveaxis::machine::Machine::from_toml_str(&format!("decimal_point_input = \"float\"\n{nmv}"), "t").unwrap_err().to_string();
    assert!(bad.contains("decimal_point_input") && bad.contains("expected \"increments\" or \"calculator\""), "{bad}");
}

/// A block that moves only Z under a Fanuc canned cycle is no G01 move (the cycle stays the modal
/// motion until G80 or G00-G03); whether the control drills there or stores the depth is not read, so
/// the block is refused. The TNC's DIN/ISO unit is its header's: a `G70` block under a `G71` header
/// is refused rather than switching the lengths that follow to inches. Klartext cycle 200's `Q395=1`
/// (the depth to the tool's full diameter) is refused.
#[test]
fn a_z_alone_under_a_cycle_a_unit_against_the_header_and_q395_are_refused() {
    let p = read("%\nO1000\nG21 G90 G94 G17\nG1 X0. Y0. Z10. F60.\nG98 G81 X10. R2. Z-18. F60.\nZ-28.\nG80 G1 X10. Y0. Z2.\nM30\n%\n", Dialect::Fanuc, "t.nc", &ReadOptions::default());
    has(&p, 6, 1, "without X or Y under a canned cycle");
    let p = read_heidenhain("%T G71 *\nN10 G17 G90 G01 X+0 Y+0 Z+0 F60 *\nN20 G70 *\nN30 G01 X+30 Y+0 *\nN99999999 %T G71 *\n");
    has(&p, 3, 5, "takes the program's unit from its header");
    let x: Vec<f64> = p.blocks.iter().filter_map(|b| b.targets.x).collect();
    assert!((x.last().unwrap() / MM - 30.0).abs() < 1e-9, "{x:?}");
    let text = "BEGIN PGM T MM\nTOOL CALL 1 Z S1000\nL Z+50 R0 FMAX\nCYCL DEF 200 DRILLING ~\n Q200=+2 ;SET-UP CLEARANCE ~\n Q201=-10 ;DEPTH ~\n Q206=+150 ;FEED RATE FOR PLNGNG ~\n Q202=+5 ;PLUNGING DEPTH ~\n Q210=+0 ;DWELL TIME AT TOP ~\n Q203=+0 ;SURFACE COORDINATE ~\n Q204=+50 ;2ND SET-UP CLEARANCE ~\n Q211=+0 ;DWELL TIME AT DEPTH ~\n Q395=+1 ;DEPTH REFERENCE\nL X+10 Y+10 R0 FMAX M99\nEND PGM T MM\n";
    let p = read(text, Dialect::Klartext, "t.h", &ReadOptions::default());
    assert!(errors(&p).iter().any(|(_, _, m)| m.contains("Q395=1")), "{:?}", errors(&p));
}

/// LinuxCNC, Fanuc and Haas start in the unit their setting says; a program that moves before it says
/// G20 or G21 is read in millimetres, and a warning says so once, at its first move (the same program
/// with G20 is 25.4 times larger; shop programs without either came out "clean" in mm, a helper found).
/// Saying the unit, or giving --units, leaves nothing to warn of.
#[test]
fn a_program_that_never_says_its_unit_is_warned_of_once() {
    let warned = |p: &Program| -> Vec<(usize, usize)> {
        p.diagnostics.iter().filter(|d| d.severity == Severity::Warning && d.message.contains("no G20/G21 before the first move")).map(|d| (d.line, d.column)).collect()
    };
    for dialect in [Dialect::Rs274, Dialect::Fanuc, Dialect::Haas] {
        let p = read("G90 G94 G17\nG0 X1. Y2. Z3.\nG1 X10. F100.\nM30\n", dialect, "t.nc", &ReadOptions::default());
        assert!(errors(&p).is_empty(), "{dialect:?}: {:?}", errors(&p));
        assert_eq!(warned(&p), [(2, 1)], "{dialect:?}");
        let x: Vec<f64> = p.blocks.iter().filter_map(|b| b.targets.x).collect();
        assert!((x[0] / MM - 1.0).abs() < 1e-12, "{dialect:?}: read in mm");
        for said in ["G20 G90 G94 G17\nG0 X1. Y2. Z3.\nG1 X10. F100.\nM30\n", "G21 G90 G94 G17\nG0 X1. Y2. Z3.\nG1 X10. F100.\nM30\n"] {
            let p = read(said, dialect, "t.nc", &ReadOptions::default());
            assert!(warned(&p).is_empty(), "{dialect:?}: {said:?}");
        }
        let forced = ReadOptions { units: Some("inch".parse().unwrap()), ..Default::default() };
        let p = read("G90 G94 G17\nG0 X1. Y2. Z3.\nM30\n", dialect, "t.nc", &forced);
        assert!(warned(&p).is_empty(), "{dialect:?}: --units inch");
        let x: Vec<f64> = p.blocks.iter().filter_map(|b| b.targets.x).collect();
        assert!((x[0] / MM - 25.4).abs() < 1e-12, "{dialect:?}: --units inch");
    }
}

/// The TNC's DIN/ISO program head, as the TNC 360 ISO manual's example writes it: the blank form
/// `G30`/`G31` (MIN and MAX points, "Define workpiece blank") and the tool definition `G99 T1 L+0 R+4`
/// define and do not move (Klartext's BLK FORM and TOOL DEF alike); they had been refused as unknown G
/// codes with axis words without a motion mode, so no TNC ISO program read past its second line.
/// The first move is N50's, from where the tool stood, and the tool is called at N40, not at its
/// definition.
#[test]
fn a_tnc_iso_programs_blank_form_and_tool_definition_move_nothing() {
    let text = "%S846I G71 *\nN10 G30 G17 X+0 Y+0 Z-20 *\nN20 G31 G90 X+100 Y+100 Z+0 *\nN30 G99 T1 L+0 R+4 *\nN40 T1 G17 S1500 *\n\
                N50 G00 G40 G90 Z+100 *\nN60 X+10 Y+10 *\nN70 G01 Z-5 F100 M03 *\nN80 G00 Z+100 M02 *\nN9999 %S846I G71 *\n";
    let p = read_heidenhain(text);
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    let moves: Vec<(u64, [Option<f64>; 3])> = p.blocks.iter().filter(|b| !b.targets.is_empty()).map(|b| (b.number.unwrap(), [b.targets.x, b.targets.y, b.targets.z])).collect();
    assert_eq!(moves.first().map(|m| m.0), Some(50), "{moves:?}");
    assert_eq!(moves.iter().map(|m| m.0).collect::<Vec<_>>(), [50, 60, 70, 80]);
    assert!((moves[2].1[2].unwrap() / MM + 5.0).abs() < 1e-12);
    // The definition's T calls no tool; the call on N40 does.
    let t_on = |line: usize| p.blocks.iter().any(|b| b.line == line && b.events.iter().any(|e| e == "T1"));
    assert!(!t_on(4) && t_on(5));
}

/// A file cut short (or a program without its end) is said at its last line in every dialect, and
/// the moves before it are kept. LinuxCNC's own interpreter (`rs274` of Debian 12's linuxcnc-uspace,
/// run on these texts) stops at the end of such a file with "File ended with no percent sign or
/// program end" (or "... no percent sign" when the file opened with `%`), after making the move before
/// it; it says nothing for M2, M30 or a closing `%`. The TNC's programs end with END PGM (DIN/ISO:
/// `N... %NAME G71 *`) as they begin with BEGIN PGM: without it, an error, as a missing start is.
#[test]
fn a_program_without_its_end_is_said_at_its_last_line() {
    let options = ReadOptions::default();
    let said = |p: &Program, line: usize, needle: &str, severity: Severity| {
        assert!(
            p.diagnostics.iter().any(|d| d.line == line && d.severity == severity && d.message.contains(needle)),
            "no {severity:?} at line {line} containing {needle:?}: {:#?}",
            p.diagnostics
        );
        assert_eq!(p.blocks.iter().filter(|b| !b.targets.is_empty()).count(), 1, "the move before the end is kept: {:#?}", p.blocks);
    };
    let quiet = |p: &Program| assert!(p.diagnostics.iter().all(|d| !d.message.contains("cut short")), "{:#?}", p.diagnostics);
    // LinuxCNC.
    let p = read("G21 G90\nG1 X10 F100\n", Dialect::Rs274, "t.ngc", &options);
    said(&p, 2, "File ended with no percent sign or program end", Severity::Warning);
    let p = read("%\nG21 G90\nG1 X10 F100\n\n", Dialect::Rs274, "t.ngc", &options);
    said(&p, 3, "\"File ended with no percent sign\"", Severity::Warning);
    for ends in ["G21 G90\nG1 X10 F100\nM2\n", "G21 G90\nG1 X10 F100\nM30\n", "%\nG21 G90\nG1 X10 F100\n%\n"] {
        quiet(&read(ends, Dialect::Rs274, "t.ngc", &options));
    }
    // Fanuc and Haas: the tape's end before M30, or no end at all.
    let p = read("%\nO0001\nG21 G90\nG1 X10. F100.\n%\n", Dialect::Fanuc, "t.nc", &options);
    said(&p, 5, "the tape's end % comes before the program's end (M30, M02 or M99) (Fanuc: alarm PS5010", Severity::Warning);
    let p = read("%\nO0001\nG21 G90\nG1 X10. F100.\n", Dialect::Haas, "t.nc", &options);
    said(&p, 4, "the file ends before the program's end", Severity::Warning);
    for ends in ["%\nO0001\nG21 G90\nG1 X10. F100.\nM30\n%\n", "G21 G90\nG1 X10. F100.\nM02\n", "%\nO0001\nG21 G90\nG1 X10. F100.\nM99\n%\n"] {
        quiet(&read(ends, Dialect::Fanuc, "t.nc", &options));
    }
    // Sinumerik.
    let p = read("G71 G90\nG1 X10 F100\n", Dialect::Sinumerik, "t.mpf", &options);
    said(&p, 2, "the file ends before the program's end (M30, M2 or M17)", Severity::Warning);
    quiet(&read("G71 G90\nG1 X10 F100\nM30\n", Dialect::Sinumerik, "t.mpf", &options));
    // Heidenhain: an error, as a missing BEGIN PGM is.
    let p = read("BEGIN PGM T MM\nL X10 R0 F100\n", Dialect::Klartext, "t.h", &options);
    said(&p, 2, "missing program end: expected END PGM", Severity::Error);
    quiet(&read("BEGIN PGM T MM\nL X10 R0 F100\nEND PGM T MM\n", Dialect::Klartext, "t.h", &options));
    let p = read("%T G71 *\nN10 G01 X+10 F100 *\n", Dialect::Heidenhain, "t.i", &options);
    said(&p, 2, "missing program end: expected N... %T G71 *", Severity::Error);
}
