//! The 840D's chamfers and roundings at contour corners (`CHF=`, `CHR=`, `RND=`, `RNDM=`, `FRC=`,
//! `FRCM=`; SINUMERIK Programming Manual Fundamentals, "Chamfer, rounding"): the corner cut after
//! the block that asks for it, checked against the fillet and chamfer worked here from the
//! corner's angle (the bisector construction), the feed by the manual's rule, and what is refused.

use super::tnc_corners::{dist, fillet};
use super::*;

fn sinumerik(text: &str) -> Program {
    read(text, Dialect::Sinumerik, "c.mpf", &ReadOptions::default())
}

/// The blocks at feed after the plunge (line 3 on), in order: their motion and end (mm).
fn moves(p: &Program) -> Vec<(Motion, [f64; 2], usize)> {
    let mut at = [0.0; 2];
    let mut out = Vec::new();
    for b in &p.blocks {
        let moved = b.targets.x.is_some() || b.targets.y.is_some();
        at = [b.targets.x.map_or(at[0], |x| x / MM), b.targets.y.map_or(at[1], |y| y / MM)];
        if moved && b.line >= 3 && b.motion != Motion::Rapid {
            out.push((b.motion, at, b.line));
        }
    }
    out
}

const HEAD: &str = "G17 G90 G71 G94\nG0 X0 Y0 Z5\nG1 Z-1 F500\n";

/// `RND=` between two lines: the first ends where the fillet leaves it, the fillet about its
/// centre on the bisector, the second from where it meets it; at a right angle (R from the corner)
/// and at 60 deg (R / tan 30 deg).
#[test]
fn rnd_between_lines_is_the_bisector_fillet() {
    for (q, r) in [([50.0, 30.0], 5.0), ([50.0 - 30.0 * 0.5, 30.0 * 3f64.sqrt() / 2.0], 4.0)] {
        let p = sinumerik(&format!("{HEAD}G1 X50 Y0 RND={r}\nG1 X{} Y{}\nM30\n", q[0], q[1]));
        assert!(errors(&p).is_empty(), "{:#?}", p.diagnostics);
        let (t1, t2, c) = fillet([0.0, 0.0], [50.0, 0.0], q, r);
        let m = moves(&p);
        assert_eq!(m.len(), 3, "{m:?}");
        assert!(m[0].0 == Motion::Linear && dist(m[0].1, t1) < 1e-9, "{m:?} {t1:?}");
        // A left turn: counter-clockwise, its centre R from both tangent points.
        assert!(m[1].0 == Motion::ArcCcw && dist(m[1].1, t2) < 1e-9 && m[1].2 == 4, "{m:?}");
        let b = p.blocks.iter().find(|b| b.motion == Motion::ArcCcw).unwrap();
        let centre = b.arc.as_ref().unwrap().centre;
        assert!(dist([centre[0] / MM, centre[1] / MM], c) < 1e-9, "{centre:?} {c:?}");
        assert!(m[2].0 == Motion::Linear && dist(m[2].1, q) < 1e-9, "{m:?}");
    }
}

/// `CHR=` the chamfer's sides along both lines, `CHF=` its own length: at a right angle CHR=3 and
/// CHF=3 sqrt 2 are the same chamfer (the manual's CHF = 2 cos(α) CHR, α = 45 deg); at a turn of
/// 60 deg CHF=4 has sides 4 / (2 cos 30 deg) and is 4 long.
#[test]
fn chr_and_chf_cut_the_corner_by_their_sides_and_length() {
    let corner = |text: &str| -> Vec<(Motion, [f64; 2], usize)> {
        let p = sinumerik(text);
        assert!(errors(&p).is_empty(), "{:#?}", p.diagnostics);
        moves(&p)
    };
    let chr = corner(&format!("{HEAD}G1 X50 Y0 CHR=3\nG1 Y30\nM30\n"));
    let chf = corner(&format!("{HEAD}G1 X50 Y0 CHF={}\nG1 Y30\nM30\n", 3.0 * 2f64.sqrt()));
    for m in [&chr, &chf] {
        assert_eq!(m.len(), 3, "{m:?}");
        assert!(dist(m[0].1, [47.0, 0.0]) < 1e-9 && m[1].0 == Motion::Linear && dist(m[1].1, [50.0, 3.0]) < 1e-9 && dist(m[2].1, [50.0, 30.0]) < 1e-9, "{m:?}");
    }
    let (s, d) = (4.0 / (2.0 * 30f64.to_radians().cos()), [60f64.to_radians().cos(), 60f64.to_radians().sin()]);
    let m = corner(&format!("{HEAD}G1 X50 Y0 CHF=4\nG1 X{} Y{}\nM30\n", 50.0 + 20.0 * d[0], 20.0 * d[1]));
    let (a, b) = ([50.0 - s, 0.0], [50.0 + s * d[0], s * d[1]]);
    assert!(dist(m[0].1, a) < 1e-9 && dist(m[1].1, b) < 1e-9 && (dist(a, b) - 4.0).abs() < 1e-9, "{m:?}");
}

/// `RNDM=` rounds every corner after it until `RNDM=0`; the corner's feed is `FRC=` for it alone,
/// `FRCM=` until `FRCM=0`, else the feed of the block leading away from the corner (MD20201 bit 0
/// = 0); up to three blocks without a move in the plane may stand between the elements, a fourth
/// leaves the corner out with a warning.
#[test]
fn modal_rounding_feeds_and_blocks_between() {
    let p = sinumerik(&format!("{HEAD}G1 X50 Y0 RNDM=2\nG1 Y30 F300\nG1 X0 FRC=100\nG1 Y0 RNDM=0\nG1 X-10 Y-10\nM30\n"));
    assert!(errors(&p).is_empty(), "{:#?}", p.diagnostics);
    let arcs: Vec<_> = p.blocks.iter().filter(|b| b.motion.is_arc()).collect();
    // Corners after lines 4, 5 and 6 (RNDM=0 in line 7 ends it before its corner).
    assert_eq!(arcs.iter().map(|b| b.line).collect::<Vec<_>>(), vec![4, 5, 6], "{arcs:#?}");
    let feed = |b: &fiveaxis::program::Block| b.feed.unwrap().value_per_min;
    // After line 4 the next block's F300; after line 6 its own FRC=100; after line 5 F300 again.
    assert!((feed(arcs[0]) - 300.0).abs() < 1e-9 && (feed(arcs[1]) - 300.0).abs() < 1e-9 && (feed(arcs[2]) - 100.0).abs() < 1e-9, "{arcs:#?}");
    let p = sinumerik(&format!("{HEAD}G1 X50 Y0 RND=2 FRCM=150\nG1 Y30 RND=2\nG1 X0\nM30\n"));
    let arcs: Vec<_> = p.blocks.iter().filter(|b| b.motion.is_arc()).map(feed).collect();
    assert_eq!(arcs, vec![150.0, 150.0]);
    // Three lines between (a function, a feed, a comment line is none): the corner is cut, after
    // them; four: it is not, and a warning says so.
    let p = sinumerik(&format!("{HEAD}G1 X50 Y0 RND=2\nM8\n; a comment\nF400\nS1000\nG1 Y30\nM30\n"));
    assert!(errors(&p).is_empty(), "{:#?}", p.diagnostics);
    assert_eq!(p.blocks.iter().filter(|b| b.motion.is_arc()).count(), 1);
    let p = sinumerik(&format!("{HEAD}G1 X50 Y0 RND=2\nM8\nF400\nS1000\nM9\nG1 Y30\nM30\n"));
    assert!(errors(&p).is_empty(), "{:#?}", p.diagnostics);
    assert_eq!(p.blocks.iter().filter(|b| b.motion.is_arc()).count(), 0);
    assert!(p.diagnostics.iter().any(|d| d.line == 4 && d.message.contains("more than 3 blocks")), "{:#?}", p.diagnostics);
}

/// A rounding between a line and an arc: the fillet's centre R from the line and R + ρ from the
/// arc's centre (the line y = 0 to (10, 0), the arc about (20, 0) of radius 10 turning right at
/// the joint, R = 2: centre (20 - sqrt(12² - 2²), -2), worked by hand).
#[test]
fn rnd_between_a_line_and_an_arc() {
    let p = sinumerik("G17 G90 G71 G94\nG0 X0 Y0 Z5\nG1 Z-1 F500\nG1 X10 Y0 RND=2\nG3 X20 Y-10 CR=10\nM30\n");
    assert!(errors(&p).is_empty(), "{:#?}", p.diagnostics);
    let b = p.blocks.iter().find(|b| b.line == 4 && b.motion.is_arc()).expect("the rounding");
    let c = b.arc.as_ref().unwrap().centre;
    let x = 20.0 - (12.0f64 * 12.0 - 4.0).sqrt();
    assert!(dist([c[0] / MM, c[1] / MM], [x, -2.0]) < 1e-9 && b.motion == Motion::ArcCw, "{b:?}");
}

/// What a corner cannot be made of is an error at its word; the elements run as programmed.
#[test]
fn corners_refused_name_the_word() {
    let t = ReadOptions::default();
    let cases = [
        (format!("{HEAD}G1 X50 Y0 CHF=2\nG3 X60 Y10 CR=10\nM30\n"), "4:11:", "a chamfer beside an arc"),
        (format!("{HEAD}G1 X50 Y0 RND=60\nG1 Y30\nM30\n"), "4:11:", "too large"),
        (format!("{HEAD}G1 X50 Y0 RND=2\nG0 Y30\nM30\n"), "4:11:", "not a contour element"),
        (format!("{HEAD}G1 X50 Y0 RND=2\nG1 Z5\nM30\n"), "4:11:", "not a contour element"),
        (format!("{HEAD}G1 X50 Y0 RND=2\nM30\n"), "4:11:", "ends"),
        (format!("{HEAD}G1 X50 Y0 RND=2 CHF=1\nG1 Y30\nM30\n"), "4:17:", "one corner"),
        (format!("{HEAD}G1 X50 Y0 RND=-2\nG1 Y30\nM30\n"), "4:11:", "positive"),
        (format!("{HEAD}G0 X50 Y0 RND=2\nG1 Y30\nM30\n"), "4:11:", "not a contour element a corner ends"),
    ];
    let cases: Vec<(&str, &str, &str)> = cases.iter().map(|(t, a, n)| (t.as_str(), *a, *n)).collect();
    refuses_each(Dialect::Sinumerik, &t, &cases);
    // The refused corner leaves the elements as programmed: N4 still ends at the corner.
    let p = sinumerik(&format!("{HEAD}G1 X50 Y0 RND=60\nG1 Y30\nM30\n"));
    let m = moves(&p);
    assert!(m.len() == 2 && dist(m[0].1, [50.0, 0.0]) < 1e-9 && dist(m[1].1, [50.0, 30.0]) < 1e-9, "{m:?}");
}

/// `FRC=` is in the feed's unit: under G70 (inch geometry) F stays in the basic system's mm/min
/// (Fundamentals, "G70/G71": "feedrate F ... in the basic system"), so FRC=100 is 100 mm/min
/// while the rounding's size is inches; under G93 a corner's feed is refused.
#[test]
fn corner_feeds_are_in_fs_unit_and_not_read_under_g93() {
    let p = sinumerik("G17 G90 G71 G94\nG0 X0 Y0 Z5\nG1 Z-1 F500\nG70\nG1 X2 Y0 RND=0.1 FRC=100\nG1 Y1\nM30\n");
    assert!(errors(&p).is_empty(), "{:#?}", p.diagnostics);
    let arc = p.blocks.iter().find(|b| b.motion.is_arc()).expect("the rounding");
    assert!((arc.feed.unwrap().value_per_min - 100.0).abs() < 1e-9, "{:?}", arc.feed);
    let r = arc.arc.as_ref().unwrap().centre;
    // The rounding of radius 0.1 in (2.54 mm) at the corner (2 in, 0): its centre 0.1 in below and
    // left of the corner.
    assert!(dist([r[0] / MM, r[1] / MM], [1.9 * 25.4, 0.1 * 25.4]) < 1e-9, "{r:?}");
    let p = sinumerik("G17 G90 G71 G93\nG0 X0 Y0 Z5\nG1 Z-1 F10\nG1 X50 Y0 RND=2 F10\nG1 Y30 F10\nM30\n");
    has(&p, 4, 11, "G93");
}

/// A corner word in a block between the elements, a subprogram called or a line refused before the
/// next element: each refused at its word; RNDM's last element before the program's end has no
/// corner and no fault.
#[test]
fn corners_interrupted_and_modal_ends() {
    let p = sinumerik(&format!("{HEAD}G1 X50 Y0 RND=2\nF300 CHF=1\nG1 Y30\nM30\n"));
    has(&p, 5, 6, "moves nothing in the plane");
    assert_eq!(p.blocks.iter().filter(|b| b.motion.is_arc()).count(), 1, "the corner of line 4 is still cut");
    let p = sinumerik(&format!("{HEAD}G1 X50 Y0 RND=2\nG1 Y30 Q7\nG1 X0\nM30\n"));
    has(&p, 4, 11, "the block after it was not read");
    let m = moves(&p);
    assert!(dist(m[0].1, [50.0, 0.0]) < 1e-9 && p.blocks.iter().all(|b| !b.motion.is_arc()), "{m:?}");
    let p = sinumerik(&format!("{HEAD}G1 X50 Y0 RNDM=2\nG1 Y30\nG1 X0 M30\n"));
    assert!(errors(&p).is_empty(), "{:#?}", p.diagnostics);
    assert_eq!(p.blocks.iter().filter(|b| b.motion.is_arc()).count(), 2);
}

/// A corner waiting when a subprogram is called: refused at its word, its element out as
/// programmed before the subprogram's blocks; one waiting in the subprogram at its RET likewise.
#[test]
fn a_call_or_return_leaves_the_corner() {
    #[derive(Debug)]
    struct Dir;
    impl fiveaxis::program::SubroutineFiles for Dir {
        fn find_file(&self, names: &[String], _any_case: bool, _own_dir: bool) -> Result<Option<(String, Vec<u8>)>, String> {
            Ok(names.iter().any(|n| n.to_ascii_uppercase().starts_with("SIDE")).then(|| ("SIDE.SPF".to_string(), b"G1 Y30 RND=2\nRET\n".to_vec())))
        }
    }
    let options = ReadOptions { subroutine_files: Some(std::sync::Arc::new(Dir)), ..ReadOptions::default() };
    let p = read(&format!("{HEAD}G1 X50 Y0 RND=2\nSIDE\nG1 X0\nM30\n"), Dialect::Sinumerik, "c.mpf", &options);
    has(&p, 4, 11, "a subprogram is called");
    has(&p, 5, 1, "its subprogram returns");
    let m = moves(&p);
    assert!(m.len() == 3 && dist(m[0].1, [50.0, 0.0]) < 1e-9 && dist(m[1].1, [50.0, 30.0]) < 1e-9 && dist(m[2].1, [0.0, 30.0]) < 1e-9, "{m:?}");
}

/// Under G41/G42 the 840D offsets the rounded contour (the corner is the contour's, compensation
/// follows it): the iTNC example's contour in 840D words, the tool centre against shapely's offset
/// curve of the rounded contour, the rounding arc's offset about the fillet's centre at R ± r; a
/// corner at the selection or deselection block is refused there.
#[test]
fn rnd_under_g41_g42_offsets_the_rounded_contour() {
    use super::tnc_comp::{path, reference, table, TOLERANCE};
    use super::tnc_corners::{near, rounded_example, unit};
    let r = 3.0;
    let options = table("T3 P3 D6\n");
    let program = |g: &str| format!("N1 T3 D1\nN2 M6\nN3 G17 G90 G71 G94\nN4 G0 X-10 Y40 Z-2\nN5 G1 {g} X10 Y40 F300\nN6 X40 Y25 RND=5\nN7 X10 Y5\nN8 G40 X-10 Y5\nN9 G0 Z50\nN10 M30\n");
    for (g, side) in [("G41", "left"), ("G42", "right")] {
        let p = read(&program(g), Dialect::Sinumerik, "c.mpf", &options);
        assert!(errors(&p).is_empty(), "{g}: {:#?}", p.diagnostics);
        let d = unit([30.0, -15.0]);
        let s = if g == "G41" { 1.0 } else { -1.0 };
        let ours = path(&p, 6..=7, [10.0 - s * d[1] * r, 40.0 + s * d[0] * r]);
        assert!(ours.len() >= 3, "{g}: {ours:?}");
        let got = reference(r, side, &rounded_example(5.0), &ours);
        assert!(got["radius_error_mm"].as_f64().unwrap() < 1e-4 && got["hausdorff_mm"].as_f64().unwrap() < TOLERANCE * r, "{g}: {got}");
        let (_, _, c) = fillet([10.0, 40.0], [40.0, 25.0], [10.0, 5.0], 5.0);
        let k = ours.iter().find(|e| e.centre.is_some_and(|m| near(m, c))).unwrap_or_else(|| panic!("{g}: no arc about {c:?}: {ours:?}"));
        let want = if g == "G41" { 5.0 + r } else { 5.0 - r };
        assert!((dist(k.from, c) - want).abs() < 1e-9 && (dist(k.to, c) - want).abs() < 1e-9, "{g}: {k:?}");
    }
    let cases = [
        (program("G41").replace("N5 G1 G41 X10 Y40 F300", "N5 G1 G41 X10 Y40 F300 RND=2"), "5:24:", "selects compensation"),
        (program("G41").replace("N7 X10 Y5", "N7 X10 Y5 RND=2"), "7:11:", "deselects compensation"),
    ];
    let cases: Vec<(&str, &str, &str)> = cases.iter().map(|(t, a, n)| (t.as_str(), *a, *n)).collect();
    refuses_each(Dialect::Sinumerik, &options, &cases);
    // A corner refused there is the only fault: the selection and the deselection still run (their
    // lines are not taken back after compensation placed them), and the program ends at N10.
    for (text, n) in cases.iter().map(|c| c.0).zip([5, 8]) {
        let p = read(text, Dialect::Sinumerik, "c.mpf", &options);
        assert_eq!(errors(&p).len(), 1, "{:#?}", p.diagnostics);
        assert!(!p.diagnostics.iter().any(|d| d.message.contains("not used")), "{:#?}", p.diagnostics);
        assert!(p.blocks.iter().any(|b| b.number == Some(n)) && p.blocks.iter().any(|b| b.number == Some(10)), "N{n}");
    }
    // Under RNDM the selection block ends no corner (a modal rounding rounds no approach, and says
    // nothing); N6's corner is rounded, N7 (RNDM=0) ends the contour with none.
    let p = read(&program("G42").replace("N4 G0", "N35 RNDM=2\nN4 G0").replace("N7 X10 Y5", "N7 X10 Y5 RNDM=0"), Dialect::Sinumerik, "c.mpf", &options);
    assert!(errors(&p).is_empty(), "{:#?}", p.diagnostics);
    let arcs: Vec<_> = p.blocks.iter().filter(|b| b.motion.is_arc()).map(|b| b.number).collect();
    assert_eq!(arcs, vec![Some(6)], "{:#?}", p.blocks);
}

/// A rounding under G42 smaller than the tool (R5 inside, a 12 mm tool): compensation cannot
/// follow it and the program stops there; nothing held or after it runs.
#[test]
fn a_rounding_the_tool_cannot_follow_stops_the_program() {
    use super::tnc_comp::table;
    let text = "N1 T3 D1\nN2 M6\nN3 G17 G90 G71 G94\nN4 G0 X-10 Y40 Z-2\nN5 G1 G42 X10 Y40 F300\nN6 X40 Y25 RND=5\nN7 X10 Y5 RND=1\nN8 X0 Y5\nN9 G40 X-10 Y5\nN10 G0 Z50\nN11 M30\n";
    let p = read(text, Dialect::Sinumerik, "c.mpf", &table("T3 P3 D12\n"));
    // One fault: the stop (N7's corner, held when it came, never runs, and is not another).
    assert_eq!(errors(&p).len(), 1, "{:#?}", errors(&p));
    let e = errors(&p);
    let at = e.iter().find(|(_, _, m)| m.contains("tool radius compensation")).unwrap_or_else(|| panic!("{e:#?}")).0;
    assert!(at <= 7, "{e:#?}");
    assert!(p.blocks.iter().all(|b| b.line <= at), "blocks after line {at} ran: {:#?}", p.blocks.iter().map(|b| b.line).collect::<Vec<_>>());
}
