//! Heidenhain `RND` and `CHF`: the corner between two contour elements rounded or chamfered, as
//! the iTNC 530 user's manual (§6.4) and the TNC 620's (§5.4) describe them, checked against the
//! rounding worked here by another construction (the bisector of the corner, or the circle
//! tangent to both elements), and under radius compensation against shapely's offset curve of the
//! rounded contour (tests/peer/offset_reference.py).

use super::tnc_comp::{arc, line, path, reference, table, El, TOLERANCE};
use super::*;

fn sub(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] - b[0], a[1] - b[1]]
}

pub(super) fn dist(a: [f64; 2], b: [f64; 2]) -> f64 {
    let d = sub(a, b);
    d[0].hypot(d[1])
}

pub(super) fn unit(v: [f64; 2]) -> [f64; 2] {
    let n = v[0].hypot(v[1]);
    [v[0] / n, v[1] / n]
}

/// The fillet of radius `r` in the corner `k` between the lines from `p` and to `q`: its tangent
/// points `r / tan(theta / 2)` from the corner along each line and its centre on the bisector
/// `r / sin(theta / 2)` from it, theta the angle between the lines (mm).
pub(super) fn fillet(p: [f64; 2], k: [f64; 2], q: [f64; 2], r: f64) -> ([f64; 2], [f64; 2], [f64; 2]) {
    let (u, v) = (unit(sub(p, k)), unit(sub(q, k)));
    let theta = (u[0] * v[0] + u[1] * v[1]).acos();
    let d = r / (theta / 2.0).tan();
    let b = unit([u[0] + v[0], u[1] + v[1]]);
    let h = r / (theta / 2.0).sin();
    ([k[0] + u[0] * d, k[1] + u[1] * d], [k[0] + v[0] * d, k[1] + v[1] * d], [k[0] + b[0] * h, k[1] + b[1] * h])
}

fn xy(b: &fiveaxis::program::Block) -> [f64; 2] {
    [b.targets.x.unwrap() / MM, b.targets.y.unwrap() / MM]
}

fn numbered(p: &Program, n: u64) -> Vec<&fiveaxis::program::Block> {
    p.blocks.iter().filter(|b| b.number == Some(n)).collect()
}

pub(super) fn near(a: [f64; 2], b: [f64; 2]) -> bool {
    dist(a, b) < 1e-9
}

/// The manual's example (iTNC 530 §6.4: `L X+10 Y+40`, `L X+40 Y+25`, `RND R5 F100`, `L X+10 Y+5`)
/// without compensation: block 4 ends where the rounding arc leaves it, the arc (the RND block's,
/// at F100 alone) meets block 6 at the bisector fillet's tangent point, and block 6 runs at F300 again.
#[test]
fn rnd_is_the_bisector_fillet_at_its_own_feed() {
    let text = "0 BEGIN PGM RND MM\n1 TOOL CALL 1 Z S3000\n2 L X+10 Y+40 Z-2 R0 FMAX\n3 L X+10 Y+40 F300\n4 L X+40 Y+25\n\
                5 RND R5 F100\n6 L X+10 Y+5\n7 L Z+50 FMAX\n8 END PGM RND MM\n";
    let p = read(text, Dialect::Klartext, "rnd.h", &ReadOptions::default());
    assert!(errors(&p).is_empty(), "{:#?}", p.diagnostics);
    let (t1, t2, c) = fillet([10.0, 40.0], [40.0, 25.0], [10.0, 5.0], 5.0);
    let (b4, b5, b6) = (numbered(&p, 4), numbered(&p, 5), numbered(&p, 6));
    assert_eq!((b4.len(), b5.len(), b6.len()), (1, 1, 1));
    assert!(near(xy(b4[0]), t1), "{:?} {t1:?}", b4[0].targets);
    let k = b5[0];
    assert_eq!(k.motion, Motion::ArcCw, "a right turn: the rounding arc is clockwise");
    assert!(near(xy(k), t2), "{:?} {t2:?}", k.targets);
    let centre = k.arc.as_ref().unwrap().centre;
    assert!(near([centre[0] / MM, centre[1] / MM], c), "{centre:?} {c:?}");
    assert_eq!(k.line, 6, "the arc is the RND block's");
    assert!(near(xy(b6[0]), [10.0, 5.0]));
    let feed = |b: &fiveaxis::program::Block| b.feed.unwrap().value_per_min;
    assert_eq!((feed(b4[0]), feed(k), feed(b6[0])), (300.0, 100.0, 300.0));
    // The corner point (40, 25) is no longer on the path.
    assert!(!p.blocks.iter().any(|b| b.targets.x.is_some() && b.targets.y.is_some() && near(xy(b), [40.0, 25.0])));
}

/// The rounded contour of the manual's example, as elements (mm): the arc the fillet's.
pub(super) fn rounded_example(r: f64) -> Vec<El> {
    let (t1, t2, c) = fillet([10.0, 40.0], [40.0, 25.0], [10.0, 5.0], r);
    vec![line([10.0, 40.0], t1), arc(t1, t2, c, false), line(t2, [10.0, 5.0])]
}

/// The example with RL and RR: the TNC offsets the rounded contour, so the tool centre follows
/// shapely's offset curve of it, outside the corner at R + r and inside it at R - r; a tool whose
/// radius is larger than the rounding arc's cannot follow it inside ("Tool radius too large").
#[test]
fn rnd_under_compensation_offsets_the_rounded_contour() {
    let r = 3.0;
    for (word, side) in [("RL", "left"), ("RR", "right")] {
        let text = format!(
            "0 BEGIN PGM RND MM\n1 TOOL CALL 3 Z S3000\n2 L X-10 Y+40 Z-2 R0 FMAX\n3 L X+10 Y+40 {word} F300\n4 L X+40 Y+25\n\
             5 RND R5 F100\n6 L X+10 Y+5\n7 L X-10 Y+5 R0\n8 L Z+50 FMAX\n9 END PGM RND MM\n"
        );
        let p = read(&text, Dialect::Klartext, "rnd.h", &table("T3 P3 D6\n"));
        assert!(errors(&p).is_empty(), "{word}: {:#?}", p.diagnostics);
        // Block 3 ends perpendicular to the first element, direction (30, -15), on its side.
        let d = unit([30.0, -15.0]);
        let s = if word == "RL" { 1.0 } else { -1.0 };
        let start = [10.0 - s * d[1] * r, 40.0 + s * d[0] * r];
        let ours = path(&p, 4..=6, start);
        let contour = rounded_example(5.0);
        let got = reference(r, side, &contour, &ours);
        let e = got["radius_error_mm"].as_f64().unwrap();
        assert!(e < 1e-4, "{word}: a point of the path stands {e} mm off the radius from the rounded contour; {ours:?} {got}");
        assert!(got["hausdorff_mm"].as_f64().unwrap() < TOLERANCE * r, "{word}: {got}");
        // The rounding arc's offset: about the fillet's centre, at R + r outside the corner (RL, the
        // left of a right turn) and R - r inside it.
        let (_, _, c) = fillet([10.0, 40.0], [40.0, 25.0], [10.0, 5.0], 5.0);
        let k = ours.iter().find(|e| e.centre.is_some_and(|m| near(m, c))).unwrap_or_else(|| panic!("{word}: no arc about {c:?}: {ours:?}"));
        let want = if word == "RL" { 5.0 + r } else { 5.0 - r };
        assert!((dist(k.from, c) - want).abs() < 1e-9 && (dist(k.to, c) - want).abs() < 1e-9, "{word}: {k:?}");
    }
    // RR with a 12 mm tool: the 5 mm rounding arc is inside, smaller than the tool.
    let text = "0 BEGIN PGM RND MM\n1 TOOL CALL 3 Z S3000\n2 L X-10 Y+40 Z-2 R0 FMAX\n3 L X+10 Y+40 RR F300\n4 L X+40 Y+25\n\
                5 RND R5 F100\n6 L X+10 Y+5\n7 L X-10 Y+5 R0\n8 END PGM RND MM\n";
    let p = read(text, Dialect::Klartext, "rnd.h", &table("T3 P3 D12\n"));
    assert!(errors(&p).iter().any(|(_, _, m)| m.contains("Tool radius too large")), "{:#?}", errors(&p));
}

/// `CHF 5 F80` between two lines at a right angle: the first line ends 5 mm before the corner, the
/// chamfer runs at F80 to 5 mm along the second, which runs at the feed before again.
#[test]
fn chf_cuts_the_side_length_off_both_lines() {
    let text = "0 BEGIN PGM CHF MM\n1 TOOL CALL 1 Z S3000\n2 L X+0 Y+0 Z-2 R0 FMAX\n3 L X+30 F200\n4 CHF 5 F80\n5 L Y+30\n\
                6 L Z+50 FMAX\n7 END PGM CHF MM\n";
    let p = read(text, Dialect::Klartext, "chf.h", &ReadOptions::default());
    assert!(errors(&p).is_empty(), "{:#?}", p.diagnostics);
    let (b3, b4, b5) = (numbered(&p, 3)[0], numbered(&p, 4)[0], numbered(&p, 5)[0]);
    assert!(near(xy(b3), [25.0, 0.0]) && near(xy(b4), [30.0, 5.0]) && near(xy(b5), [30.0, 30.0]), "{:?} {:?} {:?}", b3.targets, b4.targets, b5.targets);
    assert_eq!(b4.motion, Motion::Linear);
    assert_eq!([b3, b4, b5].map(|b| b.feed.unwrap().value_per_min), [200.0, 80.0, 200.0]);
}

/// A line into a circle, its centre `CC` between the RND and the `C` (a pole moves nothing): the
/// rounding circle is tangent to the line and to the circle from outside (its centre R from the
/// line and rho + R from the circle's), and each element keeps its own line or circle.
#[test]
fn rnd_between_a_line_and_a_circle() {
    let text = "0 BEGIN PGM RND MM\n1 TOOL CALL 1 Z S3000\n2 L X+0 Y+0 Z-2 R0 FMAX\n3 L X+10 Y+0 F200\n4 RND R2\n\
                5 CC X+20 Y+0\n6 C X+20 Y-10 DR+\n7 L Z+50 FMAX\n8 END PGM RND MM\n";
    let p = read(text, Dialect::Klartext, "rnd.h", &ReadOptions::default());
    assert!(errors(&p).is_empty(), "{:#?}", p.diagnostics);
    let (b3, k, b6) = (numbered(&p, 3)[0], numbered(&p, 4)[0], numbered(&p, 6)[0]);
    let c = k.arc.as_ref().unwrap().centre;
    let c = [c[0] / MM, c[1] / MM];
    // The centre: 2 below the line y = 0 (the line turns right into the circle) and 12 from (20, 0).
    assert!((c[1] + 2.0).abs() < 1e-9 && (dist(c, [20.0, 0.0]) - 12.0).abs() < 1e-9, "{c:?}");
    assert!(near(xy(b3), [c[0], 0.0]), "{:?}", b3.targets);
    assert!((dist(xy(k), c) - 2.0).abs() < 1e-9 && (dist(xy(k), [20.0, 0.0]) - 10.0).abs() < 1e-9, "{:?}", k.targets);
    assert_eq!(k.motion, Motion::ArcCw);
    // No F in the RND block: the feed in effect.
    assert_eq!(k.feed.unwrap().value_per_min, 200.0);
    let a6 = b6.arc.as_ref().unwrap().centre;
    assert!(near([a6[0] / MM, a6[1] / MM], [20.0, 0.0]) && near(xy(b6), [20.0, -10.0]) && b6.motion == Motion::ArcCcw);
}

/// What the TNC cannot round or chamfer, and what this reader does not, is refused at the RND or
/// CHF block; the elements beside it are kept as programmed.
#[test]
fn corners_that_cannot_be_made_are_refused_at_their_block() {
    let head = "0 BEGIN PGM T MM\n1 TOOL CALL 1 Z S3000\n2 L X+0 Y+0 Z-2 R0 FMAX\n";
    let cases: &[(&str, &str, &str)] = &[
        // No contour element before it (the positioning at FMAX).
        ("3 RND R2\n4 L X+10 F100\n", "4:3:", "not a contour element it joins"),
        // Something other than an element after it.
        ("3 L X+10 F100\n4 RND R2\n5 M5\n6 L Y+10\n", "5:3:", "not a contour element"),
        ("3 L X+10 F100\n4 RND R2\n5 L F200\n6 L Y+10\n", "5:3:", "moves nothing"),
        // The flow leaving the statement after it (a block refused where it stands, a call): the
        // corner joins two elements one after the other in the program.
        ("3 L X+10 F100\n4 RND R2\n5 FL X+10 Y+20\n6 L X+0 Y+20\n", "5:3:", "was not read"),
        ("3 L X+10 F100\n4 RND R2\n5 CALL LBL 9\n6 M30\n7 LBL 9\n8 L Y+10\n9 LBL 0\n", "5:3:", "a call after it"),
        // A rounding that ends where the arc after it ends (worked by hand: the fillet of R7.5 about
        // (5, -7.5) meets the circle about (15, 0) at (11, -3), the arc's end): no arc is left.
        ("3 CC X+15 Y+0\n4 L X+10 Y+0 F200\n5 RND R7.5\n6 C X+11 Y-3 DR+\n", "6:3:", "whole arc after it"),
        ("3 L X+10 F100\n4 RND R2\n5 L Y+10 R0\n", "5:3:", "R0"),
        ("3 L X+10 F100\n4 RND R2\n", "5:3:", "before the program ends"),
        // Too large for the elements: 3 mm lines at a right angle take R3 at most.
        ("3 L X+3 F100\n4 RND R3.5\n5 L Y+3\n", "5:3:", "too large"),
        ("3 L X+3 F100\n4 CHF 4\n5 L Y+3\n", "5:3:", "longer than a line"),
        // A chamfer beside a circle.
        ("3 L X+10 F100\n4 CHF 1\n5 CC X+10 Y+5\n6 C X+15 Y+5 DR+\n", "5:3:", "two straight lines"),
        // Elements that leave the plane.
        ("3 L X+10 Z-3 F100\n4 RND R1\n5 L Y+10\n", "5:3:", "tool axis"),
        // In line: no corner.
        ("3 L X+10 F100\n4 RND R1\n5 L X+20\n", "5:3:", "tangentially"),
        // Written wrong.
        ("3 L X+10 F100\n4 RND 2\n5 L Y+10\n", "5:7:", "unexpected word"),
        ("3 L X+10 F100\n4 CHF\n5 L Y+10\n", "5:3:", "side length"),
        ("3 L X+10 F100\n4 RND R2\n5 RND R2\n6 L Y+10\n", "6:3:", "right after another"),
    ];
    let texts: Vec<(String, &str, &str)> = cases.iter().map(|(body, at, needle)| (format!("{head}{body}99 END PGM T MM\n"), *at, *needle)).collect();
    let texts: Vec<(&str, &str, &str)> = texts.iter().map(|(text, at, needle)| (text.as_str(), *at, *needle)).collect();
    refuses_each(Dialect::Klartext, &ReadOptions::default(), &texts);
    // Refused for its size: both lines are kept whole.
    let p = read(&format!("{head}3 L X+3 F100\n4 RND R3.5\n5 L Y+3\n99 END PGM T MM\n"), Dialect::Klartext, "t.h", &ReadOptions::default());
    let (b3, b5) = (numbered(&p, 3)[0], numbered(&p, 5)[0]);
    assert!(b3.targets.x == Some(3.0 * MM) && b3.targets.y.is_none() && b5.targets.x.is_none() && b5.targets.y == Some(3.0 * MM) && numbered(&p, 4).is_empty(), "{:?} {:?}", b3.targets, b5.targets);
}

/// `call` (a TOOL CALL block) then `body` (to `END PGM T MM`) read on the Hermle with tool 3 of
/// 6 mm in the table, flat and in a plane tilted 30 deg by PLANE SPATIAL SPB+30 after the call; no
/// errors in either.
fn flat_and_tilted(call: &str, body: &str) -> (Program, Program) {
    let hermle = fiveaxis::machine::Machine::hermle_c600u();
    let mut options = table("T3 P3 D6\n").on(&hermle);
    options.tool_table = table("T3 P3 D6\n").tool_table;
    let [flat, tilted] = ["", "1 PLANE SPATIAL SPA+0 SPB+30 SPC+0 TURN FMAX\n"].map(|plane| read(&format!("0 BEGIN PGM T MM\n{call}{plane}{body}"), Dialect::Klartext, "t.h", &options));
    assert!(errors(&flat).is_empty() && errors(&tilted).is_empty(), "{:#?} {:#?}", flat.diagnostics, tilted.diagnostics);
    (flat, tilted)
}

/// A point of the plane tilted by SPB+30, given in the workpiece's coordinates, in the plane's:
/// Ry(30)^T of it.
fn back_from_spb30(v: [f64; 3]) -> [f64; 3] {
    let t = 30f64.to_radians();
    [t.cos() * v[0] - t.sin() * v[2], v[1], t.sin() * v[0] + t.cos() * v[2]]
}

/// The manual's example with `RL` in a plane tilted 30 deg (PLANE SPATIAL SPB+30 on the Hermle):
/// rounded and offset in the plane's coordinates; its blocks, turned back by the plane's rotation,
/// are the untilted reading's, the rounding arc written in the plane's frame.
#[test]
fn rnd_in_a_tilted_plane_rounds_in_the_planes_coordinates() {
    let body = "2 L X-10 Y+40 Z+5 R0 FMAX\n3 L X+10 Y+40 RL F300\n4 L X+40 Y+25\n5 RND R5 F100\n6 L X+10 Y+5\n7 L X-10 Y+5 R0\n8 END PGM T MM\n";
    let (flat, tilted) = flat_and_tilted("1 TOOL CALL 3 Z S3000\n", body);
    let moves = |p: &Program| -> Vec<(u64, fiveaxis::program::Motion, [f64; 3], Option<[f64; 3]>)> {
        p.blocks.iter().filter(|b| b.number.is_some_and(|n| (3..=7).contains(&n)) && b.targets.x.is_some() && b.targets.y.is_some()).map(|b| (b.number.unwrap(), b.motion, [b.targets.x.unwrap(), b.targets.y.unwrap(), b.targets.z.unwrap_or(0.0)], b.arc.as_ref().map(|a| a.centre))).collect()
    };
    let (f, k) = (moves(&flat), moves(&tilted));
    assert_eq!(f.len(), k.len(), "{f:?}\n{k:?}");
    assert!(f.iter().any(|m| m.0 == 5 && m.1 == Motion::ArcCw), "the rounding arc: {f:?}");
    for (a, b) in f.iter().zip(&k) {
        let (pb, cb) = (back_from_spb30(b.2), b.3.map(back_from_spb30));
        assert!(a.0 == b.0 && a.1 == b.1 && (0..2).all(|i| (a.2[i] - pb[i]).abs() < 1e-9), "{a:?} vs {b:?} turned back {pb:?}");
        if let (Some(ca), Some(cb)) = (a.3, cb) {
            assert!((0..2).all(|i| (ca[i] - cb[i]).abs() < 1e-9), "{a:?} vs {b:?}: centre {cb:?}");
        }
    }
    let arc = tilted.blocks.iter().find(|b| b.number == Some(5)).unwrap().arc.as_ref().unwrap();
    assert!(arc.frame.is_some(), "the rounding arc is written in the tilted plane");
}

/// A pole (CC) read after the held element goes out behind it, in the program's order, with
/// and without a corner.
#[test]
fn a_pole_after_the_held_element_keeps_its_place() {
    for corner in ["", "4 RND R1\n"] {
        let text = format!("0 BEGIN PGM O MM\n1 L X+0 Y+0 Z-2 FMAX\n2 L X+10 Y+0 F100\n3 CC X+20 Y+10\n{corner}5 C X+10 Y+20 DR+\n6 END PGM O MM\n");
        let p = read(&text, Dialect::Klartext, "o.h", &ReadOptions::default());
        assert!(errors(&p).is_empty(), "{:#?}", p.diagnostics);
        let order: Vec<u64> = p.blocks.iter().filter_map(|b| b.number).collect();
        let mut sorted = order.clone();
        sorted.sort_unstable();
        assert_eq!(order, sorted, "{corner:?}");
    }
}

/// `CT` after an arc in a tilted plane (SPB+30 on the Hermle) is tangent to that arc as in the flat
/// plane: the arc's centre is taken back into the plane's coordinates (it had been mixed with the
/// plane's end point in the workpiece's).
#[test]
fn ct_after_an_arc_in_a_tilted_plane() {
    let body = "2 L X+10 Y+0 Z+5 FMAX\n3 CC X+0 Y+0\n4 C X+0 Y+10 DR+ F300\n5 CT X-10 Y+0\n6 END PGM T MM\n";
    let (flat, tilted) = flat_and_tilted("1 TOOL CALL 1 Z S3000\n", body);
    let ct = |p: &Program| p.blocks.iter().find(|b| b.number == Some(5)).and_then(|b| b.arc.as_ref().map(|a| a.centre)).expect("block 5 an arc");
    // Tangent to the circle about the origin at (0, 10), on to (-10, 0): the same circle.
    let (c_flat, c_tilted) = (ct(&flat), back_from_spb30(ct(&tilted)));
    assert!(c_flat[0].abs() < 1e-9 && c_flat[1].abs() < 1e-9, "{c_flat:?}");
    assert!(c_tilted[0].abs() < 1e-9 && c_tilted[1].abs() < 1e-9, "{c_tilted:?}");
}
