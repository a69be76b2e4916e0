//! The 840D's tool radius compensation `G41`/`G42` to `G40` (Programming Manual Fundamentals,
//! NC programming 12/2019 §2.10): the tool-centre path against shapely's offset curve of the
//! programmed contour (tests/peer/offset_reference.py), where NORM starts and ends it worked by hand,
//! the feed on arcs under CFC/CFIN/CFTCP by the manual's formula, and what the reader refuses.

use super::tnc_comp::{outside_contour, path, reference, table, El, TOLERANCE};
use super::*;

/// The TNC compensation test's outside contour in 840D words, counter-clockwise with G42 (the tool
/// outside the part), the feed at the tool centre (CFTCP): convex corners, a tangential and a
/// concave arc, a notch. `{head}` stands before the contour's first block.
fn outside(head: &str) -> String {
    format!(
        "N1 T3 D1\nN2 M6\nN3 G17 G90 G71 G94 {head}\nN4 G0 X-20 Y-20 Z5\nN5 G1 Z-2 F200\nN6 G1 G42 X0 Y0 F500\n\
         N7 X60\nN8 G3 X70 Y10 CR=10\nN9 G1 Y40\nN10 X50\nN11 G2 X40 Y30 CR=10\nN12 G1 Y20\nN13 X0\nN14 Y5\n\
         N15 G40 X-20 Y-10\nN16 G0 Z50\nN17 M30\n"
    )
}

fn feed(b: &fiveaxis::program::Block) -> f64 {
    b.feed.unwrap().value_per_min
}

/// NORM: "the tool travels directly on a straight line to the contour and is positioned
/// perpendicular to the path tangent in the start point", and leaves it so at the end for G40's
/// point; G450's transition circle of the tool's radius about each outside corner, the
/// equidistants' intersection at inside ones: shapely's offset curve, within GEOS' simplification.
#[test]
fn g42_outside_contour_is_shapelys_offset_curve_and_norm_starts_and_ends_perpendicular() {
    let r = 3.0; // T3: diameter 6 mm
    let p = read(&outside("CFTCP"), Dialect::Sinumerik, "c.mpf", &table("T3 P3 D6\n"));
    assert!(errors(&p).is_empty(), "{:#?}", p.diagnostics);
    // N6 ends perpendicular to the first element (+X) at its start, on its right: (0, -r).
    let entry = p.blocks.iter().find(|b| b.number == Some(6)).expect("N6");
    assert!((entry.targets.x.unwrap() / MM).abs() < 1e-9 && (entry.targets.y.unwrap() / MM + r).abs() < 1e-9, "{:?}", entry.targets);
    // N15 (G40) runs from the last element's end (0, 5) left perpendicular, (-r, 5), to (-20, -10).
    let exit: Vec<_> = p.blocks.iter().filter(|b| b.number == Some(15)).collect();
    assert_eq!(exit.len(), 1);
    assert!((exit[0].targets.x.unwrap() / MM + 20.0).abs() < 1e-9 && (exit[0].targets.y.unwrap() / MM + 10.0).abs() < 1e-9);
    let ours = path(&p, 7..=14, [0.0, -r]);
    assert!((ours.last().unwrap().to[0] + r).abs() < 1e-9 && (ours.last().unwrap().to[1] - 5.0).abs() < 1e-9, "{:?}", ours.last());
    let got = reference(r, "right", &outside_contour(), &ours);
    let e = got["radius_error_mm"].as_f64().unwrap();
    assert!(e < 1e-4, "a point of the path stands {e} mm off the radius from the contour; {got}");
    let h = got["hausdorff_mm"].as_f64().unwrap();
    assert!(h < TOLERANCE * r, "Hausdorff distance to shapely's offset curve {h} mm; {got}");
    assert!(ours.iter().any(|e| (e.to[0] - 37.0).abs() < 1e-9 && (e.to[1] - 23.0).abs() < 1e-9), "the notch's inside corner: {ours:?}");
    // The transition circle at (70, 40) belongs to the next block, N10, and runs at its feed.
    let corner = p.blocks.iter().find(|b| b.number == Some(10) && b.motion.is_arc()).expect("a transition circle in N10");
    let c = corner.arc.as_ref().unwrap().centre;
    assert!((c[0] / MM - 70.0).abs() < 1e-9 && (c[1] / MM - 40.0).abs() < 1e-9, "{c:?}");
    assert_eq!(feed(corner), 500.0);
    // The same contour with G41 and the path reversed would be the mirror; the tool stays on the
    // left of a clockwise contour: (the same blocks, X mirrored) the offset on the left.
    let mirrored = outside("CFTCP").replace("G42", "G41").replace("X", "X-").replace("X--", "X").replace("G3", "GX").replace("G2", "G3").replace("GX", "G2");
    let p = read(&mirrored, Dialect::Sinumerik, "c.mpf", &table("T3 P3 D6\n"));
    assert!(errors(&p).is_empty(), "{:#?}", p.diagnostics);
    let contour: Vec<El> =
        outside_contour().iter().map(|e| El { from: [-e.from[0], e.from[1]], to: [-e.to[0], e.to[1]], centre: e.centre.map(|c| [-c[0], c[1]]), ccw: !e.ccw, kind: e.kind }).collect();
    let ours = path(&p, 7..=14, [0.0, -r]);
    let got = reference(r, "left", &contour, &ours);
    assert!(got["radius_error_mm"].as_f64().unwrap() < 1e-4 && got["hausdorff_mm"].as_f64().unwrap() < TOLERANCE * r, "{got}");
}

/// The feed on arcs under compensation (Fundamentals 10.2004 §7.11; SINUMERIK 808D Programming
/// and Operating Manual (Milling) 01/2014 p. 79): CFC, the reset state, keeps F on the contour:
/// the tool centre at F (r_cont + r_tool) / r_cont outside an arc, F (r_cont - r_tool) / r_cont
/// inside; CFIN only inside; CFTCP never. Two arcs of radius 20 with a 3 mm tool at F400: the
/// outside one at 400 x 23/20 = 460, the inside one at 400 x 17/20 = 340.
#[test]
fn cfc_and_cfin_keep_the_feed_on_the_contour_of_arcs() {
    // G42 from (0, 0) along +X: a counter-clockwise arc about (0, 20) has its centre on the left, the
    // tool on its outside; the clockwise one after it, about (0, 60), its centre on the right, the
    // tool inside. They meet tangentially at (0, 40).
    let text = |head: &str| format!("N1 T3 D1 M6\nN2 G90 G71 {head}\nN3 G0 X-20 Y-5 Z5\nN4 G1 G42 X0 Y0 F400\nN5 G3 X0 Y40 CR=-20\nN6 G2 X0 Y80 CR=-20\nN7 G1 G40 X-20 Y85\nN8 M30\n");
    let t = table("T3 P3 D6\n");
    let arcs = |head: &str| {
        let p = read(&text(head), Dialect::Sinumerik, "c.mpf", &t);
        assert!(errors(&p).is_empty(), "{head}: {:#?}", p.diagnostics);
        let a: Vec<f64> = [5, 6].iter().map(|n| feed(p.blocks.iter().find(|b| b.number == Some(*n) && b.motion.is_arc()).unwrap())).collect();
        (a[0], a[1])
    };
    for (head, want) in [("", (460.0, 340.0)), ("CFC", (460.0, 340.0)), ("CFIN", (400.0, 340.0)), ("CFTCP", (400.0, 400.0))] {
        let (outer, inner) = arcs(head);
        assert!((outer - want.0).abs() < 1e-9 && (inner - want.1).abs() < 1e-9, "{head}: {outer} {inner}, want {want:?}");
    }
    // Without compensation the tool centre is on the contour: F everywhere.
    let plain = text("CFC").replace("G42 ", "").replace("G40 ", "");
    let p = read(&plain, Dialect::Sinumerik, "c.mpf", &t);
    assert!(p.blocks.iter().filter(|b| b.motion.is_arc()).all(|b| feed(b) == 400.0));
    // CFC at an outside corner: the transition circle's feed is in no manual; refused there.
    let p = read(&outside(""), Dialect::Sinumerik, "c.mpf", &table("T3 P3 D6\n"));
    assert!(errors(&p).iter().any(|(l, _, m)| *l == 10 && m.contains("CFC")), "{:#?}", errors(&p));
}

/// What the 840D does and this reader does not read, and the control's own refusals, each at its
/// line and column.
#[test]
fn trc_refusals_name_the_rule() {
    let t = table("T3 P3 D6\nT4 P4 D8\n");
    let body = |mid: &str| format!("T3 D1\nM6\nG0 X-20 Y-20 Z5 F500\n{mid}\nX40\nG40 G1 X60 Y-20\nM30\n");
    let cases: Vec<(String, &str, &str)> = vec![
        (body("G2 G41 X0 Y0 CR=30"), "4:4:", "G0 or G1"),
        (body("G41 G1 Z-2"), "4:1:", "without X or Y"),
        (body("G41 KONT G1 X0 Y0"), "4:1:", "KONT"),
        (body("G451 G41 G1 X0 Y0"), "4:6:", "G451"),
        (body("DISC=50 G41 G1 X0 Y0"), "4:9:", "DISC=50"),
        (body("OFFN=1 G41 G1 X0 Y0"), "4:8:", "OFFN=1"),
        (body("G41 G1 X0 Y0\nG42 X10"), "5:1:", "change of side"),
        (body("G18 G41 G1 X0 Y0"), "4:1:", "G18 or G19"),
        (body("G41 G1 X0 Y0\nG19 X10"), "5:1:", "alarm 10757"),
        (body("G41 G1 X0 Y0\nT4 M6"), "5:4:", "M6"),
        (body("G41 G1 X0 Y0\nC90"), "5:1:", "rotary axis"),
        (body("G41 G1 X0 Y0\nG0 X10"), "5:1:", "G0 move inside"),
        (body("G41 G1 X0 Y0\nTRAORI"), "5:1:", "TRAORI with tool radius compensation"),
        (body("G41 G1 X0 Y0\nTRANS X5"), "5:1:", "TRANS with tool radius compensation"),
        (body("G41 G1 X0 Y0\nZ-1\nM8\nF300\nZ-2"), "8:1:", "alarm 10762"),
        (body("D2 G41 G1 X0 Y0"), "4:4:", "D2"),
        (body("CDON"), "4:1:", "collision detection"),
        (body("G41 G1 X0 Y0\nG40 X10"), "5:1:", "no selection takes place"),
        ("T3 D1\nG0 X-20 Y-20\nG41 G1 X0 Y0\nX40\nG40 X60\nM30\n".into(), "3:1:", "without M6"),
        ("G0 X-20 Y-20\nG41 G1 X0 Y0\nX40\nG40 X60\nM30\n".into(), "2:1:", "no tool was loaded"),
        (body("TRAORI\nG41 G1 X0 Y0"), "5:1:", "TRAORI on"),
        (body("G41 G1 X0 Y0\nG55 X10"), "5:1:", "settable frame"),
        (body("G41 G1 X0 Y0\nX10 D0"), "5:5:", "tool edge D"),
        (body("G41 G1 X0 Y0\nG93 X10 F2"), "5:1:", "inverse-time"),
        (body("G93\nG41 G1 X0 Y0 F2"), "5:1:", "inverse-time"),
    ];
    let cases: Vec<(&str, &str, &str)> = cases.iter().map(|(t, a, n)| (t.as_str(), *a, *n)).collect();
    refuses_each(Dialect::Sinumerik, &t, &cases);
    // Without a tool table the radius is not known.
    let p = read(&body("G41 G1 X0 Y0"), Dialect::Sinumerik, "c.mpf", &ReadOptions::default());
    has(&p, 4, 1, "--tool-table");
    // D0: no offsets, the contour as programmed; three blocks without a move in the plane are taken.
    let p = read(&body("D0 G41 G1 X0 Y0\nZ-1\nM8\nZ-2"), Dialect::Sinumerik, "c.mpf", &t);
    assert!(errors(&p).is_empty(), "{:#?}", p.diagnostics);
    assert!(p.blocks.iter().any(|b| b.targets.x == Some(0.0) && b.targets.y == Some(0.0)));
}

/// A tool called by name, `T="MILL_D8"`, takes the radius of the TNC-style table's NAME row; a
/// contour running to the program's end without G40 is let out there.
#[test]
fn a_named_tool_and_a_contour_open_at_the_end() {
    let t = table("BEGIN TOOL.T MM\nT    NAME       R      DR\n4    MILL_D8    +4     +0\n[END]\n");
    let text = "N1 T=\"MILL_D8\" D1\nN2 M6\nN3 G0 X-20 Y-20 Z5 CFTCP\nN4 G1 G41 X0 Y0 F300\nN5 Y40\nN6 X40\nN7 M30\n";
    let p = read(text, Dialect::Sinumerik, "c.mpf", &t);
    assert!(errors(&p).is_empty(), "{:#?}", p.diagnostics);
    // G41 along +Y: the tool on the left, -X: N4 ends at (-4, 0); N5 at the corner's equidistant
    // (-4, 40), the transition circle to (0, 44), N6 to (40, 44), left perpendicular there.
    let at = |n: u64| p.blocks.iter().filter(|b| b.number == Some(n)).last().map(|b| (b.targets.x.unwrap() / MM, b.targets.y.unwrap() / MM)).unwrap();
    let close = |a: (f64, f64), b: (f64, f64)| (a.0 - b.0).abs() < 1e-9 && (a.1 - b.1).abs() < 1e-9;
    assert!(close(at(4), (-4.0, 0.0)), "{:?}", at(4));
    assert!(close(at(5), (-4.0, 40.0)), "{:?}", at(5));
    assert!(close(at(6), (40.0, 44.0)), "{:?}", at(6));
    // M30 comes after the held move.
    let end = p.blocks.iter().position(|b| b.events.iter().any(|e| e == "M30")).unwrap();
    let last_move = p.blocks.iter().rposition(|b| b.number == Some(6)).unwrap();
    assert!(end > last_move);
}

/// In a plane swivelled by CYCLE800 (the FTV5's data set, mode 57 axis by axis: _A 30, a turn of
/// 30 deg about X) the contour is the plane's: each compensated point of the tilted reading is the
/// flat reading's turned by Rx(30 deg), as the TNC's are in its tilted working plane.
#[test]
fn in_a_swivelled_plane_the_offsets_are_the_planes() {
    let ftv5 = fiveaxis::machine::Machine::builtin("cincinnati-ftv5").unwrap();
    let mut options = ReadOptions::default().on(&ftv5);
    options.tool_table = table("T3 P3 D6\n").tool_table;
    let flat = read(&outside("CFTCP"), Dialect::Sinumerik, "c.mpf", &options);
    let swivelled = outside("CFTCP").replace("N4 G0", "N35 CYCLE800(0,\"R_DATA\",0,57,0,0,0,30,0,0,0,0,0,1)\nN4 G0");
    let tilted = read(&swivelled, Dialect::Sinumerik, "c.mpf", &options);
    assert!(errors(&flat).is_empty(), "{:#?}", flat.diagnostics);
    assert!(errors(&tilted).is_empty(), "{:#?}", tilted.diagnostics);
    let (s, c) = (30f64.to_radians().sin(), 30f64.to_radians().cos());
    let points = |p: &Program| -> Vec<[f64; 3]> {
        p.blocks.iter().filter(|b| b.number.is_some_and(|n| (6..=15).contains(&n))).map(|b| [b.targets.x.unwrap(), b.targets.y.unwrap(), b.targets.z.unwrap_or(f64::NAN)]).collect()
    };
    // An arc in the swivelled plane has its centre in the workpiece, as its end point: N8's centre
    // is (60, 10) in the plane (this was the plane's own coordinates, unturned, before), 10 mm in
    // the plane from the programmed arc's end without compensation and 13 mm from the tool centre's
    // with it.
    let turn = |p: [f64; 3]| [p[0], c * p[1] - s * p[2], s * p[1] + c * p[2]];
    let back = |p: [f64; 3]| [p[0], c * p[1] + s * p[2], -s * p[1] + c * p[2]];
    let plain = read(&swivelled.replace("G42 ", "").replace("G40 ", ""), Dialect::Sinumerik, "c.mpf", &options);
    for (p, rho) in [(&plain, 10.0), (&tilted, 13.0)] {
        let b = p.blocks.iter().find(|b| b.number == Some(8) && b.motion.is_arc()).expect("N8");
        let a = b.arc.as_ref().unwrap();
        let centre = back(a.centre);
        assert!((centre[0] / MM - 60.0).abs() < 1e-9 && (centre[1] / MM - 10.0).abs() < 1e-9 && a.frame.is_some(), "{a:?}");
        let end = back([b.targets.x.unwrap(), b.targets.y.unwrap(), b.targets.z.unwrap()]);
        let d = (end[0] - centre[0]).hypot(end[1] - centre[1]) / MM;
        assert!((d - rho).abs() < 1e-9, "{d}");
    }
    let (f, t) = (points(&flat), points(&tilted));
    assert_eq!(f.len(), t.len());
    assert!(f.len() > 10, "{f:?}");
    for (a, b) in f.iter().zip(&t) {
        // Z is the plunge's -2 where a block leaves it out.
        let want = turn([a[0], a[1], if a[2].is_nan() { -2.0 * MM } else { a[2] }]);
        assert!((0..3).all(|k| (b[k] - want[k]).abs() < 1e-9), "flat {a:?} turned {want:?}, tilted {b:?}");
    }
}

/// Programs in files beside the main one, by name (as the control finds a subprogram).
#[derive(Debug)]
struct Beside(Vec<(&'static str, &'static str)>);

impl fiveaxis::program::SubroutineFiles for Beside {
    fn find_file(&self, names: &[String], _any_case: bool, own_dir: bool) -> Result<Option<(String, Vec<u8>)>, String> {
        if !own_dir {
            return Ok(None);
        }
        Ok(names.iter().find_map(|n| self.0.iter().find(|(f, _)| f.eq_ignore_ascii_case(n))).map(|(f, t)| (f.to_string(), t.as_bytes().to_vec())))
    }
}

/// Where compensation stops the program nothing after it runs, whatever else the line holds; an
/// empty block too many is taken back whole (its Z too); a contour in a subprogram returns with
/// its M17 held and the caller runs on to its end.
#[test]
fn a_stop_ends_the_program_a_refused_block_leaves_nothing_and_m17_returns() {
    let t = table("T3 P3 D6\n");
    // CFC (the reset state) at the outside corner of line 6, which also says G64.
    let text = "T3 D1\nM6\nG0 X0 Y10 F500\nG41 G1 X0 Y0\nG1 X20 Y0\nG1 X20 Y-10 G64\nG1 X0 Y-10\nG40 G1 X0 Y-20\nM30\n";
    let p = read(text, Dialect::Sinumerik, "c.mpf", &t);
    assert!(errors(&p).iter().any(|(l, _, m)| *l == 6 && m.contains("CFC")), "{:#?}", errors(&p));
    assert!(p.blocks.iter().all(|b| b.line < 7), "{:#?}", p.blocks.iter().map(|b| b.line).collect::<Vec<_>>());
    // The fourth empty block (line 8, Z-2) is refused: X40 after it runs at the Z before, -1.
    let text = "T3 D1\nM6\nG0 X-20 Y-20 Z5 F500 CFTCP\nG41 G1 X0 Y0\nZ-1\nM8\nF300\nZ-2\nX40\nG40 G1 X60 Y-20\nM30\n";
    let p = read(text, Dialect::Sinumerik, "c.mpf", &t);
    has(&p, 8, 1, "alarm 10762");
    let x40 = p.blocks.iter().find(|b| b.line == 9).expect("line 9");
    assert!((x40.targets.z.unwrap() / MM + 1.0).abs() < 1e-12, "{:?}", x40.targets);
    // The contour's two elements in CONT1, the corner between them rounded, M17 held with the last.
    let main = "N1 T3 D1\nN2 M6\nN3 G0 X-20 Y-20 Z5 F500 CFTCP\nN4 G1 G41 X0 Y0\nN5 CONT1\nN6 G40 G1 X-20 Y60\nN7 G0 Z50\nN8 M30\n";
    let options = ReadOptions { subroutine_files: Some(std::sync::Arc::new(Beside(vec![("CONT1.SPF", "G1 Y40\nX40\nM17\n")]))), ..t };
    let p = read(main, Dialect::Sinumerik, "MAIN.MPF", &options);
    assert!(errors(&p).is_empty(), "{:#?}", p.diagnostics);
    assert!(p.blocks.iter().any(|b| b.number == Some(7) && b.targets.z.is_some_and(|z| (z / MM - 50.0).abs() < 1e-12)), "N7 ran");
    assert!(p.blocks.iter().any(|b| b.events.iter().any(|e| e == "M30")), "M30 ran");
    // N4 ends perpendicular to CONT1's first element (+Y) on its left, (-3, 0); the corner at (0, 40)
    // is rounded about it to (0, 43), and X40 ends at (40, 43).
    let ends: Vec<(f64, f64)> = p.blocks.iter().filter_map(|b| Some((b.targets.x? / MM, b.targets.y? / MM))).collect();
    for want in [(-3.0, 0.0), (-3.0, 40.0), (0.0, 43.0), (40.0, 43.0), (-20.0, 60.0)] {
        assert!(ends.iter().any(|e| (e.0 - want.0).abs() < 1e-9 && (e.1 - want.1).abs() < 1e-9), "{want:?} in {ends:?}");
    }
}

/// Under a frame turned about the tool axis without TRAORI (`ROT Z30`: a frame that turns the axes'
/// coordinates alone) the compensated contour is the flat one turned by Rz(30 deg), point for point;
/// a frame that tilts the plane without TRAORI (`AROT Y30`) leaves compensation in the basic
/// system's G17 plane (CUT2D), which is not read: refused at the selection.
#[test]
fn under_a_frame_turning_the_axes_the_offsets_turn_with_it() {
    let mut options = ReadOptions::default();
    options.tool_table = table("T3 P3 D6\n").tool_table;
    let flat = read(&outside("CFTCP"), Dialect::Sinumerik, "c.mpf", &options);
    let turned = read(&outside("CFTCP").replace("N4 G0", "N35 ROT Z30\nN4 G0"), Dialect::Sinumerik, "c.mpf", &options);
    assert!(errors(&flat).is_empty() && errors(&turned).is_empty(), "{:#?}", turned.diagnostics);
    let (s, c) = (30f64.to_radians().sin(), 30f64.to_radians().cos());
    let xy = |p: &Program| -> Vec<[f64; 2]> { p.blocks.iter().filter(|b| b.number.is_some_and(|n| (6..=15).contains(&n))).map(|b| [b.targets.x.unwrap(), b.targets.y.unwrap()]).collect() };
    let (f, t) = (xy(&flat), xy(&turned));
    assert!(f.len() > 10 && f.len() == t.len(), "{f:?} {t:?}");
    for (a, b) in f.iter().zip(&t) {
        let want = [c * a[0] - s * a[1], s * a[0] + c * a[1]];
        assert!((b[0] - want[0]).abs() < 1e-9 && (b[1] - want[1]).abs() < 1e-9, "flat {a:?} turned {want:?}, read {b:?}");
    }
    assert!(turned.blocks.iter().all(|b| !b.tcp));
    let tilted = read(&outside("CFTCP").replace("N4 G0", "N35 AROT Y30\nN4 G0"), Dialect::Sinumerik, "c.mpf", &options);
    assert!(errors(&tilted).iter().any(|(l, _, m)| *l == 7 && m.contains("tilts the plane")), "{:#?}", errors(&tilted));
}
