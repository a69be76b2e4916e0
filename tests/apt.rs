//! APT cutter-location data (CLDATA as text, as NX, CATIA and Fusion's APT post write it): the tool
//! path it describes, with times and circles computed here from the statements as written, and the
//! statements that would change the motion in ways not read refused where they stand.

mod common;
use fiveaxis::job::{self, JobOptions};
use fiveaxis::machine::Machine;
use fiveaxis::program::{read, Dialect, Program, ReadOptions, Severity};

fn errors(p: &Program) -> Vec<(usize, usize, String)> {
    p.diagnostics.iter().filter(|d| d.severity == Severity::Error).map(|d| (d.line, d.column, d.message.clone())).collect()
}

/// A contour as a CAM system writes it before post-processing: header records, a tool change, a
/// rapid approach, feeds in both orders of FEDRAT's words, a half circle in XY (ISO's seven-number
/// CIRCLE/) and a quarter circle in ZX (NX's eleven), tilted tool axes, a statement continued
/// over two lines, a move in inches, a GODLTA.
const CONTOUR: &str = "\
TOOL PATH/CONTOUR,TOOL,EM10
TLDATA/MILL,10.0000,0.0000,75.0000,0.0000,0.0000
MSYS/0.0000,0.0000,0.0000,1.0000000,0.0000000,0.0000000,0.0000000,1.0000000,0.0000000
$$ a comment line
PAINT/COLOR,186
LOADTL/1
SPINDL/RPM,4000,CLW
MULTAX/ON
RAPID
GOTO/5.0000,5.0000,50.0000,0.0000000,0.0000000,1.0000000
RAPID
GOTO/5.0000,5.0000,2.0000
FEDRAT/MMPM,200.0000
GOTO/5.0000,5.0000,-2.5000
FEDRAT/300.0000,MMPM
GOTO/5.0000,85.0000,-2.5000 $$ along Y
GOTO/30.0000,85.0000,-2.5000
CIRCLE/55.0000,85.0000,-2.5000,0.0000000,0.0000000,-1.0000000,25.0000
GOTO/80.0000,85.0000,-2.5000
GOTO/95.0000,85.0000,-2.5000
CIRCLE/95.0000,85.0000,7.5000,0.0000000,1.0000000,0.0000000,10.0000,0.0100,0.5000,10.0000,0.0000
GOTO/105.0000,85.0000,7.5000
GOTO/105.0000,60.0000,$
7.5000,0.1736482,0.0000000,0.9848078
GOTO/105.0000,40.0000,7.5000,0.0000000,0.1736482,0.9848078
UNITS/INCHES
FEDRAT/IPM,10.0000
GOTO/4.5000,1.0000,0.3000
UNITS/MM
GODLTA/0.0000,0.0000,5.0000
END
FINI
";

#[test]
fn an_apt_contour_runs_as_written() {
    let dir = common::scratch_dir("apt-contour");
    let path = dir.join("contour.cls");
    std::fs::write(&path, CONTOUR).unwrap();
    let machine = Machine::hermle_c600u();
    let job = job::run(&path.display().to_string(), &machine, &JobOptions::default()).unwrap();
    assert!(job.report.diagnostics.is_empty(), "{:#?}", job.report.diagnostics);

    // The feed moves, from the statements above (mm, mm/min): tool tip path lengths and feeds.
    let half_circle = std::f64::consts::PI * 25.0;
    let quarter = std::f64::consts::PI / 2.0 * 10.0;
    let inch = ([4.5 * 25.4, 1.0 * 25.4, 0.3 * 25.4], 10.0 * 25.4);
    let from_40 = ((inch.0[0] - 105.0f64).powi(2) + (inch.0[1] - 40.0f64).powi(2) + (inch.0[2] - 7.5f64).powi(2)).sqrt();
    let moves: [(f64, f64); 10] = [
        (4.5, 200.0),
        (80.0, 300.0),
        (25.0, 300.0),
        (half_circle, 300.0),
        (15.0, 300.0),
        (quarter, 300.0),
        (25.0, 300.0),
        (20.0, 300.0),
        (from_40, inch.1),
        (5.0, inch.1),
    ];
    let want_s: f64 = moves.iter().map(|(l, f)| l / f * 60.0).sum();
    let segments = &job.trajectory.segments;
    let feed_s: f64 = segments.iter().filter(|g| g.kind != fiveaxis::path::SegmentKind::Rapid).map(|g| g.duration).sum();
    assert!((feed_s - want_s).abs() < 1e-6, "feed moves take {feed_s} s, as written {want_s} s");

    // Each circle's tool tips lie on it, and go its way (an arc block on the line of its GOTO).
    // Seven numbers (ISO, Creo) turn counter-clockwise about the axis: about -Z the half circle
    // from (30, 85) to (80, 85) passes over the top, y 110. NX's eleven turn clockwise about it:
    // about +Y, the arc from (95, 85, -2.5) to (105, 85, 7.5) is a quarter (counter-clockwise it
    // would be three quarters).
    let (mut top, mut worst) = (f64::MIN, 0.0f64);
    for s in job.trajectory.samples(&machine) {
        let p = s.tip * 1e3;
        match segments[s.segment].line {
            19 => {
                worst = worst.max(((p.x - 55.0).hypot(p.y - 85.0) - 25.0).abs());
                top = top.max(p.y);
            }
            22 => worst = worst.max(((p.x - 95.0).hypot(p.z - 7.5) - 10.0).abs()),
            _ => {}
        }
    }
    assert!(worst < 1e-6, "a tool tip {worst:e} mm off its circle");
    assert!(top > 109.99, "the half circle is clockwise seen from +Z: its top is at y {top}");
    let quarter_len: f64 = segments.iter().filter(|g| g.line == 22).map(|g| g.length).sum();
    assert!((quarter_len * 1e3 - quarter).abs() < 1e-6, "the ZX arc is {} mm long", quarter_len * 1e3);
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn apt_statements_that_change_motion_unread_are_refused_where_they_stand() {
    let opts = ReadOptions::default();
    let cases: [(&str, usize, usize, &str); 19] = [
        ("GOTO/0,0,0\nFEDRAT/0.1,IPR\n", 2, 1, "per revolution"),
        ("GOTO/0,0,0\n  CUTCOM/LEFT\n", 2, 3, "cutter compensation"),
        ("GOTO/0,0,0\nINSERT G41 D1\n", 2, 1, "INSERT"),
        ("GOTO/0,0,0\nCIRCLE/0,0,0,0,0.6,0.8,10\nGOTO/1,0,0\n", 2, 1, "other than X, Y or Z"),
        ("GOTO/10,0,0\nCIRCLE/0,0,0,0,0,1,10,0.01,0.5,10,0,TIMES,2\nGOTO/10,0,0\n", 2, 1, "helix"),
        ("GOTO/10,0,0\nCIRCLE/0,0,0,0,0,1,10,0.01\nGOTO/0,10,0\n", 2, 1, "found 8 numbers"),
        ("MULTAX/OFF\nGOTO/0,0,0,0,0,1\n", 2, 1, "MULTAX/OFF"),
        ("GOTO/0,0,0\nGOHOME/0,0,100\n", 2, 1, "GOHOME"),
        ("GOTO/0,0,0\nCYCLE/DRILL,5,MMPM,100,2\n", 2, 1, "CYCLE"),
        ("GOTO/10,0,0\nCIRCLE/0,0,0,0,0,1,10\nSPINDL/OFF\nGOTO/0,10,0\n", 3, 1, "after CIRCLE"),
        ("GOTO/10,0,0\nCIRCLE/0,0,0,0,0,1,10\nGOTO/0,12,0\n", 3, 1, "from its centre"),
        ("GOTO/0,0,0\nGOTO/1,2,$\n", 2, 1, "ends inside this statement"),
        ("GOTO/0,0,0\nGOTO/1,2,3,4\n", 2, 1, "found 4 numbers"),
        ("GOTO/0,0,0\nFINI\nGOTO/1,0,0\n", 3, 1, "after FINI"),
        ("CSYS/1,0,0,10,0,1,0,0,0,0,1,0\nGOTO/0,0,0\n", 1, 1, "frame other"),
        ("MSYS/-120.2591,-1196.5,142.5,0,1,0,1,0,0\nGOTO/0,0,0,0,0,-1\n", 1, 1, "turned"),
        ("GOTO/0,0,0,0,0,0\n", 1, 1, "zero length"),
        ("GOTO/0,0,0\nGOTO/1,0,x1\n", 2, 1, "only numbers"),
        ("GOTO/0,0,0\nGOTO/1,0,1.2.3\n", 2, 1, "expected a number"),
    ];
    for (text, line, column, needle) in cases {
        let p = read(text, Dialect::Cl, "t.cls", &opts);
        assert!(
            errors(&p).iter().any(|(l, c, m)| *l == line && *c == column && m.contains(needle)),
            "{text:?}: no error at {line}:{column} containing {needle:?}: {:#?}",
            errors(&p)
        );
    }
    // Inches and IPM are read as mm and mm/min; a GOTO after RAPID is a rapid, the next one is not.
    let p = read("UNITS/INCHES\nGOTO/1,2,3\nFEDRAT/IPM,10\nRAPID\nGOTO/2,2,3\nGOTO/3,2,3\n", Dialect::Cl, "t.cls", &opts);
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    let b = &p.blocks;
    assert_eq!(b.len(), 3);
    assert!((b[0].targets.x.unwrap() - 0.0254).abs() < 1e-12 && (b[0].targets.z.unwrap() - 0.0762).abs() < 1e-12);
    assert!((b[2].feed.unwrap().value_per_min - 254.0).abs() < 1e-9);
    assert_eq!((b[1].motion, b[2].motion), (fiveaxis::program::Motion::Rapid, fiveaxis::program::Motion::Linear));
    // Found by its content, without the extension.
    assert_eq!(Dialect::detect(None, "PARTNO TEST\nGOTO/1,2,3\n"), Dialect::Cl);
    // And by its first statement, with no GOTO/ among the lines the guess reads (a header longer than
    // them, or a file that only sets up): the APT reader's own errors, not RS274's.
    let header = format!("PARTNO TEST\n$$ made by a CAM system\n{}MACHIN/UNCX01,1\nCUTCOM/LEFT\nGOTO/1,2,3\n", "PPRINT SET-UP NOTE\n".repeat(2500));
    assert_eq!(Dialect::detect(None, &header), Dialect::Cl);
    assert_eq!(Dialect::detect(None, "PARTNO TEST\nFEDRAT/MMPM,500\n"), Dialect::Cl);
    let p = read(&header, Dialect::detect(None, &header), "t", &opts);
    assert!(errors(&p).iter().any(|(l, c, m)| *l == 2504 && *c == 1 && m.contains("CUTCOM")), "{:#?}", errors(&p));
    // Other dialects' first lines are not APT statements.
    for (text, dialect) in [("N10 G0 X0 Y0\n", Dialect::Rs274), ("O1000\nG0 X0\n", Dialect::Rs274), ("%PGM G71 *\nN10 G0 X0 *\n", Dialect::Heidenhain), ("TRAORI\nG1 X0\n", Dialect::Sinumerik), ("1 2 3 0 0 1\n", Dialect::Cl)] {
        assert_eq!(Dialect::detect(None, text), dialect, "{text:?}");
    }
}

/// Creo Pro/CLfile's records: a `$$->` comment continued over lines ending in `$` (its CSYS), the
/// GPOST vocabulary (`PPWORD/`), the output frame `CAMERA/` (12 numbers, where the GOTOs already are);
/// a CAMERA of another size is refused. A program in inches whose tool tips span more than any
/// machine is warned of, naming `--units mm`; with `--units mm` its UNITS/INCHES is noted and its
/// numbers and IPM feeds read as mm and mm/min.
#[test]
fn creo_records_and_the_units_override() {
    let head = "$$*          Pro/CLfile  Version 9.0 - 9.0.3.0\nPPWORD/TLANGL,1\nREMARK -> FEATNO / 1014\n\
                $$-> CSYS / 1.0, 0.0, 0.0, 0.0,  $\n            0.0, 1.0, 0.0, 0.0,  $\n            0.0, 0.0, 1.0, 0.0\n\
                CAMERA/ 1.0, 0.0, 0.0,$\n -106.6,  $\n 0.0, 1.0, 0.0,$\n -121.2,  $\n 0.0, 0.0, 1.0, -100.5\nUNITS / INCHES\nMULTAX / ON\n";
    let text = format!("{head}GOTO / 0.0, 0.0, 10.0,  $\n0.0, 0.0, 1.0\nFEDRAT / 1200.0,  IPM\nGOTO / 100.0, 0.0, 10.0\nFINI\n");
    let p = read(&text, Dialect::Cl, "t.ncl", &ReadOptions::default());
    assert!(errors(&p).is_empty(), "{:#?}", errors(&p));
    assert!((p.blocks[1].targets.x.unwrap() - 100.0 * 0.0254).abs() < 1e-12);
    assert!(p.diagnostics.iter().all(|d| !d.message.contains("--units")), "100 in is a part some machines hold: {:#?}", p.diagnostics);
    // 2000 inches is 50.8 m: larger than any machine's travel, which the reader says at UNITS.
    let long = text.replace("100.0, 0.0, 10.0", "2000.0, 0.0, 10.0");
    let p = read(&long, Dialect::Cl, "t.ncl", &ReadOptions::default());
    let w = p.diagnostics.iter().find(|d| d.message.contains("--units mm")).expect("the size warning");
    assert_eq!((w.line, w.severity), (12, Severity::Warning), "{w:?}");
    // Read in mm: the numbers as they are, IPM as mm/min, UNITS noted where it stands.
    let mm = ReadOptions { units: Some("mm".parse().unwrap()), ..Default::default() };
    let p = read(&long, Dialect::Cl, "t.ncl", &mm);
    assert!(errors(&p).is_empty(), "{:#?}", errors(&p));
    assert!((p.blocks[1].targets.x.unwrap() - 2.0).abs() < 1e-12);
    assert!((p.blocks[1].feed.unwrap().value_per_min - 1200.0).abs() < 1e-9);
    assert!(p.diagnostics.iter().any(|d| d.line == 12 && d.message.contains("read in mm (--units)")), "{:#?}", p.diagnostics);
    for bad in ["CAMERA/1,0,0,0,0,1,0,0,0,0,1\n", "CAMERA/1,0,0,0,0,1,0,0,0,0,1,0,X\n"] {
        let p = read(&format!("{bad}GOTO/0,0,0\n"), Dialect::Cl, "t.ncl", &ReadOptions::default());
        assert!(errors(&p).iter().any(|(l, c, m)| (*l, *c) == (1, 1) && m.contains("CAMERA/")), "{bad}: {:#?}", errors(&p));
    }
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig { cases: 128, ..Default::default() })]
    /// APT-shaped noise: the contour with characters replaced by APT's own (`/ , $ $$` digits, words)
    /// never panics the reader or the sampler and analysis behind it, never makes more blocks than it
    /// has GOTOs, and every diagnostic names a line of the text.
    #[test]
    fn mutated_apt_never_panics(cuts in proptest::collection::vec((0usize..2000, proptest::sample::select(vec!['/', ',', '$', '.', '-', '0', '9', 'E', ' ', '\n', 'G', 'X'])), 0..10)) {
        let mut s: Vec<char> = CONTOUR.chars().collect();
        for (at, c) in cuts {
            let at = at % s.len();
            s[at] = c;
        }
        let text: String = s.into_iter().collect();
        let p = read(&text, Dialect::Cl, "t.cls", &ReadOptions::default());
        let gotos = text.lines().filter(|l| l.contains('/')).count();
        proptest::prop_assert!(p.blocks.len() <= gotos, "{} blocks from {} statements", p.blocks.len(), gotos);
        let lines = text.lines().count().max(1);
        proptest::prop_assert!(p.diagnostics.iter().all(|d| d.line >= 1 && d.line <= lines));
        let m = Machine::hermle_c600u();
        let opts = fiveaxis::path::PathOptions { period: 0.05, ..Default::default() };
        let t = fiveaxis::path::Trajectory::from_program(&p, &m, &opts);
        let _ = fiveaxis::singularity::analyze(&t, &m, &Default::default());
    }
}
