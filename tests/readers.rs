//! NC program readers: the paper's programs, their OCR-damaged copies, RS274NGC and CL data.

use fiveaxis::program::{read, read_cl, read_heidenhain, read_rs274, Dialect, FeedMode, Motion, Program, ReadOptions, Severity};
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
    has(&p, 4, 5, "G02");
    assert_eq!(p.blocks.iter().map(|b| b.number).collect::<Vec<_>>(), vec![Some(10), Some(30)]);
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
    assert_eq!(Dialect::detect(None, SING), Dialect::Heidenhain);
    assert_eq!(Dialect::detect(None, "G1 X1 Y2\n"), Dialect::Rs274);
    assert_eq!(Dialect::detect(None, "1 2 3 0 0 1\n"), Dialect::Cl);
    assert_eq!(Dialect::detect(Some(std::path::Path::new("a.ngc")), ""), Dialect::Rs274);
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]
    /// Arbitrary bytes never panic any reader, nor the sampler and analysis behind them.
    #[test]
    fn readers_never_panic_on_arbitrary_bytes(bytes in proptest::collection::vec(any::<u8>(), 0..400)) {
        let text = String::from_utf8_lossy(&bytes);
        let m = fiveaxis::machine::Machine::hermle_c600u();
        for d in [Dialect::Heidenhain, Dialect::Rs274, Dialect::Cl] {
            let p = read(&text, d, "fuzz", &ReadOptions::default());
            let opts = fiveaxis::path::PathOptions { period: 0.05, ..Default::default() };
            let t = fiveaxis::path::Trajectory::from_program(&p, &m, &opts);
            let _ = fiveaxis::singularity::analyze(&t, &m, &Default::default());
        }
    }

}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]
    /// Program-shaped noise: mutations of the real program never panic and never invent blocks.
    /// (64 cases: each one plans and analyzes a whole program in a debug build.)
    #[test]
    fn mutated_programs_never_panic(cuts in proptest::collection::vec((0usize..2500, any::<char>()), 0..12)) {
        let mut s: Vec<char> = SING.chars().collect();
        for (at, c) in cuts {
            let at = at % s.len();
            s[at] = c;
        }
        let text: String = s.into_iter().collect();
        let p = read_heidenhain(&text);
        prop_assert!(p.blocks.len() <= 75);
        let m = fiveaxis::machine::Machine::hermle_c600u();
        // A mutated feed (F2 for F2000) stretches the program: keep the sample count bounded.
        let (segments, _) = fiveaxis::path::plan(&p, &m, &Default::default());
        let duration = segments.last().map_or(0.0, |s| s.t0 + s.duration);
        let opts = fiveaxis::path::PathOptions { period: (duration / 3000.0).max(1e-3), ..Default::default() };
        let t = fiveaxis::path::Trajectory::from_program(&p, &m, &opts);
        prop_assert!(t.sample_count() <= 3100);
        let _ = fiveaxis::singularity::analyze(&t, &m, &Default::default());
    }
}
