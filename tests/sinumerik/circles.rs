//! The 840D's circles given otherwise than by a centre or a radius (`CIP`, `CT`, `AR=`, polar
//! coordinates, a full circle by its centre), each against the manual's example or one worked by
//! hand.

use super::*;

/// `CIP` (Programming Manual Fundamentals 12/2019 §2.9): a circle through an intermediate point,
/// modal. The SINUMERIK 808D milling manual's example `CIP X50 Y40 I1=40 J1=45` from X30 Y40: the
/// circle through (30,40), (40,45), (50,40) has its centre on x = 40 (the chord's bisector) at
/// y = 32.5 ((30-40)^2 + (40-y)^2 = (45-y)^2), radius 12.5, and runs over the top: clockwise (G2).
/// The next block, CIP still in effect, from (50,40) through (60,35) to (70,40): centre (60, 47.5),
/// counter-clockwise. G91 writes the same circle from the start. G1 ends CIP.
#[test]
fn cip_is_the_circle_through_its_three_points() {
    let text = "N10 G17 G90 G71 G94\nN20 G0 X30 Y40 Z0\nN30 G1 F100\nN40 CIP X50 Y40 I1=40 J1=45\nN50 X70 Y40 I1=60 J1=35\nN60 G1 X80\nN70 G0 X30 Y40\nN80 G91 CIP X20 Y0 I1=10 J1=5\n";
    let p = sin(text);
    assert!(errors(&p).is_empty(), "{:#?}", errors(&p));
    let arc = |line: usize, motion: Motion, centre: [f64; 2], end: [f64; 2]| {
        let b = blocks_of(&p, line);
        let b = b.last().unwrap_or_else(|| panic!("line {line}"));
        let a = b.arc.as_deref().unwrap_or_else(|| panic!("line {line}: no arc {b:?}"));
        assert_eq!(b.motion, motion, "line {line}");
        assert!((a.centre[0] - centre[0] * MM).abs() < 1e-9 && (a.centre[1] - centre[1] * MM).abs() < 1e-9, "line {line}: {:?}", a.centre);
        assert!(close(b.targets.x, end[0]) && close(b.targets.y, end[1]), "line {line}: {b:?}");
    };
    arc(4, Motion::ArcCw, [40.0, 32.5], [50.0, 40.0]);
    arc(5, Motion::ArcCcw, [60.0, 47.5], [70.0, 40.0]);
    assert_eq!(blocks_of(&p, 6)[0].motion, Motion::Linear);
    arc(8, Motion::ArcCw, [40.0, 32.5], [50.0, 40.0]);
    // Refused: no intermediate point, a circle inclined to G17's plane, three points on a line, CIP
    // beside G1, an intermediate point without CIP; after a refused CIP line a move gives its own G.
    let head = "N10 G17 G90 G71 G94\nN20 G0 X30 Y40 Z0\nN30 G1 F100\n";
    for (block, col, message) in [
        ("CIP X50 Y40", 1, "without its intermediate point"),
        ("CIP X50 Y40 I1=40 J1=45 K1=5", 13, "not at one Z"),
        ("CIP X50 Y40 I1=40 J1=40", 13, "on one line"),
        ("G1 CIP X50 Y40 I1=40 J1=45", 1, "G1 with CIP"),
        ("G1 X50 Y40 I1=40 J1=45", 12, "without CIP in effect"),
        ("CIP X50 I1=40 J1=45 CR=5", 21, "takes no radius"),
    ] {
        refused_once(&format!("{head}{block}\n"), 4, Some(col), message);
    }
    // A centre alone under CIP is no full circle (that is G2/G3's): refused where it stands.
    refused_once(&format!("{head}CIP X50 Y40 I1=40 J1=45\nJ-5\n"), 5, Some(1), "CIP with J-5");
    let after = errors(&sin(&format!("{head}CIP X50 Y40\nX60 Y50\n")));
    assert!(after.iter().any(|e| e.0 == 5), "{after:?}");
}

/// A circle with a centre and no end point is a full circle (Programming Manual Fundamentals
/// 10.2004 §4.6: "If the circle is programmed with a center point but no end point, the result is
/// a full circle"), its centre absolute (`I=AC() J=AC()`) or from the start: from X10 Y0 about the
/// origin, radius 10, back at X10 Y0, a path of 2 pi 10 = 62.832 mm (at F600 mm/min, 6.283 s).
/// With a radius and no end point there is no circle (CR= needs one), as before.
#[test]
fn a_centre_without_an_end_point_is_a_full_circle() {
    let head = "N10 G17 G90 G71 G94\nN20 G0 X10 Y0 Z0\nN30 G1 F600\n";
    for block in ["N40 G3 I=AC(0) J=AC(0)", "N40 G2 I-10 J0", "N40 G3 I-10"] {
        let p = sin(&format!("{head}{block}\n"));
        assert!(errors(&p).is_empty(), "{block}: {:#?}", errors(&p));
        let b = *blocks_of(&p, 4).last().unwrap();
        let a = b.arc.as_deref().unwrap_or_else(|| panic!("{block}: no arc {b:?}"));
        assert!(a.centre[0].abs() < 1e-12 && a.centre[1].abs() < 1e-12, "{block}: {:?}", a.centre);
        assert!(close(b.targets.x, 10.0) && close(b.targets.y, 0.0), "{block}: {b:?}");
        let m = fiveaxis::machine::Machine::builtin("generic-bc-table").unwrap();
        let t = fiveaxis::path::Trajectory::from_program(&p, &m, &fiveaxis::path::PathOptions::default());
        let length: f64 = t.segments.iter().filter(|s| s.line == 4).map(|s| s.length).sum();
        assert!((length / MM / (std::f64::consts::TAU * 10.0) - 1.0).abs() < 1e-6, "{block}: {} mm", length / MM);
    }
    let e = errors(&sin(&format!("{head}N40 G3 CR=10\n")));
    assert!(e.len() == 1 && e[0].0 == 4, "{e:?}");
}

/// `CT`, the circle with a tangential transition (840D Programming Manual Fundamentals 10.2004 p.
/// 4-33: the tangent at its start is "the end tangent of the programmed contour of the previous
/// block with a traversing movement"; CT is modal), worked by hand in G17: along +X to X10 Y0, `CT
/// X20 Y10` is the quarter circle about (10, 10), counter-clockwise; from there (its end tangent +Y)
/// `X30 Y20`, CT still in effect, is the one about (30, 10), clockwise; with Z-5 the first is a
/// helix. The end on the tangent's line ahead is a straight line (SINUMERIK ONE 12/2019 §2.9, "a
/// straight line is produced instead of a circle"). The manual's own example, in G18: from X23.293
/// Z0 to X40 Z-30, `CT X58.146 Z-42` leaves along that line (its centre on the line's normal
/// through X40 Z-30) and ends at its end point, as far from the centre as the start.
#[test]
fn ct_leaves_the_contour_along_its_tangent() {
    let head = "N10 G17 G90 G71 G94\nN20 G0 X0 Y0 Z0\nN30 G1 X10 Y0 F500\n";
    let arc = |p: &fiveaxis::program::Program, line: usize| {
        let b = *blocks_of(p, line).last().unwrap_or_else(|| panic!("line {line}"));
        let a = b.arc.as_deref().map(|a| [a.centre[0] / MM, a.centre[1] / MM, a.centre[2] / MM]);
        (b.motion, a, [b.targets.x.map(|v| v / MM), b.targets.y.map(|v| v / MM), b.targets.z.map(|v| v / MM)])
    };
    let near = |a: [f64; 3], b: [f64; 2]| (a[0] - b[0]).abs() < 1e-9 && (a[1] - b[1]).abs() < 1e-9;
    let p = sin(&format!("{head}N40 CT X20 Y10\nN50 X30 Y20\nN60 G1 X40\n"));
    assert!(errors(&p).is_empty(), "{:#?}", errors(&p));
    let (m, c, e) = arc(&p, 4);
    assert!(m == Motion::ArcCcw && near(c.unwrap(), [10.0, 10.0]) && e[0] == Some(20.0) && e[1] == Some(10.0), "{m:?} {c:?} {e:?}");
    let (m, c, e) = arc(&p, 5);
    assert!(m == Motion::ArcCw && near(c.unwrap(), [30.0, 10.0]) && e[0] == Some(30.0) && e[1] == Some(20.0), "{m:?} {c:?} {e:?}");
    assert_eq!(arc(&p, 6).0, Motion::Linear);
    let p = sin(&format!("{head}N40 CT X20 Y10 Z-5\n"));
    let (m, c, e) = arc(&p, 4);
    assert!(m == Motion::ArcCcw && near(c.unwrap(), [10.0, 10.0]) && e[2] == Some(-5.0), "{m:?} {c:?} {e:?}");
    let p = sin(&format!("{head}N40 CT X25 Y0\n"));
    assert!(errors(&p).is_empty() && arc(&p, 4).0 == Motion::Linear && arc(&p, 4).1.is_none(), "{:?}", arc(&p, 4));
    // The manual's G18 example: the centre on the normal of N115's line at its end, equidistant.
    let p = sin("N100 G18 G90 G71 G94 D0 G0 X23.293 Y0 Z0\nN110 G1 X23.293 Z0 F10\nN115 X40 Z-30\nN120 CT X58.146 Z-42\nN125 G1 X70\n");
    assert!(errors(&p).is_empty(), "{:#?}", errors(&p));
    let (_, c, e) = arc(&p, 4);
    let c = c.unwrap();
    let (line, radius) = ([40.0 - 23.293, -30.0 - 0.0], [40.0 - c[0], -30.0 - c[2]]);
    assert!((line[0] * radius[0] + line[1] * radius[1]).abs() < 1e-9 * 40.0 * 40.0, "{c:?}");
    let r_end = (58.146 - c[0]).hypot(-42.0 - c[2]);
    assert!((radius[0].hypot(radius[1]) - r_end).abs() < 1e-9, "{c:?}");
    assert!(e[0] == Some(58.146) && e[2] == Some(-42.0), "{e:?}");
    // TURN= with CT (ONE 12/2019 §2.9): the same circle about (10, 10) with one full turn more; on
    // the limit case's straight line TURN=0 is the line, TURN=1 refused ("TURN must either not be
    // programmed or the value must be TURN=0").
    let p = sin(&format!("{head}N40 CT X20 Y10 TURN=1\n"));
    assert!(errors(&p).is_empty(), "{:#?}", errors(&p));
    let b = *blocks_of(&p, 4).last().unwrap();
    let a = b.arc.as_deref().unwrap();
    assert!(b.motion == Motion::ArcCcw && a.extra_turns == 1 && near([a.centre[0] / MM, a.centre[1] / MM, 0.0], [10.0, 10.0]), "{b:?}");
    let p = sin(&format!("{head}N40 CT X25 Y0 TURN=0\n"));
    assert!(errors(&p).is_empty() && arc(&p, 4).0 == Motion::Linear && arc(&p, 4).2[0] == Some(25.0), "{:?} {:?}", errors(&p), arc(&p, 4));
    refused_once(&format!("{head}N40 CT X25 Y0 TURN=1\n"), 4, Some(15), "TURN must be left out or 0");
    // Turns without an end point, written or under modal CT, and TURN twice, are refused naming
    // TURN (it is read as a P word); so is a TURN on a line, as written.
    refused_once(&format!("{head}N40 CT TURN=1\nN50 G1 X20\n"), 4, Some(8), "CT with TURN=1: full turns without an end point");
    refused_once(&format!("{head}N40 CT X20 Y10\nN50 TURN=2\nN60 G1 X30\n"), 5, Some(5), "CT with TURN=2: full turns without an end point");
    refused_once(&format!("{head}N40 CT X20 Y10 TURN=0 TURN=1\n"), 4, Some(23), "TURN written twice in one block");
    refused_once(&format!("{head}N40 G1 X20 TURN=0\n"), 4, Some(12), "word TURN=0 without a G code that takes it");
    // Refused, each where it stands: no move in the plane before it, the end behind the start on
    // the tangent, a centre written, the plane changed since the tangent, CT with G2.
    for (text, line, col, message) in [
        ("N10 G17 G90 G71 G94\nN20 G0 X0 Y0 Z5\nN30 G1 Z0 F500\nN40 CT X10 Y10\n", 4, 5, "no contour element"),
        (&format!("{head}N40 CT X0 Y0\n"), 4, 5, "behind the start"),
        (&format!("{head}N40 CT X20 Y10 I5\n"), 4, 16, "give the centre"),
        (&format!("{head}N40 G18\nN50 CT X20 Z10\n"), 5, 5, "plane or the frame"),
        (&format!("{head}N40 G2 CT X20 Y10\n"), 4, 5, "G2 with CT"),
        // A centre alone under CT is no full circle (that is G2/G3's, with a centre): refused.
        (&format!("{head}N40 CT X20 Y10\nN50 I5\n"), 5, 5, "CT with I5"),
        // The first move's start is where the tool stood, which the program does not say.
        ("N10 G17 G90 G71 G94\nN20 G0 X10 Y5 Z0\nN30 CT X20 Y15 F600\n", 3, 5, "no contour element"),
    ] {
        refused_once(text, line, Some(col), message);
    }
    // A line of CT in effect refused (its tangent turned by a frame, not read): the control made
    // the circle, so the move after it starts where this reader does not know.
    let e = errors(&sin(&format!("{head}N40 CT X20 Y10\nN50 ROT RPL=10\nN60 X10 Y20\nN70 G1 X30\n")));
    assert!(e.len() == 2 && e[0].0 == 6 && e[1].0 == 7 && e[1].2.contains("line 6's CT"), "{e:?}");
}

/// `AR=`, the opening angle (Programming Manual Fundamentals 12/2019 §2.9.6.4), with the manual's
/// own example: from X67.5 Y80.211, `G3 X17.203 Y38.029 AR=140.134` and `G3 I-17.5 J-30.211
/// AR=140.134` are one arc about X50 Y50 (radius 34.913, the CR= example's), ending at X17.203
/// Y38.029. By hand: the chord is 65.644 long, its middle (42.3515, 59.120), the centre
/// (32.822 / tan 70.067 deg) = 11.895 from it on the chord's left; G2 puts it on the right,
/// (34.708, 68.234), as does G3 with the larger opening 219.866 deg.
#[test]
fn ar_gives_the_circle_its_opening_angle_makes() {
    let head = "N10 G17 G90 G71 G94 F500\nN20 G0 X67.5 Y80.211 Z0\n";
    let centre_end = |block: &str| {
        let p = sin(&format!("{head}{block}\n"));
        assert!(errors(&p).is_empty(), "{block}: {:#?}", errors(&p));
        let b = *blocks_of(&p, 3).last().unwrap();
        let a = b.arc.as_deref().unwrap();
        (b.motion, [a.centre[0] / MM, a.centre[1] / MM], [b.targets.x.unwrap() / MM, b.targets.y.unwrap() / MM])
    };
    let near = |a: [f64; 2], b: [f64; 2], tol: f64| (a[0] - b[0]).abs() < tol && (a[1] - b[1]).abs() < tol;
    let (m, c, e) = centre_end("N30 G3 X17.203 Y38.029 AR=140.134");
    assert!(m == Motion::ArcCcw && near(c, [50.0, 50.0], 0.01) && near(e, [17.203, 38.029], 1e-9), "{m:?} {c:?} {e:?}");
    let (m, c, e) = centre_end("N30 G3 I-17.5 J-30.211 AR=140.134");
    assert!(m == Motion::ArcCcw && near(c, [50.0, 50.0], 1e-9) && near(e, [17.203, 38.029], 0.002), "{m:?} {c:?} {e:?}");
    let (m, c, _) = centre_end("N30 G2 X17.203 Y38.029 AR=140.134");
    assert!(m == Motion::ArcCw && near(c, [34.708, 68.234], 0.01), "{m:?} {c:?}");
    let (m, c, _) = centre_end("N30 G3 X17.203 Y38.029 AR=219.866");
    assert!(m == Motion::ArcCcw && near(c, [34.708, 68.234], 0.01), "{m:?} {c:?}");
    for (block, message) in [
        ("N30 G3 X17.203 Y38.029 AR=360", "less than 360"),
        ("N30 G1 X17.203 Y38.029 AR=140", "belongs to a circle"),
        ("N30 G3 X17.203 Y38.029 CR=34.913 AR=140", "with CR="),
        ("N30 G3 X17.203 Y38.029 I-17.5 J-30.211 AR=140", "both an end point and a centre"),
    ] {
        refused_once(&format!("{head}{block}\n"), 3, None, message);
    }
}

/// Polar coordinates (Programming Manual Fundamentals 12/2019 §2.9.3), the SINUMERIK 808D milling
/// manual's example worked by hand: from X0 Y0, `G111 X20 Y10` sets the pole from the workpiece's
/// zero; `G1 RP=50 AP=30` ends at (20 + 50 cos 30, 10 + 50 sin 30) = (63.301, 35); `G110 X-10 Y20`
/// sets the pole from there, (53.301, 55); `RP=30 AP=45` ends at (74.514, 76.213); `G112 X40 Y20`
/// from that pole, (93.301, 75); `RP=30 AP=135` ends at (72.088, 96.213); `AP=IC(-90)` turns on
/// from 135 to 45 deg with the radius kept: (114.514, 96.213). The manual's turning example in G18,
/// `G111 X33.33 Z-54.25`, `G3 RP=30 AP=142.326` from X40 Z-25: the circle about the pole to
/// Z = -54.25 + 30 cos 142.326 = -77.995, X = 33.33 + 30 sin 142.326 = 51.665.
#[test]
fn polar_coordinates_end_where_the_pole_and_angle_say() {
    let text = "N10 G17 G90 G71 G94\nN20 G0 X0 Y0 Z0\nN30 G111 X20 Y10\nN40 G1 RP=50 AP=30 F1000\nN50 G110 X-10 Y20\nN60 G1 RP=30 AP=45\nN70 G112 X40 Y20\nN80 G1 RP=30 AP=135\nN90 AP=IC(-90)\n";
    let p = sin(text);
    assert!(errors(&p).is_empty(), "{:#?}", errors(&p));
    let end = |line: usize, x: f64, y: f64| {
        let b = *blocks_of(&p, line).last().unwrap_or_else(|| panic!("line {line}"));
        assert!(b.targets.x.is_some_and(|v| (v / MM - x).abs() < 1e-3) && b.targets.y.is_some_and(|v| (v / MM - y).abs() < 1e-3), "line {line}: {b:?}");
    };
    end(4, 63.301, 35.0);
    end(6, 74.514, 76.213);
    end(8, 72.088, 96.213);
    end(9, 114.514, 96.213);
    assert!(blocks_of(&p, 3).iter().chain(blocks_of(&p, 5).iter()).all(|b| b.targets.x.is_none()), "a pole is no move");
    let turn = sin("N10 G18 G90 G71 G94 D0\nN20 G1 X40 Z-25 F200\nN30 G111 X33.33 Z-54.25\nN40 G3 RP=30 AP=142.326\n");
    assert!(errors(&turn).is_empty(), "{:#?}", errors(&turn));
    let b = *blocks_of(&turn, 4).last().unwrap();
    let a = b.arc.as_deref().unwrap();
    assert_eq!(b.motion, Motion::ArcCcw);
    assert!((a.centre[0] / MM - 33.33).abs() < 1e-9 && (a.centre[2] / MM + 54.25).abs() < 1e-9, "{:?}", a.centre);
    assert!((b.targets.z.unwrap() / MM + 77.995).abs() < 1e-3 && (b.targets.x.unwrap() / MM - 51.665).abs() < 1e-3, "{b:?}");
    let head = "N10 G17 G90 G71 G94\nN20 G0 X0 Y0 Z0\n";
    for (block, message) in [
        ("N30 G1 AP=30 F100", "no polar radius before it"),
        ("N30 G1 RP=10 AP=IC(30) F100", "no polar angle before it"),
        ("N30 G110 AP=30 RP=10", "G110 AP= RP="),
        ("N30 G1 X5 RP=10 AP=30 F100", "not both"),
        ("N30 G111 X5", "both of the plane's coordinates"),
    ] {
        refused_once(&format!("{head}{block}\n"), 3, None, message);
    }
}

/// CIP's review cases: a block's own G700 (inches, which the lexer gives as G20) holds for its
/// circle, as for a G3 (the same arc, the same time); I1= twice is refused; in CIP a move of a
/// rotary axis alone (no end point, no intermediate point) is refused naming CIP; a refused
/// threading G331 (G group 1) ends CIP, so a later intermediate point is refused.
#[test]
fn cip_reads_its_own_blocks_unit_and_refuses_what_it_cannot() {
    let time = |text: &str| {
        let p = sin(text);
        assert!(errors(&p).is_empty(), "{text}: {:#?}", errors(&p));
        let arc = p.blocks.iter().rev().find(|b| b.arc.is_some()).unwrap();
        (arc.motion, arc.arc.as_deref().unwrap().centre, arc.targets.x, arc.targets.y)
    };
    let cip = time("G17 G90 G71 G94 F10\nG1 X25.4 Y0 Z0\nG700 CIP X0 Y-1 I1=0 J1=1\n");
    let g2 = time("G17 G90 G71 G94 F10\nG1 X25.4 Y0 Z0\nG700 G3 X0 Y-1 I=AC(0) J=AC(0)\n");
    assert_eq!(cip.0, g2.0);
    for k in 0..2 {
        assert!((cip.1[k] - g2.1[k]).abs() < 1e-9, "{cip:?} {g2:?}");
    }
    assert_eq!((cip.2, cip.3), (g2.2, g2.3));
    let head = "G17 G90 G71 G94 F600\nG0 X10 Y0 Z0\nCIP X0 Y-10 I1=0 J1=10\n";
    for (tail, line, message) in [("X10 Y0 I1=-10 J1=0 J1=1\n", 4, "J1 written twice"), ("C90\n", 4, "rotary axes alone"), ("G331 Z-10 K1\nX10 Y0 I1=-10 J1=0\n", 5, "without CIP in effect")] {
        let e = errors(&sin(&format!("{head}{tail}")));
        assert!(e.iter().any(|e| e.0 == line && e.2.contains(message)), "{tail}: {e:?}");
    }
}
