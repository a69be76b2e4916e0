//! Arcs (G02/G03) through reader, path and run: sampled tool tips on the circle computed here from
//! the program's words, durations from the arc length at the feed, LinuxCNC's five-axis demos read
//! and run, and the fail-closed reader on words it does not model.

use crate::common;
use fiveaxis::machine::Machine;
use fiveaxis::path::{PathOptions, Trajectory};
use fiveaxis::program::{read, Dialect, MCodeAction, MCodeRule, Program, ReadOptions, Severity};
use std::f64::consts::PI;
use std::path::PathBuf;
use std::process::Command;

fn root() -> PathBuf {
    PathBuf::from(env!("FIVEAXIS_ROOT"))
}

fn linuxcnc_m_codes() -> ReadOptions {
    ReadOptions {
        m_codes: vec![MCodeRule { code: 428, action: MCodeAction::TcpOn }, MCodeRule { code: 429, action: MCodeAction::TcpOff }],
        ..Default::default()
    }
}

fn errors(p: &Program) -> Vec<String> {
    p.diagnostics.iter().filter(|d| d.severity == Severity::Error).map(|d| d.to_string()).collect()
}

/// One arc block as the test states it: plane axes (first, second, normal), centre in the plane
/// (mm), radius (mm), signed sweep (rad, + counter-clockwise), normal coordinate at start and end.
struct Expect {
    line: usize,
    axes: (usize, usize, usize),
    centre: (f64, f64),
    radius: f64,
    sweep: f64,
    h: (f64, f64),
    feed_mm_per_min: f64,
}

/// Every sample of each arc block lies on its circle (to 1e-6 mm), turns the stated way, moves
/// evenly along the normal (helix), and the block takes its arc length at the feed.
fn check_arcs(program: &Program, machine: &Machine, expect: &[Expect]) {
    assert!(errors(program).is_empty(), "{:#?}", errors(program));
    let traj = Trajectory::from_program(program, machine, &PathOptions::default());
    assert!(traj.diagnostics.is_empty(), "{:#?}", traj.diagnostics);
    for e in expect {
        let (a0, a1, an) = e.axes;
        let samples: Vec<_> = traj.samples(machine).filter(|s| traj.segments[s.segment].line == e.line).collect();
        assert!(samples.len() > 100, "line {}: {} samples", e.line, samples.len());
        let mut worst = 0.0f64;
        let mut angle = None::<f64>;
        let mut swept = 0.0;
        for s in &samples {
            let p = s.tip * 1e3;
            let (u, v) = (p[a0] - e.centre.0, p[a1] - e.centre.1);
            worst = worst.max((u.hypot(v) - e.radius).abs());
            let th = v.atan2(u);
            if let Some(prev) = angle {
                let d = (th - prev + PI).rem_euclid(2.0 * PI) - PI;
                assert!(d * e.sweep.signum() >= -1e-12, "line {}: turns the wrong way ({d} rad)", e.line);
                swept += d;
            }
            angle = Some(th);
            // The normal coordinate follows the angle (helix): h0 + (h1 - h0) * swept / sweep.
            let want_h = e.h.0 + (e.h.1 - e.h.0) * swept / e.sweep;
            let tol = (e.h.1 - e.h.0).abs() * 2e-3 + 1e-6;
            assert!((p[an] - want_h).abs() <= tol, "line {}: normal coordinate {} mm, want {want_h}", e.line, p[an]);
        }
        assert!(worst <= 1e-6, "line {}: a sample is {worst:e} mm off the circle", e.line);
        // The samples cover the sweep but for up to one sample period at each end of the block.
        let step = e.feed_mm_per_min / 60.0 * 1e-3 / e.radius;
        assert!((swept - e.sweep).abs() <= 2.0 * step, "line {}: swept {swept} rad, want {}", e.line, e.sweep);
        let duration: f64 = traj.segments.iter().filter(|s| s.line == e.line).map(|s| s.duration).sum();
        let length = (e.radius * e.sweep).hypot(e.h.1 - e.h.0);
        let want = length / (e.feed_mm_per_min / 60.0);
        assert!((duration - want).abs() <= 1e-9 * want.max(1.0), "line {}: {duration} s, want {want} s", e.line);
    }
}

#[test]
fn arcs_in_every_plane_lie_on_their_circles() {
    let text = "\
G21 G90 G94 G17 G43.4 H1
G0 X10 Y0 Z0 A0 C0
G2 X0 Y-10 I-10 J0 F1000
G3 X-10 Y0 R10
G3 X-10 Y0 Z-5 I10 J0 P2
G18 G2 X0 Z-15 I10 K0
G19 G3 Y10 Z-5 J0 K10
G17 G90.1 G2 X10 Y0 Z-5 I0 J0 A5 F500
G91.1 G3 X10 Y0 R-10 Z-5
";
    // Line 9: R-10 with the end on the start cannot be an arc: the reader refuses it.
    let bad = read(text, Dialect::Rs274, "arcs.ngc", &ReadOptions::default());
    let e = errors(&bad);
    assert!(e.len() == 1 && e[0].starts_with("9:") && e[0].contains("R-10"), "{e:#?}");
    let text: String = text.lines().take(8).map(|l| format!("{l}\n")).collect();
    let p = read(&text, Dialect::Rs274, "arcs.ngc", &ReadOptions::default());
    let machine = Machine::hermle_c600u();
    let xy = (0, 1, 2);
    check_arcs(
        &p,
        &machine,
        &[
            // (10,0) -> (0,-10) clockwise about the origin: a quarter turn.
            Expect { line: 3, axes: xy, centre: (0.0, 0.0), radius: 10.0, sweep: -PI / 2.0, h: (0.0, 0.0), feed_mm_per_min: 1000.0 },
            // (0,-10) -> (-10,0), R10 counter-clockwise (short): centre (-10,-10).
            Expect { line: 4, axes: xy, centre: (-10.0, -10.0), radius: 10.0, sweep: PI / 2.0, h: (0.0, 0.0), feed_mm_per_min: 1000.0 },
            // Two full counter-clockwise turns about the origin, Z 0 -> -5 (helix).
            Expect { line: 5, axes: xy, centre: (0.0, 0.0), radius: 10.0, sweep: 4.0 * PI, h: (0.0, -5.0), feed_mm_per_min: 1000.0 },
            // G18 (Z X plane, normal Y): (z,x) = (-5,-10) -> (-15,0) about (-5,0), clockwise seen from +Y.
            Expect { line: 6, axes: (2, 0, 1), centre: (-5.0, 0.0), radius: 10.0, sweep: -PI / 2.0, h: (0.0, 0.0), feed_mm_per_min: 1000.0 },
            // G19 (Y Z plane, normal X): (y,z) = (0,-15) -> (10,-5) about (0,-5), counter-clockwise seen from +X.
            Expect { line: 7, axes: (1, 2, 0), centre: (0.0, -5.0), radius: 10.0, sweep: PI / 2.0, h: (0.0, 0.0), feed_mm_per_min: 1000.0 },
            // G90.1 absolute centre (0,0): (0,10) -> (10,0) clockwise, A turning 0 -> 5 deg on the way.
            Expect { line: 8, axes: xy, centre: (0.0, 0.0), radius: 10.0, sweep: -PI / 2.0, h: (-5.0, -5.0), feed_mm_per_min: 500.0 },
        ],
    );
}

/// Heidenhain DIN/ISO arcs (iTNC 530 ISO programming): the centre I J is absolute and modal, set in
/// its own block or with the arc, and the tool does not move to it; G02/G03 with R (R+: up to half a
/// turn); G05 runs in the direction of the last G02/G03; G91 makes I J relative to the last position.
#[test]
fn heidenhain_arcs_lie_on_their_circles() {
    let text = "%ARCS G71 *\nN10 G01 X+0 Y+0 Z+0 F1000 *\nN20 I+10 J+0 *\nN30 G02 X+20 Y+0 *\nN40 G03 X+0 Y+0 R+10 *\n\
                N50 G05 X+20 Y+0 *\nN60 G91 I-5 J+0 *\nN70 G90 G02 X+10 Y+0 *\nN80 G01 X+30 *\nN90 G06 X+40 *\nN100 R+5 *\nN999999 %ARCS G71 *\n";
    let p = read(text, Dialect::Heidenhain, "arcs.I", &ReadOptions::default());
    let e = errors(&p);
    assert!(e.len() == 2 && e[0].starts_with("10:") && e[0].contains("G06") && e[1].starts_with("11:") && e[1].contains("radius without"), "{e:#?}");
    let good: String = text.lines().filter(|l| !l.contains("G06") && !l.starts_with("N100")).map(|l| format!("{l}\n")).collect();
    let p = read(&good, Dialect::Heidenhain, "arcs.I", &ReadOptions::default());
    let xy = (0, 1, 2);
    check_arcs(
        &p,
        &Machine::hermle_c600u(),
        &[
            // (0,0) -> (20,0) clockwise about I+10 J+0: over the top (y > 0), half a turn.
            Expect { line: 4, axes: xy, centre: (10.0, 0.0), radius: 10.0, sweep: -PI, h: (0.0, 0.0), feed_mm_per_min: 1000.0 },
            // Back counter-clockwise with R+10: a half turn about (10, 0), which R leaves on either side
            // (the R+ short arc for exactly half a turn); checked by the sweep.
            Expect { line: 5, axes: xy, centre: (10.0, 0.0), radius: 10.0, sweep: PI, h: (0.0, 0.0), feed_mm_per_min: 1000.0 },
            // G05: counter-clockwise again (the last direction), about the modal centre.
            Expect { line: 6, axes: xy, centre: (10.0, 0.0), radius: 10.0, sweep: PI, h: (0.0, 0.0), feed_mm_per_min: 1000.0 },
            // G91 I-5: centre 5 mm before the last position (20, 0), i.e. (15, 0); (20,0) -> (10,0) clockwise.
            Expect { line: 8, axes: xy, centre: (15.0, 0.0), radius: 5.0, sweep: -PI, h: (0.0, 0.0), feed_mm_per_min: 1000.0 },
        ],
    );
}

/// The G02 blocks of a LinuxCNC demo with their circles, found here from the text alone (modal X Y
/// tracked line by line, I J incremental from the start as LinuxCNC's default G91.1 reads them).
fn demo_arcs(text: &str) -> Vec<Expect> {
    let word = |l: &str, c: char| -> Option<f64> {
        let l = l.split(['(', ';']).next().unwrap_or("");
        let i = l.find(c)?;
        let rest = &l[i + 1..];
        let end = rest.find(|ch: char| !(ch.is_ascii_digit() || ch == '.' || ch == '-' || ch == '+')).unwrap_or(rest.len());
        rest[..end].parse().ok()
    };
    let (mut x, mut y, mut z, mut f) = (0.0, 0.0, 0.0, 0.0);
    let mut out = Vec::new();
    for (k, l) in text.lines().enumerate() {
        let (x0, y0, z0) = (x, y, z);
        x = word(l, 'X').unwrap_or(x);
        y = word(l, 'Y').unwrap_or(y);
        z = word(l, 'Z').unwrap_or(z);
        f = word(l, 'F').unwrap_or(f);
        if l.starts_with("G02") || l.starts_with("G03") {
            let (i, j) = (word(l, 'I').unwrap(), word(l, 'J').unwrap());
            let (cx, cy) = (x0 + i, y0 + j);
            let (t0, t1) = ((y0 - cy).atan2(x0 - cx), (y - cy).atan2(x - cx));
            let ccw = l.starts_with("G03");
            let d = (t1 - t0).rem_euclid(2.0 * PI);
            let sweep = if ccw { d } else { d - 2.0 * PI };
            let r0 = (x0 - cx).hypot(y0 - cy);
            assert!(((x - cx).hypot(y - cy) - r0).abs() < 1.3e-3, "line {}: radii differ beyond LinuxCNC's tolerance", k + 1);
            out.push(Expect { line: k + 1, axes: (0, 1, 2), centre: (cx, cy), radius: r0, sweep, h: (z0, z), feed_mm_per_min: f });
        }
    }
    out
}

#[test]
fn linuxcnc_boat_arcs_lie_on_their_circles() {
    let text = std::fs::read_to_string(root().join("recordings/programs/linuxcnc/boat-xyzac.ngc")).unwrap();
    // Without saying what LinuxCNC's remapped M428/M429 do, the program is refused where they stand.
    let refused = read(&text, Dialect::Rs274, "boat-xyzac.ngc", &ReadOptions::default());
    let e = errors(&refused);
    assert!(e.len() == 2 && e[0].starts_with("2:1:") && e[0].contains("M428") && e[1].contains("M429"), "{e:#?}");
    let p = read(&text, Dialect::Rs274, "boat-xyzac.ngc", &linuxcnc_m_codes());
    let arcs = demo_arcs(&text);
    assert_eq!(arcs.len(), 4, "boat-xyzac.ngc has four G02 blocks");
    // The start and end radii the program writes differ by up to 1 um: LinuxCNC runs those as spirals,
    // so the check is against the start radius with that slack.
    let machine = Machine::hermle_c600u();
    let traj = Trajectory::from_program(&p, &machine, &PathOptions::default());
    for e in &arcs {
        let seg = traj.segments.iter().find(|s| s.line == e.line).expect("the arc is planned");
        let arc = seg.arc.as_ref().expect("an arc segment");
        assert!((arc.r0 * 1e3 - e.radius).abs() < 1e-9, "line {}: start radius {} mm, want {}", e.line, arc.r0 * 1e3, e.radius);
    }
    check_arcs_loose(&traj, &machine, &arcs, 1.3e-3);
}

/// As [`check_arcs`] but with a radius slack (mm) for programs whose arcs are spirals within LinuxCNC's
/// tolerance; the exact check holds for a circle.
fn check_arcs_loose(traj: &Trajectory, machine: &Machine, expect: &[Expect], slack_mm: f64) {
    for e in expect {
        let (a0, a1, _) = e.axes;
        let mut n = 0;
        for s in traj.samples(machine).filter(|s| traj.segments[s.segment].line == e.line) {
            let p = s.tip * 1e3;
            let r = (p[a0] - e.centre.0).hypot(p[a1] - e.centre.1);
            assert!((r - e.radius).abs() <= slack_mm, "line {}: radius {r} mm, want {} mm", e.line, e.radius);
            n += 1;
        }
        assert!(n > 10, "line {}: {n} samples", e.line);
    }
}

fn bin() -> PathBuf {
    PathBuf::from(env!("FIVEAXIS_EXE"))
}

fn impeller() -> PathBuf {
    let out = common::scratch_path("arcs", "impeller-7bl-xyzac.ngc");
    let gz = root().join("recordings/programs/linuxcnc/impeller-7bl-xyzac.ngc.gz");
    let unzipped = Command::new("gzip").arg("-dc").arg(&gz).output().expect("gzip runs");
    assert!(unzipped.status.success());
    std::fs::write(&out, unzipped.stdout).unwrap();
    out
}

#[test]
fn linuxcnc_five_axis_demos_read_and_run() {
    let demos = root().join("recordings/programs/linuxcnc");
    let imp = impeller();
    let cases = [
        (demos.join("boat-xyzac.ngc"), "hermle-c600u".to_string()),
        (imp.clone(), "hermle-c600u".to_string()),
        (demos.join("boat-xyzbc.ngc"), root().join("machines/linuxcnc-xyzbc-trt.toml").display().to_string()),
    ];
    for (program, machine) in &cases {
        let out = Command::new(bin())
            .args(["run", &program.display().to_string(), "--machine", machine, "--json", "--m-code", "428=tcp-on", "--m-code", "429=tcp-off"])
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(0), "{}: {stderr}", program.display());
        let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        assert_eq!(v["errors"], 0, "{}", program.display());
        let cycle = v["cycle_time_s"].as_f64().unwrap();
        let simulated = v["simulated"]["cycle_time_s"].as_f64().unwrap();
        assert!(cycle > 60.0 && simulated >= cycle * 0.99, "{}: programmed {cycle} s, simulated {simulated} s", program.display());
    }
    let _ = std::fs::remove_file(imp);
}

#[test]
fn words_that_change_the_motion_are_refused() {
    // Tool vectors (I J K) without G43.5 (a Fanuc program whose mode line was lost): refused, not ignored.
    let fanuc = "G21 G90 G94\nG1 X22 Y0 Z-8 I0.1736 J0 K0.9848 F2000\nG43.5 H1\nG1 X25 I0.0175 J0 K0.9998 A1\nM30\n";
    let file = common::scratch_path("arcs", "g435.ngc");
    std::fs::write(&file, fanuc).unwrap();
    let out = Command::new(bin()).args(["program", "analyze", &file.display().to_string()]).output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(2), "{stdout}");
    for at in ["g435.ngc:2:15: error: word I0.1736", "g435.ngc:4:1: error: G43.5 block with both a tool vector"] {
        assert!(stdout.contains(at), "no {at:?} in\n{stdout}");
    }
    let _ = std::fs::remove_file(&file);
    // Each of these changes the motion and is not modelled: an error at its column, the block unused.
    for (text, col, needle) in [
        // Compensation by a tool table the reader was not given.
        ("G1 X1 F100\nG41 D1 X2\n", 1, "give it with --tool-table"),
        ("G1 X1 F100\nG33 X2 K1\n", 1, "threading or probing"),
        ("G1 X1 F100\nG68.2 X0 Y0 Z0 I0 J45 K0\n", 1, "tilted working plane"),
        ("G1 X1 F100\nG87 X2 Z-1 R1\n", 1, "G87: LinuxCNC accepts it but its behaviour is undefined"),
        ("G1 X1 F100\nG1 X2 M100\n", 7, "M100 is not an RS274NGC M code"),
        ("G1 X1 F100\nG1 X2 U3\n", 7, "unsupported word U3"),
        ("G1 X1 F100\nG7\n", 1, "G7"),
        ("G1 X1 F100\nG2 X2 Y1 I1 J0 K1\n", 16, "K1: not an arc-centre word in the XY (G17) plane"),
        ("G1 X1 F100\nG2 X3 Y0 I0.5 J0\n", 1, "differs from the radius to the start"),
        ("G1 X1 F100\nG2 X9 Y0 R1\n", 10, "too small to reach"),
    ] {
        let p = read(text, Dialect::Rs274, "t.ngc", &ReadOptions::default());
        let e = errors(&p);
        assert!(e.iter().any(|m| m.starts_with(&format!("2:{col}:")) && m.contains(needle)), "{text:?}: {e:#?}");
        assert_eq!(p.blocks.len(), 1, "{text:?}: the refused block is not used");
    }
}

#[test]
fn cl_data_starts_at_its_first_pose() {
    // The paper's path at tilt 12 deg (closest approach 2 deg at x 25 mm), a pose every 0.1 mm: its
    // first pose is 14.8 deg from the pole. Nothing moves before it.
    let mut text = String::from("x,y,z,i,j,k\n");
    for k in 0..=500 {
        let x = k as f64 * 0.1;
        let a = fiveaxis::path::paper_orientation(12.0, x);
        text.push_str(&format!("{x:.4},0,-8,{:.9},{:.9},{:.9}\n", a.x, a.y, a.z));
    }
    let file = common::scratch_path("arcs", "tilt12.cl");
    std::fs::write(&file, &text).unwrap();
    let out = Command::new(bin()).args(["program", "analyze", &file.display().to_string(), "--feed", "2000", "--json"]).output().unwrap();
    let _ = std::fs::remove_file(&file);
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    // The closest approach over the poses, computed here: the angle of (i j k) to the C axis (z).
    let want = (0..=500)
        .map(|k| fiveaxis::path::paper_orientation(12.0, k as f64 * 0.1).z.clamp(-1.0, 1.0).acos().to_degrees())
        .fold(f64::INFINITY, f64::min);
    let overall = v["min_singularity_distance_all_deg"].as_f64().unwrap_or(f64::NAN);
    assert!((overall - want).abs() < 0.01, "closest approach overall {overall} deg, want {want:.3}");
    let cycle = v["cycle_time_s"].as_f64().unwrap();
    assert!((cycle - 50.0 / (2000.0 / 60.0)).abs() < 1e-6, "cycle {cycle} s: the 50 mm cut at F2000, with no move to the first pose");
}

#[test]
fn work_offsets_set_by_the_program_move_the_origin() {
    // G10 L2 P2 under a modal G03 (its P is the offset's, not turns), then G55: the machine stays at
    // X-10, so the current point is X-15 in G55 and G91 X1 ends at program X-14 (machine X-9).
    let text = "G21 G90 G94 G17\nG0 X10 Y0 Z0\nG3 X-10 Y0 I-10 J0 F1000\nG10 L2 P2 X5\nG55\nG1 G91 X1\nG90 G54 X0\nM2\n";
    let p = read(text, Dialect::Rs274, "offsets.ngc", &ReadOptions::default());
    assert!(errors(&p).is_empty(), "{:#?}", errors(&p));
    assert!(p.diagnostics.is_empty(), "{:#?}", p.diagnostics);
    let moves: Vec<_> = p.blocks.iter().filter(|b| !b.targets.is_empty()).collect();
    assert_eq!(moves.len(), 4, "G10's X5 is an offset, not a move");
    let g91 = moves[2];
    assert!((g91.targets.x.unwrap() - (-0.014)).abs() < 1e-15, "{:?}", g91.targets.x);
    assert_eq!(g91.datum, [0.005, 0.0, 0.0]);
    assert_eq!(moves[3].datum, [0.0; 3], "back in G54");
    // On a machine: the G91 move goes from machine.
    let machine = Machine::hermle_c600u();
    let traj = Trajectory::from_program(&p, &machine, &PathOptions::default());
    let seg = traj.segments.iter().find(|s| s.line == 6).unwrap();
    assert!((seg.q0[0] + 0.010).abs() < 1e-12 && (seg.q1[0] + 0.009).abs() < 1e-12, "{:?} -> {:?}", seg.q0, seg.q1);
}
