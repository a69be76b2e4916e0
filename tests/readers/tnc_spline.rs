//! The TNC's spline block `SPL` (iTNC 530 User's Manual 340 49x, "Contour movements – Spline
//! interpolation (software option 2)"): its worked example, block by block, against the manual's
//! cubic `X(t) = K3X t^3 + K2X t^2 + K1X t + X` (t from 1 to 0) evaluated here; the start within
//! 1 µm of the tool's position; and what is refused, at its word.

use super::*;

/// The manual's example: `7 L X+28.338 Y+19.385 Z-0.5 FMAX`, then two SPL blocks written as its
/// post writes them (coefficients with their exponents attached).
const EXAMPLE: &str = "0 BEGIN PGM SPL MM\n1 TOOL CALL 1 Z S5000\n2 L X+28.338 Y+19.385 Z-0.5 FMAX\n\
3 SPL X24.875 Y15.924 Z-0.5 K3X-4.688E-002 K2X2.459E-002 K1X3.486E+000 K3Y-4.563E-002 K2Y2.155E-002 K1Y3.486E+000 K3Z0.000E+000 K2Z0.000E+000 K1Z0.000E+000 F10000\n\
4 SPL X17.952 Y9.003 Z-0.500 K3X5.159E-002 K2X-5.644E-002 K1X6.928E+000 K3Y3.753E-002 K2Y-2.644E-002 K1Y6.910E+000 K3Z0.000E+000 K2Z0.000E+000 K1Z0.000E+000\n\
5 L Z+50 FMAX\n6 END PGM SPL MM\n";

/// Each block's cubic in X and Y, as the manual defines it: (end, K3, K2, K1) per axis.
const CUBICS: [[[f64; 4]; 2]; 2] = [
    [[24.875, -4.688e-2, 2.459e-2, 3.486], [15.924, -4.563e-2, 2.155e-2, 3.486]],
    [[17.952, 5.159e-2, -5.644e-2, 6.928], [9.003, 3.753e-2, -2.644e-2, 6.910]],
];

fn cubic(c: &[f64; 4], t: f64) -> f64 {
    c[1] * t.powi(3) + c[2] * t.powi(2) + c[3] * t + c[0]
}

fn to_segment(q: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let ab = [b[0] - a[0], b[1] - a[1]];
    let l2 = ab[0] * ab[0] + ab[1] * ab[1];
    let s = if l2 > 0.0 { (((q[0] - a[0]) * ab[0] + (q[1] - a[1]) * ab[1]) / l2).clamp(0.0, 1.0) } else { 0.0 };
    ((q[0] - a[0] - s * ab[0]).powi(2) + (q[1] - a[1] - s * ab[1]).powi(2)).sqrt()
}

/// Each SPL block's chords: their ends on its cubic, the cubic within 1 µm of them, ending at the end
/// point as written, at the feed F10000 the first block sets.
#[test]
fn the_manuals_spline_example_follows_its_cubics() {
    let p = read(EXAMPLE, Dialect::Klartext, "t.h", &ReadOptions::default());
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    for (n, c) in CUBICS.iter().enumerate() {
        let number = 3 + n as u64;
        let chords: Vec<[f64; 2]> = p.blocks.iter().filter(|b| b.number == Some(number)).map(|b| [b.targets.x.unwrap() / MM, b.targets.y.unwrap() / MM]).collect();
        assert!(chords.len() >= 4, "block {number}: {chords:?}");
        assert!(p.blocks.iter().filter(|b| b.number == Some(number)).all(|b| b.motion == Motion::Linear && b.feed.unwrap().value_per_min == 10000.0));
        let dense: Vec<[f64; 2]> = (0..=20_000).map(|i| 1.0 - i as f64 / 20_000.0).map(|t| [cubic(&c[0], t), cubic(&c[1], t)]).collect();
        for q in &chords {
            let d = dense.windows(2).map(|w| to_segment(*q, w[0], w[1])).fold(f64::INFINITY, f64::min);
            assert!(d < 1e-6, "block {number}: {q:?} is {d} mm off its cubic");
        }
        let mut polyline = vec![dense[0]];
        polyline.extend_from_slice(&chords);
        let worst = dense.iter().map(|q| polyline.windows(2).map(|w| to_segment(*q, w[0], w[1])).fold(f64::INFINITY, f64::min)).fold(0.0, f64::max);
        // The chords start at the tool's position, which lies within 1 µm of the cubic's start.
        assert!(worst <= 1e-3 + 1e-3, "block {number}: the cubic strays {worst} mm from its chords");
        assert_eq!(chords.last().unwrap(), &[c[0][0], c[1][0]]);
    }
}

/// A start more than 1 µm from the tool is the TNC's error; a coefficient out of its order, one
/// missing, an M function, an incremental end point, and a spline under RL/RR are refused.
#[test]
fn spline_blocks_refuse_what_the_tnc_refuses() {
    let head = "0 BEGIN PGM S MM\n1 TOOL CALL 1 Z S5000\n2 L X+0 Y+0 Z+0 R0 F500\n";
    let case = |spl: &str| format!("{head}3 {spl}\n4 END PGM S MM\n");
    refuses_each(
        Dialect::Klartext,
        &ReadOptions::default(),
        &[
            (&case("SPL X+10 Y+0 Z+0 K3X+0 K2X+0 K1X-9.998 K3Y+0 K2Y+0 K1Y+0 K3Z+0 K2Z+0 K1Z+0"), "4:3:", "more than 1 µm"),
            (&case("SPL X+10 Y+0 K2X+0 K3X+0 K1X-1 E+1 K3Y+0 K2Y+0 K1Y+0"), "4:16:", "K3, K2, K1 in that order"),
            (&case("SPL X+10 Y+0 K3X+0 K2X+0 K1X-1 E+1"), "4:3:", "needs its coefficients K3Y"),
            (&case("SPL X+10 K3X+0 K2X+0 K1X-1 E+1 M8"), "4:34:", "M function"),
            (&case("SPL IX+10 K3X+0 K2X+0 K1X-1 E+1"), "4:7:", "absolute"),
            (&case("SPL X+10 K3X+0 K2X+0 K1X-1.0E+300"), "4:24:", "exponent"),
        ],
    );
    let text = "0 BEGIN PGM S MM\n1 TOOL CALL 1 Z S5000\n2 L X+0 Y+0 Z+0 R0 F500\n3 L X+5 RL\n4 SPL X+10 K3X+0 K2X+0 K1X-5\n5 L X+20 R0\n6 END PGM S MM\n";
    let table = fiveaxis::program::ToolTable::parse("T1 P1 D6\n").unwrap();
    let options = ReadOptions { tool_table: Some(std::sync::Arc::new(table)), ..Default::default() };
    let p = read(text, Dialect::Klartext, "t.h", &options);
    assert!(errors(&p).iter().any(|(l, _, m)| *l == 5 && m.contains("a spline (SPL) with radius compensation")), "{:?}", errors(&p));
}

/// A coefficient's exponent in the word after it (`K1X-1 E+1`, the manual's `K2B-0.413 E+2`) and a
/// rotary axis: X and A on a straight line from X0 A0 to X10 A5 (the hermle-c600u's A).
#[test]
fn spline_exponents_stand_apart_and_rotary_axes_move() {
    let machine = fiveaxis::machine::Machine::builtin("hermle-c600u").unwrap();
    let text = "0 BEGIN PGM S MM\n1 TOOL CALL 1 Z S5000\n2 L X+0 Y+0 Z+0 A+0 R0 F500\n3 SPL X+10 A+5 K3X+0 K2X+0 K1X-1 E+1 K3A+0 K2A+0 K1A-5\n4 END PGM S MM\n";
    let p = read(text, Dialect::Klartext, "t.h", &ReadOptions::default().on(&machine));
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    let b: Vec<_> = p.blocks.iter().filter(|b| b.number == Some(3)).collect();
    assert!(!b.is_empty());
    let last = b.last().unwrap();
    assert_eq!((last.targets.x, last.targets.a), (Some(10.0 * MM), Some(5.0 * DEG)));
    // Along a straight line X and A keep their ratio 2 mm per degree.
    assert!(b.iter().all(|b| (b.targets.x.unwrap() / MM - 2.0 * b.targets.a.unwrap() / DEG).abs() < 1e-9));
}

/// A spline is read whole or not at all: with M116 a chord that turns A is refused, and the chord
/// before it (X alone: A(t) is 0 down to t = 0.75) is not left out either. A `CT` after a spline is
/// tangent to the curve's end, -K1: from (10, -5) heading +X to (20, 0), its centre (10, 7.5) (radius
/// 12.5: 10^2 + (12.5 - 5)^2 = 12.5^2). A spline on the endless C, one before any move placed its
/// axis, and an exponent with two signs are refused.
#[test]
fn a_spline_runs_whole_and_ct_follows_its_end() {
    let machine = fiveaxis::machine::Machine::builtin("hermle-c600u").unwrap();
    let on = ReadOptions::default().on(&machine);
    let text = "0 BEGIN PGM S MM\n1 TOOL CALL 1 Z S5000\n2 L X+0 Y+0 Z+0 A+0 R0 F500\n3 M116\n4 SPL X+10 A+0.046875 K3X+0 K2X+0 K1X-1 E+1 K3A+0 K2A+0.0625 K1A-0.109375\n5 L X+20\n6 END PGM S MM\n";
    let p = read(text, Dialect::Klartext, "t.h", &on);
    assert!(errors(&p).iter().any(|(l, _, m)| *l == 5 && m.contains("M116")), "{:?}", errors(&p));
    assert!(p.blocks.iter().all(|b| b.number != Some(4)), "a chord of the refused spline went out");
    let text = "0 BEGIN PGM S MM\n1 TOOL CALL 1 Z S5000\n2 L X+5 Y-10 Z+0 R0 F500\n3 SPL X+10 Y-5 K3X+0 K2X+5 K1X-1 E+1 K3Y+0 K2Y-5 K1Y+0\n4 CT X+20 Y+0\n5 END PGM S MM\n";
    let p = read(text, Dialect::Klartext, "t.h", &ReadOptions::default());
    assert!(errors(&p).is_empty(), "{:?}", errors(&p));
    let ct = p.blocks.iter().find(|b| b.number == Some(4)).unwrap();
    let c = ct.arc.as_ref().unwrap().centre;
    assert!((c[0] / MM - 10.0).abs() < 1e-9 && (c[1] / MM - 7.5).abs() < 1e-9, "{c:?}");
    refuses_each(
        Dialect::Klartext,
        &on,
        &[
            ("0 BEGIN PGM S MM\n1 L X+0 Y+0 Z+0 C+0 R0 F500\n2 SPL C+10 K3C+0 K2C+0 K1C-1 E+1\n", "3:7:", "turns without end"),
            ("0 BEGIN PGM S MM\n1 SPL X+10 K3X+0 K2X+0 K1X-1 E+1 F500\n", "2:7:", "no move has placed X"),
            ("0 BEGIN PGM S MM\n1 L X+0 R0 F500\n2 SPL X+10 K3X+0 K2X+0 K1X-1 E++1\n", "3:24:", "exponent"),
        ],
    );
}
