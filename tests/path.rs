//! Tool-path sampling: feed semantics per block, and distance-threshold regions.

use fiveaxis::job::{self, JobOptions};
use fiveaxis::machine::Machine;
use fiveaxis::path::{PathOptions, SegmentKind, Trajectory};
use fiveaxis::program::{read_cl, read_heidenhain, read_rs274};
use fiveaxis::singularity::{AnalysisOptions, RegionCause};
use fiveaxis::units::{DEG, MM};

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol
}

#[test]
fn tcp_blocks_run_at_the_tool_tip_feed_with_rotaries_linear() {
    let m = Machine::hermle_c600u();
    let p = read_heidenhain(include_str!("../recordings/programs/SING.I"));
    let t = Trajectory::from_program(&p, &m, &PathOptions::default());
    let seg = t.segments.iter().find(|s| s.number == Some(360)).unwrap();
    assert_eq!(seg.kind, SegmentKind::Tcp);
    // 1 mm at 2000 mm/min.
    assert!(close(seg.duration, 0.03, 1e-12), "{}", seg.duration);
    assert!(close(seg.length, 1.0 * MM, 1e-12));
    // Mid-block: tool tip half way on the line, A and C half way (linear per block).
    let mid = seg.joints_at(0.5, &m);
    assert!(close(mid[3], (1.196 + 1.0) / 2.0 * DEG, 1e-12));
    assert!(close(mid[4], (148.494 + 180.0) / 2.0 * DEG, 1e-12));
    let tip = m.forward(&mid).tip - seg.datum;
    assert!(close(tip.x, 24.5 * MM, 1e-12) && close(tip.y, 0.0, 1e-12) && close(tip.z, -8.0 * MM, 1e-12));
    // Samples are on the 1 ms grid and stay on the commanded line.
    let all: Vec<_> = t.samples(&m).collect();
    let inside: Vec<_> = all.iter().filter(|s| s.segment == t.segments.iter().position(|x| x.number == Some(360)).unwrap()).collect();
    assert!(inside.len() >= 29 && inside.len() <= 31);
    for w in inside.windows(2) {
        assert!(close(w[1].t - w[0].t, 1e-3, 1e-12));
        assert!(close(w[1].s - w[0].s, 2000.0 * MM / 60.0 * 1e-3, 1e-12));
    }
}

#[test]
fn rotary_only_moves_read_f_in_degrees_per_minute() {
    let m = Machine::hermle_c600u();
    let p = read_heidenhain(include_str!("../recordings/programs/SING.I"));
    let t = Trajectory::from_program(&p, &m, &PathOptions::default());
    let n80 = t.segments.iter().find(|s| s.number == Some(80)).unwrap();
    let angle = (14.825f64.powi(2) + 137.259f64.powi(2)).sqrt();
    assert!(close(n80.duration, angle / 2000.0 * 60.0, 1e-9), "{}", n80.duration);
}

#[test]
fn inverse_time_feed_sets_the_block_duration() {
    let m = Machine::hermle_c600u();
    let p = read_rs274("G21 G90 G94\nG1 X10 F600\nG93 G1 X20 A5 F30\n");
    let t = Trajectory::from_program(&p, &m, &PathOptions::default());
    assert_eq!(t.segments.len(), 2);
    assert!(close(t.segments[0].duration, 1.0, 1e-12), "10 mm at 600 mm/min");
    assert!(close(t.segments[1].duration, 2.0, 1e-12), "G93 F30: 1/30 min");
    assert_eq!(t.segments[1].kind, SegmentKind::Axes, "no G43.4: machine axes interpolate");
}

#[test]
fn cl_poses_go_through_the_inverse_kinematics() {
    let m = Machine::hermle_c600u();
    let (a, c) = (20f64.to_radians(), 30f64.to_radians());
    let text = format!(
        "0 0 -5 0 0 1\n10 0 -5 {} {} {}\n",
        c.sin() * a.sin(),
        c.cos() * a.sin(),
        a.cos()
    );
    let p = read_cl(&text, 1200.0);
    let t = Trajectory::from_program(&p, &m, &PathOptions::default());
    let last = t.segments.last().unwrap();
    assert!(close(last.q1[3], a, 1e-12) && close(last.q1[4], c, 1e-12), "{:?}", last.q1);
    assert!(close(last.duration, 10.0 / 1200.0 * 60.0, 1e-12));
}

#[test]
fn unknown_axes_and_unreachable_poses_are_reported_with_their_line() {
    let m = Machine::hermle_c600u();
    let p = read_rs274("G1 X1 B10 F100\nG1 X2 A120 F100\nG1 X3 F100\n");
    let t = Trajectory::from_program(&p, &m, &PathOptions::default());
    assert!(t.diagnostics.iter().any(|d| d.line == 1 && d.message.contains("axis B does not exist")));
    assert!(t.diagnostics.iter().any(|d| d.line == 2 && d.message.contains("outside its range")));
    assert_eq!(t.segments.len(), 1);
}

#[test]
fn distance_threshold_opens_regions_on_five_axis_moves() {
    let m = Machine::hermle_c600u();
    let opts = |deg: f64| JobOptions { analysis: AnalysisOptions { min_distance: Some(deg * DEG), rate_limit: None, ..Default::default() }, ..Default::default() };
    // NON_SING (cut from x 50 to 0): C stays under 25 rpm, but A < 12 deg between the crossings in
    // block x 31 -> 30 (A 12.243 -> 11.88: x = 31 - 0.243/0.363 = 30.331) and block x 20 -> 19
    // (A 11.88 -> 12.243: x = 20 - 0.12/0.363 = 19.669), A linear per block.
    let j = job::run("bundled:NON_SING.I", &m, &opts(12.0)).unwrap();
    assert_eq!(j.analysis.regions.len(), 1, "{:?}", j.report.regions);
    let r = &j.report.regions[0];
    assert_eq!(r.limit, RegionCause::Distance);
    assert_eq!(r.cause, fiveaxis::singularity::tracker::Cause::Singularity, "11 deg from the pole: within 15");
    let x_in = 31.0 - (12.243 - 12.0) / (12.243 - 11.88);
    let x_out = 20.0 - (12.0 - 11.88) / (12.243 - 11.88);
    // Boundaries lie between two 1 ms samples (0.033 mm apart).
    assert!(close(r.x_start_mm, x_in, 0.034), "start {} vs {x_in}", r.x_start_mm);
    assert!(close(r.x_end_mm, x_out, 0.034), "end {} vs {x_out}", r.x_end_mm);
    assert!(close(r.min_singularity_distance_deg, 11.0, 1e-3));
    // SING: the speed region and the distance region overlap into one.
    let j = job::run("bundled:SING.I", &m, &opts(2.0)).unwrap();
    assert_eq!(j.analysis.regions.len(), 1);
    assert_eq!(j.report.regions[0].limit, RegionCause::SpeedAndDistance);
}

/// Great-circle orientation across the pole. A circle through the singular direction itself is a
/// meridian: the table tilts through A = 0 to the other side with C standing (A linear in the
/// circle's angle), no jump. One passing 0.01 deg beside it is cut into pieces that each turn C at
/// most ORIENT_PIECE_RAD, and C turns by the 180 deg the geometry asks.
#[test]
fn great_circles_at_the_pole() {
    use fiveaxis::program::{read, Dialect, ReadOptions};
    let m = Machine::hermle_c600u();
    let prog = |y: f64| {
        let (s, c) = (10.0f64.to_radians().sin(), 10.0f64.to_radians().cos());
        format!("N10 TRAORI\nN20 G1 X0 Y0 Z0 A3={s:.12} B3={y:.12} C3={c:.12} F1000\nN30 X10 A3={:.12} B3={y:.12} C3={c:.12}\nN40 M30\n", -s)
    };
    let through = read(&prog(0.0), Dialect::Sinumerik, "pole.mpf", &ReadOptions::default());
    assert!(through.diagnostics.is_empty(), "{:#?}", through.diagnostics);
    let t = Trajectory::from_program(&through, &m, &PathOptions::default());
    assert!(t.diagnostics.is_empty(), "{:#?}", t.diagnostics);
    let (a, c) = (m.primary_axis(), m.secondary_axis());
    let c0 = t.segments.iter().find(|s| s.line == 3).unwrap().q0[c];
    let mut n = 0;
    for sm in t.samples(&m).filter(|sm| t.segments[sm.segment].line == 3) {
        let seg = &t.segments[sm.segment];
        let u = ((sm.tip.x - 0.0) / (10.0 * MM)).clamp(0.0, 1.0);
        assert!(close(sm.q[a].abs().to_degrees(), (10.0 - 20.0 * u).abs(), 1e-6), "A {} at u {u}", sm.q[a].to_degrees());
        assert!(close(sm.q[c], c0, 1e-9), "C moves: {} deg", (sm.q[c] - c0).to_degrees());
        assert!(seg.orient.is_some());
        n += 1;
    }
    assert!(n > 100);

    let beside = read(&prog(0.01f64.to_radians().sin()), Dialect::Sinumerik, "near.mpf", &ReadOptions::default());
    let t = Trajectory::from_program(&beside, &m, &PathOptions::default());
    assert!(t.diagnostics.is_empty(), "{:#?}", t.diagnostics);
    let pieces: Vec<_> = t.segments.iter().filter(|s| s.line == 3).collect();
    let turn = |s: &&fiveaxis::path::Segment| (s.q1[4] - s.q0[4]).abs().max((s.q1[3] - s.q0[3]).abs());
    assert!(pieces.iter().all(|s| turn(s) <= fiveaxis::path::ORIENT_PIECE_RAD + 1e-12));
    let c_turn = (pieces.last().unwrap().q1[c] - pieces[0].q0[c]).abs().to_degrees();
    assert!((c_turn - 180.0).abs() < 0.2, "C turns {c_turn} deg");
    assert!(pieces.len() < 5000, "{} pieces", pieces.len());
}

/// Rotary positions written under vector interpolation (840D `ORIVECT`, the reset state; the TNC's
/// `PATHCTRL VECTOR`) set the block's end tool axis; where the great circle from the block's start
/// reaches that axis on the other solution (B -1 C 0 for B 1 C 180, one tool axis: worked below by
/// rotation matrices) or on another turn of C, how the control turns the axes to the written positions
/// is in no manual at hand: an error at the block, not a C that silently never turns; the block is
/// made with the rotaries linear to the written positions, so the next starts there. With the axes
/// interpolated (`ORIAXES`) the same block reads, C turning the 180 deg it writes; the tool vector
/// written instead reads as the circle's.
#[test]
fn written_rotaries_off_the_great_circles_solution_are_refused() {
    use fiveaxis::program::{read, Dialect, ReadOptions};
    use nalgebra::{Rotation3, Vector3};
    let m = Machine::builtin("generic-bc-table").unwrap();
    // The tool axis in the part of a B/C table at (B, C): the part turned back by C about Z, then B about Y.
    let tool = |b: f64, c: f64| Rotation3::from_axis_angle(&Vector3::z_axis(), -c.to_radians()) * Rotation3::from_axis_angle(&Vector3::y_axis(), -b.to_radians()) * Vector3::z();
    assert!((tool(1.0, 180.0) - tool(-1.0, 0.0)).norm() < 1e-12, "one tool axis");
    let (a, c) = (m.primary_axis(), m.secondary_axis());
    let sin = |mode: &str, end: &str| format!("N10 G90 G71 G54\nN20 TRAORI\nN30 {mode}\nN40 G0 X0 Y0 Z50 B30 C0\nN50 G1 F1000 X10 {end}\nN60 M30\n");
    let errors = |src: &str, d: Dialect| {
        let p = read(src, d, "flip", &ReadOptions::default());
        assert!(p.diagnostics.is_empty(), "{:#?}", p.diagnostics);
        let t = Trajectory::from_program(&p, &m, &PathOptions::default());
        (t.diagnostics.iter().map(|d| (d.line, d.message.clone())).collect::<Vec<_>>(), t)
    };
    let (e, t) = errors(&sin("ORIVECT", "B1 C180\nN55 X20 B3 C180"), Dialect::Sinumerik);
    assert_eq!(e.len(), 1, "{e:#?}");
    assert_eq!(e[0].0, 5);
    assert!(e[0].1.contains("B -1.000 deg C 0.000 deg (the other solution") && e[0].1.contains("rotary axes linear"), "{}", e[0].1);
    // Made with the rotaries linear to the written B 1 C 180, so the next block (B 3 C 180) starts
    // there and reads.
    let end = t.segments.iter().filter(|s| s.line == 5).last().unwrap().q1;
    assert!(close(end[a].to_degrees(), 1.0, 1e-9) && close(end[c].to_degrees(), 180.0, 1e-9), "{end:?}");
    // C10 after C350: the circle reaches it at C 370.
    let (e, _) = errors(&sin("ORIVECT", "B30 C350\nN55 X20 B20 C10").replace("B30 C0", "B30 C350"), Dialect::Sinumerik);
    assert_eq!(e.len(), 1, "{e:#?}");
    assert!(e[0].0 == 6 && e[0].1.contains("C 370.000 deg (another turn"), "{e:?}");
    // The circle's own solution, the tool vector, and the axes interpolated: read, C where written.
    for (src, c_end) in [
        (sin("ORIVECT", "B-1 C0"), 0.0),
        (sin("ORIVECT", &{
            let v = tool(1.0, 180.0);
            format!("A3={:.12} B3={:.12} C3={:.12}", v.x, v.y, v.z)
        }), 0.0),
        (sin("ORIAXES", "B1 C180"), 180.0),
    ] {
        let (e, t) = errors(&src, Dialect::Sinumerik);
        assert!(e.is_empty(), "{src}: {e:#?}");
        let last = t.segments.iter().filter(|s| s.line == 5).last().unwrap();
        assert!(close(last.q1[c].to_degrees(), c_end, 1e-9) && close(last.q1[a].to_degrees().abs(), 1.0, 1e-9), "{src}: ends at {:?}", last.q1);
    }
    // The TNC under PATHCTRL VECTOR: the same.
    let tnc = "0 BEGIN PGM FLIP MM\n1 L X+0 Y+0 Z+50 B+30 C+0 R0 FMAX\n2 FUNCTION TCPM F TCP AXIS POS PATHCTRL VECTOR\n3 L X+10 B+1 C+180 F1000\n4 FUNCTION RESET TCPM\n5 END PGM FLIP MM\n";
    let (e, _) = errors(tnc, Dialect::Klartext);
    assert!(e.len() == 1 && e[0].0 == 4 && e[0].1.contains("the other solution"), "{e:#?}");
}

/// A TCPM move whose tool axis turns on a great circle beside the pole is timed on the whole block's
/// tip path (840D: F is the tip's speed under TRAORI), however short the pieces near the pole are,
/// where C turns fastest. Reference, independent of the planner: on a great circle whose closest
/// approach to the pole is `d`, turned at the steady rate `w`, the azimuth (C) turns at most at
/// `w / sin d` (Clairaut's relation at the closest point). A 2 mm block at F1000 turning the tool axis
/// from 1 deg tilted at azimuth 0 to 1 deg at azimuth 170 asks 1819 rpm of C; timing the pieces under
/// 1 um as rotary moves (F in deg/min) had given 352 rpm, and 2.9 rpm for a 20 um block. The
/// closest approach is the great circle's `d` down to a 0.2 um block, whose pieces beside the pole
/// are shorter than a nanometre (taken as no path move, they had left it at 0.197 deg).
#[test]
fn a_great_circle_beside_the_pole_is_timed_on_the_blocks_tip_path() {
    use fiveaxis::program::{read, Dialect, ReadOptions};
    use nalgebra::Vector3;
    let m = Machine::hermle_c600u();
    let axis = |tilt: f64, az: f64| {
        let (t, a) = (tilt.to_radians(), az.to_radians());
        Vector3::new(t.sin() * a.cos(), t.sin() * a.sin(), t.cos())
    };
    let (v0, v1) = (axis(1.0, 0.0), axis(1.0, 170.0));
    for dx_mm in [2.0, 0.2, 0.02, 0.002, 0.0002] {
        let w = |v: &Vector3<f64>| format!("A3={:.12} B3={:.12} C3={:.12}", v.x, v.y, v.z);
        let src = format!(
            "N10 G90 G71 G94\nN20 TRAORI\nN30 ORIVECT\nN40 G0 X10 Y0 Z0 {}\nN50 G1 X{} {} F1000\nN60 M30\n",
            w(&v0),
            10.0 + dx_mm,
            w(&v1)
        );
        let p = read(&src, Dialect::Sinumerik, "beside.mpf", &ReadOptions::default());
        assert!(p.diagnostics.is_empty(), "{:#?}", p.diagnostics);
        let t = Trajectory::from_program(&p, &m, &PathOptions::default());
        assert!(t.diagnostics.is_empty(), "{:#?}", t.diagnostics);
        // The block's time is its tip path over F, whatever its pieces.
        let block: Vec<_> = t.segments.iter().filter(|s| s.line == 5).collect();
        assert!(block.len() > 100, "{} pieces", block.len());
        let time: f64 = block.iter().map(|s| s.duration).sum();
        let expect_s = dx_mm / 1000.0 * 60.0;
        assert!(close(time, expect_s, 1e-9 + expect_s * 1e-9), "{dx_mm} mm block takes {time} s, not {expect_s} s");
        // The peak C speed against the closed form.
        let omega = v0.angle(&v1) / expect_s;
        let d = v0.cross(&v1).normalize().z.abs().asin();
        let expect_rpm = omega / d.sin() * 60.0 / std::f64::consts::TAU;
        let a = fiveaxis::singularity::analyze(&t, &m, &AnalysisOptions { rate_limit: None, ..Default::default() });
        let peak_rpm = a.summary.peak_rate.abs() * 60.0 / std::f64::consts::TAU;
        assert!((peak_rpm / expect_rpm - 1.0).abs() < 2e-3, "{dx_mm} mm: peak C {peak_rpm} rpm, closed form {expect_rpm} rpm");
        assert!(close(a.summary.min_distance.unwrap(), d, 1e-6), "closest {} deg, closed form {} deg", a.summary.min_distance.unwrap().to_degrees(), d.to_degrees());
    }
}

/// A stated 1 um move beside a C turn is a path move, as the control times it (LinuxCNC counts an
/// axis as moving from 1e-7 mm, emccanon.cc): `G1 X1.101 C90 F100` from X1.1 takes 1 um / F =
/// 0.6 ms and asks C for 90 deg in it, 25,000 rpm (by hand). A 1 um threshold had timed it as a
/// rotary move (54 s at 100 deg/min) or not, as the float rounding of X1.1 or X2.2 fell.
#[test]
fn a_one_micrometre_move_beside_a_c_turn_is_a_path_move() {
    let m = Machine::hermle_c600u();
    for x in [1.1, 2.2, 10.0] {
        let p = read_rs274(&format!("G21 G90 G94\nG0 X{x} Y0 Z0 A10 C0\nG1 X{} C90 F100\nM2\n", (x * 1000.0 + 1.0) / 1000.0));
        assert!(p.diagnostics.is_empty(), "{:#?}", p.diagnostics);
        let t = Trajectory::from_program(&p, &m, &PathOptions::default());
        assert!(t.diagnostics.is_empty(), "{:#?}", t.diagnostics);
        let time: f64 = t.segments.iter().filter(|s| s.line == 3).map(|s| s.duration).sum();
        assert!(close(time, 0.6e-3, 1e-9), "X{x} + 1 um: {time} s");
        let a = fiveaxis::singularity::analyze(&t, &m, &AnalysisOptions { rate_limit: None, ..Default::default() });
        let peak_rpm = a.summary.peak_rate.abs() * 60.0 / std::f64::consts::TAU;
        assert!((peak_rpm - 25_000.0).abs() < 1.0, "X{x} + 1 um: peak C {peak_rpm} rpm");
    }
}

/// The first tool-vector block after the program set the rotaries by their words takes the solution
/// nearest where they stand (as every later one does), not the first pose's convention (seed 001
/// Table 1's + sign): hyperMILL-style `L A-5 C+0 FMAX` then `LN ... TY-0.1736482 TZ+0.9848078` is
/// A -5 -> -10 with C standing (by hand: the tool axis 10 deg from Z in -Y is A-10 C0 or A+10 C180 on
/// the C600U), 5 deg from the pole at the closest. Taking A+10 C180 had swung C 180 deg through the
/// pole (50 rpm, a region; found by a helper). The same for the 840D's first vector under ORIAXES.
/// Rotaries set on the pole (SING.I's `A0 C0`) say nothing of the side: the convention stays there
/// (the twins in tests/dialects.rs).
#[test]
fn the_first_tool_vector_after_rotary_words_is_solved_nearest_them() {
    use fiveaxis::program::{read, Dialect, ReadOptions};
    let m = Machine::hermle_c600u();
    let klartext = "0 BEGIN PGM T MM\n1 TOOL CALL 1 Z S1000\n2 L M128\n3 L X+0 Y+0 Z+10 A-5 C+0 R0 FMAX\n\
                    4 LN X+10 Y+0 Z+10 NX+0 NY-0.1736482 NZ+0.9848078 TX+0 TY-0.1736482 TZ+0.9848078 F1000\n5 END PGM T MM\n";
    let sinumerik = "G71 G17 G90 G94\nTRAORI\nORIAXES\nG0 X0 Y0 Z10 A-5 C0\nG1 X10 A3=0 B3=-0.1736482 C3=0.9848078 F1000\nM30\n";
    for (src, dialect, line) in [(klartext, Dialect::Klartext, 5), (sinumerik, Dialect::Sinumerik, 5)] {
        let p = read(src, dialect, "first.nc", &ReadOptions::default());
        assert!(p.diagnostics.is_empty(), "{:#?}", p.diagnostics);
        let t = Trajectory::from_program(&p, &m, &PathOptions::default());
        assert!(t.diagnostics.is_empty(), "{:#?}", t.diagnostics);
        let (a, c) = (m.primary_axis(), m.secondary_axis());
        let moves: Vec<_> = t.segments.iter().filter(|s| s.line == line).collect();
        let (first, last) = (moves[0], moves[moves.len() - 1]);
        assert!(close(first.q0[a].to_degrees(), -5.0, 1e-9) && close(last.q1[a].to_degrees(), -10.0, 1e-6), "{dialect:?}: A {} -> {}", first.q0[a].to_degrees(), last.q1[a].to_degrees());
        assert!(close(first.q0[c], last.q1[c], 1e-9), "{dialect:?}: C turns {} deg", (last.q1[c] - first.q0[c]).to_degrees());
        let an = fiveaxis::singularity::analyze(&t, &m, &AnalysisOptions::default());
        assert!(an.summary.peak_rate.abs() < 1e-9, "{dialect:?}: peak C {} rad/s", an.summary.peak_rate);
        assert!(close(an.summary.min_distance.unwrap().to_degrees(), 5.0, 1e-6), "{dialect:?}: closest {:?}", an.summary.min_distance);
    }
}

/// A block whose tilt crosses the pole between two samples (axis-linear: A 5 -> -4.37 deg on the
/// C600U, by hand through A = 0) reports the true closest approach, 0, not the 1 ms grid's nearest
/// sample (0.37 deg had been reported, and `--min-distance-deg 0.3` opened no region; found by a
/// helper): the minimum between two samples is found where the distance stops falling. With C
/// turning along (30 -> 60 deg), the C-speed region runs through the pole as one region, though eq. 5
/// is undefined on it.
#[test]
fn a_tilt_through_the_pole_between_samples_is_its_closest_approach() {
    use fiveaxis::program::{read, Dialect, ReadOptions};
    let m = Machine::hermle_c600u();
    for c1 in ["30.", "60."] {
        let src = format!("%\nO1000\nG21 G17 G90 G94\nG43.4 H1\nG0 X0. Y0. Z10. A5. C30.\nG1 X1. A-4.37 C{c1} F5730.\nG49\nM30\n%\n");
        let p = read(&src, Dialect::Fanuc, "pole.nc", &ReadOptions::default());
        assert!(p.diagnostics.iter().all(|d| d.severity != fiveaxis::program::Severity::Error), "{:#?}", p.diagnostics);
        let t = Trajectory::from_program(&p, &m, &PathOptions::default());
        let a = fiveaxis::singularity::analyze(&t, &m, &AnalysisOptions { min_distance: Some(0.3 * DEG), rate_limit: Some(1e-3), ..Default::default() });
        let closest = a.summary.min_distance.unwrap();
        assert!(closest < 1e-9, "C {c1}: closest {} deg, by hand 0", closest.to_degrees());
        assert_eq!(a.regions.len(), 1, "C {c1}: {:#?}", a.regions);
        assert!(a.regions[0].min_distance < 1e-9, "C {c1}: {:?}", a.regions[0]);
    }
}

/// A C axis that runs out of travel: the tool axis 10 deg off the pole winds twice about it (5 deg a
/// block), so C, following the azimuth, reaches the end of the generic fork head's -360..360 deg.
/// The block where it would leave its range (found here by unwrapping the + solution's C block by
/// block) takes the other solution: the planner says so there, naming C and its range. With the
/// rotaries linear in the block (ORIAXES) A swings through 0, so the tool passes the pole there
/// although the path keeps 10 deg from it (the analysis finds 0 deg, in that block only); on the
/// great circle (ORIVECT) the axes cannot follow without a jump: the block is refused for C's range,
/// not for a pole the circle never comes near.
#[test]
fn a_rotary_range_that_forces_the_other_solution_is_named() {
    use fiveaxis::program::{read, Dialect, ReadOptions, Severity};
    let m = Machine::builtin("generic-ac-head").unwrap();
    let (a, c) = (m.primary_axis(), m.secondary_axis());
    let tilt = 10.0f64.to_radians();
    let pose = |k: usize| {
        let phi = (5.0 * k as f64).to_radians();
        let axis = nalgebra::Vector3::new(tilt.sin() * phi.cos(), tilt.sin() * phi.sin(), tilt.cos());
        (nalgebra::Vector3::new(20.0 * phi.cos(), 20.0 * phi.sin(), 0.0), axis)
    };
    let blocks = 145;
    // The block (index k) where the + solution's C, unwrapped, first leaves its range.
    let limits = &m.axes[c].limits;
    let mut cs = Vec::new();
    for k in 0..blocks {
        let (tip, axis) = pose(k);
        let all = m.inverse_all(&fiveaxis::kinematics::Pose { tip: tip * MM, axis }).unwrap();
        let plus = if all[0][a] >= 0.0 { all[0] } else { all[1] };
        let raw = plus[c];
        let v = cs.last().map_or(raw, |p: &f64| raw + (std::f64::consts::TAU * ((p - raw) / std::f64::consts::TAU).round()));
        cs.push(v);
    }
    let k_out = cs.iter().position(|v| !limits.contains(*v)).expect("C leaves its range within two turns");
    let header = 2;
    let program = |orientation: &str| {
        let mut text = format!("N10 TRAORI\nN20 {orientation}\n");
        for k in 0..blocks {
            let (tip, axis) = pose(k);
            text += &format!("N{} G1 X{:.6} Y{:.6} Z{:.6} A3={:.12} B3={:.12} C3={:.12} F2000\n", 30 + 10 * k, tip.x, tip.y, tip.z, axis.x, axis.y, axis.z);
        }
        text + "M30\n"
    };
    let line = header + k_out + 1;

    let p = read(&program("ORIAXES"), Dialect::Sinumerik, "wind.mpf", &ReadOptions::default().on(&m));
    assert!(p.diagnostics.iter().all(|d| d.severity != Severity::Error), "{:#?}", p.diagnostics);
    let t = Trajectory::from_program(&p, &m, &PathOptions::default());
    assert!(t.diagnostics.iter().all(|d| d.severity != Severity::Error), "{:#?}", t.diagnostics);
    let first = t.diagnostics.iter().find(|d| d.message.contains("on the solution nearest the last block's")).expect("the forced solution is said");
    assert_eq!(first.line, line, "{first:?}");
    assert!(first.severity == Severity::Warning && first.message.starts_with(&format!("{} would reach", m.axes[c].name)) && first.message.contains("outside its range -360.000..360.000 deg"), "{first:?}");
    // Between the first block (from the start, A 0) and the forced one the tool keeps its 10 deg;
    // in the forced one A swings from one side of the pole to the other, through 0.
    let forced: Vec<f64> = t.samples(&m).filter(|s| t.segments[s.segment].line == line).map(|s| s.q[a]).collect();
    let (first_a, last_a) = (forced[0], forced[forced.len() - 1]);
    assert!(first_a * last_a < 0.0 && close(first_a.abs(), tilt, 0.6f64.to_radians()) && close(last_a.abs(), tilt, 0.6f64.to_radians()), "A {} -> {} deg", first_a.to_degrees(), last_a.to_degrees());
    assert!(forced.iter().map(|q| q.abs()).fold(f64::INFINITY, f64::min) < 0.5f64.to_radians());
    let before = t.samples(&m).filter(|s| (header + 2..line).contains(&t.segments[s.segment].line)).map(|s| s.q[a].abs()).fold(f64::INFINITY, f64::min);
    assert!(close(before, tilt, 1e-6), "A before the forced block: {} deg", before.to_degrees());

    let p = read(&program("ORIVECT"), Dialect::Sinumerik, "wind.mpf", &ReadOptions::default().on(&m));
    let t = Trajectory::from_program(&p, &m, &PathOptions::default());
    let refused = t.diagnostics.iter().find(|d| d.severity == Severity::Error).expect("the great circle cannot be followed");
    assert_eq!(refused.line, line, "{refused:?}");
    assert!(refused.message.contains("would leave its range -360.000..360.000 deg") && !refused.message.contains("singular direction"), "{refused:?}");
}

/// `--feed` gives the tool tip its feed on every path move, inverse-time (G93) ones too: 10 mm at
/// 600 mm/min take 1 s whatever the block's F2 (30 s); a G93 move of the rotary axes alone has no
/// tip path and keeps its programmed 60 / F s.
#[test]
fn the_feed_override_times_inverse_time_path_moves_too() {
    let m = Machine::builtin("generic-ac-table").unwrap();
    let p = read_rs274("G21 G90 G94\nG0 X0 Y0 Z10 A0 C0\nG93 G1 X10 F2\nA10 F6\nG94\nM2\n");
    assert!(p.diagnostics.is_empty(), "{:#?}", p.diagnostics);
    let time = |o: Option<f64>, line: usize| {
        let t = Trajectory::from_program(&p, &m, &PathOptions { feed_override_mm_per_min: o, ..PathOptions::default() });
        assert!(t.diagnostics.is_empty(), "{:#?}", t.diagnostics);
        t.segments.iter().filter(|s| s.line == line).map(|s| s.duration).sum::<f64>()
    };
    assert!(close(time(None, 3), 30.0, 1e-9) && close(time(None, 4), 10.0, 1e-9));
    assert!(close(time(Some(600.0), 3), 1.0, 1e-9), "{}", time(Some(600.0), 3));
    assert!(close(time(Some(600.0), 4), 10.0, 1e-9));
}
