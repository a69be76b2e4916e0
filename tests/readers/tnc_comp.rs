//! Heidenhain radius compensation `RL`/`RR`: the tool-centre path against shapely's offset curve of
//! the programmed contour (tests/peer/offset_reference.py), where it starts and ends against the
//! TNC's rule worked by hand, and what the reader refuses.

use super::*;
use std::sync::Arc;

/// A path element in the working plane, mm: a line, or an arc with its centre and direction.
#[derive(Debug, Clone, Copy)]
pub(super) struct El {
    pub(super) kind: &'static str,
    pub(super) from: [f64; 2],
    pub(super) to: [f64; 2],
    pub(super) centre: Option<[f64; 2]>,
    pub(super) ccw: bool,
}

impl El {
    fn json(&self) -> serde_json::Value {
        serde_json::json!({ "kind": self.kind, "from": self.from, "to": self.to, "centre": self.centre, "ccw": self.ccw })
    }
}

pub(super) fn line(from: [f64; 2], to: [f64; 2]) -> El {
    El { kind: "line", from, to, centre: None, ccw: false }
}

pub(super) fn arc(from: [f64; 2], to: [f64; 2], centre: [f64; 2], ccw: bool) -> El {
    El { kind: "arc", from, to, centre: Some(centre), ccw }
}

/// The moves of the blocks numbered `numbers`, from `start` (mm), as path elements.
pub(super) fn path(p: &Program, numbers: std::ops::RangeInclusive<u64>, start: [f64; 2]) -> Vec<El> {
    let mut at = start;
    let mut out = Vec::new();
    for b in p.blocks.iter().filter(|b| b.number.is_some_and(|n| numbers.contains(&n))) {
        let (Some(x), Some(y)) = (b.targets.x, b.targets.y) else { continue };
        let to = [x / MM, y / MM];
        if (to[0] - at[0]).hypot(to[1] - at[1]) < 1e-9 {
            continue;
        }
        out.push(match (&b.arc, b.motion) {
            (Some(a), Motion::ArcCw | Motion::ArcCcw) => arc(at, to, [a.centre[0] / MM, a.centre[1] / MM], b.motion == Motion::ArcCcw),
            _ => line(at, to),
        });
        at = to;
    }
    out
}

pub(super) fn reference(radius: f64, side: &str, contour: &[El], path: &[El]) -> serde_json::Value {
    use std::io::Write;
    let [contour, path]: [Vec<serde_json::Value>; 2] = [contour, path].map(|els| els.iter().map(El::json).collect());
    let input = serde_json::json!({ "radius": radius, "side": side, "contour": contour, "path": path });
    let mut child = std::process::Command::new("python3")
        .arg(Path::new(env!("CARGO_MANIFEST_DIR")).join("peer/offset_reference.py"))
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .spawn()
        .expect("python3");
    child.stdin.take().unwrap().write_all(input.to_string().as_bytes()).unwrap();
    let out = child.wait_with_output().unwrap();
    assert!(out.status.success(), "offset_reference.py failed");
    serde_json::from_slice(&out.stdout).unwrap()
}

/// How far shapely's offset curve may stray, per mm of radius: GEOS simplifies the line it offsets
/// by a hundredth of the distance (BufferParameters' DEFAULT_SIMPLIFY_FACTOR, 0.01), so its elements
/// lean and its arcs flatten by about that (0.014 mm at an inside corner of a 3 mm offset, 0.061 mm
/// on a 5 mm corner arc). The exact check is each path point's distance to the contour.
pub(super) const TOLERANCE: f64 = 0.015;

pub(super) fn table(text: &str) -> ReadOptions {
    ReadOptions { tool_table: Some(Arc::new(fiveaxis::program::ToolTable::parse(text).unwrap())), ..Default::default() }
}

/// An outside contour, counter-clockwise with RR (the tool outside the part): convex corners, a
/// tangential and a concave arc, a notch whose inside corner the offset elements meet at.
const OUTSIDE: &str = "0 BEGIN PGM RC MM\n1 TOOL CALL 3 Z S3000\n2 L X-20 Y-20 Z+5 R0 FMAX\n3 L Z-2 F200\n\
4 L X+0 Y+0 RR F500\n5 L X+60\n6 CR X+70 Y+10 R+10 DR+\n7 L Y+40\n8 L X+50\n9 CR X+40 Y+30 R+10 DR-\n\
10 L Y+20\n11 L X+0\n12 L Y+5\n13 L X-20 Y-10 R0\n14 L Z+50 FMAX\n15 END PGM RC MM\n";

/// [`OUTSIDE`]'s contour, blocks 4 to 12, as elements (mm); the 840D test's N7 to N14 too.
pub(super) fn outside_contour() -> Vec<El> {
    vec![
        line([0.0, 0.0], [60.0, 0.0]),
        arc([60.0, 0.0], [70.0, 10.0], [60.0, 10.0], true),
        line([70.0, 10.0], [70.0, 40.0]),
        line([70.0, 40.0], [50.0, 40.0]),
        arc([50.0, 40.0], [40.0, 30.0], [40.0, 40.0], false),
        line([40.0, 30.0], [40.0, 20.0]),
        line([40.0, 20.0], [0.0, 20.0]),
        line([0.0, 20.0], [0.0, 5.0]),
    ]
}

#[test]
fn rr_outside_contour_is_shapelys_offset_curve_and_starts_and_ends_perpendicular() {
    let r = 3.0; // tool 3: diameter 6 mm
    let p = read(OUTSIDE, Dialect::Klartext, "rc.h", &table("T3 P3 D6\n"));
    assert!(errors(&p).is_empty(), "{:#?}", p.diagnostics);
    let contour = outside_contour();
    // Block 4 starts compensation: the tool ends it perpendicular to the first element (+X) at
    // its start, on its right: (0, -r). Block 13 (R0) leaves the last element (-Y) perpendicular at
    // its end (0, 5), on its right: (-r, 5), and goes to the programmed (-20, -10). (The contour is
    // left open: shapely offsets a closed line as a ring.)
    let entry = p.blocks.iter().find(|b| b.number == Some(4)).expect("block 4");
    assert!((entry.targets.x.unwrap() / MM).abs() < 1e-9 && (entry.targets.y.unwrap() / MM + r).abs() < 1e-9, "{:?}", entry.targets);
    let exit: Vec<_> = p.blocks.iter().filter(|b| b.number == Some(13)).collect();
    assert_eq!(exit.len(), 1);
    assert!((exit[0].targets.x.unwrap() / MM + 20.0).abs() < 1e-9 && (exit[0].targets.y.unwrap() / MM + 10.0).abs() < 1e-9);
    let ours = path(&p, 5..=12, [0.0, -r]);
    assert!((ours.last().unwrap().to[0] + r).abs() < 1e-9 && (ours.last().unwrap().to[1] - 5.0).abs() < 1e-9, "{:?}", ours.last());
    let got = reference(r, "right", &contour, &ours);
    let e = got["radius_error_mm"].as_f64().unwrap();
    assert!(e < 1e-4, "a point of the path stands {e} mm off the radius from the contour; {got}");
    let h = got["hausdorff_mm"].as_f64().unwrap();
    assert!(h < TOLERANCE * r, "Hausdorff distance to shapely's offset curve {h} mm; {got}");
    // The inside corner of the notch: where the offset elements meet, (40 - r, 20 + r).
    assert!(ours.iter().any(|e| (e.to[0] - 37.0).abs() < 1e-9 && (e.to[1] - 23.0).abs() < 1e-9), "{ours:?}");
    // shapely's curve starts and ends where the TNC's rule puts the tool.
    assert!((got["first"][0].as_f64().unwrap()).abs() < 1e-6 && (got["first"][1].as_f64().unwrap() + r).abs() < 1e-6, "{got}");
    // A sharp corner of the part gets a transitional arc about it (block 8's: (70, 40), radius r).
    let corner = p.blocks.iter().find(|b| b.number == Some(8) && b.motion.is_arc()).expect("a corner arc before block 8");
    let c = corner.arc.as_ref().unwrap().centre;
    assert!((c[0] / MM - 70.0).abs() < 1e-9 && (c[1] / MM - 40.0).abs() < 1e-9, "{c:?}");
}

/// `text` (an [`OUTSIDE`] contour) read on the Hermle with its block 2 in a plane tilted by PLANE
/// SPATIAL SPB+30, tool 3 of 6 mm; no errors.
fn read_tilted_30(text: &str) -> Program {
    let hermle = fiveaxis::machine::Machine::hermle_c600u();
    let mut options = table("T3 P3 D6\n").on(&hermle);
    options.tool_table = table("T3 P3 D6\n").tool_table;
    let text = text.replace("2 L X-20 Y-20 Z+5 R0 FMAX\n", "2 PLANE SPATIAL SPA+0 SPB+30 SPC+0 TURN FMAX\n2 L X-20 Y-20 Z+5 R0 FMAX\n");
    let p = read(&text, Dialect::Klartext, "rc.h", &options);
    assert!(errors(&p).is_empty(), "{:#?}", p.diagnostics);
    p
}

/// The outside contour in a plane tilted 30 deg (PLANE SPATIAL SPB+30 on the Hermle): the same
/// offsets in the plane's coordinates (the blocks come out in the workpiece's).
#[test]
fn rr_in_a_tilted_plane_offsets_in_the_planes_coordinates() {
    let r = 3.0;
    let mut p = read_tilted_30(OUTSIDE);
    // The plane's rotation: SPB+30 turns the coordinate system about Y by +30 deg (right-handed:
    // the plane's X axis is (cos 30, 0, -sin 30) in the workpiece), so block 2's plane point
    // (-20, -20, 5) lies at Ry(30) (-20, -20, 5).
    let b2 = p.blocks.iter().find(|b| b.number == Some(2) && b.targets.x.is_some()).expect("block 2");
    let w = [b2.targets.x.unwrap() / MM, b2.targets.y.unwrap() / MM, b2.targets.z.unwrap() / MM];
    let ry = |t: f64| [[t.cos(), 0.0, t.sin()], [0.0, 1.0, 0.0], [-t.sin(), 0.0, t.cos()]];
    let apply = |m: [[f64; 3]; 3], v: [f64; 3]| [0, 1, 2].map(|i| m[i][0] * v[0] + m[i][1] * v[1] + m[i][2] * v[2]);
    let rot = ry(30f64.to_radians());
    let e = apply(rot, [-20.0, -20.0, 5.0]);
    assert!((0..3).all(|i| (e[i] - w[i]).abs() < 1e-9), "block 2 at {w:?}, not at {e:?}: (-20, -20, 5) turned +30 deg about Y");
    let back = [0, 1, 2].map(|i| [0, 1, 2].map(|j| rot[j][i]));
    assert!(w[2] > 5.0 + 1.0 || w[2] < 5.0 - 1.0, "the plane is tilted: {w:?}");
    for b in &mut p.blocks {
        if let (Some(x), Some(y), Some(z)) = (b.targets.x, b.targets.y, b.targets.z) {
            let v = apply(back, [x, y, z]);
            (b.targets.x, b.targets.y, b.targets.z) = (Some(v[0]), Some(v[1]), Some(v[2]));
        }
        if let Some(a) = b.arc.as_mut() {
            a.centre = apply(back, a.centre);
        }
    }
    let entry = p.blocks.iter().find(|b| b.number == Some(4)).expect("block 4");
    assert!((entry.targets.x.unwrap() / MM).abs() < 1e-9 && (entry.targets.y.unwrap() / MM + r).abs() < 1e-9, "{:?}", entry.targets);
    let ours = path(&p, 5..=12, [0.0, -r]);
    let got = reference(r, "right", &outside_contour(), &ours);
    let e = got["radius_error_mm"].as_f64().unwrap();
    assert!(e < 1e-4, "a point of the path stands {e} mm off the radius from the contour; {got}");
    assert!(got["hausdorff_mm"].as_f64().unwrap() < TOLERANCE * r, "{got}");
}

#[test]
fn rl_clockwise_contour_with_a_plunge_between_entry_and_contour() {
    // A clockwise contour has its inside on the right of travel: RL runs the tool outside it. L Z-5
    // between the block that starts compensation and the contour's first element stands where that
    // element puts the tool: its first element goes +Y from (0, 20), whose left is -X, so (-r, 20).
    let text = "0 BEGIN PGM RC MM\n1 TOOL CALL 4 Z S3000\n2 L X+30 Y+20 Z+5 R0 FMAX\n3 L X+0 Y+20 RL F500\n4 L Z-5\n\
                5 L Y+40\n6 L X+60\n7 L Y+0\n8 L X+0\n9 L Y+5\n10 L X+30 R0\n11 END PGM RC MM\n";
    let r = 5.0;
    let p = read(text, Dialect::Klartext, "rc.h", &table("T4 P4 D10\n"));
    assert!(errors(&p).is_empty(), "{:#?}", p.diagnostics);
    for line in [3, 4] {
        let b = p.blocks.iter().find(|b| b.number == Some(line)).unwrap();
        assert!((b.targets.x.unwrap() / MM + r).abs() < 1e-9 && (b.targets.y.unwrap() / MM - 20.0).abs() < 1e-9, "block {line}: {:?}", b.targets);
    }
    let contour = [
        line([0.0, 20.0], [0.0, 40.0]),
        line([0.0, 40.0], [60.0, 40.0]),
        line([60.0, 40.0], [60.0, 0.0]),
        line([60.0, 0.0], [0.0, 0.0]),
        line([0.0, 0.0], [0.0, 5.0]),
    ];
    let ours = path(&p, 5..=9, [-r, 20.0]);
    let got = reference(r, "left", &contour, &ours);
    let e = got["radius_error_mm"].as_f64().unwrap();
    assert!(e < 1e-4, "a point of the path stands {e} mm off the radius from the contour; {got}");
    let h = got["hausdorff_mm"].as_f64().unwrap();
    assert!(h < TOLERANCE * r, "Hausdorff distance to shapely's offset curve {h} mm; {got}");
}

#[test]
fn rl_rr_refusals_name_the_rule() {
    let t = table("T3 P3 D6\n");
    // (Lines of the file: the body's first line is line 2.)
    let cases: &[(&str, &str, &str)] = &[
        // A change of side without R0 between.
        ("1 TOOL CALL 3 Z\n2 L X+0 Y+0 R0 FMAX\n3 L X+10 RL F100\n4 L Y+10\n5 L X+20 RR\n6 L X+0 R0\n", "6:", "at least one traversing block"),
        // Compensation starting in a circle.
        ("1 TOOL CALL 3 Z\n2 L X+0 Y+0 R0 FMAX\n3 CC X+5 Y+0\n4 C X+10 Y+0 DR+ RL F100\n", "5:", "circle block"),
        // A tool not in the table, no TOOL CALL.
        ("1 TOOL CALL 7 Z\n2 L X+0 Y+0 R0 FMAX\n3 L X+10 RL F100\n", "4:", "tool 7 is not in the tool table"),
        ("1 L X+0 Y+0 R0 FMAX\n2 L X+10 RL F100\n", "3:", "no TOOL CALL by number"),
        // A tool change under compensation.
        ("1 TOOL CALL 3 Z\n2 L X+0 Y+0 R0 FMAX\n3 L X+10 RL F100\n4 L Y+10\n5 TOOL CALL 3 Z\n", "6:", "TOOL CALL with radius compensation"),
        // A slot 2 mm wide into the part, which a 6 mm tool cannot enter: block 6, the slot's
        // bottom, is where the offset elements no longer meet.
        ("1 TOOL CALL 3 Z\n2 L X-10 Y+10 R0 FMAX\n3 L X+0 Y+10 RR F100\n4 L X+20\n5 L Y+12\n6 L X+22\n7 L Y+10\n8 L X+40\n9 L Y+30 R0\n", "7:", "cannot be reached by the tool without gouging"),
        // R0 right after the block that starts compensation.
        ("1 TOOL CALL 3 Z\n2 L X+0 Y+0 R0 FMAX\n3 L X+10 RL F100\n4 L X+20 R0\n", "5:", "before any contour element"),
        // A cycle called after every move (M89) would drill before the held blocks run; M99 in the
        // block that starts compensation likewise.
        ("1 TOOL CALL 3 Z\n2 L X+0 Y+0 R0 FMAX M89\n3 L X+10 RL F100\n", "4:", "M89 in force"),
        ("1 TOOL CALL 3 Z\n2 L X+0 Y+0 R0 FMAX\n3 L X+10 RL F100 M99\n", "4:", "cycle call (M99/M89)"),
        // Compensation ends in a straight line: an arc from the compensated point is no circle.
        ("1 TOOL CALL 3 Z\n2 L X+0 Y+0 R0 FMAX\n3 L X+10 RL F100\n4 L X+20\n5 CC X+20 Y+10\n6 C X+30 Y+10 DR+ R0\n", "7:", "R0 in a circle block"),
        // Two compensation words in one block.
        ("1 TOOL CALL 3 Z\n2 L X+0 Y+0 R0 FMAX\n3 L X+10 RL R0 F100\n", "4:", "a second radius compensation word"),
        // Under M128 / TCPM the rotary axes move the contour: not read with RL/RR.
        ("1 TOOL CALL 3 Z\n2 L X+0 Y+0 R0 FMAX M128\n3 L X+10 RL F100\n", "4:", "under M128 / FUNCTION TCPM"),
        // An outside corner before a rapid (RL, turning right): the TNC's arc there has no feed in
        // its manuals. Before, the arc ran at the last F, or stopped at "feed move without a feed"
        // with none given.
        ("1 TOOL CALL 3 Z\n2 L X+0 Y+0 R0 FMAX\n3 L X+10 RL F100\n4 L X+20\n5 L Y-10 FMAX\n6 L X+0 R0\n", "6:", "outside corner before a rapid (FMAX)"),
        ("1 TOOL CALL 3 Z\n2 L X+0 Y+0 R0 FMAX\n3 L X+10 RL FMAX\n4 L X+20 FMAX\n5 L Y-10 FMAX\n6 L X+0 R0\n", "6:", "outside corner before a rapid (FMAX)"),
    ];
    for (body, at, needle) in cases {
        let text = format!("0 BEGIN PGM T MM\n{body}99 END PGM T MM\n");
        let p = read(&text, Dialect::Klartext, "t.h", &t);
        let errs = errors(&p);
        assert!(
            errs.iter().any(|(l, c, m)| format!("{l}:{c}").starts_with(at) && m.contains(needle)),
            "{body}: no error at {at} with {needle:?}: {errs:#?}"
        );
    }
    // Without --tool-table: said so.
    let p = read("0 BEGIN PGM T MM\n1 TOOL CALL 3 Z\n2 L X+0 Y+0 R0 FMAX\n3 L X+10 RL F100\n4 END PGM T MM\n", Dialect::Klartext, "t.h", &ReadOptions::default());
    has(&p, 4, 10, "--tool-table");
}

/// Corners of less than LinuxCNC's 0.05 rad: the TNC intersects every inside corner and rounds every
/// outside one (a corner of 2.75 deg left uncompensated would cut 11.5 um into the part with a 10 mm
/// tool, or leave the corner's arc out), so the path stays at the radius from the contour, as
/// shapely's offset curve has it, on both sides.
#[test]
fn shallow_corners_are_intersected_or_rounded() {
    let r = 10.0;
    let contour = [line([0.0, 0.0], [50.0, 0.0]), line([50.0, 0.0], [100.0, 2.4])];
    for (word, side, start) in [("RL", "left", [0.0, r]), ("RR", "right", [0.0, -r])] {
        let text = format!(
            "0 BEGIN PGM RC MM\n1 TOOL CALL 5 Z S3000\n2 L X-20 Y+0 Z-2 R0 FMAX\n3 L X+0 Y+0 {word} F500\n4 L X+50\n5 L X+100 Y+2.4\n6 L X+120 Y+20 R0\n7 END PGM RC MM\n"
        );
        let p = read(&text, Dialect::Klartext, "rc.h", &table("T5 P5 D20\n"));
        assert!(errors(&p).is_empty(), "{word}: {:#?}", p.diagnostics);
        let ours = path(&p, 4..=5, start);
        let got = reference(r, side, &contour, &ours);
        let e = got["radius_error_mm"].as_f64().unwrap();
        assert!(e < 1e-4, "{word}: a point of the path stands {e} mm off the radius from the contour; {ours:?} {got}");
        assert!(got["hausdorff_mm"].as_f64().unwrap() < TOLERANCE * r, "{word}: {got}");
    }
}

/// Inside corners between a line and an arc, an arc and a line, and two arcs (a pocket run
/// counter-clockwise with RL, the tool inside it; arcs bulging out, and a boss's arc bulging in): the
/// offset elements meet at the one of their two intersections the TNC's path takes, so every point
/// stays at the radius from the contour and the path is shapely's offset curve.
#[test]
fn inside_corners_with_arcs_meet_where_the_offset_elements_do() {
    let r = 3.0;
    let text = "0 BEGIN PGM RC MM\n1 TOOL CALL 3 Z S3000\n2 L X+20 Y+20 Z+5 R0 FMAX\n3 L Z-2 F200\n4 L X+20 Y+0 RL F500\n\
                5 L X+60\n6 CC X+50 Y+20\n7 C X+60 Y+40 DR+\n8 L X+0\n9 CC X+10 Y+25\n10 C X+0 Y+10 DR+\n11 CC X+0 Y+0\n\
                12 C X+10 Y+0 DR-\n13 L X+20 Y+20 R0\n14 END PGM RC MM\n";
    let p = read(text, Dialect::Klartext, "rc.h", &table("T3 P3 D6\n"));
    assert!(errors(&p).is_empty(), "{:#?}", p.diagnostics);
    let contour = [
        line([20.0, 0.0], [60.0, 0.0]),
        arc([60.0, 0.0], [60.0, 40.0], [50.0, 20.0], true),
        line([60.0, 40.0], [0.0, 40.0]),
        arc([0.0, 40.0], [0.0, 10.0], [10.0, 25.0], true),
        arc([0.0, 10.0], [10.0, 0.0], [0.0, 0.0], false),
    ];
    let ours = path(&p, 5..=12, [20.0, r]);
    // Five elements, no transitional arc: every corner is inside.
    assert_eq!(ours.len(), 5, "{ours:?}");
    let got = reference(r, "left", &contour, &ours);
    let e = got["radius_error_mm"].as_f64().unwrap();
    assert!(e < 1e-4, "a point of the path stands {e} mm off the radius from the contour; {ours:?} {got}");
    assert!(got["hausdorff_mm"].as_f64().unwrap() < TOLERANCE * r, "{got}");
}

/// `TOOL CALL Z S5000` (a new speed, no tool) keeps the tool in the spindle, whose radius RL takes.
#[test]
fn a_speed_change_keeps_the_tool() {
    let text = "0 BEGIN PGM RC MM\n1 TOOL CALL 3 Z S3000\n2 TOOL CALL Z S5000\n3 L X-10 Y+0 R0 FMAX\n4 L X+0 Y+0 RL F100\n5 L X+20\n6 L X+30 Y+10 R0\n7 END PGM RC MM\n";
    let p = read(text, Dialect::Klartext, "rc.h", &table("T3 P3 D6\n"));
    assert!(errors(&p).is_empty(), "{:#?}", p.diagnostics);
    // Block 4 ends on the left of the first element (+X) at its start: (0, 3).
    let b = p.blocks.iter().find(|b| b.number == Some(4)).unwrap();
    assert!((b.targets.x.unwrap() / MM).abs() < 1e-9 && (b.targets.y.unwrap() / MM - 3.0).abs() < 1e-9, "{:?}", b.targets);
}

/// A negative radius (R + DR below 0), and millions of blocks held under compensation without a
/// move in the plane, are refused at the block, not guessed or held without bound.
#[test]
fn a_negative_radius_and_endless_held_blocks_are_refused() {
    let p = read("0 BEGIN PGM T MM\n1 TOOL CALL 3 Z\n2 L X+0 Y+0 R0 FMAX\n3 L X+10 RL F100\n4 END PGM T MM\n", Dialect::Klartext, "t.h", &table("T3 P3 D-6\n"));
    has(&p, 4, 10, "negative");
    let mut text = String::from("0 BEGIN PGM T MM\n1 TOOL CALL 3 Z\n2 L X+0 Y+0 R0 FMAX\n3 L X+10 RL F100\n4 L Y+10\n");
    for k in 0..10_001 {
        text.push_str(&format!("{} L Z{}\n", k + 5, if k % 2 == 0 { "+1" } else { "-1" }));
    }
    text.push_str("99999 END PGM T MM\n");
    let p = read(&text, Dialect::Klartext, "t.h", &table("T3 P3 D6\n"));
    let errs = errors(&p);
    // Held: block 4 (the last contour element) and the Z moves after it; the 10,000th Z move (file
    // line 5 + 10,000) would be the 10,001st.
    assert!(errs.iter().any(|(l, _, m)| *l == 10_005 && m.contains("more than 10000 blocks")), "{errs:#?}");
}

/// `R0` without coordinates in a tilted plane: the tool goes to the contour's last programmed point,
/// which the plane's rotation places in the workpiece (SPB+30: Ry(30) of it).
#[test]
fn r0_without_coordinates_in_a_tilted_plane_goes_to_the_programmed_point() {
    let p = read_tilted_30(&OUTSIDE.replace("13 L X-20 Y-10 R0\n", "13 L R0 F200\n"));
    let b = p.blocks.iter().filter(|b| b.number == Some(13)).last().expect("block 13");
    let w = [b.targets.x.unwrap() / MM, b.targets.y.unwrap() / MM, b.targets.z.unwrap() / MM];
    // The last programmed point, (0, 5) at Z-2, turned +30 deg about Y.
    let t = 30f64.to_radians();
    let want = [0.0 * t.cos() + -2.0 * t.sin(), 5.0, -0.0 * t.sin() + -2.0 * t.cos()];
    assert!((0..3).all(|i| (w[i] - want[i]).abs() < 1e-9), "block 13 at {w:?}, not {want:?}");
}

/// Through the command line, as a TNC shop would run it: the program with its machine's TOOL.T
/// (the TNC's format, ISO 8859-1 with an umlaut in a tool's name) reads with no defect and its
/// block 4 ends where the TNC's rule puts it; without the table, exit 2 naming `--tool-table`; a
/// table with a bad radius, exit 2 naming its line and column.
#[test]
fn a_tnc_tool_table_through_the_command_line() {
    let dir = crate::common::scratch_dir("tnc-comp-cli");
    std::fs::write(dir.join("rc.h"), OUTSIDE).unwrap();
    // Each value under its column's name (T at 0, NAME at 5, L at 26, R at 38, DR at 50).
    let row = |t: &str, name: &[u8], l: &str, r: &str, dr: &str| {
        let mut v = format!("{t:<5}").into_bytes();
        v.extend(name);
        v.extend(" ".repeat(21 - name.len()).into_bytes());
        v.extend(format!("{l:<12}{r:<12}{dr}\n").into_bytes());
        v
    };
    let mut table = b"BEGIN TOOL.T MM\n".to_vec();
    table.extend(row("T", b"NAME", "L", "R", "DR"));
    table.extend(row("1", b"FR\xc4SER_D20", "+60", "+10", "+0"));
    table.extend(row("3", b"MILL_D6.04", "+55", "+3.02", "-0.02"));
    table.extend(b"[END]\n");
    std::fs::write(dir.join("TOOL.T"), &table).unwrap();
    let analyze = |extra: &[&str]| {
        std::process::Command::new(env!("FIVEAXIS_EXE"))
            .args(["program", "analyze"])
            .arg(dir.join("rc.h"))
            .args(["--machine", "generic-ac-table", "--json"])
            .args(extra)
            .output()
            .unwrap()
    };
    let table_path = dir.join("TOOL.T");
    let out = analyze(&["--tool-table", table_path.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(0), "{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    // R + DR = 3.02 - 0.02: the path, and so the cycle time, of a radius of 3 (LinuxCNC's table, D6);
    // without the delta (3.02) another path.
    let cycle_time = |out: &std::process::Output| serde_json::from_slice::<serde_json::Value>(&out.stdout).unwrap()["cycle_time_s"].as_f64().unwrap();
    let with_delta = cycle_time(&out);
    std::fs::write(dir.join("tool.tbl"), "T3 P3 D6\n").unwrap();
    let plain = analyze(&["--tool-table", dir.join("tool.tbl").to_str().unwrap()]);
    assert_eq!(plain.status.code(), Some(0));
    assert!((with_delta - cycle_time(&plain)).abs() < 1e-9, "{with_delta} s with R+DR, {} s with D6", cycle_time(&plain));
    let mut no_delta = b"BEGIN TOOL.T MM\n".to_vec();
    no_delta.extend(row("T", b"NAME", "L", "R", "DR"));
    no_delta.extend(row("3", b"MILL_D6.04", "+55", "+3.02", "+0"));
    no_delta.extend(b"[END]\n");
    std::fs::write(dir.join("NODELTA.T"), &no_delta).unwrap();
    let other = analyze(&["--tool-table", dir.join("NODELTA.T").to_str().unwrap()]);
    assert_eq!(other.status.code(), Some(0));
    assert!((with_delta - cycle_time(&other)).abs() > 1e-6, "R 3.02 without its delta runs as R 3: {with_delta} s");
    let out = analyze(&[]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stdout).contains("--tool-table"), "{}", String::from_utf8_lossy(&out.stdout));
    std::fs::write(dir.join("BAD.T"), "BEGIN TOOL.T MM\nT    NAME     R\n3    M        +3,02\n[END]\n").unwrap();
    let bad = dir.join("BAD.T");
    let out = analyze(&["--tool-table", bad.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("line 3: column R: '+3,02'"), "{err}");
}

/// [`OUTSIDE`] in the TNC's DIN/ISO words: `G42` in a `G01` block for `RR`, `G40` for `R0`, the
/// tool called by `T3 G17`, the arcs by their centre `I J`.
const OUTSIDE_ISO: &str = "%RC G71 *\nN10 T3 G17 S3000 *\nN20 G00 X-20 Y-20 Z+5 *\nN30 G01 Z-2 F200 *\n\
N40 G42 G01 X+0 Y+0 F500 *\nN50 X+60 *\nN60 I+60 J+10 G03 X+70 Y+10 *\nN70 G01 Y+40 *\nN80 X+50 *\n\
N90 I+40 J+40 G02 X+40 Y+30 *\nN100 G01 Y+20 *\nN110 X+0 *\nN120 Y+5 *\nN130 G40 X-20 Y-10 *\nN140 G00 Z+50 *\n\
N99999999 %RC G71 *\n";

/// The TNC's DIN/ISO programs compensate as its Klartext ones (the same manual pages): the same
/// contour, the same tool-centre path, against shapely's offset curve; and the same refusals.
#[test]
fn din_iso_g41_g42_compensate_as_rl_rr() {
    let r = 3.0;
    let t = table("T3 P3 D6\n");
    let p = read(OUTSIDE_ISO, Dialect::Heidenhain, "rc.i", &t);
    assert!(errors(&p).is_empty(), "{:#?}", p.diagnostics);
    let entry = p.blocks.iter().find(|b| b.number == Some(40)).expect("N40");
    assert!((entry.targets.x.unwrap() / MM).abs() < 1e-9 && (entry.targets.y.unwrap() / MM + r).abs() < 1e-9, "{:?}", entry.targets);
    let ours = path(&p, 50..=120, [0.0, -r]);
    let got = reference(r, "right", &outside_contour(), &ours);
    assert!(got["radius_error_mm"].as_f64().unwrap() < 1e-4 && got["hausdorff_mm"].as_f64().unwrap() < TOLERANCE * r, "{got}");
    // The Klartext reading's tool-centre path, point for point.
    let k = read(OUTSIDE, Dialect::Klartext, "rc.h", &t);
    let theirs = path(&k, 5..=12, [0.0, -r]);
    assert!(ours.len() >= 8 && ours.len() == theirs.len(), "{} {}", ours.len(), theirs.len());
    for (a, b) in ours.iter().zip(&theirs) {
        assert!((a.to[0] - b.to[0]).abs() < 1e-9 && (a.to[1] - b.to[1]).abs() < 1e-9, "{a:?} {b:?}");
    }
    // N120's element left perpendicular at its end, (0, 5) with the tool right of -Y: (-3, 5).
    let left = p.blocks.iter().filter(|b| b.number == Some(120)).last().unwrap();
    assert!((left.targets.x.unwrap() / MM + r).abs() < 1e-9 && (left.targets.y.unwrap() / MM - 5.0).abs() < 1e-9, "{:?}", left.targets);
    let exit = p.blocks.iter().filter(|b| b.number == Some(130)).last().unwrap();
    assert!((exit.targets.x.unwrap() / MM + 20.0).abs() < 1e-9 && (exit.targets.y.unwrap() / MM + 10.0).abs() < 1e-9);
    let cases = [
        (OUTSIDE_ISO.replace("N40 G42 G01 X+0 Y+0", "N40 G42 I+0 J+10 G02 X+0 Y+0"), "5:5:", "circle block"),
        (OUTSIDE_ISO.replace("N50 X+60", "N50 G41 X+60"), "6:5:", "G41 and G42"),
        (OUTSIDE_ISO.replace("N80 X+50", "N80 G54 X+50"), "9:5:", "datum shift"),
        (OUTSIDE_ISO.replace("N80 X+50", "N80 T4 G17"), "9:5:", "tool call"),
        (OUTSIDE_ISO.replace("N130 G40 X-20 Y-10", "N130 G40 I+0 J+0 G02 X-20 Y-10"), "14:6:", "G40 in a circle block"),
        (OUTSIDE_ISO.replace("N10 T3", "N10 T7"), "5:5:", "tool 7 is not in the tool table"),
        (OUTSIDE_ISO.replace("N130 G40 X-20", "N130 G40 G+41 X-20"), "14:10:", "two of G40, G41 and G42"),
        (OUTSIDE_ISO.replace("N40 G42 G01 X+0 Y+0 F500", "N40 G42 G01 X+0 Y+0 F500 M30"), "5:5:", "ends the program"),
    ];
    let cases: Vec<(&str, &str, &str)> = cases.iter().map(|(t, a, n)| (t.as_str(), *a, *n)).collect();
    refuses_each(Dialect::Heidenhain, &t, &cases);
    // A tool too large for the notch stops the program there; nothing after it runs.
    let p = read(OUTSIDE_ISO, Dialect::Heidenhain, "rc.i", &table("T3 P3 D24\n"));
    let errs = errors(&p);
    assert!(errs.iter().any(|(_, _, m)| m.contains("Tool radius too large")), "{errs:#?}");
    let at = errs.iter().find(|(_, _, m)| m.contains("Tool radius too large")).unwrap().0;
    assert!(p.blocks.iter().all(|b| b.line <= at), "blocks after line {at} ran");
}
