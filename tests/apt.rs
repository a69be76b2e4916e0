//! APT cutter-location data (CLDATA as text, as NX, CATIA and Fusion's APT post write it): the tool
//! path it describes, with times and circles computed here from the statements as written, and the
//! statements that would change the motion in ways not read refused where they stand.

use crate::common;
use fiveaxis::job::{self, JobOptions};
use fiveaxis::machine::Machine;
use fiveaxis::program::{read, Dialect, Program, ReadOptions, Severity};

fn errors(p: &Program) -> Vec<(usize, usize, String)> {
    p.diagnostics.iter().filter(|d| d.severity == Severity::Error).map(|d| (d.line, d.column, d.message.clone())).collect()
}

/// Each CL text of `cases` read has an error at its line and column holding its text.
fn refuses_each(cases: &[(&str, usize, usize, &str)], opts: &ReadOptions) {
    for &(text, line, column, needle) in cases {
        let p = read(text, Dialect::Cl, "t.cls", opts);
        assert!(
            errors(&p).iter().any(|(l, c, m)| *l == line && *c == column && m.contains(needle)),
            "{text:?}: no error at {line}:{column} containing {needle:?}: {:#?}",
            errors(&p)
        );
    }
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
    let cases: [(&str, usize, usize, &str); 26] = [
        ("GOTO/0,0,0\nFEDRAT/0.1,IPR\n", 2, 1, "per revolution"),
        ("GOTO/0,0,0\n  CUTCOM/XYPLAN,LEFT\n", 2, 3, "CUTCOM/ expects"),
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
        ("CSYS/1,0,0,10,0,1,0,0,0,0,1,0\nGOTO/0,0,0\n", 1, 1, "translation"),
        ("CSYS/1,0,0,0,0,2,0,0,0,0,1,0\nGOTO/0,0,0\n", 1, 1, "not a rotation"),
        ("TRNTYP/LOCAL,0,0,0\nGOTO/0,0,0\n", 1, 1, "WORLD"),
        ("ROTABL/90,AAXIS,TABLE,CLW\nGOTO/0,0,0\n", 1, 1, "CLW"),
        ("ROTABL/90,AAXIS\nROTABL/90,CAXIS\nGOTO/0,0,0\n", 2, 1, "two axes"),
        // SOLIDWORKS CAM's radians read as APT's degrees: the turn contradicts TLAXIS/, and says so.
        ("TLAXIS/0,-1,0\nROTABL/1.570796,AAXIS,TABLE,CCLW\nGOTO/0,0,0\n", 2, 1, "--cl-angles rad"),
        ("GOTO/10,0,0\nCIRCLE/0,0,0,0,0,1,10,SOMEWAY\nGOTO/0,10,0\n", 2, 1, "CLOCKWISE or COUNTERCLOCKWISE"),
        ("GOTO/0,0,0\nCYCLE/ DRILL,G98,12.3,3.0,46.9 46.9 DWELL,0\nGOTO/1,2,3\nCYCLE/OFF\n", 2, 1, "a comma missing"),
        ("MSYS/-120.2591,-1196.5,142.5,0,1,0,1,0,0\nGOTO/0,0,0,0,0,-1\n", 1, 1, "turned"),
        ("GOTO/0,0,0,0,0,0\n", 1, 1, "zero length"),
        ("GOTO/0,0,0\nGOTO/1,0,x1\n", 2, 1, "only numbers"),
        ("GOTO/0,0,0\nGOTO/1,0,1.2.3\n", 2, 1, "expected a number"),
    ];
    refuses_each(&cases, &opts);
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
    let header = format!("PARTNO TEST\n$$ made by a CAM system\n{}MACHIN/UNCX01,1\nCUTCOM/NORMAL\nGOTO/1,2,3\n", "PPRINT SET-UP NOTE\n".repeat(2500));
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

/// SOLIDWORKS CAM's forms, as the AptPostProcessor project reads its output: CUTCOM/LEFT leaves the
/// GOTOs the tool centre's path (noted once), an INSERTed note is an event, a CSYS/ turned working
/// plane gives the tool axis of the GOTOs after it (its Z column); its `.clt` turns the table by
/// ROTABL/ in radians and writes GOTOs and CIRCLEs in the part so turned. By hand: A = 90 deg about +X
/// takes (x, y, z) written to (x, -z, y) in the part, the tool to (0, -1, 0); a full circle about the
/// turned Z, centre (0, 0, -5) radius 10, is the circle x^2 + z^2 = 100 at y = 5 in the part.
/// The holes of a cycle that is not read make no motion.
#[test]
fn solidworks_cam_csys_rotabl_and_clockwise_circles() {
    let rad = ReadOptions { cl_angles: fiveaxis::program::AngleUnit::Rad, ..ReadOptions::default() };
    let text = "UNITS/ MM\nTLAXIS/ 0,-1,0\nINSERT/[HOLDER=C40] 6MM CRB 2FL\nROTABL/ 1.570796327,AAXIS,TABLE,CCLW\nROTABL/ -0.000000,BAXIS,TABLE,CCLW\n\
RAPID/\nGOTO/ 10,0,-5\nCUTCOM/ ON\nCUTCOM/ LEFT\nFEDRAT/ MMPM,600\nMOVE_ATTRIB/ LEADIN,END_ATTRIB\n\
CIRCLE/ 0,0,-5,0,0,1,10,CLOCKWISE\nGOTO/ 10,0,-5\nCUTCOM/ OFF\nCYCLE/ ON\nCYCLE/ DRILL,G98,5,MMPM,100,3,20\nGOTO/ 1,2,3\nCYCLE/ OFF\n\
ROTABL/ 0,AAXIS,TABLE,CCLW\nCSYS/0,0,1.,0,1.,0,0,0,0,1.,0,0\nGOTO/ 30,0,0\nFINI\n";
    let p = read(text, Dialect::Cl, "t.clt", &rad);
    let errs = errors(&p);
    assert!(errs.len() == 1 && errs[0].0 == 16 && errs[0].2.contains("CYCLE/DRILL"), "{errs:#?}");
    let warned: Vec<_> = p.diagnostics.iter().filter(|d| d.severity == Severity::Warning).collect();
    assert!(warned.len() == 1 && warned[0].line == 9 && warned[0].message.contains("tool centre"), "{warned:#?}");
    let b = &p.blocks;
    assert_eq!(b.len(), 3, "the approach, the circle, the move after the CSYS: {b:#?}");
    let mm = |v: Option<f64>| v.unwrap() * 1e3;
    assert!((mm(b[0].targets.x) - 10.0).abs() < 1e-9 && (mm(b[0].targets.y) - 5.0).abs() < 1e-6 && mm(b[0].targets.z).abs() < 1e-6, "{:?}", b[0].targets);
    let axis = b[0].targets.tool_axis.unwrap();
    assert!(axis[0].abs() < 1e-9 && (axis[1] + 1.0).abs() < 1e-9 && axis[2].abs() < 1e-9, "{axis:?}");
    assert!(b[0].events.iter().any(|e| e.contains("HOLDER")), "{:?}", b[0].events);
    // After the table turns back to 0 (ROTABL/a is a position, ICAM's) and the CSYS: the tool along the CSYS's Z column, (1, 0, 0).
    let axis = b[2].targets.tool_axis.unwrap();
    assert!((axis[0] - 1.0).abs() < 1e-9 && axis[1].abs() < 1e-9 && axis[2].abs() < 1e-9, "{axis:?}");
    assert!((mm(b[2].targets.x) - 30.0).abs() < 1e-9);

    // The full circle, sampled: on x^2 + z^2 = 100 at y = 5, once round (20 pi mm), clockwise seen
    // from the turned Z's tip, (0, -1, 0): from (10, 5, 0) it first goes towards +z... seen from -Y
    // (x right, z up as seen from there is mirrored): clockwise about -Y is counter-clockwise about +Y,
    // which takes +x towards -z.
    let dir = common::scratch_dir("apt-solidworks");
    let path = dir.join("t.clt");
    let clean = text.replace("CYCLE/ ON\nCYCLE/ DRILL,G98,5,MMPM,100,3,20\nGOTO/ 1,2,3\nCYCLE/ OFF\n", "");
    std::fs::write(&path, &clean).unwrap();
    let machine = Machine::builtin("generic-ac-table").unwrap();
    let opts = JobOptions { read: rad.clone(), ..JobOptions::default() };
    let job = job::run(&path.display().to_string(), &machine, &opts).unwrap();
    assert!(job.report.diagnostics.iter().all(|d| d.severity != Severity::Error), "{:#?}", job.report.diagnostics);
    let circle: Vec<_> = job.trajectory.samples(&machine).filter(|s| job.trajectory.segments[s.segment].line == 13).map(|s| s.tip * 1e3).collect();
    assert!(circle.len() > 100);
    let worst = circle.iter().map(|p| (p.x.hypot(p.z) - 10.0).abs().max((p.y - 5.0).abs())).fold(0.0, f64::max);
    assert!(worst < 1e-6, "a tip {worst:e} mm off the circle");
    let length: f64 = job.trajectory.segments.iter().filter(|g| g.line == 13).map(|g| g.length).sum::<f64>() * 1e3;
    assert!((length - 20.0 * std::f64::consts::PI).abs() < 1e-6, "{length} mm");
    let early = circle[circle.len() / 10];
    assert!(early.z < -1.0, "clockwise about the turned Z takes +x towards -z first: {early:?}");
    let _ = std::fs::remove_dir_all(dir);
}

/// What a review found read as something else, now refused where it stands: a statement after a `$$`
/// comment or PPRINT text ending in `$` (swallowed as its continuation before), NC code in capitals
/// passed by INSERT/ (a control's words: `L Z+100 R0 FMAX M91`, `TRAORI`), RAPID before CIRCLE (an
/// arc at rapid), CUTCOM under Pro/NC's OUTPUT_ON_PROFILE (the part's profile, which the control
/// offsets), an empty field (before: the fields after it shifted). The forms still read: Pro/CLfile's
/// comment continued with numbers, notes in small letters or brackets, CUTTER/'s trailing comma,
/// CUTCOM under OUTPUT_ON_CENTER.
#[test]
fn apt_continuations_inserts_and_fields_fail_closed() {
    let opts = ReadOptions::default();
    let cases: [(&str, usize, usize, &str); 8] = [
        ("GOTO/0,0,50\n$$ cost 5 $\nGOTO/10,20,50,0,0,1\n", 3, 1, "after a `$$` comment ending in `$`"),
        ("GOTO/0,0,50\nPPRINT COST IN $\n  GOTO/10,0,50\n", 3, 3, "after PPRINT text ending in `$`"),
        ("GOTO/0,0,50\nINSERT/L Z+100 R0 FMAX M91\n", 2, 1, "INSERT/ passes NC code"),
        ("GOTO/0,0,50\nINSERT/TRAORI\n", 2, 1, "INSERT/ passes NC code"),
        ("GOTO/10,0,50\nRAPID\nCIRCLE/0,0,50,0,0,1,10\nGOTO/-10,0,50\n", 4, 1, "RAPID before the CIRCLE of line 3"),
        ("$$-> CUTCOM_GEOMETRY_TYPE / OUTPUT_ON_PROFILE\nGOTO/0,0,50\nCUTCOM/LEFT\nGOTO/10,0,50\n", 3, 1, "OUTPUT_ON_PROFILE"),
        ("GOTO/0,0,50\nGOTO/1,2,,3,0,0,1\n", 2, 1, "field 3 is empty"),
        ("x,y,z,a,c,f\n0,0,50,0,0,1000\n", 1, 7, "names 'a' where column 4"),
    ];
    refuses_each(&cases, &opts);
    let fine = "$$-> CSYS / 1.0, 0.0, 0.0, 0.0,  $\n  0.0, 1.0, 0.0, 0.0,  $\n  0.0, 0.0, 1.0, 0.0\n$$-> CUTCOM_GEOMETRY_TYPE / OUTPUT_ON_CENTER\n\
                INSERT/[HOLDER=C40-M06EM2] 6MM CRB 2FL 19 LOC\nINSERT/Stock Size X95. Y150. Z120.\nCUTTER/ 6.000000,0.000000,3.000000,\n\
                GOTO/0,0,50\nCUTCOM/LEFT\nFEDRAT/MMPM,500\nGOTO/10,0,50\nCUTCOM/OFF\n";
    let p = read(fine, Dialect::Cl, "t.cls", &opts);
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    assert_eq!(p.blocks.iter().filter(|b| b.targets.x.is_some()).count(), 2);
    // Plain CL data in inches (--units inch): 1 in is 25.4 mm, the feed column in/min.
    let inch = ReadOptions { units: Some(fiveaxis::program::LengthUnit::Inch), ..ReadOptions::default() };
    let p = read("x,y,z,i,j,k,f\n1,0,2,0,0,1,10\n", Dialect::Cl, "t.cl", &inch);
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    let b = &p.blocks[0];
    assert!((b.targets.x.unwrap() - 0.0254).abs() < 1e-12 && (b.targets.z.unwrap() - 0.0508).abs() < 1e-12, "{b:?}");
    assert!((b.feed.unwrap().value_per_min - 254.0).abs() < 1e-9, "{b:?}");
}
