//! Fanuc's and Haas's chamfering and corner R (`,C`, `,R` at the end of a G01, G02 or G03 block),
//! checked against the Fanuc 16i-M manual's example contour (N001-N011: chamfers and corner R
//! between lines and a G03 arc) with every tangent point, centre and chamfer end worked here from
//! the contour's own circles and lines, a chamfer beside an arc by its chord (NCT 2000M §16.1), and
//! what is refused at line:col.

use super::*;

fn fanuc(text: &str) -> Program {
    read(text, Dialect::Fanuc, "c.nc", &ReadOptions::default())
}

/// Each move's motion, X Y end (mm) and arc centre (mm), in order.
fn moves(p: &Program) -> Vec<(Motion, [f64; 2], Option<[f64; 2]>)> {
    let mut at = [0.0; 2];
    let mut out = Vec::new();
    for b in &p.blocks {
        if b.targets.x.is_none() && b.targets.y.is_none() {
            continue;
        }
        at = [b.targets.x.map_or(at[0], |x| x / MM), b.targets.y.map_or(at[1], |y| y / MM)];
        out.push((b.motion, at, b.arc.as_ref().map(|a| [a.centre[0] / MM, a.centre[1] / MM])));
    }
    out
}

fn near(a: [f64; 2], b: [f64; 2]) -> bool {
    (a[0] - b[0]).hypot(a[1] - b[1]) < 1e-9
}

/// The point `d` from `o` towards `c`.
fn toward(o: [f64; 2], c: [f64; 2], d: f64) -> [f64; 2] {
    let l = (c[0] - o[0]).hypot(c[1] - o[1]);
    [o[0] + (c[0] - o[0]) * d / l, o[1] + (c[1] - o[1]) * d / l]
}

/// The manual's example (Fanuc 16i-M, "Chamfering and corner R", N001-N011, its F10 as F100 and
/// its C and R with the comma 0i/30i controls want): C5 at the line-line corners, R8 between the
/// line N004 and the arc N005 (centre (50,55), R30, counter-clockwise), between the arc and the
/// line N006, and between N006 and N007. The fillets worked here: beside the line X50 the centre
/// is 8 from it; beside the circle 30+8 outside it (the path turns right into it) or 30-8 inside
/// (it turns left out of it); the tangent point on the circle lies on the line of the centres.
#[test]
fn the_manuals_contour_has_its_chamfers_and_corner_r() {
    let text = "%\nO0001\nN001 G90 G17 G21 G94\nN002 G00 X10. Y10.\nN003 G01 X50. F100. ,C5.\nN004 Y25. ,R8.\nN005 G03 X80. Y55. R30. ,R8.\nN006 G01 X50. ,R8.\nN007 Y70. ,C5.\nN008 X10. ,C5.\nN009 Y10.\nN010 G00 X0 Y0\nN011 M30\n%\n";
    let p = fanuc(text);
    assert!(errors(&p).is_empty(), "{:#?}", p.diagnostics);
    let o = [50.0, 55.0];
    // N004 (up X50) into N005: right turn, the fillet outside the circle, 8 right of X50.
    let c1 = [58.0, 55.0 - (38.0f64.powi(2) - 8.0f64.powi(2)).sqrt()];
    // N005 into N006 (along Y55 to -X): left turn, the fillet inside the circle, 8 below Y55.
    let c2 = [50.0 + (22.0f64.powi(2) - 8.0f64.powi(2)).sqrt(), 47.0];
    // N006 (-X) into N007 (+Y) at (50,55): right turn.
    let c3 = [58.0, 63.0];
    let want: Vec<(Motion, [f64; 2], Option<[f64; 2]>)> = vec![
        (Motion::Rapid, [10.0, 10.0], None),
        (Motion::Linear, [45.0, 10.0], None),
        (Motion::Linear, [50.0, 15.0], None), // C5: 5 from the corner (50,10) on both lines
        (Motion::Linear, [50.0, c1[1]], None),
        (Motion::ArcCw, toward(o, c1, 30.0), Some(c1)),
        (Motion::ArcCcw, toward(o, c2, 30.0), Some(o)),
        (Motion::ArcCcw, [c2[0], 55.0], Some(c2)),
        (Motion::Linear, [58.0, 55.0], None),
        (Motion::ArcCw, [50.0, 63.0], Some(c3)),
        (Motion::Linear, [50.0, 65.0], None),
        (Motion::Linear, [45.0, 70.0], None), // C5 at (50,70)
        (Motion::Linear, [15.0, 70.0], None),
        (Motion::Linear, [10.0, 65.0], None), // C5 at (10,70)
        (Motion::Linear, [10.0, 10.0], None),
        (Motion::Rapid, [0.0, 0.0], None),
    ];
    let got = moves(&p);
    assert_eq!(got.len(), want.len(), "{got:#?}");
    for (k, (g, w)) in got.iter().zip(&want).enumerate() {
        let centre = match (g.2, w.2) {
            (Some(a), Some(b)) => near(a, b),
            (None, None) => true,
            _ => false,
        };
        assert!(g.0 == w.0 && near(g.1, w.1) && centre, "move {k}: {g:?}, worked {w:?}");
    }
    // Each inserted element at the contour's feed, and numbered by the block that asked for it.
    assert!(p.blocks.iter().filter(|b| b.motion != Motion::Rapid && !b.targets.is_empty()).all(|b| b.feed.is_some_and(|f| (f.value_per_min - 100.0).abs() < 1e-9)));
    assert_eq!(p.blocks.iter().filter(|b| b.number == Some(4)).count(), 2);
}

/// `,C` beside an arc is the chord from the corner: the line up X20 to (20,0), then G02 about
/// (20,20); the chamfer ends on the arc where the circle of radius 4 about the corner meets it,
/// solved here: (x-20)^2 + y^2 = 16 and (x-20)^2 + (y-20)^2 = 400 give y = 0.4.
#[test]
fn a_chamfer_beside_an_arc_ends_at_its_chord() {
    let text = "%\nO0002\nG90 G17 G21 G94\nG00 X20. Y-20.\nG01 Y0. F200. ,C4.\nG02 X0. Y20. I0. J20.\nM30\n%\n";
    let p = fanuc(text);
    assert!(errors(&p).is_empty(), "{:#?}", p.diagnostics);
    let m = moves(&p);
    let on_arc = [20.0 - (16.0f64 - 0.16).sqrt(), 0.4];
    assert_eq!(m.len(), 4, "{m:#?}");
    assert!(m[1].0 == Motion::Linear && near(m[1].1, [20.0, -4.0]), "{m:?}");
    assert!(m[2].0 == Motion::Linear && near(m[2].1, on_arc), "{m:?}");
    assert!(m[3].0 == Motion::ArcCw && near(m[3].1, [0.0, 20.0]) && m[3].2.is_some_and(|c| near(c, [20.0, 20.0])), "{m:?}");
    let chord = (on_arc[0] - 20.0).hypot(on_arc[1]);
    assert!((chord - 4.0).abs() < 1e-12);
}

/// In inches, and without a decimal point (least input increments, as X is): `,R2` is 0.0002 in.
#[test]
fn a_comma_word_takes_the_programs_unit_and_increments() {
    let p = fanuc("%\nO0003\nG90 G17 G20 G94\nG00 X0. Y0.\nG01 X1. F10. ,R.25\nY1.\nX0. ,R2\nY0.\nM30\n%\n");
    assert!(errors(&p).is_empty(), "{:#?}", p.diagnostics);
    let m = moves(&p);
    let inch = 25.4;
    assert!(near(m[1].1, [0.75 * inch, 0.0]) && m[2].2.is_some_and(|c| near(c, [0.75 * inch, 0.25 * inch])), "{m:#?}");
    assert!(near(m[4].1, [0.0002 * inch, inch]), "{m:#?}");
}

/// What the manuals at hand do not settle, or forbid, is refused at the word.
#[test]
fn chamfers_and_corner_r_are_refused_where_not_read() {
    let head = "%\nO0004\nG90 G17 G21 G94\nG00 X0. Y0.\n";
    refuses_each(
        Dialect::Fanuc,
        &ReadOptions::default(),
        &[
            (&format!("{head}G01 X10. F100. ,C1. ,R1.\nY10.\nM30\n%\n"), "5:21:", "in one block"),
            (&format!("{head}G01 X10. F100. ,C1.\nM08\nY10.\nM30\n%\n"), "5:16:", "moves nothing"),
            (&format!("{head}G01 X10. F100. ,R1.\nY10. F200.\nM30\n%\n"), "5:16:", "changes the feed"),
            (&format!("{head}G01 X10. F100. ,R20.\nY10.\nM30\n%\n"), "5:16:", "too large"),
            (&format!("{head}G01 X10. F100. ,A30.\nM30\n%\n"), "5:16:", "angle (,A) is not read"),
            (&format!("{head}G00 X10. ,C1.\nG01 Y10. F100.\nM30\n%\n"), "5:10:", "not a line or circle at a feed"),
            (&format!("{head}G01 X10. F100. ,C1.\nG00 Y10.\nM30\n%\n"), "5:16:", "not a line or circle at a feed"),
            (&format!("{head}G01 X10. F100. ,C1.\nM30\n%\n"), "5:16:", "program ends"),
            (&format!("{head}G01 X10. F100. ,C1.\nG18 Y10.\nM30\n%\n"), "5:16:", "plane changes"),
            (&format!("{head}G01 X10. Z-1. F100. ,C1.\nY10.\nM30\n%\n"), "5:21:", "not a line or circle at a feed"),
            (&format!("{head}G01 X10. F100. ,C-1.\nY10.\nM30\n%\n"), "5:16:", "positive"),
            (&format!("{head}G01 X10. F100. ,C1.\nM98 P1000\nM30\n%\n"), "5:16:", "branch, loop, call or return"),
            // Two chamfers of 4 on a line of 6: the second finds 2 left after the first.
            (&format!("{head}G01 X10. F100. ,C4.\nY6. ,C4.\nX0.\nM30\n%\n"), "6:5:", "longer than the element before it"),
        ],
    );
    // Under G68 the corner is refused; a work offset changed between the two blocks too.
    let p = fanuc(&format!("{head}G68 X0. Y0. R90.\nG01 X10. F100. ,C2.\nY10.\nM30\n%\n"));
    has(&p, 6, 16, "G68");
    let p = fanuc(&format!("{head}G10 L2 P2 X5. Y0.\nG54 G01 X10. F100. ,C1.\nG55 Y10.\nM30\n%\n"));
    has(&p, 6, 20, "work coordinate system changes");
    // A refused corner word leaves its block as written: X10, then Y10 from there.
    let p = fanuc(&format!("{head}G01 X10. F100. ,C1. ,R1.\nY10.\nM30\n%\n"));
    has(&p, 5, 21, "in one block");
    let m = moves(&p);
    assert!(m.len() == 3 && near(m[1].1, [10.0, 0.0]) && near(m[2].1, [10.0, 10.0]), "{m:#?}");
    // A line the stream cannot read (longer than it holds) between the two: the corner is refused.
    let long = format!("({})", "x".repeat(1 << 21));
    let p = fanuc(&format!("{head}G01 X10. F100. ,C1.\n{long}\nY10.\nM30\n%\n"));
    has(&p, 5, 16, "not read");
    let m = moves(&p);
    assert!(m.len() == 3 && near(m[1].1, [10.0, 0.0]) && near(m[2].1, [10.0, 10.0]), "{m:#?}");
    // Haas: between two G01 lines only.
    let p = read("%\nO0005\nG90 G17 G20 G94\nG00 X0. Y0.\nG01 X1. F10. ,R.1\nG03 X2. Y1. R1.\nM30\n%\n", Dialect::Haas, "h.nc", &ReadOptions::default());
    has(&p, 5, 14, "between two linear interpolation blocks");
    // Haas: "a G04 pause may intervene" (one; dwelling after the inserted element), and a chamfer
    // 0.1 from the corner on both lines.
    let p = read("%\nO0006\nG90 G17 G20 G94\nG00 X0. Y0.\nG01 X1. F10. ,C.1\nG04 P0.5\nY1.\nM30\n%\n", Dialect::Haas, "h.nc", &ReadOptions::default());
    assert!(errors(&p).is_empty(), "{:#?}", p.diagnostics);
    let m = moves(&p);
    assert!(near(m[1].1, [0.9 * 25.4, 0.0]) && near(m[2].1, [25.4, 0.1 * 25.4]) && near(m[3].1, [25.4, 25.4]), "{m:#?}");
    let dwell = p.blocks.iter().position(|b| b.dwell_s == Some(0.5)).expect("the pause");
    let chamfer = p.blocks.iter().position(|b| b.targets.y.is_some_and(|y| (y / MM - 2.54).abs() < 1e-9)).unwrap();
    assert!(dwell == chamfer + 1, "{:#?}", p.blocks);
    // A second pause, or anything else between, is refused.
    let p = read("%\nO0007\nG90 G17 G20 G94\nG00 X0. Y0.\nG01 X1. F10. ,C.1\nG04 P0.5\nG04 P0.5\nY1.\nM30\n%\n", Dialect::Haas, "h.nc", &ReadOptions::default());
    has(&p, 5, 14, "moves nothing");
    // A corner word on the pause is its own error (the pause moves nothing).
    let p = read("%\nO0008\nG90 G17 G20 G94\nG00 X0. Y0.\nG01 X1. F10. ,C.1\nG04 P0.5 ,R.1\nY1.\nM30\n%\n", Dialect::Haas, "h.nc", &ReadOptions::default());
    has(&p, 6, 10, "moves nothing");
    // A refused corner keeps both blocks as written.
    let p = fanuc(&format!("{head}G01 X10. F100. ,R1.\nY10. F200.\nM30\n%\n"));
    let m = moves(&p);
    assert!(m.len() == 3 && near(m[1].1, [10.0, 0.0]) && near(m[2].1, [10.0, 10.0]), "{m:#?}");
}

/// LinuxCNC reads no comma words, and a line whose settings block ends the program before its
/// defect (`G28` without the machine's reference point) still ends it: nothing after runs.
#[test]
fn linuxcnc_ends_at_an_m2_before_a_defect() {
    let p = read("G21 G1 X10 F100\nG28 M2\nG1 X50\n", Dialect::Rs274, "t.ngc", &ReadOptions::default());
    assert!(!errors(&p).is_empty(), "{:#?}", p.diagnostics);
    assert!(p.blocks.iter().all(|b| b.targets.x.is_none_or(|x| (x / MM - 50.0).abs() > 1e-9)), "{:#?}", p.blocks);
    let p = read("G21 G1 X10 F100 ,C1\nY10\nM2\n", Dialect::Rs274, "t.ngc", &ReadOptions::default());
    has(&p, 1, 17, "unexpected ',C1'");
}

/// A line too long for the stream to read, between a corner and the element after it, refuses the
/// corner in every reader that cuts corners (the 840D's `RND=`, the TNC's `RND`), as in Fanuc's.
#[test]
fn a_line_not_read_refuses_a_waiting_corner_in_every_dialect() {
    let long = format!(";{}", "x".repeat(1 << 21));
    let p = read(&format!("G17 G90 G71 G94\nG0 X0 Y0 Z5\nG1 Z-1 F500\nG1 X50 Y0 RND=5\n{long}\nG1 Y30\nM30\n"), Dialect::Sinumerik, "c.mpf", &ReadOptions::default());
    has(&p, 4, 11, "not read");
    let p = read(&format!("0 BEGIN PGM C MM\n1 L X+0 Y+0 Z-1 R0 F500\n2 L X+50 Y+0\n3 RND R5\n{long}\n4 L X+50 Y+30\n5 END PGM C MM\n"), Dialect::Klartext, "c.h", &ReadOptions::default());
    has(&p, 4, 3, "not read");
}

/// In the Z-X plane (G18): down Z to -10, then along +X; `,R2` the fillet 2 from both lines,
/// centre (X2, Z-8), turning clockwise seen from +Y (a G02 in G18).
#[test]
fn a_corner_r_in_the_zx_plane() {
    let p = fanuc("%\nO0009\nG90 G18 G21 G94\nG00 X0. Y0. Z0.\nG01 Z-10. F100. ,R2.\nX10.\nM30\n%\n");
    assert!(errors(&p).is_empty(), "{:#?}", p.diagnostics);
    let feed: Vec<_> = p.blocks.iter().filter(|b| b.motion != Motion::Rapid && !b.targets.is_empty()).collect();
    assert_eq!(feed.len(), 3, "{feed:#?}");
    let xz = |b: &fiveaxis::program::Block| [b.targets.x.map_or(f64::NAN, |x| x / MM), b.targets.z.map_or(f64::NAN, |z| z / MM)];
    assert!(feed[0].motion == Motion::Linear && (feed[0].targets.z.unwrap() / MM + 8.0).abs() < 1e-9, "{feed:#?}");
    assert!(feed[1].motion == Motion::ArcCw && near(xz(feed[1]), [2.0, -10.0]), "{feed:#?}");
    let c = feed[1].arc.as_ref().unwrap().centre;
    assert!(near([c[0] / MM, c[2] / MM], [2.0, -8.0]), "{c:?}");
    assert!(feed[2].motion == Motion::Linear && (feed[2].targets.x.unwrap() / MM - 10.0).abs() < 1e-9, "{feed:#?}");
}
