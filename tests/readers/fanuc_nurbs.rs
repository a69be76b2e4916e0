//! Fanuc's NURBS interpolation `G06.2` (FANUC Series 15i/150i-MA Operator's Manual B-63324EN
//! §4.17) against curves computed here independently: a rational quadratic quarter circle (every
//! point on its circle), a cubic Bézier (Bernstein polynomials), a rational cubic B-spline with
//! interior knots (the manual's de Boor-Cox recursion for the basis), a rank-2 curve (its control
//! polygon); and the manual's alarms, each at its word.

use super::*;

/// A program that places the tool at `start` (mm), then runs `curve` (its lines), then a G01.
fn program(start: [f64; 3], curve: &str, after: &str) -> String {
    format!("%\nO1000\nG21 G17 G90 G94\nG00 X{:.4} Y{:.4} Z{:.4}\nG01 F500.\n{curve}{after}M30\n%\n", start[0], start[1], start[2])
}

/// The curve's NURBS blocks as the post writes them: knots `K`, control points and weights `R`.
fn nurbs(rank: usize, points: &[[f64; 3]], weights: &[f64], knots: &[f64]) -> String {
    let mut s = String::new();
    for (i, p) in points.iter().enumerate() {
        let head = if i == 0 { format!("G06.2 P{rank} ") } else { String::new() };
        let feed = if i == 0 { " F1000." } else { "" };
        s += &format!("{head}K{:.6} X{:.6} Y{:.6} Z{:.6} R{:.8}{feed}\n", knots[i], p[0], p[1], p[2], weights[i]);
    }
    for k in &knots[points.len()..] {
        s += &format!("K{k:.6}\n");
    }
    s
}

fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// The distance of `q` from the segment `a`-`b`.
fn to_segment(q: [f64; 3], a: [f64; 3], b: [f64; 3]) -> f64 {
    let ab = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let l2 = ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2];
    let s = if l2 > 0.0 { (((q[0] - a[0]) * ab[0] + (q[1] - a[1]) * ab[1] + (q[2] - a[2]) * ab[2]) / l2).clamp(0.0, 1.0) } else { 0.0 };
    dist(q, [a[0] + s * ab[0], a[1] + s * ab[1], a[2] + s * ab[2]])
}

/// The chords' ends lie on the curve `f` (sampled densely over [t0, t1]) within `on` mm, the curve
/// lies within `tol` mm of the chords, and the first and last ends are `f(t0)`'s successor and `f(t1)`.
fn follows(chords: &[[f64; 3]], start: [f64; 3], f: impl Fn(f64) -> [f64; 3], t0: f64, t1: f64, on: f64, tol: f64) {
    let n = 20_000;
    let dense: Vec<[f64; 3]> = (0..=n).map(|i| f(t0 + (t1 - t0) * i as f64 / n as f64)).collect();
    assert!(dist(dense[0], start) < 1e-9, "the curve starts where the tool stands");
    assert!(dist(*chords.last().unwrap(), dense[n]) < 1e-9, "the last chord ends at the curve's end: {:?} vs {:?}", chords.last(), dense[n]);
    // Each chord's end on the curve: near some dense sample, and on the segment between two of them.
    let mut polyline = vec![start];
    polyline.extend_from_slice(chords);
    for (i, c) in chords.iter().enumerate() {
        let d = dense.windows(2).map(|w| to_segment(*c, w[0], w[1])).fold(f64::INFINITY, f64::min);
        assert!(d < on, "chord {i}'s end {c:?} is {d} mm off the curve");
    }
    // The curve within the tolerance of the chords: each dense point near the polyline.
    let mut worst: f64 = 0.0;
    for q in &dense {
        let d = polyline.windows(2).map(|w| to_segment(*q, w[0], w[1])).fold(f64::INFINITY, f64::min);
        worst = worst.max(d);
    }
    assert!(worst <= tol, "the curve strays {worst} mm from its chords (tolerance {tol} mm)");
}

/// Whether some point of one of the chords (a polyline of (X mm, B deg)) lies within 1 µm in X and
/// 0.001 deg in B of `q`: the tolerance's meaning for a chord along which both axes move together.
fn near_xb(q: [f64; 2], polyline: &[[f64; 2]]) -> bool {
    let tol = [1e-3 + 1e-9, 1e-3 + 1e-9];
    polyline.windows(2).any(|w| {
        let (mut lo, mut hi) = (0.0f64, 1.0f64);
        for k in 0..2 {
            let d = w[1][k] - w[0][k];
            if d == 0.0 {
                if (q[k] - w[0][k]).abs() > tol[k] {
                    return false;
                }
            } else {
                let (s0, s1) = ((q[k] - w[0][k] - tol[k]) / d, (q[k] - w[0][k] + tol[k]) / d);
                lo = lo.max(s0.min(s1));
                hi = hi.min(s0.max(s1));
            }
        }
        lo <= hi
    })
}

/// A quarter circle of radius 10 about (0, 10) as a rational quadratic: control points (0,0),
/// (10,0), (10,10), weights 1, sqrt(2)/2, 1, knots 0 0 0 1 1 1. Every chord end lies on the circle,
/// every chord's sagitta within 1 µm, and the G01 after the curve starts at (10, 10).
#[test]
fn a_rational_quadratic_is_a_quarter_circle() {
    let w = std::f64::consts::FRAC_1_SQRT_2;
    let curve = nurbs(3, &[[0.0, 0.0, 0.0], [10.0, 0.0, 0.0], [10.0, 10.0, 0.0]], &[1.0, w, 1.0], &[0.0, 0.0, 0.0, 1.0, 1.0, 1.0]);
    let p = read(&program([0.0, 0.0, 0.0], &curve, "G01 X20.\n"), Dialect::Fanuc, "t.nc", &ReadOptions::default());
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    let e = ends(&p);
    // The first is G00 X0 Y0 Z0; the last the G01 X20.
    let chords = &e[1..e.len() - 1];
    // Radius 10 to 8 digits (the weight is written to 8), the end exactly.
    for c in chords {
        let r = (c[0].powi(2) + (c[1] - 10.0).powi(2)).sqrt();
        assert!((r - 10.0).abs() < 1e-7 && c[2] == 0.0, "{c:?} is {r} from the centre");
    }
    let mut prev = [0.0, 0.0, 0.0];
    for c in chords {
        let chord = dist(prev, *c);
        let sagitta = 10.0 - (100.0 - chord * chord / 4.0).sqrt();
        assert!(sagitta <= 1e-3 + 1e-9, "a chord of {chord} mm strays {sagitta} mm");
        prev = *c;
    }
    // The fewest chords of 1 µm sagitta on a quarter circle of radius 10: each spans at most
    // 2 acos(1 - 0.001/10).
    let fewest = (std::f64::consts::FRAC_PI_2 / (2.0 * (1.0f64 - 1e-4).acos())).ceil() as usize;
    assert!(chords.len() >= fewest && chords.len() <= 4 * fewest, "{} chords, at least {fewest}", chords.len());
    assert!(dist(*chords.last().unwrap(), [10.0, 10.0, 0.0]) < 1e-12);
    assert_eq!(e.last().unwrap(), &[20.0, 10.0, 0.0]);
    // Each chord a feed move at the curve's F.
    let moves: Vec<_> = p.blocks.iter().filter(|b| !b.targets.is_empty()).collect();
    assert!(moves[1..moves.len() - 1].iter().all(|b| b.motion == Motion::Linear && b.feed.unwrap().value_per_min == 1000.0));
}

/// The cubic Bézier of four points at `t`, by its Bernstein polynomials.
fn bernstein(pts: &[[f64; 3]; 4], t: f64) -> [f64; 3] {
    let b = [(1.0 - t).powi(3), 3.0 * t * (1.0 - t).powi(2), 3.0 * t * t * (1.0 - t), t.powi(3)];
    let mut q = [0.0; 3];
    for (k, pk) in pts.iter().enumerate() {
        for i in 0..3 {
            q[i] += b[k] * pk[i];
        }
    }
    q
}

/// The cubic Bézier of `pts` as a P4 curve (knots 0 0 0 0 1 1 1 1): its chords against the Bernstein form.
fn bezier_follows(pts: &[[f64; 3]; 4]) {
    let curve = nurbs(4, pts, &[1.0; 4], &[0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0]);
    let p = read(&program(pts[0], &curve, "G01 Z10.\n"), Dialect::Fanuc, "t.nc", &ReadOptions::default());
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    let e = ends(&p);
    follows(&e[1..e.len() - 1], pts[0], |t| bernstein(pts, t), 0.0, 1.0, 1e-6, 1e-3 + 1e-6);
}

/// A cubic Bézier (P4, four points, knots 0 0 0 0 1 1 1 1) against its Bernstein form, in 3D.
#[test]
fn a_cubic_with_four_points_is_a_bezier() {
    let pts = [[5.0, 2.0, 1.0], [15.0, 30.0, -4.0], [40.0, -20.0, 6.0], [50.0, 8.0, 0.0]];
    bezier_follows(&pts);
}

/// The manual's basis: N_i,1 = 1 on [x_i, x_i+1), N_i,k = (t - x_i) N_i,k-1 / (x_i+k-1 - x_i) +
/// (x_i+k - t) N_i+1,k-1 / (x_i+k - x_i+1), 0/0 read as 0; the last knot's interval closed.
fn basis(i: usize, k: usize, t: f64, x: &[f64]) -> f64 {
    if k == 1 {
        let last = x[x.len() - 1];
        return if (x[i] <= t && t < x[i + 1]) || (t == last && x[i] < t && x[i + 1] == last) { 1.0 } else { 0.0 };
    }
    let a = if x[i + k - 1] > x[i] { (t - x[i]) / (x[i + k - 1] - x[i]) * basis(i, k - 1, t, x) } else { 0.0 };
    let b = if x[i + k] > x[i + 1] { (x[i + k] - t) / (x[i + k] - x[i + 1]) * basis(i + 1, k - 1, t, x) } else { 0.0 };
    a + b
}

/// A rational cubic B-spline of seven points with uneven interior knots (one of them doubled) and
/// weights, in knots of the least increment (no decimal point: K0, K2500), against the manual's
/// formula P(t) = sum N_ik w_i P_i / sum N_ik w_i.
#[test]
fn a_rational_cubic_b_spline_follows_the_manuals_formula() {
    let pts = [[0.0, 0.0, 0.0], [10.0, 12.0, 1.0], [25.0, -3.0, 2.0], [32.0, 18.0, 0.5], [48.0, 20.0, -1.0], [55.0, 2.0, 0.0], [70.0, 9.0, 3.0]];
    let w = [1.0, 0.8, 1.6, 1.0, 2.5, 0.7, 1.0];
    // In thousandths: 0 0 0 0 2.5 4 4 10 10 10 10 (x 1000).
    let knots = [0.0, 0.0, 0.0, 0.0, 2500.0, 4000.0, 4000.0, 10000.0, 10000.0, 10000.0, 10000.0];
    let mut curve = String::new();
    for (i, q) in pts.iter().enumerate() {
        let head = if i == 0 { "G06.2 P4 " } else { "" };
        curve += &format!("{head}K{} X{:.3} Y{:.3} Z{:.3} R{:.3}\n", knots[i], q[0], q[1], q[2], w[i]);
    }
    for k in &knots[pts.len()..] {
        curve += &format!("K{k}\n");
    }
    let p = read(&program(pts[0], &curve, "G01 Z10.\n"), Dialect::Fanuc, "t.nc", &ReadOptions::default());
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    let e = ends(&p);
    let x: Vec<f64> = knots.iter().map(|k| k / 1000.0).collect();
    let f = |t: f64| {
        let (mut num, mut den) = ([0.0; 3], 0.0);
        for i in 0..pts.len() {
            let n = basis(i, 4, t, &x) * w[i];
            den += n;
            for c in 0..3 {
                num[c] += n * pts[i][c];
            }
        }
        num.map(|v| v / den)
    };
    follows(&e[1..e.len() - 1], pts[0], f, 0.0, 10.0, 1e-6, 1e-3 + 1e-6);
    // Each chord is made when its span's knots have come: the first span, [0, 2.5], reaches knot
    // x_6, which comes with the 7th control point (line 12).
    let lines: Vec<usize> = p.blocks.iter().filter(|b| !b.targets.is_empty()).map(|b| b.line).collect();
    assert_eq!(lines[1], 12, "{lines:?}");
}

/// Rank 2 is the control polygon: one G01 to each point; and under G91 the same curve, its points
/// written as increments from the point before (the first a travel of 0), makes the same moves.
#[test]
fn rank_two_is_the_polygon_and_g91_points_are_increments() {
    let pts = [[1.0, 1.0, 0.0], [11.0, 1.0, 0.0], [11.0, 6.0, 2.0], [4.0, 9.0, 2.0]];
    let curve = nurbs(2, &pts, &[1.0, 3.0, 0.5, 1.0], &[0.0, 0.0, 1.0, 3.0, 4.0, 4.0]);
    let p = read(&program(pts[0], &curve, "G01 X0.\n"), Dialect::Fanuc, "t.nc", &ReadOptions::default());
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    assert_eq!(&ends(&p)[1..4], &pts[1..]);
    let inc = "G91 G06.2 P2 K0. X0. Y0. Z0. F1000.\nK0. X10.\nK1. Y5. Z2. R0.5\nK3. X-7. Y3.\nK4.\nK4.\nG90 G01 X0.\n";
    let p = read(&program(pts[0], inc, ""), Dialect::Fanuc, "t.nc", &ReadOptions::default());
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    let e = ends(&p);
    assert_eq!(&e[1..4], &pts[1..]);
    assert_eq!(e[4], [0.0, 9.0, 2.0]);
}

/// The manual's alarms and what these pages leave open, each at its word (line:column).
#[test]
fn nurbs_alarms_are_said_at_their_words() {
    // M30 is no NURBS word: a G00 ends the mode first.
    let at = |curve: &str| program([0.0, 0.0, 0.0], curve, "G00 Z50.\n");
    let ok = "G06.2 P3 K0. X0. Y0. Z0. F1000.\nK0. X10. Y0.\nK0. X10. Y10.\nK1.\nK1.\nK1.\n";
    // The curve is read without them.
    let p = read(&at(ok), Dialect::Fanuc, "t.nc", &ReadOptions::default());
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    let cases = [
        (at("G06.2 P3 K0. X0. Y0. Z0. F1000.\nX10. Y0.\n"), "7:1:", "PS1002"),
        (at("G06.2 P3 X0. Y0. Z0. F1000.\n"), "6:1:", "PS1002"),
        (at("G06.2 P3 K0. X0. Y0. Z0. F1000.\nK0.5 X10. Y0.\n"), "7:1:", "PS1007"),
        (at("G06.2 P3 K0. X0. Y0. Z0. F1000.\nK0. X10. Y0.\nK0. X10. Y10.\nK1.\nK1.\nK2.\n"), "11:1:", "PS1007"),
        (at("G06.2 P2 K0. X0. Y0. Z0. F1000.\nK0. X10. Y0.\nK0. X10. Y10.\n"), "8:1:", "PS1008"),
        (at("G06.2 P3 K0. X1. Y0. Z0. F1000.\n"), "6:14:", "PS1009"),
        (at("G91 G06.2 P3 K0. X1. Y0. Z0. F1000.\n"), "6:18:", "PS1009"),
        (at("G06.2 P3 K0. X0. Y0. Z0. F1000.\nK0. X10. Y0.\nG01 X5.\n"), "8:1:", "PS1005"),
        (at("G06.2 P3 K0. X0. Y0. Z0. F1000.\nK0. X10. Y0.\nK0. X10. Y10.\nK1.\nG01 X5.\n"), "10:1:", "PS1004"),
        (at("G06.2 P3 K0. X0. Y0. Z0. F1000.\nK0. X10. Y0.\nK0. X10. Y10.\nK1.\nK1.\n"), "11:1:", "PS1004"),
        ("%\nG21 G90 G94\nG00 X0. Y0. Z0.\nG06.2 P3 K0. X0. Y0. Z0. F1000.\nK0. X10. Y0.\n".to_string(), "5:1:", "program's end"),
        (at("G06.2 P5 K0. X0. Y0. Z0. F1000.\n"), "6:7:", "rank"),
        (at("G06.2 P3 K0. X0. Y0. Z0. F1000.\nK0. X10. Y0. R0.\n"), "7:14:", "weight"),
        (at("G06.2 P3 K0. X0. Y0. Z0. F1000.\nK0. X10. Y0. F200.\n"), "7:14:", "first block"),
        (at("G06.2 P3 K0. X0. Y0. F1000.\nK0. X10. Z1.\n"), "7:10:", "did not name"),
        (at("G06.2 P3 K0. X0. Y0. Z0. F1000.\nK0. X10. Y0. M08\n"), "7:14:", "cannot be specified"),
        (at("G06.2 P3 K0. X0. Y0. Z0. F1000.\nK0. X10. Y0.\nK0. X10. Y10.\nK1.\nK1.\nK1.\nM09\n"), "12:1:", "cannot be specified"),
        (at("G06.2 P3 K0. X0. Y0. Z0. F1000.\nK0. X10. Y0.\nK0. X10. Y10.\nK0.5 X5. Y5.\nK0.2 X0. Y5.\n"), "10:1:", "never decrease"),
        (at("G93\nG06.2 P3 K0. X0. Y0. Z0. F1000.\n"), "7:1:", "PS1006"),
        (at("G06.2 P3 K0. X0. Y0. Z0. F1000.\nK0. X10. Y0.\nK0. X10. Y10.\nK1.\nK1.\nK1.\nK2. X4.\n"), "12:1:", "G06.2"),
        // A knot repeated k times inside the curve breaks it: its two ends are not joined by the curve.
        (at("G06.2 P2 K0. X0. Y0. Z0. F1000.\nK0. X10. Y0.\nK1. X10. Y10.\nK1. X0. Y10.\nK2.\nK2.\n"), "8:1:", "breaks"),
    ];
    for (text, at, needle) in &cases {
        let p = read(text, Dialect::Fanuc, "t.nc", &ReadOptions::default());
        let (l, c) = at.trim_end_matches(':').split_once(':').unwrap();
        has(&p, l.parse().unwrap(), c.parse().unwrap(), needle);
    }
    // Blocks after a refused curve's end are read: the G01 after it moves.
    let p = read(&at("G06.2 P3 K0. X0. Y0. Z0. F1000.\nK0.5 X10. Y0.\nK0. X10. Y10.\nK1.\nK1.\nK1.\nG01 X5. Y5.\n"), Dialect::Fanuc, "t.nc", &ReadOptions::default());
    assert_eq!(errors(&p).len(), 1, "{:?}", errors(&p));
    assert!(ends(&p).contains(&[5.0, 5.0, 0.0]), "{:?}", ends(&p));
    // Haas has no G06.2.
    let p = read(&at(ok), Dialect::Haas, "t.nc", &ReadOptions::default());
    has(&p, 6, 1, "G06.2 (spline or NURBS motion) is not supported");
}

/// A curve of X and B (the NMV5000's tilting axis) is one of the machine's axes, as the manual
/// allows any axes: a quadratic Bézier X 0, 10, 20 and B 0, 20, 0 is B = 2 X - X^2 / 10 (deg, mm);
/// along its chords X and B move together, and every point of the curve, densely, lies within 1 µm
/// and 0.001 deg of a point of them. On C, which turns without end there, and under tool-centre
/// point, a curve is refused.
#[test]
fn a_rotary_axis_follows_its_curve_within_a_thousandth_of_a_degree() {
    let machine = fiveaxis::machine::Machine::builtin("mori-seiki-nmv5000").unwrap();
    let on = ReadOptions::default().on(&machine);
    let text = "%\nO1000\nG21 G17 G90 G94\nG00 X0. Y0. Z150. B0. C0.\nG01 F500.\nG06.2 P3 K0. X0. B0. F1000.\nK0. X10. B20.\nK0. X20. B0.\nK1.\nK1.\nK1.\nG01 X30.\nG00 Z200.\nM30\n%\n";
    let p = read(text, Dialect::Fanuc, "t.nc", &on);
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    let mut at = [0.0, 0.0];
    let mut chords = Vec::new();
    for b in p.blocks.iter().filter(|b| !b.targets.is_empty()).skip(1) {
        if let Some(x) = b.targets.x {
            at[0] = (x + b.datum[0]) / MM;
        }
        if let Some(v) = b.targets.b {
            at[1] = v / DEG;
        }
        if b.line >= 7 && b.line <= 11 {
            chords.push(at);
        }
    }
    assert!(chords.len() >= 100, "a chord of at most 0.2 mm in X: {} of them", chords.len());
    for c in &chords {
        assert!((c[1] - (2.0 * c[0] - c[0] * c[0] / 10.0)).abs() < 1e-9, "{c:?} is off the parabola");
    }
    let mut polyline = vec![[0.0, 0.0]];
    polyline.extend_from_slice(&chords);
    for i in 0..=20_000 {
        let x = 20.0 * i as f64 / 20_000.0;
        assert!(near_xb([x, 2.0 * x - x * x / 10.0], &polyline), "the curve at X{x} is off its chords");
    }
    assert_eq!(chords.last().unwrap(), &[20.0, 0.0]);
    refuses_each(
        Dialect::Fanuc,
        &on,
        &[
            ("%\nG21 G90 G94\nG00 X0. Y0. Z150. B0. C0.\nG01 F500.\nG06.2 P3 K0. X0. C0. F1000.\n", "5:18:", "turns without end"),
            ("%\nG21 G90 G94\nG00 X0. Y0. Z150. B0. C0.\nG43.4 H1\nG01 F500.\nG06.2 P3 K0. X0. Y0. F1000.\n", "6:1:", "tool-centre point"),
        ],
    );
}

/// An S whose inflection lies at the middle of the first quarter of its span (the review's case):
/// the midpoint lies on the chord there while the curve strays on either side; the chords still
/// keep within 1 µm of the Bernstein form. A reversal of X while B goes on (a joint-space chord
/// nearest the curve's point is not where X alone puts it) is read, each chord within tolerance.
#[test]
fn chords_hold_the_tolerance_at_an_inflection_and_a_reversal() {
    let pts = [[0.0, 0.0, 0.0], [3.333, 0.156, 0.0], [6.667, -0.938, 0.0], [10.0, 6.719, 0.0]];
    bezier_follows(&pts);
    // X 0, 10, 0 and B 0, 20, 40: X = 20 t (1 - t), B = 40 t (deg): out and back in X while B turns.
    let machine = fiveaxis::machine::Machine::builtin("mori-seiki-nmv5000").unwrap();
    let on = ReadOptions::default().on(&machine);
    let text = "%\nG21 G17 G90 G94\nG00 X0. Y0. Z150. B0. C0.\nG01 F500.\nG06.2 P3 K0. X0. B0. F1000.\nK0. X10. B20.\nK0. X0. B40.\nK1.\nK1.\nK1.\nG00 Z200.\nM30\n%\n";
    let p = read(text, Dialect::Fanuc, "t.nc", &on);
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    let mut at = [0.0, 0.0];
    let mut chords = vec![[0.0, 0.0]];
    for b in p.blocks.iter().filter(|b| !b.targets.is_empty() && b.line >= 5 && b.line <= 10) {
        if let Some(x) = b.targets.x {
            at[0] = (x + b.datum[0]) / MM;
        }
        if let Some(v) = b.targets.b {
            at[1] = v / DEG;
        }
        chords.push(at);
    }
    // Each end on the curve: X = 20 t (1 - t) with t = B / 40.
    for c in &chords {
        let t = c[1] / 40.0;
        assert!((c[0] - 20.0 * t * (1.0 - t)).abs() < 1e-9, "{c:?} is off the curve");
    }
    // The curve, densely, within the tolerance of its chords.
    for i in 0..=20_000 {
        let t = i as f64 / 20_000.0;
        assert!(near_xb([20.0 * t * (1.0 - t), 40.0 * t], &chords), "the curve at t {t} is off its chords");
    }
    assert_eq!(chords.last().unwrap(), &[0.0, 40.0]);
}

/// A refused first block changes nothing: its F does not become the feed of the moves after it.
/// A subprogram call inside the mode is refused, and K without a decimal point in a G06.2 block
/// under a canned cycle is a knot (the G06.2 ends the cycle), not a repeat count.
#[test]
fn a_refused_curve_changes_nothing_and_calls_are_refused_in_the_mode() {
    let text = "%\nG21 G17 G90 G94\nG00 X0. Y0. Z0.\nG01 F500.\nG06.2 P3 K0. X5. Y0. F5000.\nK0. X10. Y0.\nK0. X10. Y10.\nK1.\nK1.\nK1.\nG01 X20.\nM30\n%\n";
    let p = read(text, Dialect::Fanuc, "t.nc", &ReadOptions::default());
    has(&p, 5, 14, "PS1009");
    let last = p.blocks.iter().rev().find(|b| !b.targets.is_empty()).unwrap();
    assert_eq!(last.feed.unwrap().value_per_min, 500.0);
    let text = "%\nO1000\nG21 G17 G90 G94\nG00 X0. Y0. Z0.\nG01 F500.\nG06.2 P3 K0. X0. Y0.\nM98 P2000\nK0. X10. Y10.\nK1.\nK1.\nK1.\nG01 X20.\nM30\nO2000\nK0. X10. Y0.\nM99\n%\n";
    let p = read(text, Dialect::Fanuc, "t.nc", &ReadOptions::default());
    has(&p, 7, 1, "NURBS mode");
    let text = "%\nG21 G17 G90 G94\nG00 X0. Y0. Z5.\nG99 G81 X0. Y0. Z-1. R1. F100.\nG06.2 P3 K0 X0. Y0. Z1. F1000.\nK0 X10. Y0.\nK0 X10. Y10.\nK1000\nK1000\nK1000\nG01 X20.\nM30\n%\n";
    let p = read(text, Dialect::Fanuc, "t.nc", &ReadOptions::default());
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    // Knots 0 0 0 1 1 1 (x 0.001): the curve's last chord ends at X10 Y10.
    assert!(ends(&p).contains(&[10.0, 10.0, 1.0]), "{:?}", ends(&p));
    // Said as a knot, which has no unit (the manual: the reference axis' least increments).
    let w = p.diagnostics.iter().find(|d| d.message.contains("no decimal point")).expect("the decimal-point warning");
    assert!(w.line == 8 && w.message.contains("K1000") && w.message.contains("read as 1 (a knot)"), "{w:?}");
}

/// A macro statement in the mode reads group 01 as G06.2 (`#4001` = 6.2, B-63324EN §4.17 puts G06.2
/// in group 01), and as G01 once a `G01` has ended the curve.
#[test]
fn group_01_reads_6_2_in_the_mode() {
    let text = "%\nG21 G17 G90 G94\nG00 X0. Y0. Z0.\nG01 F500.\nG06.2 P3 K0. X0. Y0. F1000.\nK0. X10. Y0.\n#100=#4001\nK0. X10. Y10.\nK1.\nK1.\nK1.\nG01 X#100\n#101=#4001\nG01 Y#101\nM30\n%\n";
    let p = read(text, Dialect::Fanuc, "t.nc", &ReadOptions::default());
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    let e = ends(&p);
    assert!((e[e.len() - 2][0] - 6.2).abs() < 1e-12 && (e[e.len() - 1][1] - 1.0).abs() < 1e-12, "{:?}", &e[e.len() - 2..]);
}

/// Under `G68` (set before the mode, as the manual says) the curve turns with its chords: the
/// quarter circle about (0, 10), turned 90 deg about the origin, lies on the circle of radius 10
/// about (-10, 0) and ends at (-10, 10). Under G91 before an absolute move after G68 (whose centre
/// is then the tool's position) and under G68.2, a curve is refused.
#[test]
fn a_curve_under_g68_turns_with_its_chords() {
    let w = std::f64::consts::FRAC_1_SQRT_2;
    let curve = nurbs(3, &[[0.0, 0.0, 0.0], [10.0, 0.0, 0.0], [10.0, 10.0, 0.0]], &[1.0, w, 1.0], &[0.0, 0.0, 0.0, 1.0, 1.0, 1.0]);
    let p = read(&program([0.0, 0.0, 0.0], &format!("G68 X0. Y0. R90.\n{curve}"), "G01 X20.\nG69\nG00 X0. Y0.\n"), Dialect::Fanuc, "t.nc", &ReadOptions::default());
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    let lines: Vec<usize> = p.blocks.iter().filter(|b| !b.targets.is_empty()).map(|b| b.line).collect();
    let e = ends(&p);
    let chords: Vec<[f64; 3]> = e.iter().zip(&lines).filter(|(_, l)| (7..=12).contains(*l)).map(|(p, _)| *p).collect();
    assert!(chords.len() > 50, "{chords:?}");
    for c in &chords {
        let r = ((c[0] + 10.0).powi(2) + c[1].powi(2)).sqrt();
        assert!((r - 10.0).abs() < 1e-7, "{c:?} is {r} from the turned centre");
    }
    let end = chords.last().unwrap();
    assert!((end[0] + 10.0).abs() < 1e-9 && (end[1] - 10.0).abs() < 1e-9, "{end:?}");
    refuses_each(
        Dialect::Fanuc,
        &ReadOptions::default(),
        &[
            ("%\nG21 G17 G90 G94\nG00 X0. Y0. Z0.\nG68 X5. Y5. R30.\nG91 G06.2 P2 K0. X0. Y0. F500.\n", "5:5:", "after G68 before an absolute move"),
        ],
    );
    let machine = fiveaxis::machine::Machine::builtin("mori-seiki-nmv5000").unwrap();
    refuses_each(
        Dialect::Fanuc,
        &ReadOptions::default().on(&machine),
        &[("%\nG21 G17 G90 G94\nG00 X0. Y0. Z150. B0. C0.\nG68.2 X0. Y0. Z0. I0. J10. K0.\nG06.2 P2 K0. X0. Y0. F500.\n", "5:1:", "tilted working plane")],
    );
}
